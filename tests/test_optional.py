"""``import exdex`` needs only NumPy; the optional parts say which extra to install.

Each test runs a fresh interpreter whose import system refuses the optional
packages (a meta-path finder raising ModuleNotFoundError, as a missing
package does), so the installed matplotlib/tqdm/pybullet/mujoco cannot leak in.
"""
import json

from optional_packages import run_without

OPTIONAL = ["matplotlib", "tqdm", "pybullet", "mujoco", "scipy", "pandas", "dask"]


def test_import_exdex_needs_only_numpy():
    """With every optional package blocked, ``import exdex`` works, imports
    none of them, and a simulation runs."""
    p = run_without("""
        import json, sys, time
        t0 = time.perf_counter()
        import exdex
        dt = time.perf_counter() - t0
        sc = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=2.0))
        r = exdex.simulate(sc, 0.01, 1e-3)
        mods = sorted(m for m in sys.modules if m.split(".")[0] in BLOCKED)
        print(json.dumps(dict(mods=mods, n=len(r.t), seconds=dt)))
    """, OPTIONAL)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout.strip().splitlines()[-1])
    assert out["mods"] == [] and out["n"] == 11


def test_library_and_command_modules_import_with_only_numpy():
    """The benchmark libraries and every command's module import without the
    optional packages (they are imported by the call that needs them); a
    figure asked of them names the plot extra, an engine run the engines extra."""
    p = run_without("""
        import importlib, json, sys
        from exdex import cli
        mods = ["exdex.studies.bench", "exdex.studies.hold", "exdex.engines"] + sorted({m for m, _, _ in cli.COMMANDS.values()})
        for m in mods:
            importlib.import_module(m)
        loaded = sorted(m for m in sys.modules if m.split(".")[0] in BLOCKED)
        msgs = []
        import exdex.studies.bench, exdex.engines, exdex.studies.hold
        for call in (lambda: exdex.studies.hold.plot({}, "unused.png", 1.0),
                     lambda: exdex.studies.bench.plot_maps([], "fig3", "unused.png", "", {}),
                     lambda: exdex.engines.run_drake(exdex.paper.fig3_scene(), 0.01)):
            try:
                call()
            except ImportError as exc:
                msgs.append(str(exc))
        print(json.dumps(dict(mods=mods, loaded=loaded, msgs=msgs)))
    """, OPTIONAL + ["pydrake"])
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout.strip().splitlines()[-1])
    assert out["loaded"] == [] and len(out["mods"]) >= 9
    assert len(out["msgs"]) == 3
    assert all("exdex[plot]" in m and "matplotlib" in m for m in out["msgs"][:2])
    assert "exdex[engines]" in out["msgs"][2] and "pydrake" in out["msgs"][2]


def test_plot_without_matplotlib_names_the_extra():
    p = run_without("""
        import exdex
        sc = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=2.0))
        r = exdex.simulate(sc, 0.01, 1e-3)
        try:
            r.plot()
        except ImportError as exc:
            assert isinstance(exc, exdex.MissingExtraError), type(exc)
            print("MSG", exc)
        else:
            print("NO ERROR")
    """, ["matplotlib", "tqdm"])
    assert p.returncode == 0, p.stderr
    assert "MSG" in p.stdout and "exdex[plot]" in p.stdout and "matplotlib" in p.stdout


def test_animate_and_tool_figures_without_matplotlib():
    p = run_without("""
        import exdex
        sc = exdex.Scene(body=exdex.Body.box(0.1, (0.02, 0.04, 0.02)), grasp=exdex.Grasp(mu=0.5, grip_force=2.0))
        r = exdex.simulate(sc, 0.01, 1e-3)
        for name, call in (("animate", lambda: r.animate()),
                           ("tool", lambda: exdex.tool.figure_theta_curves([]))):
            try:
                call()
            except ImportError as exc:
                print(name, "MSG", exc)
    """, ["matplotlib", "tqdm"])
    assert p.returncode == 0, p.stderr
    lines = [ln for ln in p.stdout.splitlines() if "MSG" in ln]
    assert len(lines) == 2 and all("exdex[plot]" in ln and "matplotlib" in ln for ln in lines), p.stdout


def test_sweep_progress_without_tqdm():
    """sweep's default bar appears only when tqdm is installed; asking for it
    without tqdm names the extra."""
    p = run_without("""
        import exdex
        sc = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=2.0))
        s = exdex.sweep(sc, {"mu": [0.3, 0.5]}, t_end=0.01, dt=1e-3)
        print("DEFAULT", len(s))
        try:
            exdex.sweep(sc, {"mu": [0.3, 0.5]}, t_end=0.01, dt=1e-3, progress=True)
        except ImportError as exc:
            print("MSG", exc)
    """, ["tqdm"])
    assert p.returncode == 0, p.stderr
    assert "DEFAULT 2" in p.stdout
    assert "MSG" in p.stdout and "exdex[plot]" in p.stdout and "tqdm" in p.stdout


def test_scipy_features_name_the_design_extra():
    """SciPy is not needed by ``import exdex``; the three features that use its least squares (identify,
    pose sequences, plans of several parameters) raise MissingExtraError naming ``exdex[design]``."""
    p = run_without("""
        import exdex
        sc = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=2.0),
                         motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1)))
        calls = {
            "identify": lambda: exdex.identify(sc, [0.1, 0.2], [0.0, 0.0], {"mu": (0.3, 0.7)}),
            "sequence": lambda: exdex.sequence.solve(exdex.replace(sc, dof="planar"), {"x": 0.01}),
            "plan": lambda: exdex.plan.solve(sc, {"slip": -0.01, "rotation": 0.0},
                                             vary={"grip_force": (1.0, 3.0), "mu": (0.3, 0.7)}),
        }
        for name, call in calls.items():
            try:
                call()
            except exdex.MissingExtraError as exc:
                print(name, "MSG", exc)
            except Exception as exc:
                print(name, "OTHER", type(exc).__name__, exc)
    """, ["scipy"])
    assert p.returncode == 0, p.stderr
    lines = [ln for ln in p.stdout.splitlines() if ln.split()[0] in ("identify", "sequence", "plan")]
    assert len(lines) == 3 and all(" MSG " in ln and "scipy" in ln and "exdex[design]" in ln for ln in lines), p.stdout


def test_explorer_without_ipywidgets_names_the_explore_extra():
    p = run_without("""
        import exdex
        try:
            exdex.explore(exdex.paper.fig3_scene())
        except exdex.MissingExtraError as exc:
            print("MSG", exc)
    """, ["ipywidgets"])
    assert p.returncode == 0, p.stderr
    assert "MSG" in p.stdout and "exdex[explore]" in p.stdout and "ipywidgets" in p.stdout
