# What scripts/brfd.sh and scripts/brfd-floor.sh share, sourced from the
# repository root: the release build of the CLI (`$h`), the options of every
# fit (`common`) and score (`score`), and the records of the damper protocol:
# the 30 lb training pair, the other 30 lb records (validation), the 36 lb
# record of the new-condition command, and the other 36 lb records. Each list
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
new=$d/ds2_sine_0.5Hz_36lb_1in.csv.gz
val36=()
for f in $d/ds2_*_36lb_*.csv.gz; do
  [ "$f" = "$new" ] || val36+=(--data "$f")
done
