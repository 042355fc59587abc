//! The RTU frame layer: bytes in, whole frames out.
//!
//! Modbus over Serial Line Specification and Implementation Guide V1.02
//! (modbus.org, 2006), §2.5.1.1: a frame is a run of characters with
//! silences of at most 1.5 character times between them, ended by a silence
//! of at least 3.5 character times. A frame with a longer gap inside is
//! discarded, as is one over 256 bytes (§2.5.1: address, PDU of at most 253
//! bytes, CRC) and one whose CRC is wrong. Above 19,200 baud the spec fixes
//! the two times at 750 µs and 1,750 µs.
//!
//! The receiver is fed each byte with the time it arrived ([`RtuReceiver::push`])
//! and polled with the current time ([`RtuReceiver::poll`]); both are O(1)
//! (the CRC runs byte by byte as they come). Times are ticks of a wrapping
//! `u32` clock, [`RtuTiming::from_baud_us`] for a microsecond clock: poll at
//! least once every 2³¹ ticks (35 minutes of microseconds).

use crate::crc::{crc16_update, CRC_INIT};

/// The largest RTU frame, CRC included (Modbus over Serial Line V1.02, §2.5.1).
pub const MAX_FRAME_BYTES: usize = 256;

/// The silences of the frame layer, in ticks of the caller's clock.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RtuTiming {
    /// Longest silence between two characters of one frame (1.5 characters).
    pub t15_ticks: u32,
    /// Shortest silence that ends a frame (3.5 characters).
    pub t35_ticks: u32,
}

impl RtuTiming {
    /// The times in microseconds at `baud` bits per second with 11 bits a
    /// character (start, 8 data, parity or a second stop bit, stop: the
    /// serial line spec's §2.5.1), fixed at 750 µs / 1,750 µs above 19,200
    /// baud (§2.5.1.1). A baud rate of 0 is taken as the fixed times.
    pub fn from_baud_us(baud: u32) -> Self {
        if baud == 0 || baud > 19_200 {
            return Self {
                t15_ticks: 750,
                t35_ticks: 1_750,
            };
        }
        // 1.5 × 11 bits = 16.5 bit times, 3.5 × 11 = 38.5 bit times; rounded up.
        Self {
            t15_ticks: 16_500_000_u32.div_ceil(baud),
            t35_ticks: 38_500_000_u32.div_ceil(baud),
        }
    }
}

/// What [`RtuReceiver::push`] did with a byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Push {
    /// The byte was taken.
    Taken,
    /// The byte came after the silence that ends a frame, and that frame
    /// (whole, CRC good) is waiting: take it with [`RtuReceiver::poll`],
    /// then push the same byte again.
    FrameWaiting,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    /// Silent for at least 3.5 characters: the next byte starts a frame.
    Idle,
    /// Receiving a frame that is still good.
    Receiving,
    /// Receiving a frame that is already discarded (an inner gap, too
    /// long): bytes are dropped until a silence of 3.5 characters.
    Discarding,
}

/// The frame receiver (256 bytes of buffer).
#[derive(Debug, Clone)]
pub struct RtuReceiver {
    timing: RtuTiming,
    state: State,
    len: u16,
    crc: u16,
    last_tick: u32,
    buf: [u8; MAX_FRAME_BYTES],
}

impl RtuReceiver {
    /// A receiver with these silences, idle.
    pub const fn new(timing: RtuTiming) -> Self {
        Self {
            timing,
            state: State::Idle,
            len: 0,
            crc: CRC_INIT,
            last_tick: 0,
            buf: [0; MAX_FRAME_BYTES],
        }
    }

    /// The silences in use.
    pub fn timing(&self) -> RtuTiming {
        self.timing
    }

    /// Drops whatever is being received and waits for a silence of 3.5
    /// characters from `now` before taking a frame (the spec's start-up
    /// state, and after a change of baud rate).
    pub fn reset(&mut self, timing: RtuTiming, now: u32) {
        self.timing = timing;
        self.state = State::Discarding;
        self.len = 0;
        self.last_tick = now;
    }

    fn start(&mut self, byte: u8, now: u32) {
        self.state = State::Receiving;
        self.buf[0] = byte;
        self.len = 1;
        self.crc = crc16_update(CRC_INIT, byte);
        self.last_tick = now;
    }

    /// True when the frame just ended is worth handing on.
    fn complete(&self) -> bool {
        // Address, function code and two CRC bytes at least; the CRC over
        // everything, its own two bytes included, leaves zero.
        self.state == State::Receiving && self.len >= 4 && self.crc == 0
    }

    /// A byte that arrived at tick `now`.
    pub fn push(&mut self, byte: u8, now: u32) -> Push {
        let gap = now.wrapping_sub(self.last_tick);
        match self.state {
            State::Idle => self.start(byte, now),
            _ if gap > self.timing.t35_ticks => {
                // The frame before ended at its last byte's silence.
                if self.complete() {
                    return Push::FrameWaiting;
                }
                self.start(byte, now);
            }
            State::Receiving
                if gap <= self.timing.t15_ticks && usize::from(self.len) < MAX_FRAME_BYTES =>
            {
                self.buf[usize::from(self.len)] = byte;
                self.len += 1;
                self.crc = crc16_update(self.crc, byte);
                self.last_tick = now;
            }
            // An inner gap over 1.5 characters, a frame too long, or a
            // byte of a frame already discarded.
            State::Receiving | State::Discarding => {
                self.state = State::Discarding;
                self.last_tick = now;
            }
        }
        Push::Taken
    }

    /// The frame that ended by `now`, if one did and it is whole with a
    /// good CRC: address, function code and data, without the CRC. Frames
    /// that fail are dropped without a word.
    pub fn poll(&mut self, now: u32) -> Option<&[u8]> {
        let (buf, len) = self.poll_in_place(now)?;
        buf.get(..len)
    }

    /// As [`RtuReceiver::poll`], but the whole buffer and the frame's
    /// length (without the CRC), for a reply written over the request
    /// ([`crate::Server::handle_in_place`]). The buffer is free again at
    /// the next `push`.
    pub fn poll_in_place(&mut self, now: u32) -> Option<(&mut [u8; MAX_FRAME_BYTES], usize)> {
        if self.state == State::Idle || now.wrapping_sub(self.last_tick) <= self.timing.t35_ticks {
            return None;
        }
        let good = self.complete();
        self.state = State::Idle;
        let len = usize::from(self.len);
        self.len = 0;
        if good {
            Some((&mut self.buf, len.saturating_sub(2)))
        } else {
            None
        }
    }
}
