//! The SunSpec register map of a dual-axis tracker.
//!
//! Point offsets, sizes, types, scale factors, enumerations and bits of
//! models 1 (Common), 601 (Tracker Controller) and 305 (GPS) are those of
//! the SunSpec Alliance's model definitions (SunSpec Information Model
//! Reference; the JSON models of the SunSpec Alliance's `pysunspec2`
//! package, which `tests/sunspec_layout.rs` checks this module against).
//! Offsets here count from the model's ID register (ID at 0, L at 1), as
//! those definitions do.
//!
//! The map starts at register 40000 (0-based on the wire) with the `SunS`
//! marker; then model 1, model 601 with one tracker block, model 305 when
//! the tracker has a GPS, the vendor model [`VENDOR_MODEL_ID`], and the end
//! marker (0xFFFF, 0).

use crate::pdu::{Exception, RegisterMap};

/// The first register of the map (0-based on the wire), as SunSpec
/// specifies.
pub const BASE_ADDR: u16 = 40000;
/// The `SunS` marker in the first two registers.
pub const SUNS_MARKER: [u16; 2] = [0x5375, 0x6E53];
/// The end marker's model ID (its length is 0).
pub const END_MODEL_ID: u16 = 0xFFFF;

/// SunSpec's value of an int32 point that is not implemented.
pub const NOT_IMPL_INT32: i32 = i32::MIN;
/// SunSpec's value of a uint16, enum16 or bitfield16 point that is not
/// implemented.
pub const NOT_IMPL_U16: u16 = 0xFFFF;
/// SunSpec's value of a pad register (and of an int16/sunssf not
/// implemented).
pub const PAD: u16 = 0x8000;

/// The scale factor of every angle in model 601 (`Dgr_SF`): hundredths of
/// a degree.
pub const DGR_SF: i16 = -2;
/// The scale factor of the vendor model's wind speed: tenths of m/s.
pub const WND_SPD_SF: i16 = -1;

/// Model 1, Common: point offsets from its ID register.
pub mod m1 {
    /// Model ID.
    pub const ID: u16 = 1;
    /// Model length (registers after ID and L).
    pub const LEN: u16 = 66;
    /// Manufacturer, string of 16 registers.
    pub const MN: u16 = 2;
    /// Model, string of 16 registers.
    pub const MD: u16 = 18;
    /// Options, string of 8 registers.
    pub const OPT: u16 = 34;
    /// Version, string of 8 registers.
    pub const VR: u16 = 42;
    /// Serial number, string of 16 registers.
    pub const SN: u16 = 50;
    /// Device address, uint16, read-write.
    pub const DA: u16 = 66;
    /// Pad.
    pub const PAD: u16 = 67;
}

/// Model 601, Tracker Controller: point offsets from its ID register.
pub mod m601 {
    /// Model ID.
    pub const ID: u16 = 601;
    /// Length of the fixed block after ID and L.
    pub const FIXED_LEN: u16 = 26;
    /// Length of one tracker (repeating) block.
    pub const TRACKER_LEN: u16 = 22;
    /// Model length with our one tracker.
    pub const LEN: u16 = FIXED_LEN + TRACKER_LEN;
    /// Controller name, string of 8 registers.
    pub const NAM: u16 = 2;
    /// Tracker type, enum16 (5 = Dual).
    pub const TYP: u16 = 10;
    /// Local date `YYYYMMDD`, string of 5 registers.
    pub const DT_LOC: u16 = 11;
    /// Local time `hhmmss`, string of 3 registers.
    pub const TM_LOC: u16 = 16;
    /// Day of the year, uint16.
    pub const DAY: u16 = 19;
    /// Global manual elevation target, int32, Dgr_SF, read-write.
    pub const GLBL_EL_CTL: u16 = 20;
    /// Global manual azimuth target, int32, Dgr_SF, read-write.
    pub const GLBL_AZ_CTL: u16 = 22;
    /// Global mode, enum16 (0 Automatic, 1 Manual, 2 Calibrate), read-write.
    pub const GLBL_CTL: u16 = 24;
    /// Global alarm, bitfield16 (0 SetPoint, 1 ObsEl, 2 ObsAz).
    pub const GLBL_ALM: u16 = 25;
    /// Scale factor of the angles, sunssf.
    pub const DGR_SF: u16 = 26;
    /// Number of trackers, uint16.
    pub const N: u16 = 27;
    /// Tracker: name, string of 8 registers.
    pub const TRK_ID: u16 = 28;
    /// Tracker: elevation target, int32, Dgr_SF.
    pub const EL_TRGT: u16 = 36;
    /// Tracker: azimuth target, int32, Dgr_SF.
    pub const AZ_TRGT: u16 = 38;
    /// Tracker: elevation position, int32, Dgr_SF.
    pub const EL_POS: u16 = 40;
    /// Tracker: azimuth position, int32, Dgr_SF.
    pub const AZ_POS: u16 = 42;
    /// Tracker: manual elevation target, int32, Dgr_SF, read-write.
    pub const EL_CTL: u16 = 44;
    /// Tracker: manual azimuth target, int32, Dgr_SF, read-write.
    pub const AZ_CTL: u16 = 46;
    /// Tracker: mode, enum16, read-write.
    pub const CTL: u16 = 48;
    /// Tracker: alarm, bitfield16.
    pub const ALM: u16 = 49;
    /// `Typ` of a dual-axis tracker.
    pub const TYP_DUAL: u16 = 5;
}

/// Model 305, GPS: point offsets from its ID register.
pub mod m305 {
    /// Model ID.
    pub const ID: u16 = 305;
    /// Model length.
    pub const LEN: u16 = 36;
    /// UTC time `hhmmss.sssZ`, string of 6 registers.
    pub const TM: u16 = 2;
    /// UTC date `YYYYMMDD`, string of 4 registers.
    pub const DATE: u16 = 8;
    /// Location text, string of 20 registers.
    pub const LOC: u16 = 12;
    /// Latitude, int32, degrees × 10⁻⁷.
    pub const LAT: u16 = 32;
    /// Longitude, int32, degrees × 10⁻⁷.
    pub const LONG: u16 = 34;
    /// Altitude, int32, metres.
    pub const ALT: u16 = 36;
}

/// The vendor model's ID (64xxx is SunSpec's vendor range).
pub const VENDOR_MODEL_ID: u16 = 64201;

/// The vendor model 64201, suntracker status: point offsets from its ID
/// register (its definition in pysunspec2's JSON form:
/// `modbus/sunspec/model_64201.json`).
pub mod m64201 {
    /// Model ID.
    pub const ID: u16 = super::VENDOR_MODEL_ID;
    /// Model length.
    pub const LEN: u16 = 12;
    /// The tracker's mode code, enum16 (0 service, 1 safe_stop, 2
    /// wind_stow, 3 command_stow, 4 manual, 5 wait_for_time, 6 night, 7
    /// homing, 8 tracking, 9 hail_stow, 10 external_stow, 11 snow_stow, 12
    /// low_supply_stow, 13 overcast: suntracker's `safety::Mode`, the codes
    /// kept as first published).
    pub const MODE: u16 = 2;
    /// Why the tracker is stowed, enum16 (0 not stowed, 1 wind, 2 command,
    /// 3 night, 4 fault, 5 time unknown, 6 hail, 7 the plant's stow
    /// contact, 8 snow, 9 low supply, 10 overcast).
    pub const STOW_RSN: u16 = 3;
    /// Wind speed, uint16, `WndSpd_SF` m/s.
    pub const WND_SPD: u16 = 4;
    /// Scale factor of the wind speed, sunssf (-1).
    pub const WND_SPD_SF: u16 = 5;
    /// Active faults, bitfield32 (bit n: the tracker's fault number n).
    pub const FLT: u16 = 6;
    /// Firmware version: major, minor, patch, uint16 each.
    pub const FW_MAJ: u16 = 8;
    /// Minor version.
    pub const FW_MIN: u16 = 9;
    /// Patch version.
    pub const FW_PAT: u16 = 10;
    /// Stow command, enum16, read-write: 1 stows, 0 releases the command.
    /// The only point a broadcast may write.
    pub const STOW: u16 = 11;
    /// Active faults numbered 32 to 47, bitfield16 (bit n: the tracker's
    /// fault number 32 + n).
    pub const FLT2: u16 = 12;
    /// Clear the faults, enum16, read-write: 1 clears the tracker's fault
    /// list as its console's `clear` does (a fault whose cause is still
    /// there is raised again); 0 does nothing; reads 0.
    pub const CLR_FLT: u16 = 13;
}

/// The identity strings of model 1 and the names of model 601 (ASCII;
/// longer ones are cut to their point's size).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Identity<'a> {
    /// Manufacturer (`Mn`, 32 characters).
    pub manufacturer: &'a str,
    /// Model (`Md`, 32 characters).
    pub model: &'a str,
    /// Options (`Opt`, 16 characters).
    pub options: &'a str,
    /// Firmware version (`Vr`, 16 characters).
    pub version: &'a str,
    /// Serial number (`SN`, 32 characters).
    pub serial: &'a str,
    /// Controller name (601 `Nam`, 16 characters).
    pub controller_name: &'a str,
    /// The tracker's name (601 tracker `Id`, 16 characters).
    pub tracker_name: &'a str,
}

/// A calendar date and time of day.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DateTime {
    /// Year (0 to 9999).
    pub year: u16,
    /// Month, 1 to 12.
    pub month: u8,
    /// Day of the month, 1 to 31.
    pub day: u8,
    /// Hour, 0 to 23.
    pub hour: u8,
    /// Minute.
    pub minute: u8,
    /// Second.
    pub second: u8,
    /// Milliseconds (model 305's time only).
    pub millisecond: u16,
    /// Day of the year, 1 to 366 (model 601's `Day` only).
    pub day_of_year: u16,
}

/// Elevation (from the horizon, up) and azimuth (from true north through
/// east), hundredths of a degree (`Dgr_SF` = -2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Angles {
    /// Elevation above the horizon, 0.01°.
    pub elevation_cdeg: i32,
    /// Azimuth from true north through east, 0.01°.
    pub azimuth_cdeg: i32,
}

/// Model 601's control mode (`GlblCtl`, `Ctl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u16)]
pub enum Control {
    /// Tracks by itself.
    Automatic = 0,
    /// Holds the manual targets (`ElCtl`, `AzCtl`).
    Manual = 1,
    /// Calibrates (the tracker's homing).
    Calibrate = 2,
}

/// Model 601's alarm bits (`GlblAlm`, `Alm`).
pub mod alarm {
    /// Bit 0: the set-point cannot be reached (`SetPoint`).
    pub const SET_POINT: u16 = 1 << 0;
    /// Bit 1: an obstruction on the elevation axis (`ObsEl`).
    pub const OBS_EL: u16 = 1 << 1;
    /// Bit 2: an obstruction on the azimuth axis (`ObsAz`).
    pub const OBS_AZ: u16 = 1 << 2;
}

/// A GPS fix for model 305.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpsFix {
    /// UTC date and time of the fix.
    pub utc: DateTime,
    /// Latitude, degrees × 10⁻⁷, north positive.
    pub latitude_e7deg: i32,
    /// Longitude, degrees × 10⁻⁷, east positive.
    pub longitude_e7deg: i32,
    /// Altitude, metres.
    pub altitude_m: i32,
}

/// The vendor model's status values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VendorStatus {
    /// Mode code ([`m64201::MODE`]).
    pub mode_code: u16,
    /// Stow reason ([`m64201::STOW_RSN`]).
    pub stow_reason: u16,
    /// Wind speed, 0.1 m/s, when an anemometer is fitted.
    pub wind_speed_dms: Option<u16>,
    /// Active fault bits ([`m64201::FLT`]: faults 0 to 31).
    pub fault_bits: u32,
    /// Active fault bits of faults 32 to 47 ([`m64201::FLT2`]).
    pub fault_bits_hi: u16,
    /// Firmware version: major, minor, patch.
    pub firmware: [u16; 3],
    /// The stow command is on.
    pub stow_commanded: bool,
}

/// A write from the SCADA, checked against the point's type and range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    /// Model 1 `DA`: a new Modbus address, 1 to 247. The reply still goes
    /// out from the old one: change [`crate::Server::address`] after it.
    DeviceAddress(u8),
    /// `GlblElCtl` or `ElCtl`: the manual elevation target, 0.01°, -9,000 to 9,000.
    ManualElevation(i32),
    /// `GlblAzCtl` or `AzCtl`: the manual azimuth target, 0.01°, 0 to 36,000.
    ManualAzimuth(i32),
    /// `GlblCtl` or `Ctl`: the control mode.
    Control(Control),
    /// Vendor `Stow`: stow (true) or release the stow command (false).
    Stow(bool),
    /// Vendor `ClrFlt` = 1: clear the fault list.
    ClearFaults,
}

/// What the tracker gives the map, and takes from it.
///
/// Reads happen between two loop passes of the firmware (the server runs in
/// the main loop), so the values of one request are consistent.
pub trait TrackerData {
    /// Identity strings.
    fn identity(&self) -> Identity<'_>;
    /// Our Modbus address (model 1 `DA`).
    fn device_address(&self) -> u8;
    /// Local date and time, when the time is known.
    fn local_time(&self) -> Option<DateTime>;
    /// Where the tracker aims now (the sun, a stow pose), when known.
    fn target_cdeg(&self) -> Option<Angles>;
    /// Where the tracker points, when known.
    fn position_cdeg(&self) -> Option<Angles>;
    /// The control mode.
    fn control(&self) -> Control;
    /// The manual targets, when set.
    fn manual_target_cdeg(&self) -> Option<Angles>;
    /// Alarm bits ([`alarm`]).
    fn alarms(&self) -> u16;
    /// The GPS fix, when a GPS is fitted and has one.
    fn gps_fix(&self) -> Option<GpsFix>;
    /// Vendor status values.
    fn vendor(&self) -> VendorStatus;
    /// Carries out a write; its refusal is the exception the SCADA gets
    /// (e.g. [`Exception::IllegalDataValue`] for a target outside the
    /// tracker's limits, [`Exception::ServerDeviceBusy`] while homing).
    fn command(&mut self, command: Command) -> Result<(), Exception>;
}

/// The SunSpec map over a [`TrackerData`]; a [`RegisterMap`] for the
/// [`crate::pdu::Server`].
#[derive(Debug, Clone)]
pub struct SunSpecMap<D> {
    /// The tracker's data.
    pub data: D,
    gps: bool,
}

/// Where a register lies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Place {
    Marker(u16),
    Common(u16),
    Tracker(u16),
    Gps(u16),
    Vendor(u16),
    End(u16),
}

/// Register `i` of a string point (two ASCII characters, the first in the
/// high byte; NUL past its end).
fn text(s: &[u8], i: u16) -> u16 {
    let at = usize::from(i) * 2;
    u16::from_be_bytes([
        s.get(at).copied().unwrap_or(0),
        s.get(at + 1).copied().unwrap_or(0),
    ])
}

/// Two ASCII digits of `value % 100` in one register. Not inlined: its
/// divisions by constants expand to multiplications on the AVR, 60-odd
/// bytes a copy (measured: `modbus/avr_size.sh`).
#[inline(never)]
fn two_digits(value: u16) -> u16 {
    let v = (value % 100) as u8;
    u16::from_be_bytes([b'0' + v / 10, b'0' + v % 10])
}

/// Register `i` of the string `YYYYMMDD` (two digits a register).
fn date_reg(t: &DateTime, i: u16) -> u16 {
    match i {
        0 => two_digits(t.year / 100),
        1 => two_digits(t.year),
        2 => two_digits(u16::from(t.month)),
        3 => two_digits(u16::from(t.day)),
        _ => 0,
    }
}

/// Register `i` of the string `hhmmss`, or `hhmmss.sssZ` when `millis`.
fn time_reg(t: &DateTime, i: u16, millis: bool) -> u16 {
    match i {
        0 => two_digits(u16::from(t.hour)),
        1 => two_digits(u16::from(t.minute)),
        2 => two_digits(u16::from(t.second)),
        3 if millis => u16::from_be_bytes([b'.', b'0' + (t.millisecond / 100 % 10) as u8]),
        4 if millis => two_digits(t.millisecond),
        5 if millis => u16::from_be_bytes([b'Z', 0]),
        _ => 0,
    }
}

/// Register `i` (0 or 1) of an int32 point, high word first.
fn word(v: i32, i: u16) -> u16 {
    let v = v as u32;
    if i == 0 {
        (v >> 16) as u16
    } else {
        v as u16
    }
}

/// Where register `off` lies in the point of `len` registers at `at`
/// (0 for its first), if it is one of them.
fn in_point(off: u16, at: u16, len: u16) -> Option<u16> {
    off.checked_sub(at).filter(|&i| i < len)
}

impl<D: TrackerData> SunSpecMap<D> {
    /// The map of `data`; `gps` puts model 305 in it.
    pub const fn new(data: D, gps: bool) -> Self {
        Self { data, gps }
    }

    /// Register of model 1's ID.
    pub const fn common_addr(&self) -> u16 {
        BASE_ADDR + 2
    }
    /// Register of model 601's ID.
    pub const fn tracker_addr(&self) -> u16 {
        self.common_addr() + 2 + m1::LEN
    }
    /// Register of model 305's ID, when it is in the map.
    pub const fn gps_addr(&self) -> Option<u16> {
        if self.gps {
            Some(self.tracker_addr() + 2 + m601::LEN)
        } else {
            None
        }
    }
    /// Register of the vendor model's ID.
    pub const fn vendor_addr(&self) -> u16 {
        let after_tracker = self.tracker_addr() + 2 + m601::LEN;
        if self.gps {
            after_tracker + 2 + m305::LEN
        } else {
            after_tracker
        }
    }
    /// Register of the end marker.
    pub const fn end_addr(&self) -> u16 {
        self.vendor_addr() + 2 + m64201::LEN
    }

    fn place(&self, addr: u16) -> Option<Place> {
        let rel = addr.checked_sub(BASE_ADDR)?;
        let common = self.common_addr();
        let tracker = self.tracker_addr();
        let vendor = self.vendor_addr();
        let end = self.end_addr();
        Some(if addr < common {
            Place::Marker(rel)
        } else if addr < tracker {
            Place::Common(addr - common)
        } else if addr < tracker + 2 + m601::LEN {
            Place::Tracker(addr - tracker)
        } else if addr < vendor {
            Place::Gps(addr - (tracker + 2 + m601::LEN))
        } else if addr < end {
            Place::Vendor(addr - vendor)
        } else if addr < end + 2 {
            Place::End(addr - end)
        } else {
            return None;
        })
    }

    fn read_common(&self, off: u16) -> u16 {
        // The five strings lie end to end from Mn to SN.
        if (m1::MN..m1::DA).contains(&off) {
            let id = self.data.identity();
            let (s, at) = if off < m1::MD {
                (id.manufacturer, m1::MN)
            } else if off < m1::OPT {
                (id.model, m1::MD)
            } else if off < m1::VR {
                (id.options, m1::OPT)
            } else if off < m1::SN {
                (id.version, m1::VR)
            } else {
                (id.serial, m1::SN)
            };
            return text(s.as_bytes(), off - at);
        }
        match off {
            0 => m1::ID,
            1 => m1::LEN,
            m1::DA => u16::from(self.data.device_address()),
            _ => PAD,
        }
    }

    fn read_tracker(&self, off: u16) -> u16 {
        let d = &self.data;
        // Register `i` of an elevation, azimuth pair of int32 points.
        let angle = |a: Option<Angles>, i: u16| {
            let a = a.unwrap_or(Angles {
                elevation_cdeg: NOT_IMPL_INT32,
                azimuth_cdeg: NOT_IMPL_INT32,
            });
            if i < 2 {
                word(a.elevation_cdeg, i)
            } else {
                word(a.azimuth_cdeg, i - 2)
            }
        };
        // Each value fetched only for its own registers.
        if let Some(i) = in_point(off, m601::GLBL_EL_CTL, 4) {
            return angle(d.manual_target_cdeg(), i);
        }
        if let Some(i) = in_point(off, m601::EL_CTL, 4) {
            return angle(d.manual_target_cdeg(), i);
        }
        if let Some(i) = in_point(off, m601::EL_TRGT, 4) {
            return angle(d.target_cdeg(), i);
        }
        if let Some(i) = in_point(off, m601::EL_POS, 4) {
            return angle(d.position_cdeg(), i);
        }
        if let Some(i) = in_point(off, m601::NAM, 8) {
            return text(d.identity().controller_name.as_bytes(), i);
        }
        if let Some(i) = in_point(off, m601::TRK_ID, 8) {
            return text(d.identity().tracker_name.as_bytes(), i);
        }
        if let Some(i) = in_point(off, m601::DT_LOC, 5) {
            return d.local_time().map_or(0, |t| date_reg(&t, i));
        }
        if let Some(i) = in_point(off, m601::TM_LOC, 3) {
            return d.local_time().map_or(0, |t| time_reg(&t, i, false));
        }
        match off {
            0 => m601::ID,
            1 => m601::LEN,
            m601::TYP => m601::TYP_DUAL,
            m601::DAY => d.local_time().map_or(NOT_IMPL_U16, |t| t.day_of_year),
            m601::GLBL_CTL | m601::CTL => d.control() as u16,
            m601::GLBL_ALM | m601::ALM => d.alarms(),
            m601::DGR_SF => DGR_SF as u16,
            m601::N => 1,
            _ => PAD,
        }
    }

    fn read_gps(&self, off: u16) -> u16 {
        match off {
            0 => return m305::ID,
            1 => return m305::LEN,
            _ => {}
        }
        let Some(fix) = self.data.gps_fix() else {
            // Strings all NUL, numbers "not implemented".
            return if off >= m305::LAT {
                word(NOT_IMPL_INT32, (off - m305::LAT) % 2)
            } else {
                0
            };
        };
        if let Some(i) = in_point(off, m305::TM, 6) {
            return time_reg(&fix.utc, i, true);
        }
        if let Some(i) = in_point(off, m305::DATE, 4) {
            return date_reg(&fix.utc, i);
        }
        let numbers = [
            (m305::LAT, fix.latitude_e7deg),
            (m305::LONG, fix.longitude_e7deg),
            (m305::ALT, fix.altitude_m),
        ];
        for (at, value) in numbers {
            if let Some(i) = in_point(off, at, 2) {
                return word(value, i);
            }
        }
        // Loc: no text.
        0
    }

    fn read_vendor(&self, off: u16) -> u16 {
        let v = self.data.vendor();
        if let Some(i) = in_point(off, m64201::FLT, 2) {
            return word(v.fault_bits as i32, i);
        }
        match off {
            0 => m64201::ID,
            1 => m64201::LEN,
            m64201::MODE => v.mode_code,
            m64201::STOW_RSN => v.stow_reason,
            m64201::WND_SPD => v.wind_speed_dms.unwrap_or(NOT_IMPL_U16),
            m64201::WND_SPD_SF => WND_SPD_SF as u16,
            m64201::FW_MAJ => v.firmware[0],
            m64201::FW_MIN => v.firmware[1],
            m64201::FW_PAT => v.firmware[2],
            m64201::STOW => u16::from(v.stow_commanded),
            m64201::FLT2 => v.fault_bits_hi,
            m64201::CLR_FLT => 0,
            _ => PAD,
        }
    }

    /// The writable point starting at `addr`: its size in registers and
    /// how to turn its value into a command.
    fn writable(&self, addr: u16) -> Option<(u16, Writable)> {
        Some(match self.place(addr)? {
            Place::Common(m1::DA) => (1, Writable::Address),
            Place::Tracker(m601::GLBL_EL_CTL | m601::EL_CTL) => (2, Writable::Elevation),
            Place::Tracker(m601::GLBL_AZ_CTL | m601::AZ_CTL) => (2, Writable::Azimuth),
            Place::Tracker(m601::GLBL_CTL | m601::CTL) => (1, Writable::Control),
            Place::Vendor(m64201::STOW) => (1, Writable::Stow),
            Place::Vendor(m64201::CLR_FLT) => (1, Writable::ClearFaults),
            _ => return None,
        })
    }
}

/// The kinds of writable point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Writable {
    Address,
    Elevation,
    Azimuth,
    Control,
    Stow,
    ClearFaults,
}

impl Writable {
    /// The command a value written asks for (`None`: nothing to do), or
    /// exception 03 for a value outside the point's range.
    fn command(self, raw: u32) -> Result<Option<Command>, Exception> {
        let signed = raw as i32;
        let value = raw as u16;
        let bad = Exception::IllegalDataValue;
        Ok(Some(match self {
            Writable::Address => match value {
                1..=247 => Command::DeviceAddress(value as u8),
                _ => return Err(bad),
            },
            Writable::Elevation => match signed {
                -9_000..=9_000 => Command::ManualElevation(signed),
                _ => return Err(bad),
            },
            Writable::Azimuth => match signed {
                0..=36_000 => Command::ManualAzimuth(signed),
                _ => return Err(bad),
            },
            Writable::Control => Command::Control(match value {
                0 => Control::Automatic,
                1 => Control::Manual,
                2 => Control::Calibrate,
                _ => return Err(bad),
            }),
            Writable::Stow => match value {
                0 | 1 => Command::Stow(value == 1),
                _ => return Err(bad),
            },
            Writable::ClearFaults => match value {
                0 => return Ok(None),
                1 => Command::ClearFaults,
                _ => return Err(bad),
            },
        }))
    }
}

impl<D: TrackerData> RegisterMap for SunSpecMap<D> {
    fn check_read(&mut self, start: u16, count: u16) -> Result<(), Exception> {
        let last = start
            .checked_add(count.saturating_sub(1))
            .ok_or(Exception::IllegalDataAddress)?;
        if start >= BASE_ADDR && last < self.end_addr() + 2 {
            Ok(())
        } else {
            Err(Exception::IllegalDataAddress)
        }
    }

    #[cfg_attr(target_arch = "avr", inline(never))]
    fn read(&mut self, addr: u16) -> u16 {
        match self.place(addr) {
            Some(Place::Marker(i)) => SUNS_MARKER[usize::from(i & 1)],
            Some(Place::Common(off)) => self.read_common(off),
            Some(Place::Tracker(off)) => self.read_tracker(off),
            Some(Place::Gps(off)) => self.read_gps(off),
            Some(Place::Vendor(off)) => self.read_vendor(off),
            Some(Place::End(0)) => END_MODEL_ID,
            Some(Place::End(_)) | None => 0,
        }
    }

    /// Every point written must be writable and written whole (both
    /// registers of an int32), else [`Exception::IllegalDataAddress`];
    /// every value must fit its point, else
    /// [`Exception::IllegalDataValue`]. All are checked before the first
    /// is carried out; the tracker then takes them in order and its first
    /// refusal ends the request (the points before it stay written). A
    /// broadcast may write only the stow command.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn write(&mut self, start: u16, values: &[u8], broadcast: bool) -> Result<(), Exception> {
        let count = values.len() / 2;
        for apply in [false, true] {
            let mut i = 0;
            while i < count {
                let addr = u16::try_from(i).ok().and_then(|i| start.checked_add(i));
                let (size, kind) = addr
                    .and_then(|a| self.writable(a))
                    .ok_or(Exception::IllegalDataAddress)?;
                let size = usize::from(size);
                let words = values
                    .get(i * 2..(i + size) * 2)
                    .ok_or(Exception::IllegalDataAddress)?;
                let raw = words
                    .iter()
                    .fold(0_u32, |acc, &b| (acc << 8) | u32::from(b));
                let command = kind.command(raw)?;
                if broadcast && kind != Writable::Stow {
                    return Err(Exception::IllegalFunction);
                }
                if let (true, Some(command)) = (apply, command) {
                    self.data.command(command)?;
                }
                i += size;
            }
        }
        Ok(())
    }
}
