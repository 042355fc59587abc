//! Optical incremental quadrature encoder on a shaft (YMT22 class, as in
//! Chowdhury et al. 2019): a disc of N lines gives two square waves A and B, 90°
//! (electrical) apart, so each line period holds four states and a ×4
//! decoder counts 4N per revolution.
//!
//! Figures: **N = 300 lines per revolution** by default ([`YMT22_LINES`]):
//! Chowdhury et al. 2019, Figure 2 ("YMT22 Optical Encoder — resolution up
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
//! (`QuadratureEncoder::edges_between`) change one channel at a time, so
//! a decoder fed each of them in turn never sees an illegal (two-bit)
//! transition; `QuadratureEncoder::timed_edges` times them on a piece of
//! servo motion ([`crate::servo::Segment`]). `no_std` but for those two
//! (feature `std`, lists): [`QuadratureEncoder::edges`] gives the same
//! edges one at a time, as the servo plants of the host tests
//! (`tests/common/servo.rs`) feed them to `drivers::encoder::SharedEncoder`.

#[cfg(feature = "std")]
use std::vec::Vec;

#[cfg(feature = "std")]
use crate::servo::Segment;

/// YMT22 lines per revolution (Chowdhury et al. 2019: "up to 300 ppr").
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
        libm::floor(self.counts_f(angle_deg)) as i64
    }

    /// Channel levels `(A, B)` at input angle `angle_deg`.
    pub fn levels_at(&self, angle_deg: f64) -> (bool, bool) {
        levels_of_count(self.count_at(angle_deg))
    }

    /// The edges, in order, that the channels show while the input shaft
    /// moves monotonically from `from_deg` to `to_deg`: one per count
    /// crossed, each changing one channel. None when no boundary is
    /// crossed.
    pub fn edges(&self, from_deg: f64, to_deg: f64) -> impl Iterator<Item = Edge> + '_ {
        let c0 = self.count_at(from_deg);
        let c1 = self.count_at(to_deg);
        let up = c1 >= c0;
        let edge = move |count: i64, boundary: i64| {
            let (a, b) = levels_of_count(count);
            Edge {
                count,
                angle_deg: self.angle_of_counts(boundary),
                a,
                b,
            }
        };
        (1..=(c1 - c0).abs()).map(move |i| {
            if up {
                // Up: entering count k at its lower boundary k.
                edge(c0 + i, c0 + i)
            } else {
                // Down: entering count k at its upper boundary k + 1.
                let k = c0 - i;
                edge(k, k + 1)
            }
        })
    }

    /// [`QuadratureEncoder::edges`] as a list.
    #[cfg(feature = "std")]
    pub fn edges_between(&self, from_deg: f64, to_deg: f64) -> Vec<Edge> {
        self.edges(from_deg, to_deg).collect()
    }

    /// The edges of one piece of constant-speed motion, each with the time
    /// at which the shaft reaches it.
    #[cfg(feature = "std")]
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
