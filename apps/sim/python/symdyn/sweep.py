"""sweep(): runs a sweep file (docs/sweeps.md) on this machine's cores or on
a Dask cluster, and writes its table as runs finish.

    import symdyn
    result = symdyn.sweep("tyres.json", out=["tyres.h5", "tyres.csv"])              # every core here
    result = symdyn.sweep("tyres.json", scheduler="tcp://10.0.0.5:8786", out=["tyres.h5"])  # a Dask cluster
    print(result.counts)  # {"ok": 11, "failed": 1}

Before any run: the sweep file is read and its every key checked, then an
engine (symdyn-sim --serve) loads it, checking every path it changes and
every quantity it keeps against the scenario and its model; a mistake is a
SweepError naming the file and the key, and nothing is written.
"""
import collections
import os
import time

from .engine import EngineError, Engine, find_program
from .executors import DaskWorkers, LocalWorkers
from .progress import Progress, duration
from .sweep_file import Sweep, SweepError
from .table import Columns, OutputError, open_output, same_values


class SweepResult:
    """What a sweep did: columns, counts by status, the runs made now and
    before (resumed), the files written, the rows when kept in memory, and the
    batches (tasks) the runs went in."""

    def __init__(self, columns, counts, made, resumed, outputs, rows, seconds, where, tasks):
        self.columns, self.counts, self.made, self.resumed = columns, counts, made, resumed
        self.outputs, self.rows, self.seconds, self.where = outputs, rows, seconds, where
        self.tasks = tasks  # batches of runs sent to engines (Dask tasks)

    @property
    def ok(self):
        return set(self.counts) <= {"ok"}

    def summary(self):
        counts = ", ".join(f"{n} {status}" for status, n in sorted(self.counts.items()))
        text = f"{sum(self.counts.values())} runs ({counts})"
        text += f"; {self.made} made in {duration(self.seconds)} on {self.where}"
        if self.resumed:
            text += f", {self.resumed} kept from an earlier start"
        return text


def default_workers():
    return len(os.sched_getaffinity(0))


def sweep(sweep, workers=None, scheduler=None, out=(), restart=False, progress=None, timeout=None,
          chunk_seconds=1.0, program=None, keep_rows=None, on_rows=None):
    """Runs a sweep and returns its SweepResult.

    sweep: a sweep file's path, or a Sweep. workers: local workers (default:
    every core of this machine); scheduler: a Dask scheduler's address
    instead. out: the table's files (.csv, .h5); with none, or keep_rows,
    the rows are kept in result.rows, in the order of the runs. restart:
    ignore an earlier start's FILE.partial (else the sweep resumes from it).
    progress: draw the bar on stderr (default: when it is a terminal).
    timeout: seconds after which a run is stopped and recorded as failed.
    on_rows: called with each batch of finished rows (tuples in the order of
    result.columns). Raises SweepError (a bad sweep), OutputError (an output
    it cannot write or resume) and EngineError (the engine cannot run here
    or on a worker: the runs made so far stay in FILE.partial).
    """
    spec = sweep if isinstance(sweep, Sweep) else Sweep.load(sweep)
    if workers is not None and scheduler is not None:
        raise ValueError("workers and scheduler: give one (local workers, or a Dask cluster)")
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers: expected an integer >= 1, found {workers!r}")
    program = find_program(program)
    fingerprint = spec.fingerprint()

    # The engine checks the sweep against the scenario before anything is written.
    check = Engine(program)
    try:
        kept = check.load(spec, fingerprint)
    finally:
        check.close()
    columns = Columns(spec, kept)
    for name in kept:
        if name in columns.factors or name in ("run", "status", "error", "seed"):
            raise SweepError(f"{spec.origin}: /keep: the column '{name}' is also a factor's or the table's own: "
                             "name one otherwise")

    outputs = [open_output(path, columns, spec, spec.keep.get("series", False)) for path in out]
    if len({os.path.abspath(o.path) for o in outputs}) != len(outputs):
        raise OutputError("--out names one file twice")
    kept_rows = _resume(spec, columns, outputs, restart)
    for o in outputs:
        o.start(kept_rows)

    if keep_rows is None:
        keep_rows = not outputs
    rows = dict(kept_rows) if keep_rows else None
    counts = collections.Counter(row[1] for row in kept_rows.values())
    pending = [r for r in range(spec.runs) if r not in kept_rows]
    bar = Progress(spec.runs, len(kept_rows), enabled=progress)
    executor = DaskWorkers(scheduler, program, timeout, chunk_seconds) if scheduler is not None else \
        LocalWorkers(workers or default_workers(), program, timeout)
    seen = set(kept_rows)

    def sink(batch):
        batch = [b for b in batch if b[0][0] not in seen]  # a task Dask made twice
        seen.update(b[0][0] for b in batch)
        new = [b[0] for b in batch]
        for o in outputs:
            o.write(new, [b[1] for b in batch], [b[2] for b in batch])
        counts.update(row[1] for row in new)
        if rows is not None:
            rows.update((row[0], row) for row in new)
        bar.update(len(new), sum(row[1] != "ok" for row in new))
        if on_rows is not None:
            on_rows(new)

    start = time.monotonic()
    try:
        executor.run(spec, fingerprint, pending, len(kept), sink)
        if len(seen) != spec.runs:  # never expected: say so rather than leave a hole
            raise EngineError(f"{spec.runs - len(seen)} runs never came back: the table stays in FILE.partial")
    except BaseException:
        for o in outputs:
            o.close()
        raise
    finally:
        bar.finish()
    for o in outputs:
        o.finish()
    ordered = [rows[k] for k in range(spec.runs)] if rows is not None else None
    return SweepResult(columns.names, dict(counts), len(pending), len(kept_rows), [o.path for o in outputs],
                       ordered, time.monotonic() - start, executor.describe(), executor.tasks)


def _resume(spec, columns, outputs, restart):
    """The rows of an earlier start (the outputs' FILE.partial) to keep: each
    run the outputs that have it agree on, and that every output has or can
    take from another; their inputs checked against this sweep's."""
    found = [(o, o.resume(restart)) for o in outputs]
    have = [(o, rows) for o, rows in found if rows is not None]
    if not have:
        return {}
    for o, rows in have:
        for k, row in rows.items():
            fresh = ([spec.run_seed(k)] if spec.random else []) + spec.inputs(k) if k < spec.runs else None
            if fresh is None or not same_values(row[columns.inputs], fresh):
                raise OutputError(f"{o.partial}: run {k} has other inputs than this sweep gives it: the sweep "
                                  "changed since; remove the file, or start over with --restart")
    kept = {}
    for k in sorted(set().union(*(rows for _, rows in have))):
        present = [rows[k] for _, rows in have if k in rows]
        if not all(same_values(present[0], row) for row in present[1:]):
            continue  # written by halves when the driver was killed: made again
        if any(not o.replays() for o, rows in found if rows is None or k not in rows):
            continue  # an output lacks it and cannot take it from another (series)
        kept[k] = present[0]
    return kept
