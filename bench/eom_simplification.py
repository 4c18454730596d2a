#!/usr/bin/env python3
"""Operation counts and generation times of two builds of symdyn, side by side.

    bench/eom_simplification.py --before OLD_BUILD --after NEW_BUILD [--runs 5] > out.md

OLD_BUILD and NEW_BUILD are release build directories (build/release) holding
models/symdyn_generator_<model> and bench/symdyn_paper_tgen. For every reference
model and variant, the generators run with --stats in the four cases of
docs/design.md (case 1: --no-simplify --partials numeric --no-eom; 2: --partials
numeric --no-eom; 3: --no-eom; 4: the default), and symdyn_paper_tgen gives the
generation time (CPU, median of --runs). Prints Markdown tables: the equations
of motion (case 4: mass_matrix, bias_forces, dynamics), the kinematics
(accelerations, relative_accelerations and, in case 3, their partial velocities
apart or in the fused *_partials entry points; "calls apart" counts a fused
sin/cos pair as two calls, as SymPy's count does) and the generation times.
Standard library only.
"""
import argparse
import json
import pathlib
import re
import subprocess
import tempfile

MODELS = [("double_pendulum", "absolute"), ("double_pendulum", "relative"), ("robot3d", "absolute"),
          ("robot3d", "relative"), ("slider_crank", "inline"), ("slider_crank", "dependent"), ("trike", "default"),
          ("hexapod_tree", "default"), ("amru5", "inline"), ("amru5", "dependent"), ("chain_64", "absolute"),
          ("chain_64", "relative")]
CASES = {1: ["--no-simplify", "--partials", "numeric", "--no-eom"], 2: ["--partials", "numeric", "--no-eom"],
         3: ["--no-eom"], 4: []}
FUNCTION_RE = re.compile(r"^\s+(\w+)\s+(\d+) operations\s*(.*)$")


def generator(build, model):
    return build / "models" / f"symdyn_generator_{'chain' if model.startswith('chain') else model}"


def stats(build, model, variant, case):
    """{function: (operations, sincos pairs)} from the generator's --stats."""
    with tempfile.TemporaryDirectory() as out:
        text = subprocess.run([str(generator(build, model)), "--model", model, "--variant", variant, "--out", out,
                               "--stats"] + CASES[case], capture_output=True, text=True, check=True).stdout
    functions = {}
    for line in text.splitlines()[1:]:
        m = FUNCTION_RE.match(line)
        if m:
            sincos = re.search(r"(\d+) sincos", m.group(3))
            functions[m.group(1)] = (int(m.group(2)), int(sincos.group(1)) if sincos else 0)
    return functions


def tgen(build, model, variant, case, runs):
    out = subprocess.run([str(build / "bench" / "symdyn_paper_tgen"), "--model", model, "--variant", variant,
                          "--case", str(case), "--runs", str(runs)], capture_output=True, text=True, check=True).stdout
    return json.loads(out)["cpu"]


def ops(functions, names, apart=False):
    if not all(n in functions for n in names):
        return None
    return sum(functions[n][0] + (functions[n][1] if apart else 0) for n in names)


def kinematics(functions, relative, case, fused):
    prefix = "relative_" if relative else ""
    if case < 3:
        return [prefix + "accelerations"]
    if fused:
        return [prefix + "accelerations_partials"]
    return [prefix + "accelerations", prefix + "partial_velocities"]


def cell(value):
    return "—" if value is None else str(value)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--before", type=pathlib.Path, required=True)
    parser.add_argument("--after", type=pathlib.Path, required=True)
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()

    rows = []
    for model, variant in MODELS:
        row = {"model": model, "variant": variant}
        for side in ("before", "after"):
            build = getattr(args, side)
            row[side] = {case: stats(build, model, variant, case) for case in CASES}
            row[side + "_tgen"] = {case: tgen(build, model, variant, case, args.runs) for case in CASES}
        rows.append(row)

    print("### Equations of motion (case 4)\n")
    print("| Model | Variant | mass_matrix before | after | bias_forces before | after | M + h before | after | "
          "saved | dynamics() before | after |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        b, a = r["before"][4], r["after"][4]
        mh_b, mh_a = ops(b, ["mass_matrix", "bias_forces"]), ops(a, ["mass_matrix", "bias_forces"])
        saved = f"{100 * (mh_b - mh_a) / mh_b:.0f} %" if mh_b else "—"
        print(f"| {r['model']} | {r['variant']} | {cell(ops(b, ['mass_matrix']))} | {cell(ops(a, ['mass_matrix']))} | "
              f"{cell(ops(b, ['bias_forces']))} | {cell(ops(a, ['bias_forces']))} | {mh_b} | {mh_a} | {saved} | "
              f"{cell(ops(b, ['dynamics']))} | {cell(ops(a, ['dynamics']))} |")

    print("\n### Kinematics\n")
    print("Absolute: `accelerations` (cases 1-2), plus `partial_velocities` (case 3 before; after: the fused "
          "`accelerations_partials`). Relative: the same of `relative_*`. Each as counted by the generator "
          "(a fused sin/cos pair once) / with sin and cos as two calls.\n")
    print("| Model | Variant | Case | absolute before | after | relative before | after |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for r in rows:
        for case in (1, 2, 3):
            b, a = r["before"][case], r["after"][case]
            fused = "accelerations_partials" in a
            cells = []
            for relative in (False, True):
                nb = kinematics(b, relative, case, False)
                na = kinematics(a, relative, case, fused)
                cells += [f"{cell(ops(b, nb))} / {cell(ops(b, nb, True))}", f"{cell(ops(a, na))} / {cell(ops(a, na, True))}"]
            print(f"| {r['model']} | {r['variant']} | {case} | " + " | ".join(cells) + " |")

    print("\n### Generation time (CPU s, median of %d in-process generations, symdyn_paper_tgen)\n" % args.runs)
    print("| Model | Variant | case 1 before | after | case 2 before | after | case 3 before | after | "
          "case 4 before | after |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        cells = []
        for case in CASES:
            cells += [f"{r['before_tgen'][case]:.4f}", f"{r['after_tgen'][case]:.4f}"]
        print(f"| {r['model']} | {r['variant']} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
