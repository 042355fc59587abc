//! A latitude or longitude exactly as an NMEA sentence writes it.

use sun_algos::Float;

/// A latitude or longitude as the receiver wrote it, `ddmm.mmmmm`: a whole
/// number of 10⁻¹¹ arc-minutes (the most minute decimals the parser reads),
/// north and east positive. Exact, so that each float type rounds it once
/// ([`Coordinate::deg`]): an 8-bit board reads its `f32` degrees without any
/// `f64` arithmetic, a host its `f64` ones as before.
///
/// ```
/// use drivers::gps::Coordinate;
///
/// // 47°17.11399' (u-blox's GGA example) = 47 + 17.11399/60 degrees.
/// let lat = Coordinate::from_e11_min((47 * 60 * 100_000 + 1_711_399) * 1_000_000);
/// assert_eq!(lat.deg::<f64>(), 283_711_399.0 / 6_000_000.0);
/// assert_eq!(lat.deg::<f32>(), 47.285_233);
/// assert_eq!(Coordinate::from_deg(-33.8688).map(|c| c.deg::<f64>()), Some(-33.8688));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(transparent)
)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Coordinate {
    e11_min: i64,
}

impl Coordinate {
    /// 10⁻¹¹ arc-minutes in a degree: 60 · 10¹¹.
    pub const E11_MIN_PER_DEG: i64 = 6_000_000_000_000;

    /// The coordinate of `e11_min` 10⁻¹¹ arc-minutes.
    pub const fn from_e11_min(e11_min: i64) -> Self {
        Coordinate { e11_min }
    }

    /// The coordinate in 10⁻¹¹ arc-minutes.
    ///
    /// ```
    /// use drivers::gps::Coordinate;
    ///
    /// // 1° S = −60 arc-minutes.
    /// assert_eq!(Coordinate::from_deg(-1.0).unwrap().e11_min(), -60 * 100_000_000_000);
    /// ```
    pub const fn e11_min(self) -> i64 {
        self.e11_min
    }

    /// The coordinate in degrees, the value nearest it in `T` (one rounding
    /// of the exact ratio, [`Float::from_ratio`]).
    pub fn deg<T: Float>(self) -> T {
        // The constant is positive.
        T::from_ratio(self.e11_min, Self::E11_MIN_PER_DEG.unsigned_abs())
    }

    /// The coordinate nearest `deg` degrees (to the rounding of `deg · 6·10¹²`;
    /// for fixes built by hand, as in tests and models); `None` for NaN, ±∞
    /// or beyond ±10⁶°.
    pub fn from_deg(deg: f64) -> Option<Self> {
        if !deg.is_finite() || deg.abs() > 1e6 {
            return None;
        }
        // |deg| ≤ 10⁶: at most 6·10¹⁸ < 2⁶³.
        let e11_min = libm::round(deg * Self::E11_MIN_PER_DEG as f64) as i64;
        Some(Coordinate { e11_min })
    }

    /// Whether the coordinate lies within ±`max_deg` degrees, decided on
    /// the integer, without floats (10⁻¹¹′ is coarser than an `f64`'s step
    /// at 90° or 180°, so this is also where its `f64` degrees lie).
    ///
    /// ```
    /// use drivers::gps::Coordinate;
    ///
    /// let pole = Coordinate::from_e11_min(90 * Coordinate::E11_MIN_PER_DEG);
    /// assert!(pole.within_deg(90));
    /// assert!(!Coordinate::from_e11_min(pole.e11_min() + 1).within_deg(90));
    /// ```
    // Not inlined: its 64-bit product and compare at each caller (the
    // content checks and the time keeper) are larger than a call.
    #[inline(never)]
    pub fn within_deg(self, max_deg: u8) -> bool {
        self.e11_min.unsigned_abs() <= u64::from(max_deg) * Self::E11_MIN_PER_DEG.unsigned_abs()
    }
}
