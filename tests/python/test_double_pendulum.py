"""The double pendulum's Python module against closed forms (docs/models.md 1).

Rods of mass m_i and length l_i, centre of gravity at mid-length, inertia about
z m_i l_i^2 / 12; theta1 the angle of rod 1, theta2 that of rod 2 relative to rod 1;
gravity g along -y. With c1 = cos theta2, a = m2 l1 l2 sin theta2:
  M00 = m1 l1^2/3 + m2 (l1^2 + l2^2/3 + l1 l2 c1)
  M01 = m2 (l2^2/3 + l1 l2 c1/2),  M11 = m2 l2^2/3
  V   = g (m1 l1/2 sin theta1 + m2 (l1 sin theta1 + l2/2 sin(theta1 + theta2)))
  h   = dV/dq + (-a (q0d q1d + q1d^2/2), a q0d^2/2)   (Christoffel terms of M)
"""
import math
import unittest

import numpy as np

import double_pendulum_absolute
import double_pendulum_parameters

G = 9.81


def mass_matrix(q, m1, m2, l1, l2):
    c1 = math.cos(q[1])
    m00 = m1 * l1**2 / 3 + m2 * (l1**2 + l2**2 / 3 + l1 * l2 * c1)
    m01 = m2 * (l2**2 / 3 + l1 * l2 * c1 / 2)
    return np.array([[m00, m01], [m01, m2 * l2**2 / 3]])


def potential_gradient(q, m1, m2, l1, l2):
    c0, c01 = math.cos(q[0]), math.cos(q[0] + q[1])
    return G * np.array([(m1 * l1 / 2 + m2 * l1) * c0 + m2 * l2 / 2 * c01, m2 * l2 / 2 * c01])


def bias_forces(q, qd, m1, m2, l1, l2):
    a = m2 * l1 * l2 * math.sin(q[1])
    coriolis = np.array([-a * (qd[0] * qd[1] + qd[1] ** 2 / 2), a * qd[0] ** 2 / 2])
    return potential_gradient(q, m1, m2, l1, l2) + coriolis


def energy(q, qd, m1, m2, l1, l2):
    """Total energy T + V of each row of q, qd (closed form)."""
    kinetic = np.array([0.5 * v @ mass_matrix(x, m1, m2, l1, l2) @ v for x, v in zip(q, qd)])
    s0, s01 = np.sin(q[:, 0]), np.sin(q[:, 0] + q[:, 1])
    return kinetic + G * (m1 * l1 / 2 * s0 + m2 * (l1 * s0 + l2 / 2 * s01))


def small_oscillation_frequencies(m1, m2, l1, l2):
    """Hanging down (theta1 = -pi/2, theta2 = 0): roots of det(K - w^2 M) = 0, in Hz."""
    M = mass_matrix([0.0, 0.0], m1, m2, l1, l2)
    k00 = G * (m1 * l1 / 2 + m2 * l1 + m2 * l2 / 2)
    k01 = k11 = G * m2 * l2 / 2
    a = M[0, 0] * M[1, 1] - M[0, 1] ** 2
    b = -(M[0, 0] * k11 + M[1, 1] * k00 - 2 * M[0, 1] * k01)
    c = k00 * k11 - k01**2
    roots = [(-b - s * math.sqrt(b * b - 4 * a * c)) / (2 * a) for s in (1, -1)]
    return sorted(math.sqrt(r) / (2 * math.pi) for r in roots)


UNIT = dict(m1=1.0, m2=1.0, l1=1.0, l2=1.0)
OTHER = dict(m1=1.5, m2=0.8, l1=1.2, l2=0.7)


class ModelFacts(unittest.TestCase):
    def test_names_sizes_and_initial_state(self):
        dp = double_pendulum_absolute
        self.assertEqual(dp.q_names, ("theta1", "theta2"))
        self.assertEqual(dp.body_names, ("rod1", "rod2"))
        self.assertEqual((dp.nq, dp.nbody, dp.ndep, dp.nparam), (2, 2, 0, 0))
        np.testing.assert_array_equal(dp.q_initial, [0.0, 0.0])
        np.testing.assert_array_equal(dp.gravity, [0.0, -G, 0.0])
        self.assertEqual(dp.System().nq, 2)

    def test_parameters_get_and_set(self):
        system = double_pendulum_parameters.System()
        self.assertEqual(system.parameters, UNIT)
        system.set_parameters(OTHER)
        self.assertEqual(system.get_parameter("l1"), 1.2)
        self.assertEqual(system.parameters, OTHER)


class Kinematics(unittest.TestCase):
    def test_positions_velocities(self):
        q, qd = np.array([0.3, -1.1]), np.array([0.7, 2.0])
        R, x = double_pendulum_absolute.System().positions(q)
        self.assertEqual((R.shape, x.shape), ((2, 3, 3), (2, 3)))
        a = q[0] + q[1]
        np.testing.assert_allclose(R[1], [[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]], atol=1e-15)
        np.testing.assert_allclose(x[1], [math.cos(q[0]) + math.cos(a) / 2, math.sin(q[0]) + math.sin(a) / 2, 0], atol=1e-15)
        v, w = double_pendulum_absolute.System().velocities(q, qd)
        np.testing.assert_allclose(w[1], [0, 0, qd[0] + qd[1]], atol=1e-15)
        dx = [-math.sin(q[0]) * qd[0] - math.sin(a) / 2 * (qd[0] + qd[1]),
              math.cos(q[0]) * qd[0] + math.cos(a) / 2 * (qd[0] + qd[1]), 0]
        np.testing.assert_allclose(v[1], dx, atol=1e-14)


class EquationsOfMotion(unittest.TestCase):
    STATES = [([0.0, 0.0], [0.0, 0.0]), ([0.3, -1.1], [0.7, 2.0]), ([2.5, 3.0], [-1.5, 0.4])]

    def check(self, system, p):
        for q, qd in self.STATES:
            M = mass_matrix(q, **p)
            np.testing.assert_allclose(system.mass_matrix(q), M, rtol=1e-13, atol=1e-13)
            h = bias_forces(q, qd, **p)
            np.testing.assert_allclose(system.bias_forces(q, qd), h, rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(system.accelerations(q, qd), np.linalg.solve(M, -h), rtol=1e-11, atol=1e-11)

    def test_reference_model_against_closed_form(self):
        self.check(double_pendulum_absolute.System(), UNIT)

    def test_changed_parameters_against_closed_form(self):
        system = double_pendulum_parameters.System()
        system.set_parameters(OTHER)
        self.check(system, OTHER)


class JointReactions(unittest.TestCase):
    def test_hanging_at_rest_each_rod_carries_its_weight(self):
        # Hanging straight down at rest: qdd = 0, every body moves from the
        # ground, so each rod's reaction is all its pins give it: its own
        # weight, up, which is -x in its axes; no moment about its joint point.
        reaction = double_pendulum_absolute.System().joint_reactions([-math.pi / 2, 0.0], [0, 0])
        self.assertEqual(reaction.shape, (2, 6))
        np.testing.assert_allclose(reaction, [[-G, 0, 0, 0, 0, 0]] * 2, atol=1e-12)


class Simulation(unittest.TestCase):
    def test_free_run_conserves_energy(self):
        system = double_pendulum_absolute.System()
        r = system.simulate(3.0, integrator="dopri5", rtol=1e-10, atol=1e-10, interval=0.01)
        self.assertEqual(r.q.shape, (301, 2))
        self.assertEqual(r.qdd.shape, (301, 2))
        np.testing.assert_allclose(r.t, np.linspace(0.0, 3.0, 301), atol=1e-12)
        self.assertGreater(r.statistics.steps, 0)
        # The recorded energies are those of the closed form at the recorded states.
        e = energy(r.q, r.qd, **UNIT)
        np.testing.assert_allclose(r.energies.total, e, atol=1e-11)
        # Conserved to the tolerance's order, relative to the largest kinetic energy.
        drift = np.max(np.abs(e - e[0])) / np.max(r.energies.kinetic)
        self.assertLess(drift, 1e-7)
        self.assertGreater(np.max(r.energies.kinetic), 10.0)

    def test_output_times_and_an_implicit_integrator(self):
        system = double_pendulum_absolute.System()
        start = dict(q0=[-1.2, 0.3], qd0=[0.0, 0.0])
        reference = system.simulate(1.0, integrator="dop853", rtol=1e-12, atol=1e-12, times=[0.5, 1.0], **start)
        newmark = system.simulate(1.0, integrator="newmark", rtol=1e-8, atol=1e-8, times=[0.5, 1.0], **start)
        np.testing.assert_array_equal(newmark.t, [0.0, 0.5, 1.0])
        np.testing.assert_array_equal(newmark.q[0], [-1.2, 0.3])
        np.testing.assert_allclose(newmark.q, reference.q, atol=1e-5)
        self.assertEqual(newmark.integrator, "newmark")
        self.assertGreater(newmark.statistics.jacobian_evaluations, 0)

    def test_global_tolerance_by_step_halving(self):
        system = double_pendulum_absolute.System()
        start = dict(q0=[-1.2, 0.3], qd0=[0.0, 0.0])
        reference = system.simulate(1.0, integrator="dop853", rtol=1e-13, atol=1e-13, times=[1.0], **start)
        plain = system.simulate(1.0, integrator="rk4", step=0.05, times=[1.0], **start)
        self.assertTrue(np.isnan(plain.statistics.global_error_estimate))
        self.assertFalse(plain.statistics.global_tolerance_met)
        r = system.simulate(1.0, integrator="rk4", step=0.05, times=[1.0], global_tolerance=1e-7, **start)
        self.assertTrue(r.statistics.global_tolerance_met)
        self.assertGreaterEqual(r.statistics.runs, 3)
        self.assertLessEqual(r.statistics.global_error_estimate, 1e-7)
        error = max(np.max(np.abs(r.q[-1] - reference.q[-1])), np.max(np.abs(r.qd[-1] - reference.qd[-1])))
        self.assertLess(error, 1e-7)

    def test_step_halving_extrapolates(self):
        # newmark's trapezoidal rule extrapolated: fourth order from runs at 8e-3 to 1e-3 s.
        system = double_pendulum_absolute.System()
        start = dict(q0=[-1.2, 0.3], qd0=[0.0, 0.0])
        reference = system.simulate(1.0, integrator="dop853", rtol=1e-13, atol=1e-13, times=[1.0], **start)
        r = system.simulate(1.0, integrator="newmark", fixed_step=True, step=8e-3, times=[1.0],
                            global_tolerance=1e-6, **start)
        self.assertTrue(r.statistics.global_tolerance_met)
        self.assertTrue(r.statistics.extrapolated)
        error = max(np.max(np.abs(r.q[-1] - reference.q[-1])), np.max(np.abs(r.qd[-1] - reference.qd[-1])))
        self.assertLess(error, 1e-6)
        self.assertLess(error, 10 * r.statistics.global_error_estimate)
        self.assertLess(r.statistics.global_error_estimate, 10 * error)

    def test_damping_dissipates(self):
        system = double_pendulum_absolute.System()
        friction = double_pendulum_absolute.CoordinateSpringDamper("theta2", stiffness=0.0, damping=0.5)
        r = system.simulate(3.0, rtol=1e-9, atol=1e-9, interval=0.5, forces=[friction])
        self.assertTrue(np.all(np.diff(r.energies.total) < 0))
        self.assertEqual(system.forces, [])  # the call's forces were its own


class StaticsAndModes(unittest.TestCase):
    def test_statics_of_the_pendulum_with_springs(self):
        dp = double_pendulum_parameters
        system = dp.System([dp.CoordinateSpringDamper("theta1", 30.0), dp.CoordinateSpringDamper("theta2", 10.0)])
        system.set_parameters(OTHER)
        result = system.solve_statics(q=[0.0, 0.0], tolerance=1e-12)
        q = result.q
        # Springs balance the weight: k q + dV/dq = 0.
        np.testing.assert_allclose(np.array([30.0, 10.0]) * q + potential_gradient(q, **OTHER), [0, 0], atol=1e-9)
        self.assertLess(q[0], -0.1)

    def test_locked_coordinate(self):
        dp = double_pendulum_absolute
        system = dp.System([dp.CoordinateSpringDamper("theta1", 50.0)])
        q = system.solve_statics(locked=["theta2"], tolerance=1e-12).q
        self.assertEqual(q[1], 0.0)
        # One rigid bar: 50 theta1 + g (1/2 + 3/2) cos theta1 = 0.
        self.assertAlmostEqual(50.0 * q[0] + 2.0 * G * math.cos(q[0]), 0.0, places=9)

    def test_hanging_frequencies_against_small_oscillations(self):
        for module, p in ((double_pendulum_absolute, UNIT), (double_pendulum_parameters, OTHER)):
            system = module.System()
            if p is OTHER:
                system.set_parameters(p)
            down = [-math.pi / 2, 0.0]
            modes = system.modes(q=down)
            np.testing.assert_allclose(modes.natural_frequency_hz, small_oscillation_frequencies(**p), rtol=1e-8)
            np.testing.assert_allclose(modes.damping_ratio, [0.0, 0.0], atol=1e-7)
            lin = system.linearize(q=down)
            np.testing.assert_allclose(lin.M, mass_matrix([0.0, 0.0], **p), rtol=1e-13)
            self.assertEqual(lin.A.shape, (4, 4))
            self.assertEqual(lin.coordinates, ["theta1", "theta2"])


class Derivatives(unittest.TestCase):
    def test_continuous_time_A_and_B_against_closed_forms(self):
        # qdd = M(q)^-1 (u - h(q, qd)): A and B from Richardson-extrapolated differences of the
        # closed form, independent of the module; the module's exact where generated with DERIVATIVES.
        system = double_pendulum_absolute.System()
        q, qd = np.array([0.3, -0.7]), np.array([1.1, -0.4])
        d = system.dynamics_derivatives(q=q, qd=qd)
        self.assertEqual(d.method, "exact (emitted derivatives)")

        def qdd(x):
            return np.linalg.solve(mass_matrix(x[:2], **UNIT), -bias_forces(x[:2], x[2:], **UNIT))

        def richardson(f, x, j, h=1e-3):
            def central(step):
                e = np.zeros_like(x)
                e[j] = step
                return (f(x + e) - f(x - e)) / (2 * step)

            return (4 * central(h / 2) - central(h)) / 3

        x = np.concatenate([q, qd])
        expected = np.column_stack([richardson(qdd, x, j) for j in range(4)])
        np.testing.assert_allclose(d.qdd, qdd(x), rtol=1e-12)
        np.testing.assert_allclose(d.A[2:, :], expected, rtol=1e-8, atol=1e-8)
        np.testing.assert_allclose(d.A[:2, :], np.hstack([np.zeros((2, 2)), np.eye(2)]))
        np.testing.assert_allclose(d.B[2:, :], np.linalg.inv(mass_matrix(q, **UNIT)), rtol=1e-12)
        np.testing.assert_allclose(d.B[:2, :], np.zeros((2, 2)))

    def test_rk4_step_derivatives_against_differences(self):
        system = double_pendulum_absolute.System()
        q, qd, u, h = np.array([0.3, -0.7]), np.array([1.1, -0.4]), np.array([0.5, -0.2]), 0.02
        d = system.step_derivatives(q=q, qd=qd, u=u, h=h)

        def step(x, v):
            e = system.step_derivatives(q=x[:2], qd=x[2:], u=v, h=h)
            return np.concatenate([e.q, e.qd])

        x = np.concatenate([q, qd])
        eye4, eye2 = np.eye(4), np.eye(2)

        def richardson(f, k):
            def central(s):
                return (f(s) - f(-s)) / (2 * s)

            return (4 * central(5e-4) - central(1e-3)) / 3

        A = np.column_stack([richardson(lambda s: step(x + s * eye4[j], u), j) for j in range(4)])
        B = np.column_stack([richardson(lambda s: step(x, u + s * eye2[j]), j) for j in range(2)])
        np.testing.assert_allclose(d.A, A, rtol=1e-8, atol=1e-9)
        np.testing.assert_allclose(d.B, B, rtol=1e-8, atol=1e-9)
        self.assertAlmostEqual(d.t, h)


if __name__ == "__main__":
    unittest.main()
