#!/usr/bin/env python3
"""CAGeM's derivation of a model's kinematics, in Giac (the `giac` interpreter of Debian's xcas).

    cagem_giac.py --describe MODEL.json --case 1|2|3 --out DIR [--timeout S] [--giac giac]

The same derivation as cagem_sympy.py (bench/README.md), written as a Giac
program that this script generates and runs: each body's homogeneous
transformation relative to its reference, v, a by the chain rule, w from
skew(w) = dR/dt R^T, dw; the dependent parameters as symbols with their rates
(and Jacobian in case 3). Cases 2-3 simplify each expression as it is made,
keeping the shortest printed form among the expression, normal(), tlin() (the
two CAGeM on Giac tried) and simplify(); case 3 adds the partial velocities.

Giac 1.9 has no common subexpression elimination and no C export: the emitted
C is each expression written out in full (as CAGeM's was), printed here from
Giac's output. Its operations are counted by opcount.py's rule on that text
("emitted"), and with each distinct subexpression once ("shared", what a
value-numbering compiler would keep).

Time: the CPU and wall time of the giac process less those of the same
interpreter running an empty program (its start-up, some 25 ms), each the
fastest of --runs runs (rusage of the child), the two interleaved so that
both see the same load of a shared machine. The fastest, not the median:
other jobs only ever add time, and a start-up some runs took 8 ms longer
than the others (a third of it) would be taken from the derivation. A
derivation whose first run took more than --repeat-below seconds of CPU runs
once, less the fastest of three empty runs (its few milliseconds of noise no
longer matter). Writes
DIR/giac_case<c>.giac (the program), .c (the emitted C) and .json. Standard
library only.
"""
import argparse
import json
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

here = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(here))
import opcount  # noqa: E402

FUNCTIONS = {"sin", "cos", "tan", "asin", "acos", "atan", "atan2", "exp", "log", "abs", "sqrt"}
IDENT = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")


def giac_name(name):
    return f"z{name}"  # away from Giac's own names (e, i, pi, D, ...)


def to_giac(text):
    return IDENT.sub(lambda m: m.group(0) if m.group(0) in FUNCTIONS else giac_name(m.group(0)), text)


def rotation(axis, angle):
    """The 4x4 matrix of a rotation by `angle` (Giac text) about a constant unit axis (numbers)."""
    k = [float(a) for a in axis]
    skew = [[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]]
    rows = []
    for i in range(3):
        row = []
        for j in range(3):
            c = (1.0 if i == j else 0.0) - k[i] * k[j]
            s = skew[i][j]
            const = k[i] * k[j]
            parts = []
            for coef, what in ((c, f"cos({angle})"), (s, f"sin({angle})")):
                if coef == 1:
                    parts.append(what)
                elif coef == -1:
                    parts.append(f"-{what}")
                elif coef != 0:
                    parts.append(f"{coef!r}*{what}")
            if const != 0:
                parts.append("1" if const == 1 else repr(const))
            row.append("+".join(parts).replace("+-", "-") if parts else "0")
        rows.append("[" + ",".join(row) + ",0]")
    rows.append("[0,0,0,1]")
    return "[" + ",".join(rows) + "]"


def translation(d):
    d = [f"({to_giac(x)})" for x in d]
    return f"[[1,0,0,{d[0]}],[0,1,0,{d[1]}],[0,0,1,{d[2]}],[0,0,0,1]]"


def program(doc, case, result_file):
    """The Giac program. Few top-level statements (one per body, the rest in functions and
    loops): the giac interpreter fails on scripts of about 2000 statements or more."""
    q = [giac_name(c["q"]) for c in doc["coordinates"]]
    qd = [giac_name(c["qd"]) for c in doc["coordinates"]]
    qdd = [giac_name(c["qdd"]) for c in doc["coordinates"]]
    p = [giac_name(d["p"]) for d in doc["dependents"]]
    pd = [giac_name(d["pd"]) for d in doc["dependents"]]
    pdd = [giac_name(d["pdd"]) for d in doc["dependents"]]
    t = giac_name(doc["time"])
    values = {giac_name(prm["symbol"]): prm["value"] for prm in doc["parameters"]}
    nq, np_ = len(q), len(p)
    lines = []
    if case == 1:
        lines.append("simp(ex):=ex;")
    else:
        lines.append("simp(ex):={ local L,b,j; L:=[ex,normal(ex),tlin(ex),simplify(ex)]; b:=ex; "
                     "for (j:=1;j<4;j++) { if (length(string(L[j]))<length(string(b))) { b:=L[j]; } } return b; };")
    chain = "+".join([f"diff(f,{t})"] + [f"diff(f,{x})*{xd}" for x, xd in zip(q + qd + p + pd, qd + qdd + pd + pdd)])
    lines.append(f"dt(f):={chain};")
    lines.append(f"QD:=[{','.join(qd)}];")
    lines.append(f"PD:=[{','.join(pd)}];")
    # zJk_j: the symbol of dpd_k/dqd_j (the dependent parameters' Jacobian).
    lines.append("JS:=[" + ",".join("[" + ",".join(f"zJ{k}_{j}" for j in range(nq)) + "]" for k in range(np_)) + "];"
                 if np_ else "JS:=[[0]];")
    # d ex/d qd_j through the dependent parameters' rates.
    lines.append(f"pdq(ex,j):={{ local r,k; r:=diff(ex,QD[j]); for(k:=0;k<{np_};k++){{ r:=r+diff(ex,PD[k])*JS[k,j]; }} "
                 "return r; };")
    subst = lambda e: f"subs({e},[{','.join(values)}],[{','.join(str(v) for v in values.values())}])" if values else e
    lines.append(f'fd:=fopen("{result_file}");')
    # out(tag, list of expressions)
    lines.append('out(tag,L):={ local k; for(k:=0;k<size(L);k++){ fprint(fd,Unquoted,tag,"\t",string(L[k]),"\n"); } '
                 "return 0; };")
    for k, d in enumerate(doc["dependents"]):
        lines.append(f"VP{k}:=simp({subst(to_giac(d['expression']))});")
        lines.append(f"VPD{k}:=simp(dt(VP{k}));")
        lines.append(f"VPDD{k}:=simp(dt(VPD{k}));")
    if np_:
        for prefix, names, tag in (("VP", p, "acc"), ("VPD", pd, "acc"), ("VPDD", pdd, "acc")):
            lines.append(f"VV:=[{','.join(f'{prefix}{k}' for k in range(np_))}];")
            lines.append(f"NN:=[{','.join(names)}];")
            lines.append('for(k:=0;k<size(VV);k++){ fprint(fd,Unquoted,"' + tag + ':def ",string(NN[k]),"\t",'
                         'string(VV[k]),"\n"); };')
        if case == 3:
            lines.append(f"VV:=[{','.join(f'VP{k}' for k in range(np_))}];")
            lines.append(f"NN:=[{','.join(p)}];")
            lines.append('for(k:=0;k<size(VV);k++){ fprint(fd,Unquoted,"pv:def ",string(NN[k]),"\t",string(VV[k]),"\n"); };')
            lines.append(f"VPDL:=[{','.join(f'VPD{k}' for k in range(np_))}];")
            lines.append(f"for(k:=0;k<{np_};k++){{ for(j:=0;j<{nq};j++){{ "
                         'fprint(fd,Unquoted,"pv:def ",string(JS[k,j]),"\t",string(simp(pdq(VPDL[k],j))),"\n"); } };')
    partials = ""
    if case == 3:
        partials = (f"for(j:=0;j<{nq};j++){{ out(\"pv:dv\",[simp(pdq(V[0],j)),simp(pdq(V[1],j)),simp(pdq(V[2],j))]); "
                    "out(\"pv:dw\",[simp(pdq(Om[0],j)),simp(pdq(Om[1],j)),simp(pdq(Om[2],j))]); } ")
    lines.append("body(T):={ local R,X,V,A,W,Om,dOm,j; R:=map(T[0..2,0..2],simp); X:=map(T[0..2,3],simp); "
                 "V:=map(map(X,dt),simp); A:=map(map(V,dt),simp); W:=map(R,dt)*tran(R); "
                 "Om:=map([W[2,1],W[0,2],W[1,0]],simp); dOm:=map(map(Om,dt),simp); "
                 'out("acc:R",[R[0,0],R[0,1],R[0,2],R[1,0],R[1,1],R[1,2],R[2,0],R[2,1],R[2,2]]); '
                 'out("acc:x",X); out("acc:v",V); out("acc:w",Om); out("acc:a",A); out("acc:dw",dOm); '
                 + partials + "return 0; };")
    for body in doc["bodies"]:
        factors = []
        for step in body["motion"]:
            if "translation" in step:
                factors.append(translation(step["translation"]))
            else:
                factors.append(rotation(step["rotation"], to_giac(step["angle"])))
        T = "*".join(factors) if factors else "idn(4)"
        lines.append(f"body({subst(T)});")
    lines.append("fclose(fd);")
    return "\n".join(lines) + "\n"


def run_giac(giac, script, timeout):
    """CPU (user + system, from the child's rusage) and wall seconds of `giac script`, and its output."""
    start = time.perf_counter()
    with tempfile.TemporaryFile("w+") as log:
        proc = subprocess.Popen([giac, str(script)], stdout=log, stderr=subprocess.STDOUT, text=True)
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
            raise
        wall = time.perf_counter() - start
        log.seek(0)
        output = log.read()
    usage = proc.rusage if hasattr(proc, "rusage") else None
    return (usage.ru_utime + usage.ru_stime) if usage else None, wall, proc.returncode, output


class _Popen(subprocess.Popen):
    """Popen that keeps the child's rusage (os.wait4) when it is reaped."""

    def _try_wait(self, wait_flags):
        try:
            pid, sts, usage = os.wait4(self.pid, wait_flags)
        except ChildProcessError:
            return (self.pid, 0)
        if pid == self.pid:
            self.rusage = usage
        return (pid, sts)


subprocess.Popen = _Popen  # noqa: this script's children only


def timed_runs(giac, script, empty, runs, timeout):
    """CPU and wall seconds of `runs` runs of the empty program and of the script, interleaved (so that
    both see the same load on a shared machine): the fastest of each, and every run's CPU."""
    pairs = []
    for _ in range(runs):
        e = run_giac(giac, empty, 60)[:2]
        pairs.append((e, run_giac(giac, script, timeout)[:2]))
    return ([min(e[0] for e, _ in pairs), min(e[1] for e, _ in pairs)],
            [min(r[0] for _, r in pairs), min(r[1] for _, r in pairs)],
            [r[0] for _, r in pairs], [e[0] for e, _ in pairs])


def c_of(tree):
    """A tree as C text (for the emitted size)."""
    kind = tree[0]
    if kind == "num":
        return repr(float(tree[1]))
    if kind == "sym":
        return "M_PI" if tree[1] == "pi" else tree[1][1:] if tree[1].startswith("z") else tree[1]
    if kind == "neg":
        return f"-({c_of(tree[1])})"
    if kind == "add":
        out = ""
        for sign, t in tree[1]:
            s = c_of(t)
            out += (" - " if sign < 0 else " + ") + s if out else ("-" if sign < 0 else "") + s
        return f"({out})"
    if kind == "mul":
        num = ([repr(float(tree[1]))] if tree[1] != 1 else []) + [c_of(f) for f in tree[2]]
        text = "*".join(num) if num else "1.0"
        if tree[3]:
            text += "/(" + "*".join(c_of(f) for f in tree[3]) + ")"
        return text
    if kind == "pow":
        e = tree[2]
        return f"pow({c_of(tree[1])}, {float(e)!r})"
    if kind == "call":
        return f"{tree[1]}(" + ", ".join(c_of(a) for a in tree[2]) + ")"
    raise ValueError(kind)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--describe", required=True, type=pathlib.Path)
    ap.add_argument("--case", required=True, type=int, choices=(1, 2, 3))
    ap.add_argument("--out", required=True, type=pathlib.Path)
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--giac", default="giac")
    ap.add_argument("--runs", type=int, default=7, help="runs of the derivation, the fastest (default 7)")
    ap.add_argument("--repeat-below", type=float, default=1.0,
                    help="repeat the derivation only when its first run took less CPU seconds than this (default 1)")
    ap.add_argument("--max-output", type=float, default=50,
                    help="megabytes of Giac output read and counted at most (default 50); past it, timed only")
    args = ap.parse_args()
    doc = json.loads(args.describe.read_text())
    args.out.mkdir(parents=True, exist_ok=True)
    base = args.out / f"giac_case{args.case}"
    results = base.with_suffix(".txt").resolve()
    results.unlink(missing_ok=True)
    script = base.with_suffix(".giac")
    script.write_text(program(doc, args.case, results))
    version = "?"
    with tempfile.TemporaryDirectory() as d:
        v = pathlib.Path(d) / "version.giac"
        v.write_text("version();\n")
        m = re.search(r"giac ([0-9.]+)", subprocess.run([args.giac, str(v)], capture_output=True, text=True).stdout)
        version = m.group(1) if m else "?"
    empty = base.with_name("empty.giac")
    empty.write_text("0;\n")
    starts = [run_giac(args.giac, empty, 60)[:2] for _ in range(3)]
    start_cpu, start_wall = min(c for c, _ in starts), min(w for _, w in starts)
    result = {"tool": "Giac", "version": version, "case": args.case, "timeout": args.timeout}
    try:
        cpu, wall, returncode, output = run_giac(args.giac, script, args.timeout)
        if returncode == 0 and cpu - start_cpu < args.repeat_below:
            (start_cpu, start_wall), (cpu, wall), runs, starts = timed_runs(args.giac, script, empty, args.runs,
                                                                             args.timeout)
            result.update(cpu_raw_runs=runs, startup_cpu_runs=starts)
    except subprocess.TimeoutExpired:
        result.update(status="timeout")
        base.with_suffix(".json").write_text(json.dumps(result, indent=1) + "\n")
        print(json.dumps(result))
        return
    (base.with_suffix(".log")).write_text(output[-20000:])
    result.update(startup_cpu=start_cpu, startup_wall=start_wall, cpu_raw=cpu, wall_raw=wall,
                  cpu=max(cpu - start_cpu, 0.0), wall=max(wall - start_wall, 0.0))
    if not results.exists() or returncode != 0:
        result.update(status="error", message=f"giac exited with {returncode}, no results")
        base.with_suffix(".json").write_text(json.dumps(result, indent=1) + "\n")
        print(json.dumps(result))
        return
    megabytes = results.stat().st_size / 1e6
    if megabytes > args.max_output:
        result.update(status="unparsed", size=None,
                      message=f"output of {megabytes:.0f} MB (expressions written in full), over --max-output: timed, not counted")
        base.with_suffix(".json").write_text(json.dumps(result, indent=1) + "\n")
        results.unlink()
        print(json.dumps(result))
        return
    programs = {"acc": ([], []), "pv": ([], [])}
    code = {"acc": [], "pv": []}
    problems = []
    for line in results.read_text().splitlines():
        if not line.strip():
            continue
        tag, text = line.split("\t", 1)
        prog, what = tag.split(":", 1)
        try:
            tree = opcount.parse(text)
        except ValueError as e:
            problems.append(str(e))
            continue
        syms = set(re.findall(r"[A-Za-z_][A-Za-z_0-9]*", text))
        if {"i", "undef", "infinity"} & syms:
            problems.append(f"{what}: {text[:60]}")
        programs[prog][0].append(tree)
        lhs = what.split()[1] if what.startswith("def ") else f"out[{len(code[prog])}]"
        code[prog].append(f"  {'const double ' if what.startswith('def ') else ''}{lhs} = {c_of(tree)};")
    text = ""
    counts = {}
    for prog, name in (("acc", "accelerations"), ("pv", "partial_velocities")):
        if not programs[prog][0]:
            continue
        text += f"void {name}(const double* q, const double* qd, const double* qdd, double* out) {{\n"
        text += "\n".join(code[prog]) + "\n}\n"
        emitted = opcount.count(programs[prog][0])
        shared = opcount.count_shared(programs[prog][0])
        counts[name] = {"emitted": emitted, "shared": shared}
    base.with_suffix(".c").write_text(text)
    results.unlink()
    result.update(status="error" if problems else "ok", size=len(text.encode()), operations=counts,
                  kinematics_apart=sum(c["emitted"]["apart"] for c in counts.values()),
                  kinematics_shared_fused=sum(c["shared"]["fused"] for c in counts.values()),
                  kinematics_shared_apart=sum(c["shared"]["apart"] for c in counts.values()))
    if problems:
        result["message"] = f"{len(problems)} outputs complex, undefined or unreadable; first: {problems[0]}"
    base.with_suffix(".json").write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps({k: v for k, v in result.items() if k != "operations"}))


if __name__ == "__main__":
    main()
