//! The sun's position for the tracker: one trait, [`PositionSource`], and
//! its sources over `sun_algos`' algorithms.
//!
//! | source | algorithm | site |
//! |---|---|---|
//! | [`AlgorithmSource`] | any | fixed |
//! | [`SharedSiteSource`] | any | in a shared [`Cell`], replaced by whoever owns it |
//! | [`BoardSource`] | `psa-2020` (the firmware loop of every board) | replaced by the loop |

use core::cell::Cell;

use sun_algos::{Algorithm, Error as SunError, Float, Options, Site, SunPosition, UtcTime};

/// Where the sun is at an instant, for one site.
pub trait PositionSource<T> {
    /// The site the positions are for (seed jimoh-2019 step 1 reads it).
    fn site(&self) -> Site<T>;
    /// Topocentric sun position at `time`.
    fn position(&mut self, time: &UtcTime) -> Result<SunPosition<T>, SunError>;
}

/// A [`PositionSource`] computing with one of `sun_algos`' algorithms.
#[derive(Debug, Clone, Copy)]
pub struct AlgorithmSource<T> {
    /// The algorithm (`psa-2020` on boards, any on hosts).
    pub algorithm: Algorithm,
    /// The site.
    pub site: Site<T>,
    /// ΔT, refraction and validity options.
    pub options: Options<T>,
}

impl<T: Float> PositionSource<T> for AlgorithmSource<T> {
    fn site(&self) -> Site<T> {
        self.site
    }
    fn position(&mut self, time: &UtcTime) -> Result<SunPosition<T>, SunError> {
        self.algorithm.position(time, &self.site, &self.options)
    }
}

/// A [`PositionSource`] whose site lives in a shared [`Cell`], so that the
/// site can be replaced (e.g. when GPS gets its first fix) while the
/// scheduler owns the source.
pub struct SharedSiteSource<'a, T> {
    /// The algorithm (`psa-2020` on boards).
    pub algorithm: Algorithm,
    /// The site, shared with whoever updates it.
    pub site: &'a Cell<Site<T>>,
    /// ΔT, refraction and validity options.
    pub options: Options<T>,
}

impl<T: Float> PositionSource<T> for SharedSiteSource<'_, T> {
    fn site(&self) -> Site<T> {
        self.site.get()
    }
    fn position(&mut self, time: &UtcTime) -> Result<SunPosition<T>, SunError> {
        self.algorithm
            .position(time, &self.site.get(), &self.options)
    }
}

/// The position source of the images: `psa-2020` (seed blanco-2020, valid
/// 2020–2050) for a site the loop may replace.
#[derive(Debug, Clone, Copy)]
pub struct BoardSource<T> {
    site: Site<T>,
    options: Options<T>,
}

impl<T: Float> BoardSource<T> {
    /// The source for `site` with ΔT `delta_t_s`.
    pub fn new(site: Site<T>, delta_t_s: f32) -> Self {
        BoardSource {
            site,
            options: Options {
                delta_t_s: Some(T::from_f32(delta_t_s)),
                ..Options::default()
            },
        }
    }
    /// Replaces the site.
    pub fn set_site(&mut self, site: Site<T>) {
        self.site = site;
    }
}

impl<T: Float> PositionSource<T> for BoardSource<T> {
    fn site(&self) -> Site<T> {
        self.site
    }
    #[inline(never)]
    fn position(&mut self, time: &UtcTime) -> Result<SunPosition<T>, SunError> {
        Algorithm::Psa2020.position(time, &self.site, &self.options)
    }
}
