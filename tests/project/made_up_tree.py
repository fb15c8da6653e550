"""A made-up tree of files for the project checks to be run on first, so that
each check is known to fail (tests/project/test_twins.py,
tests/project/test_import_graph.py, tests/project/test_mirror.py)."""


def write_tree(root, files):
    """Write files ({path relative to root: text}) under root, making the folders."""
    for rel, text in files.items():
        p = root / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
