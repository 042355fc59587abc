//! The mechanics of Li et al.'s (2022) tracker, shared by every board that
//! drives it (the Arduino Mega and the Black Pill images): two bipolar
//! steppers of 200 full steps per turn behind H-bridges, full-step
//! (two-phase-on) drive, each through a 50:1 worm gear — 10,000 steps per
//! axis turn, 0.036° a step — at most 2°/s (56 steps/s) with a 100 steps/s²
//! ramp. The C axis turns −180…+180° from its home switch at −180°, the A
//! axis −90…+90° from its home at −90°. No encoder: open loop, homed at
//! power-on and at every end of day.

use drivers::stepper::hbridge::{Config as BridgeConfig, StepMode};
use drivers::stepper::ramp::Ramp;

use crate::config::{AxisConfig, Config};
use crate::controller::{AttitudeSource, ControllerOptions};
use crate::hw::{DcAxisConfig, PotConfig, TimedAxisConfig};
#[cfg(feature = "linear")]
use crate::hw::{LinearAxisConfig, POT_COUNTS_PER_MM};
use crate::motion::FeedbackMode;
#[cfg(feature = "linear")]
use drivers::linear::LinearError;
use sun_algos::Float;

/// Full steps per motor turn.
pub const STEPS_PER_TURN: u32 = 200;
/// Worm gear: motor turns per axis turn.
pub const GEAR_RATIO: f32 = 50.0;
/// Highest axis speed, degrees per second (56 full steps/s).
pub const MAX_SPEED_DEG_S: f32 = 2.0;

/// The default configuration's C axis, whose drive fields the axes take.
const DEFAULT_AXIS: AxisConfig = Config::DEFAULT.axes[0];

/// The axis configuration (C then A).
///
/// A copy of a table in program memory: built in code, each field written
/// was its own instructions (the ATmega2560's `config` was 490 B).
pub fn axis_configs() -> [AxisConfig; 2] {
    AXES.load()
}

crate::progmem! {
    /// [`axis_configs`], in flash on every board (a constant the AVR
    /// copied from RAM would take 2 × 60 B of it there).
    static AXES: [AxisConfig; 2] = {
        let c = AxisConfig {
            counts_per_motor_rev: STEPS_PER_TURN,
            microsteps: 1,
            gear_ratio: GEAR_RATIO,
            min_deg: -180.0,
            max_deg: 180.0,
            home_deg: -180.0,
            backlash_deg: 0.0,
            max_speed_deg_s: MAX_SPEED_DEG_S,
            // Open loop: every set-point is driven to the nearest step.
            deadband_deg: 0.0,
            continuous: 0,
            // Steppers; the defaults of the other drives' fields.
            ..DEFAULT_AXIS
        };
        let a = AxisConfig {
            min_deg: -90.0,
            max_deg: 90.0,
            home_deg: -90.0,
            ..c
        };
        [c, a]
    };
}

/// The H-bridge drive settings: full steps, ramp from 20 to 56 steps/s.
// Out of line on the AVR: inlined, its fields were stored one by one into
// the ATmega2560 board's frame of two drivers, beyond the 63 bytes
// `ldd`/`std` reach from the frame pointer (8-12 bytes more each).
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn bridge_config() -> BridgeConfig {
    BridgeConfig {
        mode: StepMode::Full,
        ramp: Ramp {
            start_speed_sps: 20,
            max_speed_sps: 56,
            accel_sps2: 100,
        },
        settle_us: 20_000,
        release_when_idle: true,
    }
}

/// The tracker configuration: the defaults with these axes.
// The defaults written where the result goes, then the axes; not the
// struct update syntax clippy suggests, which built the defaults aside and
// copied them field by field (224 B more on the ATmega2560).
#[allow(clippy::field_reassign_with_default)]
pub fn config() -> Config {
    let mut config = Config::default();
    config.axes = axis_configs();
    config
}

/// The controller options of this build: open loop (no encoders), attitude
/// measured by the inclinometer and compass (without them the controller
/// keeps the level attitude and raises `timeout_inclinometer`), four
/// readings averaged per tick.
pub fn controller_options<T: Float>() -> ControllerOptions<T> {
    ControllerOptions {
        feedback: FeedbackMode::OpenLoop,
        attitude: AttitudeSource::Sensors,
        sensor_samples: 4,
        ..ControllerOptions::default()
    }
}

/// `options` for the drive kinds of `axes`: with an axis closed on its
/// own feedback (a DC axis on its Hall count, `dc_hall`; a linear
/// actuator, `linear_hall` or `linear_pot`; a continuous servo on its
/// encoder, `servo_encoder`) the controller corrects each axis from its
/// measured angle ([`FeedbackMode::ClosedLoop`]: a move cut short by an
/// obstruction or a stall is finished by the retry; a stepper beside one
/// has no encoder, and its counted steps stand); with a timed axis it
/// re-homes after every stow as well as every night (a timed axis knows
/// where it is from its home switch and the time it ran only, and a
/// stow's long slews add up its error).
pub fn options_for_drives<T: Float>(
    options: ControllerOptions<T>,
    axes: &[AxisConfig; 2],
) -> ControllerOptions<T> {
    let has = |kind: crate::config::DriveKind| axes.iter().any(|a| a.drive == kind as u8);
    ControllerOptions {
        feedback: if has(crate::config::DriveKind::DcHall)
            || has(crate::config::DriveKind::LinearHall)
            || has(crate::config::DriveKind::LinearPot)
            || has(crate::config::DriveKind::ServoEncoder)
        {
            FeedbackMode::ClosedLoop
        } else {
            options.feedback
        },
        rehome_after_stow: options.rehome_after_stow || has(crate::config::DriveKind::Timed),
        ..options
    }
}

/// The position loop and watch of a DC gear motor or slew drive closed on
/// its Hall count (`axis.X.drive` 2, `dc_hall`), from the axis's
/// configuration: `counts_per_deg` ([`AxisConfig::counts_per_deg`]), its
/// top speed `max_speed_deg_s` and its current watch (`max_current_ma` for
/// `overcurrent_ms`). The distances are in degrees of the axis, so that a
/// drive of other gears keeps the same behaviour: full duty beyond 4°, 15 %
/// at the target; done within 0.01°; unexpected motion beyond 0.05° while
/// at rest; an approach slower than half the top speed over its distance,
/// plus 3 s for the slow band and the stop, is too slow. The times are the
/// worm slew drive's ([`WORM_SLEW_LOOP`], which explains them): a first
/// stopping lead of 130 ms (re-measured at every stop), standstill after
/// 100 ms without a count, a stall after 500 ms. Each count is rounded to
/// the nearest whole one and kept within what [`DcAxisConfig::validate`]
/// takes (a 1-count deadband at least, at most
/// [`crate::hw::MAX_IDLE_COUNTS`] at rest), so that every valid
/// axis configuration gives a valid loop.
pub const fn dc_hall_loop_for(
    counts_per_deg: f32,
    max_speed_deg_s: f32,
    max_current_ma: u16,
    overcurrent_ms: u16,
) -> DcAxisConfig {
    /// `deg` of the axis in whole counts, at least `lo`, at most `hi`.
    const fn counts(deg: f32, counts_per_deg: f32, lo: u32, hi: u32) -> u32 {
        let c = (deg * counts_per_deg + 0.5) as u32;
        if c < lo {
            lo
        } else if c > hi {
            hi
        } else {
            c
        }
    }
    DcAxisConfig {
        max_duty_permille: 1_000,
        min_duty_permille: 150,
        slow_band_counts: counts(4.0, counts_per_deg, 2, 100_000_000),
        deadband_counts: counts(0.01, counts_per_deg, 1, 1_000_000),
        brake_lead_ms: 130,
        settle_ms: 100,
        max_reapproaches: 3,
        stall_ms: 500,
        drive_threshold_permille: 100,
        max_idle_counts: counts(0.05, counts_per_deg, 0, crate::hw::MAX_IDLE_COUNTS),
        max_current_ma: max_current_ma as u32,
        overcurrent_ms: overcurrent_ms as u32,
        min_speed_cps: counts(max_speed_deg_s * 0.5, counts_per_deg, 1, u32::MAX),
        move_margin_ms: 3_000,
    }
}

/// [`dc_hall_loop_for`] an axis's configuration.
pub fn dc_hall_loop(axis: &AxisConfig) -> DcAxisConfig {
    dc_hall_loop_for(
        axis.counts_per_deg(),
        axis.max_speed_deg_s,
        axis.max_current_ma,
        axis.overcurrent_ms,
    )
}

/// The position loop and watch of a linear actuator (`linear_hall`,
/// `linear_pot`: [`crate::hw::LinearAxis`]) whose feedback gives
/// `counts_per_mm` counts a mm of stroke, with the axis's current watch
/// (`max_current_ma` for `overcurrent_ms`). The distances are in mm of
/// the stroke, the simulator's LINAK LA12 figures
/// (`sim::linear_drive::LA12_HALL_LOOP`, which explains them, for Hall
/// pulses and the potentiometer alike): full duty beyond 5 mm, 40 % at
/// the target; done on the target's count; the spindle stops the rod when
/// braked (no stopping lead); 2 mm at rest is unexpected motion; an
/// approach slower than 5 mm/s plus 3 s is too slow; a stall after 1 s
/// without a count, or four counts' time at 10 mm/s (40 % duty) for
/// feedback coarser than 0.4 counts a mm (a reed contact).
pub fn linear_loop(axis: &AxisConfig, counts_per_mm: f32) -> DcAxisConfig {
    /// `mm` of stroke in whole counts, at least `lo`.
    fn counts(mm: f32, counts_per_mm: f32, lo: u32) -> u32 {
        ((mm * counts_per_mm + 0.5) as u32).max(lo)
    }
    DcAxisConfig {
        max_duty_permille: 1_000,
        min_duty_permille: 400,
        slow_band_counts: counts(5.0, counts_per_mm, 2),
        deadband_counts: 1,
        brake_lead_ms: 0,
        settle_ms: 100,
        max_reapproaches: 2,
        stall_ms: counts(400.0, 1.0 / counts_per_mm, 1_000),
        drive_threshold_permille: 100,
        max_idle_counts: counts(2.0, counts_per_mm, 2).min(crate::hw::MAX_IDLE_COUNTS),
        max_current_ma: u32::from(axis.max_current_ma),
        overcurrent_ms: u32::from(axis.overcurrent_ms),
        min_speed_cps: counts(5.0, counts_per_mm, 1),
        move_margin_ms: 3_000,
    }
}

/// A linear actuator's bridge ramp, per mille of duty per ms (the
/// simulator's LA12 drive, `sim::linear_drive::la12_tilt_spec`: full duty
/// in 0.2 s).
pub const LINEAR_RAMP_PERMILLE_PER_MS: u16 = 5;

/// How a linear actuator's potentiometer is read
/// ([`crate::hw::PotFeedback`]): sixteen conversions a poll (one count rms
/// of noise becomes a quarter), a hysteresis of 0.1 mm, readings within 8
/// counts outside the calibrated span taken as the end (the simulator's
/// `LA12_POT_READING`).
pub const LINEAR_POT_READING: PotConfig = PotConfig {
    samples: 16,
    hysteresis_mm: 0.1,
    end_margin_counts: 8,
};

/// The mounting and loop of a linear actuator's axis from its
/// configuration (`axis.X.pivot_a_mm` … `pot_extended_counts`): the
/// geometry; on Hall pulses (`linear_hall`) the home switch's pulse edge
/// at the extension where the axis is at `home_deg` (the first edge above
/// the switch: [`crate::hw::HallFeedback`]), on the potentiometer
/// (`linear_pot`, homed at the retracted end) an end tolerance of the
/// reading's hysteresis and two ADC counts; the loop
/// [`linear_loop`] in the feedback's counts (half pulses, 2 a pulse, or
/// tenths of a mm). `Err` when the geometry has no angle at `home_deg`
/// (a configuration that passed its checks has one).
#[cfg(feature = "linear")]
pub fn linear_mount(axis: &AxisConfig) -> Result<LinearAxisConfig, LinearError> {
    let m = &axis.linear;
    let g = m.geometry();
    let pot = axis.drive == crate::config::DriveKind::LinearPot as u8;
    let (switch_extension_mm, end_tolerance_mm, counts_per_mm) = if pot {
        let span = m.pot_retracted_counts.abs_diff(m.pot_extended_counts);
        let mm_per_count = g.stroke_mm / f32::from(span.max(1));
        (
            0.0,
            LINEAR_POT_READING.hysteresis_mm + 2.0 * mm_per_count,
            POT_COUNTS_PER_MM,
        )
    } else {
        let at_home_mm = g.extension_mm(g.length_mm(axis.home_deg)?)?;
        (
            // Not `f32::clamp`: no panic path in the image.
            Float::clamp(at_home_mm, 0.0, g.stroke_mm),
            0.0,
            2.0 * m.pulses_per_mm,
        )
    };
    Ok(LinearAxisConfig {
        geometry: g,
        switch_extension_mm,
        end_tolerance_mm,
        loop_config: linear_loop(axis, counts_per_mm),
    })
}

/// The runs of a DC motor moved by time without feedback (`axis.X.drive`
/// 5, `timed`: [`crate::hw::TimedAxis`]) from the axis's configuration:
/// forward at `max_speed_deg_s`, backward at `back_speed_deg_s` (both
/// measured on the installed axis at full duty, at the motor supply
/// `calibration_supply_mv`: `supply.calibration_mv`, 0 for runs not scaled
/// by the measured supply), every run at full duty, the current watch
/// `max_current_ma` for `overcurrent_ms`; `lag_ms` is the motor's
/// mechanical time constant (the board's motor). The configuration's
/// ranges lie within what [`TimedAxisConfig::validate`] takes (speeds
/// 0.01–30 °/s, a current limit of 100 mA at least, at most 5 s above it,
/// a calibration supply up to 60 V), so every valid configuration gives
/// valid runs for a `lag_ms` up to 10 s.
pub fn timed_runs(axis: &AxisConfig, calibration_supply_mv: u16, lag_ms: u32) -> TimedAxisConfig {
    TimedAxisConfig {
        forward_deg_s: axis.max_speed_deg_s,
        backward_deg_s: axis.back_speed_deg_s,
        duty_permille: 1_000,
        calibration_supply_mv: u32::from(calibration_supply_mv),
        max_current_ma: u32::from(axis.max_current_ma),
        overcurrent_ms: u32::from(axis.overcurrent_ms),
        lag_ms,
    }
}

/// Hall counts per motor turn of the worm slew drive (the Pololu 37D gear
/// motor's encoder: 16 pulses a turn on each of two channels, both edges
/// of both counted).
pub const WORM_SLEW_COUNTS_PER_MOTOR_REV: u32 = 64;
/// The worm slew drive's gears from the motor to the axis: 131.25
/// (gearbox) × 60 (worm).
pub const WORM_SLEW_GEAR_RATIO: f32 = 7_875.0;
/// The fastest the worm slew drive's axis is commanded, °/s: under the
/// 7.62 °/s of the motor's no-load speed through the gears.
pub const WORM_SLEW_MAX_SPEED_DEG_S: f32 = 7.0;
/// The worm slew drive's set-point deadband, degrees: a closed-loop
/// correction is made beyond it (70 Hall counts; the axis's own loop stops
/// within 14).
pub const WORM_SLEW_DEADBAND_DEG: f32 = 0.05;
/// The worm slew drive's bridge duty ramp, ‰/ms: a start to full duty
/// takes 0.5 s.
pub const WORM_SLEW_RAMP_PERMILLE_PER_MS: u16 = 2;
/// The worm slew drive's motor lag moved by time, ms: its mechanical time
/// constant, which a run cut short by an obstacle does not pay back
/// ([`TimedAxisConfig::lag_ms`]): the braked time constant with the
/// panels, 0.12 s ([`WORM_SLEW_LOOP`]'s figures; a linear actuator's is
/// shorter, and the retry of such a run then goes a few tenths of a degree
/// too far).
pub const WORM_SLEW_LAG_MS: u32 = 120;

/// The tracker configuration with both axes on worm slew drives closed on
/// their Hall counts (`axis.X.drive` 2, `dc_hall`): the stepper axes'
/// ranges and switches ([`config`]), the slew drive's counts, gears, top
/// speed and deadband.
#[allow(clippy::field_reassign_with_default)]
pub fn worm_slew_config() -> Config {
    let mut config = config();
    for ax in config.axes.iter_mut() {
        *ax = AxisConfig {
            counts_per_motor_rev: WORM_SLEW_COUNTS_PER_MOTOR_REV,
            microsteps: 1,
            gear_ratio: WORM_SLEW_GEAR_RATIO,
            backlash_deg: 0.0,
            max_speed_deg_s: WORM_SLEW_MAX_SPEED_DEG_S,
            deadband_deg: WORM_SLEW_DEADBAND_DEG,
            drive: crate::config::DriveKind::DcHall as u8,
            ..*ax
        };
    }
    config
}

/// The position loop and watch of the worm slew drive's axis (`sim::dc_drive::worm_slew_motor`: a Pololu 37D
/// 131.25:1 gear motor with a 64-count Hall encoder, then a 60:1 worm, 1,400
/// counts a degree, commanded at up to 7 °/s), [`dc_hall_loop_for`] it: full duty
/// beyond 4° (5,600 counts), 15 % at the target; a first stopping lead of
/// 130 ms (the model's mechanical time constant under braking,
/// J·R / (k_t·k_e + R·b), is 0.107 s for the bare motor and 16 % more with the axis inertia,
/// plus a few ms of speed-window lag); standstill = no count for 100 ms (the
/// braked run-down crawls at tens of counts/s at its end); done within 0.01°
/// (14 counts); stall after 500 ms without a count; unexpected motion beyond
/// 70 counts (0.05°); overcurrent above 3 A for 100 ms (20 times the 0.15 A
/// free-running current, 55 % of the 5.5 A stall current). A motor held
/// still draws V·d/R: starting a slew into an obstacle, a 2 ‰/ms ramp
/// reaches 3 A at 545 ‰ after 273 ms, so the overcurrent trips at 373 ms,
/// before the stall; held at a tracking step's duty (under 20 %, about 1 A)
/// it is a stall. An approach slower than 4,900 counts/s (3.5 °/s, half the
/// top speed; the no-load 10,000 rpm × 64 / 60 = 10,667 counts/s is
/// 7.62 °/s) over its distance, plus 3 s for the slow band and the stop, is
/// too slow.
pub const WORM_SLEW_LOOP: DcAxisConfig = dc_hall_loop_for(1_400.0, 7.0, 3_000, 100);
