"""Command line of exdex: ``exdex <command> [options]``.

Each command lives in its own module and exposes ``add_arguments(parser)`` and
``run(args)``; this file only dispatches, importing a command's module when it
is used so that e.g. ``exdex tool`` never imports the physics engines.
"""
import argparse
import importlib
import sys

# command -> (module, one-line help)
COMMANDS = {
    "paper": ("exdex.paper", "reproduce the paper's case studies (Figs. 3, 4, 6) into a folder"),
    "compare": ("exdex.engines", "cross-check the paper cases against pybullet, MuJoCo and Drake"),
    "hold": ("exdex.hold", "hold benchmark: drift of a held object in exdex and the engines' settings"),
    "bench": ("exdex.bench", "work-precision charts and stability maps of the integration methods"),
    "tool": ("exdex.tool", "assistive-tool design: twist-cone volumes and tool-angle optimisation"),
    "run": ("exdex.cli_run", "simulate a scene file (TOML or JSON): CSV, NPZ, a figure, an animation"),
    "plan": ("exdex.plan", "plan the motion or grip for a target slip or turn; band under uncertainty; poses CSV"),
}


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = argparse.ArgumentParser(prog="exdex", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", metavar="command")
    for name, (_, helptext) in COMMANDS.items():
        sub.add_parser(name, help=helptext, add_help=False)
    if not argv or argv[0] not in COMMANDS:
        parser.parse_args(argv)  # prints usage / errors on unknown commands
        parser.print_help()
        return 2
    name = argv[0]
    modname, helptext = COMMANDS[name]
    mod = importlib.import_module(modname)
    cmd = argparse.ArgumentParser(prog=f"exdex {name}", description=helptext)
    mod.add_arguments(cmd)
    args = cmd.parse_args(argv[1:])
    return mod.run(args) or 0


if __name__ == "__main__":
    sys.exit(main())
