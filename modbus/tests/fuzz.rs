//! Random and mutated traffic through the receiver, the server and the
//! SunSpec map: no panic, no reply to a frame that is not whole and good,
//! exactly one reply to each good frame for our address, none to another
//! address or to broadcast.
//!
//! The expectation comes from a model of the wire written here from the
//! serial line spec's rules (Modbus over Serial Line V1.02, §2.5.1.1: split
//! at silences over 3.5 characters, a frame with a gap over 1.5 characters
//! or over 256 bytes is bad) and a table-driven CRC of its own, not from
//! the crate's receiver. `MODBUS_FUZZ_FRAMES` sets the number of frames
//! (default 1,000,000).

mod common;

use suntracker_modbus::rtu::{Push, RtuReceiver, RtuTiming};
use suntracker_modbus::sunspec::SunSpecMap;
use suntracker_modbus::Server;

const OURS: u8 = 0x2A;
/// One character at 19,200 baud, 11 bits: 573 µs.
const CHAR_US: u32 = 573;

/// SplitMix64 (Steele, Lea, Flood: "Fast splittable pseudorandom number
/// generators", 2014): small, deterministic.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u32) -> u32 {
        (self.next() % u64::from(n)) as u32
    }
    fn byte(&mut self) -> u8 {
        self.next() as u8
    }
    fn chance(&mut self, percent: u32) -> bool {
        self.below(100) < percent
    }
}

/// The CRC-16/MODBUS by a 256-entry table (a different algorithm from the
/// crate's bit loop).
struct Crc([u16; 256]);

impl Crc {
    fn new() -> Self {
        let mut table = [0_u16; 256];
        for (i, e) in table.iter_mut().enumerate() {
            let mut c = i as u16;
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    (c >> 1) ^ 0xA001
                } else {
                    c >> 1
                };
            }
            *e = c;
        }
        Self(table)
    }
    fn of(&self, bytes: &[u8]) -> u16 {
        bytes.iter().fold(0xFFFF, |c, &b| {
            (c >> 8) ^ self.0[usize::from((c as u8) ^ b)]
        })
    }
    fn append(&self, frame: &mut Vec<u8>) {
        let c = self.of(frame);
        frame.extend_from_slice(&c.to_le_bytes());
    }
}

/// A request body (no CRC) the server may well serve.
fn request(rng: &mut Rng, address: u8) -> Vec<u8> {
    let mut f = vec![address];
    let start: u16 = if rng.chance(80) {
        39_990 + rng.below(200) as u16
    } else {
        rng.next() as u16
    };
    match rng.below(10) {
        0..=5 => {
            f.push(0x03);
            f.extend_from_slice(&start.to_be_bytes());
            let count = if rng.chance(90) {
                1 + rng.below(125)
            } else {
                rng.below(0x1_0000)
            } as u16;
            f.extend_from_slice(&count.to_be_bytes());
        }
        6 => {
            f.push(0x06);
            f.extend_from_slice(&start.to_be_bytes());
            f.extend_from_slice(&(rng.below(4) as u16).to_be_bytes());
        }
        7 | 8 => {
            f.push(0x10);
            f.extend_from_slice(&start.to_be_bytes());
            let count = if rng.chance(95) {
                1 + rng.below(8)
            } else {
                rng.below(130)
            } as u16;
            f.extend_from_slice(&count.to_be_bytes());
            let bytes = if rng.chance(95) {
                count * 2
            } else {
                rng.below(256) as u16
            };
            f.push(bytes as u8);
            for _ in 0..bytes.min(240) {
                f.push(if rng.chance(70) { 0 } else { rng.byte() });
            }
        }
        _ => {
            f.push(rng.byte());
            for _ in 0..rng.below(12) {
                f.push(rng.byte());
            }
        }
    }
    f
}

/// One frame on the wire: bytes and the gap before each.
struct Sent {
    bytes: Vec<u8>,
    gaps_us: Vec<u32>,
}

fn frame(rng: &mut Rng, crc: &Crc, t: &RtuTiming) -> Sent {
    let address = match rng.below(10) {
        0..=5 => OURS,
        6 => 0,
        _ => rng.byte(),
    };
    let mut bytes = request(rng, address);
    crc.append(&mut bytes);
    match rng.below(20) {
        // Bits flipped.
        0..=3 => {
            for _ in 0..1 + rng.below(3) {
                let i = rng.below(bytes.len() as u32) as usize;
                bytes[i] ^= 1 << rng.below(8);
            }
        }
        // A byte dropped, added or changed.
        4 => {
            bytes.remove(rng.below(bytes.len() as u32) as usize);
        }
        5 => bytes.insert(rng.below(bytes.len() as u32 + 1) as usize, rng.byte()),
        6 => {
            let i = rng.below(bytes.len() as u32) as usize;
            bytes[i] = rng.byte();
        }
        // Noise.
        7 => {
            bytes = (0..rng.below(24)).map(|_| rng.byte()).collect();
            if bytes.is_empty() {
                bytes.push(rng.byte());
            }
        }
        // Too long (with a good CRC): 257 to 300 bytes.
        8 if rng.chance(10) => {
            bytes.truncate(bytes.len() - 2);
            while bytes.len() < 255 + rng.below(44) as usize {
                bytes.push(rng.byte());
            }
            crc.append(&mut bytes);
        }
        _ => {}
    }
    let mut gaps_us: Vec<u32> = (0..bytes.len()).map(|_| CHAR_US + rng.below(100)).collect();
    // Between frames: mostly a proper silence, sometimes too short.
    gaps_us[0] = if rng.chance(97) {
        t.t35_ticks + 1 + rng.below(3_000)
    } else {
        t.t15_ticks + rng.below(t.t35_ticks - t.t15_ticks + 1)
    };
    // Sometimes a gap inside over 1.5 characters.
    if bytes.len() > 1 && rng.chance(3) {
        let i = 1 + rng.below(bytes.len() as u32 - 1) as usize;
        gaps_us[i] = t.t15_ticks + 1 + rng.below(t.t35_ticks - t.t15_ticks);
    }
    Sent { bytes, gaps_us }
}

#[test]
fn a_million_frames() {
    let frames: u32 = std::env::var("MODBUS_FUZZ_FRAMES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let timing = RtuTiming::from_baud_us(19_200);
    let crc = Crc::new();
    let mut rng = Rng(0x0005_EED0_F5A7);
    let mut rx = RtuReceiver::new(timing);
    let server = Server {
        address: OURS,
        writes_enabled: true,
    };
    let mut map = SunSpecMap::new(common::Demo::new(OURS, true), true);

    // The wire as the model splits it: each expected reply's request.
    let mut expected: Vec<Vec<u8>> = Vec::new();
    let mut replies: Vec<(Vec<u8>, Vec<u8>)> = Vec::new();
    let mut segment: Vec<u8> = Vec::new();
    let mut segment_bad = false;
    let close = |segment: &mut Vec<u8>, bad: bool, expected: &mut Vec<Vec<u8>>| {
        if !bad && (4..=256).contains(&segment.len()) && crc.of(segment) == 0 && segment[0] == OURS
        {
            expected.push(segment[..segment.len() - 2].to_vec());
        }
        segment.clear();
    };

    // The firmware's path: the reply written over the request in the
    // receiver's buffer. True when a frame was taken.
    let serve = |rx: &mut RtuReceiver,
                 at: u32,
                 map: &mut SunSpecMap<common::Demo>,
                 replies: &mut Vec<(Vec<u8>, Vec<u8>)>| {
        let Some((buf, len)) = rx.poll_in_place(at) else {
            return false;
        };
        let request = buf[..len].to_vec();
        if let Some(n) = server.handle_in_place(buf, len, map) {
            replies.push((request, buf[..n].to_vec()));
        }
        true
    };

    let mut now: u32 = 0xFFF0_0000; // wraps during the run
    let (mut good_ours, mut broadcast, mut others, mut bad) = (0_u32, 0_u32, 0_u32, 0_u32);
    for _ in 0..frames {
        let sent = frame(&mut rng, &crc, &timing);
        for (&b, &gap) in sent.bytes.iter().zip(&sent.gaps_us) {
            // Sometimes the loop polls in the silence before this byte.
            if rng.chance(30) {
                let at = now.wrapping_add(rng.below(gap));
                serve(&mut rx, at, &mut map, &mut replies);
            }
            now = now.wrapping_add(gap);
            // The model.
            if gap > timing.t35_ticks {
                close(&mut segment, segment_bad, &mut expected);
                segment_bad = false;
            } else if gap > timing.t15_ticks && !segment.is_empty() {
                segment_bad = true;
            }
            segment.push(b);
            // The receiver.
            if rx.push(b, now) == Push::FrameWaiting {
                assert!(
                    serve(&mut rx, now, &mut map, &mut replies),
                    "a waiting frame"
                );
                assert_eq!(rx.push(b, now), Push::Taken);
            }
        }
        let good = (4..=256).contains(&sent.bytes.len()) && crc.of(&sent.bytes) == 0;
        match (good, sent.bytes[0]) {
            (true, OURS) => good_ours += 1,
            (true, 0) => broadcast += 1,
            (true, _) => others += 1,
            _ => bad += 1,
        }
        if map.data.commands.len() > 1000 {
            map.data.commands.clear();
        }
    }
    now = now.wrapping_add(timing.t35_ticks + 1);
    close(&mut segment, segment_bad, &mut expected);
    serve(&mut rx, now, &mut map, &mut replies);

    eprintln!(
        "{frames} frames: {good_ours} good for us, {broadcast} good broadcast, {others} good for others, {bad} bad; \
         {} expected replies, {} replies",
        expected.len(),
        replies.len()
    );
    assert_eq!(replies.len(), expected.len());
    for ((request, reply), want) in replies.iter().zip(&expected) {
        assert_eq!(request, want, "replies in the order of the requests");
        assert_eq!(crc.of(reply), 0);
        assert_eq!(reply[0], OURS);
        assert_eq!(reply[1] & 0x7F, request[1] & 0x7F);
    }
    // Good frames for us lost only to a silence too short before them or
    // after them (3 % of frames each), or an inner gap (3 %).
    assert!(
        expected.len() as u32 > good_ours / 10 * 8,
        "most good frames for us are answered"
    );
    assert!(
        bad > frames / 4 && broadcast > frames / 20 && others > frames / 20,
        "every kind of frame is sent"
    );
}

/// Requests straight to the server, past the CRC that guards it on the
/// wire: mutated and random PDUs of every length. A reply exactly when the
/// frame is for us and has a function code; never to broadcast.
#[test]
fn a_million_pdus_to_the_server() {
    let frames: u32 = std::env::var("MODBUS_FUZZ_FRAMES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let crc = Crc::new();
    let mut rng = Rng(0xC0FF_EE00_1234);
    let mut out = [0_u8; 256];
    let (mut answered, mut exceptions) = (0_u32, 0_u32);
    for n in 0..frames {
        let server = Server {
            address: OURS,
            writes_enabled: n % 4 != 0,
        };
        let mut map = SunSpecMap::new(common::Demo::new(OURS, n % 2 == 0), n % 3 != 0);
        let address = match rng.below(4) {
            0..=1 => OURS,
            2 => 0,
            _ => rng.byte(),
        };
        let mut f = request(&mut rng, address);
        for _ in 0..rng.below(4) {
            match rng.below(3) {
                0 if !f.is_empty() => {
                    let i = rng.below(f.len() as u32) as usize;
                    f[i] = rng.byte();
                }
                1 if !f.is_empty() => {
                    f.truncate(rng.below(f.len() as u32) as usize);
                }
                _ if f.len() < 254 => f.push(rng.byte()),
                _ => {}
            }
        }
        match server.handle(&f, &mut map, &mut out) {
            Some(len) => {
                assert!(f.len() >= 2 && f[0] == OURS, "{f:02x?}");
                assert!((5..=256).contains(&len));
                assert_eq!(crc.of(&out[..len]), 0);
                assert_eq!(out[1] & 0x7F, f[1] & 0x7F);
                answered += 1;
                if out[1] & 0x80 != 0 {
                    assert_eq!(len, 5);
                    assert!((1..=6).contains(&out[2]));
                    exceptions += 1;
                }
            }
            None => assert!(f.len() < 2 || f[0] != OURS, "{f:02x?}"),
        }
    }
    eprintln!("{frames} PDUs: {answered} answered, {exceptions} of them with an exception");
    assert!(answered > frames / 3 && exceptions > answered / 10 && exceptions < answered);
}
