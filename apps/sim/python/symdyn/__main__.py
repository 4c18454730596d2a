"""symdyn-sim --sweep FILE [options], also python3 -m symdyn --sweep FILE:
runs a sweep file (docs/sweeps.md) and writes its table.

Exit codes: 0 every run ok; 1 a run is not ok (failed, crashed or a check
out of its band: the table says which and why), or the sweep stopped (its
runs so far are kept in FILE.partial, and the same command resumes it);
2 a bad sweep file or command line, refused before anything is written;
130 interrupted (resumable as well).
"""
import argparse
import os
import sys

from . import EngineError, OutputError, SweepError, sweep
from .sweep import default_workers


def positive(text):
    try:
        v = float(text)
    except ValueError:
        v = float("nan")
    if not v > 0.0 or v == float("inf"):
        raise argparse.ArgumentTypeError(f"expected a finite number > 0, found '{text}'")
    return v


def count(text):
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, found '{text}'")
    return int(text)


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="symdyn-sim --sweep", description="Runs a sweep file (docs/sweeps.md): many runs of a scenario, on "
        "this machine's cores or on a Dask cluster, into one table.")
    parser.add_argument("--sweep", required=True, metavar="FILE", help="the sweep file (JSON)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=count, metavar="N",
                       help=f"local workers, one engine each (default: every core, {default_workers()} here)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="a Dask scheduler (tcp://host:8786, or its --scheduler-file): run on its workers")
    parser.add_argument("--out", action="append", metavar="FILE",
                        help="the table: .csv or .h5, repeatable (default: <sweep>.csv and <sweep>.h5)")
    parser.add_argument("--restart", action="store_true", help="start over: ignore an earlier start's FILE.partial")
    parser.add_argument("--timeout", type=positive, metavar="S", help="stop a run after S seconds (recorded failed)")
    parser.add_argument("--chunk-seconds", type=positive, default=1.0, metavar="S",
                        help="Dask: runs per task, to last about S seconds (default 1)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    stem = os.path.splitext(os.path.basename(args.sweep))[0]
    out = args.out or [f"{stem}.csv", f"{stem}.h5"]
    try:
        result = sweep(args.sweep, workers=args.workers, scheduler=args.scheduler, out=out, restart=args.restart,
                       progress=False if args.quiet else None, timeout=args.timeout,
                       chunk_seconds=args.chunk_seconds)
    except (SweepError, OutputError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except EngineError as e:
        print(f"error: {e}", file=sys.stderr)
        print(f"  the sweep stopped; the runs made are kept in {', '.join(o + '.partial' for o in out)}: the same "
              "command resumes it", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"\ninterrupted; the runs made are kept in {', '.join(o + '.partial' for o in out)}: the same command "
              "resumes the sweep", file=sys.stderr)
        return 130
    print(result.summary())
    for path in result.outputs:
        print(f"  wrote {path}")
    return 0 if result.ok else 1


if __name__ == "__main__":
    sys.exit(main())
