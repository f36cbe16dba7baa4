#!/usr/bin/env bash
# Builds bench/families.c (the C reference of the bwbn and jiles_atherton
# kernels of `hysteron bench`) with and without -ffast-math into a
# temporary folder, and runs both.
# Usage: bash bench/run_families.sh [N] [REPS]     (defaults 10000000 5)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
N=${1:-10000000}; REPS=${2:-5}
build="$(mktemp -d)"; trap 'rm -rf "$build"' EXIT
gcc -O3 -march=native             -Wall -Wextra -o "$build/families"      "$here/families.c" -lm
gcc -O3 -march=native -ffast-math -Wall -Wextra -o "$build/families_fast" "$here/families.c" -lm
"$build/families" "$N" "$REPS"
echo
"$build/families_fast" "$N" "$REPS"
