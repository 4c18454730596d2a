"""What the sweep tests share: sweep files written to a scratch folder, the
table read back from CSV and HDF5, and a Dask cluster on 127.0.0.1 (a
scheduler and worker processes, started and always torn down)."""
import contextlib
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import h5py

SWEEPS = os.environ["SYMDYN_SWEEPS"]
SIM = os.environ["SYMDYN_SIM"]


def scratch(test):
    path = tempfile.mkdtemp(prefix="symdyn_sweep_")
    test.addCleanup(shutil.rmtree, path, ignore_errors=True)
    return path


def write_json(folder, name, document):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        json.dump(document, f, indent=1)
    return path


def copy_sweep(folder, name, change=None):
    """A sweep file of models/sweeps copied into `folder` (with the scenario
    files beside it), its document changed by `change` if given."""
    for f in os.listdir(SWEEPS):
        shutil.copy(os.path.join(SWEEPS, f), folder)
    path = os.path.join(folder, name)
    if change is not None:
        with open(path) as f:
            document = json.load(f)
        change(document)
        write_json(folder, name, document)
    return path


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def read_hdf5(path):
    """The table's bytes (numbers bit for bit, texts as written) and its attributes."""
    with h5py.File(path, "r") as f:
        runs = f["runs"][:]
        attrs = dict(f.attrs)
        series = {k: (f["series"][k][:], list(f["series"][k].attrs["columns"])) for k in f["series"]} \
            if "series" in f else {}
    columns = {}
    for name in runs.dtype.names:
        v = runs[name]
        columns[name] = v.tobytes() if v.dtype.kind != "O" else [x.decode() if isinstance(x, bytes) else x for x in v]
    return columns, attrs, series


def same_tables(test, paths):
    """Every output of `paths` (a list of [csv, h5] pairs) the same as the first."""
    first_csv, first_h5 = paths[0]
    with open(first_csv, "rb") as f:
        reference = f.read()
    ref_columns, _, ref_series = read_hdf5(first_h5)
    for csv_path, h5_path in paths[1:]:
        with open(csv_path, "rb") as f:
            test.assertEqual(f.read(), reference, f"{csv_path} differs from {first_csv}")
        columns, _, series = read_hdf5(h5_path)
        test.assertEqual(columns.keys(), ref_columns.keys())
        for name in columns:
            test.assertEqual(columns[name], ref_columns[name], f"{h5_path}: column {name} differs from {first_h5}")
        test.assertEqual(series.keys(), ref_series.keys())
        for k in series:
            test.assertEqual(series[k][0].tobytes(), ref_series[k][0].tobytes())


def run_cli(*args, cwd=None, timeout=600):
    return subprocess.run([SIM, *args], cwd=cwd, capture_output=True, text=True, timeout=timeout)


class DaskCluster:
    """A Dask scheduler and `workers` worker processes (one thread each, no
    nanny: a killed worker stays dead) on 127.0.0.1, on ports the scheduler
    chooses; each process leads its own process group, which closing kills
    (the engines a worker started end with their input)."""

    def __init__(self, folder, workers=2, timeout=180):
        self.folder = folder
        self.processes = []
        self.workers = []
        self.logs = []
        scheduler_file = os.path.join(folder, "scheduler.json")
        self._start("scheduler", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0",
                    "--no-dashboard", "--scheduler-file", scheduler_file)
        deadline = time.monotonic() + timeout
        while not os.path.exists(scheduler_file):
            self._alive()
            if time.monotonic() > deadline:
                raise TimeoutError("the Dask scheduler did not start: " + self.log())
            time.sleep(0.1)
        while True:  # read until it parses: the scheduler may be writing it
            try:
                with open(scheduler_file) as f:
                    self.address = json.load(f)["address"]
                break
            except (ValueError, KeyError):
                time.sleep(0.1)
        for k in range(workers):
            self.workers.append(self._start(f"worker{k}", "distributed.cli.dask_worker", self.address, "--nthreads",
                                            "1", "--no-nanny", "--no-dashboard", "--host", "127.0.0.1",
                                            "--local-directory", os.path.join(folder, f"worker{k}")))
        import distributed
        with distributed.Client(self.address, timeout=f"{timeout}s") as client:
            client.wait_for_workers(workers, timeout=timeout)

    def _start(self, name, module, *args):
        log = open(os.path.join(self.folder, f"{name}.log"), "w")
        self.logs.append(log.name)
        p = subprocess.Popen([sys.executable, "-m", module, *args], stdout=log, stderr=subprocess.STDOUT,
                             start_new_session=True, env=dict(os.environ))
        log.close()
        self.processes.append(p)
        return p

    def _alive(self):
        for p in self.processes:
            if p.poll() is not None and p not in self.workers:
                raise RuntimeError(f"a Dask process exited with {p.returncode}: {self.log()}")

    def log(self):
        text = ""
        for name in self.logs:
            with open(name) as f:
                text += f"--- {name}\n" + f.read()[-3000:]
        return text

    def kill_worker(self, k):
        os.kill(self.workers[k].pid, signal.SIGKILL)  # the worker alone: its engine ends with its input
        self.workers[k].wait()

    def close(self):
        for p in reversed(self.processes):
            with contextlib.suppress(ProcessLookupError):
                os.killpg(p.pid, signal.SIGKILL)
            p.wait()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
