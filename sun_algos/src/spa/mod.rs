//! NREL's Solar Position Algorithm (SPA): Reda, I. & Andreas, A. (2004),
//! "Solar Position Algorithm for Solar Radiation Applications", NREL/TP-560-34302
//! (revised January 2008). Equation numbers below are the report's.
//!
//! Complete: Earth periodic terms (Table A4.2), nutation (Table A4.3),
//! aberration, apparent sidereal time, geocentric right ascension and
//! declination, observer hour angle, topocentric parallax with the site's
//! elevation, refraction (eq. 42–43) when an atmosphere is given, zenith and
//! azimuth; plus the intermediate values ([`intermediate`]), the incidence
//! angle on a tilted surface ([`incidence_deg`], eq. 47), the equation of
//! time ([`equation_of_time_min`], appendix A.1) and sunrise, transit and
//! sunset ([`rise_transit_set`], appendix A.2).
//!
//! Generic over `f32` and `f64`. Days and the time of day stay apart; the
//! two secular angles that grow large (Earth's mean motion in L and the
//! sidereal time) are reduced modulo one turn in exact fixed point (see
//! `split`), so `f32` keeps about 10⁻⁴° instead of losing a degree. In
//! `f64` the sines and cosines of the Earth terms' directly computed
//! frequencies and of the nutation's fundamental arguments come from an
//! exact reduction in turns or degrees and fdlibm's kernels (module
//! `turns`), within 2.2·10⁻¹⁶ of the exact values.
//!
//! # Example
//!
//! ```
//! use sun_algos::{spa, Atmosphere, Options, Site, UtcTime};
//!
//! // NREL SPA report, worked example (shared/reference/nrel_spa_test_vector.json):
//! // 2003-10-17 19:30:30 UT, 39.742476° N, 105.1786° W, 1830.14 m, 820 hPa,
//! // 11 °C, ΔT 67 s.
//! let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
//! let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
//! let opts = Options {
//!     delta_t_s: Some(67.0),
//!     atmosphere: Some(Atmosphere::new(820.0, 11.0)?),
//!     ..Options::default()
//! };
//! let i = spa::intermediate(&t, &site, &opts)?;
//! // The report's printed values: zenith 50.111622°, azimuth 194.340241°,
//! // equation of time 14.641503 min.
//! assert!((i.zenith_deg - 50.111_622).abs() < 1e-6);
//! assert!((i.azimuth_deg - 194.340_241).abs() < 1e-6);
//! assert!((i.equation_of_time_min - 14.641_503).abs() < 1e-5);
//! # Ok::<(), sun_algos::Error>(())
//! ```

mod earth;
mod events;
mod fast_tables;
mod geocentric;
#[cfg(test)]
mod legacy;
mod nutation;
mod rot;
pub(crate) mod split;
mod tables;
mod topocentric;
mod turns;

pub use events::{local_hours, rise_transit_set, RiseSet, RiseTransitSet, SUNRISE_ALTITUDE_DEG};

use crate::algorithm::{Algorithm, Inputs};
use crate::error::Error;
use crate::float::Float;
use crate::position::SunPosition;
use crate::refraction::refraction_deg;
use crate::site::{Options, Site};
use crate::time::UtcTime;
use geocentric::{geocentric, Geocentric};
use split::{frac, Secular, SplitDays};
use topocentric::{topocentric, Observer};

/// The sun's position by SPA for validated inputs (the entry point of
/// [`Algorithm::Spa`]).
pub(crate) fn position<T: Float>(inp: &Inputs<'_, T>) -> SunPosition<T> {
    let t = SplitDays::new(inp.time, inp.delta_t_s);
    let geo = geocentric(&t);
    let obs = Observer::new(
        inp.site.latitude_deg(),
        inp.site.longitude_deg(),
        inp.site.elevation_m(),
    );
    let topo = topocentric(&geo, &obs);
    let e0_deg = topo.e0_rad.to_degrees();
    let (e_deg, refracted) = match &inp.atmosphere {
        Some(atm) => (e0_deg + refraction_deg(e0_deg, atm), true),
        None => (e0_deg, false),
    };
    SunPosition::new(
        T::from_f64(90.0) - e_deg,
        topo.azimuth_rad.to_degrees(),
        refracted,
    )
}

/// Every intermediate value of SPA for one instant and site (degrees unless
/// the name says otherwise), as listed in the report's worked example.
///
/// ```
/// use sun_algos::{spa, Atmosphere, Options, Site, UtcTime};
///
/// // NREL SPA report, worked example (shared/reference/nrel_spa_test_vector.json):
/// // 2003-10-17 19:30:30 UT, 39.742476° N, 105.1786° W, 1830.14 m, 820 hPa,
/// // 11 °C, ΔT 67 s.
/// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
/// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// let opts = Options {
///     delta_t_s: Some(67.0),
///     atmosphere: Some(Atmosphere::new(820.0, 11.0)?),
///     ..Options::default()
/// };
/// let i: spa::SpaIntermediate<f64> = spa::intermediate(&t, &site, &opts)?;
/// // The report's topocentric values: δ′ = −9.316179°, H′ = 11.10627°,
/// // e0 = 39.872046°, Δe = 0.016332°, e = 39.888378°.
/// assert!((i.delta_prime_deg + 9.316_179).abs() < 1e-6);
/// assert!((i.h_prime_deg - 11.106_27).abs() < 1e-5);
/// assert!((i.e0_deg - 39.872_046).abs() < 1e-6);
/// assert!((i.delta_e_deg - 0.016_332).abs() < 1e-6);
/// assert!((i.e_deg - 39.888_378).abs() < 1e-6);
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SpaIntermediate<T> {
    /// Integer part of the Julian Day (UT1), eq. 4.
    pub julian_day_int: i32,
    /// Fraction of the Julian Day, `[0, 1)`: JD = `julian_day_int + julian_day_frac`.
    pub julian_day_frac: T,
    /// Julian ephemeris century JCE (eq. 6).
    pub jce: T,
    /// Julian ephemeris millennium JME (eq. 7).
    pub jme: T,
    /// Earth heliocentric longitude L, `[0, 360)` (eq. 11).
    pub l_deg: T,
    /// Earth heliocentric latitude B (eq. 12).
    pub b_deg: T,
    /// Earth radius vector R in astronomical units (eq. 12).
    pub r_au: T,
    /// Nutation in longitude Δψ (eq. 22).
    pub dpsi_deg: T,
    /// Nutation in obliquity Δε (eq. 23).
    pub deps_deg: T,
    /// True obliquity of the ecliptic ε (eq. 25).
    pub eps_deg: T,
    /// Apparent sun longitude λ, `[0, 360)` (eq. 27).
    pub lambda_deg: T,
    /// Greenwich mean sidereal time ν0, `[0, 360)` (eq. 28).
    pub nu0_deg: T,
    /// Greenwich apparent sidereal time ν, `[0, 360)` (eq. 29).
    pub nu_deg: T,
    /// Geocentric right ascension α, `[0, 360)` (eq. 30).
    pub alpha_deg: T,
    /// Geocentric declination δ (eq. 31).
    pub delta_deg: T,
    /// Observer local hour angle H, `[0, 360)` (eq. 32).
    pub h_deg: T,
    /// Parallax in right ascension Δα (eq. 38).
    pub dalpha_deg: T,
    /// Topocentric right ascension α′ = α + Δα (eq. 38).
    pub alpha_prime_deg: T,
    /// Topocentric declination δ′ (eq. 39).
    pub delta_prime_deg: T,
    /// Topocentric local hour angle H′ = H − Δα (eq. 40).
    pub h_prime_deg: T,
    /// Topocentric elevation without refraction e0 (eq. 41).
    pub e0_deg: T,
    /// Refraction correction Δe (eq. 42; 0 without an atmosphere).
    pub delta_e_deg: T,
    /// Topocentric elevation e = e0 + Δe (eq. 43).
    pub e_deg: T,
    /// Topocentric zenith angle θ = 90° − e (eq. 44).
    pub zenith_deg: T,
    /// Topocentric azimuth Φ, east of north, `[0, 360)` (eq. 46).
    pub azimuth_deg: T,
    /// Equation of time E in minutes (appendix A.1).
    pub equation_of_time_min: T,
}

impl<T: Float> SpaIntermediate<T> {
    /// The Julian Day as one `f64` (for display; the algorithm never forms it).
    ///
    /// ```
    /// use sun_algos::{spa, Atmosphere, Options, Site, UtcTime};
    ///
    /// // NREL SPA report, worked example (shared/reference/nrel_spa_test_vector.json):
    /// // 2003-10-17 19:30:30 UT, 39.742476° N, 105.1786° W, 1830.14 m, 820 hPa,
    /// // 11 °C, ΔT 67 s.
    /// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options {
    ///     delta_t_s: Some(67.0),
    ///     atmosphere: Some(Atmosphere::new(820.0, 11.0)?),
    ///     ..Options::default()
    /// };
    /// // The report's JD: 2452930.312847.
    /// let i = spa::intermediate(&t, &site, &opts)?;
    /// assert!((i.julian_day_f64() - 2_452_930.312_847).abs() < 1e-6);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn julian_day_f64(&self) -> f64 {
        f64::from(self.julian_day_int) + self.julian_day_frac.to_f64()
    }

    /// The topocentric astronomers' azimuth Γ of eq. 45: measured westward
    /// from south, `[0, 360)`.
    ///
    /// ```
    /// use sun_algos::{spa, Atmosphere, Options, Site, UtcTime};
    ///
    /// // NREL SPA report, worked example (shared/reference/nrel_spa_test_vector.json):
    /// // 2003-10-17 19:30:30 UT, 39.742476° N, 105.1786° W, 1830.14 m, 820 hPa,
    /// // 11 °C, ΔT 67 s.
    /// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options {
    ///     delta_t_s: Some(67.0),
    ///     atmosphere: Some(Atmosphere::new(820.0, 11.0)?),
    ///     ..Options::default()
    /// };
    /// // The report's topocentric astronomers' azimuth Γ: 14.340241°.
    /// let i = spa::intermediate(&t, &site, &opts)?;
    /// assert!((i.astronomers_azimuth_deg() - 14.340_241).abs() < 1e-6);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn astronomers_azimuth_deg(&self) -> T {
        (self.azimuth_deg - T::from_f64(180.0)).rem_euclid(T::from_f64(360.0))
    }
}

/// Degrees in `[0, 360)`.
fn deg360<T: Float>(rad: T) -> T {
    rad.to_degrees().rem_euclid(T::from_f64(360.0))
}

/// All SPA intermediate values (validated like [`Algorithm::position`]; the
/// validity range is SPA's, years −2000…6000).
///
/// ```
/// use sun_algos::{spa, Atmosphere, Options, Site, UtcTime};
///
/// // NREL SPA report, worked example (shared/reference/nrel_spa_test_vector.json):
/// // 2003-10-17 19:30:30 UT, 39.742476° N, 105.1786° W, 1830.14 m, 820 hPa,
/// // 11 °C, ΔT 67 s.
/// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
/// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// let opts = Options {
///     delta_t_s: Some(67.0),
///     atmosphere: Some(Atmosphere::new(820.0, 11.0)?),
///     ..Options::default()
/// };
/// let i = spa::intermediate(&t, &site, &opts)?;
/// // The report's heliocentric and geocentric values: L = 24.0182616917°,
/// // B = −0.0001011219°, R = 0.9965422974 AU, Δψ = −0.00399840°,
/// // ε = 23.440465°, ν = 318.511910°, α = 202.227408°, δ = −9.31434°.
/// assert!((i.l_deg - 24.018_261_691_7).abs() < 1e-6);
/// assert!((i.b_deg + 0.000_101_121_9).abs() < 1e-9);
/// assert!((i.r_au - 0.996_542_297_4).abs() < 1e-9);
/// assert!((i.dpsi_deg + 0.003_998_40).abs() < 1e-8);
/// assert!((i.eps_deg - 23.440_465).abs() < 1e-6);
/// assert!((i.nu_deg - 318.511_910).abs() < 1e-6);
/// assert!((i.alpha_deg - 202.227_408).abs() < 1e-6);
/// assert!((i.delta_deg + 9.314_34).abs() < 1e-5);
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn intermediate<T: Float>(
    time: &UtcTime,
    site: &Site<T>,
    options: &Options<T>,
) -> Result<SpaIntermediate<T>, Error> {
    let inp = Inputs::new(Algorithm::Spa, time, site, options)?;
    let t = SplitDays::new(time, inp.delta_t_s);
    let geo = geocentric(&t);
    let obs = Observer::new(
        site.latitude_deg(),
        site.longitude_deg(),
        site.elevation_m(),
    );
    let topo = topocentric(&geo, &obs);
    let e0_deg = topo.e0_rad.to_degrees();
    let delta_e_deg = match &inp.atmosphere {
        Some(atm) => refraction_deg(e0_deg, atm),
        None => T::ZERO,
    };
    let e_deg = e0_deg + delta_e_deg;
    // JD = jd_midnight_int + 0.5 + day fraction.
    let day_frac: T = time.day_fraction();
    let half = T::from_f64(0.5);
    let (julian_day_int, julian_day_frac) = if day_frac >= half {
        (time.jd_midnight_int() + 1, day_frac - half)
    } else {
        (time.jd_midnight_int(), day_frac + half)
    };
    let dalpha_rad = topo.dalpha_rad();
    Ok(SpaIntermediate {
        julian_day_int,
        julian_day_frac,
        jce: geo.jce,
        jme: geo.jme,
        l_deg: deg360(geo.helio.l_rad),
        b_deg: geo.helio.b_rad.to_degrees(),
        r_au: geo.helio.r_au,
        dpsi_deg: geo.dpsi_rad.to_degrees(),
        deps_deg: geo.deps_rad.to_degrees(),
        eps_deg: geo.eps_rad.to_degrees(),
        lambda_deg: deg360(geo.lambda_rad),
        nu0_deg: deg360(geo.nu0_rad),
        nu_deg: deg360(geo.nu_rad),
        alpha_deg: deg360(geo.alpha_rad),
        delta_deg: geo.delta_rad().to_degrees(),
        h_deg: deg360(topo.h_rad),
        dalpha_deg: dalpha_rad.to_degrees(),
        alpha_prime_deg: deg360(geo.alpha_rad + dalpha_rad),
        delta_prime_deg: topo.delta_prime_rad().to_degrees(),
        h_prime_deg: deg360(topo.h_prime_rad()),
        e0_deg,
        delta_e_deg,
        e_deg,
        zenith_deg: T::from_f64(90.0) - e_deg,
        azimuth_deg: deg360(topo.azimuth_rad),
        equation_of_time_min: eot_min(&t, &geo),
    })
}

/// Sun's mean longitude M of appendix A.1 (eq. A1), degrees, as a secular
/// angle: 280.4664567° + 360007.6982779° per Julian millennium.
const MEAN_LONGITUDE: Secular = Secular::degrees(280.466_456_7, 360_007.698_277_9 / 365_250.0);

/// Appendix A.1, eq. A1–A2: E = M − 0.0057183° − α + Δψ cos ε, in minutes
/// of time, folded into ±12 h (the report's "limit to ±20 minutes" for any
/// real value).
fn eot_min<T: Float>(t: &SplitDays<T>, geo: &Geocentric<T>) -> T {
    let tau = geo.jme;
    let tau2 = tau * tau;
    // Eq. A1's τ² … τ⁵ terms, degrees.
    let m_poly_deg = tau2
        * (T::from_f64(0.030_320_28)
            + tau
                * (T::from_f64(1.0 / 49_931.0)
                    + tau
                        * (T::from_f64(-1.0 / 15_300.0) + tau * T::from_f64(-1.0 / 2_000_000.0))));
    let e_turns = MEAN_LONGITUDE.at(t.days, t.frac_tt)
        + (m_poly_deg - T::from_f64(0.005_718_3)) / T::from_f64(360.0)
        + (geo.dpsi_rad * geo.eps_rad.cos() - geo.alpha_rad) / T::TAU;
    // Fold into [−½, ½) turn; one turn is 1440 minutes of time.
    (frac(e_turns + T::from_f64(0.5)) - T::from_f64(0.5)) * T::from_f64(1440.0)
}

/// The equation of time in minutes (apparent minus mean solar time,
/// appendix A.1), for `time` and the ΔT of `options` (or the built-in model).
///
/// ```
/// use sun_algos::{spa, Options, UtcTime};
///
/// // NREL SPA worked example: E = 14.641503 min at 2003-10-17 19:30:30 UT
/// // with ΔT 67 s (the site does not enter).
/// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
/// let e = spa::equation_of_time_min(&t, &Options { delta_t_s: Some(67.0f64), ..Options::default() })?;
/// assert!((e - 14.641_503).abs() < 1e-5);
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn equation_of_time_min<T: Float>(time: &UtcTime, options: &Options<T>) -> Result<T, Error> {
    // The site does not enter; validate the rest as usual.
    let site = Site::new(T::ZERO, T::ZERO)?;
    let inp = Inputs::new(Algorithm::Spa, time, &site, options)?;
    let t = SplitDays::new(time, inp.delta_t_s);
    Ok(eot_min(&t, &geocentric(&t)))
}

/// Incidence angle I of the sun's rays on a surface (eq. 47), degrees:
/// `zenith_deg` and `azimuth_deg` (east of north) of the sun, the surface's
/// `slope_deg` from the horizontal (0…180) and its
/// `surface_azimuth_rotation_deg` γ in the report's convention: measured
/// from south to the projection of the surface normal on the horizontal
/// plane, positive toward west, negative toward east.
///
/// ```
/// use sun_algos::{spa, Error};
///
/// // NREL SPA worked example: zenith 50.111622°, azimuth 194.340241°, a
/// // surface of slope 30° turned 10° east of south: I = 25.187000°.
/// let i = spa::incidence_deg(50.111_622f64, 194.340_241, 30.0, -10.0)?;
/// assert!((i - 25.187_000).abs() < 1e-5);
/// assert_eq!(spa::incidence_deg(f64::NAN, 0.0, 30.0, 0.0), Err(Error::NotFinite));
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn incidence_deg<T: Float>(
    zenith_deg: T,
    azimuth_deg: T,
    slope_deg: T,
    surface_azimuth_rotation_deg: T,
) -> Result<T, Error> {
    if !(zenith_deg.is_finite()
        && azimuth_deg.is_finite()
        && slope_deg.is_finite()
        && surface_azimuth_rotation_deg.is_finite())
    {
        return Err(Error::NotFinite);
    }
    let (sz, cz) = zenith_deg.to_radians().sin_cos();
    let (sw, cw) = slope_deg.to_radians().sin_cos();
    // Γ = Φ − 180°, the astronomers' azimuth (eq. 45).
    let gamma_sun = azimuth_deg - T::from_f64(180.0);
    let c = (gamma_sun - surface_azimuth_rotation_deg)
        .to_radians()
        .cos();
    let cos_i = (cz * cw + sw * sz * c).clamp(-T::ONE, T::ONE);
    Ok(cos_i.acos().to_degrees())
}
