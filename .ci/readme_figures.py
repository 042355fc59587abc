#!/usr/bin/env python3
"""Every deterministic figure of the documentation (the book's chapters,
docs/src/*.md, and README.md), re-measured by the command that produces it
and compared with the text.

    python3 .ci/readme_figures.py              # check: exit 1 on any mismatch
    python3 .ci/readme_figures.py --print      # print the figures, check nothing
    FIGURES_ONLY=sizes,sim python3 .ci/readme_figures.py   # some groups only
    python3 .ci/readme_figures.py --list       # the groups and their commands
    FIGURES_LOG_DIR=/tmp/f python3 .ci/readme_figures.py   # keep each command's output

Each figure is (id, group, how to read it from the group's command output,
the text that must then appear in the documentation: README.md and every
docs/src/*.md, joined, so that a figure is found in whichever chapter holds
it). A group is one command, run
once for all its figures (the slow ones are shared). Output: one line per
figure, `ok|MISMATCH id value readme-text`. A figure that cannot be read
from its command's output (the command failed or its format changed) is a
MISMATCH too, never a silent pass. Whitespace (line wrapping) is collapsed
before comparing.

Assumes the firmware images are built (`.ci/budgets.sh` and
`.ci/avr_cycles.sh` run with NO_BUILD=1); host tests and examples are
built by cargo as needed. Timing figures (criterion ns per position, wall
times) are not deterministic and not checked here: the text names the run
that produced them. Host tools run with `--profile host` (the release
profile is the firmware's, size-optimised), as the text's commands say. Python 3 standard library only.
"""

import concurrent.futures
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
README = os.path.join(ROOT, "README.md")
BOOK_SRC = os.path.join(ROOT, "docs", "src")


def documentation():
    """README.md and the book's chapters (docs/src/*.md, sorted), joined."""
    paths = [README] + sorted(
        os.path.join(BOOK_SRC, n) for n in os.listdir(BOOK_SRC) if n.endswith(".md")
    )
    return "\n".join(open(p, encoding="utf-8").read() for p in paths)

# ---------------------------------------------------------------- commands

KANO = "--lat 11.9683 --lon 8.4261"
TROMSO = "--lat 69.65 --lon 18.96"
SIM = "cargo run -q --profile host --example simulate -- --start 2026-01-01 --days 365"
SIM_RUNS = {
    # id: (site, options)
    "kano_stepper_encoder": (KANO, "--drive stepper --feedback encoder --mount level"),
    "kano_servo_encoder": (KANO, "--drive servo --feedback encoder --mount level"),
    "kano_stepper_portable": (KANO, "--drive stepper --feedback sensors --mount portable"),
    "kano_stepper_encoder_faults": (KANO, "--drive stepper --feedback encoder --mount level --faults"),
    "kano_stepper_portable_faults": (KANO, "--drive stepper --feedback sensors --mount portable --faults"),
    "tromso_stepper_encoder": (TROMSO, "--drive stepper --feedback encoder --mount level"),
    "tromso_stepper_encoder_faults": (TROMSO, "--drive stepper --feedback encoder --mount level --faults"),
    "tromso_stepper_portable": (TROMSO, "--drive stepper --feedback sensors --mount portable"),
    "tromso_stepper_portable_faults": (TROMSO, "--drive stepper --feedback sensors --mount portable --faults"),
    "kano_dchall_encoder": (KANO, "--drive dc-hall --feedback encoder --mount level"),
    "kano_dchall_encoder_faults": (KANO, "--drive dc-hall --feedback encoder --mount level --faults"),
    "tromso_dchall_encoder_faults": (TROMSO, "--drive dc-hall --feedback encoder --mount level --faults"),
    "kano_timed_faults": (KANO, "--drive timed --mount level --faults"),
    "kano_timed_battery_faults": (KANO, "--drive timed --supply battery --mount level --faults"),
    "tromso_timed_faults": (TROMSO, "--drive timed --mount level --faults"),
    "kano_linearpot_faults": (KANO, "--drive linear-pot --feedback encoder --mount level --faults"),
    "tromso_linearpot_faults": (TROMSO, "--drive linear-pot --feedback encoder --mount level --faults"),
    "kano_linearhall_faults": (KANO, "--drive linear-hall --feedback encoder --mount level --faults"),
    "tromso_linearhall_faults": (TROMSO, "--drive linear-hall --feedback encoder --mount level --faults"),
}

# group -> shell command (run from the repository root, stdout + stderr).
COMMANDS = {
    "sizes": "NO_BUILD=1 bash .ci/budgets.sh",
    # The tables of docs/src/sizes.md (flash by crate, largest functions).
    "sizes_report": "python3 .ci/size_report.py",
    "cycles": "NO_BUILD=1 bash .ci/avr_cycles.sh",
    "accuracy": "cargo test -q -p sun_algos --release --test reference -- --nocapture --test-threads=1",
    "events": "cargo test -q -p sun_algos --release --test spa_nrel -- --nocapture --test-threads=1",
    "kano": "cargo test -q -p sun_algos --release --test geometry_kano --test geometry_kano_algorithms"
    " -- --nocapture --test-threads=1",
    "setpoints": "cargo run -q --profile host --example daily_setpoints -- --date 2018-10-19",
    "setpoints_csv": "cargo run -q --profile host --example daily_setpoints -- --date 2018-10-19 --format csv",
    "energy": "for d in 2016-03-21 2016-07-10 2016-12-15; do"
    " cargo run -q --profile host --example energy_gain -- --period day --date $d || exit 1; done;"
    " cargo run -q --profile host --example energy_gain -- --period year --date 2016-01-01",
    # A day of qemu_tracker (or the log CI already has: QEMU_DAY_LOG), its set-points
    # checked against pvlib (SUNTRACKER_PYTHON: a Python with pvlib).
    "qemu": "if [ -n \"${QEMU_DAY_LOG:-}\" ]; then T=$QEMU_DAY_LOG; else T=$(mktemp) &&"
    " timeout 900 cargo run -q --release --target thumbv7em-none-eabihf -p suntracker-mps2-an386"
    " --bin qemu_tracker -- --quiet --log \"$T\" || exit 1; fi;"
    " grep '^end ' \"$T\" && ${SUNTRACKER_PYTHON:-python3} tests/expected/check_setpoints.py \"$T\"",
    "gps_fuzz": "cargo test -q -p suntracker-drivers --release --test gps_fuzz -- --ignored --nocapture",
    "tracker_fuzz": "cargo test -q --release --test controller_fuzz -- --ignored --nocapture",
    "hw": "cargo test -q --release --test hw_stepper_day --test hw_servo_day --test hw_portable_day"
    " --test attitude -- --nocapture --test-threads=1",
    "wmm": "cargo test -q -p suntracker-drivers --release --test compass_wmm -- --nocapture --test-threads=1",
    "compact": "cargo test -q -p sun_algos --features compact-f32 --lib compact -- --nocapture --test-threads=1",
    "servo": "cargo test -q -p suntracker-drivers --release --test servo_closed_loop -- --nocapture --test-threads=1",
    "axis_property": "cargo test -q --release --test motion property -- --nocapture --test-threads=1",
    "postal": "grep -cE '^DZ,[0-9]{2}000,' data/postal_codes.csv",
    "panic": "NO_BUILD=1 bash .ci/panic_check.sh",
}
for _id, (_site, _opts) in SIM_RUNS.items():
    COMMANDS["sim_" + _id] = f"{SIM} {_site} {_opts}"
# A year at Kano with a sky of clear and overcast days, the overcast mode
# off and on.
COMMANDS["sim_weather_tracking"] = f"{SIM} {KANO} --weather"
COMMANDS["sim_weather_overcast"] = f"{SIM} {KANO} --weather --overcast-ratio 0.3"
# Three days of polar day at three sites: the C axis's unwinds.
POLAR_RUNS = {
    "tromso": "--lat 69.65 --lon 18.96 --start 2026-06-10",
    "longyearbyen": "--lat 78.22 --lon 15.65 --start 2026-06-10",
    "mcmurdo": "--lat -77.85 --lon 166.67 --start 2026-12-10",
}
for _id, _opts in POLAR_RUNS.items():
    COMMANDS["sim_polar_" + _id] = (
        f"cargo run -q --profile host --example simulate -- {_opts} --days 3"
    )

# What rewrites a group's figures in the documentation, where a command does
# (the others are edited by hand): said beside each mismatch.
REGENERATE = {"sizes_report": "python3 .ci/size_report.py --write"}

# FIGURES_ONLY names groups; a name stands for every group that starts with
# it (`sim` = the twenty-two simulation runs, `setpoints` = both set-point runs).
# A figure read from several groups runs only when all of them are selected.

# ---------------------------------------------------------------- helpers


class Unreadable(Exception):
    pass


def rx(out, pattern, flags=re.M):
    """The first match of pattern in out (its groups), or Unreadable."""
    m = re.search(pattern, out, flags)
    if not m:
        raise Unreadable(f"no match for /{pattern}/")
    return m


def thousands(n):
    return f"{n:,}"


# ---------------------------------------------------------------- figures
# A figure: (id, group, reader, template). reader(out) returns a dict of
# values; template.format(**values) must appear in the documentation.

FIGURES = []


def figure(fid, group, reader, template):
    FIGURES.append((fid, group, reader, template))


def regex_reader(pattern, **conv):
    """Named groups of pattern; conv maps a group name to a converter."""

    def read(out):
        m = rx(out, pattern)
        d = {}
        for k, v in m.groupdict().items():
            d[k] = conv[k](v) if k in conv else v
        return d

    return read


# --- sizes (.ci/budgets.sh): "image part flash budget ram budget verdict"
SIZE_IMAGES = []
for name, label, ram_fmt in [
    ("avr_tracker", "avr_tracker, ATmega328P", "{ram}"),
    ("avr_tracker_psa2020", "avr_tracker with `psa2020`, ATmega328P", "{ram}"),
    ("avr_tracker_ds1302", "avr_tracker with `ds1302`, ATmega328P", "{ram}"),
    ("avr_settings", "avr_settings, ATmega328P", "{ram}"),
    ("avr_settings_ds1302", "avr_settings with `ds1302`, ATmega328P", "{ram}"),
    ("uno_library_firmware", "example library_firmware, ATmega328P", "{ram}"),
    ("avr_mega_tracker", "avr_mega_tracker, ATmega2560", "{ram}"),
    ("avr_mega_tracker_dc", "avr_mega_tracker with `dc`, ATmega2560", "{ram}"),
    ("qemu_tracker", "qemu_tracker, Cortex-M4F", "{ram} + stack"),
    ("blackpill_tracker", "blackpill_tracker, STM32F411", "{ram} + stack"),
    ("blackpill_tracker_defmt", "blackpill_tracker with `defmt`, STM32F411", "{ram} + stack"),
    ("blackpill_tracker_modbus", "blackpill_tracker with `modbus`, STM32F411", "{ram} + stack"),
    ("blackpill_tracker_dc", "blackpill_tracker with `dc`, STM32F411", "{ram} + stack"),
]:
    SIZE_IMAGES.append(name)
    figure(
        f"size.{name}",
        "sizes",
        regex_reader(
            rf"^{name}\s.*\s(?P<flash>\d+)\s+(?P<fb>\d+)\s+(?P<ram>\d+)\s+(?P<rb>\d+)\s+ok\s*$",
            flash=lambda s: thousands(int(s)),
            fb=lambda s: thousands(int(s)),
            ram=lambda s: thousands(int(s)),
            rb=lambda s: thousands(int(s)),
        ),
        f"| {label} | {{flash}} ({{fb}}) | {ram_fmt} ({{rb}}) |",
    )
    # The README's table of boards: the images a user flashes.
    readme_images = {
        "avr_tracker": "`avr_tracker`",
        "avr_settings": "`avr_settings`",
        "avr_mega_tracker": "`avr_mega_tracker`",
        "avr_mega_tracker_dc": "`avr_mega_tracker` with `dc`",
        "blackpill_tracker": "`blackpill_tracker`",
        "blackpill_tracker_modbus": "`blackpill_tracker` with `modbus`",
        "blackpill_tracker_dc": "`blackpill_tracker` with `dc`",
        "qemu_tracker": "`qemu_tracker`",
    }
    if name in readme_images:
        figure(
            f"readme.size.{name}",
            "sizes",
            regex_reader(
                rf"^{name}\s.*\s(?P<flash>\d+)\s+(?P<fb>\d+)\s+(?P<ram>\d+)\s+(?P<rb>\d+)\s+ok\s*$",
                flash=lambda s: thousands(int(s)),
                fb=lambda s: thousands(int(s)),
                ram=lambda s: thousands(int(s)),
                rb=lambda s: thousands(int(s)),
            ),
            f"| {readme_images[name]} | {{flash}} ({{fb}}) / {ram_fmt} ({{rb}}) |",
        )




# --- sizes_report (.ci/size_report.py): the summary table, then one
# "### image" section per image, each a figure of its own
def report_part(name):
    def read(out):
        parts = re.split(r"^(?=### )", out, flags=re.M)
        if name is None:
            return {"part": parts[0].strip()}
        mine = [p for p in parts if p.startswith(f"### {name}\n")]
        if len(mine) != 1:
            raise Unreadable(f"{len(mine)} sections '### {name}' in the report")
        return {"part": mine[0].strip()}

    return read


figure("sizes_report.summary", "sizes_report", report_part(None), "{part}")
for name in SIZE_IMAGES:
    figure(f"sizes_report.{name}", "sizes_report", report_part(name), "{part}")


# --- cycles (.ci/avr_cycles.sh): the AVR table and QEMU's raw lines
def avr_row(algo):
    def read(out):
        m = rx(
            out,
            rf"^{re.escape(algo)}\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)/\s*(\d+)pt\s+(\d+)\s+ok\s*$",
        )
        mean, mx, full, full_ms, day, points, day_ms = (int(g) for g in m.groups())
        n = rx(out, r"^algorithm\s.*\s24h_(\d+)pts\s")
        return {
            "mean": thousands(mean),
            "max": thousands(mx),
            "day_mcycles": f"{day / 1e6:.2f}",
            "day_s": f"{day / 16e6:.2f}",
            "full_s": f"{full / 16e6:.2f}",
            "points": points,
            "full_points": int(n.group(1)),
            "max_ms": f"{mx / 16000:.2f}",
        }

    return read


def qemu_instr(algo):
    def read(out):
        # The Cortex-M4F table of .ci/avr_cycles.sh: "ALGO  instr/pos  budget
        # 24h_points  verdict", after its "Cortex-M4F (QEMU" heading.
        head = rx(out, r"^Cortex-M4F \(QEMU.*$")
        m = rx(out[head.end():], rf"^{re.escape(algo)}\s+(\d+)\s+\d+\s+\d+\s+ok\s*$")
        return {"instr": thousands(int(m.group(1)))}

    return read


def cycles_row(algo):
    def read(out):
        d = avr_row(algo)(out)
        d.update(qemu_instr(algo)(out))
        return d

    return read


figure("cycles.psa-2020", "cycles", cycles_row("psa-2020"),
       "| psa-2020 | {mean} ({max}) — budget 48,000 | {day_mcycles} M cycles = {day_s} s | {full_s} s | {instr} |")
figure("cycles.points", "cycles", avr_row("psa-2020"),
       "daylight table, {points} points | whole 24 h, {full_points} points |")
figure("cycles.slots", "cycles", avr_row("psa-2020"), "2026-06-21 ({points} of {full_points} slots)")
figure("cycles.psa-2020.ms", "cycles", avr_row("psa-2020"), "psa-2020 takes {max_ms} ms")
for algo in ["michalsky", "grena-2012-3"]:
    figure(f"cycles.{algo}", "cycles", cycles_row(algo),
           f"| {algo} | {{mean}} ({{max}}) | {{day_s}} s | {{full_s}} s | {{instr}} |")


# --- accuracy (sun_algos reference test): "NAME on TABLE:" then
# "NAME f64 rows N max X°  mean Y°" and the same for f32
def acc(algo, table, ty):
    def read(out):
        m = rx(
            out,
            rf"^{re.escape(algo)} on {re.escape(table)}:\n(?:.*\n){{0,3}}?{re.escape(algo)}\s+{ty}\s+rows\s+\d+\s+max ([0-9.]+)°",
        )
        return m.group(1)

    return read


def acc_row(cells):
    """cells: list of (algo, table) joined by ' / ' in each of the f64 and
    f32 columns."""

    def read(out):
        f64 = " / ".join(acc(a, t, "f64")(out) + "°" for a, t in cells)
        f32 = " / ".join(acc(a, t, "f32")(out) + "°" for a, t in cells)
        return {"f64": f64, "f32": f32}

    return read


S99, S10, S20 = "sun_1999_2022.csv", "sun_2010_2110.csv", "sun_2020_2050.csv"
figure("accuracy.spa", "accuracy", acc_row([("spa", S99), ("spa", S10), ("spa", S20)]),
       "| spa | sun_1999_2022 / 2010_2110 / 2020_2050 | {f64} | {f32} |")
figure("accuracy.psa-2020", "accuracy", acc_row([("psa-2020", S20)]), "| psa-2020 | sun_2020_2050 | {f64} | {f32} |")
figure("accuracy.psa-modified", "accuracy", acc_row([("psa-modified", S20)]),
       "| psa-modified | sun_2020_2050 | **{f64}** | {f32} |")
figure("accuracy.psa-2001", "accuracy", acc_row([("psa-2001", S99)]), "| psa-2001 | sun_1999_2022 | {f64} | {f32} |")
figure("accuracy.michalsky", "accuracy", acc_row([("michalsky", S99), ("michalsky", S20)]),
       "| michalsky | sun_1999_2022 / sun_2020_2050 | {f64} | {f32} |")
figure("accuracy.grena-2008", "accuracy", acc_row([("grena-2008", S99)]),
       "| grena-2008 | 2003–2022 rows of sun_1999_2022 | {f64} | {f32} |")


def grena2012(out):
    d = {}
    for ty in ["f64", "f32"]:
        d[ty] = ", ".join(acc(f"grena-2012-{i}", S10, ty)(out) + "°" for i in range(1, 6))
    return d


figure("accuracy.grena-2012", "accuracy", grena2012, "| grena-2012-1 … 5 | sun_2010_2110 | {f64} | {f32} |")
figure("accuracy.textbook", "accuracy", acc_row([("textbook", S20)]), "| textbook | sun_2020_2050 | {f64} | {f32} |")


def printed(out):
    # psa_modified_as_printed_is_far_off prints its stats without a header
    d = {}
    for ty in ["f64", "f32"]:
        d[ty] = rx(out, rf"^psa-modified-printed\s+{ty}\s+rows\s+\d+\s+max ([0-9.]+)°").group(1) + "°"
    return d


figure("accuracy.psa-modified-printed", "accuracy", printed,
       "| psa-modified-printed | sun_2020_2050 | {f64} | {f32} |")
figure("accuracy.psa-modified.text", "accuracy", lambda out: {"v": acc("psa-modified", S20, "f64")(out)},
       "measures {v}° on the file")
figure(
    "delta_t",
    "accuracy",
    regex_reader(r"^delta_t model vs tables: max \|diff\| (?P<a>[0-9.]+) s to 2024, (?P<b>[0-9.]+) s 2025-2050"),
    "within {a} s of the reference tables to 2024, {b} s to 2050",
)

# --- SPA events against NREL's printed example
figure(
    "spa.events",
    "events",
    regex_reader(
        r"^spa events f64 vs printed: sunrise (?P<r>[0-9.]+) s, transit (?P<t>[0-9.]+) s, sunset (?P<s>[0-9.]+) s"
    ),
    "sunrise {r} s, transit {t} s, sunset {s} s of the printed times",
)

# --- Kano geometry (Jimoh & Aliyu's (2019) equations and SPA at 10:00 / 14:00 solar time)
def minus(v):
    """The text's minus sign (U+2212) for a printed '-'."""
    return v.replace("-", "\u2212")


def kano_seed(out):
    m = rx(
        out,
        r"^kano paper eqs: 10:00 beta ([0-9.]+) gamma ([-+][0-9.]+), "
        r"14:00 beta ([0-9.]+) gamma ([-+][0-9.]+), 12:00 beta ([0-9.]+) deg",
    )
    b10, g10, b14, g14, b12 = m.groups()
    # eq 7/8: 10:00 and 14:00 are mirror images (same β, opposite γ)
    if b10 != b14 or g10.lstrip("+-") != g14.lstrip("+-") or g10[0] != "-" or g14[0] != "+":
        raise Unreadable(f"10:00 and 14:00 are not mirror images: {m.group(0)}")
    return {"b": b10, "g": g10.lstrip("+-"), "b12": b12}


figure("kano.seed", "kano", kano_seed, "Its own equations give β {b}°, γ ∓{g}°")
figure("kano.seed.noon", "kano", kano_seed, "at noon that gives β = |φ − δ| = {b12}°")


def kano_spa(out):
    a = rx(out, r"^kano spa: transit -7200 s beta ([0-9.]+) gamma ([-+][0-9.]+) deg")
    b = rx(out, r"^kano spa: transit \+7200 s beta ([0-9.]+) gamma ([-+][0-9.]+) deg")
    return {"b10": a.group(1), "g10": minus(a.group(2)), "b14": b.group(1), "g14": b.group(2)}


figure("kano.spa", "kano", kano_spa, "SPA (at its transit ∓ 2 h) gives β {b10}°, γ {g10}° / β {b14}°, γ {g14}°")


# --- daily_setpoints: the book's example lines appear in its output
def out_line(pattern):
    return lambda out: {"line": rx(out, pattern).group(0).rstrip()}


for fid, pat in [
    ("header", r"^Set-points for Kano .*$"),
    ("sunrise", r"^Sunrise .*$"),
    ("transit", r"^Transit .*$"),
    ("sunset", r"^Sunset .*$"),
    ("daylight", r"^Daylight .*$"),
    ("row0520", r"^05:20:00 .*$"),
    ("row0524", r"^05:24:00 .*$"),
    ("row0912", r"^09:12:00 .*$"),
]:
    figure(f"setpoints.{fid}", "setpoints", out_line(pat), "\n{line}\n")
figure("setpoints.csv", "setpoints_csv", out_line(r"^2018-10-19T05:20:00Z,.*$"), "\n{line}\n")


# --- energy_gain, Doha: three days and the year
def energy(out):
    d = {}
    pct = r"([-+][0-9.]+ %)"
    for key, label in [("mar", "2016-03-21"), ("jul", "2016-07-10"), ("dec", "2016-12-15"), ("year", "total")]:
        m = rx(out, rf"^{label}\s+[0-9.]+\s+[0-9.]+\s+[0-9.]+\s+{pct}\s+{pct}\s*$")
        d[key], d[key + "_s"] = m.group(1), m.group(2)
    return d


figure(
    "energy.doha",
    "energy",
    energy,
    "dual-axis over fixed {mar} (2016-03-21), {jul} (07-10), {dec} (12-15), {year} over 2016; "
    "over a horizontal N–S single axis {mar_s}, {jul_s}, {dec_s}, {year_s} (from:",
)


# --- simulation table
SIM_LABELS = {
    "kano_stepper_encoder": "Kano, stepper, encoder, level",
    "kano_servo_encoder": "Kano, servo, encoder, level",
    "kano_stepper_portable": "Kano, stepper, compass + inclinometer, portable",
    "kano_stepper_encoder_faults": "Kano, stepper, encoder, level, `--faults`",
    "kano_stepper_portable_faults": "Kano, stepper, sensors, portable, `--faults`",
    "tromso_stepper_encoder": "Tromsø, stepper, encoder, level",
    "tromso_stepper_encoder_faults": "Tromsø, stepper, encoder, level, `--faults`",
    "tromso_stepper_portable": "Tromsø, stepper, sensors, portable",
    "tromso_stepper_portable_faults": "Tromsø, stepper, sensors, portable, `--faults`",
    "kano_dchall_encoder": "Kano, DC gear motor + Hall, level",
    "kano_dchall_encoder_faults": "Kano, DC gear motor + Hall, level, `--faults`",
    "tromso_dchall_encoder_faults": "Tromsø, DC gear motor + Hall, level, `--faults`",
    "kano_timed_faults": "Kano, DC gear motor timed (no feedback), level, `--faults`",
    "kano_timed_battery_faults": "Kano, DC gear motor timed, battery, level, `--faults`",
    "tromso_timed_faults": "Tromsø, DC gear motor timed (no feedback), level, `--faults`",
    "kano_linearpot_faults": "Kano, A axis LA12 + potentiometer, level, `--faults`",
    "tromso_linearpot_faults": "Tromsø, A axis LA12 + potentiometer, level, `--faults`",
    "kano_linearhall_faults": "Kano, A axis dual-Hall actuator, level, `--faults`",
    "tromso_linearhall_faults": "Tromsø, A axis dual-Hall actuator, level, `--faults`",
}
SIM_LAST = (
    r"^simulate: pointing_p95_deg=(?P<p95>[0-9.]+) energy_vs_ideal=(?P<ideal>[0-9.]+) "
    r"energy_vs_fixed=(?P<fixed>[0-9.]+) faults_raised=(?P<raised>\d+) "
    r"faults_unrecovered=(?P<unrec>\d+) panics=0\s*$"
)
for sid, label in SIM_LABELS.items():
    figure(f"sim.{sid}", "sim_" + sid, regex_reader(SIM_LAST),
           f"| {label} | {{p95}}° | {{ideal}} | {{fixed}} | {{raised}} / {{unrec}} |")


SIM_FAULTS = r"^faults: raised \d+, recovered \d+, still active \d+, injected events (\d+)\s*$"


# --- the drive kinds over a year with faults: travel and recoveries too
SIM_TRAVEL = r"^motor travel: C axis (?P<c>\d+) deg, A axis (?P<a>\d+) deg\s*$"
SIM_RECOVERED = r"^faults: raised (?P<raised>\d+), recovered (?P<rec>\d+), still active \d+"


def sim_drive_row(out):
    last, travel, faults = rx(out, SIM_LAST), rx(out, SIM_TRAVEL), rx(out, SIM_RECOVERED)
    return {
        "p95": last["p95"], "ideal": last["ideal"],
        "c": thousands(int(travel["c"])), "a": thousands(int(travel["a"])),
        "raised": faults["raised"], "rec": faults["rec"],
    }


for sid, label in [
    ("kano_stepper_encoder_faults", "Kano, stepper"),
    ("kano_dchall_encoder_faults", "Kano, DC gear motor + Hall"),
    ("kano_timed_faults", "Kano, DC gear motor timed"),
    ("kano_timed_battery_faults", "Kano, DC gear motor timed, battery"),
    ("tromso_stepper_encoder_faults", "Tromsø, stepper"),
    ("tromso_dchall_encoder_faults", "Tromsø, DC gear motor + Hall"),
    ("tromso_timed_faults", "Tromsø, DC gear motor timed"),
    ("kano_linearpot_faults", "Kano, A axis LA12 + potentiometer"),
    ("tromso_linearpot_faults", "Tromsø, A axis LA12 + potentiometer"),
    ("kano_linearhall_faults", "Kano, A axis dual-Hall actuator"),
    ("tromso_linearhall_faults", "Tromsø, A axis dual-Hall actuator"),
]:
    figure(f"sim.drive.{sid}", "sim_" + sid, sim_drive_row,
           f"| {label} | {{p95}}° | {{ideal}} | {{c}}° / {{a}}° | {{raised}} / {{rec}} |")


# --- the polar days: unwinds, the sun's elevation at each, tracking off
SIM_UNWIND = (
    r"^unwind: (?P<n>\d+) swings \(sun elevation at each: (?P<elev>[^)]*) deg\); "
    r"minutes tracking more than 1 deg off the sun: (?P<off>\d+); C axis (?P<cday>\d+) deg a day\s*$"
)


def sim_polar_row(out):
    u, last = rx(out, SIM_UNWIND), rx(out, SIM_LAST)
    return {
        "n": u["n"], "elev": u["elev"].replace(", ", " / "), "off": u["off"],
        "cday": u["cday"], "ideal": last["ideal"],
    }


for sid, label in [
    ("tromso", "Tromsø 69.65° N, 10–12 June"),
    ("longyearbyen", "Longyearbyen 78.22° N, 10–12 June"),
    ("mcmurdo", "McMurdo 77.85° S, 10–12 December"),
]:
    figure(f"sim.polar.{sid}", "sim_polar_" + sid, sim_polar_row,
           f"| {label} | {{n}} | {{elev}}° | {{off}} | {{cday}}° | {{ideal}} |")


SIM_WEATHER = (
    r"^weather: (?P<days>\d+) overcast days of \d+; energy with diffuse light (?P<e>[0-9.]+) kWh/m2; "
    r"overcast mode (?P<h>[0-9.]+) h; motor moves per day (?P<moves>\d+)\s*$"
)
for sid, label in [("tracking", "tracking always"), ("overcast", "`overcast.ratio` 0.3")]:
    figure(f"sim.weather.{sid}", "sim_weather_" + sid, regex_reader(SIM_WEATHER),
           f"| Kano 2026, {label} | {{days}} | {{e}} kWh/m² | {{h}} h | {{moves}} |")


def sim_faults(kano, tromso):
    k, t = rx(kano, SIM_LAST), rx(tromso, SIM_LAST)
    ik, it = rx(kano, SIM_FAULTS).group(1), rx(tromso, SIM_FAULTS).group(1)
    return {
        "events": ik if ik == it else f"{ik} / {it}",
        "rk": k["raised"], "rt": t["raised"], "uk": k["unrec"], "ut": t["unrec"],
        "pk": k["p95"], "pt": t["p95"],
    }


figure(
    "sim.faults_summary",
    ("sim_kano_stepper_encoder_faults", "sim_tromso_stepper_encoder_faults"),
    sim_faults,
    "| {events} injected events each | 0 panics, {rk} / {rt} faults raised, {uk} / {ut} unrecovered; "
    "pointing p95 {pk}° / {pt}° |",
)


# --- a --faults year's modes: minutes in each and times entered, at Kano
# and Tromsø (one table), and the weather days of the schedule
SIM_MODES = r"^modes \(minutes / entries\): (?P<modes>.*?)\s*$"


def sim_modes(kano, tromso):
    def parse(out):
        items = [m.rsplit(" ", 3) for m in rx(out, SIM_MODES)["modes"].split(", ")]
        return {name: (int(minutes), int(entries)) for name, minutes, _, entries in items}

    k, t = parse(kano), parse(tromso)
    if list(k) != list(t):
        raise Unreadable("the two runs list different modes")
    rows = [
        f"| {name} | {thousands(k[name][0])} | {k[name][1]} | {thousands(t[name][0])} | {t[name][1]} |"
        for name in k
    ]
    return {"rows": "\n".join(rows)}


figure(
    "sim.faults_modes",
    ("sim_kano_stepper_encoder_faults", "sim_tromso_stepper_encoder_faults"),
    sim_modes,
    "| mode | Kano: minutes | entries | Tromsø: minutes | entries |\n|---|---|---|---|---|\n{rows}",
)

SIM_WEATHER_DAYS = (
    r"^weather days \(--faults\): (?P<days>snow .* overcast \d+ days); for the run supply.stow_mv "
    r"(?P<stow>\d+), supply.resume_mv (?P<resume>\d+), overcast.ratio (?P<ratio>[0-9.]+)\s*$"
)
figure(
    "sim.faults_weather_days",
    "sim_kano_stepper_encoder_faults",
    regex_reader(SIM_WEATHER_DAYS, stow=lambda s: thousands(int(s)), resume=lambda s: thousands(int(s))),
    "`weather days (--faults): {days}` (the same at both sites); `supply.stow_mv` {stow}, "
    "`supply.resume_mv` {resume}, `overcast.ratio` {ratio}",
)


# --- QEMU day summary
def qemu_day(out):
    end = rx(out, r"^end ms=\d+ ticks=\d+ setpoints=(?P<n>\d+) faults_active=(?P<faults>\d+) ")
    chk = rx(out, r"^\S+: (?P<n>\d+) setpoint lines \(minimum \d+\) checked against pvlib SPA: worst printed sun "
                  r"(?P<sun>[0-9.]+)°, commanded normal (?P<normal>[0-9.]+)°, axes (?P<axes>[0-9.]+)° from the pose; "
                  r"0 problems$")
    if end.group("n") != chk.group("n"):
        raise Unreadable(f"qemu: {end.group('n')} set-points in the end line, {chk.group('n')} checked")
    return {"n": chk.group("n"), "normal": chk.group("normal"), "axes": chk.group("axes"),
            "faults": end.group("faults")}


figure(
    "qemu.day",
    "qemu",
    qemu_day,
    "({n} set-points; commanded panel normal at most {normal}° from NREL SPA (pvlib), simulated axes within "
    "{axes}° of the commanded pose when each set-point ended; {faults} faults active at the end)",
)


# --- fuzz
def tracker_fuzz(out):
    m = rx(out, r"^Figures \{(.*)\}\s*$")
    fields = dict(re.findall(r"(\w+): (\d+)", m.group(1)))
    need = ["ticks", "clock_steps", "gale_ticks"]
    for k in need:
        if k not in fields:
            raise Unreadable(f"tracker_fuzz: no field {k} in {m.group(0)[:200]}")
    return {k: thousands(int(v)) for k, v in fields.items()}


figure("fuzz.tracker", "tracker_fuzz", tracker_fuzz,
       "40 runs × 20,000 ticks = {ticks} ticks, {clock_steps} wall-clock steps, {gale_ticks} gale ticks")


def gps_fuzz(out):
    m = rx(
        out,
        r"^gps_fuzz: (?P<streams>\d+) streams fuzzed, (?P<sentences>\d+) sentences .*?"
        r"(?P<imp>\d+) impossible sentences injected, (?P<rej>\d+) of them rejected, .*?"
        r"(?P<wrong>\d+) wrong fixes accepted",
    )
    d = {k: int(v) for k, v in m.groupdict().items()}
    if d["rej"] != d["imp"] or d["wrong"] != 0:
        raise Unreadable(f"gps_fuzz: {m.group(0)}")
    return {k: thousands(v) for k, v in d.items()}


figure("fuzz.gps.prose", "gps_fuzz", gps_fuzz, "{streams} random and mutated streams with checksum-valid impossible")
figure("fuzz.gps", "gps_fuzz", gps_fuzz,
       "| {streams} streams, {sentences} sentences, {imp} checksum-valid impossible sentences |")

# --- f32 against f64: the two columns of the accuracy table
def f32_vs_f64(out):
    pairs = re.findall(r"^(\S+)\s+f64\s+rows\s+\d+\s+max ([0-9.]+)°.*\n\1\s+f32\s+rows\s+\d+\s+max ([0-9.]+)°", out, re.M)
    if len(pairs) < 15:
        raise Unreadable(f"only {len(pairs)} f64/f32 pairs in the accuracy output")
    worst = max(abs(float(a) - float(b)) for name, a, b in pairs if name != "psa-modified-printed")
    if worst > 0.0001:
        raise Unreadable(f"f32 and f64 maxima differ by {worst:.5f}° > 0.0001°")
    return {"bound": "0.0001", "worst": f"{worst:.5f}"}


figure("accuracy.f32_vs_f64", "accuracy", f32_vs_f64, "its maximum errors stay within {bound}° of `f64`'s")


# --- whole-controller tests on mock buses, attitude
def hw(out):
    day = rx(out, r"^ticks=\d+ homing_ticks=\d+ entries=(\d+) applied=(\d+) .*max_err_deg=([0-9.]+)")
    if day.group(1) != day.group(2):
        raise Unreadable(f"hw day: entries {day.group(1)} != applied {day.group(2)}")
    servo = rx(out, r"^servo day: entries=(\d+) applied=(\d+) max_err_deg=([0-9.]+)")
    port = rx(out, r"^portable day: entries=(\d+) applied=(\d+) max_err_deg=([0-9.]+)")
    return {
        "n": day.group(1),
        "day": f"{float(day.group(3)):.3f}",
        "servo": f"{float(servo.group(3)):.3f}",
        "portable": f"{float(port.group(3)):.3f}",
    }


figure("hw.day", "hw", hw, "all {n} set-points applied with at most {day}° pointing error against NREL SPA")
figure("hw.servo_portable", "hw", hw, "Servo/encoder axes in closed loop: {servo}°")
figure("hw.portable", "hw", hw, "QMC5883L bus bytes: {portable}°")


def attitude(out):
    m = rx(out, r"^case 1: Pose \{ gamma_deg: ([-0-9.e]+), alpha_deg: ([-0-9.e]+) \} Pose \{ gamma_deg: ([-0-9.e]+), alpha_deg: ([-0-9.e]+) \}")
    g, a1, a2 = float(m.group(1)), float(m.group(2)), float(m.group(4))
    if a1 * a2 >= 0:
        raise Unreadable("case 1: the two alpha do not have opposite signs")
    p = rx(out, r"^property test: worst pointing error ([0-9.e+-]+) deg over (\d+) cases")
    return {
        "gamma": f"{g:.2f}",
        "alpha": f"{abs(a1):.2f}" if f"{abs(a1):.2f}" == f"{abs(a2):.2f}" else f"{abs(a1):.2f}/{abs(a2):.2f}",
        "worst": f"{float(p.group(1)):.1e}",
        "cases": thousands(int(p.group(2))).replace(",", " "),
    }


figure("attitude.case1", "hw", attitude, "Table IV Case 1 gives γ {gamma}°, α ∓{alpha}°")
figure("attitude.property", "hw", attitude, "{cases} random attitudes and sun directions point the panel normal at the sun within {worst}°")

figure(
    "wmm",
    "wmm",
    regex_reader(r"^WMM2025 worst \|D - official\| = (?P<d>[0-9.]+) deg"),
    "within {d}° of NOAA's published test values",
)
figure(
    "wmm.f32",
    "wmm",
    regex_reader(r"^WMM2025 in f32: worst component error [0-9.]+ nT, \|D - official\| (?P<d>[0-9.]+) deg"),
    "in `f32`, as the 8-bit boards run it, within {d}°",
)


def compact(out):
    # a bound: the book's "within 2 ulp" holds while sin and cos stay <= 2
    m = rx(out, r"^\|x\| <= 6\.3: sin ([0-9.]+) ulp, cos ([0-9.]+) ulp")
    worst = max(float(m.group(1)), float(m.group(2)))
    return {"ulp": "2" if worst <= 2.0 else f"{worst:.2f}"}


figure("compact.sin_cos", "compact", compact, "routines (within {ulp} ulp on |x| ≤ 2π, the bound asserted by")


def servo(out):
    # a bound: the book's "within one count" holds while every error is <= 1
    m = rx(out, r"^300 ppr final errors \(counts\): \[([-0-9, ]+)\]")
    worst = max(abs(int(v)) for v in m.group(1).split(","))
    return {"n": "one" if worst <= 1 else str(worst)}


figure("servo.counts", "servo", servo, "within {n} encoder count on a simulated FS5106R (300 pulses/rev)")


def axis_property(out):
    m = rx(out, r"^property: (\d+) configs, (\d+) homing steps, \d+ homings done, (\d+) updates")
    return {
        "configs": thousands(int(m.group(1))),
        "homing": f"{int(m.group(2)) / 1e6:.2f} M",
        "updates": thousands(int(m.group(3))),
    }


figure("axis.property", "axis_property", axis_property,
       "{configs} configurations with every range end, {homing} homing steps and {updates} updates")
figure("axis.property.table", "axis_property", axis_property, "| {configs} valid configurations |")

figure("postal.wilaya", "postal", regex_reader(r"^(?P<n>\d+)\s*$"), "Algeria's {n} wilaya seats")

def panic(out):
    def sites(image):
        return rx(out, rf"^{image}\s+(\d+)\s+0\s+\d+\s+0\s+ok\s*$").group(1)

    return {"q": sites("qemu_tracker"), "b": sites("blackpill_tracker")}


figure("panic.cortex_m", "panic", panic, "The Cortex-M images have {q} (QEMU) and {b} (STM32F411) sites")


# --------------------------------------------------------------- machinery


def collapse(text):
    return re.sub(r"\s+", " ", text)


def brief(text, limit=240):
    """A long figure (a whole table) cut for the log."""
    return text if len(text) <= limit else text[:limit] + f" … ({len(text)} characters)"


def cleaned(out):
    """A command's output without simavr's and the terminal's colours, and
    without the progress dots `cargo test -q` prints on the line where a
    test's own output starts."""
    out = re.sub(r"\x1b\[[0-9;]*m", "", out)
    return re.sub(r"^\.+(?=\S)", "", out, flags=re.M)


def run(group):
    t0 = time.time()
    # A group's output this run already has (FIGURES_FROM/<group>.txt: CI's
    # own fuzz and cycle runs), read rather than run again.
    kept = os.path.join(os.environ.get("FIGURES_FROM") or "", group + ".txt")
    if os.environ.get("FIGURES_FROM") and os.path.isfile(kept):
        with open(kept, encoding="utf-8", errors="replace") as f:
            return group, 0, cleaned(f.read()), time.time() - t0
    p = subprocess.run(
        COMMANDS[group],
        shell=True,
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        executable="/bin/bash",
    )
    return group, p.returncode, cleaned(p.stdout.decode("utf-8", "replace")), time.time() - t0


def groups_of(fig):
    g = fig[1]
    return list(g) if isinstance(g, tuple) else [g]


def selected(groups_env):
    if not groups_env:
        return list(FIGURES)
    wanted = [g.strip() for g in groups_env.split(",") if g.strip()]
    unknown = [w for w in wanted if not any(c.startswith(w) for c in COMMANDS)]
    if unknown:
        raise SystemExit(f"readme_figures: no group {', '.join(unknown)} (see --list)")
    return [f for f in FIGURES if all(any(g.startswith(w) for w in wanted) for g in groups_of(f))]


def main(argv):
    print_only = "--print" in argv
    if "--list" in argv:
        for g, c in COMMANDS.items():
            print(f"{g}: {c}")
        return 0
    figs = selected(os.environ.get("FIGURES_ONLY", ""))
    if not figs:
        print("readme_figures: no figure selected", file=sys.stderr)
        return 2
    groups = sorted({g for f in figs for g in groups_of(f)}, key=list(COMMANDS).index)
    jobs = int(os.environ.get("FIGURES_JOBS", "2"))
    outputs = {}
    t0 = time.time()
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        for group, rc, out, secs in pool.map(run, groups):
            outputs[group] = (rc, out)
            if os.environ.get("FIGURES_LOG_DIR"):
                with open(os.path.join(os.environ["FIGURES_LOG_DIR"], group + ".txt"), "w", encoding="utf-8") as f:
                    f.write(out)
            print(f"# {group}: exit {rc}, {secs:.1f} s: {COMMANDS[group]}", file=sys.stderr)
    readme = collapse(documentation())
    bad = 0
    for fid, group, reader, template in figs:
        gs = groups_of((fid, group))
        rcs = [outputs[g][0] for g in gs]
        outs = [outputs[g][1] for g in gs]
        rc = max(rcs, key=abs)
        try:
            if rc != 0:
                raise Unreadable(f"command exited {rc}")
            values = reader(*outs)
            if not isinstance(values, dict):
                values = {"v": values}
            text = template.format(**values)
            value = " ".join(f"{k}={v}" for k, v in values.items())
        except (Unreadable, KeyError, ValueError) as e:
            bad += 1
            print(f"MISMATCH {fid} <unreadable: {e}> {template!r}", flush=True)
            for g, r, o in zip(gs, rcs, outs):
                if r != 0:
                    tail = "\n".join(o.splitlines()[-15:])
                    print(f"  last lines of `{COMMANDS[g]}`:\n{tail}", file=sys.stderr)
            continue
        shown = brief(collapse(text).strip())
        value = brief(collapse(value))
        if print_only:
            print(f"{fid} {value} {shown}", flush=True)
            continue
        if collapse(text) in readme:
            print(f"ok {fid} {value} {shown}", flush=True)
        else:
            bad += 1
            print(f"MISMATCH {fid} {value} {shown}", flush=True)
            # a figure of several lines (a table): the lines the text lacks
            lines = [ln for ln in text.splitlines() if ln.strip()]
            if len(lines) > 1:
                for ln in [ln for ln in lines if collapse(ln).strip() not in readme][:5]:
                    print(f"  not in the documentation: {ln}", flush=True)
            for g in gs:
                if g in REGENERATE:
                    print(f"  regenerate with: {REGENERATE[g]}", flush=True)
    print(
        f"readme_figures: {len(figs)} figures from {len(groups)} commands, "
        f"{bad} mismatched or unreadable, {time.time() - t0:.0f} s",
        file=sys.stderr,
    )
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
