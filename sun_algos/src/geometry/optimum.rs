//! The optimum set-point for an instant, free and within mechanical limits.
//!
//! Free: Jimoh & Aliyu (2019), eq (14), `c6 cos β + c7 sin β − 1 = 0` with the
//! surface azimuth set to the sun's (γ = γs). With γ = γs the coefficients
//! are c6 = cos θz and c7 = sin θz (eq 7 and 8b), so the root is β = θz in
//! closed form — no bisection or `fminbnd` needed: [`normal_to_sun`].
//!
//! Limited: the mechanics allow β ∈ [β_min, β_max] and γ on an arc
//! [γ_min, γ_max]. [`best_within`] maximises cos θ over that box by an exact
//! reduction rather than a numeric search (the paper suggests a bounded
//! one-dimensional search; the reduction below needs none):
//!
//! 1. cos θ = cos β cos θz + sin β sin θz cos(γs − γ). For β ∈ [0°, 180°] and
//!    θz ∈ [0°, 180°] both sines are ≥ 0, so for every slope cos θ is
//!    non-increasing in the circular distance |γs − γ|. Hence so is its
//!    maximum over β, and the best azimuth is the point of the allowed arc
//!    nearest to γs (γs itself when inside, else the nearer end).
//! 2. With γ fixed, cos θ = A cos β + B sin β is a sinusoid in β; its
//!    maximum over an interval is at the unconstrained peak atan2(B, A) when
//!    that lies inside, otherwise at an end of the interval. The three
//!    candidates are evaluated and the best kept.
//!
//! `tests/geometry_optimum.rs` checks the result against a brute-force grid
//! at 0.01° steps.
//!
//! # Example
//!
//! ```
//! use sun_algos::geometry::optimum::{best_within, Limits};
//! use sun_algos::SunPosition;
//!
//! // The NREL SPA worked example's sun: zenith 50.111622°, azimuth 194.340241°.
//! // A mount that tilts at most 30° points at the sun's azimuth and tilts all
//! // the way; what remains is 50.111622° − 30° (hand geometry: the sun and the
//! // normal lie in one vertical plane).
//! let sun = SunPosition::new(50.111_622f64, 194.340_241, true);
//! let sp = best_within(&sun, &Limits::new(0.0, 30.0, 0.0, 360.0)?)?;
//! assert!((sp.surface.slope_deg - 30.0).abs() < 1e-9);
//! assert!((sp.surface.azimuth_deg - 194.340_241).abs() < 1e-9);
//! assert!((sp.incidence_deg - 20.111_622).abs() < 1e-6);
//! # Ok::<(), sun_algos::geometry::GeometryError>(())
//! ```

use crate::float::Float;
use crate::position::SunPosition;

use super::incidence::{incidence_deg, Surface};
use super::GeometryError;

/// Mechanical limits of a two-axis mount.
///
/// ```
/// use sun_algos::geometry::{Limits, Surface};
///
/// // The southern two thirds of the sky, tilts 5…85°.
/// let lim = Limits::new(5.0f64, 85.0, 60.0, 300.0)?;
/// assert!(lim.contains(&Surface::new(45.0, 180.0)?, 0.0));
/// assert!(!lim.contains(&Surface::new(45.0, 0.0)?, 0.0));
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Limits<T> {
    slope_min_deg: T,
    slope_max_deg: T,
    azimuth_min_deg: T,
    azimuth_max_deg: T,
}

impl<T: Float> Limits<T> {
    /// Slope in `[slope_min, slope_max]` ⊂ [0°, 180°] and surface azimuth
    /// (east of north) on the arc from `azimuth_min` clockwise to
    /// `azimuth_max`; `azimuth_max − azimuth_min` must be in 0…360 (e.g.
    /// −90…90 is the northern half, 60…300 the southern two thirds).
    ///
    /// ```
    /// use sun_algos::geometry::{GeometryError, Limits};
    ///
    /// // −90…90 is the northern half of the azimuths (an arc through north).
    /// let lim = Limits::new(0.0f32, 60.0, -90.0, 90.0)?;
    /// assert_eq!(lim.azimuth_max_deg() - lim.azimuth_min_deg(), 180.0);
    /// assert_eq!(Limits::new(10.0f32, 5.0, 0.0, 10.0), Err(GeometryError::InvalidLimits));
    /// assert_eq!(Limits::new(0.0f32, 90.0, 0.0, 400.0), Err(GeometryError::InvalidLimits));
    /// assert_eq!(Limits::new(0.0f32, f32::NAN, 0.0, 10.0), Err(GeometryError::NotFinite));
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn new(
        slope_min_deg: T,
        slope_max_deg: T,
        azimuth_min_deg: T,
        azimuth_max_deg: T,
    ) -> Result<Self, GeometryError> {
        for v in [
            slope_min_deg,
            slope_max_deg,
            azimuth_min_deg,
            azimuth_max_deg,
        ] {
            if !v.is_finite() {
                return Err(GeometryError::NotFinite);
            }
        }
        let width = azimuth_max_deg - azimuth_min_deg;
        if slope_min_deg < T::ZERO
            || slope_max_deg > T::from_f64(180.0)
            || slope_min_deg > slope_max_deg
            || width < T::ZERO
            || width > T::from_f64(360.0)
        {
            return Err(GeometryError::InvalidLimits);
        }
        Ok(Limits {
            slope_min_deg,
            slope_max_deg,
            azimuth_min_deg,
            azimuth_max_deg,
        })
    }

    /// No limits: slope 0…180°, any azimuth.
    ///
    /// ```
    /// use sun_algos::geometry::{optimum::best_within, Limits};
    /// use sun_algos::SunPosition;
    ///
    /// // Any sun can be faced: zero incidence, even below the horizon.
    /// let sun = SunPosition::new(120.0f64, 45.0, false);
    /// assert!(best_within(&sun, &Limits::unconstrained())?.incidence_deg < 1e-6);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn unconstrained() -> Self {
        Limits {
            slope_min_deg: T::ZERO,
            slope_max_deg: T::from_f64(180.0),
            azimuth_min_deg: T::ZERO,
            azimuth_max_deg: T::from_f64(360.0),
        }
    }

    /// A typical tracker: slope 0…90°, any azimuth.
    ///
    /// ```
    /// use sun_algos::geometry::{optimum::best_within, Limits};
    /// use sun_algos::SunPosition;
    ///
    /// // A sun 10° below the horizon: the panel stands vertical, 10° off.
    /// let sun = SunPosition::new(100.0f64, 270.0, false);
    /// let sp = best_within(&sun, &Limits::upward())?;
    /// assert_eq!(sp.surface.slope_deg, 90.0);
    /// assert!((sp.incidence_deg - 10.0).abs() < 1e-9);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn upward() -> Self {
        Limits {
            slope_max_deg: T::from_f64(90.0),
            ..Self::unconstrained()
        }
    }

    /// Lowest slope, degrees.
    ///
    /// ```
    /// use sun_algos::geometry::Limits;
    ///
    /// assert_eq!(Limits::new(5.0f64, 85.0, 60.0, 300.0)?.slope_min_deg(), 5.0);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn slope_min_deg(&self) -> T {
        self.slope_min_deg
    }
    /// Highest slope, degrees.
    ///
    /// ```
    /// use sun_algos::geometry::Limits;
    ///
    /// assert_eq!(Limits::<f64>::upward().slope_max_deg(), 90.0);
    /// ```
    pub fn slope_max_deg(&self) -> T {
        self.slope_max_deg
    }
    /// Start of the azimuth arc, degrees east of north.
    ///
    /// ```
    /// use sun_algos::geometry::Limits;
    ///
    /// assert_eq!(Limits::new(5.0f64, 85.0, 60.0, 300.0)?.azimuth_min_deg(), 60.0);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn azimuth_min_deg(&self) -> T {
        self.azimuth_min_deg
    }
    /// End of the azimuth arc (clockwise from the start), degrees.
    ///
    /// ```
    /// use sun_algos::geometry::Limits;
    ///
    /// assert_eq!(Limits::new(5.0f64, 85.0, 60.0, 300.0)?.azimuth_max_deg(), 300.0);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn azimuth_max_deg(&self) -> T {
        self.azimuth_max_deg
    }

    /// True when `surface` lies inside the limits (azimuth compared on the
    /// circle, with a tolerance of `tol_deg`).
    ///
    /// ```
    /// use sun_algos::geometry::{Limits, Surface};
    ///
    /// // The arc −45…45 runs through north: 350° is on it, 50° only with 5° of
    /// // tolerance.
    /// let lim = Limits::new(0.0f64, 90.0, -45.0, 45.0)?;
    /// assert!(lim.contains(&Surface::new(30.0, 350.0)?, 0.0));
    /// assert!(!lim.contains(&Surface::new(30.0, 50.0)?, 0.0));
    /// assert!(lim.contains(&Surface::new(30.0, 50.0)?, 5.0));
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn contains(&self, surface: &Surface<T>, tol_deg: T) -> bool {
        let in_slope = surface.slope_deg >= self.slope_min_deg - tol_deg
            && surface.slope_deg <= self.slope_max_deg + tol_deg;
        let d =
            (surface.azimuth_deg - self.azimuth_min_deg + tol_deg).rem_euclid(T::from_f64(360.0));
        let width = self.azimuth_max_deg - self.azimuth_min_deg;
        in_slope && (d <= width + tol_deg + tol_deg || width >= T::from_f64(360.0))
    }

    /// The point of the azimuth arc nearest (on the circle) to `azimuth_deg`.
    fn nearest_azimuth_deg(&self, azimuth_deg: T) -> T {
        let full = T::from_f64(360.0);
        let width = self.azimuth_max_deg - self.azimuth_min_deg;
        let d = (azimuth_deg - self.azimuth_min_deg).rem_euclid(full);
        let g = if d <= width {
            azimuth_deg
        } else if d - width <= full - d {
            self.azimuth_max_deg
        } else {
            self.azimuth_min_deg
        };
        g.rem_euclid(full)
    }
}

/// A set-point and the incidence it leaves.
///
/// ```
/// use sun_algos::geometry::{optimum::best_within, Limits};
/// use sun_algos::SunPosition;
///
/// // Inside the limits the sun is faced exactly.
/// let sun = SunPosition::new(40.0f64, 250.0, false);
/// let sp = best_within(&sun, &Limits::upward())?;
/// assert!(sp.incidence_deg < 1e-6);
/// assert_eq!((sp.surface.slope_deg, sp.surface.azimuth_deg), (40.0, 250.0));
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SetPoint<T> {
    /// Where the surface points.
    pub surface: Surface<T>,
    /// Remaining angle of incidence in degrees (0 when the sun is reachable).
    pub incidence_deg: T,
}

/// The zero-incidence set-point (Jimoh & Aliyu 2019, eq 14, in closed form):
/// β = θz, γ = γs.
///
/// ```
/// use sun_algos::geometry::optimum::normal_to_sun;
/// use sun_algos::SunPosition;
///
/// // Jimoh & Aliyu (2019), eq. 14: slope = zenith, surface azimuth = sun azimuth.
/// let s = normal_to_sun(&SunPosition::new(50.111_622f32, 194.340_241, true));
/// assert_eq!((s.slope_deg, s.azimuth_deg), (50.111_622, 194.340_241));
/// ```
pub fn normal_to_sun<T: Float>(sun: &SunPosition<T>) -> Surface<T> {
    Surface::facing(sun)
}

/// Root of eq (14) of Jimoh & Aliyu (2019), `c6 cos β + c7 sin β = 1`, in
/// degrees, for coefficients with c6² + c7² = 1 (as they are when γ = γs):
/// β = atan2(c7, c6). For other coefficients this is the β that maximises the
/// left side, i.e. the closest the equation can come to holding.
///
/// ```
/// use sun_algos::geometry::optimum::eq14_slope_deg;
///
/// // c6 = cos θz, c7 = sin θz: the root is θz itself (eq. 14 with γ = γs).
/// let z = 35.0f64.to_radians();
/// assert!((eq14_slope_deg(z.cos(), z.sin()) - 35.0).abs() < 1e-12);
/// ```
pub fn eq14_slope_deg<T: Float>(c6: T, c7: T) -> T {
    c7.atan2(c6).to_degrees()
}

/// The set-point within `limits` that minimises the incidence (method in
/// the module documentation). Errors only for non-finite sun angles.
///
/// ```
/// use sun_algos::geometry::optimum::{best_within, Limits};
/// use sun_algos::SunPosition;
///
/// // Azimuths 90…270 only (east through south to west); a sun in the
/// // north-east at azimuth 20° is nearer the 90° end (70° away) than the 270°
/// // end (110°), hand geometry.
/// let lim = Limits::new(0.0f64, 90.0, 90.0, 270.0)?;
/// let sp = best_within(&SunPosition::new(60.0, 20.0, false), &lim)?;
/// assert!((sp.surface.azimuth_deg - 90.0).abs() < 1e-9);
/// // cos θ = cos β cos 60° + sin β sin 60° cos 70° is largest at
/// // β = atan(tan 60° · cos 70°) = 30.64°.
/// let beta = (60.0f64.to_radians().tan() * 70.0f64.to_radians().cos()).atan().to_degrees();
/// assert!((sp.surface.slope_deg - beta).abs() < 1e-9);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
pub fn best_within<T: Float>(
    sun: &SunPosition<T>,
    limits: &Limits<T>,
) -> Result<SetPoint<T>, GeometryError> {
    let surface = best_surface_within(sun, limits)?;
    let zenith = sun.zenith_deg.clamp(T::ZERO, T::from_f64(180.0));
    let sun_c = SunPosition::new(zenith, sun.azimuth_deg, sun.refracted);
    Ok(SetPoint {
        surface,
        incidence_deg: incidence_deg(&sun_c, &surface),
    })
}

/// The surface of [`best_within`] without its incidence, for callers that
/// keep the surface only (the day table): the incidence's own sines,
/// cosines and arctangent are not computed (an 8-bit board's libm cannot
/// drop calls whose result is unused). Out of line on AVR, where the day
/// table's fill is smaller calling it.
#[cfg_attr(target_arch = "avr", inline(never))]
pub(crate) fn best_surface_within<T: Float>(
    sun: &SunPosition<T>,
    limits: &Limits<T>,
) -> Result<Surface<T>, GeometryError> {
    if !sun.zenith_deg.is_finite() || !sun.azimuth_deg.is_finite() {
        return Err(GeometryError::NotFinite);
    }
    let zenith = sun.zenith_deg.clamp(T::ZERO, T::from_f64(180.0));
    let gamma = limits.nearest_azimuth_deg(sun.azimuth_deg);
    let (sz, cz) = zenith.to_radians().sin_cos();
    let a = cz;
    let b = sz * (sun.azimuth_deg - gamma).to_radians().cos();
    let peak = b.atan2(a).to_degrees();
    let value = |beta: T| {
        let (sb, cb) = beta.to_radians().sin_cos();
        a * cb + b * sb
    };
    let mut best = limits.slope_min_deg;
    let mut best_v = value(best);
    let mut consider = |beta: T| {
        let v = value(beta);
        if v > best_v {
            best_v = v;
            best = beta;
        }
    };
    consider(limits.slope_max_deg);
    if peak >= limits.slope_min_deg && peak <= limits.slope_max_deg {
        consider(peak);
    }
    Ok(Surface {
        slope_deg: best,
        azimuth_deg: gamma,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_optimum_has_zero_incidence() {
        let sun = SunPosition::new(40.0f64, 250.0, false);
        let sp = best_within(&sun, &Limits::unconstrained()).unwrap();
        assert!(sp.incidence_deg < 1e-6);
        assert!((sp.surface.slope_deg - 40.0).abs() < 1e-9);
        assert!((sp.surface.azimuth_deg - 250.0).abs() < 1e-9);
    }

    #[test]
    fn azimuth_outside_arc_goes_to_nearer_end() {
        // Arc 90..270 (east through south to west); sun at azimuth 20° is
        // nearer to 90 (70°) than to 270 (110°).
        let lim = Limits::new(0.0f64, 90.0, 90.0, 270.0).unwrap();
        let sun = SunPosition::new(60.0, 20.0, false);
        let sp = best_within(&sun, &lim).unwrap();
        assert!((sp.surface.azimuth_deg - 90.0).abs() < 1e-9);
        // Arc wrapping through north: −45..45; sun at 300 → −45 = 315.
        let lim = Limits::new(0.0f64, 90.0, -45.0, 45.0).unwrap();
        let sun = SunPosition::new(60.0, 300.0, false);
        let sp = best_within(&sun, &lim).unwrap();
        assert!((sp.surface.azimuth_deg - 315.0).abs() < 1e-9);
    }

    #[test]
    fn bad_limits_are_errors() {
        assert_eq!(
            Limits::new(10.0f32, 5.0, 0.0, 10.0),
            Err(GeometryError::InvalidLimits)
        );
        assert_eq!(
            Limits::new(0.0f32, 5.0, 0.0, 400.0),
            Err(GeometryError::InvalidLimits)
        );
        assert_eq!(
            Limits::new(0.0f32, f32::NAN, 0.0, 10.0),
            Err(GeometryError::NotFinite)
        );
    }
}
