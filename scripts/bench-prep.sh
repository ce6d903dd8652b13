#!/usr/bin/env bash
# Whole-process comparison for docs/benchmarks.md: `softnc check` and `softnc path -o
# /dev/null` beside LinuxCNC's `rs274 -g`, on the same generated G41 contour
# (nc_kernel::synthetic), same machine, same run. SHAPE: g41 (the tangent serpentine),
# roughing (roughing rows, a corner at every block) or bars (a row of bars, 90° corners).
# The two files differ only in the header: softnc selects with `G41` and D1 (radius 10),
# rs274 with `G41.1 D20` (a diameter there).
# Needs Debian's linuxcnc-uspace (rs274). Usage: scripts/bench-prep.sh [BLOCKS] [RUNS] [SHAPE]
# With BEFORE=path/to/an/older/softnc, its `softnc check` runs in the same rounds (a before
# and after table on a noisy machine).
set -euo pipefail
cd "$(dirname "$0")/.."
blocks=${1:-200000}
runs=${2:-7}
shape=${3:-g41}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cargo build --release -q --bin softnc -p softnc
cargo build --release -q -p nc-kernel --example gen_program
./target/release/examples/gen_program "$blocks" "--$shape" > "$work/prog.mpf"
./target/release/examples/gen_program "$blocks" "--$shape" --rs274 > "$work/prog.ngc"
command -v rs274 >/dev/null || { echo "rs274 not found: apt-get install linuxcnc-uspace" >&2; exit 1; }

# The contours run far beyond the default machine's travel: software limits out of the way.
travel="--md axes.X.software_limits=[-1e9,1e9] --md axes.Y.software_limits=[-1e9,1e9]"
# Each must succeed on the whole program: a run that stops early would be fast for nothing.
./target/release/softnc check "$work/prog.mpf" $travel
rs274 -g "$work/prog.ngc" > "$work/rs274.out" 2>&1
grep -q "G41.1\|ENABLE_CUTTER\|STRAIGHT_FEED" "$work/rs274.out" || { echo "rs274 failed:"; tail "$work/rs274.out"; exit 1; }
echo "rs274: $(grep -c -E 'STRAIGHT_FEED|ARC_FEED' "$work/rs274.out") moves; softnc: $(./target/release/softnc path "$work/prog.mpf" $travel | wc -l) segments"

median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
# softnc with the shipped machine data (whole-program check, window 64), with the window
# alone, and with no check at all.
only="--md trc.whole_program_check=false $travel"
off="--md trc.whole_program_check=false --md trc.bottleneck_window=0 $travel"
labels=("softnc check" "softnc path -o /dev/null" "softnc check, window 64 only" "softnc check, no check" "rs274 -g")
cmds=("./target/release/softnc check $work/prog.mpf $travel"
      "./target/release/softnc path $work/prog.mpf -o /dev/null $travel"
      "./target/release/softnc check $work/prog.mpf $only"
      "./target/release/softnc check $work/prog.mpf $off"
      "rs274 -g $work/prog.ngc")
if [ -n "${BEFORE:-}" ]; then
  [ -x "$BEFORE" ] || { echo "BEFORE=$BEFORE is not an executable" >&2; exit 1; }
  labels+=("softnc check (BEFORE)")
  cmds+=("$BEFORE check $work/prog.mpf $travel")
fi
declare -A times
echo "program: $shape, $blocks contour blocks, $(wc -c < "$work/prog.mpf") bytes; $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); load $(cut -d' ' -f1-3 /proc/loadavg)"
# Interleaved rounds, so that a noisy neighbour hits all three alike.
for _ in $(seq "$runs"); do
  for i in "${!cmds[@]}"; do
    t0=$(date +%s.%N)
    ${cmds[$i]} > /dev/null 2>&1
    t1=$(date +%s.%N)
    times[$i]+="$(echo "$t1 - $t0" | bc -l) "
  done
done
declare -A med
for i in "${!cmds[@]}"; do
  med[$i]=$(printf '%s\n' ${times[$i]} | median)
  printf '%-28s median %.3f s over %d runs (%s)  %.2f M blocks/s\n' "${labels[$i]}" "${med[$i]}" "$runs" \
    "$(printf '%.3f ' ${times[$i]} | sed 's/ $//')" "$(echo "$blocks / ${med[$i]} / 1000000" | bc -l)"
done
for i in "${!cmds[@]}"; do
  [ "$i" -eq 4 ] && continue
  printf 'ratio: %-26s %.1fx faster than rs274 -g\n' "${labels[$i]}" "$(echo "${med[4]} / ${med[$i]}" | bc -l)"
done
# Memory: the whole-program check keeps the longest compensation run.
if [ -x /usr/bin/time ]; then
  for i in 0 3; do
    /usr/bin/time -f '%M' -o "$work/rss" ${cmds[$i]} > /dev/null 2>&1
    kb=$(tail -1 "$work/rss")
    printf 'max RSS: %-26s %s KB\n' "${labels[$i]}" "$kb"
  done
fi
