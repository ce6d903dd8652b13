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
cargo build --release -q -p nc-kernel --bin nc-kernel --example ipo_timing
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
summary() {
    awk -v name="$1" '!/^#/ && NF >= 2 { n[$1+0] += $2; tot += $2; if ($1+0 > max) max = $1+0 }
        END { c = 0; split("0.5 0.99 0.999", qs, " "); k = 1; line = sprintf("%-11s cycles %d:", name, tot);
              for (us = 0; us <= 30000 && k <= 3; us++) { c += n[us];
                  while (k <= 3 && c >= qs[k] * tot) { line = line sprintf(" p%s %d µs", qs[k]*100, us); k++ } }
              print line sprintf(" max %d µs", max) }'
}
cat "$tmp"/nc.[0-9]* | summary nc-kernel
cat "$tmp"/ct.[0-9]* | summary cyclictest
grep -h 'Max Latencies' "$tmp"/ct.* | sed 's/^/cyclictest per round: /'
