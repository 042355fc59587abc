#!/bin/bash
# pysunspec2 (the SunSpec Alliance's Python client) reads and commands the
# Modbus server of the QEMU image (mps2-an386, qemu_tracker) over a
# pseudo-terminal bridged to its RS-485 UART by .ci/qemu_gps.py
# --modbus-pty: builds the image (unless NO_BUILD=1), puts pysunspec2,
# pyserial and pvlib in a virtual environment under the target directory
# (once, modbus/e2e_venv.sh), and runs modbus/sunspec/sunspec_e2e.py qemu
# (two runs, started together, paced to the wall clock while the client is
# attached).
#   bash modbus/e2e_qemu.sh        (from the workspace root)
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=../.ci/firmware_env.sh
source .ci/firmware_env.sh
# shellcheck source=e2e_venv.sh
source modbus/e2e_venv.sh
if [ "${NO_BUILD:-}" != 1 ]; then
  build_qemu
fi
timeout 600 "$VENV/bin/python" modbus/sunspec/sunspec_e2e.py qemu "$ELF_QEMU" "$FW_TARGET_DIR/qemu-modbus-e2e"
