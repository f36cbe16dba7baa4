#!/usr/bin/env bash
# The measured friction damper with backlash (data/brfd, README there):
# the device model composed from the algebra, identified on two 30 lb
# records, validated without refitting on the other eight; the structures of
# examples/compare/brfd.json ranked by one `hysteron compare` call under the
# same protocol; and the new-condition command (36 lb: refit only the
# friction levels on two records of the new condition, chosen by the rule in
# scripts/brfd-common.sh, and validate on the other eight). Writes
# examples/specs/brfd.json and brfd-36lb.json, and tables and figures into
# out/brfd/ (or $1).
#
# Protocol: every fit and every score leaves out the first second of each
# record (--skip 1: the model starts at rest, the records mid-stroke or
# preloaded); figures are NRMSE = RMS(model - measured) / RMS(measured) over
# the rest, full band and after a zero-phase 4th-order Butterworth low-pass
# at 10 Hz (the stick-slip chatter no rate-independent model follows).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/brfd}
mkdir -p "$out"
source scripts/brfd-common.sh

echo "== the device model: fit on ${train[*]}"
$h fit --model examples/specs/brfd/start.json "${train[@]}" "${common[@]}" \
  --free f_pos,f_neg,gain.k,b,k1,k2,offset.c --max-seconds 600 \
  --output examples/specs/brfd.json --plot "$out/fit.svg"
echo "== validated on the other 30 lb records"
$h validate --model examples/specs/brfd.json "${val30[@]}" "${score[@]}" \
  --csv "$out/validate-30lb.csv" --plot "$out/30lb"

echo "== every structure of examples/compare/brfd.json, ranked on the other 30 lb records"
$h compare --candidates examples/compare/brfd.json "${train_c[@]}" "${val30_c[@]}" "${score[@]}" \
  --max-seconds 600 --no-progress --work-dir "$out/compare" --csv "$out/compare.csv" --plot "$out/compare.svg"

echo "== new condition (36 lb): refit the friction levels on ${pair36[*]}"
$h fit --model examples/specs/brfd.json "${new[@]}" "${common[@]}" \
  --free f_pos,f_neg --output examples/specs/brfd-36lb.json
$h validate --model examples/specs/brfd-36lb.json "${val36[@]}" "${score[@]}" \
  --csv "$out/validate-36lb.csv"
