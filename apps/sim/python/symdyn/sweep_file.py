"""Sweep files (docs/sweeps.md): a scenario, the factors that vary from run
to run, what each run changes in the scenario, and what to keep of it.

    {"scenario": "trike",
     "factors": {"stiffness": {"values": [1e5, 2e5]},
                 "mass": {"distribution": "normal", "mean": 1.0, "sd": 0.05, "set": "parameters.m1"}},
     "samples": 20, "seed": 7,
     "set": {"forces.front.stiffness": "stiffness", "forces.rear.stiffness": "0.8 * stiffness"},
     "keep": {"extrema": ["z"]}}

Runs: every combination of the grid factors (those with values, or from, to
and count; the first factor varies slowest), each with `samples` draws of
the random factors (those with a distribution): run r is grid point
r // samples, sample r % samples. Every error is a SweepError naming the file
and the JSON pointer of the culprit:

    tyres.json: /factors/speed/count: expected an integer >= 1, found 0
"""
import ast
import hashlib
import json
import math
import os
import re

from . import sampling

ROOT_KEYS = ("$schema", "description", "scenario", "factors", "set", "samples", "seed", "sampling", "keep")
RESERVED = ("run", "status", "error", "seed")  # the table's own columns
FUNCTIONS = {
    "sqrt": math.sqrt, "exp": math.exp, "log": math.log, "sin": math.sin, "cos": math.cos, "tan": math.tan,
    "asin": math.asin, "acos": math.acos, "atan": math.atan, "atan2": math.atan2, "hypot": math.hypot,
    "abs": abs, "min": min, "max": max,
}
CONSTANTS = {"pi": math.pi}
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


class SweepError(ValueError):
    """A sweep file that cannot run: the message names the file and the key."""


class RunInputError(ValueError):
    """A run whose changes cannot be computed (an expression of "set" divides
    by zero, say): the run is recorded as failed with this message."""


def _escape(key):
    return key.replace("~", "~0").replace("/", "~1")


class _NonFinite:
    def __init__(self, text):
        self.text = text


class _Duplicates(dict):
    """An object of the document, remembering keys given twice."""

    def __init__(self, pairs):
        super().__init__(pairs)
        seen = set()
        self.twice = []
        for key, _ in pairs:
            if key in seen:
                self.twice.append(key)
            seen.add(key)


def _check_document(value, at):
    """What json lets through and a sweep refuses: keys given twice, NaN,
    Infinity and numbers beyond a double."""
    if isinstance(value, dict):
        twice = getattr(value, "twice", [])
        if twice:
            at.child(twice[0]).fail(f"key '{twice[0]}' is given twice in this object (a JSON reader keeps one of them)")
        for key, member in value.items():
            _check_document(member, at.child(key))
    elif isinstance(value, list):
        for k, element in enumerate(value):
            _check_document(element, at.child(k))
    elif isinstance(value, _NonFinite):
        at.fail(f"{value.text} is not a number in JSON, and numbers here must be finite")
    elif isinstance(value, float) and not math.isfinite(value):
        at.fail("a number beyond the range of a double: not a finite number")


def _plain(value):
    """The document with its objects as plain dicts (for the engine)."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_plain(v) for v in value]
    return value


class At:
    """A value of the sweep document and its JSON pointer, for messages."""

    def __init__(self, origin, value, path=""):
        self.origin, self.value, self.path = origin, value, path

    def child(self, key):
        value = None
        if isinstance(self.value, dict):
            value = self.value.get(key)
        elif isinstance(self.value, list) and isinstance(key, int):
            value = self.value[key]
        return At(self.origin, value, f"{self.path}/{_escape(str(key))}")

    def fail(self, what):
        raise SweepError(f"{self.origin}: {self.path or '/'}: {what}")

    def kind(self):
        v = self.value
        if isinstance(v, bool):
            return "true or false"
        if isinstance(v, (int, float)):
            return "a number"
        if isinstance(v, str):
            return "a string"
        if isinstance(v, list):
            return "an array"
        if isinstance(v, dict):
            return "an object"
        return "null"

    def object(self):
        if not isinstance(self.value, dict):
            self.fail(f"expected an object, found {self.kind()}")
        return self

    def allow_only(self, keys):
        self.object()
        for key in self.value:
            if key not in keys:
                self.child(key).fail(f"unknown key '{key}' (expected: {', '.join(keys)})")

    def has(self, key):
        return isinstance(self.value, dict) and key in self.value

    def __getitem__(self, key):
        self.object()
        if key not in self.value:
            self.fail(f"missing key '{key}'")
        return self.child(key)

    def optional(self, key):
        return self[key] if self.has(key) else None

    def items(self):
        self.object()
        return [(key, self.child(key)) for key in self.value]

    def elements(self):
        if not isinstance(self.value, list):
            self.fail(f"expected an array, found {self.kind()}")
        return [self.child(k) for k in range(len(self.value))]

    def is_number(self):
        return isinstance(self.value, (int, float)) and not isinstance(self.value, bool)

    def number(self):
        if not self.is_number():
            self.fail(f"expected a number, found {self.kind()}")
        return float(self.value)

    def positive(self):
        v = self.number()
        if not v > 0.0:
            self.fail(f"expected a number > 0, found {v:g}")
        return v

    def integer(self, low):
        if not isinstance(self.value, int) or isinstance(self.value, bool) or self.value < low:
            found = self.kind() if not self.is_number() else repr(self.value)
            self.fail(f"expected an integer >= {low}, found {found}")
        return self.value

    def string(self):
        if not isinstance(self.value, str):
            self.fail(f"expected a string, found {self.kind()}")
        return self.value

    def boolean(self):
        if not isinstance(self.value, bool):
            self.fail(f"expected true or false, found {self.kind()}")
        return self.value


class Expression:
    """A value of "set" written as text: arithmetic of the factors' names
    (+ - * / and ^ or ** for powers, pi, and the functions of FUNCTIONS), or
    a string factor's name alone."""

    def __init__(self, text, at, factors):
        self.text = text
        try:
            tree = ast.parse(text.replace("^", "**"), mode="eval")
        except SyntaxError as e:
            at.fail(f"'{text}' is not an expression: {e.msg} at column {e.offset}")
        self.body = tree.body
        self.names = set()
        self._check(self.body, at, factors)
        if not isinstance(self.body, ast.Name):
            for name in self.names:
                if factors[name].is_text:
                    at.fail(f"'{name}' is a factor of texts: it can only be given alone")

    def _check(self, node, at, factors):
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow)):
            self._check(node.left, at, factors)
            self._check(node.right, at, factors)
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            self._check(node.operand, at, factors)
        elif isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(
                node.value, bool):
            pass
        elif isinstance(node, ast.Name):
            if node.id not in factors and node.id not in CONSTANTS:
                names = ", ".join(factors) or "none"
                at.fail(f"in '{self.text}': unknown name '{node.id}' (factors: {names}; and pi)")
            if node.id in factors:
                self.names.add(node.id)
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS \
                and not node.keywords:
            for a in node.args:
                self._check(a, at, factors)
        else:
            at.fail(f"in '{self.text}': '{ast.unparse(node)}' is not allowed (numbers, factors, + - * / ^, "
                    f"parentheses and the functions {', '.join(FUNCTIONS)})")

    def evaluate(self, values):
        return self._eval(self.body, values)

    def _eval(self, node, values):
        if isinstance(node, ast.BinOp):
            a, b = self._eval(node.left, values), self._eval(node.right, values)
            if isinstance(node.op, ast.Add):
                return a + b
            if isinstance(node.op, ast.Sub):
                return a - b
            if isinstance(node.op, ast.Mult):
                return a * b
            if isinstance(node.op, ast.Div):
                return a / b
            return a ** b
        if isinstance(node, ast.UnaryOp):
            v = self._eval(node.operand, values)
            return -v if isinstance(node.op, ast.USub) else v
        if isinstance(node, ast.Constant):
            return float(node.value)
        if isinstance(node, ast.Name):
            return values[node.id] if node.id in values else CONSTANTS[node.id]
        return float(FUNCTIONS[node.func.id](*(self._eval(a, values) for a in node.args)))


class Factor:
    """A named input of the sweep: a grid (values) or a distribution."""

    def __init__(self, name, at):
        self.name, self.at = name, at
        if not IDENTIFIER.match(name):
            at.fail(f"'{name}' cannot name a factor (letters, digits and _, not starting with a digit)")
        if name in RESERVED or name in FUNCTIONS or name in CONSTANTS:
            at.fail(f"'{name}' is taken (by the table's columns {', '.join(RESERVED)}, or a function): "
                    "name the factor otherwise")
        self.values = None        # a grid's
        self.distribution = None  # a random factor's, as written
        self.targets = []         # (path, at) of its own "set"
        keys = set(at.object().value)
        if "distribution" in keys:
            self._read_distribution(at)
        elif "values" in keys:
            at.allow_only(("values", "set"))
            self._read_values(at["values"])
        elif keys & {"from", "to", "count", "log"}:
            at.allow_only(("from", "to", "count", "log", "set"))
            self._read_range(at)
        else:
            at.fail("expected \"values\", \"from\"/\"to\"/\"count\", or a \"distribution\"")
        if at.has("set"):
            s = at["set"]
            for p in ([s] if isinstance(s.value, str) else s.elements()):
                self.targets.append((p.string(), p.path))
            if not self.targets:
                s.fail("expected a path or a non-empty list of paths")

    @property
    def is_random(self):
        return self.distribution is not None

    @property
    def is_text(self):
        return self.values is not None and isinstance(self.values[0], str)

    def _read_values(self, v):
        elements = v.elements()
        if not elements:
            v.fail("expected a non-empty array")
        if all(isinstance(e.value, str) for e in elements):
            self.values = [e.value for e in elements]
        else:
            self.values = [e.number() for e in elements]
        for k, value in enumerate(self.values):
            if value in self.values[:k]:
                elements[k].fail(f"{value!r} is given twice: the runs would repeat")

    def _read_range(self, at):
        low, high = at["from"].number(), at["to"].number()
        count = at["count"].integer(1)
        log = at["log"].boolean() if at.has("log") else False
        if log and not (low > 0.0 and high > 0.0):
            at["from" if low <= 0.0 else "to"].fail("a log range needs from and to > 0")
        if count == 1:
            if low != high:
                at["count"].fail("one value from a range of two ends: give count >= 2, or values")
            self.values = [low]
            return
        if low == high:
            at["to"].fail("from and to are equal: the runs would repeat")
        if log:  # in decades: 1e4 to 1e6 in 3 gives 1e5 exactly
            a, b = math.log10(low), math.log10(high)
            self.values = [10.0 ** (a + (b - a) * k / (count - 1)) for k in range(count)]
        else:
            self.values = [low + (high - low) * k / (count - 1) for k in range(count)]
        self.values[0], self.values[-1] = low, high  # the ends as written

    def _read_distribution(self, at):
        kind = at["distribution"].string()
        if kind not in sampling.DISTRIBUTIONS:
            at["distribution"].fail(f"unknown distribution '{kind}' (expected: {', '.join(sampling.DISTRIBUTIONS)})")
        required, optional = sampling.DISTRIBUTIONS[kind]
        at.allow_only(("distribution",) + required + optional + ("set",))
        d = {"distribution": kind}
        for key in required + optional:
            if key in required or at.has(key):
                d[key] = at[key].number()
        if kind == "uniform" and not d["low"] < d["high"]:
            at["high"].fail(f"expected high > low = {d['low']:g}")
        if kind in ("normal", "lognormal") and not d["sd"] > 0.0:
            at["sd"].fail(f"expected a number > 0, found {d['sd']:g}")
        if kind == "lognormal" and not d["mean"] > 0.0:
            at["mean"].fail(f"a lognormal value is > 0: expected a mean > 0, found {d['mean']:g}")
        if kind == "normal" and "low" in d and "high" in d and not d["low"] < d["high"]:
            at["high"].fail(f"expected high > low = {d['low']:g}")
        self.distribution = d


class Sweep:
    """A sweep read from its file (Sweep.load) or from a dict: the runs, each
    run's inputs, and what the engine (symdyn-sim --serve) needs to run them."""

    @classmethod
    def load(cls, path):
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise SweepError(f"cannot read sweep file '{path}': {e.strerror}") from None
        try:
            document = json.loads(text, object_pairs_hook=_Duplicates, parse_constant=_NonFinite)
        except json.JSONDecodeError as e:
            raise SweepError(f"{path}: not JSON: {e.msg} at line {e.lineno}, column {e.colno}") from None
        return cls(document, origin=str(path), directory=os.path.dirname(os.path.abspath(path)), text=text)

    @classmethod
    def from_payload(cls, payload):
        """The sweep as payload() gave it (on a worker, which need not see its files)."""
        return cls(payload["document"], payload["origin"], payload["directory"], payload["text"],
                   scenario=(payload["scenario"], payload["scenario_text"]))

    def __init__(self, document, origin="sweep", directory=".", text=None, scenario=None):
        """document: the sweep file's object; origin names it in messages;
        directory: where a scenario file's path starts; scenario: (request,
        text) already read, else read here."""
        self.origin = origin
        self.directory = directory
        root = At(origin, document)
        _check_document(document, root)
        self.document = _plain(document)
        self.text = text if text is not None else json.dumps(self.document, sort_keys=True)
        root.allow_only(ROOT_KEYS)
        self.description = root["description"].string() if root.has("description") else ""
        if scenario is None:
            self._read_scenario(root["scenario"])
        else:
            self.scenario, self.scenario_text = scenario
        self.factors = [Factor(name, at) for name, at in root["factors"].items()] if root.has("factors") else []
        self._read_set(root)
        self._read_samples(root)
        keep = root.optional("keep")
        self.keep = _plain(keep.object().value) if keep else {}

    def _read_scenario(self, at):
        name = at.string()
        if name.endswith(".json") or "/" in name:
            path = os.path.join(self.directory, name)
            try:
                with open(path, encoding="utf-8") as f:
                    text = f.read()
            except OSError as e:
                at.fail(f"cannot read scenario file '{path}': {e.strerror}")
            self.scenario = {"text": text, "origin": name, "directory": os.path.dirname(os.path.abspath(path))}
            self.scenario_text = text
        else:
            self.scenario = {"builtin": name}
            self.scenario_text = name

    def _read_set(self, root):
        factors = {f.name: f for f in self.factors}
        self.targets = []  # (path, at) in the order the engine gets them
        self.sources = []  # per target: a factor's name, an Expression, or a fixed JSON value
        first = {}
        for f in self.factors:
            for path, at in f.targets:
                self._add_target(path, At(self.origin, path, at), first)
                self.sources.append(f.name)
        s = root.optional("set")
        for path, at in (s.items() if s else []):
            self._add_target(path, At(self.origin, path, at.path), first)
            if isinstance(at.value, str):
                e = Expression(at.value, at, factors)
                self.sources.append(e.body.id if isinstance(e.body, ast.Name) and e.body.id in factors else e)
            elif at.is_number():
                self.sources.append(("fixed", at.value))
            else:
                self.sources.append(("fixed", _plain(at.value)))
        used = {x for x in self.sources if isinstance(x, str)}
        for e in self.sources:
            if isinstance(e, Expression):
                used |= e.names
        for f in self.factors:
            if f.name not in used:
                f.at.fail(f"factor '{f.name}' changes nothing: give it \"set\" (a path), or use it in \"set\"")

    def _add_target(self, path, at, first):
        if not path:
            at.fail("expected a path (forces.spring.stiffness, parameters.m1, initial.qd.q0, ...)")
        if path in first:
            at.fail(f"{path} is set twice (also at {first[path]})")
        first[path] = at.path
        self.targets.append((path, at.path))

    def _read_samples(self, root):
        random_factors = [f for f in self.factors if f.is_random]
        self.seed = root["seed"].integer(0) if root.has("seed") else 0
        self.sampling = root["sampling"].string() if root.has("sampling") else "random"
        if self.sampling not in ("random", "latin_hypercube"):
            root["sampling"].fail(f"unknown sampling '{self.sampling}' (expected random or latin_hypercube)")
        if random_factors:
            if not root.has("samples"):
                random_factors[0].at.fail("a factor with a distribution needs \"samples\" (the draws per grid point)")
            self.samples = root["samples"].integer(1)
        else:
            if root.has("samples"):
                root["samples"].fail("without a factor with a distribution every sample would repeat the same run")
            self.samples = 1
        self.grid = [f for f in self.factors if not f.is_random]
        self.random = random_factors
        self.points = math.prod(len(f.values) for f in self.grid)
        self.runs = self.points * self.samples
        self._lhs = {f.name: sampling.lhs_permutation(self.seed, f.name, self.samples) for f in random_factors} \
            if self.sampling == "latin_hypercube" else None

    # --- runs -------------------------------------------------------------

    def run_seed(self, run):
        return sampling.run_seed(self.seed, run)

    def inputs(self, run):
        """The factors' values of a run, in the order of self.factors."""
        if not 0 <= run < self.runs:
            raise IndexError(f"run {run} of a sweep of {self.runs}")
        point, sample = divmod(run, self.samples)
        values = {}
        for f in reversed(self.grid):  # the first factor varies slowest
            point, k = divmod(point, len(f.values))
            values[f.name] = f.values[k]
        if self.random:
            seed = self.run_seed(run)
            for f in self.random:
                u = sampling.uniform01(seed, f.name)
                if self._lhs is not None:
                    u = (self._lhs[f.name][sample] + u) / self.samples
                values[f.name] = sampling.quantile(f.distribution, u)
        return [values[f.name] for f in self.factors]

    def values(self, run, inputs=None):
        """What the run puts at each target, in the order of self.targets;
        RunInputError when an expression of "set" fails for it."""
        inputs = self.inputs(run) if inputs is None else inputs
        by_name = {f.name: v for f, v in zip(self.factors, inputs)}
        out = []
        for (path, at), source in zip(self.targets, self.sources):
            if isinstance(source, str):
                out.append(by_name[source])
            elif isinstance(source, Expression):
                try:
                    v = source.evaluate(by_name)
                except (ArithmeticError, ValueError) as e:
                    raise RunInputError(f"{self.origin}: {at}: '{source.text}' fails for this run: {e}") from None
                if not math.isfinite(v):
                    raise RunInputError(f"{self.origin}: {at}: '{source.text}' is {v} for this run")
                out.append(v)
            else:
                out.append(source[1])
        return out

    def payload(self):
        """What a worker needs to rebuild the sweep (from_payload): plain data."""
        return {"document": self.document, "origin": self.origin, "directory": self.directory, "text": self.text,
                "scenario": self.scenario, "scenario_text": self.scenario_text}

    def fingerprint(self):
        """Names this sweep's runs: its file and its scenario's, hashed."""
        return hashlib.sha256(f"{self.text}\0{self.scenario_text}".encode()).hexdigest()

    def load_request(self):
        """The engine's "load" request (serve.hpp)."""
        return {"scenario": self.scenario, "origin": self.origin,
                "targets": [{"path": p, "at": at} for p, at in self.targets],
                "keep": self.keep, "keep_at": "/keep"}
