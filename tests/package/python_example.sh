#!/usr/bin/env bash
# A project of its own asks for a Python module of its model from installed symdyn:
# find_package(symdyn), one symdyn_add_model(... PYTHON) line, then Python runs the
# spinning top (examples/spinning_top) from steady precession and checks that
# the nutation stays put and the energy is conserved; the module and its result
# name the coordinates as the model file does.
#   python_example.sh <repo> <symdyn build dir> <work dir> [cmake option]...
set -euo pipefail
repo=$1 symdyn_build=$2 work=$3
shift 3
fail() { echo "error: $*" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work/project"
cmake --install "$symdyn_build" --prefix "$work/prefix" >/dev/null || fail "cmake --install failed"
cat > "$work/project/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.25)
project(top_in_python LANGUAGES CXX)
find_package(symdyn 0.1 REQUIRED)
symdyn_add_model(spinning_top $repo/examples/spinning_top/spinning_top.cpp PYTHON)
CMAKE
cmake -S "$work/project" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" "$@" >"$work/configure.log" 2>&1 ||
  { cat "$work/configure.log"; fail "configuring the Python project failed"; }
cmake --build "$work/build" || fail "building the Python module failed"
PYTHONPATH="$work/build/python" /usr/bin/python3 - <<'PY' || fail "the Python checks failed"
import numpy as np
import spinning_top as top

system = top.System()
run = system.simulate(2.0, integrator="dop853", rtol=1e-10, atol=1e-10, interval=0.01)
nutation = np.max(np.abs(run.q[:, 1] - run.q[0, 1]))
drift = np.max(np.abs(run.energies.total - run.energies.total[0])) / abs(run.energies.total[0])
print(f"spinning top from Python: {run.t.shape[0]} samples, max |theta - theta0| {nutation:.2e} rad, "
      f"energy drift {drift:.2e}")
assert nutation < 1e-8, nutation
assert drift < 1e-10, drift
# The coordinates' names, as the model file gives them, in the module and in a run's result.
assert top.q_names == ("psi", "theta", "phi"), top.q_names
assert list(run.q_names) == ["psi", "theta", "phi"], run.q_names
assert top.body_names == ("top",), top.body_names
# A coordinate by its name; a value that is not finite refused, naming its coordinate.
damper = top.CoordinateSpringDamper("theta", stiffness=0.0, damping=1.0)
rates = [0.0, 2.0, 0.0]
added = system.applied_forces(qd=rates, forces=[damper]) - system.applied_forces(qd=rates)
assert np.allclose(added, [0.0, -2.0, 0.0], rtol=0, atol=1e-12), added
try:
    system.positions(q=[0.0, float("nan"), 0.0])
    raise AssertionError("a NaN nutation was accepted")
except ValueError as e:
    assert "coordinate 'theta'" in str(e), e
PY
