//! One whole simulated day of the controller on the real drivers with mocked
//! buses: Kano (11.9683° N, 8.4261° E), 2026-03-20, one tick a minute.
//!
//! - RTC: the real DS3231 driver (through `ds323x`) on an embedded-hal-mock
//!   I2C bus; every tick's transactions are set exactly from the datasheet
//!   register layout (status read, time burst read; once, the setting from
//!   GPS because the RTC starts 7 s slow).
//! - GPS: the real NMEA reader on an in-memory UART fed one RMC + GGA epoch
//!   per tick.
//! - Axes: the real H-bridge stepper driver (half-step, ramps, min limit
//!   switch, coil release) through `hw::StepperAxis`. The step pins are too
//!   busy for a transaction list (≈10⁵ steps a day), so they drive a small
//!   recording motor model instead: it turns the four bridge inputs into the
//!   coil current vector and the rotor follows it (half-step phases at 45°),
//!   so the axis angle comes from what the driver really put on its pins.
//!
//! Independent check: the panel normal the *motor model* reached (from the
//! decoded coil phases, `n = Rz(γ)·Rx(α)·ẑ` written out below) against NREL
//! SPA (Reda & Andreas 2004, `sun_algos::Algorithm::Spa`), while the
//! controller computes its table with PSA+ (Blanco et al. 2020,
//! `Algorithm::Psa2020`): a different algorithm and a different code path
//! for the kinematics.

mod tracker_hw_common;

use std::cell::{Cell, RefCell};
use std::convert::Infallible;
use std::rc::Rc;

use drivers::rtc::Ds3231;
use drivers::stepper::hbridge::{BridgePins, Config as BridgeConfig, HBridgeStepper, StepMode};
use drivers::stepper::ramp::Ramp;
use drivers::stepper::LimitSwitches;
use embedded_hal::digital::{ErrorType, InputPin, OutputPin};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};
use sun_algos::{Algorithm, Options, Site, UtcTime};
use suntracker::axis::{AxisDrive, FeedbackMode};
use suntracker::config::Config;
use suntracker::controller::{Controller, ControllerOptions, TickInputs};
use suntracker::hw::{GpsPort, StepperAxis};
use suntracker::safety::Mode;
use suntracker::scheduler::Phase;
use suntracker::sim::sensors::MountSensors;
use suntracker::sources::{resolve_site, SharedSiteSource, SiteOrigin, TimeConfig, TimeKeeper};
use tracker_hw_common::*;

/// 200 full steps per motor revolution, half-stepped, 100:1 worm gear.
const STEPS_PER_REV: u32 = 200;
const HALF_STEP: u16 = 2;
const GEAR: f32 = 100.0;
/// Motor half-steps per axis degree: 200 × 2 × 100 / 360.
const COUNTS_PER_DEG: f64 = 200.0 * 2.0 * 100.0 / 360.0;

/// Pointing tolerance at each set-point. Per axis: homing finds the switch
/// within one half-step (0.009°) and each move truncates to a whole
/// half-step (≤ 0.009°); PSA+ and SPA differ by ≈ 0.004° here. Measured:
/// 0.023° at worst. 0.05° leaves room for neither a lost step (0.009° each,
/// but they add up) nor a wrong table entry (the sun moves ≈ 1° per entry).
const TOL_DEG: f64 = 0.05;

// ---------------------------------------------------------------- motor model

/// A bipolar stepper and its axis, seen through the four bridge inputs.
#[derive(Debug)]
struct Motor {
    /// Bridge inputs IN1..IN4 (A+, A−, B+, B−).
    pins: [bool; 4],
    /// Last rotor phase (multiples of 45°), once a coil was energised.
    phase: Option<i64>,
    /// Rotor position in half-steps from the start.
    half_steps: i64,
    /// Axis angle at the start, degrees (unknown to the controller).
    start_deg: f64,
    /// The limit switch is closed at or below this axis angle.
    switch_deg: f64,
    /// Both ends of one coil driven high (shoot-through).
    shoot_through: u32,
    /// Phase jumps of 135° or more (the rotor would lose sync).
    lost_sync: u32,
    /// Times the axis was driven beyond the hard stop (1° past the switch).
    hit_stop: u32,
    pin_writes: u64,
}

impl Motor {
    fn new(start_deg: f64, switch_deg: f64) -> Rc<RefCell<Motor>> {
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

    fn angle_deg(&self) -> f64 {
        self.start_deg + self.half_steps as f64 / COUNTS_PER_DEG
    }

    fn switch_closed(&self) -> bool {
        self.angle_deg() <= self.switch_deg
    }

    fn energised(&self) -> bool {
        self.pins.iter().any(|&p| p)
    }

    /// A pin write. A bridge leg driven high at both ends shorts the supply
    /// at once, so that is checked on every write.
    fn set(&mut self, pin: usize, high: bool) {
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
    fn settle(&mut self) {
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

struct CoilPin {
    motor: Rc<RefCell<Motor>>,
    index: usize,
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
struct SwitchPin {
    motor: Rc<RefCell<Motor>>,
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

type Axis = StepperAxis<CoilPin, SwitchPin, SwitchPin>;

fn stepper_axis(motor: &Rc<RefCell<Motor>>) -> Axis {
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
fn sun_xyz(elevation_deg: f64, azimuth_deg: f64) -> [f64; 3] {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    [-a.sin() * e.cos(), -a.cos() * e.cos(), e.sin()]
}

/// Panel normal of a level mount after the C axis turned γ about Z and the
/// A axis α about the turned x axis: Rz(γ)·Rx(α)·(0, 0, 1) =
/// (sin γ sin α, −cos γ sin α, cos α).
fn normal_xyz(gamma_deg: f64, alpha_deg: f64) -> [f64; 3] {
    let (g, a) = (gamma_deg.to_radians(), alpha_deg.to_radians());
    [g.sin() * a.sin(), -g.cos() * a.sin(), a.cos()]
}

fn angle_deg(u: [f64; 3], v: [f64; 3]) -> f64 {
    let d = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    d.clamp(-1.0, 1.0).acos().to_degrees()
}

fn utc_at(secs: u32) -> UtcTime {
    let (h, m, s) = DayTime { secs }.hms();
    UtcTime::from_ymd_hms(2026, 3, 20, h as u8, m as u8, s as u8).unwrap()
}

// ---------------------------------------------------------------- the day

#[test]
fn kano_equinox_day_on_real_drivers() {
    // Devices.
    let c_motor = Motor::new(20.0, -180.0);
    let a_motor = Motor::new(10.0, -90.0);
    let mut i2c = I2cMock::new(&[]);
    let mut keeper = TimeKeeper::new(Ds3231::new(i2c.clone()), TimeConfig { max_drift_s: 2 });
    let uart = MemSerial::default();
    let mut gps = GpsPort::new(uart.clone(), 3_000);

    // Power-on: the first GPS epoch gives the site (issue 6 item 2).
    let mut t: u32 = 60; // seconds after 2026-03-20 00:00 UTC
    uart.push(&gps_epoch(DayTime { secs: t }, true));
    let fix = gps.service(u64::from(t) * 1_000).unwrap();
    let stored = Config::default().site;
    let (site, origin) = resolve_site(&fix, Some(&stored), None).unwrap();
    assert_eq!(origin, SiteOrigin::Gps);
    assert_eq!(
        (
            site.latitude_deg(),
            site.longitude_deg(),
            site.elevation_m()
        ),
        (11.9683, 8.4261, 480.0)
    );
    let site_cell = Cell::new(site);
    let source = SharedSiteSource {
        algorithm: Algorithm::Psa2020,
        site: &site_cell,
        options: Options::default(),
    };

    // The tracker: level mount, open loop on counted half-steps (seed
    // li-2022's H-bridge steppers have no encoders), re-homed every night.
    let mut config = Config::default();
    for ax in config.axes.iter_mut() {
        ax.counts_per_motor_rev = STEPS_PER_REV;
        ax.microsteps = HALF_STEP;
        ax.gear_ratio = GEAR;
        ax.backlash_deg = 0.0;
    }
    let options = ControllerOptions {
        feedback: FeedbackMode::OpenLoop,
        ..ControllerOptions::default()
    };
    let axes = [stepper_axis(&c_motor), stepper_axis(&a_motor)];
    let mut ctrl: Controller<_, Axis, MountSensors, 360> =
        Controller::new(config, options, source, axes, None).unwrap();

    // The independent sun.
    let spa_site = Site::with_elevation(11.9683, 8.4261, 480.0).unwrap();
    let spa = |secs: u32| {
        Algorithm::Spa
            .position(&utc_at(secs), &spa_site, &Options::default())
            .unwrap()
    };

    let mut rtc_offset_s: i64 = -7; // the RTC starts 7 s slow
    let mut last_set_point = None;
    let mut applied = 0usize;
    let mut max_err_deg: f64 = 0.0;
    let mut ticks = 0u32;
    let mut homing_ticks = 0u32;
    let mut first_track_s = None;
    let mut go_home_s = None;
    let end_s = 23 * 3600;
    while t < end_s {
        ticks += 1;
        // GPS epoch of this second, then the exact RTC traffic of the tick.
        if ticks > 1 {
            uart.push(&gps_epoch(DayTime { secs: t }, true));
        }
        let fix = gps.service(u64::from(t) * 1_000).unwrap();
        let rtc_reads = DayTime {
            secs: (i64::from(t) + rtc_offset_s) as u32,
        };
        let mut tx: Vec<I2c> = vec![read_status(STATUS_RUNNING), read_time(rtc_reads)];
        if rtc_offset_s.abs() > 2 {
            tx.extend(set_time(DayTime { secs: t }));
            rtc_offset_s = 0;
        }
        i2c.update_expectations(&tx);
        let status = keeper.update(&fix);
        assert_eq!(status.now, Some(utc_at(t)), "GPS time at t={t}");

        let report = ctrl.tick(&TickInputs {
            now: status.tick_time(utc_at(t)),
            time_valid: status.time_valid(),
            gps_fix: status.gps_fix,
            wind_pulses: 0,
            wind_interval_s: 60.0,
        });
        if report.homing {
            homing_ticks += 1;
        }

        // The main loop runs the drivers until the motion (and the coil
        // settle time) is over, at most until the next minute.
        let next = if report.homing {
            t + 1
        } else {
            (t / 60 + 1) * 60
        };
        let mut now_us = u64::from(t) * 1_000_000;
        let stop_us = u64::from(next) * 1_000_000;
        loop {
            let mut busy = false;
            for (ax, motor) in ctrl.axes_mut().iter_mut().zip([&c_motor, &a_motor]) {
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

        // A new table entry applied: where does the panel point now?
        let tracking = matches!(ctrl.scheduler().phase(), Phase::Tracking { .. });
        if report.mode == Mode::Tracking && tracking && report.set_point != last_set_point {
            let late = t % 240;
            assert!(late < 30, "entry applied {late} s after its time");
            let entry_s = t - late;
            let sun = spa(entry_s);
            let n = normal_xyz(c_motor.borrow().angle_deg(), a_motor.borrow().angle_deg());
            let err = angle_deg(n, sun_xyz(90.0 - sun.zenith_deg, sun.azimuth_deg));
            assert!(err <= TOL_DEG, "pointing error {err}° at t={t}");
            max_err_deg = max_err_deg.max(err);
            applied += 1;
            first_track_s.get_or_insert(t);
        }
        if report.mode == Mode::Tracking && tracking {
            last_set_point = report.set_point;
        }
        if first_track_s.is_some() && go_home_s.is_none() && report.mode == Mode::Night {
            go_home_s = Some(t);
        }
        t = next;
    }
    i2c.done();

    let first = first_track_s.expect("tracked");
    let home_at = go_home_s.expect("went home");
    let table = ctrl.scheduler().table();
    println!(
        "ticks={ticks} homing_ticks={homing_ticks} entries={} applied={applied} \
         first={first} s go_home={home_at} s max_err_deg={max_err_deg:.4} \
         c_writes={} a_writes={}",
        table.len(),
        c_motor.borrow().pin_writes,
        a_motor.borrow().pin_writes
    );
    // Every table entry was applied, once.
    assert_eq!(applied, table.len());
    // The daylight span against SPA: the sun is up at the first entry and
    // down 4 minutes after the last one.
    assert!(90.0 - spa(first).zenith_deg > 0.0);
    let last_entry_s = first + 240 * (table.len() as u32 - 1);
    assert!(90.0 - spa(last_entry_s + 240).zenith_deg < 0.0);
    assert!(home_at > last_entry_s && home_at <= last_entry_s + 300);

    // Home at day end: the panel faces the day's first entry again (seed
    // li-2022), checked against SPA at that entry's time.
    let home_sun = spa(first);
    let n = normal_xyz(c_motor.borrow().angle_deg(), a_motor.borrow().angle_deg());
    let err = angle_deg(n, sun_xyz(90.0 - home_sun.zenith_deg, home_sun.azimuth_deg));
    assert!(err <= TOL_DEG, "home pose off by {err}°");

    // Night: coils released, no fault left, nothing went wrong on the pins.
    for (name, m) in [("C", &c_motor), ("A", &a_motor)] {
        let m = m.borrow();
        assert!(!m.energised(), "{name} coils still powered at night");
        assert_eq!(
            (m.shoot_through, m.lost_sync, m.hit_stop),
            (0, 0, 0),
            "{name} axis pin faults"
        );
    }
    // Homed twice each (boot and night): the fast approach of each homing
    // ends with the driver refusing to step past the closed switch.
    for ax in ctrl.axes().iter() {
        assert!(
            ax.drive().limit_stops() >= 2,
            "{}",
            ax.drive().limit_stops()
        );
    }
    assert_eq!(ctrl.faults().active_count(), 0);
    assert_eq!(keeper.rtc_sets(), 1);
    let stats = gps.stats();
    assert_eq!(stats.sentences, stats.accepted);
}
