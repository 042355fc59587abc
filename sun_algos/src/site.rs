//! Validated inputs: the observer's site, the atmosphere and the options.

use crate::error::Error;
use crate::float::Float;

/// Where the observer stands.
///
/// ```
/// use sun_algos::{Error, Site};
///
/// // Validated once: every Site in circulation is inside −90…90°, −180…180°,
/// // −500…10 000 m.
/// let golden = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// assert_eq!(
///     (golden.latitude_deg(), golden.longitude_deg(), golden.elevation_m()),
///     (39.742476, -105.1786, 1830.14)
/// );
/// assert_eq!(Site::new(0.0f32, 200.0), Err(Error::LongitudeOutOfRange));
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Site<T> {
    latitude_deg: T,
    longitude_deg: T,
    elevation_m: T,
}

impl<T: Float> Site<T> {
    /// A site at sea level. Latitude −90…90° (north positive), longitude
    /// −180…180° (east positive).
    ///
    /// ```
    /// use sun_algos::{Error, Site};
    ///
    /// let kano = Site::new(11.9683f32, 8.4261)?;
    /// assert_eq!(kano.elevation_m(), 0.0);
    /// assert_eq!(Site::new(91.0f64, 0.0), Err(Error::LatitudeOutOfRange));
    /// assert_eq!(Site::new(0.0f64, -180.5), Err(Error::LongitudeOutOfRange));
    /// assert_eq!(Site::new(f32::NAN, 0.0), Err(Error::NotFinite));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn new(latitude_deg: T, longitude_deg: T) -> Result<Self, Error> {
        Self::with_elevation(latitude_deg, longitude_deg, T::ZERO)
    }

    /// A site with its elevation above sea level in metres (−500…10 000).
    ///
    /// ```
    /// use sun_algos::{Algorithm, Atmosphere, Error, Options, Site, UtcTime};
    ///
    /// // NREL SPA report, worked example (shared/reference/nrel_spa_test_vector.json):
    /// // 39.742476° N, 105.1786° W, 1830.14 m, 820 hPa, 11 °C, ΔT 67 s,
    /// // 2003-10-17 19:30:30 UT → topocentric zenith 50.111622°, azimuth 194.340241°.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options {
    ///     delta_t_s: Some(67.0),
    ///     atmosphere: Some(Atmosphere::new(820.0, 11.0)?),
    ///     ..Options::default()
    /// };
    /// let p = Algorithm::Spa.position(&"2003-10-17T19:30:30Z".parse()?, &site, &opts)?;
    /// assert!((p.zenith_deg - 50.111_622).abs() < 1e-6);
    /// assert!((p.azimuth_deg - 194.340_241).abs() < 1e-6);
    /// assert_eq!(Site::with_elevation(0.0f64, 0.0, -600.0), Err(Error::ElevationOutOfRange));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    // Always inlined: three f64 do not fit the AVR argument registers, and
    // LLVM reads stack-passed arguments one byte low on the ATmega2560
    // (3-byte return address), so an out-of-line call there saw 480 m as
    // out of range.
    #[inline(always)]
    pub fn with_elevation(
        latitude_deg: T,
        longitude_deg: T,
        elevation_m: T,
    ) -> Result<Self, Error> {
        if !latitude_deg.is_finite() || !longitude_deg.is_finite() || !elevation_m.is_finite() {
            return Err(Error::NotFinite);
        }
        if latitude_deg.abs() > T::from_f64(90.0) {
            return Err(Error::LatitudeOutOfRange);
        }
        if longitude_deg.abs() > T::from_f64(180.0) {
            return Err(Error::LongitudeOutOfRange);
        }
        if elevation_m < T::from_f64(-500.0) || elevation_m > T::from_f64(10_000.0) {
            return Err(Error::ElevationOutOfRange);
        }
        Ok(Site {
            latitude_deg,
            longitude_deg,
            elevation_m,
        })
    }

    /// Latitude in degrees, north positive.
    ///
    /// ```
    /// use sun_algos::Site;
    ///
    /// assert_eq!(Site::new(-33.9249f64, 18.4241)?.latitude_deg(), -33.9249); // Cape Town: south
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn latitude_deg(&self) -> T {
        self.latitude_deg
    }
    /// Longitude in degrees, east positive.
    ///
    /// ```
    /// use sun_algos::Site;
    ///
    /// assert_eq!(Site::new(39.742476f64, -105.1786)?.longitude_deg(), -105.1786); // Golden, CO: west
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn longitude_deg(&self) -> T {
        self.longitude_deg
    }
    /// Elevation above sea level in metres.
    ///
    /// ```
    /// use sun_algos::Site;
    ///
    /// assert_eq!(Site::with_elevation(39.742476f64, -105.1786, 1830.14)?.elevation_m(), 1830.14);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn elevation_m(&self) -> T {
        self.elevation_m
    }
}

/// Local air pressure and temperature, for atmospheric refraction.
///
/// ```
/// use sun_algos::{Algorithm, Atmosphere, Options, Site, UtcTime};
///
/// // Refraction lifts the sun most near the horizon: the NREL SPA worked
/// // example's 820 hPa and 11 °C raise a 39.87° sun by 0.016332°
/// // (nrel_spa_test_vector.json).
/// let atm = Atmosphere::new(820.0f64, 11.0)?;
/// let site = Site::with_elevation(39.742476, -105.1786, 1830.14)?;
/// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
/// let geo = Options { delta_t_s: Some(67.0), ..Options::default() };
/// let app = Options { atmosphere: Some(atm), ..geo };
/// let lift = Algorithm::Spa.position(&t, &site, &geo)?.zenith_deg
///     - Algorithm::Spa.position(&t, &site, &app)?.zenith_deg;
/// assert!((lift - 0.016_332).abs() < 1e-6);
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Atmosphere<T> {
    pressure_hpa: T,
    temperature_c: T,
}

impl<T: Float> Atmosphere<T> {
    /// Pressure in hPa (0 < p ≤ 2000) and temperature in °C (−100…100).
    ///
    /// ```
    /// use sun_algos::refraction::refraction_deg;
    /// use sun_algos::{Atmosphere, Error};
    ///
    /// // NREL SPA worked example: at 820 hPa and 11 °C a true elevation of
    /// // 39.872046° is raised by 0.016332° (nrel_spa_test_vector.json).
    /// let atm = Atmosphere::new(820.0f64, 11.0)?;
    /// assert!((refraction_deg(39.872_046, &atm) - 0.016_332).abs() < 1e-6);
    /// assert_eq!(Atmosphere::new(0.0f64, 11.0), Err(Error::PressureOutOfRange));
    /// assert_eq!(Atmosphere::new(1000.0f64, 150.0), Err(Error::TemperatureOutOfRange));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn new(pressure_hpa: T, temperature_c: T) -> Result<Self, Error> {
        if !pressure_hpa.is_finite() || !temperature_c.is_finite() {
            return Err(Error::NotFinite);
        }
        if pressure_hpa <= T::ZERO || pressure_hpa > T::from_f64(2000.0) {
            return Err(Error::PressureOutOfRange);
        }
        if temperature_c.abs() > T::from_f64(100.0) {
            return Err(Error::TemperatureOutOfRange);
        }
        Ok(Atmosphere {
            pressure_hpa,
            temperature_c,
        })
    }

    /// The standard atmosphere at sea level: 1013.25 hPa, 10 °C (NREL SPA's
    /// defaults are 1010 hPa and 10 °C; the ICAO standard is 1013.25 hPa).
    ///
    /// ```
    /// use sun_algos::Atmosphere;
    ///
    /// // ICAO standard atmosphere: 1013.25 hPa at sea level.
    /// let atm = Atmosphere::<f64>::standard();
    /// assert_eq!((atm.pressure_hpa(), atm.temperature_c()), (1013.25, 10.0));
    /// ```
    pub fn standard() -> Self {
        Atmosphere {
            pressure_hpa: T::from_f64(1013.25),
            temperature_c: T::from_f64(10.0),
        }
    }

    /// Pressure in hPa (millibar).
    ///
    /// ```
    /// use sun_algos::Atmosphere;
    ///
    /// assert_eq!(Atmosphere::new(820.0f32, 11.0)?.pressure_hpa(), 820.0);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn pressure_hpa(&self) -> T {
        self.pressure_hpa
    }
    /// Temperature in °C.
    ///
    /// ```
    /// use sun_algos::Atmosphere;
    ///
    /// assert_eq!(Atmosphere::new(820.0f32, -11.0)?.temperature_c(), -11.0);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn temperature_c(&self) -> T {
        self.temperature_c
    }
}

/// Options of a position computation.
///
/// ```
/// use sun_algos::{Algorithm, Atmosphere, Error, Options, Site, UtcTime};
///
/// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
/// // The NREL SPA worked example's inputs give its printed apparent zenith,
/// // 50.111622° (nrel_spa_test_vector.json).
/// let nrel = Options {
///     delta_t_s: Some(67.0),
///     atmosphere: Some(Atmosphere::new(820.0, 11.0)?),
///     ..Options::default()
/// };
/// let apparent = Algorithm::Spa.position(&t, &site, &nrel)?;
/// assert!(apparent.refracted && (apparent.zenith_deg - 50.111_622).abs() < 1e-6);
/// // The default: geometric, the built-in ΔT, only inside the validity range.
/// let geometric = Algorithm::Spa.position(&t, &site, &Options::default())?;
/// assert!(!geometric.refracted);
/// // Refraction lifts the sun by the worked example's 0.016332°.
/// assert!((geometric.zenith_deg - apparent.zenith_deg - 0.016_332).abs() < 1e-4);
/// let late: UtcTime = "2060-01-01T12:00:00Z".parse()?;
/// assert!(Algorithm::Psa2020.position(&late, &site, &Options::default()).is_err());
/// let anyway = Options { allow_out_of_range: true, ..Options::default() };
/// assert!(Algorithm::Psa2020.position(&late, &site, &anyway).is_ok());
/// assert_eq!(
///     Algorithm::Spa.position(&t, &site, &Options { delta_t_s: Some(f64::NAN), ..nrel }),
///     Err(Error::NotFinite)
/// );
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "T: Float + serde::Serialize",
        deserialize = "T: Float + serde::Deserialize<'de>"
    ))
)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Options<T> {
    /// ΔT = TT − UT1 in seconds; `None` takes the built-in model
    /// ([`crate::delta_t::estimate_s`]).
    pub delta_t_s: Option<T>,
    /// Pressure and temperature: when given, the result is apparent
    /// (refracted); when `None` it is geometric.
    pub atmosphere: Option<Atmosphere<T>>,
    /// Compute even when the instant lies outside the algorithm's stated
    /// validity range (by default that is an error).
    #[cfg_attr(feature = "serde", serde(default))]
    pub allow_out_of_range: bool,
}
