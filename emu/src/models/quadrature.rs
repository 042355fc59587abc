//! Optical incremental quadrature encoder on a shaft (YMT22 class, Chowdhury
//! et al. 2019): two channels 90° apart, ×4 decoding. The model, its
//! figures and their sources are `sim::encoder` (the host tests' servo
//! plants feed its edges to `drivers::encoder::SharedEncoder`); the Uno
//! bench puts [`QuadratureEncoder::timed_edges`] on the encoder pins.

pub use sim::encoder::{levels_of_count, Edge, QuadratureEncoder, FORWARD, YMT22_LINES};

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
