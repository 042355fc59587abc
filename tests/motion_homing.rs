//! Homing runs at the drive's speed whatever the controller's tick.
//!
//! The axis is homed as the firmware loop does it: the drive is a stepper
//! plant serviced every pass of the loop ([`Motion::service`], every
//! 100 ms here, as the QEMU image's plant is every 500 ms), and homing
//! steps come once a controller tick (1 s or 10 s) at that tick's
//! monotonic instant, repeated while the drive finishes a move at once
//! (as `Controller::tick` runs them).
//!
//! The expected times come from the configuration alone: the travel to the
//! switch over `max_speed_deg_s`, plus at most four ticks and one second
//! for the plant's stepping: the first step of an attempt moves one chunk
//! (no time has passed yet), the switch closes between two ticks and is
//! seen at the next, the slow back-off opens it within a tick, and the
//! final approach closes it again within one more. The old pace, one chunk
//! a tick, took the travel in chunks × ticks: ten times longer with 10 s
//! ticks than with 1 s ones.

use sim::plant::MotorPlant;
use suntracker::config::{AxisConfig, Config};
use suntracker::firmware::Motion;
use suntracker::motion::{AxisController, AxisDrive, AxisError, HomeState, HOMING_FINE_DIVISOR};

/// 1.8° full steps through 90:1: 50 counts a degree (0.02° a step), 2°/s.
const STEP_ANGLE_DEG: f64 = 1.8;
const GEAR_RATIO: f32 = 90.0;
const COUNT_DEG: f64 = 0.02;
const SPEED_DEG_S: f32 = 2.0;
/// The plant's service period (a pass of the firmware loop), ms.
const SERVICE_MS: u64 = 100;
/// Least move of a homing step (the controller's `homing_chunk_deg`).
const CHUNK_DEG: f32 = 1.0;

/// The A axis of the default configuration (soft limits −90…90°, the
/// switch at −90°) on the plant's mechanics, no backlash.
fn axis_config() -> AxisConfig {
    AxisConfig {
        counts_per_motor_rev: 200,
        microsteps: 1,
        gear_ratio: GEAR_RATIO,
        backlash_deg: 0.0,
        max_speed_deg_s: SPEED_DEG_S,
        ..Config::default().axes[1]
    }
}

/// A stepper plant of [`axis_config`] at `speed_deg_s`, `travel_deg`
/// above its switch (at the home angle).
fn plant(c: &AxisConfig, speed_deg_s: f64, travel_deg: f64) -> MotorPlant {
    let home = f64::from(c.home_deg);
    MotorPlant::stepper(
        STEP_ANGLE_DEG,
        1,
        f64::from(GEAR_RATIO),
        0.0,
        speed_deg_s,
        None,
        home,
        f64::from(c.max_deg),
        home + travel_deg,
    )
}

/// What a homing run came to.
#[derive(Debug)]
struct Run {
    /// Monotonic ms from the first step to `Done` (or to the error).
    elapsed_ms: u64,
    result: Result<(), AxisError<sim::plant::SimError>>,
    /// Most counts the drive had queued right after a tick's steps.
    max_queued_counts: i32,
}

/// Homes `ax` with controller ticks every `tick_ms`, the plant serviced
/// every [`SERVICE_MS`]; gives up after an hour.
fn home(ax: &mut AxisController<MotorPlant>, tick_ms: u64) -> Run {
    let mut max_queued_counts = 0;
    let mut now_ms = 0;
    while now_ms <= 3_600_000 {
        ax.drive_mut().service(now_ms);
        if now_ms % tick_ms == 0 {
            // As Controller::tick: steps at this instant while the drive
            // finishes their moves at once (bounded).
            for _ in 0..1000 {
                match ax.home_step(
                    CHUNK_DEG,
                    suntracker::time::monotonic::from_board_ms(now_ms),
                ) {
                    Ok(HomeState::Done) => {
                        return Run {
                            elapsed_ms: now_ms,
                            result: Ok(()),
                            max_queued_counts,
                        }
                    }
                    Ok(_) if ax.drive().pending() != 0 => break,
                    Ok(_) => {}
                    Err(e) => {
                        return Run {
                            elapsed_ms: now_ms,
                            result: Err(e),
                            max_queued_counts,
                        }
                    }
                }
            }
            max_queued_counts = max_queued_counts.max(ax.drive().pending().abs());
        }
        now_ms += SERVICE_MS;
    }
    panic!("homing neither finished nor failed in an hour");
}

/// Travel / speed + four ticks + 1 s, in ms: the bound stated above.
fn bound_ms(travel_deg: f32, speed_deg_s: f32, tick_ms: u64) -> u64 {
    (travel_deg / speed_deg_s * 1000.0) as u64 + 4 * tick_ms + 1000
}

#[test]
fn homing_time_is_travel_over_speed_with_ticks_of_1_s_and_10_s() {
    let c = axis_config();
    let travel_deg = 110.0;
    let at_speed_ms = (travel_deg / SPEED_DEG_S * 1000.0) as u64; // 55 s
    let mut times_ms = Vec::new();
    for tick_ms in [1_000, 10_000] {
        let mut ax = AxisController::new(plant(&c, f64::from(SPEED_DEG_S), 110.0), c);
        let run = home(&mut ax, tick_ms);
        assert_eq!(run.result, Ok(()), "tick {tick_ms} ms");
        assert!(
            run.elapsed_ms >= at_speed_ms
                && run.elapsed_ms <= bound_ms(travel_deg, SPEED_DEG_S, tick_ms),
            "tick {tick_ms} ms: homed in {} ms, travel/speed {at_speed_ms} ms",
            run.elapsed_ms
        );
        // The drive stops at the switch: the reference is within a count.
        let off_deg = ax.drive().output_deg() - f64::from(c.home_deg);
        assert!(
            off_deg.abs() <= COUNT_DEG + 1e-9,
            "tick {tick_ms} ms: {off_deg}°"
        );
        assert_eq!(ax.counted_deg(), c.home_deg);
        times_ms.push(run.elapsed_ms);
    }
    // One chunk a tick (the old pace) would take 110 s and 1,100 s.
    assert!(times_ms[1] - times_ms[0] <= 4 * 10_000, "{times_ms:?}");
}

#[test]
fn the_c_axis_homes_at_speed_from_190_deg() {
    // The QEMU image's C axis at power-on: 190° above its switch.
    let c = AxisConfig {
        counts_per_motor_rev: 200,
        microsteps: 1,
        gear_ratio: GEAR_RATIO,
        backlash_deg: 0.0,
        max_speed_deg_s: SPEED_DEG_S,
        ..Config::default().axes[0]
    };
    let mut ax = AxisController::new(plant(&c, f64::from(SPEED_DEG_S), 190.0), c);
    let run = home(&mut ax, 10_000);
    assert_eq!(run.result, Ok(()));
    // 95 s at 2°/s; 40 minutes at one 1° chunk a 10 s tick.
    assert!(
        run.elapsed_ms <= bound_ms(190.0, SPEED_DEG_S, 10_000),
        "{run:?}"
    );
}

#[test]
fn a_drive_slower_than_configured_is_topped_up_not_flooded() {
    // Configured 2°/s, the drive does 1°/s (5 counts a 100 ms service): homing takes the drive's time, and what is queued never
    // exceeds one tick at the configured speed plus a chunk.
    let c = axis_config();
    let tick_ms = 10_000;
    let mut ax = AxisController::new(plant(&c, 1.0, 60.0), c);
    let run = home(&mut ax, tick_ms);
    assert_eq!(run.result, Ok(()));
    assert!(
        run.elapsed_ms >= 60_000 && run.elapsed_ms <= bound_ms(60.0, 1.0, tick_ms),
        "{run:?}"
    );
    let tick_travel_deg = f64::from(SPEED_DEG_S) * tick_ms as f64 / 1000.0;
    let queue_bound = ((tick_travel_deg + f64::from(CHUNK_DEG)) / COUNT_DEG).round() as i32;
    assert!(
        run.max_queued_counts <= queue_bound,
        "{run:?} > {queue_bound}"
    );
}

#[test]
fn a_drive_that_runs_past_the_switch_homes_to_one_ticks_slow_move() {
    // Without the driver's own stop at the switch the plant runs on to its
    // hard stop 1° past it: the slow back-off covers that 1° at
    // speed / 50, and the reference is as good as one step's slow move.
    let c = axis_config();
    for tick_ms in [1_000, 10_000] {
        let mut p = plant(&c, f64::from(SPEED_DEG_S), 110.0);
        p.stops_at_switch = false;
        let mut ax = AxisController::new(p, c);
        let run = home(&mut ax, tick_ms);
        assert_eq!(run.result, Ok(()));
        let fine_speed_deg_s = SPEED_DEG_S / HOMING_FINE_DIVISOR;
        let back_off_ms = (1.0 / fine_speed_deg_s * 1000.0) as u64 + tick_ms;
        assert!(
            run.elapsed_ms <= bound_ms(110.0, SPEED_DEG_S, tick_ms) + back_off_ms,
            "tick {tick_ms} ms: {run:?}"
        );
        // A tick at the slow speed plus the slow chunk.
        let slow_move_deg = f64::from(fine_speed_deg_s) * tick_ms as f64 / 1000.0
            + f64::from(CHUNK_DEG / HOMING_FINE_DIVISOR);
        let off_deg = f64::from(c.home_deg) - ax.drive().output_deg();
        assert!(
            (0.0..=slow_move_deg + COUNT_DEG).contains(&off_deg),
            "tick {tick_ms} ms: {off_deg}° past the switch"
        );
    }
}

#[test]
fn a_switch_that_never_closes_is_reported_after_the_travel_at_speed() {
    // The seek of an attempt is bounded to max − min + 10° (+ backlash)
    // below its start: 190° at 2°/s, 95 s, then HomeNotFound (once the
    // drive has run it), whatever the tick.
    let c = axis_config();
    for tick_ms in [1_000, 10_000] {
        let mut p = plant(&c, f64::from(SPEED_DEG_S), 110.0);
        p.switch_stuck_open = true;
        let mut ax = AxisController::new(p, c);
        let start = ax.position_counts();
        let run = home(&mut ax, tick_ms);
        assert_eq!(run.result, Err(AxisError::HomeNotFound), "{run:?}");
        let seek_deg = c.max_deg - c.min_deg + 10.0;
        assert!(
            run.elapsed_ms >= (seek_deg / SPEED_DEG_S * 1000.0) as u64
                && run.elapsed_ms <= bound_ms(seek_deg, SPEED_DEG_S, tick_ms),
            "tick {tick_ms} ms: {run:?}"
        );
        let seek_counts = start - ax.position_counts();
        assert_eq!(
            seek_counts,
            (f64::from(seek_deg) / COUNT_DEG).round() as i32
        );
    }
}
