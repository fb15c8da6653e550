"""Build the documentation site: the API reference and the executed notebooks as HTML pages.

    python docs/build.py                   # writes docs/site/index.html
    python docs/build.py OUT               # writes OUT/index.html
    python docs/build.py OUT --notebooks tutorial_1_first_scene fig3_inertial   # a subset

The site is ``index.html`` (links to everything), ``api/`` (pdoc, from the
docstrings: docs/build_api.py) and ``notebooks/<name>.html``: each notebook in
notebooks/ executed from top to bottom in a fresh kernel (working folder
notebooks/, the repository on PYTHONPATH, matplotlib's Agg backend) and
converted with nbconvert, outputs and figures included. Links between
notebooks (``other.ipynb``) point to their pages.

The build fails (exit status 1, each problem printed) when a notebook cell
raises, pdoc warns, or a page links to a file the site does not have (a
broken relative link or a missing page). Needs the ``docs`` extra (pdoc,
nbconvert, nbclient, ipykernel): ``pip install -e ".[docs]"``; .ci/setup.sh
installs it.
"""
import argparse
import html
import json
import os
import pathlib
import re
import sys
import urllib.parse

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
NOTEBOOKS = ROOT / "notebooks"

#: the index's sections: notebook names by the start of their file name
SECTIONS = [("Tutorials", ("tutorial_",)), ("The paper's cases", ("fig",)), ("More notebooks", ("",))]


def notebook_title(nb, fallback):
    """The first markdown heading of a notebook (nbformat node), or ``fallback``."""
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            m = re.search(r"^#+\s+(.+)$", cell.source, re.M)
            if m:
                return m.group(1).strip()
    return fallback


def execute(path, timeout=600):
    """The notebook at ``path`` executed in a fresh python3 kernel (an nbformat node); a cell that
    raises raises nbclient's CellExecutionError."""
    import nbclient
    import nbformat

    env = {"PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])),
           "MPLBACKEND": "Agg"}
    old = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    try:
        nb = nbformat.read(str(path), as_version=4)
        nbclient.NotebookClient(nb, timeout=timeout, kernel_name="python3",
                                resources={"metadata": {"path": str(path.parent)}}).execute()
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    return nb


def _relink(nb, names):
    """Links to other notebooks of the site (``x.ipynb``) point to their pages (``x.html``)."""
    pattern = re.compile(r"(\]\(|href=\")(?:\./)?([A-Za-z0-9_\-]+)\.ipynb(#[^)\"]*)?(?=[)\"])")
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            cell.source = pattern.sub(lambda m: f"{m.group(1)}{m.group(2)}.html{m.group(3) or ''}"
                                      if m.group(2) in names else m.group(0), cell.source)


def notebook_page(nb, out_path):
    """Write the executed notebook ``nb`` as a standalone HTML page (figures embedded)."""
    import nbconvert

    body, _ = nbconvert.HTMLExporter(template_name="lab").from_notebook_node(nb)
    out_path.write_text(body, encoding="utf-8")


def index_page(out, pages, api=True):
    """``out/index.html``: the API reference and the notebook pages by section; ``pages`` maps a
    notebook name to its title."""
    items, left = [], dict(pages)
    for head, prefixes in SECTIONS:
        names = [n for n in sorted(left) if n.startswith(prefixes)]
        if not names:
            continue
        links = "".join(f'<li><a href="notebooks/{n}.html">{html.escape(left.pop(n))}</a></li>' for n in names)
        items.append(f"<h2>{html.escape(head)}</h2><ul>{links}</ul>")
    text = ("<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>exdex documentation</title></head>"
            "<body><h1>exdex documentation</h1>"
            "<p>In-hand manipulation by extrinsic dexterity, simulated exactly and fast.</p>" + ("<h2>Reference</h2><ul><li><a href=\"api/index.html\">API reference</a> "
                                "(from the docstrings)</li></ul>" if api else "") + "".join(items) + "</body></html>")
    (out / "index.html").write_text(text, encoding="utf-8")


_LINK = re.compile(r"""(?:href|src)\s*=\s*["']([^"']*)["']""", re.I)


def broken_links(out):
    """Relative links (href, src) of the site's HTML pages whose target file is missing:
    ``[(page, link)]``. Absolute URLs, data: URIs and in-page anchors are not checked."""
    out = pathlib.Path(out)
    bad = []
    for page in sorted(out.rglob("*.html")):
        # scripts hold templates (pdoc's search: href="${url}"), not links
        text = re.sub(r"<script\b.*?</script>", "", page.read_text(encoding="utf-8", errors="replace"),
                      flags=re.S | re.I)
        for link in _LINK.findall(text):
            link = html.unescape(link.strip())
            parts = urllib.parse.urlsplit(link)
            if not link or parts.scheme or parts.netloc or link.startswith("#"):
                continue
            target = (page.parent / urllib.parse.unquote(parts.path)).resolve()
            if parts.path.endswith("/"):
                target = target / "index.html"
            try:
                target.relative_to(out.resolve())
            except ValueError:
                bad.append((str(page.relative_to(out)), link))
                continue
            if not target.exists():
                bad.append((str(page.relative_to(out)), link))
    return bad


def build(out, notebooks=None, api=True):
    """Build the site into ``out``; ``notebooks``: names (file stems) of a subset, default all.
    Returns the list of problems (empty: the site is complete)."""
    out = pathlib.Path(out)
    (out / "notebooks").mkdir(parents=True, exist_ok=True)
    problems = []
    if api:
        sys.path.insert(0, str(HERE))
        import build_api

        _, warns = build_api.build(out / "api")
        problems += [f"API reference: {w}" for w in warns]
    paths = sorted(NOTEBOOKS.glob("*.ipynb"))
    if notebooks:
        known = {p.stem: p for p in paths}
        unknown = [n for n in notebooks if n not in known]
        if unknown:
            raise SystemExit(f"docs/build.py: no notebook named {', '.join(unknown)} in notebooks/ "
                             f"(there are: {', '.join(sorted(known))})")
        paths = [known[n] for n in notebooks]
    names = {p.stem for p in paths}
    pages = {}
    for path in paths:
        import nbclient.exceptions

        print(f"executing {path.name}", flush=True)
        try:
            nb = execute(path)
        except nbclient.exceptions.CellExecutionError as exc:
            problems.append(f"{path.name}: a cell raised: {str(exc).splitlines()[-1] if str(exc) else exc!r}")
            continue
        _relink(nb, names)
        notebook_page(nb, out / "notebooks" / f"{path.stem}.html")
        pages[path.stem] = notebook_title(nb, path.stem)
    index_page(out, pages, api)
    (out / "pages.json").write_text(json.dumps(pages, indent=1), encoding="utf-8")
    problems += [f"{page}: broken link {link!r}" for page, link in broken_links(out)]
    return problems


def main(argv=None):
    ap = argparse.ArgumentParser(prog="docs/build.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("out", nargs="?", default=str(HERE / "site"), help="output folder (default docs/site)")
    ap.add_argument("--notebooks", nargs="+", default=None, help="build only these notebooks (file stems)")
    ap.add_argument("--no-api", action="store_true", help="leave out the API reference")
    args = ap.parse_args(argv)
    problems = build(args.out, args.notebooks, api=not args.no_api)
    for p in problems:
        print(f"error: {p}", file=sys.stderr)
    print(f"documentation site: {pathlib.Path(args.out) / 'index.html'} ({len(problems)} problems)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
