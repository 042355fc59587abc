//! Decoder of one H-bridge stepper axis from its four bridge inputs, and the
//! axis's end switches.
//!
//! Coil table of `drivers/src/stepper/hbridge.rs` (half-step phases 0..7 of
//! `[IN1, IN2, IN3, IN4]`): 1000, 1010, 0010, 0110, 0100, 0101, 0001, 1001;
//! forward (increasing angle) is increasing phase. Full step uses the odd
//! phases, two half-phases per step, and the driver writes the pins one at
//! a time, lows first then highs, so every full step passes through the
//! even half-phase between (e.g. 1010 → 0010 → 0110). All-low is released:
//! the rotor stays at its last phase, and re-energising must resume at that
//! phase or one half-phase beside it.
//!
//! A pattern the driver leaves within [`SETTLE_CYCLES`] (the one-coil
//! pattern a release passes through as it drops the coils one at a time,
//! for example) does not move the rotor: released after it, the rotor is
//! still at the phase held before.
//!
//! Anything else — a pattern not in the table (e.g. 1100, both ends of a
//! coil high: a shoot-through), or a jump of more than one half-phase
//! between consecutive observed patterns — is an illegal sequence and is
//! recorded (the rotor position is then unknown; the decoder keeps counting
//! from the new phase, taking the shortest way).
//!
//! A power cut ([`StepperDecoder::power_cut`]) drops the coils and the
//! driver's memory of its phase (`drivers::stepper::hbridge`: the rotor's
//! phase is unknown until the first energising after power-on, which starts
//! at the step mode's first phase): the first pattern after it is a first
//! energising again, as at power-on, not a jump.

/// Half-step coil table, IN1 as bit 0 … IN4 as bit 3.
const PHASES: [u8; 8] = [
    0b0001, 0b0101, 0b0100, 0b0110, 0b0010, 0b1010, 0b1000, 0b1001,
];

/// A pattern held for less than this many CPU cycles (100 µs at 16 MHz)
/// does not move the rotor: a small stepper's mechanical time constant is
/// milliseconds.
pub const SETTLE_CYCLES: u64 = 1_600;

fn phase_of(bits: u8) -> Option<u8> {
    PHASES.iter().position(|&p| p == bits).map(|p| p as u8)
}

/// One illegal observation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IllegalStep {
    /// CPU cycle of the write.
    pub cycle: u64,
    /// Previous pattern (IN1 = bit 0).
    pub from: u8,
    /// New pattern.
    pub to: u8,
}

/// Axis geometry and end switches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisGeometry {
    /// Half-steps per degree of axis rotation (2 × 10,000 / 360).
    pub half_steps_per_deg: f64,
    /// Home switch closed at and below this angle.
    pub home_deg: f64,
    /// Max-end switch closed at and above this angle.
    pub max_deg: f64,
    /// The axis turns without end (a slip ring): no max-end switch, and
    /// the home switch an index cam closed from [`INDEX_ARC_DEG`] below
    /// `home_deg` up to it, once a turn.
    pub continuous: bool,
}

/// Arc of the index cam of an axis that turns without end, degrees.
pub const INDEX_ARC_DEG: f64 = 5.0;

impl AxisGeometry {
    /// 200-step motor, 50:1 gear: 10,000 full steps per turn.
    pub const HALF_STEPS_PER_DEG: f64 = 20_000.0 / 360.0;

    /// C axis: −180…+180°, max switch at +181°.
    pub fn c_axis() -> Self {
        AxisGeometry {
            half_steps_per_deg: Self::HALF_STEPS_PER_DEG,
            home_deg: -180.0,
            max_deg: 181.0,
            continuous: false,
        }
    }

    /// C axis turning without end: the index at −180° (≡ 180°).
    pub fn c_axis_continuous() -> Self {
        AxisGeometry {
            continuous: true,
            ..Self::c_axis()
        }
    }

    /// A axis: −90…+90°, max switch at +91°.
    pub fn a_axis() -> Self {
        AxisGeometry {
            half_steps_per_deg: Self::HALF_STEPS_PER_DEG,
            home_deg: -90.0,
            max_deg: 91.0,
            continuous: false,
        }
    }
}

/// The decoder of one axis.
#[derive(Debug, Clone)]
pub struct StepperDecoder {
    geometry: AxisGeometry,
    /// Position in half-steps from angle 0.
    half_steps: i64,
    /// Last energised phase (the rotor's), `None` before the first one.
    phase: Option<u8>,
    last_bits: u8,
    /// CPU cycle of the last pattern change.
    last_change: u64,
    /// Phase and position of the last pattern held for at least
    /// [`SETTLE_CYCLES`].
    settled: Option<(u8, i64)>,
    /// Illegal observations.
    pub illegal: Vec<IllegalStep>,
    /// Half-steps moved in total (both directions).
    pub travelled: u64,
    /// Pattern writes observed (including repeats and releases).
    pub writes: u64,
}

impl StepperDecoder {
    /// An axis at `angle_deg` at power-on, rotor at the odd (full-step)
    /// phase nearest that position.
    pub fn new(geometry: AxisGeometry, angle_deg: f64) -> Self {
        let hs = (angle_deg * geometry.half_steps_per_deg).round() as i64;
        StepperDecoder {
            geometry,
            half_steps: hs,
            phase: None,
            last_bits: 0,
            last_change: 0,
            settled: None,
            illegal: Vec::new(),
            travelled: 0,
            writes: 0,
        }
    }

    /// Axis angle, degrees.
    pub fn angle_deg(&self) -> f64 {
        self.half_steps as f64 / self.geometry.half_steps_per_deg
    }

    /// Position in half-steps.
    pub fn half_steps(&self) -> i64 {
        self.half_steps
    }

    /// Whether the coils are energised now.
    pub fn energised(&self) -> bool {
        self.last_bits != 0
    }

    /// Home switch closed (angle at or below the home angle).
    pub fn home_closed(&self) -> bool {
        let g = &self.geometry;
        if g.continuous {
            // Above the index within the turn; the cam's arc below it
            // counts as 360° − that.
            let w = (self.angle_deg() - g.home_deg - 1e-9).rem_euclid(360.0);
            return w == 0.0 || w >= 360.0 - INDEX_ARC_DEG - 1e-9;
        }
        self.angle_deg() <= g.home_deg + 1e-9
    }

    /// Max-end switch closed (never on an axis that turns without end).
    pub fn max_closed(&self) -> bool {
        !self.geometry.continuous && self.angle_deg() >= self.geometry.max_deg - 1e-9
    }

    /// The power was cut at CPU cycle `cycle`: the bridge inputs fall
    /// (released), and the image that boots next knows nothing of the
    /// rotor's phase, so its first energising snaps the rotor to the
    /// nearest position with that phase (as at power-on) instead of
    /// counting as a jump. The position is kept.
    pub fn power_cut(&mut self, cycle: u64) {
        self.last_bits = 0;
        self.last_change = cycle;
        self.phase = None;
        self.settled = None;
    }

    /// One observed pattern of IN1..IN4 (IN1 = bit 0).
    pub fn observe(&mut self, cycle: u64, bits: u8) {
        let bits = bits & 0x0F;
        self.writes += 1;
        if bits == self.last_bits {
            return;
        }
        let from = self.last_bits;
        let held = cycle.saturating_sub(self.last_change) >= SETTLE_CYCLES;
        if held && from != 0 {
            if let Some(p) = self.phase {
                self.settled = Some((p, self.half_steps));
            }
        }
        self.last_bits = bits;
        self.last_change = cycle;
        if bits == 0 {
            // Released: the rotor keeps its phase, the one it was held at
            // (not a pattern passed through on the way to all-low).
            if !held {
                if let Some((p, hs)) = self.settled {
                    self.travelled = self.travelled.saturating_sub(self.half_steps.abs_diff(hs));
                    self.half_steps = hs;
                    self.phase = Some(p);
                }
            }
            return;
        }
        let Some(p) = phase_of(bits) else {
            self.illegal.push(IllegalStep {
                cycle,
                from,
                to: bits,
            });
            return;
        };
        let Some(old) = self.phase else {
            // First energising: the rotor snaps to the nearest position
            // with this phase (the harness's power-on angle is a guess).
            let cur = self.half_steps.rem_euclid(8) as u8;
            let d = (i64::from(p) - i64::from(cur) + 8).rem_euclid(8);
            let d = if d > 4 { d - 8 } else { d };
            self.half_steps += d;
            self.phase = Some(p);
            return;
        };
        let d = (i64::from(p) - i64::from(old) + 8).rem_euclid(8);
        let d = if d > 4 { d - 8 } else { d };
        if d.abs() > 1 {
            self.illegal.push(IllegalStep {
                cycle,
                from,
                to: bits,
            });
        }
        self.half_steps += d;
        self.travelled += d.unsigned_abs();
        self.phase = Some(p);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The driver's full step forward from phase 1 to 3: lows first
    /// (IN1 low: 0100), then highs (IN2 high: 0110).
    fn bits(in1: u8, in2: u8, in3: u8, in4: u8) -> u8 {
        in1 | in2 << 1 | in3 << 2 | in4 << 3
    }

    #[test]
    fn full_steps_through_half_phases_count_forward_and_back() {
        let mut d = StepperDecoder::new(AxisGeometry::a_axis(), 0.0);
        // Energise at phase 1 (1010): snaps from 0 (phase 0) to +1.
        d.observe(0, bits(1, 0, 1, 0));
        assert_eq!(d.half_steps(), 1);
        // Forward 1 → 3: 0010 (phase 2) then 0110 (phase 3).
        d.observe(1, bits(0, 0, 1, 0));
        d.observe(2, bits(0, 1, 1, 0));
        assert_eq!(d.half_steps(), 3);
        // Release and resume at the same phase: no motion.
        for (i, b) in [bits(0, 1, 0, 0), bits(0, 0, 0, 0), bits(0, 1, 1, 0)]
            .into_iter()
            .enumerate()
        {
            d.observe(3 + i as u64, b);
        }
        // Releasing lows-first passes 0100 (phase 4, one half-phase on),
        // re-energising highs-in-order passes it again: net zero.
        assert_eq!(d.half_steps(), 3);
        // Backward 3 → 1: IN2 low (0010, phase 2), IN1 high (1010).
        d.observe(10, bits(0, 0, 1, 0));
        d.observe(11, bits(1, 0, 1, 0));
        assert_eq!(d.half_steps(), 1);
        assert!(d.illegal.is_empty(), "{:?}", d.illegal);
        assert_eq!(d.travelled, 2 + 2 + 2);
    }

    #[test]
    fn after_a_power_cut_the_first_energising_snaps_and_is_legal() {
        let mut d = StepperDecoder::new(AxisGeometry::a_axis(), 0.0);
        // Held at phase 5 (0101 as IN1..IN4): position 5.
        d.observe(0, bits(1, 0, 1, 0));
        for (i, b) in [
            bits(0, 0, 1, 0),
            bits(0, 1, 1, 0),
            bits(0, 1, 0, 0),
            bits(0, 1, 0, 1),
        ]
        .into_iter()
        .enumerate()
        {
            d.observe(1 + i as u64, b);
        }
        assert_eq!(d.half_steps(), 5);
        // Without a power cut, phase 0 after phase 5 is a jump of three.
        let mut jumped = d.clone();
        jumped.observe(10_000, bits(1, 0, 0, 0));
        assert_eq!(jumped.illegal.len(), 1);
        // After one, the booted driver's first pattern (phase 0, on its way
        // to phase 1) snaps the rotor to the nearest phase-0 position, 8,
        // and the step to phase 1 counts on from there.
        d.power_cut(10_000);
        assert!(!d.energised());
        d.observe(20_000, bits(1, 0, 0, 0));
        d.observe(20_001, bits(1, 0, 1, 0));
        assert!(d.illegal.is_empty(), "{:?}", d.illegal);
        assert_eq!(d.half_steps(), 9);
    }

    #[test]
    fn ten_thousand_full_steps_are_one_turn() {
        let mut d = StepperDecoder::new(AxisGeometry::c_axis(), 0.0);
        let full = [
            bits(1, 0, 1, 0),
            bits(0, 1, 1, 0),
            bits(0, 1, 0, 1),
            bits(1, 0, 0, 1),
        ];
        d.observe(0, full[0]);
        let start = d.half_steps();
        let mut cur = full[0];
        for s in 1..=10_000usize {
            let next = full[s % 4];
            // Lows first, then highs.
            d.observe(0, cur & next);
            d.observe(0, next);
            cur = next;
        }
        assert!(d.illegal.is_empty());
        assert!(
            (d.angle_deg() - (start as f64 / AxisGeometry::HALF_STEPS_PER_DEG + 360.0)).abs()
                < 1e-9
        );
    }

    #[test]
    fn a_release_through_one_coil_leaves_the_rotor_where_it_was_held() {
        let mut d = StepperDecoder::new(AxisGeometry::a_axis(), 0.0);
        // Held at phase 1 (1010), then released IN1 first: 0010 (phase 2)
        // for 36 cycles, then 0000.
        d.observe(0, bits(1, 0, 1, 0));
        d.observe(10_000, bits(0, 0, 1, 0));
        d.observe(10_036, 0);
        assert_eq!(d.half_steps(), 1);
        // Re-energised at phase 1 through 1000 (phase 0): legal.
        d.observe(50_000, bits(1, 0, 0, 0));
        d.observe(50_040, bits(1, 0, 1, 0));
        assert!(d.illegal.is_empty(), "{:?}", d.illegal);
        assert_eq!(d.half_steps(), 1);
        // A pattern held longer than the settle time is where the rotor went.
        d.observe(60_000, bits(0, 0, 1, 0));
        d.observe(60_000 + SETTLE_CYCLES, 0);
        assert_eq!(d.half_steps(), 2);
    }

    #[test]
    fn jumps_and_shoot_through_are_illegal() {
        let mut d = StepperDecoder::new(AxisGeometry::a_axis(), 0.0);
        d.observe(0, bits(1, 0, 1, 0)); // phase 1
        d.observe(1, bits(0, 1, 1, 0)); // phase 3 directly: a 2-half-phase jump
        assert_eq!(d.illegal.len(), 1);
        d.observe(2, bits(1, 1, 0, 0)); // IN1 and IN2 high: not in the table
        assert_eq!(d.illegal.len(), 2);
        // A released rotor re-energised two half-phases away is a jump too.
        let mut d = StepperDecoder::new(AxisGeometry::a_axis(), 0.0);
        d.observe(0, bits(1, 0, 1, 0));
        d.observe(1, 0);
        d.observe(2, bits(0, 1, 1, 0));
        assert_eq!(d.illegal.len(), 1);
    }

    #[test]
    fn switches_follow_the_angle() {
        let mut d = StepperDecoder::new(AxisGeometry::a_axis(), -89.99);
        assert!(!d.home_closed());
        d.half_steps = (-90.0 * AxisGeometry::HALF_STEPS_PER_DEG).round() as i64;
        assert!(d.home_closed());
        d.half_steps = (91.0 * AxisGeometry::HALF_STEPS_PER_DEG).round() as i64;
        assert!(d.max_closed());
    }
}
