//! The configuration's binary payload, layout version 3
//! ([`super::LAYOUT_VERSION`]): every field of the key table
//! ([`super::KEYS`], which lists them in declaration order) but the derived
//! counts per degree, in its order, then the operator's hold; little-endian,
//! [`PAYLOAD_LEN`] bytes (version 2's, without the
//! operator's hold, [`PAYLOAD_LEN_V2`], is still read); and the little-endian cursors
//! that write and read it (the store writes its slot header with the same
//! writer).

use super::{slot, Config, Slot, KEYS};
use crate::safety::OperatorHold;

/// Payload length of layout version 2 (version 1 had no `log` fields).
pub const PAYLOAD_LEN_V2: usize = 12 + 20 + 2 * 34 + 12 + 13 + 16 + 2;

/// Payload length of layout version 3: version 2's and the operator's
/// hold, one byte ([`OperatorHold::to_bits`]).
pub const PAYLOAD_LEN: usize = PAYLOAD_LEN_V2 + 1;

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
    pub(crate) fn u8(&mut self, v: u8) {
        self.bytes(&[v]);
    }
    pub(crate) fn u16(&mut self, v: u16) {
        self.bytes(&v.to_le_bytes());
    }
    pub(crate) fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
    pub(crate) fn f32(&mut self, v: f32) {
        self.bytes(&v.to_le_bytes());
    }
}

/// A little-endian reader of `buf` from `pos`.
struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn take<const K: usize>(&mut self) -> Option<[u8; K]> {
        let s = self.buf.get(self.pos..self.pos + K)?;
        self.pos += K;
        let mut a = [0u8; K];
        a.copy_from_slice(s);
        Some(a)
    }
    fn u8(&mut self) -> Option<u8> {
        self.take::<1>().map(|a| a[0])
    }
    fn u16(&mut self) -> Option<u16> {
        self.take().map(u16::from_le_bytes)
    }
    fn u32(&mut self) -> Option<u32> {
        self.take().map(u32::from_le_bytes)
    }
    fn f32(&mut self) -> Option<f32> {
        self.u32().map(f32::from_bits)
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
        for &key in KEYS {
            match slot(&mut fields, key) {
                Slot::F32(v) => w.f32(*v),
                Slot::U32(v) => w.u32(*v),
                Slot::U16(v) => w.u16(*v),
                Slot::U8(v) => w.u8(*v),
                Slot::Derived => {}
            }
        }
        w.u8(self.hold.to_bits());
        if w.overflow {
            None
        } else {
            Some(w.pos)
        }
    }

    /// Parses a payload of layout version 3, or of version 2 (which has no
    /// hold: none is in force), and checks every value; `None` for a
    /// buffer of another length or any value out of range.
    pub fn decode(buf: &[u8]) -> Option<Config> {
        let mut r = Reader { buf, pos: 0 };
        // Every field is read; the defaults only give the value its type.
        let mut cfg = Config::default();
        for &key in KEYS {
            match slot(&mut cfg, key) {
                Slot::F32(v) => *v = r.f32()?,
                Slot::U32(v) => *v = r.u32()?,
                Slot::U16(v) => *v = r.u16()?,
                Slot::U8(v) => *v = r.u8()?,
                Slot::Derived => {}
            }
        }
        let hold = if buf.len() == PAYLOAD_LEN_V2 {
            OperatorHold::default()
        } else {
            OperatorHold::from_bits(r.u8()?)?
        };
        if r.pos != buf.len() {
            return None;
        }
        cfg.hold = hold;
        cfg.is_valid().then_some(cfg)
    }
}
