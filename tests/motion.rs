//! Axis control over the simulated plants.

use sim::plant::MotorPlant;
use suntracker::config::{AxisConfig, Config};
use suntracker::motion::{AxisController, AxisDrive, FeedbackMode, HomeState};

fn cfg() -> AxisConfig {
    // 1.8° stepper, 16 microsteps, 100:1 → 200·16·100/360 = 888.9 counts/°;
    // the plants below have no backlash unless a test says so.
    AxisConfig {
        backlash_deg: 0.0,
        ..Config::default().axes[1]
    }
}

fn home(ax: &mut AxisController<MotorPlant>) {
    for _ in 0..1_000_000 {
        ax.drive_mut().begin_tick(1.0);
        if ax.home_step(1.0, 0).unwrap() == HomeState::Done {
            return;
        }
    }
    panic!("homing did not finish");
}

#[test]
fn counts_per_degree_from_configuration() {
    assert!((cfg().counts_per_deg() - 200.0 * 16.0 * 100.0 / 360.0).abs() < 1e-3);
}

#[test]
fn homing_finds_the_switch_and_soft_limits_clamp() {
    let c = cfg();
    // The switch sits at the home angle −90°; the axis starts at +30°.
    let plant = MotorPlant::stepper(1.8, 16, 100.0, 0.0, 5.0, None, -90.0, 90.0, 30.0);
    let mut ax = AxisController::new(plant, c);
    assert!(ax.update(10.0, FeedbackMode::OpenLoop, None).is_err());
    home(&mut ax);
    // Within the fine approach step (1°/50) of the switch.
    assert!((ax.drive().output_deg() - -90.0).abs() <= 0.02 + 1e-9);
    ax.drive_mut().begin_tick(1000.0);
    let r = ax.update(45.0, FeedbackMode::OpenLoop, None).unwrap();
    assert!(!r.clamped);
    assert!((ax.drive().output_deg() - 45.0).abs() < 0.03);
    // Beyond the soft limit: clamped to +90°.
    ax.drive_mut().begin_tick(1000.0);
    let r = ax.update(120.0, FeedbackMode::OpenLoop, None).unwrap();
    assert!(r.clamped);
    assert_eq!(r.target_deg, 90.0);
    assert!((ax.drive().output_deg() - 90.0).abs() < 0.03);
    // NaN targets are errors, not motion.
    assert!(ax.update(f32::NAN, FeedbackMode::OpenLoop, None).is_err());
}

#[test]
fn move_to_clamps_and_takes_up_backlash_as_update_does() {
    let mut c = cfg();
    c.backlash_deg = 0.5;
    // A plant with 0.5° of slack, switch at −90°, starting at +30°.
    let plant = MotorPlant::stepper(1.8, 16, 100.0, 0.5, 5.0, None, -90.0, 90.0, 30.0);
    let mut ax = AxisController::new(plant, c);
    assert!(ax.move_to(10.0).is_err(), "moved before homing");
    home(&mut ax);
    // The plant's output shaft is the reference: each move lands within
    // the fine approach's 0.02° plus a count, reversals included.
    for target in [45.0, 20.0, 60.0, -30.0] {
        ax.drive_mut().begin_tick(1000.0);
        ax.move_to(target).unwrap();
        let out = ax.drive().output_deg();
        assert!((out - f64::from(target)).abs() < 0.03, "{target}: {out}");
        assert!((ax.counted_deg() - target).abs() < 0.01, "{target}");
    }
    // Beyond the soft limit: held at +90°.
    ax.drive_mut().begin_tick(1000.0);
    ax.move_to(120.0).unwrap();
    assert!((ax.drive().output_deg() - 90.0).abs() < 0.03);
    // NaN is an error, and no motion.
    let before = ax.position_counts();
    assert!(ax.move_to(f32::NAN).is_err());
    assert_eq!(ax.position_counts(), before);
}

#[test]
fn stuck_switch_is_backed_off_or_reported() {
    let plant = MotorPlant::stepper(1.8, 16, 100.0, 0.0, 5.0, None, -90.0, 90.0, 0.0);
    let mut ax = AxisController::new(plant, cfg());
    ax.drive_mut().switch_stuck = true;
    let mut err = false;
    for _ in 0..10_000 {
        ax.drive_mut().begin_tick(1.0);
        match ax.home_step(1.0, 0) {
            Ok(HomeState::Done) => panic!("homed on a stuck switch"),
            Ok(_) => {}
            Err(_) => {
                err = true;
                break;
            }
        }
    }
    assert!(err);
}

#[test]
fn backlash_compensation_on_reversal() {
    let mut c = cfg();
    c.backlash_deg = 0.5;
    let run = |c: AxisConfig| {
        let plant = MotorPlant::stepper(1.8, 16, 100.0, 0.5, 5.0, None, -90.0, 90.0, 0.0);
        let mut ax = AxisController::new(plant, c);
        home(&mut ax);
        let mut worst = 0.0f64;
        for target in [10.0, 20.0, 5.0, 15.0, -30.0, 40.0, 39.0] {
            ax.drive_mut().begin_tick(1000.0);
            ax.update(target, FeedbackMode::OpenLoop, None).unwrap();
            worst = worst.max((ax.drive().output_deg() - f64::from(target)).abs());
        }
        worst
    };
    let with = run(c);
    c.backlash_deg = 0.0;
    let without = run(c);
    // Uncompensated, a reversal leaves the whole 0.5° of slack.
    assert!(without > 0.45, "{without}");
    assert!(with < 0.03, "{with}");
}

#[test]
fn closed_loop_corrects_lost_steps_pseudo_closed_only_reports() {
    for mode in [FeedbackMode::ClosedLoop, FeedbackMode::PseudoClosed] {
        let plant = MotorPlant::stepper(1.8, 16, 100.0, 0.0, 5.0, Some(1 << 16), -90.0, 90.0, 0.0);
        let mut ax = AxisController::new(plant, cfg());
        home(&mut ax);
        ax.drive_mut().begin_tick(1000.0);
        ax.update(20.0, mode, None).unwrap();
        // The motor slips 2° (lost steps).
        ax.drive_mut().slip(-2.0);
        let fb = ax.drive_mut().encoder_deg().unwrap().unwrap();
        ax.drive_mut().begin_tick(1000.0);
        let r = ax.update(20.0, mode, Some(fb)).unwrap();
        let dev = r.deviation_deg.unwrap();
        assert!((dev + 2.0).abs() < 0.03, "{dev}");
        let out = ax.drive().output_deg();
        match mode {
            FeedbackMode::ClosedLoop => assert!((out - 20.0).abs() < 0.03, "{out}"),
            _ => assert!((out - 18.0).abs() < 0.03, "{out}"),
        }
        // Inside the deadband nothing moves.
        let fb = ax.drive_mut().encoder_deg().unwrap().unwrap();
        ax.drive_mut().begin_tick(1000.0);
        let r = ax
            .update(fb + 0.01, FeedbackMode::ClosedLoop, Some(fb))
            .unwrap();
        assert_eq!(r.commanded_counts, 0);
    }
}

#[test]
fn servo_lands_on_encoder_counts_and_speed_limits_a_tick() {
    let mut c = cfg();
    c.counts_per_motor_rev = 4096;
    c.microsteps = 1;
    c.gear_ratio = 1.0;
    c.backlash_deg = 0.0;
    let plant = MotorPlant::servo(4096, 3.0, -90.0, 90.0, 0.0);
    let mut ax = AxisController::new(plant, c);
    home(&mut ax);
    // 3°/s for 10 s: at most 30° this tick.
    ax.drive_mut().begin_tick(10.0);
    ax.update(0.0, FeedbackMode::OpenLoop, None).unwrap();
    let moved = ax.drive().output_deg() - -90.0;
    assert!((moved - 30.0).abs() < 0.2, "{moved}");
    ax.drive_mut().begin_tick(100.0);
    let out = ax.drive().output_deg();
    // 360/4096 = 0.088° resolution.
    assert!(out.abs() < 0.09, "{out}");
}

// ---------------------------------------------------------------------------
// Homing bounds and overflow-free arithmetic, over a mock drive in counts.

use sim::rng::SplitMix64;
use suntracker::config::ranges;
use suntracker::motion::{
    AxisError, FEEDBACK_MARGIN_DEG, HOMING_BACKOFF_MAX_DEG, HOMING_SEEK_EXTRA_DEG,
    HOMING_SEEK_MARGIN_DEG,
};

#[derive(Debug, Clone, Copy, PartialEq)]
enum Switch {
    /// Closed at and below the home angle.
    Normal,
    StuckClosed,
    StuckOpen,
}

/// A drive in motor counts: `pos` is the true position, 0 at the switch
/// edge (the home angle); hard stops hold the axis; `speed` counts run per
/// `tick`.
#[derive(Debug)]
struct Mock {
    pos: i64,
    pending: i64,
    speed: i64,
    switch: Switch,
    lo_stop: i64,
    hi_stop: i64,
    up_counts: u64,
    down_counts: u64,
    /// Highest and lowest counts commanded so far (sum of all moves).
    net: i64,
    net_hi: i64,
    net_lo: i64,
}

impl Mock {
    fn new(pos: i64, switch: Switch, lo_stop: i64, hi_stop: i64) -> Self {
        Mock {
            pos,
            pending: 0,
            speed: i64::MAX,
            switch,
            lo_stop,
            hi_stop,
            up_counts: 0,
            down_counts: 0,
            net: 0,
            net_hi: 0,
            net_lo: 0,
        }
    }
    fn tick(&mut self) {
        let n = self.pending.clamp(-self.speed, self.speed);
        self.pending -= n;
        self.pos = (self.pos + n).clamp(self.lo_stop, self.hi_stop);
    }
    fn reset_net(&mut self) {
        self.net = 0;
        self.net_hi = 0;
        self.net_lo = 0;
    }
}

impl AxisDrive for Mock {
    type Error = ();
    fn move_counts(&mut self, counts: i32) -> Result<(), ()> {
        let c = i64::from(counts);
        self.pending += c;
        if c > 0 {
            self.up_counts += c as u64;
        } else {
            self.down_counts += c.unsigned_abs();
        }
        self.net += c;
        self.net_hi = self.net_hi.max(self.net);
        self.net_lo = self.net_lo.min(self.net);
        Ok(())
    }
    fn pending(&self) -> i32 {
        i32::try_from(self.pending).unwrap()
    }
    fn stop(&mut self) -> Result<(), ()> {
        self.pending = 0;
        Ok(())
    }
    fn at_limit(&mut self) -> Result<bool, ()> {
        Ok(match self.switch {
            Switch::Normal => self.pos <= 0,
            Switch::StuckClosed => true,
            Switch::StuckOpen => false,
        })
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, ()> {
        Ok(None)
    }
}

/// Counts of `deg`, to the nearest count as the axis computes them.
fn counts(c: &AxisConfig, deg: f32) -> i64 {
    (deg * c.counts_per_deg()).round() as i64
}

/// A mock for axis `c` with the true angle `start_deg`; hard stops 1° past
/// the soft limits (and the switch).
fn mock(c: &AxisConfig, start_deg: f32, switch: Switch) -> Mock {
    let lo = counts(c, c.min_deg.min(c.home_deg) - 1.0 - c.home_deg);
    let hi = counts(c, c.max_deg + 1.0 - c.home_deg);
    let pos = counts(c, start_deg - c.home_deg).clamp(lo, hi);
    Mock::new(pos, switch, lo, hi)
}

/// Runs homing attempts until `Done` or `attempts` errors; returns
/// `Ok(())` when homed. Each call is followed by a tick of the drive.
fn home_attempts(ax: &mut AxisController<Mock>, chunk_deg: f32, attempts: u32) -> Result<(), u32> {
    let mut errors = 0;
    for _ in 0..10_000_000u32 {
        match ax.home_step(chunk_deg, 0) {
            Ok(HomeState::Done) => return Ok(()),
            Ok(_) => ax.drive_mut().tick(),
            Err(AxisError::HomeNotFound) => {
                errors += 1;
                if errors == attempts {
                    return Err(errors);
                }
            }
            Err(e) => panic!("{e:?}"),
        }
    }
    panic!("homing neither finished nor gave up");
}

#[test]
fn stuck_closed_switch_backs_off_at_most_15_degrees_over_all_attempts() {
    // Formerly each attempt backed off another 15°, without end.
    let c = Config::default().axes[0];
    let backoff = counts(&c, HOMING_BACKOFF_MAX_DEG) as u64;
    for chunk_deg in [0.3, 1.0, 4.0, 40.0] {
        // Power-on: no reference.
        let mut ax = AxisController::new(mock(&c, 0.0, Switch::StuckClosed), c);
        assert_eq!(home_attempts(&mut ax, chunk_deg, 50), Err(50));
        let d = ax.drive();
        assert_eq!(d.down_counts, 0);
        assert!(d.up_counts <= backoff, "{chunk_deg}: {}", d.up_counts);
        assert!(d.up_counts + 1 >= backoff - 1, "backs off the whole 15°");
    }
}

#[test]
fn stuck_closed_switch_after_a_reference_stays_below_max() {
    // The C axis (−180…180°, home −180°) tracking at 170° when its switch
    // sticks closed; it is unhomed and homing retried again and again.
    // Formerly it ended at its hard stop (181°).
    let c = AxisConfig {
        backlash_deg: 0.0,
        ..Config::default().axes[0]
    };
    let mut ax = AxisController::new(mock(&c, -100.0, Switch::Normal), c);
    home_attempts(&mut ax, 1.0, 1).unwrap();
    ax.update(170.0, FeedbackMode::OpenLoop, None).unwrap();
    ax.drive_mut().tick();
    ax.drive_mut().switch = Switch::StuckClosed;
    ax.unhome();
    assert_eq!(home_attempts(&mut ax, 1.0, 20), Err(20));
    assert!(ax.counted_deg() <= c.max_deg + 1e-3, "{}", ax.counted_deg());
    let true_deg = c.home_deg + ax.drive().pos as f32 / c.counts_per_deg();
    assert!(true_deg <= c.max_deg + 1e-3, "{true_deg}");
    // 10° of room to max, not 15°.
    assert!((ax.counted_deg() - 180.0).abs() < 1e-3);
}

#[test]
fn an_axis_still_on_its_switch_after_a_move_away_is_at_home_not_above_it() {
    // A drive that starts slowly (a DC motor ramping up) still closes its
    // switch after a move of 90° away from it is commanded: the axis is
    // where the drive is, not where the count already says. The
    // controller raises `limit_switch` for a switch closed more than 2°
    // above home, so by the count alone it raised one on every such move.
    let c = AxisConfig {
        backlash_deg: 0.0,
        ..Config::default().axes[0]
    };
    let mut ax = AxisController::new(mock(&c, -100.0, Switch::Normal), c);
    home_attempts(&mut ax, 1.0, 1).unwrap();
    ax.drive_mut().speed = counts(&c, 1.0);
    ax.move_to(c.home_deg + 90.0).unwrap();
    assert!(
        ax.drive_mut().at_limit().unwrap(),
        "the drive has not moved yet"
    );
    assert!(ax.above_home_deg().abs() < 0.1, "{}", ax.above_home_deg());
    ax.drive_mut().tick();
    assert!(
        (ax.above_home_deg() - 1.0).abs() < 0.1,
        "{}",
        ax.above_home_deg()
    );
    while ax.drive().pending() != 0 {
        ax.drive_mut().tick();
    }
    assert!(
        (ax.above_home_deg() - 90.0).abs() < 0.1,
        "{}",
        ax.above_home_deg()
    );
}

#[test]
fn stuck_closed_then_repaired_switch_still_homes() {
    let c = Config::default().axes[1];
    let mut ax = AxisController::new(mock(&c, 0.0, Switch::StuckClosed), c);
    assert_eq!(home_attempts(&mut ax, 1.0, 5), Err(5));
    ax.drive_mut().switch = Switch::Normal;
    home_attempts(&mut ax, 1.0, 1).unwrap();
    // Within a fine step (1°/50) of the switch edge.
    let d = ax.drive();
    assert!(d.pos <= 0 && d.pos > -counts(&c, 0.021), "{}", d.pos);
}

#[test]
fn stuck_open_switch_seek_stops_after_the_documented_travel() {
    let c = Config::default().axes[1];
    let travel = counts(
        &c,
        c.max_deg - c.min_deg + HOMING_SEEK_EXTRA_DEG + c.backlash_deg,
    );
    // No reference: one travel per attempt.
    let mut ax = AxisController::new(mock(&c, 50.0, Switch::StuckOpen), c);
    for _ in 0..5 {
        let before = ax.drive().down_counts;
        assert_eq!(home_attempts(&mut ax, 1.0, 1), Err(1));
        let seek = (ax.drive().down_counts - before) as i64;
        assert!(seek <= travel && seek >= travel - 1, "{seek} vs {travel}");
    }
    assert_eq!(ax.drive().up_counts, 0);

    // With a reference: the attempt stops at home − margin − backlash.
    let mut ax = AxisController::new(mock(&c, 50.0, Switch::Normal), c);
    home_attempts(&mut ax, 1.0, 1).unwrap();
    ax.update(60.0, FeedbackMode::OpenLoop, None).unwrap();
    ax.drive_mut().tick();
    ax.drive_mut().switch = Switch::StuckOpen;
    ax.unhome();
    ax.drive_mut().reset_net();
    assert_eq!(home_attempts(&mut ax, 1.0, 1), Err(1));
    let floor_deg = c.min_deg.min(c.home_deg) - HOMING_SEEK_MARGIN_DEG - c.backlash_deg;
    assert!(ax.counted_deg() >= floor_deg - 1e-3, "{}", ax.counted_deg());
    assert!((ax.counted_deg() - floor_deg).abs() < 1e-3);
    let d = ax.drive();
    assert!(d.net_lo >= counts(&c, floor_deg - 60.0) - 1, "{}", d.net_lo);
    // Reaching the floor without the switch means the count was no
    // reference (steps lost): it is dropped, and the next attempt runs the
    // whole documented travel rather than stopping at the same floor for
    // ever.
    assert!(!ax.has_had_reference());
    let before = ax.drive().down_counts;
    assert_eq!(home_attempts(&mut ax, 1.0, 1), Err(1));
    let seek = (ax.drive().down_counts - before) as i64;
    assert!(seek <= travel && seek >= travel - 1, "{seek} vs {travel}");
}

// ---------------------------------------------------------------------------
// Property test over the whole valid ranges.

fn pick_u32(r: &mut SplitMix64, (lo, hi): (u32, u32)) -> u32 {
    match r.next_u64() % 8 {
        0 => lo,
        1 => hi,
        _ => lo + (r.next_u64() % u64::from(hi - lo + 1)) as u32,
    }
}

fn pick_f32(r: &mut SplitMix64, (lo, hi): (f32, f32)) -> f32 {
    match r.next_u64() % 8 {
        0 => lo,
        1 => hi,
        _ => r.uniform(f64::from(lo), f64::from(hi)) as f32,
    }
}

/// Log-uniform in `lo..=hi` (both > 0), with the ends often.
fn pick_log(r: &mut SplitMix64, (lo, hi): (f32, f32)) -> f32 {
    match r.next_u64() % 8 {
        0 => lo,
        1 => hi,
        _ => libm::exp(r.uniform(libm::log(f64::from(lo)), libm::log(f64::from(hi)))) as f32,
    }
}

/// A random axis configuration that validates, the extremes of every range
/// included.
fn random_axis(r: &mut SplitMix64) -> AxisConfig {
    loop {
        let mut a = Config::default().axes[0];
        match r.next_u64() % 6 {
            // Counts per degree at the ends of their range: 1 and 10^6.
            0 => {
                a.counts_per_motor_rev = 360;
                a.microsteps = 1;
                a.gear_ratio = 1.0;
            }
            1 => {
                a.counts_per_motor_rev = 36_000;
                a.microsteps = 1;
                a.gear_ratio = 10_000.0;
            }
            _ => {
                a.counts_per_motor_rev = match r.next_u64() % 3 {
                    0 => pick_u32(r, ranges::COUNTS_PER_MOTOR_REV),
                    1 => [200, 400, 4096, 1 << 14, 1 << 20][(r.next_u64() % 5) as usize],
                    _ => pick_log(r, (1.0, 16_777_216.0)) as u32,
                };
                let (m_lo, m_hi) = ranges::MICROSTEPS;
                a.microsteps = pick_u32(r, (u32::from(m_lo), u32::from(m_hi))) as u16;
                a.gear_ratio = pick_log(r, ranges::GEAR_RATIO);
            }
        }
        a.min_deg = pick_f32(r, ranges::LIMIT_DEG);
        a.max_deg = pick_f32(r, (a.min_deg, ranges::LIMIT_DEG.1));
        let (b, t) = ranges::HOME_ABOVE_MIN_DEG;
        a.home_deg = pick_f32(r, (a.min_deg + b, (a.min_deg + t).min(a.max_deg)));
        a.backlash_deg = pick_f32(r, ranges::BACKLASH_DEG);
        a.max_speed_deg_s = pick_f32(r, ranges::MAX_SPEED_DEG_S);
        a.deadband_deg = pick_f32(r, ranges::DEADBAND_DEG);
        let mut cfg = Config::default();
        cfg.safety.max_deviation_deg = ranges::MAX_DEVIATION_DEG.1;
        cfg.axes = [a, a];
        if cfg.validate().is_ok() {
            return a;
        }
    }
}

fn random_angle(r: &mut SplitMix64, c: &AxisConfig) -> f32 {
    const WILD: [f32; 10] = [
        1e30,
        -1e30,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MAX,
        f32::MIN,
        f32::MIN_POSITIVE,
        720.0,
        -720.0,
    ];
    match r.next_u64() % 6 {
        0 => WILD[(r.next_u64() % 10) as usize],
        1 => [c.min_deg, c.max_deg, c.home_deg][(r.next_u64() % 3) as usize],
        _ => r.uniform(f64::from(c.min_deg) - 100.0, f64::from(c.max_deg) + 100.0) as f32,
    }
}

struct Figures {
    configs: u32,
    homing_steps: u64,
    homed: u32,
    updates: u64,
}

/// Homing over `d`, checking the bounds after every step (steps at
/// random instants); returns whether it homed.
fn checked_homing(
    r: &mut SplitMix64,
    c: &AxisConfig,
    ax: &mut AxisController<Mock>,
    f: &mut Figures,
) -> bool {
    let cpd = c.counts_per_deg();
    let eps_deg = 2.0 / cpd + 1e-3;
    let floor_deg = c.min_deg.min(c.home_deg) - HOMING_SEEK_MARGIN_DEG - c.backlash_deg;
    let travel = counts(
        c,
        c.max_deg - c.min_deg + HOMING_SEEK_EXTRA_DEG + c.backlash_deg,
    );
    let chunk_deg = match r.next_u64() % 8 {
        0 => 1e30,
        1 => 0.2,
        _ => r.uniform(0.5, 20.0) as f32,
    };
    ax.drive_mut().speed = (r.uniform(0.2, 30.0) * f64::from(cpd)) as i64 + 1;
    let attempts = 1 + (r.next_u64() % 4) as u32;
    let referenced = ax.has_had_reference();
    let up0 = ax.drive().up_counts;
    let mut errors = 0;
    // The last tracking move completes first.
    let speed = ax.drive().speed;
    ax.drive_mut().speed = i64::MAX;
    ax.drive_mut().tick();
    ax.drive_mut().speed = speed;
    // An attempt without a reference counts from where it starts.
    let mut attempt_start = if referenced { ax.position_counts() } else { 0 };
    // Homing moves never take the count above max_deg (or where it was, if
    // higher) nor below the floor (or where it was, if lower).
    let start_deg = ax.counted_deg();
    let (lo_deg, hi_deg) = (start_deg.min(floor_deg), start_deg.max(c.max_deg));
    // Steps at instants 0 to 40 s apart on the monotonic clock: the moves
    // cover the speed × the time since the previous step, or a chunk.
    let mut now_ms = r.next_u64() % 1_000_000;
    for _ in 0..2_000_000u32 {
        let res = ax.home_step(
            chunk_deg,
            suntracker::time::monotonic::from_board_ms(now_ms),
        );
        now_ms += [0, 1_000, 10_000, 40_000][(r.next_u64() % 4) as usize];
        f.homing_steps += 1;
        let after = ax.counted_deg();
        // Bounded by the reference while the axis still has one (a seek
        // that reaches the floor without the switch drops it).
        if referenced && ax.has_had_reference() {
            assert!(after <= hi_deg + eps_deg, "{c:?}: {start_deg} → {after}");
            assert!(after >= lo_deg - eps_deg, "{c:?}: {start_deg} → {after}");
        }
        let d = ax.drive();
        if d.switch == Switch::StuckClosed {
            assert!(d.up_counts - up0 <= counts(c, HOMING_BACKOFF_MAX_DEG) as u64 + 1);
        }
        if res != Ok(HomeState::Done) {
            // (Done re-zeroes the count at the switch: no motion.)
            let seek = attempt_start - ax.position_counts();
            assert!(
                i64::from(seek) <= travel + 1,
                "{c:?}: seek {seek} > {travel}"
            );
        }
        match res {
            Ok(HomeState::Done) => return true,
            Ok(_) => ax.drive_mut().tick(),
            Err(AxisError::HomeNotFound) => {
                errors += 1;
                attempt_start = if ax.has_had_reference() {
                    ax.position_counts()
                } else {
                    0
                };
                if errors == attempts {
                    return false;
                }
            }
            Err(e) => panic!("{e:?}"),
        }
    }
    panic!("{c:?}: homing neither finished nor gave up");
}

#[test]
fn property_no_overflow_and_positions_within_limits_over_valid_ranges() {
    let mut r = SplitMix64::new(0x5eed_a715);
    let mut f = Figures {
        configs: 0,
        homing_steps: 0,
        homed: 0,
        updates: 0,
    };
    let cases = 4000;
    for _ in 0..cases {
        let c = random_axis(&mut r);
        f.configs += 1;
        let cpd = c.counts_per_deg();
        let switch = match r.next_u64() % 5 {
            0 => Switch::StuckClosed,
            1 => Switch::StuckOpen,
            _ => Switch::Normal,
        };
        let start = r.uniform(f64::from(c.min_deg) - 1.0, f64::from(c.max_deg) + 1.0) as f32;
        let mut ax = AxisController::new(mock(&c, start, switch), c);
        for round in 0..3 {
            if !checked_homing(&mut r, &c, &mut ax, &mut f) {
                // Repair the switch now and then: it homes afterwards.
                ax.drive_mut().switch = Switch::Normal;
                continue;
            }
            f.homed += 1;
            // Homed at the switch edge, within a fine step.
            assert_eq!(ax.position_counts(), 0);
            for _ in 0..40 {
                let target = random_angle(&mut r, &c);
                let mode = [
                    FeedbackMode::OpenLoop,
                    FeedbackMode::PseudoClosed,
                    FeedbackMode::ClosedLoop,
                ][(r.next_u64() % 3) as usize];
                let fb = match r.next_u64() % 3 {
                    0 => None,
                    _ => Some(random_angle(&mut r, &c)),
                };
                let res = ax.update(target, mode, fb);
                f.updates += 1;
                ax.drive_mut().tick();
                let counted = ax.counted_deg();
                let eps = 1.0 / cpd + 1e-3;
                match res {
                    Ok(rep) => {
                        assert!(target.is_finite() && fb.is_none_or(f32::is_finite));
                        assert!(rep.target_deg >= c.min_deg && rep.target_deg <= c.max_deg);
                        assert_eq!(rep.clamped, rep.target_deg != target);
                        let max_move = counts(&c, ranges::MAX_MOVE_DEG);
                        assert!(i64::from(rep.commanded_counts).abs() <= max_move);
                        assert!(
                            counted >= c.min_deg - FEEDBACK_MARGIN_DEG - eps
                                && counted <= c.max_deg + FEEDBACK_MARGIN_DEG + eps,
                            "{c:?}: {counted}"
                        );
                        if mode != FeedbackMode::ClosedLoop || fb.is_none() {
                            // Open loop: the count lands on the target.
                            assert!((counted - rep.target_deg).abs() <= eps, "{c:?}: {counted}");
                        }
                    }
                    Err(AxisError::NotFinite) => {
                        assert!(!target.is_finite() || fb.is_some_and(|v| !v.is_finite()));
                    }
                    Err(e) => panic!("{e:?}"),
                }
            }
            if round < 2 {
                // A fault: the switch may fail now, and homing is redone
                // from the counted position.
                ax.drive_mut().switch = match r.next_u64() % 3 {
                    0 => Switch::StuckClosed,
                    1 => Switch::StuckOpen,
                    _ => Switch::Normal,
                };
                ax.unhome();
            }
        }
    }
    eprintln!(
        "property: {} configs, {} homing steps, {} homings done, {} updates",
        f.configs, f.homing_steps, f.homed, f.updates
    );
    assert_eq!(f.configs, cases);
    assert!(f.homed > cases / 2);
}

#[test]
fn invalid_configurations_do_not_panic() {
    // Any bits at all: the controller clamps, never overflows.
    let mut r = SplitMix64::new(42);
    for _ in 0..2000 {
        let c = AxisConfig {
            counts_per_motor_rev: r.next_u64() as u32,
            microsteps: r.next_u64() as u16,
            gear_ratio: f32::from_bits(r.next_u64() as u32),
            min_deg: f32::from_bits(r.next_u64() as u32),
            max_deg: f32::from_bits(r.next_u64() as u32),
            home_deg: f32::from_bits(r.next_u64() as u32),
            backlash_deg: f32::from_bits(r.next_u64() as u32),
            max_speed_deg_s: f32::from_bits(r.next_u64() as u32),
            deadband_deg: f32::from_bits(r.next_u64() as u32),
            continuous: r.next_u64() as u8,
            drive: r.next_u64() as u8,
            max_current_ma: r.next_u64() as u16,
            overcurrent_ms: r.next_u64() as u16,
            back_speed_deg_s: f32::from_bits(r.next_u64() as u32),
            // Not read by the axis controller.
            linear: suntracker::config::LinearMount::DEFAULT,
        };
        let mut d = Mock::new(0, Switch::Normal, -1_000_000, 1_000_000);
        d.pos = (r.next_u64() % 2_000_000) as i64 - 1_000_000;
        let mut ax = AxisController::new(d, c);
        for _ in 0..2000 {
            match ax.home_step(
                f32::from_bits(r.next_u64() as u32).abs(),
                suntracker::time::monotonic::from_board_ms(r.next_u64()),
            ) {
                Ok(HomeState::Done) => break,
                Ok(_) => ax.drive_mut().tick(),
                Err(_) => {}
            }
        }
        for _ in 0..20 {
            let t = f32::from_bits(r.next_u64() as u32);
            let fb = f32::from_bits(r.next_u64() as u32);
            let _ = ax.update(t, FeedbackMode::ClosedLoop, Some(fb));
            let _ = ax.update(t, FeedbackMode::OpenLoop, None);
            ax.drive_mut().tick();
            let _ = ax.counted_deg();
        }
    }
}
