"""Command line of exdex: ``exdex <command> [options]``.

:mod:`exdex.cli.main` dispatches; each command is a module of this package
(``exdex.cli.paper``, ``.compare``, ``.hold``, ``.bench``, ``.tool``,
``.run``, ``.plan``) with ``add_arguments(parser)`` and ``run(args)``.
"""
from exdex.cli.main import COMMANDS, EXIT_MISSING_EXTRA, command_parser, main, require_engines

__all__ = ["main", "COMMANDS", "EXIT_MISSING_EXTRA", "command_parser", "require_engines"]
