//! The whole controller over the simulated plants and sensors: a full day,
//! faults with their recoveries, stow, manual override.

use sim::plant::MotorPlant;
use sim::sensors::{MountSensors, SensorAccuracy};
use sun_algos::{Algorithm, Options, Site, UtcTime};
use suntracker::attitude::{angle_between_deg, sun_vector_xyz, MountAttitude, Pose};
use suntracker::config::Config;
use suntracker::controller::{
    AttitudeSource, Controller, ControllerOptions, TickInputs, STALL_MIN_WAIT_MS,
};
use suntracker::motion::{AxisDrive, FeedbackMode};
use suntracker::safety::{AxisId, Fault, Mode, NoWeather, Reading, Sensor, StowInputs, Weather};
use suntracker::sun::{AlgorithmSource, PositionSource};

type Ctl = Controller<f64, AlgorithmSource<f64>, MotorPlant, MountSensors, 1441>;

fn source() -> AlgorithmSource<f64> {
    AlgorithmSource {
        algorithm: Algorithm::Psa2020,
        site: Site::new(11.9683, 8.4261).unwrap(),
        options: Options::default(),
    }
}

fn config() -> Config {
    let mut c = Config::default();
    c.schedule.table_step_s = 60;
    c.schedule.hold_s = 30;
    for a in c.axes.iter_mut() {
        a.deadband_deg = 0.02;
    }
    c
}

fn plants(encoder: bool) -> [MotorPlant; 2] {
    let enc = encoder.then_some(1u32 << 16);
    [
        MotorPlant::stepper(1.8, 16, 100.0, 0.2, 2.0, enc, -180.0, 180.0, 10.0),
        MotorPlant::stepper(1.8, 16, 100.0, 0.2, 2.0, enc, -90.0, 90.0, 20.0),
    ]
}

fn controller(encoder: bool, attitude: AttitudeSource<f64>, truth: MountAttitude<f64>) -> Ctl {
    let opts = ControllerOptions {
        feedback: if encoder {
            FeedbackMode::ClosedLoop
        } else {
            FeedbackMode::OpenLoop
        },
        attitude,
        ..ControllerOptions::default()
    };
    let sensors = MountSensors::new(truth, SensorAccuracy::exact(), 3);
    Controller::new(config(), opts, source(), plants(encoder), Some(sensors)).unwrap()
}

fn inputs(now: UtcTime) -> TickInputs {
    TickInputs {
        // No clock steps here: the monotonic clock runs with UTC.
        now_ms: suntracker::time::monotonic::from_board_ms(
            now.unix_seconds().unsigned_abs() * 1000,
        ),
        now,
        time_valid: true,
        gps_fix: true,
        gps_time_implausible: false,
        gps_time_unstable: false,
        gps_position_unstable: false,
        wind_pulses: 300, // 5 Hz: calm
        wind_interval_ms: 60_000,
        stow_inputs: Default::default(),
    }
}

fn true_error(ctl: &Ctl, truth: &MountAttitude<f64>, now: &UtcTime) -> Option<f64> {
    let sun = source().position(now).ok()?;
    if !sun.is_above_horizon() {
        return None;
    }
    let s = sun_vector_xyz(sun.elevation_deg(), sun.azimuth_deg);
    let ax = ctl.axes();
    let pose = Pose {
        gamma_deg: ax[0].drive().output_deg(),
        alpha_deg: ax[1].drive().output_deg(),
    };
    Some(angle_between_deg(&truth.normal_xyz(&pose), &s))
}

fn step(ctl: &mut Ctl, inp: &TickInputs) -> suntracker::controller::TickReport<f64> {
    for ax in ctl.axes_mut().iter_mut() {
        ax.drive_mut().begin_tick(60.0);
    }
    ctl.tick(inp)
}

fn t(s: &str) -> UtcTime {
    s.parse().unwrap()
}

#[test]
fn full_day_on_a_level_mount_with_encoders() {
    let truth = MountAttitude::level();
    let mut ctl = controller(true, AttitudeSource::Fixed(truth), truth);
    let start = t("2026-03-20T00:00:00Z");
    let mut errs = Vec::new();
    let mut modes = Vec::new();
    for m in 0..1440 {
        let now = start.add_seconds(m * 60).unwrap();
        let r = step(&mut ctl, &inputs(now));
        modes.push(r.mode);
        if r.mode == Mode::Tracking {
            if let Some(e) = true_error(&ctl, &truth, &now) {
                errs.push(e);
            }
        }
    }
    // Sunrise to sunset near the equinox at 12° N: about 12 h of tracking.
    assert!(errs.len() > 700 && errs.len() < 740, "{}", errs.len());
    // Waiting at night facing the coming sunrise, the first minute of the
    // day is already on the sun.
    assert!(errs[0] < 0.05, "first minute {}", errs[0]);
    errs.sort_by(f64::total_cmp);
    let p95 = errs[errs.len() * 95 / 100];
    assert!(p95 < 0.05, "p95 {p95}");
    // Power-on at night: the axes home first (homing ranks above night).
    assert_eq!(modes[0], Mode::Homing);
    assert_eq!(modes[1], Mode::Night);
    assert_eq!(*modes.last().unwrap(), Mode::Night);
    assert_eq!(ctl.faults().raised, 0);
}

#[test]
fn portable_mount_from_sensors_points_at_the_sun() {
    let truth = MountAttitude {
        alpha0_deg: 10.0,
        beta0_deg: -6.0,
        gamma0_deg: 40.0,
    };
    let mut ctl = controller(false, AttitudeSource::Sensors, truth);
    let now0 = t("2026-06-01T07:00:00Z");
    let mut worst: f64 = 0.0;
    for m in 0..120 {
        let now = now0.add_seconds(m * 60).unwrap();
        let r = step(&mut ctl, &inputs(now));
        if m > 10 {
            assert_eq!(r.mode, Mode::Tracking);
            worst = worst.max(true_error(&ctl, &truth, &now).unwrap());
        }
    }
    // Exact sensors, counted steps with compensated backlash.
    assert!(worst < 0.05, "{worst}");
    let est = ctl.attitude();
    assert!((est.alpha0_deg - 10.0).abs() < 1e-6 && (est.gamma0_deg - 40.0).abs() < 1e-6);
}

#[test]
fn wind_and_command_stow_and_manual_override() {
    let truth = MountAttitude::level();
    let mut ctl = controller(true, AttitudeSource::Fixed(truth), truth);
    let now0 = t("2026-03-20T09:00:00Z");
    let at = |m: i64| now0.add_seconds(m * 60).unwrap();
    // Power-on: set-points zero (Jimoh & Aliyu 2019 step 1), not yet
    // tracking; the axes home first.
    assert_eq!(step(&mut ctl, &inputs(at(-1))).mode, Mode::Homing);
    for m in 0..5 {
        assert_eq!(step(&mut ctl, &inputs(at(m))).mode, Mode::Tracking);
    }
    // 40 Hz counted over a minute: above the threshold for longer than the
    // 3-second hold → stowed flat (α = 0) on that very tick.
    let mut windy = inputs(at(5));
    windy.wind_pulses = 2400;
    assert_eq!(step(&mut ctl, &windy).mode, Mode::WindStow);
    windy = inputs(at(6));
    windy.wind_pulses = 2400;
    let r = step(&mut ctl, &windy);
    assert_eq!(r.mode, Mode::WindStow);
    assert!(ctl.axes()[1].drive().output_deg().abs() < 0.05);
    // Calm again from minute 6 (the interval counted up to minute 7), but
    // stowed for the 10-minute release time.
    for m in 7..16 {
        assert_eq!(step(&mut ctl, &inputs(at(m))).mode, Mode::WindStow);
    }
    let mut back = None;
    for m in 16..20 {
        if step(&mut ctl, &inputs(at(m))).mode == Mode::Tracking {
            back = Some(m);
            break;
        }
    }
    assert_eq!(back, Some(16));
    // Command stow, then manual override.
    ctl.command_stow(true);
    assert_eq!(step(&mut ctl, &inputs(at(30))).mode, Mode::CommandStow);
    ctl.command_stow(false);
    let manual = Pose {
        gamma_deg: 30.0,
        alpha_deg: 45.0,
    };
    ctl.manual(Some(manual));
    assert_eq!(step(&mut ctl, &inputs(at(31))).mode, Mode::Manual);
    assert!((ctl.axes()[0].drive().output_deg() - 30.0).abs() < 0.05);
    assert!((ctl.axes()[1].drive().output_deg() - 45.0).abs() < 0.05);
    ctl.manual(None);
    assert_eq!(step(&mut ctl, &inputs(at(32))).mode, Mode::Tracking);
}

#[test]
fn weather_stows_with_weather_inputs_and_never_without_them() {
    // Snow reported and the supply input at a rail, with the low-supply
    // stow configured (`supply.stow_mv`): a board with weather inputs
    // stows for the snow (snow before low supply in the mode order) and
    // raises `supply_reading`; one without (`NoWeather`, the Uno) tracks
    // on, as its pins read nothing of the kind, and still stows for wind.
    let truth = MountAttitude::level();
    let opts = ControllerOptions {
        attitude: AttitudeSource::Fixed(truth),
        ..ControllerOptions::default()
    };
    let mut cfg = config();
    cfg.supply.stow_mv = 11_000;
    cfg.supply.resume_mv = 12_000;
    let mut wired: Ctl = Controller::new(cfg, opts, source(), plants(true), None).unwrap();
    let mut bare = Controller::<f64, _, _, MountSensors, 1441, NoWeather>::new(
        cfg,
        opts,
        source(),
        plants(true),
        None,
    )
    .unwrap();
    let now0 = t("2026-03-20T09:00:00Z");
    let at = |m: i64| now0.add_seconds(m * 60).unwrap();
    let snowy = |m: i64| TickInputs {
        stow_inputs: StowInputs {
            snow: Some(true),
            supply_mv: Some(Reading::Impossible),
            ..StowInputs::default()
        },
        ..inputs(at(m))
    };
    fn tick<W: Weather>(
        ctl: &mut Controller<f64, AlgorithmSource<f64>, MotorPlant, MountSensors, 1441, W>,
        inp: &TickInputs,
    ) -> suntracker::controller::TickReport<f64> {
        for ax in ctl.axes_mut().iter_mut() {
            ax.drive_mut().begin_tick(60.0);
        }
        ctl.tick(inp)
    }
    for m in -1..5 {
        tick(&mut wired, &inputs(at(m)));
        tick(&mut bare, &inputs(at(m)));
    }
    assert_eq!(tick(&mut wired, &snowy(5)).mode, Mode::SnowStow);
    assert!(wired.faults().is_active(Fault::SupplyReading));
    assert_eq!(tick(&mut bare, &snowy(5)).mode, Mode::Tracking);
    assert!(!bare.faults().is_active(Fault::SupplyReading));
    let mut windy = snowy(6);
    windy.wind_pulses = 2400;
    assert_eq!(tick(&mut bare, &windy).mode, Mode::WindStow);
}

#[test]
fn faults_are_raised_handled_and_cleared() {
    let truth = MountAttitude {
        alpha0_deg: 5.0,
        beta0_deg: 3.0,
        gamma0_deg: -20.0,
    };
    let mut ctl = controller(true, AttitudeSource::Sensors, truth);
    let now0 = t("2026-03-20T08:00:00Z");
    let at = |m: i64| now0.add_seconds(m * 60).unwrap();
    let m = std::cell::Cell::new(0i64);
    let run = |ctl: &mut Ctl, n: i64, inp: &dyn Fn(UtcTime) -> TickInputs| {
        let mut last = None;
        for _ in 0..n {
            last = Some(step(ctl, &inp(at(m.get()))));
            m.set(m.get() + 1);
        }
        last.unwrap()
    };
    run(&mut ctl, 5, &inputs);

    // Compass bus error: retried, then open loop on the last attitude.
    ctl.sensors_mut().unwrap().failing = true;
    let r = run(&mut ctl, 6, &inputs);
    assert_eq!(r.mode, Mode::Tracking);
    assert!(ctl.faults().is_active(Fault::I2cError(Sensor::Compass)));
    assert!(ctl.faults().open_loop());
    ctl.sensors_mut().unwrap().failing = false;
    run(&mut ctl, 1, &inputs);
    assert!(!ctl.faults().is_active(Fault::I2cError(Sensor::Compass)));

    // Motor stall on the C axis: driven, no encoder motion.
    ctl.axes_mut()[0].drive_mut().stalled = true;
    // The sun moves ~0.25°/min; ask for a bigger move with a manual pose.
    ctl.manual(Some(Pose {
        gamma_deg: -60.0,
        alpha_deg: 30.0,
    }));
    run(&mut ctl, 6, &inputs);
    assert!(ctl.faults().is_active(Fault::MotorStalled(AxisId::C)));
    assert!(ctl.faults().axis_disabled(AxisId::C));
    ctl.axes_mut()[0].drive_mut().stalled = false;
    // Probed every 10 ticks: motion after a probe clears the fault.
    run(&mut ctl, 25, &inputs);
    assert!(!ctl.faults().is_active(Fault::MotorStalled(AxisId::C)));
    ctl.manual(None);

    // A limit switch that closes far from home: re-homed, then tracking.
    ctl.axes_mut()[1].drive_mut().switch_stuck = true;
    run(&mut ctl, 1, &inputs);
    assert!(ctl.faults().is_active(Fault::LimitSwitchHit(AxisId::A)));
    ctl.axes_mut()[1].drive_mut().switch_stuck = false;
    let r = run(&mut ctl, 15, &inputs);
    assert!(!ctl.faults().is_active(Fault::LimitSwitchHit(AxisId::A)));
    assert_eq!(r.mode, Mode::Tracking);
    let e = true_error(&ctl, &truth, &at(m.get() - 1)).unwrap();
    assert!(e < 0.1, "{e}");

    // GPS lost: keep tracking on RTC; RTC invalid: stow until time is back.
    let no_gps = |now| TickInputs {
        gps_fix: false,
        ..inputs(now)
    };
    assert_eq!(run(&mut ctl, 2, &no_gps).mode, Mode::Tracking);
    assert!(ctl.faults().is_active(Fault::GpsLost));
    let no_time = |now| TickInputs {
        time_valid: false,
        ..inputs(now)
    };
    assert_eq!(run(&mut ctl, 2, &no_time).mode, Mode::WaitForTime);
    let r = run(&mut ctl, 2, &inputs);
    assert_eq!(r.mode, Mode::Tracking);
    assert_eq!(ctl.faults().active_count(), 0);
    assert_eq!(ctl.faults().raised, ctl.faults().recovered);
    assert!(ctl.faults().raised >= 5);
}

/// A tick that comes at once after the one that commanded a move (the
/// pass before it ran longer than the tick interval, and the firmware runs
/// the late tick straight away) finds a drive that has not had time to
/// move: the stall is judged at the first tick `STALL_MIN_WAIT_MS` after
/// the command, not at that one. Seen in the ATmega2560 emulator with a
/// servo axis, whose first pulse comes in the 20 ms frame after the tick.
#[test]
fn a_stall_is_judged_only_once_the_drive_had_time_to_move() {
    let truth = MountAttitude::level();
    let mut ctl = controller(true, AttitudeSource::Fixed(truth), truth);
    let now0 = t("2026-03-20T09:00:00Z");
    let at = |m: i64| now0.add_seconds(m * 60).unwrap();
    for m in -1..3 {
        step(&mut ctl, &inputs(at(m)));
    }
    let stalled = |ctl: &Ctl| ctl.faults().is_active(Fault::MotorStalled(AxisId::C));
    assert!(!stalled(&ctl));
    let base = inputs(at(3));
    // A tick `dt_ms` after `base`, the drives given `motion_s` to move in.
    let tick_at = |ctl: &mut Ctl, dt_ms: u32, motion_s: f64| {
        for ax in ctl.axes_mut().iter_mut() {
            ax.drive_mut().begin_tick(motion_s);
        }
        ctl.tick(&TickInputs {
            now_ms: base.now_ms.wrapping_add(dt_ms),
            ..base
        });
    };
    // A swing of the C axis, with no time to start it.
    ctl.manual(Some(Pose {
        gamma_deg: -60.0,
        alpha_deg: 30.0,
    }));
    tick_at(&mut ctl, 0, 0.0);
    tick_at(&mut ctl, 10, 0.0);
    assert!(!stalled(&ctl), "judged 10 ms after the command");
    // A tick later it has moved, and the next has nothing more to judge.
    tick_at(&mut ctl, 1_000, 60.0);
    tick_at(&mut ctl, 1_600, 60.0);
    assert!(!stalled(&ctl));
    // Stalled: not at the tick 10 ms after the command, at the one
    // STALL_MIN_WAIT_MS after it.
    ctl.axes_mut()[0].drive_mut().stalled = true;
    ctl.manual(Some(Pose {
        gamma_deg: 60.0,
        alpha_deg: 30.0,
    }));
    tick_at(&mut ctl, 2_000, 60.0);
    tick_at(&mut ctl, 2_010, 60.0);
    assert!(!stalled(&ctl), "judged 10 ms after the command");
    // Commanded again at each tick, judged from the first command.
    tick_at(&mut ctl, 2_000 + STALL_MIN_WAIT_MS - 1, 60.0);
    assert!(!stalled(&ctl), "judged before STALL_MIN_WAIT_MS");
    tick_at(&mut ctl, 2_000 + STALL_MIN_WAIT_MS, 60.0);
    assert!(stalled(&ctl));
}

// ------------------------------------------------ field incidents, replayed

/// A tick with its own monotonic time `ms` and wall clock `now`.
fn at_clock(ms: u32, now: UtcTime) -> TickInputs {
    TickInputs {
        now_ms: ms,
        ..inputs(now)
    }
}

#[test]
fn a_gale_after_the_clock_steps_back_a_day_stows_within_one_tick() {
    // Before: the wind hold ran on UTC. With the clock stepped back a day
    // during a gale, the hold "began" a day in the future and the panel
    // kept tracking for 24 hours at |α| ≈ 90°.
    let truth = MountAttitude::level();
    let mut ctl = controller(true, AttitudeSource::Fixed(truth), truth);
    let now0 = t("2026-03-20T09:00:00Z");
    let mut ms = 0u32;
    for m in 0..5 {
        ms += 60_000;
        step(&mut ctl, &at_clock(ms, now0.add_seconds(m * 60).unwrap()));
    }
    assert_eq!(ctl.faults().active_count(), 0);
    // The gale begins within a minute (counted 50 Hz over a 1-s window of
    // a 1-s tick), then the RTC is corrected back by a day.
    let mut gale = at_clock(ms + 1_000, now0.add_seconds(300).unwrap());
    gale.wind_pulses = 50;
    gale.wind_interval_ms = 1_000;
    assert_eq!(step(&mut ctl, &gale).mode, Mode::Tracking);
    let stepped = now0.add_seconds(300 - 86_400).unwrap();
    for k in 2..=3u32 {
        gale.now_ms = ms + k * 1_000;
        gale.now = stepped.add_seconds(k as i64).unwrap();
        let mode = step(&mut ctl, &gale).mode;
        // Three seconds above 25 Hz: stowed at the third second.
        assert_eq!(mode == Mode::WindStow, k == 3, "second {k}: {mode:?}");
    }
    // Calm from here; the wall clock jumps forward two days: the release
    // still takes its 600 s on the monotonic clock, no more, no less.
    let calm_from = ms + 3_000;
    let jumped = now0.add_seconds(2 * 86_400).unwrap();
    let mut released_after_s = None;
    for s in 1..=700u32 {
        let inp = TickInputs {
            wind_pulses: 5,
            wind_interval_ms: 1_000,
            ..at_clock(calm_from + s * 1_000, jumped.add_seconds(s as i64).unwrap())
        };
        if step(&mut ctl, &inp).mode != Mode::WindStow {
            released_after_s = Some(s);
            break;
        }
    }
    assert_eq!(released_after_s, Some(600));
}

#[test]
fn a_time_outside_the_algorithm_range_stops_tracking_with_a_fault() {
    // Before: after a forward jump out of psa-2020's range (2020–2050) the
    // scheduler errored every minute, no fault was raised and the mode
    // stayed Tracking on a frozen set-point all night.
    let truth = MountAttitude::level();
    let mut ctl = controller(true, AttitudeSource::Fixed(truth), truth);
    let now0 = t("2026-03-20T09:00:00Z");
    let mut ms = 0;
    let mut tick = |ctl: &mut Ctl, now: UtcTime| {
        ms += 60_000;
        step(ctl, &at_clock(ms, now))
    };
    for m in 0..5 {
        assert_ne!(
            tick(&mut ctl, now0.add_seconds(m * 60).unwrap()).mode,
            Mode::SafeStop
        );
    }
    assert_eq!(
        tick(&mut ctl, now0.add_seconds(300).unwrap()).mode,
        Mode::Tracking
    );
    let far = t("2051-03-20T09:06:00Z");
    for m in 0..30 {
        let r = tick(&mut ctl, far.add_seconds(m * 60).unwrap());
        assert_eq!(r.mode, Mode::WaitForTime, "minute {m}");
        assert!(r.set_point.is_none());
        assert!(ctl.faults().is_active(Fault::TimeOutOfRange));
    }
    // Before the range too (the week-rollover year 2006).
    let early = t("2006-08-04T09:36:00Z");
    let r = tick(&mut ctl, early);
    assert_eq!(r.mode, Mode::WaitForTime);
    // A correct time again: the fault clears and tracking resumes.
    let back = now0.add_seconds(3600).unwrap();
    let mut resumed = None;
    for m in 0..5 {
        if tick(&mut ctl, back.add_seconds(m * 60).unwrap()).mode == Mode::Tracking {
            resumed = Some(m);
            break;
        }
    }
    assert!(resumed.is_some());
    assert!(!ctl.faults().is_active(Fault::TimeOutOfRange));
}

#[test]
fn a_limit_switch_stuck_closed_ends_in_a_safe_stop_within_soft_limits() {
    // Before: homing backed off 15° per attempt, attempt after attempt,
    // with no soft-limit check; the C axis ended at its hard stop (181°),
    // the fault stayed at attempt 1 and the mode read Tracking while the
    // axis was unhomed.
    let truth = MountAttitude::level();
    let mut ctl = controller(true, AttitudeSource::Fixed(truth), truth);
    ctl.axes_mut()[0].drive_mut().switch_stuck = true;
    let now0 = t("2026-03-20T09:00:00Z");
    let limits = Config::default().axes;
    let mut stop_at = None;
    for m in 0..120i64 {
        let now = now0.add_seconds(m * 60).unwrap();
        let r = step(&mut ctl, &at_clock((m as u32 + 1) * 60_000, now));
        let c = ctl.axes()[0].drive().output_deg();
        assert!(
            c <= f64::from(limits[0].max_deg) && c >= f64::from(limits[0].min_deg) - 1.0,
            "C axis at {c}° at minute {m}"
        );
        let unhomed = ctl
            .axes()
            .iter()
            .any(|a| a.home_state() != suntracker::motion::HomeState::Done);
        assert!(!(unhomed && r.mode == Mode::Tracking), "minute {m}");
        if r.mode == Mode::SafeStop {
            stop_at.get_or_insert(m);
        }
    }
    // Four failed attempts 10, 20 and 40 s of back-off apart (one-minute
    // ticks): the safe stop comes within 5 minutes and holds.
    let stop_at = stop_at.expect("no safe stop");
    assert!(stop_at <= 5, "safe stop at minute {stop_at}");
    let lim = ctl.faults().get(Fault::LimitSwitchHit(AxisId::C)).unwrap();
    assert!(lim.attempts >= 4);
    // The technician frees the switch and clears the stop: homed, tracking.
    ctl.axes_mut()[0].drive_mut().switch_stuck = false;
    ctl.reset_faults();
    let mut tracking = None;
    for m in 120..140i64 {
        let now = now0.add_seconds(m * 60).unwrap();
        if step(&mut ctl, &at_clock((m as u32 + 1) * 60_000, now)).mode == Mode::Tracking {
            tracking = Some(m);
            break;
        }
    }
    assert!(tracking.is_some_and(|m| m <= 125), "{tracking:?}");
}

/// Without a trusted time the tracker homes and then waits stowed: the
/// panel flat (α = 0) and the C axis left at its home switch, not swung
/// 180° to an azimuth nobody commanded; after that nothing moves.
#[test]
fn without_time_it_homes_then_stows_without_an_azimuth_swing() {
    let truth = MountAttitude::level();
    let mut ctl = controller(true, AttitudeSource::Fixed(truth), truth);
    let now0 = t("2026-03-20T09:00:00Z");
    let mut positions = Vec::new();
    for m in 0..30u32 {
        let inp = TickInputs {
            time_valid: false,
            gps_fix: false,
            ..at_clock(m * 60_000, now0)
        };
        let r = step(&mut ctl, &inp);
        assert_eq!(r.mode, Mode::WaitForTime, "minute {m}");
        let ax = ctl.axes();
        positions.push((ax[0].drive().output_deg(), ax[1].drive().output_deg()));
    }
    let (c, a) = *positions.last().unwrap();
    // Homed at the low stops (C −180°, A −90°), then A to the flat stow.
    assert!((c - (-180.0)).abs() < 0.5, "C at {c}");
    assert!(a.abs() < 0.5, "A at {a}");
    // The last ten minutes: still.
    for p in &positions[20..] {
        assert_eq!(*p, (c, a));
    }
}

/// An axis stopped mid-move (the other axis lost its reference, so the
/// tracker homes it and holds the homed one still) keeps counting where it
/// really is: the counts its drive dropped are taken off its position. Open
/// loop, where nothing else would ever correct the count.
#[test]
fn an_axis_held_still_mid_move_counts_where_it_stopped() {
    let truth = MountAttitude::level();
    let mut ctl = controller(false, AttitudeSource::Fixed(truth), truth);
    let t0 = t("2026-03-20T07:00:00Z");
    let mut ms = 0u32;
    // Minutes with whole moves: homed and tracking.
    let mut r = None;
    for m in 0..30 {
        ms += 60_000;
        r = Some(step(
            &mut ctl,
            &at_clock(ms, t0.add_seconds(m * 60).unwrap()),
        ));
    }
    assert_eq!(r.unwrap().mode, Mode::Tracking);
    // Five hours on (a long move for both axes), with 1 s of motion a tick.
    let later = t("2026-03-20T12:00:00Z");
    let short_tick = |ctl: &mut Ctl, ms: u32, now: UtcTime| {
        for ax in ctl.axes_mut().iter_mut() {
            ax.drive_mut().begin_tick(1.0);
        }
        ctl.tick(&at_clock(ms, now))
    };
    ms += 1_000;
    short_tick(&mut ctl, ms, later);
    assert!(ctl.axes()[1].drive().pending() != 0, "A should be mid-move");
    // C loses its reference: the tracker homes it and holds A still.
    ctl.axes_mut()[0].unhome();
    ms += 1_000;
    let r = short_tick(&mut ctl, ms, later.add_seconds(1).unwrap());
    assert_eq!(r.mode, Mode::Homing);
    let a = &ctl.axes()[1];
    assert_eq!(a.drive().pending(), 0);
    let counted = f64::from(a.counted_deg());
    let real = a.drive().output_deg();
    assert!(
        (counted - real).abs() < 0.01,
        "A counts {counted}° but stands at {real}°"
    );
}

/// A source that counts the sun positions it computes.
struct CountingSource {
    inner: AlgorithmSource<f64>,
    calls: u32,
}

impl PositionSource<f64> for CountingSource {
    fn site(&self) -> Site<f64> {
        self.inner.site()
    }
    fn position(&mut self, t: &UtcTime) -> Result<sun_algos::SunPosition<f64>, sun_algos::Error> {
        self.calls += 1;
        self.inner.position(t)
    }
}

/// Powered on after sunset (Kano, 2026-06-21 19:30 UTC) for 4 hours. The
/// pose to wait for sunrise in is searched by sampling the sun every 30
/// minutes over 24 hours (48 positions: some 135 ms on an ATmega2560). With
/// the boards' budget of four positions a tick the search is spread over
/// ticks: no tick computes more than the scheduler's budget and the
/// search's (plus the search's first position), where all at once one tick
/// computes the 48; both find the same pose (the axes end at the same
/// angles) with the same number of positions in all (each search runs once
/// for each instant the scheduler waits for, then is kept).
#[test]
fn a_night_after_power_on_spreads_its_waiting_pose_search_over_ticks() {
    fn night(budget: u16) -> (Vec<u32>, [f32; 2]) {
        let src = CountingSource {
            inner: source(),
            calls: 0,
        };
        let opts = ControllerOptions {
            plan_positions_per_tick: budget,
            ..ControllerOptions::default()
        };
        let sensors = MountSensors::new(MountAttitude::level(), SensorAccuracy::exact(), 3);
        let mut ctl: Controller<f64, CountingSource, MotorPlant, MountSensors, 240> =
            Controller::new(Config::default(), opts, src, plants(false), Some(sensors)).unwrap();
        let start = UtcTime::from_ymd_hms(2026, 6, 21, 19, 30, 0).unwrap();
        let mut per_tick = Vec::new();
        for s in 0..4 * 3600 {
            let now = start.add_seconds(s).unwrap();
            let before = ctl.position_source_mut().calls;
            let r = ctl.tick(&inputs(now));
            for ax in ctl.axes_mut().iter_mut() {
                ax.drive_mut().begin_tick(1.0);
            }
            assert_ne!(r.mode, Mode::Tracking, "tracking at {now}");
            per_tick.push(ctl.position_source_mut().calls - before);
        }
        let axes = ctl.axes();
        (per_tick, [axes[0].counted_deg(), axes[1].counted_deg()])
    }
    let (spread, spread_axes) = night(4);
    let (at_once, at_once_axes) = night(0);
    let max = |v: &[u32]| v.iter().copied().max().unwrap_or(0);
    let total = |v: &[u32]| v.iter().sum::<u32>();
    println!(
        "4 h from 19:30: budget 4: {} positions, at most {} a tick; all at once: {}, at most {} a tick",
        total(&spread),
        max(&spread),
        total(&at_once),
        max(&at_once)
    );
    assert!(max(&spread) <= 4 + 4 + 1, "{}", max(&spread));
    assert!(max(&at_once) >= 48, "{}", max(&at_once));
    assert_eq!(spread_axes, at_once_axes);
    // The same searches (the plans in one tick or four positions a tick
    // compute the same positions too).
    assert_eq!(total(&spread), total(&at_once));
    // Each search once: 49 positions (sunrise and 48 samples) for each of
    // the two instants the scheduler waits for (the solar day's end at
    // about 23:26 UTC, then sunrise), the plans besides.
    assert!(total(&spread) < 2 * 49 + 3 * 400, "{}", total(&spread));
}

/// The service lock ends a manual mode: after `service off` the axes home
/// and the tracker tracks, as the console's docs say, not manual with the
/// axes still.
#[test]
fn service_ends_a_manual_mode() {
    let truth = MountAttitude::level();
    let mut ctl = controller(true, AttitudeSource::Fixed(truth), truth);
    let now0 = t("2026-03-20T09:00:00Z");
    let at = |m: i64| now0.add_seconds(m * 60).unwrap();
    step(&mut ctl, &inputs(at(-1)));
    for m in 0..5 {
        step(&mut ctl, &inputs(at(m)));
    }
    ctl.manual(Some(Pose {
        gamma_deg: 10.0,
        alpha_deg: 20.0,
    }));
    assert_eq!(step(&mut ctl, &inputs(at(5))).mode, Mode::Manual);
    ctl.service(true);
    assert_eq!(step(&mut ctl, &inputs(at(6))).mode, Mode::Service);
    ctl.service(false);
    assert_eq!(ctl.hold(), Default::default());
    let modes: Vec<Mode> = (7..20)
        .map(|m| step(&mut ctl, &inputs(at(m))).mode)
        .collect();
    assert!(!modes.contains(&Mode::Manual), "{modes:?}");
    assert_eq!(modes.last(), Some(&Mode::Tracking), "{modes:?}");
}
