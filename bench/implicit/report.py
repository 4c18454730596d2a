#!/usr/bin/env python3
"""The section of bench/results/derivatives.md written by before_after.sh.

  report.py WORK_DIR [--into FILE]

Writes WORK_DIR/section.md and, with --into, puts it in FILE in place of the
section of the same title (at the end when it has none).

WORK_DIR holds meta.txt (key = value lines) and runs.tsv, whose lines are
  <side> <problem> <integrator> <tol> <rep> <cpu_ms> <steps> <rejected> <newton>
  <residuals> <rhs> <jacobians> <q..> <qd..>
(the last fields as symdyn_bench_implicit_run prints them); side is "old" or "new".
The references are the runs of integrators dop853 and dopri5.
"""
import math
import statistics
import sys
from collections import defaultdict
from pathlib import Path

TITLE = "## Implicit integrators against the code before the exact derivatives (2dd6e1f)"
TARGET_ERRORS = [1e-4, 1e-5, 1e-6]
REFERENCE, CHECK = "dop853", "dopri5"
COUNTERS = ["steps", "rejected", "newton", "residuals", "rhs", "jacobians"]


class Run:
    def __init__(self, fields):
        self.cpu = [float(fields[0])]
        self.counts = dict(zip(COUNTERS, map(int, fields[1:7])))
        self.state = [float(x) for x in fields[7:]]


def read_instructions(path):
    """(side, problem, integrator, tol) -> instructions, from instructions.tsv when there."""
    if not Path(path).exists():
        return {}
    rows = (line.split("\t") for line in Path(path).read_text().splitlines())
    return {(side, p, i, float(tol)): int(n) for side, p, i, tol, n in rows}


def read_runs(path):
    runs = {}  # (side, problem, integrator, tol) -> Run, the CPU times of every repetition
    for line in Path(path).read_text().splitlines():
        side, problem, integrator, tol, _rep, *fields = line.split("\t")
        key = (side, problem, integrator, float(tol))
        if key in runs:
            runs[key].cpu += [float(fields[0])]
        else:
            runs[key] = Run(fields)
    return runs


def distance(a, b):
    return max(abs(x - y) for x, y in zip(a, b))


def fmt_count(n):
    return f"{n:,}".replace(",", " ")


def interpolate(points, error):
    """CPU at this error on the log-log line through the two runs around it (points: (error, cpu))."""
    points = sorted(points)
    for (e0, c0), (e1, c1) in zip(points, points[1:]):
        if e0 <= error <= e1 and e0 < e1:
            w = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(c0) + w * (math.log(c1) - math.log(c0)))
    return None


def slope(points):
    """Least-squares slope of log y against log x."""
    xs, ys = [math.log(x) for x, _ in points], [math.log(y) for _, y in points]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def loosest_reaching(rows, error):
    """The run of the loosest tolerance whose error is at most this one."""
    reaching = [r for r in rows if r["error"] <= error]
    return max(reaching, key=lambda r: r["tol"]) if reaching else None


def make_section(work):
    work = Path(work)
    meta = dict(line.split(" = ", 1) for line in (work / "meta.txt").read_text().splitlines() if " = " in line)
    runs = read_runs(work / "runs.tsv")
    problems = list(dict.fromkeys((p, i) for (_, p, i, _) in runs if i not in (REFERENCE, CHECK)))
    ref = {p: runs[("new", p, REFERENCE, t)] for (s, p, i, t) in runs if s == "new" and i == REFERENCE}
    out = [TITLE, ""]
    out.append(
        f"`{meta['command']}` (`bench/implicit/`): `symdyn_bench_implicit_run` (`implicit_run.cpp`, one run of a "
        "built-in scenario as symdyn-sim runs it, force elements included, nothing written on the way) built from "
        f"the same source in the tree of commit {meta['old']} (\"before\": the code before the exact derivatives, "
        "where Newmark's iteration matrix took C and K from central differences and CVODE differenced its own "
        f"Jacobian) and in today's ({meta['new']}, \"after\"), each run in its own process, the two builds "
        f"interleaved, {meta['reps']} repetitions. CPU: the median of the process CPU time of the run alone (the "
        "scenario's set-up excluded). Error: the largest |q − q_ref|, |qd − qd_ref| at t_end against "
        f"{REFERENCE} at rtol = atol = 1e-12 of today's build. Newmark's error goes as tol^(2/3) before and as tol "
        "after: the same tolerance is not the same error, so the runs are compared at the same error. Between the "
        "two trees: Newmark's rework (its error at t_end in proportion to the tolerance, Newton stopped on its "
        "estimated remaining error, about one iteration per step, a parabola's prediction), the exact Jacobians "
        "(Newmark's iteration matrix, CVODE's dense Jacobian) and all else on main since; the share of the exact "
        "Jacobians alone, the same build with differenced ones, is in \"Implicit integrators: exact against "
        "differenced Jacobians\".")
    out.append("")
    out.append(f"- machine: {meta['machine']}")
    out.append(f"- compiler: {meta['compiler']}")
    out.append(f"- commits: before {meta['old']}, after {meta['new']}")
    out.append(f"- load: {meta['load_start']} at the start, {meta['load_end']} at the end (1, 5, 15 minute averages)")
    counted = " (callgrind's runs included)" if (work / "instructions.tsv").exists() else ""
    out.append(f"- duration: {meta['duration']} s, the builds excluded{counted}")
    out.append("")
    out.append("The same problem in both trees, and the references (rtol = atol = 1e-12):")
    out.append("")
    for p in dict.fromkeys(p for p, _ in problems):
        r = ref[p]
        tol = next(t for (s, q, i, t) in runs if q == p and i == REFERENCE)
        check = runs[("new", p, CHECK, tol)]
        old_ref = runs[("old", p, REFERENCE, tol)]
        out.append(
            f"- {p}: {REFERENCE} after against {CHECK} after {distance(r.state, check.state):.1e}, "
            f"against {REFERENCE} before {distance(r.state, old_ref.state):.1e} "
            f"(largest |q|, |qd| at the end {max(abs(x) for x in r.state):.3g})")
    out.append("")

    rows = defaultdict(list)  # (problem, integrator, side) -> rows by tolerance
    for (side, p, i, tol), run in sorted(runs.items(), key=lambda kv: (kv[0][1], kv[0][2], -kv[0][3], kv[0][0])):
        if i in (REFERENCE, CHECK):
            continue
        differenced = 4 * len(run.state) // 2 * run.counts["jacobians"] if (side, i) == ("old", "newmark") else 0
        rows[(p, i, side)].append({"tol": tol, "error": distance(run.state, ref[p].state),
                                   "cpu": statistics.median(run.cpu), "all": run.counts["residuals"] + differenced,
                                   **run.counts})
    out.append("Every run. Residuals: the integrator's calls; before, each of Newmark's Jacobians also took 4·nq "
               "residuals of central differences, not counted there, added in \"all residuals\" (after, the "
               "Jacobians are exact: no residual). Right-hand sides: CVODE's calls, before with its own forward "
               "differences of the Jacobian (2·nq per Jacobian) among them.")
    out.append("")
    out.append("| problem | integrator | tol | side | error | CPU (ms) | steps | rejected | Newton iterations | "
               "residuals | all residuals | right-hand sides | Jacobians |")
    out.append("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for p, i in problems:
        for side in ("old", "new"):
            for r in rows[(p, i, side)]:
                out.append(f"| {p} | {i} | {r['tol']:g} | {'before' if side == 'old' else 'after'} | "
                           f"{r['error']:.2e} | {r['cpu']:.1f} | "
                           + " | ".join(fmt_count(r[c]) for c in COUNTERS[:-2]) + f" | {fmt_count(r['all'])} | "
                           + " | ".join(fmt_count(r[c]) for c in COUNTERS[-2:]) + " |")
    out.append("")
    same = [f"{p} {i} before at {a['tol']:g} and after at {b['tol']:g} ({fmt_count(a['steps'])} steps, CPU "
            f"{a['cpu']:.1f} and {b['cpu']:.1f} ms)"
            for p, i in problems for a in rows[(p, i, "old")] for b in rows[(p, i, "new")]
            if (a["steps"], a["newton"], a["jacobians"]) == (b["steps"], b["newton"], b["jacobians"])]
    if same:
        out.append("Runs that take the same steps, Newton iterations and Jacobians before and after (the same "
                   "integration, the difference in CPU is the cost of the evaluations): " + "; ".join(same) + ".")
        out.append("")
    out.append("How the error follows the tolerance (least-squares slope of log error against log tol over the sweep):")
    out.append("")
    for p, i in problems:
        slopes = [slope([(r["tol"], r["error"]) for r in rows[(p, i, s)]]) for s in ("old", "new")]
        out.append(f"- {p}, {i}: before {slopes[0]:.2f}, after {slopes[1]:.2f}")
    out.append("")

    out.append("At the same error: \"interpolated\", the CPU of each side on the log-log line between its two runs "
               "around that error; \"loosest reaching\", each side's run of the loosest tolerance whose error is at "
               "most that error (its tolerance and error given).")
    out.append("")
    out.append("| problem | integrator | error | before, interpolated (ms) | after, interpolated (ms) | "
               "before / after | before: tol, error, CPU (ms) | after: tol, error, CPU (ms) | before / after |")
    out.append("|---|---|---:|---:|---:|---:|---|---|---:|")
    verdicts = {}
    for p, i in problems:
        for target in TARGET_ERRORS:
            cells, ratios = [], []
            interp = [interpolate([(r["error"], r["cpu"]) for r in rows[(p, i, s)]], target) for s in ("old", "new")]
            cells += [f"{c:.1f}" if c else "outside" for c in interp]
            ratios.append(interp[0] / interp[1] if all(interp) else None)
            cells.append(f"**{ratios[0]:.2f}**" if ratios[0] else "")
            picks = [loosest_reaching(rows[(p, i, s)], target) for s in ("old", "new")]
            cells += [f"{r['tol']:g}, {r['error']:.1e}, {r['cpu']:.1f}" if r else "not reached" for r in picks]
            ratios.append(picks[0]["cpu"] / picks[1]["cpu"] if all(picks) else None)
            cells.append(f"**{ratios[1]:.2f}**" if ratios[1] else "")
            out.append(f"| {p} | {i} | {target:.0e} | " + " | ".join(cells) + " |")
            verdicts[(p, i, target)] = ratios
    out.append("")

    instructions = read_instructions(work / "instructions.tsv")
    counted = {}
    if instructions:
        table, counted = instruction_table(instructions, rows)
        out += table
    for target in (1e-4, 1e-6):
        ratios = verdicts.get(("amru5_2s", "newmark", target), [None, None])
        shown = [f"{r:.2f}x" if r else "not measured" for r in ratios]
        count = counted.get(("amru5_2s", "newmark", target))
        shown[0] += f" ({count:.2f}x in instructions)" if count else ""
        verdict = ("not measured" if None in ratios else "met" if min(ratios) >= 1.5
                   else "not met" if max(ratios) < 1.5 else "met interpolated only" if ratios[0] >= 1.5
                   else "met between the loosest tolerances only")
        out.append(f"Target: Newmark on amru5 at least 1.5 times faster at the same error, against the code before "
                   f"(2dd6e1f), at error {target:.0e}: **{verdict}**, {shown[0]} interpolated, "
                   f"{shown[1]} between the loosest tolerances reaching it.")
        out.append("")
    return "\n".join(out).rstrip() + "\n"


def instruction_table(instructions, rows):
    """Instructions of the runs counted (callgrind), and before / after at the target errors on their log-log
    line: the table's lines and those ratios by (problem, integrator, error)."""
    ratios = {}
    out = ["Instructions of the integration (callgrind, `--toggle-collect='*integrate_with_breakpoints*'`, one "
           "run each; repeatable where the CPU times of a shared machine are not), interpolated at the same error "
           "as above:", "",
           "| problem | integrator | error | before (G instructions) | after (G instructions) | before / after |",
           "|---|---|---:|---:|---:|---:|"]
    for p, i in dict.fromkeys((p, i) for (_, p, i, _) in instructions):
        lines = []
        for side in ("old", "new"):
            errors = {r["tol"]: r["error"] for r in rows[(p, i, side)]}
            lines.append([(errors[t], n) for (s, q, j, t), n in instructions.items()
                          if (s, q, j) == (side, p, i) and t in errors])
        for target in TARGET_ERRORS:
            counts = [interpolate(points, target) for points in lines]
            cells = [f"{c / 1e9:.3f}" if c else "outside" for c in counts]
            if all(counts):
                ratios[(p, i, target)] = counts[0] / counts[1]
            ratio = f"**{ratios[(p, i, target)]:.2f}**" if all(counts) else ""
            out.append(f"| {p} | {i} | {target:.0e} | {cells[0]} | {cells[1]} | {ratio} |")
    return out + [""], ratios


def put_section(section, path):
    """section in place of the one of the same title in path (up to the next "## " heading); a
    first time, after the section on exact against differenced Jacobians, else at the end."""
    lines = Path(path).read_text().splitlines(keepends=True)
    headings = [k for k, line in enumerate(lines) if line.startswith("## ")] + [len(lines)]
    if TITLE + "\n" in lines:
        begin = lines.index(TITLE + "\n")
        end = next(k for k in headings if k > begin)
    else:
        after = next((k for k in headings[:-1] if lines[k].startswith("## Implicit integrators: exact")), None)
        begin = end = next(k for k in headings if k > after) if after is not None else len(lines)
    head = "".join(lines[:begin]).rstrip("\n") + "\n\n"
    tail = "\n" + "".join(lines[end:]) if end < len(lines) else ""
    Path(path).write_text(head + section + tail)


if __name__ == "__main__":
    section = make_section(sys.argv[1])
    (Path(sys.argv[1]) / "section.md").write_text(section)
    if len(sys.argv) == 4 and sys.argv[2] == "--into":
        put_section(section, sys.argv[3])
