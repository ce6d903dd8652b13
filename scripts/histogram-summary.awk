# Sums histograms in cyclictest's format ("<µs> <count>" lines; "# samples|lost|late N"
# comment lines as plc-sim and wake_baseline write them) and prints one line:
# count, p50, p99, p99.9, max, and lost/late when the inputs give them.
# Usage: awk -v name=NAME -f scripts/histogram-summary.awk FILE...
/^# (samples|lost|late) / { extra[$2] += $3; seen[$2] = 1; next }
!/^#/ && NF >= 2 { n[$1 + 0] += $2; tot += $2; if ($1 + 0 > max) max = $1 + 0 }
END {
    c = 0; split("0.5 0.99 0.999", qs, " "); k = 1
    line = sprintf("%-11s cycles %d:", name, tot)
    for (us = 0; us <= max && k <= 3; us++) {
        c += n[us]
        while (k <= 3 && c >= qs[k] * tot) { line = line sprintf(" p%s %d µs", qs[k] * 100, us); k++ }
    }
    line = line sprintf(" max %d µs", max)
    if (seen["lost"]) line = line sprintf("; lost %d", extra["lost"])
    if (seen["late"]) line = line sprintf(", after the deadline %d (%.4f %%)", extra["late"], tot ? 100 * extra["late"] / tot : 0)
    print line
}
