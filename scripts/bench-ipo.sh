#!/bin/sh
# IPO benchmarks (issue 5): compute time per cycle on the simulated clock, then the live
# clock's wake-up latency of nc-kernel beside cyclictest (Debian rt-tests) with the same
# scheduling (SCHED_FIFO 80, mlockall, 1000 µs interval, clock_nanosleep TIMER_ABSTIME,
# /dev/cpu_dma_latency 0), each for SECONDS, one after the other in the same run.
# Usage: scripts/bench-ipo.sh [SECONDS]   (needs root or CAP_SYS_NICE for SCHED_FIFO)
set -eu
secs=${1:-60}
cd "$(dirname "$0")/.."
cargo build --release -q -p nc-kernel --bin nc-kernel --example ipo_timing
echo "## machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "## IPO compute time per cycle (simulated clock)"
./target/release/examples/ipo_timing
echo "## nc-kernel live, ${secs} s (ISG grinding cycle: F5, never ends within the run)"
./target/release/nc-kernel programs/isg/grinding_cycle.nc --machine config/isg.toml --seconds "$secs" 2>&1
echo "## cyclictest, ${secs} s, same scheduling"
hist=$(mktemp)
cyclictest -m -p 80 -i 1000 -D "$secs" -q -t 1 -h 20000 > "$hist"
grep -E '^# (Min|Avg|Max) Latencies|^# Histogram Overflows' "$hist"
awk '!/^#/ && NF >= 2 { n[$1+0] = $2; tot += $2 }
     END { c = 0; split("0.5 0.99 0.999", qs, " "); k = 1;
           for (us = 0; us <= 20000 && k <= 3; us++) { c += n[us];
             while (k <= 3 && c >= qs[k] * tot) { printf "cyclictest p%s %d us\n", qs[k]*100, us; k++ } } }' "$hist"
rm -f "$hist"
