#!/usr/bin/env python3
"""Input CSV for examples/solar_position.rs: benchmark rows or edge cases.

    python3 examples/solar_position_support/make_rows.py --rows 1000000 > /tmp/rows_1m.csv
    python3 examples/solar_position_support/make_rows.py --rows 1000000 --edge > /tmp/rows_edge.csv

Default (benchmark) rows: `utc,latitude,longitude,delta_t` with instants
uniform in 2020-01-01 .. 2050-12-31 (inside the validity range of psa-2020
and spa), sites uniform on the globe's latitude/longitude box with 5
decimals, and delta_t 69.0..72.0 s. Deterministic for a given --seed.

--edge adds what the tool must treat exactly as before on every row: a
UTF-8 BOM, CRLF and bare CR line ends, blank and blank-looking lines,
quoted fields (commas, doubled quotes, line breaks), fields that are not
UTF-8, wrong field counts, bad numbers and dates, out-of-range sites and
years, empty delta_t, fractional seconds, extra columns, and sites and
instants picked near the poles, the antimeridian and the horizon so that
negative values and many rounding cases occur. Used to check that the
output of one build is byte-identical to another's.
"""

import argparse
import random
import sys

START_S = 1577836800  # 2020-01-01T00:00:00Z
END_S = 2556143999  # 2050-12-31T23:59:59Z


def utc(t: int) -> str:
    import datetime as dt

    return dt.datetime.fromtimestamp(t, dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def bench_rows(rng: random.Random, n: int):
    yield b"utc,latitude,longitude,delta_t\n"
    for _ in range(n):
        t = rng.randint(START_S, END_S)
        lat = rng.uniform(-90.0, 90.0)
        lon = rng.uniform(-180.0, 180.0)
        dt = rng.uniform(69.0, 72.0)
        yield f"{utc(t)},{lat:.5f},{lon:.5f},{dt:.1f}\n".encode()


def edge_row(rng: random.Random) -> bytes:
    t = rng.randint(START_S, END_S)
    lat = rng.choice([rng.uniform(-90, 90), rng.uniform(89, 90), rng.uniform(-90, -89), 0.0])
    lon = rng.choice([rng.uniform(-180, 180), rng.uniform(179, 180), rng.uniform(-180, -179), 0.0])
    dt = f"{rng.uniform(-100, 200):.3f}"
    u = utc(t)
    digits = rng.choice([0, 1, 3, 5, 9, 12])
    slat, slon = f"{lat:.{digits}f}", f"{lon:.{digits}f}"
    note = "n"
    kind = rng.randrange(40)
    line_end = b"\n"
    if kind == 0:
        return b"\n"  # blank line: skipped
    if kind == 1:
        return b"   \t \r\n"  # blank after trimming: skipped
    if kind == 2:
        line_end = b"\r\n"
    elif kind == 3:
        line_end = b"\r"
    elif kind == 4:
        note = '"Kano, NG ""roof"""'
    elif kind == 5:
        note = '"two\nlines, and\r\nthree"'
    elif kind == 6:
        slat = f'"{slat}"'
        u = f'"{u}"'
    elif kind == 7:
        return f"{u},{slat},{slon},{dt}\n".encode()  # one field short
    elif kind == 8:
        return f"{u},{slat},{slon},{dt},{note},extra\n".encode()
    elif kind == 9:
        return f"{u},{slat}".encode() + b"\xb0" + f",{slon},{dt},{note}\n".encode()
    elif kind == 10:
        return f"{u}".encode() + b"\xff\xfe" + f",{slat},{slon},{dt},{note}\n".encode()
    elif kind == 11:
        return f"{u},{slat},{slon},{dt},caf".encode() + b"\xe9\n"  # unread column
    elif kind == 12:
        slat = rng.choice(["91", "-90.5", "abc", "1e400", "nan", "inf", "", "4x"])
    elif kind == 13:
        slon = rng.choice(["181", "-180.0001", "-", "0x10", "", "NaN"])
    elif kind == 14:
        u = rng.choice([
            "2030-02-30T12:00:00Z", "2030-06-01T25:00:00Z", "not-a-date", "",
            "2060-06-01T12:00:00Z", "1999-12-31T23:59:59Z", "2030-06-01 12:00:00",
            "2030-06-01T12:00:00.25Z", "2030-06-01T12:00:00.Z", "-0001-01-01T00:00:00Z",
        ])
    elif kind == 15:
        dt = rng.choice(["", "NaN", "1e6", "-100000.5", "x", "  70.5  "])
    elif kind == 16:
        slat, slon = f"  {slat} ", f"\t{slon}"
    elif kind == 17:
        u = u[:-1] + f".{rng.randrange(1000):03d}Z"
    elif kind == 18:
        return f'{u},"{slat}"x,{slon},{dt},{note}\n'.encode()  # text after a closing quote
    elif kind == 19:
        return f'{u},{slat},{slon},{dt},ab"c\n'.encode()  # quote inside an unquoted field
    elif kind == 20:
        return f'{u},{slat},{slon},{dt},""""\n'.encode()
    elif kind == 21:
        return b",,,,\n"
    elif kind == 22:
        return b'""\n'  # one empty quoted field: blank, skipped
    return f"{u},{slat},{slon},{dt},{note}".encode() + line_end


def edge_rows(rng: random.Random, n: int):
    yield b"\xef\xbb\xbf\"utc\",latitude , longitude,delta_t,note\r\n"
    for _ in range(n):
        yield edge_row(rng)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--seed", type=int, default=20240601)
    ap.add_argument("--edge", action="store_true", help="edge cases for output comparisons")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    out = sys.stdout.buffer
    rows = edge_rows(rng, a.rows) if a.edge else bench_rows(rng, a.rows)
    buf = []
    for r in rows:
        buf.append(r)
        if len(buf) >= 10000:
            out.write(b"".join(buf))
            buf.clear()
    out.write(b"".join(buf))


if __name__ == "__main__":
    main()
