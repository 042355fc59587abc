//! The configuration's binary payload, layout version 3
//! ([`super::LAYOUT_VERSION`]): every field in declaration order,
//! little-endian, [`PAYLOAD_LEN`] bytes (version 2's, without the
//! operator's hold, [`PAYLOAD_LEN_V2`], is still read); and the little-endian cursors
//! that write and read it (the store writes its slot header with the same
//! writer).

use super::{AxisConfig, Calibration, Config, LogConfig, SafetyConfig, SiteConfig, WindConfig};
use crate::plan::ScheduleConfig;
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
    // Not inlined: some thirty fields call it (through `f32` too).
    #[inline(never)]
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
        w.f32(self.site.latitude_deg);
        w.f32(self.site.longitude_deg);
        w.f32(self.site.elevation_m);
        let s = &self.schedule;
        for v in [
            s.table_step_s,
            s.hold_s,
            s.recheck_s,
            s.max_tick_gap_s,
            s.max_backward_s,
        ] {
            w.u32(v);
        }
        for a in &self.axes {
            w.u32(a.counts_per_motor_rev);
            w.u16(a.microsteps);
            for v in [
                a.gear_ratio,
                a.min_deg,
                a.max_deg,
                a.home_deg,
                a.backlash_deg,
                a.max_speed_deg_s,
                a.deadband_deg,
            ] {
                w.f32(v);
            }
        }
        w.f32(self.wind.threshold_hz);
        w.u32(self.wind.hold_s);
        w.u32(self.wind.release_s);
        w.f32(self.safety.max_deviation_deg);
        w.u32(self.safety.stall_timeout_s);
        w.u32(self.safety.sensor_timeout_s);
        w.u8(self.safety.max_retries);
        let c = &self.calibration;
        for v in [
            c.declination_deg,
            c.heading_offset_deg,
            c.tilt_x_offset_deg,
            c.tilt_y_offset_deg,
        ] {
            w.f32(v);
        }
        w.u16(self.log.status_every_min);
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
        let site = SiteConfig {
            latitude_deg: r.f32()?,
            longitude_deg: r.f32()?,
            elevation_m: r.f32()?,
        };
        let schedule = ScheduleConfig {
            table_step_s: r.u32()?,
            hold_s: r.u32()?,
            recheck_s: r.u32()?,
            max_tick_gap_s: r.u32()?,
            max_backward_s: r.u32()?,
        };
        let mut axis = || -> Option<AxisConfig> {
            Some(AxisConfig {
                counts_per_motor_rev: r.u32()?,
                microsteps: r.u16()?,
                gear_ratio: r.f32()?,
                min_deg: r.f32()?,
                max_deg: r.f32()?,
                home_deg: r.f32()?,
                backlash_deg: r.f32()?,
                max_speed_deg_s: r.f32()?,
                deadband_deg: r.f32()?,
            })
        };
        let axes = [axis()?, axis()?];
        let wind = WindConfig {
            threshold_hz: r.f32()?,
            hold_s: r.u32()?,
            release_s: r.u32()?,
        };
        let safety = SafetyConfig {
            max_deviation_deg: r.f32()?,
            stall_timeout_s: r.u32()?,
            sensor_timeout_s: r.u32()?,
            max_retries: r.u8()?,
        };
        let calibration = Calibration {
            declination_deg: r.f32()?,
            heading_offset_deg: r.f32()?,
            tilt_x_offset_deg: r.f32()?,
            tilt_y_offset_deg: r.f32()?,
        };
        let log = LogConfig {
            status_every_min: r.u16()?,
        };
        let hold = if buf.len() == PAYLOAD_LEN_V2 {
            OperatorHold::default()
        } else {
            OperatorHold::from_bits(r.u8()?)?
        };
        if r.pos != buf.len() {
            return None;
        }
        let cfg = Config {
            site,
            schedule,
            axes,
            wind,
            safety,
            calibration,
            log,
            hold,
        };
        cfg.is_valid().then_some(cfg)
    }
}
