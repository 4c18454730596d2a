"""Operation counts of emitted code by symdyn's rule, for the computer algebra scripts.

The rule is the one of symdyn's `--stats` (symbolic::OperationCount, counted on the
scheduled program) applied to an expression written out by another tool:

- a + b, a - b: one add each (a sum of k terms: k - 1); a sum whose terms are all
  negative also one neg;
- a*b: one mul (a product of k factors: k - 1; a numeric coefficient other than
  +-1 is a factor); a product with a denominator: the numerator's and the
  denominator's muls and one div (1/x: one div);
- -x: one neg, unless it is a term of a sum (then it is the subtraction);
- x^n, n a positive integer: the muls of repeated squaring (x^2: 1, x^3: 2, x^4: 2);
  x^(-n): those and one div; x^(1/2): one sqrt; x^(k + 1/2): sqrt, the muls of
  x^k and one mul; any other exponent: one pow;
- every call (sin, cos, atan2, ...): one, and its arguments' operations;
- numbers and symbols: nothing.

Counted on a program (common subexpressions assigned once, as SymPy's cse
writes it) or on expressions written in full (Giac's output, which has no
common subexpression elimination): `Counter.add(tree)` counts every node of the
tree; `count_shared` counts each distinct subexpression once (what a
value-numbering scheduler such as symdyn's would execute).

Two totals: `apart` counts sin(x) and cos(x) as two calls; `fused` counts a sin
and a cos of the same argument once (symdyn's sincos), as symdyn's "Kin. ops".

Trees are tuples: ("num", value) | ("sym", name) | ("add", [(sign, tree)...]) |
("mul", coefficient, [factors], [denominator factors]) | ("neg", tree) |
("pow", tree, exponent) | ("call", name, [args]). `parse` reads infix text
(Giac's output) into such trees; cagem_sympy.py converts SymPy's.
Standard library only.
"""
import collections
import fractions
import re


def integer_power_muls(n):
    """Multiplications of x^n by repeated squaring (symbolic::scalar::integer_power)."""
    if n <= 1:
        return 0
    return integer_power_muls(n // 2) + 1 if n % 2 == 0 else integer_power_muls(n - 1) + 1


class Counter:
    """Operations of trees, by kind, with the arguments of sin and cos kept for fusing.
    shared: each distinct subtree (in or out of a sum) counted once (trees are hashable tuples)."""

    def __init__(self, shared=False):
        self.kinds = collections.Counter()
        self.sin_args = collections.Counter()
        self.cos_args = collections.Counter()
        self.seen = set() if shared else None

    def add(self, tree, in_sum=False):
        if self.seen is not None:
            if (tree, in_sum) in self.seen:
                return
            self.seen.add((tree, in_sum))
        kind = tree[0]
        if kind in ("num", "sym"):
            return
        if kind == "neg":
            if not in_sum:
                self.kinds["neg"] += 1
            self.add(tree[1])
        elif kind == "add":
            terms = tree[1]
            self.kinds["add"] += len(terms) - 1
            if all(sign < 0 for sign, _ in terms):
                self.kinds["neg"] += 1
            for _, t in terms:
                self.add(t, in_sum=True)
        elif kind == "mul":
            coefficient, num, den = tree[1], tree[2], tree[3]
            n_num = len(num) + (1 if abs(coefficient) != 1 else 0)
            if coefficient < 0 and abs(coefficient) == 1 and not in_sum:
                self.kinds["neg"] += 1
            if n_num > 1:
                self.kinds["mul"] += n_num - 1
            if den:
                self.kinds["mul"] += len(den) - 1
                self.kinds["div"] += 1
            for f in num + den:
                self.add(f)
        elif kind == "pow":
            base, e = tree[1], tree[2]
            self.add(base)
            if e < 0:
                self.kinds["div"] += 1
                e = -e
            if e.denominator == 1:
                self.kinds["mul"] += integer_power_muls(e.numerator)
            elif e.denominator == 2:
                self.kinds["sqrt"] += 1
                whole = e.numerator // 2
                if whole > 0:
                    self.kinds["mul"] += integer_power_muls(whole) + 1
            else:
                self.kinds["pow"] += 1
        elif kind == "call":
            name, args = tree[1], tree[2]
            self.kinds[name] += 1
            if name == "sin":
                self.sin_args[args[0]] += 1
            elif name == "cos":
                self.cos_args[args[0]] += 1
            for a in args:
                self.add(a)
        else:
            raise ValueError(f"opcount: unknown node {kind}")

    def result(self):
        apart = sum(self.kinds.values())
        pairs = sum(min(n, self.cos_args[a]) for a, n in self.sin_args.items())
        return {"apart": apart, "fused": apart - pairs, "sincos_pairs": pairs, "by_kind": dict(sorted(self.kinds.items()))}


def count(trees, shared=False):
    c = Counter(shared)
    for t in trees:
        c.add(t)
    return c.result()


def count_shared(trees):
    """Each distinct subtree counted once (trees are hashable tuples)."""
    return count(trees, shared=True)


# --- infix text (Giac's output) into trees -----------------------------------

TOKEN = re.compile(r"\s*(?:(\d+\.\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?|\d+(?:[eE][-+]?\d+)?)|([A-Za-z_][A-Za-z_0-9]*)|(\*\*|[-+*/^(),]))")


def tokens(text):
    pos, out = 0, []
    text = text.strip()
    while pos < len(text):
        m = TOKEN.match(text, pos)
        if not m or m.end() == pos:
            raise ValueError(f"opcount.parse: cannot read {text[pos:pos + 30]!r}")
        pos = m.end()
        if m.group(1):
            out.append(("num", m.group(1)))
        elif m.group(2):
            out.append(("name", m.group(2)))
        else:
            out.append(("op", "^" if m.group(3) == "**" else m.group(3)))
    return out


def number(text):
    if re.fullmatch(r"\d+", text):
        return fractions.Fraction(int(text))
    return float(text)


def parse(text):
    """Infix with + - * / ^ (or **), unary minus, calls and numbers, into a tree."""
    toks = tokens(text)
    pos = 0

    def peek():
        return toks[pos] if pos < len(toks) else (None, None)

    def take(expected=None):
        nonlocal pos
        tok = toks[pos]
        if expected and tok != ("op", expected):
            raise ValueError(f"opcount.parse: expected {expected!r} at token {pos} of {text[:80]!r}")
        pos += 1
        return tok

    def sum_():
        terms = [term_signed()]
        while peek() in (("op", "+"), ("op", "-")):
            sign = 1 if take()[1] == "+" else -1
            s, t = term()
            terms.append((sign * s, t))
        return terms[0][1] if len(terms) == 1 and terms[0][0] > 0 else ("add", terms) if len(terms) > 1 else ("neg", terms[0][1])

    def term_signed():
        if peek() == ("op", "-"):
            take()
            s, t = term()
            return -s, t
        if peek() == ("op", "+"):
            take()
        return term()

    def term():
        """A product; its sign (+-1) apart from its magnitude."""
        factors, den = [], []
        factors.append(unary())
        while peek() in (("op", "*"), ("op", "/")):
            op = take()[1]
            (factors if op == "*" else den).append(unary())
        sign, coefficient, num = 1, 1, []
        for f in factors:
            if f[0] == "neg":
                sign, f = -sign, f[1]
            if f[0] == "num" and isinstance(f[1], fractions.Fraction):
                coefficient *= f[1]
            elif f[0] == "num":
                coefficient *= f[1]
            else:
                num.append(f)
        dens = []
        for f in den:
            if f[0] == "neg":
                sign, f = -sign, f[1]
            if f[0] == "num":
                coefficient = coefficient / f[1]
            else:
                dens.append(f)
        if coefficient < 0:
            sign, coefficient = -sign, -coefficient
        if not num and not dens:
            return sign, ("num", coefficient)
        if coefficient == 1 and len(num) == 1 and not dens:
            return sign, num[0]
        return sign, ("mul", coefficient, tuple(num), tuple(dens))

    def unary():
        if peek() == ("op", "-"):
            take()
            return ("neg", unary())
        return power()

    def power():
        base = atom()
        if peek() == ("op", "^"):
            take()
            if peek() == ("op", "-"):
                take()
                e = -exponent(unary())
            else:
                e = exponent(power())
            if isinstance(e, fractions.Fraction):
                return ("pow", base, e)
            return ("pow", base, fractions.Fraction(2, 3))  # a non-rational exponent: one pow
        return base

    def exponent(tree):
        if tree[0] == "num":
            v = tree[1]
            return v if isinstance(v, fractions.Fraction) else fractions.Fraction(v).limit_denominator(1000)
        if tree[0] == "mul" and not tree[2] and tree[1] and all(d[0] == "num" for d in tree[3]):
            return fractions.Fraction(tree[1])
        if tree[0] == "neg":
            return -exponent(tree[1])
        return None

    def atom():
        kind, value = take()
        if kind == "num":
            return ("num", number(value))
        if kind == "name":
            if peek() == ("op", "("):
                take("(")
                args = [sum_()]
                while peek() == ("op", ","):
                    take()
                    args.append(sum_())
                take(")")
                return ("call", value, tuple(args))
            return ("sym", value)
        if value == "(":
            inner = sum_()
            take(")")
            return inner
        raise ValueError(f"opcount.parse: unexpected {value!r} in {text[:80]!r}")

    tree = sum_()
    if pos != len(toks):
        raise ValueError(f"opcount.parse: trailing text in {text[:80]!r}")
    return freeze(tree)


def freeze(tree):
    """Lists into tuples, so that trees hash (count_shared)."""
    kind = tree[0]
    if kind == "add":
        return ("add", tuple((s, freeze(t)) for s, t in tree[1]))
    if kind == "mul":
        return ("mul", tree[1], tuple(freeze(f) for f in tree[2]), tuple(freeze(f) for f in tree[3]))
    if kind == "neg":
        return ("neg", freeze(tree[1]))
    if kind == "pow":
        return ("pow", freeze(tree[1]), tree[2])
    if kind == "call":
        return ("call", tree[1], tuple(freeze(a) for a in tree[2]))
    return tree
