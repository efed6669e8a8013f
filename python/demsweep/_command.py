"""The ``demsweep`` command of ``pip install .``: the wheel's console entry point runs the
command-line interface compiled into ``demsweep._native``, the same source as the ``demsweep``
binary of ``cargo install``."""

import sys

from . import _native


def main() -> None:
    """Runs ``demsweep`` with this process's arguments and exits with its status."""
    _native.main(sys.argv)
