#!/bin/bash
# `monitor --modbus` (examples/monitor.rs) polls the QEMU image's Modbus
# server (mps2-an386, qemu_tracker) over the pseudo-terminal that
# .ci/qemu_gps.py --modbus-pty bridges to its RS-485 UART: builds the image
# (unless NO_BUILD=1) and the monitor, starts the image at Kano from
# 2026-03-20 09:00 UTC with the GPS stream, waits in its log until it
# tracks, polls it every second for 20 s (the harness paces the emulation
# to the wall clock while the monitor holds the terminal), and checks that
# every poll's target (the CSV's zenith, 90 deg - 601's ElTrgt, and
# azimuth, AzTrgt) is the set-point the image logged last at or before the
# poll's time (601's DtLoc/TmLoc; within a tick of a new set-point's time,
# the one before may still be in force), within the map's 0.01 deg; that the
# position is within a step of the target; the mode tracking, no fault, the
# site the stream's (model 305 has it for 1.5 s after each epoch: see
# docs/src/monitor.md). Python 3's standard library only; 20 to 40 s with
# NO_BUILD=1.
#   bash modbus/e2e_monitor.sh        (from the workspace root)
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=../.ci/firmware_env.sh
source .ci/firmware_env.sh
if [ "${NO_BUILD:-}" != 1 ]; then
  build_qemu
fi
cargo build -q --profile host --example monitor
MONITOR="$FW_TARGET_DIR/host/examples/monitor"
WORK="$FW_TARGET_DIR/qemu-monitor-e2e"
mkdir -p "$WORK"
rm -f "$WORK/image.log" "$WORK/modbus.tty" "$WORK/polls.csv"
python3 .ci/qemu_gps.py "$ELF_QEMU" --start 2026-03-20T09:00:00Z --minutes 600 --quiet \
  --timeout 300 --log "$WORK/image.log" --modbus-pty "$WORK/modbus.tty" \
  >"$WORK/harness.txt" 2>&1 &
HARNESS=$!
stop_harness() {
  # The harness stops the image at its next gate (`end` line).
  kill -TERM "$HARNESS" 2>/dev/null || true
  wait "$HARNESS" 2>/dev/null || true
}
trap stop_harness EXIT
for _ in $(seq 600); do
  if grep -q '^setpoint ' "$WORK/image.log" 2>/dev/null && [ -e "$WORK/modbus.tty" ]; then
    break
  fi
  if ! kill -0 "$HARNESS" 2>/dev/null; then
    echo "FAIL the harness ended before the image tracked: $(tail -3 "$WORK/harness.txt")"
    exit 1
  fi
  sleep 0.2
done
"$MONITOR" --modbus "$WORK/modbus.tty" --address 1 --every-s 1 --seconds 20 \
  --csv "$WORK/polls.csv" >"$WORK/monitor.out" 2>"$WORK/monitor.err"
stop_harness
trap - EXIT
cat "$WORK/monitor.err"
python3 - "$WORK/image.log" "$WORK/polls.csv" "$WORK/monitor.out" <<'EOF'
import csv, datetime as dt, re, sys

log_path, csv_path, out_path = sys.argv[1:4]
# One step of the simulated axes (boards/mps2_an386/src/mount.rs) and the
# map's 0.01 deg (as modbus/sunspec/sunspec_e2e.py).
STEP_DEG = 0.018 + 0.01
failures = []


def check(what, ok, detail=""):
    print("%-4s %s%s" % ("ok" if ok else "FAIL", what, (": " + detail) if detail else ""))
    if not ok:
        failures.append(what)


def angle_diff(a, b):
    d = abs(a - b) % 360.0
    return min(d, 360.0 - d)


setpoints = []
tick_s = 10
for line in open(log_path, encoding="utf-8"):
    m = re.match(r"^setpoint utc=(\S+) zenith=(\S+) azimuth=(\S+) ", line)
    if m:
        setpoints.append((m.group(1), float(m.group(2)), float(m.group(3))))
    m = re.match(r"^config .* tick_ms=(\d+)", line)
    if m:
        tick_s = int(m.group(1)) / 1000


def seconds(utc):
    return dt.datetime.fromisoformat(utc.replace("Z", "+00:00")).timestamp()


rows = list(csv.DictReader(open(csv_path, encoding="utf-8")))
out = open(out_path, encoding="utf-8").read()
check("the map found with models 1, 601, 305 and 64201",
      re.search(r"^monitor: modbus: SunS at 40000, model 1 at 40002 \(L 66\), model 601 .*"
                r"model 305 .*model 64201 .*end at", out, re.M) is not None)
check("at least 15 polls in tracking mode", len(rows) >= 15, "%d rows" % len(rows))
summary = re.search(r"^monitor: modbus: (\d+) polls: (\d+) answered, (\d+) missed", out, re.M)
check("every poll answered", summary is not None and summary.group(3) == "0",
      summary.group(0) if summary else "no summary")
worst_zen = worst_az = worst_pos = 0.0
earlier = 0
for r in rows:
    before = [s for s in setpoints if s[0] <= r["utc"]]
    if not before:
        check("a set-point logged at or before the poll at %s" % r["utc"], False)
        continue
    # The set-point of a time is taken at the first tick at or after it:
    # within a tick of its time a poll may still read the one before.
    candidates = before[-1:]
    if len(before) > 1 and seconds(r["utc"]) - seconds(before[-1][0]) < tick_s:
        candidates.append(before[-2])
    off = [(abs(float(r["zenith_deg"]) - zen), angle_diff(float(r["azimuth_deg"]), az), i)
           for i, (utc, zen, az) in enumerate(candidates)]
    dz, da, i = min(off, key=lambda o: max(o[0], o[1]))
    earlier += i
    utc, zen, az = candidates[i]
    worst_zen, worst_az = max(worst_zen, dz), max(worst_az, da)
    # The axes reach a new set-point within its tick.
    if seconds(r["utc"]) - seconds(utc) >= tick_s:
        dpe = abs((90.0 - float(r["zenith_deg"])) - float(r["el_deg"]))
        dpa = angle_diff(float(r["azimuth_deg"]), float(r["az_deg"]))
        worst_pos = max(worst_pos, dpe, dpa)
    if dz > 0.01 or da > 0.01:
        check("poll at %s: the target is the set-point of %s" % (r["utc"], utc), False,
              "zenith %s vs %s, azimuth %s vs %s" % (r["zenith_deg"], zen, r["azimuth_deg"], az))
    if r["mode"] != "tracking" or r["faults"] != "":
        check("poll at %s: tracking, no fault" % r["utc"], False, "%s %s" % (r["mode"], r["faults"]))
distinct = sorted({r["utc"] for r in rows})
check("each poll's target is the set-point logged last at or before its time, within 0.01 deg",
      worst_zen <= 0.01 and worst_az <= 0.01,
      "worst zenith %.4f, azimuth %.4f deg over %d polls (%s to %s), set-points %s"
      % (worst_zen, worst_az, len(rows), distinct[0] if distinct else "-",
         distinct[-1] if distinct else "-",
         ", ".join(sorted({s[0][11:19] for s in setpoints
                           if distinct and s[0] <= distinct[-1]})[-3:]))
      + ("; %d polls within a tick of a new set-point's time read the one before" % earlier
         if earlier else ""))
check("the position within a step of the target a tick after the set-point", worst_pos <= STEP_DEG, "worst %.3f deg" % worst_pos)
check("the site the GPS stream's (11.9683 N, 8.4261 E)",
      "site 11.9683 N 8.4261 E (gps)" in out)
statuses = [l for l in out.splitlines() if l.startswith("status ")]
check("model 305's fix in every poll, between GPS epochs too (10 s apart here)",
      statuses and all("lat=11.9683 lon=8.4261" in l for l in statuses),
      "%d of %d polls" % (sum("lat=11.9683 lon=8.4261" in l for l in statuses), len(statuses)))
print("%d checks failed" % len(failures) if failures else "all checks passed")
sys.exit(1 if failures else 0)
EOF
