//! Errors returned instead of panics.

use crate::algorithm::Algorithm;

/// Why a position (or other result) could not be computed.
///
/// ```
/// use sun_algos::{Algorithm, Error, Options, Site, UtcTime};
///
/// let site = Site::new(40.0f64, 0.0)?;
/// let t: UtcTime = "2060-06-01T12:00:00Z".parse()?;
/// match Algorithm::Psa2020.position(&t, &site, &Options::default()) {
///     Err(e @ Error::OutOfValidityRange { algorithm, year }) => {
///         assert_eq!((algorithm, year), (Algorithm::Psa2020, 2060));
///         assert_eq!(e.to_string(), "year 2060 outside psa-2020 validity 2020..2050");
///     }
///     other => panic!("{other:?}"),
/// }
/// assert_eq!("2023-02-29T00:00:00Z".parse::<UtcTime>(), Err(Error::InvalidDate));
/// assert_eq!(Error::NotFinite.to_string(), "input is NaN or infinite");
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error {
    /// Latitude outside −90°…90°.
    LatitudeOutOfRange,
    /// Longitude outside −180°…180°.
    LongitudeOutOfRange,
    /// Elevation outside −500 m…10 000 m.
    ElevationOutOfRange,
    /// Pressure not in 0 < p ≤ 2000 hPa.
    PressureOutOfRange,
    /// Temperature outside −100 °C…100 °C.
    TemperatureOutOfRange,
    /// ΔT outside ±100 000 s.
    DeltaTOutOfRange,
    /// An input was NaN or infinite.
    NotFinite,
    /// Not a calendar date (month 13, 30 February, year outside −4000…8000, …).
    InvalidDate,
    /// Not a time of day (hour 24, minute 60, …).
    InvalidTime,
    /// The instant lies outside the algorithm's stated validity range; pass
    /// `allow_out_of_range` in [`crate::Options`] to compute anyway.
    OutOfValidityRange {
        /// The algorithm asked for.
        algorithm: Algorithm,
        /// The year of the instant.
        year: i32,
    },
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::LatitudeOutOfRange => f.write_str("latitude outside -90..90 degrees"),
            Error::LongitudeOutOfRange => f.write_str("longitude outside -180..180 degrees"),
            Error::ElevationOutOfRange => f.write_str("elevation outside -500..10000 m"),
            Error::PressureOutOfRange => f.write_str("pressure outside 0..2000 hPa"),
            Error::TemperatureOutOfRange => f.write_str("temperature outside -100..100 C"),
            Error::DeltaTOutOfRange => f.write_str("delta T outside +-100000 s"),
            Error::NotFinite => f.write_str("input is NaN or infinite"),
            Error::InvalidDate => f.write_str("invalid date"),
            Error::InvalidTime => f.write_str("invalid time of day"),
            Error::OutOfValidityRange { algorithm, year } => {
                let (lo, hi) = algorithm.validity_years();
                write!(
                    f,
                    "year {} outside {} validity {}..{}",
                    year,
                    algorithm.name(),
                    lo,
                    hi
                )
            }
        }
    }
}

impl core::error::Error for Error {}
