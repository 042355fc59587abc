//! Optical incremental quadrature encoder on a shaft (YMT22 class, seed
//! chowdhury-2019): a disc of N lines gives two square waves A and B, 90°
//! (electrical) apart, so each line period holds four states and a ×4
//! decoder counts 4N per revolution.
//!
//! Figures: **N = 300 lines per revolution** by default ([`YMT22_LINES`]):
//! seed chowdhury-2019, Figure 2 ("YMT22 Optical Encoder — resolution up
//! to 300 pulse per rotation (ppr); max. rotation speed 3000 rpm; supply
//! DC 5 V ±10 %"), the figure `drivers/src/encoder.rs` is written for.
//! The servo's 95 rpm is far below the encoder's 3,000 rpm; the same table's
//! "max. response frequency 30 Hz" cannot be a line rate (95 rpm × 300
//! lines is 475 Hz) and is not modelled: every edge is produced.
//!
//! States `(A, B)` in forward (increasing angle) order, A leading B — the
//! order `drivers::encoder` counts as forward: `00 → 10 → 11 → 01 → 00`
//! ([`FORWARD`]). Count and angle (floor semantics):
//!
//! ```text
//! count(θ) = floor(θ_enc · 4N / 360°),   θ_enc = ratio · θ + offset
//! (A, B)   = FORWARD[count mod 4]
//! ```
//!
//! so the count is `k` on `[k, k+1) · 360° / 4N` of the encoder disc, the
//! state at angle 0 is `00`, and an edge happens exactly when the disc
//! crosses a multiple of `360° / 4N`. `ratio` is the encoder's revolutions
//! per revolution of the input shaft (a gear between them; 1 when the
//! encoder sits on the servo's output shaft). The edges between two angles
//! ([`QuadratureEncoder::edges_between`]) change one channel at a time, so
//! a decoder fed each of them in turn never sees an illegal (two-bit)
//! transition; [`QuadratureEncoder::timed_edges`] times them on a piece of
//! servo motion ([`super::fs5106r::Segment`]).

use super::fs5106r::Segment;

/// YMT22 lines per revolution (seed chowdhury-2019: "up to 300 ppr").
pub const YMT22_LINES: u32 = 300;

/// Channel levels `(A, B)` for `count mod 4`, forward order (A leads B).
pub const FORWARD: [(bool, bool); 4] = [(false, false), (true, false), (true, true), (false, true)];

/// One level change of the channels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// The count after the edge.
    pub count: i64,
    /// Input-shaft angle at which it happens, degrees.
    pub angle_deg: f64,
    /// Level of A after the edge.
    pub a: bool,
    /// Level of B after the edge.
    pub b: bool,
}

/// An encoder: lines per revolution, gear ratio and angular offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadratureEncoder {
    lines_per_rev: u32,
    ratio: f64,
    offset_deg: f64,
}

impl QuadratureEncoder {
    /// An encoder of `lines_per_rev` lines on the input shaft (ratio 1,
    /// offset 0). Panics on 0 lines.
    pub fn new(lines_per_rev: u32) -> Self {
        assert!(lines_per_rev > 0, "an encoder needs at least one line");
        QuadratureEncoder {
            lines_per_rev,
            ratio: 1.0,
            offset_deg: 0.0,
        }
    }

    /// A YMT22 (300 lines) on the input shaft.
    pub fn ymt22() -> Self {
        Self::new(YMT22_LINES)
    }

    /// The encoder turns `ratio` revolutions per input revolution (negative:
    /// the gear reverses). Panics unless finite and non-zero.
    pub fn with_ratio(mut self, ratio: f64) -> Self {
        assert!(ratio.is_finite() && ratio != 0.0, "gear ratio {ratio}");
        self.ratio = ratio;
        self
    }

    /// The encoder disc is at `offset_deg` when the input shaft is at 0.
    pub fn with_offset_deg(mut self, offset_deg: f64) -> Self {
        self.offset_deg = offset_deg;
        self
    }

    /// Lines per revolution, N.
    pub fn lines_per_rev(&self) -> u32 {
        self.lines_per_rev
    }

    /// Counts per encoder revolution in ×4 decoding, 4N.
    pub fn counts_per_rev(&self) -> u32 {
        4 * self.lines_per_rev
    }

    /// Input-shaft degrees per count.
    pub fn deg_per_count(&self) -> f64 {
        360.0 / (f64::from(self.counts_per_rev()) * self.ratio.abs())
    }

    /// Encoder disc position in counts (fractional).
    fn counts_f(&self, angle_deg: f64) -> f64 {
        (self.ratio * angle_deg + self.offset_deg) * f64::from(self.counts_per_rev()) / 360.0
    }

    /// Input-shaft angle at which the disc is at `counts` (exact boundary).
    fn angle_of_counts(&self, counts: i64) -> f64 {
        (counts as f64 * 360.0 / f64::from(self.counts_per_rev()) - self.offset_deg) / self.ratio
    }

    /// Count at input angle `angle_deg`: `floor(θ_enc · 4N / 360)`.
    pub fn count_at(&self, angle_deg: f64) -> i64 {
        self.counts_f(angle_deg).floor() as i64
    }

    /// Channel levels `(A, B)` at input angle `angle_deg`.
    pub fn levels_at(&self, angle_deg: f64) -> (bool, bool) {
        levels_of_count(self.count_at(angle_deg))
    }

    /// The edges, in order, that the channels show while the input shaft
    /// moves monotonically from `from_deg` to `to_deg`: one per count
    /// crossed, each changing one channel. Empty when no boundary is
    /// crossed.
    pub fn edges_between(&self, from_deg: f64, to_deg: f64) -> Vec<Edge> {
        let c0 = self.count_at(from_deg);
        let c1 = self.count_at(to_deg);
        let edge = |count: i64, boundary: i64| {
            let (a, b) = levels_of_count(count);
            Edge {
                count,
                angle_deg: self.angle_of_counts(boundary),
                a,
                b,
            }
        };
        if c1 >= c0 {
            // Up: entering count k at its lower boundary k.
            (c0 + 1..=c1).map(|k| edge(k, k)).collect()
        } else {
            // Down: entering count k at its upper boundary k + 1.
            (c1..c0).rev().map(|k| edge(k, k + 1)).collect()
        }
    }

    /// The edges of one piece of constant-speed motion, each with the time
    /// at which the shaft reaches it.
    pub fn timed_edges(&self, segment: &Segment) -> Vec<(f64, Edge)> {
        if segment.speed_deg_s == 0.0 {
            return Vec::new();
        }
        self.edges_between(segment.angle0_deg, segment.angle1_deg())
            .into_iter()
            .map(|e| {
                let t = segment.t0_s + (e.angle_deg - segment.angle0_deg) / segment.speed_deg_s;
                (t.clamp(segment.t0_s, segment.t1_s), e)
            })
            .collect()
    }
}

/// Channel levels for a count.
pub fn levels_of_count(count: i64) -> (bool, bool) {
    FORWARD[count.rem_euclid(4) as usize]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::fs5106r::Fs5106r;
    use drivers::encoder::{transition, QuadratureDecoder, Transition};

    fn state((a, b): (bool, bool)) -> u8 {
        (u8::from(a) << 1) | u8::from(b)
    }

    /// Feeds `edges` to the repository's decoder started at `start`.
    fn decode(start: (bool, bool), edges: &[Edge]) -> QuadratureDecoder {
        let mut d = QuadratureDecoder::new(start.0, start.1);
        for e in edges {
            d.update(e.a, e.b);
        }
        d
    }

    #[test]
    fn one_revolution_forward_is_4n_legal_edges() {
        let enc = QuadratureEncoder::ymt22();
        let start = enc.levels_at(0.0);
        assert_eq!(start, (false, false));
        let edges = enc.edges_between(0.0, 360.0);
        assert_eq!(edges.len(), 1_200);
        let mut prev = start;
        for e in &edges {
            // Exactly one channel changes, in the decoder's forward sense.
            assert_eq!(u8::count_ones(state(prev) ^ state((e.a, e.b))), 1);
            assert_eq!(
                transition(state(prev), state((e.a, e.b))),
                Transition::Forward
            );
            prev = (e.a, e.b);
        }
        assert_eq!(prev, start);
        // Boundaries every 0.3° (360° / 1,200), increasing.
        assert!((edges[0].angle_deg - 0.3).abs() < 1e-12);
        assert!((edges[1_199].angle_deg - 360.0).abs() < 1e-9);
        assert!(edges.windows(2).all(|w| w[1].angle_deg > w[0].angle_deg));
        let d = decode(start, &edges);
        assert_eq!((d.count(), d.errors()), (1_200, 0));
    }

    #[test]
    fn backward_reverses() {
        let enc = QuadratureEncoder::ymt22();
        let fwd = enc.edges_between(0.0, 360.0);
        let back = enc.edges_between(360.0, 0.0);
        assert_eq!(back.len(), 1_200);
        // The same states in reverse order, ending at the start state.
        let fwd_states: Vec<(bool, bool)> = fwd.iter().map(|e| (e.a, e.b)).collect();
        let mut back_states: Vec<(bool, bool)> = back.iter().map(|e| (e.a, e.b)).collect();
        back_states.pop();
        back_states.reverse();
        assert_eq!(back_states[..], fwd_states[..1_199]);
        assert_eq!((back[1_199].a, back[1_199].b), (false, false));
        let mut prev = enc.levels_at(360.0);
        for e in &back {
            assert_eq!(
                transition(state(prev), state((e.a, e.b))),
                Transition::Backward
            );
            prev = (e.a, e.b);
        }
        let d = decode(enc.levels_at(360.0), &back);
        assert_eq!((d.count(), d.errors()), (-1_200, 0));
        assert!(back.windows(2).all(|w| w[1].angle_deg < w[0].angle_deg));
    }

    #[test]
    fn fractional_moves_give_no_edge_until_a_boundary() {
        let enc = QuadratureEncoder::ymt22(); // 0.3° per count
        assert!(enc.edges_between(0.1, 0.25).is_empty());
        assert!(enc.edges_between(0.25, 0.1).is_empty());
        assert!(enc.edges_between(0.31, 0.59).is_empty());
        let one = enc.edges_between(0.25, 0.31);
        assert_eq!(one.len(), 1);
        assert_eq!((one[0].count, one[0].a, one[0].b), (1, true, false));
        let back = enc.edges_between(0.31, 0.25);
        assert_eq!(back.len(), 1);
        assert_eq!((back[0].count, back[0].a, back[0].b), (0, false, false));
        assert!((back[0].angle_deg - 0.3).abs() < 1e-12);
    }

    #[test]
    fn decoded_count_is_floor_of_angle_times_4n_over_360() {
        // Hand-computed floor(θ · 1200 / 360) = floor(θ · 10 / 3):
        // 1234.567° → 4115.22 → 4115; 359.95° → 1199.83 → 1199;
        // 0.29° → 0.97 → 0; −77.75° → −259.17 → −260; −0.01° → −1.
        let enc = QuadratureEncoder::ymt22();
        for (angle, expected) in [
            (1_234.567, 4_115),
            (359.95, 1_199),
            (0.29, 0),
            (-77.75, -260),
            (-0.01, -1),
        ] {
            let d = decode(enc.levels_at(0.0), &enc.edges_between(0.0, angle));
            assert_eq!((d.count(), d.errors()), (expected, 0), "{angle}°");
            assert_eq!(enc.count_at(angle), i64::from(expected));
        }
        // N = 100 (400 counts/rev): 100.1° → 111.2 → 111.
        let small = QuadratureEncoder::new(100);
        let d = decode((false, false), &small.edges_between(0.0, 100.1));
        assert_eq!(d.count(), 111);
    }

    #[test]
    fn a_gear_multiplies_the_counts() {
        // The encoder turns twice per input revolution: 2 × 4N edges.
        let enc = QuadratureEncoder::ymt22().with_ratio(2.0);
        let edges = enc.edges_between(0.0, 360.0);
        assert_eq!(edges.len(), 2_400);
        assert!((edges[0].angle_deg - 0.15).abs() < 1e-12);
        let d = decode((false, false), &edges);
        assert_eq!((d.count(), d.errors()), (2_400, 0));
    }

    #[test]
    fn servo_motion_back_and_forth_decodes_to_the_final_angle() {
        // Full speed forward 1 s, full reverse 0.4 s, with pulses every
        // 20 ms; edges timed on each piece and fed in time order.
        let enc = QuadratureEncoder::ymt22();
        let mut servo = Fs5106r::at_6v(0.0, 0.0);
        let mut d = QuadratureDecoder::new(false, false);
        let mut last_t = 0.0;
        let mut n_edges = 0;
        for k in 0..70 {
            let t = k as f64 * 0.020;
            for seg in servo.segments_to(t) {
                for (te, e) in enc.timed_edges(&seg) {
                    assert!(te >= last_t);
                    last_t = te;
                    d.update(e.a, e.b);
                    n_edges += 1;
                }
            }
            servo.pulse(t, if k < 50 { 2_300.0 } else { 700.0 });
        }
        for seg in servo.segments_to(1.4) {
            for (_, e) in enc.timed_edges(&seg) {
                d.update(e.a, e.b);
                n_edges += 1;
            }
        }
        servo.advance_to(1.4);
        // 570 °/s × (1.0 − 0.4) s = 342° → 1,140 counts.
        assert!((servo.angle_deg() - 342.0).abs() < 1e-6);
        assert_eq!(d.errors(), 0);
        assert_eq!(i64::from(d.count()), enc.count_at(servo.angle_deg()));
        assert!((1_139..=1_140).contains(&d.count()), "{}", d.count());
        // 570° forward (1,900 edges) and 228° back (760 edges).
        assert!((2_659..=2_661).contains(&n_edges), "{n_edges}");
    }
}
