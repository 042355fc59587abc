//! Earth heliocentric longitude, latitude and radius vector (NREL SPA report,
//! section 3.2, eq. 9–12, Table A4.2).

use super::split::{frac, Secular};
use super::tables::{Series, B0, B1, L0, L1, L2, L3, L4, L5, R0, R1, R2, R3, R4};
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

/// Σ A cos(B + C τ) over the terms from `skip` on (report eq. 9).
#[inline]
fn sum<T: Float>(s: &Series, tau: T, skip: usize) -> T {
    let mut acc = T::ZERO;
    if is_f32::<T>() {
        for t in s.f32s.iter().skip(skip) {
            acc += c32::<T>(t[0]) * (c32::<T>(t[1]) + c32::<T>(t[2]) * tau).cos();
        }
    } else {
        for t in s.f64s.iter().skip(skip) {
            acc += T::from_f64(t[0]) * (T::from_f64(t[1]) + T::from_f64(t[2]) * tau).cos();
        }
    }
    acc
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
    // L1 without its secular first term.
    let l_periodic = sum(&L0, tau, 0)
        + tau
            * (sum(&L1, tau, 1)
                + tau
                    * (sum(&L2, tau, 0)
                        + tau
                            * (sum(&L3, tau, 0)
                                + tau * (sum(&L4, tau, 0) + tau * sum(&L5, tau, 0)))));
    let l_turns = frac(L1_SECULAR.at(days, frac_tt) + l_periodic * e8 / T::TAU);
    let b = (sum(&B0, tau, 0) + tau * sum(&B1, tau, 0)) * e8;
    let r = (sum(&R0, tau, 0)
        + tau
            * (sum(&R1, tau, 0)
                + tau * (sum(&R2, tau, 0) + tau * (sum(&R3, tau, 0) + tau * sum(&R4, tau, 0)))))
        * e8;
    Heliocentric {
        l_rad: l_turns * T::TAU,
        b_rad: b,
        r_au: r,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn secular_term_is_the_first_l1_row() {
        let first = L1.f64s.first().copied().unwrap_or_default();
        assert_eq!(first, [L1_SECULAR_RAD_PER_MILLENNIUM * 1e8, 0.0, 0.0]);
    }
}
