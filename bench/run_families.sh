#!/usr/bin/env bash
# Builds bench/families.c (the C reference of the bwbn and jiles_atherton
# kernels of `hysteron bench`) with and without -ffast-math into a
# temporary folder, and runs both.
# Usage: bash bench/run_families.sh [N] [REPS] [KERNEL]   (defaults 10000000 5, all;
#        KERNEL: only the rows whose label contains it, e.g. Bouc-Wen)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
N=${1:-10000000}; REPS=${2:-5}; ONLY=${3:-}
build="$(mktemp -d)"; trap 'rm -rf "$build"' EXIT
gcc -O3 -march=native             -Wall -Wextra -o "$build/families"      "$here/families.c" -lm
gcc -O3 -march=native -ffast-math -Wall -Wextra -o "$build/families_fast" "$here/families.c" -lm
"$build/families" "$N" "$REPS" "$ONLY"
echo
"$build/families_fast" "$N" "$REPS" "$ONLY"
