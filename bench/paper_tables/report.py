#!/usr/bin/env python3
"""Writes the paper tables from the raw measurements of run.sh.

    report.py --work DIR --results DIR --paper paper_numbers.json [--missing "a b"]

DIR/<model>/<variant>/case<c>/ holds stats.txt (generator --stats output),
generator_time.txt, tgen.json, compile_time.txt, bench.json (symdyn_paper_bench)
and, in cases 1-3, cas/ (the generator's --describe and what cagem_sympy.py and
cagem_giac.py measured: <tool>_case<c>.json).
Writes paper_tables.md, paper_tables.json and chain_scaling.png (gnuplot).
Standard library only.
"""
import argparse
import datetime
import hashlib
import json
import math
import pathlib
import re
import subprocess

HEADER_RE = re.compile(r"generated in ([0-9.]+) s, (\d+) bytes \((\d+) header \+ (\d+) source\)")
FUNCTION_RE = re.compile(r"^\s+(\w+)\s+(\d+) operations\s*(.*)$")
PAPER_MODELS = ["double_pendulum", "robot3d", "slider_crank", "trike", "amru5", "hexapod_tree"]
CASE_TEXT = {
    1: "no simplification, numeric partial velocities",
    2: "simplification, numeric partial velocities",
    3: "simplification, symbolic partial velocities",
    4: "as 3, with the mass matrix and bias forces emitted (Robotran-style)",
}
# The computer algebra measured beside symdyn (cagem_sympy.py, cagem_giac.py): file key, label.
CAS_TOOLS = [("sympy", "SymPy"), ("giac", "Giac")]
GIAC_FACTOR = 10  # target: symdyn's derivation at least this many times faster than Giac's


INSTRUCTION_NOISE = 1.01  # programs of equal operation counts differ by up to 0.6 % in instructions


def slower(fast, slow, key):
    """Whether row `slow` runs workload `key` (T1 or T2) slower than row `fast`:
    over 1 % more instructions per evaluation (callgrind). Timings cannot tell:
    on this shared machine the medians of identical code differ by up to 1.7x.
    Instructions are repeatable, but not time either: the same operations
    scheduled in another order (robot3d relative, cases 1 and 2) compile to
    0.6 % more of them."""
    return slow["instructions"][key] > INSTRUCTION_NOISE * fast["instructions"][key]


def run(cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return ""


def machine():
    cpu = next((l.split(":", 1)[1].strip() for l in run(["lscpu"]).splitlines() if l.startswith("Model name")), "?")
    cores = next((l.split(":", 1)[1].strip() for l in run(["lscpu"]).splitlines() if l.startswith("CPU(s)")), "?")
    hypervisor = next((l.split(":", 1)[1].strip() for l in run(["lscpu"]).splitlines()
                       if l.startswith("Hypervisor vendor")), None)
    compiler = run(["g++", "--version"]).splitlines()[:1]
    commit = run(["git", "rev-parse", "--short", "HEAD"]).strip()
    dirty = run(["git", "status", "--porcelain", "--untracked-files=no"]).strip()
    return {
        "cpu": cpu,
        "cpus": cores,
        "hypervisor": hypervisor,
        "compiler": compiler[0] if compiler else "?",
        "flags": "-std=c++20 -O2 -fPIC -fvisibility=hidden",
        "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
        "commit": commit + (" (with uncommitted changes)" if dirty else ""),
    }


def parse_stats(path):
    text = path.read_text()
    m = HEADER_RE.search(text)
    if not m:
        raise SystemExit(f"report.py: no --stats header in {path}")
    functions = {}
    for line in text.splitlines()[1:]:
        f = FUNCTION_RE.match(line)
        if f:
            detail = {}
            for part in (p.strip() for p in f.group(3).split(",")):
                if part in ("", "nothing"):
                    continue
                count, kind = part.split()
                detail[kind] = int(count)
            functions[f.group(1)] = {"total": int(f.group(2)), "detail": detail}
    return float(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4)), functions


# What a generation-only row (run.sh measures chain_N from N = 32 on without
# compiling or running its code) has instead of compile times and bench.json.
def generation_only(model):
    n = int(model[6:])
    return (None, None, None), {
        "nq": n, "nbody": n, "ndep": 0, "equations": None, "errors": {"max": None, "qdd_at_states": []},
        "timings": {k: None for k in ("T1", "T1_accelerations", "T1_partials", "T2", "T1_min", "T2_min", "reps")}}


LINK_GUARD_HASH = re.compile(r"(symdyn_model_\w+?)_[0-9a-f]{16}\b")


def code_digest(case_dir, model, variant):
    """A digest of the emitted code, its comments (they name the options) and the hash in its link
    guard's name (of everything, comments included) aside: rows of equal digests run the same code."""
    digest = hashlib.sha256()
    for suffix in (".hpp", ".cpp"):
        path = case_dir / f"{model}_{variant}{suffix}"
        if path.exists():
            for line in path.read_text().splitlines():
                if not line.startswith("//"):
                    digest.update(LINK_GUARD_HASH.sub(r"\1", line).encode() + b"\n")
    return digest.hexdigest()


def median_compilation(path):
    """The compilation of median CPU time (user + system) among the lines "wall user system" of path:
    its wall, user and system seconds, and every run's CPU seconds."""
    runs = sorted((tuple(float(x) for x in line.split()) for line in path.read_text().splitlines() if line.strip()),
                  key=lambda r: r[1] + r[2])
    wall, user, system = runs[(len(runs) - 1) // 2]
    return wall, user, system, [round(r[1] + r[2], 3) for r in runs]


def load_row(case_dir, model, variant, case):
    generator_wall, size, header, source, functions = parse_stats(case_dir / "stats.txt")
    process_wall = float((case_dir / "generator_time.txt").read_text().split()[0])
    tgen = json.loads((case_dir / "tgen.json").read_text())
    if (case_dir / "bench.json").exists():
        compile_wall, compile_user, compile_system, compile_runs = median_compilation(case_dir / "compile_time.txt")
        bench = json.loads((case_dir / "bench.json").read_text())
    else:
        (compile_wall, compile_user, compile_system), bench = generation_only(model)
        compile_runs = []
    ops = lambda name: functions.get(name, {}).get("total", 0)
    sincos = lambda name: functions.get(name, {}).get("detail", {}).get("sincos", 0)
    # Cases 3-4: accelerations and partial velocities from the one fused entry
    # point when emitted (as SymPy's one function), else the two.
    kin = ["accelerations"] + (["partial_velocities"] if case >= 3 else [])
    relative = ["relative_accelerations"] + (["relative_partial_velocities"] if case >= 3 else [])
    if case >= 3 and "accelerations_partials" in functions:
        kin, relative = ["accelerations_partials"], ["relative_accelerations_partials"]
    row = {
        "model": model, "variant": variant, "case": case,
        "nq": bench["nq"], "nbody": bench["nbody"], "ndep": bench["ndep"],
        "tgen": tgen["cpu"], "tgen_runs": tgen["cpu_runs"],
        "tgen_wall": tgen["wall"], "tgen_wall_runs": tgen["wall_runs"],
        "tgen_generator_reported": generator_wall, "generator_process_wall": process_wall,
        "size": size, "header_bytes": header, "source_bytes": source,
        "code_digest": code_digest(case_dir, model, variant),
        "operations": {k: v["total"] for k, v in functions.items()},
        "operation_detail": {k: v["detail"] for k, v in functions.items()},
        # Kinematics as timed in T1; each fused sin/cos pair counts once.
        "kinematics_ops": sum(ops(f) for f in kin),
        # The same with sin and cos counted as two calls, as SymPy's count does.
        "kinematics_ops_calls_apart": sum(ops(f) + sincos(f) for f in kin),
        "accelerations_ops_calls_apart": ops("accelerations") + sincos("accelerations"),
        # Each body relative to its reference, as CAGeM emitted and SymPy's reference counts.
        "relative_ops_calls_apart": sum(ops(f) + sincos(f) for f in relative),
        "eom_ops": ops("mass_matrix") + ops("bias_forces") if case == 4 else None,
        "compile_time": None if compile_user is None else compile_user + compile_system, "compile_wall": compile_wall,
        "compile_runs": compile_runs,
        "T1": bench["timings"]["T1"], "T1_accelerations": bench["timings"]["T1_accelerations"],
        "T1_partials": bench["timings"]["T1_partials"], "T2": bench["timings"]["T2"],
        "T1_min": bench["timings"]["T1_min"], "T2_min": bench["timings"]["T2_min"],
        "reps": bench["timings"]["reps"], "equations": bench["equations"],
        "errors": {k: v for k, v in bench["errors"].items() if k != "qdd_at_states"},
        "qdd_at_states": bench["errors"]["qdd_at_states"],
        # Instructions per evaluation of T1's and T2's workloads (callgrind; cases 1-2).
        "instructions": (json.loads((case_dir / "instructions.json").read_text())
                         if (case_dir / "instructions.json").exists() else None),
    }
    row["cagem_scope"] = cagem_scope(tgen)
    row["cas"] = {}
    for key, _ in CAS_TOOLS:
        path = case_dir / "cas" / f"{key}_case{case}.json"
        if path.exists():
            row["cas"][key] = json.loads(path.read_text())
    return row


def cagem_scope(tgen):
    """symdyn generating what CAGeM derives (and cagem_*.py), alone (generator --only, symdyn_paper_tgen):
    each body's motion relative to the reference the model file gives it, relative_accelerations
    (relative_accelerations_partials in case 3), or accelerations (accelerations_partials) when every body
    moves from the ground and the generator made some relative (chain_N absolute). Its Tgen, and its
    operations with a fused sin/cos pair once and with sin and cos apart. None in case 4."""
    scope = tgen.get("cagem_scope")
    if scope is None:
        return None
    return {"entries": scope["entry_points"], "tgen": scope["cpu"], "tgen_runs": scope["cpu_runs"],
            "fused": scope["operations"], "apart": scope["operations"] + scope["sincos"]}


def load_rows(work):
    rows = []
    for case_dir in sorted(work.glob("*/*/case*")):
        if (case_dir / "tgen.json").exists():
            model, variant = case_dir.parent.parent.name, case_dir.parent.name
            rows.append(load_row(case_dir, model, variant, int(case_dir.name[4:])))
    return rows


def cross_case_errors(rows):
    """Largest qdd difference of each row against every other case and variant of its model."""
    by_model = {}
    for r in rows:
        by_model.setdefault(r["model"], []).append(r)
    for group in by_model.values():
        for r in group:
            if not r["qdd_at_states"]:  # generation only
                r["errors"]["qdd_vs_other_cases"] = None
                continue
            worst = 0.0
            for o in group:
                if o is r:
                    continue
                for a, b in zip(r["qdd_at_states"], o["qdd_at_states"]):
                    scale = max([1.0] + [abs(x) for x in b])
                    worst = max(worst, max(abs(x - y) for x, y in zip(a, b)) / scale)
            r["errors"]["qdd_vs_other_cases"] = worst if len(group) > 1 else None


def fmt_bytes(n):
    return f"{n:,}".replace(",", " ")


def fmt_s(x):
    if x is None:
        return "—"
    return f"{x:.2g}" if x < 1e-3 else f"{x:.3g}" if x < 10 else f"{x:.1f}"


def fmt_e(x):
    return "—" if x is None else f"{x:.0e}" if x > 0 else "0"


def find(rows, model, variant, case):
    return next((r for r in rows if r["model"] == model and r["variant"] == variant and r["case"] == case), None)


def cas_label(rows, key):
    """"SymPy 1.11.1": the tool's name and the version its runs reported."""
    versions = sorted({r["cas"][key]["version"] for r in rows if r["cas"].get(key, {}).get("version")})
    return f"{dict(CAS_TOOLS)[key]} {versions[0]}" if versions else dict(CAS_TOOLS)[key]


def cas_time(res):
    status = res.get("status")
    if status == "timeout":
        return f"timeout (> {res.get('timeout', 0):g} s)"
    if status == "not run":
        return "not run"
    if res.get("cpu") is None:
        return status
    return fmt_s(res["cpu"]) + (" (failed)" if status == "error" else " (output not counted)" if status == "unparsed" else "")


def cas_ops(key, res):
    """Kinematics operations, CAGeM's scope: SymPy's cse output with sin and cos of one argument fused;
    Giac's output as emitted (no cse: sin, cos apart) and, in parentheses, each distinct subexpression once, fused."""
    if res.get("status") != "ok":
        return "—"
    if key == "sympy":
        return str(res["kinematics_fused"])
    return f"{res['kinematics_apart']} ({res['kinematics_shared_fused']})"


def ratio(a, b):
    return None if a is None or not b else a / b


def fmt_ratio(x, prefix=""):
    return "—" if x is None else f"{prefix}{x:.3g}"


def cas_ratios(key, res, r):
    """(Tgen ratio, kinematics ratio) of a tool's row to symdyn's, as text."""
    scope = r["cagem_scope"]
    status = res.get("status")
    ours = scope["tgen"] if scope else None
    if status == "timeout":
        t = fmt_ratio(ratio(res.get("timeout"), ours), "> ")
    elif status in ("ok", "unparsed"):
        t = fmt_ratio(ratio(res.get("cpu"), ours))
    else:
        t = "—"
    if status != "ok" or scope is None:
        return t, "—"
    if key == "sympy":
        return t, fmt_ratio(ratio(res["kinematics_fused"], scope["fused"]))
    return t, (f"{fmt_ratio(ratio(res['kinematics_apart'], scope['apart']))} "
               f"({fmt_ratio(ratio(res['kinematics_shared_fused'], scope['fused']))})")


def model_table(rows, paper, model, variant, out):
    paper_tables = [t for t in paper["tables"] if t["model"] == model and t["variant"] == variant]
    title = f"{model}, variant {variant}"
    if paper_tables:
        t = paper_tables[0]
        out.append(f"### Table {t['table']}: {title} (paper: \"{t['title']}\")\n")
    else:
        out.append(f"### {title} (not in the paper)\n")
    ours = [find(rows, model, variant, c) for c in (1, 2, 3, 4)]
    ref = next(r for r in ours if r)
    out.append(f"{ref['nbody']} bodies, {ref['nq']} DOF, {ref['ndep']} dependent parameters.\n")
    out.append("| System | Case | Tgen/s | Size/bytes | T1/s | T2/s | Kin. ops | CAGeM Tgen/s | CAGeM kin. ops | EoM ops "
               "| T1 partials/s | Compile/s | Max error | qdd vs other cases | Tgen / symdyn's | CAGeM kin. ops / symdyn's |")
    out.append("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for t in paper_tables:
        for system, cases in t["rows"].items():
            for c in cases:
                out.append(f"| {system} (paper) | {c[0]} | {c[1]} | {c[2]} | {c[3]} | {c[4]} | | | | | | | | | | |")
    for r in ours:
        if r is None:
            continue
        scope = r["cagem_scope"]
        out.append(
            f"| **symdyn** | {r['case']} | {fmt_s(r['tgen'])} | {fmt_bytes(r['size'])} | {fmt_s(r['T1'])} | {fmt_s(r['T2'])} "
            f"| {r['kinematics_ops']} | {fmt_s(scope['tgen']) if scope else '—'} | {scope['fused'] if scope else '—'} "
            f"| {r['eom_ops'] if r['eom_ops'] is not None else '—'} | {fmt_s(r['T1_partials'])} "
            f"| {fmt_s(r['compile_time'])} | {fmt_e(r['errors']['max'])} | {fmt_e(r['errors'].get('qdd_vs_other_cases'))} | | |")
    for key, _ in CAS_TOOLS:
        for r in ours:
            if r is None or key not in r["cas"]:
                continue
            res = r["cas"][key]
            t_ratio, ops_ratio = cas_ratios(key, res, r)
            size = fmt_bytes(res["size"]) if res.get("status") == "ok" else "—"
            out.append(f"| {cas_label(rows, key)} | {r['case']} | {cas_time(res)} | {size} | | | | | {cas_ops(key, res)} "
                       f"| | | | | | {t_ratio} | {ops_ratio} |")
    if len(paper_tables) > 1:
        out.append("")
    for t in paper_tables[1:]:
        out.append(f"(Paper Table {t['table']} also: \"{t['title']}\".)")
    out.append("")


def cas_section(rows, out):
    """Every model, variant and case measured by the computer algebra, chain_N included."""
    measured = [r for r in rows if r["cas"]]
    if not measured:
        out.append("No computer algebra measured (run.sh --cas none, or neither tool available).\n")
        return
    tools = [k for k, _ in CAS_TOOLS if any(k in r["cas"] for r in measured)]
    out.append("## symdyn against today's computer algebra, every row\n")
    out.append("CAGeM's derivation (bench/paper_tables/cagem_sympy.py, cagem_giac.py) run on the model the generator "
               "describes (`--describe`), in the same run as symdyn. symdyn generating CAGeM's scope alone (generator "
               "`--only`: each body relative to the reference the model file gives it, `relative_accelerations`, in case 3 "
               "`relative_accelerations_partials`; `accelerations` and `accelerations_partials` when every body moves from "
               "the ground and the generator made some relative), what the two scripts derive: its Tgen (median of the "
               "generations in process: model construction, derivation, simplification, CSE, printing) and its operations "
               "(a fused sin/cos pair once). Beside it, Tgen of the generator emitting every entry point. The tools' Tgen: "
               "CPU seconds, start-up excluded (SymPy: timed inside the script, after Python's start-up and imports; Giac: "
               "the fastest of the giac process's runs less that of interleaved runs of an empty program). SymPy's ops: its cse output by the "
               "same rule; Giac's: its output written in full (Giac has no cse), sin and cos apart, and in parentheses "
               "each distinct subexpression once, fused. Ratios: the tool's figure over symdyn's for CAGeM's scope.\n")
    head = "| Model | Variant | Case | symdyn Tgen/s, every entry point | symdyn Tgen/s | symdyn ops |"
    rule = "|---|---|---|---:|---:|---:|"
    for key in tools:
        label = cas_label(rows, key)
        head += f" {label} Tgen/s | {label} ops | Tgen ratio | ops ratio |"
        rule += "---:|---:|---:|---:|"
    out.append(head)
    out.append(rule)
    order = lambda r: (r["model"].startswith("chain_"), int(r["model"][6:]) if r["model"].startswith("chain_") else 0,
                       r["model"], r["variant"], r["case"])
    for r in sorted(measured, key=order):
        scope = r["cagem_scope"]
        line = (f"| {r['model']} | {r['variant']} | {r['case']} | {fmt_s(r['tgen'])} | "
                f"{fmt_s(scope['tgen']) if scope else '—'} | {scope['fused'] if scope else '—'} |")
        for key in tools:
            res = r["cas"].get(key)
            if res is None:
                line += " — | — | — | — |"
                continue
            t_ratio, ops_ratio = cas_ratios(key, res, r)
            line += f" {cas_time(res)} | {cas_ops(key, res)} | {t_ratio} | {ops_ratio} |"
        out.append(line)
    out.append("")


def fit_exponent(ns, values):
    """Least squares slope of log(value) against log(N)."""
    pts = [(math.log(n), math.log(v)) for n, v in zip(ns, values) if v and v > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


CHAIN_COLUMNS = [("tgen", "Tgen/s"), ("size", "Size/bytes"), ("kinematics_ops", "Kin. ops"),
                 ("eom_ops", "EoM ops"), ("T1", "T1/s"), ("T2", "T2/s"), ("compile_time", "Compile/s")]


def chain_study(rows, results, out, summary):
    chain = [r for r in rows if r["model"].startswith("chain_") and r["case"] == 4]
    if not chain:
        out.append("No chain_N measured (models/chain.cpp missing or not selected).\n")
        return
    out.append("## Scaling: chain_N (case 4)\n")
    out.append("Growth exponent p of each column, least squares of log(value) on log(N) over the N measured "
               "(value ~ N^p). Case 4: simplification, symbolic partial velocities, emitted mass matrix and bias forces. "
               "Kin. ops: accelerations_partials (accelerations and partial velocities in one function); "
               "EoM ops: mass_matrix + bias_forces.\n")
    for variant in ("relative", "absolute"):
        vr = sorted((r for r in chain if r["variant"] == variant), key=lambda r: int(r["model"][6:]))
        if not vr:
            continue
        ns = [int(r["model"][6:]) for r in vr]
        out.append(f"### chain_N, {variant}\n")
        out.append("| N | " + " | ".join(c[1] for c in CHAIN_COLUMNS) + " | Max error |")
        out.append("|---:|" + "---:|" * (len(CHAIN_COLUMNS) + 1))
        for n, r in zip(ns, vr):
            cells = [fmt_bytes(r[k]) if k == "size" else str(r[k]) if k.endswith("ops") else fmt_s(r[k]) for k, _ in CHAIN_COLUMNS]
            cells = [c.replace("None", "—") for c in cells]
            out.append(f"| {n} | " + " | ".join(cells) + f" | {fmt_e(r['errors']['max'])} |")
        exps = {k: fit_exponent(ns, [r[k] for r in vr]) for k, _ in CHAIN_COLUMNS}
        summary[variant] = {"N": ns, "exponents": exps,
                            **{k: [r[k] for r in vr] for k, _ in CHAIN_COLUMNS}}
        out.append("| **p** | " + " | ".join("—" if exps[k] is None else f"{exps[k]:.2f}" for k, _ in CHAIN_COLUMNS) + " | |")
        out.append("")
    plot_chain(summary, results)
    out.append("![chain_N scaling](chain_scaling.png)\n")


def plot_chain(summary, results):
    data = results / "chain_scaling.dat"
    lines = []
    for variant, s in summary.items():
        lines.append(f"# {variant}: N " + " ".join(k for k, _ in CHAIN_COLUMNS))
        for i, n in enumerate(s["N"]):
            lines.append(f"{n} " + " ".join(str(s[k][i]) for k, _ in CHAIN_COLUMNS))
        lines.append("\n")
    data.write_text("\n".join(lines))
    plots = []
    for col, (key, label) in enumerate(CHAIN_COLUMNS[:6], start=2):
        series = []
        for idx, variant in enumerate(summary):
            p = summary[variant]["exponents"][key]
            tag = f"{variant} (p = {p:.2f})" if p is not None else variant
            series.append(f"'{data}' index {idx} using 1:{col} with linespoints title '{tag}'")
        plots.append(f"set title '{label}'\nplot " + ", ".join(series))
    script = "\n".join([
        f"set terminal pngcairo size 1500,900 font ',10'", f"set output '{results / 'chain_scaling.png'}'",
        "set multiplot layout 2,3 title 'symdyn: chain\\_N scaling (case 4)'",
        "set logscale xy", "set xlabel 'N (bodies, DOF)'", "set key top left", "set grid",
        *plots, "unset multiplot"])
    try:
        subprocess.run(["gnuplot"], input=script, text=True, check=True)
    except (OSError, subprocess.CalledProcessError) as e:
        print(f"report.py: gnuplot failed ({e}); chain_scaling.png not written")
    data.unlink()


def verdict(ok):
    return "**met**" if ok else "**not met**"


def targets(rows, out):
    out.append("## Targets: generation, equations, compile time, computer algebra\n")
    out.append("Measured figures from the tables above. Generation times are medians; T1 and T2 are compared between "
               "cases 1 and 2 by the instructions their workloads execute per evaluation (valgrind --tool=callgrind, "
               "repeatable), since on this shared machine the medians of identical code differ by up to 1.7x.\n")
    results = []

    def add(name, ok, text):
        results.append({"target": name, "met": ok, "measured": text})
        out.append(f"- {name}: {verdict(ok) if ok is not None else '**not measured**'}. {text}")

    small = [r for r in rows if r["model"] in PAPER_MODELS and r["model"] != "amru5"]
    if small:
        worst = max(small, key=lambda r: r["tgen"])
        add("every paper model, variant and case (amru5 aside) and hexapod_tree generated in under 30 ms",
            worst["tgen"] < 0.030,
            f"Slowest: {worst['model']} {worst['variant']} case {worst['case']}, {worst['tgen'] * 1e3:.1f} ms "
            f"(CPU; wall {worst['tgen_wall'] * 1e3:.1f} ms; the whole generator process: {worst['generator_process_wall'] * 1e3:.0f} ms wall).")
    chain = [r for r in rows if r["model"].startswith("chain_")]
    if chain:
        over = [r for r in chain if r["tgen"] >= 0.030]
        worst = max(chain, key=lambda r: r["tgen"])
        out.append(f"  - (for information, no target) chain_N: {len(over)} of {len(chain)} rows at 30 ms or more; "
                   f"slowest {worst['model']} {worst['variant']} case {worst['case']}, {worst['tgen'] * 1e3:.1f} ms.")
    amru = [r for r in rows if r["model"] == "amru5"]
    if amru:
        worst = max(amru, key=lambda r: r["tgen"])
        add("amru5 generated in every case in under 0.3 s", worst["tgen"] < 0.3,
            f"Slowest: {worst['variant']} case {worst['case']}, {worst['tgen']:.3f} s.")
    else:
        add("amru5 generated in every case in under 0.3 s", None, "amru5 not measured.")
    c64 = [r for r in rows if r["model"] == "chain_64" and r["variant"] == "absolute"]
    if c64:
        worst = max(c64, key=lambda r: r["tgen"])
        add("chain_64 absolute generated in under 1 s", worst["tgen"] < 1.0,
            f"Slowest case {worst['case']}: {worst['tgen']:.3f} s.")
    else:
        add("chain_64 absolute generated in under 1 s", None, "chain_64 not measured.")
    # Simplification (case 2) against case 1.
    bad = []
    pairs = identical = 0
    ratios = {"T1": [], "T2": []}
    for r1 in (r for r in rows if r["case"] == 1):
        r2 = find(rows, r1["model"], r1["variant"], 2)
        if not r2 or r1["instructions"] is None or r2["instructions"] is None:
            continue
        pairs += 1
        if r1["code_digest"] == r2["code_digest"]:
            identical += 1  # the same code: T1 and T2 differ by the machine's noise alone
            continue
        for key in ratios:
            ratios[key].append(r2["instructions"][key] / r1["instructions"][key])
        checks = [("size", r2["size"] <= r1["size"], f"{r2['size']} > {r1['size']} bytes"),
                  ("ops", r2["kinematics_ops"] <= r1["kinematics_ops"], f"{r2['kinematics_ops']} > {r1['kinematics_ops']} ops"),
                  *((key, not slower(r1, r2, key),
                     f"{key} {r2['instructions'][key]} > 1.01 x {r1['instructions'][key]} instructions per evaluation")
                    for key in ("T1", "T2"))]
        for _, ok, text in checks:
            if not ok:
                bad.append(f"{r1['model']} {r1['variant']}: {text}")
    gains = [find(rows, r["model"], r["variant"], 2)["kinematics_ops"] / r["kinematics_ops"]
             for r in rows if r["case"] == 1 and find(rows, r["model"], r["variant"], 2) and r["kinematics_ops"]]
    add("simplification never makes the code longer or slower than case 1 (case 2 against case 1: size, kinematics "
        "operations, T1, T2; slower: over 1 % more instructions per evaluation)", not bad,
        f"{pairs} model/variant pairs, of which {identical} emit the same code in both cases (comments aside: "
        f"simplification changes nothing there, so neither its size nor its speed); case 2 / case 1 kinematics "
        f"operations from {min(gains):.2f} to {max(gains):.2f}"
        + "".join(f", {key} instructions from {min(v):.3f} to {max(v):.3f}" for key, v in ratios.items() if v)
        + ". "
        + ("Exceptions: " + "; ".join(bad) + "." if bad else "No exception."))
    cas_targets(rows, add)
    for variant in ("inline", "dependent"):
        r = find(rows, "amru5", variant, 4)
        name = f"amru5 {variant} emitted equations of motion (case 4) at most 500 operations per DOF"
        if r:
            per = r["eom_ops"] / r["nq"]
            add(name, per <= 500, f"mass_matrix + bias_forces: {r['eom_ops']} operations, {per:.0f} per DOF.")
        else:
            add(name, None, "amru5 not measured.")
        sub = [r for r in rows if r["model"] == "amru5" and r["variant"] == variant]
        name = f"amru5 {variant} emitted code compiles in under 10 s at -O2 (every case)"
        if sub:
            worst = max(sub, key=lambda r: r["compile_time"])
            add(name, worst["compile_time"] < 10, f"Slowest: case {worst['case']}, {worst['compile_time']:.1f} s.")
        else:
            add(name, None, "amru5 not measured.")
    out.append("")
    return results


def row_name(r):
    return f"{r['model']} {r['variant']} case {r['case']}"


def cas_targets(rows, add):
    """The two targets against the computer algebra, from this run's measurements."""
    # symdyn's kinematics no longer than SymPy's.
    compared, longer, missing = [], [], []
    for r in rows:
        res = r["cas"].get("sympy")
        if res is None:
            continue
        if res.get("status") != "ok" or r["cagem_scope"] is None:
            missing.append(f"{row_name(r)} ({res.get('status') if res.get('status') != 'ok' else 'no symdyn counterpart'})")
            continue
        ours, theirs = r["cagem_scope"]["fused"], res["kinematics_fused"]
        compared.append(ours / theirs)
        if ours > theirs:
            longer.append(f"{row_name(r)}: symdyn {ours} > SymPy {theirs} ({ours / theirs:.2f} x; sin, cos apart: "
                          f"{r['cagem_scope']['apart']} against {res['kinematics_apart']})")
    name = "symdyn's kinematics no longer than SymPy's (CAGeM's scope, cse, a fused sin/cos pair once), every model/case row"
    if not compared:
        add(name, None, "SymPy not measured.")
    else:
        add(name, not longer,
            f"{len(compared)} rows compared, symdyn / SymPy from {min(compared):.2f} to {max(compared):.2f}; "
            + (f"{len(longer)} longer: " + "; ".join(longer) + "." if longer else "none longer.")
            + (f" Not compared (SymPy timed out or failed): {'; '.join(missing)}." if missing else ""))
    # symdyn's derivation at least GIAC_FACTOR times faster than Giac's.
    compared, slow, failed = [], [], []
    for r in rows:
        res = r["cas"].get("giac")
        if res is None or res.get("status") == "not run" or r["cagem_scope"] is None:
            continue
        ours = r["cagem_scope"]["tgen"]
        if res.get("status") == "timeout":
            compared.append(res["timeout"] / ours)  # at least
            continue
        if res.get("status") not in ("ok", "unparsed") or res.get("cpu") is None:
            failed.append(f"{row_name(r)} ({res.get('message', res.get('status'))})")
            continue
        factor = res["cpu"] / ours
        compared.append(factor)
        if factor < GIAC_FACTOR:
            slow.append(f"{row_name(r)}: Giac {res['cpu'] * 1e3:.1f} ms, symdyn {ours * 1e3:.2f} ms ({factor:.1f} x)")
    name = (f"symdyn's derivation at least {GIAC_FACTOR}x faster than Giac's (CAGeM's scope, CPU, Giac's start-up "
            "subtracted), every model and case")
    if not compared:
        add(name, None, "Giac not measured.")
    else:
        add(name, not slow,
            f"{len(compared)} rows compared (a Giac timeout counts as its limit), Giac / symdyn from "
            f"{min(compared):.1f} to {max(compared):.0f}; "
            + (f"{len(slow)} under {GIAC_FACTOR}x: " + "; ".join(slow) + "." if slow else f"none under {GIAC_FACTOR}x.")
            + (f" Giac failed (not compared): {'; '.join(failed)}." if failed else ""))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--work", required=True, type=pathlib.Path)
    ap.add_argument("--results", required=True, type=pathlib.Path)
    ap.add_argument("--paper", required=True, type=pathlib.Path)
    ap.add_argument("--missing", default="")
    ap.add_argument("--reps", type=int, default=7)
    ap.add_argument("--gen-runs", type=int, default=5)
    ap.add_argument("--note", default="", help="a sentence added to the set-up line (e.g. rows measured again)")
    args = ap.parse_args()
    paper = json.loads(args.paper.read_text())
    rows = load_rows(args.work)
    if not rows:
        raise SystemExit(f"report.py: no measurement under {args.work}")
    cross_case_errors(rows)
    m = machine()
    missing = args.missing.split()
    out = ["# The paper's tables, reproduced by symdyn\n",
           "Generated by `bench/paper_tables/run.sh` (see bench/README.md); do not edit by hand.\n",
           f"- Ours: {m['cpu']} ({m['cpus']} vCPUs{' under ' + m['hypervisor'] if m['hypervisor'] else ''}, shared with "
           f"other jobs), {m['compiler']}, emitted code compiled with "
           f"`{m['flags']}`; {m['date']}; commit {m['commit']}." + (f" {args.note}" if args.note else ""),
           f"- The paper's: {paper['machine']}, {paper['systems']['MuPAD']} and {paper['systems']['Xcas/Giac']} "
           "(numbers copied as printed; \"—\" where Giac crashed).",
           f"- Models measured: {', '.join(sorted({r['model'] for r in rows}, key=lambda s: (s.startswith('chain'), len(s) if s.startswith('chain') else 0, s)))}."
           + (f" Missing (no model file yet): {', '.join(missing)}." if missing else ""),
           "",
           "Cases: " + "; ".join(f"{c} = {t}" for c, t in CASE_TEXT.items()) + ". Paper Table 7's case A is "
           "beside our case 1 and B (symbolic partials, MuPAD without simplification) beside our cases 3-4.\n",
           "Columns:",
           f"- Tgen: generation in CPU seconds, median of {args.gen_runs} generations in process (`symdyn_paper_tgen`: "
           "model construction, derivation, simplification, scheduling and printing, what the generator does between "
           "its command line and its files). The JSON also has the wall times (`tgen_wall`), the time the generator "
           "executable reported (`tgen_generator_reported`) and its whole process' wall time "
           "(`generator_process_wall`): on this shared machine wall times run 2-5 times longer.",
           "- Size: bytes of the emitted header and source together (SymPy, Giac: of the emitted C functions).",
           f"- T1: CPU seconds of the measuring thread (wall time would count the time other jobs took) for 10 000 evaluations of the kinematics of all bodies, median of {args.reps} runs: the emitted "
           "`accelerations()` (rotation, position, velocity, angular velocity, acceleration, angular acceleration of "
           "every body) and, in cases 3-4 only, `partial_velocities()` (symbolic). As in the paper, numeric partial "
           "velocities (cases 1-2) are not in T1; T1 partials gives 10 000 `partial_velocities()` alone in every case "
           "(cases 1-2: nq + 1 calls of `velocities()`).",
           f"- T2: CPU seconds for 1 000 evaluations of the equations of motion under gravity (no force element), median of "
           f"{args.reps} runs: `runtime::MultibodySystem::accelerations` = mass matrix, right-hand side and LDLT solve "
           "for qdd; assembled from the kinematics and partial velocities (EasyDyn's way) in cases 1-3, from the "
           "emitted `mass_matrix` and `bias_forces` in case 4.",
           "- Kin. ops: arithmetic operations and calls of the emitted `accelerations()` in cases 1-2, of "
           "`accelerations_partials()` (accelerations and partial velocities in one function, as SymPy's) in cases 3-4 "
           "(a fused sin/cos pair counts once). EoM ops: `mass_matrix` + `bias_forces` (case 4).",
           "- CAGeM Tgen and CAGeM kin. ops: symdyn generating the kinematics of CAGeM's scope alone (generator `--only`, "
           "Tgen as above), each body relative to the reference the model file gives it (positions, velocities, "
           "accelerations; in case 3 also the partial velocities), as CAGeM derived them and the computer algebra rows do: "
           "`relative_accelerations` (case 3: `relative_accelerations_partials`, both in one function, as SymPy's), or "
           "`accelerations` (case 3: `accelerations_partials`) when every body moves from the ground and the generator "
           "made some relative to another (chain_N absolute); a fused sin/cos pair once. SymPy: its cse output counted by the same "
           "rule (bench/paper_tables/opcount.py); Giac: its output written in full (no cse in Giac), sin and cos apart, "
           "and in parentheses each distinct subexpression once, fused.",
           "- SymPy and Giac rows: CAGeM's derivation (bench/paper_tables/cagem_sympy.py, cagem_giac.py) on the model "
           "the generator describes (`--describe`), run in this run; Tgen in CPU seconds with the tool's start-up "
           "excluded (SymPy timed inside the script after its imports; Giac: the fastest of the giac process's runs less "
           "that of interleaved runs of an empty program), \"timeout\" past run.sh's --cas-timeout. Tgen / symdyn's and CAGeM kin. ops / "
           "symdyn's: the tool's figure over symdyn's CAGeM Tgen and CAGeM kin. ops in the same case (Giac's ops: as emitted over symdyn's with sin, cos apart, and in parentheses "
           "shared over fused).",
           "- Compile: CPU seconds (user + system) to compile the emitted source with g++ at -O2, median of the "
           "runs (the JSON has every run's, `compile_runs`, and the median run's wall time, `compile_wall`).",
           "- Max error: largest of the errors of R, x, v, w, a, dw, the partial velocities and qdd against an "
           "independent reference (4x4 products of the elementary motions evaluated numerically, fourth-order central "
           "differences along the path and in each q, qdd from M and h assembled from those), at 3 random states "
           "(q = q0 + 0.1 U(-1, 1), qd, qdd, t = U(-1, 1)), each as max |ours - ref| / max(1, max |ref|); the finite "
           "differences limit it to about 1e-9. qdd vs other cases: the same measure between this row's qdd and every "
           "other case and variant of the model at the same states.",
           ""]
    out.append("## Tables\n")
    pairs = sorted({(r["model"], r["variant"]) for r in rows if not r["model"].startswith("chain_")},
                   key=lambda mv: (next((t["table"] for t in paper["tables"] if (t["model"], t["variant"]) == mv), 99), mv))
    for model, variant in pairs:
        model_table(rows, paper, model, variant, out)
    target_results = targets(rows, out)
    cas_section(rows, out)
    summary = {}
    chain_study(rows, args.results, out, summary)
    chain_rows = [r for r in rows if r["model"].startswith("chain_")]
    if chain_rows:
        out.append("### chain_N, every case\n")
        out.append("| Model | Variant | Case | Tgen/s | Size/bytes | T1/s | T2/s | Kin. ops | EoM ops | Compile/s | Max error |")
        out.append("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
        for r in sorted(chain_rows, key=lambda r: (r["variant"], int(r["model"][6:]), r["case"])):
            out.append(f"| {r['model']} | {r['variant']} | {r['case']} | {fmt_s(r['tgen'])} | {fmt_bytes(r['size'])} | "
                       f"{fmt_s(r['T1'])} | {fmt_s(r['T2'])} | {r['kinematics_ops']} | "
                       f"{r['eom_ops'] if r['eom_ops'] is not None else '—'} | {fmt_s(r['compile_time'])} | {fmt_e(r['errors']['max'])} |")
        out.append("")
    args.results.mkdir(parents=True, exist_ok=True)
    (args.results / "paper_tables.md").write_text("\n".join(out) + "\n")
    for r in rows:
        r.pop("qdd_at_states")
    doc = {"machine": m, "note": args.note, "paper": {"machine": paper["machine"], "systems": paper["systems"]},
           "missing_models": missing, "cases": CASE_TEXT, "rows": rows, "targets": target_results,
           "chain_scaling": summary, "paper_tables": paper["tables"]}
    (args.results / "paper_tables.json").write_text(json.dumps(doc, indent=1) + "\n")
    print(f"wrote {args.results / 'paper_tables.md'} and paper_tables.json ({len(rows)} rows)")


if __name__ == "__main__":
    main()
