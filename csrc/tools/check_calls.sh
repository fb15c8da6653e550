#!/bin/sh
# check_calls.sh OBJ... -- the call graph between the core's files has no
# cycle: no file calls back into a file that (directly or through others)
# calls it. Edges come from nm: file A -> file B when A references a global
# symbol that B defines; and from the sources: A -> B when A.c calls a
# static inline function of B.h (a header's inline functions belong to the
# file of its name, or to the header alone when no .c file has its name or
# it is the private header of a family of files, listed in SHARED). Prints
# the edges and exits 1 on a cycle (naming it).
# Usage: tools/check_calls.sh build/*.o   (SRCDIR: the sources, default .)
set -eu
src=${SRCDIR:-.}
# hybrid.h: the private header of hybrid.c and hybrid_*.c, whose inline helpers all of them share
SHARED=${SHARED:-hybrid.h}
tmp=${TMPDIR:-/tmp}/exdex_calls.$$
trap 'rm -f "$tmp".def "$tmp".use "$tmp".inl' EXIT
: > "$tmp.def"
: > "$tmp.use"
: > "$tmp.inl"
for o in "$@"; do
    f=$(basename "$o" .o)
    nm -g "$o" | awk -v f="$f" '$2 ~ /^[TDRBC]$/ { print $3, f }' >> "$tmp.def"
    nm -g -u "$o" | awk -v f="$f" '{ print f, $NF }' >> "$tmp.use"
done
# the headers' static inline functions and their owners
for h in "$src"/*.h; do
    [ -f "$h" ] || continue
    b=$(basename "$h")
    u=${b%.h}
    case " $SHARED " in *" $b "*) u=$b ;; esac
    [ -f "$src/$u.c" ] || u=$b
    sed -n 's/^static inline[^(]*[ *]\([A-Za-z_][A-Za-z0-9_]*\)(.*/\1/p' "$h" | awk -v u="$u" '{ print $1, u }' >> "$tmp.inl"
done
cat "$tmp.inl" >> "$tmp.def"
# the calls of each object's source (comments removed) to those functions
for o in "$@"; do
    f=$(basename "$o" .o)
    [ -f "$src/$f.c" ] || continue
    ${CC:-cc} -fpreprocessed -dD -E -P "$src/$f.c" 2>/dev/null |
        grep -o '[A-Za-z_][A-Za-z0-9_]*[[:space:]]*(' | sed 's/[[:space:]]*($//' | sort -u |
        awk -v f="$f" 'NR == FNR { inl[$1] = 1; next } ($1 in inl) { print f, $1 }' "$tmp.inl" - >> "$tmp.use"
done
awk '
    NR == FNR { owner[$1] = $2; next }
    ($2 in owner) && owner[$2] != $1 { e = $1 " " owner[$2]; if (!(e in seen)) { seen[e] = 1; edges[n++] = e } }
    END {
        for (i = 0; i < n; i++) {
            split(edges[i], p, " ")
            adj[p[1]] = adj[p[1]] " " p[2]
            node[p[1]] = 1; node[p[2]] = 1
            print "  " p[1] " -> " p[2]
        }
        # depth-first search with colours: 1 on the stack, 2 done
        bad = 0
        for (v in node) if (!(v in col)) bad += dfs(v, v)
        if (bad) exit 1
        print "no call cycle between " length(node) " files"
    }
    function dfs(v, path,    k, m, w, ws, r) {
        col[v] = 1
        r = 0
        m = split(adj[v], ws, " ")
        for (k = 1; k <= m; k++) {
            w = ws[k]
            if (!(w in col)) r += dfs(w, path " -> " w)
            else if (col[w] == 1) { print "call cycle: " path " -> " w; r = 1 }
        }
        col[v] = 2
        return r
    }
' "$tmp.def" "$tmp.use"
