# Shared by the firmware scripts of .ci/ (sourced, not run): where each
# release ELF lands, and how each image is built. The Black Pill's images and
# the Mega's default build in target directories of their own; the QEMU and
# the Uno's default images in the workspace's (each under its target). The
# AVR images that differ from their board's default only by features or
# the emulator's clock (SUNTRACKER_EMU_MS_PER_TICK) build one after another
# in one directory per board (uno-variants, mega-variants), where their
# dependencies, `core` and the host's build tools among them, are built once
# (about 40 s of a 47 s build); each ELF is then copied to its own path
# below, which no other build writes. So building one never overwrites
# another's ELF, and a default image is never rebuilt for a variant.
#
# Needs: rustup with the stable toolchain + target thumbv7em-none-eabihf, the
# nightly toolchain with rust-src (for avr-none), and avr-gcc + avr-libc
# (the AVR linker and its libm).

FW_TARGET_DIR=${CARGO_TARGET_DIR:-target}
# Absolute, so that scripts may change directory.
case "$FW_TARGET_DIR" in /*) ;; *) FW_TARGET_DIR="$PWD/$FW_TARGET_DIR" ;; esac

ELF_QEMU="$FW_TARGET_DIR/thumbv7em-none-eabihf/release/qemu_tracker"
ELF_QEMU_BENCH="$FW_TARGET_DIR/thumbv7em-none-eabihf/release/qemu_bench"
ELF_BLACKPILL="$FW_TARGET_DIR/blackpill/thumbv7em-none-eabihf/release/blackpill_tracker"
ELF_BLACKPILL_DEFMT="$FW_TARGET_DIR/blackpill-defmt/thumbv7em-none-eabihf/release/blackpill_tracker"
ELF_BLACKPILL_MODBUS="$FW_TARGET_DIR/blackpill-modbus/thumbv7em-none-eabihf/release/blackpill_tracker"
ELF_BLACKPILL_DC="$FW_TARGET_DIR/blackpill-dc/thumbv7em-none-eabihf/release/blackpill_tracker"
ELF_AVR_UNO="$FW_TARGET_DIR/avr-none/release/avr_tracker.elf"
ELF_AVR_BENCH="$FW_TARGET_DIR/avr-none/release/avr_bench.elf"
ELF_AVR_MEGA="$FW_TARGET_DIR/mega/avr-none/release/avr_mega_tracker.elf"
ELF_AVR_MEGA_EMU="$FW_TARGET_DIR/mega-emu/avr-none/release/avr_mega_tracker.elf"
# The Mega's `dc` image (both axes DC gear motors in its own configuration), and its emulator build.
ELF_AVR_MEGA_DC="$FW_TARGET_DIR/mega-dc/avr-none/release/avr_mega_tracker.elf"
ELF_AVR_MEGA_DC_EMU="$FW_TARGET_DIR/mega-dc-emu/avr-none/release/avr_mega_tracker.elf"
ELF_AVR_UNO_EMU="$FW_TARGET_DIR/uno-emu/avr-none/release/avr_tracker.elf"
ELF_AVR_UNO_PSA2020="$FW_TARGET_DIR/uno-psa2020/avr-none/release/avr_tracker.elf"
ELF_AVR_UNO_DS1302="$FW_TARGET_DIR/uno-ds1302/avr-none/release/avr_tracker.elf"
ELF_AVR_SETTINGS="$FW_TARGET_DIR/avr-none/release/avr_settings.elf"
# The library's firmware loop on the Uno's parts (boards/uno/examples/library_firmware.rs):
# built and held to a budget to measure how far it is from fitting the part; never flashed.
ELF_AVR_UNO_LIBRARY="$FW_TARGET_DIR/avr-none/release/examples/library_firmware.elf"
ELF_AVR_SETTINGS_DS1302="$FW_TARGET_DIR/uno-ds1302/avr-none/release/avr_settings.elf"
ELF_AVR_SETTINGS_EMU="$FW_TARGET_DIR/uno-emu/avr-none/release/avr_settings.elf"
ELF_AVR_UNO_DS1302_EMU="$FW_TARGET_DIR/uno-ds1302-emu/avr-none/release/avr_tracker.elf"
ELF_AVR_SETTINGS_DS1302_EMU="$FW_TARGET_DIR/uno-ds1302-emu/avr-none/release/avr_settings.elf"
ELF_AVR_SELFTEST_UNO="$FW_TARGET_DIR/avr-none/release/avr_board_selftest.elf"
ELF_AVR_SELFTEST="$FW_TARGET_DIR/mega/avr-none/release/avr_board_selftest.elf"

# The ATmega2560 flags: the same as .cargo/config.toml's avr-none flags but
# for the other CPU, with boards/mega2560/.cargo/config.toml's inline
# threshold (RUSTFLAGS replaces the config files' lists entirely).
AVR_MEGA_RUSTFLAGS="-C target-cpu=atmega2560 --cfg avr_atmega2560 -C link-arg=-Wl,--whole-archive -C link-arg=-lm -C link-arg=-Wl,--no-whole-archive -C link-arg=-Wl,--relax -C debuginfo=0 -C llvm-args=-inline-threshold=5"

# Where the AVR variants build (see the top of this file).
UNO_VARIANTS_DIR="$FW_TARGET_DIR/uno-variants"
MEGA_VARIANTS_DIR="$FW_TARGET_DIR/mega-variants"
# Copies the ELFs a variant build left in its directory to that variant's
# paths: variant_elfs build-dir [elf-name dest-path]...
variant_elfs() {
  local dir=$1
  shift
  while [ $# -ge 2 ]; do
    mkdir -p "$(dirname "$2")"
    cp "$dir/avr-none/release/$1" "$2"
    shift 2
  done
}

build_qemu() {
  cargo build --release --target thumbv7em-none-eabihf -p suntracker-mps2-an386 \
    --bin qemu_tracker --bin qemu_bench
}
# Both Black Pill builds run in the board's directory, so that its
# .cargo/config.toml (the profile this image is built with) holds as it does
# for `cargo run` there.
build_blackpill() {
  (cd boards/stm32f411 && cargo build --release --target thumbv7em-none-eabihf -p suntracker-stm32f411 \
    --bin blackpill_tracker --target-dir "$FW_TARGET_DIR/blackpill")
}
# The Black Pill with its log over defmt/RTT: defmt's linker script joins
# the root config's -Tlink.x (cargo joins rustflags lists across configs).
build_blackpill_defmt() {
  (cd boards/stm32f411 && cargo build --release --target thumbv7em-none-eabihf -p suntracker-stm32f411 --features defmt \
    --bin blackpill_tracker --target-dir "$FW_TARGET_DIR/blackpill-defmt" \
    --config 'target.thumbv7em-none-eabihf.rustflags=["-C", "link-arg=-Tdefmt.x"]')
}
# The Black Pill with the Modbus RTU server on USART2's RS-485 transceiver.
build_blackpill_modbus() {
  (cd boards/stm32f411 && cargo build --release --target thumbv7em-none-eabihf -p suntracker-stm32f411 --features modbus \
    --bin blackpill_tracker --target-dir "$FW_TARGET_DIR/blackpill-modbus")
}
# The Black Pill with each axis of any kind by configuration (src/dc.rs).
build_blackpill_dc() {
  (cd boards/stm32f411 && cargo build --release --target thumbv7em-none-eabihf -p suntracker-stm32f411 --features dc \
    --bin blackpill_tracker --target-dir "$FW_TARGET_DIR/blackpill-dc")
}
build_avr_uno() {
  cargo +nightly build --release --target avr-none -Z build-std=core \
    -p suntracker-uno --bin avr_tracker --bin avr_settings --example library_firmware \
    -p suntracker-avr --bin avr_bench --bin avr_board_selftest
}
# The Uno image's build options: psa-2020 instead of Chowdhury et al.'s (2019) michalsky,
# a DS1302 instead of the DS3231 (the settings image too: its `time set`
# sets that clock); built and held to the same budget.
build_avr_uno_psa2020() {
  cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-uno --features psa2020 \
    --bin avr_tracker --target-dir "$UNO_VARIANTS_DIR" &&
    variant_elfs "$UNO_VARIANTS_DIR" avr_tracker.elf "$ELF_AVR_UNO_PSA2020"
}
build_avr_uno_ds1302() {
  cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-uno --features ds1302 \
    --bin avr_tracker --bin avr_settings --target-dir "$UNO_VARIANTS_DIR" &&
    variant_elfs "$UNO_VARIANTS_DIR" avr_tracker.elf "$ELF_AVR_UNO_DS1302" avr_settings.elf "$ELF_AVR_SETTINGS_DS1302"
}
build_avr_mega() {
  RUSTFLAGS="$AVR_MEGA_RUSTFLAGS" \
    cargo +nightly build --release --target avr-none -Z build-std=core \
    -p suntracker-mega2560 --bin avr_mega_tracker -p suntracker-avr --bin avr_board_selftest --target-dir "$FW_TARGET_DIR/mega"
}
# The Mega with DC gear motors on IBT-2 (BTS7960) bridges and Hall encoders
# (feature `dc`, boards/mega2560/src/dc.rs), held to the Mega's budget.
build_avr_mega_dc() {
  RUSTFLAGS="$AVR_MEGA_RUSTFLAGS" \
    cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-mega2560 --features dc \
    --bin avr_mega_tracker --target-dir "$MEGA_VARIANTS_DIR" &&
    variant_elfs "$MEGA_VARIANTS_DIR" avr_mega_tracker.elf "$ELF_AVR_MEGA_DC"
}
# The same image for the emulator harness (emu/): its Timer0 clock advances
# EMU_MS_PER_TICK ms per 1 ms tick (boards/avr/src/millis.rs); nothing else
# differs.
EMU_MS_PER_TICK=60
build_avr_mega_emu() {
  SUNTRACKER_EMU_MS_PER_TICK=$EMU_MS_PER_TICK RUSTFLAGS="$AVR_MEGA_RUSTFLAGS" \
    cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-mega2560 \
    --bin avr_mega_tracker --target-dir "$MEGA_VARIANTS_DIR" &&
    variant_elfs "$MEGA_VARIANTS_DIR" avr_mega_tracker.elf "$ELF_AVR_MEGA_EMU"
}
# The `dc` image for the emulator harness, the same way (the harness holds
# PL0 high, real time, while a motor is driven or turns).
build_avr_mega_dc_emu() {
  SUNTRACKER_EMU_MS_PER_TICK=$EMU_MS_PER_TICK RUSTFLAGS="$AVR_MEGA_RUSTFLAGS" \
    cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-mega2560 --features dc \
    --bin avr_mega_tracker --target-dir "$MEGA_VARIANTS_DIR" &&
    variant_elfs "$MEGA_VARIANTS_DIR" avr_mega_tracker.elf "$ELF_AVR_MEGA_DC_EMU"
}
# The Uno images for the emulator harness, the same way.
build_avr_uno_emu() {
  SUNTRACKER_EMU_MS_PER_TICK=$EMU_MS_PER_TICK \
    cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-uno \
    --bin avr_tracker --bin avr_settings --target-dir "$UNO_VARIANTS_DIR" &&
    variant_elfs "$UNO_VARIANTS_DIR" avr_tracker.elf "$ELF_AVR_UNO_EMU" avr_settings.elf "$ELF_AVR_SETTINGS_EMU"
}
# The DS1302 build of both Uno images for the harness's DS1302 model.
build_avr_uno_ds1302_emu() {
  SUNTRACKER_EMU_MS_PER_TICK=$EMU_MS_PER_TICK \
    cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-uno --features ds1302 \
    --bin avr_tracker --bin avr_settings --target-dir "$UNO_VARIANTS_DIR" &&
    variant_elfs "$UNO_VARIANTS_DIR" avr_tracker.elf "$ELF_AVR_UNO_DS1302_EMU" avr_settings.elf "$ELF_AVR_SETTINGS_DS1302_EMU"
}
build_all_firmware() {
  build_qemu
  build_blackpill
  build_blackpill_defmt
  build_blackpill_modbus
  build_blackpill_dc
  build_avr_uno
  build_avr_uno_psa2020
  build_avr_uno_ds1302
  build_avr_mega
  build_avr_mega_dc
  build_avr_mega_emu
  build_avr_mega_dc_emu
  build_avr_uno_emu
  build_avr_uno_ds1302_emu
}
