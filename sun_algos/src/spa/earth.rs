//! Earth heliocentric longitude, latitude and radius vector (NREL SPA report,
//! section 3.2, eq. 9–12, Table A4.2).

use super::fast_tables::{
    FastSeries, B0, B1, DERIVED, DIRECT, FREQUENCIES, L0, L1, L2, L3, L4, L5, N_FREQUENCIES, R0,
    R1, R2, R3, R4,
};
use super::split::{frac, Secular};
use crate::float::Float;

/// Days in a Julian millennium.
pub(crate) const DAYS_PER_MILLENNIUM: f64 = 365_250.0;

/// The first term of L1, `628 331 966 747 · 10⁻⁸ rad` per millennium with
/// B = C = 0: Earth's mean motion. Multiplied by τ it grows to hundreds of
/// radians, so it is evaluated apart, in exact turns (see [`super::split`]).
const L1_SECULAR_RAD_PER_MILLENNIUM: f64 = 628_331_966_747.0e-8;
const L1_SECULAR: Secular = Secular::turns(
    0.0,
    L1_SECULAR_RAD_PER_MILLENNIUM / (core::f64::consts::TAU * DAYS_PER_MILLENNIUM),
);

/// True when `T` is the single-precision type (a compile-time constant).
#[inline(always)]
pub(crate) fn is_f32<T>() -> bool {
    core::mem::size_of::<T>() == 4
}

/// `f32` constant into `T` (folds to nothing when `T` is `f32`).
#[inline(always)]
pub(crate) fn c32<T: Float>(v: f32) -> T {
    T::from_f64(f64::from(v))
}

/// Σ A cos(B + C τ) over the terms from `skip` on (report eq. 9), written
/// literally: the reference the regrouped evaluation is tested against.
#[cfg(test)]
fn sum<T: Float>(s: &super::tables::Series, tau: T, skip: usize) -> T {
    let mut acc = T::ZERO;
    for t in s.f64s.iter().skip(skip) {
        acc += T::from_f64(t[0]) * (T::from_f64(t[1]) + T::from_f64(t[2]) * tau).cos();
    }
    acc
}

/// C τ of each direct frequency as a secular angle in days (rad per
/// millennium → turns per day).
const DIRECT_SECULAR: [Secular; DIRECT.len()] = {
    let mut out = [Secular::turns(0.0, 0.0); DIRECT.len()];
    let mut i = 0;
    while i < DIRECT.len() {
        let c = FREQUENCIES.f64s[DIRECT[i] as usize];
        out[i] = Secular::turns(0.0, c / (core::f64::consts::TAU * DAYS_PER_MILLENNIUM));
        i += 1;
    }
    out
};

/// sin(C τ) and cos(C τ) of every distinct frequency C.
struct Rotations<T>([(T, T); N_FREQUENCIES]);

impl<T: Float> Rotations<T> {
    /// The pairs at `days + frac_tt` days (TT) from J2000.0.
    fn new(days: i32, frac_tt: T) -> Self {
        let mut r = [(T::ZERO, T::ONE); N_FREQUENCIES];
        // Index 0 is C = 0: sin 0 = 0, cos 0 = 1 as initialised. The direct
        // ones take C τ in exact turns from the whole days, so even `f32`
        // keeps its precision when C τ reaches 10⁵ rad (τ = ±4 millennia).
        for (&k, s) in DIRECT.iter().zip(DIRECT_SECULAR.iter()) {
            if let Some(out) = r.get_mut(usize::from(k)) {
                *out = s.rad(days, frac_tt).sin_cos();
            }
        }
        for &(c, a, b, plus) in DERIVED.iter() {
            let get = |i: u8| r.get(usize::from(i)).copied().unwrap_or((T::ZERO, T::ONE));
            let ((sa, ca), (sb, cb)) = (get(a), get(b));
            let v = if plus {
                (sa * cb + ca * sb, ca * cb - sa * sb)
            } else {
                (sa * cb - ca * sb, ca * cb + sa * sb)
            };
            if let Some(out) = r.get_mut(usize::from(c)) {
                *out = v;
            }
        }
        Rotations(r)
    }

    /// Σ A cos(B + C τ) = Σ (A cos B) cos(C τ) − (A sin B) sin(C τ) over the
    /// terms of `s` from `skip` on (report eq. 9).
    #[inline]
    fn sum(&self, s: &FastSeries, skip: usize) -> T {
        let mut acc = T::ZERO;
        let rot = |i: u8| {
            self.0
                .get(usize::from(i))
                .copied()
                .unwrap_or((T::ZERO, T::ZERO))
        };
        if is_f32::<T>() {
            for (&i, k) in s.freq.iter().zip(s.f32s).skip(skip) {
                let (sn, cs) = rot(i);
                acc += c32::<T>(k[0]) * cs - c32::<T>(k[1]) * sn;
            }
        } else {
            for (&i, k) in s.freq.iter().zip(s.f64s).skip(skip) {
                let (sn, cs) = rot(i);
                acc += T::from_f64(k[0]) * cs - T::from_f64(k[1]) * sn;
            }
        }
        acc
    }
}

/// Heliocentric position of the Earth.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Heliocentric<T> {
    /// L, radians in `[0, 2π)` (eq. 10–11).
    pub l_rad: T,
    /// B, radians (eq. 12 with the B tables).
    pub b_rad: T,
    /// R, astronomical units (eq. 12 with the R tables).
    pub r_au: T,
}

/// Eq. 9–12 at `days + frac_tt` days (TT) from J2000.0; `tau` is the same
/// instant in Julian millennia (JME).
pub(crate) fn heliocentric<T: Float>(days: i32, frac_tt: T, tau: T) -> Heliocentric<T> {
    let e8 = T::from_f64(1e-8);
    let r = Rotations::new(days, frac_tt);
    let s = |series: &FastSeries| r.sum(series, 0);
    // L1 without its secular first term.
    let l_periodic = s(&L0)
        + tau * (r.sum(&L1, 1) + tau * (s(&L2) + tau * (s(&L3) + tau * (s(&L4) + tau * s(&L5)))));
    let l_turns = frac(L1_SECULAR.at(days, frac_tt) + l_periodic * e8 / T::TAU);
    let b = (s(&B0) + tau * s(&B1)) * e8;
    let r_au = (s(&R0) + tau * (s(&R1) + tau * (s(&R2) + tau * (s(&R3) + tau * s(&R4))))) * e8;
    Heliocentric {
        l_rad: l_turns * T::TAU,
        b_rad: b,
        r_au,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::spa::tables as report;

    #[test]
    fn secular_term_is_the_first_l1_row() {
        let first = report::L1.f64s.first().copied().unwrap_or_default();
        assert_eq!(first, [L1_SECULAR_RAD_PER_MILLENNIUM * 1e8, 0.0, 0.0]);
    }

    #[test]
    fn fast_tables_match_the_report() {
        let pairs: [(&report::Series, &FastSeries); 13] = [
            (&report::L0, &L0),
            (&report::L1, &L1),
            (&report::L2, &L2),
            (&report::L3, &L3),
            (&report::L4, &L4),
            (&report::L5, &L5),
            (&report::B0, &B0),
            (&report::B1, &B1),
            (&report::R0, &R0),
            (&report::R1, &R1),
            (&report::R2, &R2),
            (&report::R3, &R3),
            (&report::R4, &R4),
        ];
        for (rep, fast) in pairs {
            assert_eq!(rep.f64s.len(), fast.f64s.len());
            assert_eq!(rep.f64s.len(), fast.freq.len());
            assert_eq!(rep.f32s.len(), fast.f32s.len());
            for ((t, k), &i) in rep.f64s.iter().zip(fast.f64s).zip(fast.freq) {
                let [a, b, c] = *t;
                assert_eq!(FREQUENCIES.f64s[usize::from(i)], c);
                assert!((k[0] - a * b.cos()).abs() <= 1e-15 * a.abs());
                assert!((k[1] - a * b.sin()).abs() <= 1e-15 * a.abs());
            }
        }
        // Every frequency is direct or derived exactly once, from known ones.
        let mut known = [false; N_FREQUENCIES];
        known[0] = true;
        for &k in DIRECT.iter() {
            assert!(!known[usize::from(k)]);
            known[usize::from(k)] = true;
        }
        for &(c, a, b, plus) in DERIVED.iter() {
            let (c, a, b) = (usize::from(c), usize::from(a), usize::from(b));
            assert!(known[a] && known[b] && !known[c]);
            known[c] = true;
            let f = FREQUENCIES.f64s;
            let sum = if plus { f[a] + f[b] } else { f[a] - f[b] };
            assert!((sum - f[c]).abs() <= 1e-12 * f[c], "{c}");
        }
        assert!(known.iter().all(|&k| k));
        // The derived sin/cos pairs equal direct ones, to the rounding of
        // arguments C τ (up to 3 × 10⁵ rad at SPA's τ = ±4 millennia).
        for tau in [-4.0f64, -0.6, -0.1, 0.0038, 0.11, 0.6, 4.0] {
            let days = (tau * DAYS_PER_MILLENNIUM).round() as i32;
            let tau = f64::from(days) / DAYS_PER_MILLENNIUM;
            let r = Rotations::new(days, 0.0);
            let tol = 1e-14 * (1.0 + 80_000.0 * tau.abs());
            for (k, &(s, c)) in r.0.iter().enumerate() {
                let (s0, c0) = (FREQUENCIES.f64s[k] * tau).sin_cos();
                assert!(
                    (s - s0).abs() < tol && (c - c0).abs() < tol,
                    "{k} {tau}: {} {}",
                    s - s0,
                    c - c0
                );
            }
        }
        // Series agree with the literal sum of eq. 9 at several epochs.
        for tau in [-4.0f64, -0.4, -0.1, 0.0, 0.0038, 0.05, 0.11, 0.4, 4.0] {
            let days = (tau * DAYS_PER_MILLENNIUM).round() as i32;
            let tau = f64::from(days) / DAYS_PER_MILLENNIUM;
            let r = Rotations::new(days, 0.0);
            for (rep, fast) in pairs {
                let want = sum(rep, tau, 0);
                let got = r.sum(fast, 0);
                // Both round the argument B + C τ (or C τ) to f64, and the
                // derived sin/cos pairs add a few more roundings: allow some
                // ulps of each term's argument, times its amplitude.
                let tol: f64 = rep
                    .f64s
                    .iter()
                    .map(|t| t[0].abs() * (1.0 + t[1].abs() + (t[2] * tau).abs()) * 2e-14)
                    .sum();
                assert!((got - want).abs() <= tol, "{tau}: {got} vs {want}");
            }
        }
    }
}
