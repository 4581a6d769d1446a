"""The driver's progress line (jobs done/running/failed, ETA) and the closing summary."""
from __future__ import annotations

import statistics
import sys
import time


def _clock(seconds: float) -> str:
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02}:{s:02}" if h else f"{m}:{s:02}"


class Progress:
    """A live bar on a terminal; elsewhere (logs, CI) a line at most every `every_s`."""

    WIDTH = 30

    def __init__(self, total: int, stream=None, live: bool | None = None, every_s: float = 10.0):
        self.total = total
        self.stream = stream or sys.stderr
        self.live = self.stream.isatty() if live is None else live
        self.every_s = every_s
        self.start = time.monotonic()
        self._last_line = 0.0
        self.done = self.failed = self.running = 0

    def eta(self) -> float | None:
        finished = self.done + self.failed
        if finished == 0:
            return None
        return (time.monotonic() - self.start) * (self.total - finished) / finished

    def line(self) -> str:
        finished = self.done + self.failed
        filled = self.WIDTH * finished // self.total if self.total else self.WIDTH
        eta = self.eta()
        return (f"[{'#' * filled}{'.' * (self.WIDTH - filled)}] {finished}/{self.total} jobs: "
                f"{self.done} done, {self.running} running, {self.failed} failed  "
                f"{_clock(time.monotonic() - self.start)}  ETA {_clock(eta) if eta is not None else '?'}")

    def update(self, *, done: int, failed: int, running: int, force: bool = False) -> None:
        changed = (done, failed, running) != (self.done, self.failed, self.running)
        self.done, self.failed, self.running = done, failed, running
        now = time.monotonic()
        if self.live:
            if changed or force or now - self._last_line >= 1.0:
                self.stream.write("\r" + self.line() + " ")
                self.stream.flush()
                self._last_line = now
        elif force or now - self._last_line >= self.every_s:
            self.stream.write(self.line() + "\n")
            self.stream.flush()
            self._last_line = now

    def message(self, text: str) -> None:
        """A line above the bar (a failure report)."""
        if self.live:
            self.stream.write("\r" + " " * (len(self.line()) + 1) + "\r")
        self.stream.write(text.rstrip() + "\n")
        self.stream.flush()

    def finish(self) -> None:
        if self.live:
            self.stream.write("\r" + self.line() + "\n")
            self.stream.flush()


def summary(*, frames: int, skipped: int, rendered: int, failed: int, jobs_run: int,
            job_seconds: list[float], wall_s: float, failed_scenes: int = 0) -> str:
    # A scene that does not load has no images in the plan: it is counted apart.
    scenes = f"; {failed_scenes} scene(s) failed to load" if failed_scenes else ""
    lines = [f"zigzag-farm: {frames} image(s): {rendered} rendered, {skipped} already complete, "
             f"{failed} failed{scenes}; {jobs_run} job(s) run in {_clock(wall_s)} ({wall_s:.1f} s)"]
    if job_seconds:
        lines.append(f"zigzag-farm: job time mean {statistics.fmean(job_seconds):.2f} s, median "
                     f"{statistics.median(job_seconds):.2f} s, max {max(job_seconds):.2f} s, "
                     f"total {sum(job_seconds):.1f} s")
    return "\n".join(lines)
