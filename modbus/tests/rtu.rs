//! The RTU frame layer against Modbus over Serial Line V1.02, §2.5.1.1.

use suntracker_modbus::crc::crc16;
use suntracker_modbus::rtu::{Push, RtuReceiver, RtuTiming, MAX_FRAME_BYTES};

const READ_10: [u8; 8] = [0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD];

fn with_crc(body: &[u8]) -> Vec<u8> {
    let mut v = body.to_vec();
    v.extend_from_slice(&crc16(body).to_le_bytes());
    v
}

/// Feeds `bytes` one every `step` ticks from `t`; the time of the last.
fn feed(rx: &mut RtuReceiver, bytes: &[u8], t: u32, step: u32) -> u32 {
    let mut now = t;
    for (i, &b) in bytes.iter().enumerate() {
        now = t.wrapping_add(step * i as u32);
        assert_eq!(rx.push(b, now), Push::Taken);
    }
    now
}

#[test]
fn character_times() {
    // 11 bits a character: 1.5 chars = 16.5 bit times, 3.5 = 38.5.
    assert_eq!(
        RtuTiming::from_baud_us(9600),
        RtuTiming {
            t15_ticks: 1719,
            t35_ticks: 4011
        }
    );
    assert_eq!(
        RtuTiming::from_baud_us(19_200),
        RtuTiming {
            t15_ticks: 860,
            t35_ticks: 2006
        }
    );
    // Fixed above 19,200 baud.
    assert_eq!(
        RtuTiming::from_baud_us(38_400),
        RtuTiming {
            t15_ticks: 750,
            t35_ticks: 1750
        }
    );
    assert_eq!(
        RtuTiming::from_baud_us(115_200),
        RtuTiming {
            t15_ticks: 750,
            t35_ticks: 1750
        }
    );
}

#[test]
fn frame_after_three_and_a_half_characters_of_silence() {
    let timing = RtuTiming::from_baud_us(19_200);
    let mut rx = RtuReceiver::new(timing);
    let last = feed(&mut rx, &READ_10, 1000, 573);
    // Not yet at 3.5 characters.
    assert_eq!(rx.poll(last + timing.t35_ticks), None);
    assert_eq!(rx.poll(last + timing.t35_ticks + 1), Some(&READ_10[..6]));
    // Taken once.
    assert_eq!(rx.poll(last + 10 * timing.t35_ticks), None);
}

#[test]
fn inner_gap_over_one_and_a_half_characters_discards() {
    let timing = RtuTiming::from_baud_us(9600);
    let mut rx = RtuReceiver::new(timing);
    let t = feed(&mut rx, &READ_10[..3], 0, 100);
    // A gap of 1.5 characters exactly is still inside the frame.
    let t = feed(&mut rx, &READ_10[3..4], t + timing.t15_ticks, 100);
    assert_eq!(rx.poll(t + 1), None);
    let t = feed(&mut rx, &READ_10[4..], t + timing.t15_ticks + 1, 100);
    assert_eq!(rx.poll(t + timing.t35_ticks + 1), None);
    // The next frame is taken.
    let t = feed(&mut rx, &READ_10, t + 2 * timing.t35_ticks, 100);
    assert_eq!(rx.poll(t + timing.t35_ticks + 1), Some(&READ_10[..6]));
}

#[test]
fn bytes_of_a_discarded_frame_extend_it() {
    let timing = RtuTiming::from_baud_us(9600);
    let mut rx = RtuReceiver::new(timing);
    let t = feed(&mut rx, &READ_10[..2], 0, 100);
    // A gap between 1.5 and 3.5 characters, then the whole frame: all one
    // discarded frame, since no silence of 3.5 characters separates them.
    let t = feed(&mut rx, &READ_10, t + timing.t35_ticks, 100);
    assert_eq!(rx.poll(t + timing.t35_ticks + 1), None);
}

#[test]
fn bad_crc_dropped() {
    let mut frame = READ_10;
    frame[7] ^= 0x01;
    let mut rx = RtuReceiver::new(RtuTiming::from_baud_us(19_200));
    let t = feed(&mut rx, &frame, 0, 100);
    assert_eq!(rx.poll(t + 5000), None);
}

#[test]
fn short_frames_dropped() {
    let mut rx = RtuReceiver::new(RtuTiming::from_baud_us(19_200));
    // Three bytes can't hold an address, a function code and a CRC, even
    // when their CRC residue is zero.
    let three = with_crc(&[0x01]);
    let t = feed(&mut rx, &three, 0, 100);
    assert_eq!(rx.poll(t + 5000), None);
}

#[test]
fn longest_frame_taken_longer_dropped() {
    let timing = RtuTiming::from_baud_us(115_200);
    let mut rx = RtuReceiver::new(timing);
    let body: Vec<u8> = (0..MAX_FRAME_BYTES - 2).map(|i| i as u8).collect();
    let frame = with_crc(&body);
    assert_eq!(frame.len(), 256);
    let t = feed(&mut rx, &frame, 0, 87);
    assert_eq!(rx.poll(t + 2000), Some(&body[..]));

    let body: Vec<u8> = (0..MAX_FRAME_BYTES - 1).map(|i| i as u8).collect();
    let frame = with_crc(&body);
    let t = feed(&mut rx, &frame, t + 10_000, 87);
    assert_eq!(rx.poll(t + 2000), None);
}

#[test]
fn next_frame_before_poll_waits() {
    let timing = RtuTiming::from_baud_us(9600);
    let mut rx = RtuReceiver::new(timing);
    let t = feed(&mut rx, &READ_10, 0, 1000);
    // The next request's first byte came (its time stamp read from a
    // queue) before we polled: the finished frame goes first.
    let next = t + timing.t35_ticks + 1;
    assert_eq!(rx.push(0x01, next), Push::FrameWaiting);
    assert_eq!(rx.poll(next), Some(&READ_10[..6]));
    assert_eq!(rx.push(0x01, next), Push::Taken);
    let t = feed(&mut rx, &READ_10[1..], next + 1000, 1000);
    assert_eq!(rx.poll(t + timing.t35_ticks + 1), Some(&READ_10[..6]));
}

#[test]
fn clock_wraps() {
    let timing = RtuTiming::from_baud_us(19_200);
    let mut rx = RtuReceiver::new(timing);
    let t = feed(&mut rx, &READ_10, u32::MAX - 1500, 500);
    assert!(t < 10_000, "the clock wrapped during the frame");
    assert_eq!(rx.poll(t.wrapping_add(timing.t35_ticks)), None);
    assert_eq!(
        rx.poll(t.wrapping_add(timing.t35_ticks + 1)),
        Some(&READ_10[..6])
    );
}

#[test]
fn reset_waits_for_silence() {
    let timing = RtuTiming::from_baud_us(19_200);
    let mut rx = RtuReceiver::new(timing);
    rx.reset(timing, 0);
    // Bytes within 3.5 characters of the reset are the tail of something
    // we did not see the start of.
    let t = feed(&mut rx, &READ_10, 1000, 100);
    assert_eq!(rx.poll(t + timing.t35_ticks + 1), None);
    let t = feed(&mut rx, &READ_10, t + 3 * timing.t35_ticks, 100);
    assert_eq!(rx.poll(t + timing.t35_ticks + 1), Some(&READ_10[..6]));
}

#[test]
fn frame_in_place() {
    let timing = RtuTiming::from_baud_us(19_200);
    let mut rx = RtuReceiver::new(timing);
    let t = feed(&mut rx, &READ_10, 0, 573);
    let (buf, len) = rx.poll_in_place(t + timing.t35_ticks + 1).unwrap();
    assert_eq!((&buf[..len], buf.len()), (&READ_10[..6], MAX_FRAME_BYTES));
    // Written over, then the next frame.
    buf.fill(0);
    let t = feed(&mut rx, &READ_10, t + 10_000, 573);
    assert_eq!(rx.poll(t + timing.t35_ticks + 1), Some(&READ_10[..6]));
}
