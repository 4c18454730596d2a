"""symdyn: sweeps and Monte Carlo studies of symdyn-sim's scenarios, on this
machine's cores or on a Dask cluster (docs/sweeps.md).

    import symdyn
    result = symdyn.sweep("tyres.json", out=["tyres.h5", "tyres.csv"])
"""
from .engine import EngineError
from .sweep import SweepResult, default_workers, sweep
from .sweep_file import Sweep, SweepError
from .table import OutputError

__all__ = ["sweep", "Sweep", "SweepResult", "SweepError", "OutputError", "EngineError", "default_workers"]
