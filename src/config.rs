//! Configuration: site, mechanics, limits, intervals and calibration, kept
//! in a versioned binary layout with a CRC-32 in two slots.
//!
//! # Layout (little-endian)
//! Each slot is [`SLOT_LEN`] bytes at offset `slot × SLOT_LEN`:
//!
//! | bytes | field |
//! |---|---|
//! | 0..4 | magic `b"STCF"` |
//! | 4..6 | layout version ([`LAYOUT_VERSION`]) |
//! | 6..8 | payload length `n` |
//! | 8..12 | sequence number (wrapping) |
//! | 12..12+n | payload ([`Config::encode`]) |
//! | 12+n..16+n | CRC-32 (IEEE 802.3, reflected, poly 0xEDB88320) of bytes 0..12+n |
//!
//! A save writes the slot that does *not* hold the newest good copy, with the
//! next sequence number; an interrupted write leaves at worst that slot
//! corrupt and the other one good. A load takes the good slot with the
//! newest sequence; a bad CRC, a wrong magic or version, a payload of the
//! wrong length or values out of range make a slot bad as a whole. With no
//! good slot the defaults are used. Nothing is ever applied in part.

use crate::scheduler::ScheduleConfig;
use crate::traits::Storage;

/// Layout version written by this firmware.
pub const LAYOUT_VERSION: u16 = 1;
/// Bytes per slot.
pub const SLOT_LEN: usize = 256;
/// Header bytes before the payload.
const HEADER_LEN: usize = 12;
const MAGIC: [u8; 4] = *b"STCF";

/// CRC-32 (IEEE 802.3: reflected, polynomial 0xEDB88320, initial and final
/// XOR 0xFFFFFFFF), bit by bit: small code, no table.
pub fn crc32(data: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &b in data {
        crc ^= u32::from(b);
        for _ in 0..8 {
            let mask = (crc & 1).wrapping_neg();
            crc = (crc >> 1) ^ (0xEDB8_8320 & mask);
        }
    }
    !crc
}

/// The tracker's site.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SiteConfig {
    /// Latitude, degrees north.
    pub latitude_deg: f32,
    /// Longitude, degrees east.
    pub longitude_deg: f32,
    /// Elevation, metres.
    pub elevation_m: f32,
}

/// Mechanics and limits of one axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisConfig {
    /// Motor full steps per motor revolution (stepper) or encoder counts per
    /// motor revolution (servo).
    pub counts_per_motor_rev: u32,
    /// Microsteps per full step (1 for a servo).
    pub microsteps: u16,
    /// Gear ratio, motor revolutions per axis revolution.
    pub gear_ratio: f32,
    /// Soft limit, lowest angle, degrees.
    pub min_deg: f32,
    /// Soft limit, highest angle, degrees.
    pub max_deg: f32,
    /// Angle of the homing limit switch, degrees.
    pub home_deg: f32,
    /// Backlash of the gear train, degrees.
    pub backlash_deg: f32,
    /// Highest axis speed, degrees per second.
    pub max_speed_deg_s: f32,
    /// Closed-loop deadband, degrees.
    pub deadband_deg: f32,
}

impl AxisConfig {
    /// Motor counts per axis degree: counts × microsteps × gear / 360.
    pub fn counts_per_deg(&self) -> f32 {
        self.counts_per_motor_rev as f32 * f32::from(self.microsteps) * self.gear_ratio / 360.0
    }

    fn is_valid(&self) -> bool {
        let finite = [
            self.gear_ratio,
            self.min_deg,
            self.max_deg,
            self.home_deg,
            self.backlash_deg,
            self.max_speed_deg_s,
            self.deadband_deg,
        ]
        .iter()
        .all(|v| v.is_finite());
        finite
            && self.counts_per_motor_rev > 0
            && self.microsteps > 0
            && self.gear_ratio > 0.0
            && self.min_deg < self.max_deg
            && self.min_deg >= -360.0
            && self.max_deg <= 360.0
            && self.home_deg >= self.min_deg - 5.0
            && self.home_deg <= self.max_deg + 5.0
            && (0.0..=10.0).contains(&self.backlash_deg)
            && self.max_speed_deg_s > 0.0
            && (0.0..=10.0).contains(&self.deadband_deg)
    }
}

/// Wind stow (anemometer pulse rate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindConfig {
    /// Pulse rate that means "too windy", Hz.
    pub threshold_hz: f32,
    /// Seconds above the threshold before stowing.
    pub hold_s: u32,
    /// Seconds of calm (below the threshold) before leaving stow.
    pub release_s: u32,
}

/// Fault thresholds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SafetyConfig {
    /// Largest allowed difference between set-point and feedback, degrees.
    pub max_deviation_deg: f32,
    /// Seconds a driven axis may show no encoder motion before "stalled".
    pub stall_timeout_s: u32,
    /// Seconds without a sensor reading before "timeout".
    pub sensor_timeout_s: u32,
    /// Retries of a failed operation before degrading.
    pub max_retries: u8,
}

/// Sensor calibration offsets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibration {
    /// Magnetic declination, degrees east (true = magnetic + declination).
    pub declination_deg: f32,
    /// Compass mounting offset, degrees.
    pub heading_offset_deg: f32,
    /// Inclinometer x offset, degrees.
    pub tilt_x_offset_deg: f32,
    /// Inclinometer y offset, degrees.
    pub tilt_y_offset_deg: f32,
}

/// The whole configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    /// Site (used until GPS gives one).
    pub site: SiteConfig,
    /// Scheduler intervals.
    pub schedule: ScheduleConfig,
    /// C axis (vertical at home), then A axis.
    pub axes: [AxisConfig; 2],
    /// Wind stow.
    pub wind: WindConfig,
    /// Fault thresholds.
    pub safety: SafetyConfig,
    /// Calibration offsets.
    pub calibration: Calibration,
}

impl Default for Config {
    /// Kano (seed jimoh-2019's site); 1.8° steppers with 16 microsteps and a
    /// 100:1 worm gear; the seed's 4-minute table, 2-minute hold, 30-second
    /// re-check.
    fn default() -> Self {
        let axis = AxisConfig {
            counts_per_motor_rev: 200,
            microsteps: 16,
            gear_ratio: 100.0,
            min_deg: -180.0,
            max_deg: 180.0,
            home_deg: -180.0,
            backlash_deg: 0.2,
            max_speed_deg_s: 2.0,
            deadband_deg: 0.05,
        };
        Config {
            site: SiteConfig {
                latitude_deg: 11.9683,
                longitude_deg: 8.4261,
                elevation_m: 480.0,
            },
            schedule: ScheduleConfig::default(),
            axes: [
                axis,
                AxisConfig {
                    min_deg: -90.0,
                    max_deg: 90.0,
                    home_deg: -90.0,
                    ..axis
                },
            ],
            wind: WindConfig {
                threshold_hz: 25.0,
                hold_s: 3,
                release_s: 600,
            },
            safety: SafetyConfig {
                max_deviation_deg: 5.0,
                stall_timeout_s: 5,
                sensor_timeout_s: 10,
                max_retries: 3,
            },
            calibration: Calibration {
                declination_deg: 0.0,
                heading_offset_deg: 0.0,
                tilt_x_offset_deg: 0.0,
                tilt_y_offset_deg: 0.0,
            },
        }
    }
}

/// Payload length of layout version 1.
pub const PAYLOAD_LEN: usize = 12 + 20 + 2 * 34 + 12 + 13 + 16;

struct Writer<'a> {
    buf: &'a mut [u8],
    pos: usize,
    overflow: bool,
}

impl Writer<'_> {
    fn bytes(&mut self, b: &[u8]) {
        match self.buf.get_mut(self.pos..self.pos + b.len()) {
            Some(dst) => dst.copy_from_slice(b),
            None => self.overflow = true,
        }
        self.pos += b.len();
    }
    fn u8(&mut self, v: u8) {
        self.bytes(&[v]);
    }
    fn u16(&mut self, v: u16) {
        self.bytes(&v.to_le_bytes());
    }
    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
    fn f32(&mut self, v: f32) {
        self.bytes(&v.to_le_bytes());
    }
}

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
        self.take().map(f32::from_le_bytes)
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
        if w.overflow {
            None
        } else {
            Some(w.pos)
        }
    }

    /// Parses a payload of layout version 1 and checks every value; `None`
    /// for a short buffer or any value out of range.
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
        };
        cfg.is_valid().then_some(cfg)
    }

    /// Every value inside its range.
    pub fn is_valid(&self) -> bool {
        let s = &self.site;
        let site_ok = s.latitude_deg.is_finite()
            && s.longitude_deg.is_finite()
            && s.elevation_m.is_finite()
            && s.latitude_deg.abs() <= 90.0
            && s.longitude_deg.abs() <= 180.0
            && (-500.0..=10_000.0).contains(&s.elevation_m);
        let sc = &self.schedule;
        let sched_ok = sc.table_step_s > 0
            && sc.table_step_s.is_multiple_of(60)
            && 86_400 % sc.table_step_s == 0
            && sc.recheck_s > 0
            && sc.max_tick_gap_s > 0;
        let w = &self.wind;
        let wind_ok = w.threshold_hz.is_finite() && w.threshold_hz > 0.0;
        let sf = &self.safety;
        let safety_ok = sf.max_deviation_deg.is_finite()
            && sf.max_deviation_deg > 0.0
            && sf.stall_timeout_s > 0
            && sf.sensor_timeout_s > 0;
        let c = &self.calibration;
        let cal_ok = [
            c.declination_deg,
            c.heading_offset_deg,
            c.tilt_x_offset_deg,
            c.tilt_y_offset_deg,
        ]
        .iter()
        .all(|v| v.is_finite() && v.abs() <= 180.0);
        site_ok
            && sched_ok
            && self.axes.iter().all(AxisConfig::is_valid)
            && wind_ok
            && safety_ok
            && cal_ok
    }
}

/// Why a slot was not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlotState {
    /// Good, with its sequence number.
    Good(u32),
    /// Never written (magic missing).
    Empty,
    /// Written by another layout version.
    OldVersion(u16),
    /// CRC, length or a value is wrong.
    Corrupt,
    /// The storage could not be read.
    Unreadable,
}

/// The result of [`ConfigStore::load`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Loaded {
    /// The configuration in force (defaults when no slot was good).
    pub config: Config,
    /// True when `config` are the defaults because no slot was good.
    pub defaults: bool,
    /// What each slot held.
    pub slots: [SlotState; 2],
}

/// Errors of [`ConfigStore::save`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SaveError<E> {
    /// The configuration has a value out of range.
    Invalid,
    /// The storage is smaller than two slots.
    TooSmall,
    /// The storage failed.
    Storage(E),
}

/// Two-slot configuration store over a [`Storage`].
#[derive(Debug)]
pub struct ConfigStore<S> {
    storage: S,
    newest: Option<(usize, u32)>,
}

fn seq_newer(a: u32, b: u32) -> bool {
    // Serial-number arithmetic (RFC 1982 style): a is newer than b.
    a != b && a.wrapping_sub(b) < 0x8000_0000
}

impl<S: Storage> ConfigStore<S> {
    /// A store over `storage`.
    pub fn new(storage: S) -> Self {
        ConfigStore {
            storage,
            newest: None,
        }
    }

    /// Gives the storage back.
    pub fn release(self) -> S {
        self.storage
    }

    fn read_slot(&mut self, slot: usize) -> (SlotState, Option<Config>) {
        let mut buf = [0u8; SLOT_LEN];
        if self.storage.read(slot * SLOT_LEN, &mut buf).is_err() {
            return (SlotState::Unreadable, None);
        }
        if buf.get(0..4) != Some(&MAGIC[..]) {
            return (SlotState::Empty, None);
        }
        let field = |a: usize, b: usize| buf.get(a..b);
        let version = field(4, 6).map(|s| u16::from_le_bytes([s[0], s[1]]));
        let len = field(6, 8).map(|s| usize::from(u16::from_le_bytes([s[0], s[1]])));
        let seq = field(8, 12).map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]));
        let (Some(version), Some(len), Some(seq)) = (version, len, seq) else {
            return (SlotState::Corrupt, None);
        };
        let end = HEADER_LEN + len;
        let (Some(body), Some(crc_bytes)) = (buf.get(..end), buf.get(end..end + 4)) else {
            return (SlotState::Corrupt, None);
        };
        let stored = u32::from_le_bytes([crc_bytes[0], crc_bytes[1], crc_bytes[2], crc_bytes[3]]);
        if crc32(body) != stored {
            return (SlotState::Corrupt, None);
        }
        if version != LAYOUT_VERSION {
            return (SlotState::OldVersion(version), None);
        }
        match body.get(HEADER_LEN..).and_then(Config::decode) {
            Some(cfg) => (SlotState::Good(seq), Some(cfg)),
            None => (SlotState::Corrupt, None),
        }
    }

    /// Reads both slots and returns the newest good configuration, or the
    /// defaults when neither is good.
    pub fn load(&mut self) -> Loaded {
        let (s0, c0) = self.read_slot(0);
        let (s1, c1) = self.read_slot(1);
        let pick = match (s0, s1) {
            (SlotState::Good(a), SlotState::Good(b)) => {
                if seq_newer(b, a) {
                    Some((1, b, c1))
                } else {
                    Some((0, a, c0))
                }
            }
            (SlotState::Good(a), _) => Some((0, a, c0)),
            (_, SlotState::Good(b)) => Some((1, b, c1)),
            _ => None,
        };
        match pick {
            Some((slot, seq, Some(cfg))) => {
                self.newest = Some((slot, seq));
                Loaded {
                    config: cfg,
                    defaults: false,
                    slots: [s0, s1],
                }
            }
            _ => {
                self.newest = None;
                Loaded {
                    config: Config::default(),
                    defaults: true,
                    slots: [s0, s1],
                }
            }
        }
    }

    /// Writes `cfg` into the slot not holding the newest good copy.
    pub fn save(&mut self, cfg: &Config) -> Result<(), SaveError<S::Error>> {
        if !cfg.is_valid() {
            return Err(SaveError::Invalid);
        }
        if self.storage.capacity() < 2 * SLOT_LEN {
            return Err(SaveError::TooSmall);
        }
        if self.newest.is_none() {
            // Find out which slot is newest before overwriting anything.
            self.load();
        }
        let (slot, seq) = match self.newest {
            Some((s, q)) => (1 - s, q.wrapping_add(1)),
            None => (0, 1),
        };
        let mut buf = [0u8; SLOT_LEN];
        let n = {
            let payload = buf.get_mut(HEADER_LEN..).ok_or(SaveError::TooSmall)?;
            cfg.encode(payload).ok_or(SaveError::TooSmall)?
        };
        let len = u16::try_from(n).map_err(|_| SaveError::TooSmall)?;
        let mut w = Writer {
            buf: &mut buf,
            pos: 0,
            overflow: false,
        };
        w.bytes(&MAGIC);
        w.u16(LAYOUT_VERSION);
        w.u16(len);
        w.u32(seq);
        let end = HEADER_LEN + n;
        let crc = crc32(buf.get(..end).ok_or(SaveError::TooSmall)?);
        let mut w = Writer {
            buf: &mut buf,
            pos: end,
            overflow: false,
        };
        w.u32(crc);
        if w.overflow {
            return Err(SaveError::TooSmall);
        }
        let data = buf.get(..end + 4).ok_or(SaveError::TooSmall)?;
        self.storage
            .write(slot * SLOT_LEN, data)
            .map_err(SaveError::Storage)?;
        self.newest = Some((slot, seq));
        Ok(())
    }
}

/// Storage in RAM (tests, simulation): `N` bytes, erased to 0xFF.
#[derive(Debug, Clone)]
pub struct MemStorage<const N: usize> {
    /// The bytes.
    pub bytes: [u8; N],
    /// When `Some(k)`, the next write stops after `k` bytes and fails, as a
    /// power cut would (then the budget is cleared).
    pub tear_after: Option<usize>,
}

/// Errors of [`MemStorage`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MemError {
    /// Access beyond the end.
    OutOfRange,
    /// The write was cut short.
    Torn,
}

impl<const N: usize> MemStorage<N> {
    /// Erased storage.
    pub fn new() -> Self {
        MemStorage {
            bytes: [0xFF; N],
            tear_after: None,
        }
    }
}

impl<const N: usize> Default for MemStorage<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Storage for MemStorage<N> {
    type Error = MemError;
    fn capacity(&self) -> usize {
        N
    }
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), MemError> {
        let src = self
            .bytes
            .get(offset..offset + buf.len())
            .ok_or(MemError::OutOfRange)?;
        buf.copy_from_slice(src);
        Ok(())
    }
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), MemError> {
        let dst = self
            .bytes
            .get_mut(offset..offset + data.len())
            .ok_or(MemError::OutOfRange)?;
        match self.tear_after.take() {
            Some(k) if k < data.len() => {
                if let (Some(d), Some(s)) = (dst.get_mut(..k), data.get(..k)) {
                    d.copy_from_slice(s);
                }
                Err(MemError::Torn)
            }
            _ => {
                dst.copy_from_slice(data);
                Ok(())
            }
        }
    }
}
