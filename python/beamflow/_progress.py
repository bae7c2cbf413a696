"""Progress of long computations: a callback of the caller's, or bars (tqdm's when tqdm is
installed, else one line of text on standard error)."""

from __future__ import annotations

import sys
from typing import Any, Callable, Dict, Optional, Tuple, Union

__all__ = ["ProgressArg", "callback"]

Event = Dict[str, Any]
#: ``None``/``False``: nothing shown; ``True``: bars; a callable: called with each event, a
#: dict with ``task`` (e.g. ``"transient"``, ``"sweep"``), ``done``, ``total`` (None if
#: unknown), ``unit`` (``"periods"``, ``"cases"``, …) and ``message``.
ProgressArg = Union[None, bool, Callable[[Event], Any]]


class _Bars:
    """One bar per task, the finished ones closed as the next begins."""

    def __init__(self) -> None:
        self.task: Optional[str] = None
        self.bar: Any = None

    def __call__(self, e: Event) -> None:
        if e["task"] != self.task:
            self.close()
            self.task = e["task"]
            self.bar = self.open(e)
        self.show(e)

    def open(self, e: Event) -> Any:
        raise NotImplementedError

    def show(self, e: Event) -> None:
        raise NotImplementedError

    def close(self) -> None:
        self.task = None


class _Tqdm(_Bars):
    def __init__(self, tqdm: Any) -> None:
        super().__init__()
        self.tqdm = tqdm

    def open(self, e: Event) -> Any:
        return self.tqdm(total=e["total"], unit=f" {e['unit']}", desc=e["task"], leave=False)

    def show(self, e: Event) -> None:
        self.bar.n = e["done"]
        if e["message"]:
            self.bar.set_postfix_str(e["message"], refresh=False)
        self.bar.refresh()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None
        super().close()


class _Text(_Bars):
    def open(self, e: Event) -> Any:
        return sys.stderr

    def show(self, e: Event) -> None:
        total = f"/{e['total']}" if e["total"] is not None else ""
        note = f" ({e['message']})" if e["message"] else ""
        self.bar.write(f"\r{e['task']}: {e['done']}{total} {e['unit']}{note}\033[K")
        self.bar.flush()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.write("\n")
            self.bar = None
        super().close()


def callback(progress: ProgressArg) -> Tuple[Optional[Callable[[Event], Any]], Callable[[], None]]:
    """The callback to hand to the library for ``progress``, and what ends its display."""
    if progress is None or progress is False:
        return None, lambda: None
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            bars: _Bars = _Text()
        else:
            bars = _Tqdm(tqdm)
        return bars, bars.close
    if callable(progress):
        return progress, lambda: None
    raise TypeError(f"progress must be None, a bool or a callable, not {type(progress).__name__}")
