#!/bin/bash
# pysunspec2 (the SunSpec Alliance's Python client) reads and commands the
# Modbus server of the QEMU image (mps2-an386, qemu_tracker) over a
# pseudo-terminal bridged to its RS-485 UART by .ci/qemu_gps.py
# --modbus-pty: builds the image (unless NO_BUILD=1), puts pysunspec2,
# pyserial and pvlib in a virtual environment under the target directory
# (once), and runs modbus/sunspec/qemu_e2e.py (two runs of about half a
# minute each, paced to the wall clock while the client is attached).
#   bash modbus/e2e_qemu.sh        (from the workspace root)
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=../.ci/firmware_env.sh
source .ci/firmware_env.sh
PVLIB_VERSION=0.16.1
VENV="$FW_TARGET_DIR/qemu-modbus-venv"
if ! "$VENV/bin/python" -c "import sunspec2, serial, pvlib, sys; sys.exit(pvlib.__version__ != '$PVLIB_VERSION')" 2>/dev/null; then
  rm -rf "$VENV"
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install -q --disable-pip-version-check "pysunspec2==1.3.7" "pyserial==3.5" "pvlib==$PVLIB_VERSION"
fi
if [ "${NO_BUILD:-}" != 1 ]; then
  build_qemu
fi
timeout 600 "$VENV/bin/python" modbus/sunspec/qemu_e2e.py "$ELF_QEMU" "$FW_TARGET_DIR/qemu-modbus-e2e"
