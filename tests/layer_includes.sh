#!/bin/sh
# The layers' include rules, one mode a test (run from the repository root given as $2):
#   core    src/ and fclib/ include no solver header, by any path (their include path has no
#           solvers/ either);
#   mpi     mpi/ includes from solvers/ only the kit (solvers/kit/);
#   solvers a solver family (solvers/<family>/) includes from solvers/ only the kit, the entries'
#           declarations and its own folder; the kit only itself.
# Prints every include that breaks the rule; fails if there is one.
mode=$1
cd "$2" || exit 2
bad=0
report() { echo "$1: $2"; bad=1; }
case $mode in
core)
    for h in $(find solvers -name '*.hpp'); do
        name=$(basename "$h")
        grep -rnE "#include [<\"]([^>\"]*/)?$name[>\"]" src fclib && bad=1
    done ;;
mpi)
    grep -rnE '#include "solvers/' mpi | grep -v '#include "solvers/kit/' && bad=1 ;;
solvers)
    for f in $(find solvers -mindepth 2 -name '*.[ch]pp'); do
        family=$(echo "$f" | cut -d/ -f2)
        for inc in $(grep -oE '#include "solvers/[^"]+"' "$f" | sed 's/#include "//; s/"$//'); do
            case $inc in
            solvers/kit/*) ;;
            solvers/entries.hpp) [ "$family" = kit ] && report "$f" "$inc" ;;
            solvers/$family/*) ;;
            *) report "$f" "$inc" ;;
            esac
        done
    done ;;
*) echo "unknown mode $mode"; exit 2 ;;
esac
exit $bad
