//! Plant models of one axis: a stepper through a gear with backlash, or a
//! servo positioning on its output encoder; limit switch, hard stops, and
//! injectable faults (stall, lost steps, stuck switch, encoder timeout).
//!
//! Time advances in ticks: [`MotorPlant::begin_tick`] gives the axis
//! `dt` seconds of motion at its top speed; moves beyond that wait for the
//! next tick.

use suntracker::firmware::Motion;
use suntracker::motion::AxisDrive;

/// The limit switch reads closed up to this far above its angle, degrees:
/// an axis stepped onto the switch angle (a whole number of counts from a
/// start on the step grid) lands there within the rounding of the sums of
/// its steps, above or below; this closes the switch there either way.
const SWITCH_TOL_DEG: f64 = 1e-9;

/// On an axis that turns without end ([`MotorPlant::make_continuous`]) the
/// home switch is an index cam: closed from this far below its angle up
/// to it, once a turn, degrees.
const INDEX_ARC_DEG: f64 = 5.0;

/// `deg` within the turn, 0 ≤ … < 360°.
fn turn_of(deg: f64) -> f64 {
    deg - 360.0 * libm::floor(deg / 360.0)
}

/// Faults a run injects into one axis's hardware.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Injected {
    /// The motor turns no more (a stepper loses its steps; a DC motor is
    /// jammed and draws its stall current).
    pub stalled: bool,
    /// An obstacle holds the axis where it is.
    pub obstructed: bool,
    /// The feedback fails (an output encoder times out; a Hall sensor gives
    /// no more pulses).
    pub feedback_failed: bool,
    /// The limit switch reads closed.
    pub switch_stuck_closed: bool,
    /// The limit switch never closes.
    pub switch_stuck_open: bool,
}

/// One simulated axis as a whole-tracker run uses it: the controller
/// drives it ([`AxisDrive`]); the run gives it time, reads the truth and
/// injects faults.
pub trait SimAxis: AxisDrive + Clone {
    /// Starts a tick of `dt_s` seconds: motion still pending runs now, and
    /// moves commanded during the tick run at once within what is left.
    fn begin_tick(&mut self, dt_s: f64);
    /// The true output angle, degrees.
    fn output_deg(&self) -> f64;
    /// Output travel so far, degrees.
    fn travel_deg(&self) -> f64;
    /// Sets the injected faults.
    fn inject(&mut self, injected: Injected);
    /// The axis turns by `deg` without being driven (lost steps; a
    /// back-driven DC axis).
    fn slip(&mut self, deg: f64);
    /// Sets the motor's supply, V: a DC motor's speed follows it; the
    /// default (steppers and servos, whose drivers regulate their own)
    /// ignores it.
    fn set_supply_v(&mut self, supply_v: f64) {
        let _ = supply_v;
    }
}

/// Errors of the simulated drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SimError {
    /// The sensor did not answer.
    Timeout,
}

/// Kind of drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DriveKind {
    /// Stepper motor, gear with backlash, optional output encoder.
    Stepper,
    /// Servo closing its own loop on the output encoder (no backlash seen).
    Servo,
}

/// One simulated axis.
#[derive(Debug, Clone)]
pub struct MotorPlant {
    kind: DriveKind,
    /// True motor counts per output degree.
    counts_per_deg: f64,
    /// True backlash, degrees (stepper only).
    backlash_deg: f64,
    /// Top speed, output degrees per second.
    speed_deg_s: f64,
    /// Output encoder counts per revolution (None: no encoder).
    encoder_cpr: Option<u32>,
    /// Limit switch closes at or below this output angle.
    switch_deg: f64,
    /// Mechanical end stops.
    hard_min_deg: f64,
    hard_max_deg: f64,
    /// Motor angle expressed in output degrees.
    motor_deg: f64,
    /// Output (panel) angle, degrees.
    output_deg: f64,
    pending: i64,
    budget_s: f64,
    /// Injected: steps are lost (motor stalled).
    pub stalled: bool,
    /// Injected: the limit switch reads closed.
    pub switch_stuck: bool,
    /// Injected: the limit switch never closes (broken wire).
    pub switch_stuck_open: bool,
    /// Injected: the encoder does not answer.
    pub encoder_timeout: bool,
    /// The drive stops a move toward the switch where the switch closes,
    /// dropping the rest (as the H-bridge driver given the home switch as
    /// its `min` limit and the servo axis do); false: it runs on to the
    /// hard stop 1° past the switch. True unless a test says otherwise.
    pub stops_at_switch: bool,
    /// Output travel, degrees.
    pub travel_deg: f64,
    /// Monotonic time of the last [`Motion::service`], ms.
    last_service_ms: Option<u64>,
    /// The axis turns without end (a slip ring): no end stops, the switch
    /// an index once a turn, an absolute single-turn output encoder.
    continuous: bool,
}

impl MotorPlant {
    /// A stepper of `step_angle_deg` (1.8° → 200 steps/rev) with
    /// `microsteps`, `gear_ratio`, true `backlash_deg`, top speed, optional
    /// encoder, starting at `start_deg`; switch at `switch_deg`, hard stops
    /// 1° beyond it and at `max_deg` + 1°.
    #[allow(clippy::too_many_arguments)]
    pub fn stepper(
        step_angle_deg: f64,
        microsteps: u32,
        gear_ratio: f64,
        backlash_deg: f64,
        speed_deg_s: f64,
        encoder_cpr: Option<u32>,
        switch_deg: f64,
        max_deg: f64,
        start_deg: f64,
    ) -> Self {
        let steps_per_rev = 360.0 / step_angle_deg;
        MotorPlant {
            kind: DriveKind::Stepper,
            counts_per_deg: steps_per_rev * f64::from(microsteps) * gear_ratio / 360.0,
            backlash_deg,
            speed_deg_s,
            encoder_cpr,
            switch_deg,
            hard_min_deg: switch_deg - 1.0,
            hard_max_deg: max_deg + 1.0,
            motor_deg: start_deg,
            output_deg: start_deg,
            pending: 0,
            budget_s: 0.0,
            stalled: false,
            switch_stuck: false,
            switch_stuck_open: false,
            encoder_timeout: false,
            stops_at_switch: true,
            travel_deg: 0.0,
            last_service_ms: None,
            continuous: false,
        }
    }

    /// A servo positioning on an output encoder of `encoder_cpr` counts per
    /// revolution (commands are in encoder counts).
    pub fn servo(
        encoder_cpr: u32,
        speed_deg_s: f64,
        switch_deg: f64,
        max_deg: f64,
        start_deg: f64,
    ) -> Self {
        MotorPlant {
            kind: DriveKind::Servo,
            counts_per_deg: f64::from(encoder_cpr) / 360.0,
            backlash_deg: 0.0,
            speed_deg_s,
            encoder_cpr: Some(encoder_cpr),
            switch_deg,
            hard_min_deg: switch_deg - 1.0,
            hard_max_deg: max_deg + 1.0,
            motor_deg: start_deg,
            output_deg: start_deg,
            pending: 0,
            budget_s: 0.0,
            stalled: false,
            switch_stuck: false,
            switch_stuck_open: false,
            encoder_timeout: false,
            stops_at_switch: true,
            travel_deg: 0.0,
            last_service_ms: None,
            continuous: false,
        }
    }

    /// Makes the axis one that turns without end (a slip ring or an
    /// unlimited slewing drive): no end stops, the home switch an index
    /// cam closed over the 5° below its angle once a turn,
    /// the output encoder (if any) absolute within a turn.
    pub fn make_continuous(&mut self) {
        self.continuous = true;
        self.hard_min_deg = f64::NEG_INFINITY;
        self.hard_max_deg = f64::INFINITY;
    }

    /// The true output angle, degrees.
    pub fn output_deg(&self) -> f64 {
        self.output_deg
    }

    /// The drive kind.
    pub fn kind(&self) -> DriveKind {
        self.kind
    }

    /// Lost steps: the motor slips by `deg` without the count knowing.
    pub fn slip(&mut self, deg: f64) {
        self.motor_deg += deg;
        self.follow();
    }

    /// Starts a tick of `dt_s` seconds and runs pending counts.
    pub fn begin_tick(&mut self, dt_s: f64) {
        self.budget_s = dt_s.max(0.0);
        self.run();
    }

    fn follow(&mut self) {
        let half = self.backlash_deg / 2.0;
        let before = self.output_deg;
        if self.motor_deg - self.output_deg > half {
            self.output_deg = self.motor_deg - half;
        } else if self.output_deg - self.motor_deg > half {
            self.output_deg = self.motor_deg + half;
        }
        // End stops hold the output, and the motor against it.
        if self.output_deg < self.hard_min_deg {
            self.output_deg = self.hard_min_deg;
            self.motor_deg = self.motor_deg.max(self.hard_min_deg - half);
        }
        if self.output_deg > self.hard_max_deg {
            self.output_deg = self.hard_max_deg;
            self.motor_deg = self.motor_deg.min(self.hard_max_deg + half);
        }
        self.travel_deg += (self.output_deg - before).abs();
    }

    /// The limit switch reads closed.
    fn switch_closed(&self) -> bool {
        let at = if self.continuous {
            // Above the switch within the turn, `INDEX_ARC_DEG` below it
            // counted as 360° − that.
            let w = turn_of(self.output_deg - self.switch_deg - SWITCH_TOL_DEG);
            w == 0.0 || w >= 360.0 - INDEX_ARC_DEG - SWITCH_TOL_DEG
        } else {
            self.output_deg <= self.switch_deg + SWITCH_TOL_DEG
        };
        self.switch_stuck || (!self.switch_stuck_open && at)
    }

    /// Motor counts down to where the switch reads closed (0 when it does).
    fn counts_to_switch(&self) -> i64 {
        if self.switch_closed() {
            return 0;
        }
        // Moving down, the output follows the motor half the backlash
        // above it (stepper; the servo lands on the encoder count).
        let half = match self.kind {
            DriveKind::Stepper => self.backlash_deg / 2.0,
            DriveKind::Servo => 0.0,
        };
        let motor_at_switch = self.switch_deg + SWITCH_TOL_DEG - half;
        let above_deg = if self.continuous {
            // The index next met turning down.
            turn_of(self.motor_deg - motor_at_switch)
        } else {
            self.motor_deg - motor_at_switch
        };
        let d = above_deg * self.counts_per_deg;
        // At least one count: the motor may sit in the slack above it.
        (libm::ceil(d) as i64).max(1)
    }

    fn run(&mut self) {
        if self.pending == 0 {
            return;
        }
        let max_counts = (self.speed_deg_s * self.budget_s * self.counts_per_deg) as i64;
        // max/min, not clamp: no panic path in the firmware image.
        let mut n = self.pending.max(-max_counts).min(max_counts);
        // (A stalled motor does not turn: the switch stays as it is, and
        // the steps are issued.)
        if self.pending < 0 && self.stops_at_switch && !self.switch_stuck_open && !self.stalled {
            // The driver reads the switch before each step toward it and
            // halts where it closes, dropping the rest of the move.
            let to_switch = self.counts_to_switch();
            if to_switch == 0 {
                self.pending = 0;
                return;
            }
            if to_switch <= -n {
                n = -to_switch;
                self.pending = n;
            }
        }
        if n == 0 {
            return;
        }
        self.pending -= n;
        self.budget_s -= (n.abs() as f64) / self.counts_per_deg / self.speed_deg_s;
        if self.stalled {
            return; // the steps are issued but nothing turns
        }
        match self.kind {
            DriveKind::Stepper => {
                self.motor_deg += n as f64 / self.counts_per_deg;
                self.follow();
            }
            DriveKind::Servo => {
                // The servo loop lands on a whole encoder count.
                let target = self.output_deg + n as f64 / self.counts_per_deg;
                let q = libm::round(target * self.counts_per_deg) / self.counts_per_deg;
                self.motor_deg = q;
                self.follow();
            }
        }
    }
}

impl AxisDrive for MotorPlant {
    type Error = SimError;
    fn move_counts(&mut self, counts: i32) -> Result<(), SimError> {
        self.pending = self.pending.saturating_add(i64::from(counts));
        self.run();
        Ok(())
    }
    fn pending(&self) -> i32 {
        i32::try_from(self.pending).unwrap_or(i32::MAX)
    }
    fn stop(&mut self) -> Result<(), SimError> {
        self.pending = 0;
        Ok(())
    }
    fn at_limit(&mut self) -> Result<bool, SimError> {
        Ok(self.switch_closed())
    }
    /// The driver stops at the switch, or (an axis that turns without end,
    /// homed) passes it.
    fn switch_stops(&mut self, on: bool) {
        self.stops_at_switch = on;
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, SimError> {
        if self.encoder_timeout {
            return Err(SimError::Timeout);
        }
        // Absolute within a turn on an axis that turns without end.
        let deg = if self.continuous {
            turn_of(self.output_deg)
        } else {
            self.output_deg
        };
        Ok(self.encoder_cpr.map(|cpr| {
            let cpd = f64::from(cpr) / 360.0;
            (libm::floor(deg * cpd) / cpd) as f32
        }))
    }
}

impl SimAxis for MotorPlant {
    fn begin_tick(&mut self, dt_s: f64) {
        MotorPlant::begin_tick(self, dt_s);
    }
    fn output_deg(&self) -> f64 {
        self.output_deg
    }
    fn travel_deg(&self) -> f64 {
        self.travel_deg
    }
    /// An obstruction stalls the motor (the steps are issued, nothing
    /// turns).
    fn inject(&mut self, injected: Injected) {
        self.stalled = injected.stalled || injected.obstructed;
        self.encoder_timeout = injected.feedback_failed;
        self.switch_stuck = injected.switch_stuck_closed;
        self.switch_stuck_open = injected.switch_stuck_open;
    }
    fn slip(&mut self, deg: f64) {
        MotorPlant::slip(self, deg);
    }
}

/// A plant driven by the firmware loop's clock (boards without motors, e.g.
/// QEMU's): each service gives the axis the monotonic time elapsed since
/// the previous one, then ends the tick, so a move commanded afterwards
/// starts at the next service (no motion before the command).
impl Motion for MotorPlant {
    fn service(&mut self, now_ms: u64) -> bool {
        let dt_ms = self.last_service_ms.map_or(0, |t| now_ms.saturating_sub(t));
        self.last_service_ms = Some(now_ms);
        self.begin_tick(dt_ms as f64 * 1e-3);
        self.begin_tick(0.0);
        true
    }
}
