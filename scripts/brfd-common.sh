# What scripts/brfd.sh and scripts/brfd-floor.sh share, sourced from the
# repository root: the release build of the CLI (`$h`), the options of every
# fit (`common`) and score (`score`), and the records of the damper protocol:
# the 30 lb training pair, the other 30 lb records (validation), the two
# 36 lb records of the new-condition command, and the other 36 lb records. Each list
# holds `--data FILE` pairs, as hysteron takes them.
cargo build --release -q -p hysteron-cli
h=target/release/hysteron
common=(--output-column F --time-column t --skip 1 --no-progress)
score=(--output-column F --time-column t --skip 1 --lowpass 10)
d=data/brfd
train=(--data $d/ds3_sine_0.25Hz_30lb_1in.csv.gz --data $d/ds3_sine_1Hz_30lb_1.5in.csv.gz)
val30=()
for f in $d/ds3_*.csv.gz; do
  case $f in
    *0.25Hz_30lb_1in*|*1Hz_30lb_1.5in*) ;;
    *) val30+=(--data "$f") ;;
  esac
done
# The new-condition rule: of a condition's records, the two at its slowest
# frequency with the smallest and the largest amplitude (names
# *_sine_<f>Hz_*_<a>in.csv.gz). Prints them, one a line.
new_pair() {
  printf '%s\n' "$@" | sed -E 's/.*_sine_([0-9.]+)Hz_.*_([0-9.]+)in\.csv\.gz$/\1 \2 &/' |
    sort -g -k1,1 -k2,2 | awk 'NR == 1 { f = $1 } $1 == f { print $3 }' | sed -n '1p;$p'
}
mapfile -t pair36 < <(new_pair $d/ds2_*_36lb_*.csv.gz)
new=(--data "${pair36[0]}" --data "${pair36[1]}")
val36=()
for f in $d/ds2_*_36lb_*.csv.gz; do
  [ "$f" = "${pair36[0]}" ] || [ "$f" = "${pair36[1]}" ] || val36+=(--data "$f")
done
# The same records as `hysteron compare` takes them.
train_c=("${train[@]/#--data/--train}")
val30_c=("${val30[@]/#--data/--validate}")
