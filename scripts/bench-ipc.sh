#!/bin/sh
# Setpoint latency kernel -> plc-sim over iceoryx2 (issue 6) beside a plain pipe wake-up
# between two processes (plc-sim/examples/wake_baseline.rs), in the same run. Both sides use
# the same timing: the sender SCHED_FIFO 80 on absolute 1 ms deadlines, the receiver
# SCHED_FIFO 79, memory locked, timer slack 1 ns, /dev/cpu_dma_latency 0. The latency is
# taken from the sender's clock reading just before the send to the receiver's right after
# it woke; "after the deadline" counts samples received after the end of their cycle.
# The VM's noise comes in bursts, so the two alternate in ROUNDS rounds of SECONDS/ROUNDS
# each and their histograms are summed. The kernel runs a zig-zag program at F3000 all along.
# Usage: scripts/bench-ipc.sh [SECONDS] [ROUNDS]   (root or CAP_SYS_NICE for SCHED_FIFO)
set -eu
secs=${1:-60}
rounds=${2:-6}
per=$((secs / rounds))
cd "$(dirname "$0")/.."
cargo build --release -q --bin softnc
cargo build --release -q -p plc-sim --example wake_baseline
exe=./target/release/softnc
tmp=$(mktemp -d)
inst="bench-$$"
cleanup() {
    [ -n "${nck:-}" ] && kill "$nck" 2>/dev/null || true
    [ -n "${plc:-}" ] && kill "$plc" 2>/dev/null || true
    wait 2>/dev/null || true
    $exe clean --instance "$inst" > /dev/null 2>&1 || true
    rm -rf "$tmp"
}
trap cleanup EXIT
# 100 mm legs at 50 mm/s: 2 s each, enough for a round.
legs=$((per / 2 + 2))
{
    echo "N1 G0 X0 Y0 Z0"
    echo "N2 G1 F3000"
    i=0
    while [ "$i" -lt "$legs" ]; do
        echo "X$(( (i % 2) == 0 ? 100 : 0 )) Y$((i % 7))"
        i=$((i + 1))
    done
    echo "M30"
} > "$tmp/zigzag.mpf"
echo "## machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "## ${rounds} rounds of ${per} s each: nc-kernel -> plc-sim over iceoryx2, then the pipe baseline"
i=1
while [ "$i" -le "$rounds" ]; do
    $exe plc-sim --instance "$inst" --priority 79 --histogram "$tmp/ice.$i" 2> "$tmp/plc.log.$i" &
    plc=$!
    $exe nc-kernel --instance "$inst" "$tmp/zigzag.mpf" --start --priority 80 2> "$tmp/nck.log.$i" &
    nck=$!
    sleep "$per"
    kill -TERM "$nck"
    wait "$nck" || true
    nck=""
    kill -TERM "$plc"
    wait "$plc" || true
    plc=""
    grep -h "alarm" "$tmp/nck.log.$i" "$tmp/plc.log.$i" || true
    $exe clean --instance "$inst" > /dev/null
    ./target/release/examples/wake_baseline --seconds "$per" --histogram "$tmp/pipe.$i" 2> "$tmp/pipe.log.$i"
    echo "round $i: $(awk -v name=iceoryx2 -f scripts/histogram-summary.awk "$tmp/ice.$i")"
    echo "round $i: $(awk -v name=pipe -f scripts/histogram-summary.awk "$tmp/pipe.$i")"
    i=$((i + 1))
done
grep -h "SCHED" "$tmp/nck.log.1" "$tmp/plc.log.1" "$tmp/pipe.log.1" | sed 's/^/## /'
grep -h "skipped\|terminating" "$tmp"/nck.log.* | sort | uniq -c | sed 's/^/## /' || true
echo "## sum over all rounds"
awk -v name=iceoryx2 -f scripts/histogram-summary.awk "$tmp"/ice.[0-9]*
awk -v name=pipe -f scripts/histogram-summary.awk "$tmp"/pipe.[0-9]*
