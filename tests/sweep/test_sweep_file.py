"""Sweep files (docs/sweeps.md): every bad key refused before anything is
written, naming the file and the key; the runs' inputs in their documented
order; samples that depend on the seed, the run and the factor only."""
import json
import math
import os
import statistics
import unittest

import symdyn
from symdyn.sweep_file import Sweep
from sweep_support import SWEEPS, run_cli, scratch, write_json

TRIKE = {
    "scenario": "trike",
    "factors": {"k": {"values": [1e5, 2e5]}, "speed": {"from": 3, "to": 7, "count": 3}},
    "set": {"forces.front.stiffness": "k", "variables.speed": "speed", "initial.qd.x": "speed"},
}


def changed(base, path, value):
    """`base` with the member at `path` (a list of keys) set, or removed when value is ..."""
    document = json.loads(json.dumps(base))
    at = document
    for key in path[:-1]:
        at = at[key]
    if value is ...:
        del at[path[-1]]
    else:
        at[path[-1]] = value
    return document


class BadSweepFiles(unittest.TestCase):
    """One case per refusal, each naming the file and the key."""

    def refused(self, document, message, text=None):
        folder = scratch(self)
        path = os.path.join(folder, "bad.json")
        with open(path, "w") as f:
            f.write(text if text is not None else json.dumps(document))
        with self.assertRaises(symdyn.SweepError) as e:
            symdyn.sweep(path, workers=1, out=[os.path.join(folder, "t.csv"), os.path.join(folder, "t.h5")])
        self.assertIn(message, str(e.exception))
        self.assertTrue(str(e.exception).startswith(path + ": "), str(e.exception))
        self.assertEqual(sorted(os.listdir(folder)), ["bad.json"])  # nothing written

    def test_structure(self):
        self.refused(changed(TRIKE, ["factor"], 1), "/factor: unknown key 'factor' (expected: $schema, description")
        self.refused(changed(TRIKE, ["scenario"], ...), "/: missing key 'scenario'")
        self.refused(changed(TRIKE, ["scenario"], "nope.json"), "/scenario: cannot read scenario file")
        self.refused(changed(TRIKE, ["factors"], []), "/factors: expected an object, found an array")
        self.refused(None, "not JSON: Expecting ',' delimiter at line 1", text='{"scenario": "trike" "x": 1}')
        self.refused(None, "/factors/k: key 'k' is given twice in this object",
                     text='{"scenario": "trike", "factors": {"k": {"values": [1]}, "k": {"values": [2]}}}')
        self.refused(None, "/factors/k/values/1: NaN is not a number in JSON",
                     text='{"scenario": "trike", "factors": {"k": {"values": [1, NaN]}}}')
        self.refused(None, "/seed: a number beyond the range of a double", text='{"scenario": "trike", "seed": 1e400}')

    def test_factors(self):
        f = ["factors"]
        self.refused(changed(TRIKE, f + ["2k"], {"values": [1]}), "/factors/2k: '2k' cannot name a factor")
        self.refused(changed(TRIKE, f + ["seed"], {"values": [1]}), "/factors/seed: 'seed' is taken")
        self.refused(changed(TRIKE, f + ["k"], {"value": [1]}), '/factors/k: expected "values", "from"/"to"/"count"')
        self.refused(changed(TRIKE, f + ["k", "values"], []), "/factors/k/values: expected a non-empty array")
        self.refused(changed(TRIKE, f + ["k", "values"], [1, "a"]), "/factors/k/values/1: expected a number, found a string")
        self.refused(changed(TRIKE, f + ["k", "values"], [1, 2, 1]), "/factors/k/values/2: 1.0 is given twice")
        self.refused(changed(TRIKE, f + ["speed", "count"], 0), "/factors/speed/count: expected an integer >= 1, found 0")
        self.refused(changed(TRIKE, f + ["speed", "count"], 2.5), "/factors/speed/count: expected an integer >= 1, found 2.5")
        self.refused(changed(TRIKE, f + ["speed", "to"], 3), "/factors/speed/to: from and to are equal")
        self.refused(changed(changed(TRIKE, f + ["speed", "from"], -1), f + ["speed", "log"], True),
                     "/factors/speed/from: a log range needs from and to > 0")
        self.refused(changed(TRIKE, f + ["m"], {"values": [1]}), "/factors/m: factor 'm' changes nothing")

    def test_distributions(self):
        mc = changed(TRIKE, ["samples"], 4)
        f = ["factors", "m"]
        self.refused(changed(mc, f, {"distribution": "gaussian", "set": "t_end"}),
                     "/factors/m/distribution: unknown distribution 'gaussian' (expected: uniform, normal, lognormal)")
        self.refused(changed(mc, f, {"distribution": "normal", "mean": 1, "set": "t_end"}), "/factors/m: missing key 'sd'")
        self.refused(changed(mc, f, {"distribution": "normal", "mean": 1, "sd": 0, "set": "t_end"}),
                     "/factors/m/sd: expected a number > 0, found 0")
        self.refused(changed(mc, f, {"distribution": "uniform", "low": 2, "high": 1, "set": "t_end"}),
                     "/factors/m/high: expected high > low = 2")
        self.refused(changed(mc, f, {"distribution": "lognormal", "mean": -1, "sd": 1, "set": "t_end"}),
                     "/factors/m/mean: a lognormal value is > 0")
        self.refused(changed(mc, f, {"distribution": "uniform", "low": 1, "high": 2, "mean": 1, "set": "t_end"}),
                     "/factors/m/mean: unknown key 'mean' (expected: distribution, low, high, set)")
        self.refused(changed(TRIKE, f, {"distribution": "uniform", "low": 1, "high": 2, "set": "t_end"}),
                     '/factors/m: a factor with a distribution needs "samples"')
        self.refused(changed(TRIKE, ["samples"], 3), "/samples: without a factor with a distribution")
        self.refused(changed(mc, ["samples"], 3), "/samples: without a factor with a distribution")
        random = changed(mc, f, {"distribution": "uniform", "low": 1, "high": 2, "set": "t_end"})
        self.refused(changed(random, ["samples"], 0), "/samples: expected an integer >= 1, found 0")
        self.refused(changed(random, ["seed"], -1), "/seed: expected an integer >= 0, found -1")
        self.refused(changed(random, ["sampling"], "sobol"), "/sampling: unknown sampling 'sobol'")

    def test_set(self):
        s = ["set"]
        self.refused(changed(TRIKE, s + ["initial.qd.x"], "sped"),
                     "/set/initial.qd.x: in 'sped': unknown name 'sped' (factors: k, speed; and pi)")
        self.refused(changed(TRIKE, s + ["initial.qd.x"], "speed +"), "/set/initial.qd.x: 'speed +' is not an expression")
        self.refused(changed(TRIKE, s + ["initial.qd.x"], "__import__('os')"),
                     "/set/initial.qd.x: in '__import__('os')': '__import__('os')' is not allowed")
        self.refused(changed(TRIKE, s + ["initial.qd.x"], "speed.real"), "'speed.real' is not allowed")
        self.refused(changed(TRIKE, ["factors", "speed", "set"], "initial.qd.x"),
                     "/set/initial.qd.x: initial.qd.x is set twice (also at /factors/speed/set)")
        self.refused(changed(TRIKE, ["factors", "speed", "set"], []), "/factors/speed/set: expected a path")
        texts = changed(TRIKE, ["factors", "integrator"], {"values": ["cvode", "dop853"]})
        self.refused(changed(texts, s + ["integrator.name"], "integrator + 1"),
                     "/set/integrator.name: 'integrator' is a factor of texts: it can only be given alone")

    def test_against_the_scenario(self):
        """What only the scenario and its model know: checked by the engine before any run."""
        self.refused(changed(TRIKE, ["set", "forces.frnt.stiffness"], "k"),
                     "/set/forces.frnt.stiffness: no force element 'frnt' (elements: rear_suspension, rear_axle_roll,")
        self.refused(changed(TRIKE, ["set", "forces.front.stifness"], "k"),
                     "/set/forces.front.stifness: a simple_tyre has no member 'stifness' (members: enabled, body, radius,")
        self.refused(changed(TRIKE, ["factors", "k", "set"], ["parameters.k"]),
                     "/factors/k/set/0: unknown parameter 'k' (parameters of trike: none)")
        self.refused(changed(TRIKE, ["set", "initial.qd.q99"], 1), "/set/initial.qd.q99: unknown coordinate 'q99'")
        self.refused(changed(TRIKE, ["keep"], {"extremes": ["z"]}),
                     "/keep/extremes: unknown key 'extremes' (expected: final, values, extrema, at, checks, counters, series)")
        self.refused(changed(TRIKE, ["keep"], {"extrema": ["chassis.height"]}), "/keep/extrema/0: in 'minimum(chassis.height)'")
        self.refused(changed(TRIKE, ["keep"], {"at": {"times": [9], "of": ["yaw"]}}),
                     "/keep/at/of/0: in 'at(yaw, 9)' at column 1: at(): the time 9 is outside the run [0, t_end = 5]")
        self.refused(changed(TRIKE, ["keep"], {"values": {"speed": "end(x_dot)"}}),
                     "/keep: the column 'speed' is also a factor's or the table's own")

    def test_command_line(self):
        """symdyn-sim --sweep: a bad file is exit code 2 with the culprit on stderr, nothing written."""
        folder = scratch(self)
        path = write_json(folder, "bad.json", changed(TRIKE, ["set", "forces.frnt.stiffness"], "k"))
        done = run_cli("--sweep", path, "--workers", "1", cwd=folder)
        self.assertEqual(done.returncode, 2, done.stderr)
        self.assertIn(f"error: {path}: /set/forces.frnt.stiffness: no force element 'frnt'", done.stderr)
        self.assertEqual(os.listdir(folder), ["bad.json"])
        done = run_cli("--sweep", path, "--workers", "0", cwd=folder)
        self.assertEqual(done.returncode, 2)
        self.assertIn("--workers: expected an integer >= 1, found '0'", done.stderr)
        done = run_cli("--sweep", os.path.join(SWEEPS, "trike_tyres.json"), "--out", "t.txt", cwd=folder)
        self.assertEqual(done.returncode, 2)
        self.assertIn("--out t.txt: the file must end in .csv, .h5 or .hdf5", done.stderr)


class Runs(unittest.TestCase):
    def test_grid_order_first_factor_slowest(self):
        s = Sweep(TRIKE)
        self.assertEqual(s.runs, 6)
        self.assertEqual([s.inputs(r) for r in range(6)],
                         [[1e5, 3.0], [1e5, 5.0], [1e5, 7.0], [2e5, 3.0], [2e5, 5.0], [2e5, 7.0]])
        self.assertEqual(s.values(4), [2e5, 5.0, 5.0])

    def test_ranges_keep_their_ends(self):
        s = Sweep(changed(TRIKE, ["factors", "k"], {"from": 1e4, "to": 1e6, "count": 3, "log": True}))
        self.assertEqual([s.inputs(r)[0] for r in (0, 3, 6)], [1e4, 1e5, 1e6])
        s = Sweep(changed(TRIKE, ["factors", "speed"], {"from": 0.1, "to": 0.3, "count": 3}))
        self.assertEqual([s.inputs(r)[1] for r in range(3)], [0.1, 0.2, 0.3])

    def test_expressions_of_set(self):
        s = Sweep(changed(TRIKE, ["set", "initial.qd.left_spin"], "speed / 0.3 + 2^2 - sqrt(4)"))
        self.assertEqual(s.values(1)[-1], 5.0 / 0.3 + 4.0 - 2.0)
        s = Sweep(changed(TRIKE, ["set", "initial.qd.left_spin"], "1 / (speed - 5)"))
        with self.assertRaisesRegex(symdyn.sweep_file.RunInputError, "/set/initial.qd.left_spin: '1 / \\(speed - 5\\)' fails "
                                                                     "for this run: float division by zero"):
            s.values(1)

    def monte_carlo(self, **change):
        document = {"scenario": "slider_crank", "samples": 400, "seed": 11,
                    "factors": {"w": {"distribution": "normal", "mean": 50, "sd": 2, "set": "initial.qd.crank"},
                                "c": {"distribution": "lognormal", "mean": 0.5, "sd": 0.1, "set": "initial.q.crank"},
                                "u": {"distribution": "uniform", "low": -1, "high": 1, "set": "t_end"}}}
        document.update(change)
        return Sweep(document)

    def test_samples_follow_their_distributions(self):
        s = self.monte_carlo()
        w, c, u = zip(*(s.inputs(r) for r in range(s.runs)))
        self.assertAlmostEqual(statistics.fmean(w), 50, delta=4 * 2 / math.sqrt(400))
        self.assertAlmostEqual(statistics.stdev(w), 2, delta=0.3)
        self.assertAlmostEqual(statistics.fmean(c), 0.5, delta=4 * 0.1 / math.sqrt(400))
        self.assertAlmostEqual(statistics.stdev(c), 0.1, delta=0.02)
        self.assertTrue(all(-1 <= x < 1 for x in u))
        self.assertTrue(all(x > 0 for x in c))

    def test_truncated_normal_stays_in_its_bounds(self):
        s = self.monte_carlo(factors={"w": {"distribution": "normal", "mean": 0, "sd": 1, "low": 0.5, "high": 0.7,
                                            "set": "t_end"}})
        values = [s.inputs(r)[0] for r in range(s.runs)]
        self.assertTrue(all(0.5 <= v <= 0.7 for v in values))

    def test_a_sample_depends_on_the_seed_the_run_and_its_factor_alone(self):
        s = self.monte_carlo()
        self.assertEqual(s.inputs(7), self.monte_carlo().inputs(7))  # reproducible
        self.assertNotEqual(s.inputs(7), self.monte_carlo(seed=12).inputs(7))
        # More samples, or another factor added: the draws of the others do not move.
        more = self.monte_carlo(samples=800)
        self.assertEqual([s.inputs(r) for r in range(400)], [more.inputs(r) for r in range(400)])
        extra = self.monte_carlo()
        document = json.loads(json.dumps(extra.document))
        document["factors"]["v"] = {"distribution": "uniform", "low": 0, "high": 1, "set": "output_interval"}
        self.assertEqual(Sweep(document).inputs(5)[:3], s.inputs(5))
        self.assertEqual(s.run_seed(5), symdyn.sampling.run_seed(11, 5))

    def test_latin_hypercube_puts_one_sample_in_each_stratum(self):
        s = self.monte_carlo(sampling="latin_hypercube", samples=50)
        u = [s.inputs(r)[2] for r in range(50)]  # uniform on [-1, 1): strata of width 2/50
        self.assertEqual(sorted(int((x + 1) / (2 / 50)) for x in u), list(range(50)))

    def test_grid_times_samples(self):
        document = dict(TRIKE, samples=3, factors=dict(TRIKE["factors"], m={"distribution": "uniform", "low": 0,
                                                                              "high": 1, "set": "t_end"}))
        s = Sweep(document)
        self.assertEqual(s.runs, 18)
        self.assertEqual(s.inputs(4)[:2], [1e5, 5.0])  # grid point 1, sample 1
        self.assertEqual(s.inputs(17)[:2], [2e5, 7.0])

    def test_example_files_read(self):
        for name in sorted(os.listdir(SWEEPS)):
            path = os.path.join(SWEEPS, name)
            with open(path) as f:
                if "factors" in json.load(f):
                    Sweep.load(path)


if __name__ == "__main__":
    unittest.main()
