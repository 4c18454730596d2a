"""The four-bar's Python module (models/four_bar.cpp, loop C solved at run
time): its implicit parameters against the two-circle intersection, body
accelerations against differences of velocities, and the force at C of the
crank held static against the coupler's and the rocker's moment balances,
written out here.
"""
import math
import unittest

import numpy as np

import four_bar as fb

R1, R2, R3, D = 0.1, 0.35, 0.3, 0.4
M2, M3 = 0.5, 0.4
G = np.array([0.0, -9.81])


def cross(r, f):
    return r[0] * f[1] - r[1] * f[0]


def closed_form(q0):
    """Joint C (circles about A, radius R2, and about D, radius R3, on the
    left of A -> D), with phi (the coupler relative to the crank) and psi."""
    a_pt = np.array([R1 * math.cos(q0), R1 * math.sin(q0)])
    d_pt = np.array([D, 0.0])
    e = np.linalg.norm(d_pt - a_pt)
    a = (R2**2 - R3**2 + e**2) / (2 * e)
    h = math.sqrt(R2**2 - a**2)
    u = (d_pt - a_pt) / e
    c_pt = a_pt + a * u + h * np.array([-u[1], u[0]])
    phi = math.atan2(c_pt[1] - a_pt[1], c_pt[0] - a_pt[0]) - q0
    psi = math.atan2(c_pt[1], c_pt[0] - D)
    return a_pt, c_pt, d_pt, phi, psi


class FourBar(unittest.TestCase):
    def test_facts(self):
        self.assertEqual((fb.nq, fb.nindependent), (3, 1))
        self.assertEqual(fb.q_names, ("crank", "phi", "psi"))
        self.assertEqual(fb.loop_names, ("C",))
        self.assertEqual(fb.loop_reaction_names, ("C.Fx", "C.Fy"))

    def test_implicit_parameters(self):
        system = fb.System()
        # Each solve from the last solution, moved along dp/dq0: a whole turn in steps.
        for q0 in np.linspace(0.0, 2 * math.pi, 13):
            p, _, _ = system.implicit_parameters([q0], [0.0], [0.0])
            _, _, _, phi, psi = closed_form(q0)
            wrap = lambda angle: math.remainder(angle, 2 * math.pi)
            self.assertAlmostEqual(wrap(p[0] - phi), 0.0, delta=1e-10)
            self.assertAlmostEqual(wrap(p[1] - psi), 0.0, delta=1e-10)

    def test_body_accelerations_against_differences(self):
        system = fb.System()
        q0, qd0, qdd0, h = 0.9, 4.0, -30.0, 1e-5
        system.set_loop_guess(closed_form(q0)[3:])
        a, dw = system.body_accelerations([q0], [qd0], [qdd0])
        # Along q(t) = q0 + qd0 t + qdd0 t^2 / 2, central differences of v and w.
        ahead = system.velocities([q0 + qd0 * h + qdd0 * h * h / 2], [qd0 + qdd0 * h])
        behind = system.velocities([q0 - qd0 * h + qdd0 * h * h / 2], [qd0 - qdd0 * h])
        np.testing.assert_allclose(a, (ahead[0] - behind[0]) / (2 * h), atol=1e-5)
        np.testing.assert_allclose(dw, (ahead[1] - behind[1]) / (2 * h), atol=1e-5)

    def test_force_at_c_held_static(self):
        for q0 in (0.4, 2.0, 4.2):
            # The torque that holds the crank: M qdd = Q - h with qd = 0, qdd = 0.
            guess = closed_form(q0)[3:]
            free = fb.System()
            free.set_loop_guess(guess)
            tau = free.bias_forces([q0], [0.0])[0]
            system = fb.System(forces=[fb.CoordinateForce("crank", lambda t, q, qd: tau)])
            system.set_loop_guess(guess)
            self.assertLess(abs(system.accelerations([q0], [0.0])[0]), 1e-9)
            a_pt, c_pt, d_pt, _, _ = closed_form(q0)
            # F, the coupler's force on the rocker at C: the rocker's moments
            # about D and the coupler's about A (which receives -F) vanish.
            g2, g3 = (a_pt + c_pt) / 2, (c_pt + d_pt) / 2
            rows = np.array([[-(c_pt - d_pt)[1], (c_pt - d_pt)[0]],
                             [(c_pt - a_pt)[1], -(c_pt - a_pt)[0]]])
            rhs = -np.array([cross(g3 - d_pt, M3 * G), cross(g2 - a_pt, M2 * G)])
            force = np.linalg.solve(rows, rhs)
            np.testing.assert_allclose(system.loop_reactions([q0], [0.0]), force,
                                       atol=1e-9 * (1 + np.linalg.norm(force)))
            # The free hinges of the coupler and the rocker transmit no moment.
            joints = system.joint_reactions([q0], [0.0])
            self.assertLess(abs(joints[1, 5]), 1e-9)
            self.assertLess(abs(joints[2, 5]), 1e-9)
            self.assertAlmostEqual(joints[0, 5], tau, delta=1e-9 * (1 + abs(tau)))


if __name__ == "__main__":
    unittest.main()
