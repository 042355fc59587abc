//! A linear actuator on the ATmega2560 images' A (tilt) axis (`axis.a.drive`
//! `linear_pot` or `linear_hall`): a LINAK LA12 driven through the A axis's
//! IBT-2 module (two Infineon BTS7960 half bridges, read from the image's
//! registers exactly as the DC gear motor of [`crate::models::ibt2`]:
//! [`Ibt2Wiring::A`], RPWM/LPWM on OC4B/OC4C, R_EN/L_EN on PA4/PA5), its
//! rod tilting the panel through [`LA12_TILT_MOUNT`]. The physics is
//! `sim::linear_actuator::LinearActuator`'s, shared with the host
//! simulator: a speed and current that follow the load linearly, a
//! self-locking spindle (the rod stops the moment the bridge brakes or
//! coasts), built-in end switches that open the motor circuit at both
//! stroke ends.
//!
//! Figures (LINAK, *Actuator LA12 User manual*, "I/O specifications", as
//! `sim/src/linear_actuator.rs` reads them):
//!
//! - supply 12 V, at most 5 A at rated load; 26 mm/s free and 14 mm/s at
//!   rated load on the 1 mm-a-pulse spindle (the model's reading of the
//!   manual's 14–26 Hz single-Hall frequency); the 1 A no-load current is
//!   the model's assumption, and gives 9.67 A stalled at full duty;
//! - potentiometer (option K): 0.5 V fully retracted to 4.5 V fully
//!   extended over the 100 mm stroke;
//! - dual Hall, digital (LINAK, *Actuator system* user manual,
//!   "Input/output specifications"): two outputs in quadrature, 16 state
//!   shifts a spindle turn, 0.1875 mm a shift on a 3 mm spindle
//!   ([`ActuatorSpec::LA12_DUAL_HALL_12V`], an assumed LA12 with that
//!   encoder: the LA12 itself is sold with a single Hall).
//!
//! What the image sees:
//!
//! - [`LinearFeedback::Pot`] ([`ActuatorSpec::LA12_L1_12V`]): the wiper on
//!   ADC5 ([`POT_ADC_CHANNEL`], PF5, header A5), put there in mV and
//!   changed whenever the rounded mV changes (at the end of each model
//!   step), the ADC referred to AVcc = 5 V. simavr converts `mV · 1023 /
//!   5000` rounded down ([`adc_counts_at_avcc`]): 102 counts retracted,
//!   920 extended.
//! - [`LinearFeedback::Hall`] ([`ActuatorSpec::LA12_DUAL_HALL_12V`]): the
//!   pair A/B on PK6/PK7 ([`Ibt2Wiring::A`]'s `hall_bits`), the state
//!   `⌊extension / 0.1875 mm⌋` (the model's `hall_pulses`) on the levels of
//!   [`sim::encoder::FORWARD`] (the DC model's sequence: extending counts
//!   up), each edge put on its pin at the CPU cycle the rod reaches it
//!   (interpolated within a step: the speed is constant between events).
//! - The BTS7960's current sense: the conducting high side's IS pin
//!   sources `I / k_ILIS` (k_ILIS = 8,500, Infineon BTS 7960 data sheet
//!   item 4.4.6) into 1 kΩ on ADC3, from the actuator's current
//!   ([`sim::dc_motor::Bts7960Sense::TYPICAL_1K_5V`]).
//! - The home switch (PC1, active low) closed at an extension of 0 mm or
//!   less, as `sim::linear_drive::RetractedSwitch`; no high-end switch
//!   (PC3 stays open: the actuator's own end switch cuts the motor there).
//!
//! The actuator's figures are at 12 V: the bench's supply level
//! (`MegaBench::supply_at`) does not change them.

use drivers::dc_motor::Output;
use drivers::linear::ActuatorGeometry;
use sim::dc_motor::duty_of;
use sim::linear_actuator::{ActuatorSpec, LinearActuator};
use sim::linear_drive::{FeedbackKind, LA12_HALL_LOOP, LA12_TILT_MOUNT};

use crate::models::ibt2::{self, Ibt2Wiring, ADC_VREF_V};
use crate::models::quadrature::levels_of_count;

/// The potentiometer's wiper: ADC5 (PF5, the Mega's header A5).
pub const POT_ADC_CHANNEL: u8 = 5;
/// The current the bench records the actuator's rises above, A: the host
/// simulator's LA12 loops' overcurrent limit
/// (`sim::linear_drive::LA12_HALL_LOOP`, 6 A), above the 5 A at rated
/// load, below the 9.67 A stalled at full duty.
pub const CURRENT_MARK_A: f64 = LA12_HALL_LOOP.max_current_ma as f64 / 1_000.0;
/// Model steps per emulated millisecond (the rod moves at constant speed
/// between events, so one step a ms is exact; edges are interpolated).
pub const STEPS_PER_MS: u32 = 1;

/// Which of the LA12's outputs the image reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearFeedback {
    /// The potentiometer (`linear_pot`), [`ActuatorSpec::LA12_L1_12V`].
    Pot,
    /// The dual Hall pair (`linear_hall`),
    /// [`ActuatorSpec::LA12_DUAL_HALL_12V`].
    Hall,
}

impl LinearFeedback {
    /// The actuator's figures for this feedback.
    pub fn spec(self) -> ActuatorSpec {
        match self {
            LinearFeedback::Pot => ActuatorSpec::LA12_L1_12V,
            LinearFeedback::Hall => ActuatorSpec::LA12_DUAL_HALL_12V,
        }
    }

    /// The host simulator's name of the same feedback
    /// (`sim::linear_drive::la12_tilt_axis_config` takes it).
    pub fn kind(self) -> FeedbackKind {
        match self {
            LinearFeedback::Pot => FeedbackKind::Pot,
            LinearFeedback::Hall => FeedbackKind::Hall,
        }
    }
}

/// What the model puts on the image's pins at a cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearEvent {
    /// The Hall pair's levels (A, B) after an edge.
    Hall(bool, bool),
    /// The wiper's new voltage, mV.
    PotMv(u32),
}

/// The potentiometer's voltage as the bench puts it on the ADC pin, mV
/// (rounded, 0..=AVcc; not finite: 0).
pub fn pot_mv(volts: f64) -> u32 {
    if !volts.is_finite() {
        return 0;
    }
    (volts * 1_000.0).round().clamp(0.0, ADC_VREF_V * 1_000.0) as u32
}

/// The 10-bit result the image reads for `mv` on a pin with the reference
/// at AVcc = 5 V: simavr's `avr_adc.c` scales `mV · 0x3FF / Vref` (integer,
/// rounded down) and clips at 0x3FF.
pub fn adc_counts_at_avcc(mv: u32) -> u16 {
    let vref_mv = (ADC_VREF_V * 1_000.0) as u64;
    (u64::from(mv) * 0x3FF / vref_mv).min(0x3FF) as u16
}

/// The quadrature levels (A, B) of the pair for `spec` at `extension_mm`:
/// the levels of state `⌊extension / mm_per_pulse⌋` (what the model's
/// `hall_pulses` counts).
pub fn quadrature_levels(actuator: &LinearActuator) -> (bool, bool) {
    levels_of_count(actuator.hall_pulses())
}

/// The LA12 on the A axis: the bridge's wiring, the actuator, the mount,
/// the obstacle and the current rises.
#[derive(Debug, Clone)]
pub struct LinearAxisModel {
    /// The bridge's wiring ([`Ibt2Wiring::A`]).
    pub wiring: Ibt2Wiring,
    /// The feedback the image reads.
    pub feedback: LinearFeedback,
    /// The actuator.
    pub actuator: LinearActuator,
    /// The mounting: extension → axis angle.
    pub geometry: ActuatorGeometry,
    /// A current worth noting, A: [`LinearAxisModel::crossings`] lists when
    /// the current, while driven, rose above it.
    pub current_mark_a: f64,
    /// The CPU cycles at which the current rose above `current_mark_a`.
    pub crossings: Vec<u64>,
    above: bool,
    /// The bridge's command last applied.
    output: Output,
    /// An obstacle's extension (`Some`), and whether it is in the rod's
    /// way yet (it is once the rod has been at or below it).
    obstacle: Option<(f64, bool)>,
    /// The wiper voltage last put on the ADC, mV (`None`: not since a
    /// reset).
    pot_driven_mv: Option<u32>,
}

impl LinearAxisModel {
    /// The A axis's LA12 on `feedback`, on [`LA12_TILT_MOUNT`], the rod at
    /// `start_extension_mm` (0..=100 mm).
    pub fn a_axis(feedback: LinearFeedback, start_extension_mm: f64) -> Result<Self, String> {
        LinearAxisModel::new(Ibt2Wiring::A, feedback, LA12_TILT_MOUNT, start_extension_mm)
    }

    /// The actuator of `feedback` over `wiring` and `geometry` (whose
    /// stroke must be the actuator's), the rod at `start_extension_mm`.
    pub fn new(
        wiring: Ibt2Wiring,
        feedback: LinearFeedback,
        geometry: ActuatorGeometry,
        start_extension_mm: f64,
    ) -> Result<Self, String> {
        let spec = feedback.spec();
        geometry
            .validate()
            .map_err(|e| format!("linear actuator mounting {geometry:?}: {e}"))?;
        if (f64::from(geometry.stroke_mm) - spec.stroke_mm).abs() > 1e-3 {
            return Err(format!(
                "linear actuator mounting: stroke {} mm, the actuator's {} mm",
                geometry.stroke_mm, spec.stroke_mm
            ));
        }
        if !(0.0..=spec.stroke_mm).contains(&start_extension_mm) {
            return Err(format!(
                "linear actuator: start extension {start_extension_mm} mm outside the stroke 0..={} mm",
                spec.stroke_mm
            ));
        }
        Ok(LinearAxisModel {
            wiring,
            feedback,
            actuator: LinearActuator::new(spec, start_extension_mm),
            geometry,
            current_mark_a: f64::INFINITY,
            crossings: Vec::new(),
            above: false,
            output: Output::Coast,
            obstacle: None,
            pot_driven_mv: None,
        })
    }

    /// Extension from fully retracted, mm.
    pub fn extension_mm(&self) -> f64 {
        self.actuator.extension_mm()
    }

    /// The axis angle for extension `extension_mm` on the mounting:
    /// `axis_deg(retracted + extension)`, degrees.
    pub fn angle_at_mm(&self, extension_mm: f64) -> Result<f64, String> {
        let length_mm = f64::from(self.geometry.retracted_mm) + extension_mm;
        self.geometry
            .axis_deg(length_mm as f32)
            .map(f64::from)
            .map_err(|e| format!("linear actuator: extension {extension_mm} mm: {e}"))
    }

    /// The extension at axis angle `deg` on the mounting, mm.
    pub fn extension_at_deg(&self, deg: f64) -> Result<f64, String> {
        self.geometry
            .length_mm(deg as f32)
            .map(|l| f64::from(l) - f64::from(self.geometry.retracted_mm))
            .map_err(|e| format!("linear actuator: axis angle {deg}°: {e}"))
    }

    /// The axis angle now, degrees (the geometry was validated and the
    /// model keeps the rod within the stroke, where every extension has an
    /// angle: NaN would be a bug of the model).
    pub fn angle_deg(&self) -> f64 {
        self.angle_at_mm(self.extension_mm()).unwrap_or(f64::NAN)
    }

    /// The home switch (at the retracted end) is closed.
    pub fn home_closed(&self) -> bool {
        self.extension_mm() <= 0.0
    }

    /// The high-end switch: none is fitted (open).
    pub fn max_closed(&self) -> bool {
        false
    }

    /// The Hall pair's levels (A, B) now.
    pub fn hall_levels(&self) -> (bool, bool) {
        quadrature_levels(&self.actuator)
    }

    /// The wiper's voltage now, mV.
    pub fn pot_mv(&self) -> u32 {
        pot_mv(self.actuator.pot_voltage_v())
    }

    /// The inputs the image reads, as they are now, to drive at power-on
    /// and after a reset: the Hall levels or the wiper's voltage.
    pub fn inputs_now(&mut self) -> LinearEvent {
        match self.feedback {
            LinearFeedback::Hall => {
                let (a, b) = self.hall_levels();
                LinearEvent::Hall(a, b)
            }
            LinearFeedback::Pot => {
                let mv = self.pot_mv();
                self.pot_driven_mv = Some(mv);
                LinearEvent::PotMv(mv)
            }
        }
    }

    /// Puts an obstacle at extension `at_mm` (`None`: takes it away): the
    /// rod is held there coming from below. One set while the rod is above
    /// it takes effect once the rod has come back to it or below.
    pub fn set_obstacle_mm(&mut self, at_mm: Option<f64>) {
        let at_mm = at_mm.filter(|x| x.is_finite());
        if self.obstacle.map(|(x, _)| x) != at_mm {
            self.obstacle = at_mm.map(|x| (x, false));
            self.actuator.set_obstruction_mm(None);
        }
        self.arm_obstacle();
    }

    fn arm_obstacle(&mut self) {
        if let Some((x, false)) = self.obstacle {
            if self.extension_mm() <= x {
                self.actuator.set_obstruction_mm(Some(x));
                self.obstacle = Some((x, true));
            }
        }
    }

    /// The rod is driven (the bench must step it; the spindle holds it
    /// the moment the bridge brakes or coasts).
    pub fn active(&self, output: Output) -> bool {
        matches!(output, Output::Forward(_) | Output::Backward(_))
    }

    /// The IS voltage on the ADC pin, mV.
    pub fn sense_mv(&self) -> u32 {
        ibt2::sense_mv(self.output, self.actuator.current_a())
    }

    /// Runs the actuator under `output` for the `cycles` CPU cycles from
    /// `cycle0` (at `f_cpu`: emulated time = CPU time) in steps of at most
    /// 1/[`STEPS_PER_MS`] ms, and returns what to put on the pins with the
    /// cycle of each: the Hall edges (interpolated in extension within a
    /// step), or the wiper's voltage at the end of each step where its mV
    /// changed.
    pub fn advance(
        &mut self,
        output: Output,
        cycle0: u64,
        cycles: u64,
        f_cpu: u32,
    ) -> Vec<(u64, LinearEvent)> {
        self.output = output;
        self.actuator.set_output(output);
        let max_step_cycles = f64::from(f_cpu) * 1e-3 / f64::from(STEPS_PER_MS);
        let steps = ((cycles as f64 / max_step_cycles).ceil() as u64).max(1);
        let cycles_per_step = cycles as f64 / steps as f64;
        let dt_s = cycles_per_step / f64::from(f_cpu);
        let p = self.actuator.spec().mm_per_pulse;
        let mut events = Vec::new();
        for k in 0..steps {
            let (from, n0) = (self.extension_mm(), self.actuator.hall_pulses());
            self.actuator.step(dt_s);
            let (to, n1) = (self.extension_mm(), self.actuator.hall_pulses());
            self.arm_obstacle();
            let t0 = cycle0 as f64 + k as f64 * cycles_per_step;
            let at = |x: f64| {
                let frac = if to != from {
                    ((x - from) / (to - from)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (t0 + frac * cycles_per_step) as u64
            };
            // While driven: the current a high side carries, which the IS
            // pin reports.
            let above =
                duty_of(output).is_some() && self.actuator.current_a().abs() > self.current_mark_a;
            if above && !self.above {
                self.crossings.push((t0 + cycles_per_step) as u64);
            }
            self.above = above;
            match self.feedback {
                LinearFeedback::Hall if n1 > n0 => {
                    // Up: state n entered at its lower boundary n · p.
                    for n in n0 + 1..=n1 {
                        let (a, b) = levels_of_count(n);
                        events.push((at(n as f64 * p), LinearEvent::Hall(a, b)));
                    }
                }
                LinearFeedback::Hall => {
                    // Down: state n entered at its upper boundary (n + 1) · p.
                    for n in (n1..n0).rev() {
                        let (a, b) = levels_of_count(n);
                        events.push((at((n + 1) as f64 * p), LinearEvent::Hall(a, b)));
                    }
                }
                LinearFeedback::Pot => {
                    let mv = self.pot_mv();
                    if self.pot_driven_mv != Some(mv) {
                        self.pot_driven_mv = Some(mv);
                        events.push(((t0 + cycles_per_step) as u64, LinearEvent::PotMv(mv)));
                    }
                }
            }
        }
        events
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use drivers::encoder::QuadratureDecoder;

    const F_CPU: u32 = 16_000_000;
    const MS: u64 = 16_000;

    fn model(feedback: LinearFeedback, mm: f64) -> LinearAxisModel {
        match LinearAxisModel::a_axis(feedback, mm) {
            Ok(m) => m,
            Err(e) => panic!("{e}"),
        }
    }

    /// Runs `m` under `output` for `ms` emulated ms, one span a ms as the
    /// bench does; the events in order.
    fn run(m: &mut LinearAxisModel, output: Output, ms: u64) -> Vec<(u64, LinearEvent)> {
        (0..ms)
            .flat_map(|k| m.advance(output, k * MS, MS, F_CPU))
            .collect()
    }

    /// Option K: 0.5 V retracted, 4.5 V extended, linear between; on the
    /// pin in mV, and as simavr's 10-bit conversion at AVcc = 5 V gives it
    /// to the image (⌊mV · 1023 / 5000⌋).
    #[test]
    fn pot_voltage_to_adc_mv_and_counts() {
        let at = |mm| model(LinearFeedback::Pot, mm).pot_mv();
        assert_eq!(at(0.0), 500);
        assert_eq!(at(25.0), 1_500);
        assert_eq!(at(50.0), 2_500);
        assert_eq!(at(100.0), 4_500);
        // 0.5 + 4 · (100/3) / 100 = 1.8333 V.
        assert_eq!(at(100.0 / 3.0), 1_833);
        assert_eq!(adc_counts_at_avcc(500), 102);
        assert_eq!(adc_counts_at_avcc(2_500), 511);
        assert_eq!(adc_counts_at_avcc(4_500), 920);
        assert_eq!(adc_counts_at_avcc(5_000), 1_023);
        assert_eq!(adc_counts_at_avcc(6_000), 1_023);
        assert_eq!((pot_mv(f64::NAN), pot_mv(-1.0), pot_mv(9.0)), (0, 0, 5_000));
    }

    /// Extending at full duty for 1 s from 10 mm (26 mm/s free): the wiper
    /// is put on the pin each ms its mV changes (1.04 mV/ms), at the end of
    /// the ms, ending at 0.5 + 4 · 0.36 = 1.94 V.
    #[test]
    fn the_wiper_follows_the_rod_every_ms() {
        let mut m = model(LinearFeedback::Pot, 10.0);
        assert_eq!(m.inputs_now(), LinearEvent::PotMv(900));
        let events = run(&mut m, Output::Forward(1_000), 1_000);
        assert!((m.extension_mm() - 36.0).abs() < 1e-9);
        assert_eq!(events.len(), 1_000);
        assert!(events
            .iter()
            .enumerate()
            .all(|(k, (c, _))| *c == (k as u64 + 1) * MS));
        assert_eq!(events[999].1, LinearEvent::PotMv(1_940));
        assert_eq!(events[0].1, LinearEvent::PotMv(901));
        // At rest: nothing new.
        assert!(run(&mut m, Output::Brake, 10).is_empty());
    }

    /// An independent table of the pair's states, extending: 00, 10, 11,
    /// 01 (A leads B), a shift every 0.1875 mm from 0.
    fn levels_by_hand(extension_mm: f64) -> (bool, bool) {
        let state = (extension_mm / 0.1875).floor() as i64;
        [(false, false), (true, false), (true, true), (false, true)][state.rem_euclid(4) as usize]
    }

    #[test]
    fn quadrature_levels_against_extension() {
        for k in 0..=1_000 {
            let mm = f64::from(k) * 0.1;
            let m = model(LinearFeedback::Hall, mm);
            assert_eq!(m.hall_levels(), levels_by_hand(mm), "{mm} mm");
        }
        // Just either side of the first shifts.
        for (mm, want) in [
            (0.187, (false, false)),
            (0.1875, (true, false)),
            (0.374, (true, false)),
            (0.375, (true, true)),
            (0.5625, (false, true)),
            (0.75, (false, false)),
        ] {
            assert_eq!(
                model(LinearFeedback::Hall, mm).hall_levels(),
                want,
                "{mm} mm"
            );
        }
    }

    /// 1 s out at 26 mm/s from 10 mm, then 1 s back: ⌊10 / 0.1875⌋ = 53 to
    /// ⌊36 / 0.1875⌋ = 192, 139 edges each way, at the cycles the rod
    /// reaches each boundary; the repository's quadrature decoder counts
    /// them up, then down, with no error.
    #[test]
    fn hall_edges_at_their_cycles_count_up_extending() {
        let mut m = model(LinearFeedback::Hall, 10.0);
        let start = m.hall_levels();
        let out = run(&mut m, Output::Forward(1_000), 1_000);
        assert_eq!(out.len(), 139);
        // State 54 is entered at 54 · 0.1875 = 10.125 mm: 0.125 / 26 s.
        let want = (0.125 / 26.0 * f64::from(F_CPU)) as u64;
        assert!(out[0].0.abs_diff(want) <= 1, "{} vs {want}", out[0].0);
        assert!(out.windows(2).all(|w| w[1].0 > w[0].0));
        let back = run(&mut m, Output::Backward(1_000), 1_000);
        assert_eq!(back.len(), 139);
        assert!((m.extension_mm() - 10.0).abs() < 1e-9);
        let mut d = QuadratureDecoder::new(start.0, start.1);
        let mut counts = Vec::new();
        for (_, e) in out.iter().chain(&back) {
            let LinearEvent::Hall(a, b) = *e else {
                panic!("a Hall axis puts no wiper on the ADC");
            };
            d.update(a, b);
            counts.push(d.count());
        }
        assert_eq!(counts[138], 139);
        assert_eq!((d.count(), d.errors()), (0, 0));
        assert_eq!(m.hall_levels(), start);
    }

    /// The angle through the mounting against the law of cosines worked
    /// here: pivots 237 mm and 110 mm from the hinge, L = 245 + extension,
    /// γ = acos((237² + 110² − L²) / (2 · 237 · 110)), axis = γ − 172.9°.
    #[test]
    fn angle_is_the_mountings_law_of_cosines() {
        let by_hand = |mm: f64| {
            let l = 245.0 + mm;
            let cos_g = (237.0f64.powi(2) + 110.0f64.powi(2) - l * l) / (2.0 * 237.0 * 110.0);
            cos_g.acos().to_degrees() - 172.9
        };
        for mm in [0.0, 0.1875, 10.0, 33.3, 50.0, 77.7, 99.0, 100.0] {
            let got = model(LinearFeedback::Pot, mm).angle_deg();
            assert!(
                (got - by_hand(mm)).abs() < 2e-3,
                "{mm} mm: {got} vs {}",
                by_hand(mm)
            );
        }
        // The stroke's ends: −92.0° and −6.13° (sim::linear_drive's figures).
        assert!((by_hand(0.0) - -92.0).abs() < 0.01);
        assert!((by_hand(100.0) - -6.13).abs() < 0.01);
        // And back: the extension at an angle.
        let m = model(LinearFeedback::Hall, 0.0);
        let Ok(mm) = m.extension_at_deg(by_hand(40.0)) else {
            panic!("inside the stroke");
        };
        assert!((mm - 40.0).abs() < 1e-2, "{mm}");
        assert!(m.extension_at_deg(0.0).is_err());
    }

    #[test]
    fn the_current_mark_is_between_rated_load_and_stall() {
        let spec = LinearFeedback::Hall.spec();
        assert_eq!(CURRENT_MARK_A, 6.0);
        assert!(CURRENT_MARK_A > spec.rated_load_a);
        assert!(CURRENT_MARK_A < spec.stall_current_a(1.0));
    }

    #[test]
    fn bad_start_extensions_are_refused() {
        for mm in [f64::NAN, -0.1, 100.1, f64::INFINITY] {
            assert!(
                LinearAxisModel::a_axis(LinearFeedback::Pot, mm).is_err(),
                "{mm}"
            );
        }
    }

    /// Home closed at 0 mm only; the rod retracting into its end switch
    /// stops there with no current (the switch opens the motor circuit).
    #[test]
    fn home_switch_at_the_retracted_end() {
        let mut m = model(LinearFeedback::Hall, 0.5);
        assert!(!m.home_closed() && !m.max_closed());
        run(&mut m, Output::Backward(1_000), 100);
        assert_eq!(m.extension_mm(), 0.0);
        assert!(m.home_closed() && !m.max_closed());
        assert_eq!(m.sense_mv(), 0);
        run(&mut m, Output::Forward(1_000), 1);
        assert!(!m.home_closed());
    }

    /// Free at full duty: 1 A, 1 / 8,500 · 1 kΩ = 0.118 V on IS. Held by
    /// an obstacle: the stall current 1 + 4 · 26 / 12 = 9.67 A, 1.137 V,
    /// and one rise above the mark; the obstacle set while the rod is
    /// above it waits until the rod has come down to it.
    #[test]
    fn an_obstacle_stalls_the_rod_and_the_current_rises() {
        let mut m = model(LinearFeedback::Pot, 40.0);
        m.current_mark_a = 6.0;
        m.set_obstacle_mm(Some(30.0));
        run(&mut m, Output::Forward(1_000), 100);
        assert!(
            (m.extension_mm() - 42.6).abs() < 1e-9,
            "not in the way above"
        );
        assert_eq!(m.sense_mv(), 118);
        run(&mut m, Output::Backward(1_000), 1_000);
        assert!(m.extension_mm() < 30.0);
        m.set_obstacle_mm(Some(30.0));
        run(&mut m, Output::Forward(1_000), 1_000);
        assert_eq!(m.extension_mm(), 30.0);
        assert_eq!(m.sense_mv(), 1_137);
        assert_eq!(m.crossings.len(), 1);
        m.set_obstacle_mm(None);
        run(&mut m, Output::Forward(1_000), 100);
        assert!((m.extension_mm() - 32.6).abs() < 1e-9);
        assert_eq!(m.crossings.len(), 1);
    }
}
