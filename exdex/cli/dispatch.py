"""Command line of exdex: exdex <command> [options].

Each command lives in its own module of exdex.cli and exposes ``add_arguments(parser)`` and
``run(args)``; this file only dispatches, importing a command's module when it
is used so that e.g. ``exdex tool`` never imports the physics engines. Every
command takes ``--no-progress``; a command whose optional dependencies are
missing says in one line which extra installs them and exits with status 3.
"""
import argparse
import importlib
import sys
import warnings

from exdex._optional import EXTRAS, MissingExtraError, available

#: exit status of a command whose optional dependencies are missing
EXIT_MISSING_EXTRA = 3

#: commands that reproduce fixed studies (scenes chosen to probe limits):
#: their PhysicsWarnings are expected and not printed
FIXED_STUDIES = {"paper", "compare", "hold", "bench", "tool"}


def _needs_paper(args):
    return ["matplotlib"] + ([] if args.no_progress else ["tqdm"])


ENGINES = ["pybullet", "mujoco", "pydrake"]


def _needs_compare(args):
    return ENGINES + (["matplotlib"] if getattr(args, "plots", True) else [])


def _needs_hold(args):
    return ENGINES + ["matplotlib"]


def _needs_bench(args):
    return ["matplotlib"] + ([] if args.no_progress else ["tqdm"]) + (ENGINES if getattr(args, "engines", True) else [])


def _needs_run(args):
    return []   # the figure and animation need the plot extra; cli_run says so when they are asked for


def _needs_tool(args):
    return ["matplotlib"] + ([] if args.no_progress else ["tqdm"])


# command -> (module, one-line help, optional modules it needs for given args)
COMMANDS = {
    "paper": ("exdex.cli.paper", "reproduce the paper's case studies (Figs. 3, 4, 6) into a folder", _needs_paper),
    "compare": ("exdex.cli.compare", "cross-check the paper cases against pybullet, MuJoCo and Drake", _needs_compare),
    "hold": ("exdex.cli.hold", "hold benchmark: drift of a held object in exdex and the engines' settings", _needs_hold),
    "bench": ("exdex.cli.bench", "work-precision charts and stability maps of the integration methods", _needs_bench),
    "tool": ("exdex.cli.tool", "assistive-tool design: twist-cone volumes and tool-angle optimisation", _needs_tool),
    "run": ("exdex.cli.run", "simulate a scene file (TOML or JSON): CSV, NPZ, a figure, an animation", _needs_run),
    "plan": ("exdex.cli.plan", "plan the motion or grip for a target slip or turn; band under uncertainty; poses CSV",
             _needs_run),
}


def require_engines(command):
    """One line on stderr naming the extra and return 2 if an engine is missing, else None."""
    from exdex.engines import missing_engines

    missing = missing_engines()
    if missing:
        print(f"exdex {command} needs the engines extra ({', '.join(missing)} not installed): "
              f"pip install 'exdex[engines]'", file=sys.stderr)
        return 2
    return None


def _version():
    from exdex import __version__

    return __version__


def _missing_message(name, modules):
    """One line: which packages are missing and the extra(s) that install them."""
    extras = sorted({EXTRAS.get(m, m) for m in modules})
    pkgs = ", ".join(modules)
    install = " ".join(f"'exdex[{e}]'" for e in extras)
    return f"exdex {name}: needs {pkgs}, not installed: pip install {install}"


def command_parser(name, mod):
    """The argparse parser of command ``name`` (its module ``mod`` adds the
    options); every command gets ``--no-progress``."""
    cmd = argparse.ArgumentParser(prog=f"exdex {name}", description=COMMANDS[name][1])
    mod.add_arguments(cmd)
    if not any("--no-progress" in a.option_strings for a in cmd._actions):
        cmd.add_argument("--no-progress", action="store_true", help="hide progress bars")
    return cmd


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = argparse.ArgumentParser(prog="exdex", description="exdex: in-hand manipulation by extrinsic "
                                     "dexterity. Run 'exdex <command> --help' for a command's options.")
    parser.add_argument("--version", action="version", version=f"exdex {_version()}")
    sub = parser.add_subparsers(dest="command", metavar="command")
    for name, (_, helptext, _) in COMMANDS.items():
        sub.add_parser(name, help=helptext, add_help=False)
    if not argv or argv[0] not in COMMANDS:
        parser.parse_args(argv)  # --help, --version, or usage / errors on unknown commands
        parser.print_help()
        return 2
    name = argv[0]
    modname, helptext, needs = COMMANDS[name]
    try:
        mod = importlib.import_module(modname)
    except MissingExtraError as exc:
        print(_missing_message(name, [exc.module]), file=sys.stderr)
        return EXIT_MISSING_EXTRA
    args = command_parser(name, mod).parse_args(argv[1:])
    missing = [m for m in needs(args) if not available(m)]
    if missing:
        print(_missing_message(name, missing), file=sys.stderr)
        return EXIT_MISSING_EXTRA
    try:
        with warnings.catch_warnings():
            if name in FIXED_STUDIES:
                from exdex.diagnostics import PhysicsWarning

                warnings.simplefilter("ignore", PhysicsWarning)
            return mod.run(args) or 0
    except MissingExtraError as exc:
        print(_missing_message(name, [exc.module]), file=sys.stderr)
        return EXIT_MISSING_EXTRA
    except ModuleNotFoundError as exc:
        top = (exc.name or "").split(".")[0]
        if top not in EXTRAS:
            raise
        print(_missing_message(name, [top]), file=sys.stderr)
        return EXIT_MISSING_EXTRA


if __name__ == "__main__":
    sys.exit(main())
