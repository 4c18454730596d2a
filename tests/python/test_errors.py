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
        nan_torque = dp.CoordinateForce("q0", lambda t, q, qd: math.nan, name="broken motor")
        with self.assertRaisesRegex(dp.NumericError, "broken motor"):
            dp.System([nan_torque]).accelerations()


class ArgumentErrors(unittest.TestCase):
    def test_state_of_the_wrong_size(self):
        with self.assertRaisesRegex(ValueError, r"q: 2 numbers expected, got an array of shape \(3\)"):
            dp.System().mass_matrix([0.0, 1.0, 2.0])

    def test_unknown_property(self):
        with self.assertRaisesRegex(TypeError, "SimpleTyre: unknown property 'radious'"):
            dp.SimpleTyre("rod2", radious=0.3)

    def test_python_exception_in_a_force_propagates(self):
        def law(t, q, qd):
            raise ZeroDivisionError("from the law")

        with self.assertRaisesRegex(ZeroDivisionError, "from the law"):
            dp.System([dp.CoordinateForce("q1", law)]).simulate(0.1)


class PythonForce(unittest.TestCase):
    def test_callable_equals_the_spring_it_imitates(self):
        spring = dp.System([dp.CoordinateSpringDamper("q1", 40.0, 0.3)])
        law = dp.System([dp.CoordinateForce("q1", lambda t, q, qd: -40.0 * q - 0.3 * qd)])
        a = spring.simulate(1.0, rtol=1e-9, atol=1e-9, interval=0.1)
        b = law.simulate(1.0, rtol=1e-9, atol=1e-9, interval=0.1)
        self.assertEqual(a.q.tolist(), b.q.tolist())


if __name__ == "__main__":
    unittest.main()
