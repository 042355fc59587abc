//! The physical ranges of the configuration, as checked by
//! [`Config::validate`](super::Config::validate); each field's doc comment
//! gives the reason. The texts that the console prints for them
//! ([`Reason::text`](super::Reason::text)) are built from these constants
//! when compiling ([`super::range_text`]).

/// Latitude, degrees: the geographic range.
pub const LAT_DEG: (f32, f32) = (-90.0, 90.0);
/// Longitude, degrees: the geographic range.
pub const LON_DEG: (f32, f32) = (-180.0, 180.0);
/// Elevation, metres: Dead Sea shore (−430 m) to above Everest.
pub const ELEVATION_M: (f32, f32) = (-500.0, 10_000.0);
/// Set-point table interval, seconds: one minute to half a day.
pub const TABLE_STEP_S: (u32, u32) = (60, 43_200);
/// Hold after a set-point, seconds: none to one hour.
pub const HOLD_S: (u32, u32) = (0, 3_600);
/// Re-check interval, seconds: one second to one hour.
pub const RECHECK_S: (u32, u32) = (1, 3_600);
/// Forward clock jump that re-plans, seconds: one second to one day.
pub const MAX_TICK_GAP_S: (u32, u32) = (1, 86_400);
/// Backward clock step that re-plans, seconds: none to one day.
pub const MAX_BACKWARD_S: (u32, u32) = (0, 86_400);
/// Full steps or encoder counts per motor revolution: 1 to 2^24 (a
/// 24-bit absolute encoder).
pub const COUNTS_PER_MOTOR_REV: (u32, u32) = (1, 16_777_216);
/// Microsteps per full step, as stepper drivers offer: 1 to 256.
pub const MICROSTEPS: (u16, u16) = (1, 256);
/// Gear ratio, motor revolutions per axis revolution: direct drive to a
/// worm plus planetary stack.
pub const GEAR_RATIO: (f32, f32) = (1.0, 10_000.0);
/// Motor counts per axis degree (derived: counts × microsteps × gear /
/// 360): a 1° resolution at least; at most 10^6, so that the largest
/// move of an axis ([`MAX_MOVE_DEG`] = 925°) is 9.25 × 10^8 counts,
/// under half of `i32::MAX` (2.1 × 10^9).
pub const COUNTS_PER_DEG: (f32, f32) = (1.0, 1_000_000.0);
/// The largest move of an axis, degrees: the widest soft-limit span
/// (720°), a home switch 5° below it, feedback believed up to
/// `motion::FEEDBACK_MARGIN_DEG` (90°) beyond either limit, and the
/// backlash take-up (5°), rounded up.
pub const MAX_MOVE_DEG: f32 = 925.0;
/// Soft limits, degrees: at most one turn either way (720° of cable
/// wrap in all).
pub const LIMIT_DEG: (f32, f32) = (-360.0, 360.0);
/// Home switch angle relative to `min_deg`, degrees: from 5° below the
/// lowest soft limit (a switch just outside the working range) to 10°
/// above it (inside the range); homing drives negative onto it, and
/// backs off a closed switch by at most `motion::HOMING_BACKOFF_MAX_DEG`
/// (15°), which must get an axis resting at its lowest limit off it.
/// Never above `max_deg` either: homed, the axis is at the switch.
pub const HOME_ABOVE_MIN_DEG: (f32, f32) = (-5.0, 10.0);
/// Backlash, degrees: worm gears and slewing drives have 0.1–1°;
/// beyond 5° counting the slack is meaningless.
pub const BACKLASH_DEG: (f32, f32) = (0.0, 5.0);
/// Highest axis speed, degrees per second: a slow slewing drive to a
/// 12-second sweep of a 360° span.
pub const MAX_SPEED_DEG_S: (f32, f32) = (0.01, 30.0);
/// Closed-loop deadband, degrees: none to 5° (cos 5° = 0.996, 0.4 %
/// of the direct beam); also below `safety.max_deviation_deg`.
pub const DEADBAND_DEG: (f32, f32) = (0.0, 5.0);
/// Anemometer pulse rate that means "too windy", Hz: a cup anemometer
/// gives 1–20 pulses per turn and turns at most ~30 times a second.
pub const STOW_HZ: (f32, f32) = (0.1, 1_000.0);
/// Seconds above the threshold before stowing: at once to 10 minutes.
pub const WIND_HOLD_S: (u32, u32) = (0, 600);
/// Seconds of calm before leaving stow: at once to one day.
pub const WIND_RELEASE_S: (u32, u32) = (0, 86_400);
/// Largest set-point deviation, degrees: above the attitude sensors'
/// noise (0.1°), below the 45° that would let a reversed axis pass.
pub const MAX_DEVIATION_DEG: (f32, f32) = (0.1, 45.0);
/// Seconds without encoder motion before "stalled": 1 s to 10 minutes.
pub const STALL_TIMEOUT_S: (u32, u32) = (1, 600);
/// Seconds without a sensor reading before "timeout": 1 s to one hour.
pub const SENSOR_TIMEOUT_S: (u32, u32) = (1, 3_600);
/// Retries before degrading: none to 20.
pub const MAX_RETRIES: (u8, u8) = (0, 20);
/// Magnetic declination and compass mounting offset, degrees: any
/// direction (declination reaches ±180° near the magnetic poles).
pub const HEADING_DEG: (f32, f32) = (-180.0, 180.0);
/// Inclinometer offsets, degrees: a sensor mounted more than 45° off
/// has its x and y axes swapped, not offset.
pub const TILT_OFFSET_DEG: (f32, f32) = (-45.0, 45.0);
/// Modbus device address: 1 to 247 (0 is broadcast, 248 to 255 are
/// reserved; Modbus over Serial Line V1.02 §2.2).
pub const MODBUS_ADDRESS: (u8, u8) = (1, 247);
/// Modbus serial rate, baud: 1,200 to 115,200, and one of the standard
/// rates ([`MODBUS_BAUDS`]).
pub const MODBUS_BAUD: (u32, u32) = (1_200, 115_200);
crate::progmem! {
    /// The standard serial rates a Modbus device offers (the serial line
    /// spec requires 9,600 and 19,200, §2.5.1; the others are common). In
    /// program memory on the AVR: as a constant it took 32 B of RAM.
    pub static MODBUS_BAUDS: [u32; 8] = [1_200, 2_400, 4_800, 9_600, 19_200, 38_400, 57_600, 115_200];
}
/// Modbus parity: 0 none (with two stop bits), 1 odd, 2 even (the
/// default the serial line spec requires, §2.5.1).
pub const MODBUS_PARITY: (u8, u8) = (0, 2);
/// A stow's panel slope from horizontal, degrees: flat to upright (the
/// A axis's limits bound it further).
pub const STOW_SLOPE_DEG: (f32, f32) = (0.0, 90.0);
/// Supply thresholds, millivolts: 0 (off) to 60 V, beyond any tracker's
/// motor supply (12, 24 or 48 V).
pub const SUPPLY_MV: (u16, u16) = (0, 60_000);
/// The overcast threshold, a fraction of the clear sky's irradiance: 0
/// (off) to 1.
pub const OVERCAST_RATIO: (f32, f32) = (0.0, 1.0);
/// Changes of the overcast mode an hour: at least one, at most 8 (the
/// monitor keeps that many change times).
pub const OVERCAST_MOVES: (u8, u8) = (1, 8);
/// The site's offset of local time from UTC, hours: UTC−12 (Baker Island)
/// to UTC+14 (Line Islands), the time zones in use; quarter hours are
/// exact in `f32` (India +5.5, Nepal +5.75, the Chatham Islands +12.75).
pub const UTC_OFFSET_H: (f32, f32) = (-12.0, 14.0);
/// The anemometer's wind speed per pulse rate, m/s per Hz: 0 (not known)
/// to 10 (cup anemometers give 0.3–2.5: the common 2.4 km/h per Hz type
/// 0.667).
pub const WIND_M_S_PER_HZ: (f32, f32) = (0.0, 10.0);
/// An axis's drive kind: the codes 0 to 5 of
/// [`DriveKind`](super::DriveKind).
pub const DRIVE: (u8, u8) = (0, 5);
/// A DC axis's current limit, milliamperes: 0.1 A (a small gear motor on
/// an L298N) to 40 A (under the BTS7960's 43 A).
pub const MAX_CURRENT_MA: (u16, u16) = (100, 40_000);
/// Time above the current limit that is an obstruction, milliseconds:
/// 10 ms (a few periods of a 1 kHz current reading) to 5 s (a stalled
/// gear motor draws its stall current, several times the rated one: it
/// must not wait longer).
pub const OVERCURRENT_MS: (u16, u16) = (10, 5_000);
/// A linear actuator's pivot distances, lengths and stroke, mm: 1 cm
/// (the smallest actuators' strokes) to 5 m (beyond any tracker's
/// actuator and mounting).
pub const LENGTH_MM: (f32, f32) = (10.0, 5_000.0);
/// A linear actuator's feedback pulses per mm: a reed contact every
/// 10 cm to an optical encoder's 1,000 a mm (a LINAK LA12's single Hall
/// gives 1, its dual Hall outputs 5.3 edges).
pub const PULSES_PER_MM: (f32, f32) = (0.01, 1_000.0);
/// A potentiometer's ADC reading: a 12-bit converter's codes (the
/// ATmega's 10-bit ADC reads 0…1,023).
pub const ADC_COUNTS: (u16, u16) = (0, 4_095);
/// An input's active level: 0 low, 1 high.
pub const ACTIVE_LEVEL: (u8, u8) = (0, 1);
/// An on/off switch: 0 off, 1 on.
pub const SWITCH: (u8, u8) = (0, 1);
/// Minutes between periodic `status` log lines; 0 turns them off, a
/// day is the longest period that still shows a logger the tracker
/// is alive every day.
pub const STATUS_MIN: (u16, u16) = (0, 1_440);
