#!/usr/bin/env python3
"""The rows of a solar_position input through pvlib's spa_python (numpy).

    python3 -m venv /tmp/pvlib-venv && /tmp/pvlib-venv/bin/pip install pvlib
    /tmp/pvlib-venv/bin/python examples/solar_position_support/pvlib_spa.py \\
        /tmp/rows_1m.csv /tmp/pvlib_out.csv [--compare ours_spa.csv]

Reads `utc,latitude,longitude,delta_t` (the benchmark rows of make_rows.py:
every row valid), computes pvlib.solarposition.spa_python(how="numpy") with
each row's site and delta_t (geometric: pvlib's `zenith` column, no
refraction; elevation 0 m, as solar_position's sites), writes
`utc,latitude,longitude,zenith,azimuth` with 9 decimals, and prints the
seconds spent reading, computing and writing and the rows per second. With
--compare, also the largest zenith and azimuth differences from a
solar_position output of the same rows (`--algorithm spa --float f64`).
"""

import argparse
import sys
import time

import numpy as np
import pandas as pd
import pvlib


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--compare", help="solar_position output of the same rows")
    a = ap.parse_args()

    t0 = time.perf_counter()
    df = pd.read_csv(a.input, dtype={"utc": str, "latitude": str, "longitude": str})
    times = pd.DatetimeIndex(pd.to_datetime(df["utc"], format="%Y-%m-%dT%H:%M:%SZ", utc=True))
    lat = df["latitude"].astype(float).to_numpy()
    lon = df["longitude"].astype(float).to_numpy()
    delta_t = df["delta_t"].astype(float).to_numpy()
    t1 = time.perf_counter()
    pos = pvlib.solarposition.spa_python(times, lat, lon, delta_t=delta_t, how="numpy")
    t2 = time.perf_counter()
    out = pd.DataFrame({
        "utc": df["utc"],
        "latitude": df["latitude"],
        "longitude": df["longitude"],
        "zenith": pos["zenith"].to_numpy(),
        "azimuth": pos["azimuth"].to_numpy(),
    })
    out.to_csv(a.output, index=False, float_format="%.9f")
    t3 = time.perf_counter()

    n = len(df)
    print(f"pvlib {pvlib.__version__} spa_python(how='numpy'), numpy {np.__version__}, "
          f"pandas {pd.__version__}: {n} rows")
    print(f"read {t1 - t0:.2f} s, compute {t2 - t1:.2f} s, write {t3 - t2:.2f} s, "
          f"total {t3 - t0:.2f} s")
    print(f"rows/s: compute only {n / (t2 - t1):,.0f}, end to end {n / (t3 - t0):,.0f}")

    if a.compare:
        ours = pd.read_csv(a.compare, dtype={"utc": str, "latitude": str, "longitude": str})
        if len(ours) != n or not (ours["utc"].to_numpy() == df["utc"].to_numpy()).all():
            sys.exit("--compare: not the same rows")
        dz = np.abs(ours["zenith"].to_numpy() - pos["zenith"].to_numpy())
        da = np.abs(ours["azimuth"].to_numpy() - pos["azimuth"].to_numpy())
        da = np.minimum(da, 360.0 - da)
        print(f"largest difference from {a.compare}: zenith {dz.max():.3e} deg, "
              f"azimuth {da.max():.3e} deg (rows with zenith < 89.9 deg: "
              f"{da[pos['zenith'].to_numpy() < 89.9].max():.3e})")


if __name__ == "__main__":
    main()
