"""Sweeps on a real Dask cluster (a scheduler and two worker processes on
127.0.0.1, started and torn down here): the same table, bit for bit, as one
local worker and two; a worker killed during the sweep has its runs made
again by the other, and the table is still the same."""
import os
import re
import unittest

import symdyn
from sweep_support import DaskCluster, copy_sweep, same_tables, scratch


def outputs(folder, stem):
    return [os.path.join(folder, f"{stem}.csv"), os.path.join(folder, f"{stem}.h5")]


class OnDask(unittest.TestCase):
    def test_serial_local_and_dask_agree_and_a_killed_worker_loses_nothing(self):
        folder = scratch(self)
        monte_carlo = copy_sweep(folder, "slider_crank_monte_carlo.json")
        trike = copy_sweep(folder, "trike_tyres.json")
        for name, sweep in (("mc", monte_carlo), ("trike", trike)):
            symdyn.sweep(sweep, workers=1, out=outputs(folder, f"{name}_serial"))
            symdyn.sweep(sweep, workers=2, out=outputs(folder, f"{name}_local"))

        with DaskCluster(os.path.join(folder)) as cluster:
            result = symdyn.sweep(monte_carlo, scheduler=cluster.address, out=outputs(folder, "mc_dask"))
            self.assertEqual(result.counts, {"ok": 40})
            self.assertIn("2 worker threads", result.where)

            killed = []

            def kill_a_worker(rows):
                if not killed:
                    cluster.kill_worker(0)
                    killed.append(len(rows))

            result = symdyn.sweep(trike, scheduler=cluster.address, out=outputs(folder, "trike_dask"),
                                  on_rows=kill_a_worker)
            self.assertEqual(killed and result.counts, {"ok": 9})
            with open(os.path.join(folder, "scheduler.log")) as f:
                removed = re.findall(r"Remove worker <WorkerState .*processing: (\d+)>", f.read())
            self.assertEqual(len(removed), 1, "the scheduler saw the worker go")
            print(f"\nthe killed worker was processing {removed[0]} tasks", flush=True)

        same_tables(self, [outputs(folder, "mc_serial"), outputs(folder, "mc_local"), outputs(folder, "mc_dask")])
        same_tables(self, [outputs(folder, "trike_serial"), outputs(folder, "trike_local"),
                           outputs(folder, "trike_dask")])


if __name__ == "__main__":
    unittest.main()
