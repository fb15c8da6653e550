"""Build the API reference of exdex from its docstrings (HTML, with pdoc).

    python docs/build_api.py            # writes docs/api/index.html
    python docs/build_api.py OUT        # writes OUT/index.html

Needs pdoc (in the ``test`` extra: ``pip install -e ".[test]"``). Every
warning pdoc raises (a docstring it cannot parse, a broken reference) is
printed and makes the build fail, so the reference stays clean.
"""
import pathlib
import sys
import warnings

#: The documented modules: the package and its public submodules.
MODULES = ["exdex", "exdex.scene", "exdex.simulate", "exdex.stepper", "exdex.batch", "exdex.io", "exdex.animation", "exdex.explorer",
           "exdex.design", "exdex.design.tool", "exdex.design.plan", "exdex.design.sequence", "exdex.design.fit",
           "exdex.studies", "exdex.studies.paper", "exdex.studies.bench", "exdex.engines", "exdex.engines.pybullet",
           "exdex.engines.mujoco", "exdex.engines.drake", "exdex.engines.ablation"]


def build(out):
    import pdoc
    import pdoc.render

    out = pathlib.Path(out)
    pdoc.render.configure(docformat="numpy", footer_text="exdex", show_source=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # a submodule that ``exdex.__all__`` already brings in is listed again on purpose
        warnings.filterwarnings("ignore", message="The module specification .* has already been added")
        pdoc.pdoc(*MODULES, output_directory=out)
    return out, [str(w.message) for w in caught]


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    out = argv[0] if argv else pathlib.Path(__file__).resolve().parent / "api"
    out, problems = build(out)
    for p in problems:
        print(f"warning: {p}", file=sys.stderr)
    print(f"API reference: {out / 'index.html'} ({len(problems)} warnings)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
