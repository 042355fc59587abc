//! Nutation in longitude and obliquity (NREL SPA report, section 3.4,
//! eq. 15–23, Table A4.3).

use super::earth::{c32, is_f32};
use super::tables::{NUTATION_ABCD, NUTATION_Y};
use crate::float::Float;

/// A unit complex number `cos x + i sin x`.
#[derive(Debug, Clone, Copy)]
struct Rot<T> {
    c: T,
    s: T,
}

impl<T: Float> Rot<T> {
    const ONE: Rot<T> = Rot {
        c: T::ONE,
        s: T::ZERO,
    };
    #[inline(always)]
    fn mul(self, o: Rot<T>) -> Rot<T> {
        Rot {
            c: self.c * o.c - self.s * o.s,
            s: self.s * o.c + self.c * o.s,
        }
    }
    #[inline(always)]
    fn conj(self) -> Rot<T> {
        Rot {
            c: self.c,
            s: -self.s,
        }
    }
}

/// The five fundamental arguments X0…X4 (D, M, M′, F, Ω) in degrees for
/// `jce` Julian centuries (TT): eq. 15–19.
pub(crate) fn fundamental_arguments_deg<T: Float>(jce: T) -> [T; 5] {
    let p = |a: f64, b: f64, c: f64, d: f64| {
        T::from_f64(a) + jce * (T::from_f64(b) + jce * (T::from_f64(c) + jce * T::from_f64(d)))
    };
    [
        p(297.85036, 445_267.111_480, -0.001_914_2, 1.0 / 189_474.0),
        p(357.52772, 35_999.050_340, -0.000_160_3, -1.0 / 300_000.0),
        p(134.96298, 477_198.867_398, 0.008_697_2, 1.0 / 56_250.0),
        p(93.27191, 483_202.017_538, -0.003_682_5, 1.0 / 327_270.0),
        p(125.04452, -1_934.136_261, 0.002_070_8, 1.0 / 450_000.0),
    ]
}

/// Nutation `(Δψ, Δε)` in radians for `jce` Julian centuries (TT), eq. 20–23.
///
/// The sine and cosine of each term's argument Σ Xj Yij are built from
/// those of the five Xj by complex multiplication (exact identities), so
/// 5 sin/cos pairs replace 63.
pub(crate) fn nutation_rad<T: Float>(jce: T) -> (T, T) {
    let x = fundamental_arguments_deg(jce);
    // powers[j][k] = e^{i k Xj}, k = 0…4 (|Yij| ≤ 4 in Table A4.3).
    let mut powers = [[Rot::<T>::ONE; 5]; 5];
    for (pj, xj) in powers.iter_mut().zip(x) {
        let (s, c) = xj.to_radians().sin_cos();
        let z = Rot { c, s };
        let mut acc = Rot::ONE;
        for p in pj.iter_mut().skip(1) {
            acc = acc.mul(z);
            *p = acc;
        }
    }
    let (mut dpsi, mut deps) = (T::ZERO, T::ZERO);
    let mut term = |y: &[i8; 5], a: T, b: T, c: T, d: T| {
        let mut r = Rot::ONE;
        for (pj, &k) in powers.iter().zip(y) {
            if k != 0 {
                let p = pj
                    .get(usize::from(k.unsigned_abs()))
                    .copied()
                    .unwrap_or(Rot::ONE);
                r = r.mul(if k < 0 { p.conj() } else { p });
            }
        }
        dpsi += (a + b * jce) * r.s;
        deps += (c + d * jce) * r.c;
    };
    if is_f32::<T>() {
        for (y, k) in NUTATION_Y.iter().zip(NUTATION_ABCD.f32s) {
            term(y, c32(k[0]), c32(k[1]), c32(k[2]), c32(k[3]));
        }
    } else {
        for (y, k) in NUTATION_Y.iter().zip(NUTATION_ABCD.f64s) {
            let f = T::from_f64;
            term(y, f(k[0]), f(k[1]), f(k[2]), f(k[3]));
        }
    }
    // Units of 0.0001″ → radians.
    let scale = T::from_f64(1e-4 / 3600.0).to_radians();
    (dpsi * scale, deps * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multipliers_fit_the_power_table() {
        assert!(NUTATION_Y.iter().flatten().all(|k| k.unsigned_abs() <= 4));
    }

    #[test]
    fn products_equal_direct_sines() {
        // Independent check of the complex-product shortcut: direct sin/cos of
        // Σ Xj Yij (eq. 22–23 as printed) give the same sums.
        let jce = 0.037_927_6f64;
        let x = fundamental_arguments_deg(jce);
        let (mut p, mut e) = (0.0, 0.0);
        for (y, k) in NUTATION_Y.iter().zip(NUTATION_ABCD.f64s) {
            let arg: f64 = y.iter().zip(x).map(|(&yy, xx)| f64::from(yy) * xx).sum();
            p += (k[0] + k[1] * jce) * arg.to_radians().sin();
            e += (k[2] + k[3] * jce) * arg.to_radians().cos();
        }
        let (dpsi, deps) = nutation_rad(jce);
        let s = (1e-4f64 / 3600.0).to_radians();
        assert!((dpsi - p * s).abs() < 1e-14);
        assert!((deps - e * s).abs() < 1e-14);
    }
}
