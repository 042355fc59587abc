//! The tracker on a Modbus RTU bus: the SunSpec map of `suntracker-modbus`
//! over what the firmware loop ([`Firmware`]) knows, and the port a board
//! drives once per loop pass ([`ModbusPort::poll`]).
//!
//! Board-independent: a board gives the port a [`ModbusLine`] (its RS-485
//! UART's received bytes with their arrival times in µs, and a send with the
//! transceiver's driver-enable around it) and calls [`ModbusPort::poll`]
//! after each [`Firmware::poll`]. The register map is the crate's
//! (`docs/src/modbus.md` lists it); this module supplies its values:
//!
//! | point | here |
//! |---|---|
//! | 601 `ElTrgt`, `AzTrgt` | while tracking: the set-point in force (Jimoh & Aliyu 2019: the panel normal toward the sun of its table time; elevation = 90° − slope); otherwise the normal of the pose commanded (stow, night, manual) |
//! | 601 `ElPos`, `AzPos` | the normal of the counted pose, through the mount's attitude ([`panel_normal_angles`]); unknown until both axes have homed |
//! | 601 `DtLoc`, `TmLoc`, `Day` | the trusted UTC of the last tick plus the monotonic time since, moved by `site.utc_offset_h` (0 by default: UTC) |
//! | 601 `GlblCtl`, `Ctl` | Manual under the operator's manual hold, Calibrate while homing, else Automatic |
//! | 601 `GlblElCtl`, `GlblAzCtl` | the manual pose's normal, else the targets last written |
//! | 601 `GlblAlm` | `SetPoint` for a deviation, stall or move time-out; `ObsEl` / `ObsAz` for an obstruction of the A / C axis |
//! | 305 | the GPS receiver's last fix with a position (when the board has a GPS), kept by the port: the loop's own fix expires a moment after each epoch |
//! | 64201 | the mode ([`mode_code`]), why stowed, the wind speed (the anemometer's rate times `wind.m_s_per_hz`), the active faults as bits ([`fault_bit`]), the version, the stow command, the fault clearing |
//!
//! Writes (when the settings allow them: [`ModbusSettings::write`]) do what
//! the console does: `GlblCtl` Manual is `jog`'s manual mode (to the targets
//! written, or where the axes stand), Automatic is `manual off`, Calibrate
//! is `home`, `Stow` is `stow` and its release, `ClrFlt` is `clear`; a
//! manual target is turned
//! into a pose by the same solver the tracker uses for the sun
//! ([`MountAttitude::choose`]) and refused with exception 03 when no pose
//! within the axes' soft limits reaches it (nothing moves). Inside the
//! service lock only the stow command is taken (exception 06 for the rest).
//! A command from the bus changes the hold in force but does not store it
//! (a power cut ends it), unlike the console's.
//!
//! A master that falls silent: `modbus.timeout_s` without a request to this
//! tracker ends a manual mode the bus set, and with `modbus.timeout_stow`
//! (once a master has been heard) commands a stow, which its next request
//! releases.
//!
//! Bounded work a pass: at most [`MODBUS_BYTES_PER_PASS`] bytes are taken
//! and at most one request served (a read of 125 registers computes 125
//! values, each from the state in memory: no sun position, no I/O), so a
//! flood of requests delays a controller tick by one request's service at
//! most.

use drivers::gps::FixQuality;
use drivers::rtc::Clock as RtcDriver;
use sun_algos::{Float, UtcTime};
use suntracker_modbus::rtu::MAX_FRAME_BYTES;
use suntracker_modbus::sunspec::{
    alarm, Angles, Command, Control, DateTime, GpsFix, Identity, VendorStatus,
};
use suntracker_modbus::{Exception, Push, RtuReceiver, RtuTiming, Server, SunSpecMap, TrackerData};

use crate::attitude::{sun_vector_xyz, Choice, MountAttitude, Pose, PoseLimits, Vec3};
use crate::config::{Config, ModbusConfig};
use crate::firmware::{Firmware, Motion};
use crate::log::Sink;
use crate::motion::AxisDrive;
use crate::ports::AttitudeSensor;
use crate::safety::{AxisId, Fault, Mode, Sensor};
use crate::time::{datetime_from_utc, monotonic};

/// The Modbus server's settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModbusSettings {
    /// Our address, 1 to 247.
    pub address: u8,
    /// Bits per second.
    pub baud: u32,
    /// 0 none (two stop bits), 1 odd, 2 even.
    pub parity: u8,
    /// Writes from the bus are carried out.
    pub write: bool,
    /// Seconds without a request to us after which a manual mode set over
    /// the bus ends (back to Automatic); 0 never.
    pub timeout_s: u32,
    /// The silence (`timeout_s`, once a master has been heard) also
    /// commands a stow, released by the master's next request.
    pub timeout_stow: bool,
}

/// The settings of a configuration's `modbus` keys.
pub const fn settings_of(m: &ModbusConfig) -> ModbusSettings {
    ModbusSettings {
        address: m.address,
        baud: m.baud,
        parity: m.parity,
        write: m.write != 0,
        timeout_s: m.timeout_s,
        timeout_stow: m.timeout_stow != 0,
    }
}

/// The default configuration's settings (the serial line spec's 19,200
/// baud with even parity, address 1, writes refused, no time-out): what
/// the port starts with before its first poll.
pub const MODBUS_DEFAULTS: ModbusSettings = settings_of(&Config::DEFAULT.modbus);

/// Bytes a pass takes from the line at most (a whole frame is 256).
pub const MODBUS_BYTES_PER_PASS: usize = 64;

/// A board's RS-485 port.
pub trait ModbusLine {
    /// The oldest byte received and not yet taken, with its arrival time
    /// (µs of a wrapping 32-bit clock, stamped in the receive interrupt).
    fn receive(&mut self) -> Option<(u8, u32)>;
    /// The present time on that clock.
    fn now_us(&mut self) -> u32;
    /// Sends a reply: the transceiver's driver enabled, the bytes out, the
    /// driver released once the last one has left. The port leaves the
    /// bytes of `frame` (its receive buffer) as they are while [`busy`]
    /// says true, so a line may go on sending from them after it returns,
    /// by interrupts, as long as the port itself stays where it is (the
    /// ATmega2560's line does, from a port that is a local of the loop
    /// that never returns).
    ///
    /// [`busy`]: ModbusLine::busy
    fn send(&mut self, frame: &[u8]);
    /// A reply is still going out: the port then takes no byte and serves
    /// nothing. A line that has sent everything when [`send`] returns
    /// (the default) is never busy.
    ///
    /// [`send`]: ModbusLine::send
    fn busy(&mut self) -> bool {
        false
    }
}

/// What the bus set, kept between requests.
#[derive(Debug, Clone, Copy, Default)]
struct Remote {
    /// A new address written to model 1's `DA`, taken after the reply.
    new_address: Option<u8>,
    /// The manual targets last written.
    target: Option<Angles>,
    /// The manual mode was set over the bus.
    manual_by_bus: bool,
    /// Monotonic ms of the last request to us.
    last_request_ms: u32,
    /// A request to us has come since start.
    heard: bool,
    /// The master's silence commanded the stow in force.
    silence_stow: bool,
}

/// The Modbus RTU server of a board's RS-485 port: receiver, server and
/// what the bus set (about 360 bytes of RAM).
pub struct ModbusPort {
    receiver: RtuReceiver,
    server: Server,
    identity: Identity<'static>,
    gps: bool,
    remote: Remote,
    /// A byte taken from the line that begins the next frame, while the
    /// frame before it waits to be served.
    held: Option<(u8, u32)>,
    /// The receiver's last fix with a position, for model 305 (the loop's
    /// fix expires a moment after each epoch), and the monotonic ms its
    /// time was received at (a new fix is converted once).
    last_fix: Option<GpsFix>,
    last_fix_ms: Option<u32>,
    settings: ModbusSettings,
}

impl ModbusPort {
    /// The port of a board: its identity strings, and whether it has a
    /// GPS (model 305 in the map). Takes its settings at the first poll.
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn new(identity: Identity<'static>, gps: bool) -> Self {
        ModbusPort {
            receiver: RtuReceiver::new(RtuTiming::from_baud_us(MODBUS_DEFAULTS.baud)),
            server: Server {
                address: MODBUS_DEFAULTS.address,
                writes_enabled: MODBUS_DEFAULTS.write,
            },
            identity,
            gps,
            remote: Remote::default(),
            held: None,
            last_fix: None,
            last_fix_ms: None,
            settings: MODBUS_DEFAULTS,
        }
    }

    /// The settings the port works with now.
    pub fn settings(&self) -> ModbusSettings {
        self.settings
    }

    /// The address answered now (the settings', or one written to `DA`).
    pub fn address(&self) -> u8 {
        self.server.address
    }

    /// One pass: takes at most [`MODBUS_BYTES_PER_PASS`] bytes from `line`
    /// and serves at most one request; never waits; nothing while the
    /// line is sending the last reply ([`ModbusLine::busy`]). `board_ms` is the
    /// board's monotonic ms ([`crate::firmware::Platform::now_ms`]). Not
    /// inlined: its frame (the map, the request's values) is then on the
    /// stack only during the call, not in the caller's for good.
    #[inline(never)]
    pub fn poll<T, R, G, D, S, L, const N: usize>(
        &mut self,
        fw: &mut Firmware<T, R, G, D, S, L, N>,
        line: &mut impl ModbusLine,
        board_ms: u64,
    ) where
        T: Float,
        R: RtcDriver,
        G: crate::hw::GpsInput<T>,
        D: AxisDrive + Motion,
        S: AttitudeSensor<T>,
        L: Sink,
    {
        if line.busy() {
            return;
        }
        let now_ms = monotonic::from_board_ms(board_ms);
        if let Some(fix) = fw.gps_fix() {
            if fix.utc_received_ms != self.last_fix_ms {
                if let Some(f) = model_305_fix(fix) {
                    self.last_fix = Some(f);
                    self.last_fix_ms = fix.utc_received_ms;
                }
            }
        }
        // The settings in force: the configuration's `modbus` keys.
        let settings = settings_of(&fw.controller().config().modbus);
        self.apply_settings(settings, line.now_us());
        let mut frame_at = None;
        for _ in 0..MODBUS_BYTES_PER_PASS {
            let Some((byte, t_us)) = self.held.take().or_else(|| line.receive()) else {
                break;
            };
            if self.receiver.push(byte, t_us) == Push::FrameWaiting {
                // The frame before this byte is whole: served now, the
                // byte pushed again at the next pass.
                self.held = Some((byte, t_us));
                frame_at = Some(t_us);
                break;
            }
        }
        let t_us = frame_at.unwrap_or_else(|| line.now_us());
        if let Some((buf, len)) = self.receiver.poll_in_place(t_us) {
            let mut map = SunSpecMap::new(
                FirmwareData {
                    fw: &mut *fw,
                    remote: &mut self.remote,
                    identity: &self.identity,
                    address: self.server.address,
                    now_ms,
                    gps: self.last_fix,
                },
                self.gps,
            );
            let to_us = buf.first() == Some(&self.server.address);
            if let Some(n) = self.server.handle_in_place(buf, len, &mut map) {
                line.send(buf.get(..n.min(MAX_FRAME_BYTES)).unwrap_or(&[]));
            }
            if to_us {
                self.remote.last_request_ms = now_ms;
                self.remote.heard = true;
                if self.remote.silence_stow {
                    // The master speaks again: the stow its silence made
                    // is released.
                    self.remote.silence_stow = false;
                    fw.controller_mut().command_stow(false);
                }
            }
            if let Some(a) = self.remote.new_address.take() {
                self.server.address = a;
            }
        }
        if self.timed_out(fw.controller().hold().manual, now_ms) {
            fw.controller_mut().manual(None);
        }
        if self.silence_stows(now_ms) {
            fw.controller_mut().command_stow(true);
        }
    }

    /// True once when a master heard before has been silent for
    /// `timeout_s` and the settings ask for a stow then.
    fn silence_stows(&mut self, now_ms: u32) -> bool {
        let timeout_ms = self.settings.timeout_s.saturating_mul(1000);
        let due = self.settings.timeout_stow
            && timeout_ms > 0
            && self.remote.heard
            && !self.remote.silence_stow
            && monotonic::elapsed_ms(now_ms, self.remote.last_request_ms) > timeout_ms;
        if due {
            self.remote.silence_stow = true;
        }
        due
    }

    /// Takes new settings: the address and writes at once, the frame
    /// timing of a new baud rate after a silence.
    fn apply_settings(&mut self, s: ModbusSettings, now_us: u32) {
        if s == self.settings {
            return;
        }
        if s.address != self.settings.address {
            self.server.address = s.address;
        }
        if s.baud != self.settings.baud {
            self.receiver.reset(RtuTiming::from_baud_us(s.baud), now_us);
        }
        self.server.writes_enabled = s.write;
        self.settings = s;
    }

    /// True when a manual mode the bus set (`manual`: the hold in force
    /// is manual) ends: `timeout_s` without a request to us.
    fn timed_out(&mut self, manual: bool, now_ms: u32) -> bool {
        let timeout_ms = self.settings.timeout_s.saturating_mul(1000);
        if !self.remote.manual_by_bus || timeout_ms == 0 {
            return false;
        }
        // Ended otherwise (the console), or by the time-out now.
        let ended =
            !manual || monotonic::elapsed_ms(now_ms, self.remote.last_request_ms) > timeout_ms;
        if ended {
            self.remote.manual_by_bus = false;
        }
        ended && manual
    }
}

/// Model 305's fix of a receiver's fix: `None` unless it is valid, with a
/// position and a time.
fn model_305_fix(fix: &drivers::gps::GpsFix) -> Option<GpsFix> {
    if fix.quality == FixQuality::Invalid {
        return None;
    }
    let (lat, lon) = (fix.latitude_deg?, fix.longitude_deg?);
    let utc = fix.utc?;
    let alt = fix.altitude_m.map_or(0.0, |m| m + 0.5);
    Some(GpsFix {
        utc: DateTime {
            year: utc.year(),
            month: utc.month(),
            day: utc.day(),
            hour: utc.hour(),
            minute: utc.minute(),
            second: utc.second(),
            millisecond: utc.millis(),
            day_of_year: 0,
        },
        latitude_e7deg: e7_deg(lat),
        longitude_e7deg: e7_deg(lon),
        altitude_m: Float::floor(alt) as i32,
    })
}

/// The firmware as the map's [`TrackerData`], for one request.
struct FirmwareData<'a, T, R, G: crate::hw::GpsInput<T>, D, S, L, const N: usize> {
    fw: &'a mut Firmware<T, R, G, D, S, L, N>,
    remote: &'a mut Remote,
    identity: &'a Identity<'static>,
    /// The address answered.
    address: u8,
    now_ms: u32,
    /// The receiver's last fix with a position (model 305).
    gps: Option<GpsFix>,
}

/// Hundredths of a degree, rounded (saturating; 0 for NaN).
fn cdeg<T: Float>(deg: T) -> i32 {
    (deg * T::from_f64(100.0) + T::from_f64(0.5))
        .floor()
        .to_f32() as i32
}

/// Elevation (from the horizon) and azimuth (from true north through east)
/// of a direction in the horizontal frame XYZ of Choi et al. (X west, Y
/// south, Z up; [`crate::attitude`]), 0.01°: `atan2(Z, √(X² + Y²))` and
/// `atan2(−X, −Y)` (east = −X, north = −Y), the inverse of
/// [`sun_vector_xyz`] (their eq. 13). Straight up the azimuth is 0.
pub fn direction_angles<T: Float>(v: &Vec3<T>) -> Angles {
    let horiz = (v[0] * v[0] + v[1] * v[1]).sqrt();
    Angles {
        elevation_cdeg: cdeg(v[2].atan2(horiz).to_degrees()),
        azimuth_cdeg: (-v[0]).atan2(-v[1]).to_degrees().centi_round_mod_turn() as i32,
    }
}

/// Where the panel normal points at `pose` on a mount of `attitude`: the
/// normal `n(γ, α) = Rz(γ)·Rx(α)·ẑ` of Choi et al. eq. 15–17 turned into
/// the horizontal frame by the mount's rotation (eq. 12,
/// [`MountAttitude::normal_xyz`]), as elevation and azimuth.
pub fn panel_normal_angles<T: Float>(attitude: &MountAttitude<T>, pose: &Pose<T>) -> Angles {
    direction_angles(&attitude.normal_xyz(pose))
}

/// The vendor model's mode code (`modbus/sunspec/model_64201.json`): 0 to 8
/// in the order [`Mode`] had when the model was first published, the
/// weather, plant and supply stows added after them (9 hail, 10 external,
/// 11 snow, 12 low supply) and overcast (13),
/// so that a code once read never changes meaning; [`Mode::Unwind`]
/// (following the sun, on the way to another branch) reads as tracking.
pub fn mode_code(mode: Mode) -> u16 {
    match mode {
        Mode::Service => 0,
        Mode::SafeStop => 1,
        Mode::WindStow => 2,
        Mode::CommandStow => 3,
        Mode::Manual => 4,
        Mode::WaitForTime => 5,
        Mode::Night => 6,
        Mode::Homing => 7,
        Mode::Unwind | Mode::Tracking => 8,
        Mode::HailStow => 9,
        Mode::ExternalStow => 10,
        Mode::SnowStow => 11,
        Mode::LowSupplyStow => 12,
        Mode::Overcast => 13,
    }
}

/// The vendor model's stow reason: 1 wind, 2 command, 3 night, 4 fault,
/// 5 time unknown, 6 hail, 7 the plant's stow contact, 8 snow, 9 low
/// supply, 10 overcast (the panel flat), 0 not stowed.
pub fn stow_reason(mode: Mode) -> u16 {
    match mode {
        Mode::WindStow => 1,
        Mode::CommandStow => 2,
        Mode::Night => 3,
        Mode::SafeStop => 4,
        Mode::WaitForTime => 5,
        Mode::HailStow => 6,
        Mode::ExternalStow => 7,
        Mode::SnowStow => 8,
        Mode::LowSupplyStow => 9,
        Mode::Overcast => 10,
        _ => 0,
    }
}

/// A fault's number in the list of fault names of the log and the console
/// (`Fault::name`: the sensor time-outs and bus errors by sensor,
/// inclinometer, compass, encoder C, encoder A, RTC, GPS; then each axis
/// fault C before A; the supply reading 31, the irradiance reading 32):
/// its bit in the vendor model's `Flt` when under 32, in `Flt2` (less 32)
/// from 32 ([`fault_bits`]).
pub fn fault_bit(fault: Fault) -> u32 {
    let sensor = |s: Sensor| match s {
        Sensor::Inclinometer => 0,
        Sensor::Compass => 1,
        Sensor::Encoder(AxisId::C) => 2,
        Sensor::Encoder(AxisId::A) => 3,
        Sensor::Rtc => 4,
        Sensor::Gps => 5,
    };
    let axis = |first: u32, a: AxisId| if a == AxisId::C { first } else { first + 1 };
    match fault {
        Fault::SensorTimeout(s) => sensor(s),
        Fault::I2cError(s) => 6 + sensor(s),
        Fault::GpsLost => 12,
        Fault::RtcInvalid => 13,
        Fault::MotorStalled(a) => axis(14, a),
        Fault::SetPointDeviation(a) => axis(16, a),
        Fault::LimitSwitchHit(a) => axis(18, a),
        Fault::GpsTimeImplausible => 20,
        Fault::GpsTimeUnstable => 21,
        Fault::GpsPositionUnstable => 22,
        Fault::TimeOutOfRange => 23,
        Fault::ScheduleFailed => 24,
        Fault::Obstruction(a) => axis(25, a),
        Fault::UnexpectedMotion(a) => axis(27, a),
        Fault::MoveTimeout(a) => axis(29, a),
        Fault::SupplyReading => 31,
        Fault::IrradianceReading => 32,
    }
}

/// The vendor model's `Flt` and `Flt2` of active faults: bit n of `Flt`
/// for fault number n under 32, bit n − 32 of `Flt2` from 32
/// ([`fault_bit`]).
pub fn fault_bits<'a>(faults: impl Iterator<Item = &'a Fault>) -> (u32, u16) {
    faults.fold((0, 0), |(lo, hi), f| {
        let n = fault_bit(*f);
        match n.checked_sub(32) {
            None => (lo | 1u32.checked_shl(n).unwrap_or(0), hi),
            Some(m) => (lo, hi | 1u16.checked_shl(m).unwrap_or(0)),
        }
    })
}

/// Seconds east of UTC of an offset in hours (`site.utc_offset_h`,
/// −12…14: whole minutes, rounded), as model 601's local date and time
/// are moved by it (a client turns them back to UTC with it).
pub fn utc_offset_s(hours: f32) -> i32 {
    let minutes = (hours * 60.0 + 0.5).floor();
    // Within ±841 for a configuration that passed its checks; clamped for
    // any other.
    (minutes.clamp(-900.0, 900.0) as i32) * 60
}

/// The wind speed in 0.1 m/s of the anemometer's pulse rate, when both the
/// rate and the factor (`wind.m_s_per_hz`, 0: not known) are known.
fn wind_speed_dms(hz: Option<f32>, m_s_per_hz: f32) -> Option<u16> {
    let hz = hz?;
    // A factor of 0 (not known) or NaN, or a rate that is not a number.
    if m_s_per_hz.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) || !hz.is_finite() {
        return None;
    }
    let dms = (hz * m_s_per_hz * 10.0 + 0.5).floor();
    // 0xFFFF is SunSpec's "not implemented".
    Some(dms.clamp(0.0, 65_534.0) as u16)
}

/// The mode a vendor model `Mode` code stands for, the inverse of
/// [`mode_code`] for a client (the PC monitor's `--modbus`): 8 reads as
/// [`Mode::Tracking`] (unwinding shares its code); `None` for a code no
/// mode has.
pub fn mode_of_code(code: u16) -> Option<Mode> {
    Some(match code {
        0 => Mode::Service,
        1 => Mode::SafeStop,
        2 => Mode::WindStow,
        3 => Mode::CommandStow,
        4 => Mode::Manual,
        5 => Mode::WaitForTime,
        6 => Mode::Night,
        7 => Mode::Homing,
        8 => Mode::Tracking,
        9 => Mode::HailStow,
        10 => Mode::ExternalStow,
        11 => Mode::SnowStow,
        12 => Mode::LowSupplyStow,
        13 => Mode::Overcast,
        _ => return None,
    })
}

/// The sensors in the order of their faults' numbers ([`fault_bit`]).
const SENSORS: [Sensor; 6] = [
    Sensor::Inclinometer,
    Sensor::Compass,
    Sensor::Encoder(AxisId::C),
    Sensor::Encoder(AxisId::A),
    Sensor::Rtc,
    Sensor::Gps,
];

/// The fault numbered `bit` ([`fault_bit`]: bit `bit` of the vendor
/// model's `Flt` below 32, bit `bit` − 32 of `Flt2` from 32), the inverse
/// of [`fault_bit`] for a client (the PC monitor's `--modbus`); `None` for
/// a number no fault has.
pub fn fault_of_bit(bit: u32) -> Option<Fault> {
    use AxisId::{A, C};
    let sensor = |first: u32| SENSORS.get(usize::try_from(bit - first).ok()?).copied();
    let axis = |first: u32| if bit == first { C } else { A };
    Some(match bit {
        0..=5 => Fault::SensorTimeout(sensor(0)?),
        6..=11 => Fault::I2cError(sensor(6)?),
        12 => Fault::GpsLost,
        13 => Fault::RtcInvalid,
        14 | 15 => Fault::MotorStalled(axis(14)),
        16 | 17 => Fault::SetPointDeviation(axis(16)),
        18 | 19 => Fault::LimitSwitchHit(axis(18)),
        20 => Fault::GpsTimeImplausible,
        21 => Fault::GpsTimeUnstable,
        22 => Fault::GpsPositionUnstable,
        23 => Fault::TimeOutOfRange,
        24 => Fault::ScheduleFailed,
        25 | 26 => Fault::Obstruction(axis(25)),
        27 | 28 => Fault::UnexpectedMotion(axis(27)),
        29 | 30 => Fault::MoveTimeout(axis(29)),
        31 => Fault::SupplyReading,
        32 => Fault::IrradianceReading,
        _ => return None,
    })
}

/// Model 601's alarm bits of one fault.
fn alarm_bits(fault: Fault) -> u16 {
    match fault {
        Fault::SetPointDeviation(_) | Fault::MotorStalled(_) | Fault::MoveTimeout(_) => {
            alarm::SET_POINT
        }
        Fault::Obstruction(AxisId::A) => alarm::OBS_EL,
        Fault::Obstruction(AxisId::C) => alarm::OBS_AZ,
        _ => 0,
    }
}

/// A calendar number of at most 5 digits from a version string's part.
const fn version_part(s: &str) -> u16 {
    let b = s.as_bytes();
    let mut v: u16 = 0;
    let mut i = 0;
    while i < b.len() && i < 4 {
        if b[i].is_ascii_digit() {
            v = v * 10 + (b[i] - b'0') as u16;
        }
        i += 1;
    }
    v
}

/// This firmware's version, major, minor, patch.
pub const FIRMWARE_VERSION: [u16; 3] = [
    version_part(env!("CARGO_PKG_VERSION_MAJOR")),
    version_part(env!("CARGO_PKG_VERSION_MINOR")),
    version_part(env!("CARGO_PKG_VERSION_PATCH")),
];

/// The map's date and time of a UTC instant (`None` outside the calendar).
fn map_datetime(t: &UtcTime) -> Option<DateTime> {
    let d = datetime_from_utc(t).ok()?;
    let jan1 = UtcTime::from_ymd_hms(i32::from(d.year()), 1, 1, 0, 0, 0).ok()?;
    let day_of_year = t.days_since_2000() - jan1.days_since_2000() + 1;
    Some(DateTime {
        year: d.year(),
        month: d.month(),
        day: d.day(),
        hour: d.hour(),
        minute: d.minute(),
        second: d.second(),
        millisecond: d.millis(),
        day_of_year: u16::try_from(day_of_year).unwrap_or(0),
    })
}

/// Degrees × 10⁷ of a GPS coordinate (10⁻¹¹ arc-minutes: 600,000 of them
/// in 10⁻⁷°), rounded down; without a 64-bit division routine.
fn e7_deg(c: drivers::gps::Coordinate) -> i32 {
    sun_algos::time::div_rem_euclid_i64(c.e11_min(), 600_000)
        .and_then(|(q, _)| i32::try_from(q).ok())
        .unwrap_or(i32::MIN)
}

impl<T, R, G, D, S, L, const N: usize> FirmwareData<'_, T, R, G, D, S, L, N>
where
    T: Float,
    R: RtcDriver,
    G: crate::hw::GpsInput<T>,
    D: AxisDrive + Motion,
    S: AttitudeSensor<T>,
    L: Sink,
{
    /// The counted pose, when both axes have their reference.
    fn counted_pose(&self) -> Option<Pose<T>> {
        let [c, a] = self.fw.controller().axes();
        (c.has_had_reference() && a.has_had_reference()).then(|| Pose {
            gamma_deg: T::from_f32(c.counted_deg()),
            alpha_deg: T::from_f32(a.counted_deg()),
        })
    }

    /// The pose within the soft limits that points the panel normal at
    /// `t` (the least move from the manual pose or where the axes stand),
    /// or exception 03.
    fn reachable(&self, t: Angles) -> Result<Pose<T>, Exception> {
        let c = self.fw.controller();
        let from = c
            .manual_pose()
            .or_else(|| self.counted_pose())
            .unwrap_or_default();
        let ax = &c.config().axes;
        let limits = PoseLimits {
            gamma_min_deg: T::from_f32(ax[0].min_deg),
            gamma_max_deg: T::from_f32(ax[0].max_deg),
            alpha_min_deg: T::from_f32(ax[1].min_deg),
            alpha_max_deg: T::from_f32(ax[1].max_deg),
        };
        let hundredth = T::from_f64(0.01);
        let dir = sun_vector_xyz(
            T::from_i32(t.elevation_cdeg) * hundredth,
            T::from_i32(t.azimuth_cdeg) * hundredth,
        );
        match c.attitude().choose(&dir, &from, &limits) {
            Ok(Choice::Reachable(p)) => Ok(p),
            _ => Err(Exception::IllegalDataValue),
        }
    }

    /// A new manual target (one angle written, the other kept): checked,
    /// kept, and driven to at once in manual mode.
    fn set_target(&mut self, t: Angles) -> Result<(), Exception> {
        let pose = self.reachable(t)?;
        self.remote.target = Some(t);
        if self.fw.controller().hold().manual {
            self.fw.controller_mut().manual(Some(pose));
        }
        Ok(())
    }

    /// The targets a single written angle completes: the last written,
    /// else the manual pose's, else where the panel points.
    fn target_base(&self) -> Angles {
        self.remote
            .target
            .or_else(|| self.manual_target_cdeg())
            .or_else(|| self.position_cdeg())
            .unwrap_or_default()
    }
}

impl<T, R, G, D, S, L, const N: usize> TrackerData for FirmwareData<'_, T, R, G, D, S, L, N>
where
    T: Float,
    R: RtcDriver,
    G: crate::hw::GpsInput<T>,
    D: AxisDrive + Motion,
    S: AttitudeSensor<T>,
    L: Sink,
{
    fn identity(&self) -> Identity<'_> {
        *self.identity
    }

    fn device_address(&self) -> u8 {
        // A new one written in this request: answered from the next.
        self.remote.new_address.unwrap_or(self.address)
    }

    fn local_time(&self) -> Option<DateTime> {
        let (t, _, tick_ms) = self.fw.last_time()?;
        let offset_s = utc_offset_s(self.fw.controller().config().site.utc_offset_h);
        let now = t
            .add_millis_u32(monotonic::elapsed_ms(self.now_ms, tick_ms))
            .and_then(|u| u.add_seconds_i32(offset_s))
            .ok()?;
        map_datetime(&now)
    }

    fn target_cdeg(&self) -> Option<Angles> {
        let report = self.fw.last_report()?;
        match (report.mode, report.set_point) {
            (Mode::Tracking | Mode::Unwind, Some(sp)) => Some(Angles {
                elevation_cdeg: cdeg(sp.elevation_deg()),
                azimuth_cdeg: sp.azimuth_deg.centi_round_mod_turn() as i32,
            }),
            _ => report
                .target
                .map(|p| panel_normal_angles(&self.fw.controller().attitude(), &p)),
        }
    }

    fn position_cdeg(&self) -> Option<Angles> {
        let pose = self.counted_pose()?;
        Some(panel_normal_angles(&self.fw.controller().attitude(), &pose))
    }

    fn control(&self) -> Control {
        let report = self.fw.last_report();
        if self.fw.controller().hold().manual {
            Control::Manual
        } else if report.is_some_and(|r| r.mode == Mode::Homing) {
            Control::Calibrate
        } else {
            Control::Automatic
        }
    }

    fn manual_target_cdeg(&self) -> Option<Angles> {
        let c = self.fw.controller();
        c.manual_pose()
            .map(|p| panel_normal_angles(&c.attitude(), &p))
            .or(self.remote.target)
    }

    fn alarms(&self) -> u16 {
        self.fw
            .controller()
            .faults()
            .active()
            .fold(0, |bits, a| bits | alarm_bits(a.fault))
    }

    fn gps_fix(&self) -> Option<GpsFix> {
        self.gps
    }

    fn vendor(&self) -> VendorStatus {
        let c = self.fw.controller();
        let mode = self.fw.last_report().map_or(Mode::WaitForTime, |r| r.mode);
        let (fault_bits, fault_bits_hi) = fault_bits(c.faults().active().map(|a| &a.fault));
        VendorStatus {
            mode_code: mode_code(mode),
            stow_reason: stow_reason(mode),
            wind_speed_dms: wind_speed_dms(self.fw.wind_hz(), c.config().wind.m_s_per_hz),
            fault_bits,
            fault_bits_hi,
            firmware: FIRMWARE_VERSION,
            stow_commanded: c.hold().stow,
        }
    }

    fn command(&mut self, command: Command) -> Result<(), Exception> {
        let hold = self.fw.controller().hold();
        match command {
            Command::DeviceAddress(a) => self.remote.new_address = Some(a),
            Command::Stow(on) => self.fw.controller_mut().command_stow(on),
            // An operator works on the tracker: nothing else from the bus.
            _ if hold.service => return Err(Exception::ServerDeviceBusy),
            Command::ManualElevation(el) => {
                let t = Angles {
                    elevation_cdeg: el,
                    ..self.target_base()
                };
                self.set_target(t)?;
            }
            Command::ManualAzimuth(az) => {
                let t = Angles {
                    azimuth_cdeg: az,
                    ..self.target_base()
                };
                self.set_target(t)?;
            }
            Command::Control(Control::Manual) => {
                // To the targets written, else where the axes stand.
                let pose = match self.remote.target {
                    Some(t) => self.reachable(t)?,
                    None => self
                        .fw
                        .controller()
                        .manual_pose()
                        .or_else(|| self.counted_pose())
                        .ok_or(Exception::ServerDeviceBusy)?,
                };
                self.fw.controller_mut().manual(Some(pose));
                self.remote.manual_by_bus = true;
            }
            Command::Control(Control::Automatic) => {
                self.fw.controller_mut().manual(None);
                self.remote.manual_by_bus = false;
            }
            Command::Control(Control::Calibrate) => self.fw.controller_mut().rehome(),
            Command::ClearFaults => self.fw.controller_mut().reset_faults(),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_round_trip_through_the_sun_vector() {
        for el in (-85..=85).step_by(5) {
            for az in (0..360).step_by(15) {
                let v = sun_vector_xyz(el as f64, az as f64);
                let a = direction_angles(&v);
                assert_eq!(a.elevation_cdeg, el * 100, "{el} {az}");
                assert_eq!(a.azimuth_cdeg, az * 100, "{el} {az}");
            }
        }
    }

    #[test]
    fn a_level_mount_at_home_faces_the_zenith() {
        let a = panel_normal_angles(&MountAttitude::<f64>::level(), &Pose::default());
        assert_eq!(a.elevation_cdeg, 9_000);
    }

    #[test]
    fn fault_numbers_follow_the_names_and_bits_fit_32() {
        use AxisId::{A, C};
        let sensors = SENSORS;
        let mut all = [Fault::GpsLost; 33];
        let mut n = 0;
        let mut put = |f: Fault| {
            all[n] = f;
            n += 1;
        };
        for s in sensors {
            put(Fault::SensorTimeout(s));
        }
        for s in sensors {
            put(Fault::I2cError(s));
        }
        put(Fault::GpsLost);
        put(Fault::RtcInvalid);
        for k in [
            Fault::MotorStalled as fn(AxisId) -> Fault,
            Fault::SetPointDeviation,
            Fault::LimitSwitchHit,
        ] {
            put(k(C));
            put(k(A));
        }
        for f in [
            Fault::GpsTimeImplausible,
            Fault::GpsTimeUnstable,
            Fault::GpsPositionUnstable,
            Fault::TimeOutOfRange,
            Fault::ScheduleFailed,
        ] {
            put(f);
        }
        for k in [
            Fault::Obstruction as fn(AxisId) -> Fault,
            Fault::UnexpectedMotion,
            Fault::MoveTimeout,
        ] {
            put(k(C));
            put(k(A));
        }
        put(Fault::SupplyReading);
        put(Fault::IrradianceReading);
        assert_eq!(n, 33);
        let mut seen = (0u32, 0u16);
        for (i, f) in all.iter().enumerate() {
            let b = fault_bit(*f);
            // In the order the names are listed.
            assert_eq!(b as usize, i, "{}", f.name());
            let (lo, hi) = fault_bits([*f].iter());
            // One bit each, of `Flt` below 32, of `Flt2` from 32.
            assert_eq!(lo.count_ones() + hi.count_ones(), 1);
            assert_eq!((seen.0 & lo, seen.1 & hi), (0, 0));
            seen = (seen.0 | lo, seen.1 | hi);
            // A client reads the number back as the same fault.
            assert_eq!(fault_of_bit(b), Some(*f));
        }
        // Bits 0 to 31 of `Flt` taken, the 33rd fault bit 0 of `Flt2`.
        assert_eq!(seen, (u32::MAX, 1));
        assert_eq!(fault_bits([Fault::IrradianceReading].iter()), (0, 1));
    }

    #[test]
    fn every_mode_code_reads_back_as_its_mode() {
        for code in 0..=u16::MAX {
            match mode_of_code(code) {
                Some(m) => assert_eq!(mode_code(m), code),
                None => assert!(code > 13, "{code}"),
            }
        }
        assert_eq!(mode_of_code(mode_code(Mode::Unwind)), Some(Mode::Tracking));
        assert_eq!(fault_of_bit(32), Some(Fault::IrradianceReading));
        assert_eq!(fault_of_bit(33), None);
    }

    #[test]
    fn the_version_is_the_crate_version() {
        let mut parts = env!("CARGO_PKG_VERSION").split('.');
        for v in FIRMWARE_VERSION {
            let p = parts.next().and_then(|p| p.parse::<u16>().ok());
            assert_eq!(p, Some(v));
        }
    }
}
