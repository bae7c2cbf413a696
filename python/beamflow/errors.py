"""Exceptions raised by beamflow.

Every error of the library arrives as one of these, with the fields of the message as
attributes, so a script can report or handle them precisely::

    try:
        case["actuator[0].x_e"] = 0.9
    except beamflow.InputError as e:
        print(e.file, e.field, e.reason)
"""

from __future__ import annotations

from typing import Any, Optional

__all__ = [
    "BeamflowError",
    "InputError",
    "FieldNotFound",
    "ParseError",
    "IoError",
    "Hdf5Error",
    "NumericalError",
    "ConvergenceWarning",
    "SweepInterrupted",
]


class BeamflowError(Exception):
    """Base class of every beamflow error."""


class InputError(BeamflowError, ValueError):
    """A value in an input (case, sweep, argument) is not acceptable.

    Attributes: ``file`` (the file or label the value came from), ``field`` (dotted path
    of the field, e.g. ``actuator[0].x_e``) and ``reason``.
    """

    def __init__(self, file: str, field: str, reason: str) -> None:
        super().__init__(f"{file}: field `{field}`: {reason}")
        self.file = file
        self.field = field
        self.reason = reason

    def __reduce__(self) -> Any:
        # Rebuilt from its fields (the default passes the message alone), so that it
        # crosses to and from other processes (multiprocessing, Dask workers) intact.
        return type(self), (self.file, self.field, self.reason)

    def __str__(self) -> str:
        return f"{self.file}: field `{self.field}`: {self.reason}"


class FieldNotFound(InputError, KeyError):
    """A dotted path names no field of the case (also a ``KeyError``)."""


class ParseError(BeamflowError, ValueError):
    """A file could not be parsed at all (syntax); ``message`` has the parser's location."""

    def __init__(self, file: str, message: str) -> None:
        super().__init__(f"{file}: {message}")
        self.file = file
        self.message = message

    def __reduce__(self) -> Any:
        return type(self), (self.file, self.message)


class IoError(BeamflowError, OSError):
    """Reading or writing a file failed (``path``, ``message``, ``errno``)."""

    def __init__(self, path: str, message: str, errno: Optional[int] = None) -> None:
        super().__init__(f"{path}: {message}")
        self.path = path
        self.message = message
        self.errno = errno
        self.filename = path

    def __reduce__(self) -> Any:
        return type(self), (self.path, self.message, self.errno)

    def __str__(self) -> str:
        return f"{self.path}: {self.message}"


class Hdf5Error(BeamflowError, OSError):
    """The HDF5 library reported an error (``path``, ``message``)."""

    def __init__(self, path: str, message: str) -> None:
        super().__init__(f"{path}: HDF5: {message}")
        self.path = path
        self.message = message
        self.filename = path

    def __reduce__(self) -> Any:
        return type(self), (self.path, self.message)

    def __str__(self) -> str:
        return f"{self.path}: HDF5: {self.message}"


class NumericalError(BeamflowError, ArithmeticError):
    """A solver met a situation it cannot handle (singular matrix, no convergence)."""

    def __init__(self, message: str) -> None:
        super().__init__(f"numerical failure: {message}")
        self.message = message

    def __reduce__(self) -> Any:
        return type(self), (self.message,)


class ConvergenceWarning(RuntimeWarning):
    """A result that did not reach the accuracy it was asked for: a transient that ran out
    of periods before its start-up transient died away (the command line prints "NOT
    settled"). Its numbers are those of the last period run, and may be far off (even of the
    wrong sign); the result says so too (:attr:`beamflow.Analysis.settled`)."""


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C stopped a sweep. ``table`` holds the cases finished before it (the ``case``
    column says which), in the form the sweep would have returned; ``total_cases`` is how
    many the whole sweep has."""

    def __init__(self, table: Any, done: int, total_cases: int) -> None:
        super().__init__(f"sweep interrupted with {done} of {total_cases} cases done (kept in the exception's `table`)")
        self.table = table
        self.total_cases = total_cases
