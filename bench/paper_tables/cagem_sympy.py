#!/usr/bin/env python3
"""CAGeM's derivation of a model's kinematics, in SymPy.

    cagem_sympy.py --describe MODEL.json --case 1|2|3 --out DIR

MODEL.json is the generator's `--describe` output (the model as its file
describes it). What CAGeM did (bench/README.md, "cagem_sympy.py and cagem_giac.py"):

- each body's 4x4 homogeneous transformation, the product of its elementary
  ones, relative to its reference body (or the ground): R and x;
- v = dx/dt, a = dv/dt; the angular velocity from skew(w) = dR/dt R^T and
  dw = dw/dt, all in the reference's axes; d/dt by the chain rule over q (qd),
  qd (qdd), the dependent parameters p (pd), pd (pdd) and t;
- the dependent parameters (kept as symbols, not inlined) with their pd, pdd,
  and in case 3 their Jacobian dp/dq, computed before the bodies;
- case 1: no simplification; cases 2-3: each expression simplified as it is
  made (velocities differentiated from simplified positions, as CAGeM on Giac),
  keeping the shortest of the expression and trigsimp's (CAGeM kept the shortest
  of its candidates); case 3 also the partial velocities dv/dqd_j, dw/dqd_j;
- then cse and ccode: an accelerations() program and, in case 3, a
  partial_velocities() program, as symdyn emits them.

Writes DIR/sympy_case<c>.c (the emitted C) and DIR/sympy_case<c>.json: the time
of the derivation in this process (CPU and wall, from the model read to the C
written: Python's and SymPy's start-up and imports excluded), the size, the
operations counted by opcount.py's rule. Python standard library and SymPy only.
"""
import argparse
import json
import pathlib
import sys
import time

here = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(here))
import opcount  # noqa: E402

import sympy  # noqa: E402
from sympy import Matrix, Symbol  # noqa: E402

FUNCTIONS = {"sin": sympy.sin, "cos": sympy.cos, "tan": sympy.tan, "asin": sympy.asin, "acos": sympy.acos,
             "atan": sympy.atan, "atan2": sympy.atan2, "exp": sympy.exp, "log": sympy.log, "abs": sympy.Abs,
             "sqrt": sympy.sqrt}
CALL_NAMES = {sympy.sin: "sin", sympy.cos: "cos", sympy.tan: "tan", sympy.asin: "asin", sympy.acos: "acos",
              sympy.atan: "atan", sympy.atan2: "atan2", sympy.exp: "exp", sympy.log: "log", sympy.Abs: "abs"}


class Model:
    def __init__(self, doc):
        self.names = {}
        sym = lambda name: self.names.setdefault(name, Symbol(name, real=True))
        self.t = sym(doc["time"])
        self.q = [sym(c["q"]) for c in doc["coordinates"]]
        self.qd = [sym(c["qd"]) for c in doc["coordinates"]]
        self.qdd = [sym(c["qdd"]) for c in doc["coordinates"]]
        self.p = [sym(d["p"]) for d in doc["dependents"]]
        self.pd = [sym(d["pd"]) for d in doc["dependents"]]
        self.pdd = [sym(d["pdd"]) for d in doc["dependents"]]
        for prm in doc["parameters"]:
            sym(prm["symbol"])
        self.p_expr = [self.parse(d["expression"]) for d in doc["dependents"]]
        self.values = {self.names[prm["symbol"]]: sympy.Float(prm["value"]) for prm in doc["parameters"]}
        self.bodies = doc["bodies"]

    def parse(self, text):
        return sympy.sympify(text, locals={**self.names, **FUNCTIONS}, convert_xor=True)

    def d_dt(self, f):
        """Total time derivative by the chain rule."""
        free = f.free_symbols
        out = sympy.diff(f, self.t) if self.t in free else sympy.S.Zero
        for x, xd in zip(self.q + self.qd + self.p + self.pd, self.qd + self.qdd + self.pd + self.pdd):
            if x in free:
                out += sympy.diff(f, x) * xd
        return out

    def transform(self, motion):
        T = sympy.eye(4)
        for step in motion:
            if "translation" in step:
                d = [self.parse(s) for s in step["translation"]]
                M = sympy.eye(4)
                M[0, 3], M[1, 3], M[2, 3] = d
            else:
                k = Matrix([self.parse(s) for s in step["axis" if "axis" in step else "rotation"]])
                a = self.parse(step["angle"])
                c, s = sympy.cos(a), sympy.sin(a)
                K = Matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
                R = c * sympy.eye(3) + s * K + (1 - c) * k * k.T
                M = sympy.eye(4)
                M[:3, :3] = R
            T = T * M
        return T.subs(self.values) if self.values else T


def size_of(e):
    return opcount.count([tree(e)])["apart"]


def simplifier(case):
    if case == 1:
        return lambda e: e

    def simplify(e):
        candidates = [e, sympy.trigsimp(e)]
        return min(candidates, key=size_of)
    return simplify


def tree(e, in_sum=False):
    """A SymPy expression as an opcount tree (signs of products apart)."""
    if e.is_Number or e.is_NumberSymbol:  # pi, which trigsimp may bring, is a constant
        return ("num", float(e))
    if e.is_Symbol:
        return ("sym", e.name)
    if e.is_Add:
        terms = []
        for a in e.args:
            sign, t = signed(a)
            terms.append((sign, t))
        return ("add", tuple(terms))
    if e.is_Mul or e.is_Pow:
        sign, t = signed(e)
        return t if sign > 0 else ("neg", t)
    if e.is_Function:  # any other function simplification may bring (sign, ...) is a call too
        return ("call", CALL_NAMES.get(e.func, e.func.__name__), tuple(tree(a) for a in e.args))
    raise ValueError(f"cagem_sympy: cannot count {e.func}")


def signed(e):
    """A term: its sign and the tree of its magnitude."""
    if e.is_NumberSymbol:
        return 1, ("num", float(e))
    if e.is_Number:
        return (1, ("num", float(e))) if e >= 0 else (-1, ("num", float(-e)))
    if e.is_Pow:
        base, exponent = e.args
        if exponent.is_Rational:
            return 1, ("pow", tree(base), opcount.fractions.Fraction(int(exponent.p), int(exponent.q)))
        return 1, ("call", "pow", (tree(base), tree(exponent)))
    if not e.is_Mul:
        return 1, tree(e)
    coefficient, factors = e.as_coeff_mul()
    sign = -1 if coefficient < 0 else 1
    coefficient = abs(coefficient)
    num, den = [], []
    for f in factors:
        if f.is_Pow and f.args[1].is_Rational and f.args[1] < 0:
            inv = 1 / f
            den.append(tree(inv))
        else:
            num.append(tree(f))
    c = float(coefficient)
    if not num and not den:
        return sign, ("num", c)
    if c == 1 and len(num) == 1 and not den:
        return sign, num[0]
    return sign, ("mul", c, tuple(num), tuple(den))


def kinematics(m, case):
    simplify = simplifier(case)
    simp_all = lambda M: M.applyfunc(simplify)
    definitions = []  # (symbol, expression), in order
    # Dependent parameters: p, pd, pdd (and, for case 3, the Jacobian dp/dq).
    p_val, pd_val, pdd_val = [], [], []
    for p, pd, pdd, e in zip(m.p, m.pd, m.pdd, m.p_expr):
        e = simplify(e.subs(m.values))
        ed = simplify(m.d_dt(e))
        edd = simplify(m.d_dt(ed))
        p_val.append((p, e))
        pd_val.append((pd, ed))
        pdd_val.append((pdd, edd))
    definitions = p_val + pd_val + pdd_val
    outputs = {"R": [], "x": [], "v": [], "w": [], "a": [], "dw": []}
    partials = {"dv": [], "dw": []}
    for body in m.bodies:
        T = m.transform(body["motion"])
        R = simp_all(T[:3, :3])
        x = simp_all(T[:3, 3])
        v = simp_all(x.applyfunc(m.d_dt))
        a = simp_all(v.applyfunc(m.d_dt))
        W = R.applyfunc(m.d_dt) * R.T
        w = simp_all(Matrix([W[2, 1], W[0, 2], W[1, 0]]))
        dw = simp_all(w.applyfunc(m.d_dt))
        for key, value in (("R", R), ("x", x), ("v", v), ("w", w), ("a", a), ("dw", dw)):
            outputs[key].extend(list(value))
        if case == 3:
            for j, qdj in enumerate(m.qd):
                for key, vec in (("dv", v), ("dw", w)):
                    partials[key].extend(simplify(partial(m, e, j)) for e in vec)
    programs = [("accelerations", definitions, [e for k in outputs for e in outputs[k]])]
    if case == 3:
        jac = []
        for k, (pd, ed) in enumerate(pd_val):  # J_kj = dpd_k/dqd_j, through earlier dependents' rates
            for j, qdj in enumerate(m.qd):
                jac.append((Symbol(f"J_{pd.name}_{j}", real=True), simplify(partial(m, ed, j))))
        programs.append(("partial_velocities", p_val + jac, [e for k in partials for e in partials[k]]))
    return programs


def partial(m, e, j):
    """d e / d qd_j, through the dependent parameters' rates: pd_k = sum_j (dp_k/dq_j) qd_j."""
    out = sympy.diff(e, m.qd[j])
    for k, pd in enumerate(m.pd):
        if pd in e.free_symbols:
            out += sympy.diff(e, pd) * Symbol(f"J_{pd.name}_{j}", real=True)
    return out


def emit(name, definitions, outputs):
    """cse + ccode: one C function body; the trees of what it executes."""
    exprs = [e for _, e in definitions] + outputs
    replacements, reduced = sympy.cse(exprs, symbols=sympy.numbered_symbols("t_"), order="none")
    lines = [f"void {name}(const double* q, const double* qd, const double* qdd, double* out) {{"]
    trees = []
    nd = len(definitions)
    # cse's temporaries and the definitions (dependent parameters, their Jacobian), each after what it uses.
    assignments = dict(replacements)
    assignments.update((s, e) for (s, _), e in zip(definitions, reduced[:nd]))
    done = set()

    def assign(s):
        if s in done:
            return
        done.add(s)
        e = assignments[s]
        for u in sorted(e.free_symbols & assignments.keys(), key=str):
            assign(u)
        lines.append(f"  const double {s} = {sympy.ccode(e)};")
        trees.append(tree(e))
    for s, _ in replacements:
        assign(s)
    for s, _ in definitions:
        assign(s)
    for i, e in enumerate(reduced[nd:]):
        lines.append(f"  out[{i}] = {sympy.ccode(e)};")
        trees.append(tree(e))
    lines.append("}")
    return "\n".join(lines) + "\n", trees


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--describe", required=True, type=pathlib.Path)
    ap.add_argument("--case", required=True, type=int, choices=(1, 2, 3))
    ap.add_argument("--out", required=True, type=pathlib.Path)
    args = ap.parse_args()
    doc = json.loads(args.describe.read_text())
    cpu0, wall0 = time.process_time(), time.perf_counter()
    m = Model(doc)
    programs = kinematics(m, args.case)
    code, counts = "", {}
    for name, definitions, outputs in programs:
        text, trees = emit(name, definitions, outputs)
        code += text
        counts[name] = opcount.count(trees)
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / f"sympy_case{args.case}.c").write_text(code)
    result = {"tool": "SymPy", "version": sympy.__version__, "case": args.case, "status": "ok",
              "cpu": cpu, "wall": wall, "size": len(code.encode()),
              "operations": counts,
              "kinematics_fused": sum(c["fused"] for c in counts.values()),
              "kinematics_apart": sum(c["apart"] for c in counts.values())}
    (args.out / f"sympy_case{args.case}.json").write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps({k: v for k, v in result.items() if k != "operations"}))


if __name__ == "__main__":
    main()
