#!/bin/bash
# pysunspec2 (the SunSpec Alliance's Python client) scans and writes the
# simulated tracker's SunSpec map over a pseudo-terminal: builds the
# pty_server example, puts pysunspec2 in a virtual environment under the
# target directory (once), checks that the point table the layout test
# reads still matches pysunspec2's models, and runs
# modbus/sunspec/pysunspec2_e2e.py.
#   bash modbus/e2e_pysunspec2.sh        (from the workspace root)
set -euo pipefail
cd "$(dirname "$0")/.."
TARGET=${CARGO_TARGET_DIR:-target}
VENV="$TARGET/pysunspec2-venv"
if ! "$VENV/bin/python" -c "import sunspec2, serial" 2>/dev/null; then
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install -q "pysunspec2==1.3.7" "pyserial==3.5"
fi
"$VENV/bin/python" modbus/sunspec/expected_points.py --check modbus/tests/data/sunspec_points.tsv
cargo build -q -p suntracker-modbus --example pty_server
timeout 300 "$VENV/bin/python" modbus/sunspec/pysunspec2_e2e.py "$TARGET/debug/examples/pty_server"
