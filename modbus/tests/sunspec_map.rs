//! The SunSpec map served over RTU frames: what a SCADA reads and writes.

mod common;

use common::Demo;
use suntracker_modbus::crc::crc16;
use suntracker_modbus::sunspec::{m1, m601, m64201, Angles, Command, Control, SunSpecMap};
use suntracker_modbus::Server;

const ADDRESS: u8 = 7;

fn transact(server: &Server, map: &mut SunSpecMap<Demo>, request: &[u8]) -> Option<Vec<u8>> {
    let mut out = [0; 256];
    let len = server.handle(request, map, &mut out)?;
    assert_eq!(crc16(&out[..len]), 0);
    Some(out[..len - 2].to_vec())
}

fn read(map: &mut SunSpecMap<Demo>, start: u16, count: u16) -> Result<Vec<u16>, u8> {
    let server = Server {
        address: ADDRESS,
        writes_enabled: false,
    };
    let mut req = vec![ADDRESS, 0x03];
    req.extend_from_slice(&start.to_be_bytes());
    req.extend_from_slice(&count.to_be_bytes());
    let reply = transact(&server, map, &req).unwrap();
    if reply[1] == 0x83 {
        return Err(reply[2]);
    }
    assert_eq!(reply[2] as usize, count as usize * 2);
    Ok(reply[3..]
        .chunks(2)
        .map(|c| u16::from_be_bytes([c[0], c[1]]))
        .collect())
}

/// The whole map from 40000 to the end marker, read as a SunSpec client
/// does (125 registers at most a request).
fn whole(map: &mut SunSpecMap<Demo>) -> Vec<u16> {
    let end = map.end_addr() + 2;
    let mut regs = Vec::new();
    let mut at = 40000;
    while at < end {
        let n = (end - at).min(125);
        regs.extend(read(map, at, n).unwrap());
        at += n;
    }
    regs
}

fn string(regs: &[u16]) -> String {
    let bytes: Vec<u8> = regs
        .iter()
        .flat_map(|r| r.to_be_bytes())
        .take_while(|&b| b != 0)
        .collect();
    String::from_utf8(bytes).unwrap()
}

fn int32(regs: &[u16]) -> i32 {
    ((u32::from(regs[0]) << 16) | u32::from(regs[1])) as i32
}

#[test]
fn walk_the_models_as_a_client_does() {
    for gps in [false, true] {
        let mut map = SunSpecMap::new(Demo::new(ADDRESS, gps), gps);
        let regs = whole(&mut map);
        assert_eq!(regs[..2], [0x5375, 0x6E53], "SunS");
        let mut at = 2;
        let mut models = Vec::new();
        while regs[at] != 0xFFFF {
            models.push((regs[at], at + 40000));
            at += 2 + usize::from(regs[at + 1]);
        }
        assert_eq!(regs[at + 1], 0, "the end marker's length");
        assert_eq!(at + 2, regs.len());
        let expected: Vec<u16> = if gps {
            vec![1, 601, 305, 64201]
        } else {
            vec![1, 601, 64201]
        };
        assert_eq!(models.iter().map(|m| m.0).collect::<Vec<_>>(), expected);
    }
}

#[test]
fn common_model() {
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, false), false);
    let regs = whole(&mut map);
    let m = &regs[2..];
    assert_eq!(m[..2], [1, 66]);
    assert_eq!(string(&m[2..18]), "suntracker");
    assert_eq!(string(&m[18..34]), "dual-axis ATmega2560");
    assert_eq!(string(&m[34..42]), "gps wind");
    assert_eq!(string(&m[42..50]), "0.1.0");
    assert_eq!(string(&m[50..66]), "ST-000042");
    assert_eq!(m[66], u16::from(ADDRESS));
    assert_eq!(m[67], 0x8000, "pad");
}

#[test]
fn tracker_controller_model() {
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, false), false);
    let base = usize::from(map.tracker_addr() - 40000);
    let regs = whole(&mut map);
    let m = &regs[base..];
    assert_eq!(m[..2], [601, 48]);
    assert_eq!(string(&m[2..10]), "suntracker");
    assert_eq!(m[10], 5, "Typ: Dual");
    assert_eq!(string(&m[11..16]), "20260320");
    assert_eq!(string(&m[16..19]), "123456");
    assert_eq!(m[19], 79, "day of the year");
    assert_eq!(
        int32(&m[20..22]),
        i32::MIN,
        "no manual target: not implemented"
    );
    assert_eq!(int32(&m[22..24]), i32::MIN);
    assert_eq!(m[24], 0, "Automatic");
    assert_eq!(m[25], 0b010, "ObsEl");
    assert_eq!(m[26] as i16, -2, "Dgr_SF");
    assert_eq!(m[27], 1, "one tracker");
    assert_eq!(string(&m[28..36]), "tracker 1");
    assert_eq!(int32(&m[36..38]), 7_734, "ElTrgt 77.34°");
    assert_eq!(int32(&m[38..40]), 18_050, "AzTrgt 180.50°");
    assert_eq!(int32(&m[40..42]), 7_730);
    assert_eq!(int32(&m[42..44]), 18_041);
    assert_eq!(int32(&m[44..46]), i32::MIN);
    assert_eq!(m[48], 0);
    assert_eq!(m[49], 0b010);
}

#[test]
fn gps_model() {
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, true), true);
    let base = usize::from(map.gps_addr().unwrap() - 40000);
    let regs = whole(&mut map);
    let m = &regs[base..];
    assert_eq!(m[..2], [305, 36]);
    assert_eq!(string(&m[2..8]), "123456.789Z");
    assert_eq!(string(&m[8..12]), "20260320");
    assert_eq!(string(&m[12..32]), "");
    assert_eq!(int32(&m[32..34]), 120_022_000);
    assert_eq!(int32(&m[34..36]), 85_919_000);
    assert_eq!(int32(&m[36..38]), 488);

    // A GPS without a fix: strings empty, numbers not implemented.
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, false), true);
    let regs = whole(&mut map);
    let m = &regs[base..];
    assert_eq!(m[..2], [305, 36]);
    assert!(m[2..32].iter().all(|&r| r == 0));
    assert_eq!(int32(&m[32..34]), i32::MIN);
    assert_eq!(int32(&m[36..38]), i32::MIN);
}

#[test]
fn vendor_model() {
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, false), false);
    let base = usize::from(map.vendor_addr() - 40000);
    let regs = whole(&mut map);
    let m = &regs[base..];
    assert_eq!(
        m[..14],
        [
            64201,
            12,
            8,
            0,
            53,
            (-1_i16) as u16,
            0x8000,
            0x0005,
            0,
            1,
            0,
            0,
            // Flt2: fault 32; ClrFlt reads 0.
            0x0001,
            0
        ]
    );
    assert_eq!(m[14..], [0xFFFF, 0]);
}

#[test]
fn clearing_the_faults() {
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, false), false);
    let clr = map.vendor_addr() + m64201::CLR_FLT;
    // 1 clears, 0 does nothing, anything else is refused (03).
    write(&mut map, &WRITER, ADDRESS, clr, &[1]).unwrap();
    assert_eq!(map.data.commands, [Command::ClearFaults]);
    write(&mut map, &WRITER, ADDRESS, clr, &[0]).unwrap();
    assert_eq!(map.data.commands, [Command::ClearFaults]);
    let refused = write(&mut map, &WRITER, ADDRESS, clr, &[2]).unwrap();
    assert_eq!(refused[..3], [ADDRESS, 0x86, 3]);
    // Not by broadcast.
    assert_eq!(write(&mut map, &WRITER, 0, clr, &[1]), None);
    assert_eq!(map.data.commands, [Command::ClearFaults]);
}

#[test]
fn reads_outside_the_map() {
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, false), false);
    let end = map.end_addr() + 2;
    assert_eq!(read(&mut map, 39_999, 2), Err(2));
    assert_eq!(read(&mut map, 0, 1), Err(2));
    assert_eq!(read(&mut map, end - 2, 3), Err(2));
    assert_eq!(read(&mut map, end - 2, 2), Ok(vec![0xFFFF, 0]));
    // Half of an int32 reads fine.
    let el_trgt = map.tracker_addr() + m601::EL_TRGT;
    assert_eq!(read(&mut map, el_trgt + 1, 1), Ok(vec![7_734]));
}

fn write(
    map: &mut SunSpecMap<Demo>,
    server: &Server,
    address: u8,
    start: u16,
    values: &[u16],
) -> Option<Vec<u8>> {
    let mut req = vec![address];
    if values.len() == 1 {
        req.push(0x06);
        req.extend_from_slice(&start.to_be_bytes());
        req.extend_from_slice(&values[0].to_be_bytes());
    } else {
        req.push(0x10);
        req.extend_from_slice(&start.to_be_bytes());
        req.extend_from_slice(&(values.len() as u16).to_be_bytes());
        req.push((values.len() * 2) as u8);
        for v in values {
            req.extend_from_slice(&v.to_be_bytes());
        }
    }
    transact(server, map, &req)
}

const WRITER: Server = Server {
    address: ADDRESS,
    writes_enabled: true,
};

#[test]
fn manual_control_over_model_601() {
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, false), false);
    let t = map.tracker_addr();
    // Manual targets 30.00° up, 135.25° (south-east), then Manual, in one request.
    let el = 3_000_i32 as u32;
    let az = 13_525_u32;
    let values = [
        (el >> 16) as u16,
        el as u16,
        (az >> 16) as u16,
        az as u16,
        1,
    ];
    let start = t + m601::GLBL_EL_CTL;
    let reply = write(&mut map, &WRITER, ADDRESS, start, &values).unwrap();
    let [hi, lo] = start.to_be_bytes();
    assert_eq!(reply, [ADDRESS, 0x10, hi, lo, 0, 5]);
    assert_eq!(
        map.data.commands,
        [
            Command::ManualElevation(3_000),
            Command::ManualAzimuth(13_525),
            Command::Control(Control::Manual)
        ]
    );
    assert_eq!(
        map.data.manual,
        Some(Angles {
            elevation_cdeg: 3_000,
            azimuth_cdeg: 13_525
        })
    );
    let back = read(&mut map, t + m601::GLBL_EL_CTL, 5).unwrap();
    assert_eq!(back, values);
    // The tracker block's own controls are the same (one tracker); a
    // negative elevation.
    let el = (-1_250_i32) as u32;
    write(
        &mut map,
        &WRITER,
        ADDRESS,
        t + m601::EL_CTL,
        &[(el >> 16) as u16, el as u16],
    )
    .unwrap();
    assert_eq!(
        read(&mut map, t + m601::GLBL_EL_CTL, 2).unwrap(),
        [0xFFFF, (-1_250_i16) as u16]
    );
    write(&mut map, &WRITER, ADDRESS, t + m601::CTL, &[0]).unwrap();
    assert_eq!(map.data.control, Control::Automatic);
}

#[test]
fn write_exceptions() {
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, false), false);
    let t = map.tracker_addr();
    let da = map.common_addr() + m1::DA;
    let (el, az, ctl) = (
        t + m601::GLBL_EL_CTL,
        t + m601::GLBL_AZ_CTL,
        t + m601::GLBL_CTL,
    );
    // (first register, values, exception code); function 06 for one
    // register, 16 for more.
    let cases: &[(u16, &[u16], u8)] = &[
        // Half of an int32, or a run that ends inside one: 02.
        (el, &[0], 2),
        (el + 1, &[0, 0], 2),
        (el, &[0, 0, 0], 2),
        // Read-only points: 02.
        (t + m601::EL_TRGT, &[0, 0], 2),
        (40000, &[0], 2),
        // Values outside the point's range: 03.
        (ctl, &[3], 3),
        (el, &[0, 9_001], 3),
        (az, &[0xFFFF, 0xFFFF], 3),
        (da, &[0], 3),
        (da, &[248], 3),
        // A good value then a bad one in one request: 03, nothing done.
        (el, &[0, 100, 0, 36_001], 3),
    ];
    for &(start, values, code) in cases {
        let reply = write(&mut map, &WRITER, ADDRESS, start, values).unwrap();
        let function = if values.len() == 1 { 0x86 } else { 0x90 };
        assert_eq!(reply, [ADDRESS, function, code], "{start} {values:?}");
    }
    assert!(map.data.commands.is_empty());
    // Writes disabled: 01.
    let reader = Server {
        address: ADDRESS,
        writes_enabled: false,
    };
    assert_eq!(
        write(&mut map, &reader, ADDRESS, ctl, &[1]).unwrap(),
        [ADDRESS, 0x86, 1]
    );
    assert!(map.data.commands.is_empty());
    // The tracker's refusal passes through.
    map.data.refuse = Some(suntracker_modbus::Exception::ServerDeviceBusy);
    assert_eq!(
        write(&mut map, &WRITER, ADDRESS, ctl, &[2]).unwrap(),
        [ADDRESS, 0x86, 6]
    );
}

#[test]
fn device_address_and_stow() {
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, false), false);
    let da = map.common_addr() + m1::DA;
    write(&mut map, &WRITER, ADDRESS, da, &[12]).unwrap();
    assert_eq!(map.data.commands, [Command::DeviceAddress(12)]);
    let stow = map.vendor_addr() + m64201::STOW;
    write(&mut map, &WRITER, ADDRESS, stow, &[1]).unwrap();
    assert!(map.data.stow);
    let mode = map.vendor_addr() + m64201::MODE;
    assert_eq!(read(&mut map, mode, 2).unwrap(), [3, 2]);
    assert_eq!(read(&mut map, stow, 1).unwrap(), [1]);
}

#[test]
fn broadcast_only_stows() {
    let mut map = SunSpecMap::new(Demo::new(ADDRESS, false), false);
    let stow = map.vendor_addr() + m64201::STOW;
    // Stow to every tracker on the bus: done, no reply.
    assert_eq!(write(&mut map, &WRITER, 0, stow, &[1]), None);
    assert_eq!(map.data.commands, [Command::Stow(true)]);
    assert_eq!(write(&mut map, &WRITER, 0, stow, &[0]), None);
    assert!(!map.data.stow);
    // Anything else broadcast: not done, no reply.
    map.data.commands.clear();
    let (ctl, da) = (
        map.tracker_addr() + m601::GLBL_CTL,
        map.common_addr() + m1::DA,
    );
    assert_eq!(write(&mut map, &WRITER, 0, ctl, &[1]), None);
    assert_eq!(write(&mut map, &WRITER, 0, da, &[9]), None);
    assert!(map.data.commands.is_empty());
    // Nor when writes are disabled.
    let reader = Server {
        address: ADDRESS,
        writes_enabled: false,
    };
    assert_eq!(write(&mut map, &reader, 0, stow, &[1]), None);
    assert!(map.data.commands.is_empty());
}
