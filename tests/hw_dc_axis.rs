//! The DC-motor axis (`hw::DcAxis`) on the simulated gear motor
//! (`sim::dc_motor`, Pololu 37D 131.25:1 at 12 V with its 64 CPR motor-shaft
//! Hall encoder), polled every millisecond as a main loop would.
//!
//! The motor drives a further 60:1 worm stage (`sim::dc_drive::worm_slew_motor`,
//! whose documentation gives the figures): 1,400 Hall counts a degree, at
//! most 7.6°/s.
//!
//! The Hall edges are decoded by `drivers::encoder::SharedEncoder`, fed
//! after every 10 µs step of the model as an interrupt would be; the bridge
//! is `drivers::dc_motor::DcMotor` over a bridge that hands its output to
//! the model; the current is read through the BTS7960 current sense of the
//! drivers (`bts7960::CurrentSense`, data-sheet k_ILIS 8,500 and R_IS 1 kΩ)
//! from the model's IS voltage on a 10-bit ADC at 5 V.

use std::cell::RefCell;
use std::convert::Infallible;
use std::rc::Rc;

use drivers::adc::AdcChannel;
use drivers::dc_motor::bts7960::{CurrentSense, SenseConfig};
use drivers::dc_motor::{Bridge, Config as MotorConfig, DcMotor, Error, Output, RestMode};
use drivers::encoder::SharedEncoder;
use embedded_hal::digital::{ErrorType, InputPin};
use sim::dc_drive::{worm_slew_axis_config, worm_slew_motor, WORM_SLEW_LOOP};
use sim::dc_motor::{Bts7960Sense, DcMotor as Plant, MotorSpec, DEFAULT_STEP_S};
use suntracker::config::AxisConfig;
use suntracker::hw::{
    DcAxis, DcAxisConfig, DcAxisConfigError, DcAxisError, DcFault, DcState, NoCurrentSense,
};
use suntracker::motion::AxisDrive;

/// Hall counts per output degree: 64 · 131.25 · 60 / 360.
const COUNTS_PER_DEG: f64 = 1_400.0;
const TOL_DEG: f64 = 0.2;

type Shared = Rc<RefCell<Plant>>;

struct SimBridge(Shared);

impl Bridge for SimBridge {
    type PwmError = Infallible;
    type PinError = Infallible;
    type State = ();
    fn init(&mut self) -> Result<(), Error<Infallible, Infallible>> {
        self.0.borrow_mut().set_output(Output::Coast);
        Ok(())
    }
    fn apply(&mut self, _: &mut (), output: Output) -> Result<(), Error<Infallible, Infallible>> {
        self.0.borrow_mut().set_output(output);
        Ok(())
    }
}

/// The IS pin of the IBT-2 on a 10-bit ADC at 5 V.
struct IsPin(Shared);

impl AdcChannel for IsPin {
    type Error = Infallible;
    fn read_raw(&mut self) -> Result<u16, Infallible> {
        let m = self.0.borrow();
        Ok(Bts7960Sense::TYPICAL_1K_5V.adc_counts(m.output(), m.current_a(), 5.0, 1_023))
    }
    fn full_scale(&self) -> u16 {
        1_023
    }
}

/// Home switch, closed at or below −90° of output.
struct Switch(Shared);

impl ErrorType for Switch {
    type Error = Infallible;
}

impl InputPin for Switch {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(self.0.borrow().output_angle_deg() <= -90.0)
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        self.is_high().map(|h| !h)
    }
}

type Sense = CurrentSense<IsPin>;
type Axis<'a, C> = DcAxis<SimBridge, &'a SharedEncoder, Switch, C>;

fn spec() -> MotorSpec {
    worm_slew_motor()
}

fn axis_config() -> AxisConfig {
    worm_slew_axis_config(-90.0, 90.0)
}

/// `sim::dc_drive::WORM_SLEW_LOOP` (its documentation gives each value's
/// reason): stall after 500 ms without a count, overcurrent above 3 A for
/// 100 ms, too slow under 4,900 counts/s plus 3 s.
fn dc_config() -> DcAxisConfig {
    WORM_SLEW_LOOP
}

struct Rig {
    plant: Shared,
    enc: SharedEncoder,
}

impl Rig {
    fn new() -> Self {
        let plant = Rc::new(RefCell::new(Plant::new(spec())));
        let enc = SharedEncoder::new();
        let (a, b) = plant.borrow().hall_levels();
        enc.set_levels(a, b);
        Rig { plant, enc }
    }

    fn axis<C: suntracker::hw::MotorCurrent>(&self, sense: Option<C>) -> Axis<'_, C> {
        let motor = DcMotor::new(
            SimBridge(Rc::clone(&self.plant)),
            MotorConfig {
                ramp_permille_per_ms: 2,
                rest: RestMode::Brake,
            },
        )
        .unwrap();
        DcAxis::new(
            motor,
            &self.enc,
            Switch(Rc::clone(&self.plant)),
            false,
            sense,
            dc_config(),
            &axis_config(),
        )
        .unwrap()
    }

    fn sense(&self) -> Sense {
        CurrentSense::new(IsPin(Rc::clone(&self.plant)), SenseConfig::DATASHEET_1K_5V).unwrap()
    }

    /// One millisecond of the model, the encoder fed after every step.
    fn step_ms(&self) {
        let mut m = self.plant.borrow_mut();
        for _ in 0..100 {
            m.step(DEFAULT_STEP_S);
            let (a, b) = m.hall_levels();
            self.enc.update(a, b);
        }
    }

    fn deg(&self) -> f64 {
        self.plant.borrow().output_angle_deg()
    }
}

/// Counts the reversals of the count's motion.
#[derive(Default)]
struct Reversals {
    last: Option<i32>,
    dir: i32,
    n: u32,
}

impl Reversals {
    fn see(&mut self, count: i32) {
        if let Some(l) = self.last {
            let d = (count - l).signum();
            if d != 0 {
                if self.dir != 0 && d != self.dir {
                    self.n += 1;
                }
                self.dir = d;
            }
        }
        self.last = Some(count);
    }
}

/// Polls every ms until the axis rests, then 2 s more, checking the duty
/// ramp; returns the ms to rest, the reversals and the count on coming to
/// rest.
fn settle<C: suntracker::hw::MotorCurrent>(
    rig: &Rig,
    axis: &mut Axis<'_, C>,
    now: &mut u32,
    max_ms: u32,
) -> (u32, u32, i32)
where
    C::Error: std::fmt::Debug,
{
    let mut rev = Reversals::default();
    let mut rest_ms = None;
    let mut rest_count = 0;
    let mut duty = axis.duty_permille();
    for ms in 0..max_ms {
        axis.poll(*now).unwrap();
        // Soft starts and stops: the duty moves by the ramp's 2 ‰ per ms,
        // or drops to 0 at a brake.
        let d = axis.duty_permille();
        assert!(d == 0 || (d - duty).abs() <= 2, "duty {duty} → {d}");
        duty = d;
        rig.step_ms();
        *now = now.wrapping_add(1);
        rev.see(axis.count());
        let resting = matches!(axis.state(), DcState::Idle { .. });
        match rest_ms {
            None if resting => {
                rest_ms = Some(ms);
                rest_count = axis.count();
            }
            Some(r) if ms >= r + 2_000 => return (r, rev.n, rest_count),
            _ => {}
        }
    }
    panic!("not at rest after {max_ms} ms: {axis:?}");
}

#[test]
fn tracker_moves_end_on_target_without_hunting() {
    let rig = Rig::new();
    let mut axis = rig.axis::<Sense>(Some(rig.sense()));
    // The millisecond counter wraps during the first slew.
    let mut now: u32 = u32::MAX - 3_000;
    let mut moves: Vec<f64> = vec![45.0];
    moves.extend([0.25; 8]);
    moves.push(-60.0);
    moves.extend([0.25; 4]);
    moves.push(30.0);
    moves.extend([-0.25; 3]);
    let (mut target_deg, mut target_counts) = (0.0f64, 0i64);
    let mut worst = 0.0f64;
    let mut report = Vec::new();
    for step in moves {
        target_deg += step;
        let want = (target_deg * COUNTS_PER_DEG).round() as i64;
        axis.move_counts(i32::try_from(want - target_counts).unwrap())
            .unwrap();
        target_counts = want;
        assert_ne!(axis.pending(), 0);
        let start = now;
        let (rest_ms, reversals, _) = settle(&rig, &mut axis, &mut now, 60_000);
        let err = rig.deg() - target_deg;
        report.push(format!(
            "{step:+}° → {target_deg:.2}°: err {err:+.4}° rest {rest_ms} ms lead {} ms",
            axis.lead_ms()
        ));
        assert!(err.abs() <= TOL_DEG, "{}", report.join("\n"));
        assert_eq!(reversals, 0, "{}", report.join("\n"));
        assert_eq!(axis.pending(), 0);
        assert_eq!(axis.output(), Output::Brake);
        worst = worst.max(err.abs());
        // A slew at ≤ 7.6°/s takes at least |step| / 7.6 s.
        assert!(f64::from(rest_ms) >= step.abs() / 7.62 * 1_000.0 - 1.0);
        // Next move four minutes after this one started.
        let used = now.wrapping_sub(start);
        now = now.wrapping_add(240_000 - used);
    }
    println!("{}\nworst {worst:.4}°", report.join("\n"));
}

/// Drives into a hard stop at +5° while slewing to +10°; returns the ms
/// from the current first exceeding 3 A to the error, and the error.
fn into_hard_stop<C: suntracker::hw::MotorCurrent>(
    rig: &Rig,
    mut axis: Axis<'_, C>,
) -> (u32, DcFault)
where
    C::Error: std::fmt::Debug + PartialEq,
{
    rig.plant
        .borrow_mut()
        .set_hard_stops_deg(Some((-1_000.0, 5.0)));
    let mut now: u32 = 1_000;
    axis.move_counts((10.0 * COUNTS_PER_DEG) as i32).unwrap();
    let mut over_at = None;
    for _ in 0..20_000 {
        let r = axis.poll(now);
        if let Err(e) = r {
            let DcAxisError::Fault(f) = e else {
                panic!("{e:?}");
            };
            let over = over_at.expect("the current rose first");
            let took = now.wrapping_sub(over);
            // Braked at once; the motor current dies away.
            assert_eq!(rig.plant.borrow().output(), Output::Brake);
            for _ in 0..50 {
                rig.step_ms();
                now += 1;
                assert_eq!(axis.poll(now), Ok(Output::Brake), "reported once");
            }
            assert!(rig.plant.borrow().current_a().abs() < 0.01);
            assert!((rig.deg() - 5.0).abs() < 1e-9);
            assert_eq!(axis.fault(), Some(f));
            assert_eq!(axis.pending(), 0);
            assert_eq!(axis.move_counts(100), Err(DcAxisError::Fault(f)));
            axis.clear_fault(now);
            assert_eq!(axis.fault(), None);
            return (took, f);
        }
        rig.step_ms();
        now += 1;
        if over_at.is_none() && rig.plant.borrow().current_a() > 3.0 {
            over_at = Some(now);
        }
    }
    panic!("no fault");
}

#[test]
fn an_obstruction_trips_overcurrent_with_a_current_sense() {
    let rig = Rig::new();
    let axis = rig.axis::<Sense>(Some(rig.sense()));
    let (took, fault) = into_hard_stop(&rig, axis);
    println!("overcurrent after {took} ms above 3 A");
    // Above 3 A for overcurrent_ms = 100 ms (a poll or two of slack), and
    // before the 500 ms stall watch.
    assert_eq!(fault, DcFault::Overcurrent);
    assert!((100..=102).contains(&took), "{took}");
}

#[test]
fn an_obstruction_trips_the_stall_watch_without_one() {
    let rig = Rig::new();
    let axis = rig.axis::<NoCurrentSense>(None);
    let (took, fault) = into_hard_stop(&rig, axis);
    println!("stall after {took} ms above 3 A");
    // The last count comes as the output reaches the stop, the current
    // rises within a few τ_e (0.46 ms) of it: the stall follows after
    // stall_ms = 500 ms, well inside a second.
    assert_eq!(fault, DcFault::Stall);
    assert!((495..=505).contains(&took), "{took}");
}

/// A supply sagging to 5 V (a flat battery, a long thin cable) turns the
/// motor at 5/12 of its speed, drawing no more current than at 12 V: only
/// the move timeout sees it. An 80° slew (112,000 counts) may take
/// 112,000 / 4,900 s + 3 s = 25.86 s (half of the 7 °/s top speed, 1,400
/// counts a degree); at 5 V it needs longer, at 12 V about 12 s.
#[test]
fn a_slow_motor_trips_the_move_timeout() {
    let slew = |supply_v: f64| {
        let rig = Rig::new();
        *rig.plant.borrow_mut() = {
            let mut m = Plant::new(MotorSpec { supply_v, ..spec() });
            m.set_output_angle_deg(-85.0);
            m
        };
        let (a, b) = rig.plant.borrow().hall_levels();
        rig.enc.set_levels(a, b);
        let mut axis = rig.axis::<Sense>(Some(rig.sense()));
        axis.move_counts(112_000).unwrap();
        for now in 0..40_000u32 {
            if let Err(e) = axis.poll(now) {
                return (now, Some(e));
            }
            if matches!(axis.state(), DcState::Idle { .. }) {
                return (now, None);
            }
            rig.step_ms();
        }
        panic!("neither done nor faulted: {axis:?}");
    };
    let (ms, fault) = slew(12.0);
    println!("12 V: at rest after {ms} ms");
    assert_eq!(fault, None);
    assert!(ms < 15_000, "{ms}");
    let (ms, fault) = slew(5.0);
    println!("5 V: too slow after {ms} ms");
    assert_eq!(fault, Some(DcAxisError::Fault(DcFault::TooSlow)));
    assert!((25_856..=25_859).contains(&ms), "{ms}");
}

#[test]
fn a_back_driven_axis_at_rest_is_unexpected_motion() {
    let rig = Rig::new();
    let mut axis = rig.axis::<Sense>(Some(rig.sense()));
    let mut now = 0u32;
    axis.move_counts(1_400).unwrap();
    let (_, _, rest) = settle(&rig, &mut axis, &mut now, 10_000);
    // The braked run-down (viscous friction only in the model: an
    // exponential tail) adds at most a count or two in the 2 s after it.
    let creep = (axis.count() - rest).abs();
    assert!(creep <= 2, "{creep}");
    // Wind on the panels: 200 N·m against positive motion, back-driving
    // the braked motor through the worm.
    rig.plant.borrow_mut().set_load_torque_nm(200.0);
    let mut seen = None;
    for _ in 0..5_000 {
        match axis.poll(now) {
            Ok(out) => assert_eq!(out, Output::Brake, "never driven"),
            Err(e) => {
                assert_eq!(e, DcAxisError::Fault(DcFault::UnexpectedMotion));
                assert!(seen.is_none(), "reported once");
                seen = Some(rest - axis.count());
            }
        }
        rig.step_ms();
        now += 1;
    }
    let moved = seen.expect("unexpected motion reported");
    println!("unexpected motion after {moved} counts");
    // More than max_idle_counts = 70 counts since the axis came to rest
    // (the creep's included), at the first poll past it: a millisecond of
    // back-drive is far less than 70 counts.
    assert!((71 - 2 * creep..140).contains(&moved), "{moved}");
    assert_eq!(axis.fault(), None, "not latched");
    assert!(matches!(axis.state(), DcState::Idle { reported: true }));
}

#[test]
fn absurd_configurations_are_refused() {
    let ok = dc_config();
    assert_eq!(ok.validate(), Ok(()));
    let bad = [
        (
            DcAxisConfig {
                max_duty_permille: 1_001,
                ..ok
            },
            DcAxisConfigError::Duty,
        ),
        (
            DcAxisConfig {
                min_duty_permille: 1_000,
                max_duty_permille: 900,
                ..ok
            },
            DcAxisConfigError::Duty,
        ),
        (
            DcAxisConfig {
                deadband_counts: 0,
                ..ok
            },
            DcAxisConfigError::Band,
        ),
        (
            DcAxisConfig {
                slow_band_counts: 14,
                ..ok
            },
            DcAxisConfigError::Band,
        ),
        (
            DcAxisConfig {
                brake_lead_ms: 2_001,
                ..ok
            },
            DcAxisConfigError::BrakeLead,
        ),
        (
            DcAxisConfig { settle_ms: 0, ..ok },
            DcAxisConfigError::Settle,
        ),
        (DcAxisConfig { stall_ms: 0, ..ok }, DcAxisConfigError::Stall),
        (
            DcAxisConfig {
                drive_threshold_permille: 150,
                ..ok
            },
            DcAxisConfigError::DriveThreshold,
        ),
        (
            DcAxisConfig {
                max_current_ma: 0,
                ..ok
            },
            DcAxisConfigError::Current,
        ),
        (
            DcAxisConfig {
                max_idle_counts: 10_001,
                ..ok
            },
            DcAxisConfigError::IdleCounts,
        ),
        (
            DcAxisConfig {
                move_margin_ms: 600_001,
                ..ok
            },
            DcAxisConfigError::MoveMargin,
        ),
        (
            DcAxisConfig {
                stall_ms: 600_001,
                ..ok
            },
            DcAxisConfigError::Stall,
        ),
    ];
    let rig = Rig::new();
    for (c, want) in bad {
        assert_eq!(c.validate(), Err(want));
        let motor = DcMotor::new(
            SimBridge(Rc::clone(&rig.plant)),
            MotorConfig {
                ramp_permille_per_ms: 2,
                rest: RestMode::Brake,
            },
        )
        .unwrap();
        let axis = DcAxis::new(
            motor,
            &rig.enc,
            Switch(Rc::clone(&rig.plant)),
            false,
            None::<NoCurrentSense>,
            c,
            &axis_config(),
        );
        assert_eq!(axis.err(), Some(want));
    }
}

#[test]
fn homing_through_the_axis_controller_then_closed_loop() {
    use suntracker::motion::{AxisController, FeedbackMode, HomeState};
    let rig = Rig::new();
    // Start 4° above the switch (closed at −90°).
    rig.plant.borrow_mut().set_output_angle_deg(-86.0);
    let (a, b) = rig.plant.borrow().hall_levels();
    rig.enc.set_levels(a, b);
    let cfg = axis_config();
    let mut ax = AxisController::new(rig.axis::<Sense>(Some(rig.sense())), cfg);
    assert_eq!(ax.drive_mut().encoder_deg(), Ok(None));
    let mut now = 0u32;
    let mut steps = 0;
    loop {
        steps += 1;
        assert!(steps < 2_000, "homing did not finish");
        match ax.home_step(1.0, now).unwrap() {
            HomeState::Done => break,
            _ => {
                // Until the step's move is over.
                for _ in 0..20_000 {
                    let d = ax.drive_mut();
                    d.poll(now).unwrap();
                    rig.step_ms();
                    now = now.wrapping_add(1);
                    if matches!(d.state(), DcState::Idle { .. }) {
                        break;
                    }
                }
            }
        }
    }
    let truth = rig.deg();
    let fb = f64::from(ax.drive_mut().encoder_deg().unwrap().unwrap());
    println!("homed at {truth:.4}°, encoder {fb:.4}°");
    // The switch closes at −90°: the axis rests past it by at most the
    // run-on from the slow band's end, 150 ‰ of 10,667 counts/s for the
    // 130 ms lead: 208 counts, 0.15°. The encoder took the closing edge,
    // within a millisecond of the approach (a few counts, 0.005°) of the
    // truth.
    assert!((-90.15..=-90.0).contains(&truth), "{truth}");
    assert!((fb - truth).abs() < 0.005, "{fb} vs {truth}");
    // Closed loop to 12.5°: a 102.5° slew.
    for _ in 0..3 {
        let fb = ax.drive_mut().encoder_deg().unwrap();
        ax.update(12.5, FeedbackMode::ClosedLoop, fb).unwrap();
        settle(&rig, ax.drive_mut(), &mut now, 60_000);
    }
    let truth = rig.deg();
    println!("closed loop to 12.5°: at {truth:.4}°");
    assert!((truth - 12.5).abs() <= TOL_DEG, "{truth}");
}

#[test]
fn a_load_back_driving_the_stop_ends_it_as_unexpected_motion() {
    let rig = Rig::new();
    let mut axis = rig.axis::<Sense>(Some(rig.sense()));
    axis.move_counts(1_400).unwrap();
    let mut stop_at = None;
    for now in 0..20_000u32 {
        let r = axis.poll(now);
        if stop_at.is_none() && matches!(axis.state(), DcState::Stopping { .. }) {
            // The wind rises as the axis brakes: the counts never stand still.
            rig.plant.borrow_mut().set_load_torque_nm(200.0);
            stop_at = Some(now);
        }
        if let Err(e) = r {
            assert_eq!(e, DcAxisError::Fault(DcFault::UnexpectedMotion));
            let took = now - stop_at.unwrap();
            println!("back-driven stop ended after {took} ms");
            // The stop is cut at settle_ms + STOP_LEADS · lead; this first
            // stop never settles, so the lead is never measured and stays
            // brake_lead_ms = 130 ms. The next 71 counts at rest, at
            // hundreds of counts/s, trip the watch within 200 ms.
            let max = 100 + suntracker::hw::STOP_LEADS * 130;
            assert!((max..max + 200).contains(&took), "{took}");
            assert_eq!(axis.lead_ms(), 130);
            assert_eq!(rig.plant.borrow().output(), Output::Brake);
            return;
        }
        rig.step_ms();
    }
    panic!("no unexpected motion: {axis:?}");
}

#[test]
fn the_dc_hall_loop_follows_the_axis_configuration() {
    use suntracker::mechanics::{dc_hall_loop, dc_hall_loop_for};
    // The worm slew drive: 64 counts a motor turn × 7,875 / 360 = 1,400
    // counts a degree; 4° = 5,600, 0.01° = 14, 0.05° = 70 counts, half of
    // 7 °/s = 4,900 counts/s.
    let slew = dc_hall_loop(&worm_slew_axis_config(-180.0, 180.0));
    assert_eq!(slew, WORM_SLEW_LOOP);
    assert_eq!(
        (
            slew.slow_band_counts,
            slew.deadband_counts,
            slew.max_idle_counts,
            slew.min_speed_cps,
            slew.max_current_ma,
            slew.overcurrent_ms,
        ),
        (5_600, 14, 70, 4_900, 3_000, 100)
    );
    // The configuration's current watch goes into the loop.
    let mut axis = worm_slew_axis_config(-180.0, 180.0);
    axis.max_current_ma = 4_500;
    axis.overcurrent_ms = 250;
    let watched = dc_hall_loop(&axis);
    assert_eq!(
        (watched.max_current_ma, watched.overcurrent_ms),
        (4_500, 250)
    );
    // Every counts per degree the configuration allows (1 to 10^6) and
    // every speed gives a loop the DC axis takes.
    for cpd in [1.0, 1.7, 10.0, 99.9, 1_400.0, 37_777.7, 1_000_000.0] {
        for speed in [0.01, 1.0, 30.0] {
            for (ma, ms) in [(100, 10), (40_000, 5_000)] {
                let l = dc_hall_loop_for(cpd, speed, ma, ms);
                assert!(l.validate().is_ok(), "{cpd} {speed}: {l:?}");
                assert!(l.deadband_counts >= 1 && l.min_speed_cps >= 1);
            }
        }
    }
}
