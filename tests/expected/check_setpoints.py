#!/usr/bin/env python3
"""Checks the set-points of a firmware's expected output against pvlib.

Independent source: pvlib's NREL SPA (`pvlib.solarposition.spa_python`,
numpy), geometric zenith and azimuth (no refraction, as the firmware
prints), ΔT = 69.2 s, sea level.

A file is a firmware log (`suntracker::log`: the QEMU image's, and the
Uno image's from the emulator harness); its `setpoint utc=YYYY-MM-DDTHH:MM:SSZ
zenith= azimuth= c= a=` lines (the Uno's end with ` panel_mv=<whole mV>`) are
each checked at their utc (to the second):

  (zenith, azimuth) = pvlib's sun within 0.02° of angular distance
           (psa-2020's f32 bound 0.011° plus the 0.0005° print rounding)
  c, a     = the commanded pose (level mount): its panel normal n =
           Rz(γ)·Rx(α)·ẑ = (sin γ sin α, −cos γ sin α, cos α) in (west,
           south, up) lies within 0.027° of pvlib's sun (0.02° plus the
           0.005° print rounding of each angle)
  axes     = the one `axes utc=<that utc> c= a=` line (QEMU: where the
           simulated axes were when the set-point ended; Uno: the pose the
           emulator harness decodes from its encoder models' counts at the
           end of the set-point's slot) holds c and a within one axis step
           (`axis_step_deg=` of the file: the Uno's encoder count, 0.300°)
           plus 0.005° rounding

and the day is that of a `time source=… utc=` line.

The set-point times must cover pvlib's daylight at the file's step:
the first set-point is at most two steps after pvlib's sunrise, the last at
most one step from pvlib's sunset, consecutive set-points at most one step
apart, and the number of daylight set-points is at least the multiples of
the step inside pvlib's sunrise–sunset span less two (one per end; 178 for
2026-03-20 at Kano with 240 s) and at most that span's count plus one.

Strict format: a line holding `setpoint` or `zenith=`, or starting
`axes`, must parse completely, and the file must state the site and day
above, one `step_s=` and one `axis_step_deg=`; anything else fails the
file, so a changed log format cannot pass with nothing checked.

  python3 -m venv .venv && .venv/bin/pip install pvlib==0.16.1
  .venv/bin/python tests/expected/check_setpoints.py tests/expected/qemu_tracker.txt ...
  .venv/bin/python tests/expected/check_setpoints.py --self-test FILE...
      (doctored copies of each good FILE must each fail)
"""
import re
import sys

import numpy as np
import pandas as pd
from pvlib import solarposition

DAY = "2026-03-20"
LAT, LON, DELTA_T = 11.9683, 8.4261, 69.2
# The site and day every checked run must state (the inputs CI gives the
# images: the stored site or the GPS fix of tests/firmware, the RTC's or
# the GPS's day); a file of another site or day fails rather than being
# checked against the wrong sky.
SITE = "lat=11.9683 lon=8.4261"
STEP = re.compile(r"step_s=(\d+)\b")
# The firmware loop's log (src/log.rs) and the QEMU board's `axes` lines.
UTC = r"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)"
LOG_CANDIDATE = re.compile(r"\bsetpoint\b|zenith=|^axes")
# The Uno image (Chowdhury et al. 2019) ends each set-point with the panel
# voltage it read, ` panel_mv=<whole mV>` (`suntracker::log::setpoint_with_panel`).
LOG_SETPOINT = re.compile(rf"^setpoint utc={UTC} zenith=(-?\d+\.\d{{3}}) azimuth=(-?\d+\.\d{{3}}) "
                          r"c=(-?\d+\.\d\d) a=(-?\d+\.\d\d)(?: panel_mv=(?:0|[1-9]\d*))?$")
LOG_AXES = re.compile(rf"^axes utc={UTC} c=(-?\d+\.\d{{4}}) a=(-?\d+\.\d{{4}})$")
LOG_DAY = re.compile(rf"^time source=(?:gps|rtc) utc={DAY}T")
AXIS_STEP = re.compile(r"axis_step_deg=(\d+\.\d+)\b")


def is_log_format(text):
    return any(l.startswith("boot suntracker ") for l in text)


def sun(times):
    idx = pd.DatetimeIndex(times, tz="UTC")
    r = solarposition.spa_python(idx, LAT, LON, altitude=0, pressure=0, temperature=12,
                                 delta_t=DELTA_T, how="numpy")
    return r["zenith"].to_numpy(), r["azimuth"].to_numpy()


def angle_deg(z1, a1, z2, a2):
    z1, a1, z2, a2 = map(np.radians, (z1, a1, z2, a2))
    c = np.cos(z1) * np.cos(z2) + np.sin(z1) * np.sin(z2) * np.cos(a1 - a2)
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def level_normal(gamma, alpha):
    """(zenith, azimuth) of the panel normal of a level mount at pose (γ, α).

    Choi et al. (portable tracker) eq. 15–17: n = Rz(γ)·Rx(α)·ẑ = (sin γ sin α,
    −cos γ sin α, cos α) in the horizontal frame (west, south, up); azimuth
    east of north = atan2(east, north) = atan2(−x, −y).
    """
    g, a = np.radians(gamma), np.radians(alpha)
    x, y, zc = np.sin(g) * np.sin(a), -np.cos(g) * np.sin(a), np.cos(a)
    return float(np.degrees(np.arccos(np.clip(zc, -1, 1)))), float(np.degrees(np.arctan2(-x, -y)))


def daylight():
    """pvlib's daylight at minute resolution: (sunrise, sunset) minutes."""
    minutes = pd.date_range(f"{DAY}T00:00:00", periods=24 * 60, freq="min")
    zmin, _ = sun(minutes)
    up = minutes[zmin < 90.0]
    return up[0], up[-1]


def coverage_problems(sp_times, step_s):
    """The daylight set-point times must start at pvlib's sunrise, end at its
    sunset and be at most one step apart."""
    problems = []
    rise, set_ = daylight()
    step = pd.Timedelta(seconds=step_s)
    if sp_times:
        if not (rise - pd.Timedelta(minutes=1) <= sp_times[0] <= rise + 2 * step):
            problems.append(f"first set-point {sp_times[0]} vs pvlib sunrise {rise}")
        if not (set_ - step <= sp_times[-1] <= set_ + step):
            problems.append(f"last set-point {sp_times[-1]} vs pvlib sunset {set_}")
        gaps = [(a, b) for a, b in zip(sp_times, sp_times[1:]) if not pd.Timedelta(0) < b - a <= step]
        for a, b in gaps[:3]:
            problems.append(f"set-points {a.time()} then {b.time()}: not one step apart at most")
    return problems


def minimum_setpoints(step_s):
    """The least number of daylight set-points a run may print: the multiples
    of its step inside pvlib's sunrise–sunset span, less one at each end (the
    scheduler's own span may differ from pvlib's by up to a step)."""
    rise, set_ = daylight()
    day0 = pd.Timestamp(f"{DAY}T00:00:00")
    first = -(-int((rise - day0).total_seconds()) // step_s)
    last = int((set_ - day0).total_seconds()) // step_s
    return last - first + 1 - 2, last - first + 1


def check_log(path, text):
    """The checks of a firmware-loop log (see the module documentation)."""
    problems = []
    if not any(SITE in l for l in text if l.startswith("site ")):
        problems.append(f"no site line states '{SITE}'")
    if not any(LOG_DAY.match(l) for l in text):
        problems.append(f"no time line states the day {DAY}")
    steps = {int(m.group(1)) for l in text if (m := STEP.search(l))}
    axis_steps = {float(m.group(1)) for l in text if (m := AXIS_STEP.search(l))}
    if len(steps) != 1 or len(axis_steps) != 1:
        problems.append(f"expected one step_s=N and one axis_step_deg=X, found {sorted(steps)}, "
                        f"{sorted(axis_steps)}")
        return problems
    step_s, axis_step = steps.pop(), axis_steps.pop()
    rows, axes = [], {}
    for line in text:
        if not LOG_CANDIDATE.search(line):
            continue
        m = LOG_SETPOINT.match(line)
        x = LOG_AXES.match(line)
        if m:
            rows.append((line, m))
        elif x:
            if x.group(1) in axes:
                problems.append(f"second axes line for {x.group(1)}: {line!r}")
            axes[x.group(1)] = (float(x.group(2)), float(x.group(3)))
        else:
            problems.append(f"set-point line does not parse (changed format?): {line!r}")
    times = [pd.Timestamp(m.group(1).rstrip("Z")) for _, m in rows]
    zen, az = sun(times) if rows else ([], [])
    worst_sun = worst_normal = worst_axes = 0.0
    sp_times = []
    for (line, m), z, a, t in zip(rows, zen, az, times):
        if t.strftime("%Y-%m-%d") != DAY:
            problems.append(f"set-point of another day: {line!r}")
            continue
        sp_times.append(t)
        zf, af, c, al = (float(m.group(i)) for i in range(2, 6))
        d_sun = angle_deg(zf, af, z, a)
        d_normal = angle_deg(*level_normal(c, al), z, a)
        worst_sun, worst_normal = max(worst_sun, d_sun), max(worst_normal, d_normal)
        ok = d_sun <= 0.02 and d_normal <= 0.027
        pos = axes.pop(m.group(1), None)
        if pos is None:
            problems.append(f"no axes line for {line!r}")
            continue
        d_axes = max(abs(pos[0] - c), abs(pos[1] - al))
        worst_axes = max(worst_axes, d_axes)
        ok &= d_axes <= axis_step + 0.005 + 1e-9
        if not ok:
            problems.append(f"MISMATCH {line!r}: pvlib zenith {z:.4f} azimuth {a:.4f}, "
                            f"printed sun {d_sun:.4f}°, normal {d_normal:.4f}° off; axes at {pos}")
    for utc in list(axes)[:3]:
        problems.append(f"axes line without its set-point: {utc}")
    least, expected = minimum_setpoints(step_s)
    if not least <= len(sp_times) <= expected + 1:
        problems.append(f"{len(sp_times)} daylight set-points, expected {least}..{expected + 1} "
                        f"(pvlib daylight at step {step_s} s holds {expected})")
    problems += coverage_problems(sp_times, step_s)
    for p in problems:
        print(f"{path}: {p}")
    print(f"{path}: {len(rows)} setpoint lines (minimum {least}) checked against pvlib SPA: worst "
          f"printed sun {worst_sun:.4f}°, commanded normal {worst_normal:.4f}°, axes {worst_axes:.4f}° "
          f"from the pose; {len(problems)} problems")
    return problems


def check(path):
    """Returns the list of problems of one file (empty: it passes)."""
    text = open(path).read().splitlines()
    if not is_log_format(text):
        problems = ["not a firmware log (no 'boot suntracker' line)"]
        print(f"{path}: {problems[0]}")
        return problems
    return check_log(path, text)


def axis_step_of(text):
    """The `axis_step_deg=` a file states (0 when it states none)."""
    m = AXIS_STEP.search(text)
    return float(m.group(1)) if m else 0.0


def self_test(paths):
    """Doctored copies of good files must each fail; the files must pass."""
    import os
    import tempfile

    def sub_first(pattern, repl):
        return lambda t: re.sub(pattern, repl, t, count=1, flags=re.M)

    log_doctors = {
        "format change: 'setpoint' renamed 'set-point'": lambda t: t.replace("setpoint utc", "set-point utc"),
        "format change: 'zenith=' became 'zenith:' on one line": sub_first(r"zenith=", "zenith:"),
        "garbled number on one line": sub_first(r"(^setpoint .*) azimuth=\d+\.\d+", r"\1 azimuth=1.2.3"),
        "unknown field on one line": sub_first(r"^(setpoint .*)$", r"\1 speed=3"),
        "fields out of order on one line": sub_first(r"^setpoint (utc=\S+) (zenith=\S+)", r"setpoint \2 \1"),
        "panel voltage not a whole number on one line": sub_first(
            r"^(setpoint .*?)(?: panel_mv=\d+)?$", r"\1 panel_mv=7.5"),
        "azimuth 1° off on one line": lambda t: re.sub(
            r"^(setpoint utc=\S+T12:00:00Z zenith=\S+ azimuth=)(\d+)",
            lambda m: m.group(1) + str(int(m.group(2)) + 1), t, count=1, flags=re.M),
        "commanded c 0.1° off on one line": lambda t: re.sub(
            r"^(setpoint utc=\S+T12:00:00Z .* c=-?\d+\.)(\d)",
            lambda m: m.group(1) + str((int(m.group(2)) + 1) % 10), t, count=1, flags=re.M),
        # One axis step (the file's) and 0.1° more: out of tolerance
        # whatever the step (QEMU 0.018°, Uno 0.300°).
        "axes one axis step + 0.1° from the pose on one line": lambda t: re.sub(
            r"^(axes utc=\S+T12:00:00Z c=)(-?\d+\.\d+)",
            lambda m: m.group(1) + f"{float(m.group(2)) + axis_step_of(t) + 0.1:.4f}",
            t, count=1, flags=re.M),
        "one axes line dropped": sub_first(r"^axes utc=\S+T12:00:00Z .*\n", ""),
        "every other setpoint line dropped": lambda t: "\n".join(
            l for i, l in enumerate(t.splitlines())
            if not l.startswith("setpoint") or sum(x.startswith("setpoint") for x in t.splitlines()[:i]) % 2) + "\n",
        "set-points after 15:00 dropped": lambda t: "\n".join(
            l for l in t.splitlines() if not re.match(r"^(setpoint|axes) utc=\S+T1[5-9]:", l)) + "\n",
        "another site": lambda t: t.replace("lat=11.9683", "lat=12.9683"),
        "no step line": lambda t: re.sub(r"step_s=\d+", "step=?", t),
        "empty output": lambda t: "",
    }
    failures = 0
    with tempfile.TemporaryDirectory() as d:
        for path in paths:
            good = open(path).read()
            doctors_here = log_doctors
            if check(path):
                print(f"self-test: the undoctored {path} fails")
                failures += 1
            for name, doctor in doctors_here.items():
                bad = doctor(good)
                doctored = os.path.join(d, os.path.basename(path))
                with open(doctored, "w") as fh:
                    fh.write(bad)
                if bad == good:
                    print(f"self-test: {path}: '{name}' changed nothing (doctor out of date)")
                    failures += 1
                    continue
                import contextlib
                import io
                with contextlib.redirect_stdout(io.StringIO()):
                    problems = check(doctored)
                if problems:
                    print(f"self-test: red as it should: {path}: {name} -> {problems[0]}")
                else:
                    print(f"self-test: {path}: '{name}' was NOT caught")
                    failures += 1
    print(f"check_setpoints: self-test {'FAILED' if failures else 'passed'} ({failures} uncaught)")
    return failures == 0


if __name__ == "__main__":
    args = sys.argv[1:]
    if args[:1] == ["--self-test"]:
        sys.exit(0 if args[1:] and self_test(args[1:]) else 1)
    if not args:
        sys.exit("usage: check_setpoints.py [--self-test] FILE...")
    sys.exit(0 if all([not check(p) for p in args]) else 1)
