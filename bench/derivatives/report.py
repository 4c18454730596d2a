#!/usr/bin/env python3
"""Writes bench/results/derivatives.md from what bench/derivatives/run.sh measured.

report.py [--integrators-only] WORK_DIR OUT.md: WORK_DIR holds time.tsv (symdyn_bench_derivatives time:
scale, steps, rounding, check and time rows), counts.tsv (model, method, instructions
per call, calls), breakdown.tsv (model, part, instructions per call of symdyn_exact),
integrators.tsv (symdyn_bench_implicit_jacobians), build.tsv (chain_64's generation
and compilation, from run.sh --measure-build) and meta.txt (key = value lines).
--integrators-only: only integrators.tsv and meta.txt, whose sections (and the summary's
line on them) replace those of the existing OUT.md.
"""
import collections
import os
import sys

METHODS = [
    ("symdyn_exact", "symdyn exact", "`MultibodySystem::dynamics_derivatives` (what a user calls): qdd "
     "by `accelerations`, the emitted `inverse_dynamics_derivatives` (∂τ/∂q = K, ∂τ/∂qd = C at qdd; "
     "above 20 coordinates `inverse_dynamics_jacobians`, M with them in one call), "
     "then −M⁻¹·K and −M⁻¹·C, all columns of each in one solve: by M's sparse factorization along its "
     "elimination tree (`TreeSolver`, leaves first, no fill-in) where that tree has zeros enough to pay, "
     "else by the dense Cholesky factor of M (the one `accelerations` made where it took the way of M)"),
    ("symdyn_exact_by_columns", "by columns", "the baseline, what `dynamics_derivatives` did before "
     "(from public calls): qdd, then M evaluated and factored again, then a solve per column of K and of C"),
    ("symdyn_differences", "symdyn differences", "`dynamics_derivatives` after `set_exact_jacobians(false)`: "
     "the runtime's central differences of the residual (4·nq residuals), then the same solves"),
    ("symdyn_central", "symdyn central", "central differences of `MultibodySystem::accelerations`: "
     "4·nq calls, relative step 1e-6 (floor 1e-6)"),
    ("symdyn_emitted_code", "emitted code", "the emitted `inverse_dynamics_derivatives` alone: a floor, "
     "not a result"),
    ("mujoco_qacc_centered", "MuJoCo qacc centered", "central differences of `mj_forward`'s `qacc`, step "
     "1e-6: velocities first with `mj_forwardSkip(mjSTAGE_POS)`, then positions with "
     "`mj_forwardSkip(mjSTAGE_NONE)`, sensors skipped, as `mjd_stepFD` does for a step; 4·nq + 1 "
     "evaluations"),
    ("mujoco_qacc_forward", "MuJoCo qacc forward", "the same with forward differences: 2·nq + 1 evaluations"),
    ("mujoco_transition_centered", "MuJoCo transitionFD centered", "`mjd_transitionFD(m, d, 1e-6, 1, A, "
     "NULL, NULL, NULL)`: A of one Euler step (h = 0.002), 4·nq + 1 steps"),
    ("mujoco_transition_forward", "MuJoCo transitionFD forward", "the same, `centered = 0`: 2·nq + 1 steps"),
]
TITLE = {k: t for k, t, _ in METHODS}
PEER_METHODS = [k for k, _, _ in METHODS if k.startswith("mujoco_")]
EPS_MACHINE = 2.220446049250313e-16


def read_tsv(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [line.rstrip("\n").split("\t") for line in f if line.strip()]


def fmt_ns(v):
    return f"{v:,.0f}".replace(",", " ") if v >= 100 else f"{v:.1f}"


def fmt_int(v):
    return f"{int(v):,}".replace(",", " ")


def tolerances(k, m, scale, rounding, steps):
    """The tolerances of method k's errors on model m (dq, dqd), as "Values" says."""
    delta, qdd_size = rounding.get(m, (0.0, 0.0))
    eps, h_step = steps.get(m, (1e-6, 0.002))
    tols = []
    for sc in scale[m]:
        tol = 10 * delta / (eps * sc) + 1e-8
        if k.endswith("_forward"):
            tol += 1e-4
        if k.startswith("mujoco_transition"):
            tol += 10 * EPS_MACHINE * (1 + h_step * qdd_size) / (eps * h_step) / sc
        if k == "symdyn_exact_by_columns":
            tol = 1e-10
        tols.append(tol)
    return tols


def all_values_ok(models, checks, scale, rounding, steps):
    return all(all(e <= t for e, t in zip(errs, tolerances(k, m, scale, rounding, steps)))
               for m in models for k, errs in checks[m].items())


def solves_time(work, n):
    """The runtime's solve of nq = n alone (solves.tsv), or NaN."""
    for r in read_tsv(os.path.join(work, "solves.tsv")):
        if r[0] == "solve" and int(r[1]) == n and r[2] == "runtime":
            return float(r[3])
    return float("nan")


def amru5_summary(integ):
    """The summary's line on Newmark on amru5, or None."""
    cpu = {(r[3], r[4]): float(r[6]) for r in integ
           if r[0] == "run" and r[1].startswith("amru5") and r[2] == "newmark"}
    rs = [(cpu[(tol, "differences")] / cpu[(tol, "exact")], tol) for (tol, j) in cpu
          if j == "exact" and (tol, "differences") in cpu]
    if not rs:
        return None
    return ("Newmark on amru5 walking, exact against differenced Jacobians at the same error: " +
            ", ".join(f"{r:.2f}x at tol {tol}" for r, tol in rs) + " (target 1.5x).")


def integrators_section(integ, measured=None):
    """The sections on the time per Jacobian and the implicit integrators (lines); measured:
    a line naming the commit and machine, when they were measured apart."""
    o = []
    runs = [r for r in integ if r[0] == "run"]
    refs = {r[1]: r for r in integ if r[0] == "reference"}
    jacs = [r for r in integ if r[0] == "jacobian"]
    if jacs:
        o.append("## Time per Jacobian: the force elements' exact derivatives against differenced ones\n")
        o.append("`symdyn_bench_implicit_jacobians`: one `MultibodySystem::jacobians` (M, C and K of the "
                 "residual, what an implicit integrator asks for) at the end state of the scenario, the "
                 "scenario's force elements included: \"exact\", with the emitted derivatives and the "
                 "force elements' own (the tyres' and contacts' laws differentiated automatically, "
                 "`runtime/kinematics_derivatives.hpp`); \"elements differenced\", the same but every "
                 "force element's part by central differences of its Q (`set_exact_load_derivatives(false)`: "
                 "the kinematics evaluated twice per coordinate in q); \"differences\", central "
                 "differences of the whole residual (`set_exact_jacobians(false)`). CPU time, median of 21 "
                 "interleaved rounds.\n")
        if measured:
            o.append(measured + "\n")
        o.append("| problem | Jacobians | time per Jacobian (µs) | / exact | method |")
        o.append("|---|---|---:|---:|---|")
        exact = {r[1]: float(r[3]) for r in jacs if r[2] == "exact"}
        for r in jacs:
            rr = f"**{float(r[3]) / exact[r[1]]:.2f}**" if r[2] != "exact" and r[1] in exact else ""
            o.append(f"| {r[1]} | {r[2]} | {float(r[3]):.1f} | {rr} | {r[5]} |")
        o.append("")
    if not runs:
        return o
    o.append("## Implicit integrators: exact against differenced Jacobians\n")
    o.append("`symdyn_bench_implicit_jacobians` (`bench/derivatives/implicit_jacobians.cpp`): the scenarios "
             "of `models/scenarios` as `symdyn-sim` runs them, force elements included (each run's output "
             "interval is its whole interval, so no output is written), each problem and tolerance in "
             "three ways in one process, interleaved: with the emitted derivatives and the force elements' "
             "own (\"exact\", the default); with every force element's part differenced "
             "(\"elements differenced\", `set_exact_load_derivatives(false)`); after "
             "`set_exact_jacobians(false)` (\"differences\"), where Newmark's iteration matrix "
             "M + γh·C + βh²·K takes C and K from central differences of the residual (4·nq residuals per "
             "matrix, not counted among the integrator's residuals below), CVODE's Jacobian falls back to "
             "its forward differences of the accelerations (2·nq calls, counted among its right-hand "
             "sides) and midpoint's Newton matrix (tol: its fixed step) to forward differences of its map "
             "(2·nq maps, not counted). Error: the largest |q − q_ref|, |qd − qd_ref| at the end against "
             "dop853 at rtol = atol = 1e-12 (\"reference\": its distance to dopri5 at 1e-12). CPU: median "
             "of the repetitions, the set-up excluded.\n")
    if measured:
        o.append(measured + "\n")
    for name, r in refs.items():
        o.append(f"- reference of {name}: dop853 at 1e-12, agreement with dopri5 {float(r[4]):.1e}, "
                 f"both computed in {float(r[5]):.1f} s")
    o.append("")
    o.append("| problem | integrator | tol | Jacobians | error | CPU (ms) | steps | rejected | Newton "
             "iterations | residuals | right-hand sides | Jacobian evaluations | / exact (CPU) |")
    o.append("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    cpu = {(r[1], r[2], r[3], r[4]): float(r[6]) for r in runs}
    for r in runs:
        rr = ""
        if r[4] != "exact" and (r[1], r[2], r[3], "exact") in cpu:
            rr = f"**{cpu[(r[1], r[2], r[3], r[4])] / cpu[(r[1], r[2], r[3], 'exact')]:.2f}**"
        o.append(f"| {r[1]} | {r[2]} | {r[3]} | {r[4]} | {float(r[5]):.2e} | {float(r[6]):.1f} | {r[7]} | "
                 f"{r[8]} | {r[9]} | {r[10]} | {r[11]} | {r[12]} | {rr} |")
    o.append("")
    o.append("How each run obtained its Jacobians (`MultibodySystem::jacobian_method()`):\n")
    seen = set()
    for r in runs:
        if (r[1], r[2], r[4]) not in seen:
            seen.add((r[1], r[2], r[4]))
            o.append(f"- {r[1]}, {r[2]}, {r[4]}: {r[13]}")
    o.append("")
    o.append("The slider-crank has one coordinate: differences cost CVODE two evaluations per Jacobian, "
             "nothing for exact derivatives to save. With CVODE the kinds of Jacobian also lead to "
             "different steps (forward differences are less accurate, and CVODE's step and Jacobian "
             "reuse follow its Newton convergence): compare the rows' steps before their times. With "
             "the force elements differenced (the trike's tyres, amru5's contacts), the exact Jacobian "
             "evaluates the kinematics twice per coordinate in q for them. Differencing any element "
             "evaluates the kinematics at every shifted q: the trike's Jacobian and amru5's, all of whose "
             "elements are exact (the trike's drive, a coordinate force given as an expression, "
             "differentiated through its expression), are cheaper than with their elements differenced "
             "(\"Time per Jacobian\"). Midpoint's exact Newton matrix costs six "
             "Jacobians (M, C and K at the midpoint and at q ± d·v, with qdd = 0 and qdd = v) where its "
             "differenced one costs 2·nq maps.\n")
    amru = [(cpu[(p, i, tol, 'differences')] / cpu[(p, i, tol, 'exact')], tol)
            for (p, i, tol, j) in cpu
            if p.startswith("amru5") and i == "newmark" and j == "exact" and (p, i, tol, "differences") in cpu]
    if amru:
        errs = {(r[3], r[4]): float(r[5]) for r in runs if r[1].startswith("amru5") and r[2] == "newmark"}
        same = all(abs(errs[(tol, 'exact')] - errs[(tol, 'differences')]) <= 0.1 * errs[(tol, 'exact')]
                   for _, tol in amru)
        lo = min(amru)
        o.append(f"Target: Newmark on amru5 at least 1.5 times faster at the same error: "
                 f"{'**met**' if lo[0] >= 1.5 and same else '**not met**'}: " +
                 ", ".join(f"{r:.2f}x at tol {tol} (errors {errs[(tol, 'exact')]:.2e} exact, "
                           f"{errs[(tol, 'differences')]:.2e} differences)"
                           for r, tol in sorted(amru, key=lambda x: x[1])) + ".\n")
    return o


def replace_integrators(work, out):
    """Rewrites, in the results file out, the sections integrators_section writes (and the
    summary's line on amru5) from WORK_DIR's integrators.tsv and meta.txt alone."""
    meta = read_meta(work)
    integ = read_tsv(os.path.join(work, "integrators.tsv"))
    measured = (f"Measured apart (`bench/derivatives/run.sh --integrators-only`) at commit "
                f"{meta.get('commit', '?')}: {meta.get('machine', '')}; {meta.get('compiler', '')}; "
                f"{meta.get('reps', '?')} repetitions.")
    with open(out) as f:
        text = f.read()
    first = min(i for i in (text.find("## Time per Jacobian"), text.find("## Implicit integrators")) if i >= 0)
    rest = text.find("\n## ", text.find("## Implicit integrators") + 1)
    tail = text[rest + 1:] if rest >= 0 else ""
    text = text[:first] + "\n".join(integrators_section(integ, measured)) + "\n" + tail
    line = amru5_summary(integ)
    if line:
        text = "\n".join(f"- {line}" if x.startswith("- Newmark on amru5 walking") else x
                         for x in text.split("\n"))
    with open(out, "w") as f:
        f.write(text)


def read_meta(work):
    meta = {}
    with open(os.path.join(work, "meta.txt")) as f:
        for line in f:
            if " = " in line:
                k, v = line.rstrip("\n").split(" = ", 1)
                meta[k] = v
    return meta


def main(work, out):
    meta = read_meta(work)
    models, nq, scale, steps, rounding = [], {}, {}, {}, {}
    checks = collections.defaultdict(dict)  # model -> method -> (e_dq, e_dqd)
    times = {}  # (model, method) -> (median, q1, q3)
    skips = {}
    for r in read_tsv(os.path.join(work, "time.tsv")):
        kind = r[0]
        if kind == "scale":
            models.append(r[1])
            nq[r[1]] = int(r[2])
            scale[r[1]] = (float(r[3]), float(r[4]))
        elif kind == "steps":
            steps[r[1]] = (float(r[3]), float(r[4]))
        elif kind == "rounding":
            rounding[r[1]] = (float(r[3]), float(r[4]))
        elif kind == "check":
            checks[r[1]][r[2]] = (float(r[3]), float(r[4]))
        elif kind == "time":
            times[(r[1], r[2])] = tuple(float(x) for x in r[3:6])
        elif kind == "skip":
            skips[(r[1], r[2])] = r[3]
    counts = {(r[0], r[1]): int(r[2]) for r in read_tsv(os.path.join(work, "counts.tsv"))}
    breakdown = collections.defaultdict(dict)
    for m, part, n in read_tsv(os.path.join(work, "breakdown.tsv")):
        breakdown[m][part] = int(n)
    integ = read_tsv(os.path.join(work, "integrators.tsv"))
    build = read_tsv(os.path.join(work, "build.tsv"))
    methods = [k for k, _, _ in METHODS if any((m, k) in times for m in models)]

    def t(m, k):
        return times[(m, k)][0] if (m, k) in times else None

    def ratio(m, k):
        a, b = t(m, k), t(m, "symdyn_exact")
        return a / b if a and b else None

    o = []
    o.append("# Derivatives of the forward dynamics: symdyn exact, differences, MuJoCo\n")
    o.append("Written by `bench/derivatives/run.sh` (`bench/README.md`); every figure below was measured by "
             "that run, in one process per table, interleaved, so that ratios compare like with like. The "
             "quantity: ∂qdd/∂q and ∂qdd/∂qd (nq x nq each) of the forward dynamics qdd(q, qd) under gravity, "
             "at the 64 random states of `bench/results/peers.md` (q within 1 of the model's initial "
             "configuration, qd in [-1, 1], seed 2013), on the mechanisms of `bench/peers/` (the same "
             "mechanism for both libraries, coordinates in symdyn's order, checked). symdyn runs the "
             "emitted code of the `*_absolute` variants, generated with `DERIVATIVES` (chain_32 and chain_64 "
             "by `bench/peers/CMakeLists.txt`).\n")
    o.append("## Measured\n")
    for k in ["machine", "cpu", "compiler", "commit", "mujoco", "valgrind", "rounds", "reps", "duration", "load"]:
        if k in meta:
            o.append(f"- {k}: {meta[k]}")
    o.append("")
    o.append("## Summary\n")
    summary = []
    if checks:
        summary.append("Values: " + ("every method agrees with symdyn's exact derivatives to its own accuracy on "
                                     "every model (\"Values\")." if all_values_ok(models, checks, scale, rounding, steps)
                                     else "**some methods disagree** (\"Values\")."))
    for k in ("mujoco_qacc_centered", "mujoco_qacc_forward"):
        rs = [(ratio(m, k), m) for m in models if ratio(m, k)]
        if rs:
            low = [m for r, m in rs if r < 10]
            summary.append(f"symdyn exact against {TITLE[k]}: {min(rs)[0]:.1f}x ({min(rs)[1]}) to "
                           f"{max(rs)[0]:.1f}x ({max(rs)[1]}) faster" +
                           (f"; under 10x on {', '.join(low)}." if low else ", at least 10x on every model."))
    if ratio("chain_64_absolute", "symdyn_central"):
        summary.append(f"symdyn exact against its own central differences at chain_64: "
                       f"{ratio('chain_64_absolute', 'symdyn_central'):.1f}x (target 10x, not reachable on this path: "
                       f"\"Why chain_64 ...\").")
    rb = [(ratio(m, "symdyn_exact_by_columns"), m) for m in models if ratio(m, "symdyn_exact_by_columns")]
    if rb:
        summary.append(f"This change to `dynamics_derivatives` (all columns in one solve, M's factorization reused): "
                       f"{min(rb)[0]:.2f}x ({min(rb)[1]}) to {max(rb)[0]:.2f}x ({max(rb)[1]}) faster than before.")
    line = amru5_summary(integ)
    if line:
        summary.append(line)
    for x in summary:
        o.append(f"- {x}")
    o.append("")
    o.append("| method | what it computes |")
    o.append("|---|---|")
    for k, title, what in METHODS:
        if k in methods:
            o.append(f"| {title} (`{k}`) | {what} |")
    o.append("")
    o.append("MuJoCo offers `mjd_transitionFD`, the derivatives of one step of its integrator: with Euler and "
             "no joint damping its velocity update is qd + h·qdd, so A's lower blocks are h·∂qdd/∂q and "
             "1 + h·∂qdd/∂qd, and the check below reads ∂qdd from them. It times a step per evaluation "
             "besides the forward dynamics; the fairer comparison for the same quantity is the differences "
             "of `mj_forward`'s `qacc` (\"MuJoCo qacc\"), which the targets below are reported against; "
             "the transition rows are beside them.\n")

    # Values.
    o.append("## Values, checked before any timing\n")
    o.append("At the first 8 states, each method's ∂qdd/∂q and ∂qdd/∂qd against symdyn's exact ones: "
             "max |X − exact| / max |exact| over the entries, ∂qdd/∂q and ∂qdd/∂qd apart, the largest over "
             "the states. What differences can reach: δ, the largest |qdd_MuJoCo − qdd_symdyn| at those "
             "states, is the rounding of the forward dynamics, which a difference with step h = 1e-6 "
             "turns into an error up to δ/h. Tolerance of central differences: 10·δ/(h·max|exact|) + 1e-8 "
             "(their truncation, O(h²)); of forward differences the same + 1e-4 (their truncation, "
             "h/2·|∂²qdd|, taken up to 200 times the first derivative); of the transition matrix the same + "
             "10·ε·(1 + h_step·max|qdd|)/(1e-6·h_step) (the rounding of qd_next, divided by the step "
             "h_step = 0.002 to read ∂qdd). \"by columns\" computes the same as symdyn exact in another "
             "order: rounding only.\n")
    cols = [k for k in methods if k not in ("symdyn_exact", "symdyn_emitted_code")]
    o.append("| model | nq | max\\|∂qdd/∂q\\| | max\\|∂qdd/∂qd\\| | δ | " +
             " | ".join(TITLE[k] for k in cols) + " | verdict |")
    o.append("|---|---:|---:|---:|---:|" + "---:|" * len(cols) + "---|")
    all_ok = True
    worst = {}
    for m in models:
        delta, qdd_size = rounding.get(m, (0.0, 0.0))
        eps, h_step = steps.get(m, (1e-6, 0.002))
        cells, bad = [], []
        for k in cols:
            e = checks[m].get(k)
            if e is None:
                cells.append("—")
                continue
            tols = tolerances(k, m, scale, rounding, steps)
            ok = all(x <= tl for x, tl in zip(e, tols))
            worst[k] = max(worst.get(k, 0.0), *e)
            if not ok:
                bad.append(f"{TITLE[k]} ({e[0]:.1e}, {e[1]:.1e} against {tols[0]:.1e}, {tols[1]:.1e})")
            cells.append(f"{e[0]:.1e} / {e[1]:.1e}" + ("" if ok else " **!**"))
        all_ok = all_ok and not bad
        verdict = "agree" if not bad else "**disagree: " + "; ".join(bad) + "**"
        o.append(f"| {m} | {nq[m]} | {scale[m][0]:.3g} | {scale[m][1]:.3g} | {delta:.1e} | " +
                 " | ".join(cells) + f" | {verdict} |")
    o.append("")
    o.append("Each cell: error of ∂qdd/∂q / error of ∂qdd/∂qd. " +
             ("Every method agrees with the exact derivatives to its own accuracy on every model. "
              if all_ok else "A **!** marks an error past its tolerance. ") +
             "The forward differences' error is their truncation (h·|∂²qdd|/2, about 1e-6 of the "
             "derivatives), their price for half the evaluations.\n")

    # Times.
    o.append("## CPU time per call (ns)\n")
    o.append(f"Median over {meta.get('rounds', '?')} interleaved rounds (each round times one batch of every "
             "method in turn, about 10 ms or one call, cycling through the 64 states), CPU time of the thread "
             "per call. The machine is shared: the figures of a row move together by tens of percent from "
             "one run to the next, the ratios much less; the instruction counts further down do not move.\n")
    o.append("| model | nq | " + " | ".join(TITLE[k] for k in methods) + " |")
    o.append("|---|---:|" + "---:|" * len(methods))
    for m in models:
        o.append(f"| {m} | {nq[m]} | " + " | ".join(fmt_ns(t(m, k)) if t(m, k) else "—" for k in methods) + " |")
    o.append("")
    o.append("### Ratios to symdyn exact (time of the method / time of symdyn exact)\n")
    rcols = [k for k in methods if k not in ("symdyn_exact", "symdyn_emitted_code")]
    o.append("| model | " + " | ".join(TITLE[k] for k in rcols) + " | emitted code share |")
    o.append("|---|" + "---:|" * len(rcols) + "---:|")
    for m in models:
        cells = []
        for k in rcols:
            r = ratio(m, k)
            cells.append("—" if r is None else (f"**{r:.1f}**" if k in ("mujoco_qacc_centered", "mujoco_qacc_forward")
                                               else f"{r:.2f}" if r < 10 else f"{r:.1f}"))
        share = ratio(m, "symdyn_emitted_code")
        o.append(f"| {m} | " + " | ".join(cells) + (f" | {share:.0%} |" if share else " | — |"))
    o.append("")
    o.append("\"emitted code share\": the emitted `inverse_dynamics_derivatives` alone over symdyn exact, "
             "timed apart (the rest: qdd, M, its factorization, the solves, the runtime's checks and "
             "copies).\n")

    # Instructions.
    if counts:
        o.append("## Instructions per call (callgrind)\n")
        o.append("`symdyn_bench_derivatives --count METHOD MODEL CALLS` under `valgrind --tool=callgrind "
                 "--toggle-collect='*counted_workload*'`, CALLS about 5 ms of the method (1 to 64), after 2 "
                 "warm-up calls outside the counted function; repeatable whatever else the machine does. "
                 "Instructions are not time: the solves of \"by columns\" run close to the instructions of "
                 "symdyn exact's blocked ones, in up to twice the time (a chain of dependent "
                 "multiply-adds per entry, where the blocked solve is vectorized across columns).\n")
        o.append("| model | " + " | ".join(TITLE[k] for k in methods) + " | MuJoCo qacc forward / symdyn exact |")
        o.append("|---|" + "---:|" * len(methods) + "---:|")
        for m in models:
            cells = [fmt_int(counts[(m, k)]) if (m, k) in counts else "—" for k in methods]
            a, b = counts.get((m, "mujoco_qacc_forward")), counts.get((m, "symdyn_exact"))
            o.append(f"| {m} | " + " | ".join(cells) + (f" | {a / b:.1f} |" if a and b else " | — |"))
        o.append("")

    # Targets.
    o.append("## Targets\n")
    for k, accuracy in (("mujoco_qacc_centered", "the same accuracy class as symdyn's central differences"),
                        ("mujoco_qacc_forward", "half the evaluations, errors of 1e-6 of the derivatives"),
                        ("mujoco_transition_centered", "what `mjd_transitionFD` costs, a step included"),
                        ("mujoco_transition_forward", "the same, forward")):
        rs = [(ratio(m, k), m) for m in models if ratio(m, k)]
        if not rs:
            continue
        low = [f"{m} {r:.2f}x" for r, m in sorted(rs) if r < 10]
        lo, hi = min(rs), max(rs)
        verdict = "**met**" if not low else f"**not met** on {len(low)} of {len(rs)} models"
        o.append(f"- symdyn's exact derivatives at least 10 times faster than {TITLE[k]} ({accuracy}), "
                 f"every model: {verdict}. From {lo[0]:.1f}x ({lo[1]}) to {hi[0]:.1f}x ({hi[1]})" +
                 (f"; below 10x: {', '.join(low)}." if low else "."))
    r64 = ratio("chain_64_absolute", "symdyn_central")
    if r64:
        o.append(f"- symdyn's exact derivatives at least 10 times faster than its own central differences "
                 f"at chain_64: {'**met**' if r64 >= 10 else '**not met**'}, {r64:.1f}x "
                 f"({fmt_ns(t('chain_64_absolute', 'symdyn_exact'))} ns against "
                 f"{fmt_ns(t('chain_64_absolute', 'symdyn_central'))} ns); see below.")
    o.append("")

    # Where the time goes.
    if breakdown:
        o.append("## Where symdyn exact spends its instructions (callgrind, per call)\n")
        parts = [("emitted_derivatives", "emitted derivatives"), ("solves", "solves −M⁻¹·[K C]"),
                 ("factor", "Cholesky of M"), ("emitted_mass_matrix", "emitted M"),
                 ("accelerations", "qdd (`accelerations`)")]
        o.append("| model | total | " + " | ".join(title for _, title in parts) + " | the rest (checks, copies, calls) |")
        o.append("|---|---:|" + "---:|" * len(parts) + "---:|")
        for m in models:
            b = breakdown.get(m)
            if not b or "total" not in b:
                continue
            total = b["total"]
            cells = []
            for p, _ in parts:
                cells.append(f"{fmt_int(b[p])} ({b[p] / total:.0%})" if p in b else "—")
            rest = total - sum(b.get(p, 0) for p, _ in parts)
            o.append(f"| {m} | {fmt_int(total)} | " + " | ".join(cells) + f" | {fmt_int(rest)} ({rest / total:.0%}) |")
        o.append("")
        o.append("\"emitted M\" is absent where `accelerations` took the way of M: its dense factorization serves "
                 "the solves unless M's tree is sparse enough. \"Cholesky of M\" and \"solves\" count whichever "
                 "solver ran: `TreeSolver` (M = Lᵀ·L along M's elimination tree, leaves first, no fill-in, as "
                 "MuJoCo's `mj_factorM`; used above `TreeSolver::kDenseUpTo` = 8 coordinates where the tree "
                 "leaves at most `TreeSolver::kDenseShare` = 0.8 of the dense triangle's entries below the "
                 "diagonal: the trees, hexapod_tree and trike) or `SpdSolver` (dense: the chains, whose absolute "
                 "angles couple every pair of coordinates, and the small models). A "
                 "floating base's six coordinates stay a dense block that every branch hangs from, so a tree's "
                 "solves shrink by about its share of zeros, not to O(nq). With the recursive derivatives the "
                 "solves are the largest part from chain_8 up (2·nq³ multiply-adds, where the derivatives grow as "
                 "nq²); the emitted code takes a larger share of the time than of the instructions (the "
                 "\"emitted code share\" above: instructions from beyond the instruction caches run slower).\n")

    # Why the targets at the large chains are out of reach of this path.
    big = "chain_64_absolute"
    ops = {r[1]: int(r[2]) for r in build if r[0] == "operations"}
    if big in nq and (big, "symdyn_exact") in counts and (big, "symdyn_emitted_code") in counts:
        n = nq[big]
        code_rate = counts[(big, "symdyn_emitted_code")] / t(big, "symdyn_emitted_code")
        central_rate = counts[(big, "symdyn_central")] / t(big, "symdyn_central")
        b = breakdown.get(big, {})
        compiled = [r for r in build if r[0] == "compilation"]
        object_size = f" (the model's object file: {int(compiled[0][5]) / 1e6:.1f} MB)" if compiled else ""
        o.append(f"### Why chain_64 stays short of 10 times its central differences\n")
        lines = [
            f"- The emitted derivatives run at {code_rate:.1f} instructions per ns, the central differences "
            f"(the articulated-body algorithm, {fmt_int(counts[(big, 'symdyn_central')] // (4 * n))} instructions "
            f"a call) at {central_rate:.1f}: the derivatives are {fmt_int(counts[(big, 'symdyn_emitted_code')])} "
            f"instructions of straight-line code{object_size}, each executed once per call, so the "
            f"processor streams them from beyond its instruction caches; the articulated-body algorithm is "
            f"short enough to stay in them.",
        ]
        if "solves" in b:
            lines.append(
                f"- The solves −M⁻¹·[K C] are {fmt_int(2 * n ** 3)} multiply-adds (2·nq³), "
                f"{fmt_int(b['solves'])} instructions a call ({b['solves'] / b['total']:.0%} of symdyn exact's), "
                f"about {fmt_ns(solves_time(work, n))} ns (\"The solves alone\" below), 1/"
                f"{t(big, 'symdyn_central') / solves_time(work, n):.0f} of the central differences: with qdd, M "
                f"and its factorization on top, no path through −M⁻¹·K reaches 10 times here by faster solves "
                f"alone (these run AVX2 with FMA where the processor has them, \"The solves alone\").")
        if "inverse_dynamics_derivatives" in ops and "forward_dynamics_pivots" in ops:
            lines.append(
                f"- In operations (`--stats`): the emitted derivatives are {fmt_int(ops['inverse_dynamics_derivatives'])}, "
                f"{ops['inverse_dynamics_derivatives'] / ops.get('inverse_dynamics', 1):.0f} times the inverse dynamics "
                f"({fmt_int(ops.get('inverse_dynamics', 0))}); 4·nq articulated-body calls are "
                f"{fmt_int(4 * n * ops['forward_dynamics_pivots'])}. They are the recursive derivative algorithm's "
                f"(Carpentier and Mansard's, Pinocchio's `computeRNEADerivatives`, `model/dynamics_derivatives.hpp`): "
                f"a few spatial products per joint, then two to four 6-vector dot products per pair of joints, "
                f"where forward mode over the 2·nq directions of the recursive Newton-Euler program gave 584 782 "
                f"(commit 0d86a0a): O(nq²) both, with a constant about a third. What is left is the solves above.")
        else:
            lines.append(
                f"- The emitted derivatives are the recursive derivative algorithm's (Carpentier and Mansard's, "
                f"Pinocchio's `computeRNEADerivatives`, `model/dynamics_derivatives.hpp`: a few spatial products per "
                f"joint, then two to four 6-vector dot products per pair of joints): "
                f"{fmt_int(counts[(big, 'symdyn_emitted_code')])} instructions a call, where forward mode over the "
                f"2·nq directions of the recursive Newton-Euler program took 1 069 925 (commit 0d86a0a). What keeps "
                f"chain_64 from 10 times its central differences is now mostly the solves above.")
        q_exact, q_central = times[(big, "symdyn_exact")], times[(big, "symdyn_central")]
        lines.append(
            f"- That code is also what the machine's other work slows most: streamed from the cache the "
            f"processor shares with other virtual machines, or from memory. Interquartile ranges in this run: "
            f"symdyn exact {fmt_ns(q_exact[1])} to {fmt_ns(q_exact[2])} ns, its central differences "
            f"{fmt_ns(q_central[1])} to {fmt_ns(q_central[2])} ns; the instruction counts, "
            f"{fmt_int(counts[(big, 'symdyn_exact')])} against {fmt_int(counts[(big, 'symdyn_central')])} "
            f"({counts[(big, 'symdyn_central')] / counts[(big, 'symdyn_exact')]:.1f} times fewer), do not move.")
        o.extend(lines)
        o.append("")

    solves = collections.defaultdict(dict)
    for r in read_tsv(os.path.join(work, "solves.tsv")):
        if r[0] == "solve":
            solves[int(r[1])][r[2]] = float(r[3])
    if solves:
        o.append("## The solves alone: −M⁻¹·B, B of nq x 2·nq (ns)\n")
        o.append("`symdyn_bench_derivatives solves`: a random SPD M (seeded), B the size of [K C]; medians over "
                 "interleaved rounds. \"runtime\": `SpdSolver::solve_negated_in_place` with the kernels it picks "
                 "(`src/runtime/detail/dense_kernels.hpp`: compiled for the build's x86-64 baseline, SSE2, and once "
                 "more for AVX2 with FMA, taken where the processor runs it, as here): tiles of up to 32 columns "
                 "copied row by row, each row's sums in registers across the columns (up to 3 coordinates the "
                 "row loop on B in place); \"plain\": the baseline kernels forced, as on a processor without "
                 "AVX2 (tiles of up to 16 columns up to 8 coordinates, Eigen's blocked solves above); \"previous\": the runtime's solve before them (a row loop on B in "
                 "place up to 8 coordinates, Eigen's blocked triangular solves above); \"Eigen blocked\": those at "
                 "every size; \"by columns\": `solve_negated` on each column (a chain of dependent multiply-adds "
                 "per entry).\n")
        o.append("| nq | runtime | plain | previous | Eigen blocked | by columns | previous / runtime |")
        o.append("|---:|---:|---:|---:|---:|---:|---:|")
        for n in sorted(solves):
            v = solves[n]
            o.append(f"| {n} | {fmt_ns(v['runtime'])} | {fmt_ns(v['plain'])} | {fmt_ns(v['previous'])} | "
                     f"{fmt_ns(v['eigen_blocked'])} | {fmt_ns(v['by_columns'])} | "
                     f"{v['previous'] / v['runtime']:.2f} |")
        o.append("")

    o += integrators_section(integ)

    if build:
        b = {r[0]: r[1:] for r in build}
        o.append("## Building chain_64 with its derivatives\n")
        o.append("Measured once by `bench/derivatives/run.sh --measure-build` (the generator, then "
                 "`g++ -std=c++20 -O3 -DNDEBUG -c` on the emitted source, ccache off, each under "
                 f"`/usr/bin/time`), at commit {b.get('commit', ['?'])[0]}, on the machine above:\n")
        o.append("| step | user (s) | system (s) | wall (s) | max resident (MB) | output (MB) |")
        o.append("|---|---:|---:|---:|---:|---:|")
        for step in ("generation", "compilation"):
            if step in b:
                u, s, e, mem, size = b[step]
                o.append(f"| {step} | {float(u):.1f} | {float(s):.1f} | {float(e):.1f} | {int(mem) / 1024:.0f} | "
                         f"{int(size) / 1e6:.1f} |")
        ops = [(r[1], r[2]) for r in build if r[0] == "operations"]
        if ops:
            o.append("")
            o.append("Operations (`--stats`): " + ", ".join(f"{n} {c}" for n, c in ops) + ".")
        o.append("")

    with open(out, "w") as f:
        f.write("\n".join(o))


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "--integrators-only":
        replace_integrators(sys.argv[2], sys.argv[3])
    else:
        main(sys.argv[1], sys.argv[2])
