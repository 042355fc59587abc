//! A bipolar stepper axis seen through its four H-bridge inputs, the
//! controller configuration of the whole-tracker tests, and the geometry
//! used to check pointing independently of the tracker's code.

use std::cell::RefCell;
use std::convert::Infallible;
use std::rc::Rc;

use drivers::stepper::hbridge::{BridgePins, Config as BridgeConfig, HBridgeStepper, StepMode};
use drivers::stepper::ramp::Ramp;
use drivers::stepper::LimitSwitches;
use embedded_hal::digital::{ErrorType, InputPin, OutputPin};
use sun_algos::{Algorithm, Options, Site, SunPosition, UtcTime};
use suntracker::controller::TickInputs;
use suntracker::hw::StepperAxis;

use super::DayTime;

/// 200 full steps per motor revolution, half-stepped, 100:1 worm gear.
pub const STEPS_PER_REV: u32 = 200;
pub const HALF_STEP: u16 = 2;
pub const GEAR: f32 = 100.0;
/// Motor half-steps per axis degree: 200 × 2 × 100 / 360.
pub const COUNTS_PER_DEG: f64 = 200.0 * 2.0 * 100.0 / 360.0;

/// Pointing tolerance at each set-point. Per axis: homing finds the switch
/// within one half-step (0.009°) and each move truncates to a whole
/// half-step (≤ 0.009°); PSA+ and SPA differ by ≈ 0.004° here. Measured:
/// 0.023° at worst. 0.05° leaves room for neither a lost step (0.009° each,
/// but they add up) nor a wrong table entry (the sun moves ≈ 1° per entry).
pub const TOL_DEG: f64 = 0.05;

// ---------------------------------------------------------------- motor model

/// A bipolar stepper and its axis, seen through the four bridge inputs.
#[derive(Debug)]
pub struct Motor {
    /// Bridge inputs IN1..IN4 (A+, A−, B+, B−).
    pub pins: [bool; 4],
    /// Last rotor phase (multiples of 45°), once a coil was energised.
    pub phase: Option<i64>,
    /// Rotor position in half-steps from the start.
    pub half_steps: i64,
    /// Axis angle at the start, degrees (unknown to the controller).
    pub start_deg: f64,
    /// The limit switch is closed at or below this axis angle.
    pub switch_deg: f64,
    /// Both ends of one coil driven high (shoot-through).
    pub shoot_through: u32,
    /// Phase jumps of 135° or more (the rotor would lose sync).
    pub lost_sync: u32,
    /// Times the axis was driven beyond the hard stop (1° past the switch).
    pub hit_stop: u32,
    pub pin_writes: u64,
}

impl Motor {
    pub fn new(start_deg: f64, switch_deg: f64) -> Rc<RefCell<Motor>> {
        Rc::new(RefCell::new(Motor {
            pins: [false; 4],
            phase: None,
            half_steps: 0,
            start_deg,
            switch_deg,
            shoot_through: 0,
            lost_sync: 0,
            hit_stop: 0,
            pin_writes: 0,
        }))
    }

    pub fn angle_deg(&self) -> f64 {
        self.start_deg + self.half_steps as f64 / COUNTS_PER_DEG
    }

    pub fn switch_closed(&self) -> bool {
        self.angle_deg() <= self.switch_deg
    }

    pub fn energised(&self) -> bool {
        self.pins.iter().any(|&p| p)
    }

    /// A pin write. A bridge leg driven high at both ends shorts the supply
    /// at once, so that is checked on every write.
    pub fn set(&mut self, pin: usize, high: bool) {
        self.pins[pin] = high;
        self.pin_writes += 1;
        let [a_pos, a_neg, b_pos, b_neg] = self.pins;
        if (a_pos && a_neg) || (b_pos && b_neg) {
            self.shoot_through += 1;
        }
    }

    /// The rotor follows the coil state that lasts: called after each
    /// `poll`, as the pins then stay unchanged for at least the pump's
    /// 100 µs (the states between single pin writes of one step last
    /// nanoseconds, too short to move a rotor). The rotor aligns with the
    /// coil current vector (A, B): half-step phase k is the vector at k·45°
    /// from A+ toward B+. With no current it stays where it is (the worm
    /// gear is self-locking).
    pub fn settle(&mut self) {
        let [a_pos, a_neg, b_pos, b_neg] = self.pins;
        if (a_pos && a_neg) || (b_pos && b_neg) {
            return;
        }
        let a = i32::from(a_pos) - i32::from(a_neg);
        let b = i32::from(b_pos) - i32::from(b_neg);
        if a == 0 && b == 0 {
            return;
        }
        let deg = f64::from(b).atan2(f64::from(a)).to_degrees();
        let k = ((deg / 45.0).round() as i64).rem_euclid(8);
        if let Some(old) = self.phase {
            let mut d = (k - old).rem_euclid(8);
            if d > 4 {
                d -= 8;
            }
            if d.abs() >= 3 {
                self.lost_sync += 1;
            } else {
                self.half_steps += d;
                if self.angle_deg() < self.switch_deg - 1.0 {
                    self.hit_stop += 1;
                }
            }
        }
        self.phase = Some(k);
    }
}

pub struct CoilPin {
    pub motor: Rc<RefCell<Motor>>,
    pub index: usize,
}

impl ErrorType for CoilPin {
    type Error = Infallible;
}

impl OutputPin for CoilPin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.motor.borrow_mut().set(self.index, false);
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.motor.borrow_mut().set(self.index, true);
        Ok(())
    }
}

/// The home switch, closed = high.
pub struct SwitchPin {
    pub motor: Rc<RefCell<Motor>>,
}

impl ErrorType for SwitchPin {
    type Error = Infallible;
}

impl InputPin for SwitchPin {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(self.motor.borrow().switch_closed())
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        Ok(!self.motor.borrow().switch_closed())
    }
}

pub type Axis = StepperAxis<CoilPin, SwitchPin, SwitchPin>;

pub fn stepper_axis(motor: &Rc<RefCell<Motor>>) -> Axis {
    let pin = |index| CoilPin {
        motor: Rc::clone(motor),
        index,
    };
    let stepper = HBridgeStepper::new(
        BridgePins {
            in1: pin(0),
            in2: pin(1),
            in3: pin(2),
            in4: pin(3),
        },
        LimitSwitches {
            min: Some(SwitchPin {
                motor: Rc::clone(motor),
            }),
            max: None,
            active_low: false,
        },
        BridgeConfig {
            mode: StepMode::Half,
            ramp: Ramp {
                start_speed_sps: 200,
                max_speed_sps: 2_000,
                accel_sps2: 4_000,
            },
            settle_us: 20_000,
            release_when_idle: true,
        },
    )
    .unwrap();
    StepperAxis::new(
        stepper,
        SwitchPin {
            motor: Rc::clone(motor),
        },
        false,
    )
}

// ---------------------------------------------------------------- geometry

/// Sun direction in the horizontal frame (X west, Y south, Z up) from the
/// elevation and the azimuth east of north: east = sin A cos e, north =
/// cos A cos e.
pub fn sun_xyz(elevation_deg: f64, azimuth_deg: f64) -> [f64; 3] {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    [-a.sin() * e.cos(), -a.cos() * e.cos(), e.sin()]
}

/// Panel normal of a level mount after the C axis turned γ about Z and the
/// A axis α about the turned x axis: Rz(γ)·Rx(α)·(0, 0, 1) =
/// (sin γ sin α, −cos γ sin α, cos α).
pub fn normal_xyz(gamma_deg: f64, alpha_deg: f64) -> [f64; 3] {
    let (g, a) = (gamma_deg.to_radians(), alpha_deg.to_radians());
    [g.sin() * a.sin(), -g.cos() * a.sin(), a.cos()]
}

pub fn angle_deg(u: [f64; 3], v: [f64; 3]) -> f64 {
    let d = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    d.clamp(-1.0, 1.0).acos().to_degrees()
}

pub fn utc_at(secs: u32) -> UtcTime {
    let (h, m, s) = DayTime { secs }.hms();
    UtcTime::from_ymd_hms(2026, 3, 20, h as u8, m as u8, s as u8).unwrap()
}

/// The sun at Kano (11.9683° N, 8.4261° E, 480 m) `secs` after midnight
/// UTC of 2026-03-20, by NREL SPA: the independent sun the pointing of the
/// whole-day tests is checked against (the controller computes PSA+).
pub fn spa_kano(secs: u32) -> SunPosition<f64> {
    let site = Site::with_elevation(11.9683, 8.4261, 480.0).unwrap();
    Algorithm::Spa
        .position(&utc_at(secs), &site, &Options::default())
        .unwrap()
}

/// A tick `t` seconds after midnight UTC of 2026-03-20 with valid time, a
/// GPS fix and no wind.
pub fn calm_tick(t: u32) -> TickInputs {
    TickInputs {
        now_ms: suntracker::time::monotonic::from_board_ms(u64::from(t) * 1000),
        now: utc_at(t),
        time_valid: true,
        gps_fix: true,
        gps_time_implausible: false,
        gps_time_unstable: false,
        gps_position_unstable: false,
        wind_pulses: 0,
        wind_interval_ms: 60_000,
        stow_inputs: Default::default(),
    }
}

/// When the whole-day tests tick after `t`: a second later while an axis
/// homes, else on the next whole minute.
pub fn next_tick(t: u32, homing: bool) -> u32 {
    if homing {
        t + 1
    } else {
        (t / 60 + 1) * 60
    }
}

/// The tracker of these tests: `Config::default()` (Kano, Jimoh & Aliyu's (2019) intervals)
/// with the axes of the motor model (200 steps, half-stepped, 100:1, no
/// backlash), open loop (Li et al.'s (2022) H-bridge steppers have no encoder).
pub fn tracker_config() -> (
    suntracker::config::Config,
    suntracker::controller::ControllerOptions<f64>,
) {
    let mut config = suntracker::config::Config::default();
    for ax in config.axes.iter_mut() {
        ax.counts_per_motor_rev = STEPS_PER_REV;
        ax.microsteps = HALF_STEP;
        ax.gear_ratio = GEAR;
        ax.backlash_deg = 0.0;
    }
    let options = suntracker::controller::ControllerOptions {
        feedback: suntracker::motion::FeedbackMode::OpenLoop,
        ..Default::default()
    };
    (config, options)
}

/// The main loop between two controller ticks: polls both stepper drivers
/// every 100 µs from `from_s` until the motion and the coil settle time
/// are over, or until `to_s`.
pub fn pump<P, S, const N: usize>(
    ctrl: &mut suntracker::controller::Controller<f64, P, Axis, S, N>,
    motors: [&Rc<RefCell<Motor>>; 2],
    from_s: u32,
    to_s: u32,
) where
    P: suntracker::sun::PositionSource<f64>,
    S: suntracker::ports::AttitudeSensor<f64>,
{
    use suntracker::motion::AxisDrive;
    let mut now_us = u64::from(from_s) * 1_000_000;
    let stop_us = u64::from(to_s) * 1_000_000;
    loop {
        let mut busy = false;
        for (ax, motor) in ctrl.axes_mut().iter_mut().zip(motors) {
            let d = ax.drive_mut();
            d.poll(now_us).unwrap();
            motor.borrow_mut().settle();
            busy |= d.pending() != 0 || d.is_moving() || d.is_energised();
        }
        now_us += 100;
        if !busy || now_us >= stop_us {
            break;
        }
    }
}

/// Pointing error of the motor model's pose against a sun position
/// (zenith, azimuth east of north), degrees.
pub fn pointing_error_deg(
    c: &Rc<RefCell<Motor>>,
    a: &Rc<RefCell<Motor>>,
    zenith_deg: f64,
    azimuth_deg: f64,
) -> f64 {
    let n = normal_xyz(c.borrow().angle_deg(), a.borrow().angle_deg());
    angle_deg(n, sun_xyz(90.0 - zenith_deg, azimuth_deg))
}

/// How far the sun is below what a level mount whose A axis stops at ±90°
/// can face (the horizon): an entry computed with the sun just below the
/// horizon can only be met that far off.
pub fn below_reach_deg(zenith_deg: f64) -> f64 {
    (zenith_deg - 90.0).max(0.0)
}
