//! A DC gear-motor axis of the ATmega2560's images (an axis whose
//! `axis.X.drive` is `dc_hall`: `boards/mega2560/src/dc.rs`): an IBT-2 module (two Infineon BTS7960 half
//! bridges) read from the image's registers, the motor, gears and Hall
//! encoder of `sim::dc_drive::worm_slew_motor` (the physics is
//! `sim::dc_motor`'s, shared with the host simulator), the encoder's edges
//! put on the image's pin-change pins at the instants the motor reaches
//! them, and the BTS7960's current sense on its ADC input.
//!
//! The bridge: each half bridge's IN is a 20 kHz PWM output of Timer1 or
//! Timer4 (fast PWM, TOP = ICRn, non-inverting: high for OCRnx + 1 of
//! ICRn + 1 counts while COMnx = 10; low, its PORT bit, while COMnx = 00;
//! ATmega2560 datasheet §17.9.3 and Table 17-4), INH its enable on port A.
//! The module's table (`drivers::dc_motor::bts7960`): both enables high,
//! RPWM at duty d, LPWM low: forward at d; LPWM at d: backward; both low:
//! brake (both low sides on); an enable low: that half bridge asleep, taken
//! here as coasting. The duty is read from the registers rather than from
//! the pins' 20 kHz edges: the motor's electrical time constant (0.46 ms)
//! is nine PWM periods, so the motor sees the mean voltage, as the model
//! takes it.
//!
//! Current sense: the conducting high side's IS pin sources `I_L /
//! k_ILIS` into 1 kΩ ([`Bts7960Sense::TYPICAL_1K_5V`], k_ILIS = 8,500,
//! Infineon BTS 7960 data sheet item 4.4.6), the mean over the PWM period
//! as the board's filter capacitor gives it.

use drivers::dc_motor::Output;
use sim::dc_drive::worm_slew_motor;
use sim::dc_motor::{duty_of, Bts7960Sense, DcMotor};

use crate::sim::Sim;

/// Data-space addresses of the registers the model reads (ATmega2560
/// datasheet "Register Summary"; 16-bit registers low byte first).
mod reg {
    pub const PORTA: u16 = 0x22;
    pub const TCCR1A: u16 = 0x80;
    pub const ICR1L: u16 = 0x86;
    pub const OCR1AL: u16 = 0x88;
    pub const OCR1BL: u16 = 0x8A;
    pub const TCCR4A: u16 = 0xA0;
    pub const ICR4L: u16 = 0xA6;
    pub const OCR4BL: u16 = 0xAA;
    pub const OCR4CL: u16 = 0xAC;
}

/// One PWM output: its timer's TCCRnA, the COMnx bits' shift in it, its
/// OCRnx and the timer's ICRn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct PwmOut {
    tccra: u16,
    com_shift: u8,
    ocr: u16,
    icr: u16,
}

impl PwmOut {
    /// The output's duty, 0..=1.
    fn duty(self, sim: &Sim) -> f64 {
        let com = (sim.peek(self.tccra) >> self.com_shift) & 0b11;
        if com != 0b10 {
            return 0.0;
        }
        let word = |a: u16| u16::from(sim.peek(a)) | (u16::from(sim.peek(a + 1)) << 8);
        let top = f64::from(word(self.icr)) + 1.0;
        ((f64::from(word(self.ocr)) + 1.0) / top).min(1.0)
    }
}

/// Where one axis's module and encoder are wired.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ibt2Wiring {
    rpwm: PwmOut,
    lpwm: PwmOut,
    /// R_EN and L_EN bits of PORTA.
    en_bits: (u8, u8),
    /// Hall channels A and B: bits of port K.
    pub hall_bits: (u8, u8),
    /// R_IS/L_IS ADC channel.
    pub sense_channel: u8,
}

impl Ibt2Wiring {
    /// The C axis: RPWM/LPWM on OC1A/OC1B, R_EN/L_EN PA0/PA1, Hall PK4/PK5,
    /// IS on ADC2.
    pub const C: Ibt2Wiring = Ibt2Wiring {
        rpwm: PwmOut {
            tccra: reg::TCCR1A,
            com_shift: 6,
            ocr: reg::OCR1AL,
            icr: reg::ICR1L,
        },
        lpwm: PwmOut {
            tccra: reg::TCCR1A,
            com_shift: 4,
            ocr: reg::OCR1BL,
            icr: reg::ICR1L,
        },
        en_bits: (0, 1),
        hall_bits: (4, 5),
        sense_channel: 2,
    };
    /// The A axis: RPWM/LPWM on OC4B/OC4C, R_EN/L_EN PA4/PA5, Hall PK6/PK7,
    /// IS on ADC3.
    pub const A: Ibt2Wiring = Ibt2Wiring {
        rpwm: PwmOut {
            tccra: reg::TCCR4A,
            com_shift: 4,
            ocr: reg::OCR4BL,
            icr: reg::ICR4L,
        },
        lpwm: PwmOut {
            tccra: reg::TCCR4A,
            com_shift: 2,
            ocr: reg::OCR4CL,
            icr: reg::ICR4L,
        },
        en_bits: (4, 5),
        hall_bits: (6, 7),
        sense_channel: 3,
    };

    /// What the module does with the image's registers as they are now.
    pub fn output(&self, sim: &Sim) -> Output {
        let porta = sim.peek(reg::PORTA);
        let enabled = porta & (1 << self.en_bits.0) != 0 && porta & (1 << self.en_bits.1) != 0;
        if !enabled {
            return Output::Coast;
        }
        let permille = |d: f64| (d * 1_000.0).round() as i32;
        match permille(self.rpwm.duty(sim)) - permille(self.lpwm.duty(sim)) {
            0 => Output::Brake,
            d if d > 0 => Output::Forward(d.min(1_000) as u16),
            d => Output::Backward((-d).min(1_000) as u16),
        }
    }
}

/// Model steps per emulated millisecond: 0.25 ms, as `sim::dc_drive`'s.
pub const STEPS_PER_MS: u32 = 4;
/// Below this motor speed, braked or coasting, the motor stands still,
/// rad/s (`sim::dc_drive`'s threshold: what is left of the run-down is
/// under a Hall count).
pub const AT_REST_RAD_S: f64 = 0.5;
/// The ADC reference (AVcc), V.
pub const ADC_VREF_V: f64 = 5.0;

/// An edge of the Hall outputs: CPU cycle, levels of A and B after it.
pub type HallEdge = (u64, bool, bool);

/// One DC axis: the module's wiring, the motor and gears, the mechanical
/// stops and the home and max switches.
#[derive(Debug, Clone)]
pub struct DcAxisModel {
    /// The wiring.
    pub wiring: Ibt2Wiring,
    /// The motor, gears and Hall encoder.
    pub motor: DcMotor,
    /// The home switch is closed at and below this output angle, degrees.
    pub home_deg: f64,
    /// The max-end switch is closed at and above this angle, degrees.
    pub max_deg: f64,
    /// The axis's own end stops, degrees.
    pub ends_deg: (f64, f64),
    /// An obstacle: the axis cannot pass this angle from below (`Some`).
    pub obstacle_deg: Option<f64>,
    /// A current worth noting, A: [`DcAxisModel::crossings`] lists when
    /// the motor's current, while driven, rose above it.
    pub current_mark_a: f64,
    /// The CPU cycles at which the current rose above `current_mark_a`.
    pub crossings: Vec<u64>,
    above: bool,
}

impl DcAxisModel {
    /// An axis over `wiring` at output angle `start_deg`, switches at
    /// `home_deg` and `max_deg`, stopped 2° beyond each.
    pub fn new(wiring: Ibt2Wiring, start_deg: f64, home_deg: f64, max_deg: f64) -> Self {
        let mut motor = DcMotor::new(worm_slew_motor());
        motor.set_output_angle_deg(start_deg);
        let mut m = DcAxisModel {
            wiring,
            motor,
            home_deg,
            max_deg,
            ends_deg: (home_deg - 2.0, max_deg + 2.0),
            obstacle_deg: None,
            current_mark_a: f64::INFINITY,
            crossings: Vec::new(),
            above: false,
        };
        m.apply_stops();
        m
    }

    /// The C axis of the stepper bench's geometry: −180…+180°, home
    /// switch at −180°, max switch at +181°.
    pub fn c_axis(start_deg: f64) -> Self {
        DcAxisModel::new(Ibt2Wiring::C, start_deg, -180.0, 181.0)
    }

    /// The A axis: home switch at −90°, max switch at +91°.
    pub fn a_axis(start_deg: f64) -> Self {
        DcAxisModel::new(Ibt2Wiring::A, start_deg, -90.0, 91.0)
    }

    fn apply_stops(&mut self) {
        let (lo, hi) = self.ends_deg;
        let hi = self.obstacle_deg.map_or(hi, |o| o.min(hi));
        self.motor.set_hard_stops_deg(Some((lo, hi.max(lo))));
    }

    /// Puts an obstacle at `deg` (the axis is held there coming from
    /// below) or takes it away (`None`).
    pub fn set_obstacle(&mut self, deg: Option<f64>) {
        if self.obstacle_deg != deg {
            self.obstacle_deg = deg;
            self.apply_stops();
        }
    }

    /// Output angle, degrees.
    pub fn angle_deg(&self) -> f64 {
        self.motor.output_angle_deg()
    }

    /// The home switch is closed.
    pub fn home_closed(&self) -> bool {
        self.angle_deg() <= self.home_deg + 1e-9
    }

    /// The max-end switch is closed.
    pub fn max_closed(&self) -> bool {
        self.angle_deg() >= self.max_deg - 1e-9
    }

    /// The Hall levels (A, B) now.
    pub fn hall_levels(&self) -> (bool, bool) {
        self.motor.hall_levels()
    }

    /// The motor is driven or still turns: the bench must step it.
    pub fn active(&self, output: Output) -> bool {
        matches!(output, Output::Forward(_) | Output::Backward(_))
            || self.motor.motor_speed_rad_s().abs() >= AT_REST_RAD_S
    }

    /// The IS voltage on the ADC pin, mV.
    pub fn sense_mv(&self) -> u32 {
        sense_mv(self.motor.output(), self.motor.current_a())
    }

    /// Runs the motor under `output` for the `cycles` CPU cycles from
    /// `cycle0` (at 16 MHz, one emulated ms = 16,000 cycles at real time)
    /// in steps of 1/[`STEPS_PER_MS`] ms, and returns the Hall edges with
    /// the cycle each happens at (interpolated in angle within a step).
    pub fn advance(
        &mut self,
        output: Output,
        cycle0: u64,
        cycles: u64,
        f_cpu: u32,
    ) -> Vec<HallEdge> {
        self.motor.set_output(output);
        let dt_s = 1e-3 / f64::from(STEPS_PER_MS);
        let cycles_per_step = f64::from(f_cpu) * dt_s;
        let steps = ((cycles as f64 / cycles_per_step).round() as u64).max(1);
        let mut edges = Vec::new();
        for k in 0..steps {
            let from = self.motor.motor_angle_deg();
            self.motor.step(dt_s);
            let to = self.motor.motor_angle_deg();
            let t0 = cycle0 as f64 + k as f64 * cycles_per_step;
            // While driven: the current a high side carries, which the IS
            // pin reports (a brake's reverse current is not sensed).
            let above =
                duty_of(output).is_some() && self.motor.current_a().abs() > self.current_mark_a;
            if above && !self.above {
                self.crossings.push((t0 + cycles_per_step) as u64);
            }
            self.above = above;
            for e in self.motor.hall.edges(from, to) {
                let frac = if to != from {
                    ((e.angle_deg - from) / (to - from)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                edges.push(((t0 + frac * cycles_per_step) as u64, e.a, e.b));
            }
        }
        edges
    }
}

/// The IS voltage a BTS7960 pair puts on its 1 kΩ sense resistor
/// ([`Bts7960Sense::TYPICAL_1K_5V`]) under `output` at `current_a`, mV:
/// what a bridge-driven model (a DC motor, a linear actuator) puts on its
/// ADC pin.
pub fn sense_mv(output: Output, current_a: f64) -> u32 {
    let v = Bts7960Sense::TYPICAL_1K_5V.is_voltage_v(output, current_a);
    (v * 1_000.0).round() as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At full duty forward from rest, the axis reaches the motor's no-load
    /// speed through the gears within a second (mechanical time constant
    /// 0.12 s), and the Hall edges count 64 a motor turn, 1,400 an axis
    /// degree.
    #[test]
    fn full_duty_runs_at_the_geared_speed_and_counts_1400_a_degree() {
        let mut m = DcAxisModel::a_axis(0.0);
        let mut edges = 0usize;
        let mut cycle = 0u64;
        for _ in 0..2_000 {
            edges += m
                .advance(Output::Forward(1_000), cycle, 16_000, 16_000_000)
                .len();
            cycle += 16_000;
        }
        let spec = worm_slew_motor();
        // 10,000 rpm at the motor less the load of the output stage.
        let no_load_deg_s = (spec.no_load_motor_rad_s() / spec.gear_ratio).to_degrees();
        let speed_deg_s = m.motor.output_speed_rpm() * 6.0;
        assert!(
            speed_deg_s > 0.9 * no_load_deg_s && speed_deg_s <= no_load_deg_s,
            "{speed_deg_s}"
        );
        let counts_per_deg = edges as f64 / m.angle_deg();
        assert!((counts_per_deg - 1_400.0).abs() < 1.0, "{counts_per_deg}");
    }

    /// Against the obstacle the motor is held: at full duty it draws the
    /// stall current V / R (5.5 A), and the IS pin shows it over 1 kΩ at
    /// k_ILIS = 8,500: 5.5 / 8,500 · 1,000 = 0.647 V.
    #[test]
    fn an_obstacle_holds_the_axis_at_the_stall_current() {
        let mut m = DcAxisModel::a_axis(-10.0);
        m.set_obstacle(Some(-9.9));
        for k in 0..1_000 {
            m.advance(Output::Forward(1_000), k * 16_000, 16_000, 16_000_000);
        }
        assert!((m.angle_deg() - -9.9).abs() < 1e-6);
        let stall_a = worm_slew_motor().stall_current_a();
        assert!((m.motor.current_a() - stall_a).abs() < 0.01 * stall_a);
        let mv = m.sense_mv();
        assert!((640..=655).contains(&mv), "{mv} mV");
        m.set_obstacle(None);
        m.advance(Output::Forward(1_000), 0, 160_000, 16_000_000);
        assert!(m.angle_deg() > -9.9);
    }
}
