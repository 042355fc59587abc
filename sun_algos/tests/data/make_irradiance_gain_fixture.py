#!/usr/bin/env python3
"""Clear-sky daily energy on three mounts in Doha, for
sun_algos/tests/geometry_irradiance.rs, computed with pvlib and numpy:

    python3 sun_algos/tests/data/make_irradiance_gain_fixture.py > sun_algos/tests/data/doha_clear_sky_energy_pvlib.csv

The quantity is the one `geometry::irradiance::clear_sky_day_energy_wh_m2`
documents, recomputed here without this repository's code:

- sun: pvlib's NREL SPA (`solarposition.spa_python`), geometric topocentric
  zenith and azimuth (the test asks `Algorithm::Spa` with default options:
  no refraction, sea level, ΔT from the IERS/USNO observed values on
  1 January, 2016: 68.10 s, 2017: 68.59 s, interpolated to the date);
- clear sky: the ASHRAE clear-day model with Masters' sinusoidal fits
  (G. M. Masters, Renewable and Efficient Electric Power Systems, 2004,
  §7.8): A = 1160 + 75 sin(360/365 (n − 275)) W/m², k = 0.174 + 0.035
  sin(360/365 (n − 100)), C = 0.095 + 0.04 sin(360/365 (n − 100)), with n
  the UTC day of year of each sample; DNI = A exp(−k m), DHI = C·DNI,
  GHI = DNI cos z + DHI; air mass m from pvlib
  (`atmosphere.get_relative_airmass`, Kasten & Young 1989); nothing with
  the sun's centre at or below the horizon;
- plane of array: pvlib `irradiance.get_total_irradiance`, isotropic sky,
  albedo 0.2 (beam DNI·max(cos θ, 0) with θ from pvlib `irradiance.aoi`,
  sky DHI (1 + cos β)/2, ground GHI·ρ (1 − cos β)/2);
- mounts: fixed at latitude tilt facing south (tilt 25.37463°, azimuth
  180°); one horizontal north-south axis, ±90°, no backtracking (pvlib
  `tracking.singleaxis`); dual axis (tilt = zenith, azimuth = azimuth);
- energy: the trapezoid rule over 289 samples every 300 s from local mean
  midnight (UTC midnight − longitude × 240 s, rounded to the second), Wh/m².

Site and days: the Doha site of Chowdhury et al. (2019) (25.37463 N,
51.49128 E) and its three simulation days of 2016. Written with pvlib 0.16.1.
"""
import sys

import numpy as np
import pandas as pd
import pvlib

LAT, LON = 25.37463, 51.49128
DAYS = [(3, 21), (7, 10), (12, 15)]
ALBEDO = 0.2
STEP_S = 300


def delta_t_s(t):
    start = pd.Timestamp("2016-01-01T00:00:00Z")
    frac = (t - start) / (pd.Timestamp("2017-01-01T00:00:00Z") - start)
    return 68.10 + (68.59 - 68.10) * frac


def day_energy(month, day):
    midnight = pd.Timestamp(f"2016-{month:02d}-{day:02d}T00:00:00Z")
    start = midnight - pd.Timedelta(seconds=round(LON * 240.0))
    times = start + pd.to_timedelta(np.arange(0, 86_400 + 1, STEP_S), unit="s")
    sp = pvlib.solarposition.spa_python(
        times, LAT, LON, altitude=0.0, delta_t=delta_t_s(start + pd.Timedelta(hours=12))
    )
    zen = sp["zenith"].to_numpy()
    azi = sp["azimuth"].to_numpy()
    n = times.day_of_year.to_numpy().astype(float)
    w = np.radians(360.0 / 365.0)
    a = 1160.0 + 75.0 * np.sin(w * (n - 275.0))
    k = 0.174 + 0.035 * np.sin(w * (n - 100.0))
    c = 0.095 + 0.04 * np.sin(w * (n - 100.0))
    up = zen < 90.0
    am = pvlib.atmosphere.get_relative_airmass(np.where(up, zen, 0.0), "kastenyoung1989")
    dni = np.where(up, a * np.exp(-k * am), 0.0)
    dhi = c * dni
    ghi = dni * np.maximum(np.cos(np.radians(zen)), 0.0) + dhi

    single = pvlib.tracking.singleaxis(
        np.where(up, zen, 0.0), azi, axis_tilt=0, axis_azimuth=0, max_angle=90, backtrack=False
    )
    mounts = {
        "fixed": (np.full_like(zen, LAT), np.full_like(zen, 180.0)),
        "single": (
            np.nan_to_num(np.asarray(single["surface_tilt"], dtype=float)),
            np.nan_to_num(np.asarray(single["surface_azimuth"], dtype=float), nan=90.0),
        ),
        "dual": (zen, azi),
    }
    out = {}
    for name, (tilt, saz) in mounts.items():
        # pvlib takes acos of cos θ: a few 1e-7° where θ is 0.
        aoi = pvlib.irradiance.aoi(tilt, saz, zen, azi)
        assert name != "dual" or np.all(np.abs(aoi[up]) < 1e-5)
        poa = pvlib.irradiance.get_total_irradiance(
            tilt, saz, zen, azi, dni, ghi, dhi, albedo=ALBEDO, model="isotropic"
        )["poa_global"]
        poa = np.where(up, np.nan_to_num(poa), 0.0)
        out[name] = np.sum((poa[1:] + poa[:-1]) * 0.5 * STEP_S) / 3600.0
    return out


def main():
    sys.stdout.write("date,fixed_wh_m2,single_wh_m2,dual_wh_m2\n")
    for m, d in DAYS:
        e = day_energy(m, d)
        sys.stdout.write(
            f"2016-{m:02d}-{d:02d},{e['fixed']:.4f},{e['single']:.4f},{e['dual']:.4f}\n"
        )


if __name__ == "__main__":
    main()
