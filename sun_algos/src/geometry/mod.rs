//! Solar geometry for a tracker: what the sun's direction means for a flat
//! panel, and the day's set-points.
//!
//! Nothing here knows any hardware:
//! - [`incidence`]: angle between the beam and a surface normal (seed
//!   jimoh-2019 eq 1/13, seed dahli-2023 eq 8, one implementation).
//! - [`optimum`]: the set-point that makes the incidence zero (seed
//!   jimoh-2019 eq 14), and the best one inside mechanical limits.
//! - [`simple`]: the seed's textbook sun model (jimoh-2019 eq 2–8) used by
//!   the simple events.
//! - [`events`]: sunrise, transit, sunset, daylight hours; the seed's simple
//!   model (eq 9–12) and precise events of any position source.
//! - [`day_table`]: set-points every N minutes from sunrise to sunset in a
//!   fixed-capacity table.
//! - [`irradiance`]: extraterrestrial and clear-sky irradiance, the tilted
//!   plane (seed dahli-2023), daily energy (seed chowdhury-2019).

pub mod day_table;
pub mod events;
pub mod incidence;
pub mod irradiance;
pub mod optimum;
pub mod simple;

pub use incidence::Surface;
pub use optimum::Limits;

/// Why a geometry result could not be computed (never a panic).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
