import numpy as np

import double_pendulum_absolute as dp

print(dp.q_names, dp.body_names)  # ('theta1', 'theta2') ('rod1', 'rod2')
system = dp.System()

# Equations of motion and kinematics at a state (q, qd default to the initial state).
q, qd = [0.3, -1.1], [0.7, 2.0]
M = system.mass_matrix(q)               # (2, 2)
h = system.bias_forces(q, qd)           # (2,): M qdd + h = Q
qdd = system.accelerations(q, qd)       # (2,)
R, x = system.positions(q)              # (2, 3, 3) rotations, (2, 3) centres of gravity
v, w = system.velocities(q, qd)         # (2, 3) each

# A free run from horizontal at rest: energy is conserved.
run = system.simulate(3.0, integrator="dopri5", rtol=1e-10, atol=1e-10, interval=0.01)
print(run.t.shape, run.q.shape)         # (301,) (301, 2)
drift = np.max(np.abs(run.energies.total - run.energies.total[0]))
print(f"energy drift {drift:.1e} J in {run.statistics.steps} steps")

# Joint friction for one run only (forces=...), or for good (System([...]) or add).
friction = dp.CoordinateSpringDamper("theta2", stiffness=0.0, damping=0.5)
damped = system.simulate(3.0, interval=0.5, forces=[friction])

# Torsional springs at both joints: the static equilibrium, and the modes about it.
springs = dp.System([dp.CoordinateSpringDamper("theta1", 30.0), dp.CoordinateSpringDamper("theta2", 10.0)])
equilibrium = springs.solve_statics()
print(equilibrium.q, equilibrium.iterations)
around = springs.modes(q=equilibrium.q)
print(around.natural_frequency_hz)

# Small oscillations hanging down.
hanging = system.modes(q=[-np.pi / 2, 0.0])
print(np.round(hanging.natural_frequency_hz, 4))  # [0.4266 1.1441] Hz

# Errors are exceptions naming the culprit.
try:
    system.add(dp.CoordinateSpringDamper("q2", 1.0))
except dp.ModelError as e:              # also a ValueError
    print(e)
