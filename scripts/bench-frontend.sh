#!/usr/bin/env bash
# Whole-process comparison for docs/benchmarks.md: `softnc parse` vs LinuxCNC's `rs274 -g`
# on the same generated 1 M-block line/arc program, same machine, same run.
# Needs Debian's linuxcnc-uspace (rs274). Usage: scripts/bench-frontend.sh [BLOCKS] [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
blocks=${1:-1000000}
runs=${2:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cargo build --release -q --bin softnc -p softnc
cargo run --release -q -p nc-kernel --example gen_program -- "$blocks" > "$work/prog.ngc"
command -v rs274 >/dev/null || { echo "rs274 not found: apt-get install linuxcnc-uspace" >&2; exit 1; }

median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
measure() { # label, command...
  local label=$1; shift
  local times=()
  for _ in $(seq "$runs"); do
    local t0 t1
    t0=$(date +%s.%N)
    "$@" > /dev/null 2>&1
    t1=$(date +%s.%N)
    times+=("$(echo "$t1 - $t0" | bc -l)")
  done
  local med
  med=$(printf '%s\n' "${times[@]}" | median)
  printf '%-28s median %.3f s over %d runs (%s)  %.2f M blocks/s\n' "$label" "$med" "$runs" \
    "$(printf '%s ' "${times[@]}" | sed 's/ $//')" "$(echo "$blocks / $med / 1000000" | bc -l)"
}
echo "program: $blocks blocks, $(wc -c < "$work/prog.ngc") bytes; $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
measure "softnc parse (JSON Lines)" ./target/release/softnc parse "$work/prog.ngc"
measure "rs274 -g" rs274 -g "$work/prog.ngc"
