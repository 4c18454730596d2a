"""Force elements built from Python, on the double pendulum (rods of unit
length and mass), against the virtual work of their forces written out here:
Q_j = F . dP/dq_j for a force F at a point P. The rod 2 tip is
P = (c0 + c01, s0 + s01) and its centre C = (c0 + c01/2, s0 + s01/2)."""
import math
import unittest

import numpy as np

import double_pendulum_absolute as dp

Q = np.array([-1.2, -0.3])


def tip(q):
    return np.array([math.cos(q[0]) + math.cos(q[0] + q[1]), math.sin(q[0]) + math.sin(q[0] + q[1]), 0.0])


def tip_jacobian(q):
    """Columns dP/dq0, dP/dq1 (3 x 2)."""
    s0, s01, c0, c01 = math.sin(q[0]), math.sin(q[0] + q[1]), math.cos(q[0]), math.cos(q[0] + q[1])
    return np.array([[-s0 - s01, -s01], [c0 + c01, c01], [0.0, 0.0]])


def centre_jacobian(q):
    s0, s01, c0, c01 = math.sin(q[0]), math.sin(q[0] + q[1]), math.cos(q[0]), math.cos(q[0] + q[1])
    return np.array([[-s0 - s01 / 2, -s01 / 2], [c0 + c01 / 2, c01 / 2], [0.0, 0.0]])


def applied(force, q=Q):
    return dp.System([force]).applied_forces(q, [0.0, 0.0])


class Forces(unittest.TestCase):
    def test_coordinate_tracking(self):
        f = dp.CoordinateTracking("theta2", kp=100.0, kd=3.0, reference=0.2, rate=0.1)
        Qa = dp.System([f]).applied_forces(Q, [0.0, 0.5])
        np.testing.assert_allclose(Qa, [0.0, -100.0 * (Q[1] - 0.2) - 3.0 * (0.5 - 0.1)], rtol=1e-14)

    def test_point_load_at_the_tip(self):
        F = np.array([3.0, -10.0, 0.0])
        f = dp.PointLoad("rod2", point=[0.5, 0.0, 0.0], force=F)
        np.testing.assert_allclose(applied(f), F @ tip_jacobian(Q), rtol=1e-13)

    def test_point_spring_from_the_ground_to_the_tip(self):
        anchor, k, L0 = np.array([0.5, -3.0, 0.0]), 200.0, 0.4
        f = dp.PointSpringDamper(None, anchor, "rod2", [0.5, 0.0, 0.0], stiffness=k, free_length=L0)
        d = tip(Q) - anchor
        L = np.linalg.norm(d)
        np.testing.assert_allclose(applied(f), -k * (L - L0) * (d / L) @ tip_jacobian(Q), rtol=1e-12)
        e = dp.System([f]).energies(Q, [0.0, 0.0])
        self.assertAlmostEqual(e["elastic"], 0.5 * k * (L - L0) ** 2, places=10)

    def test_plane_contact_of_the_tip(self):
        # Plane y = tip_y + 0.03 facing +y: penetration 0.03, no sliding at rest.
        plane_y = tip(Q)[1] + 0.03
        f = dp.PlaneContact("rod2", point=[0.5, 0.0, 0.0], stiffness=1e4, friction=0.5,
                            plane_point=[0.0, plane_y, 0.0], plane_normal=[0.0, 1.0, 0.0])
        np.testing.assert_allclose(applied(f), [0.0, 1e4 * 0.03, 0.0] @ tip_jacobian(Q), rtol=1e-10)

    def test_simple_tyre_on_rod2(self):
        # Wheel of radius 0.3 at rod 2's centre spinning about z; ground 0.01 into it.
        centre_y = math.sin(Q[0]) + math.sin(Q[0] + Q[1]) / 2
        f = dp.SimpleTyre("rod2", radius=0.3, stiffness=2e4, damping=0.0, axis=[0, 0, 1],
                          plane_point=[0.0, centre_y - 0.29, 0.0], plane_normal=[0.0, 1.0, 0.0])
        np.testing.assert_allclose(applied(f), [0.0, 2e4 * 0.01, 0.0] @ centre_jacobian(Q), rtol=1e-9)

    def test_gim_tyre_on_rod2(self):
        # At rest, no slip and no camber: only the vertical force Kz pen.
        centre_y = math.sin(Q[0]) + math.sin(Q[0] + Q[1]) / 2
        f = dp.GimTyre("rod2", r1=0.3, r2=0.05, Kz=3e4, axis=[0, 0, 1],
                       plane_point=[0.0, centre_y - 0.29, 0.0], plane_normal=[0.0, 1.0, 0.0])
        np.testing.assert_allclose(applied(f), [0.0, 3e4 * 0.01, 0.0] @ centre_jacobian(Q), rtol=1e-9)

    def test_bushing_at_the_hinge(self):
        # Frame A on the ground at the hinge, B on rod 1 at its end (G - l1/2 x):
        # no translation, a rotation theta1 about z, resisted by K_rz.
        f = dp.Bushing(None, "rod1", origin_b=[-0.5, 0.0, 0.0], rotational_stiffness=[0.0, 0.0, 40.0])
        np.testing.assert_allclose(applied(f), [-40.0 * Q[0], 0.0], rtol=1e-12, atol=1e-12)

    def test_forces_resolve_against_each_system(self):
        f = dp.PointLoad("rod2", force=[0.0, -1.0, 0.0], name="weight")
        a, b = dp.System(), dp.System()
        a.add(f)
        b.add(f)
        self.assertEqual(a.forces, ["load 'weight'"])
        self.assertEqual(repr(f), "PointLoad('weight')")

    def test_coordinate_force_with_its_derivatives(self):
        # Q = -5 q^3 - 0.7 qd |qd| on theta2: with its derivatives the Jacobians are exact and
        # equal Richardson differences of the accelerations; without, the law is differenced
        # and named; a wrong derivative is caught by the same comparison.
        def law(t, q, qd):
            return -5.0 * q**3 - 0.7 * qd * abs(qd)

        def derivatives(t, q, qd):
            return -15.0 * q**2, -1.4 * abs(qd)

        exact = dp.CoordinateForce("theta2", law, name="cubic", derivatives=derivatives)
        plain = dp.CoordinateForce("theta2", law, name="cubic")
        wrong = dp.CoordinateForce("theta2", law, name="cubic", derivatives=lambda t, q, qd: (0.0, 0.0))
        system = dp.System()
        x = np.array([0.4, -0.9, 1.3, -0.8])

        def qdd(y):
            return system.accelerations(q=y[:2], qd=y[2:], forces=[plain])

        def richardson(j, h=1e-3):
            def central(step):
                e = np.zeros_like(x)
                e[j] = step
                return (qdd(x + e) - qdd(x - e)) / (2 * step)

            return (4 * central(h / 2) - central(h)) / 3

        expected = np.column_stack([richardson(j) for j in range(4)])
        d = system.dynamics_derivatives(q=x[:2], qd=x[2:], forces=[exact])
        self.assertEqual(d.method, "exact (emitted derivatives)")
        np.testing.assert_allclose(d.A[2:, :], expected, rtol=1e-8, atol=1e-8)
        p = system.dynamics_derivatives(q=x[:2], qd=x[2:], forces=[plain])
        self.assertEqual(p.method, "exact (emitted derivatives), but by central differences for coordinate force 'cubic'")
        np.testing.assert_allclose(p.A[2:, :], expected, rtol=1e-6, atol=1e-6)
        w = system.dynamics_derivatives(q=x[:2], qd=x[2:], forces=[wrong])
        self.assertGreater(np.abs(w.A[2:, :] - expected).max(), 0.1)
        with self.assertRaisesRegex(TypeError, "CoordinateForce 'cubic': derivatives must return"):
            bad = dp.CoordinateForce("theta2", law, name="cubic", derivatives=lambda t, q, qd: 1.0)
            system.dynamics_derivatives(q=x[:2], qd=x[2:], forces=[bad])


if __name__ == "__main__":
    unittest.main()
