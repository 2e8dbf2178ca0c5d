"""The ``selfalign`` command line (docs/reference/cli.md): ``selfalign --help``.

This module only checks that click is there and runs :mod:`selfalign.cli.commands`,
so that a missing click is one line, not an ImportError, and ``import selfalign``
never loads click.
"""

from __future__ import annotations

import logging
import sys

from ..solvers.jit import LOGGER as COMPILE_LOGGER


def _announce_compiles() -> None:
    """Print the compiled-code loader's announcement (a first run compiles for seconds) on stderr."""
    if not any(getattr(h, "name", "") == "selfalign-cli" for h in COMPILE_LOGGER.handlers):
        handler = logging.StreamHandler(sys.stderr)
        handler.name = "selfalign-cli"
        handler.setFormatter(logging.Formatter("selfalign: %(message)s"))
        COMPILE_LOGGER.addHandler(handler)
        COMPILE_LOGGER.setLevel(logging.INFO)


def main(argv: list[str] | None = None) -> None:
    """Run the command line on ``argv`` (default ``sys.argv[1:]``) and exit with its code.

    Exit codes: 0 success; 1 ``check`` found problems or ``simulate``'s run ended in status
    error; 2 bad usage or bad input (one line on stderr; ``--debug`` adds the traceback).
    """
    try:
        import click
    except ModuleNotFoundError as exc:
        if exc.name != "click":
            raise
        print("selfalign: the command line needs click; install it with pip install 'selfalign[cli]'",
              file=sys.stderr)
        sys.exit(2)
    from .commands import selfalign

    _announce_compiles()
    try:
        code = selfalign.main(sys.argv[1:] if argv is None else list(argv), prog_name="selfalign",
                              standalone_mode=False)
    except click.ClickException as exc:
        where = f"{exc.ctx.command_path}: " if getattr(exc, "ctx", None) else "selfalign: "
        print(f"{where}error: {' '.join(exc.format_message().split())}", file=sys.stderr)
        sys.exit(exc.exit_code)
    except click.Abort:
        print("selfalign: aborted", file=sys.stderr)
        sys.exit(1)
    sys.exit(code or 0)
