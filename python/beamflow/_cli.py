"""The ``beamflow`` command installed with the package: the command line's own main."""

from __future__ import annotations

import signal
import sys
from typing import List, Optional

from . import _native

__all__ = ["main"]


def main(argv: Optional[List[str]] = None) -> None:
    """Runs ``beamflow`` with ``argv`` (default: the process's arguments) and exits with its
    status, as the binary does."""
    args = sys.argv[1:] if argv is None else argv
    # Ctrl-C ends the command as it ends the binary (Python's handler would only run after
    # the command returns).
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    sys.stdout.flush()
    sys.exit(_native.cli_main(["beamflow", *args]))
