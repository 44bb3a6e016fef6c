"""Progress reports of long calls: the ``progress`` argument of natura's
functions as the callable the native module calls.

``progress`` may be ``None`` (no reports), a callable
``progress(stage, done, total)`` (``stage`` the Rust stage's name, ``done``
the units finished so far, ``total`` the stage's units, 0 if unknown), or
``True``: a ``tqdm`` bar per stage when tqdm is installed (an optional
import), else one line per stage on standard error when it completes.
"""

from __future__ import annotations

import sys
from typing import Any, Callable, Optional, Union

Callback = Callable[[str, int, int], Any]
ProgressArg = Union[None, bool, Callback]


class Bars:
    """A ``progress`` callable that shows one ``tqdm`` bar per stage (or,
    without tqdm, prints each stage's name when it completes)."""

    def __init__(self) -> None:
        try:
            from tqdm import tqdm  # optional dependency
        except ImportError:
            tqdm = None
        self._tqdm = tqdm
        self._bar: Any = None
        self._stage: Optional[str] = None
        self._done = 0

    def __call__(self, stage: str, done: int, total: int) -> None:
        if stage != self._stage or done < self._done:
            self.close()
            self._stage = stage
            self._done = 0
            if self._tqdm is not None:
                self._bar = self._tqdm(total=total or None, desc=stage, leave=False)
        if self._bar is not None:
            self._bar.update(done - self._done)
        elif self._tqdm is None and total and done >= total > self._done:
            print(f"natura: {stage} done ({total})", file=sys.stderr)
        self._done = done

    def close(self) -> None:
        """Closes the current bar (called when a stage changes and at the end)."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None


def reporter(progress: ProgressArg) -> Optional[Callback]:
    """The callable for the native module, or ``None`` for no reports.

    Raises ``TypeError`` naming ``progress`` if it is neither ``None``, a
    bool nor a callable."""
    if progress is None or progress is False:
        return None
    if progress is True:
        return Bars()
    if callable(progress):
        return progress
    raise TypeError(f"progress must be None, True or a callable, not {type(progress).__name__}")


def closing(cb: Optional[Callback]) -> None:
    """Closes the bars of a :class:`Bars` reporter after a call."""
    if isinstance(cb, Bars):
        cb.close()
