"""The table of a sweep: one row per run, in the order of the runs, written
as runs finish, so that a sweep stopped for any reason resumes where it stopped.

Columns: run, status, error, seed (with random factors), the factors, then
the kept columns the engine names. status is ok, out_of_band, failed or
crashed (docs/sweeps.md); numbers are doubles as the runs computed them.

Both formats are written to FILE.partial while the sweep runs, and renamed
to FILE when every run is in:

- CSV: rows appended as they come (in the order they finish), flushed at
  each batch; at the end sorted by run into FILE. A torn last line (the
  driver killed while writing it) is dropped when resuming.
- HDF5 (h5py): the compound dataset "runs" has one row per run from the
  start, empty status until the run is in, and each row is written in place
  (at least once a second: a kill loses the last second's rows here, which
  the CSV has, and they are made again);
  "timing" (cpu and wall seconds, worker) beside it, "series/<run>" the time
  series when kept; attributes: the sweep and scenario texts, their
  fingerprint, runs, seed, complete.

Resuming keeps the runs that every output holding them has alike (an
output without its FILE.partial, or with one a kill left unreadable, gets
them written again: but the series only HDF5 holds); the others are made
again. It refuses outputs written by another sweep (another fingerprint,
other columns, or other inputs for a run).
"""
import csv
import io
import math
import os
import sys
import time

try:
    import h5py
    import numpy as np
except ImportError:  # CSV alone still works
    h5py = None


class OutputError(ValueError):
    """An output that cannot be written or resumed: names the file."""


class Columns:
    def __init__(self, sweep, kept):
        self.factors = [f.name for f in sweep.factors]
        self.kept = list(kept)
        self.names = ["run", "status", "error"] + (["seed"] if sweep.random else []) + self.factors + self.kept
        text = {"status", "error"} | {f.name for f in sweep.factors if f.is_text}
        self.kinds = ["int" if n in ("run", "seed") else "text" if n in text else "float" for n in self.names]
        self.inputs = slice(3, 3 + (1 if sweep.random else 0) + len(self.factors))  # seed and factors


def format_value(value, kind):
    if kind == "float":
        return repr(float(value))  # the shortest text that reads back exactly
    return str(value)


def parse_value(text, kind):
    if kind == "int":
        return int(text)
    if kind == "float":
        return float(text)
    return text


class CsvOutput:
    def __init__(self, path, columns):
        self.path, self.columns = os.fspath(path), columns
        self.partial = self.path + ".partial"
        self.file = None

    def resume(self, restart):
        """The rows of an earlier start of this sweep (FILE.partial), by run;
        None when there is none."""
        if restart or not os.path.exists(self.partial):
            return None
        with open(self.partial, newline="", encoding="utf-8") as f:
            text = f.read()
        if not text.endswith("\n"):
            text = text[:text.rfind("\n") + 1]  # a line torn by a kill
        reader = csv.reader(io.StringIO(text, newline=""))
        header = next(reader, None)
        if header is None:
            return None
        if header != self.columns.names:
            raise OutputError(f"{self.partial} has other columns than this sweep's ({', '.join(header[:8])}, ...): "
                              "it comes from another sweep; remove it, or start over with --restart")
        rows = {}
        for line, fields in enumerate(reader, start=2):
            if len(fields) != len(header):
                raise OutputError(f"{self.partial}: line {line} has {len(fields)} fields, the header {len(header)}")
            row = tuple(parse_value(t, k) for t, k in zip(fields, self.columns.kinds))
            rows[row[0]] = row
        return rows

    def replays(self):
        return True

    def start(self, kept_rows):
        """Writes FILE.partial again with the rows kept, then appends."""
        self.file = open(self.partial, "w", newline="", encoding="utf-8")
        self.writer = csv.writer(self.file, lineterminator="\n")
        self.writer.writerow(self.columns.names)
        self.write(kept_rows.values())

    def write(self, rows, timings=None, series=None):
        kinds = self.columns.kinds
        self.writer.writerows([format_value(v, k) for v, k in zip(row, kinds)] for row in rows)
        self.file.flush()

    def close(self):
        if self.file is not None:
            self.file.close()
            self.file = None

    def finish(self):
        """Sorted by run into FILE."""
        self.close()
        with open(self.partial, newline="", encoding="utf-8") as f:
            lines = f.read().splitlines(keepends=True)
        body = sorted(lines[1:], key=lambda line: int(line[:line.index(",")]))
        temporary = self.path + ".sorting"
        with open(temporary, "w", newline="", encoding="utf-8") as f:
            f.write(lines[0])
            f.writelines(body)
        os.replace(temporary, self.path)
        os.remove(self.partial)


class Hdf5Output:
    def __init__(self, path, columns, sweep, series):
        if h5py is None:
            raise OutputError(f"{path}: HDF5 needs h5py (Debian: apt-get install python3-h5py)")
        self.path, self.columns, self.sweep, self.series = os.fspath(path), columns, sweep, series
        self.partial = self.path + ".partial"
        self.file = None
        text = h5py.string_dtype()
        types = {"int": np.int64, "float": np.float64, "text": text}
        self.dtype = np.dtype([(n, types[k]) for n, k in zip(columns.names, columns.kinds)])
        self.timing_dtype = np.dtype([("cpu_seconds", np.float64), ("wall_seconds", np.float64), ("worker", text)])

    def resume(self, restart):
        """The rows of an earlier start (FILE.partial), by run; None when there
        is none, or it cannot be read (a kill while it was written): then its
        runs are made again, and a warning says so."""
        self.reopen = False
        if restart or not os.path.exists(self.partial):
            return None
        try:
            with h5py.File(self.partial, "r") as f:
                if f.attrs.get("fingerprint") != self.sweep.fingerprint() or "runs" not in f \
                        or f["runs"].dtype.names != self.dtype.names:
                    raise OutputError(f"{self.partial} comes from another sweep (another sweep file, scenario or "
                                      "columns): remove it, or start over with --restart")
                table = f["runs"][:]
        except OSError as e:
            print(f"warning: {self.partial} cannot be read ({e}): its runs are made again", file=sys.stderr)
            return None
        rows = {}
        for r in table:
            if r["status"]:
                rows[int(r["run"])] = tuple(_plain(v) for v in r)
        self.reopen, self.had = True, set(rows)
        return rows

    def replays(self):
        """Whether rows kept from another output can be written here: not when
        it keeps series, which only it holds."""
        return not self.series

    def start(self, kept_rows):
        """Opens FILE.partial: the earlier one with its rows not in `kept_rows`
        cleared and those it lacks written, or a new one with `kept_rows`
        written (the timing of rows written so: 0)."""
        fresh = not self.reopen
        self.file = h5py.File(self.partial, "w" if fresh else "r+")
        self.waiting, self.written = [], time.monotonic()
        n = self.sweep.runs
        if fresh:
            self.runs = self.file.create_dataset("runs", shape=(n,), dtype=self.dtype)
            self.runs["run"] = np.arange(n, dtype=np.int64)
            self.timing = self.file.create_dataset("timing", shape=(n,), dtype=self.timing_dtype)
            if self.series:
                self.file.create_group("series")
            attrs = self.file.attrs
            attrs["sweep"], attrs["scenario"] = self.sweep.text, self.sweep.scenario_text
            attrs["fingerprint"], attrs["runs"], attrs["seed"] = self.sweep.fingerprint(), n, self.sweep.seed
            attrs["complete"] = False
            rows = list(kept_rows.values())
            self.write(rows, [(0.0, 0.0, "")] * len(rows))
        else:
            self.runs, self.timing = self.file["runs"], self.file["timing"]
            status = self.runs["status"]
            clear = [k for k in range(n) if status[k] and k not in kept_rows]
            if clear:
                empty = np.zeros(len(clear), dtype=self.dtype)
                empty["run"] = clear
                self.runs[clear] = empty
            missing = [row for k, row in kept_rows.items() if k not in self.had]  # from the CSV
            self.write(missing, [(0.0, 0.0, "")] * len(missing))
            for k in clear:
                if self.series and str(k) in self.file["series"]:
                    del self.file["series"][str(k)]
        self.file.flush()

    def write(self, rows, timings=None, series=None):
        """Rows are kept until a second has passed since the last write to the
        file, or 4096 are waiting (writing a few rows costs about as much as
        writing many); close() writes the rest."""
        rows = list(rows)
        timings = list(timings) if timings is not None else [(0.0, 0.0, "")] * len(rows)
        self.waiting.extend(zip(rows, timings))
        if self.series and series is not None:
            for row, text in zip(rows, series):
                if text is not None:
                    self._write_series(row[0], text)
        if len(self.waiting) >= 4096 or time.monotonic() - self.written >= 1.0:
            self._write_waiting()

    def _write_waiting(self):
        if self.waiting:
            self.waiting.sort(key=lambda w: w[0][0])
            runs = np.array([w[0] for w in self.waiting], dtype=self.dtype)
            timing = np.array([w[1] for w in self.waiting], dtype=self.timing_dtype)
            index = runs["run"]
            # Consecutive runs in one slice each: far faster than a list of points.
            breaks = np.flatnonzero(np.diff(index) != 1) + 1
            for a, b in zip(np.concatenate(([0], breaks)), np.concatenate((breaks, [len(index)]))):
                self.runs[index[a]:index[b - 1] + 1] = runs[a:b]
                self.timing[index[a]:index[b - 1] + 1] = timing[a:b]
            self.waiting = []
        self.file.flush()
        self.written = time.monotonic()

    def _write_series(self, run, text):
        lines = text.splitlines()
        if not lines:
            return
        names = lines[0].split(",")
        values = np.array([[float(x) for x in line.split(",")] for line in lines[1:]], dtype=np.float64)
        ds = self.file["series"].create_dataset(str(run), data=values.reshape(-1, len(names)))
        ds.attrs["columns"] = names

    def close(self):
        if self.file is not None:
            self._write_waiting()
            self.file.close()
            self.file = None

    def finish(self):
        self._write_waiting()
        self.file.attrs["complete"] = True
        self.close()
        os.replace(self.partial, self.path)


def _plain(value):
    if isinstance(value, bytes):
        return value.decode()
    return value if isinstance(value, str) else value.item()


def open_output(path, columns, sweep, series):
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext == ".csv":
        return CsvOutput(path, columns)
    if ext in (".h5", ".hdf5"):
        return Hdf5Output(path, columns, sweep, series)
    raise OutputError(f"--out {path}: the file must end in .csv, .h5 or .hdf5")


def same_values(a, b):
    return len(a) == len(b) and all(x == y or (isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y))
               for x, y in zip(a, b))
