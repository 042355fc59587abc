//! World Magnetic Model (WMM2025), `no_std`, no heap, `f64` or `f32`
//! through `libm`.
//!
//! Implements the main-field synthesis of the WMM technical report
//! (Chulliat et al., *The US/UK World Magnetic Model for 2025–2030*, section 1.2):
//!
//! 1. geodetic (WGS-84) → geocentric spherical coordinates (report eqs. 7–8),
//! 2. Gauss coefficients moved from the epoch with the secular variation (eq. 9),
//! 3. Schmidt semi-normalised associated Legendre functions `P̆ₙᵐ(sin φ′)` and
//!    their derivatives by the standard three-term recursions,
//! 4. field in geocentric components `X′, Y′, Z′` (eq. 10), degree and order 12,
//! 5. rotation to the ellipsoidal frame (eq. 11) and the elements `H, F, I, D` (eq. 19).
//!
//! The recursion keeps only the last two degrees of `P̆ₙᵐ`, so the stack cost is
//! four arrays of 13 floats.
//!
//! The synthesis runs in `f64` or in `f32` (any `sun_algos::Float`): an 8-bit board
//! without an FPU does it in `f32`, about ten times faster than in software
//! `f64` (a whole synthesis in `f64` takes about a second on a 16 MHz
//! ATmega). In `f32` the declination stays within 0.01° of NOAA's published
//! test values (`tests/compass_wmm.rs`), far inside the model's own
//! uncertainty (about 0.5°, report section 4), and no `f64` arithmetic is
//! linked: the coefficients are whole tenths of a nanotesla, the epoch a
//! whole year.
//!
//! Coefficients: NOAA NCEI's official `WMM.COF` for WMM2025 (public domain),
//! committed as `WMM2025.COF` and turned into a const table by
//! `gen_wmm_coefficients.py` (see `wmm2025_coefficients.rs`). The file gives
//! every coefficient to 0.1 nT (0.1 nT/year), so a row holds them exactly as
//! `i32` tenths; the synthesis sums in tenths of a nanotesla (the field is
//! linear in the coefficients) and scales X, Y and Z once at the end.
//!
//! The declinations in the examples are NOAA's WMM2025 test values (WMM2025
//! technical report, test-value table), given there to 0.01°.
//!
//! ```
//! use drivers::compass::wmm::{decimal_year, WmmModel};
//!
//! // NOAA's WMM2025 test values: 2027.5, 0 km, 80° S, 240° E: D = 68.49°.
//! let d: f64 = WmmModel::wmm2025().declination_deg(-80.0, 240.0, 0.0, 2027.5)?;
//! assert!((d - 68.49).abs() < 0.005);
//! // The date as the model wants it: 2027-07-02T12:00Z is half way
//! // through 2027 (day 183 of 365, at noon).
//! assert_eq!(decimal_year::<f64>(2027, 7, 2, 43_200)?, 2027.5);
//! # Ok::<(), drivers::compass::wmm::WmmError>(())
//! ```

use super::wmm2025_coefficients::{COEFFICIENTS, EPOCH_YEAR};
use sun_algos::Float;

/// Highest degree and order of the model.
const MAX_DEGREE: usize = 12;
/// Geomagnetic reference radius, km (report Table 1).
const REFERENCE_RADIUS_KM: f64 = 6371.2;
/// WGS-84 semi-major axis, km.
const WGS84_A_KM: f64 = 6378.137;
/// WGS-84 flattening.
const WGS84_F: f64 = 1.0 / 298.257_223_563;
/// Years a WMM stays valid after its epoch.
const LIFESPAN_YEARS: f64 = 5.0;

/// One row of a WMM coefficient file, in the file's own resolution of
/// 0.1 nT (nT/year).
///
/// ```
/// use drivers::compass::wmm::WmmCoefficient;
///
/// // The first row of NOAA's WMM2025 WMM.COF: n = 1, m = 0,
/// // g = −29351.8 nT, h = 0, ġ = 12.0 nT/yr, ḣ = 0.
/// let row = WmmCoefficient {
///     n: 1,
///     m: 0,
///     g_tenth_nt: -293_518,
///     h_tenth_nt: 0,
///     g_dot_tenth_nt_per_yr: 120,
///     h_dot_tenth_nt_per_yr: 0,
/// };
/// assert_eq!((row.n, row.m), (1, 0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WmmCoefficient {
    /// Degree n.
    pub n: u8,
    /// Order m.
    pub m: u8,
    /// Main-field coefficient gₙᵐ at the epoch, 0.1 nT.
    pub g_tenth_nt: i32,
    /// Main-field coefficient hₙᵐ at the epoch, 0.1 nT.
    pub h_tenth_nt: i32,
    /// Secular variation of gₙᵐ, 0.1 nT/year.
    pub g_dot_tenth_nt_per_yr: i32,
    /// Secular variation of hₙᵐ, 0.1 nT/year.
    pub h_dot_tenth_nt_per_yr: i32,
}

/// Why the model could not be evaluated.
///
/// ```
/// use drivers::compass::wmm::{WmmError, WmmModel};
///
/// let wmm = WmmModel::wmm2025();
/// assert_eq!(wmm.declination_deg(91.0, 0.0, 0.0, 2026.0), Err(WmmError::LatitudeOutOfRange));
/// assert_eq!(wmm.declination_deg(90.0, 0.0, 0.0, 2026.0), Err(WmmError::AtGeographicPole));
/// assert_eq!(wmm.declination_deg(0.0, 0.0, 900.0, 2026.0), Err(WmmError::HeightOutOfRange));
/// assert_eq!(wmm.declination_deg(0.0, 0.0, 0.0, 2024.9), Err(WmmError::DateOutsideModel));
/// assert_eq!(wmm.declination_deg(f64::NAN, 0.0, 0.0, 2026.0), Err(WmmError::NonFinite));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WmmError {
    /// An input was NaN or infinite.
    NonFinite,
    /// Latitude outside −90..=90°.
    LatitudeOutOfRange,
    /// Longitude outside −360..=360°.
    LongitudeOutOfRange,
    /// Height outside −10..=850 km (the model's stated range).
    HeightOutOfRange,
    /// Date outside the model's five-year life span.
    DateOutsideModel,
    /// At a geographic pole the east component and the declination are undefined.
    AtGeographicPole,
    /// A calendar date that does not exist.
    InvalidDate,
    /// The coefficient table is not in (n, m) order for n = 1..=12.
    BadCoefficientTable,
}

impl core::fmt::Display for WmmError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            WmmError::NonFinite => f.write_str("WMM input NaN or infinite"),
            WmmError::LatitudeOutOfRange => f.write_str("latitude outside −90..=90°"),
            WmmError::LongitudeOutOfRange => f.write_str("longitude outside −360..=360°"),
            WmmError::HeightOutOfRange => {
                f.write_str("height outside the model range, −10..=850 km")
            }
            WmmError::DateOutsideModel => f.write_str("date outside the model's life span"),
            WmmError::AtGeographicPole => f.write_str("declination undefined at a geographic pole"),
            WmmError::InvalidDate => f.write_str("calendar date does not exist"),
            WmmError::BadCoefficientTable => {
                f.write_str("WMM coefficient table out of (n, m) order")
            }
        }
    }
}

impl core::error::Error for WmmError {}

/// The seven magnetic elements at a point (report section 1.2).
///
/// ```
/// use drivers::compass::wmm::WmmModel;
///
/// // NOAA's WMM2025 test values: 2025.0, 100 km, 80° N, 0° E:
/// // X = 6216.0, Y = 92.4, Z = 52598.8 nT, I = 83.26°, D = 0.85°.
/// let e = WmmModel::wmm2025().field(80.0_f64, 0.0, 100.0, 2025.0)?;
/// assert!((e.north_nt - 6216.0).abs() < 0.05);
/// assert!((e.east_nt - 92.4).abs() < 0.05);
/// assert!((e.down_nt - 52_598.8).abs() < 0.05);
/// assert!((e.inclination_deg - 83.26).abs() < 0.005);
/// assert!((e.declination_deg - 0.85).abs() < 0.005);
/// // H and F follow from X, Y, Z.
/// assert!((e.horizontal_nt - e.north_nt.hypot(e.east_nt)).abs() < 1e-9);
/// assert!((e.total_nt - e.horizontal_nt.hypot(e.down_nt)).abs() < 1e-9);
/// # Ok::<(), drivers::compass::wmm::WmmError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MagneticElements<F = f64> {
    /// X, northward component, nT.
    pub north_nt: F,
    /// Y, eastward component, nT.
    pub east_nt: F,
    /// Z, downward component, nT.
    pub down_nt: F,
    /// H, horizontal intensity, nT.
    pub horizontal_nt: F,
    /// F, total intensity, nT.
    pub total_nt: F,
    /// I, inclination (dip), degrees, positive down.
    pub inclination_deg: F,
    /// D, declination, degrees, east of true north positive.
    pub declination_deg: F,
}

/// Where a model's coefficients are.
#[derive(Debug, Clone, Copy)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum Table {
    /// The built-in WMM2025 table; on AVR it lives in flash (`.progmem`):
    /// avr-gcc would otherwise copy its 1 KB into RAM at start-up.
    Wmm2025,
    /// A table given by the caller.
    Slice(&'static [WmmCoefficient]),
}

/// One row of the built-in table as stored: the row's place gives n and m,
/// and every value fits an `i16` but the degree-1 main field (g₁⁰, g₁¹,
/// h₁¹ reach ±293,518 tenths of a nanotesla), which [`DEGREE_1`] holds:
/// 8 bytes a row instead of [`WmmCoefficient`]'s 18 to 20.
#[derive(Debug, Clone, Copy)]
struct PackedRow {
    g_tenth_nt: i16,
    h_tenth_nt: i16,
    g_dot_tenth_nt_per_yr: i16,
    h_dot_tenth_nt_per_yr: i16,
}

/// Rows of a degree-and-order-12 table: n = 1..=12, m = 0..=n.
const ROWS: usize = 90;

/// g and h of the degree-1 rows (n = 1, m = 0 and 1), whole.
const DEGREE_1: [(i32, i32); 2] = [
    (COEFFICIENTS[0].g_tenth_nt, COEFFICIENTS[0].h_tenth_nt),
    (COEFFICIENTS[1].g_tenth_nt, COEFFICIENTS[1].h_tenth_nt),
];

/// `v` as an `i16`; fails to compile (in [`pack`]) when it does not fit.
const fn narrow(v: i32) -> i16 {
    assert!(
        v >= i16::MIN as i32 && v <= i16::MAX as i32,
        "WMM value beyond i16"
    );
    v as i16
}

/// The generated table packed, checked at compile time: rows in (n, m)
/// order for n = 1..=12, m = 0..=n, every value but the degree-1 main
/// field within `i16` (a table that breaks either does not build).
const fn pack(rows: &[WmmCoefficient; ROWS]) -> [PackedRow; ROWS] {
    let mut packed = [PackedRow {
        g_tenth_nt: 0,
        h_tenth_nt: 0,
        g_dot_tenth_nt_per_yr: 0,
        h_dot_tenth_nt_per_yr: 0,
    }; ROWS];
    let (mut i, mut n, mut m) = (0, 1, 0);
    while i < ROWS {
        let row = rows[i];
        assert!(row.n == n && row.m == m, "WMM table out of (n, m) order");
        let main = if i < DEGREE_1.len() {
            (0, 0)
        } else {
            (narrow(row.g_tenth_nt), narrow(row.h_tenth_nt))
        };
        packed[i] = PackedRow {
            g_tenth_nt: main.0,
            h_tenth_nt: main.1,
            g_dot_tenth_nt_per_yr: narrow(row.g_dot_tenth_nt_per_yr),
            h_dot_tenth_nt_per_yr: narrow(row.h_dot_tenth_nt_per_yr),
        };
        if m == n {
            (n, m) = (n + 1, 0);
        } else {
            m += 1;
        }
        i += 1;
    }
    packed
}

#[cfg(target_arch = "avr")]
avr_progmem::progmem! {
    /// WMM2025 in flash, read with `lpm` one row at a time.
    static progmem WMM2025_FLASH: [PackedRow; ROWS] = pack(&COEFFICIENTS);
}

/// The built-in table as one static (a `const` would be copied per use).
#[cfg(not(target_arch = "avr"))]
static WMM2025_PACKED: [PackedRow; ROWS] = pack(&COEFFICIENTS);

impl Table {
    /// Report eq. 9: the coefficients g and h of row `i` (n, m) moved
    /// `dt_years` from the epoch, in tenths of a nanotesla (the epoch's and
    /// the rates' whole numbers are exact in `f32`). Out of line on the
    /// AVR: the synthesis's loop then holds fewer values at once.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn at_date<F: Float>(
        &self,
        i: usize,
        n: usize,
        m: usize,
        dt_years: F,
    ) -> Result<(F, F), WmmError> {
        let coef = self.get(i, n, m)?;
        Ok((
            F::from_i32(coef.g_tenth_nt) + dt_years * F::from_i32(coef.g_dot_tenth_nt_per_yr),
            F::from_i32(coef.h_tenth_nt) + dt_years * F::from_i32(coef.h_dot_tenth_nt_per_yr),
        ))
    }

    /// Row `i`, which must be (n, m): the built-in table is in that order
    /// by construction ([`pack`]), a caller's table is checked.
    fn get(&self, i: usize, n: usize, m: usize) -> Result<WmmCoefficient, WmmError> {
        let packed = match self {
            #[cfg(target_arch = "avr")]
            Table::Wmm2025 => (i < WMM2025_FLASH.len()).then(|| WMM2025_FLASH.load_at(i)),
            #[cfg(not(target_arch = "avr"))]
            Table::Wmm2025 => WMM2025_PACKED.get(i).copied(),
            Table::Slice(rows) => {
                let row = rows.get(i).copied().ok_or(WmmError::BadCoefficientTable)?;
                if usize::from(row.n) != n || usize::from(row.m) != m {
                    return Err(WmmError::BadCoefficientTable);
                }
                return Ok(row);
            }
        };
        let row = packed.ok_or(WmmError::BadCoefficientTable)?;
        let (g_tenth_nt, h_tenth_nt) = match DEGREE_1.get(i) {
            Some(&whole) => whole,
            None => (i32::from(row.g_tenth_nt), i32::from(row.h_tenth_nt)),
        };
        // n, m ≤ 12: they came from the table's own order.
        Ok(WmmCoefficient {
            n: n as u8,
            m: m as u8,
            g_tenth_nt,
            h_tenth_nt,
            g_dot_tenth_nt_per_yr: i32::from(row.g_dot_tenth_nt_per_yr),
            h_dot_tenth_nt_per_yr: i32::from(row.h_dot_tenth_nt_per_yr),
        })
    }
}

/// A spherical-harmonic main-field model with secular variation.
///
/// ```
/// use drivers::compass::wmm::WmmModel;
///
/// // NOAA's WMM2025 test values: 2025.0, 0 km, 0° N, 120° E: D = −0.16°,
/// // in f64 and, on a board without an FPU, in f32.
/// let wmm = WmmModel::wmm2025();
/// let d64: f64 = wmm.declination_deg(0.0, 120.0, 0.0, 2025.0)?;
/// let d32: f32 = wmm.declination_deg(0.0, 120.0, 0.0, 2025.0)?;
/// assert!((d64 + 0.16).abs() < 0.005);
/// assert!((d32 + 0.16).abs() < 0.01);
/// # Ok::<(), drivers::compass::wmm::WmmError>(())
/// ```
#[derive(Debug, Clone, Copy)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WmmModel {
    epoch_year: u16,
    coefficients: Table,
}

impl WmmModel {
    /// The WMM2025 model (epoch 2025.0, valid until 2030.0).
    ///
    /// ```
    /// use drivers::compass::wmm::WmmModel;
    ///
    /// const WMM: WmmModel = WmmModel::wmm2025();
    /// assert_eq!(WMM.epoch_year(), 2025);
    /// // NOAA's WMM2025 test values: 2027.5, 100 km, 80° N, 0° E: D = 2.16°.
    /// let d: f64 = WMM.declination_deg(80.0, 0.0, 100.0, 2027.5)?;
    /// assert!((d - 2.16).abs() < 0.005);
    /// # Ok::<(), drivers::compass::wmm::WmmError>(())
    /// ```
    pub const fn wmm2025() -> Self {
        Self {
            epoch_year: EPOCH_YEAR,
            coefficients: Table::Wmm2025,
        }
    }

    /// A model from another WMM coefficient table (same layout as `WMM.COF`:
    /// rows n = 1..=12, m = 0..=n) and its epoch, a whole year as every
    /// WMM's. Used by the tests to check the synthesis against NOAA's
    /// WMM2020 test values.
    ///
    /// ```
    /// use drivers::compass::wmm::{WmmCoefficient, WmmError, WmmModel};
    ///
    /// // A pure axial dipole: g₁⁰ = −30 000 nT, every other coefficient 0
    /// // (rows n = 1..=12, m = 0..=n, as in WMM.COF).
    /// let rows: Vec<WmmCoefficient> = (1..=12u8)
    ///     .flat_map(|n| (0..=n).map(move |m| (n, m)))
    ///     .map(|(n, m)| WmmCoefficient {
    ///         n,
    ///         m,
    ///         g_tenth_nt: if (n, m) == (1, 0) { -300_000 } else { 0 },
    ///         h_tenth_nt: 0,
    ///         g_dot_tenth_nt_per_yr: 0,
    ///         h_dot_tenth_nt_per_yr: 0,
    ///     })
    ///     .collect();
    /// let dipole = WmmModel::from_table(2025, Vec::leak(rows));
    /// // On the equator at 0° E a dipole field points due north, level, with
    /// // X = −g₁⁰ (a/r)³ = 30 000 × (6371.2 / 6378.137)³ = 29 902.22 nT
    /// // (reference radius a, WGS-84 equatorial radius r).
    /// let e = dipole.field(0.0_f64, 0.0, 0.0, 2026.0)?;
    /// assert!((e.north_nt - 29_902.22).abs() < 0.01);
    /// assert!(e.east_nt.abs() < 1e-9 && e.down_nt.abs() < 1e-9);
    /// // A table without all rows n = 1..=12 is refused when used.
    /// let short = WmmModel::from_table(2025, Vec::leak(Vec::new()));
    /// assert_eq!(short.field(0.0_f64, 0.0, 0.0, 2026.0), Err(WmmError::BadCoefficientTable));
    /// # Ok::<(), WmmError>(())
    /// ```
    pub const fn from_table(epoch_year: u16, coefficients: &'static [WmmCoefficient]) -> Self {
        Self {
            epoch_year,
            coefficients: Table::Slice(coefficients),
        }
    }

    /// Epoch of the model, a whole year (its 1 January, 0 h).
    ///
    /// ```
    /// use drivers::compass::wmm::WmmModel;
    ///
    /// assert_eq!(WmmModel::wmm2025().epoch_year(), 2025);
    /// assert_eq!(WmmModel::from_table(2020, &[]).epoch_year(), 2020);
    /// ```
    pub fn epoch_year(&self) -> u16 {
        self.epoch_year
    }

    /// Declination in degrees (east positive) at a geodetic position.
    ///
    /// ```
    /// use drivers::compass::wmm::WmmModel;
    ///
    /// // NOAA's WMM2025 test values, 0 km: (2025.0, 80° N, 0° E) D = 1.28°,
    /// // (2027.5, 0° N, 120° E) D = −0.24°.
    /// let wmm = WmmModel::wmm2025();
    /// assert!((wmm.declination_deg(80.0, 0.0, 0.0, 2025.0)? - 1.28f64).abs() < 0.005);
    /// assert!((wmm.declination_deg(0.0, 120.0, 0.0, 2027.5)? + 0.24f64).abs() < 0.005);
    /// // Longitudes may be given east of 180° or as negative (240° = −120°).
    /// let a: f64 = wmm.declination_deg(-80.0, 240.0, 0.0, 2025.0)?;
    /// let b: f64 = wmm.declination_deg(-80.0, -120.0, 0.0, 2025.0)?;
    /// assert!((a - 68.78).abs() < 0.005 && (a - b).abs() < 1e-9);
    /// # Ok::<(), drivers::compass::wmm::WmmError>(())
    /// ```
    pub fn declination_deg<F: Float>(
        &self,
        latitude_deg: F,
        longitude_deg: F,
        height_km: F,
        decimal_year: F,
    ) -> Result<F, WmmError> {
        // The components only: on the AVR the other elements' square roots
        // and arctangent are library calls the compiler cannot drop.
        let [north_nt, east_nt, _] =
            self.components(latitude_deg, longitude_deg, height_km, decimal_year)?;
        Ok(declination_deg(north_nt, east_nt))
    }

    /// All magnetic elements at a geodetic position (WGS-84 latitude and
    /// longitude in degrees, height above the ellipsoid in km) and a decimal year.
    ///
    /// ```
    /// use drivers::compass::wmm::WmmModel;
    ///
    /// // NOAA's WMM2025 test values: 2027.5, 0 km, 80° S, 240° E:
    /// // X = 6200.7, Y = 15730.3, Z = −51783.7 nT, I = −71.92°, D = 68.49°.
    /// let e = WmmModel::wmm2025().field(-80.0_f64, 240.0, 0.0, 2027.5)?;
    /// assert!((e.north_nt - 6200.7).abs() < 0.05);
    /// assert!((e.east_nt - 15_730.3).abs() < 0.05);
    /// assert!((e.down_nt + 51_783.7).abs() < 0.05);
    /// assert!((e.inclination_deg + 71.92).abs() < 0.005);
    /// assert!((e.declination_deg - 68.49).abs() < 0.005);
    /// # Ok::<(), drivers::compass::wmm::WmmError>(())
    /// ```
    pub fn field<F: Float>(
        &self,
        latitude_deg: F,
        longitude_deg: F,
        height_km: F,
        decimal_year: F,
    ) -> Result<MagneticElements<F>, WmmError> {
        let [north_nt, east_nt, down_nt] =
            self.components(latitude_deg, longitude_deg, height_km, decimal_year)?;
        let horizontal_nt = (north_nt * north_nt + east_nt * east_nt).sqrt();
        Ok(MagneticElements {
            north_nt,
            east_nt,
            down_nt,
            horizontal_nt,
            total_nt: (horizontal_nt * horizontal_nt + down_nt * down_nt).sqrt(),
            inclination_deg: down_nt.atan2(horizontal_nt).to_degrees(),
            declination_deg: declination_deg(north_nt, east_nt),
        })
    }

    /// The field's north, east and down components, nT (report eqs. 7–11).
    fn components<F: Float>(
        &self,
        latitude_deg: F,
        longitude_deg: F,
        height_km: F,
        decimal_year: F,
    ) -> Result<[F; 3], WmmError> {
        let c = F::from_f64;
        if !(latitude_deg.is_finite()
            && longitude_deg.is_finite()
            && height_km.is_finite()
            && decimal_year.is_finite())
        {
            return Err(WmmError::NonFinite);
        }
        if !(c(-90.0)..=c(90.0)).contains(&latitude_deg) {
            return Err(WmmError::LatitudeOutOfRange);
        }
        if !(c(-360.0)..=c(360.0)).contains(&longitude_deg) {
            return Err(WmmError::LongitudeOutOfRange);
        }
        if !(c(-10.0)..=c(850.0)).contains(&height_km) {
            return Err(WmmError::HeightOutOfRange);
        }
        let dt_years = decimal_year - F::from_u32(u32::from(self.epoch_year));
        if !(c(0.0)..=c(LIFESPAN_YEARS)).contains(&dt_years) {
            return Err(WmmError::DateOutsideModel);
        }
        let (zero, one) = (c(0.0), c(1.0));

        // Geodetic -> geocentric spherical (report eqs. 7-8).
        let lat_rad = latitude_deg.to_radians();
        let lon_rad = longitude_deg.to_radians();
        let (sin_lat, cos_lat) = lat_rad.sin_cos();
        let e2 = c(WGS84_F * (2.0 - WGS84_F));
        let rc_km = c(WGS84_A_KM) / (one - e2 * sin_lat * sin_lat).sqrt();
        let p_km = (rc_km + height_km) * cos_lat;
        let z_km = (rc_km * (one - e2) + height_km) * sin_lat;
        let r_km = (p_km * p_km + z_km * z_km).sqrt();
        let lat_gc_rad = (z_km / r_km).asin();
        let (sin_gc, cos_gc) = lat_gc_rad.sin_cos();
        if cos_gc.abs() < c(1e-10) {
            return Err(WmmError::AtGeographicPole);
        }

        // cos(m λ), sin(m λ) by the angle-addition recurrence, one step
        // per m (no per-m arrays: an 8-bit board has 8 KB of RAM for all).
        let (sin_l, cos_l) = lon_rad.sin_cos();

        // Legendre rows n-1 and n-2 (values and d/dφ′), seeded with n = 0.
        // Row n is computed over row n-2 in place, then the two swap roles:
        // two pairs of rows, no copies.
        let mut rows_a = LegendreRow::zero();
        let mut rows_b = LegendreRow::zero();
        rows_a.p[0] = one;
        let (mut prev, mut prev2) = (&mut rows_a, &mut rows_b);

        let ratio = c(REFERENCE_RADIUS_KM) / r_km;
        let mut ratio_pow = ratio * ratio; // (a/r)^(n+2) for n = 0
        let mut x_gc = zero;
        let mut y_gc = zero;
        let mut z_gc = zero;
        let terms = DegreeTerms {
            table: &self.coefficients,
            dt_years,
            sin_l,
            cos_l,
        };
        let mut row_index = 0;

        for n in 1..=MAX_DEGREE {
            ratio_pow *= ratio;
            // Row n takes the place of row n-2.
            prev2.advance(n, prev, sin_gc, cos_gc);
            // n ≤ 12.
            let nf = F::from_u32(n as u32);
            let [sum_x, sum_y, sum_z] = terms.sums(n, prev2, row_index)?;
            // Degree n has n + 1 rows (n ≤ 12).
            row_index += n + 1;
            // Report eq. 10.
            x_gc -= ratio_pow * sum_x;
            y_gc += ratio_pow * sum_y;
            z_gc -= (nf + one) * ratio_pow * sum_z;
            // Row n is now the previous one, row n-1 the one before.
            core::mem::swap(&mut prev, &mut prev2);
        }
        y_gc /= cos_gc;
        // The sums are in tenths of a nanotesla.
        let tenths = c(10.0);
        let (x_gc, y_gc, z_gc) = (x_gc / tenths, y_gc / tenths, z_gc / tenths);

        // Report eq. 11: rotate from geocentric to ellipsoidal components.
        let (sin_d, cos_d) = (lat_gc_rad - lat_rad).sin_cos();
        let north_nt = x_gc * cos_d - z_gc * sin_d;
        let east_nt = y_gc;
        let down_nt = x_gc * sin_d + z_gc * cos_d;
        Ok([north_nt, east_nt, down_nt])
    }
}

/// What the sums of each degree take besides its Legendre row: the
/// coefficients, the date's years from the epoch, and sin λ, cos λ.
struct DegreeTerms<'a, F> {
    table: &'a Table,
    dt_years: F,
    sin_l: F,
    cos_l: F,
}

impl<F: Float> DegreeTerms<'_, F> {
    /// Report eq. 10's sums over m = 0..=n for degree `n` (rows
    /// `row_index..=row_index + n` of the table), for X, Y and Z. Out of
    /// line on the AVR: the synthesis's frame then holds fewer values at
    /// once, within reach of its frame pointer (`ldd`/`std` reach 63
    /// bytes; a slot beyond costs 8–12 more bytes at each use).
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn sums(&self, n: usize, row: &LegendreRow<F>, row_index: usize) -> Result<[F; 3], WmmError> {
        let (zero, one) = (F::from_f64(0.0), F::from_f64(1.0));
        let (mut sum_x, mut sum_y, mut sum_z) = (zero, zero, zero);
        // cos(m λ), sin(m λ) for m = 0.
        let (mut cm, mut sm) = (one, zero);
        for m in 0..=n {
            let mf = F::from_u32(m as u32);
            let p = get(&row.p, m);
            let dp = get(&row.dp, m);
            // Below the table's 90 rows.
            let (g, h) = self.table.at_date(row_index + m, n, m, self.dt_years)?;
            let gc_hs = g * cm + h * sm;
            sum_x += gc_hs * dp;
            sum_y += mf * (g * sm - h * cm) * p;
            sum_z += gc_hs * p;
            // cos((m+1)λ), sin((m+1)λ).
            (cm, sm) = (
                cm * self.cos_l - sm * self.sin_l,
                sm * self.cos_l + cm * self.sin_l,
            );
        }
        Ok([sum_x, sum_y, sum_z])
    }
}

/// D from the north and east components (report eq. 19).
fn declination_deg<F: Float>(north_nt: F, east_nt: F) -> F {
    east_nt.atan2(north_nt).to_degrees()
}

/// One degree n of the Schmidt semi-normalised associated Legendre
/// functions P̆ₙᵐ(sin φ′) and their derivatives d/dφ′, m = 0..=n (step 3
/// of the synthesis in the module documentation).
struct LegendreRow<F> {
    p: [F; MAX_DEGREE + 1],
    dp: [F; MAX_DEGREE + 1],
}

impl<F: Float> LegendreRow<F> {
    fn zero() -> Self {
        Self {
            p: [F::ZERO; MAX_DEGREE + 1],
            dp: [F::ZERO; MAX_DEGREE + 1],
        }
    }

    /// Turns this row, degree n − 2, into degree n from `prev`, degree
    /// n − 1: entry m of row n − 2 is last needed for entry m of row n.
    /// Out of line on the AVR: the synthesis, without these temporaries,
    /// then keeps more of its own within reach of its frame pointer
    /// (`ldd`/`std` reach 63 bytes; a slot beyond costs 8–12 more bytes
    /// at each use). 728 B less on the ATmega2560.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn advance(&mut self, n: usize, prev: &Self, sin_gc: F, cos_gc: F) {
        let (zero, one, two) = (F::ZERO, F::from_f64(1.0), F::from_f64(2.0));
        // n ≤ 12.
        let nf = F::from_u32(n as u32);
        // Entries m < n, then the sectoral one, m = n, outside the loop (each
        // entry reads only `prev` and its own entry of this row; n ≥ 1, the
        // caller's degrees 1..=12).
        let a = two * nf - one;
        for m in 0..n {
            let mf = F::from_u32(m as u32);
            // P̆ₙᵐ = [(2n−1) sin φ′ P̆ₙ₋₁ᵐ − √((n−1)²−m²) P̆ₙ₋₂ᵐ] / √(n²−m²)
            let b = ((nf - one) * (nf - one) - mf * mf).max(zero).sqrt();
            let cc = (nf * nf - mf * mf).sqrt();
            let p1 = get(&prev.p, m);
            let dp1 = get(&prev.dp, m);
            let p2 = get(&self.p, m);
            let dp2 = get(&self.dp, m);
            if let Some(slot) = self.p.get_mut(m) {
                *slot = (a * sin_gc * p1 - b * p2) / cc;
            }
            if let Some(slot) = self.dp.get_mut(m) {
                *slot = (a * (cos_gc * p1 + sin_gc * dp1) - b * dp2) / cc;
            }
        }
        // Sectoral: P̆ₙⁿ = k cos φ′ P̆ₙ₋₁ⁿ⁻¹, k = 1 for n = 1, √((2n−1)/2n) after.
        let k = if n == 1 { one } else { (a / (two * nf)).sqrt() };
        let pm = get(&prev.p, n - 1);
        let dpm = get(&prev.dp, n - 1);
        if let Some(slot) = self.p.get_mut(n) {
            *slot = k * cos_gc * pm;
        }
        if let Some(slot) = self.dp.get_mut(n) {
            *slot = k * (-sin_gc * pm + cos_gc * dpm);
        }
    }
}

fn get<F: Float>(row: &[F; MAX_DEGREE + 1], i: usize) -> F {
    row.get(i).copied().unwrap_or(F::ZERO)
}

/// Decimal year of a UTC calendar date and time of day, as the WMM uses it:
/// `year + (day_of_year − 1 + seconds_of_day / 86400) / days_in_year`, in
/// the float type of the synthesis (`f32` needs no `f64` on the way).
///
/// ```
/// use drivers::compass::wmm::{decimal_year, WmmError};
///
/// assert_eq!(decimal_year::<f64>(2025, 1, 1, 0)?, 2025.0);
/// // 2028 is a leap year: 2028-07-02 starts day 184 of 366, (184 − 1)/366 = 0.5.
/// assert_eq!(decimal_year::<f64>(2028, 7, 2, 0)?, 2028.5);
/// assert_eq!(decimal_year::<f32>(2028, 7, 2, 0)?, 2028.5);
/// assert_eq!(decimal_year::<f64>(2027, 2, 29, 0), Err(WmmError::InvalidDate));
/// assert_eq!(decimal_year::<f64>(2027, 1, 1, 86_400), Err(WmmError::InvalidDate));
/// # Ok::<(), WmmError>(())
/// ```
pub fn decimal_year<F: Float>(
    year: i32,
    month: u8,
    day: u8,
    seconds_of_day: u32,
) -> Result<F, WmmError> {
    let leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
    const CUMULATIVE: [u16; 12] = [0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334];
    const LENGTH: [u8; 12] = [31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31];
    let mi = usize::from(month)
        .checked_sub(1)
        .ok_or(WmmError::InvalidDate)?;
    let start = *CUMULATIVE.get(mi).ok_or(WmmError::InvalidDate)?;
    let len = LENGTH.get(mi).copied().unwrap_or(0) + u8::from(leap && month == 2);
    if day == 0 || day > len || seconds_of_day >= 86_400 {
        return Err(WmmError::InvalidDate);
    }
    let extra = u16::from(leap && month > 2);
    let day_of_year = start + extra + u16::from(day);
    let days_in_year = F::from_u32(if leap { 366 } else { 365 });
    let day_fraction = F::from_u32(seconds_of_day) / F::from_u32(86_400);
    Ok(F::from_i32(year) + (F::from_u32(u32::from(day_of_year - 1)) + day_fraction) / days_in_year)
}
