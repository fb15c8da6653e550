"""Command line of exdex: ``exdex <command> [options]``.

:mod:`exdex.cli.dispatch` dispatches; each command is a module of this package
(``exdex.cli.paper``, ``.compare``, ``.hold``, ``.bench``, ``.tool``,
``.run``, ``.plan``) with ``add_arguments(parser)`` and ``run(args)``.
"""
from exdex.cli.dispatch import COMMANDS, EXIT_MISSING_EXTRA, command_parser, main, require_engines

__all__ = ["main", "COMMANDS", "EXIT_MISSING_EXTRA", "command_parser", "require_engines"]
