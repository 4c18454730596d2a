"""Sweeps: runs per second and the overhead per run, on local workers and on a
Dask cluster on this machine (docs/sweeps.md; results in bench/results/sweep.md).

    PYTHONPATH=build/release/python /usr/bin/python3 bench/sweep_bench.py [--runs N] [--repeat R]

The sweep: models/sweeps/trike_tyres.json as a Monte Carlo (tyre stiffness and
speed drawn), its end time set to 1, 5 and 20 s: runs of about 4, 10 and 22 ms of
CPU. Each setting runs on 1 and 2 local workers and on Dask clusters that
this script starts on 127.0.0.1.

Three Dask clusters: 2 worker processes of 1 thread; 1 process of 2 threads
(each thread has its own engine: the runs do not share the process); and the
latter with Dask's background work made rarer (QUIET).

Overhead is measured in CPU time, which the other processes of a shared
machine do not inflate: everything the sweep's processes spent (the driver
with its local workers' threads, the engines, and on Dask the scheduler and
the workers) less the runs' own CPU time, over the runs' own time. A run's
own time is what its engine measures around it: building the scenario with
the run's changes, and integrating it, as symdyn-sim alone would. "fixed" is
the overhead of a sweep of 2 runs (starting engines, loading the sweep,
creating the files; on Dask, connecting), "per run" the rest over the runs.
Runs per second are wall-clock: on a loaded machine, a lower bound.
"""
import argparse
import json
import os
import platform
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

import symdyn

HERE = os.path.dirname(os.path.abspath(__file__))
SWEEPS = os.path.join(HERE, "..", "models", "sweeps")
TICK = os.sysconf("SC_CLK_TCK")


def tree_cpu(pid):
    """CPU seconds (user + system) of a process and its live descendants (the
    children of every thread: a Dask worker starts its engines from a thread)."""
    total, children = 0.0, []
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        total += (int(fields[11]) + int(fields[12])) / TICK
        for task in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{task}/children") as f:
                children += [int(c) for c in f.read().split()]
    except FileNotFoundError:
        return total
    return total + sum(tree_cpu(c) for c in children)


# Dask's background work, made rarer: the statistical profiler (every 10 ms
# by default), the event loop's health check (20 ms), the memory monitor
# (100 ms) and the system monitor (500 ms).
QUIET = {"DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED": "False", "DASK_DISTRIBUTED__ADMIN__TICK__INTERVAL": "1s",
         "DASK_DISTRIBUTED__WORKER__MEMORY__MONITOR_INTERVAL": "1s",
         "DASK_DISTRIBUTED__ADMIN__SYSTEM_MONITOR__INTERVAL": "2s"}


class Cluster:
    """A Dask scheduler and worker processes on 127.0.0.1."""

    def __init__(self, folder, workers, threads=1, environment=None):
        env = dict(os.environ, **(environment or {}))
        scheduler_file = os.path.join(folder, "scheduler.json")
        self.processes = [subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0",
             "--no-dashboard", "--scheduler-file", scheduler_file],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True, env=env)]
        while True:
            try:
                with open(scheduler_file) as f:
                    self.address = json.load(f)["address"]
                break
            except (OSError, ValueError, KeyError):
                time.sleep(0.1)
        for k in range(workers):
            self.processes.append(subprocess.Popen(
                [sys.executable, "-m", "distributed.cli.dask_worker", self.address, "--nthreads", str(threads),
                 "--no-nanny", "--no-dashboard", "--host", "127.0.0.1", "--local-directory",
                 os.path.join(folder, f"w{k}")],
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True, env=env))
        import distributed
        with distributed.Client(self.address, timeout="120s") as c:
            c.wait_for_workers(workers, timeout=120)
        os.remove(scheduler_file)

    def cpu(self):
        """(scheduler, workers with their engines) CPU seconds so far."""
        return tree_cpu(self.processes[0].pid), sum(tree_cpu(p.pid) for p in self.processes[1:])

    def close(self):
        for p in self.processes:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()


def trike(t_end, samples):
    """models/sweeps/trike_tyres.json as a Monte Carlo: tyre stiffness and
    speed drawn, the end time set."""
    with open(os.path.join(SWEEPS, "trike_tyres.json")) as f:
        d = json.load(f)
    d["factors"] = {"tyre_stiffness": {"distribution": "uniform", "low": 1e5, "high": 4e5},
                    "speed": {"distribution": "uniform", "low": 3, "high": 7}}
    d["samples"], d["seed"] = samples, 1
    d["set"]["t_end"] = t_end
    d["keep"]["at"]["times"] = [min(2, t_end)]
    return symdyn.Sweep(d, origin=f"trike to {t_end:g} s", directory=SWEEPS)


def rusage():
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime, c.ru_utime + c.ru_stime


def measure(spec, folder, workers=None, cluster=None):
    """One sweep: its figures, from the CPU its processes spent."""
    out = os.path.join(folder, "bench.h5")
    self0, children0 = rusage()
    scheduler0, workers0 = cluster.cpu() if cluster else (0.0, 0.0)
    start = time.perf_counter()
    result = symdyn.sweep(spec, workers=workers, scheduler=cluster.address if cluster else None, out=[out],
                          progress=False, restart=True)
    wall = time.perf_counter() - start
    self1, children1 = rusage()
    scheduler1, workers1 = cluster.cpu() if cluster else (0.0, 0.0)
    with h5py.File(out, "r") as f:
        timing = f["timing"][:]
        status = set(f["runs"]["status"])
    assert status <= {b"ok", b"out_of_band"}, status
    run_cpu = float(np.sum(timing["cpu_seconds"]))
    return {"runs": len(timing), "tasks": result.tasks, "wall": wall, "run_cpu": run_cpu,
            "run_wall": float(np.sum(timing["wall_seconds"])), "driver": self1 - self0,
            "engines": children1 - children0, "scheduler": scheduler1 - scheduler0, "workers": workers1 - workers0}


def overhead(m):
    return m["driver"] + m["engines"] + m["scheduler"] + m["workers"] - m["run_cpu"]


# (name, local workers, or the Dask cluster: worker processes, threads each, environment)
MODES = (("local, 1 worker", 1, None), ("local, 2 workers", 2, None),
         ("Dask, 2 workers x 1 thread", None, (2, 1, None)), ("Dask, 1 worker x 2 threads", None, (1, 2, None)),
         ("Dask, 1 worker x 2 threads, quiet", None, (1, 2, QUIET)))


def dask_task_cost(folder, tasks=4000):
    """CPU per task of Dask itself (scheduler, worker), from no-op tasks on a
    quiet cluster of 1 worker x 2 threads, its idle background taken off."""
    import distributed
    cluster = Cluster(folder, 1, 2, QUIET)
    try:
        with distributed.Client(cluster.address, timeout="120s") as client:
            s0, w0 = cluster.cpu()
            time.sleep(5.0)
            s1, w1 = cluster.cpu()
            idle = ((s1 - s0) / 5.0, (w1 - w0) / 5.0)
            start = time.perf_counter()
            futures = client.map(abs, range(-tasks, 0), pure=False)
            client.gather(futures)
            del futures
            wall = time.perf_counter() - start
            s2, w2 = cluster.cpu()
    finally:
        cluster.close()
    return {"tasks_per_s": tasks / wall, "scheduler": (s2 - s1 - idle[0] * wall) / tasks,
            "worker": (w2 - w1 - idle[1] * wall) / tasks, "idle_scheduler": idle[0], "idle_worker": idle[1]}


def driver_rows(folder, runs=100_000, batch=100):
    """CPU per row of the driver's outputs alone (CSV and HDF5), rows coming in
    batches of `batch`, as from Dask tasks."""
    from symdyn.table import Columns, open_output
    spec = trike(20.0, runs)
    kept = [f"k{j}" for j in range(16)]  # as many kept columns as the trike sweep's
    columns = Columns(spec, kept)
    outputs = [open_output(os.path.join(folder, f"rows.{e}"), columns, spec, False) for e in ("csv", "h5")]
    for o in outputs:
        o.resume(True)
        o.start({})
    rows = [(r, "ok", "", spec.run_seed(r), 2e5, 5.0, *[0.1 * j + r for j in range(16)]) for r in range(runs)]
    timing = [(0.01, 0.01, "host:1")] * batch
    t0 = time.process_time()
    for k in range(0, runs, batch):
        for o in outputs:
            o.write(rows[k:k + batch], timing, [None] * batch)
    for o in outputs:
        o.finish()
    return (time.process_time() - t0) / runs


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=400, help="runs per measurement (default 400)")
    parser.add_argument("--repeat", type=int, default=3, help="measurements per mode, the least overhead kept (3)")
    parser.add_argument("--json", help="write the measurements here too")
    args = parser.parse_args()
    folder = tempfile.mkdtemp(prefix="symdyn_sweep_bench_")
    print(f"{platform.node()}, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} at the start\n")
    results = []
    try:
        for name, workers, dask in MODES:  # one cluster at a time: an idle one still takes CPU
            cluster = Cluster(folder, *dask) if dask else None
            try:
                fixed = min(overhead(measure(trike(1.0, 2), folder, workers, cluster)) for _ in range(args.repeat))
                for t_end in (1.0, 5.0, 20.0):
                    ms = [measure(trike(t_end, args.runs), folder, workers, cluster) for _ in range(args.repeat)]
                    m = min(ms, key=overhead)
                    m.update(runs_per_s=max(x["runs"] / x["wall"] for x in ms), t_end=t_end, mode=name, fixed=fixed,
                             overhead=overhead(m), processes=dask[0] if dask else 0)
                    results.append(m)
                    print(f"measured {name}, trike {t_end:g} s", file=sys.stderr, flush=True)
            finally:
                if cluster:
                    cluster.close()
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    results.sort(key=lambda m: m["t_end"])
    print("| run length | where | runs/s | run CPU | wall per run | overhead, per run | overhead | fixed | "
          "driver per run | tasks |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for m in results:
        n = m["runs"]
        per_run = (m["overhead"] - m["fixed"]) / n
        print(f"| trike {m['t_end']:g} s | {m['mode']} | {m['runs_per_s']:.1f} | {1e3 * m['run_cpu'] / n:.2f} ms | "
              f"{1e3 * m['run_wall'] / n:.2f} ms | {1e6 * per_run:.0f} us = {100 * per_run * n / m['run_cpu']:.2f} % | "
              f"{100 * m['overhead'] / m['run_cpu']:.2f} % | {1e3 * m['fixed']:.0f} ms | "
              f"{1e6 * m['driver'] / n:.0f} us | {m['tasks']} |")
    print("\n| run length | where | scheduler per task | scheduler, % of a core | workers beyond the runs, "
          "% of a core per worker process |")
    print("|---|---|---:|---:|---:|")
    for m in results:
        if m["processes"]:
            print(f"| trike {m['t_end']:g} s | {m['mode']} | {1e3 * m['scheduler'] / m['tasks']:.2f} ms | "
                  f"{100 * m['scheduler'] / m['wall']:.1f} % | "
                  f"{100 * (m['workers'] - m['run_cpu']) / m['wall'] / m['processes']:.1f} % |")
    folder = tempfile.mkdtemp(prefix="symdyn_sweep_bench_")
    try:
        task = dask_task_cost(folder)
        row = driver_rows(folder)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    print(f"\nDask alone, 4000 no-op tasks on 1 worker x 2 threads (quiet): {task['tasks_per_s']:.0f} tasks/s, "
          f"{1e3 * task['scheduler']:.2f} ms of scheduler CPU and {1e3 * task['worker']:.2f} ms of worker CPU per "
          f"task; idle, the scheduler takes {100 * task['idle_scheduler']:.1f} % of a core and the worker "
          f"{100 * task['idle_worker']:.1f} %")
    print(f"The driver's outputs alone (CSV and HDF5, batches of 100 rows of the trike sweep's columns): "
          f"{1e6 * row:.1f} us of CPU per row")
    results.append({"dask_task": task, "driver_row": row})
    print(f"\nload average {os.getloadavg()[0]:.2f} at the end")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
