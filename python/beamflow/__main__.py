"""``python -m beamflow``: the ``beamflow`` command."""

from ._cli import main

if __name__ == "__main__":
    main()
