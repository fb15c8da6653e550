"""exdex.cli.dispatch: ``exdex <command>``: the version, every command's --help
(plain text, no reST markup) and --no-progress, and the one-line message and
exit status 3 of a command whose optional packages are missing (a fresh
interpreter whose import system refuses them)."""
import importlib
import os
import re
import subprocess
import sys

import pytest

import exdex
from exdex import cli
from optional_packages import run_without

RST = re.compile(r"``|:(func|class|meth|mod|attr|ref):`|\*\*\w|^\s*\.\. \w", re.M)


def _command_parser(name):
    mod = importlib.import_module(cli.COMMANDS[name][0])
    return cli.command_parser(name, mod)


def test_version(capsys):
    with pytest.raises(SystemExit) as info:
        cli.main(["--version"])
    assert info.value.code == 0
    assert capsys.readouterr().out.strip() == f"exdex {exdex.__version__}"


@pytest.mark.parametrize("name", list(cli.COMMANDS))
def test_every_command_takes_no_progress(name):
    parser = _command_parser(name)
    # a placeholder for each required positional argument (e.g. run's scene file)
    positional = ["x" for a in parser._actions if not a.option_strings and a.required]
    args = parser.parse_args(positional + ["--no-progress"])
    assert args.no_progress is True


@pytest.mark.parametrize("name", [None] + list(cli.COMMANDS))
def test_help_has_no_rst_markup(name, capsys):
    with pytest.raises(SystemExit):
        cli.main(["--help"] if name is None else [name, "--help"])
    text = capsys.readouterr().out
    assert "usage: exdex" in text
    assert not RST.search(text), RST.search(text).group(0)


@pytest.mark.parametrize("argv,blocked,extra", [
    (["paper", "--cases", "fig3"], ["matplotlib"], "plot"),
    (["tool", "--quick", "--no-progress"], ["matplotlib"], "plot"),
    (["bench", "--quick"], ["matplotlib", "tqdm"], "plot"),
    (["compare", "--cases", "fig3", "--no-plots"], ["pybullet"], "engines"),
    (["compare", "--cases", "fig3"], ["mujoco", "matplotlib"], "engines"),
])
def test_cli_missing_extra_is_one_line(argv, blocked, extra, tmp_path):
    """A command whose optional packages are missing prints one line naming
    them and the extra, and exits with status 3 (not a traceback)."""
    p = run_without("""
        import sys
        from exdex.cli import main
        sys.exit(main(sys.argv[1:]))
    """, blocked, *argv, "--out", str(tmp_path))
    assert p.returncode == 3, (p.returncode, p.stdout, p.stderr)
    lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, p.stderr
    assert f"exdex[{extra}]" in lines[0] and "Traceback" not in p.stderr
    for mod in blocked:
        assert mod in lines[0]
    assert os.listdir(tmp_path) == []  # nothing was computed before the check


@pytest.mark.parametrize("command", ["compare", "hold", "bench"])
def test_engine_commands_name_the_missing_extra(command, tmp_path):
    code = ("import sys; sys.modules['pydrake'] = None; from exdex.cli import main; "
            f"sys.exit(main([{command!r}, '--out', {str(tmp_path)!r}]))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode != 0
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, out.stderr
    assert "exdex[engines]" in lines[0] and "drake" in lines[0]
    assert "Traceback" not in out.stderr


def test_cli_dispatch(tmp_path):
    from exdex.cli import main
    assert main(["paper", "--out", str(tmp_path), "--cases", "fig3", "--no-progress"]) == 0
    assert (tmp_path / "fig3.csv").exists()
