//! The simulated mount (QEMU has no motors): per axis an ideal open-loop
//! stepper (no backlash, no lost steps) through the board's gear, its
//! position kept in whole steps from the home switch. Whole steps keep the
//! model exact without software `f64` in the image: the switch reads closed
//! at step 0 and below, the hard stops sit one degree beyond the switch and
//! the top of the travel, and the axis runs at most one step every
//! [`US_PER_STEP`] µs of the monotonic clock.

use core::convert::Infallible;

use suntracker::firmware::Motion;
use suntracker::motion::AxisDrive;

/// Full steps of the motor per revolution (a 1.8° stepper, no microsteps).
pub const STEPS_PER_MOTOR_REV: u32 = 200;
/// Gear between the motor and the axis.
pub const GEAR_RATIO: u32 = 100;
/// Top speed of the axis, degrees per second.
pub const SPEED_DEG_S: u32 = 2;
/// Axis steps per revolution: 20,000 (0.018° a step).
const STEPS_PER_AXIS_REV: u32 = STEPS_PER_MOTOR_REV * GEAR_RATIO;
/// One axis step, degrees.
pub const STEP_DEG: f32 = 360.0 / STEPS_PER_AXIS_REV as f32;
/// Monotonic µs per step at the top speed: 360° / (20,000 steps × 2°/s)
/// = 9,000 µs (a whole number for this gear and speed).
pub const US_PER_STEP: u32 = 360_000_000 / (STEPS_PER_AXIS_REV * SPEED_DEG_S);
/// Steps in the degree between the switch and the lower hard stop, and
/// between the top of the travel and the upper one.
const STOP_STEPS: i32 = (STEPS_PER_AXIS_REV / 360) as i32;

/// One simulated axis.
#[derive(Debug, Clone)]
pub struct StepperModel {
    /// The switch angle, degrees (the axis's `home_deg`).
    home_deg: f32,
    /// Steps above the switch (the switch reads closed at 0 and below).
    steps: i32,
    /// The hard stops, steps from the switch.
    min_steps: i32,
    max_steps: i32,
    /// Steps commanded and not yet taken (negative: toward the switch).
    pending: i32,
    /// Monotonic time of the last [`Motion::service`], ms.
    last_service_ms: Option<u64>,
}

impl StepperModel {
    /// An axis whose switch is at `home_deg`, whose travel ends at
    /// `max_deg`, standing `start_steps` steps above its switch.
    pub fn new(home_deg: f32, max_deg: f32, start_steps: i32) -> Self {
        // The travel in steps (`as` saturates; a configuration keeps it
        // within 720°, 40,000 steps).
        let travel_steps = ((max_deg - home_deg) / STEP_DEG) as i32;
        StepperModel {
            home_deg,
            steps: start_steps,
            min_steps: -STOP_STEPS,
            max_steps: travel_steps.saturating_add(STOP_STEPS),
            pending: 0,
            last_service_ms: None,
        }
    }

    /// The axis angle, degrees.
    pub fn output_deg(&self) -> f32 {
        self.home_deg + self.steps as f32 * STEP_DEG
    }

    /// Takes up to `budget` pending steps. A move toward the switch halts
    /// where it closes and drops the rest (the driver reads the switch
    /// before each step toward it, as the H-bridge driver given the switch
    /// as its `min` limit does).
    fn run(&mut self, budget: i32) {
        if self.pending < 0 && self.steps <= 0 {
            self.pending = 0;
            return;
        }
        // max/min, not clamp: no panic path in the image.
        let mut n = self.pending.max(-budget).min(budget);
        if n < 0 && self.steps <= -n {
            n = -self.steps;
            self.pending = n;
        }
        self.pending -= n;
        self.steps = self
            .steps
            .saturating_add(n)
            .max(self.min_steps)
            .min(self.max_steps);
    }
}

impl AxisDrive for StepperModel {
    type Error = Infallible;
    fn move_counts(&mut self, counts: i32) -> Result<(), Infallible> {
        self.pending = self.pending.saturating_add(counts);
        // Steps wait for the next service; only a move onto a closed
        // switch is dropped at once.
        self.run(0);
        Ok(())
    }
    fn pending(&self) -> i32 {
        self.pending
    }
    fn stop(&mut self) -> Result<(), Infallible> {
        self.pending = 0;
        Ok(())
    }
    fn at_limit(&mut self) -> Result<bool, Infallible> {
        Ok(self.steps <= 0)
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, Infallible> {
        Ok(None)
    }
}

/// Each service gives the axis the steps of the monotonic time elapsed
/// since the previous one; a move commanded afterwards starts at the next
/// service (no motion before the command).
impl Motion for StepperModel {
    fn service(&mut self, now_ms: u64) -> bool {
        let dt_ms = self.last_service_ms.map_or(0, |t| now_ms.saturating_sub(t));
        self.last_service_ms = Some(now_ms);
        // A 32-bit division (no 64-bit division routine in the image):
        // the elapsed time saturates at 71 minutes, far past any move.
        let dt_us = u32::try_from(dt_ms.saturating_mul(1_000)).unwrap_or(u32::MAX);
        let budget = i32::try_from(dt_us / US_PER_STEP).unwrap_or(i32::MAX);
        self.run(budget);
        true
    }
}
