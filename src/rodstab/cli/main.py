"""The ``rodstab`` group and its entry point :func:`main`: exit statuses, one-line errors.

The commands live one group per module (:mod:`.paper`, :mod:`.design`, :mod:`.continuation`,
:mod:`.states`, :mod:`.multistable`, :mod:`.barrier`); each imports its solvers inside the
command, so ``rodstab --help`` and the closed-form commands start without scipy or pint.
"""

from __future__ import annotations

import sys
from typing import NoReturn

import click

from .. import __version__
from ..errors import NotConverged, RodstabInputError
from ..numerics import serial_blas
from . import barrier, continuation, design, diagram, hexagram, multistable, paper, states
from .output import SHOWN_WARNINGS, elapsed_indicator, warnings_as_lines

#: Exit statuses of the ``rodstab`` command (module docstring, ``rodstab --help``,
#: docs/guide/limits.md).
EXIT_OK = 0
EXIT_BAD_INPUT = 2
EXIT_NOT_CONVERGED = 3

#: Commands that draw their own progress bar (tqdm, with --no-progress).
_OWN_PROGRESS = {"continue", "sweep", "atlas", "reproduce", "diagram"}


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="rodstab")
@click.pass_context
def cli(ctx: click.Context) -> None:
    """Elastic stability of Kirchhoff rods and rings in circular or straight states.

    \b
    Exit status: 0 done; 2 invalid input (one line on stderr);
    3 not converged (one line on stderr; equilibrium, continue and sweep
    print their table or JSON first).
    """  # noqa: D301 - "\b" is click's no-rewrap marker (a backspace character), not a regex
    if ctx.invoked_subcommand and ctx.invoked_subcommand not in _OWN_PROGRESS:
        ctx.with_resource(elapsed_indicator(f"rodstab {ctx.invoked_subcommand}: working"))


# In the order of the one-file CLI (``rodstab --help`` sorts them by name).
for _command in (paper.section, paper.ring, paper.arc, paper.arc_max_length, paper.michell,
                 design.analyze, design.equilibrium_cmd, continuation.continue_cmd,
                 design.sweep, paper.birod, paper.folded_ring, states.states, hexagram.hexagram,
                 paper.reproduce, multistable.discover, multistable.transitions,
                 barrier.barrier, states.atlas_cmd, diagram.diagram):
    cli.add_command(_command)

#: Click >= 8.2 raises this usage error for ``rodstab`` without arguments; its message is the
#: full help, shown as click shows it (not squeezed onto one line).
_NoArgsIsHelpError: type[Exception] | None = getattr(click.exceptions, "NoArgsIsHelpError",
                                                     None)


def _fail(prefix: str, message: str, status: int) -> NoReturn:
    """Print ``rodstab: <prefix>: <message>`` as one stderr line and exit with ``status``."""
    click.echo(f"rodstab: {prefix}: {' '.join(message.split())}", err=True)
    sys.exit(status)


def main(argv: list[str] | None = None) -> None:
    """Entry point of the ``rodstab`` command: run it and exit with the documented status.

    ``RodstabInputError`` and click's usage errors: one stderr line, status 2 (EXIT_BAD_INPUT).
    ``NotConverged``: one stderr line, status 3 (EXIT_NOT_CONVERGED). Anything else is a bug
    and propagates with its traceback.
    """
    SHOWN_WARNINGS.clear()
    # One BLAS thread unless the user chose a count (rodstab.numerics.threads says why).
    try:
        with warnings_as_lines(), serial_blas():
            status = cli.main(args=argv, prog_name="rodstab", standalone_mode=False)
    except click.exceptions.Abort:
        click.echo("rodstab: aborted", err=True)
        sys.exit(130)
    except click.exceptions.ClickException as exc:
        if _NoArgsIsHelpError is not None and isinstance(exc, _NoArgsIsHelpError):
            exc.show()  # usage and the list of commands, as click shows them
            sys.exit(exc.exit_code)
        _fail("error", exc.format_message(), EXIT_BAD_INPUT)
    except RodstabInputError as exc:
        _fail("error", str(exc), EXIT_BAD_INPUT)
    except NotConverged as exc:
        _fail("not converged", str(exc), EXIT_NOT_CONVERGED)
    if isinstance(status, int) and status != EXIT_OK:  # click's Exit(status), e.g. from help
        sys.exit(status)
