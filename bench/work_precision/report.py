#!/usr/bin/env python3
"""Turns symdyn_bench_work_precision's rows (work_precision.tsv) into
work_precision.md and one log-log diagram per problem (PNG and SVG, gnuplot).

    report.py RESULTS.tsv OUTDIR
    report.py --merge PARTIAL.tsv COMMIT RESULTS.tsv

--merge: the rows of PARTIAL.tsv (a run with --integrator) replace those of the same
integrators in RESULTS.tsv, in place; a meta row names them, the commit and the load.
"""
import collections
import os
import subprocess
import sys

GOAL_ERROR, GOAL_MS = 3e-8, 0.1  # on the double pendulum over 1 s


def read(path):
    meta, refs, runs, fails, checks = {}, {}, [], [], []
    for line in open(path):
        f = line.rstrip("\n").split("\t")
        if f[0] == "meta":
            meta[f[1]] = f[2]
        elif f[0] == "reference":
            refs[f[1]] = (float(f[2]), f[3])
        elif f[0] == "run":
            runs.append(dict(problem=f[1], library=f[2], integrator=f[3], kind=f[4], setting=f[5],
                             error=float(f[6]), ms=float(f[7]), steps=f[8], rejected=f[9], rhs=f[10]))
        elif f[0] == "fail":
            fails.append(f[1:])
        elif f[0] == "check":
            checks.append(f[1:])
    return meta, refs, runs, fails, checks


def method(r):
    return r["integrator"] if r["library"] == "symdyn" else f'{r["library"]} {r["integrator"]}'


def plot(problem, rows, outdir):
    series = collections.OrderedDict()
    for r in rows:
        series.setdefault(method(r), []).append(r)
    data = os.path.join(outdir, f"work_precision_{problem}.dat")
    with open(data, "w") as out:
        for name, rs in series.items():
            out.write(f'"{name}"\n')
            for r in sorted(rs, key=lambda r: r["ms"]):
                out.write(f'{r["error"]:.6e} {r["ms"]:.6e}\n')
            out.write("\n\n")
    # A colour per method; the peers dashed.
    colours = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf",
               "#7f7f7f", "#bcbd22", "#000000", "#393b79", "#ad494a"]
    plots = ", ".join(f'"{data}" index {i} using 1:2 with linespoints lw 1.5 pt {i % 13 + 1} '
                      f'lc rgb "{colours[i % len(colours)]}" dt {1 if " " not in name else 2} title columnheader(1)'
                      for i, name in enumerate(series))
    for term, ext in (("pngcairo size 1000,700", "png"), ("svg size 1000,700", "svg")):
        script = f"""
set terminal {term}
set output "{os.path.join(outdir, f'work_precision_{problem}.{ext}')}"
set logscale xy
set format x "10^{{%T}}"
set format y "10^{{%T}}"
set xlabel "final error: max |q - q_{{ref}}|, |qd - qd_{{ref}}|"
set ylabel "CPU time per run (ms, median)"
set title "{problem.replace('_', ' ')}: work against precision"
set key outside right
set grid
plot {plots}
"""
        subprocess.run(["gnuplot"], input=script, text=True, check=True)
    os.remove(data)


def goal(runs):
    best = [r for r in runs if r["problem"] == "double_pendulum_1s" and r["error"] <= GOAL_ERROR]
    lines = []
    by_method = {}
    for r in best:
        m = method(r)
        if m not in by_method or r["ms"] < by_method[m]["ms"]:
            by_method[m] = r
    for m, r in sorted(by_method.items(), key=lambda kv: kv[1]["ms"]):
        lines.append(f'| {m} | {r["kind"]}={r["setting"]} | {r["error"]:.2e} | {r["ms"]:.3g} |')
    fastest = min(by_method.values(), key=lambda r: r["ms"]) if by_method else None
    met = fastest is not None and fastest["library"] == "symdyn" and fastest["ms"] < GOAL_MS
    return met, fastest, lines


def merge(partial, commit, results):
    new = [line.rstrip("\n").split("\t") for line in open(partial)]
    load = {f[1]: f[2] for f in new if f[0] == "meta"}
    rows = [f for f in new if f[0] in ("run", "fail")]
    # The new rows' errors are against the references of their own run.
    references = {f[1]: f for f in new if f[0] == "reference"}
    names = sorted({(f[2], f[3]) for f in rows})
    label = ", ".join(i for _, i in names)
    kept = []
    for line in open(results):
        f = line.rstrip("\n").split("\t")
        if f[0] in ("run", "fail") and (f[2], f[3]) in names:
            continue
        if f[0] == "meta" and f[1] == label:
            continue
        kept.append(f)
    # Each integrator's rows after the row before its first old one, else at the end of the problem.
    out = [f for f in kept if f[0] == "meta"]
    out.append(["meta", label, f"measured again at {commit}, load {load.get('load', '?')} before, "
                                f"{load.get('load_after', '?')} after, with the references; the other rows at the "
                                "commit above"])
    problems = [f[1] for f in kept if f[0] == "reference"]
    for p in problems:
        body = [f for f in kept if f[0] != "meta" and f[1] == p]
        out += [references.get(p, f) for f in body if f[0] == "reference"]
        out += [f for f in rows if f[0] == "run" and f[1] == p]
        out += [f for f in body if f[0] == "run"]
    out += [f for f in kept if f[0] == "fail" and f[1] in problems] + [f for f in rows if f[0] == "fail"]
    out += [f for f in kept if f[0] == "check"]
    with open(results, "w") as w:
        for f in out:
            w.write("\t".join(f) + "\n")


def main():
    if sys.argv[1] == "--merge":
        merge(sys.argv[2], sys.argv[3], sys.argv[4])
        return
    tsv, outdir = sys.argv[1], sys.argv[2]
    meta, refs, runs, fails, checks = read(tsv)
    problems = list(refs)
    md = ["# Work against precision: CPU time against final error", ""]
    md += [f"Machine: {meta.get('machine', '?')} ({meta.get('cpu', '?')}); {meta.get('compiler', '?')}.",
           f"Commit measured: `{meta.get('commit', '?')}`. Load average {meta.get('load', '?')} before, "
           f"{meta.get('load_after', '?')} after (a machine shared by other builds: CPU times, "
           "not wall times, are reported; differences under ~20 % are noise).",
           *[f"Note: {v}." if k == "note" else f"Measured separately: {k}: {v}." for k, v in meta.items()
             if k not in ("commit", "machine", "cpu", "compiler", "mujoco", "simbody", "load", "load_after")],
           f"Peers: MuJoCo {meta.get('mujoco', '?')}, Simbody {meta.get('simbody', '?')} (Debian packages).",
           "", "```sh", "bench/work_precision/run.sh          # builds, runs, writes this file, the .tsv and the diagrams",
           "```", "",
           "Each problem is the model's symdyn-sim scenario (apps/sim: initial state and force elements, "
           "e.g. the trike's tyres, suspensions, steering and drive) over the stated interval. Error: the "
           "largest |q - q_ref| and |qd - qd_ref| at the end; q_ref from dop853 at rtol = atol = 1e-13, "
           "confirmed by dopri5 at 1e-13 (their distance is the agreement below: errors under it are not "
           "resolved). Tolerances: rtol = atol; rk4 and midpoint take fixed steps h. CPU time: median over 5 "
           "repetitions (3 for runs over 1 s) of the process CPU time per run, each repetition a batch of at "
           "least 10 ms; a sweep stops after a run over 1 s of CPU.",
           "",
           "Peers on the double pendulum over 1 s (the same mechanism, built from bench/peers/mechanism.cpp's "
           "double_pendulum()): MuJoCo's mj_step at fixed steps with its Euler (semi-implicit), RK4 and "
           "implicit integrators, every option at MuJoCo's default except contacts and constraints disabled "
           "(there are none); Simbody's TimeStepper with RungeKuttaMersonIntegrator and CPodesIntegrator "
           "(its default BDF/Newton) at setAccuracy(tol), every other setting Simbody's default. Each peer's "
           "finest run is checked against the reference at t = 0.5 s and 1 s (within 1e-4) before it is "
           "plotted.", ""]
    met, fastest, lines = goal(runs)
    md += ["## Goal: 3e-8 on the double pendulum over 1 s in under 0.1 ms of CPU", ""]
    if fastest:
        md += [f"**{'Met' if met else 'Not met'}**: the cheapest run reaching {GOAL_ERROR:g} is "
               f"{method(fastest)} at {fastest['kind']}={fastest['setting']}, error {fastest['error']:.2e} in "
               f"{fastest['ms']:.3g} ms. Cheapest run of each method reaching it:", "",
               "| method | setting | error | CPU ms |", "|---|---|---:|---:|"] + lines + [""]
    findings = os.path.join(os.path.dirname(os.path.abspath(__file__)), "findings.md")
    if os.path.exists(findings):
        md += [open(findings).read().rstrip("\n"), ""]
    md += ["## Peer checks", "", "| library | integrator | finest setting | error at 0.5 s | error at 1 s | verdict |",
           "|---|---|---:|---:|---:|---|"]
    for c in checks:
        md.append(f"| {c[1]} | {c[2]} | {c[3]} | {c[4]} | {c[5]} | {c[6]} |")
    if fails:
        md += ["", "## Failures", "", "| problem | library | integrator | setting | message |", "|---|---|---|---|---|"]
        for f in fails:
            md.append(f"| {f[0]} | {f[1]} | {f[2]} | {f[3]}={f[4]} | {f[5].replace('|', '/')} |")
    for p in problems:
        rows = [r for r in runs if r["problem"] == p]
        agreement, what = refs[p]
        plot(p, rows, outdir)
        md += ["", f"## {p}", "", f"Reference: {what}: agreement {agreement:.1e}.", "",
               f"![{p}](work_precision_{p}.svg)", "",
               "| method | setting | final error | CPU ms | steps | rejected | accelerations |",
               "|---|---|---:|---:|---:|---:|---:|"]
        for r in rows:
            md.append(f'| {method(r)} | {r["kind"]}={r["setting"]} | {r["error"]:.2e} | {r["ms"]:.3g} | '
                      f'{r["steps"]} | {r["rejected"]} | {r["rhs"]} |')
    with open(os.path.join(outdir, "work_precision.md"), "w") as out:
        out.write("\n".join(md) + "\n")


if __name__ == "__main__":
    main()
