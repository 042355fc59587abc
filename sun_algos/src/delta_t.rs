//! ΔT = TT − UT1 in seconds: a built-in model for when the caller has none.
//!
//! - Before 2005: the polynomials of Espenak & Meeus ("Five Millennium Canon
//!   of Solar Eclipses", NASA/TP-2006-214141; NASA eclipse web site,
//!   "Polynomial expressions for Delta T"), built on Morrison & Stephenson
//!   2004, valid −1999…3000; before −1999 their long-term parabola
//!   `−20 + 32·u²`, `u = (y − 1820)/100`.
//! - 2005.0–2024.0: linear interpolation of the observed annual values
//!   (1 January) published by the IERS / USNO (`ΔT = 32.184 s + (TAI − UTC)
//!   − (UT1 − UTC)`). Espenak & Meeus' own 2005–2050 extrapolation
//!   (`62.92 + 0.32217 t + 0.005589 t²`) has overshot: +2.3 s in 2020 and
//!   +21 s by 2050 against current predictions, so it is not used.
//! - After 2024.0: the long-term model of Stephenson, Morrison & Hohenkerk
//!   2016 (Proc. R. Soc. A 472) as updated by Morrison et al. 2021 (Proc. R.
//!   Soc. A 477): excess length of day `1.72·t − 3.5·sin(2π(t + 0.75)/14)`
//!   ms/day, `t = (y − 1825)/100`, integrated to
//!   `ΔT = 31.4115 t² + 284.8436 cos(2π(t + 0.75)/14) + c`, with `c` making
//!   it continuous at 2024.0.
//!
//! The year argument is the decimal year of the instant (Espenak & Meeus
//! take the middle of the month, `y = year + (month − 0.5)/12`; the
//! difference is below half a month, under 0.03 s today).
//!
//! Accuracy: about 0.1 s 1900–2024 (observed data), within 1 s of the
//! reference tables' ΔT (skyfield's model) up to 2050, then a prediction
//! whose own uncertainty grows to tens of seconds by 2100. Any year
//! [`crate::time::MIN_YEAR`]…[`crate::time::MAX_YEAR`] gives a finite value
//! without panicking.
//!
//! # Example
//!
//! ```
//! use sun_algos::{delta_t, UtcTime};
//!
//! // The reference files' ΔT is skyfield's (IERS data): 64.886 s on
//! // 2006-03-01T13:45:38Z (tests/data/sun_1999_2022.csv).
//! let t: UtcTime = "2006-03-01T13:45:38Z".parse()?;
//! assert!((delta_t::estimate_s::<f64>(&t) - 64.886).abs() < 0.1);
//! # Ok::<(), sun_algos::Error>(())
//! ```

use crate::float::Float;
use crate::time::UtcTime;

/// First year of the observed table.
const TABLE_FIRST_YEAR: i32 = 2005;
/// ΔT on 1 January of 2005, 2006, … 2024, centiseconds (IERS / USNO, given
/// to 0.01 s): whole numbers, so that no `f64` is read at run time.
const OBSERVED_CS: [i16; 20] = [
    6469, 6485, 6515, 6546, 6578, 6607, 6632, 6660, 6691, 6728, 6764, 6810, 6859, 6897, 6922, 6936,
    6936, 6929, 6920, 6918,
];
/// Makes the long-term model continuous at the table's last value:
/// `69.18 − (31.4115·1.99² + 284.8436·cos(2π·2.74/14))` (hand/Python check,
/// and `long_term_joins_the_table` below).
const LONG_TERM_OFFSET_S: f64 = -150.496_237_07;

/// ΔT in seconds for an instant (see the module documentation).
///
/// ```
/// use sun_algos::{delta_t, UtcTime};
///
/// // skyfield's ΔT in the reference files: 64.886 s on 2006-03-01 (observed
/// // era, this model within 0.1 s) and 70.188 s on 2043-05-30 (predicted,
/// // within 1 s up to 2050).
/// let t: UtcTime = "2006-03-01T13:45:38Z".parse()?;
/// assert!((delta_t::estimate_s::<f64>(&t) - 64.886).abs() < 0.1);
/// let t: UtcTime = "2043-05-30T18:16:49Z".parse()?;
/// assert!((delta_t::estimate_s::<f32>(&t) - 70.188).abs() < 1.0);
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn estimate_s<T: Float>(time: &UtcTime) -> T {
    let year = time.year();
    let len = if crate::time::is_leap_year(year) {
        366
    } else {
        365
    };
    let elapsed = T::from_u32(u32::from(time.day_of_year().saturating_sub(1)));
    let frac = (elapsed + time.day_fraction::<T>()) / T::from_u32(len);
    estimate_for_year(year, frac)
}

/// `c0 + c1·t + c2·t² + …` by Horner's rule, each coefficient a constant
/// of `T` folded at compile time (a slice of `f64` read at run time would
/// be converted by software `f64` routines on an 8-bit board).
macro_rules! poly {
    ($t:expr; $($c:expr),+) => {{
        let t: T = $t;
        poly!(@horner t; $($c),+)
    }};
    (@horner $t:ident; $c0:expr) => {
        T::from_f64($c0)
    };
    (@horner $t:ident; $c0:expr, $($c:expr),+) => {
        T::from_f64($c0) + $t * poly!(@horner $t; $($c),+)
    };
}

/// ΔT for the decimal year `year + frac` (`0 ≤ frac < 1`).
///
/// ```
/// use sun_algos::delta_t::estimate_for_year;
///
/// // Morrison & Stephenson 2004 as tabulated by Espenak & Meeus (NASA):
/// // year −500: 17 190 ± 430 s; year 1000: 1 570 ± 55 s; 1950: 29 s.
/// assert!((estimate_for_year::<f64>(-500, 0.0) - 17_190.0).abs() < 430.0);
/// assert!((estimate_for_year::<f64>(1000, 0.0) - 1_570.0).abs() < 55.0);
/// assert!((estimate_for_year::<f64>(1950, 0.0) - 29.0).abs() < 0.5);
/// // skyfield's ΔT on 2021-01-07 (tests/data/sun_2010_2110.csv): 69.359 s.
/// assert!((estimate_for_year::<f64>(2021, 6.5 / 365.0) - 69.359).abs() < 0.1);
/// ```
pub fn estimate_for_year<T: Float>(year: i32, frac: T) -> T {
    // Years since `base`, formed exactly from the integer year.
    let since = |base: i32| T::from_i32(year - base) + frac;
    let last_table_year = TABLE_FIRST_YEAR + OBSERVED_CS.len() as i32 - 1;
    if year < -500 {
        let u = since(1820) / T::from_f64(100.0);
        return T::from_f64(-20.0) + T::from_f64(32.0) * u * u;
    }
    if year < 500 {
        let u = since(0) / T::from_f64(100.0);
        return poly!(u; 10583.6,
                -1014.41,
                33.78311,
                -5.952053,
                -0.1798452,
                0.022174192,
                0.0090316521);
    }
    if year < 1600 {
        let u = since(1000) / T::from_f64(100.0);
        return poly!(u; 1574.2,
                -556.01,
                71.23472,
                0.319781,
                -0.8503463,
                -0.005050998,
                0.0083572073);
    }
    if year < 1700 {
        return poly!(since(1600); 120.0, -0.9808, -0.01532, 1.0 / 7129.0);
    }
    if year < 1800 {
        return poly!(since(1700); 8.83, 0.1603, -0.0059285, 0.00013336, -1.0 / 1_174_000.0);
    }
    if year < 1860 {
        return poly!(since(1800); 13.72,
                -0.332447,
                0.0068612,
                0.0041116,
                -0.00037436,
                0.0000121272,
                -0.0000001699,
                0.000000000875);
    }
    if year < 1900 {
        return poly!(since(1860); 7.62,
                0.5737,
                -0.251754,
                0.01680668,
                -0.0004473624,
                1.0 / 233_174.0);
    }
    if year < 1920 {
        return poly!(since(1900); -2.79, 1.494119, -0.0598939, 0.0061966, -0.000197);
    }
    if year < 1941 {
        return poly!(since(1920); 21.20, 0.84493, -0.076100, 0.0020936);
    }
    if year < 1961 {
        return poly!(since(1950); 29.07, 0.407, -1.0 / 233.0, 1.0 / 2547.0);
    }
    if year < 1986 {
        return poly!(since(1975); 45.45, 1.067, -1.0 / 260.0, -1.0 / 718.0);
    }
    if year < TABLE_FIRST_YEAR {
        return poly!(since(2000); 63.86,
                0.3345,
                -0.060374,
                0.0017275,
                0.000651814,
                0.00002373599);
    }
    if year < last_table_year {
        let i = (year - TABLE_FIRST_YEAR) as usize;
        if let (Some(&a), Some(&b)) = (OBSERVED_CS.get(i), OBSERVED_CS.get(i + 1)) {
            let (a, b) = (i32::from(a), i32::from(b));
            return (T::from_i32(a) + T::from_i32(b - a) * frac) / T::from_f64(100.0);
        }
    }
    // Long-term length-of-day model, t in centuries since 1825.
    let t = since(1825) / T::from_f64(100.0);
    T::from_f64(31.4115) * t * t
        + T::from_f64(284.843_580_525)
            * (T::from_f64(core::f64::consts::TAU / 14.0) * (t + T::from_f64(0.75))).cos()
        + T::from_f64(LONG_TERM_OFFSET_S)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::{MAX_YEAR, MIN_YEAR};

    fn at(year: i32) -> f64 {
        estimate_s(&UtcTime::from_ymd_hms(year, 1, 1, 0, 0, 0).unwrap())
    }

    #[test]
    fn published_values() {
        // Observed ΔT (Espenak & Meeus table "Delta T: past, present and
        // future"; IERS): 1900 −2.79 s, 1950 29.07 s, 1980 50.54 s,
        // 2000 63.83 s, 2010 66.07 s, 2020 69.36 s.
        for (y, dt) in [
            (1900, -2.79),
            (1950, 29.07),
            (1980, 50.54),
            (2000, 63.83),
            (2010, 66.07),
            (2020, 69.36),
        ] {
            assert!((at(y) - dt).abs() < 0.1, "{y}: {}", at(y));
        }
        // Morrison & Stephenson 2004 via Espenak & Meeus: 1700 ≈ 9 s,
        // 1800 ≈ 14 s, 1000 ≈ 1570 s, year 0 ≈ 10 580 s.
        for (y, dt, tol) in [(1700, 8.83, 0.1), (1800, 13.72, 0.1), (1000, 1574.2, 1.0)] {
            assert!((at(y) - dt).abs() < tol, "{y}: {}", at(y));
        }
        let y0: f64 = estimate_for_year(0, 0.0);
        assert!((y0 - 10583.6).abs() < 0.1);
    }

    #[test]
    fn continuous_at_segment_joins() {
        // Espenak & Meeus' pieces meet within about a second; ours too.
        for y in [
            -500, 500, 1600, 1700, 1800, 1860, 1900, 1920, 1941, 1961, 1986, 2005, 2024,
        ] {
            let before: f64 = estimate_for_year(y - 1, 0.999_999);
            let after: f64 = estimate_for_year(y, 0.0);
            let tol = if y <= 500 { 5.0 } else { 1.0 };
            assert!((before - after).abs() < tol, "{y}: {before} {after}");
        }
    }

    #[test]
    fn long_term_joins_the_table() {
        let after: f64 = estimate_for_year(2024, 0.0);
        assert!((after - 69.18).abs() < 1e-6, "{after}");
    }

    #[test]
    fn finite_for_every_year_and_both_floats() {
        let mut y = MIN_YEAR;
        while y <= MAX_YEAR {
            let t = UtcTime::from_ymd_hms(y, 12, 31, 23, 59, 59).unwrap();
            let a: f64 = estimate_s(&t);
            let b: f32 = estimate_s(&t);
            assert!(a.is_finite() && b.is_finite(), "{y}");
            // f32 loses a few ms where the 1800–1860 polynomial cancels.
            assert!(
                (a - f64::from(b)).abs() <= 1e-4 * a.abs() + 0.01,
                "{y}: {a} {b}"
            );
            y += 7;
        }
    }
}
