//! The constrained optimum (`best_within`) against brute-force grids at
//! 0.01° steps.

use sun_algos::geometry::incidence::{incidence_deg, Surface};
use sun_algos::geometry::optimum::{best_within, Limits};
use sun_algos::SunPosition;

struct Rng(u64);
impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// Best (slope, azimuth, cos θ) over a grid of step `step_deg` on the box.
fn grid(
    sun: &SunPosition<f64>,
    s0: f64,
    s1: f64,
    a0: f64,
    a1: f64,
    step_deg: f64,
) -> (f64, f64, f64) {
    let ns = ((s1 - s0) / step_deg).round() as usize;
    let na = ((a1 - a0) / step_deg).round() as usize;
    let (sz, cz) = sun.zenith_deg.to_radians().sin_cos();
    // cos θ = cos β cos θz + sin β sin θz cos(γs − γ), tabulated per axis.
    let slope: Vec<(f64, f64, f64)> = (0..=ns)
        .map(|i| {
            let b = (s0 + i as f64 * step_deg).min(s1);
            let (sb, cb) = b.to_radians().sin_cos();
            (b, cb * cz, sb * sz)
        })
        .collect();
    let az: Vec<(f64, f64)> = (0..=na)
        .map(|j| {
            let g = (a0 + j as f64 * step_deg).min(a1);
            (g, (sun.azimuth_deg - g).to_radians().cos())
        })
        .collect();
    let mut best = (0.0, 0.0, f64::NEG_INFINITY);
    for &(b, p, q) in &slope {
        for &(g, c) in &az {
            let v = p + q * c;
            if v > best.2 {
                best = (b, g, v);
            }
        }
    }
    best
}

fn circ_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

fn check(sun: &SunPosition<f64>, lim: &Limits<f64>, gb: (f64, f64, f64)) {
    let ours = best_within(sun, lim).unwrap();
    let grid_surface = Surface::new(gb.0, gb.1).unwrap();
    let grid_inc = incidence_deg(sun, &grid_surface);
    // Never worse than any grid point, and the grid point is within 0.01°.
    assert!(
        ours.incidence_deg <= grid_inc + 1e-9,
        "ours {ours:?} grid {gb:?}"
    );
    assert!(
        (ours.surface.slope_deg - gb.0).abs() <= 0.01 + 1e-9,
        "slope {} vs grid {} ({sun:?} {lim:?})",
        ours.surface.slope_deg,
        gb.0
    );
    assert!(
        circ_diff(ours.surface.azimuth_deg, gb.1) <= 0.01 + 1e-9,
        "azimuth {} vs grid {} ({sun:?} {lim:?})",
        ours.surface.azimuth_deg,
        gb.1
    );
    assert!(lim.contains(&ours.surface, 1e-9));
}

#[test]
fn small_boxes_match_a_full_001_degree_grid() {
    let mut rng = Rng(0xB0C5_2024);
    for case in 0..12 {
        let sun = SunPosition::new(rng.range(0.0, 100.0), rng.range(0.0, 360.0), false);
        // Boxes 5°–15° wide with a slope floor above 1° (at β = 0 every
        // azimuth is optimal and the comparison would be meaningless).
        let s0 = rng.range(1.0, 75.0);
        let s1 = s0 + rng.range(5.0, 15.0);
        // Every third box contains the sun's azimuth; the rest lie elsewhere.
        let a0 = if case % 3 == 0 {
            sun.azimuth_deg - 5.0
        } else {
            rng.range(-180.0, 360.0)
        };
        let a1 = a0 + rng.range(5.0, 15.0);
        let lim = Limits::new(s0, s1, a0, a1).unwrap();
        let gb = grid(&sun, s0, s1, a0, a1, 0.01);
        check(&sun, &lim, gb);
    }
}

#[test]
fn wide_boxes_match_a_two_level_grid() {
    // Full-range boxes are searched at 0.5°, then at 0.01° over ±1° around
    // the best coarse point (still no use of the method under test).
    let mut rng = Rng(0x0DD_BA11);
    for _ in 0..20 {
        let sun = SunPosition::new(rng.range(0.0, 110.0), rng.range(0.0, 360.0), false);
        let s0 = rng.range(2.0, 30.0);
        let s1 = s0 + rng.range(20.0, 60.0);
        let a0 = rng.range(-180.0, 360.0);
        let a1 = a0 + rng.range(60.0, 300.0);
        let lim = Limits::new(s0, s1, a0, a1).unwrap();
        let c = grid(&sun, s0, s1, a0, a1, 0.5);
        let fs0 = (c.0 - 1.0).max(s0);
        let fs1 = (c.0 + 1.0).min(s1);
        let fa0 = (c.1 - 1.0).max(a0);
        let fa1 = (c.1 + 1.0).min(a1);
        let gb = grid(&sun, fs0, fs1, fa0, fa1, 0.01);
        check(&sun, &lim, gb);
    }
}

#[test]
fn reachable_sun_gives_zero_incidence() {
    let sun = SunPosition::new(30.0f64, 200.0, false);
    let lim = Limits::new(0.0, 60.0, 90.0, 270.0).unwrap();
    let sp = best_within(&sun, &lim).unwrap();
    assert!(sp.incidence_deg < 1e-6);
}
