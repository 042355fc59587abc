//! The site in force: the GPS position first, then the site stored in the
//! configuration, then a postal code from the table of [`crate::site`]
//! (Dahli & Cheggaga 2023 replaces the GPS receiver by the postal code); and the
//! magnetic declination there.
//!
//! Nothing here blocks or panics; every error is a value.

use core::cell::Cell;

use drivers::compass::wmm::{decimal_year, WmmError, WmmModel};
use drivers::gps::{FixQuality, GpsFix};
use sun_algos::{Error as SunError, Float, Site, UtcTime};

use crate::config::SiteConfig;
use crate::site::{lookup_str, PostalError};

/// Where the site came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SiteOrigin {
    /// The GPS position.
    Gps,
    /// The site stored in the configuration.
    Stored,
    /// A postal code (Dahli & Cheggaga 2023).
    PostalCode,
}

/// Why no site could be found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SiteError {
    /// No GPS position, no stored site and no postal code.
    NoSource,
    /// The postal code gave no site (and nothing came before it).
    Postal(PostalError),
    /// The chosen source held impossible coordinates.
    Invalid(SunError),
}

/// The site from a GPS fix with a position (altitude from GGA, else sea
/// level; an altitude outside −500…10 000 m is dropped), in the float type
/// `T`: the fix's exact coordinates rounded once (`f32` on a board without
/// an FPU, about a metre: no `f64` arithmetic).
pub fn site_from_fix<T: Float>(fix: &GpsFix) -> Option<Site<T>> {
    if fix.quality == FixQuality::Invalid {
        return None;
    }
    let (lat, lon) = (fix.latitude_deg?.deg(), fix.longitude_deg?.deg());
    let alt = fix.altitude_m.map_or(T::ZERO, T::from_f32);
    Site::with_elevation(lat, lon, alt)
        .or_else(|_| Site::new(lat, lon))
        .ok()
}

/// The site from the stored configuration.
pub fn site_from_config<T: Float>(s: &SiteConfig) -> Result<Site<T>, SunError> {
    Site::with_elevation(
        T::from_f32(s.latitude_deg),
        T::from_f32(s.longitude_deg),
        T::from_f32(s.elevation_m),
    )
}

/// Chooses the site: the GPS position, else `stored` (pass it only when
/// the configuration was loaded from storage, not defaulted), else
/// `postal_code` (`COUNTRY:CODE`, e.g. `DZ:16000`).
pub fn resolve_site<T: Float>(
    gps: &GpsFix,
    stored: Option<&SiteConfig>,
    postal_code: Option<&str>,
) -> Result<(Site<T>, SiteOrigin), SiteError> {
    if let Some(s) = site_from_fix(gps) {
        return Ok((s, SiteOrigin::Gps));
    }
    let mut stored_error = None;
    if let Some(cfg) = stored {
        match site_from_config(cfg) {
            Ok(s) => return Ok((s, SiteOrigin::Stored)),
            Err(e) => stored_error = Some(e),
        }
    }
    if let Some(code) = postal_code {
        return match lookup_str(code) {
            Ok(entry) => entry
                .site()
                .map(|s| (s, SiteOrigin::PostalCode))
                .map_err(SiteError::Invalid),
            Err(e) => Err(stored_error.map_or(SiteError::Postal(e), SiteError::Invalid)),
        };
    }
    Err(stored_error.map_or(SiteError::NoSource, SiteError::Invalid))
}

/// Whether `a` lies more than `min_move_deg` (degrees of a great circle)
/// from `b`, longitudes compared modulo 360°
/// ([`super::filter::site_distance_deg`]).
pub fn site_moved<T: Float>(a: &Site<T>, b: &Site<T>, min_move_deg: T) -> bool {
    super::filter::site_distance_deg(a, b) > min_move_deg
}

/// Replaces the shared site by the GPS position when the fix is valid and
/// the position moved more than `min_move_deg` in latitude or longitude
/// from the site in use. Returns whether it replaced it. (A portable
/// tracker carried to a new place; fix noise of a few metres is ignored.)
pub fn follow_gps_site<T: Float>(cell: &Cell<Site<T>>, fix: &GpsFix, min_move_deg: T) -> bool {
    let Some(s) = site_from_fix(fix) else {
        return false;
    };
    let moved = site_moved(&s, &cell.get(), min_move_deg);
    if moved {
        cell.set(s);
    }
    moved
}

/// Magnetic declination (degrees, east positive) at the site and instant
/// from the World Magnetic Model 2025 (the drivers' `no_std` synthesis),
/// which turns a magnetic heading into a true one: Choi et al. (portable
/// tracker, §V) find the largest part of their error in the geomagnetic
/// sensor, which gives magnetic rather than true north.
/// The site's elevation is taken as the height above the ellipsoid (the
/// geoid difference, tens of metres, changes D by far less than 0.01°).
/// Errors outside the model's 2025–2030 span or at a pole. The synthesis
/// runs in the site's float type `T`: `f32` on a board without an FPU
/// (about a tenth of the software-`f64` time, within 0.005° of NOAA's
/// WMM2025 test values; no `f64` arithmetic), `f64` on hosts.
pub fn wmm_declination_deg<T: Float>(site: &Site<T>, now: &UtcTime) -> Result<f32, WmmError> {
    let (y, mo, d) = now.ymd();
    let seconds_of_day = now.ms_of_day() / 1000;
    let year = decimal_year::<T>(y, mo, d, seconds_of_day)?;
    WmmModel::wmm2025()
        .declination_deg(
            site.latitude_deg(),
            site.longitude_deg(),
            site.elevation_m() / T::from_f64(1000.0),
            year,
        )
        .map(Float::to_f32)
}
