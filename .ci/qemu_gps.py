#!/usr/bin/env python3
"""Runs a suntracker image in QEMU mps2-an386 with a GPS on UART0, paced by
the guest's emulated time.

QEMU runs with `-icount shift=5,sleep=off`: 32 ns of emulated time per
instruction (about the an386's 25 MHz), and idle time (`wfi`) skipped, so an
emulated day passes in a minute or two of wall time, decoupled from the host.
The host cannot see when the guest's clock moves, so the image asks
(boards/mps2_an386/src/lib.rs, "the gate"): once per controller tick (10 emulated
seconds) it stops its clocks, writes `T<monotonic ms>` on UART1 and waits for
an answer there. This script then writes the NMEA epoch of that instant
(UTC = the stream's first time + ms) into UART0, and the console lines due
into UART2, and answers with the number of bytes (`<gps>` or
`<gps>,<console>`; `stop` once `--minutes` have passed); the image waits
until the bytes are in and restarts its clocks. The image then exits through
semihosting with its status, which is this script's exit status (2 for a
usage error, 3 when QEMU ended without the image's `end` line or timed
out).

The NMEA: each epoch is the first GGA and RMC of `--nmea FILE` (default
tests/firmware/gps_kano_2026-03-20.nmea) with their time (and RMC date)
re-stamped: the file's first time plus the emulated time, or `--start` plus
it. `--no-gps` keeps UART0 silent. A recorded stream with the week-rollover
bug keeps its wrong date running on the same way.

`--move MINUTE:LAT,LON` (repeatable): from that emulated minute the epochs
report that position instead of the stream's (a receiver carried away, or
one whose position jumps). `--time-lie MINUTE:SECONDS`: from that emulated
minute the epochs' time is off by +SECONDS and -SECONDS in turn (a receiver
whose time alternates).

The console: `--type MINUTE:LINE` (repeatable) types LINE and a newline
into UART2 (QEMU's third `-serial`, the image's console) at the first gate
at or after that emulated minute (fractions allowed), lines of one minute
in the order given. The gate's answer then also counts them (`<gps>,<console>`)
and the image waits until they are in its console ring before its clock
runs on, so a typed line takes effect at the same emulated instant in every
run. At most CONSOLE_RING_LEN bytes (the image's console ring) go in at one
gate; whole lines beyond that wait for the next gate.

The configuration file: QEMU runs in a fresh temporary directory, where the
image keeps its stored configuration (`suntracker-config.bin`, semihosting
file I/O), so every run starts with none (`config source=defaults`) unless
`--config-file PATH` names a file to use instead (created when missing,
kept after the run): a later run on the same file boots with what an
earlier one saved (`config source=stored`).

The Modbus port: `--modbus-pty PATH` connects the image's RS-485 port
(UART3, QEMU's fourth `-serial`) to a new pseudo-terminal, symlinked at PATH,
for a Modbus RTU master (pysunspec2, mbpoll, a SCADA) to open. While a
client holds the terminal open (no hang-up on its master side) the script
paces the emulation to the wall clock: it answers each gate with a third
number and a fourth, `<gps>,<console>,<pace ms>,<modbus>`, and the image then gates every
`--modbus-pace-ms` emulated ms (default 20) instead of every 10 s and never
sleeps in `wfi` between them; the answer to a gate waits until as much wall
time has passed since pacing began as emulated time has, so the emulated
clock runs at most one pace ahead of the wall's and a master's time-outs
(hundreds of ms) mean what they say. Meanwhile the GPS epoch still goes in
every 10 emulated s, at the first gate at or after it. The client's
requests go into UART3 at the gates too (`<modbus>` bytes, which the image
waits for as for the others): QEMU's UART hands the guest each byte when
its main loop gets round to it, so bytes fed while the clock runs may lie
further apart in emulated time than the 1.5 characters that end an RTU
frame; put in while the clock stands still, a request's bytes arrive at one
instant, and the silence after them ends the frame (a request waits for the
next gate: at most one pace). The replies go out as the image writes them. Without a client (or
without the option) the run is not paced and the answers are as before.
SIGTERM or SIGINT ends a run at its next gate (the `stop` answer: the image
writes its `end` line), for a run whose length the client decides.

The log (semihosting output, QEMU's stdout here) is printed and, with
`--log OUT`, written to OUT (line by line, flushed).

  python3 .ci/qemu_gps.py ELF [--nmea FILE | --no-gps] [--start UTC]
                          [--minutes N] [--type MINUTE:LINE]...
                          [--move MINUTE:LAT,LON]... [--time-lie MINUTE:SECONDS]
                          [--config-file PATH] [--log OUT] [--quiet]
                          [--timeout S] [--modbus-pty PATH [--modbus-pace-ms MS]]

Any ELF that does not gate (qemu_bench) just runs to its exit.
"""
import argparse
import datetime as dt
import os
import select
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import tty

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_NMEA = os.path.join(ROOT, "tests", "firmware", "gps_kano_2026-03-20.nmea")
# The image's console receive ring (CONSOLE_RING_LEN in
# boards/mps2_an386/src/lib.rs): the most bytes typed at one gate.
CONSOLE_RING_LEN = 256
# The image's configuration file, in QEMU's working directory (CONFIG_FILE
# in boards/mps2_an386/src/lib.rs).
CONFIG_FILE = "suntracker-config.bin"
# Emulated ms between two gates of the image when not paced (GATE_MS in
# boards/mps2_an386/src/lib.rs): one GPS epoch each.
GATE_MS = 10_000
# The image's Modbus receive ring (MODBUS_RING_LEN in
# boards/mps2_an386/src/lib.rs): the most request bytes put in at one gate.
MODBUS_RING_LEN = 256


class ModbusPty:
    """A pseudo-terminal for a Modbus master, bridged to the image's UART3
    socket. Its slave side is closed here: the master side reports a
    hang-up exactly while no client holds the terminal open."""

    def __init__(self, link):
        self.master, slave = os.openpty()
        # Raw: no line discipline between the master and the image.
        tty.setraw(slave)
        self.name = os.ttyname(slave)
        os.close(slave)
        os.set_blocking(self.master, False)
        self.link = link
        if os.path.lexists(link):
            os.unlink(link)
        os.symlink(self.name, link)
        self.poller = select.poll()
        self.poller.register(self.master, select.POLLIN)

    def attached(self):
        return not any(ev & select.POLLHUP for _, ev in self.poller.poll(0))

    def read(self):
        """Bytes the client wrote (b"" when none or none attached)."""
        try:
            return os.read(self.master, 4096)
        except (BlockingIOError, OSError):
            return b""

    def write(self, data):
        """Passes the image's bytes on; dropped while no client is there."""
        if self.attached():
            try:
                os.write(self.master, data)
            except OSError:
                pass

    def close(self):
        os.close(self.master)
        if os.path.islink(self.link):
            os.unlink(self.link)


def checksum(body):
    c = 0
    for ch in body.encode():
        c ^= ch
    return f"{c:02X}"


def sentence(fields):
    body = ",".join(fields)
    return f"${body}*{checksum(body)}\r\n"


def parse_template(path):
    """The first GGA and RMC of a recorded stream, as field lists, and the
    RMC's UTC."""
    gga = rmc = None
    with open(path, encoding="ascii") as f:
        for line in f:
            line = line.strip()
            if not line.startswith("$") or "*" not in line:
                continue
            fields = line[1:line.index("*")].split(",")
            if fields[0].endswith("GGA") and gga is None:
                gga = fields
            elif fields[0].endswith("RMC") and rmc is None:
                rmc = fields
    if gga is None or rmc is None:
        raise SystemExit(f"qemu_gps: {path} has no GGA and RMC")
    t = rmc[1]
    d = rmc[9]
    first = dt.datetime(2000 + int(d[4:6]), int(d[2:4]), int(d[0:2]),
                        int(t[0:2]), int(t[2:4]), int(t[4:6]), tzinfo=dt.timezone.utc)
    return gga, rmc, first


def position_fields(lat, lon):
    """NMEA 0183 `ddmm.mmmm,N` and `dddmm.mmmm,E` fields of a position."""
    def field(v, width, pos, neg):
        a = abs(v)
        deg = int(a)
        minutes = round((a - deg) * 60, 4)
        if minutes >= 60:
            deg, minutes = deg + 1, 0.0
        return [f"{deg:0{width}d}{minutes:07.4f}", pos if v >= 0 else neg]
    return field(lat, 2, "N", "S") + field(lon, 3, "E", "W")


def epoch(gga, rmc, when, position=None):
    """The template's GGA and RMC at `when`, at `position` ((lat, lon)
    degrees) when given, else at the template's."""
    hms = when.strftime("%H%M%S") + f".{when.microsecond // 10000:02d}"
    g = list(gga)
    r = list(rmc)
    g[1] = hms
    r[1] = hms
    r[9] = when.strftime("%d%m%y")
    if position is not None:
        f = position_fields(*position)
        g[2:6] = f
        r[3:7] = f
    return (sentence(g) + sentence(r)).encode("ascii")


def parse_time_lie(s):
    """`MINUTE:SECONDS` -> (ms, seconds); ValueError saying what is wrong."""
    minute, sep, rest = s.partition(":")
    try:
        ms = round(float(minute) * 60_000)
        off = int(rest)
    except ValueError:
        ms = -1
    if not sep or ms < 0:
        raise ValueError(f"bad --time-lie {s!r}, want MINUTE:SECONDS")
    return ms, off


def parse_move(s):
    """`MINUTE:LAT,LON` -> (ms, (lat, lon)); ValueError saying what is
    wrong."""
    minute, sep, rest = s.partition(":")
    try:
        ms = round(float(minute) * 60_000)
        lat, lon = (float(x) for x in rest.split(","))
    except ValueError:
        ms = -1
    if not sep or ms < 0 or not (-90 <= lat <= 90 and -180 <= lon <= 180):
        raise ValueError(f"bad --move {s!r}, want MINUTE:LAT,LON (degrees north, east)")
    return ms, (lat, lon)


def parse_utc(s):
    try:
        return dt.datetime.strptime(s, "%Y-%m-%dT%H:%M:%SZ").replace(tzinfo=dt.timezone.utc)
    except ValueError:
        raise SystemExit(f"qemu_gps: bad time {s}, want YYYY-MM-DDTHH:MM:SSZ") from None


def parse_type(s):
    """`MINUTE:LINE` -> (ms, bytes of LINE + newline); ValueError saying
    what is wrong."""
    minute, sep, line = s.partition(":")
    try:
        ms = round(float(minute) * 60_000)
    except ValueError:
        ms = -1
    if not sep or ms < 0:
        raise ValueError(f"bad --type {s!r}, want MINUTE:LINE (MINUTE >= 0)")
    if not line.isascii() or not line.isprintable():
        raise ValueError(f"--type {s!r}: the line must be printable ASCII")
    return ms, (line + "\n").encode("ascii")


def take_console(pending):
    """Whole lines from the front of `pending` (removed there) that fit the
    image's console ring together; a single longer line goes alone."""
    out = b""
    while pending and (not out or len(out) + len(pending[0]) <= CONSOLE_RING_LEN):
        out += pending.pop(0)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("elf")
    ap.add_argument("--nmea", default=DEFAULT_NMEA)
    ap.add_argument("--no-gps", action="store_true")
    ap.add_argument("--start", help="UTC of the first epoch (default: the stream's)")
    ap.add_argument("--minutes", type=float, default=1440.0)
    ap.add_argument("--log")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--timeout", type=float, default=900.0, help="wall seconds")
    ap.add_argument("--qemu", default="qemu-system-arm")
    ap.add_argument("--qemu-arg", action="append", default=[],
                    help="extra QEMU argument (QEMU runs in a temporary directory)")
    ap.add_argument("--type", action="append", default=[], metavar="MINUTE:LINE",
                    help="type LINE on the console (UART2) at that emulated minute")
    ap.add_argument("--time-lie", metavar="MINUTE:SECONDS",
                    help="from that emulated minute the epochs' time is off by +SECONDS and "
                         "-SECONDS in turn")
    ap.add_argument("--move", action="append", default=[], metavar="MINUTE:LAT,LON",
                    help="from that emulated minute the receiver reports this position")
    ap.add_argument("--config-file", metavar="PATH",
                    help="the image's configuration file (default: a new one per run)")
    ap.add_argument("--modbus-pty", metavar="PATH",
                    help="bridge the image's RS-485 port (UART3) to a pseudo-terminal linked "
                         "at PATH; paced to the wall clock while a client has it open")
    ap.add_argument("--modbus-pace-ms", type=int, default=20, metavar="MS",
                    help="emulated ms between two gates while paced (default 20)")
    a = ap.parse_args()
    if not 1 <= a.modbus_pace_ms <= GATE_MS:
        ap.error(f"--modbus-pace-ms must lie in 1..{GATE_MS}")

    gga, rmc, first = parse_template(a.nmea)
    if a.start:
        first = parse_utc(a.start)
    end_ms = int(a.minutes * 60_000)
    try:
        parsed = [parse_type(t) for t in a.type]
        moves = sorted((parse_move(m) for m in a.move), key=lambda x: x[0])
        lie = parse_time_lie(a.time_lie) if a.time_lie else None
    except ValueError as e:
        ap.error(str(e))
    late = [t for t, (ms, _) in zip(a.type, parsed) if ms >= end_ms]
    if late:
        ap.error(f"--type at or after --minutes {a.minutes:g} is never typed: {late}")
    # Stable sort: lines of one minute keep their order.
    typed = sorted(parsed, key=lambda x: x[0])
    pending = []
    lies = 0

    tmp = tempfile.mkdtemp(prefix="qemu_gps.")
    if a.config_file:
        path = os.path.abspath(a.config_file)
        open(path, "ab").close()
        os.symlink(path, os.path.join(tmp, CONFIG_FILE))
    names = ("gps", "gate", "console") + (("modbus",) if a.modbus_pty else ())
    paths = {k: os.path.join(tmp, k + ".sock") for k in names}
    listeners = {}
    for k, p in paths.items():
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        s.bind(p)
        s.listen(1)
        s.settimeout(30)
        listeners[k] = s
    cmd = [a.qemu, "-cpu", "cortex-m4", "-machine", "mps2-an386", "-nographic",
           "-monitor", "none", "-no-reboot", "-icount", "shift=5,sleep=off",
           "-chardev", f"socket,id=gps,path={paths['gps']}", "-serial", "chardev:gps",
           "-chardev", f"socket,id=gate,path={paths['gate']}", "-serial", "chardev:gate",
           "-chardev", f"socket,id=console,path={paths['console']}", "-serial", "chardev:console",
           *(["-chardev", f"socket,id=modbus,path={paths['modbus']}",
              "-serial", "chardev:modbus"] if a.modbus_pty else []),
           "-semihosting-config", "enable=on,target=native",
           "-kernel", os.path.abspath(a.elf), *a.qemu_arg]
    t0 = time.monotonic()
    # In the temporary directory: the image's semihosting file lives there.
    qemu = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, cwd=tmp)
    out = qemu.stdout.fileno()
    try:
        gps, _ = listeners["gps"].accept()
        gate, _ = listeners["gate"].accept()
        console, _ = listeners["console"].accept()
        modbus = listeners["modbus"].accept()[0] if a.modbus_pty else None
    except OSError as e:
        qemu.kill()
        raise SystemExit(f"qemu_gps: QEMU did not connect: {e}") from None
    log = open(a.log, "w", encoding="utf-8") if a.log else None
    pty = ModbusPty(a.modbus_pty) if a.modbus_pty else None
    stop_asked = False

    def ask_stop(_signum, _frame):
        nonlocal stop_asked
        stop_asked = True

    signal.signal(signal.SIGTERM, ask_stop)
    signal.signal(signal.SIGINT, ask_stop)
    # While paced: (emulated ms, wall clock) when pacing began.
    pace = None
    # A gate whose answer waits for the wall clock (its emulated ms).
    waiting = None
    last_epoch_ms = None
    paced_gates = 0
    # What the Modbus client wrote, write by write, for the next gate.
    mb_in = []

    def answer(ms):
        nonlocal lies, last_epoch_ms
        if ms >= end_ms or stop_asked:
            gate.sendall(b"stop\n")
            return
        paced = pace is not None
        # Unpaced, every gate is an epoch's (the image gates every 10 s);
        # paced, the first gate at or after each 10 s.
        due_epoch = (not paced or last_epoch_ms is None
                     or ms // GATE_MS > last_epoch_ms // GATE_MS)
        nmea = b""
        if due_epoch:
            last_epoch_ms = ms
            position = None
            for at_ms, p in moves:
                if at_ms <= ms:
                    position = p
            when = first + dt.timedelta(milliseconds=ms)
            if lie is not None and ms >= lie[0]:
                lies += 1
                when += dt.timedelta(seconds=lie[1] if lies % 2 else -lie[1])
            nmea = b"" if a.no_gps else epoch(gga, rmc, when, position)
        if nmea:
            gps.sendall(nmea)
        while typed and typed[0][0] <= ms:
            pending.append(typed.pop(0)[1])
        keys = take_console(pending)
        if keys:
            console.sendall(keys)
        # The client's requests: whole writes (a master writes a request
        # at once) that fit the image's ring together. At one gate they
        # arrive at one emulated instant (its clock stands still), so a
        # request is one frame however QEMU's UART spaces its bytes.
        frames = b""
        while mb_in and len(frames) + len(mb_in[0]) <= MODBUS_RING_LEN:
            frames += mb_in.pop(0)
        if mb_in and not frames:
            # Longer than a frame can be: dropped (the master times out).
            mb_in.pop(0)
        if frames:
            modbus.sendall(frames)
        fields = [len(nmea), len(keys), a.modbus_pace_ms if paced else 0, len(frames)]
        while len(fields) > 1 and fields[-1] == 0:
            fields.pop()
        gate.sendall((",".join(str(f) for f in fields) + "\n").encode())

    buf = b""
    gbuf = b""
    gates = 0
    ended = False
    timed_out = False
    out_open = True
    modbus_open = modbus is not None
    while out_open:
        now = time.monotonic()
        left = a.timeout - (now - t0)
        if left <= 0:
            timed_out = True
            break
        attached = pty is not None and pty.attached()
        if waiting is not None and (stop_asked or not attached):
            # The client left (or the run ends): unpaced from here on.
            pace = None
            answer(waiting)
            waiting = None
        wait_s = min(left, 1.0)
        if waiting is not None:
            due = pace[1] + (waiting - pace[0]) / 1000
            wait_s = max(0.0, min(wait_s, due - now))
        rlist = [out, gate]
        if modbus_open:
            rlist.append(modbus)
        if attached:
            rlist.append(pty.master)
        r, _, _ = select.select(rlist, [], [], wait_s)
        if modbus_open and modbus in r:
            data = modbus.recv(65536)
            if data:
                pty.write(data)
            else:
                modbus_open = False
        if attached and pty.master in r:
            data = pty.read()
            if data and modbus_open:
                mb_in.append(data)
        if waiting is not None and time.monotonic() >= pace[1] + (waiting - pace[0]) / 1000:
            answer(waiting)
            waiting = None
        if gate in r:
            data = gate.recv(65536)
            gbuf += data
            while b"\n" in gbuf:
                req, gbuf = gbuf.split(b"\n", 1)
                ms = int(req.decode("ascii").lstrip("T"))
                gates += 1
                if attached and not stop_asked and ms < end_ms:
                    if pace is None:
                        pace = (ms, time.monotonic())
                    paced_gates += 1
                    waiting = ms
                else:
                    pace = None
                    answer(ms)
        if out in r:
            data = os.read(out, 65536)
            if not data:
                out_open = False
            buf += data
            while b"\n" in buf:
                raw, buf = buf.split(b"\n", 1)
                line = raw.decode("utf-8", "replace")
                if line.startswith("end "):
                    ended = True
                if not a.quiet:
                    print(line, flush=False)
                if log:
                    log.write(line + "\n")
                    log.flush()
    if timed_out:
        qemu.kill()
    rc = qemu.wait()
    sys.stdout.flush()
    if log:
        log.close()
    for s in (gps, gate, console, *listeners.values()):
        s.close()
    if modbus is not None:
        modbus.close()
    if pty is not None:
        pty.close()
    # The sockets, the image's file or the link to --config-file (not its
    # target).
    shutil.rmtree(tmp)
    if pending or typed:
        print(f"qemu_gps: {len(pending) + len(typed)} typed line(s) not sent before the end",
              file=sys.stderr)
    wall = time.monotonic() - t0
    print(f"qemu_gps: {gates} gates" + (f" ({paced_gates} paced)" if pty else "")
          + f", {wall:.1f} s wall, exit {rc}"
          + (" (timed out)" if timed_out else ""), file=sys.stderr)
    if timed_out or (gates > 0 and not ended):
        return 3
    return rc


if __name__ == "__main__":
    sys.exit(main())
