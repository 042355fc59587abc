//! The PSA sun position algorithm (Plataforma Solar de Almería) and its
//! later coefficient sets.
//!
//! Sources:
//! - Blanco-Muriel, Alarcón-Padilla, López-Moratalla & Lara-Coira 2001,
//!   "Computing the solar vector", Solar Energy 70(5) 431–441 (the
//!   algorithm; its coefficients are printed again in Li et al.
//!   2022, Table 2, left column);
//! - Blanco, Milidonis & Bonanos 2020, "Updating the PSA sun position
//!   algorithm", Solar Energy 212 339–341 ("PSA+": the same 15-coefficient
//!   form refitted for 2020–2050);
//! - Li, Wang & Munochiveyi 2022, "Experimental verification of the
//!   modified PSA algorithm", IEEE Access: Table 1, eqs. 2–17.
//!
//! The algorithm, with `n` the days since JD 2451545.0 and `h` the UT hour:
//! node `Ω = p0 + p1·n`, mean longitude `L = p2 + p3·n`, mean anomaly
//! `g = p4 + p5·n`, ecliptic longitude `l = L + p6·sin g + p7·sin 2g + p8 +
//! p9·sin Ω`, obliquity `ε = p10 + p11·n + p12·cos Ω`, sidereal time
//! `gmst = p13 + p14·n + h` hours; then right ascension, declination, hour
//! angle and the horizontal coordinates, plus the parallax
//! `(R⊕ / AU)·sin θz`.
//!
//! **Time scale.** PSA is driven by UT only: it has no ΔT, and the caller's
//! or the built-in ΔT is ignored (its fits absorb TT − UT over their range).
//!
//! **Precision.** Every angle that grows with time (`L`, `g`, `gmst`) is
//! reduced exactly: the whole-day part `rate × days` is computed as a
//! fraction of a turn in 64-bit fixed point (`whole_day_turns`) and only
//! the part of a day is multiplied in floating point. `f32` therefore keeps
//! its full precision (no Julian Day is ever formed in `T`). The horizontal
//! coordinates are taken from the sun's unit vector (`horizontal`), which
//! is the same as the paper's `acos`/`atan` formulas but well conditioned
//! near the zenith in `f32`.
//!
//! # Example
//!
//! ```
//! use sun_algos::{Algorithm, Options, Site, SunPosition, UtcTime};
//!
//! // tests/data/sun_2020_2050.csv (JPL DE421 through skyfield): 2045-07-06T04:35:23Z,
//! // 44.99275°, 165.49365° → zenith 48.4104141°, azimuth 260.8232083°.
//! let t: UtcTime = "2045-07-06T04:35:23Z".parse()?;
//! let truth = SunPosition::new(48.410_414_1f64, 260.823_208_3, false);
//! let p64 = Algorithm::Psa2020.position(&t, &Site::new(44.99275f64, 165.49365)?, &Options::default())?;
//! let p32 = Algorithm::Psa2020.position(&t, &Site::new(44.99275f32, 165.49365)?, &Options::default())?;
//! // PSA's declared 0.008°, and f32 within 0.0001° of f64: no Julian Day is
//! // formed in f32.
//! assert!(p64.angular_distance_deg(&truth) < 0.008);
//! let p32_in_f64 = SunPosition::new(f64::from(p32.zenith_deg), f64::from(p32.azimuth_deg), false);
//! assert!(p32_in_f64.angular_distance_deg(&p64) < 1e-4);
//! # Ok::<(), sun_algos::Error>(())
//! ```

use crate::algorithm::Inputs;
use crate::float::Float;
use crate::position::SunPosition;
use crate::site::{Atmosphere, Site};
use crate::time::UtcTime;

/// PSA coefficient sets, chosen through [`crate::Algorithm`] (`Psa2001`,
/// `Psa2020`, `PsaModified`, `PsaModifiedAsPrinted`).
///
/// ```
/// use sun_algos::psa::Variant;
/// use sun_algos::{Algorithm, Options, Site, UtcTime};
///
/// // The coefficient set of each PSA algorithm, by name; the NREL SPA worked
/// // example's instant and site (nrel_spa_test_vector.json: zenith
/// // 50.111622° with refraction, 50.127954° geometric: e0 = 39.872046°).
/// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
/// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// let p = Algorithm::Psa2001.position(&t, &site, &Options::default())?;
/// // PSA's declared 0.008°, plus the 1830 m elevation's parallax, which PSA
/// // leaves out (below 0.0001°).
/// assert!((p.zenith_deg - (90.0 - 39.872_046)).abs() < 0.008);
/// assert_ne!(Variant::Psa2001, Variant::Psa2020);
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Variant {
    /// Blanco-Muriel et al. 2001, stated for 1999–2015 (Li et al. 2022, Table 2,
    /// left column, with the nutation/aberration terms in `sin Ω`/`cos Ω` of
    /// the original paper, where `Ω = 2.1429 − 0.0010394594·n`; Li et al.
    /// print `sin(g)`/`cos(g)` there).
    Psa2001,
    /// "PSA+", Blanco, Milidonis & Bonanos 2020, stated for 2020–2050.
    Psa2020,
    /// The modified PSA of Li et al. 2022 with its printing errors corrected:
    /// `E1 = 0.033423055`; sidereal time `G1 + G2·n + G3·h` read as the
    /// complete IAU 1982 formula its `G3 = 1.00273790935` comes from
    /// (`G1 = 6.697374558`, `G2 = 24·(G3 − 1)`, `n` at 0 h UT; the printed
    /// `G1 = 6.6208844` matches no source and puts the sun 1.15° off);
    /// parallax adding `(R⊕/AU)·sin θz` to the zenith angle; refraction
    /// (eq. 17, `I1…I3`) with the pressure in atmospheres and the argument
    /// being the elevation in radians.
    ///
    /// Where Table 1 comes from: `C1 = 280.459°`, `D1 = 357.528°`,
    /// `E1 = 1.915°`, `E2 = 0.020°` (in radians) are the low-precision solar
    /// coordinates of the Astronomical Almanac / USNO (as in Michalsky
    /// 1988); `C2`, `D2`, `F1`–`F3` and `G2` are PSA 2001's; `G3 =
    /// 1.00273790935` is the hour factor of the IAU 1982 GMST
    /// `6.697374558 + 0.06570982441908·D0 + 1.00273790935·H` (`D0` at 0 h
    /// UT). PSA's `Ω` terms (nutation, aberration) are dropped.
    ///
    /// Measured (geometric, sun above the horizon): on sun_2020_2050
    /// (`tests/reference.rs`, 986 rows) max 0.00874° f64, 0.00877° f32,
    /// mean 0.0033°; 0.0087° also on 99 962 random instants and sites in
    /// 2020–2050 checked against this crate's SPA; the goal set for it was 0.008°.
    /// No correction that only repairs a misprint reaches it (measured,
    /// nothing fitted):
    /// - eq. 10 with PSA 2001's sidereal constants (`G1 = 6.6974243242`,
    ///   `G2 = 0.0657098283`, hour factor 1): 0.0094° (file), 0.0100° (dense);
    ///   the IAU 1982 constant with the printed `G2`: 0.0088° / 0.0093°;
    /// - `cos Ω` (2001 node) for eq. 6's `cos g`, as in PSA 2001 (Li et al.
    ///   print `g` for `Ω` in their 2001 column too): no change of the max.
    ///
    /// What limits it (diagnostic: one physical term of Meeus, Astronomical
    /// Algorithms ch. 22/25, added to this model; dense maxima):
    /// - `E1 = 1.915°` is the equation of centre of epoch 2000, while `2e`
    ///   falls by 0.0048° per century: a longitude error
    ///   `(0.0004° + 0.0048°·T)·sin g` (T in centuries from 2000), 0.0014° in
    ///   2020, 0.0021° in 2035, 0.0028° in 2050 — the only term that grows
    ///   toward 2050. With `2e` declining: 0.0100° → 0.0093°, and the
    ///   2045–2049 block 0.0100° → 0.0089°.
    /// - no nutation (`Δψ` 17.2″, `Δε` 9.2″; `F3·cos g` is no substitute):
    ///   up to about 0.003°. With Meeus's nutation: 0.0100° → 0.0094°; with
    ///   both: 0.0088° (0.0077° with the IAU 1982 reading of eq. 10).
    /// - the rest is the floor every 15-coefficient PSA shares (Earth–Moon
    ///   barycentre offset 6.4″·sin D, planetary terms): PSA+ measures
    ///   0.0079° on the same data.
    ///
    /// The mean-longitude rate is not a cause: `C2` equals Meeus's
    /// 36 000.76983° per century to 5e−13 rad/day. Dense maximum by 5-year
    /// block: 2020 0.0093°, 2025 0.0093°, 2030 0.0080°, 2035 0.0087°, 2040
    /// 0.0086°, 2045 0.0100°, 2050 0.0095°.
    Modified,
    /// Table 1 and eqs. 10, 15–17 of Li et al. 2022 exactly as printed:
    /// `E1 = 0.33423055`, `gmst = 6.6208844 + G2·n + G3·h` with `n` at the
    /// instant, parallax `−4.26e−5·cos(h)`, refraction with the pressure in
    /// millibars and the zenith angle as argument. Kept so the paper can be
    /// reproduced; **not usable**: measured against the reference ephemeris
    /// (`tests/reference.rs`, sun_2020_2050, sun above the horizon) its
    /// maximum error is 18.3°, its mean 11.1° (f64 and f32 alike), almost all
    /// of it from `E1` being ten times too large (the equation of centre
    /// swings by ±19°); `G1` alone would put it 1.15° off.
    ModifiedAsPrinted,
}

/// Earth's mean radius in km (Blanco-Muriel et al. 2001, parallax term).
///
/// ```
/// use sun_algos::psa::EARTH_MEAN_RADIUS_KM;
///
/// // IUGG mean Earth radius: 6371.0088 km.
/// assert!((EARTH_MEAN_RADIUS_KM - 6371.0088).abs() < 0.01);
/// ```
pub const EARTH_MEAN_RADIUS_KM: f64 = 6371.01;
/// The astronomical unit in km as used by Blanco-Muriel et al. 2001.
///
/// ```
/// use sun_algos::psa::ASTRONOMICAL_UNIT_KM;
///
/// // IAU 2012: 1 au = 149 597 870.7 km; PSA's value is 19.3 km larger.
/// assert!((ASTRONOMICAL_UNIT_KM - 149_597_870.7).abs() < 20.0);
/// ```
pub const ASTRONOMICAL_UNIT_KM: f64 = 149_597_890.0;
/// Horizontal solar parallax in radians, `R⊕ / AU` (≈ 4.2587e−5 rad,
/// 0.00244°).
///
/// ```
/// use sun_algos::psa::PARALLAX_RAD;
///
/// // The sun's mean horizontal parallax, 8.794″ (IAU; with the equatorial
/// // radius, 6378.137 km): the mean radius gives 0.1% less.
/// let arcsec = PARALLAX_RAD.to_degrees() * 3600.0;
/// assert!((arcsec - 8.794 * 6371.01 / 6378.137).abs() < 0.001);
/// ```
pub const PARALLAX_RAD: f64 = EARTH_MEAN_RADIUS_KM / ASTRONOMICAL_UNIT_KM;

/// The 15 coefficients of PSA plus the few switches the variants of Li et al. 2022 need.
struct Coefficients {
    /// `Ω = node[0] + node[1]·n` (rad).
    node: [f64; 2],
    /// `L = mean_longitude[0] + mean_longitude[1]·n` (rad).
    mean_longitude: [f64; 2],
    /// `g = mean_anomaly[0] + mean_anomaly[1]·n` (rad).
    mean_anomaly: [f64; 2],
    /// Factors of `sin g` and `sin 2g` (rad).
    centre: [f64; 2],
    /// Constant and factor of `sin Ω` added to the ecliptic longitude (rad).
    aberration: [f64; 2],
    /// `ε = obliquity[0] + obliquity[1]·n + obliquity[2]·cos(Ω or g)` (rad).
    obliquity: [f64; 3],
    /// `sin obliquity[0]` and `cos obliquity[0]` (Python `math.sin`/`math.cos`
    /// in f64; checked against libm by a test).
    obliquity0_sin_cos: [f64; 2],
    /// Eq. 6 of Li et al. 2022 takes `cos g` where PSA takes `cos Ω`.
    obliquity_cos_of_anomaly: bool,
    /// `gmst = gmst_h[0] + gmst_h[1]·n + hour_factor·h` (hours).
    gmst_h: [f64; 2],
    /// 1 for PSA; the `G3` of Li et al. 2022 in the printed set.
    hour_factor: f64,
    /// Sign of the parallax term (−1 only as printed in Li et al. 2022, eq. 15).
    parallax_sign: f64,
}

/// Blanco-Muriel et al. 2001 (Li et al. 2022, Table 2, left column).
const PSA_2001: Coefficients = Coefficients {
    node: [2.1429, -0.001_039_459_4],
    mean_longitude: [4.895_063_0, 0.017_202_791_698],
    mean_anomaly: [6.240_060_0, 0.017_201_969_9],
    centre: [0.033_416_07, 0.000_348_94],
    aberration: [-0.000_113_4, -0.000_020_3],
    obliquity: [0.409_092_8, -6.2140e-9, 0.000_039_6],
    obliquity0_sin_cos: [0.397_777_152_058_002_6, 0.917_482_063_748_727_9],
    obliquity_cos_of_anomaly: false,
    gmst_h: [6.697_424_324_2, 0.065_709_828_3],
    hour_factor: 1.0,
    parallax_sign: 1.0,
};

/// Blanco, Milidonis & Bonanos 2020 ("PSA+"), the 15 published coefficients.
const PSA_2020: Coefficients = Coefficients {
    node: [2.267_127_827, -9.300_339_267e-4],
    mean_longitude: [4.895_036_035, 1.720_279_602e-2],
    mean_anomaly: [6.239_468_336, 1.720_200_135e-2],
    centre: [3.338_320_972e-2, 3.497_596_876e-4],
    aberration: [-1.544_353_226e-4, -8.689_729_360e-6],
    obliquity: [4.090_904_909e-1, -6.213_605_399e-9, 4.418_094_944e-5],
    obliquity0_sin_cos: [0.397_775_033_499_108_75, 0.917_482_982_253_503_7],
    obliquity_cos_of_anomaly: false,
    gmst_h: [6.697_096_103, 6.570_984_737e-2],
    hour_factor: 1.0,
    parallax_sign: 1.0,
};

/// Li et al. 2022, Table 1, corrected (see [`Variant::Modified`]).
const MODIFIED: Coefficients = Coefficients {
    node: [0.0, 0.0],
    mean_longitude: [4.894_932_9, 0.017_202_791_698],
    mean_anomaly: [6.240_058_2, 0.017_201_969_9],
    centre: [0.033_423_055, 0.000_349_06],
    aberration: [0.0, 0.0],
    obliquity: [0.409_092_8, -6.2140e-9, 0.000_039_6],
    obliquity0_sin_cos: [0.397_777_152_058_002_6, 0.917_482_063_748_727_9],
    obliquity_cos_of_anomaly: true,
    // IAU 1982 GMST, whose hour factor is the G3 = 1.00273790935 of
    // Li et al. 2022:
    // 6.697374558 h + G2·n₀ + G3·h with G2 = 24·(G3 − 1) and n₀ at 0 h UT,
    // which is this structure's `G1 + G2·n + h` with n at the instant.
    gmst_h: [6.697_374_558, 0.065_709_824_4],
    hour_factor: 1.0,
    parallax_sign: 1.0,
};

/// Li et al. 2022, Table 1, as printed (see [`Variant::ModifiedAsPrinted`]).
const MODIFIED_AS_PRINTED: Coefficients = Coefficients {
    centre: [0.334_230_55, 0.000_349_06],
    gmst_h: [6.620_884_4, 0.065_709_828_3],
    hour_factor: 1.002_737_909_35,
    parallax_sign: -1.0,
    ..MODIFIED
};

/// A rate in turns per day as a 64-bit fixed-point fraction of a turn
/// (unit 2⁻⁶⁴ turn). Evaluated at compile time; the rate must lie in
/// `[0, 1)` turn per day.
pub(crate) const fn turns_per_day_fixed(turns_per_day: f64) -> u64 {
    (turns_per_day * 18_446_744_073_709_551_616.0) as u64
}

/// `rate × days` modulo one turn, as a value in `[0, 1]` turns.
///
/// `rate_fixed` comes from [`turns_per_day_fixed`]. The product is exact
/// modulo 2⁶⁴ (wrapping integer arithmetic; negative day counts work
/// through two's complement), so the result carries the full precision of
/// `T` whatever the number of days.
pub(crate) fn whole_day_turns<T: Float>(rate_fixed: u64, days: i32) -> T {
    let turns = rate_fixed.wrapping_mul(i64::from(days) as u64);
    let hi = (turns >> 32) as u32;
    let lo = turns as u32;
    T::from_u32(hi) * T::from_f64(1.0 / 4_294_967_296.0)
        + T::from_u32(lo) * T::from_f64(1.0 / 18_446_744_073_709_551_616.0)
}

/// `x − floor(x)` in turns, times 2π: an angle in `[0, 2π]`.
pub(crate) fn turns_to_rad<T: Float>(turns: T) -> T {
    (turns - turns.floor()) * T::TAU
}

/// Topocentric horizontal coordinates from the sun's declination and hour
/// angle, given as `sin δ`, `cos δ·cos H` and `cos δ·sin H`.
///
/// The standard spherical-astronomy relations (e.g. Blanco-Muriel et al.
/// 2001 eqs. for θz and γ; Li et al. 2022, eqs. 13–14) written for the unit
/// vector: east `= −cos δ sin H`, north `= sin δ cos φ − cos δ cos H sin φ`,
/// up `= sin δ sin φ + cos δ cos H cos φ`; zenith `= atan2(√(e²+n²), up)`,
/// azimuth `= atan2(e, n)` east of north. Returns `(zenith, azimuth,
/// sin zenith)` in radians; the arguments must form a unit vector (up to
/// rounding), as `sin zenith` is taken as its horizontal length.
pub(crate) fn horizontal<T: Float>(
    sin_dec: T,
    cos_dec_cos_h: T,
    cos_dec_sin_h: T,
    site: &Site<T>,
) -> (T, T, T) {
    let (sin_lat, cos_lat) = site.latitude_deg().to_radians().sin_cos();
    let east = -cos_dec_sin_h;
    let north = sin_dec * cos_lat - cos_dec_cos_h * sin_lat;
    let up = sin_dec * sin_lat + cos_dec_cos_h * cos_lat;
    let horiz = (east * east + north * north).sqrt();
    let zenith = horiz.atan2(up);
    let azimuth = east.atan2(north);
    // sin θz = horiz / |v|, and |v| = 1 up to rounding (a few ulp, from the
    // callers' sine/cosine pairs), so `horiz` itself is sin θz to ~1e−7
    // relative: the parallax (4.3e−5 rad) it multiplies moves by ~4e−12 rad.
    // No normalising square root and division.
    (zenith, azimuth, horiz)
}

/// Julian Day Number (of the noon starting the civil day) by the formula of
/// the PSA reference code (Fliegel & Van Flandern), with C's truncating
/// integer division.
///
/// With flooring division, `(month − 14) / 12` becomes −2 instead of −1 in
/// March–December and the result is off. With truncation it equals the
/// proleptic Gregorian day count for every date [`UtcTime`] accepts
/// (tested), so the algorithm itself uses [`UtcTime::days_since_2000`]
/// directly (JDN − 2451545).
///
/// ```
/// use sun_algos::psa::julian_day_number;
/// use sun_algos::UtcTime;
///
/// // Meeus, Astronomical Algorithms, ch. 7: 2000-01-01 12:00 is JD 2451545.0,
/// // and 1957-10-04 19:26:24 (example 7.a) is JD 2436116.31.
/// assert_eq!(julian_day_number(2000, 1, 1), 2_451_545);
/// assert_eq!(julian_day_number(1957, 10, 4), 2_436_116);
/// // The same day count as UtcTime's.
/// let t = UtcTime::from_ymd_hms(2024, 2, 29, 0, 0, 0)?;
/// assert_eq!(julian_day_number(2024, 2, 29), t.days_since_2000() + 2_451_545);
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn julian_day_number(year: i32, month: i32, day: i32) -> i32 {
    // Rust's `/` on integers truncates toward zero, like C.
    let aux1 = (month - 14) / 12;
    (1461 * (year + 4800 + aux1)) / 4 + (367 * (month - 2 - 12 * aux1)) / 12
        - (3 * ((year + 4900 + aux1) / 100)) / 4
        + day
        - 32075
}

/// Topocentric sun position by PSA with coefficient set `v`.
pub(crate) fn position<T: Float>(inp: &Inputs<'_, T>, v: Variant) -> SunPosition<T> {
    // One copy per set, so that every coefficient is a compile-time constant.
    match v {
        Variant::Psa2001 => position_with(inp, v, &PSA_2001),
        Variant::Psa2020 => position_with(inp, v, &PSA_2020),
        Variant::Modified => position_with(inp, v, &MODIFIED),
        Variant::ModifiedAsPrinted => position_with(inp, v, &MODIFIED_AS_PRINTED),
    }
}

#[inline(always)]
fn position_with<T: Float>(inp: &Inputs<'_, T>, v: Variant, c: &Coefficients) -> SunPosition<T> {
    let (days, frac) = elapsed_days(inp.time);
    // n = days + frac, with frac = (hour / 24) − 0.5 in [−0.5, 0.5).
    let n = T::from_i32(days) + frac;

    // Ecliptic coordinates (Blanco-Muriel et al. 2001; Li et al. 2022, eqs. 3–6).
    let node = T::from_f64(c.node[0]) + T::from_f64(c.node[1]) * n;
    let mean_longitude = daily_angle(c.mean_longitude, days, frac);
    let mean_anomaly = daily_angle(c.mean_anomaly, days, frac);
    let (sin_node, cos_node) = node.sin_cos();
    let (sin_g, cos_g) = mean_anomaly.sin_cos();
    let sin_2g = T::from_f64(2.0) * sin_g * cos_g;
    let ecliptic_longitude = mean_longitude
        + T::from_f64(c.centre[0]) * sin_g
        + T::from_f64(c.centre[1]) * sin_2g
        + T::from_f64(c.aberration[0])
        + T::from_f64(c.aberration[1]) * sin_node;
    let cos_arg = if c.obliquity_cos_of_anomaly {
        cos_g
    } else {
        cos_node
    };
    let obliquity_change = T::from_f64(c.obliquity[1]) * n + T::from_f64(c.obliquity[2]) * cos_arg;
    let (sin_eps, cos_eps) = obliquity_sin_cos(c, obliquity_change);

    // Equatorial unit vector: cos δ cos α = cos l, cos δ sin α = cos ε sin l,
    // sin δ = sin ε sin l (2001 paper; Li et al. 2022, eqs. 7–8, without
    // forming α).
    let (sin_l, cos_l) = ecliptic_longitude.sin_cos();
    let x = cos_l;
    let y = cos_eps * sin_l;
    let sin_dec = sin_eps * sin_l;

    // Local mean sidereal time (Li et al. 2022, eqs. 9–10): in turns, whole days
    // exactly, then the part of the day and the longitude.
    let gmst_rate = c.gmst_h[1] / 24.0;
    let gmst_turns = T::from_f64(c.gmst_h[0] / 24.0)
        + whole_day_turns::<T>(fixed(gmst_rate), days)
        + T::from_f64(gmst_rate) * frac
        + T::from_f64(c.hour_factor) * inp.time.day_fraction::<T>();
    let lmst = turns_to_rad(gmst_turns) + inp.site.longitude_deg().to_radians();
    // Hour angle H = lmst − α (eq. 12): cos δ cos H, cos δ sin H.
    let (sin_t, cos_t) = lmst.sin_cos();
    let cos_dec_cos_h = x * cos_t + y * sin_t;
    let cos_dec_sin_h = x * sin_t - y * cos_t;

    let (zenith, azimuth, sin_zenith) = horizontal(sin_dec, cos_dec_cos_h, cos_dec_sin_h, inp.site);
    // Parallax (2001 paper; Li et al. 2022, eqs. 15–16, sign corrected
    // unless printed).
    let zenith = zenith + T::from_f64(c.parallax_sign * PARALLAX_RAD) * sin_zenith;

    let geometric = SunPosition::new(zenith.to_degrees(), azimuth.to_degrees(), false);
    match v {
        Variant::Modified | Variant::ModifiedAsPrinted => match inp.atmosphere {
            None => geometric,
            Some(atm) => {
                let dz = li_refraction_rad(zenith, &atm, v == Variant::ModifiedAsPrinted);
                SunPosition::new((zenith - dz).to_degrees(), geometric.azimuth_deg, true)
            }
        },
        Variant::Psa2001 | Variant::Psa2020 => {
            crate::refraction::apply(geometric, inp.atmosphere.as_ref())
        }
    }
}

/// `sin ε` and `cos ε` for the obliquity `ε = ε₀ + δ` (eq. 6), `δ` the
/// change `obliquity[1]·n + obliquity[2]·cos(Ω or g)`.
///
/// `δ` is tiny (|δ| < 1.6e−4 rad over 2020–2050), so instead of a sine and a
/// cosine this takes the angle-addition formulas with `sin ε₀`, `cos ε₀`
/// constant and `sin δ ≈ δ`, `cos δ ≈ 1 − δ²/2`: `sin ε = sin ε₀·(1 − δ²/2) +
/// cos ε₀·δ`, `cos ε = cos ε₀·(1 − δ²/2) − sin ε₀·δ`, whose truncation error
/// is below `|δ|³/6` (7e−13 rad at 1.6e−4, 1.7e−10 at the 1e−3 cut-off,
/// about ±440 years from 2000). Beyond the cut-off (only reachable with
/// `allow_out_of_range`) the sine and cosine are computed.
#[inline(always)]
fn obliquity_sin_cos<T: Float>(c: &Coefficients, change: T) -> (T, T) {
    if change.abs() > T::from_f64(1e-3) {
        return (T::from_f64(c.obliquity[0]) + change).sin_cos();
    }
    let [sin0, cos0] = c.obliquity0_sin_cos;
    let half_sq = change * change;
    let sin_eps =
        T::from_f64(sin0) + (T::from_f64(cos0) * change - T::from_f64(0.5 * sin0) * half_sq);
    let cos_eps =
        T::from_f64(cos0) - (T::from_f64(sin0) * change + T::from_f64(0.5 * cos0) * half_sq);
    (sin_eps, cos_eps)
}

/// Days since JD 2451545.0 split as whole days and `hour/24 − 0.5`.
fn elapsed_days<T: Float>(time: &UtcTime) -> (i32, T) {
    (
        time.days_since_2000(),
        time.day_fraction::<T>() - T::from_f64(0.5),
    )
}

/// `a[0] + a[1]·n` reduced to `[0, 2π]` for a rate `a[1]` in rad/day.
#[inline(always)]
fn daily_angle<T: Float>(a: [f64; 2], days: i32, frac: T) -> T {
    let rate_turns = a[1] / core::f64::consts::TAU;
    let turns = T::from_f64(a[0] / core::f64::consts::TAU)
        + whole_day_turns::<T>(fixed(rate_turns), days)
        + T::from_f64(rate_turns) * frac;
    turns_to_rad(turns)
}

/// [`turns_per_day_fixed`] at run time for the selected set (an `f64`
/// multiply by a constant that the compiler folds per variant; no `f64`
/// math reaches `T`).
#[inline(always)]
fn fixed(turns_per_day: f64) -> u64 {
    turns_per_day_fixed(turns_per_day)
}

/// Refraction of Li et al. 2022, eq. 17, in radians, to subtract from the
/// zenith angle.
///
/// Corrected: `R = I1·P / ((273 + T)·tan(e + I2 / (e + I3)))` with `P` in
/// atmospheres (the formula is Bennett's in radians: `I2 = 10.3 deg²`,
/// `I3 = 5.11°`, `I1 ≈ 1.02′ × 283 K`) and `e` the elevation in radians;
/// none below the horizon limit of [`crate::refraction`].
/// As printed: `P` in millibars and the zenith angle as argument.
fn li_refraction_rad<T: Float>(zenith: T, atm: &Atmosphere<T>, as_printed: bool) -> T {
    const I1: f64 = 0.084_217;
    const I2: f64 = 0.003_137_6;
    const I3: f64 = 0.089_186;
    let kelvin = T::from_f64(273.0) + atm.temperature_c();
    if as_printed {
        let arg = zenith + T::from_f64(I2) / (zenith + T::from_f64(I3));
        return T::from_f64(I1) * atm.pressure_hpa() / (kelvin * arg.tan());
    }
    let elevation = T::FRAC_PI_2 - zenith;
    let limit =
        -T::from_f64(crate::refraction::SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG).to_radians();
    if elevation < limit {
        return T::ZERO;
    }
    let pressure_atm = atm.pressure_hpa() / T::from_f64(1013.25);
    let arg = elevation + T::from_f64(I2) / (elevation + T::from_f64(I3));
    T::from_f64(I1) * pressure_atm / (kelvin * arg.tan())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::{MAX_YEAR, MIN_YEAR};

    #[test]
    fn truncating_julian_day_number_matches_the_calendar() {
        // JDN 2451545 is 2000-01-01 (Meeus, Astronomical Algorithms, ch. 7).
        assert_eq!(julian_day_number(2000, 1, 1), 2_451_545);
        // Meeus example 7.a: 1957-10-04.81 is JD 2436116.31 → JDN 2436116.
        assert_eq!(julian_day_number(1957, 10, 4), 2_436_116);
        let mut d = UtcTime::from_ymd_hms(MIN_YEAR, 1, 1, 0, 0, 0)
            .unwrap()
            .days_since_2000();
        let end = UtcTime::from_ymd_hms(MAX_YEAR, 12, 31, 0, 0, 0)
            .unwrap()
            .days_since_2000();
        while d <= end {
            let t = UtcTime::from_days_ms(d, 0).unwrap();
            let (y, m, dd) = t.ymd();
            assert_eq!(
                julian_day_number(y, i32::from(m), i32::from(dd)),
                t.jd_midnight_int() + 1,
                "{t}"
            );
            d += 97;
        }
    }

    #[test]
    fn flooring_division_would_be_wrong() {
        fn floored(year: i32, month: i32, day: i32) -> i32 {
            let aux1 = (month - 14).div_euclid(12);
            (1461 * (year + 4800 + aux1)).div_euclid(4)
                + (367 * (month - 2 - 12 * aux1)).div_euclid(12)
                - (3 * (year + 4900 + aux1).div_euclid(100)).div_euclid(4)
                + day
                - 32075
        }
        // 2021-06-15: JDN 2459381 (Meeus ch. 7 algorithm, hand-computed).
        assert_eq!(julian_day_number(2021, 6, 15), 2_459_381);
        assert_ne!(floored(2021, 6, 15), 2_459_381);
    }

    #[test]
    fn whole_day_turns_is_exact_for_large_day_counts() {
        // 0.25 turn/day × 1001 days = 250.25 turns → 0.25.
        let k = turns_per_day_fixed(0.25);
        assert_eq!(whole_day_turns::<f64>(k, 1001), 0.25);
        assert_eq!(whole_day_turns::<f32>(k, -1001), 0.75);
        // PSA's mean-longitude rate: compare with an f64 reduction that is
        // accurate for this size (18 000 days × 0.0027 turn ≈ 49 turns).
        let rate = 0.017_202_791_698 / core::f64::consts::TAU;
        let direct = (rate * 18_000.0).fract();
        let ours = whole_day_turns::<f64>(turns_per_day_fixed(rate), 18_000);
        assert!((direct - ours).abs() < 1e-12, "{direct} {ours}");
        let ours32 = whole_day_turns::<f32>(turns_per_day_fixed(rate), 18_000);
        assert!((f64::from(ours32) - direct).abs() < 1e-7);
    }

    #[test]
    fn obliquity_constants_and_expansion() {
        for c in [&PSA_2001, &PSA_2020, &MODIFIED, &MODIFIED_AS_PRINTED] {
            let e0 = c.obliquity[0];
            assert!((c.obliquity0_sin_cos[0] - libm::sin(e0)).abs() < 1e-16);
            assert!((c.obliquity0_sin_cos[1] - libm::cos(e0)).abs() < 1e-16);
            // Against libm's sine and cosine of ε₀ + δ, both sides of the cut-off.
            for change in [-2e-3, -1e-3, -1.6e-4, 0.0, 4.4e-5, 1.6e-4, 1e-3, 3e-3] {
                let (s, co) = obliquity_sin_cos::<f64>(c, change);
                assert!((s - libm::sin(e0 + change)).abs() < 2e-10, "{change}");
                assert!((co - libm::cos(e0 + change)).abs() < 2e-10, "{change}");
                let (s32, co32) = obliquity_sin_cos::<f32>(c, change as f32);
                assert!(
                    (f64::from(s32) - libm::sin(e0 + change)).abs() < 6e-8,
                    "{change}"
                );
                assert!(
                    (f64::from(co32) - libm::cos(e0 + change)).abs() < 1.2e-7,
                    "{change}"
                );
            }
        }
    }

    #[test]
    fn li_refraction_corrected_is_bennett_in_radians() {
        // Elevation 30°, 1013.25 hPa, 10 °C: 0.084217 / (283·tan(0.5236 +
        // 0.0031376/0.6128)) rad = 0.029186°; Bennett (NREL SPA eq. 42)
        // gives 1.02/tan(30.2934°)/60 × 1013.25/1010 = 0.029193° (hand/Python).
        let atm = Atmosphere::new(1013.25f64, 10.0).unwrap();
        let dz = li_refraction_rad(60f64.to_radians(), &atm, false).to_degrees();
        assert!((dz - 0.029_186).abs() < 1e-6, "{dz}");
        // Below the horizon limit: none.
        assert_eq!(li_refraction_rad(92f64.to_radians(), &atm, false), 0.0);
        // As printed (millibars, zenith argument) it is a different number
        // altogether — finite, never a panic.
        let printed = li_refraction_rad(60f64.to_radians(), &atm, true);
        assert!(printed.is_finite() && (printed.to_degrees() - dz).abs() > 1.0);
    }

    #[test]
    fn modified_with_atmosphere_is_apparent() {
        use crate::{Algorithm, Options};
        let t = UtcTime::from_ymd_hms(2030, 6, 21, 9, 0, 0).unwrap();
        let site = Site::new(39.1f64, 117.2).unwrap(); // Tianjin
        let geo = Algorithm::PsaModified
            .position(&t, &site, &Options::default())
            .unwrap();
        let opts = Options {
            atmosphere: Some(Atmosphere::new(1013.25, 10.0).unwrap()),
            ..Options::default()
        };
        let app = Algorithm::PsaModified.position(&t, &site, &opts).unwrap();
        assert!(app.refracted && !geo.refracted);
        assert_eq!(app.azimuth_deg, geo.azimuth_deg);
        let e = 90.0 - geo.zenith_deg;
        let bennett = 1.02 / (e + 10.3 / (e + 5.11)).to_radians().tan() / 60.0 * 1013.25 / 1010.0;
        let dz = geo.zenith_deg - app.zenith_deg;
        assert!((dz - bennett).abs() < 2e-5, "{dz} {bennett}");
    }

    #[test]
    fn horizontal_matches_the_textbook_formulas() {
        // δ = 10°, H = 30°, φ = 40°: cos θz = sin δ sin φ + cos δ cos φ cos H.
        let site = Site::new(40.0f64, 0.0).unwrap();
        let (d, h, p) = (10f64.to_radians(), 30f64.to_radians(), 40f64.to_radians());
        let (z, a, sz) = horizontal(d.sin(), d.cos() * h.cos(), d.cos() * h.sin(), &site);
        let cz = d.sin() * p.sin() + d.cos() * p.cos() * h.cos();
        assert!((z.cos() - cz).abs() < 1e-15);
        assert!((sz - z.sin()).abs() < 1e-15);
        // Afternoon (H > 0): the sun is west of the meridian, azimuth in (180, 360).
        let a = a.to_degrees().rem_euclid(360.0);
        assert!(a > 180.0 && a < 360.0, "{a}");
    }
}
