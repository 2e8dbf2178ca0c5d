"""Progress of long computations: a bar on a terminal, periodic lines in a log, or nothing.

A loop that takes seconds (a grid of settings in chunks, an optimiser's iterations, the runs
of a study) reports between its chunks, never per event::

    with Progress(len(chunks), "Fig. 17 positioning", unit="settings", mode=progress) as bar:
        for chunk in chunks:
            ...
            bar.advance(chunk.size)

``mode`` (the ``progress=`` argument of the library functions that loop):

* ``"bar"``: one line on ``stream`` (stderr), redrawn at most every :data:`BAR_INTERVAL`
  seconds, with done/total, rate and ETA; a newline when the work ends.
* ``"log"``: an INFO line through the logger ``selfalign.progress`` every
  :data:`LOG_INTERVAL` seconds with the same numbers, and a final line with the time taken.
  The workflow scripts' :func:`selfalign.stages.common.logged` puts these into the job's log.
* ``"quiet"``: nothing.
* ``"auto"`` (default): the environment variable ``SELFALIGN_PROGRESS`` if set (one of
  the modes above), else ``"log"`` when the ``selfalign`` logger has a handler and is enabled
  for INFO (a workflow job: log lines even if stderr is a terminal, since parallel jobs
  share it), else ``"bar"`` when stderr is a terminal, else ``"quiet"``.

This module is below every layer of the package and imports none of them.
"""

from __future__ import annotations

import logging
import os
import sys
import time

#: Seconds between two log lines.
LOG_INTERVAL = 5.0
#: Seconds between two redraws of the bar (at most ~10 per second).
BAR_INTERVAL = 0.1
#: Characters of the bar itself.
BAR_WIDTH = 30
#: Environment variable that chooses the mode of ``mode="auto"``.
ENVIRONMENT = "SELFALIGN_PROGRESS"
MODES = ("auto", "bar", "log", "quiet")
#: The logger of log mode, a child of the one the workflow scripts configure.
LOGGER = logging.getLogger("selfalign.progress")


def resolve_mode(mode: str = "auto", stream=None) -> str:
    """The mode ``"bar"``, ``"log"`` or ``"quiet"`` that ``mode`` stands for (module docstring)."""
    if not isinstance(mode, str):
        raise TypeError(f"progress must be a string, one of {list(MODES)}, got {mode!r} ({type(mode).__name__})")
    if mode not in MODES:
        raise ValueError(f"progress must be one of {list(MODES)}, got {mode!r}")
    if mode != "auto":
        return mode
    chosen = os.environ.get(ENVIRONMENT, "")
    if chosen:
        if chosen not in MODES:
            raise ValueError(f"{ENVIRONMENT} must be one of {list(MODES)}, got {chosen!r}")
        if chosen != "auto":
            return chosen
    if LOGGER.isEnabledFor(logging.INFO) and LOGGER.hasHandlers():
        return "log"
    stream = sys.stderr if stream is None else stream
    return "bar" if getattr(stream, "isatty", lambda: False)() else "quiet"


def duration(seconds: float) -> str:
    """``seconds`` for people: "42 s", "3 min 05 s", "2 h 07 min"."""
    seconds = max(0, round(seconds))
    if seconds < 60:
        return f"{seconds} s"
    if seconds < 3600:
        return f"{seconds // 60} min {seconds % 60:02d} s"
    return f"{seconds // 3600} h {seconds % 3600 // 60:02d} min"


class Progress:
    """Progress of ``total`` units of work called ``label`` (module docstring).

    :meth:`advance` after each piece of work, :meth:`close` (or the ``with`` block) at the
    end.  ``clock`` (seconds, monotonic) and ``stream`` are there for tests.
    """

    def __init__(self, total: int, label: str, *, unit: str = "items", mode: str = "auto", stream=None,
                 clock=time.monotonic):
        if isinstance(total, bool) or not isinstance(total, int) or total < 0:
            raise ValueError(f"progress total must be an integer >= 0, got {total!r}")
        self.total, self.label, self.unit = total, label, unit
        self.stream = sys.stderr if stream is None else stream
        self.mode = resolve_mode(mode, self.stream)
        self.interval = BAR_INTERVAL if self.mode == "bar" else LOG_INTERVAL
        self.clock = clock
        self.done, self.note, self.closed = 0, "", False
        self.start = clock()
        self._next = self.start + self.interval
        self._drawn = 0

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, kind, error, traceback) -> None:
        self.close(failed=kind is not None)

    def advance(self, n: int = 1, note: str = "") -> None:
        """Count ``n`` more units done; ``note`` (e.g. the current objective) is shown with them."""
        self.done += n
        if note:
            self.note = note
        if self.mode != "quiet":
            now = self.clock()
            if now >= self._next:
                self._next = now + self.interval
                self._report(now)

    def close(self, failed: bool = False) -> None:
        """The final line: the whole count and time taken (or where it stopped, if ``failed``)."""
        if self.closed or self.mode == "quiet":
            self.closed = True
            return
        self.closed = True
        now = self.clock()
        if self.mode == "bar":
            self._report(now)
            self.stream.write("\n")
            self.stream.flush()
            return
        elapsed = now - self.start
        rate = f", {self.done / elapsed:.3g} {self.unit}/s" if elapsed > 0 else ""
        verb = "stopped after" if failed else "done:"
        LOGGER.info("%s: %s %d/%d %s in %s%s%s", self.label, verb, self.done, self.total, self.unit,
                    duration(elapsed), rate, f"; {self.note}" if self.note else "")

    def status(self, now: float) -> str:
        """done/total, percentage, rate and ETA at time ``now``."""
        elapsed = now - self.start
        parts = [f"{self.done}/{self.total} {self.unit}"]
        if self.total:
            parts[0] += f" ({100 * self.done / self.total:.0f} %)"
        if elapsed > 0 and self.done:
            rate = self.done / elapsed
            parts.append(f"{rate:.3g} {self.unit}/s")
            parts.append(f"ETA {duration(max(self.total - self.done, 0) / rate)}")
        if self.note:
            parts.append(self.note)
        return ", ".join(parts)

    def _report(self, now: float) -> None:
        if self.mode == "log":
            LOGGER.info("%s: %s", self.label, self.status(now))
            return
        filled = BAR_WIDTH * min(self.done, self.total) // self.total if self.total else BAR_WIDTH
        line = f"\r{self.label} [{'#' * filled}{'.' * (BAR_WIDTH - filled)}] {self.status(now)}"
        self.stream.write(line + " " * max(self._drawn - len(line), 0))
        self.stream.flush()
        self._drawn = len(line)
