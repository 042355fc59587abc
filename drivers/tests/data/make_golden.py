#!/usr/bin/env python3
"""Writes the golden NMEA logs of this directory.

The sentence bodies below are written by hand to look like a u-blox M8/M9
multi-GNSS receiver near Seoul (37 deg 34.002' N, 126 deg 58.998' E).
Checksums are computed here, independently of the Rust code, as the XOR of
every character between '$' and '*', printed as two upper-case hex digits
(NMEA 0183). Faults are injected on purpose where the comments say so.

Run: python3 make_golden.py   (rewrites the .nmea files next to it)
"""
import functools
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def cs(body: str) -> str:
    return "%02X" % functools.reduce(lambda a, c: a ^ ord(c), body, 0)


def good(body: str) -> bytes:
    return ("$%s*%s\r\n" % (body, cs(body))).encode("ascii")


def bad_checksum(body: str) -> bytes:
    wrong = (int(cs(body), 16) ^ 0x01)
    return ("$%s*%02X\r\n" % (body, wrong)).encode("ascii")


lines = [
    # Cold start: nothing known yet.
    good("GPTXT,01,01,02,u-blox ag - www.u-blox.com"),
    good("GPRMC,,V,,,,,,,,,,N"),
    good("GPVTG,,,,,,,,,N"),
    good("GPGGA,,,,,,0,00,99.99,,,,,,"),
    good("GPGSA,A,1,,,,,,,,,,,,,99.99,99.99,99.99"),
    good("GPGLL,,,,,,V,N"),
    # Epoch 03:15:00: time and date known, no position (RMC V, GGA 0).
    good("GNRMC,031500.00,V,,,,,,,150624,,,N"),
    good("GNGGA,031500.00,,,,,0,03,25.3,,,,,,"),
    good("GPGSV,1,1,03,05,45,120,30,13,60,250,28,15,20,045,22"),
    # Epoch 03:15:01: first fix, GN talker, GPS quality 1, 8 satellites.
    good("GNRMC,031501.00,A,3734.00200,N,12658.99800,E,0.012,,150624,,,A"),
    good("GNVTG,,T,,M,0.012,N,0.022,K,A"),
    good("GNGGA,031501.00,3734.00200,N,12658.99800,E,1,08,1.02,38.5,M,18.3,M,,"),
    good("GNGSA,A,3,05,13,15,18,20,,,,,,,,1.85,1.02,1.54"),
    # Epoch 03:15:02: GP talker, DGPS quality 2, 10 satellites, moved north.
    good("GPRMC,031502.00,A,3734.00260,N,12658.99800,E,0.020,,150624,,,D"),
    good("GPGGA,031502.00,3734.00260,N,12658.99800,E,2,10,0.90,38.7,M,18.3,M,1.0,0000"),
    # Junk between epochs: a line without '$', a line too long for 82
    # characters, a line cut off by the next '$', a non-ASCII byte.
    b"garbage without a dollar sign\r\n",
    ("$GPTXT,01,01,02," + "X" * 80 + "*00\r\n").encode("ascii"),
    b"$GPGSV,3,1,12,05,45,12",
    good("GPTXT,01,01,02,ANTSTATUS=OK"),
    b"$GPTXT,01,01,02,caf\xc3\xa9*00\r\n",
    # Epoch 03:15:03: BeiDou-only talker.
    good("BDRMC,031503.00,A,3734.00300,N,12658.99700,E,0.010,,150624,,,A"),
    good("BDGGA,031503.00,3734.00300,N,12658.99700,E,1,07,1.20,38.9,M,18.3,M,,"),
    # Epoch 03:15:04: GLONASS talker.
    good("GLRMC,031504.00,A,3734.00300,N,12658.99600,E,0.010,,150624,,,A"),
    good("GLGGA,031504.00,3734.00300,N,12658.99600,E,1,06,1.30,39.0,M,18.3,M,,"),
    # Epoch 03:15:05: Galileo talker, but the RMC is corrupted (bad checksum):
    # the fix has the GGA position and altitude but no date-time.
    bad_checksum("GARMC,031505.00,A,3734.00300,N,12658.99500,E,0.010,,150624,,,A"),
    good("GAGGA,031505.00,3734.00300,N,12658.99500,E,1,05,1.40,39.1,M,18.3,M,,"),
    # Epoch 03:15:06: fix lost (RMC V, GGA 0): date-time only.
    good("GNRMC,031506.00,V,,,,,,,150624,,,N"),
    good("GNGGA,031506.00,,,,,0,02,30.0,,,,,,"),
    # Epoch 03:15:07: GGA with a malformed quality field (checksum right,
    # nmea cannot parse it), then a valid RMC: fix from RMC alone.
    good("GNGGA,031507.00,3734.00300,N,12658.99500,E,X,05,1.40,39.1,M,18.3,M,,"),
    good("GNRMC,031507.00,A,3734.00300,N,12658.99500,E,0.010,,150624,,,A"),
    # Southern/western hemisphere sentence pair (same receiver, spoofed
    # test signal): 33 deg 51.5' S, 151 deg 12.5' W, 23:59:59.50 on 31 Dec 2024.
    good("GPRMC,235959.50,A,3351.50000,S,15112.50000,W,0.0,,311224,,,A"),
    good("GPGGA,235959.50,3351.50000,S,15112.50000,W,1,09,0.80,-12.5,M,20.0,M,,"),
    # The log ends in the middle of a sentence.
    b"$GNRMC,000000.00,A,33",
]

with open(os.path.join(HERE, "gps_golden_mixed.nmea"), "wb") as f:
    f.write(b"".join(lines))


# gps_impossible.nmea: sentences with a right checksum whose content cannot
# be true, each alone in its epoch (its own time of day), between sentences
# that are possible but sit right at the limits. Each line is
# (possible?, body). tests/gps_golden.rs::impossible_log_* expects exactly the
# lines marked False to be rejected, and no position from them.
def gga(t, lat="3734.00300", ns="N", lon="12658.99500", ew="E", q="1",
        hdop="1.00", alt="39.0"):
    return "GPGGA,%s,%s,%s,%s,%s,%s,08,%s,%s,M,18.3,M,," % (
        t, lat, ns, lon, ew, q, hdop, alt)


def rmc(t, date="150624", lat="3734.00300", ns="N", lon="12658.99500",
        ew="E", speed="0.010", course=""):
    return "GPRMC,%s,A,%s,%s,%s,%s,%s,%s,%s,,,A" % (
        t, lat, ns, lon, ew, speed, course, date)


impossible = [
    (True, gga("031500.00")),                        # 0 reference epoch
    (False, gga("031501.00", lat="9100.00000")),     # 1 latitude 91 deg
    (False, gga("031502.00", lat="9000.50000")),     # 2 latitude 90 deg 0.5'
    (False, gga("031503.00", lon="20000.00000")),    # 3 longitude 200 deg
    (False, gga("031504.00", lon="18000.10000", ew="W")),  # 4 180 deg 0.1' W
    (False, gga("031505.00", lat="3760.00000")),     # 5 latitude minutes 60
    (False, gga("031506.00", lon="12699.50000")),    # 6 longitude minutes 99
    (False, gga("031507.00", ns="X")),               # 7 hemisphere X
    (False, gga("031508.00", lat="37nan")),          # 8 latitude minutes nan
    (False, gga("031509.00", lon="126inf")),         # 9 longitude minutes inf
    (False, gga("031510.00", alt="nan")),            # 10 altitude nan
    (False, gga("031511.00", alt="25000.0")),        # 11 altitude 25 km
    (False, gga("031512.00", alt="-600.0")),         # 12 altitude -600 m
    (False, gga("031513.00", hdop="NaN")),           # 13 HDOP NaN
    (False, gga("031514.00", lat="37-4.00300")),     # 14 negative minutes
    (False, gga("031515.00", lat="37.34e2")),        # 15 minutes with exponent
    (False, gga("240000.00")),                       # 16 hour 24
    (False, gga("036000.00")),                       # 17 minute 60
    (False, gga("235960.00")),                       # 18 leap second 60
    (False, gga("235961.00")),                       # 19 second 61
    (False, rmc("031520.00", date="310624")),        # 20 31 June
    (False, rmc("031521.00", date="290223")),        # 21 29 Feb 2023
    (False, rmc("031522.00", date="300224")),        # 22 30 Feb 2024
    (False, rmc("031523.00", date="151324")),        # 23 month 13
    (False, rmc("031524.00", date="150024")),        # 24 month 0
    (False, rmc("031525.00", date="000624")),        # 25 day 0
    (False, rmc("031526.00", speed="inf")),          # 26 speed inf
    (False, rmc("031527.00", course="-nan")),        # 27 course -nan
    (False, rmc("031528.00", lat="9500.00000", ns="S")),  # 28 latitude 95 S
    # Possible, at the limits: all must give a position.
    (True, gga("031530.00", lat="9000.00000")),      # 29 north pole
    (True, gga("031531.00", lon="18000.00000", ew="W")),  # 30 180 deg W
    (True, gga("031532.00", lat="3759.99999", alt="-500.0")),  # 31
    (True, gga("031533.00", alt="20000.0")),         # 32 20 km
    (True, rmc("235959.99", date="290224")),         # 33 29 Feb 2024
    (True, rmc("000000.00", date="010325", lat="0000.00000", ns="S",
               lon="00000.00000", ew="W")),          # 34 0 deg, 1 Mar 2025
]

with open(os.path.join(HERE, "gps_impossible.nmea"), "wb") as f:
    f.write(b"".join(good(body) for _, body in impossible))
