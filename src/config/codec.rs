//! The configuration's binary payload, layout version 10
//! ([`super::LAYOUT_VERSION`]): the fields of the key table ([`super::KEYS`],
//! which lists them in declaration order) but the derived counts per
//! degree, in its order, with the operator's hold after the fields of
//! version 3 ([`V3_KEYS`]) and the fields added since (`modbus.*`,
//! `stow.*`, `supply.*`, `overcast.*` in version 4, `axis.c.continuous`
//! in version 5, `site.utc_offset_h`, `wind.m_s_per_hz` and
//! `modbus.timeout_stow` in version 6, each axis's `drive`,
//! `max_current_ma` and `overcurrent_ms` in version 7, each axis's
//! `back_speed_deg_s` in version 8, `supply.calibration_mv` in version 9, each axis's linear actuator
//! (`pivot_a_mm` to `pot_extended_counts`) in version 10) after it;
//! little-endian, [`PAYLOAD_LEN`] bytes. The payloads of versions 2
//! ([`PAYLOAD_LEN_V2`], without the hold), 3 ([`PAYLOAD_LEN_V3`]), 4
//! ([`PAYLOAD_LEN_V4`]), 5 ([`PAYLOAD_LEN_V5`]), 6 ([`PAYLOAD_LEN_V6`])
//! 7 ([`PAYLOAD_LEN_V7`]), 8 ([`PAYLOAD_LEN_V8`]) and 9
//! ([`PAYLOAD_LEN_V9`]) are still read, the
//! fields they lack at their defaults. Also the
//! little-endian cursors that write and read it (the store writes its slot
//! header with the same writer).

use super::{slot, Config, Slot, KEYS, KEY_LIST};
use crate::persist::{Payload, PayloadBytes};
use crate::safety::OperatorHold;

/// Payload length of layout version 2 (version 1 had no `log` fields).
pub const PAYLOAD_LEN_V2: usize = 12 + 20 + 2 * 34 + 12 + 13 + 16 + 2;

/// Payload length of layout version 3: version 2's and the operator's
/// hold, one byte ([`OperatorHold::to_bits`]).
pub const PAYLOAD_LEN_V3: usize = PAYLOAD_LEN_V2 + 1;

/// Payload length of layout version 4: version 3's, the Modbus server's
/// settings (address, baud, parity, write, timeout: 11 bytes), the weather
/// stows' (three slopes, two release times, a level, the sensor-fault
/// switch: 22 bytes), the supply watch's (two thresholds: 4 bytes) and
/// the overcast mode's (a ratio, two times, a count: 13 bytes).
pub const PAYLOAD_LEN_V4: usize = PAYLOAD_LEN_V3 + 11 + 22 + 4 + 13;

/// Payload length of layout version 5: version 4's and the C axis's
/// `continuous` switch (1 byte).
pub const PAYLOAD_LEN_V5: usize = PAYLOAD_LEN_V4 + 1;

/// Payload length of layout version 6: version 5's, the site's UTC offset
/// (4 bytes), the anemometer's m/s per Hz (4 bytes) and the Modbus
/// silence's stow switch (1 byte).
pub const PAYLOAD_LEN_V6: usize = PAYLOAD_LEN_V5 + 4 + 4 + 1;

/// Payload length of layout version 7: version 6's and each axis's drive
/// kind (1 byte), current limit and overcurrent time (2 bytes each).
pub const PAYLOAD_LEN_V7: usize = PAYLOAD_LEN_V6 + 2 * (1 + 2 + 2);

/// Payload length of layout version 8: version 7's and each axis's
/// backward speed (4 bytes).
pub const PAYLOAD_LEN_V8: usize = PAYLOAD_LEN_V7 + 2 * 4;

/// Payload length of layout version 9: version 8's and the timed axes'
/// calibration supply (2 bytes).
pub const PAYLOAD_LEN_V9: usize = PAYLOAD_LEN_V8 + 2;

/// Payload length of layout version 10: version 9's and each axis's
/// linear actuator (six lengths, angles and scales of 4 bytes, two ADC
/// readings of 2). An image built without the `linear` feature writes
/// version 9, the length below.
#[cfg(feature = "linear")]
pub const PAYLOAD_LEN: usize = PAYLOAD_LEN_V9 + 2 * (6 * 4 + 2 * 2);
/// Payload length of this image's layout: version 9's, without the
/// linear actuators' keys (the `linear` feature adds them: version 10).
#[cfg(not(feature = "linear"))]
pub const PAYLOAD_LEN: usize = PAYLOAD_LEN_V9;

/// How many of [`KEYS`] there are up to and including `last`: the keys of
/// a layout version that ended with it.
const fn keys_through(last: super::Field) -> usize {
    let mut i = 0;
    while i < KEY_LIST.len() && KEY_LIST[i] as usize != last as usize {
        i += 1;
    }
    i + 1
}

/// The keys of layout version 9, the first of [`KEYS`]: those up to
/// `supply.calibration_mv`.
const V9_KEYS: usize = keys_through(super::Field::SupplyCalibrationMv);

/// The keys of layout version 8, the first of [`KEYS`]: those up to the A
/// axis's `back_speed_deg_s`.
const V8_KEYS: usize = keys_through(super::Field::AxisABackSpeedDegS);

/// The keys of layout version 7, the first of [`KEYS`]: those up to the A
/// axis's `overcurrent_ms`.
const V7_KEYS: usize = keys_through(super::Field::AxisAOvercurrentMs);

/// The keys of layout version 6, the first of [`KEYS`]: those up to
/// `modbus.timeout_stow`.
const V6_KEYS: usize = keys_through(super::Field::ModbusTimeoutStow);

/// The keys of layout version 5, the first of [`KEYS`]: those up to
/// `axis.c.continuous`.
const V5_KEYS: usize = keys_through(super::Field::AxisCContinuous);

/// The keys of layout version 4, the first of [`KEYS`]: those up to
/// `overcast.max_moves_per_hour`.
const V4_KEYS: usize = keys_through(super::Field::OvercastMaxMovesPerHour);

/// The keys of layout versions 2 and 3, the first of [`KEYS`]: those up to
/// `log.status_min`. The operator's hold follows them; the keys after are
/// newer.
const V3_KEYS: usize = keys_through(super::Field::LogStatusMin);

/// A little-endian writer into `buf` from `pos`; a write past the end
/// sets `overflow` and writes nothing.
pub(crate) struct Writer<'a> {
    pub(crate) buf: &'a mut [u8],
    pub(crate) pos: usize,
    pub(crate) overflow: bool,
}

impl Writer<'_> {
    /// Not inlined: a record's encoder calls it once for each field.
    #[inline(never)]
    pub(crate) fn bytes(&mut self, b: &[u8]) {
        match self.buf.get_mut(self.pos..self.pos + b.len()) {
            Some(dst) => {
                crate::bytes::copy_prefix(dst, b);
            }
            None => self.overflow = true,
        }
        self.pos += b.len();
    }
    /// `v`'s low `n` bytes (1, 2 or 4), little-endian: one writer for
    /// every width.
    pub(crate) fn word(&mut self, v: u32, n: usize) {
        match v.to_le_bytes().get(..n) {
            Some(b) => self.bytes(b),
            None => self.overflow = true,
        }
    }
}

/// A little-endian reader of a payload, in order.
struct Reader<'a> {
    payload: &'a mut dyn Payload,
    /// Bytes read.
    pos: usize,
}

impl Reader<'_> {
    /// The next `n` bytes (1, 2 or 4), little-endian, widened: one reader
    /// for every width.
    fn word(&mut self, n: usize) -> Option<u32> {
        let mut a = [0u8; 4];
        let part = a.get_mut(..n)?;
        let ok = self.payload.read(part);
        self.pos += n;
        ok.then_some(u32::from_le_bytes(a))
    }
}

impl Config {
    /// Serialises into `buf` (at least [`PAYLOAD_LEN`] bytes); returns the
    /// length written, or `None` when `buf` is too small.
    pub fn encode(&self, buf: &mut [u8]) -> Option<usize> {
        let mut w = Writer {
            buf,
            pos: 0,
            overflow: false,
        };
        // Each field by its slot in the table (a copy: the slots are
        // mutable references).
        let mut fields = *self;
        for i in 0..KEYS.len() {
            let Some(key) = KEYS.get(i) else { break };
            if i == V3_KEYS {
                w.word(u32::from(self.hold.to_bits()), 1);
            }
            match slot(&mut fields, key) {
                Slot::F32(v) => w.word(v.to_bits(), 4),
                Slot::U32(v) => w.word(*v, 4),
                Slot::U16(v) => w.word(u32::from(*v), 2),
                Slot::U8(v) => w.word(u32::from(*v), 1),
                Slot::Derived => {}
            }
        }
        if w.overflow {
            None
        } else {
            Some(w.pos)
        }
    }

    /// Parses a payload of layout version 10, or of version 9 (without the
    /// axes' linear actuators: their defaults), 8 (also without the
    /// timed axes' calibration supply: 0, unscaled), 7 (also without the
    /// axes' backward speeds: the defaults), 6 (also without the
    /// axes' drive kinds and current watch: steppers, the defaults), 5
    /// (also without the
    /// UTC offset, the anemometer's factor and the Modbus silence's stow:
    /// 0, 0, off), 4 (also without `axis.c.continuous`: off), 3 (also without the Modbus, stow, supply
    /// and overcast settings: their defaults) or 2 (also without the hold:
    /// none is in force), and checks every value; `None` for a buffer of
    /// another length or any value out of range.
    pub fn decode(buf: &[u8]) -> Option<Config> {
        let mut cfg = Config::default();
        Config::decode_from(&mut PayloadBytes::new(buf), &mut cfg).then_some(cfg)
    }

    /// [`Config::decode`] of the payload `payload` reads, into `cfg` in
    /// place: true when it was good, now in `cfg`; false for a wrong
    /// length, a value out of range or a failed read, with `cfg` holding
    /// fields of it and the defaults (not a configuration to use). The
    /// store reads a slot this way, from the storage into its caller's
    /// copy: a payload buffer and a configuration returned were two more
    /// on an 8-bit board's stack.
    pub(crate) fn decode_from(payload: &mut dyn Payload, cfg: &mut Config) -> bool {
        let len = payload.length();
        let mut r = Reader { payload, pos: 0 };
        // The fields a payload has are read; the others keep their
        // defaults.
        super::table::write_defaults(cfg);
        for i in 0..KEYS.len() {
            let Some(key) = KEYS.get(i) else { break };
            if (i == V4_KEYS && len == PAYLOAD_LEN_V4)
                || (i == V5_KEYS && len == PAYLOAD_LEN_V5)
                || (i == V6_KEYS && len == PAYLOAD_LEN_V6)
                || (i == V7_KEYS && len == PAYLOAD_LEN_V7)
                || (i == V8_KEYS && len == PAYLOAD_LEN_V8)
                || (cfg!(feature = "linear") && i == V9_KEYS && len == PAYLOAD_LEN_V9)
            {
                break;
            }
            if i == V3_KEYS {
                if len == PAYLOAD_LEN_V2 {
                    break;
                }
                let Some(hold) = r.word(1).and_then(|b| OperatorHold::from_bits(b as u8)) else {
                    return false;
                };
                cfg.hold = hold;
                if len == PAYLOAD_LEN_V3 {
                    break;
                }
            }
            let read = match slot(cfg, key) {
                // Each narrowing keeps the bytes read (`word`'s width).
                Slot::F32(v) => r.word(4).map(|x| *v = f32::from_bits(x)),
                Slot::U32(v) => r.word(4).map(|x| *v = x),
                Slot::U16(v) => r.word(2).map(|x| *v = x as u16),
                Slot::U8(v) => r.word(1).map(|x| *v = x as u8),
                Slot::Derived => Some(()),
            };
            if read.is_none() {
                return false;
            }
        }
        r.pos == len && cfg.check_in_place().is_ok()
    }
}
