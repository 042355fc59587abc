//! A fixed tracker does not travel: which GPS positions become the site.
//!
//! A position within [`SiteFilterConfig::radius_deg`] of the site in use
//! confirms it and is taken at once (a fix refines a stored site; noise of a
//! few metres is far inside the radius). A position farther away is a
//! *candidate*: it becomes the site only after every fresh fix has stayed
//! within the radius of it for [`SiteFilterConfig::settle_ms`] on the
//! monotonic clock (a tracker carried to a new place, or a new stored site
//! the receiver contradicts). A candidate that moves by more than the radius
//! before it settles is a *jump*; after [`SiteFilterConfig::unstable_jumps`]
//! jumps the stream is unstable (fault `gps_position_unstable`) until a
//! position has been consistent for the settle time again. Meanwhile the
//! site in use (the stored one, or the last good GPS site) stays.
//!
//! Distances are those of an equirectangular projection: the latitude
//! difference and the longitude difference modulo 360° scaled by the cosine
//! of the latitude, so that ±180° meet and every longitude at a pole is the
//! same place. Within the radii used here (kilometres) this differs from
//! the great-circle distance by far less than the radius.

use sun_algos::{Float, Site};

use crate::time::monotonic;

/// Settings of [`SiteFilter`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SiteFilterConfig {
    /// Positions this close (degrees of a great circle) are the same place.
    pub radius_deg: f32,
    /// How long a new place must be consistent before it is taken, ms.
    pub settle_ms: u32,
    /// Jumps of a candidate before the stream counts as unstable.
    pub unstable_jumps: u8,
}

impl Default for SiteFilterConfig {
    /// 0.01° (1.1 km: the sun's position moves by under 0.01° for it);
    /// ten minutes (longer than the receiver's cold start, and than any
    /// glitch a real receiver shows); three jumps (a move away from the
    /// site in use is one, so one bad fix and the return from it are two).
    fn default() -> Self {
        SiteFilterConfig {
            radius_deg: 0.01,
            settle_ms: 600_000,
            unstable_jumps: 3,
        }
    }
}

/// The angular distance between two sites, degrees (equirectangular: see
/// the module documentation), longitudes compared modulo 360°.
pub fn site_distance_deg<T: Float>(a: &Site<T>, b: &Site<T>) -> T {
    let d_lat = a.latitude_deg() - b.latitude_deg();
    let full = T::from_f32(360.0);
    let half = T::from_f32(180.0);
    // In (−180, 180].
    let d_lon = (a.longitude_deg() - b.longitude_deg() + half).rem_euclid(full) - half;
    let mean_lat = (a.latitude_deg() + b.latitude_deg()) * T::from_f32(0.5);
    let east = d_lon * mean_lat.to_radians().cos();
    (d_lat * d_lat + east * east).sqrt()
}

/// What the filter decided for one fix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SiteDecision<T> {
    /// Use this position as the site (it confirms the site in use, or a
    /// new place settled).
    Take(Site<T>),
    /// Keep the site in use.
    Keep,
}

/// Decides which GPS positions become the site; see the module
/// documentation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SiteFilter<T> {
    config: SiteFilterConfig,
    /// The new place being confirmed and the monotonic ms it was first seen.
    candidate: Option<(Site<T>, u32)>,
    /// Jumps since the positions were last consistent for the settle time.
    jumps: u8,
    /// Monotonic ms of the last jump, while jumps are counted.
    last_jump_ms: Option<u32>,
}

impl<T: Float> SiteFilter<T> {
    /// No candidate yet.
    pub fn new(config: SiteFilterConfig) -> Self {
        SiteFilter {
            config,
            candidate: None,
            jumps: 0,
            last_jump_ms: None,
        }
    }

    /// True while the positions jump (fault `gps_position_unstable`): from
    /// the [`SiteFilterConfig::unstable_jumps`]-th jump until the positions
    /// have been consistent for the settle time.
    pub fn unstable(&self) -> bool {
        self.jumps >= self.config.unstable_jumps
    }

    /// Takes a fresh fix's position `seen` at monotonic `now_ms`, against
    /// the site in use.
    pub fn update(&mut self, seen: Site<T>, in_use: &Site<T>, now_ms: u32) -> SiteDecision<T> {
        self.expire(now_ms);
        let radius = T::from_f32(self.config.radius_deg);
        if site_distance_deg(&seen, in_use) <= radius {
            // Back at the site in use: a candidate elsewhere was a glitch
            // (a place left before it settled is a jump).
            if self.candidate.take().is_some() {
                self.jump(now_ms);
            }
            SiteDecision::Take(seen)
        } else {
            match self.candidate {
                Some((c, since_ms)) if site_distance_deg(&seen, &c) <= radius => {
                    // A place reached by a jump was first seen at the jump:
                    // it settles only when the stream is stable again.
                    if monotonic::elapsed_ms(now_ms, since_ms) >= self.config.settle_ms {
                        self.candidate = None;
                        SiteDecision::Take(seen)
                    } else {
                        SiteDecision::Keep
                    }
                }
                // Leaving the site in use, or the candidate.
                _ => {
                    self.jump(now_ms);
                    self.candidate = Some((seen, now_ms));
                    SiteDecision::Keep
                }
            }
        }
    }

    /// Forgets what is too old to count; the firmware calls it every tick
    /// (with a fix or without), so that no stamp on the 32-bit monotonic
    /// clock lives to its wrap (49.7 days), where it would look recent
    /// again. Consistent for the settle time since the last jump: stable
    /// again. A candidate not confirmed within an hour after its settle
    /// time (no fix came) is dropped. Out of line on the AVR, where two
    /// callers held a copy.
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn expire(&mut self, now_ms: u32) {
        let settle_ms = self.config.settle_ms;
        if let Some(t) = self.last_jump_ms {
            if monotonic::elapsed_ms(now_ms, t) >= settle_ms {
                self.jumps = 0;
                self.last_jump_ms = None;
            }
        }
        if let Some((_, since_ms)) = self.candidate {
            if monotonic::elapsed_ms(now_ms, since_ms) > settle_ms.saturating_add(3_600_000) {
                self.candidate = None;
            }
        }
    }

    fn jump(&mut self, now_ms: u32) {
        self.jumps = self.jumps.saturating_add(1);
        self.last_jump_ms = Some(now_ms);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn site(lat: f64, lon: f64) -> Site<f64> {
        Site::new(lat, lon).unwrap()
    }

    const KANO: (f64, f64) = (11.9683, 8.4317);
    const SYDNEY: (f64, f64) = (-33.8688, 151.2093);

    fn kano() -> Site<f64> {
        site(KANO.0, KANO.1)
    }

    fn sydney() -> Site<f64> {
        site(SYDNEY.0, SYDNEY.1)
    }

    #[test]
    fn distances_meet_at_the_date_line_and_the_poles() {
        // 2 m apart across ±180° at the equator: 0.000018°.
        let d = site_distance_deg(&site(0.0, 179.99999), &site(0.0, -179.99999));
        assert!(d < 0.0001, "{d}");
        // Every longitude at a pole is the same place.
        assert!(site_distance_deg(&site(90.0, 0.0), &site(90.0, 120.0)) < 1e-9);
        // 0.01° of longitude at 60° N is 0.005° of a great circle
        // (cos 60° = 0.5).
        let d = site_distance_deg(&site(60.0, 10.0), &site(60.0, 10.01));
        assert!((d - 0.005).abs() < 1e-6, "{d}");
        // Kano to Sydney: far beyond any radius.
        assert!(site_distance_deg(&kano(), &sydney()) > 100.0);
    }

    #[test]
    fn the_site_in_use_is_confirmed_at_once() {
        let mut f = SiteFilter::new(SiteFilterConfig::default());
        // 100 m from the site in use.
        let seen = site(KANO.0 + 0.0009, KANO.1);
        assert_eq!(f.update(seen, &kano(), 0), SiteDecision::Take(seen));
        assert!(!f.unstable());
    }

    #[test]
    fn one_bad_fix_is_no_fault() {
        let mut f = SiteFilter::new(SiteFilterConfig::default());
        let in_use = kano();
        assert_eq!(f.update(sydney(), &in_use, 0), SiteDecision::Keep);
        assert_eq!(f.update(kano(), &in_use, 1_000), SiteDecision::Take(kano()));
        assert!(!f.unstable());
    }

    #[test]
    fn a_new_place_is_taken_after_the_settle_time() {
        let cfg = SiteFilterConfig::default();
        let mut f = SiteFilter::new(cfg);
        let in_use = kano();
        for t_ms in (0..cfg.settle_ms).step_by(1000) {
            assert_eq!(
                f.update(sydney(), &in_use, t_ms),
                SiteDecision::Keep,
                "{t_ms}"
            );
        }
        assert_eq!(
            f.update(sydney(), &in_use, cfg.settle_ms),
            SiteDecision::Take(sydney())
        );
        assert!(!f.unstable());
    }

    #[test]
    fn a_receiver_that_jumps_every_second_is_never_followed() {
        let mut f = SiteFilter::new(SiteFilterConfig::default());
        let in_use = kano();
        let places = [sydney(), site(51.5, -0.12), site(40.7, -74.0)];
        for (i, t_ms) in (0..1_200_000u32).step_by(1000).enumerate() {
            let d = f.update(places[i % 3], &in_use, t_ms);
            assert_eq!(d, SiteDecision::Keep, "{t_ms}");
            // Unstable from the third jump (the third fix) on.
            assert_eq!(f.unstable(), i >= 2, "{t_ms}");
        }
    }

    #[test]
    fn kano_and_sydney_every_five_minutes_keeps_kano_and_is_unstable() {
        let mut f = SiteFilter::new(SiteFilterConfig::default());
        let in_use = kano();
        let mut unstable_from = None;
        for t_s in 0..7_200u32 {
            let seen = if (t_s / 300) % 2 == 1 {
                sydney()
            } else {
                kano()
            };
            let d = f.update(seen, &in_use, t_s * 1000);
            assert_ne!(d, SiteDecision::Take(sydney()), "{t_s}");
            if f.unstable() && unstable_from.is_none() {
                unstable_from = Some(t_s);
            }
        }
        // Left for Sydney at 300 s, back at 600 s, away again at 900 s:
        // the third jump.
        assert_eq!(unstable_from, Some(900));
        assert!(f.unstable());
    }

    #[test]
    fn stability_returns_after_the_settle_time() {
        let cfg = SiteFilterConfig::default();
        let mut f = SiteFilter::new(cfg);
        let in_use = kano();
        f.update(sydney(), &in_use, 0);
        f.update(kano(), &in_use, 1_000);
        f.update(sydney(), &in_use, 2_000);
        f.update(kano(), &in_use, 3_000);
        assert!(f.unstable());
        let end = 3_000 + cfg.settle_ms;
        for t_ms in (4_000..end).step_by(1000) {
            f.update(kano(), &in_use, t_ms);
            assert!(f.unstable(), "{t_ms}");
        }
        f.update(kano(), &in_use, end);
        assert!(!f.unstable());
    }

    #[test]
    fn a_place_reached_by_jumps_settles_only_after_the_last_one() {
        let cfg = SiteFilterConfig::default();
        let mut f = SiteFilter::new(cfg);
        let in_use = kano();
        let london = site(51.5, -0.12);
        f.update(sydney(), &in_use, 0);
        f.update(london, &in_use, 1_000);
        f.update(sydney(), &in_use, 2_000);
        assert!(f.unstable());
        // Sydney from 2 s on: taken when the jumps are settle_ms old.
        let take_ms = 2_000 + cfg.settle_ms;
        for t_ms in (3_000..take_ms).step_by(1000) {
            assert_eq!(f.update(sydney(), &in_use, t_ms), SiteDecision::Keep);
        }
        assert_eq!(
            f.update(sydney(), &in_use, take_ms),
            SiteDecision::Take(sydney())
        );
        assert!(!f.unstable());
    }

    #[test]
    fn f32_sites_near_the_date_line_and_the_pole() {
        let a = Site::<f32>::new(-16.5, 179.9999).unwrap();
        let b = Site::<f32>::new(-16.5, -179.9999).unwrap();
        assert!(site_distance_deg(&a, &b) < 0.001);
        let p = Site::<f32>::new(89.9999, 45.0).unwrap();
        let q = Site::<f32>::new(89.9999, -135.0).unwrap();
        // 0.0002° apart through the pole.
        assert!(site_distance_deg(&p, &q) < 0.01);
    }
}
