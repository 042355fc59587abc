//! The whole controller under random abuse, with its invariants checked on
//! every tick:
//!
//! - no panic (tests build with overflow checks);
//! - a gale above the stow threshold for longer than the hold ⇒ wind stow
//!   (or a safe stop, which outranks it) on that tick, whatever the wall
//!   clock did;
//! - no pose commanded beyond the soft limits, and no axis driven beyond
//!   them by tracking or homing;
//! - Tracking only with a trusted time inside the algorithm's range, a
//!   set-point, and both axes homed.
//!
//! Each tick draws: wall-clock steps (seconds to days, either way, and
//! jumps out of the algorithm's range), untrusted time, GPS loss, a
//! week-rollover flag, gusts and gales, motor stalls, encoder timeouts,
//! limit switches stuck closed or open, attitude sensor failures, and the
//! operator's commands (stow, manual poses beyond the limits, re-home,
//! clear). `cargo test --release --test controller_fuzz -- --ignored
//! --nocapture` runs the long version.

use sim::plant::MotorPlant;
use sim::rng::SplitMix64;
use sim::sensors::{MountSensors, SensorAccuracy};
use sun_algos::{Algorithm, Options, Site, UtcTime};
use suntracker::attitude::{MountAttitude, Pose};
use suntracker::config::Config;
use suntracker::controller::{AttitudeSource, Controller, ControllerOptions, TickInputs};
use suntracker::motion::{FeedbackMode, HomeState};
use suntracker::safety::Mode;
use suntracker::sun::AlgorithmSource;

/// The controller under test; `N` = 361 (a table for any day), or 0 (no
/// table: the scheduler's real-time mode of the 2 KB boards).
type Ctl<const N: usize> = Controller<f64, AlgorithmSource<f64>, MotorPlant, MountSensors, N>;

#[derive(Debug, Default)]
struct Figures {
    ticks: u64,
    clock_steps: u64,
    gale_ticks: u64,
    tracking_ticks: u64,
    safe_stops: u64,
}

fn new_controller<const N: usize>(rng: &mut SplitMix64, config: &Config) -> Ctl<N> {
    let source = AlgorithmSource {
        algorithm: Algorithm::Psa2020,
        site: Site::new(rng.uniform(-66.0, 66.0), rng.uniform(-180.0, 180.0)).unwrap(),
        options: Options::default(),
    };
    let c = config.axes[0];
    let a = config.axes[1];
    let plant = |min: f32, max: f32, start: f64| {
        MotorPlant::stepper(
            1.8,
            16,
            100.0,
            0.2,
            2.0,
            Some(1 << 16),
            f64::from(min),
            f64::from(max),
            start,
        )
    };
    let plants = [
        plant(c.min_deg, c.max_deg, rng.uniform(-170.0, 170.0)),
        plant(a.min_deg, a.max_deg, rng.uniform(-80.0, 80.0)),
    ];
    let options = ControllerOptions {
        feedback: if rng.next_f64() < 0.5 {
            FeedbackMode::ClosedLoop
        } else {
            FeedbackMode::OpenLoop
        },
        attitude: if rng.next_f64() < 0.5 {
            AttitudeSource::Sensors
        } else {
            AttitudeSource::Fixed(MountAttitude::level())
        },
        ..ControllerOptions::default()
    };
    let truth = MountAttitude {
        alpha0_deg: rng.uniform(-5.0, 5.0),
        beta0_deg: rng.uniform(-5.0, 5.0),
        gamma0_deg: rng.uniform(-180.0, 180.0),
    };
    let sensors = MountSensors::new(truth, SensorAccuracy::exact(), rng.next_u64());
    Controller::new(*config, options, source, plants, Some(sensors)).unwrap()
}

/// Turns a rare condition on with probability `p_on`, off with 0.02.
fn flip(rng: &mut SplitMix64, on: &mut bool, p_on: f64) {
    let p = if *on { 0.02 } else { p_on };
    if rng.next_f64() < p {
        *on = !*on;
    }
}

/// One run of `ticks` ticks; panics (fails) on a broken invariant.
fn run<const N: usize>(seed: u64, ticks: u32, fig: &mut Figures) {
    let mut rng = SplitMix64::new(seed);
    let config = Config::default();
    let mut ctl = new_controller::<N>(&mut rng, &config);
    let (lo_year, hi_year) = Algorithm::Psa2020.validity_years();
    let threshold_hz = f64::from(config.wind.threshold_hz);
    let hold_ms = u64::from(config.wind.hold_s) * 1000;
    // Wall clock and monotonic clock.
    let mut now: UtcTime = "2026-06-01T00:00:00Z".parse().unwrap();
    let mut now_ms: u64 = 0;
    let mut gale_since_ms: Option<u64> = None;
    let mut time_invalid = false;
    let mut gps_lost = false;
    let mut rollover = false;
    for tick in 0..ticks {
        fig.ticks += 1;
        // The monotonic clock advances 1 s to 5 min per tick.
        let dt_ms = match rng.next_u64() % 4 {
            0 => 1_000,
            1 => 10_000,
            2 => 60_000,
            _ => 1_000 + rng.next_u64() % 300_000,
        };
        now_ms += dt_ms;
        // The wall clock follows, and now and then steps.
        let mut step_s = (dt_ms / 1000) as i64;
        let r = rng.next_f64();
        if r < 0.01 {
            step_s += match rng.next_u64() % 6 {
                0 => -86_400,
                1 => 86_400,
                2 => -3_600,
                3 => 7 * 86_400,
                4 => 30 * 365 * 86_400, // past the algorithm's range
                _ => -((rng.next_u64() % 100_000) as i64),
            };
            fig.clock_steps += 1;
        }
        now = match now.add_seconds(step_s) {
            Ok(t) => t,
            Err(_) => "2026-06-01T00:00:00Z".parse().unwrap(),
        };
        // Back into a sane epoch now and then, so most ticks can track.
        if !(2020..=2050).contains(&now.year()) && rng.next_f64() < 0.05 {
            now = "2027-03-01T06:00:00Z".parse().unwrap();
        }
        // Conditions that come rarely and last a while.
        flip(&mut rng, &mut time_invalid, 0.003);
        flip(&mut rng, &mut gps_lost, 0.005);
        flip(&mut rng, &mut rollover, 0.002);
        // Wind over the interval: calm, gusts, or a gale.
        let hz = match rng.next_u64() % 40 {
            0 => rng.uniform(26.0, 80.0),
            1 | 2 => rng.uniform(0.0, 40.0),
            _ => rng.uniform(0.0, 20.0),
        };
        let pulses = (hz * dt_ms as f64 / 1000.0) as u32;
        let rate = f64::from(pulses) * 1000.0 / dt_ms as f64;
        let windy = rate > threshold_hz;
        if windy {
            gale_since_ms.get_or_insert(now_ms - dt_ms);
        } else {
            gale_since_ms = None;
        }
        // Plant and sensor faults: rare, and each lasts a few ticks to a
        // few hundred.
        for i in 0..2 {
            let p = ctl.axes_mut()[i].drive_mut();
            flip(&mut rng, &mut p.stalled, 0.002);
            flip(&mut rng, &mut p.encoder_timeout, 0.002);
            flip(&mut rng, &mut p.switch_stuck, 0.001);
            flip(&mut rng, &mut p.switch_stuck_open, 0.001);
            p.begin_tick(dt_ms as f64 / 1000.0);
        }
        if let Some(s) = ctl.sensors_mut() {
            flip(&mut rng, &mut s.failing, 0.002);
        }
        // The operator.
        match rng.next_u64() % 300 {
            0 => ctl.command_stow(true),
            1 => ctl.command_stow(false),
            2 => ctl.manual(Some(Pose {
                gamma_deg: rng.uniform(-400.0, 400.0),
                alpha_deg: rng.uniform(-200.0, 200.0),
            })),
            3 => ctl.manual(None),
            4 => ctl.rehome(),
            5..=9 => ctl.reset_faults(),
            _ => {}
        }
        let report = ctl.tick(&TickInputs {
            now_ms: suntracker::time::monotonic::from_board_ms(now_ms),
            now,
            time_valid: !time_invalid,
            gps_fix: !gps_lost,
            gps_time_implausible: rollover,
            gps_time_unstable: false,
            gps_position_unstable: false,
            wind_pulses: pulses,
            wind_interval_ms: dt_ms as u32,
            stow_inputs: Default::default(),
        });
        let ctx = || format!("seed {seed} tick {tick} at {now} ({now_ms} ms): {report:?}");
        // Gale held ⇒ stowed (or stopped) on this very tick.
        if let Some(since) = gale_since_ms {
            if now_ms - since >= hold_ms {
                fig.gale_ticks += 1;
                assert!(
                    matches!(report.mode, Mode::WindStow | Mode::SafeStop),
                    "gale held {} ms: {}",
                    now_ms - since,
                    ctx()
                );
            }
        }
        // Commanded poses inside the soft limits.
        if let Some(p) = report.target {
            let (c, a) = (config.axes[0], config.axes[1]);
            assert!(
                p.gamma_deg >= f64::from(c.min_deg) - 1e-9
                    && p.gamma_deg <= f64::from(c.max_deg) + 1e-9
                    && p.alpha_deg >= f64::from(a.min_deg) - 1e-9
                    && p.alpha_deg <= f64::from(a.max_deg) + 1e-9,
                "target beyond the soft limits: {}",
                ctx()
            );
        }
        // Tracking only with a trusted in-range time, a set-point and homed
        // axes.
        if report.mode == Mode::Tracking {
            fig.tracking_ticks += 1;
            assert!(!time_invalid, "tracking on untrusted time: {}", ctx());
            assert!(
                (lo_year..=hi_year).contains(&now.year()),
                "tracking out of range: {}",
                ctx()
            );
            assert!(report.set_point.is_some(), "{}", ctx());
            assert!(
                ctl.axes().iter().all(|a| a.home_state() == HomeState::Done),
                "tracking while unhomed: {}",
                ctx()
            );
        }
        if report.mode == Mode::SafeStop {
            fig.safe_stops += 1;
        }
    }
}

#[test]
fn controller_invariants_hold_under_random_faults() {
    let mut fig = Figures::default();
    for seed in 1..=8 {
        run::<361>(seed, 3_000, &mut fig);
    }
    println!("{fig:?}");
    assert!(fig.tracking_ticks > 1_000, "{fig:?}");
    assert!(fig.gale_ticks > 100, "{fig:?}");
}

#[test]
#[ignore = "long: 40 runs of 20,000 ticks (release: a few seconds)"]
fn controller_invariants_hold_under_random_faults_long() {
    let mut fig = Figures::default();
    for seed in 1..=40 {
        run::<361>(1000 + seed, 20_000, &mut fig);
    }
    println!("{fig:?}");
}

#[test]
fn controller_invariants_hold_under_random_faults_in_real_time_mode() {
    let mut fig = Figures::default();
    for seed in 1..=8 {
        run::<0>(seed, 3_000, &mut fig);
    }
    println!("real-time {fig:?}");
    assert!(fig.tracking_ticks > 1_000, "{fig:?}");
    assert!(fig.gale_ticks > 100, "{fig:?}");
}

#[test]
#[ignore = "long: 40 runs of 20,000 ticks, real-time mode"]
fn controller_invariants_hold_under_random_faults_in_real_time_mode_long() {
    let mut fig = Figures::default();
    for seed in 1..=40 {
        run::<0>(1000 + seed, 20_000, &mut fig);
    }
    println!("real-time {fig:?}");
}
