//! FEETECH FS5106R continuous-rotation servo (seed chowdhury-2019's axis
//! drive): the pulse width on its signal pin sets the output shaft's SPEED,
//! not its angle. The model takes the pulses the bench decodes from the pin
//! (width, time) and gives the shaft angle over time.
//!
//! Figures ([`ServoSpec::FS5106R_6V`]):
//!
//! - **No-load speed 95 rpm at 6 V** (570 °/s): seed chowdhury-2019, Figure 2
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
//! ([`Fs5106r::segments_to`] lists them, so a bench can time encoder edges
//! from them). No inertia is modelled: the speed steps at each event.

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

#[cfg(test)]
mod tests {
    use super::*;

    /// 95 rpm (seed chowdhury-2019, FEETECH) in °/s: 95 × 360 / 60.
    const FULL_DEG_S: f64 = 570.0;

    /// Drives `servo` with `width_us` pulses every 20 ms over `[from, to)`.
    fn drive(servo: &mut Fs5106r, width_us: f64, from_s: f64, to_s: f64) {
        let frames = ((to_s - from_s) / FRAME_S).round() as i64;
        for k in 0..frames {
            servo.pulse(from_s + k as f64 * FRAME_S, width_us);
        }
        servo.advance_to(to_s);
    }

    fn within(actual: f64, expected: f64, rel: f64) -> bool {
        (actual - expected).abs() <= rel * expected.abs()
    }

    #[test]
    fn dead_band_gives_no_motion() {
        for width in [1_500.0, 1_497.0, 1_503.0, 1_496.0, 1_504.0] {
            let mut s = Fs5106r::at_6v(12.5, 0.0);
            drive(&mut s, width, 0.0, 30.0);
            assert_eq!(s.angle_deg(), 12.5, "{width} µs");
            assert_eq!(s.pulses, 1_500);
        }
        // Just outside it, it creeps.
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut s, 1_505.0, 0.0, 30.0);
        assert!(s.angle_deg() > 0.0);
    }

    #[test]
    fn full_pulse_is_95_rpm() {
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut s, 2_300.0, 0.0, 60.0);
        // 95 revolutions in a minute.
        assert!(
            within(s.angle_deg(), 95.0 * 360.0, 0.01),
            "{}",
            s.angle_deg()
        );
        assert!(within(s.speed_deg_s(59.99), FULL_DEG_S, 0.01));
        // Wider than the range: saturated, not faster.
        let mut w = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut w, 2_500.0, 0.0, 60.0);
        assert!(within(w.angle_deg(), 95.0 * 360.0, 0.01));
    }

    #[test]
    fn narrow_pulse_reverses() {
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut s, 700.0, 0.0, 60.0);
        assert!(
            within(s.angle_deg(), -95.0 * 360.0, 0.01),
            "{}",
            s.angle_deg()
        );
        // Symmetric about neutral.
        let mut a = Fs5106r::at_6v(0.0, 0.0);
        let mut b = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut a, 1_700.0, 0.0, 10.0);
        drive(&mut b, 1_300.0, 0.0, 10.0);
        assert!(a.angle_deg() > 0.0);
        assert_eq!(a.angle_deg(), -b.angle_deg());
    }

    #[test]
    fn speed_rises_with_the_offset() {
        let spec = ServoSpec::FS5106R_6V;
        let mut last = 0.0;
        for w in (1_505..=2_300).step_by(5) {
            let v = spec.no_load_speed_deg_s(f64::from(w));
            assert!(v > last, "{w}");
            last = v;
        }
    }

    #[test]
    fn half_load_halves_speed() {
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        s.set_load(0.0, 0.5);
        drive(&mut s, 2_300.0, 0.0, 60.0);
        assert!(
            within(s.angle_deg(), 95.0 * 360.0 / 2.0, 0.01),
            "{}",
            s.angle_deg()
        );
        // Load changed mid-way: 30 s at full, 30 s at half.
        let mut t = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut t, 2_300.0, 0.0, 30.0);
        t.set_load(30.0, 0.5);
        drive(&mut t, 2_300.0, 30.0, 60.0);
        assert!(
            within(t.angle_deg(), FULL_DEG_S * 30.0 * 1.5, 0.01),
            "{}",
            t.angle_deg()
        );
    }

    #[test]
    fn stall_stops_the_shaft_for_its_interval() {
        // Full speed for 12 minutes, stalled for ten of them (60 s – 660 s).
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        s.add_stall(60.0, 660.0);
        drive(&mut s, 2_300.0, 0.0, 60.0);
        let at_stall = s.angle_deg();
        drive(&mut s, 2_300.0, 60.0, 660.0);
        assert_eq!(s.angle_deg(), at_stall);
        drive(&mut s, 2_300.0, 660.0, 720.0);
        assert!(
            within(s.angle_deg(), FULL_DEG_S * 120.0, 0.01),
            "{}",
            s.angle_deg()
        );
    }

    #[test]
    fn signal_loss_stops_the_shaft() {
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut s, 2_300.0, 0.0, 10.0);
        let at_loss = s.advance_to(10.0);
        // The last pulse (9.98 s) holds for three frames, then nothing.
        let stopped = s.advance_to(11.0);
        assert!(stopped > at_loss);
        assert!(stopped - at_loss < FULL_DEG_S * 3.0 * FRAME_S);
        assert_eq!(s.advance_to(3_600.0), stopped);
        assert_eq!(s.speed_deg_s(3_600.0), 0.0);
        // And it starts again with the next pulse.
        s.pulse(3_600.0, 2_300.0);
        assert!(s.advance_to(3_600.02) > stopped);
    }

    #[test]
    fn integration_is_exact_between_events() {
        // One pulse, one stall inside its hold: 10 ms moving, 20 ms
        // stalled, 30 ms moving, then the hold (60 ms) ends.
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        s.add_stall(0.010, 0.030);
        s.pulse(0.0, 2_300.0);
        let segs = s.segments_to(1.0);
        let cuts: Vec<f64> = segs.iter().map(|g| g.t0_s).collect();
        assert_eq!(cuts, vec![0.0, 0.010, 0.030, 0.060]);
        assert_eq!(segs[1].speed_deg_s, 0.0);
        assert_eq!(segs[3].speed_deg_s, 0.0);
        let end = s.advance_to(1.0);
        assert!((end - FULL_DEG_S * 0.040).abs() < 1e-9, "{end}");
        // Stepping in small increments gives the same angle.
        let mut t = Fs5106r::at_6v(0.0, 0.0);
        t.add_stall(0.010, 0.030);
        t.pulse(0.0, 2_300.0);
        for k in 1..=1_000 {
            t.advance_to(k as f64 * 0.001);
        }
        assert!((t.angle_deg() - end).abs() < 1e-9);
        // Segment timing.
        let g = segs[0];
        let t_half = g
            .time_at(g.angle0_deg + FULL_DEG_S * 0.005)
            .expect("inside");
        assert!((t_half - 0.005).abs() < 1e-12);
        assert_eq!(segs[1].time_at(0.0), None);
    }
}
