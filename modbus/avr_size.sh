#!/bin/bash
# Flash and RAM of the Modbus frame layer, server and SunSpec map on the
# ATmega2560: builds modbus/examples/avr_size.rs and its baseline
# avr_size_base.rs (release profile, the Mega's flags of
# .ci/firmware_env.sh less its --cfg) and prints avr-size of both and the
# difference; fails if either image holds software f64 or 64-bit division.
#   bash modbus/avr_size.sh [cargo options]   (from the workspace root)
set -euo pipefail
cd "$(dirname "$0")/.."
TARGET=${CARGO_TARGET_DIR:-target}
case "$TARGET" in /*) ;; *) TARGET="$PWD/$TARGET" ;; esac
DIR="$TARGET/modbus-avr"
# The assembler runtime the boards' images link (boards/avr/asm_runtime.rs):
# libgcc's 32-bit division and avr-libc's memcpy/memset over
# compiler_builtins' weak ones, so that the difference is this crate's code.
RT="$DIR/asm-runtime"
mkdir -p "$RT"
(cd "$RT" && avr-ar x "$(avr-gcc -mmcu=atmega2560 -print-libgcc-file-name)" _udivmodsi4.o _divmodsi4.o _negsi2.o \
  && avr-ar x "$(avr-gcc -mmcu=atmega2560 -print-file-name=libc.a)" memcpy.o memset.o)
RT_ARGS=""
for o in "$RT"/*.o; do RT_ARGS="$RT_ARGS -C link-arg=$o"; done
RUSTFLAGS="-C target-cpu=atmega2560 -C link-arg=-Wl,--whole-archive -C link-arg=-lm -C link-arg=-Wl,--no-whole-archive -C link-arg=-Wl,--relax -C debuginfo=0$RT_ARGS" \
  cargo +nightly build -q --release --target avr-none -Z build-std=core -p suntracker-modbus \
  --example avr_size --example avr_size_base --target-dir "$DIR" "$@"
ELF="$DIR/avr-none/release/examples/avr_size.elf"
BASE="$DIR/avr-none/release/examples/avr_size_base.elf"
avr-size "$BASE" "$ELF"
read -r t1 d1 b1 _ < <(avr-size "$BASE" | tail -1)
read -r t2 d2 b2 _ < <(avr-size "$ELF" | tail -1)
echo "Modbus RTU + server + SunSpec map: $((t2 + d2 - t1 - d1)) B flash (text + data), $((d2 + b2 - d1 - b1)) B static RAM (data + bss)"
WIDE='__(add|sub|mul|div)df3|__(extendsfdf2|truncdfsf2)|__u?(div|mod)(di|ti)3|__u?divmod(di|ti)4|[iu](64|128)_div_rem'
if avr-nm -C "$ELF" | grep -E " ($WIDE)" ; then
  echo "software f64 or 64-bit division in $ELF" >&2
  exit 1
fi
echo "no software f64, no 64-bit division"
