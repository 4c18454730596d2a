"""The slider-crank's Python module (docs/models.md 3): dependent parameters
and motion against the loop closure, written out here.

  alpha = asin(l1 sin q0 / l2),  x = l1 cos q0 + l2 cos alpha
"""
import math
import unittest

import numpy as np

import slider_crank_dependent as sc

L1, L2 = 0.1, 0.3


def closure(q0):
    alpha = math.asin(L1 * math.sin(q0) / L2)
    return np.array([alpha, L1 * math.cos(q0) + L2 * math.cos(alpha)])


class SliderCrank(unittest.TestCase):
    def test_facts(self):
        self.assertEqual((sc.nq, sc.nbody, sc.ndep), (1, 3, 2))
        self.assertEqual(sc.body_names, ("crank", "rod", "slider"))
        np.testing.assert_array_equal(sc.qd_initial, [50.0])

    def test_dependent_parameters_and_rates(self):
        system = sc.System()
        q0, qd0, step = 0.7, 3.0, 1e-5
        p, pd, _ = system.dependent_parameters([q0], [qd0], [0.0])
        np.testing.assert_allclose(p, closure(q0), rtol=1e-14)
        # pd = dp/dq0 qd0, by central differences.
        slope = (closure(q0 + step) - closure(q0 - step)) / (2 * step)
        np.testing.assert_allclose(pd, slope * qd0, rtol=1e-8)

    def test_slider_moves_with_x(self):
        system = sc.System()
        _, x = system.positions([1.2])
        np.testing.assert_allclose(x[2], [closure(1.2)[1], 0.0, 0.0], atol=1e-15)

    def test_mass_matrix_is_twice_the_kinetic_energy(self):
        system = sc.System()
        for q0 in (0.0, 0.4, 2.0):
            M = system.mass_matrix([q0])
            e = system.energies([q0], [1.0])
            self.assertAlmostEqual(M[0, 0], 2.0 * e["kinetic"], places=13)

    def test_free_run_conserves_energy_and_closure(self):
        r = sc.System().simulate(0.5, integrator="dop853", rtol=1e-10, atol=1e-10, interval=0.01)
        drift = np.max(np.abs(r.energies.total - r.energies.total[0])) / np.max(r.energies.kinetic)
        self.assertLess(drift, 1e-8)
        self.assertGreater(r.q[-1, 0], 10.0)  # several crank turns


if __name__ == "__main__":
    unittest.main()
