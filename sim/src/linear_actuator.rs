//! Linear actuator tilting a tracker axis (LINAK LA12 class): the H-bridge
//! command ([`Output`]) in; the rod's extension, the motor current, the
//! single-Hall pulses, the potentiometer voltage and, through
//! [`drivers::linear::ActuatorGeometry`], the axis angle out. `no_std`.
//!
//! # Speed and current against load
//!
//! Not a motor-and-spindle model but the data-sheet law of a DC motor
//! behind a self-locking spindle: speed falls and current rises linearly
//! with the load the rod works against. With `d` the duty (−1..1, positive
//! extends), `f` the load as a fraction of the rated load, positive when it
//! pushes the rod in, and `o = f·sign(d)` the part of it the motion works
//! against:
//!
//! ```text
//! speed   = max(0, |d|·v₀ − (v₀ − v_full)·o) · sign(d)
//! current = max(0, i₀ + (i_full − i₀)·o)
//! ```
//!
//! A load that helps the motion speeds it up and the current falls no
//! lower than 0 (the spindle's friction takes the rest). Brake and coast
//! stop the rod at once: the spindle holds the load and the rod's inertia is
//! not modelled (as in [`crate::servo`], speed steps at each event, and the
//! integration is exact: constant speed between events).
//!
//! Blocked: driving into an obstruction ([`LinearActuator::set_obstruction_mm`])
//! or into a stroke end without end switches, the rod stays put and the
//! current is the stall current at that duty, where the speed law reaches
//! zero: `o_stall = |d|·v₀ / (v₀ − v_full)`, `i_stall = i₀ + (i_full −
//! i₀)·o_stall`. With end switches (LINAK's built-in limit switches, which
//! open the motor circuit at each end) the current at an end driven into is
//! 0 and the rod can be driven away from it.
//!
//! # Figures ([`ActuatorSpec::LA12_L1_12V`])
//!
//! LINAK, *Actuator LA12 User manual*, "I/O specifications":
//!
//! - **12 V, max. 5 A depending on load**: the current at rated load.
//! - **Single Hall, option L: 1 mm per pulse on the 12xLxx-1 spindle**;
//!   **frequency 14–26 Hz on the single Hall output depending on load**:
//!   read here as 26 mm/s with no load and 14 mm/s at rated load on that
//!   spindle (the manual gives the frequency, not the speed: this reading
//!   is the model's).
//! - **Potentiometer feedback 0.5–4.5 V over the stroke (option K)**; the
//!   slide potentiometer spans 100 mm of stroke (1 kΩ = 0 mm, 11 kΩ =
//!   100 mm), the stroke of the preset.
//!
//! The manual gives no no-load current: **1 A is an assumption** (a field).
//! Derived stall point at full duty: `o_stall = 26 / (26 − 14) = 2.167`
//! rated loads, `i_stall = 1 + 4 · 2.167 = 9.67 A`.
//!
//! # Dual Hall ([`ActuatorSpec::LA12_DUAL_HALL_12V`])
//!
//! LINAK's larger actuators (the TECHLINE LA36 of many solar trackers
//! among them) are sold with **dual Hall, digital** feedback: two Hall
//! outputs A and B in quadrature, **16 state shifts per spindle turn, 3 mm
//! pitch → 0.1875 mm, 4 mm pitch → 0.25 mm per shift**, each state held
//! at least 5 ms (LINAK, *Actuator system* user manual, "Input/output
//! specifications: Dual Hall, digital (F2) positioning"). A quadrature
//! pair tells the direction itself, so a rod pushed back by its load is
//! counted back, where a single output is counted by the commanded
//! direction. The preset keeps the LA12's motor figures above and puts
//! such an encoder on a 3 mm spindle (0.1875 mm a shift; at 26 mm/s a
//! state lasts 7.2 ms): an assumed actuator, a finer pulse on the same mount
//! (`simulate --drive linear-hall`).

use drivers::dc_motor::Output;
use drivers::linear::{ActuatorGeometry, LinearError};

use crate::dc_motor::duty_of;

/// An actuator's data-sheet figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActuatorSpec {
    /// Stroke, mm.
    pub stroke_mm: f64,
    /// Speed at full duty and no load, mm/s.
    pub no_load_speed_mm_s: f64,
    /// Speed at full duty and rated load, mm/s (< `no_load_speed_mm_s`).
    pub rated_load_speed_mm_s: f64,
    /// Current with no load, A.
    pub no_load_a: f64,
    /// Current at rated load, A.
    pub rated_load_a: f64,
    /// Rod travel per Hall pulse, mm (> 0); with two outputs in
    /// quadrature, per state shift of the pair.
    pub mm_per_pulse: f64,
    /// Two Hall outputs in quadrature (LINAK's dual Hall, digital): the
    /// counter has the rod's own direction. Otherwise a single output,
    /// counted by the commanded direction.
    pub hall_quadrature: bool,
    /// Potentiometer output fully retracted, V.
    pub pot_retracted_v: f64,
    /// Potentiometer output fully extended, V.
    pub pot_extended_v: f64,
    /// Built-in end switches cut the motor at both stroke ends.
    pub end_switches: bool,
}

impl ActuatorSpec {
    /// LINAK LA12, spindle 1, single Hall option L, analogue option K, 12 V
    /// (module documentation).
    pub const LA12_L1_12V: ActuatorSpec = ActuatorSpec {
        stroke_mm: 100.0,
        no_load_speed_mm_s: 26.0,
        rated_load_speed_mm_s: 14.0,
        no_load_a: 1.0,
        rated_load_a: 5.0,
        mm_per_pulse: 1.0,
        hall_quadrature: false,
        pot_retracted_v: 0.5,
        pot_extended_v: 4.5,
        end_switches: true,
    };

    /// [`ActuatorSpec::LA12_L1_12V`]'s motor and stroke with a dual Hall
    /// encoder of 0.1875 mm a state shift (module documentation: the LA12
    /// itself is sold with a single Hall only).
    pub const LA12_DUAL_HALL_12V: ActuatorSpec = ActuatorSpec {
        mm_per_pulse: 0.1875,
        hall_quadrature: true,
        ..Self::LA12_L1_12V
    };

    /// Speed lost per rated load, mm/s.
    fn droop_mm_s(&self) -> f64 {
        self.no_load_speed_mm_s - self.rated_load_speed_mm_s
    }

    /// Free speed at duty `duty` (−1..1) against `opposing` rated loads, mm/s.
    pub fn speed_mm_s(&self, duty: f64, opposing: f64) -> f64 {
        let magnitude =
            duty.abs().min(1.0) * self.no_load_speed_mm_s - self.droop_mm_s() * opposing;
        magnitude.max(0.0) * duty.signum()
    }

    /// Current against `opposing` rated loads while moving, A.
    pub fn current_a(&self, opposing: f64) -> f64 {
        (self.no_load_a + (self.rated_load_a - self.no_load_a) * opposing).max(0.0)
    }

    /// Current when blocked at duty `duty`, A.
    pub fn stall_current_a(&self, duty: f64) -> f64 {
        let droop = self.droop_mm_s();
        if droop <= 0.0 {
            return self.rated_load_a;
        }
        self.current_a(duty.abs().min(1.0) * self.no_load_speed_mm_s / droop)
    }
}

/// Where the rod is held, if it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Blocked {
    /// Moving freely (or not driven).
    No,
    /// An end switch opened: no current.
    EndSwitch,
    /// Pushing against a stroke end or an obstruction: stall current.
    Stalled,
}

/// One actuator: extension, command, load, obstruction, Hall and pot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearActuator {
    spec: ActuatorSpec,
    extension_mm: f64,
    output: Output,
    load_fraction: f64,
    /// The obstruction's extension and whether it lies beyond the rod
    /// (on the extending side) when set.
    obstruction_mm: Option<(f64, bool)>,
    hall_frozen: Option<i64>,
    time_s: f64,
}

impl LinearActuator {
    /// An actuator of `spec` at `extension_mm` (clamped to the stroke),
    /// coasting, no load.
    pub fn new(spec: ActuatorSpec, extension_mm: f64) -> Self {
        let mut a = LinearActuator {
            spec,
            extension_mm: 0.0,
            output: Output::Coast,
            load_fraction: 0.0,
            obstruction_mm: None,
            hall_frozen: None,
            time_s: 0.0,
        };
        a.extension_mm = a.clamp_stroke(extension_mm);
        a
    }

    fn clamp_stroke(&self, mm: f64) -> f64 {
        if mm.is_nan() {
            0.0
        } else {
            mm.clamp(0.0, self.spec.stroke_mm.max(0.0))
        }
    }

    /// The figures in use.
    pub fn spec(&self) -> &ActuatorSpec {
        &self.spec
    }

    /// Sets the bridge command.
    pub fn set_output(&mut self, output: Output) {
        self.output = output;
    }

    /// Load in rated loads, positive pushing the rod in (non-finite: 0).
    pub fn set_load_fraction(&mut self, load_fraction: f64) {
        self.load_fraction = if load_fraction.is_finite() {
            load_fraction
        } else {
            0.0
        };
    }

    /// An obstruction at extension `at_mm` (`None`: removed) on the side
    /// of the rod it is on when set (beyond it when equal): the rod cannot
    /// move past it towards that side, and backs off from it freely.
    pub fn set_obstruction_mm(&mut self, at_mm: Option<f64>) {
        self.obstruction_mm = at_mm
            .filter(|x| x.is_finite())
            .map(|x| (x, x >= self.extension_mm));
    }

    /// Extension from fully retracted, mm.
    pub fn extension_mm(&self) -> f64 {
        self.extension_mm
    }

    /// Time reached, s.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    /// The limit the rod would hit moving in `direction` (±1) from here:
    /// the stroke end or a nearer obstruction; `(limit, is_stroke_end)`.
    fn limit(&self, direction: f64) -> (f64, bool) {
        let end = if direction > 0.0 {
            self.spec.stroke_mm
        } else {
            0.0
        };
        match self.obstruction_mm {
            Some((o, true)) if direction > 0.0 && o < end => (o, false),
            Some((o, false)) if direction < 0.0 && o > end => (o, false),
            _ => (end, true),
        }
    }

    /// Whether, and how, the rod is held against a limit now.
    pub fn blocked(&self) -> Blocked {
        let Some(duty) = duty_of(self.output).filter(|d| *d != 0.0) else {
            return Blocked::No;
        };
        let (limit, is_end) = self.limit(duty.signum());
        // Exact: `step` stops the rod on the limit itself (`min`/`max`).
        // With a tolerance a rod a hair short of the retracted end (a
        // rounding residue of 1e-12 mm) was held there by the end switch
        // while the home switch, closed at 0 mm, read open.
        if self.extension_mm != limit {
            Blocked::No
        } else if is_end && self.spec.end_switches {
            Blocked::EndSwitch
        } else {
            Blocked::Stalled
        }
    }

    /// Rod speed now, mm/s (positive extending).
    pub fn speed_mm_s(&self) -> f64 {
        match (duty_of(self.output), self.blocked()) {
            (Some(duty), Blocked::No) => self
                .spec
                .speed_mm_s(duty, self.load_fraction * duty.signum()),
            _ => 0.0,
        }
    }

    /// Motor current now, A (signed with the drive: negative retracting).
    pub fn current_a(&self) -> f64 {
        let Some(duty) = duty_of(self.output).filter(|d| *d != 0.0) else {
            return 0.0;
        };
        let magnitude = match self.blocked() {
            Blocked::EndSwitch => 0.0,
            Blocked::Stalled => self.spec.stall_current_a(duty),
            Blocked::No if self.speed_mm_s() == 0.0 => self.spec.stall_current_a(duty),
            Blocked::No => self.spec.current_a(self.load_fraction * duty.signum()),
        };
        magnitude * duty.signum()
    }

    /// Advances by `dt_s` (ignored unless finite and > 0): exact for the
    /// constant speed, stopping at the first limit on the way.
    pub fn step(&mut self, dt_s: f64) {
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return;
        }
        let v = self.speed_mm_s();
        if v != 0.0 {
            let (limit, _) = self.limit(v.signum());
            let x = self.extension_mm + v * dt_s;
            self.extension_mm = if v > 0.0 { x.min(limit) } else { x.max(limit) };
        }
        self.time_s += dt_s;
    }

    /// Single-Hall position, pulses: `⌊extension / mm_per_pulse⌋` (a pulse
    /// starts at each multiple of it), stuck while the sensor is failed.
    pub fn hall_pulses(&self) -> i64 {
        self.hall_frozen.unwrap_or_else(|| {
            if self.spec.mm_per_pulse > 0.0 {
                libm::floor(self.extension_mm / self.spec.mm_per_pulse) as i64
            } else {
                0
            }
        })
    }

    /// The Hall output level: high over the first half of each pulse
    /// period (rising edge at each multiple of `mm_per_pulse`); stuck while
    /// failed.
    pub fn hall_level(&self) -> bool {
        if self.hall_frozen.is_some() || self.spec.mm_per_pulse <= 0.0 {
            return false;
        }
        let phase = self.extension_mm / self.spec.mm_per_pulse;
        phase - libm::floor(phase) < 0.5
    }

    /// Moves the rod to `extension_mm` (clamped to the stroke) without
    /// driving it: an external force.
    pub fn set_extension_mm(&mut self, extension_mm: f64) {
        self.extension_mm = self.clamp_stroke(extension_mm);
    }

    /// Fails the Hall sensor (no more pulses, output low) or recovers it.
    pub fn set_hall_failed(&mut self, failed: bool) {
        self.hall_frozen = None;
        if failed {
            self.hall_frozen = Some(self.hall_pulses());
        }
    }

    /// Potentiometer output, V: linear from `pot_retracted_v` to
    /// `pot_extended_v` over the stroke.
    pub fn pot_voltage_v(&self) -> f64 {
        let s = &self.spec;
        if s.stroke_mm <= 0.0 {
            return s.pot_retracted_v;
        }
        s.pot_retracted_v + (s.pot_extended_v - s.pot_retracted_v) * self.extension_mm / s.stroke_mm
    }

    /// The axis angle for this extension on `geometry` (its `stroke_mm`
    /// should be the actuator's), degrees.
    pub fn axis_deg(&self, geometry: &ActuatorGeometry) -> Result<f32, LinearError> {
        geometry.axis_deg(geometry.length_from_extension_mm(self.extension_mm as f32)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FULL_OUT: Output = Output::Forward(1_000);
    const FULL_IN: Output = Output::Backward(1_000);
    const STEP_S: f64 = 1.0e-3;

    fn la12(extension_mm: f64) -> LinearActuator {
        LinearActuator::new(ActuatorSpec::LA12_L1_12V, extension_mm)
    }

    fn run(a: &mut LinearActuator, duration_s: f64) {
        for _ in 0..libm::round(duration_s / STEP_S) as u32 {
            a.step(STEP_S);
        }
    }

    fn close(got: f64, want: f64, abs: f64) -> bool {
        (got - want).abs() <= abs
    }

    #[test]
    fn no_load_speed_and_hall_pulses_are_the_manuals() {
        let mut a = la12(10.5);
        a.set_output(FULL_OUT);
        let before = a.hall_pulses();
        run(&mut a, 1.0);
        // 26 Hz single Hall at 1 mm per pulse: 26 mm and 26 pulses in 1 s.
        assert!(close(a.extension_mm(), 36.5, 1e-6));
        assert_eq!(a.hall_pulses() - before, 26);
        assert!(close(a.current_a(), 1.0, 1e-12));
    }

    #[test]
    fn rated_load_slows_to_14_mm_s_at_5_a() {
        let mut a = la12(50.0);
        a.set_load_fraction(1.0);
        a.set_output(FULL_OUT);
        // Manual: 14 Hz (14 mm/s here) and max. 5 A under load.
        assert!(close(a.speed_mm_s(), 14.0, 1e-12));
        assert!(close(a.current_a(), 5.0, 1e-12));
        // The same load helps retraction: 26 + 12 mm/s, current down to 0.
        a.set_output(FULL_IN);
        assert!(close(a.speed_mm_s(), -38.0, 1e-12));
        assert_eq!(a.current_a(), 0.0);
    }

    #[test]
    fn end_switches_cut_the_motor_and_release_the_other_way() {
        let mut a = la12(90.0);
        a.set_output(FULL_OUT);
        run(&mut a, 1.0);
        assert_eq!(a.extension_mm(), 100.0);
        assert_eq!(
            (a.blocked(), a.current_a(), a.speed_mm_s()),
            (Blocked::EndSwitch, 0.0, 0.0)
        );
        a.set_output(FULL_IN);
        assert_eq!(a.blocked(), Blocked::No);
        assert!(close(a.speed_mm_s(), -26.0, 1e-12));
        assert!(close(a.current_a(), -1.0, 1e-12));
    }

    #[test]
    fn a_retracting_rod_stops_on_the_end_itself() {
        // 0.13 mm less five steps of 0.026 mm is 6.9e-18 mm in f64, not 0:
        // the rod must still run on to the end (where the home switch,
        // closed at 0 mm, reads it), not stop a rounding residue short.
        let mut a = la12(0.13);
        a.set_output(FULL_IN);
        run(&mut a, 0.010);
        assert_eq!(a.extension_mm(), 0.0);
        assert_eq!(a.blocked(), Blocked::EndSwitch);
    }

    #[test]
    fn a_dual_hall_shift_is_0_1875_mm() {
        // LINAK: 16 state shifts per turn of a 3 mm spindle.
        let mut a = LinearActuator::new(ActuatorSpec::LA12_DUAL_HALL_12V, 10.0);
        let before = a.hall_pulses();
        a.set_output(FULL_OUT);
        run(&mut a, 1.0);
        // 26 mm at 26 mm/s: from ⌊10 / 0.1875⌋ = 53 to ⌊36 / 0.1875⌋ = 192.
        assert_eq!((before, a.hall_pulses()), (53, 192));
    }

    #[test]
    fn without_end_switches_a_stroke_end_stalls() {
        let spec = ActuatorSpec {
            end_switches: false,
            ..ActuatorSpec::LA12_L1_12V
        };
        let mut a = LinearActuator::new(spec, 0.0);
        a.set_output(FULL_IN);
        // i_stall = 1 + 4 · 26 / 12 = 9.667 A.
        assert_eq!(a.blocked(), Blocked::Stalled);
        assert!(close(a.current_a(), -(1.0 + 4.0 * 26.0 / 12.0), 1e-9));
        // Half duty: o = 0.5 · 26 / 12, i = 1 + 4·o = 5.333 A.
        a.set_output(Output::Backward(500));
        assert!(close(a.current_a(), -(1.0 + 4.0 * 13.0 / 12.0), 1e-9));
    }

    #[test]
    fn an_obstruction_stalls_the_rod_until_removed() {
        let mut a = la12(40.0);
        a.set_obstruction_mm(Some(50.0));
        a.set_output(FULL_OUT);
        run(&mut a, 1.0); // 10 mm at 26 mm/s takes 0.385 s
        assert_eq!(a.extension_mm(), 50.0);
        assert_eq!(a.blocked(), Blocked::Stalled);
        assert!(close(a.current_a(), 1.0 + 4.0 * 26.0 / 12.0, 1e-9));
        // Backing off is free; so is going on once it is removed.
        a.set_output(FULL_IN);
        assert_eq!(a.blocked(), Blocked::No);
        a.set_output(FULL_OUT);
        a.set_obstruction_mm(None);
        run(&mut a, 0.5);
        assert!(close(a.extension_mm(), 63.0, 1e-6));
    }

    #[test]
    fn overload_past_the_stall_point_holds_at_stall_current() {
        let mut a = la12(50.0);
        a.set_load_fraction(3.0); // beyond 26 / 12 = 2.167 rated loads
        a.set_output(FULL_OUT);
        run(&mut a, 0.5);
        assert_eq!(a.extension_mm(), 50.0);
        assert!(close(a.current_a(), 1.0 + 4.0 * 26.0 / 12.0, 1e-9));
    }

    #[test]
    fn pot_voltage_is_option_k() {
        // 0.5 V retracted, 4.5 V extended, 2.5 V at mid-stroke.
        assert_eq!(la12(0.0).pot_voltage_v(), 0.5);
        assert_eq!(la12(50.0).pot_voltage_v(), 2.5);
        assert_eq!(la12(100.0).pot_voltage_v(), 4.5);
        assert_eq!(la12(150.0).pot_voltage_v(), 4.5, "clamped to the stroke");
    }

    #[test]
    fn axis_angle_through_the_geometry() {
        let g = ActuatorGeometry {
            a_mm: 300.0,
            b_mm: 150.0,
            offset_deg: 75.0,
            retracted_mm: 245.0,
            stroke_mm: 100.0,
        };
        // γ = 90° at L = √(300² + 150²) = 335.410 mm: axis 90 − 75 = 15°.
        let at_15 = la12(335.410_2 - 245.0);
        let Ok(deg) = at_15.axis_deg(&g) else {
            panic!("inside the stroke");
        };
        assert!((deg - 15.0).abs() < 0.01);
        // Retracted, L = 245: γ = acos((300² + 150² − 245²) / (2·300·150)).
        let gamma = libm::acos((90_000.0 + 22_500.0 - 60_025.0) / 90_000.0).to_degrees();
        let Ok(deg) = la12(0.0).axis_deg(&g) else {
            panic!("inside the stroke");
        };
        assert!((f64::from(deg) - (gamma - 75.0)).abs() < 0.01);
    }

    #[test]
    fn the_drivers_single_hall_counts_the_pulses_and_sees_a_failure() {
        use drivers::hall::{HallConfig, SingleHall, Watch};
        let config = HallConfig {
            stall_ms: 300,
            drive_threshold_permille: 100,
            max_idle_pulses: 3,
        };
        let Ok(mut hall) = SingleHall::new(config) else {
            panic!("valid config");
        };
        let mut a = la12(0.25);
        let start = a.hall_pulses();
        a.set_output(FULL_OUT);
        hall.set_drive(1_000, 0);
        let mut level = a.hall_level();
        let mut feed = |a: &mut LinearActuator, hall: &mut SingleHall, from_ms: u32, ms: u32| {
            for t in from_ms..from_ms + ms {
                a.step(STEP_S);
                let now = a.hall_level();
                if now && !level {
                    hall.pulse(t);
                }
                level = now;
            }
        };
        feed(&mut a, &mut hall, 0, 2_000);
        // 52 mm in 2 s at 26 mm/s, from 0.25 mm: 52 rising edges.
        assert_eq!(i64::from(hall.position()), a.hall_pulses() - start);
        assert_eq!(hall.position(), 52);
        a.set_hall_failed(true);
        feed(&mut a, &mut hall, 2_000, 1_000);
        assert!(a.extension_mm() > 70.0, "the rod still moves");
        assert_eq!(hall.position(), 52);
        assert_eq!(hall.check(3_000), Watch::Stall);
    }
}
