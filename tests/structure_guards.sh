#!/bin/sh
# The house rules on the size of library code (src/ solvers/ fclib/ mpi/ under ROOT), as CTest
# guards. Each prints every offender, longest first, and exits 1 if there is one:
#   structure_guards.sh file-sizes ROOT [MAX]              no file over MAX lines (600)
#   structure_guards.sh function-lengths ROOT CTAGS [MAX]  no function over MAX lines (120)
# A function's length is Universal Ctags' end - line + 1 (from its name to its closing brace),
# lambdas left to the function around them: the measure the reviews use.
set -eu
what=$1
root=$2
cd "$root"

# The library's C and C++ sources, one a line.
library_files() {
    for dir in src solvers fclib mpi; do
        if [ -d "$dir" ]; then
            find "$dir" -type f \( -name '*.c' -o -name '*.cpp' -o -name '*.h' -o -name '*.hpp' \)
        fi
    done | LC_ALL=C sort
}

# Reads "length<TAB>what" lines; prints those over $1, longest first; fails if any.
report_over() {
    sort -t "$(printf '\t')" -k1,1nr | awk -F '\t' -v max="$1" -v rule="$2" '
        $1 > max { print $2 ": " $1 " lines (the rule: " rule ")"; ++over }
        END { if (over) { print over " over the rule"; exit 1 } }'
}

case "$what" in
file-sizes)
    max=${3:-600}
    library_files | while IFS= read -r f; do
        printf '%s\t%s\n' "$(wc -l < "$f")" "$f"
    done | report_over "$max" "no file over $max lines"
    ;;
function-lengths)
    ctags=$3
    max=${4:-120}
    if ! "$ctags" --version 2>/dev/null | grep -q 'Universal Ctags'; then
        echo "structure_guards.sh: '$ctags' is not Universal Ctags (Debian: universal-ctags)" >&2
        exit 2
    fi
    # Tag lines: name, file, line number, then fields such as "f", "line:N", "end:M". A ctags that
    # fails, or finds no function at all, fails the guard rather than pass it.
    tags=$(library_files | "$ctags" --kinds-C=f --kinds-C++=f --fields=+ne --extras=-q --excmd=number --sort=no -f - -L -)
    if [ -z "$tags" ]; then
        echo "structure_guards.sh: ctags found no function under $root" >&2
        exit 2
    fi
    printf '%s\n' "$tags" |
        awk -F '\t' '
            $1 ~ /^__anon/ { next }
            {
                line = 0; end = 0
                for (i = 4; i <= NF; ++i) {
                    if ($i ~ /^line:/) line = substr($i, 6) + 0
                    if ($i ~ /^end:/) end = substr($i, 5) + 0
                }
                if (line > 0 && end >= line) printf "%d\t%s:%d %s\n", end - line + 1, $2, line, $1
            }' |
        report_over "$max" "no function over $max lines"
    ;;
*)
    echo "usage: structure_guards.sh file-sizes ROOT [MAX] | function-lengths ROOT CTAGS [MAX]" >&2
    exit 2
    ;;
esac
