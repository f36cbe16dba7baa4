#!/usr/bin/env bash
# The measured friction damper with backlash (data/brfd, README there):
# the device model composed from the algebra, identified on two 30 lb
# records, validated without refitting on the other eight; the new-condition
# command (36 lb: refit only the friction levels on one record, validate on
# the other nine); and four single-element baselines under the same
# protocol. Writes examples/specs/brfd.json and brfd-36lb.json, and tables
# and figures into out/brfd/ (or $1).
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

echo "== new condition (36 lb): refit the friction levels on $new"
$h fit --model examples/specs/brfd.json --data "$new" "${common[@]}" \
  --free f_pos,f_neg --output examples/specs/brfd-36lb.json
$h validate --model examples/specs/brfd-36lb.json "${val36[@]}" "${score[@]}" \
  --csv "$out/validate-36lb.csv"

for m in dahl lugre maxwell-slip bouc-wen; do
  case $m in
    dahl) free=sigma,dahl.f_c,alpha,offset.c ;;
    lugre) free=sigma0,sigma1,sigma2,lugre.f_c,f_s,v_s,offset.c ;;
    maxwell-slip) free="k[0],k[1],k[2],k[3],f_b[0],f_b[1],f_b[2],f_b[3],offset.c" ;;
    bouc-wen) free=w,beta,gamma,n,stiffness.s[0],offset.c ;;
  esac
  echo "== baseline $m"
  $h fit --model examples/specs/brfd/baseline-$m.json "${train[@]}" "${common[@]}" \
    --free "$free" --max-seconds 600 --output "$out/baseline-$m.json" || [ $? -eq 3 ]
  $h validate --model "$out/baseline-$m.json" "${val30[@]}" "${score[@]}" \
    --csv "$out/baseline-$m-30lb.csv"
done
