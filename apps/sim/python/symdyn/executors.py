"""Where the runs of a sweep are made: this machine's cores, or a Dask cluster.

Both call engine.execute, so a run is the same computation, and gives the
same row bit for bit, wherever it is made. The driver (sweep.py) receives
rows through sink(rows), in the order runs finish.

LocalWorkers: one thread per worker, each with its own engine process (the
runtime's systems are not shared between threads); a thread takes the next
runs as soon as it is free: one at first, then as many as last about
batch_seconds (0.2 s), never more than a share of what is left that keeps
every worker busy to the end. Nothing to start.

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


def batch_size(seconds, rows, left, workers):
    """Runs in the next batch (or task): as many as last `seconds` at the pace
    of `rows` (those of the last batch), at most left / (2 workers)."""
    walls = [t[1] for _, t, _ in rows if t[1] > 0.0]
    size = int(seconds * len(walls) / sum(walls)) if walls else 1
    return max(1, min(size, 10_000, left // (2 * workers)))


class LocalWorkers:
    def __init__(self, workers, program, timeout=None, batch_seconds=0.2):
        self.workers, self.program, self.timeout = workers, program, timeout
        self.batch_seconds = batch_seconds
        self.tasks = 0  # batches made

    def describe(self):
        return f"{self.workers} local worker{'s' if self.workers != 1 else ''}"

    def run(self, sweep, fingerprint, pending, ncolumns, sink):
        payload = sweep.payload()
        runs = iter(pending)
        left = [len(pending)]
        lock = threading.Lock()
        results = queue.Queue()
        stop = threading.Event()
        engines = []

        def work():
            try:
                with lock:
                    engines.append(thread_engine(self.program))
                size = 1
                while not stop.is_set():
                    with lock:
                        batch = list(itertools.islice(runs, size))
                        left[0] -= len(batch)
                    if not batch:
                        break
                    rows = execute(payload, fingerprint, batch, self.program, self.timeout, stop)
                    results.put(("rows", rows))
                    with lock:
                        self.tasks += 1
                    size = batch_size(self.batch_seconds, rows, left[0], self.workers)
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
                # What has come meanwhile goes to the outputs in one batch.
                batch = [results.get()]
                while True:
                    try:
                        batch.append(results.get_nowait())
                    except queue.Empty:
                        break
                rows = []
                for kind, value in batch:
                    if kind == "rows":
                        rows.extend(value)
                    elif kind == "error":
                        stop.set()
                        error = error or value
                    else:
                        running -= 1
                if rows and not stop.is_set():
                    sink(rows)
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
        self.tasks = 0  # submitted

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
                self.tasks += 1

            def fill():
                while len(futures) < 2 * self.threads:
                    batch = list(itertools.islice(runs, max(1, min(chunk, left // (2 * self.threads)))))
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
                chunk = batch_size(self.chunk_seconds, rows, left, self.threads)
                fill()
        finally:
            for f, _ in futures.values():
                f.cancel()
            client.close()

