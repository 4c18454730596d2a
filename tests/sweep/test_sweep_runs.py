"""Sweeps on this machine (docs/sweeps.md): the same table, row for row and
bit for bit, from one worker or two; a run's row the same as symdyn-sim's
own run of it; failures recorded and the sweep going on; a sweep stopped (an
exception, a kill of the driver) resumed where it stopped."""
import contextlib
import io
import os
import signal
import subprocess
import sys
import textwrap
import time
import unittest

import symdyn
from symdyn.progress import Progress
from sweep_support import SIM, copy_sweep, read_csv, read_hdf5, run_cli, same_tables, scratch, write_json

MODULE = os.environ["SWEEP_MODULE"]


def outputs(folder, stem):
    return [os.path.join(folder, f"{stem}.csv"), os.path.join(folder, f"{stem}.h5")]


class SameTableEverywhere(unittest.TestCase):
    def test_trike_tyre_stiffness_by_speed(self):
        folder = scratch(self)
        sweep = copy_sweep(folder, "trike_tyres.json")
        one = symdyn.sweep(sweep, workers=1, out=outputs(folder, "one"))
        two = symdyn.sweep(sweep, workers=2, out=outputs(folder, "two"))
        self.assertEqual(one.counts, {"ok": 9})
        self.assertEqual(two.counts, {"ok": 9})
        same_tables(self, [outputs(folder, "one"), outputs(folder, "two")])
        rows = read_csv(os.path.join(folder, "one.csv"))
        header = rows[0]
        self.assertEqual(header[:5], ["run", "status", "error", "tyre_stiffness", "speed"])
        self.assertIn("maximum(rear_left.normal_force)", header)
        self.assertIn("check: final forward speed", header)
        for row in rows[1:]:
            r = dict(zip(header, row))
            # The drive holds each speed; a stiffer tyre rides higher on its smaller deflection.
            self.assertAlmostEqual(float(r["final_speed"]), float(r["speed"]), delta=0.05 * float(r["speed"]))
        heights = {float(r[3]): float(r[header.index("minimum(z)")]) for r in rows[1:] if r[4] == "5.0"}
        self.assertLess(heights[1e5], heights[2e5])
        self.assertLess(heights[2e5], heights[4e5])

    def test_slider_crank_monte_carlo_with_series(self):
        folder = scratch(self)
        sweep = copy_sweep(folder, "slider_crank_monte_carlo.json",
                           lambda d: d.update(samples=12) or d["keep"].update(series=True))
        one = symdyn.sweep(sweep, workers=1, out=outputs(folder, "one"))
        two = symdyn.sweep(sweep, workers=2, out=outputs(folder, "two"), keep_rows=True)
        self.assertEqual(one.counts, {"ok": 12})
        same_tables(self, [outputs(folder, "one"), outputs(folder, "two")])
        columns, attrs, series = read_hdf5(os.path.join(folder, "two.h5"))
        self.assertTrue(attrs["complete"])
        self.assertEqual(sorted(series, key=int), [str(k) for k in range(12)])
        # A run of the sweep is symdyn-sim's own run of the scenario so changed, bit for bit.
        names = two.columns
        row = dict(zip(names, two.rows[5]))
        csv_path = os.path.join(folder, "single.csv")
        done = run_cli(os.path.join(folder, "slider_crank_bearing.json"), "--out", csv_path,
                       "--set", f"forces.bearing.damping={row['bearing_damping']!r}",
                       "--set", f"forces.return_spring.stiffness={row['spring_stiffness']!r}",
                       "--set", f"initial.qd.crank={row['launch_speed']!r}")
        self.assertEqual(done.returncode, 0, done.stderr)
        single = read_csv(csv_path)
        last = dict(zip(single[0], single[-1]))
        self.assertEqual(float(last["crank"]), row["end(crank)"])
        self.assertEqual(float(last["crank_dot"]), row["end(crank_dot)"])
        values, columns_of_series = series["5"]
        self.assertEqual(columns_of_series, single[0])
        self.assertEqual(values.tolist(), [[float(x) for x in line] for line in single[1:]])

    def test_a_model_module_and_its_parameters(self):
        folder = scratch(self)
        scenario = write_json(folder, "pendulum.json", {
            "model": {"name": "double_pendulum_parameters", "module": MODULE},
            "t_end": 0.5, "integrator": {"name": "dop853", "tolerance": 1e-10}})
        sweep = write_json(folder, "masses.json", {
            "scenario": "pendulum.json",
            "factors": {"m1": {"values": [0.5, 1, 2], "set": "parameters.m1"},
                        "l2": {"distribution": "uniform", "low": 0.5, "high": 1.5, "set": "parameters.l2"}},
            "samples": 2, "seed": 3, "keep": {"final": ["q"]}})
        result = symdyn.sweep(sweep, workers=2)
        self.assertEqual(result.counts, {"ok": 6})
        for row in result.rows:
            r = dict(zip(result.columns, row))
            done = run_cli(scenario, "--out", os.path.join(folder, "one.csv"), "--set", f"parameters.m1={r['m1']!r}",
                           "--set", f"parameters.l2={r['l2']!r}")
            self.assertEqual(done.returncode, 0, done.stderr)
            last = read_csv(os.path.join(folder, "one.csv"))[-1]
            self.assertEqual([float(last[1]), float(last[2])], [r["end(theta1)"], r["end(theta2)"]])


class NothingLostNothingSilent(unittest.TestCase):
    def test_failed_runs_are_kept_and_the_sweep_goes_on(self):
        folder = scratch(self)

        def change(d):
            d["factors"]["tyre_stiffness"]["values"] = [-1e5, 2e5]
            d["factors"]["speed"]["values"] = [0, 5, 12]
            d["set"]["initial.qd.left_spin"] = "speed / 0.3 + 1 / speed"

        sweep = copy_sweep(folder, "trike_tyres.json", change)
        result = symdyn.sweep(sweep, workers=2, keep_rows=True)
        status = {(r[3], r[4]): (r[1], r[2]) for r in result.rows}
        self.assertEqual(status[(-1e5, 5.0)][0], "failed")
        self.assertIn("models/scenarios/trike.json: /forces/5/stiffness (force element 'rear_left'): expected a finite "
                      "number > 0, found -100000", status[(-1e5, 5.0)][1])
        self.assertEqual(status[(2e5, 0.0)][0], "failed")
        self.assertIn("/set/initial.qd.left_spin: 'speed / 0.3 + 1 / speed' fails for this run: float division by zero",
                      status[(2e5, 0.0)][1])
        self.assertEqual(status[(2e5, 5.0)], ("ok", ""))
        self.assertEqual(status[(2e5, 12.0)][0], "out_of_band")
        self.assertIn("out of band: final forward speed = ", status[(2e5, 12.0)][1])
        failed = [r for r in result.rows if r[1] == "failed"]
        self.assertTrue(all(x != x for r in failed for x in r[5:]))  # NaN where a run made nothing
        self.assertEqual(result.counts, {"failed": 4, "ok": 1, "out_of_band": 1})
        done = run_cli("--sweep", sweep, "--workers", "2", "--out", "t.csv", cwd=folder)
        self.assertEqual(done.returncode, 1, done.stderr)
        self.assertIn("6 runs (4 failed, 1 ok, 1 out_of_band)", done.stdout)

    def test_an_engine_that_dies_on_a_run(self):
        """An engine killed by its run: retried once on a fresh engine, then
        recorded as crashed; every other run as without it."""
        folder = scratch(self)
        sweep = copy_sweep(folder, "trike_tyres.json")
        dying = os.path.join(folder, "dying_engine.py")
        with open(dying, "w") as f:
            f.write(textwrap.dedent(f"""\
                #!{sys.executable}
                # symdyn-sim --serve, but a request for run 4 kills it.
                import json, os, signal, subprocess, sys
                engine = subprocess.Popen([{SIM!r}, "--serve"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
                for line in sys.stdin:
                    if json.loads(line).get("run") == 4:
                        os.kill(os.getpid(), signal.SIGSEGV)
                    engine.stdin.write(line)
                    engine.stdin.flush()
                    sys.stdout.write(engine.stdout.readline())
                    sys.stdout.flush()
                """))
        os.chmod(dying, 0o755)
        crashed = symdyn.sweep(sweep, workers=2, program=dying, keep_rows=True)
        fine = symdyn.sweep(sweep, workers=1, keep_rows=True)
        self.assertEqual(crashed.counts, {"ok": 8, "crashed": 1})
        self.assertEqual(crashed.rows[4][1:3], ("crashed", "the engine (symdyn-sim --serve) was killed by SIGSEGV, "
                                                           "twice, running it"))
        self.assertEqual([r for k, r in enumerate(crashed.rows) if k != 4],
                         [r for k, r in enumerate(fine.rows) if k != 4])

    def test_a_run_past_the_timeout_is_stopped_and_recorded(self):
        folder = scratch(self)
        sweep = copy_sweep(folder, "trike_tyres.json",
                           lambda d: d["factors"]["speed"].update(values=[5]) or d["set"].update(t_end=600))
        result = symdyn.sweep(sweep, workers=2, timeout=0.05, keep_rows=True)
        self.assertEqual(result.counts, {"failed": 3})
        for row in result.rows:
            self.assertEqual(row[2], "stopped after 0.05 s (the sweep's timeout); its engine was killed")

    def test_resume_after_an_exception(self):
        folder = scratch(self)
        sweep = copy_sweep(folder, "slider_crank_monte_carlo.json")
        out = outputs(folder, "mc")

        class Stop(Exception):
            pass

        seen = []

        def stop_after_five(rows):
            seen.extend(rows)
            if len(seen) >= 5:
                raise Stop()

        with self.assertRaises(Stop):
            symdyn.sweep(sweep, workers=2, out=out, on_rows=stop_after_five)
        self.assertTrue(all(os.path.exists(p + ".partial") and not os.path.exists(p) for p in out))
        # A line torn by a kill at the end of the CSV: dropped when resuming.
        with open(out[0] + ".partial", "a") as f:
            f.write("39,ok,,123")
        # An HDF5 file a kill left unreadable: made again from the CSV's rows, saying so.
        with open(out[1] + ".partial", "r+b") as f:
            f.write(b"\0" * 512)
        warnings = io.StringIO()
        with contextlib.redirect_stderr(warnings):
            resumed = symdyn.sweep(sweep, workers=2, out=out)
        self.assertIn(f"warning: {out[1]}.partial cannot be read", warnings.getvalue())
        self.assertGreaterEqual(resumed.resumed, 5)
        self.assertEqual(resumed.resumed + resumed.made, 40)
        whole = symdyn.sweep(sweep, workers=1, out=outputs(folder, "whole"))
        self.assertEqual(whole.resumed, 0)
        same_tables(self, [outputs(folder, "whole"), out])

    def test_resume_after_the_driver_is_killed(self):
        folder = scratch(self)
        sweep = copy_sweep(folder, "slider_crank_monte_carlo.json",
                           lambda d: d.update(samples=200))
        command = [SIM, "--sweep", sweep, "--workers", "2", "--out", "mc.csv", "--out", "mc.h5"]
        driver = subprocess.Popen(command, cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        partial = os.path.join(folder, "mc.csv.partial")
        deadline = time.monotonic() + 300
        while time.monotonic() < deadline and driver.poll() is None:
            if os.path.exists(partial) and len(read_csv(partial)) >= 4:
                break
            time.sleep(0.01)
        self.assertIsNone(driver.poll(), "the sweep ended before it could be killed")
        driver.send_signal(signal.SIGKILL)
        driver.communicate()
        again = subprocess.run(command, cwd=folder, capture_output=True, text=True, timeout=600)
        whole = symdyn.sweep(sweep, workers=1, out=outputs(folder, "whole"))
        self.assertEqual(sum(whole.counts.values()), 200)
        self.assertEqual(again.returncode, 0 if whole.ok else 1, again.stderr)  # a stalled crank is out of band
        self.assertIn("kept from an earlier start", again.stdout)
        same_tables(self, [outputs(folder, "whole"), outputs(folder, "mc")])

    def test_a_partial_table_of_another_sweep_is_refused(self):
        folder = scratch(self)
        sweep = copy_sweep(folder, "trike_tyres.json")
        out = outputs(folder, "t")

        def stop(rows):
            raise KeyboardInterrupt()

        with self.assertRaises(KeyboardInterrupt):
            symdyn.sweep(sweep, workers=1, out=out, on_rows=stop)
        copy_sweep(folder, "trike_tyres.json", lambda d: d["factors"]["tyre_stiffness"].update(values=[1.5e5, 4e5]))
        with self.assertRaisesRegex(symdyn.OutputError, "t.h5.partial comes from another sweep"):
            symdyn.sweep(sweep, workers=1, out=out)
        with self.assertRaisesRegex(symdyn.OutputError, "t.csv.partial: run 0 has other inputs than this sweep"):
            symdyn.sweep(sweep, workers=1, out=out[:1])
        restarted = symdyn.sweep(sweep, workers=1, out=out, restart=True)
        self.assertEqual((restarted.resumed, restarted.made), (0, 6))


class Documentation(unittest.TestCase):
    def test_the_example_of_docs_sweeps_md_python_runs_as_written(self):
        # documented_example.py is the page's block (tests/docs/code_blocks.py keeps them equal).
        example = os.path.join(os.path.dirname(os.path.abspath(__file__)), "documented_example.py")
        with open(example) as f:
            block = f.read()
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            exec(compile(block, example, "exec"), {})
        lines = printed.getvalue().splitlines()
        self.assertEqual(lines[0], "['run', 'status', 'error', 'tolerance', 'end(crank)', 'steps']")
        self.assertEqual(len(lines), 6)
        rows = [line.split() for line in lines[1:]]
        self.assertEqual([r[0] for r in rows], ["ok"] * 5)
        self.assertEqual([float(r[1]) for r in rows], [1e-10, 1e-9, 1e-8, 1e-7, 1e-6])
        self.assertTrue(rows[0][2].startswith("39.17129013"), rows[0])
        steps = [float(r[3]) for r in rows]
        self.assertEqual(steps, sorted(steps, reverse=True))


class ProgressBar(unittest.TestCase):
    def test_the_bar_says_runs_rate_and_time_left(self):
        stream = io.StringIO()
        bar = Progress(100, 10, stream=stream, enabled=True)
        bar.start -= 10.0
        bar.recent[0] = (bar.start, 10)
        bar.update(20, 2)
        bar.finish()
        line = stream.getvalue().split("\r")[-1]
        self.assertRegex(line, r"\[#########\s+\]  30/100 runs  2(\.\d+)? runs/s  0:3\d left  2 not ok")


if __name__ == "__main__":
    unittest.main()
