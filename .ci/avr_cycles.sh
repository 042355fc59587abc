#!/usr/bin/env bash
# Speed of the sun-position algorithms on the 8-bit part, cycle
# exact: builds the avr_bench image (release, f32, sun_algos' avr-libc-math
# feature: avr-libc's assembler trigonometry and float routines), runs it in simavr at
# 16 MHz and checks the budgets. Also runs the Cortex-M bench in QEMU with
# `-icount shift=0` and checks its instructions per position.
#
#   bash .ci/avr_cycles.sh                 # ATmega328P (the budgeted part)
#   AVR_BENCH_CHIP=atmega2560 bash .ci/avr_cycles.sh
#   SAVE_DIR=dir bash .ci/avr_cycles.sh    # also keep both bench outputs there
#   SELF_TEST=1 bash .ci/avr_cycles.sh     # the parser must reject doctored outputs
#   SELF_TEST=1 AVR_BENCH_OUT=f QEMU_BENCH_OUT=g bash .ci/avr_cycles.sh
#                                          # ... doctored copies of captured outputs
#
# Method (see boards/avr/src/bin/avr_bench.rs): Timer1 free-running at clk/1, overflow
# interrupt extends it to 32 bits; empty-measurement overhead subtracted.
# The day table is Jimoh & Aliyu's (2019) step 7: the set-points from sunrise to
# sunset (Kano, 2026-06-21); the whole 24-hour sweep of 360 positions is
# printed beside it for reference.
#
# Every algorithm of the table below must appear exactly once in each kind
# of bench line (position, day_table, daylight_table) with every field a
# number; an algorithm line that is missing, repeated, garbled or of an
# algorithm not in the table fails the script, so a rename cannot skip a
# budget. Exits non-zero over budget.
set -euo pipefail
cd "$(dirname "$0")/.."

# Budgets, one row per benched algorithm (the names sun_algos prints):
#   avr_max   cycles per position on the ATmega328P at 16 MHz, worst case
#             over the cases: 48,000 = 3 ms, the real-time loop's allowance
#             for one position (any algorithm may be configured on the Uno)
#   avr_day   cycles of the daylight table: 16,000,000 = 1 s at 16 MHz
#   cm4_pos   Cortex-M4F instructions per position (QEMU -icount): measured
#             with the board crate at opt-level "z" (Cargo.toml) and linked
#             with the board crate's 32-line vector table (psa-2020 1,000;
#             michalsky 957; grena-2012-3 855; before that table, with
#             cortex-m-rt's own, LTO inlined differently: 1,061, 1,016, 984)
#             plus 10 %, rounded up, so that a slowdown of more than 10 % fails
#             (with the library crates at "z" too: 987, 944, 842; and
#             the square root as one VSQRT instruction: 919, 876, 774)
BUDGETS="
psa-2020      48000 16000000 1100
michalsky     48000 16000000 1053
grena-2012-3  48000 16000000 941
"
# The 24-hour table: 86,400 s / 240 s step = 360 positions.
DAY_POINTS=360

ALGOS=()
declare -A AVR_MAX AVR_DAY CM4_POS
while read -r name a b c; do
  [ -n "$name" ] || continue
  ALGOS+=("$name")
  AVR_MAX[$name]=$a
  AVR_DAY[$name]=$b
  CM4_POS[$name]=$c
done <<<"$BUDGETS"

err() { echo "avr_cycles: $*" >&2; }

# The one line of the bench output that starts with "KIND ALGO "; fails
# unless there is exactly one, and unless the whole line matches REGEX.
one_line() { # file kind algo regex
  local n line
  n=$(grep -c -- "^$2 $3 " "$1" || true)
  if [ "$n" -ne 1 ]; then
    err "expected exactly one '$2 $3 …' line in the bench output, found $n"
    return 1
  fi
  line=$(grep -- "^$2 $3 " "$1")
  if ! [[ "$line" =~ $4 ]]; then
    err "garbled bench line (not '$2 $3 f32 …' with numeric fields): '$line'"
    return 1
  fi
  echo "$line"
}

# The number after " KEY=" in LINE (decimal, leading zeros allowed).
num() { # line key
  local v
  v=$(sed -n "s/.* $2=\([^ ]*\).*/\1/p" <<<"$1")
  if ! [[ "$v" =~ ^[0-9]{1,10}$ ]]; then
    err "field $2 is not a number ('$v') in: '$1'"
    return 1
  fi
  echo $((10#$v))
}

# Lines of KIND naming an algorithm that has no budget row.
unknown_algorithms() { # file kinds-regex
  local line algo known status=0 a
  while read -r line; do
    algo=$(awk '{print $2}' <<<"$line")
    known=0
    for a in "${ALGOS[@]}"; do [ "$a" = "$algo" ] && known=1; done
    if [ "$known" = 0 ]; then
      err "bench line of an algorithm without a budget row (renamed?): '$line'"
      status=1
    fi
  done < <(grep -E "^($2) " "$1" || true)
  return "$status"
}

N='([0-9]+)'
# Checks a captured (colour-stripped) avr_bench output; prints the table.
check_avr() { # file chip
  local f=$1 status=0 algo line mean max full day points verdict
  if ! grep -q '^avr_bench done$' "$f"; then
    err "the AVR bench did not finish (no 'avr_bench done' line)"
    return 1
  fi
  if grep -q '^panic' "$f"; then err "the AVR bench panicked"; return 1; fi
  unknown_algorithms "$f" 'position|day_table|daylight_table' || status=1
  echo "AVR $2 @ 16 MHz, f32, cycles (simavr, Timer1 clk/1):"
  printf '%-14s %11s %11s %14s %8s %16s %8s  %s\n' algorithm cycles/pos max/pos 24h_360pts 24h_ms daylight_cycles day_ms verdict
  for algo in "${ALGOS[@]}"; do
    if ! line=$(one_line "$f" position "$algo" "^position $algo f32 cycles_mean=$N cycles_max=$N\$") ||
      ! mean=$(num "$line" cycles_mean) || ! max=$(num "$line" cycles_max) ||
      ! line=$(one_line "$f" day_table "$algo" "^day_table $algo f32 points=$N cycles=$N ms=$N\$") ||
      ! full=$(num "$line" cycles) || ! points=$(num "$line" points) ||
      ! line=$(one_line "$f" daylight_table "$algo" "^daylight_table $algo f32 points=$N cycles=$N ms=$N\$") ||
      ! day=$(num "$line" cycles) || ! daypoints=$(num "$line" points); then
      printf '%-14s %s\n' "$algo" "MISSING or GARBLED bench line"
      status=1
      continue
    fi
    verdict=ok
    if [ "$points" -ne "$DAY_POINTS" ] || [ "$daypoints" -le 0 ] || [ "$daypoints" -ge "$DAY_POINTS" ]; then
      verdict="BAD TABLE ($points points for 24 h, $daypoints daylight)"; status=1
    fi
    if [ "$mean" -le 0 ] || [ "$max" -lt "$mean" ]; then
      verdict="$verdict; IMPLAUSIBLE (mean $mean, max $max)"; status=1
    fi
    if [ "$max" -gt "${AVR_MAX[$algo]}" ]; then verdict="$verdict; OVER (${AVR_MAX[$algo]}/pos)"; status=1; fi
    if [ "$day" -gt "${AVR_DAY[$algo]}" ]; then verdict="$verdict; OVER (${AVR_DAY[$algo]}/day)"; status=1; fi
    printf '%-14s %11d %11d %14d %8d %11d/%3dpt %8d  %s\n' "$algo" "$mean" "$max" "$full" \
      $((full / 16000)) "$day" "$daypoints" $((day / 16000)) "${verdict#ok; }"
  done
  return "$status"
}

# Checks a captured qemu_bench output; prints the table.
check_qemu() { # file
  local f=$1 status=0 algo line ipp points verdict
  if ! grep -q '^qemu_bench done$' "$f"; then
    err "the Cortex-M bench did not finish (no 'qemu_bench done' line)"
    return 1
  fi
  unknown_algorithms "$f" 'position|day_table|daylight_table' || status=1
  echo "Cortex-M4F (QEMU mps2-an386, -icount shift=0), f32:"
  printf '%-14s %14s %8s %10s  %s\n' algorithm instr/pos budget 24h_points verdict
  for algo in "${ALGOS[@]}"; do
    if ! line=$(one_line "$f" position "$algo" "^position $algo f32 instructions_per_position=$N\$") ||
      ! ipp=$(num "$line" instructions_per_position) ||
      ! line=$(one_line "$f" day_table "$algo" "^day_table $algo f32 points=$N instructions=$N\$") ||
      ! points=$(num "$line" points) ||
      ! line=$(one_line "$f" daylight_table "$algo" "^daylight_table $algo f32 points=$N instructions=$N\$"); then
      printf '%-14s %s\n' "$algo" "MISSING or GARBLED bench line"
      status=1
      continue
    fi
    verdict=ok
    if [ "$points" -ne "$DAY_POINTS" ]; then verdict="BAD TABLE ($points points)"; status=1; fi
    if [ "$ipp" -le 0 ]; then verdict="$verdict; IMPLAUSIBLE (0)"; status=1; fi
    if [ "$ipp" -gt "${CM4_POS[$algo]}" ]; then verdict="$verdict; OVER"; status=1; fi
    printf '%-14s %14d %8d %10d  %s\n' "$algo" "$ipp" "${CM4_POS[$algo]}" "$points" "${verdict#ok; }"
  done
  return "$status"
}

# A bench output in the images' format with made-up numbers (within
# budget), for the self-test when no captured output is given.
sample_avr() {
  echo "suntracker 0.1.0"
  echo "calibration overhead_cycles=12"
  for algo in "${ALGOS[@]}"; do
    echo "position $algo f32 cycles_mean=20000 cycles_max=30000"
    echo "day_table $algo f32 points=360 cycles=7200000 ms=450"
    echo "daylight_table $algo f32 points=190 cycles=3800000 ms=237"
  done
  echo "avr_bench done"
}
sample_qemu() {
  echo "suntracker 0.1.0 qemu_bench on mps2-an386 (run with -icount shift=0)"
  for algo in "${ALGOS[@]}"; do
    echo "position $algo f32 instructions_per_position=800"
    echo "day_table $algo f32 points=360 instructions=288000"
    echo "daylight_table $algo f32 points=190 instructions=152000"
  done
  echo "qemu_bench done"
}

# Each doctored copy of a good output must fail the check; the good one
# must pass.
self_test() {
  local dir avr qemu failures=0 a=${ALGOS[0]} b=${ALGOS[1]} msg
  dir=$(mktemp -d)
  avr="$dir/avr.txt"
  qemu="$dir/qemu.txt"
  if [ -n "${AVR_BENCH_OUT:-}" ]; then cp "$AVR_BENCH_OUT" "$avr"; else sample_avr >"$avr"; fi
  if [ -n "${QEMU_BENCH_OUT:-}" ]; then cp "$QEMU_BENCH_OUT" "$qemu"; else sample_qemu >"$qemu"; fi
  if ! check_avr "$avr" self-test >/dev/null 2>"$dir/msg"; then
    cat "$dir/msg" >&2; err "self-test: the undoctored AVR output fails"; return 1
  fi
  if ! check_qemu "$qemu" >/dev/null 2>"$dir/msg"; then
    cat "$dir/msg" >&2; err "self-test: the undoctored Cortex-M output fails"; return 1
  fi
  expect_red() { # description checker file sed-script
    sed -e "$4" "$3" >"$dir/doctored"
    if cmp -s "$3" "$dir/doctored"; then
      err "self-test: '$1' changed nothing (doctoring script out of date)"
      failures=$((failures + 1))
    elif $2 "$dir/doctored" self-test >"$dir/table" 2>"$dir/msg"; then
      err "self-test: '$1' was NOT caught"
      failures=$((failures + 1))
    else
      msg=$(head -1 "$dir/msg")
      [ -n "$msg" ] || msg=$(grep -E 'OVER|BAD|IMPLAUSIBLE' "$dir/table" | head -1 | tr -s ' ')
      echo "self-test: red as it should: $1 -> $msg"
    fi
  }
  # check_qemu takes one argument; the extra one is ignored.
  for kind in avr qemu; do
    local f=$avr c=check_avr k=cycles_max
    [ "$kind" = qemu ] && f=$qemu c=check_qemu k=instructions_per_position
    expect_red "$kind: no position line for $a" $c "$f" "/^position $a /d"
    expect_red "$kind: no position lines at all" $c "$f" "/^position /d"
    expect_red "$kind: $b renamed to $b-v2" $c "$f" "s/ $b / $b-v2 /"
    expect_red "$kind: $a's $k garbled (12x4)" $c "$f" "/^position $a /s/ $k=[0-9]*/ $k=12x4/"
    expect_red "$kind: $a's $k empty" $c "$f" "/^position $a /s/ $k=[0-9]*/ $k=/"
    expect_red "$kind: $a's $k over budget" $c "$f" "/^position $a /s/ $k=[0-9]*/ $k=99999999/"
    expect_red "$kind: $b's position line twice" $c "$f" "/^position $b /p"
    expect_red "$kind: an extra algorithm line" $c "$f" "/^position $b /{p;s/ $b / foo-2030 /}"
    expect_red "$kind: day_table of $a missing" $c "$f" "/^day_table $a /d"
    expect_red "$kind: day_table of $a with 359 points" $c "$f" "/^day_table $a /s/ points=[0-9]*/ points=359/"
    expect_red "$kind: bench did not finish" $c "$f" "/ done\$/d"
    expect_red "$kind: empty output" $c "$f" "d"
  done
  expect_red "avr: daylight table of $a over budget" check_avr "$avr" \
    "/^daylight_table $a /s/ cycles=[0-9]*/ cycles=99999999/"
  expect_red "avr: daylight cycles of $b garbled" check_avr "$avr" \
    "/^daylight_table $b /s/ cycles=[0-9]*/ cycles=-5/"
  rm -rf "$dir"
  if [ "$failures" -ne 0 ]; then
    err "self-test FAILED: $failures doctored outputs passed"
    return 1
  fi
  echo "avr_cycles: self-test passed (every doctored bench output fails)"
}

if [ "${SELF_TEST:-0}" = 1 ]; then
  self_test
  exit $?
fi

# shellcheck source=.ci/firmware_env.sh
source .ci/firmware_env.sh

chip=${AVR_BENCH_CHIP:-atmega328p}
case "$chip" in
  atmega328p)
    elf=$ELF_AVR_BENCH
    [ "${NO_BUILD:-0}" = 1 ] || cargo +nightly build --release --target avr-none \
      -Z build-std=core -p suntracker-avr --bin avr_bench >&2
    ;;
  atmega2560)
    elf="$FW_TARGET_DIR/mega/avr-none/release/avr_bench.elf"
    [ "${NO_BUILD:-0}" = 1 ] || RUSTFLAGS="$AVR_MEGA_RUSTFLAGS" \
      cargo +nightly build --release --target avr-none -Z build-std=core \
      -p suntracker-avr --bin avr_bench --target-dir "$FW_TARGET_DIR/mega" >&2
    ;;
  *) err "unknown AVR_BENCH_CHIP $chip"; exit 2 ;;
esac

status=0
out=$(mktemp)
[ -f "$elf" ] || { err "missing ELF $elf"; exit 1; }
timeout 600 simavr -m "$chip" -f 16000000 "$elf" 2>&1 >/dev/null \
  | sed -e 's/\x1b\[[0-9;]*m//g' -e 's/\.$//' | grep -v '^$' >"$out" || true
[ -z "${SAVE_DIR:-}" ] || cp "$out" "$SAVE_DIR/avr_bench_$chip.txt"
if ! check_avr "$out" "$chip"; then
  echo "--- AVR bench output:" >&2
  cat "$out" >&2
  status=1
fi

# Cortex-M4F: QEMU counts instructions exactly with -icount shift=0 (one
# virtual nanosecond per instruction); the bench reads the 25 MHz SysTick,
# i.e. one tick per 40 instructions, over many positions.
if [ "${SKIP_QEMU:-0}" != 1 ]; then
  [ "${NO_BUILD:-0}" = 1 ] || cargo build --release --target thumbv7em-none-eabihf -p suntracker-mps2-an386 --bin qemu_bench >&2
  [ -f "$ELF_QEMU_BENCH" ] || { err "missing ELF $ELF_QEMU_BENCH"; exit 1; }
  echo
  qout=$(mktemp)
  rc=0
  timeout 600 qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -monitor none \
    -serial null -icount shift=0 -semihosting-config enable=on,target=native \
    -kernel "$ELF_QEMU_BENCH" >"$qout" || rc=$?
  [ -z "${SAVE_DIR:-}" ] || cp "$qout" "$SAVE_DIR/qemu_bench.txt"
  if [ "$rc" -ne 0 ]; then err "qemu_bench exited $rc"; status=1; fi
  if ! check_qemu "$qout"; then
    echo "--- Cortex-M bench output:" >&2
    cat "$qout" >&2
    status=1
  fi
fi

if [ "$status" -ne 0 ]; then
  err "FAILED (over the speed budget, or a bench line missing or garbled)"
fi
exit "$status"
