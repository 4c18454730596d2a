"""The trike's Python module (models/trike.cpp): a run near the singularity of
its chassis' Z-Y-X angles (pitch = 90 deg) warns, naming the angles, in its
result and as a Python RuntimeWarning; a run well away from it does not.
"""
import math
import unittest
import warnings

import trike


def run_pitched(offset):
    """0.01 s of the free trike with its chassis pitched pi/2 - offset."""
    system = trike.System()
    q = list(system.q_initial)
    q[system.q_names.index("pitch")] = math.pi / 2 - offset
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run = system.simulate(0.01, q0=q, interval=0.01)
    return run, [w for w in caught if issubclass(w.category, RuntimeWarning)]


class Conditioning(unittest.TestCase):
    def test_near_the_lock_one_warning_naming_the_angles(self):
        run, caught = run_pitched(1e-6)
        self.assertEqual(len(run.warnings), 1)
        self.assertIn("'yaw', 'pitch', 'roll' of body 'chassis'", run.warnings[0])
        self.assertIn("lost more than half", run.warnings[0])
        self.assertEqual([str(w.message) for w in caught], run.warnings)

    def test_away_from_it_none(self):
        run, caught = run_pitched(0.3)
        self.assertEqual(run.warnings, [])
        self.assertEqual(caught, [])


if __name__ == "__main__":
    unittest.main()
