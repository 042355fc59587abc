//! FEETECH FS5106R continuous-rotation servo (Chowdhury et al.'s (2019) axis
//! drive): the pulse width on its signal pin sets the output shaft's SPEED,
//! not its angle. [`ServoSpec`] is the pulse-to-speed law, `no_std`: the
//! servo plants of the host tests (`tests/common/servo.rs`) drive their
//! shafts by it. `Fs5106r` (feature `std`) takes the pulses a bench
//! decodes from the pin (width, time) and gives the shaft angle over time:
//! the emulator harness's Uno bench (`emu/src/uno.rs`) runs it.
//!
//! Figures ([`ServoSpec::FS5106R_6V`]):
//!
//! - **No-load speed 95 rpm at 6 V** (570 °/s): Chowdhury et al. 2019, Figure 2
//!   ("FS5106R FEETECH Continuous Rotation Servo — Speed @ 6 V 95 rpm; stall
//!   torque @ 6 V 83 oz-in").
//! - **Neutral (stop) 1,500 µs, control range 700–2,300 µs**: FEETECH's
//!   FS5106R specification sheet (the one Pololu distributes as
//!   `FS5106R-specs.pdf`: pulse width range 700 to 2,300 µs, neutral
//!   position 1,500 µs). The model reaches full speed at the ends of that
//!   range, ±800 µs from neutral; the 1,000–2,000 µs range of the Arduino
//!   `Servo` library and of `drivers::servo::ServoConfig::STANDARD_50HZ`
//!   therefore gives (500 − 4) / (800 − 4) = 62 % of full speed at its ends.
//! - **Dead band ±4 µs** about neutral: the same sheet's "dead band width"
//!   (a few µs), read as a half-width on each side of neutral, the way
//!   Pololu reads FEETECH's figure for the FS90R ("deadband ±5 µs").
//!
//! The sheet itself could not be opened where this model was written: the
//! range and dead band above are FEETECH's figures as recalled, not
//! re-read, and are [`ServoSpec`] fields so that a bench can set others
//! (`drivers/tests/servo_closed_loop.rs` uses ±20 µs and a ±500 µs range,
//! `tests/hw_servo_day.rs` ±8 µs, each for its own plant).
//!
//! Speed law: zero for `|w − 1500| ≤ dead band`; beyond it, rising linearly
//! from 0 at the dead-band edge to the no-load speed at the end of the
//! control range, and held there for wider pulses (the amplifier
//! saturates); the sign of `w − 1500` gives the direction: wider pulses turn
//! the shaft counter-clockwise seen from the horn (FEETECH's convention,
//! the one Pololu states for the FS90R), which is a positive angle here.
//!
//! Load: a factor 0..1 (1 = no load) scales the speed (a loaded DC motor
//! slows roughly in proportion to torque/stall torque). Stall: intervals in
//! which the shaft does not move at all whatever the pulses say (a jammed
//! axis, "a servo that stalls for ten minutes").
//!
//! Signal loss: an analog servo drives its motor only in response to pulses;
//! a command holds for [`ServoSpec::signal_timeout_s`] (3 frames of 20 ms)
//! after the pulse that gave it, then the shaft stops until the next pulse.
//!
//! Time: seconds on one monotonic clock, the one the pulse times are given
//! in. The servo sees pulses in real time; under the harness's compressed
//! time (60 emulated s per CPU s) 50 Hz frames are 1.2 emulated s apart, so
//! a bench feeding emulated times must either run real time while a servo
//! moves (as the Mega bench does for the steppers) or scale
//! `signal_timeout_s`.
//!
//! Integration is exact for this law: between events (a pulse, the end of a
//! command's hold, the start or end of a stall, a load change) the speed is
//! constant, and the angle advances by speed × Δt over each such piece
//! (`Fs5106r::segments_to` lists them, so a bench can time encoder edges
//! from them). No inertia is modelled: the speed steps at each event.

#[cfg(feature = "std")]
use std::{vec, vec::Vec};

/// Pulse-to-speed law and timing of a continuous-rotation servo.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoSpec {
    /// Stop pulse, µs.
    pub neutral_us: f64,
    /// Half-width of the dead band about neutral, µs: no motion within it.
    pub dead_band_us: f64,
    /// Pulse for full speed clockwise (negative angle), µs.
    pub min_pulse_us: f64,
    /// Pulse for full speed counter-clockwise (positive angle), µs.
    pub max_pulse_us: f64,
    /// No-load output speed at the ends of the control range, rpm.
    pub no_load_rpm: f64,
    /// A command holds this long after its pulse, s; then the shaft stops.
    pub signal_timeout_s: f64,
}

/// The servo frame at 50 Hz, s.
pub const FRAME_S: f64 = 0.020;

impl ServoSpec {
    /// FEETECH FS5106R at 6 V (see the module documentation for sources).
    pub const FS5106R_6V: ServoSpec = ServoSpec {
        neutral_us: 1_500.0,
        dead_band_us: 4.0,
        min_pulse_us: 700.0,
        max_pulse_us: 2_300.0,
        no_load_rpm: 95.0,
        signal_timeout_s: 3.0 * FRAME_S,
    };

    /// No-load speed of the output shaft for a pulse of `width_us`, °/s
    /// (positive: counter-clockwise seen from the horn). Non-finite widths
    /// give 0.
    pub fn no_load_speed_deg_s(&self, width_us: f64) -> f64 {
        let d = width_us - self.neutral_us;
        if !d.is_finite() || d.abs() <= self.dead_band_us {
            return 0.0;
        }
        let half_range = if d > 0.0 {
            self.max_pulse_us - self.neutral_us
        } else {
            self.neutral_us - self.min_pulse_us
        };
        let fraction = ((d.abs() - self.dead_band_us) / (half_range - self.dead_band_us)).min(1.0);
        fraction * self.no_load_rpm * 6.0 * d.signum()
    }
}

/// A piece of motion at constant speed: `angle(t) = angle0 + speed·(t − t0)`
/// for `t0 ≤ t ≤ t1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Start, s.
    pub t0_s: f64,
    /// End, s.
    pub t1_s: f64,
    /// Shaft angle at `t0_s`, degrees.
    pub angle0_deg: f64,
    /// Speed over the piece, °/s.
    pub speed_deg_s: f64,
}

impl Segment {
    /// Angle at `t_s` (extrapolated outside the piece).
    pub fn angle_at(&self, t_s: f64) -> f64 {
        self.angle0_deg + self.speed_deg_s * (t_s - self.t0_s)
    }

    /// Angle at the end of the piece.
    pub fn angle1_deg(&self) -> f64 {
        self.angle_at(self.t1_s)
    }

    /// When the shaft passes `angle_deg` within the piece, if it does.
    pub fn time_at(&self, angle_deg: f64) -> Option<f64> {
        if self.speed_deg_s == 0.0 {
            return None;
        }
        let t = self.t0_s + (angle_deg - self.angle0_deg) / self.speed_deg_s;
        (self.t0_s..=self.t1_s).contains(&t).then_some(t)
    }
}

/// One servo: its shaft angle, the last command, load and stalls.
#[cfg(feature = "std")]
#[derive(Debug, Clone)]
pub struct Fs5106r {
    spec: ServoSpec,
    angle_deg: f64,
    t_s: f64,
    /// The last pulse: (time, no-load speed it commands).
    command: Option<(f64, f64)>,
    load: f64,
    /// Stall intervals `[from, to)`, s.
    stalls: Vec<(f64, f64)>,
    /// Pulses received.
    pub pulses: u64,
}

#[cfg(feature = "std")]
impl Fs5106r {
    /// A servo after `spec`, its shaft at `angle_deg` at time `t_s`, no
    /// pulse yet (stopped), no load.
    pub fn new(spec: ServoSpec, angle_deg: f64, t_s: f64) -> Self {
        Fs5106r {
            spec,
            angle_deg,
            t_s,
            command: None,
            load: 1.0,
            stalls: Vec::new(),
            pulses: 0,
        }
    }

    /// An FS5106R at 6 V ([`ServoSpec::FS5106R_6V`]).
    pub fn at_6v(angle_deg: f64, t_s: f64) -> Self {
        Self::new(ServoSpec::FS5106R_6V, angle_deg, t_s)
    }

    /// The spec in use.
    pub fn spec(&self) -> &ServoSpec {
        &self.spec
    }

    /// Shaft angle at the time reached so far ([`Fs5106r::time_s`]), degrees.
    pub fn angle_deg(&self) -> f64 {
        self.angle_deg
    }

    /// Time the model has been advanced to, s.
    pub fn time_s(&self) -> f64 {
        self.t_s
    }

    /// Load factor in use (1 = no load).
    pub fn load(&self) -> f64 {
        self.load
    }

    /// From `t_s` on, the speed is scaled by `load` (clamped to 0..1; 1 =
    /// no load, 0.5 = half speed). Advances to `t_s` first.
    pub fn set_load(&mut self, t_s: f64, load: f64) {
        self.advance_to(t_s);
        self.load = if load.is_nan() {
            1.0
        } else {
            load.clamp(0.0, 1.0)
        };
    }

    /// The shaft does not move in `[from_s, to_s)` (e.g. ten minutes jammed).
    /// Only the part after the time already reached has an effect.
    pub fn add_stall(&mut self, from_s: f64, to_s: f64) {
        if to_s > from_s {
            self.stalls.push((from_s, to_s));
        }
    }

    /// Whether a stall interval covers `t_s`.
    pub fn is_stalled(&self, t_s: f64) -> bool {
        self.stalls.iter().any(|&(a, b)| a <= t_s && t_s < b)
    }

    /// A pulse of `width_us` at `t_s` (the bench passes its rising edge):
    /// advances to `t_s`, then commands the speed of that width. A pulse
    /// earlier than the time reached takes effect at the time reached.
    /// Widths that are not positive (no pulse) are ignored.
    pub fn pulse(&mut self, t_s: f64, width_us: f64) {
        self.advance_to(t_s);
        if width_us > 0.0 {
            self.command = Some((self.t_s, self.spec.no_load_speed_deg_s(width_us)));
            self.pulses += 1;
        }
    }

    /// When the last pulse's command runs out (its time plus
    /// [`ServoSpec::signal_timeout_s`]) if no pulse follows; `None` before
    /// the first pulse.
    pub fn command_end_s(&self) -> Option<f64> {
        self.command.map(|(t0, _)| t0 + self.spec.signal_timeout_s)
    }

    /// The command's speed at `t_s` without stalls: 0 before the first
    /// pulse and after the hold of the last one.
    fn commanded_deg_s(&self, t_s: f64) -> f64 {
        match self.command {
            Some((t0, v)) if t_s < t0 + self.spec.signal_timeout_s => v * self.load,
            _ => 0.0,
        }
    }

    /// Shaft speed at `t_s` (≥ the time reached, before the next event), °/s.
    pub fn speed_deg_s(&self, t_s: f64) -> f64 {
        if self.is_stalled(t_s) {
            0.0
        } else {
            self.commanded_deg_s(t_s)
        }
    }

    /// The motion from the time reached to `t_s`, in pieces of constant
    /// speed, given the pulses received so far (none is assumed before
    /// `t_s`). Empty if `t_s` is not later than the time reached.
    pub fn segments_to(&self, t_s: f64) -> Vec<Segment> {
        if t_s.is_nan() || t_s <= self.t_s {
            return Vec::new();
        }
        let mut cuts = vec![self.t_s, t_s];
        if let Some((t0, _)) = self.command {
            cuts.push(t0 + self.spec.signal_timeout_s);
        }
        for &(a, b) in &self.stalls {
            cuts.push(a);
            cuts.push(b);
        }
        cuts.retain(|&c| c >= self.t_s && c <= t_s);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        let mut angle = self.angle_deg;
        let mut out = Vec::with_capacity(cuts.len() - 1);
        for w in cuts.windows(2) {
            let (a, b) = (w[0], w[1]);
            // Every event boundary is a cut, so the speed at the start of
            // a piece holds over all of it.
            let speed = self.speed_deg_s(a);
            out.push(Segment {
                t0_s: a,
                t1_s: b,
                angle0_deg: angle,
                speed_deg_s: speed,
            });
            angle += speed * (b - a);
        }
        out
    }

    /// Advances the shaft to `t_s` (no-op if not later than the time
    /// reached); returns the angle there.
    pub fn advance_to(&mut self, t_s: f64) -> f64 {
        if let Some(last) = self.segments_to(t_s).last() {
            self.angle_deg = last.angle1_deg();
            self.t_s = t_s;
        }
        self.angle_deg
    }
}
