#!/usr/bin/env bash
# Regenerates the table of docs/benchmarks.md: times the kernels of
# `hysteron bench` and, with --reference DIR, the same kernels in C (DIR
# holds the C reference's run_limits.sh, kept outside this repository; the
# bwbn and jiles_atherton kernels' C reference is this repository's
# bench/families.c, run by bench/run_families.sh), the two interleaved:
# reference, hysteron, reference, hysteron, ...
# Prints one markdown table: each kernel's ns/sample (the median of --runs
# timed runs per invocation, as a range over the invocations), the C
# reference's (the faster of its two builds, -O3 and -O3 -ffast-math), and
# the ratio hysteron / C, each invocation against the reference run just
# before it; then the paper model's ratios and the CPU.
#
# Usage: bash scripts/bench.sh [--runs R] [--samples N] [--rounds K]
#                              [--reference DIR] [--bin PATH] [--keep DIR]
#   --runs R       timed runs per kernel and invocation (default 5)
#   --samples N    samples per run (default 10000000)
#   --rounds K     invocations of each side (default 3)
#   --reference D  also run D/run_limits.sh, interleaved
#   --bin PATH     time this hysteron binary instead of `cargo run --release`
#                  (a build made earlier, or an older commit's to compare)
#   --keep DIR     keep the raw outputs in DIR (default: a temporary folder,
#                  removed at the end)
#   --from DIR     measure nothing: print the table of the raw outputs that
#                  an earlier run kept in DIR
# Needs bash, python3 (standard library only) and, for the reference, gcc.
set -euo pipefail
cd "$(dirname "$0")/.."

runs=5 samples=10000000 rounds=3 reference="" bin="" keep="" from=""
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --samples) samples="$2"; shift 2 ;;
        --rounds) rounds="$2"; shift 2 ;;
        --reference) reference="$2"; shift 2 ;;
        --bin) bin="$2"; shift 2 ;;
        --keep) keep="$2"; shift 2 ;;
        --from) from="$2"; shift 2 ;;
        -h|--help) sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "bench.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
done
for n in "$runs" "$samples" "$rounds"; do
    case "$n" in ''|*[!0-9]*) echo "bench.sh: '$n' is not a positive integer" >&2; exit 2 ;; esac
done
if [ -n "$reference" ] && [ ! -f "$reference/run_limits.sh" ]; then
    echo "bench.sh: $reference/run_limits.sh not found" >&2; exit 2
fi

if [ -n "$from" ]; then
    # the settings of that run, as it recorded them
    out="$from"
    read -r runs samples rounds hysteron_shown reference <"$out/settings.txt"
    [ "$reference" = "-" ] && reference=""
elif [ -n "$keep" ]; then
    out="$keep"; mkdir -p "$out"
else
    out="$(mktemp -d)"; trap 'rm -rf "$out"' EXIT
fi

if [ -z "$from" ]; then
    if [ -n "$bin" ]; then
        hysteron=("$bin")
        hysteron_shown="$bin"
    else
        hysteron=(cargo run --release -q --)
        hysteron_shown="cargo-run"
    fi
    rm -f "$out/load.txt" "$out/cpu.txt"
    echo "$runs $samples $rounds $hysteron_shown ${reference:--}" >"$out/settings.txt"
    for i in $(seq 1 "$rounds"); do
        if [ -n "$reference" ]; then
            echo "round $i/$rounds: C reference (load $(cut -d' ' -f1-3 /proc/loadavg))" >&2
            cut -d' ' -f1 /proc/loadavg >>"$out/load.txt"
            bash "$reference/run_limits.sh" "$samples" "$runs" >"$out/c-$i.txt"
            bash bench/run_families.sh "$samples" "$runs" >>"$out/c-$i.txt"
        fi
        echo "round $i/$rounds: hysteron bench (load $(cut -d' ' -f1-3 /proc/loadavg))" >&2
        cut -d' ' -f1 /proc/loadavg >>"$out/load.txt"
        "${hysteron[@]}" bench --runs "$runs" --samples "$samples" >"$out/h-$i.txt"
    done
    if [ -n "$keep" ]; then echo "raw outputs in $out" >&2; fi
fi

python3 - "$out" "$rounds" "$runs" "$samples" "$hysteron_shown" "${reference:+yes}" <<'PY'
import datetime, pathlib, re, sys

out, rounds, runs, samples, shown, with_ref = sys.argv[1:7]
out, rounds = pathlib.Path(out), int(rounds)
if shown == "cargo-run":
    shown = "cargo run --release --"

def hysteron_rows(text):
    """kernel -> median ns/sample of one `hysteron bench` invocation."""
    rows = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 6 and cells[0] == "hysteron":
            rows[cells[1]] = float(cells[4])
    return rows

C_ROW = re.compile(r"^(\S.*?)\s+([0-9.]+)\s+([0-9.]+)\s+(-?[0-9.]+e[-+][0-9]+)(\s+[0-9.]+)+\s*$")

def c_rows(text):
    """(kernel, build) -> ns/sample of one run of the C reference."""
    rows, build = {}, None
    for line in text.splitlines():
        if line.startswith(("limits.c", "families.c")):
            build = "-ffast-math" if "-ffast-math" in line else "-O3"
            continue
        m = C_ROW.match(line)
        if m and build:
            rows[(m.group(1).strip(), build)] = float(m.group(3))
    return rows

# hysteron's kernel, its C counterparts (the fastest of these, over both
# builds unless the builds are named)
PAIRS = [
    ("play", "play, r = 0.5", ["play r=0.5"]),
    ("pi_bank 64", "PI bank, 64 plays", ["PI-64 naive loop", "PI-64 8-lane (vectorised)"]),
    ("bouc_wen n=1", "Bouc-Wen n = 1 (exact)", ["Bouc-Wen n=1 exact (exp)"]),
    ("bouc_wen n=1.5", "Bouc-Wen n = 1.5", ["Bouc-Wen n=1.5 Euler (sqrt)"]),
    ("bouc_wen n=1.5", "the same, against C's general `pow`", ["Bouc-Wen n=1.5 Euler (pow)"]),
    ("mms", "MMS, F_c = 1, K = 5", ["MMS 1 element (exp)"]),
    # -ffast-math drops the checks for non-finite values that the adaptive
    # integrator rejects a sub-step by: only the -O3 build is the same step
    ("bwbn", "BWBN (adaptive Dormand–Prince)", ["BWBN (DP5)"], ["-O3"]),
    ("jiles_atherton", "Jiles-Atherton (adaptive Dormand–Prince)", ["Jiles-Atherton (DP5)"], ["-O3"]),
]
ONLY_H = [
    ("paper model", "paper model (bedstop + spring)"),
    ("paper model, boxed from JSON", "paper model, boxed from JSON"),
    ("paper model batch x64, 1 thread(s)", "paper model, 64 records, 1 thread"),
    ("paper model batch x64, 2 thread(s)", "paper model, 64 records, 2 threads"),
]

H = [hysteron_rows((out / f"h-{i}.txt").read_text()) for i in range(1, rounds + 1)]
C = [c_rows((out / f"c-{i}.txt").read_text()) for i in range(1, rounds + 1)] if with_ref else []

def rng(values, digits):
    lo, hi = min(values), max(values)
    a, b = f"{lo:.{digits}f}", f"{hi:.{digits}f}"
    return a if a == b else f"{a}–{b}"

def spread(values):
    return f"{100 * (max(values) / min(values) - 1):.1f} %" if len(values) > 1 else "—"

def fastest_c(c, names, builds=("-O3", "-ffast-math")):
    best = min(((v, k) for k, v in c.items() if k[0] in names and k[1] in builds), default=None)
    return best

print(f"hysteron: `{shown} bench --runs {runs} --samples {samples}`, {rounds} invocation(s)"
      + (f", interleaved with the C reference (`run_limits.sh {samples} {runs}`)" if with_ref else ""))
print()
if with_ref:
    print("| kernel | hysteron ns/sample | spread | C reference ns/sample | C loop, faster build | hysteron / C |")
    print("|---|---:|---:|---:|---|---:|")
else:
    print("| kernel | hysteron ns/sample | spread |")
    print("|---|---:|---:|")
for key, label, names, *only in PAIRS:
    h = [r[key] for r in H]
    if not with_ref:
        print(f"| {label} | {rng(h, 2)} | {spread(h)} |")
        continue
    best = [fastest_c(c, names, *only) for c in C]
    cns = [b[0] for b in best]
    builds = {}
    for b in best:
        builds.setdefault(b[1][0], set()).add(b[1][1])
    which = [f"`{n}` ({', '.join(sorted(v))})" for n, v in sorted(builds.items())]
    ratio = [hv / cv for hv, cv in zip(h, cns)]
    print(f"| {label} | {rng(h, 2)} | {spread(h)} | {rng(cns, 2)} | {'; '.join(which)} | {rng(ratio, 2)}× |")
for key, label in ONLY_H:
    h = [r[key] for r in H]
    print(f"| {label} | {rng(h, 2)} | {spread(h)} |" + (" — | — | — |" if with_ref else ""))
if with_ref:
    floor = [min(v for k, v in c.items() if k[0].startswith("stream floor")) for c in C]
    print(f"| stream floor (read, scale, write), C only | — | — | {rng(floor, 2)} | `stream floor` | — |")
print()
paper = [r["paper model"] / (r["bouc_wen n=1"] + r["mms"]) for r in H]
boxed = [r["paper model, boxed from JSON"] / r["paper model"] for r in H]
threads = [r["paper model batch x64, 1 thread(s)"] / r["paper model batch x64, 2 thread(s)"] for r in H]
print(f"- paper model / (Bouc-Wen n = 1 + MMS), same invocation: {rng(paper, 2)}×")
print(f"- paper model boxed from JSON / static, same invocation: {rng(boxed, 2)}×")
print(f"- 64 records, 2 threads / 1 thread (throughput): {rng(threads, 2)}×")

def cpu_line():
    """The CPU and the date, as the table's caption gives them."""
    info = {}
    for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
        k, _, v = line.partition(":")
        info.setdefault(k.strip(), v.strip())
    fam, model = int(info.get("cpu family", "0")), int(info.get("model", "0"))
    flags = info.get("flags", "").split()
    zen = {26: "Zen 5", 23: "Zen / Zen 2"}.get(fam)
    if fam == 25:
        zen = "Zen 4" if (0x10 <= model <= 0x1F or 0x60 <= model <= 0x7F or 0xA0 <= model <= 0xAF) else "Zen 3"
    if info.get("vendor_id") != "AuthenticAMD":
        zen = None
    isa = "AVX-512" if "avx512f" in flags else ("AVX2, no AVX-512" if "avx2" in flags else "no AVX2")
    cpus = sum(1 for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines() if line.startswith("processor"))
    return (f"{cpus}-vCPU {info.get('model name', '?')}, family {fam} model {model}"
            + (f" ({zen})" if zen else "") + f", {isa}; {datetime.date.today().isoformat()}")

cpu_file = out / "cpu.txt"
if not cpu_file.exists():
    cpu_file.write_text(cpu_line() + "\n")
load = (out / "load.txt").read_text().split()
print()
print(f"1-minute load average before each invocation: {', '.join(load)}")
print(f"CPU: {cpu_file.read_text().strip()}")
PY
