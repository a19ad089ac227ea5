#!/bin/sh
# The ABI of a library against its committed baseline (abi_check: libfrix.so and
# abi/libfrix.so.0.abi; abi_check_mpi: libfrix_mpi.so and abi/libfrix_mpi.so.0.abi).
#   abi_check.sh LIBRARY BASELINE SUPPRESSIONS OUT_DIR HEADER_DIR...
# Fails on any change a program built against the baseline could notice: a removed function
# (abidiff's ABI_INCOMPATIBLE_CHANGE bit) or a changed public type or enum value (its
# ABI_CHANGE bit, once the compatible changes are left out). Additions pass: new functions
# (--no-added-syms), enumerators appended to an enum (abidiff's own harmless-change filter).
# The plugin table, and through it every function signature, is checked by abi_plugin_table
# (tests/abi_table.c), because libabigail 2.2 cannot do either (abi/frix.suppr says why).
# The baselines are regenerated with `cmake --build BUILD --target abi-baseline` (libfrix) and
# `abi-baseline-mpi` (libfrix_mpi) (docs/abi.md).
set -u
lib=$1 baseline=$2 suppr=$3 out=$4
shift 4
hd=
for d in "$@"; do hd="$hd --headers-dir $d"; done
mkdir -p "$out"
# shellcheck disable=SC2086
abidw $hd --drop-private-types --exported-interfaces-only --type-id-style hash \
      --no-corpus-path --no-comp-dir-path --short-locs \
      --out-file "$out/current.abi" "$lib" || { echo "abidw failed on $lib"; exit 1; }
abidiff --no-added-syms --suppressions "$suppr" "$baseline" "$out/current.abi"
rc=$?
if [ $((rc & 3)) -ne 0 ]; then
    echo "abidiff could not compare (exit $rc)"
    exit 1
fi
if [ $((rc & 12)) -ne 0 ]; then
    echo "ABI check FAILED: the change above is incompatible with abi/${baseline##*/} (abidiff exit $rc)."
    echo "Undo it, or, if the break is intended (and the SONAME major raised), regenerate the"
    echo "baseline: cmake --build BUILD --target abi-baseline (abi-baseline-mpi for libfrix_mpi)"
    exit 1
fi
echo "ABI check passed: compatible with abi/${baseline##*/}"
