//! Brushed DC gear motor on an H-bridge (the DC-motor tracker axis of
//! `drivers::dc_motor`): the bridge's command ([`Output`]: a duty forward or
//! backward, brake, coast) in, the motor current, speed and output angle
//! out, with the motor-shaft Hall encoder ([`HallSensor`]) and the BTS7960's
//! current-sense voltage ([`Bts7960Sense`]). `no_std`.
//!
//! # Equations
//!
//! With `V` the supply, `d` the duty (−1..1), `i` the armature current,
//! `ω` the motor-shaft speed, `N` the gear ratio and `η` its efficiency:
//!
//! ```text
//! driven:  L·di/dt = V·d − R·i − k_e·ω
//! brake:   L·di/dt =     − R·i − k_e·ω      (terminals shorted by the bridge)
//! coast:   i = 0                            (bridge off: no path for current)
//! J·dω/dt = k_t·i − T_load/(N·η) − b·ω
//! output angle = motor angle / N
//! ```
//!
//! `T_load` is the torque the load puts on the output shaft, positive
//! against positive motion; it is divided by `N·η` while the motor drives
//! it (or holds it) and multiplied by `η/N` when the load back-drives the
//! motor. The PWM is averaged: at the frequencies of the drivers (kHz) the
//! armature's L/R (below a millisecond, see below) and the rotor smooth it.
//! In coast the inductive current is taken to vanish at once (it actually
//! flows back through the bridge's body diodes for about L/R), and the motor
//! is assumed never to be spun faster than its supply's no-load speed, so
//! the diodes never rectify a generated voltage.
//!
//! An obstruction is a load torque ([`DcMotor::set_load_torque_nm`]) or hard
//! stops at output angles ([`DcMotor::set_hard_stops_deg`]): at a stop the
//! output stays put while the motor pushes into it, the back EMF vanishes and
//! the current rises to the stall current `V·d/R`: the model's current is
//! what a current sense watches for a jam.
//!
//! # Integration and its stability
//!
//! Fixed steps of `dt` ([`DEFAULT_STEP_S`] = 10 µs), backward (implicit)
//! Euler on the two coupled linear equations, the load torque held over
//! the step:
//!
//! ```text
//! (L/dt + R)·i' + k_e·ω'     = V·d + (L/dt)·i
//! −k_t·i'      + (J/dt + b)·ω' = (J/dt)·ω − T
//! ```
//!
//! solved by Cramer's rule; the determinant `(L/dt + R)(J/dt + b) + k_e·k_t`
//! is positive for every `dt > 0`. The system matrix has eigenvalues with
//! negative real parts (R, b ≥ 0, k_t·k_e > 0), and backward Euler maps
//! each of them into the unit circle for any step, so the step is stable
//! however small L/R is (an explicit step would need `dt < 2·L/R`, 0.9 ms
//! here, and would ring near it). Accuracy is another matter: backward
//! Euler's decay per step is `1/(1 + dt/τ)` instead of `e^(−dt/τ)`, so with
//! the electrical time constant `τ_e = L/R` = 0.46 ms of the Pololu preset
//! and dt = 10 µs = τ_e/46, the current after one τ_e is within 1 % of the
//! exact first-order value (the tests hold it to that).
//!
//! # Figures: Pololu 37D 131.25:1, 12 V ([`MotorSpec::pololu_37d_131_12v`])
//!
//! Pololu, *37D Metal Gearmotors* data sheet (performance summary table)
//! and the product page of the 37Dx52L gearmotor with 64 CPR encoder
//! (pololu.com/product/1442, its table of versions): at 12 V the motor
//! alone (1:1, no gearbox) runs at **10,000 rpm no load, 0.15 A no-load
//! current, 5.5 A stall current, 0.5 kg·cm extrapolated stall torque**;
//! the **131.25:1** version gives **76 rpm** no load and **45 kg·cm** stall
//! torque; the encoder gives **64 counts per revolution of the motor shaft**
//! (quadrature, both edges of both channels). Derived:
//!
//! ```text
//! R   = V / I_stall           = 12 / 5.5                 = 2.1818 Ω
//! k_t = T_stall / I_stall     = 0.5·0.0980665 / 5.5      = 8.9151·10⁻³ N·m/A
//! ω₀  = 10,000 rpm · 2π / 60                             = 1,047.20 rad/s
//! k_e = (V − R·I₀) / ω₀       = (12 − 0.32727) / 1,047.20 = 1.11467·10⁻² V·s/rad
//! b   = k_t·I₀ / ω₀           = 1.33727·10⁻³ / 1,047.20  = 1.27700·10⁻⁶ N·m·s/rad
//! η   = 45 / (0.5 · 131.25)                              = 0.6857
//! output counts = 64 · 131.25                            = 8,400 per revolution
//! ```
//!
//! (the no-load current is all viscous friction at ω₀, so no-load speed and
//! current come back exactly in steady state; k_e and k_t differ by 25 %,
//! as extrapolated catalogue figures of small gear motors often do: they are
//! kept apart rather than averaged). Pololu publishes neither the armature
//! inductance nor the rotor inertia: **L = 1 mH** and **J = 5·10⁻⁶ kg·m²**
//! are assumptions of the order of a 35 mm can motor (a 60 g rotor of
//! 13 mm radius: ½·0.060·0.013² = 5.1·10⁻⁶ kg·m²), fields to set from a
//! measurement; they give τ_e = L/R = 0.46 ms and the mechanical time
//! constant τ_m = J·R / (k_t·k_e + R·b) = 0.107 s.

use drivers::dc_motor::Output;

use crate::encoder::{levels_of_count, Edge, QuadratureEncoder};

/// The integration step the presets are checked at, s (see the module
/// documentation: τ_e / 46 for the Pololu preset).
pub const DEFAULT_STEP_S: f64 = 1.0e-5;

/// Newton-metres per kilogram-force centimetre (catalogue torque unit).
pub const NM_PER_KGF_CM: f64 = 0.098_066_5;

/// Radians per second per revolution per minute.
pub const RAD_S_PER_RPM: f64 = core::f64::consts::PI / 30.0;

/// The catalogue figures of a gear motor at its rated voltage, from which
/// [`MotorSpec::from_figures`] derives the model parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorFigures {
    /// Rated (supply) voltage, V.
    pub rated_v: f64,
    /// No-load speed of the motor shaft, rpm.
    pub no_load_motor_rpm: f64,
    /// No-load current, A.
    pub no_load_a: f64,
    /// Stall current, A.
    pub stall_a: f64,
    /// Stall torque of the motor alone (no gearbox), N·m.
    pub motor_stall_nm: f64,
    /// Gear ratio, motor revolutions per output revolution.
    pub gear_ratio: f64,
    /// Stall torque at the gearbox output, N·m.
    pub output_stall_nm: f64,
    /// Quadrature counts per motor revolution of the motor-shaft encoder.
    pub encoder_counts_per_rev: u32,
}

/// Model parameters of a gear motor (motor-shaft quantities unless named
/// `output`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorSpec {
    /// Supply voltage at full duty, V.
    pub supply_v: f64,
    /// Armature resistance, Ω.
    pub resistance_ohm: f64,
    /// Armature inductance, H (> 0).
    pub inductance_h: f64,
    /// Torque constant, N·m/A.
    pub k_t_nm_a: f64,
    /// Back-EMF constant, V·s/rad.
    pub k_e_v_s_rad: f64,
    /// Rotor inertia plus everything reflected to the motor shaft, kg·m² (> 0).
    pub inertia_kg_m2: f64,
    /// Viscous friction at the motor shaft, N·m·s/rad.
    pub viscous_nm_s_rad: f64,
    /// Gear ratio, motor revolutions per output revolution (> 0).
    pub gear_ratio: f64,
    /// Gearbox efficiency, 0..1.
    pub gear_efficiency: f64,
    /// Quadrature counts per motor revolution of the motor-shaft encoder.
    pub encoder_counts_per_rev: u32,
}

/// Pololu 37D, 12 V motor, 131.25:1 gearbox, 64 CPR encoder (module
/// documentation).
pub const POLOLU_37D_131_12V: MotorFigures = MotorFigures {
    rated_v: 12.0,
    no_load_motor_rpm: 10_000.0,
    no_load_a: 0.15,
    stall_a: 5.5,
    motor_stall_nm: 0.5 * NM_PER_KGF_CM,
    gear_ratio: 131.25,
    output_stall_nm: 45.0 * NM_PER_KGF_CM,
    encoder_counts_per_rev: 64,
};

impl MotorSpec {
    /// Parameters from catalogue figures plus the two a catalogue rarely
    /// gives (inductance, inertia); the arithmetic is the module
    /// documentation's.
    pub fn from_figures(f: &MotorFigures, inductance_h: f64, inertia_kg_m2: f64) -> Self {
        let resistance_ohm = f.rated_v / f.stall_a;
        let k_t_nm_a = f.motor_stall_nm / f.stall_a;
        let no_load_rad_s = f.no_load_motor_rpm * RAD_S_PER_RPM;
        MotorSpec {
            supply_v: f.rated_v,
            resistance_ohm,
            inductance_h,
            k_t_nm_a,
            k_e_v_s_rad: (f.rated_v - resistance_ohm * f.no_load_a) / no_load_rad_s,
            inertia_kg_m2,
            viscous_nm_s_rad: k_t_nm_a * f.no_load_a / no_load_rad_s,
            gear_ratio: f.gear_ratio,
            gear_efficiency: f.output_stall_nm / (f.motor_stall_nm * f.gear_ratio),
            encoder_counts_per_rev: f.encoder_counts_per_rev,
        }
    }

    /// The Pololu 37D 131.25:1 at 12 V with the assumed L = 1 mH and
    /// J = 5·10⁻⁶ kg·m².
    pub fn pololu_37d_131_12v() -> Self {
        Self::from_figures(&POLOLU_37D_131_12V, 1.0e-3, 5.0e-6)
    }

    /// The same motor driving through a further stage, e.g. the worm of a
    /// slew drive: ratios multiply, efficiencies multiply. Ratios that are
    /// not finite and positive, and efficiencies outside 0..1, leave the
    /// spec unchanged. (No slew-drive preset: no published ratio and
    /// efficiency of one were at hand; take them from its data sheet.)
    pub fn with_output_stage(mut self, ratio: f64, efficiency: f64) -> Self {
        if ratio.is_finite() && ratio > 0.0 && (0.0..=1.0).contains(&efficiency) {
            self.gear_ratio *= ratio;
            self.gear_efficiency *= efficiency;
        }
        self
    }

    /// Adds a load inertia at the output (the axis and its panels),
    /// reflected to the motor shaft as `J_out / N²`. Non-finite or negative
    /// values leave the spec unchanged.
    pub fn with_output_inertia_kg_m2(mut self, output_kg_m2: f64) -> Self {
        if output_kg_m2.is_finite() && output_kg_m2 >= 0.0 && self.gear_ratio > 0.0 {
            self.inertia_kg_m2 += output_kg_m2 / (self.gear_ratio * self.gear_ratio);
        }
        self
    }

    /// Stall current at full duty, `V / R`, A.
    pub fn stall_current_a(&self) -> f64 {
        self.supply_v / self.resistance_ohm
    }

    /// Stall torque at the output at full duty, `N·η·k_t·V/R`, N·m.
    pub fn output_stall_torque_nm(&self) -> f64 {
        self.gear_ratio * self.gear_efficiency * self.k_t_nm_a * self.stall_current_a()
    }

    /// Steady no-load motor speed at full duty,
    /// `V·k_t / (R·b + k_e·k_t)`, rad/s.
    pub fn no_load_motor_rad_s(&self) -> f64 {
        self.supply_v * self.k_t_nm_a
            / (self.resistance_ohm * self.viscous_nm_s_rad + self.k_e_v_s_rad * self.k_t_nm_a)
    }

    /// Electrical time constant `L / R`, s.
    pub fn electrical_time_constant_s(&self) -> f64 {
        self.inductance_h / self.resistance_ohm
    }

    /// Mechanical time constant (L neglected) `J·R / (k_t·k_e + R·b)`, s.
    pub fn mechanical_time_constant_s(&self) -> f64 {
        self.inertia_kg_m2 * self.resistance_ohm
            / (self.k_t_nm_a * self.k_e_v_s_rad + self.resistance_ohm * self.viscous_nm_s_rad)
    }
}

/// Signed duty of a bridge command, −1..1 (`None` for brake and coast).
pub fn duty_of(output: Output) -> Option<f64> {
    match output {
        Output::Forward(p) => Some(f64::from(p.min(1_000)) / 1_000.0),
        Output::Backward(p) => Some(-f64::from(p.min(1_000)) / 1_000.0),
        Output::Brake | Output::Coast => None,
    }
}

/// The motor-shaft Hall encoder: quadrature counts per motor revolution,
/// the channel levels, single-channel pulses, and a `failed` switch that
/// freezes the outputs (no more pulses) for fault scenarios.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HallSensor {
    encoder: QuadratureEncoder,
    /// The count the outputs are stuck at, while failed.
    frozen: Option<i64>,
}

impl HallSensor {
    /// A sensor of `counts_per_rev` quadrature counts per motor revolution
    /// (rounded down to whole lines of 4 counts, at least one line).
    pub fn new(counts_per_rev: u32) -> Self {
        HallSensor {
            encoder: QuadratureEncoder::new((counts_per_rev / 4).max(1)),
            frozen: None,
        }
    }

    /// Quadrature counts per motor revolution (4 per line).
    pub fn counts_per_rev(&self) -> u32 {
        self.encoder.counts_per_rev()
    }

    /// Pulses of one channel per motor revolution (lines).
    pub fn pulses_per_rev(&self) -> u32 {
        self.encoder.lines_per_rev()
    }

    /// Quadrature count at motor angle `motor_deg` (floor semantics of
    /// [`crate::encoder`]), or the stuck count while failed.
    pub fn count_at(&self, motor_deg: f64) -> i64 {
        self.frozen
            .unwrap_or_else(|| self.encoder.count_at(motor_deg))
    }

    /// Channel levels `(A, B)` at `motor_deg`.
    pub fn levels_at(&self, motor_deg: f64) -> (bool, bool) {
        levels_of_count(self.count_at(motor_deg))
    }

    /// Single-channel position: rising edges of A from angle 0 (A rises
    /// entering counts 1, 5, 9, …, so this is `⌊(count + 3) / 4⌋`).
    pub fn pulses_at(&self, motor_deg: f64) -> i64 {
        (self.count_at(motor_deg) + 3).div_euclid(4)
    }

    /// The channel edges, in order, while the motor shaft turns
    /// monotonically from `from_motor_deg` to `to_motor_deg`
    /// ([`QuadratureEncoder::edges`]: one channel changes per edge); none
    /// while failed.
    pub fn edges(&self, from_motor_deg: f64, to_motor_deg: f64) -> impl Iterator<Item = Edge> + '_ {
        let live = self.frozen.is_none();
        self.encoder
            .edges(from_motor_deg, to_motor_deg)
            .filter(move |_| live)
    }

    /// Fails (outputs stuck at their levels at `motor_deg`) or recovers.
    pub fn set_failed(&mut self, failed: bool, motor_deg: f64) {
        self.frozen = if failed {
            Some(self.count_at(motor_deg))
        } else {
            None
        };
    }

    /// Whether the sensor is failed.
    pub fn is_failed(&self) -> bool {
        self.frozen.is_some()
    }
}

/// The BTS7960's current sense (IBT-2 module) as a voltage on an ADC pin:
/// `I_IS = I_load / k_ILIS` into `R_IS`, clamped at the supply of the sense
/// pin. Infineon, *BTS 7960* data sheet, section 4.4 "Current sense"
/// (k_ILIS typically 8.5·10³), the figures `drivers::dc_motor::bts7960`
/// reads it back with. Only a conducting high side sources sense current:
/// while braking (both low sides on) or coasting the pin reads 0 V.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bts7960Sense {
    /// Load current to sense current ratio.
    pub k_ilis: f64,
    /// Sense resistor, Ω.
    pub r_is_ohm: f64,
    /// The voltage the pin cannot exceed (the logic supply), V.
    pub clamp_v: f64,
}

impl Bts7960Sense {
    /// k_ILIS = 8,500 (typical), R_IS = 1 kΩ (the data sheet's test
    /// resistor), clamped at 5 V.
    pub const TYPICAL_1K_5V: Bts7960Sense = Bts7960Sense {
        k_ilis: 8_500.0,
        r_is_ohm: 1_000.0,
        clamp_v: 5.0,
    };

    /// IS voltage for a motor current `current_a` under bridge command
    /// `output`, V (0..`clamp_v`).
    pub fn is_voltage_v(&self, output: Output, current_a: f64) -> f64 {
        if duty_of(output).is_none() || !current_a.is_finite() || self.k_ilis <= 0.0 {
            return 0.0;
        }
        (current_a.abs() / self.k_ilis * self.r_is_ohm).clamp(0.0, self.clamp_v.max(0.0))
    }

    /// The same voltage as ADC counts for a reference `vref_v` and
    /// `full_scale` counts (rounded down, clamped to `full_scale`).
    pub fn adc_counts(&self, output: Output, current_a: f64, vref_v: f64, full_scale: u16) -> u16 {
        if vref_v <= 0.0 {
            return 0;
        }
        let counts = self.is_voltage_v(output, current_a) / vref_v * f64::from(full_scale);
        libm::floor(counts.clamp(0.0, f64::from(full_scale))) as u16
    }
}

/// A gear motor on an H-bridge: current, speed, angles, obstruction, Hall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DcMotor {
    spec: MotorSpec,
    output: Output,
    current_a: f64,
    motor_rad_s: f64,
    motor_rad: f64,
    load_nm: f64,
    /// Output-angle stops `(low, high)`, degrees.
    stops_deg: Option<(f64, f64)>,
    time_s: f64,
    /// The motor-shaft Hall encoder.
    pub hall: HallSensor,
}

impl DcMotor {
    /// A motor at rest at output angle 0, bridge coasting, no load.
    pub fn new(spec: MotorSpec) -> Self {
        DcMotor {
            spec,
            output: Output::Coast,
            current_a: 0.0,
            motor_rad_s: 0.0,
            motor_rad: 0.0,
            load_nm: 0.0,
            stops_deg: None,
            time_s: 0.0,
            hall: HallSensor::new(spec.encoder_counts_per_rev),
        }
    }

    /// The parameters in use.
    pub fn spec(&self) -> &MotorSpec {
        &self.spec
    }

    /// Sets the supply voltage at full duty, V (from the next step on;
    /// non-finite or negative values are taken as 0): a battery's charge,
    /// a long cable.
    pub fn set_supply_v(&mut self, supply_v: f64) {
        self.spec.supply_v = if supply_v.is_finite() && supply_v > 0.0 {
            supply_v
        } else {
            0.0
        };
    }

    /// Sets the bridge command (from the next step on).
    pub fn set_output(&mut self, output: Output) {
        self.output = output;
        if output == Output::Coast {
            self.current_a = 0.0;
        }
    }

    /// The bridge command in use.
    pub fn output(&self) -> Output {
        self.output
    }

    /// Load torque on the output shaft, N·m, positive against positive
    /// motion (0 = no load); non-finite values are taken as 0.
    pub fn set_load_torque_nm(&mut self, load_nm: f64) {
        self.load_nm = if load_nm.is_finite() { load_nm } else { 0.0 };
    }

    /// Hard stops at output angles `low_deg ≤ high_deg` (`None`: free).
    pub fn set_hard_stops_deg(&mut self, stops_deg: Option<(f64, f64)>) {
        self.stops_deg = stops_deg.filter(|(lo, hi)| lo <= hi);
    }

    /// Armature current, A (positive: driving forward).
    pub fn current_a(&self) -> f64 {
        self.current_a
    }

    /// Motor-shaft speed, rad/s.
    pub fn motor_speed_rad_s(&self) -> f64 {
        self.motor_rad_s
    }

    /// Output-shaft speed, rpm.
    pub fn output_speed_rpm(&self) -> f64 {
        self.motor_rad_s / self.spec.gear_ratio / RAD_S_PER_RPM
    }

    /// Motor-shaft angle, degrees.
    pub fn motor_angle_deg(&self) -> f64 {
        self.motor_rad.to_degrees()
    }

    /// Output-shaft angle, degrees.
    pub fn output_angle_deg(&self) -> f64 {
        self.motor_angle_deg() / self.spec.gear_ratio
    }

    /// Sets the output angle (the motor angle follows), e.g. a start pose.
    pub fn set_output_angle_deg(&mut self, output_deg: f64) {
        self.motor_rad = (output_deg * self.spec.gear_ratio).to_radians();
    }

    /// Torque the motor makes, `k_t·i`, N·m.
    pub fn motor_torque_nm(&self) -> f64 {
        self.spec.k_t_nm_a * self.current_a
    }

    /// Time reached, s.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    /// Hall quadrature count now.
    pub fn hall_count(&self) -> i64 {
        self.hall.count_at(self.motor_angle_deg())
    }

    /// Hall levels `(A, B)` now.
    pub fn hall_levels(&self) -> (bool, bool) {
        self.hall.levels_at(self.motor_angle_deg())
    }

    /// Hall single-channel pulse position now.
    pub fn hall_pulses(&self) -> i64 {
        self.hall.pulses_at(self.motor_angle_deg())
    }

    /// Fails or recovers the Hall sensor at the present angle.
    pub fn set_hall_failed(&mut self, failed: bool) {
        let deg = self.motor_angle_deg();
        self.hall.set_failed(failed, deg);
    }

    /// Load torque reflected to the motor shaft for motion `motor_rad_s`.
    fn reflected_load_nm(&self) -> f64 {
        let s = &self.spec;
        let backdriven = self.load_nm * self.motor_rad_s < 0.0;
        if backdriven {
            self.load_nm * s.gear_efficiency / s.gear_ratio
        } else if s.gear_efficiency > 0.0 {
            self.load_nm / (s.gear_ratio * s.gear_efficiency)
        } else {
            0.0
        }
    }

    /// One backward-Euler step of `dt_s` (ignored unless finite and > 0).
    pub fn step(&mut self, dt_s: f64) {
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return;
        }
        let s = self.spec;
        let t_nm = self.reflected_load_nm();
        let m = s.inertia_kg_m2 / dt_s + s.viscous_nm_s_rad;
        let (mut i1, mut w1) = if self.output == Output::Coast {
            (0.0, (s.inertia_kg_m2 / dt_s * self.motor_rad_s - t_nm) / m)
        } else {
            // Brake: the terminals shorted, no applied voltage.
            let v = s.supply_v * duty_of(self.output).unwrap_or(0.0);
            let e = s.inductance_h / dt_s + s.resistance_ohm;
            let r1 = v + s.inductance_h / dt_s * self.current_a;
            let r2 = s.inertia_kg_m2 / dt_s * self.motor_rad_s - t_nm;
            let det = e * m + s.k_e_v_s_rad * s.k_t_nm_a;
            (
                (r1 * m - s.k_e_v_s_rad * r2) / det,
                (e * r2 + s.k_t_nm_a * r1) / det,
            )
        };
        let mut angle = self.motor_rad + w1 * dt_s;
        if let Some((lo_deg, hi_deg)) = self.stops_deg {
            let lo = (lo_deg * s.gear_ratio).to_radians();
            let hi = (hi_deg * s.gear_ratio).to_radians();
            let blocked = (angle >= hi && w1 > 0.0) || (angle <= lo && w1 < 0.0);
            if blocked {
                angle = angle.clamp(lo, hi);
                w1 = 0.0;
                // The shaft is held: the current follows the electrical
                // equation alone, with no back EMF.
                if let Some(duty) = duty_of(self.output) {
                    let e = s.inductance_h / dt_s + s.resistance_ohm;
                    i1 = (s.supply_v * duty + s.inductance_h / dt_s * self.current_a) / e;
                } else if self.output == Output::Brake {
                    let e = s.inductance_h / dt_s + s.resistance_ohm;
                    i1 = s.inductance_h / dt_s * self.current_a / e;
                }
            }
        }
        self.current_a = i1;
        self.motor_rad_s = w1;
        self.motor_rad = angle;
        self.time_s += dt_s;
    }

    /// Steps of `step_s` (the last one shortened) until `duration_s` more
    /// has passed.
    pub fn run_for(&mut self, duration_s: f64, step_s: f64) {
        if !(duration_s.is_finite() && step_s.is_finite() && step_s > 0.0) {
            return;
        }
        let end = self.time_s + duration_s;
        while self.time_s < end {
            let dt = step_s.min(end - self.time_s);
            if dt <= step_s * 1e-9 {
                break;
            }
            self.step(dt);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FULL: Output = Output::Forward(1_000);

    fn motor() -> DcMotor {
        DcMotor::new(MotorSpec::pololu_37d_131_12v())
    }

    fn close(got: f64, want: f64, rel: f64) -> bool {
        (got - want).abs() <= rel * want.abs()
    }

    #[test]
    fn parameters_follow_from_the_published_figures() {
        let s = MotorSpec::pololu_37d_131_12v();
        // R = 12 / 5.5, k_t = 0.5 kgf·cm / 5.5 A, η = 45 / (0.5 · 131.25).
        assert!(close(s.resistance_ohm, 2.181_818, 1e-6));
        assert!(close(s.k_t_nm_a, 0.049_033_25 / 5.5, 1e-9));
        assert!(close(s.gear_efficiency, 45.0 / 65.625, 1e-9));
        // k_e = (12 − 2.1818·0.15) / 1047.1976.
        assert!(close(s.k_e_v_s_rad, 11.672_727 / 1_047.197_6, 1e-6));
        assert!(close(
            s.electrical_time_constant_s(),
            1.0e-3 / 2.181_818,
            1e-6
        ));
        // 64 CPR on the motor shaft: 64 · 131.25 = 8,400 per output turn.
        assert_eq!(f64::from(s.encoder_counts_per_rev) * s.gear_ratio, 8_400.0);
    }

    #[test]
    fn no_load_speed_and_current_are_the_catalogue_figures() {
        let mut m = motor();
        m.set_output(FULL);
        m.run_for(1.0, DEFAULT_STEP_S); // ≈ 10 τ_m
                                        // Pololu: 10,000 rpm and 0.15 A free run (motor), 76 rpm (131:1).
        assert!(close(
            m.motor_speed_rad_s(),
            10_000.0 * RAD_S_PER_RPM,
            0.002
        ));
        assert!(close(m.current_a(), 0.15, 0.01));
        assert!(close(m.output_speed_rpm(), 76.0, 0.01));
    }

    #[test]
    fn speed_scales_with_duty_and_turns_with_its_sign() {
        let mut m = motor();
        m.set_output(Output::Backward(500));
        m.run_for(1.0, DEFAULT_STEP_S);
        // ω = d·V·k_t / (R·b + k_e·k_t) = d · 10,000 rpm, current −d·0.15 A.
        assert!(close(
            m.motor_speed_rad_s(),
            -5_000.0 * RAD_S_PER_RPM,
            0.002
        ));
        assert!(close(m.current_a(), -0.075, 0.01));
        assert!(m.output_angle_deg() < 0.0);
    }

    #[test]
    fn a_hard_stop_gives_the_stall_current_and_torque() {
        let mut m = motor();
        m.set_hard_stops_deg(Some((-10.0, 0.0)));
        m.set_output(FULL);
        m.run_for(0.02, DEFAULT_STEP_S); // ≈ 44 τ_e
        assert_eq!(m.output_angle_deg(), 0.0);
        // Pololu: 5.5 A stall; 45 kg·cm at the 131.25:1 output.
        assert!(close(m.current_a(), 5.5, 1e-3));
        let output_nm = m.motor_torque_nm() * m.spec().gear_ratio * m.spec().gear_efficiency;
        assert!(close(output_nm, 45.0 * NM_PER_KGF_CM, 1e-3));
        assert!(close(
            m.spec().output_stall_torque_nm(),
            45.0 * NM_PER_KGF_CM,
            1e-9
        ));
    }

    #[test]
    fn current_rises_with_the_electrical_time_constant() {
        let mut m = motor();
        m.set_hard_stops_deg(Some((0.0, 0.0)));
        m.set_output(FULL);
        let tau = m.spec().electrical_time_constant_s();
        m.run_for(tau, DEFAULT_STEP_S);
        // i(τ_e) = I_stall · (1 − e⁻¹) for a blocked rotor.
        assert!(close(m.current_a(), 5.5 * (1.0 - libm::exp(-1.0)), 0.01));
    }

    #[test]
    fn speed_rises_with_the_mechanical_time_constant() {
        let mut m = motor();
        m.set_output(FULL);
        let tau = m.spec().mechanical_time_constant_s();
        m.run_for(tau, DEFAULT_STEP_S);
        // ω(τ_m) = ω₀ · (1 − e⁻¹), L neglected (τ_e / τ_m ≈ 0.5 %).
        let w0 = 10_000.0 * RAD_S_PER_RPM;
        assert!(close(
            m.motor_speed_rad_s(),
            w0 * (1.0 - libm::exp(-1.0)),
            0.02
        ));
    }

    #[test]
    fn energy_balances_and_the_supply_delivers_it() {
        let mut m = motor();
        let s = *m.spec();
        m.set_output(FULL);
        let (mut input_j, mut copper_j, mut emf_j, mut shaft_j, mut friction_j) =
            (0.0, 0.0, 0.0, 0.0, 0.0);
        for _ in 0..30_000 {
            m.step(DEFAULT_STEP_S);
            let (i, w) = (m.current_a(), m.motor_speed_rad_s());
            input_j += s.supply_v * i * DEFAULT_STEP_S;
            copper_j += s.resistance_ohm * i * i * DEFAULT_STEP_S;
            emf_j += s.k_e_v_s_rad * w * i * DEFAULT_STEP_S;
            shaft_j += s.k_t_nm_a * i * w * DEFAULT_STEP_S;
            friction_j += s.viscous_nm_s_rad * w * w * DEFAULT_STEP_S;
        }
        let (i, w) = (m.current_a(), m.motor_speed_rad_s());
        assert!(input_j > 0.0 && emf_j > 0.0, "driving draws power");
        // Electrical: ∫V·i = ∫R·i² + ∫k_e·ω·i + ½·L·i².
        let electrical = copper_j + emf_j + 0.5 * s.inductance_h * i * i;
        assert!(close(electrical, input_j, 0.01));
        // Mechanical: ∫k_t·i·ω = ½·J·ω² + ∫b·ω².
        let mechanical = 0.5 * s.inertia_kg_m2 * w * w + friction_j;
        assert!(close(mechanical, shaft_j, 0.01));
    }

    #[test]
    fn braking_stops_with_tau_m_coasting_with_the_friction() {
        let w0 = 10_000.0 * RAD_S_PER_RPM;
        let mut free = motor();
        free.set_output(FULL);
        free.run_for(1.0, DEFAULT_STEP_S);
        let (w_start, tau_m) = (
            free.motor_speed_rad_s(),
            free.spec().mechanical_time_constant_s(),
        );
        assert!(close(w_start, w0, 0.002));

        let mut braked = free;
        braked.set_output(Output::Brake);
        // Within τ_e the current swings from +0.15 A towards −k_e·ω₀/R.
        let tau_e = braked.spec().electrical_time_constant_s();
        braked.run_for(tau_e, DEFAULT_STEP_S);
        assert!(
            braked.current_a() < -1.0,
            "braking current opposes the motion"
        );
        braked.run_for(tau_m - tau_e, DEFAULT_STEP_S);
        // Shorted: ω(t) = ω₀·e^(−t/τ_m) (L neglected).
        assert!(close(
            braked.motor_speed_rad_s(),
            w_start * libm::exp(-1.0),
            0.03
        ));

        let mut coasted = free;
        coasted.set_output(Output::Coast);
        coasted.run_for(tau_m, DEFAULT_STEP_S);
        assert_eq!(coasted.current_a(), 0.0);
        // Open: ω(t) = ω₀·e^(−t·b/J), only the viscous friction slows it.
        let s = coasted.spec();
        let want = w_start * libm::exp(-tau_m * s.viscous_nm_s_rad / s.inertia_kg_m2);
        assert!(close(coasted.motor_speed_rad_s(), want, 0.001));
        assert!(coasted.motor_speed_rad_s() > 2.0 * braked.motor_speed_rad_s());
    }

    #[test]
    fn a_load_torque_raises_the_current_to_its_closed_form() {
        let mut m = motor();
        let s = *m.spec();
        m.set_load_torque_nm(2.0);
        m.set_output(FULL);
        m.run_for(1.0, DEFAULT_STEP_S);
        // Steady: i = (T_m·k_e + b·V) / (k_t·k_e + b·R), T_m = T / (N·η).
        let t_m = 2.0 / (s.gear_ratio * s.gear_efficiency);
        let want = (t_m * s.k_e_v_s_rad + s.viscous_nm_s_rad * s.supply_v)
            / (s.k_t_nm_a * s.k_e_v_s_rad + s.viscous_nm_s_rad * s.resistance_ohm);
        assert!(close(m.current_a(), want, 0.002));
        assert!(m.motor_speed_rad_s() > 0.0);
    }

    #[test]
    fn a_further_stage_divides_the_speed_and_multiplies_the_torque() {
        let base = MotorSpec::pololu_37d_131_12v();
        // A 60:1 stage of 40 % efficiency after the gearbox (illustrative
        // worm figures, not a product's).
        let s = base.with_output_stage(60.0, 0.4);
        assert!(close(s.gear_ratio, 131.25 * 60.0, 1e-12));
        assert!(close(
            s.output_stall_torque_nm(),
            45.0 * NM_PER_KGF_CM * 24.0,
            1e-9
        ));
        let mut m = DcMotor::new(s);
        m.set_output(FULL);
        m.run_for(1.0, DEFAULT_STEP_S);
        // 10,000 rpm / 7,875 = 1.27 rpm at the output.
        assert!(close(m.output_speed_rpm(), 10_000.0 / 7_875.0, 0.002));
        // An axis of 50 kg·m² adds 50 / 7,875² = 8.06·10⁻⁷ kg·m² at the motor.
        let j = s.with_output_inertia_kg_m2(50.0).inertia_kg_m2;
        assert!(close(j - s.inertia_kg_m2, 50.0 / (7_875.0 * 7_875.0), 1e-9));
        assert_eq!(base.with_output_stage(f64::NAN, 0.5), base);
        assert_eq!(base.with_output_stage(10.0, 1.5), base);
    }

    #[test]
    fn an_obstruction_switched_on_and_off() {
        let mut m = motor();
        m.set_output(FULL);
        m.run_for(0.5, DEFAULT_STEP_S);
        let here = m.output_angle_deg();
        m.set_hard_stops_deg(Some((-1_000.0, here + 0.5)));
        m.run_for(0.2, DEFAULT_STEP_S);
        assert!(close(m.output_angle_deg(), here + 0.5, 1e-9));
        assert!(close(m.current_a(), 5.5, 1e-3));
        m.set_hard_stops_deg(None);
        m.run_for(1.0, DEFAULT_STEP_S);
        assert!(close(m.current_a(), 0.15, 0.01));
        assert!(m.output_angle_deg() > here + 1.0);
    }

    #[test]
    fn hall_counts_a_known_move_and_a_failed_sensor_stops() {
        let mut m = motor();
        assert_eq!(m.hall.pulses_per_rev(), 16);
        // One output turn = 131.25 motor turns = 8,400 counts = 2,100 pulses.
        m.set_output_angle_deg(360.0);
        assert_eq!(m.hall_count(), 8_400);
        assert_eq!(m.hall_pulses(), 2_100);
        m.set_output_angle_deg(0.0);
        m.set_hall_failed(true);
        m.set_output(FULL);
        m.run_for(0.3, DEFAULT_STEP_S);
        assert!(m.output_angle_deg() > 10.0);
        assert_eq!((m.hall_count(), m.hall_levels()), (0, (false, false)));
        m.set_hall_failed(false);
        let want = libm::floor(m.motor_angle_deg() * 64.0 / 360.0) as i64;
        assert_eq!(m.hall_count(), want);
    }

    #[test]
    fn hall_edges_of_one_motor_turn() {
        let mut hall = HallSensor::new(64);
        // 64 counts per turn: 64 edges, one channel at a time, 16 A rises.
        let (mut prev, mut n, mut a_rises) = (hall.levels_at(0.1), 0, 0);
        for e in hall.edges(0.1, 360.1) {
            assert_eq!(u8::from(e.a != prev.0) + u8::from(e.b != prev.1), 1);
            a_rises += u32::from(e.a && !prev.0);
            prev = (e.a, e.b);
            n += 1;
        }
        assert_eq!(n, 64);
        assert_eq!(a_rises, hall.pulses_per_rev());
        hall.set_failed(true, 0.1);
        assert_eq!(hall.edges(0.1, 720.0).count(), 0);
    }

    #[test]
    fn hall_edges_decode_in_the_driver() {
        use drivers::encoder::Transition;
        use drivers::hall::{HallConfig, QuadratureHall};
        let config = HallConfig {
            stall_ms: 500,
            drive_threshold_permille: 150,
            max_idle_pulses: 4,
        };
        let mut m = motor();
        let (a, b) = m.hall_levels();
        let Ok(mut hall) = QuadratureHall::new(a, b, config) else {
            panic!("valid config");
        };
        m.set_output(Output::Forward(400));
        // 4,000 rpm = 66.7 rev/s · 64 = 4,267 counts/s: an edge every
        // 234 µs, so one per 10 µs step at most.
        for k in 0..40_000u32 {
            m.step(DEFAULT_STEP_S);
            let (a, b) = m.hall_levels();
            assert_ne!(hall.update(a, b, k / 100), Transition::Illegal);
        }
        assert!(m.hall_count() > 1_000);
        assert_eq!(i64::from(hall.position()), m.hall_count());
        assert_eq!(hall.errors(), 0);
    }

    #[test]
    fn bts7960_sense_voltage() {
        let s = Bts7960Sense::TYPICAL_1K_5V;
        // 8.5 A / 8,500 · 1 kΩ = 1 V; 5.5 A → 0.647 V; 50 A → 5.88 V, clamped.
        assert!(close(s.is_voltage_v(FULL, 8.5), 1.0, 1e-12));
        assert!(close(
            s.is_voltage_v(Output::Backward(300), -5.5),
            5.5 / 8.5,
            1e-12
        ));
        assert_eq!(s.is_voltage_v(FULL, 50.0), 5.0);
        assert_eq!(s.is_voltage_v(Output::Brake, 5.0), 0.0);
        assert_eq!(s.is_voltage_v(Output::Coast, 5.0), 0.0);
        // 1 V of 5 V on 10 bits: 1023 / 5 = 204.6 → 204.
        assert_eq!(s.adc_counts(FULL, 8.5, 5.0, 1_023), 204);
    }
}
