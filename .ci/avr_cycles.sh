#!/usr/bin/env bash
# Speed of the sun-position algorithms on the 8-bit part, cycle
# exact: builds the avr_bench image (release, f32, sun_algos' avr-libc-math
# feature: avr-libc's assembler trigonometry and float routines), runs it in simavr at
# 16 MHz and checks the budgets. Also runs the Cortex-M bench in QEMU with
# `-icount shift=0` and reports instructions per position.
#
#   bash .ci/avr_cycles.sh                 # ATmega328P (the budgeted part)
#   AVR_BENCH_CHIP=atmega2560 bash .ci/avr_cycles.sh
#
# Method (see src/bin/avr_bench.rs): Timer1 free-running at clk/1, overflow
# interrupt extends it to 32 bits; empty-measurement overhead subtracted.
# Budgets: psa-2020 ≤ 48,000 cycles per position (3 ms at 16 MHz); a whole
# 4-minute day table ≤ 16,000,000 cycles (1 s) for every measured
# algorithm. The day table is seed jimoh-2019's step 7: the set-points from
# sunrise to sunset (Kano, 2026-06-21: 191 of the 360 slots); the whole
# 24-hour sweep of 360 positions is printed beside it for reference. Exits non-zero over budget.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=.ci/firmware_env.sh
source .ci/firmware_env.sh

chip=${AVR_BENCH_CHIP:-atmega328p}
case "$chip" in
  atmega328p)
    elf=$ELF_AVR_BENCH
    [ "${NO_BUILD:-0}" = 1 ] || cargo +nightly build --release --target avr-none \
      -Z build-std=core --bin avr_bench >&2
    ;;
  atmega2560)
    elf="$FW_TARGET_DIR/mega/avr-none/release/avr_bench.elf"
    [ "${NO_BUILD:-0}" = 1 ] || RUSTFLAGS="$AVR_MEGA_RUSTFLAGS" \
      cargo +nightly build --release --target avr-none -Z build-std=core \
      --bin avr_bench --target-dir "$FW_TARGET_DIR/mega" >&2
    ;;
  *) echo "avr_cycles: unknown AVR_BENCH_CHIP $chip" >&2; exit 2 ;;
esac

out=$(mktemp)
timeout 600 simavr -m "$chip" -f 16000000 "$elf" 2>&1 >/dev/null \
  | sed -e 's/\x1b\[[0-9;]*m//g' -e 's/\.$//' | grep -v '^$' >"$out" || true
if ! grep -q '^avr_bench done' "$out"; then
  cat "$out" >&2
  echo "avr_cycles: the bench did not finish" >&2
  exit 1
fi

field() { # line key
  sed -n "s/.* $2=\([0-9]*\).*/\1/p" <<<"$1"
}

status=0
echo "AVR $chip @ 16 MHz, f32, cycles (simavr, Timer1 clk/1):"
printf '%-14s %11s %11s %14s %8s %16s %8s  %s\n' algorithm cycles/pos max/pos 24h_360pts 24h_ms daylight_cycles day_ms verdict
while read -r line; do
  algo=$(awk '{print $2}' <<<"$line")
  mean=$(field "$line" cycles_mean)
  max=$(field "$line" cycles_max)
  full=$(field "$(grep "^day_table $algo " "$out")" cycles)
  day_line=$(grep "^daylight_table $algo " "$out")
  day=$(field "$day_line" cycles)
  points=$(field "$day_line" points)
  verdict=ok
  if [ "$algo" = psa-2020 ] && [ "$max" -gt 48000 ]; then verdict="OVER (48000/pos)"; status=1; fi
  if [ "$day" -gt 16000000 ]; then verdict="$verdict; OVER (16M/day)"; status=1; fi
  printf '%-14s %11d %11d %14d %8d %11d/%3dpt %8d  %s\n' "$algo" "$mean" "$max" "$full" \
    $((full / 16000)) "$day" "$points" $((day / 16000)) "$verdict"
done < <(grep '^position ' "$out")

# Cortex-M4F: QEMU counts instructions exactly with -icount shift=0 (one
# virtual nanosecond per instruction); the bench reads the 25 MHz SysTick,
# i.e. one tick per 40 instructions, over many positions.
if [ "${SKIP_QEMU:-0}" != 1 ]; then
  [ "${NO_BUILD:-0}" = 1 ] || cargo build --release --target thumbv7em-none-eabihf --bin qemu_bench >&2
  echo
  echo "Cortex-M4F (QEMU mps2-an386, -icount shift=0), f32:"
  timeout 600 qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -monitor none \
    -serial null -icount shift=0 -semihosting-config enable=on,target=native \
    -kernel "$ELF_QEMU_BENCH" | grep -E "^(position|day_table|daylight_table)" || status=1
fi

if [ "$status" -ne 0 ]; then
  echo "avr_cycles: FAILED (over the speed budget, or a bench failed)" >&2
fi
exit "$status"
