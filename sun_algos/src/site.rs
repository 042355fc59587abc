//! Validated inputs: the observer's site, the atmosphere and the options.

use crate::error::Error;
use crate::float::Float;

/// Where the observer stands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Site<T> {
    latitude_deg: T,
    longitude_deg: T,
    elevation_m: T,
}

impl<T: Float> Site<T> {
    /// A site at sea level. Latitude −90…90° (north positive), longitude
    /// −180…180° (east positive).
    pub fn new(latitude_deg: T, longitude_deg: T) -> Result<Self, Error> {
        Self::with_elevation(latitude_deg, longitude_deg, T::ZERO)
    }

    /// A site with its elevation above sea level in metres (−500…10 000).
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
    pub fn latitude_deg(&self) -> T {
        self.latitude_deg
    }
    /// Longitude in degrees, east positive.
    pub fn longitude_deg(&self) -> T {
        self.longitude_deg
    }
    /// Elevation above sea level in metres.
    pub fn elevation_m(&self) -> T {
        self.elevation_m
    }
}

/// Local air pressure and temperature, for atmospheric refraction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Atmosphere<T> {
    pressure_hpa: T,
    temperature_c: T,
}

impl<T: Float> Atmosphere<T> {
    /// Pressure in hPa (0 < p ≤ 2000) and temperature in °C (−100…100).
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
    pub fn standard() -> Self {
        Atmosphere {
            pressure_hpa: T::from_f64(1013.25),
            temperature_c: T::from_f64(10.0),
        }
    }

    /// Pressure in hPa (millibar).
    pub fn pressure_hpa(&self) -> T {
        self.pressure_hpa
    }
    /// Temperature in °C.
    pub fn temperature_c(&self) -> T {
        self.temperature_c
    }
}

/// Options of a position computation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Options<T> {
    /// ΔT = TT − UT1 in seconds; `None` takes the built-in model
    /// ([`crate::delta_t::estimate_s`]).
    pub delta_t_s: Option<T>,
    /// Pressure and temperature: when given, the result is apparent
    /// (refracted); when `None` it is geometric.
    pub atmosphere: Option<Atmosphere<T>>,
    /// Compute even when the instant lies outside the algorithm's stated
    /// validity range (by default that is an error).
    pub allow_out_of_range: bool,
}
