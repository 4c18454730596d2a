"""Where the runs of a sweep are made: this machine's cores, or a Dask cluster.

Both call engine.execute, so a run is the same computation, and gives the
same row bit for bit, wherever it is made. The driver (sweep.py) receives
rows through sink(rows), in the order runs finish.

LocalWorkers: one thread per worker, each with its own engine process (the
runtime's systems are not shared between threads); a thread takes the next
run as soon as it is free. Nothing to start.

DaskWorkers: a running Dask scheduler's workers, on any number of machines.
Runs go in tasks of a few runs each, sized so that a task lasts about
chunk_seconds (the first tasks hold one run, to measure), with at most two
tasks per worker thread in flight. A task lost with its worker is run again
by Dask elsewhere; a task that has killed distributed.scheduler.allowed-failures
workers (3 by default) is split into its runs, and a run that does it alone
is recorded as crashed.
"""
import itertools
import os
import queue
import threading

from .engine import EngineError, close_thread_engines, execute, failed_row, thread_engine


class LocalWorkers:
    def __init__(self, workers, program, timeout=None):
        self.workers, self.program, self.timeout = workers, program, timeout

    def describe(self):
        return f"{self.workers} local worker{'s' if self.workers != 1 else ''}"

    def run(self, sweep, fingerprint, pending, ncolumns, sink):
        payload = sweep.payload()
        runs = iter(pending)
        lock = threading.Lock()
        results = queue.Queue()
        stop = threading.Event()
        engines = []

        def work():
            try:
                with lock:
                    engines.append(thread_engine(self.program))
                while not stop.is_set():
                    with lock:
                        run = next(runs, None)
                    if run is None:
                        break
                    rows = execute(payload, fingerprint, [run], self.program, self.timeout, stop)
                    results.put(("rows", rows))
            except BaseException as e:  # handed to the driver's thread
                results.put(("error", e))
            finally:
                close_thread_engines()
                results.put(("done", None))

        threads = [threading.Thread(target=work, name=f"symdyn worker {k}", daemon=True)
                   for k in range(self.workers)]
        for t in threads:
            t.start()
        running, error = len(threads), None
        try:
            while running:
                kind, value = results.get()
                if kind == "rows":
                    if not stop.is_set():
                        sink(value)
                elif kind == "error":
                    stop.set()
                    error = error or value
                else:
                    running -= 1
        except BaseException:  # KeyboardInterrupt: no row after this one, engines stopped
            stop.set()
            with lock:
                for e in engines:
                    if e.process is not None:
                        e.process.kill()
            raise
        if error is not None:
            raise error


class DaskWorkers:
    def __init__(self, address, program, timeout=None, chunk_seconds=1.0, connect_timeout=60.0):
        self.address, self.program, self.timeout = address, program, timeout
        self.chunk_seconds, self.connect_timeout = chunk_seconds, connect_timeout
        self.threads = 0

    def describe(self):
        return f"the Dask cluster at {self.address} ({self.threads} worker threads)"

    def run(self, sweep, fingerprint, pending, ncolumns, sink):
        import distributed
        from distributed.scheduler import KilledWorker

        try:
            # An address, or the file a scheduler wrote it to (dask scheduler --scheduler-file).
            where = {"scheduler_file": self.address} if os.path.isfile(self.address) else {"address": self.address}
            client = distributed.Client(**where, timeout=f"{self.connect_timeout}s", set_as_default=False)
        except OSError as e:
            raise EngineError(f"--scheduler {self.address}: cannot reach the Dask scheduler: {e}") from None
        futures = {}
        try:
            try:
                client.wait_for_workers(1, timeout=self.connect_timeout)
            except TimeoutError:
                raise EngineError(f"--scheduler {self.address}: no worker joined within {self.connect_timeout:g} s") \
                    from None
            self.threads = max(1, sum(client.nthreads().values()))
            payload = sweep.payload()
            runs = iter(pending)
            left = len(pending)
            chunk = 1
            serial = itertools.count()
            done = distributed.as_completed(loop=client.loop)

            def submit(batch):
                key = f"symdyn-sweep-{fingerprint[:12]}-{next(serial)}"
                f = client.submit(execute, payload, fingerprint, batch, self.program, self.timeout, key=key,
                                  pure=False)
                futures[f.key] = (f, batch)
                done.add(f)

            def fill():
                while len(futures) < 2 * self.threads:
                    size = max(1, min(chunk, left // (2 * self.threads)))
                    batch = list(itertools.islice(runs, size))
                    if not batch:
                        return
                    submit(batch)

            fill()
            for f in done:
                _, batch = futures.pop(f.key)
                try:
                    rows = f.result()
                except KilledWorker:
                    if len(batch) > 1:
                        for run in batch:
                            submit([run])
                        continue
                    rows = [failed_row(sweep, batch[0], "crashed", "its task killed every Dask worker that ran it "
                                       "(distributed.scheduler.allowed-failures times)", ncolumns)]
                except EngineError:
                    raise
                except Exception as e:
                    raise EngineError(f"a Dask worker could not run the sweep's task: {type(e).__name__}: {e} "
                                      "(do the workers import symdyn and find symdyn-sim? docs/sweeps.md)") from None
                finally:
                    f.release()
                left -= len(rows)
                sink(rows)
                walls = [t[1] for _, t, _ in rows if t[1] > 0.0]
                if walls:
                    chunk = max(1, min(10_000, int(self.chunk_seconds * len(walls) / sum(walls))))
                fill()
        finally:
            for f, _ in futures.values():
                f.cancel()
            client.close()

