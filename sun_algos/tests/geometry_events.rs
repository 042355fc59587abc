//! Events: the simple model of Jimoh & Aliyu (2019, eq 9–12) and the precise
//! finder, and the property that neither (nor the day table) panics or gives
//! NaN at any latitude and date.

use sun_algos::geometry::day_table::{capacity_for_interval, DayTable};
use sun_algos::geometry::events::{find, simple, solar_day_start, DayKind};
use sun_algos::geometry::optimum::Limits;
use sun_algos::geometry::simple::{declination_deg, equation_of_time_h, position};
use sun_algos::UtcTime;

/// Sunset hour angle for a sun centre at altitude h0 (spherical astronomy,
/// NREL SPA report A.2 step 4): cos H = (sin h0 − sin φ sin δ)/(cos φ cos δ).
fn sunset_hour_angle_deg(lat: f64, delta: f64, h0: f64) -> f64 {
    let (sp, cp) = lat.to_radians().sin_cos();
    let (sd, cd) = delta.to_radians().sin_cos();
    ((h0.to_radians().sin() - sp * sd) / (cp * cd))
        .acos()
        .to_degrees()
}

#[test]
fn simple_model_kano() {
    // Eq 9 with δ = −10.90806°, φ = 11.9683°: ω_s = acos(tan 11.9683° ×
    // tan 10.90806°) = acos(0.040852) = 87.659°; eq 12: N = 11.688 h
    // (computed by hand in Python).
    let e = simple(11.9683f64, 292).unwrap();
    assert_eq!(e.kind, DayKind::Normal);
    assert!((e.sunset_hour_angle_deg - 87.659).abs() < 0.001, "{e:?}");
    assert!((e.daylight_h - 11.688).abs() < 0.001);
}

#[test]
fn precise_finder_on_the_simple_sun_matches_the_closed_form() {
    // With the simple model as the sun (constant δ and ET through the UT
    // day) the finder must land on the analytic crossing of h0 = −0.8333°.
    let (lat, lon) = (11.9683f64, 8.4261f64);
    let start = solar_day_start(2018, 10, 19, lon).unwrap();
    let ev = find(start, |t| Ok(position(t, lat, lon))).unwrap();
    let delta: f64 = declination_deg(292);
    let et_h: f64 = equation_of_time_h(292);
    let hs = sunset_hour_angle_deg(lat, delta, -0.8333);
    let noon_utc_h = 12.0 - lon / 15.0 - et_h;
    let rise_utc_s = (noon_utc_h - hs / 15.0) * 3600.0;
    let set_utc_s = (noon_utc_h + hs / 15.0) * 3600.0;
    let day0 = UtcTime::from_ymd_hms(2018, 10, 19, 0, 0, 0)
        .unwrap()
        .unix_seconds() as f64;
    let rise = ev.sunrise.unwrap().unix_seconds() as f64 - day0;
    let set = ev.sunset.unwrap().unix_seconds() as f64 - day0;
    assert!((rise - rise_utc_s).abs() <= 1.5, "{rise} vs {rise_utc_s}");
    assert!((set - set_utc_s).abs() <= 1.5, "{set} vs {set_utc_s}");
    let transit = ev.transit.unix_seconds() as f64 - day0;
    assert!((transit - noon_utc_h * 3600.0).abs() <= 2.0, "{transit}");
    assert_eq!(ev.kind, DayKind::Normal);
}

#[test]
fn polar_day_and_night_in_the_finder() {
    let start = solar_day_start(2024, 6, 21, 0.0f64).unwrap();
    let north = find(start, |t| Ok(position(t, 80.0f64, 0.0))).unwrap();
    assert_eq!(north.kind, DayKind::PolarDay);
    assert_eq!(north.daylight_s, 86_400);
    assert!(north.sunrise.is_none() && north.sunset.is_none());
    let south = find(start, |t| Ok(position(t, -80.0f64, 0.0))).unwrap();
    assert_eq!(south.kind, DayKind::PolarNight);
    assert_eq!(south.daylight_s, 0);
}

/// xorshift64* for the sampled dates.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

#[test]
fn simple_events_never_nan_any_latitude_any_day() {
    for lat_cdeg in (-9000..=9000).step_by(25) {
        let lat = f64::from(lat_cdeg) / 100.0;
        for n in 1..=366u16 {
            let e = simple(lat, n).unwrap();
            for v in [
                e.sunset_hour_angle_deg,
                e.sunrise_solar_h,
                e.sunset_solar_h,
                e.daylight_h,
            ] {
                assert!(v.is_finite(), "lat {lat} n {n}: {e:?}");
            }
            assert!((0.0..=24.0).contains(&e.daylight_h));
            let e32 = simple(lat as f32, n).unwrap();
            assert!(e32.daylight_h.is_finite() && (0.0..=24.0).contains(&e32.daylight_h));
        }
    }
}

#[test]
fn events_and_day_table_never_panic_nor_nan_1950_2100() {
    // Every latitude −90…90 in 2° steps (and ±89.99, ±66.56, ±1), one date per year
    // 1950–2100 at a pseudo-random day, f64 and f32; positions from
    // Jimoh & Aliyu's model so the property is about our code, not an
    // algorithm's.
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut lats: Vec<f64> = (-45..=45).map(|l| f64::from(2 * l)).collect();
    lats.extend([-89.99, 89.99, 66.56, -66.56, 1.0, -1.0]);
    let mut polar_days = 0;
    for year in 1950..=2100 {
        let doy = (rng.next() % 365) as i32;
        let day = UtcTime::from_ymd_hms(year, 1, 1, 0, 0, 0)
            .unwrap()
            .add_seconds(i64::from(doy) * 86_400)
            .unwrap();
        let (y, m, d) = day.ymd();
        let lon = (rng.next() % 36_001) as f64 / 100.0 - 180.0;
        for &lat in &lats {
            let start = solar_day_start(y, m, d, lon).unwrap();
            let ev = find(start, |t| Ok(position(t, lat, lon))).unwrap();
            assert!(ev.transit_zenith_deg.is_finite());
            assert!(ev.daylight_s <= 86_400);
            if ev.kind == DayKind::PolarDay {
                polar_days += 1;
            }
            let table =
                DayTable::<{ capacity_for_interval(4) }>::compute(&ev, 4, &Limits::upward(), |t| {
                    Ok(position(t, lat, lon))
                })
                .unwrap();
            for (t, e) in table.iter() {
                let s = e.surface::<f64>();
                assert!(s.slope_deg.is_finite() && (0.0..=90.0).contains(&s.slope_deg));
                assert!(t.unix_seconds() >= start.unix_seconds() - 240);
            }
            let ev32 = find(start, |t| Ok(position(t, lat as f32, lon as f32))).unwrap();
            assert!(ev32.transit_zenith_deg.is_finite());
        }
    }
    assert!(polar_days > 100, "the sample should include polar days");
}

#[test]
fn spa_events_and_tables_never_panic_nor_nan_1950_2100() {
    // The same property with NREL SPA (appendix A.2 events, SPA positions)
    // on a coarser grid: latitudes every 10° plus ±89.99°, every year,
    // f64 on even and f32 on odd years, a 30-minute table.
    use sun_algos::{Algorithm, Options, Site};
    let mut rng = Rng(0xDEAD_BEEF_F00D_0001);
    let mut lats: Vec<f64> = (-9..=9).map(|l| f64::from(10 * l)).collect();
    lats.extend([-89.99, 89.99]);
    for year in 1950..=2100 {
        let doy = (rng.next() % 365) as i64;
        let day = UtcTime::from_ymd_hms(year, 1, 1, 0, 0, 0)
            .unwrap()
            .add_seconds(doy * 86_400)
            .unwrap();
        let ymd = day.ymd();
        let lon = (rng.next() % 36_001) as f64 / 100.0 - 180.0;
        for &lat in &lats {
            if year % 2 == 0 {
                let site = Site::new(lat, lon).unwrap();
                let opts = Options::default();
                let ev = sun_algos::geometry::events::spa(ymd, &site, &opts).unwrap();
                assert!(ev.transit_zenith_deg.is_finite(), "{lat} {ymd:?}");
                let t = DayTable::<{ capacity_for_interval(30) }>::compute(
                    &ev,
                    30,
                    &Limits::upward(),
                    |t| Algorithm::Spa.position(t, &site, &opts),
                )
                .unwrap();
                assert!(t
                    .iter()
                    .all(|(_, e)| e.surface::<f64>().slope_deg.is_finite()));
            } else {
                let site = Site::new(lat as f32, lon as f32).unwrap();
                let opts = Options::default();
                let ev = sun_algos::geometry::events::spa(ymd, &site, &opts).unwrap();
                assert!(ev.transit_zenith_deg.is_finite(), "{lat} {ymd:?}");
                let t = DayTable::<{ capacity_for_interval(30) }>::compute(
                    &ev,
                    30,
                    &Limits::upward(),
                    |t| Algorithm::Spa.position(t, &site, &opts),
                )
                .unwrap();
                assert!(t
                    .iter()
                    .all(|(_, e)| e.surface::<f32>().slope_deg.is_finite()));
            }
        }
    }
}
