//! The sun's position for the tracker: one trait, [`PositionSource`], and
//! its sources over `sun_algos`' algorithms.
//!
//! | source | algorithm | site |
//! |---|---|---|
//! | [`AlgorithmSource`] | any | fixed |
//! | [`SharedSiteSource`] | any | in a shared [`Cell`], replaced by whoever owns it |
//! | [`BoardSource`] | built in: `psa-2020` (the firmware loop of every board), `michalsky` (the Uno's servo tracker) | replaced by the loop |

use core::cell::Cell;
use core::marker::PhantomData;

use sun_algos::{Algorithm, Error as SunError, Float, Options, Site, SunPosition, UtcTime};

/// Where the sun is at an instant, for one site.
pub trait PositionSource<T> {
    /// The site the positions are for (Jimoh & Aliyu 2019 step 1 reads it).
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

/// A `sun_algos` algorithm chosen when the image is built, so that the
/// image links that algorithm's code only (a runtime [`Algorithm`] links
/// every one of them).
pub trait BuiltInAlgorithm {
    /// The algorithm.
    const ALGORITHM: Algorithm;
}

/// `psa-2020` (Blanco, Milidonis & Bonanos 2020, valid 2020–2050): the
/// firmware loop of every board.
#[derive(Debug, Clone, Copy)]
pub struct Psa2020;

impl BuiltInAlgorithm for Psa2020 {
    const ALGORITHM: Algorithm = Algorithm::Psa2020;
}

/// `michalsky` (Michalsky 1988, the Astronomical Almanac's algorithm,
/// 1950–2050): the Uno's servo tracker (Chowdhury et al. 2019 call it "AA").
#[derive(Debug, Clone, Copy)]
pub struct Michalsky;

impl BuiltInAlgorithm for Michalsky {
    const ALGORITHM: Algorithm = Algorithm::Michalsky;
}

/// The position source of the images: a built-in algorithm `A` with a
/// fixed ΔT, for a site the loop may replace.
#[derive(Debug, Clone, Copy)]
pub struct BoardSource<T, A = Psa2020> {
    site: Site<T>,
    delta_t_s: T,
    algorithm: PhantomData<A>,
}

impl<T: Float, A: BuiltInAlgorithm> BoardSource<T, A> {
    /// The source for `site` with ΔT `delta_t_s`.
    pub fn new(site: Site<T>, delta_t_s: f32) -> Self {
        BoardSource {
            site,
            delta_t_s: T::from_f32(delta_t_s),
            algorithm: PhantomData,
        }
    }

    /// Replaces the site.
    pub fn set_site(&mut self, site: Site<T>) {
        self.site = site;
    }

    /// The topocentric sun at `time`.
    #[inline(never)]
    pub fn at(&self, time: &UtcTime) -> Result<SunPosition<T>, SunError> {
        // Options built here with ΔT given: the ΔT model's code (taken
        // when none is given) is not linked.
        let options = Options {
            delta_t_s: Some(self.delta_t_s),
            ..Options::default()
        };
        A::ALGORITHM.position(time, &self.site, &options)
    }
}

impl<T: Float, A: BuiltInAlgorithm> PositionSource<T> for BoardSource<T, A> {
    fn site(&self) -> Site<T> {
        self.site
    }
    fn position(&mut self, time: &UtcTime) -> Result<SunPosition<T>, SunError> {
        self.at(time)
    }
}
