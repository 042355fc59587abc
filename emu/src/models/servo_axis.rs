//! A servo axis of the ATmega2560's images (`axis.X.drive`
//! `servo_encoder`: `boards/mega2560/src/servo.rs`): a FEETECH FS5106R
//! continuous-rotation servo ([`crate::models::fs5106r`]) on a Timer3
//! output, turning the axis through a gear of `gear` servo turns per axis
//! turn, a YMT22 quadrature encoder ([`crate::models::quadrature`], 300
//! lines, 1,200 counts a turn) on the servo's shaft, its edges put on the
//! image's pin-change pins (port K, the DC axes' Hall inputs) at the
//! instants the shaft reaches them, the home switch closed at and below
//! the home angle, a hard stop 2° below it.
//!
//! The pulse: Timer3 in fast PWM mode 14 (TOP = ICR3, clk/8: 0.5 µs a
//! count, 20 ms frames), the output high for OCR3x + 1 counts from BOTTOM
//! while COM3x = 10, no pulse while COM3x = 00 (ATmega2560 datasheet
//! §17.9.3 and Table 17-4). The width is read from the registers, not from
//! the pin: simavr applies an OCRnx write at once rather than at BOTTOM
//! (see [`crate::uno`]'s notes), which on a pin makes pulses no servo on a
//! board gets. The servo takes each frame's pulse at the frame's start,
//! on a 20 ms grid of CPU time from power-on (the timer's own phase is
//! not modelled: a new width acts within one frame, as on the board).
//!
//! Time: the servo turns in CPU time, as on a board. The Mega bench runs
//! at real time (emulated time = CPU time) whenever a servo is commanded
//! to turn or still turns ([`ServoAxisModel::active`]), so the image's
//! emulated clock and the servo agree.

use crate::models::fs5106r::{Fs5106r, FRAME_S};
use crate::models::quadrature::QuadratureEncoder;
use crate::sim::Sim;

/// Data-space addresses of Timer3's registers (ATmega2560 datasheet
/// "Register Summary"; 16-bit registers low byte first).
mod reg {
    pub const TCCR3A: u16 = 0x90;
    pub const OCR3AL: u16 = 0x98;
    pub const OCR3CL: u16 = 0x9C;
}

/// Timer3 counts per µs (16 MHz / 8).
const COUNTS_PER_US: f64 = 2.0;
/// The hard stop below the home switch, degrees of axis.
pub const HARD_STOP_BELOW_DEG: f64 = 2.0;

/// Where one servo axis is wired.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ServoWiring {
    /// COM3x's shift in TCCR3A.
    com_shift: u8,
    /// OCR3x's low byte.
    ocr: u16,
    /// Encoder channels A and B: bits of port K.
    pub encoder_bits: (u8, u8),
}

impl ServoWiring {
    /// The C axis: OC3A (PE3, D5), encoder on PK4/PK5.
    pub const C: ServoWiring = ServoWiring {
        com_shift: 6,
        ocr: reg::OCR3AL,
        encoder_bits: (4, 5),
    };
    /// The A axis: OC3C (PE5, D3), encoder on PK6/PK7.
    pub const A: ServoWiring = ServoWiring {
        com_shift: 2,
        ocr: reg::OCR3CL,
        encoder_bits: (6, 7),
    };

    /// The pulse the registers give each frame now, µs (`None`: the
    /// output disconnected, no pulse).
    pub fn pulse_us(&self, sim: &Sim) -> Option<f64> {
        let com = (sim.peek(reg::TCCR3A) >> self.com_shift) & 0b11;
        if com != 0b10 {
            return None;
        }
        let ocr = u16::from(sim.peek(self.ocr)) | (u16::from(sim.peek(self.ocr + 1)) << 8);
        Some((f64::from(ocr) + 1.0) / COUNTS_PER_US)
    }
}

/// An encoder edge on the pins: CPU cycle, levels of A and B after it.
pub type EncoderEdge = (u64, bool, bool);

/// One servo axis: wiring, servo, gear, encoder, switches and stops.
#[derive(Debug, Clone)]
pub struct ServoAxisModel {
    /// The wiring.
    pub wiring: ServoWiring,
    servo: Fs5106r,
    encoder: QuadratureEncoder,
    /// Servo shaft turns per axis turn.
    gear: f64,
    /// The home switch is closed at and below this axis angle, degrees.
    pub home_deg: f64,
    /// The max-end switch is closed at and above this angle, degrees.
    pub max_deg: f64,
    /// Pulses the servo got.
    pub pulses: u64,
    /// Times the shaft came down onto the hard stop.
    pub hard_stop_hits: u32,
}

impl ServoAxisModel {
    /// An axis over `wiring` at `start_deg`, geared `gear`:1, its switches
    /// at `home_deg` and `max_deg`; the shaft angle is the axis angle times
    /// the gear, the encoder's disc set half a count off the switch (the
    /// switch closes in the middle of a count, not on an edge).
    pub fn new(
        wiring: ServoWiring,
        start_deg: f64,
        gear: f64,
        home_deg: f64,
        max_deg: f64,
    ) -> Self {
        let stop = home_deg - HARD_STOP_BELOW_DEG;
        let encoder = QuadratureEncoder::ymt22();
        let half_count = encoder.deg_per_count() / 2.0;
        // The disc half a count on at the switch's shaft angle.
        let encoder = encoder.with_offset_deg(half_count - home_deg * gear);
        ServoAxisModel {
            wiring,
            servo: Fs5106r::at_6v(start_deg.max(stop) * gear, 0.0),
            encoder,
            gear,
            home_deg,
            max_deg,
            pulses: 0,
            hard_stop_hits: 0,
        }
    }

    /// The A axis of the bench's geometry: home switch at −90°, max switch
    /// at +91°.
    pub fn a_axis(start_deg: f64, gear: f64) -> Self {
        ServoAxisModel::new(ServoWiring::A, start_deg, gear, -90.0, 91.0)
    }

    /// The axis angle, degrees.
    pub fn angle_deg(&self) -> f64 {
        self.servo.angle_deg() / self.gear
    }

    /// The home switch is closed.
    pub fn home_closed(&self) -> bool {
        self.angle_deg() <= self.home_deg + 1e-9
    }

    /// The max-end switch is closed.
    pub fn max_closed(&self) -> bool {
        self.angle_deg() >= self.max_deg - 1e-9
    }

    /// The encoder's levels (A, B) now.
    pub fn encoder_levels(&self) -> (bool, bool) {
        self.encoder.levels_at(self.servo.angle_deg())
    }

    /// The servo is commanded to turn (a pulse outside its dead band) or
    /// still turns on its last pulse: the bench must step it.
    pub fn active(&self, pulse_us: Option<f64>) -> bool {
        let spec = self.servo.spec();
        pulse_us.is_some_and(|w| (w - spec.neutral_us).abs() > spec.dead_band_us)
            || self.servo.speed_deg_s(self.servo.time_s()) != 0.0
    }

    /// Turns the servo for the `cycles` CPU cycles from `cycle0` under
    /// `pulse_us` (each frame that starts in that span gets it), and
    /// returns the encoder edges with the cycle each happens at.
    pub fn advance(
        &mut self,
        pulse_us: Option<f64>,
        cycle0: u64,
        cycles: u64,
        f_cpu: u32,
    ) -> Vec<EncoderEdge> {
        let f = f64::from(f_cpu);
        // The frames' starts in whole cycles (320,000 at 16 MHz).
        let frame_cycles = (FRAME_S * f).round() as u64;
        let end = cycle0 + cycles;
        let mut edges = Vec::new();
        let mut frame = cycle0.div_ceil(frame_cycles) * frame_cycles;
        while frame < end {
            let t = frame as f64 / f;
            self.run_to(t, f, &mut edges);
            if let Some(w) = pulse_us {
                self.servo.pulse(t, w);
                self.pulses += 1;
            }
            frame += frame_cycles;
        }
        self.run_to(end as f64 / f, f, &mut edges);
        edges
    }

    /// Moves the shaft on to CPU time `t_s`, its encoder edges into
    /// `edges`, held at the hard stop below the home switch.
    fn run_to(&mut self, t_s: f64, f_cpu: f64, edges: &mut Vec<EncoderEdge>) {
        let stop = (self.home_deg - HARD_STOP_BELOW_DEG) * self.gear;
        for mut seg in self.servo.segments_to(t_s) {
            let hit = seg.speed_deg_s < 0.0 && seg.angle1_deg() < stop;
            if hit {
                let t_hit = seg.t0_s + (stop - seg.angle0_deg) / seg.speed_deg_s;
                seg.t1_s = t_hit.clamp(seg.t0_s, seg.t1_s);
            }
            edges.extend(
                self.encoder
                    .timed_edges(&seg)
                    .into_iter()
                    .map(|(t, e)| ((t * f_cpu).round() as u64, e.a, e.b)),
            );
            if hit {
                // Held at the stop: the servo rebuilt there, its last
                // command gone (the next pulse gives it one again).
                if seg.angle0_deg > stop {
                    self.hard_stop_hits += 1;
                }
                self.servo = Fs5106r::at_6v(stop, t_s);
                return;
            }
        }
        self.servo.advance_to(t_s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const F: u32 = 16_000_000;

    #[test]
    fn a_full_pulse_turns_the_axis_at_the_servos_speed_over_its_gear() {
        // 2,300 µs: 95 rpm = 570 °/s at the shaft, 5.7 °/s of axis at 100:1.
        let mut m = ServoAxisModel::a_axis(0.0, 100.0);
        let mut edges = 0;
        for k in 0..1_000u64 {
            edges += m.advance(Some(2_300.0), k * 16_000, 16_000, F).len();
        }
        // One second: 50 frames, the first at t = 0.
        assert_eq!(m.pulses, 50);
        assert!((m.angle_deg() - 5.7).abs() < 0.01, "{}", m.angle_deg());
        // 570° of shaft: 1,900 counts of 0.3°.
        assert!((edges as i64 - 1_900).abs() <= 1, "{edges}");
    }

    #[test]
    fn the_neutral_pulse_and_no_pulse_leave_it_still() {
        let mut m = ServoAxisModel::a_axis(10.0, 100.0);
        assert!(!m.active(Some(1_500.0)));
        assert!(m.advance(Some(1_500.0), 0, 320_000, F).is_empty());
        assert!(m.advance(None, 320_000, 320_000, F).is_empty());
        assert_eq!(m.angle_deg(), 10.0);
        assert!(m.active(Some(1_700.0)));
    }

    #[test]
    fn the_shaft_runs_out_its_last_pulse_then_stops() {
        let mut m = ServoAxisModel::a_axis(0.0, 1.0);
        m.advance(Some(2_300.0), 0, 16_000, F);
        assert!(m.active(None));
        // No pulse after the first: three frames' hold (60 ms).
        m.advance(None, 16_000, 16 * 16_000_000 / 10, F);
        assert!(!m.active(None));
        assert!(
            (m.angle_deg() - 570.0 * 0.060).abs() < 1e-6,
            "{}",
            m.angle_deg()
        );
    }

    #[test]
    fn the_switch_closes_at_home_and_the_stop_holds_the_axis_below_it() {
        let mut m = ServoAxisModel::a_axis(-89.0, 10.0);
        assert!(!m.home_closed());
        // 700 µs: full speed down, 57 °/s of axis: past the switch within
        // 20 ms, at the stop (−92°) within 60 ms.
        for k in 0..100u64 {
            m.advance(Some(700.0), k * 16_000, 16_000, F);
        }
        assert!(m.home_closed());
        assert!((m.angle_deg() - -92.0).abs() < 1e-9, "{}", m.angle_deg());
        assert_eq!(m.hard_stop_hits, 1);
        // And back up.
        for k in 100..200u64 {
            m.advance(Some(2_300.0), k * 16_000, 16_000, F);
        }
        assert!(m.angle_deg() > -92.0);
    }

    #[test]
    fn the_switch_lies_half_a_count_inside_a_count() {
        let m = ServoAxisModel::a_axis(-90.0, 100.0);
        // 0.3° of shaft a count: 0.1° either side of the switch's shaft
        // angle is the same count.
        let enc = m.encoder;
        let shaft = -90.0 * 100.0;
        assert_eq!(enc.count_at(shaft - 0.1), enc.count_at(shaft + 0.1));
        assert_ne!(enc.count_at(shaft - 0.2), enc.count_at(shaft + 0.2));
        assert_eq!(m.encoder_levels(), enc.levels_at(shaft));
    }
}
