#!/bin/sh
# test_check_calls.sh -- check_calls.sh on made-up files: it must fail on a
# cycle through a global function and on one through a header's static
# inline function, and pass when the inline function lives in a header of
# its own that both files use (the way pose.h serves model.c and contact.c).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
d=${TMPDIR:-/tmp}/exdex_check_calls.$$
trap 'rm -rf "$d"' EXIT
cc=${CC:-cc}
expect() {   # expect STATUS DIR: check_calls.sh on DIR's objects exits with STATUS
    (cd "$1" && for c in *.c; do $cc -c "$c" -o "${c%.c}.o"; done)
    set +e
    SRCDIR="$1" sh "$here/check_calls.sh" "$1"/*.o > "$1/out.txt"
    st=$?
    set -e
    if [ "$st" -ne "$2" ]; then
        echo "check_calls.sh: expected status $2 on $1, got $st:"; cat "$1/out.txt"; exit 1
    fi
}
# a.c calls b_g (global); b.c calls a_pose, a static inline function of a.h: a cycle
mkdir -p "$d/inline"
printf 'static inline int a_pose(int x) { return x + 1; }\n' > "$d/inline/a.h"
printf '#include "a.h"\nint b_g(int);\nint a_f(int x) { return b_g(a_pose(x)); }\n' > "$d/inline/a.c"
printf '#include "a.h"\n/* a comment naming b_none(1) is no call */\nint b_g(int x) { return a_pose(x) * 2; }\n' > "$d/inline/b.c"
expect "$d/inline" 1
grep -q "call cycle: .*a -> b\|call cycle: .*b -> a" "$d/inline/out.txt"
# the same through globals only: a cycle
mkdir -p "$d/global"
printf 'int b_g(int);\nint a_f(int x) { return b_g(x); }\n' > "$d/global/a.c"
printf 'int a_f(int);\nint b_g(int x) { return x > 0 ? a_f(x - 1) : 0; }\n' > "$d/global/b.c"
expect "$d/global" 1
# the inline function in a header of its own (pose.h, no pose.c): one direction, no cycle
mkdir -p "$d/split"
printf 'static inline int pose_f(int x) { return x + 1; }\n' > "$d/split/pose.h"
printf '#include "pose.h"\nint b_g(int);\nint a_f(int x) { return b_g(pose_f(x)); }\n' > "$d/split/a.c"
printf '#include "pose.h"\nint b_g(int x) { return pose_f(x) * 2; }\n' > "$d/split/b.c"
expect "$d/split" 0
grep -q "b -> pose.h" "$d/split/out.txt"
echo "check_calls.sh: fails on a global and an inline cycle, passes on the split"
