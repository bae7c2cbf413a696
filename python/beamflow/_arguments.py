"""Arguments of the functions that stand for the command line's commands: the library's
messages name the command line's flags (``--max-memory``), turned here into the Python
arguments (``max_memory``), and the checks the library leaves to its argument parser."""

from __future__ import annotations

import contextlib
import re
from typing import Any, Iterator, Mapping, Optional, Union

import numpy as np

from .errors import InputError

__all__ = ["Size", "as_arguments", "budget_text", "check_numbers"]

#: A budget: a size such as ``"8G"`` or a number of bytes; a count such as ``1e9``.
Size = Union[int, str]

_FLAG = re.compile(r"--([a-z][a-z0-9-]*)")


def _argument(flag: str) -> str:
    """The Python argument of a command-line flag: ``--max-memory`` → ``max_memory``."""
    return _FLAG.sub(lambda m: m.group(1).replace("-", "_"), flag)


@contextlib.contextmanager
def as_arguments() -> Iterator[None]:
    """Re-raises the library's input errors naming the Python arguments where they name
    the command line's flags."""
    try:
        yield
    except InputError as e:
        if e.file != "<cli>" and not _FLAG.search(e.field + e.reason):
            raise
        file = "<arguments>" if e.file == "<cli>" else e.file
        raise type(e)(file, _argument(e.field), _argument(e.reason)) from None


def budget_text(value: Optional[Size], name: str) -> Optional[str]:
    """A budget argument as the text the library parses."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise InputError("<arguments>", name, f"give a number or a text such as \"8G\", not {type(value).__name__}")
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    return str(value)


def check_numbers(whole: Optional[Mapping[str, Any]] = None, real: Optional[Mapping[str, Any]] = None) -> None:
    """Arguments of the wrong type, and whole numbers below zero (the library takes them
    unsigned), refused here naming the argument; the library checks their ranges."""
    for name, value in (whole or {}).items():
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise InputError("<arguments>", name, f"give a whole number, not {value!r}")
        if value < 0:
            raise InputError("<arguments>", name, f"{value} is negative: give a whole number from 0")
    for name, value in (real or {}).items():
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating))):
            raise InputError("<arguments>", name, f"give a number, not {value!r}")
