#!/bin/bash
# pysunspec2 (the SunSpec Alliance's Python client) reads and commands the
# Modbus server of the ATmega2560 image — the board ELF a user flashes, at
# 1:1 — over a pseudo-terminal bridged to its RS-485 port (USART2) by
# `suntracker-emu --image mega --modbus-pty`: builds the image and the
# harness (unless NO_BUILD=1; the harness is then taken as built), puts
# pysunspec2, pyserial and pvlib in a virtual environment under the target
# directory (once, modbus/e2e_venv.sh), and runs
# modbus/sunspec/sunspec_e2e.py mega (two runs, started together, paced to
# the wall clock while the client is attached).
#   bash modbus/e2e_mega.sh        (from the workspace root)
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=../.ci/firmware_env.sh
source .ci/firmware_env.sh
# shellcheck source=e2e_venv.sh
source modbus/e2e_venv.sh
TARGET_DIR="${CARGO_TARGET_DIR:-target}"
if [ "${NO_BUILD:-}" != 1 ]; then
  build_avr_mega
  cargo build --release -p suntracker-emu
fi
timeout 900 "$VENV/bin/python" modbus/sunspec/sunspec_e2e.py mega "$ELF_AVR_MEGA" \
  "$FW_TARGET_DIR/mega-modbus-e2e" "$TARGET_DIR/release/suntracker-emu"
