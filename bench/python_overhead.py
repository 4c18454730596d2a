"""What the Python module adds to the runtime, on the double pendulum
(docs/python.md): microseconds per call of the evaluation methods, and a free
run of symdyn-sim's double pendulum scenario (10 s, dopri5, tolerance 1e-10,
outputs every 10 ms) bare, with a compiled joint damper, and with the same
damper as a Python callable.

  PYTHONPATH=build/release/python /usr/bin/python3 bench/python_overhead.py
"""
import time
import timeit

import numpy as np

import double_pendulum_absolute as dp


def per_call_us(statement, scope, number=20000):
    best = min(timeit.repeat(statement, globals=scope, number=number, repeat=7))
    return 1e6 * best / number


def run_seconds(system, **kwargs):
    best, result = float("inf"), None
    for _ in range(20):
        start = time.perf_counter()
        result = system.simulate(10.0, integrator="dopri5", rtol=1e-10, atol=1e-10, interval=0.01, **kwargs)
        best = min(best, time.perf_counter() - start)
    return best, result


def main():
    system = dp.System()
    q, qd = np.array([0.3, -1.1]), np.array([0.7, 2.0])
    scope = {"system": system, "q": q, "qd": qd}
    print("| call | us per call |")
    print("|---|---:|")
    for call in ("system.mass_matrix(q)", "system.bias_forces(q, qd)", "system.accelerations(q, qd)",
                 "system.positions(q)", "system.energies(q, qd)"):
        print(f"| `{call}` | {per_call_us(call, scope):.2f} |")
    print()
    print("| run | wall s (best of 20) | steps | rhs evaluations | us per rhs evaluation |")
    print("|---|---:|---:|---:|---:|")
    damper = dp.CoordinateSpringDamper("theta2", 0.0, 0.05)
    law = dp.CoordinateForce("theta2", lambda t, q, qd: -0.05 * qd)
    for label, forces in (("free", []), ("compiled damper on theta2", [damper]), ("Python damper on theta2", [law])):
        seconds, r = run_seconds(system, forces=forces)
        n = r.statistics.rhs_evaluations
        print(f"| {label} | {seconds:.4f} | {r.statistics.steps} | {n} | {1e6 * seconds / n:.2f} |")


if __name__ == "__main__":
    main()
