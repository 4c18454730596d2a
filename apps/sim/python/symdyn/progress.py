"""The progress of a sweep on stderr, when it is a terminal:

    [##############                ]  456/1200 runs  12.3 runs/s  1:01 left  3 failed

redrawn at most five times a second; the time left is the runs left over the
rate of the last minute's runs (the whole run's before that)."""
import collections
import sys
import time


def duration(seconds):
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


class Progress:
    def __init__(self, total, done, stream=None, enabled=None):
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = self.stream.isatty() if enabled is None else enabled
        self.total, self.done, self.not_ok = total, done, 0
        self.start = time.monotonic()
        self.last_draw = 0.0
        self.recent = collections.deque()  # (time, runs done)
        self.recent.append((self.start, done))
        self.drawn = False

    def update(self, runs, not_ok):
        self.done += runs
        self.not_ok += not_ok
        now = time.monotonic()
        self.recent.append((now, self.done))
        while len(self.recent) > 2 and now - self.recent[1][0] > 60.0:
            self.recent.popleft()
        if self.enabled and now - self.last_draw >= 0.2:
            self.draw(now)

    def rate(self, now):
        t0, d0 = self.recent[0]
        return (self.done - d0) / (now - t0) if now > t0 and self.done > d0 else 0.0

    def line(self, now):
        width = 30
        filled = int(width * self.done / self.total) if self.total else width
        rate = self.rate(now)
        left = duration((self.total - self.done) / rate) if rate > 0 else "?"
        text = f"[{'#' * filled}{' ' * (width - filled)}] {self.done:>{len(str(self.total))}}/{self.total} runs"
        text += f"  {rate:.3g} runs/s  {left} left"
        if self.not_ok:
            text += f"  {self.not_ok} not ok"
        return text

    def draw(self, now):
        self.last_draw = now
        self.stream.write("\r" + self.line(now) + "\033[K")
        self.stream.flush()
        self.drawn = True

    def finish(self):
        if self.drawn:
            self.draw(time.monotonic())
            self.stream.write("\n")
            self.stream.flush()
