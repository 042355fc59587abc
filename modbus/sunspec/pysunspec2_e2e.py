#!/usr/bin/env python3
"""End to end: pysunspec2 scans the simulated tracker's map over a pseudo-terminal.

Starts SERVER (the pty_server example) with a pty's master as its standard input
and output, opens the pty's other side with the SunSpec Alliance's pysunspec2
(SunSpecModbusClientDeviceRTU, scan()), and checks that models 1, 601, 305 and
the vendor model 64201 are found, that their points decode to the simulated
tracker's values (tests/common/mod.rs), and that writes of model 601's manual
controls and the vendor stow command land.

  python3 modbus/sunspec/pysunspec2_e2e.py path/to/pty_server
"""
import os
import subprocess
import sys
import tty

import sunspec2.device
import sunspec2.modbus.client as client
import sunspec2.modbus.modbus as modbus

HERE = os.path.dirname(os.path.abspath(__file__))
ADDRESS = 7
BAUD = 19200

failures = []
passed = []


def check(what, got, want, tol=None):
    ok = abs(got - want) <= tol if tol is not None else got == want
    print("%-4s %-32s %r%s" % ("ok" if ok else "FAIL", what, got, "" if ok else " (want %r)" % (want,)))
    (passed if ok else failures).append(what)


def start(server, *args):
    """The server on a new pty's master, and a pysunspec2 device on its other side."""
    master, slave = os.openpty()
    tty.setraw(slave)  # no echo of the server's replies back into it
    cmd = [server, "--address", str(ADDRESS), "--baud", str(BAUD), *args]
    proc = subprocess.Popen(cmd, stdin=master, stdout=master)
    dev = client.SunSpecModbusClientDeviceRTU(slave_id=ADDRESS, name=os.ttyname(slave), baudrate=BAUD, timeout=2)
    return proc, dev


def main():
    server = sys.argv[1]
    # The vendor model's definition beside this script, then pysunspec2's own.
    sunspec2.device.set_model_defs_path([HERE] + sunspec2.device.get_model_defs_path())
    proc, dev = start(server)
    try:
        dev.scan()
        found = sorted(k for k in dev.models if isinstance(k, int))
        check("models found", found, [1, 305, 601, 64201])

        common = dev.models[1][0]
        check("1 Mn", common.Mn.value, "suntracker")
        check("1 Md", common.Md.value, "dual-axis ATmega2560")
        check("1 SN", common.SN.value, "ST-000042")
        check("1 DA", common.DA.value, ADDRESS)

        tc = dev.models[601][0]
        check("601 Typ (Dual)", tc.Typ.value, 5)
        check("601 DtLoc", tc.DtLoc.value, "20260320")
        check("601 TmLoc", tc.TmLoc.value, "123456")
        check("601 Day", tc.Day.value, 79)
        check("601 Dgr_SF", tc.Dgr_SF.value, -2)
        check("601 N", tc.N.value, 1)
        check("601 GlblCtl (Automatic)", tc.GlblCtl.value, 0)
        check("601 GlblAlm (ObsEl)", tc.GlblAlm.value, 0b010)
        check("601 GlblElCtl unimplemented", tc.GlblElCtl.value, None)
        trk = tc.tracker[0]
        check("601 tracker Id", trk.Id.value, "tracker 1")
        check("601 ElTrgt deg", trk.ElTrgt.cvalue, 77.34, 1e-9)
        check("601 AzTrgt deg", trk.AzTrgt.cvalue, 180.50, 1e-9)
        check("601 ElPos deg", trk.ElPos.cvalue, 77.30, 1e-9)
        check("601 AzPos deg", trk.AzPos.cvalue, 180.41, 1e-9)

        gps = dev.models[305][0]
        check("305 Tm", gps.Tm.value, "123456.789Z")
        check("305 Date", gps.Date.value, "20260320")
        check("305 Lat deg", gps.Lat.cvalue, 12.0022, 1e-9)
        check("305 Long deg", gps.Long.cvalue, 8.5919, 1e-9)
        check("305 Alt m", gps.Alt.value, 488)

        vendor = dev.models[64201][0]
        check("64201 Mode (TRACKING)", vendor.Mode.value, 8)
        check("64201 WndSpd m/s", vendor.WndSpd.cvalue, 5.3, 1e-9)
        check("64201 Flt", vendor.Flt.value, 0x80000005)
        check("64201 Flt2", vendor.Flt2.value, 0x0001)
        check("64201 ClrFlt reads 0", vendor.ClrFlt.value, 0)
        check("64201 FwMin", vendor.FwMin.value, 1)

        # Writes (function code 16): manual targets, Manual, then stow.
        tc.GlblElCtl.cvalue = 30.0
        tc.GlblAzCtl.cvalue = 135.25
        tc.GlblCtl.value = 1
        tc.write()
        tc.read()
        check("601 GlblElCtl written", tc.GlblElCtl.cvalue, 30.0, 1e-9)
        check("601 GlblAzCtl written", tc.GlblAzCtl.cvalue, 135.25, 1e-9)
        check("601 GlblCtl written (Manual)", tc.GlblCtl.value, 1)
        check("601 tracker Ctl follows", tc.tracker[0].Ctl.value, 1)
        vendor.Stow.value = 1
        vendor.write()
        vendor.read()
        check("64201 Stow written", vendor.Stow.value, 1)
        check("64201 StowRsn (COMMAND)", vendor.StowRsn.value, 2)
        vendor.ClrFlt.value = 1
        vendor.ClrFlt.write()
        vendor.read()
        check("64201 ClrFlt written (the server took it)", vendor.ClrFlt.value, 0)

        # A value outside the enumeration (function code 06): exception 03.
        try:
            tc.GlblCtl.value = 7
            tc.GlblCtl.write()
            check("601 GlblCtl = 7 refused", "no exception", "Modbus exception: 3")
        except modbus.ModbusClientException as e:
            check("601 GlblCtl = 7 refused", str(e), "Modbus exception: 3")
        dev.close()
    finally:
        proc.terminate()
        proc.wait()

    # Without a GPS: no model 305, the vendor model right after 601.
    proc, dev = start(server, "--no-gps")
    try:
        dev.scan()
        found = sorted(k for k in dev.models if isinstance(k, int))
        check("models found without GPS", found, [1, 601, 64201])
        check("64201 after 601", dev.models[64201][0].model_addr, dev.models[601][0].model_addr + 50)
        dev.close()
    finally:
        proc.terminate()
        proc.wait()
    print("pysunspec2: %d passed, %d failed" % (len(passed), len(failures)))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
