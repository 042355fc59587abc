#!/usr/bin/env python3
"""End to end: pysunspec2 reads and commands an image's Modbus server.

Two targets, one test:

* `qemu`: the qemu_tracker ELF under .ci/qemu_gps.py with `--modbus-pty`
  (Kano, the GPS stream of 2026-03-20 from 09:00 UTC, 472 m);
* `mega`: the ATmega2560 image (the board ELF a user flashes, 1:1) under
  `suntracker-emu --image mega --modbus-pty` (Kano, the harness's generated
  GPS fix, 480 m, an epoch a second, from 2026-03-20 09:00 UTC): its
  RS-485 port, USART2.

Each run waits in the log until the tracker tracks, then opens the
pseudo-terminal with the SunSpec Alliance's pysunspec2
(SunSpecModbusClientDeviceRTU, scan()); the harness paces the emulation to
the wall clock while it is open. Two runs, one after the other (an image
without a client attached runs unpaced, faster than the wall clock):

1. The default configuration (`modbus.write` 0): models 1, 601, 305 and
   64201 found; model 601's ElTrgt/AzTrgt (the set-point in force) against
   pvlib's NREL SPA at that set-point's time (the last `setpoint` line of the
   log at or before the instant model 601 says), within 0.05 deg; then, the
   client attached (the emulation paced to the wall clock), model 601 read
   again as soon as the log shows the next set-point, against SPA at the
   instant read (601's DtLoc/TmLoc), within 0.05 deg (the tracker steps to
   a new set-point each 4 minutes of its day table and holds it between:
   read later in a step, the target lags the sun by up to a step's motion,
   which is reported); the position within a step of the target; model 305
   the GPS stream's fix; the vendor model tracking. A write of
   GlblCtl=Manual gets exception 01 and changes nothing (no `mode manual`
   in the log, the axes where they were).
2. `set modbus.write 1` typed on the console at boot: a manual target and
   GlblCtl=Manual in one write move the axes there (ElPos/AzPos within
   0.05 deg of it) and the log says `mode manual`; a target below the
   horizon (out of the A axis's limits) gets exception 03 and nothing moves;
   GlblCtl=Automatic: tracking again; the vendor Stow: `mode command_stow`.

  python3 modbus/sunspec/sunspec_e2e.py qemu|mega ELF WORKDIR [HARNESS]

HARNESS: the suntracker-emu binary for `mega`.
"""
import datetime as dt
import os
import re
import signal
import subprocess
import sys
import time

import pandas as pd
import sunspec2.device
import sunspec2.modbus.client as client
from pvlib import solarposition

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
START = "2026-03-20T09:00:00Z"
LAT, LON = 11.9683, 8.4261
ADDRESS = 1
BAUD = 19200
SPA_TOL_DEG = 0.05


class Target:
    """What differs between the images: the harness, the identity, the
    GPS altitude, an axis step, how a run ends, how long a boot takes."""

    def __init__(self, name, elf, harness):
        self.name = name
        common = ["--start", START, "--minutes", "600", "--quiet"]
        if name == "qemu":
            self.cmd = [sys.executable, os.path.join(ROOT, ".ci", "qemu_gps.py"), elf, *common,
                        "--timeout", "600"]
            self.model = "mps2-an386"
            # The GPS stream's altitude (tests/firmware/gps_kano_2026-03-20.nmea).
            self.alt_m = 472
            # One step of the simulated axes (boards/mps2_an386/src/mount.rs),
            # with the map's 0.01 deg rounding.
            self.step_deg = 0.018 + 0.01
            self.boot_s = 120
            # The console is read from the first instant.
            self.type_at_min = "0"
        elif name == "mega":
            # A fix a second, as most receivers send them: model 305 shows a
            # fix only while it is fresh (the GPS reader's staleness).
            self.cmd = [harness, "--image", "mega", "--elf", elf, *common, "--gps-period-s", "1"]
            self.model = "mega2560"
            # The harness's generated Kano fix (emu/src/models/nmea.rs).
            self.alt_m = 480
            # One step of the stepper axes (10,000 full steps a turn), with
            # the map's rounding.
            self.step_deg = 0.036 + 0.01
            # Homing at 1:1 from the bench's power-on angles, then the first
            # set-point: some 6 emulated minutes, several times faster than
            # the wall clock unpaced.
            self.boot_s = 240
            # Bytes before the image turns its console's receiver on are
            # lost, as on a board: typed 3 emulated seconds after power-on.
            self.type_at_min = "0.05"
        else:
            raise SystemExit("target %r: want qemu or mega" % name)

    def text(self, line):
        """A log line's text: suntracker-emu's log prefixes `<utc> c=… a=… | `."""
        return line.split(" | ", 1)[1] if self.name == "mega" and " | " in line else line

    def ended(self, rc, lines, harness_out):
        """Whether the run ended as asked: QEMU's image writes `end` at the
        gate after SIGTERM; suntracker-emu stops at its next service and
        says so in its summary."""
        if self.name == "qemu":
            return any(l.startswith("end ") for l in lines)
        return rc == 0 and "stopped by a signal" in harness_out


T = None

failures = []
passed = []


def check(what, ok, detail=""):
    print("%-4s %s%s" % ("ok" if ok else "FAIL", what, (": " + detail) if detail else ""), flush=True)
    (passed if ok else failures).append(what)


def angle_diff(a, b):
    d = abs(a - b) % 360.0
    return min(d, 360.0 - d)


class Run:
    """One harness run with the Modbus pseudo-terminal."""

    def __init__(self, workdir, name, *args):
        self.log = os.path.join(workdir, name + ".log")
        self.tty = os.path.join(workdir, name + ".tty")
        # A log or link of an earlier run would be read as this one's.
        for old in (self.log, self.tty):
            if os.path.lexists(old):
                os.unlink(old)
        self.out = os.path.join(workdir, name + ".harness.txt")
        self.err = open(self.out, "w")
        cmd = [*T.cmd, "--log", self.log, "--modbus-pty", self.tty, *args]
        self.proc = subprocess.Popen(cmd, stdout=self.err, stderr=subprocess.STDOUT)
        self.dev = None

    def lines(self):
        try:
            with open(self.log, encoding="utf-8") as f:
                return [T.text(l) for l in f.read().splitlines()]
        except FileNotFoundError:
            return []

    def wait_for(self, pattern, timeout_s=None):
        timeout_s = T.boot_s if timeout_s is None else timeout_s
        rx = re.compile(pattern)
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            if any(rx.search(l) for l in self.lines()):
                return True
            if self.proc.poll() is not None:
                break
            time.sleep(0.2)
        return False

    def open(self):
        end = time.monotonic() + 30
        while not os.path.exists(self.tty) and time.monotonic() < end:
            time.sleep(0.1)
        self.dev = client.SunSpecModbusClientDeviceRTU(
            slave_id=ADDRESS, name=self.tty, baudrate=BAUD, timeout=2)
        self.dev.scan()
        return self.dev

    def stop(self):
        if self.dev is not None:
            self.dev.close()
        # The harness stops the image at its next gate (`end` line).
        self.proc.send_signal(signal.SIGTERM)
        rc = self.proc.wait(timeout=60)
        self.err.close()
        return rc

    def ended(self, rc):
        with open(self.out, encoding="utf-8", errors="replace") as f:
            return T.ended(rc, self.lines(), f.read())


def setpoint_before(lines, t):
    """The last `setpoint` line's UTC at or before `t`."""
    best = None
    for l in lines:
        m = re.match(r"^setpoint utc=(\S+)Z ", l)
        if m:
            u = dt.datetime.fromisoformat(m.group(1)).replace(tzinfo=dt.timezone.utc)
            if u <= t:
                best = u
    return best


def setpoint_after(lines, t):
    """The first `setpoint` line's UTC after `t`."""
    for l in lines:
        m = re.match(r"^setpoint utc=(\S+)Z ", l)
        if m:
            u = dt.datetime.fromisoformat(m.group(1)).replace(tzinfo=dt.timezone.utc)
            if u > t:
                return u
    return None


def spa(t):
    sp = solarposition.spa_python(pd.DatetimeIndex([t]), LAT, LON, altitude=0, pressure=0,
                                  temperature=12, delta_t=69.2, how="numpy")
    return 90.0 - float(sp["zenith"].iloc[0]), float(sp["azimuth"].iloc[0])


def read_instant(tc):
    d, t = tc.DtLoc.value, tc.TmLoc.value
    return dt.datetime.strptime(d + t, "%Y%m%d%H%M%S").replace(tzinfo=dt.timezone.utc)


def modbus_exception(fn):
    """The Modbus exception code `fn` raised (pysunspec2's text), or None."""
    try:
        fn()
    except Exception as e:  # pysunspec2 raises ModbusClientException("Modbus exception N")
        m = re.search(r"exception[^0-9]*(\d+)", str(e), re.I)
        return int(m.group(1)) if m else str(e)
    return None


def wait_position(tc, el, az, timeout_s=90):
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        tc.read()
        trk = tc.tracker[0]
        if (trk.ElPos.cvalue is not None and abs(trk.ElPos.cvalue - el) <= T.step_deg
                and angle_diff(trk.AzPos.cvalue, az) <= T.step_deg):
            return trk.ElPos.cvalue, trk.AzPos.cvalue
        time.sleep(0.5)
    return trk.ElPos.cvalue, trk.AzPos.cvalue


def run_read_only(run):
    try:
        check("run 1: the tracker tracks (log)", run.wait_for(r"^setpoint "))
        t0 = time.monotonic()
        dev = run.open()
        found = sorted(k for k in dev.models if isinstance(k, int))
        check("models found", found == [1, 305, 601, 64201], str(found))
        print("     scan took %.2f s" % (time.monotonic() - t0))
        common = dev.models[1][0]
        check("1 Mn, Md, DA", (common.Mn.value, common.Md.value, common.DA.value)
              == ("suntracker", T.model, ADDRESS),
              "%s %s %s" % (common.Mn.value, common.Md.value, common.DA.value))
        tc = dev.models[601][0]
        tc.read()
        trk = tc.tracker[0]
        t_read = read_instant(tc)
        el, az = trk.ElTrgt.cvalue, trk.AzTrgt.cvalue
        time.sleep(0.5)  # the log line of that set-point is written by now
        t_sp = setpoint_before(run.lines(), t_read)
        check("601 Typ Dual, GlblCtl Automatic", (tc.Typ.value, tc.GlblCtl.value) == (5, 0))
        if t_sp is None:
            check("a set-point before the instant read", False, str(t_read))
        else:
            sel, saz = spa(t_sp)
            de, da = abs(el - sel), angle_diff(az, saz)
            check("601 ElTrgt/AzTrgt vs pvlib SPA at the set-point's time within %.2f deg" % SPA_TOL_DEG,
                  de <= SPA_TOL_DEG and da <= SPA_TOL_DEG,
                  "read %s, set-point %s: El %.2f vs %.4f (%.4f), Az %.2f vs %.4f (%.4f)"
                  % (t_read.strftime("%H:%M:%S"), t_sp.strftime("%H:%M:%S"), el, sel, de, az, saz, da))
            iel, iaz = spa(t_read)
            print("     at the instant read (%s) SPA says El %.4f Az %.4f: the set-point differs by "
                  "%.3f / %.3f deg (the schedule's 4-minute step)"
                  % (t_read.strftime("%H:%M:%S"), iel, iaz, abs(el - iel), angle_diff(az, iaz)))
        pe, pa = trk.ElPos.cvalue, trk.AzPos.cvalue
        check("601 ElPos/AzPos at the target within a step",
              abs(pe - el) <= T.step_deg and angle_diff(pa, az) <= T.step_deg,
              "pos %.2f %.2f, target %.2f %.2f" % (pe, pa, el, az))
        # The next set-point, read as soon as the log shows it (a step is
        # 4 minutes: at most that long, paced to the wall clock).
        t_next, end = None, time.monotonic() + 300
        while t_next is None and time.monotonic() < end:
            time.sleep(0.1)
            t_next = setpoint_after(run.lines(), t_sp or t_read)
        if t_next is None:
            check("a new set-point within a step", False, "none after %s" % (t_sp or t_read))
        else:
            tc.read()
            t_now = read_instant(tc)
            trk = tc.tracker[0]
            nel, naz = trk.ElTrgt.cvalue, trk.AzTrgt.cvalue
            iel, iaz = spa(t_now)
            de, da = abs(nel - iel), angle_diff(naz, iaz)
            check("601 ElTrgt/AzTrgt vs pvlib SPA at the instant read within %.2f deg" % SPA_TOL_DEG,
                  de <= SPA_TOL_DEG and da <= SPA_TOL_DEG,
                  "set-point %s, read %s (%d s later): El %.2f vs %.4f (%.4f), Az %.2f vs %.4f (%.4f)"
                  % (t_next.strftime("%H:%M:%S"), t_now.strftime("%H:%M:%S"),
                     (t_now - t_next).total_seconds(), nel, iel, de, naz, iaz, da))
        gps = dev.models[305][0]
        check("305 Lat, Long, Alt (the stream's fix)",
              abs(gps.Lat.cvalue - LAT) < 1e-6 and abs(gps.Long.cvalue - LON) < 1e-6
              and gps.Alt.value == T.alt_m and gps.Date.value == t_read.strftime("%Y%m%d"),
              "%s %s %s %s %s" % (gps.Lat.cvalue, gps.Long.cvalue, gps.Alt.value, gps.Date.value, gps.Tm.value))
        v = dev.models[64201][0]
        check("64201 Mode tracking, no stow, no fault",
              (v.Mode.value, v.StowRsn.value, v.Flt.value) == (8, 0, 0),
              "%s %s %s" % (v.Mode.value, v.StowRsn.value, v.Flt.value))
        # Writes are off: exception 01, nothing moves.
        tc.GlblCtl.value = 1
        code = modbus_exception(tc.write)
        check("GlblCtl=Manual with writes off: exception 01", code == 1, str(code))
        time.sleep(2)
        tc.read()
        v.read()
        check("nothing changed: GlblCtl Automatic, Mode tracking",
              (tc.GlblCtl.value, v.Mode.value) == (0, 8), "%s %s" % (tc.GlblCtl.value, v.Mode.value))
    finally:
        rc = run.stop()
    lines = run.lines()
    check("run 1: no `mode manual` in the log", "mode manual" not in lines)
    check("run 1: ends when asked, exit 0", rc == 0 and run.ended(rc), "exit %s" % rc)


def run_writes(run):
    try:
        check("run 2: `ok modbus.write=1`", run.wait_for(r"^ok modbus\.write=1$"))
        check("run 2: the tracker tracks (log)", run.wait_for(r"^setpoint "))
        dev = run.open()
        tc = dev.models[601][0]
        tc.read()
        trk = tc.tracker[0]
        el0, az0 = trk.ElPos.cvalue, trk.AzPos.cvalue
        el, az = round(el0 + 8.0, 2), round((az0 - 8.0) % 360.0, 2)
        tc.GlblElCtl.cvalue = el
        tc.GlblAzCtl.cvalue = az
        tc.GlblCtl.value = 1
        code = modbus_exception(tc.write)
        check("GlblElCtl, GlblAzCtl, GlblCtl=Manual written", code is None, str(code))
        check("the log says `mode manual`", run.wait_for(r"^mode manual$", 30))
        pe, pa = wait_position(tc, el, az)
        check("the axes move there (ElPos/AzPos)",
              abs(pe - el) <= T.step_deg and angle_diff(pa, az) <= T.step_deg,
              "target %.2f %.2f from %.2f %.2f, now %.2f %.2f" % (el, az, el0, az0, pe, pa))
        v = dev.models[64201][0]
        v.read()
        check("601 GlblCtl Manual, 64201 Mode manual", (tc.GlblCtl.value, v.Mode.value) == (1, 4),
              "%s %s" % (tc.GlblCtl.value, v.Mode.value))
        # Below the horizon: out of the A axis's limits.
        tc.read()
        tc.GlblElCtl.cvalue = -80.0
        code = modbus_exception(tc.write)
        check("a target below the horizon: exception 03", code == 3, str(code))
        time.sleep(3)
        tc.read()
        trk = tc.tracker[0]
        check("nothing moved, the target kept",
              abs(trk.ElPos.cvalue - pe) <= 0.005 and angle_diff(trk.AzPos.cvalue, pa) <= 0.005
              and abs(tc.GlblElCtl.cvalue - el) <= 0.005,
              "pos %.2f %.2f, GlblElCtl %.2f" % (trk.ElPos.cvalue, trk.AzPos.cvalue, tc.GlblElCtl.cvalue))
        n_tracking = run.lines().count("mode tracking")
        tc.GlblCtl.value = 0
        code = modbus_exception(tc.write)
        check("GlblCtl=Automatic written", code is None, str(code))
        end = time.monotonic() + 60
        while time.monotonic() < end and run.lines().count("mode tracking") == n_tracking:
            time.sleep(0.5)
        check("tracking again (`mode tracking` after manual)", run.lines().count("mode tracking") > n_tracking)
        v.read()
        v.Stow.value = 1
        code = modbus_exception(v.write)
        check("64201 Stow=1 written", code is None, str(code))
        check("the log says `mode command_stow`", run.wait_for(r"^mode command_stow$", 30))
        v.read()
        check("64201 Mode command_stow, StowRsn command", (v.Mode.value, v.StowRsn.value) == (3, 2),
              "%s %s" % (v.Mode.value, v.StowRsn.value))
    finally:
        rc = run.stop()
    check("run 2: ends when asked", run.ended(rc), "exit %s" % rc)


def main():
    global T
    if len(sys.argv) not in (4, 5):
        raise SystemExit(__doc__)
    name, elf, workdir = sys.argv[1:4]
    T = Target(name, elf, sys.argv[4] if len(sys.argv) == 5 else None)
    os.makedirs(workdir, exist_ok=True)
    t0 = time.monotonic()
    # The vendor model's definition beside this script, then pysunspec2's own.
    sunspec2.device.set_model_defs_path([HERE] + sunspec2.device.get_model_defs_path())
    # One after the other: an image without a client runs unpaced, and the
    # first run waits up to a table step (4 minutes) with its client
    # attached, in which the second would run on to the evening.
    runs = [Run(workdir, "writes_off")]
    try:
        run_read_only(runs[0])
        runs.append(Run(workdir, "writes_on", "--type", T.type_at_min + ":set modbus.write 1"))
        run_writes(runs[1])
    finally:
        for r in runs:
            if r.proc.poll() is None:
                r.proc.kill()
    print("%s: %.1f s wall" % (name, time.monotonic() - t0))
    print("%d passed, %d failed%s" % (len(passed), len(failures),
                                      (": " + ", ".join(failures)) if failures else ""))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
