# shellcheck shell=bash
# The virtual environment of the pysunspec2 end-to-end tests
# (modbus/e2e_qemu.sh, modbus/e2e_mega.sh): pysunspec2 1.3.7, pyserial 3.5
# and pvlib under the target directory, made once. Sourced after
# .ci/firmware_env.sh; sets VENV.
PVLIB_VERSION=0.16.1
VENV="$FW_TARGET_DIR/qemu-modbus-venv"
if ! "$VENV/bin/python" -c "import sunspec2, serial, pvlib, sys; sys.exit(pvlib.__version__ != '$PVLIB_VERSION')" 2>/dev/null; then
  rm -rf "$VENV"
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install -q --disable-pip-version-check "pysunspec2==1.3.7" "pyserial==3.5" "pvlib==$PVLIB_VERSION"
fi
