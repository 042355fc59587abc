#!/bin/bash
# Rows per second of two solar_position binaries on the same input, run
# alternately in the same session (so that both see the same machine load).
#
#   examples/solar_position_support/bench_rows.sh OLD_BINARY NEW_BINARY INPUT.csv [RUNS]
#
# For each of `--algorithm psa-2020` and `--algorithm spa` (`--float f64`):
# RUNS (default 3) runs of each binary, stdin from INPUT, stdout to a file
# in $TMPDIR; prints every run's wall and CPU seconds and the median rows
# per second, and checks that both binaries wrote the same bytes.
# The machine's load average is printed before and after: the figures are
# only comparable between binaries of the same invocation.
set -euo pipefail
old=$1 new=$2 input=$3 runs=${4:-3}
tmp=${TMPDIR:-/tmp}
rows=$(($(grep -c '' "$input") - 1))
echo "input $input: $rows data rows; $(nproc) cores; load $(cut -d' ' -f1-3 /proc/loadavg)"
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
for alg in psa-2020 spa; do
  for which in old new; do : > "$tmp/bench_$which.times"; done
  for ((i = 1; i <= runs; i++)); do
    for which in old new; do
      bin=$old; [ "$which" = new ] && bin=$new
      /usr/bin/time -f "%e %U %S" -o "$tmp/bench_time" \
        "$bin" --algorithm "$alg" --float f64 < "$input" > "$tmp/bench_$which.csv"
      read -r wall user sys < "$tmp/bench_time"
      echo "$wall" >> "$tmp/bench_$which.times"
      printf '  %-8s %-3s run %d: %6.2f s wall, %6.2f s CPU\n' "$alg" "$which" "$i" \
        "$wall" "$(echo "$user + $sys" | bc)"
    done
  done
  cmp -s "$tmp/bench_old.csv" "$tmp/bench_new.csv" && same=identical || same=DIFFERENT
  w_old=$(median < "$tmp/bench_old.times")
  w_new=$(median < "$tmp/bench_new.times")
  printf '%-8s old %9.0f rows/s  new %9.0f rows/s  speed-up %.2fx  (median of %d; output %s)\n' \
    "$alg" "$(echo "$rows / $w_old" | bc -l)" "$(echo "$rows / $w_new" | bc -l)" \
    "$(echo "$w_old / $w_new" | bc -l)" "$runs" "$same"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
