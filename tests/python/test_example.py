"""The example of docs/python.md, run as written there, its values checked
against the closed forms of test_double_pendulum.py."""
import contextlib
import io
import math
import os
import re
import unittest

import numpy as np

from test_double_pendulum import (UNIT, bias_forces, mass_matrix, potential_gradient,
                                  small_oscillation_frequencies)


def example_source():
    """The block of docs/python.md, which is this file (tests/docs/code_blocks.py)."""
    with open(os.path.join(os.path.dirname(__file__), "documented_example.py"), encoding="utf-8") as f:
        return f.read()


class DocumentedExample(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out = io.StringIO()
        cls.ns = {}
        with contextlib.redirect_stdout(cls.out):
            exec(compile(example_source(), "documented_example.py", "exec"), cls.ns)

    def test_equations_at_the_state(self):
        q, qd = self.ns["q"], self.ns["qd"]
        np.testing.assert_allclose(self.ns["M"], mass_matrix(q, **UNIT), rtol=1e-13)
        np.testing.assert_allclose(self.ns["h"], bias_forces(q, qd, **UNIT), rtol=1e-12)
        self.assertEqual(self.ns["R"].shape, (2, 3, 3))

    def test_free_run(self):
        run = self.ns["run"]
        self.assertEqual(run.q.shape, (301, 2))
        self.assertLess(self.ns["drift"], 1e-7 * np.max(run.energies.kinetic))

    def test_damped_run_loses_energy(self):
        self.assertTrue(np.all(np.diff(self.ns["damped"].energies.total) < 0))

    def test_equilibrium_balances_springs_and_weight(self):
        # Converged to |dq| <= 1e-8 (the default tolerance): |f| within stiffness times that.
        q = self.ns["equilibrium"].q
        np.testing.assert_allclose(np.array([30.0, 10.0]) * q + potential_gradient(q, **UNIT), [0, 0], atol=2e-6)
        self.assertEqual(len(self.ns["around"].natural_frequency_hz), 2)

    def test_hanging_frequencies(self):
        np.testing.assert_allclose(self.ns["hanging"].natural_frequency_hz,
                                   small_oscillation_frequencies(**UNIT), rtol=1e-8)
        # The comment in the example prints them to 4 digits.
        self.assertIn("[0.4266 1.1441]", self.out.getvalue())

    def test_error_names_the_coordinate(self):
        self.assertIn("'q2'", self.out.getvalue())


if __name__ == "__main__":
    unittest.main()
