//! Nutation in longitude and obliquity (NREL SPA report, section 3.4,
//! eq. 15–23, Table A4.3).

use super::earth::{c32, is_f32};
use super::rot::{Rot, RotTable};
use super::tables::{NUTATION_ABCD, NUTATION_Y};
use super::turns::sin_cos_deg;
use crate::float::Float;

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

/// Slot of the power e^{i k Xj} in the work table: `9 j + 4 + k` for
/// k = −4…4 (|Yij| ≤ 4 in Table A4.3; the k = 0 slots are never read). The
/// products of [`PROGRAM`] follow from slot [`N_POWERS`] on.
const fn power_slot(j: usize, k: i8) -> u8 {
    (9 * j as i32 + 4 + k as i32) as u8
}
const N_POWERS: usize = 45;

/// The evaluation order of the 63 arguments' sin/cos pairs, fixed at compile
/// time. Each term's pair is the product of the powers of its non-zero
/// multiples Yij in order of j, formed left to right, and terms that share
/// a leading run of factors (e.g. `2F + 2Ω` after the same D, M, M′) share
/// its product: one complex multiplication per distinct prefix, 78 for
/// Table A4.3 instead of 104, each rounded exactly as the term-by-term chain
/// (the `f32` results equal the old term-by-term evaluation bit for bit,
/// tested in `legacy`).
struct Program {
    /// `(dst, a, b)`: slot `dst` = slot `a` × slot `b` (`b` a power).
    ops: [(u8, u8, u8); N_OPS_MAX],
    n_ops: usize,
    /// The slot of each term's product.
    term: [u8; 63],
}

/// An upper bound of the distinct prefixes (every non-leading factor).
const N_OPS_MAX: usize = 63 * 4;

const PROGRAM: Program = {
    let mut p = Program {
        ops: [(0, 0, 0); N_OPS_MAX],
        n_ops: 0,
        term: [0; 63],
    };
    let mut i = 0;
    while i < 63 {
        let mut cur = 0u8;
        let mut first = true;
        let mut j = 0;
        while j < 5 {
            let k = NUTATION_Y[i][j];
            assert!(k >= -4 && k <= 4);
            if k != 0 {
                let f = power_slot(j, k);
                if first {
                    cur = f;
                    first = false;
                } else {
                    // An existing product of the same prefix and factor?
                    let mut found = N_OPS_MAX;
                    let mut o = 0;
                    while o < p.n_ops {
                        if p.ops[o].1 == cur && p.ops[o].2 == f {
                            found = o;
                        }
                        o += 1;
                    }
                    if found == N_OPS_MAX {
                        let dst = (N_POWERS + p.n_ops) as u8;
                        p.ops[p.n_ops] = (dst, cur, f);
                        p.n_ops += 1;
                        cur = dst;
                    } else {
                        cur = p.ops[found].0;
                    }
                }
            }
            j += 1;
        }
        assert!(!first, "every term has a non-zero multiple");
        p.term[i] = cur;
        i += 1;
    }
    p
};

/// Slots the program needs.
const N_SLOTS: usize = N_POWERS + PROGRAM.n_ops;
/// `f64` rounds the slots up to a power of two, so a masked index is in
/// range by construction (no bounds check in the loops); `f32` keeps the
/// exact count (the smaller stack frame, for 8-bit targets) and checks.
const SLOTS_F64: usize = N_SLOTS.next_power_of_two();
const SLOTS_F32: usize = N_SLOTS;
const _: () = assert!(SLOTS_F64 <= 256);

/// The number of leading terms of Table A4.3 with a time-dependent
/// coefficient (b or d non-zero): after them, a + b T = a and c + d T = c
/// exactly, so the rest skip the product with T.
const N_SECULAR_TERMS: usize = {
    let mut n = 0;
    let mut i = 0;
    while i < NUTATION_ABCD.f64s.len() {
        if NUTATION_ABCD.f64s[i][1] != 0.0 || NUTATION_ABCD.f64s[i][3] != 0.0 {
            n = i + 1;
        }
        i += 1;
    }
    n
};

/// The sin/cos pairs of the powers and products, in `N` slots.
struct Work<T, const N: usize>(RotTable<T, N>);

impl<T: Float, const N: usize> Work<T, N> {
    /// Every term's e^{i Σ Yij Xj} for the fundamental arguments `x`
    /// (degrees).
    #[inline(always)]
    fn new(x: [T; 5]) -> Self {
        let mut w = RotTable::zeroed();
        for (j, xj) in x.into_iter().enumerate() {
            let z = if is_f32::<T>() {
                Rot::of_rad(xj.to_radians())
            } else {
                // Reduced in degrees first, exactly (see `turns`).
                let (s, c) = sin_cos_deg(xj.to_f64());
                Rot {
                    c: T::from_f64(c),
                    s: T::from_f64(s),
                }
            };
            let mut acc = Rot::ONE;
            for k in 1..=4i8 {
                acc = acc.mul(z);
                w.set(power_slot(j, k), acc);
                w.set(power_slot(j, -k), acc.conj());
            }
        }
        // A term's first factor stands for 1 · e^{i k Xj}, which rounds to
        // itself; each op multiplies on the next factor.
        let ops = PROGRAM.ops.get(..PROGRAM.n_ops).unwrap_or(&[]);
        for &(dst, a, b) in ops {
            w.set(dst, w.get(a).mul(w.get(b)));
        }
        Work(w)
    }

    /// Eq. 20–23 (before the unit conversion): Σ (a + b T) sin(Σ Xj Yij)
    /// and Σ (c + d T) cos(Σ Xj Yij), in 0.0001″, in table order.
    #[inline(always)]
    fn sums(&self, jce: T) -> (T, T) {
        let (mut dpsi, mut deps) = (T::ZERO, T::ZERO);
        let (secular, constant) = PROGRAM.term.split_at(N_SECULAR_TERMS);
        if is_f32::<T>() {
            let (k_sec, k_const) = NUTATION_ABCD.f32s.split_at(N_SECULAR_TERMS);
            for (&i, k) in secular.iter().zip(k_sec) {
                let r = self.0.get(i);
                dpsi += (c32::<T>(k[0]) + c32::<T>(k[1]) * jce) * r.s;
                deps += (c32::<T>(k[2]) + c32::<T>(k[3]) * jce) * r.c;
            }
            for (&i, k) in constant.iter().zip(k_const) {
                let r = self.0.get(i);
                dpsi += c32::<T>(k[0]) * r.s;
                deps += c32::<T>(k[2]) * r.c;
            }
        } else {
            let (k_sec, k_const) = NUTATION_ABCD.f64s.split_at(N_SECULAR_TERMS);
            for (&i, k) in secular.iter().zip(k_sec) {
                let r = self.0.get(i);
                dpsi += (T::from_f64(k[0]) + T::from_f64(k[1]) * jce) * r.s;
                deps += (T::from_f64(k[2]) + T::from_f64(k[3]) * jce) * r.c;
            }
            for (&i, k) in constant.iter().zip(k_const) {
                let r = self.0.get(i);
                dpsi += T::from_f64(k[0]) * r.s;
                deps += T::from_f64(k[2]) * r.c;
            }
        }
        (dpsi, deps)
    }
}

/// Nutation `(Δψ, Δε)` in radians for `jce` Julian centuries (TT), eq. 20–23.
///
/// The sine and cosine of each term's argument Σ Xj Yij are built from
/// those of the five Xj by complex multiplication (exact identities), so
/// 5 sin/cos pairs replace 63.
pub(crate) fn nutation_rad<T: Float>(jce: T) -> (T, T) {
    let x = fundamental_arguments_deg(jce);
    let (dpsi, deps) = if is_f32::<T>() {
        Work::<T, SLOTS_F32>::new(x).sums(jce)
    } else {
        Work::<T, SLOTS_F64>::new(x).sums(jce)
    };
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
    fn program_shares_prefixes_and_fits_its_table() {
        // Without sharing, a term with n non-zero multiples needs n − 1
        // multiplications.
        let unshared: usize = NUTATION_Y
            .iter()
            .map(|y| y.iter().filter(|&&k| k != 0).count() - 1)
            .sum();
        assert!(PROGRAM.n_ops < unshared, "{} vs {unshared}", PROGRAM.n_ops);
        assert!(N_SLOTS <= SLOTS_F64 && SLOTS_F64.is_power_of_two());
        // Every op reads slots written before it (the powers k ≠ 0 first);
        // every term reads a slot that is written.
        let mut written = [false; N_SLOTS];
        for (i, w) in written.iter_mut().enumerate().take(N_POWERS) {
            *w = i % 9 != 4;
        }
        for &(dst, a, b) in &PROGRAM.ops[..PROGRAM.n_ops] {
            assert!(written[usize::from(a)] && written[usize::from(b)]);
            assert!(usize::from(b) < N_POWERS && !written[usize::from(dst)]);
            written[usize::from(dst)] = true;
        }
        assert!(PROGRAM.term.iter().all(|&t| written[usize::from(t)]));
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
