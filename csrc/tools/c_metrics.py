"""c_metrics.py -- size and branching of C functions, and the numeric
thresholds a file spells out: for each file its lines and functions, then the
longest functions (lines, branch points, brace depth), the branch points per
100 lines, the numeric #defines and the numeric literals in code (beyond 0..4,
6, 9, 27 and 0.5: counts, state indices, halves).

A function is a top-level definition whose body closes with a "}" in column 0
(the core's style). Branch points: if, for, while, case, ?, &&, || outside
comments. Depth: the deepest brace nesting inside the body.

Usage: python3 csrc/tools/c_metrics.py [--rev REV] [--top N] FILE...
  --rev REV  read the files as they are at git revision REV (e.g. main)
"""
import argparse
import re
import subprocess
import sys

COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
HEAD = re.compile(r"^(static\s+)?(inline\s+)?(const\s+)?[a-zA-Z_][\w\s\*]*?\b(\w+)\s*\(")
BRANCH = re.compile(r"\b(if|for|while|case)\b|\?|&&|\|\|")
LITERAL = re.compile(r"(?<![\w.\[])(\d+\.\d*(?:e-?\d+)?|\d+e-?\d+|\d+)(?![\w\]\.])")
PLAIN = {"0", "1", "2", "3", "4", "6", "9", "27", "0.0", "1.0", "2.0", "3.0", "4.0", "5.0", "0.5"}
DEFINE = re.compile(r"^#define (\w+) +\(?-?[\d.]+(?:e[+-]?\d+)?\)? *(?:/\*.*)?$")


def functions(lines):
    """(name, first, last) 0-based line ranges of the top-level function definitions."""
    out, i, n = [], 0, len(lines)
    while i < n:
        line = lines[i]
        m = HEAD.match(line)
        if not m or line.startswith((" ", "#", "typedef")) or line.rstrip().endswith(";") or "=" in line.split("(")[0]:
            i += 1
            continue
        if "{" in line and line.rstrip().endswith("}"):
            out.append((m.group(4), i, i))
            i += 1
            continue
        j = i
        while j < n and not lines[j].rstrip().endswith(("{", ";")):
            j += 1
        if j >= n or lines[j].rstrip().endswith(";"):
            i = j + 1
            continue
        k = j + 1
        while k < n and lines[k] != "}":
            k += 1
        out.append((m.group(4), i, k))
        i = k + 1
    return out


def code(text):
    return COMMENT.sub(lambda m: "\n" * m.group(0).count("\n"), text)


def read(path, rev):
    if rev is None:
        with open(path) as f:
            return f.read()
    return subprocess.check_output(["git", "show", f"{rev}:{path}"], text=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rev")
    ap.add_argument("--top", type=int, default=8)
    ap.add_argument("files", nargs="+")
    a = ap.parse_args(argv)
    rows, total_lines, defines, literals = [], 0, [], 0
    for path in a.files:
        text = read(path, a.rev)
        lines, clean = text.split("\n"), code(text).split("\n")
        fs = functions(lines)
        print(f"{path:28s} {len(lines):5d} lines {len(fs):3d} functions")
        for name, s, e in fs:
            body = "\n".join(clean[s:e + 1])
            depth = deepest = 0
            for ch in body:
                if ch == "{":
                    depth += 1
                    deepest = max(deepest, depth)
                elif ch == "}":
                    depth -= 1
            rows.append((e - s + 1, len(BRANCH.findall(body)), deepest - 1, name, path))
            total_lines += e - s + 1
        for line in lines:
            m = DEFINE.match(line)
            if m:
                defines.append(m.group(1))
        for line in clean:
            if not line.startswith("#"):
                literals += sum(1 for m in LITERAL.finditer(line) if m.group(1) not in PLAIN)
    rows.sort(reverse=True)
    branches = sum(r[1] for r in rows)
    print(f"functions: {len(rows)}, lines in functions: {total_lines}, branch points: {branches} "
          f"({100.0 * branches / max(total_lines, 1):.1f} per 100 lines)")
    for r in rows[:a.top]:
        print(f"  {r[3]:28s} {r[0]:4d} lines {r[1]:4d} branch points, depth {r[2]} ({r[4]})")
    print(f"numeric #defines: {len(defines)} ({' '.join(defines)})")
    print(f"numeric literals in code beyond 0..4, 6, 9, 27, 0.5: {literals}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
