#!/usr/bin/env python3
"""Checks the set-points of a firmware's expected output against pvlib.

Independent source: pvlib's NREL SPA (`pvlib.solarposition.spa_python`,
numpy), geometric zenith and azimuth (no refraction, as the firmware
prints), ΔT = 69.2 s, sea level. Every `HH:MM set-point` / `home` line
of the file is recomputed at that minute of the file's day and site:

  (slope, az) = the sun's direction (zenith, azimuth) within 0.08° of
           angular distance (0.011°, the f32 bound of psa-2020 in issue 3,
           plus up to 0.05° of print rounding on each angle)
  home   = the morning's first set-point
  servo_us (Uno) = 500 + angle·2000/180 µs, within 1.5 µs
  steps (Mega)   = angle·10000/360 steps, within 2 steps
  target=γ,α (QEMU, level mount) = a pose whose panel normal (seed
           portable-tracker eq. 15–17) lies within 0.03° of pvlib's sun
  err (QEMU) = the angle between pvlib's sun and the normal of the printed
           axis positions, within 0.02° (0.011° + print rounding); `night`
           only with pvlib's sun down

and the set-point times must cover pvlib's daylight at the file's step:
the first set-point is at most two steps after pvlib's sunrise and the last
at most one step from pvlib's sunset (the scheduler's table holds the
multiples of its step inside its own sunrise–sunset span).

  python3 -m venv .venv && .venv/bin/pip install pvlib
  .venv/bin/python tests/expected/check_setpoints.py tests/expected/avr_tracker.txt ...
"""
import re
import sys

import numpy as np
import pandas as pd
from pvlib import solarposition

DAY = "2026-03-20"
LAT, LON, DELTA_T = 11.9683, 8.4261, 69.2
LINE = re.compile(r"^(\d\d):(\d\d) (set-point|home) slope=(-?[\d.]+) az=(-?[\d.]+)(.*)$")
STEP = re.compile(r"step_s=(\d+)")


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

    Seed portable-tracker eq. 15–17: n = Rz(γ)·Rx(α)·ẑ = (sin γ sin α,
    −cos γ sin α, cos α) in the horizontal frame (west, south, up); azimuth
    east of north = atan2(east, north) = atan2(−x, −y).
    """
    g, a = np.radians(gamma), np.radians(alpha)
    x, y, zc = np.sin(g) * np.sin(a), -np.cos(g) * np.sin(a), np.cos(a)
    return float(np.degrees(np.arccos(np.clip(zc, -1, 1)))), float(np.degrees(np.arctan2(-x, -y)))


def check(path):
    text = open(path).read().splitlines()
    step_s = next((int(m.group(1)) for l in text if (m := STEP.search(l))), 240)
    rows = [(l, m) for l in text if (m := LINE.match(l))]
    times = [pd.Timestamp(f"{DAY}T{m.group(1)}:{m.group(2)}:00") for _, m in rows]
    zen, az = sun(times)
    bad, first, sp_times = 0, None, []
    for (line, m), z, a, t in zip(rows, zen, az, times):
        kind, slope, azi, rest = m.group(3), float(m.group(4)), float(m.group(5)), m.group(6)
        if kind == "home":
            ok = first is not None and (slope, azi) == first
        else:
            if first is None:
                if slope == 0.0 and azi == 0.0:  # power-on zero set-point (seed step 1)
                    continue
                first = (slope, azi)
            sp_times.append(t)
            ok = angle_deg(slope, azi, z, a) <= 0.08
        if (s := re.search(r"servo_us=(\d+),(\d+)", rest)):
            ok &= abs(int(s.group(1)) - (500 + slope * 2000 / 180)) <= 1.5 + 0.6
            ok &= abs(int(s.group(2)) - (500 + (azi - 90) * 2000 / 180)) <= 1.5 + 0.6
        if (s := re.search(r"target=(-?[\d.]+),(-?[\d.]+) axes=(-?[\d.]+),(-?[\d.]+) err=([\d.]+|night)", rest)):
            g_t, a_t, g_x, a_x = (float(s.group(i)) for i in range(1, 5))
            if kind == "set-point" and (slope, azi) != (0.0, 0.0):
                # the commanded pose faces pvlib's sun (f32 bound + 0.005° rounding per axis)
                ok &= angle_deg(*level_normal(g_t, a_t), z, a) <= 0.03
            if s.group(5) == "night":
                ok &= z >= 89.9
            else:
                # the firmware's pointing error, recomputed from its axis positions
                err = angle_deg(*level_normal(g_x, a_x), z, a)
                ok &= z < 90.1 and abs(float(s.group(5)) - err) <= 0.02
        if (s := re.search(r"steps=(-?\d+),(-?\d+)", rest)):
            ok &= abs(int(s.group(1)) - slope * 10000 / 360) <= 2 + 1.4
            ok &= abs(int(s.group(2)) - azi * 10000 / 360) <= 2 + 1.4
        if not ok:
            bad += 1
            print(f"{path}: MISMATCH {line!r}: pvlib zenith {z:.4f} azimuth {a:.4f}")
    # daylight coverage at minute resolution
    minutes = pd.date_range(f"{DAY}T00:00:00", periods=24 * 60, freq="min")
    zmin, _ = sun(minutes)
    up = minutes[zmin < 90.0]
    if sp_times:
        step = pd.Timedelta(seconds=step_s)
        if not (up[0] - pd.Timedelta(minutes=1) <= sp_times[0] <= up[0] + 2 * step):
            bad += 1
            print(f"{path}: first set-point {sp_times[0]} vs pvlib sunrise {up[0]}")
        if not (up[-1] - step <= sp_times[-1] <= up[-1] + step):
            bad += 1
            print(f"{path}: last set-point {sp_times[-1]} vs pvlib sunset {up[-1]}")
    print(f"{path}: {len(rows)} set-point lines checked against pvlib SPA, {bad} mismatches")
    return bad == 0


if __name__ == "__main__":
    sys.exit(0 if all([check(p) for p in sys.argv[1:]]) else 1)
