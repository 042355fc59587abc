//! The periodic-term and nutation sums as they were before the
//! table-driven rewrite (test builds only), kept so that the tests below
//! pin what the rewrite may change: nothing in `f32`, and in `f64` only
//! the roundings of the sines and cosines of the Earth terms' direct
//! frequencies and of the nutation's fundamental arguments, which now
//! reduce their angles exactly (see `turns`) instead of through radians.

use super::earth::{c32, heliocentric, is_f32, Heliocentric, DAYS_PER_MILLENNIUM};
use super::fast_tables::{
    FastSeries, B0, B1, DERIVED, DIRECT, FREQUENCIES, L0, L1, L2, L3, L4, L5, N_FREQUENCIES, R0,
    R1, R2, R3, R4,
};
use super::nutation::{fundamental_arguments_deg, nutation_rad};
use super::split::{frac, Secular};
use super::tables::{NUTATION_ABCD, NUTATION_Y};
use crate::float::Float;

/// The same secular angles as `earth`'s.
fn l1_secular() -> Secular {
    Secular::turns(
        0.0,
        628_331_966_747.0e-8 / (core::f64::consts::TAU * DAYS_PER_MILLENNIUM),
    )
}

fn direct_secular(k: u8) -> Secular {
    let c = FREQUENCIES.f64s[usize::from(k)];
    Secular::turns(0.0, c / (core::f64::consts::TAU * DAYS_PER_MILLENNIUM))
}

/// sin(C τ) and cos(C τ) of every distinct frequency C (the old layout:
/// pairs, checked look-ups, libm's sin/cos of the angle in radians).
struct Rotations<T>([(T, T); N_FREQUENCIES]);

impl<T: Float> Rotations<T> {
    fn new(days: i32, frac_tt: T) -> Self {
        let mut r = [(T::ZERO, T::ONE); N_FREQUENCIES];
        for &k in DIRECT.iter() {
            if let Some(out) = r.get_mut(usize::from(k)) {
                *out = direct_secular(k).rad(days, frac_tt).sin_cos();
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

/// The old `heliocentric`.
fn old_heliocentric<T: Float>(days: i32, frac_tt: T, tau: T) -> Heliocentric<T> {
    let e8 = T::from_f64(1e-8);
    let r = Rotations::new(days, frac_tt);
    let s = |series: &FastSeries| r.sum(series, 0);
    let l_periodic = s(&L0)
        + tau * (r.sum(&L1, 1) + tau * (s(&L2) + tau * (s(&L3) + tau * (s(&L4) + tau * s(&L5)))));
    let l_turns = frac(l1_secular().at(days, frac_tt) + l_periodic * e8 / T::TAU);
    let b = (s(&B0) + tau * s(&B1)) * e8;
    let r_au = (s(&R0) + tau * (s(&R1) + tau * (s(&R2) + tau * (s(&R3) + tau * s(&R4))))) * e8;
    Heliocentric {
        l_rad: l_turns * T::TAU,
        b_rad: b,
        r_au,
    }
}

/// A unit complex number (the old nutation's).
#[derive(Clone, Copy)]
struct Rot<T> {
    c: T,
    s: T,
}

impl<T: Float> Rot<T> {
    const ONE: Rot<T> = Rot {
        c: T::ONE,
        s: T::ZERO,
    };
    fn mul(self, o: Rot<T>) -> Rot<T> {
        Rot {
            c: self.c * o.c - self.s * o.s,
            s: self.s * o.c + self.c * o.s,
        }
    }
    fn conj(self) -> Rot<T> {
        Rot {
            c: self.c,
            s: -self.s,
        }
    }
}

/// The old `nutation_rad`: each term's product formed on its own, by a
/// branch per multiple.
fn old_nutation_rad<T: Float>(jce: T) -> (T, T) {
    let x = fundamental_arguments_deg(jce);
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
    let scale = T::from_f64(1e-4 / 3600.0).to_radians();
    (dpsi * scale, deps * scale)
}

/// 10 000 instants over SPA's range (years −2000…6000) from a fixed linear
/// congruential generator (Knuth's MMIX constants): whole days, a day
/// fraction in `[−0.5, 0.5)` and ΔT in `[−20, 180)` s.
fn instants() -> impl Iterator<Item = (i32, f64)> {
    let mut state: u64 = 0x5eed_5ba0;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..10_000).map(move |_| {
        let days = -1_461_000.0 + next() * 2_922_000.0;
        let frac_tt = next() - 0.5 + (next() * 200.0 - 20.0) / 86_400.0;
        (days as i32, frac_tt)
    })
}

#[test]
fn f32_is_bit_identical_to_the_old_sums() {
    for (days, frac_tt) in instants() {
        let f = frac_tt as f32;
        let tau = days as f32 / DAYS_PER_MILLENNIUM as f32 + f / DAYS_PER_MILLENNIUM as f32;
        let (new, old) = (heliocentric(days, f, tau), old_heliocentric(days, f, tau));
        assert_eq!(
            (new.l_rad.to_bits(), new.b_rad.to_bits(), new.r_au.to_bits()),
            (old.l_rad.to_bits(), old.b_rad.to_bits(), old.r_au.to_bits()),
            "{days} {frac_tt}"
        );
        let jce = tau * 10.0;
        let (new, old) = (nutation_rad(jce), old_nutation_rad(jce));
        assert_eq!(
            (new.0.to_bits(), new.1.to_bits()),
            (old.0.to_bits(), old.1.to_bits()),
            "{days} {frac_tt}"
        );
    }
}

#[test]
fn f64_differs_from_the_old_sums_by_roundings_only() {
    let mut worst = [0.0f64; 5];
    for (days, frac_tt) in instants() {
        let tau = f64::from(days) / DAYS_PER_MILLENNIUM + frac_tt / DAYS_PER_MILLENNIUM;
        let (new, old) = (
            heliocentric(days, frac_tt, tau),
            old_heliocentric(days, frac_tt, tau),
        );
        // L in [0, 2π): compare on the circle.
        let dl = (new.l_rad - old.l_rad).abs();
        let dl = dl.min(core::f64::consts::TAU - dl);
        let jce = tau * 10.0;
        let (new_n, old_n) = (nutation_rad(jce), old_nutation_rad(jce));
        for (w, d) in worst.iter_mut().zip([
            dl,
            (new.b_rad - old.b_rad).abs(),
            (new.r_au - old.r_au).abs(),
            (new_n.0 - old_n.0).abs(),
            (new_n.1 - old_n.1).abs(),
        ]) {
            *w = w.max(d);
        }
    }
    // Measured on these instants: L 1.8e-15 rad (2 ulp of L near 2π), B
    // 3.7e-21 rad (B is ~1e-6 rad), R 2.2e-16 AU (1 ulp), Δψ 6.8e-16 rad and
    // Δε 3.1e-16 rad (7e-11″: the old radians path rounded the fundamental
    // arguments at up to 3.3e5 rad, year 6000, to ~3e-11 rad).
    let bounds = [2.7e-15, 1.0e-20, 4.5e-16, 1.5e-15, 1.5e-15];
    for ((w, b), name) in worst
        .iter()
        .zip(bounds)
        .zip(["L", "B", "R", "dpsi", "deps"])
    {
        assert!(w <= &b, "{name}: {w:e} > {b:e}");
    }
}
