"""Errors reach Python as exceptions naming the culprit: the runtime's
ModelError and OptionError as ValueError subclasses, NumericError as a
RuntimeError subclass, all with the runtime's message; the module's own
argument checks as ValueError or TypeError."""
import math
import unittest

import double_pendulum_absolute as dp
import double_pendulum_parameters as dpp


class RuntimeErrors(unittest.TestCase):
    def test_hierarchy(self):
        self.assertTrue(issubclass(dp.ModelError, ValueError))
        self.assertTrue(issubclass(dp.OptionError, ValueError))
        self.assertTrue(issubclass(dp.NumericError, RuntimeError))
        for e in (dp.ModelError, dp.OptionError, dp.NumericError):
            self.assertTrue(issubclass(e, dp.Error))

    def test_unknown_parameter(self):
        with self.assertRaisesRegex(dp.ModelError, "no parameter named 'stiffness'"):
            dp.System().set_parameter("stiffness", 1.0)

    def test_parameter_that_makes_a_body_unphysical(self):
        system = dpp.System()
        with self.assertRaisesRegex(dpp.ModelError, "rod2"):
            system.set_parameter("m2", -1.0)
        self.assertEqual(system.get_parameter("m2"), 1.0)  # the old value is kept

    def test_parameter_not_finite(self):
        with self.assertRaisesRegex(dpp.ModelError, "parameter 'l1' must be finite"):
            dpp.System().set_parameter("l1", math.nan)

    def test_unknown_coordinate_in_a_force(self):
        with self.assertRaisesRegex(dp.ModelError, "'q7'"):
            dp.System().add(dp.CoordinateSpringDamper("q7", 1.0))

    def test_unknown_body_in_a_force(self):
        with self.assertRaisesRegex(dp.ModelError, "'arm'"):
            dp.System([dp.PointLoad("arm", force=[0, 1, 0])])

    def test_unknown_integrator(self):
        with self.assertRaisesRegex(dp.OptionError, "unknown integrator 'euler'"):
            dp.System().simulate(1.0, integrator="euler")

    def test_bad_tolerance(self):
        with self.assertRaises(dp.OptionError):
            dp.System().simulate(1.0, rtol=-1.0)

    def test_force_that_is_not_finite(self):
        nan_torque = dp.CoordinateForce("theta1", lambda t, q, qd: math.nan, name="broken motor")
        with self.assertRaisesRegex(dp.NumericError, "broken motor"):
            dp.System([nan_torque]).accelerations()


class ForceElementConstants(unittest.TestCase):
    """Each constant of a force element is finite and of the sign its law
    needs: a ModelError naming the element and the property."""

    def refused(self, force, message):
        with self.assertRaisesRegex(dp.ModelError, message):
            dp.System([force])

    def test_negative_spring_stiffness(self):
        self.refused(dp.CoordinateSpringDamper("theta1", -10.0),
                     r"coordinate spring 'theta1': stiffness: expected a finite number >= 0, found -10")

    def test_nan_damping(self):
        self.refused(dp.CoordinateSpringDamper("theta2", 10.0, math.nan, name="hinge"),
                     r"coordinate spring 'hinge': damping: expected a finite number >= 0, found nan")

    def test_contact_without_stiffness(self):
        # The body would sink through the plane with zero force.
        self.refused(dp.PlaneContact("rod2", stiffness=0.0, name="tip"),
                     r"contact 'tip': stiffness: expected a finite number > 0, found 0")

    def test_contact_negative_friction(self):
        self.refused(dp.PlaneContact("rod2", stiffness=1e5, friction=-0.3),
                     r"contact 'rod2': friction: expected a finite number >= 0, found -0.3")

    def test_contact_plane_normal_zero(self):
        self.refused(dp.PlaneContact("rod2", stiffness=1e5, plane_normal=[0, 0, 0]),
                     r"contact 'rod2': plane_normal: expected a non-zero direction, found \(0, 0, 0\)")

    def test_tyre_axis_zero(self):
        self.refused(dp.SimpleTyre("rod2", axis=[0, 0, 0]),
                     r"tyre 'rod2': axis: expected a non-zero direction")

    def test_gim_tyre_section_wider_than_the_tyre(self):
        self.refused(dp.GimTyre("rod2", r1=0.3, r2=0.5),
                     r"Gim tyre 'rod2': r2: expected the section radius <= r1 = 0.3, found 0.5")

    def test_bushing_axes_not_a_rotation(self):
        self.refused(dp.Bushing("ground", "rod1", axes_a=[[2, 0, 0], [0, 1, 0], [0, 0, 1]]),
                     r"bushing 'rod1': a/axes: expected orthonormal axes")

    def test_bushing_negative_damping(self):
        self.refused(dp.Bushing("ground", "rod1", damping=[1, 1, -1]),
                     r"bushing 'rod1': damping: expected 3 finite numbers >= 0, found \(1, 1, -1\)")

    def test_point_load_infinite_force(self):
        self.refused(dp.PointLoad("rod2", force=[0, math.inf, 0]),
                     r"load 'rod2': force: expected 3 finite numbers, found \(0, inf, 0\)")

    def test_spring_negative_free_length(self):
        self.refused(dp.PointSpringDamper(None, [0, 0, 0], "rod2", [0, 0, 0], 100.0, -1.0),
                     r"spring 'rod2': free_length: expected a finite number >= 0, found -1")

    def test_tracking_reference_not_finite(self):
        with self.assertRaisesRegex(dp.ModelError, r"coordinate tracking 'theta1': reference: expected a finite number"):
            dp.CoordinateTracking("theta1", 100.0, 10.0, reference=math.nan)


class IntegratorOptions(unittest.TestCase):
    def test_infinite_tolerance(self):
        # Every step would be accepted: a silently wrong run.
        with self.assertRaisesRegex(dp.OptionError, "tolerances must be finite and positive"):
            dp.System().simulate(1.0, rtol=math.inf)

    def test_final_time_not_finite(self):
        with self.assertRaisesRegex(dp.OptionError, "the final time nan must be finite"):
            dp.System().simulate(math.nan)

    def test_interval_not_finite(self):
        with self.assertRaisesRegex(dp.OptionError, "output_interval inf must be finite"):
            dp.System().simulate(1.0, interval=math.inf)

    def test_output_times_out_of_order(self):
        with self.assertRaisesRegex(dp.OptionError, r"output times must increase \(0.2 after 0.5\)"):
            dp.System().simulate(1.0, times=[0.5, 0.2])


class ArgumentErrors(unittest.TestCase):
    def test_state_of_the_wrong_size(self):
        with self.assertRaisesRegex(ValueError, r"q: 2 numbers expected, got an array of shape \(3\)"):
            dp.System().mass_matrix([0.0, 1.0, 2.0])

    def test_state_not_finite(self):
        # positions() and the other kinematics returned NaN silently.
        with self.assertRaisesRegex(ValueError, r"q: coordinate 'theta2' is nan, not a finite number"):
            dp.System().positions([0.0, math.nan])
        with self.assertRaisesRegex(ValueError, r"qd: coordinate 'theta1' is inf, not a finite number"):
            dp.System().velocities([0.0, 0.0], [math.inf, 0.0])
        with self.assertRaisesRegex(ValueError, r"qdd: coordinate 'theta1' is nan"):
            dp.System().body_accelerations([0.0, 0.0], [0.0, 0.0], [math.nan, 0.0])
        with self.assertRaisesRegex(ValueError, r"t = nan is not a finite time"):
            dp.System().mass_matrix(t=math.nan)

    def test_simulate_from_a_state_not_finite(self):
        with self.assertRaisesRegex(ValueError, r"q: coordinate 'theta1' is nan"):
            dp.System().simulate(1.0, q0=[math.nan, 0.0])

    def test_unknown_property(self):
        with self.assertRaisesRegex(TypeError, r"SimpleTyre: unknown property 'radious' \(properties: radius, "
                                    r"stiffness, damping, friction, epsilon, axis, centre\); did you mean radius\?"):
            dp.SimpleTyre("rod2", radious=0.3)
        with self.assertRaisesRegex(TypeError, r"GimTyre: unknown property 'kz' .*; did you mean Kz or Cz\?"):
            dp.GimTyre("rod2", kz=2e5)
        with self.assertRaisesRegex(TypeError, r"Bushing: unknown property 'elasticity' \([^)]*\)$"):
            dp.Bushing(None, "rod1", elasticity=[1, 1, 1])

    def test_missing_required_constant(self):
        with self.assertRaisesRegex(TypeError, r"CoordinateSpringDamper: missing property 'stiffness' "
                                    r"\(a number >= 0, N/m or N·m/rad: k in Q = -k \(q - free_value\) - c qd\)"):
            dp.CoordinateSpringDamper("q0", damping=1.0)
        with self.assertRaisesRegex(TypeError, r"PointSpringDamper: missing property 'free_length'"):
            dp.PointSpringDamper(None, [0, 0, 0], "rod2", [0, 0, 0], 100.0)

    def test_constant_given_twice_or_too_many(self):
        with self.assertRaisesRegex(TypeError, r"CoordinateSpringDamper: 'stiffness' given twice"):
            dp.CoordinateSpringDamper("q0", 10.0, stiffness=5.0)
        with self.assertRaisesRegex(TypeError, r"CoordinateTracking: 3 constants given by position, at most 2 \(kp, kd\)"):
            dp.CoordinateTracking("q0", 1.0, 2.0, 3.0)

    def test_constant_out_of_its_range(self):
        self.assertRaisesRegex(dp.ModelError, r"tyre 'rod2': epsilon: expected a finite number > 0, found 0",
                               dp.System, [dp.SimpleTyre("rod2", epsilon=0.0)])

    def test_constructors_document_their_constants(self):
        self.assertIn("stiffness (a number >= 0, N/m or N·m/rad; required): k in Q", dp.CoordinateSpringDamper.__doc__)
        self.assertIn("r2 (a number > 0, m; default 0.1): section radius (<= r1)", dp.GimTyre.__doc__)
        self.assertIn("axis (a direction: 3 numbers not all 0; default [0, 1, 0]): the spin axis", dp.SimpleTyre.__doc__)

    def test_python_exception_in_a_force_propagates(self):
        def law(t, q, qd):
            raise ZeroDivisionError("from the law")

        with self.assertRaisesRegex(ZeroDivisionError, "from the law"):
            dp.System([dp.CoordinateForce("theta2", law)]).simulate(0.1)


class PythonForce(unittest.TestCase):
    def test_callable_equals_the_spring_it_imitates(self):
        spring = dp.System([dp.CoordinateSpringDamper("theta2", 40.0, 0.3)])
        law = dp.System([dp.CoordinateForce("theta2", lambda t, q, qd: -40.0 * q - 0.3 * qd)])
        a = spring.simulate(1.0, rtol=1e-9, atol=1e-9, interval=0.1)
        b = law.simulate(1.0, rtol=1e-9, atol=1e-9, interval=0.1)
        self.assertEqual(a.q.tolist(), b.q.tolist())


if __name__ == "__main__":
    unittest.main()
