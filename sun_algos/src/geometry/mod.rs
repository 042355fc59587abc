//! Solar geometry for a tracker: what the sun's direction means for a flat
//! panel, and the day's set-points.
//!
//! Nothing here knows any hardware:
//! - [`incidence`]: angle between the beam and a surface normal (Jimoh &
//!   Aliyu 2019, eq 1/13; Dahli & Cheggaga 2023, eq 8; one implementation).
//! - [`optimum`]: the set-point that makes the incidence zero (Jimoh & Aliyu
//!   2019, eq 14), and the best one inside mechanical limits.
//! - [`simple`]: the textbook sun model of Jimoh & Aliyu (2019, eq 2–8) used
//!   by the simple events.
//! - [`events`]: sunrise, transit, sunset, daylight hours; Jimoh & Aliyu's
//!   simple model (eq 9–12) and precise events of any position source.
//! - [`day_table`]: set-points every N minutes from sunrise to sunset in a
//!   fixed-capacity table.
//! - [`irradiance`]: extraterrestrial and clear-sky irradiance, the tilted
//!   plane (Dahli & Cheggaga 2023), daily energy (Chowdhury et al. 2019).
//!
//! # Example
//!
//! ```
//! use sun_algos::geometry::{incidence, optimum, Surface};
//! use sun_algos::SunPosition;
//!
//! // NREL SPA report, worked example: the sun at zenith 50.111622°, azimuth
//! // 194.340241°; a surface of slope 30° turned 10° east of south (azimuth
//! // 170°) sees it at I = 25.187000° (nrel_spa_test_vector.json).
//! let sun = SunPosition::new(50.111_622f64, 194.340_241, true);
//! let panel = Surface::new(30.0, 170.0)?;
//! assert!((incidence::incidence_deg(&sun, &panel) - 25.187_000).abs() < 1e-5);
//! // Pointed at the sun, the incidence is zero.
//! let tracked = optimum::normal_to_sun(&sun);
//! assert!(incidence::incidence_deg(&sun, &tracked) < 1e-6);
//! # Ok::<(), sun_algos::geometry::GeometryError>(())
//! ```

pub mod day_table;
pub mod events;
pub mod incidence;
pub mod irradiance;
pub mod optimum;
pub mod simple;

pub use incidence::Surface;
pub use optimum::Limits;

/// Why a geometry result could not be computed (never a panic).
///
/// ```
/// use sun_algos::geometry::{events, GeometryError};
/// use sun_algos::{Algorithm, Error, Options, Site};
///
/// let site = Site::new(11.9683f64, 8.4261)?;
/// // Michalsky's validity ends in 2050: the position error, wrapped.
/// let e = events::for_algorithm(Algorithm::Michalsky, (2060, 6, 21), &site, &Options::default());
/// assert_eq!(
///     e,
///     Err(GeometryError::Position(Error::OutOfValidityRange {
///         algorithm: Algorithm::Michalsky,
///         year: 2060,
///     }))
/// );
/// assert_eq!(
///     GeometryError::CapacityExceeded { needed: 400, capacity: 361 }.to_string(),
///     "day needs 400 entries, table holds 361"
/// );
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum GeometryError {
    /// The sun position could not be computed (bad site, date, options…).
    Position(crate::Error),
    /// An angle or other input was NaN or infinite.
    NotFinite,
    /// Mechanical limits out of order or outside slope 0…180°, or an azimuth
    /// range wider than 360°.
    InvalidLimits,
    /// Table interval not in 1…720 minutes or not dividing 1440.
    InvalidInterval,
    /// The day needs more entries than the table's capacity.
    CapacityExceeded {
        /// Entries the day would need.
        needed: usize,
        /// Entries the table holds.
        capacity: usize,
    },
}

impl From<crate::Error> for GeometryError {
    fn from(e: crate::Error) -> Self {
        GeometryError::Position(e)
    }
}

impl core::fmt::Display for GeometryError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            GeometryError::Position(e) => write!(f, "sun position: {e}"),
            GeometryError::NotFinite => f.write_str("input is NaN or infinite"),
            GeometryError::InvalidLimits => f.write_str("invalid slope/azimuth limits"),
            GeometryError::InvalidInterval => {
                f.write_str("interval must be 1..=720 minutes and divide 1440")
            }
            GeometryError::CapacityExceeded { needed, capacity } => {
                write!(f, "day needs {needed} entries, table holds {capacity}")
            }
        }
    }
}

impl core::error::Error for GeometryError {}
