#!/usr/bin/env bash
# How close can the device model's structure come to each record when it is
# allowed to cheat? A floor for the validation figures of scripts/brfd.sh.
#
# Only the validation records of scripts/brfd.sh are scored.
# - 30 lb: every free parameter of the device model (the same seven as
#   scripts/brfd.sh) fitted to each record by itself, from brfd.json, then
#   scored on that same record.
# - 36 lb: only the friction levels (f_pos, f_neg) fitted to each record by
#   itself, from brfd-36lb.json, then scored on that same record: what the
#   new-condition command would give if it could refit the levels on every
#   record instead of one.
#
# The same skip and score as scripts/brfd.sh. No figure of this script is a
# validation: each record is its own training set. Tables into out/brfd-floor/
# (or $1).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/brfd-floor}
mkdir -p "$out"
source scripts/brfd-common.sh

floor() { # floor START FREE CSV --data FILE ...
  local start=$1 free=$2 csv=$3
  shift 3
  : > "$csv"
  while [ $# -gt 0 ]; do
    local f=$2 b
    shift 2
    b=$(basename "$f" .csv.gz)
    $h fit --model "$start" --data "$f" "${common[@]}" --free "$free" \
      --max-seconds 120 --output "$out/$b.json" > "$out/$b.fit.txt" || [ $? -eq 3 ]
    $h validate --model "$out/$b.json" --data "$f" "${score[@]}" | grep '^| data/' >> "$csv"
  done
  echo "| record | samples | RMS | max \|err\| | NRMSE | low-passed NRMSE |"
  cat "$csv"
  awk -F'|' '{ n++; full += $6; low += $7 } END { printf "| mean of %d records | | | | %.4f | %.4f |\n", n, full / n, low / n }' "$csv"
}

echo "== 30 lb: all seven parameters fitted to each record by itself"
floor examples/specs/brfd.json f_pos,f_neg,gain.k,b,k1,k2,offset.c "$out/floor-30lb.csv" "${val30[@]}"
echo "== 36 lb: the friction levels fitted to each record by itself"
floor examples/specs/brfd-36lb.json f_pos,f_neg "$out/floor-36lb.csv" "${val36[@]}"
