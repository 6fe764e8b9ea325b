"""A progress bar on stderr for sweeps: drawn in place on a terminal,
quiet elsewhere unless asked for (then one line a finished variant)."""

from __future__ import annotations

import sys
import time
from typing import Optional


class Progress:
    """Counts finished variants out of ``total``."""

    def __init__(self, total: int, enabled: Optional[bool] = None, label: str = "sweep"):
        self.total = total
        self.tty = sys.stderr.isatty()
        self.enabled = self.tty if enabled is None else enabled
        self.label = label
        self.done = 0
        self.failed = 0
        self.start = time.monotonic()

    def advance(self, failed: bool = False, reused: bool = False) -> None:
        """One more variant finished (``reused``: done by an earlier run)."""
        self.done += 1
        self.failed += failed
        if self.enabled and (self.tty or not reused):
            self._draw()

    def close(self) -> None:
        """Ends the bar's line."""
        if self.enabled and self.tty:
            sys.stderr.write("\n")
            sys.stderr.flush()

    def _draw(self) -> None:
        elapsed = time.monotonic() - self.start
        width = 30
        filled = width * self.done // max(self.total, 1)
        bar = "=" * filled + (">" if filled < width else "") + " " * (width - filled - 1)
        eta = elapsed / self.done * (self.total - self.done) if self.done else 0.0
        line = (
            f"{self.label} [{bar[:width]}] {self.done}/{self.total} variants, "
            f"{self.failed} failed, {elapsed:.0f} s elapsed, eta {eta:.0f} s"
        )
        sys.stderr.write(("\r" + line) if self.tty else (line + "\n"))
        sys.stderr.flush()
