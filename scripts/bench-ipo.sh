#!/bin/sh
# IPO benchmarks (issue 5): compute time per cycle on the simulated clock, then the live
# clock's wake-up latency of nc-kernel beside cyclictest (Debian rt-tests) with the same
# scheduling (SCHED_FIFO 80, mlockall, 1000 µs interval, clock_nanosleep TIMER_ABSTIME,
# /dev/cpu_dma_latency 0). The VM's noise comes in bursts, so the two alternate in ROUNDS
# rounds of SECONDS/ROUNDS each and their histograms are summed: both see the same weather.
# Usage: scripts/bench-ipo.sh [SECONDS] [ROUNDS]   (root or CAP_SYS_NICE for SCHED_FIFO)
set -eu
secs=${1:-60}
rounds=${2:-6}
per=$((secs / rounds))
cd "$(dirname "$0")/.."
cargo build --release -q -p nc-runtime --bin nc-kernel --example ipo_timing
echo "## machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "## IPO compute time per cycle (simulated clock)"
./target/release/examples/ipo_timing
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "## live: ${rounds} rounds of ${per} s each, nc-kernel (ISG grinding cycle at F5) then cyclictest"
i=1
while [ "$i" -le "$rounds" ]; do
    ./target/release/nc-kernel programs/isg/grinding_cycle.nc --machine config/isg.toml \
        --seconds "$per" --histogram "$tmp/nc.$i" > "$tmp/nc.out.$i" 2>&1
    grep -E 'cycle work' "$tmp/nc.out.$i"
    cyclictest -m -p 80 -i 1000 -D "$per" -q -t 1 -h 30000 > "$tmp/ct.$i"
    i=$((i + 1))
done
head -1 "$tmp/nc.out.1"
awk -v name=nc-kernel -f scripts/histogram-summary.awk "$tmp"/nc.[0-9]*
awk -v name=cyclictest -f scripts/histogram-summary.awk "$tmp"/ct.[0-9]*
grep -h 'Max Latencies' "$tmp"/ct.* | sed 's/^/cyclictest per round: /'
