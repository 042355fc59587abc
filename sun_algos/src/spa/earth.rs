//! Earth heliocentric longitude, latitude and radius vector (NREL SPA report,
//! section 3.2, eq. 9–12, Table A4.2).

use super::fast_tables::{
    FastSeries, B0, B1, DERIVED, DIRECT, FREQUENCIES, L0, L1, L2, L3, L4, L5, N_FREQUENCIES, R0,
    R1, R2, R3, R4,
};
use super::rot::{Rot, RotTable};
use super::split::{frac, Secular};
use super::turns::sin_cos_turns;
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

/// Slots of the `f64` rotation table: [`N_FREQUENCIES`] rounded up to a
/// power of two, so that an index masked with `SLOTS_F64 − 1` is in range
/// by construction (no bounds check, no panic path in the hot loops).
const SLOTS_F64: usize = 128;
/// The `f32` table keeps exactly [`N_FREQUENCIES`] slots (the smallest stack
/// frame, for 8-bit targets); its look-ups are checked.
const SLOTS_F32: usize = N_FREQUENCIES;

/// Every frequency index of the tables is below [`N_FREQUENCIES`] (checked
/// at compile time, so masking never aliases two frequencies).
const _: () = {
    assert!(N_FREQUENCIES <= SLOTS_F64 && SLOTS_F64.is_power_of_two());
    let series = [
        &L0, &L1, &L2, &L3, &L4, &L5, &B0, &B1, &R0, &R1, &R2, &R3, &R4,
    ];
    let mut s = 0;
    while s < series.len() {
        let f = series[s].freq;
        assert!(f.len() == series[s].f64s.len() && f.len() == series[s].f32s.len());
        let mut i = 0;
        while i < f.len() {
            assert!((f[i] as usize) < N_FREQUENCIES);
            i += 1;
        }
        s += 1;
    }
    let mut i = 0;
    while i < DIRECT.len() {
        assert!((DIRECT[i] as usize) < N_FREQUENCIES);
        i += 1;
    }
    let mut i = 0;
    while i < DERIVED.len() {
        let (c, a, b, _) = DERIVED[i];
        assert!((c as usize) < N_FREQUENCIES);
        assert!((a as usize) < N_FREQUENCIES && (b as usize) < N_FREQUENCIES);
        i += 1;
    }
};

/// e^{i C τ} of every distinct frequency C, at its index in [`FREQUENCIES`],
/// in `N` slots ([`SLOTS_F64`] or [`SLOTS_F32`]).
struct Rotations<T, const N: usize>(RotTable<T, N>);

impl<T: Float, const N: usize> Rotations<T, N> {
    /// The table at `days + frac_tt` days (TT) from J2000.0.
    #[inline(always)]
    fn new(days: i32, frac_tt: T) -> Self {
        let mut r = RotTable::zeroed();
        // Index 0 is C = 0: sin 0 = 0, cos 0 = 1.
        r.set(0, Rot::ONE);
        // The direct ones take C τ in exact turns from the whole days, so even
        // `f32` keeps its precision when C τ reaches 10⁵ rad (τ = ±4 millennia).
        // `f64` reduces the turns exactly and evaluates sine and cosine in
        // one kernel (`turns`); `f32` goes through its trigonometry backend.
        for (&k, s) in DIRECT.iter().zip(DIRECT_SECULAR.iter()) {
            let v = if is_f32::<T>() {
                Rot::of_rad(s.rad(days, frac_tt))
            } else {
                let (sin, cos) = sin_cos_turns(s.at(days, frac_tt).to_f64());
                Rot {
                    c: T::from_f64(cos),
                    s: T::from_f64(sin),
                }
            };
            r.set(k, v);
        }
        // e^{i (a ± b)} = e^{i a} · e^{±i b}.
        for &(c, a, b, plus) in DERIVED.iter() {
            let rb = r.get(b);
            r.set(c, r.get(a).mul(if plus { rb } else { rb.conj() }));
        }
        Rotations(r)
    }

    /// Σ A cos(B + C τ) = Σ (A cos B) cos(C τ) − (A sin B) sin(C τ) over the
    /// terms of `s` from `skip` on (report eq. 9), in table order.
    #[inline(always)]
    fn sum(&self, s: &FastSeries, skip: usize) -> T {
        let mut acc = T::ZERO;
        let freq = s.freq.get(skip..).unwrap_or(&[]);
        if is_f32::<T>() {
            let k32 = s.f32s.get(skip..).unwrap_or(&[]);
            for (&i, k) in freq.iter().zip(k32) {
                let r = self.0.get(i);
                acc += c32::<T>(k[0]) * r.c - c32::<T>(k[1]) * r.s;
            }
        } else {
            let k64 = s.f64s.get(skip..).unwrap_or(&[]);
            for (&i, k) in freq.iter().zip(k64) {
                let r = self.0.get(i);
                acc += T::from_f64(k[0]) * r.c - T::from_f64(k[1]) * r.s;
            }
        }
        acc
    }

    /// Eq. 9–12 with this table (see [`heliocentric`]).
    #[inline(always)]
    fn heliocentric(&self, days: i32, frac_tt: T, tau: T) -> Heliocentric<T> {
        let e8 = T::from_f64(1e-8);
        let s = |series: &FastSeries| self.sum(series, 0);
        // L1 without its secular first term.
        let l_periodic = s(&L0)
            + tau
                * (self.sum(&L1, 1)
                    + tau * (s(&L2) + tau * (s(&L3) + tau * (s(&L4) + tau * s(&L5)))));
        let l_turns = frac(L1_SECULAR.at(days, frac_tt) + l_periodic * e8 / T::TAU);
        let b = (s(&B0) + tau * s(&B1)) * e8;
        let r_au = (s(&R0) + tau * (s(&R1) + tau * (s(&R2) + tau * (s(&R3) + tau * s(&R4))))) * e8;
        Heliocentric {
            l_rad: l_turns * T::TAU,
            b_rad: b,
            r_au,
        }
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
    if is_f32::<T>() {
        Rotations::<T, SLOTS_F32>::new(days, frac_tt).heliocentric(days, frac_tt, tau)
    } else {
        Rotations::<T, SLOTS_F64>::new(days, frac_tt).heliocentric(days, frac_tt, tau)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::spa::tables as report;

    /// The `f64` table at `days` days (TT) from J2000.0.
    fn filled(days: i32) -> Rotations<f64, SLOTS_F64> {
        Rotations::new(days, 0.0)
    }

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
            let r = filled(days);
            let tol = 1e-14 * (1.0 + 80_000.0 * tau.abs());
            for k in 0..N_FREQUENCIES {
                let Rot { c, s } = r.0.get(k as u8);
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
            let r = filled(days);
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
