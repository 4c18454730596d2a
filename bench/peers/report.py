#!/usr/bin/env python3
"""Writes bench/results/peers.md from what bench/peers/run.sh measured.

report.py WORK_DIR OUT.md: WORK_DIR holds time.tsv (symdyn_bench_peers time),
counts.tsv (library, model, instructions per call of forward dynamics, from
callgrind), build.tsv (target, step, seconds, from ninja's log) and meta.txt
(key = value lines: machine, commit, versions, rounds, duration).
"""
import collections
import os
import sys

LIBS = ["symdyn_emitted", "symdyn_system", "mujoco", "simbody", "kdl", "dart"]
PEERS = ["mujoco", "simbody", "kdl", "dart"]
TITLE = {"symdyn_emitted": "symdyn emitted", "symdyn_system": "symdyn system", "mujoco": "MuJoCo",
         "simbody": "Simbody", "kdl": "KDL", "dart": "DART"}
OPS = [("forward_dynamics", "Forward dynamics (qdd from q, qd under gravity)"),
       ("mass_matrix", "Mass matrix"),
       ("inverse_dynamics", "Inverse dynamics (tau from q, qd, qdd)"),
       ("positions", "Positions of all bodies")]


def read_tsv(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [line.rstrip("\n").split("\t") for line in f if line.strip()]


def fmt_ns(v):
    return f"{v:,.0f}".replace(",", " ") if v >= 100 else f"{v:.1f}"


def main(work, out):
    meta = {}
    with open(os.path.join(work, "meta.txt")) as f:
        for line in f:
            if " = " in line:
                k, v = line.rstrip("\n").split(" = ", 1)
                meta[k] = v
    rows = read_tsv(os.path.join(work, "time.tsv"))
    models = []
    times = {}          # (model, op, lib) -> (median, q1, q3)
    verify = collections.defaultdict(dict)  # (model, lib) -> quantity -> (err, ok)
    skips = {}          # (model, lib) -> why
    skipops = {}        # (model, op, lib) -> why
    cond = {}
    dynamics = {}       # model -> "recursive" or "mass_matrix": the generator's choice
    for r in rows:
        kind = r[0]
        if kind == "mass" and r[1] not in models:
            models.append(r[1])
        elif kind == "time":
            times[(r[1], r[2], r[3])] = tuple(float(x) for x in r[4:7])
        elif kind == "verify":
            verify[(r[1], r[2])][r[3]] = (float(r[4]), r[6] == "ok")
        elif kind == "skip":
            skips[(r[1], r[2])] = r[3]
        elif kind == "skipop":
            skipops[(r[1], r[3], r[2])] = r[4]
        elif kind == "dynamics":
            dynamics[r[1]] = r[2]
        elif kind == "cond":
            cond[r[1]] = r[2]
    counts = {(r[0], r[1]): r[2] for r in read_tsv(os.path.join(work, "counts.tsv"))}
    build = read_tsv(os.path.join(work, "build.tsv"))

    def agreed(model, lib):
        v = verify.get((model, lib))
        return v is not None and all(ok for _, ok in v.values())

    def cell(model, op, lib):
        if (model, lib) in skips or (model, op, lib) in skipops:
            return "—"
        if lib in PEERS and not agreed(model, lib):
            return "disagrees"
        t = times.get((model, op, lib))
        return fmt_ns(t[0]) if t else "—"

    o = []
    o.append("# symdyn against its peers: MuJoCo, Simbody, KDL, DART\n")
    o.append("Written by `bench/peers/run.sh` (`bench/README.md`); every figure below was measured by that "
             "run. The same mechanism is written once per library from `bench/peers/mechanism.cpp` (a joint "
             "tree read off `models/*.cpp`: same masses, inertias at the same centres of mass, joint axes, "
             "lengths and gravity); every library takes the coordinates in symdyn's order and sign, checked "
             "when each model is built (no permutation). symdyn runs the emitted code of the `*_absolute` "
             "variants (chain_N: `chain_N_absolute`; hexapod_tree and trike: their only variant). trike is its "
             "multibody system under gravity alone, like every model here: its tyre, suspension, steering "
             "and drive forces are not part of the comparison.\n")
    o.append("## Measured\n")
    for k in ["machine", "cpu", "compiler", "commit", "mujoco", "simbody", "kdl", "dart", "valgrind",
              "rounds", "duration"]:
        if k in meta:
            o.append(f"- {k}: {meta[k]}")
    o.append("")
    o.append("Each library's operation, on its recommended fast path:\n")
    o.append("| operation | symdyn | MuJoCo 2.2.2 | Simbody | KDL | DART |")
    o.append("|---|---|---|---|---|---|")
    recursive = [m for m in models if dynamics.get(m) == "recursive"]
    by_matrix = [m for m in models if dynamics.get(m) == "mass_matrix"]
    o.append("| forward dynamics | emitted `forward_dynamics()` (the articulated-body algorithm) where the "
             "generator chose it (" + (", ".join(recursive) or "none") + "), else emitted `dynamics()` + the "
             "runtime's `SpdSolver` (" + (", ".join(by_matrix) or "none") + ") (\"emitted\"); "
             "`MultibodySystem::accelerations` (\"system\"), which calls the same | `mj_kinematics`, `mj_comPos`, `mj_crb`, "
             "`mj_factorM`, `mj_comVel`, `mj_rne`, `mj_solveM` | `realize(Acceleration)`, `getUDot` | "
             "`ChainFdSolver_RNE` | `computeForwardDynamics` |")
    o.append("| mass matrix | emitted `mass_matrix()` (dense) | `mj_kinematics`, `mj_comPos`, `mj_crb` "
             "(sparse `qM`, not expanded) | `realize(Position)`, `calcM` | `ChainDynParam::JntToMass` | "
             "`getMassMatrix` |")
    o.append("| inverse dynamics | emitted `inverse_dynamics()` (recursive Newton-Euler) | `mj_kinematics`, "
             "`mj_comPos`, `mj_comVel`, `mj_rne` | `realize(Dynamics)`, "
             "`calcResidualForceIgnoringConstraints` | `ChainIdSolver_RNE` | `computeInverseDynamics` |")
    o.append("| positions | emitted `positions()` (R, x of every body) | `mj_kinematics` | "
             "`realize(Position)` | `ChainFkSolverPos_recursive` (all frames, one sweep) | "
             "`getWorldTransform` of every body |")
    o.append("")

    o.append("## Verification (before any timing)\n")
    o.append("At 64 random states (q within 1 of the model's initial configuration, qd and qdd in [-1, 1], "
             "seed 2013) and at q = qd = qdd = 0, each library's M, qdd, tau, body axes R and centres of "
             "mass x against symdyn's emitted code (M, and qdd = M⁻¹·(−h), tau = M·qdd + h from "
             "`dynamics()`; R, x from `positions()`), and its total mass against the model's. Error: "
             "max |peer − symdyn| / max |symdyn| over the entries of each result, the largest over the "
             "states. Tolerance 1e-9: rounding of different algorithms leaves ~1e-15 on M, and qdd is "
             "M⁻¹·(−h) whose error grows with cond(M) (largest cond(M) per model below): chain_64 "
             "reaches 4e-10 at cond(M) 1.6e8, still inside 1e-9, where a wrong axis, centre of mass or "
             "inertia shows as 1e-1 or worse. A library that disagrees is reported here and not timed. symdyn's own "
             "`MultibodySystem` (`accelerations` and `residual`: its recursive forward and inverse dynamics where "
             "emitted) is checked against the emitted M and h the same way.\n")
    o.append("| model | cond(M) max | library | total mass | M | qdd | tau | R | x | M at q = 0 | verdict |")
    o.append("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|")
    for m in models:
        for lib in ["symdyn_system"] + PEERS:
            if (m, lib) in skips:
                o.append(f"| {m} | {cond.get(m, '')} | {TITLE[lib]} | — | — | — | — | — | — | — | "
                         f"cannot express: {skips[(m, lib)]} |")
                continue
            v = verify.get((m, lib))
            if not v:
                continue
            g = lambda q: f"{v[q][0]:.1e}" if q in v else ("" if lib == "symdyn_system" else "—")
            verdict = "agrees" if all(ok for _, ok in v.values()) else "**disagrees: not timed**"
            missing = sorted({why for (mm, op, ll), why in skipops.items() if mm == m and ll == lib})
            if missing:
                ops = [op.replace("_", " ") for (mm, op, ll) in skipops if mm == m and ll == lib]
                verdict += f" (no {' nor '.join(ops)}: {'; '.join(missing)})"
            o.append(f"| {m} | {cond.get(m, '')} | {TITLE[lib]} | {g('mass')} | {g('M')} | {g('qdd')} | "
                     f"{g('tau')} | {g('R')} | {g('x')} | {g('M_at_q0')} | {verdict} |")
    o.append("")

    o.append("## CPU time per call (ns)\n")
    o.append(f"Median over {meta.get('rounds', '?')} interleaved rounds (each round times one batch of every "
             "library in turn, about 2 ms each, cycling through the same 64 states), CPU time of the thread "
             "per call. Every call goes through one `std::function` (and, for peers, one virtual call): "
             "the same few ns for every library. \"fastest peer\" is the fastest of MuJoCo, Simbody, KDL, "
             "DART; the ratio is symdyn's time over it (below 1: symdyn ahead). The machine is shared with "
             "other work: all figures move together by tens of percent from one run to the next, so a ratio "
             "within about 0.2 of 1 needs a rerun before it is trusted; the instruction counts below do "
             "not move. \"symdyn system\" is what "
             "users call on `runtime::MultibodySystem`: `accelerations`, `mass_matrix`, and `residual` "
             "(f = inverse_dynamics(qdd) − Q with no force element, Q = 0) for inverse dynamics; the runtime has no call "
             "for positions alone, so positions compare the emitted `positions()`.\n")
    not_ahead = []
    for op, title in OPS:
        o.append(f"### {title}\n")
        system = op != "positions"
        libs = LIBS if system else [l for l in LIBS if l != "symdyn_system"]
        sym = "symdyn_system" if system else "symdyn_emitted"
        head = " | ".join(TITLE[l] for l in libs)
        ratio_title = "**system / fastest peer**" if system else "**emitted / fastest peer**"
        extra = " | emitted / fastest peer" if system else ""
        o.append(f"| model | {head} | fastest peer | {ratio_title}{extra} |")
        o.append("|---|" + "---:|" * len(libs) + "---|---:|" + ("---:|" if extra else ""))
        for m in models:
            cells = [cell(m, op, l) for l in libs]
            peer_t = [(times[(m, op, p)][0], p) for p in PEERS if (m, op, p) in times]
            if peer_t:
                best, who = min(peer_t)
                r = times[(m, op, sym)][0] / best
                row = f"| {m} | " + " | ".join(cells) + f" | {TITLE[who]} | **{r:.2f}**"
                if extra:
                    row += f" | {times[(m, op, 'symdyn_emitted')][0] / best:.2f}"
                for lib in ([sym, "symdyn_emitted"] if system else [sym]):
                    r_lib = times[(m, op, lib)][0] / best
                    if r_lib >= 1:
                        not_ahead.append(f"{title.split(' (')[0].lower()} of {m}: {TITLE[lib]} "
                                         f"{fmt_ns(times[(m, op, lib)][0])} ns against {TITLE[who]}'s "
                                         f"{fmt_ns(best)} ns ({r_lib:.2f}x)")
            else:
                row = f"| {m} | " + " | ".join(cells) + " | — | —" + (" | —" if extra else "")
            o.append(row + " |")
        o.append("")

    o.append("## Instructions per forward dynamics call (callgrind)\n")
    o.append("`symdyn_bench_peers --count LIBRARY forward_dynamics MODEL 256` under `valgrind --tool=callgrind "
             "--toggle-collect='*counted_workload*'`: 256 calls over the 64 states, after 64 warm-up calls "
             "outside the counted function; "
             "repeatable whatever else the machine does.\n")
    o.append("| model | " + " | ".join(TITLE[l] for l in LIBS) + " | system / fewest of the peers |")
    o.append("|---|" + "---:|" * len(LIBS) + "---:|")
    for m in models:
        cells = []
        for l in LIBS:
            c = counts.get((l, m))
            cells.append("—" if (m, l) in skips or (m, "forward_dynamics", l) in skipops else ("disagrees" if l in PEERS and not agreed(m, l) else
                                                       (f"{int(c):,}".replace(",", " ") if c and c.isdigit() else "—")))
        peer_c = [int(counts[(p, m)]) for p in PEERS if counts.get((p, m), "").isdigit() and agreed(m, p)]
        sysc = counts.get(("symdyn_system", m), "")
        r = f"{int(sysc) / min(peer_c):.2f}" if peer_c and sysc.isdigit() else "—"
        o.append(f"| {m} | " + " | ".join(cells) + f" | {r} |")
    o.append("")

    o.append("## Where symdyn is not ahead\n")
    if not_ahead:
        for s in not_ahead:
            o.append(f"- {s}")
    else:
        o.append("- nowhere in the tables above: symdyn, through `MultibodySystem` and through the emitted "
                 "code alike, is faster than the fastest peer on every model and operation measured.")
    o.append("")

    o.append("## About the peers as installed\n")
    o.append("- MuJoCo is Debian's 2.2.2 (bookworm), built by Debian; MuJoCo 3 is not packaged here. Its "
             "mass matrix is left in its own sparse storage (`qM`), not expanded to the dense matrix symdyn "
             "writes, and its forward dynamics skips what `mj_forward` would add (sensors, actuation, "
             "passive forces, constraints): both in MuJoCo's favour.")
    o.append("- Simbody is Debian's 3.7, whose libraries are built without `NDEBUG` (libSimTKcommon exports "
             "`recordPrerequisiteVersions`, a debug-only member of its cache entries; the headers then "
             "need `-UNDEBUG` to match their layout). Its cache checks therefore run on every realize: a "
             "release build from source would be faster than the figures here. It is the slowest peer on "
             "most rows, so the ratio to the fastest peer does not depend on it.")
    o.append("- DART is Debian's 6.12.1; it warns about the massless links (robot3d's shoulder and wrist, "
             "the floating base steps of hexapod_tree and trike, trike's strut, steering and fork) and computes them correctly (verified above). DART's own "
             "multi-DOF joints (EulerJoint, TranslationalJoint, UniversalJoint) and Simbody's would avoid "
             "them; they were not tried. MuJoCo, the fastest peer on those models, puts several joints in "
             "one body, its own way.")
    o.append("- KDL is Debian's 1.5.1; it holds every link as a segment (massless ones included, its usual "
             "form).")
    o.append("")

    o.append("## Models out of reach\n")
    o.append("- KDL, hexapod_tree and trike: trees; KDL's forward dynamics and mass matrix solvers "
             "(`ChainFdSolver_RNE`, `ChainDynParam`) take chains only. Its `TreeIdSolver_RNE` (inverse "
             "dynamics) and `TreeFkSolverPos_recursive` (poses, one body per call) are measured.")
    o.append("- slider_crank and amru5: closed kinematic loops, which symdyn writes in minimal coordinates "
             "with dependent parameters p(q). The peers would need loop constraints (MuJoCo's soft equality "
             "constraints, Simbody's constraints with projection, DART's constraint solver inside its World "
             "step; KDL has none): a different set of equations, not the same ODE in the same coordinates, "
             "so no like-for-like timing.")
    o.append("- trike's scenario: the multibody system is compared above (an inclined slider for the "
             "rear strut, a slider along −z for the front suspension), but not the tyre, suspension, "
             "steering and drive forces that make the scenario: each peer would need them reimplemented, "
             "and then the comparison would be of force models, not of dynamics.")
    o.append("")

    if build:
        o.append("## Building chain_32 and chain_64 (not built by default)\n")
        o.append("From ninja's log of the build `run.sh` ran (or the earlier build that produced them): "
                 "wall-clock seconds of each step, `-j2` on the machine above.\n")
        o.append("| target | step | seconds |")
        o.append("|---|---|---:|")
        for t, step, s in build:
            o.append(f"| {t} | {step} | {float(s):.1f} |")
        o.append("")
    with open(out, "w") as f:
        f.write("\n".join(o))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
