"""Progress of a long command, phase by phase, on stderr (stdout keeps the report).

On a terminal: one bar over the phases (``verify [3/9] stock 2.1 s``), redrawn in place, with
the stock's own bar of cutters under it. Elsewhere (CI logs, a pipe): one short line per
finished phase with its elapsed time (``vmach verify: stock 4.08 s``), so that a log shows
where the time went and where a run stopped. Silent with ``--quiet``.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO


class Progress:
    """Reports phases; ``start(name)`` then ``done(name, seconds)``.

    mode : "bar" (a terminal), "log" (one line a phase) or "off".
    phases : the names expected, for the bar's length (a phase not listed adds to it).
    """

    def __init__(self, command: str, mode: str, phases: tuple[str, ...] = (), stream: TextIO | None = None):
        self.command = command
        self.mode = mode
        self.stream = stream if stream is not None else sys.stderr
        self.phases = list(phases)
        self.seen: list[str] = []
        self._done: set[str] = set()
        self._bar = None
        self._t0 = time.perf_counter()

    @classmethod
    def for_stream(cls, command: str, quiet: bool, phases: tuple[str, ...] = (),
                   stream: TextIO | None = None) -> Progress:
        """Bars on a terminal, log lines otherwise, nothing when ``quiet``."""
        s = stream if stream is not None else sys.stderr
        tty = bool(getattr(s, "isatty", lambda: False)())
        return cls(command, "off" if quiet else "bar" if tty else "log", phases, s)

    def start(self, name: str) -> None:
        if self.mode == "off":
            return
        if name not in self.seen:
            self.seen.append(name)
        if name not in self.phases:
            self.phases.append(name)
        if self.mode == "bar":
            if self._bar is None:
                from tqdm import tqdm

                self._bar = tqdm(total=len(self.phases), file=self.stream, leave=False, position=0,
                                 bar_format="{desc} |{bar}| {n_fmt}/{total_fmt} {elapsed}")
            self._bar.total = len(self.phases)
            self._bar.set_description_str(f"vmach {self.command}: {name}")
            self._bar.refresh()

    def done(self, name: str, seconds: float) -> None:
        """``name`` finished after ``seconds``; a phase that runs again in parts (the stock's
        last batches after the collisions) logs its later parts as ``continued``."""
        again = name in self._done
        self._done.add(name)
        if self.mode == "log":
            part = " (continued)" if again else ""
            self.stream.write(f"vmach {self.command}: {name}{part} {seconds:.2f} s\n")
            self.stream.flush()
        elif self.mode == "bar" and self._bar is not None and not again:
            self._bar.n = min(self._bar.n + 1, self._bar.total)
            self._bar.refresh()

    def close(self, finished: bool = True) -> None:
        """End the bar (it leaves no line behind) or write the total time (``finished``) or
        where the run stopped."""
        if self.mode == "bar" and self._bar is not None:
            self._bar.close()
            self._bar = None
        elif self.mode == "log":
            t = time.perf_counter() - self._t0
            last = self.seen[-1] if self.seen else 'setup'
            where = f"done in {t:.2f} s" if finished else f"stopped in {last}"
            self.stream.write(f"vmach {self.command}: {where}\n")
            self.stream.flush()
        self.mode = "off"
