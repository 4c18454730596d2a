"""Runs of a sweep, made by the engine symdyn-sim --serve (apps/sim/serve.hpp).

Each worker thread (a local worker, or a thread of a Dask worker) keeps one
engine process for its life: a run costs a request and a reply on a pipe,
never a process start. execute() is the one function that makes runs: the
local workers call it, and so does every Dask task, on whatever machine. It
sends its runs in one request, so that the driver wakes once for all of them
(a wake-up after a run costs more CPU than the request and the reply).

An engine that dies during a run (a crash in a model module, a kill) is
started again and the run retried once; a run that kills it twice is
recorded as crashed, and the next run gets a fresh engine.
"""
import json
import os
import select
import signal
import socket
import subprocess
import threading

from .sweep_file import RunInputError, Sweep, SweepError


class EngineError(RuntimeError):
    """The engine cannot be started or run here, or a worker cannot run the
    sweep: nothing of the sweep can run where this happens."""


class _EngineDied(RuntimeError):
    pass


class _EngineTimeout(RuntimeError):
    pass


def find_program(given=None):
    """The symdyn-sim to run: `given` (the driver's) when this machine has it,
    else $SYMDYN_SIM, else the one of the build this package was copied by, or
    installed with (_build.py), else the one on PATH."""
    program = given if given and os.path.isfile(given) else os.environ.get("SYMDYN_SIM") or given
    if not program:
        try:
            from ._build import SYMDYN_SIM as program
        except ImportError:
            program = None
    if not program:
        raise EngineError("no symdyn-sim: set SYMDYN_SIM to its path, or put it on PATH")
    return program


class Engine:
    """One symdyn-sim --serve process, started on the first request."""

    def __init__(self, program):
        self.program = program
        self.process = None
        self.loaded = None  # the fingerprint of the sweep it holds
        self.columns = None

    def _start(self):
        try:
            # A process group of its own: Ctrl-C reaches the driver, which stops the engines itself.
            self.process = subprocess.Popen([self.program, "--serve"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                            stderr=subprocess.DEVNULL, text=True, encoding="utf-8",
                                            start_new_session=True)
        except OSError as e:
            raise EngineError(f"cannot start the engine '{self.program}' on {socket.gethostname()}: "
                              f"{e.strerror}") from None
        self.loaded = None

    def _discard(self):
        for pipe in (self.process.stdin, self.process.stdout):
            try:
                pipe.close()
            except OSError:  # a broken pipe's unwritten line
                pass
        self.process = None

    def _death(self):
        try:
            code = self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            code = self.process.wait()
        self._discard()
        if code < 0:
            try:
                return f"the engine (symdyn-sim --serve) was killed by {signal.Signals(-code).name}"
            except ValueError:
                return f"the engine (symdyn-sim --serve) was killed by signal {-code}"
        return f"the engine (symdyn-sim --serve) exited with code {code}"

    def request(self, message, timeout=None):
        if self.process is None or self.process.poll() is not None:
            self._start()
        try:
            self.process.stdin.write(json.dumps(message) + "\n")
            self.process.stdin.flush()
            if timeout is not None and not select.select([self.process.stdout], [], [], timeout)[0]:
                self.stop()
                raise _EngineTimeout()
            line = self.process.stdout.readline()
        except (BrokenPipeError, ConnectionResetError):
            line = ""
        if not line:
            raise _EngineDied(self._death())
        # Integers read as floats: "-0" keeps its sign, and every number is a double as the engine wrote it.
        return json.loads(line, parse_int=float)

    def request_runs(self, runs):
        """Several runs in one request: their replies come together (the
        driver wakes once for them). _EngineDied when it dies among them."""
        if self.process is None or self.process.poll() is not None:
            self._start()
        try:
            self.process.stdin.write(json.dumps({"runs": runs}) + "\n")
            self.process.stdin.flush()
            lines = [self.process.stdout.readline() for _ in runs]
        except (BrokenPipeError, ConnectionResetError):
            lines = [""]
        if not all(lines):
            raise _EngineDied(self._death())
        return [json.loads(line, parse_int=float) for line in lines]

    def load(self, sweep, fingerprint):
        if self.loaded == fingerprint and self.process is not None:
            return self.columns
        try:
            reply = self.request({"load": sweep.load_request()})
        except _EngineDied as e:
            raise EngineError(f"{e} while loading the sweep") from None
        if "error" in reply:  # the sweep, its scenario or a kept quantity refused
            raise SweepError(reply["error"])
        self.loaded, self.columns = fingerprint, reply["loaded"]["columns"]
        return self.columns

    def stop(self):
        if self.process is not None:
            self.process.kill()
            self.process.wait()
            self._discard()

    def close(self):
        """Ends the engine (the end of its input ends it)."""
        if self.process is not None:
            try:
                self.process.stdin.close()
                self.process.wait(timeout=10)
            except (OSError, subprocess.TimeoutExpired):
                self.process.kill()
                self.process.wait()
            self._discard()


_local = threading.local()
_sweeps = {}  # fingerprint -> Sweep, rebuilt once per worker process
_sweeps_lock = threading.Lock()


def thread_engine(program):
    """This thread's engine, started when first needed."""
    engines = getattr(_local, "engines", None)
    if engines is None:
        engines = _local.engines = {}
    if program not in engines:
        engines[program] = Engine(program)
    return engines[program]


def close_thread_engines():
    for engine in getattr(_local, "engines", {}).values():
        engine.close()
    _local.engines = {}


def _sweep(payload, fingerprint):
    with _sweeps_lock:
        if fingerprint not in _sweeps:
            _sweeps[fingerprint] = Sweep.from_payload(payload)
        return _sweeps[fingerprint]


def worker_name(engine=None):
    """host:pid of the engine that made a run (else of this process)."""
    pid = engine.process.pid if engine is not None and engine.process is not None else os.getpid()
    return f"{socket.gethostname()}:{pid}"


def failed_row(sweep, run, status, message, ncolumns, seconds=0.0):
    """(row, timing, series) of a run without results: its inputs, NaN for the kept columns."""
    head = ([sweep.run_seed(run)] if sweep.random else []) + sweep.inputs(run)
    row = (run, status, message, *head, *[float("nan")] * ncolumns)
    return row, (seconds, seconds, worker_name()), None


def execute(payload, fingerprint, runs, program, timeout=None, stop=None):
    """Makes the runs (a list of run indices) of a sweep on this thread's
    engine. Returns one (row, timing, series) per run: row as the table's
    columns (run, status, error, [seed], factors, kept columns), timing
    (cpu s, wall s, worker), series the run's CSV text or None. `stop` (an
    Event): once set, an engine that dies is not started again."""
    sweep = _sweep(payload, fingerprint)
    engine = thread_engine(find_program(program))
    ncolumns = len(engine.load(sweep, fingerprint))
    out, todo = {}, []
    for run in runs:
        inputs = sweep.inputs(run)
        try:
            values = sweep.values(run, inputs)
        except RunInputError as e:
            out[run] = failed_row(sweep, run, "failed", str(e), ncolumns)
            continue
        todo.append((run, ([sweep.run_seed(run)] if sweep.random else []) + inputs, values))
    if len(todo) > 1 and timeout is None:
        # All in one request; if the engine dies among them, each is made alone
        # below, which finds the run that kills it.
        try:
            replies = engine.request_runs([{"run": run, "values": values} for run, _, values in todo])
        except _EngineDied:
            if stop is not None and stop.is_set():
                raise
            replies = []
        for (run, head, _), reply in zip(todo, replies):
            out[run] = _row(engine, run, head, reply)
        todo = todo[len(replies):]
    for run, head, values in todo:
        out[run] = _run(engine, sweep, fingerprint, run, values, head, ncolumns, timeout, stop)
    return [out[run] for run in runs]


def _row(engine, run, head, reply):
    if "run" not in reply:  # a request the engine could not read: a bug, not a run's failure
        raise EngineError(f"run {run}: {reply['error']}")
    row = (run, reply["status"], reply["error"], *head, *reply["values"])
    return row, (reply["cpu"], reply["wall"], worker_name(engine)), reply.get("series")


def _run(engine, sweep, fingerprint, run, values, head, ncolumns, timeout, stop):
    died = None
    for _ in range(2):
        try:
            engine.load(sweep, fingerprint)
            reply = engine.request({"run": run, "values": values}, timeout)
        except _EngineTimeout:
            message = f"stopped after {timeout:g} s (the sweep's timeout); its engine was killed"
            return failed_row(sweep, run, "failed", message, ncolumns, timeout)
        except _EngineDied as e:
            if stop is not None and stop.is_set():
                raise
            died = e
            continue
        return _row(engine, run, head, reply)
    return failed_row(sweep, run, "crashed", f"{died}, twice, running it", ncolumns)
