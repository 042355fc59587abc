//! Day table: size, capacity errors, lookup by time, f32.

use sun_algos::geometry::day_table::{capacity_for_interval, DayTable, Entry};
use sun_algos::geometry::events::{self, find, solar_day_start};
use sun_algos::geometry::incidence::Surface;
use sun_algos::geometry::optimum::Limits;
use sun_algos::geometry::simple::position;
use sun_algos::geometry::GeometryError;
use sun_algos::{Algorithm, Options, Site, UtcTime};

#[test]
fn ram_figures() {
    // 4-byte entries; table = 4·N + 14 bytes (8-byte instant, 2-byte
    // interval, 2-byte length, 2-byte length once complete), padded here to
    // the instant's 4-byte alignment (none on AVR).
    assert_eq!(core::mem::size_of::<Entry>(), 4);
    assert_eq!(capacity_for_interval(4), 361);
    assert_eq!(capacity_for_interval(8), 181);
    assert_eq!(core::mem::size_of::<DayTable<361>>(), 4 * 361 + 16);
    assert_eq!(core::mem::size_of::<DayTable<181>>(), 4 * 181 + 16);
    assert_eq!(core::mem::size_of::<DayTable<211>>(), 4 * 211 + 16);
}

#[test]
fn polar_day_fills_exactly_the_worst_case_capacity() {
    let start = solar_day_start(2024, 6, 21, 0.0f64).unwrap();
    let ev = find(start, |t| Ok(position(t, 85.0f64, 0.0))).unwrap();
    let t = DayTable::<361>::compute(&ev, 4, &Limits::upward(), |t| Ok(position(t, 85.0f64, 0.0)))
        .unwrap();
    assert_eq!(t.len(), 361);
    // One fewer slot is a clear error, never a truncated table.
    let e = DayTable::<360>::compute(&ev, 4, &Limits::upward(), |t| Ok(position(t, 85.0f64, 0.0)));
    assert_eq!(
        e,
        Err(GeometryError::CapacityExceeded {
            needed: 361,
            capacity: 360
        })
    );
}

#[test]
fn lookup_by_time_and_bad_interval() {
    let site = Site::new(11.9683f32, 8.4261).unwrap();
    let opts = Options::default();
    let ev = events::spa((2018, 10, 19), &site, &opts).unwrap();
    let sun = |t: &UtcTime| {
        Algorithm::Psa2020.position(
            t,
            &site,
            &Options {
                allow_out_of_range: true,
                ..opts
            },
        )
    };
    let table = DayTable::<211>::compute(&ev, 4, &Limits::upward(), sun).unwrap();
    let first = table.first_time();
    // Before the first entry: none; 3 min 59 s after: still the first.
    assert!(table.at(&first.add_seconds(-1).unwrap()).is_none());
    assert_eq!(table.at(&first.add_seconds(239).unwrap()).unwrap().0, first);
    assert_eq!(
        table.at(&first.add_seconds(240).unwrap()).unwrap().0,
        first.add_seconds(240).unwrap()
    );
    let (last, _) = table.get(table.len() - 1).unwrap();
    assert!(table.at(&last.add_seconds(239).unwrap()).is_some());
    assert!(table.at(&last.add_seconds(240).unwrap()).is_none());
    for bad in [0u16, 7, 721] {
        assert_eq!(
            DayTable::<211>::compute(&ev, bad, &Limits::upward(), sun),
            Err(GeometryError::InvalidInterval)
        );
    }
}

#[test]
fn entries_round_to_centidegrees() {
    let e = Entry::from_surface(&Surface {
        slope_deg: 37.566f64,
        azimuth_deg: 359.996,
    });
    assert_eq!((e.slope_cdeg(), e.azimuth_cdeg()), (3757, 0));
    let e = Entry::from_surface(&Surface {
        slope_deg: f64::NAN,
        azimuth_deg: -90.0,
    });
    assert_eq!((e.slope_cdeg(), e.azimuth_cdeg()), (0, 27_000));
}

/// The rounding as it was done in `f64` (exact there for an `f32`
/// surface: its hundredfold needs 31 bits): the reference for the integer
/// rounding that replaced it.
fn rounded_in_f64(slope_deg: f32, azimuth_deg: f32) -> (i16, u16) {
    let round = |v: f64| {
        if !v.is_finite() {
            0
        } else if v >= 0.0 {
            (v + 0.5) as i64
        } else {
            (v - 0.5) as i64
        }
    };
    let s = f64::from(slope_deg).clamp(-180.0, 180.0) * 100.0;
    let a = round(f64::from(azimuth_deg).rem_euclid(360.0) * 100.0);
    (round(s) as i16, if a >= 36_000 { 0 } else { a as u16 })
}

#[test]
fn f32_surfaces_round_as_in_f64() {
    // xorshift32 (Marsaglia 2003) over degrees of every size, with the
    // halfway cases (odd eighths: j/8 · 100 = 12.5 j) and the ends.
    let mut state = 0x1234_5678u32;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state
    };
    let mut values = vec![
        0.0f32, -0.0, 180.0, -180.0, 360.0, -360.0, 359.995, -1e-30, 1e30, -3e38,
    ];
    values.extend([
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MIN_POSITIVE,
        -1e-45,
    ]);
    for _ in 0..200_000 {
        let r = next();
        values.push(match r % 4 {
            0 => (r >> 2) as i32 as f32 / 8.0 / 2f32.powi((r % 7) as i32 * 8),
            1 => ((r >> 8) as f32 / 16_777_216.0 - 0.5) * 1440.0,
            2 => f32::from_bits(next()),
            _ => (r as i32 % 5_760) as f32 / 8.0,
        });
    }
    for pair in values.windows(2) {
        let (slope_deg, azimuth_deg) = (pair[0], pair[1]);
        let e = Entry::from_surface(&Surface {
            slope_deg,
            azimuth_deg,
        });
        assert_eq!(
            (e.slope_cdeg(), e.azimuth_cdeg()),
            rounded_in_f64(slope_deg, azimuth_deg),
            "{slope_deg} {azimuth_deg}"
        );
    }
}

#[test]
fn filling_a_few_entries_at_a_time_gives_the_same_table() {
    // Kano, 20 March 2026, psa-2020 in f32: the whole table at once and
    // three entries per call must agree entry for entry.
    let site = Site::new(11.9683f32, 8.4261).unwrap();
    let opts = Options::default();
    let sun = |t: &UtcTime| Algorithm::Psa2020.position(t, &site, &opts);
    let start = solar_day_start(2026, 3, 20, 8.4261f32).unwrap();
    let ev = find(start, sun).unwrap();
    let whole = DayTable::<211>::compute(&ev, 4, &Limits::upward(), sun).unwrap();
    let mut table = DayTable::<211>::empty(start);
    table.begin(&ev, 4).unwrap();
    assert!(table.is_empty() && !table.is_complete());
    let mut calls = 0;
    let mut src = sun;
    while !table.fill(&Limits::upward(), &mut src, 3).unwrap() {
        calls += 1;
        assert_eq!(table.len(), 3 * calls);
    }
    assert!(table.is_complete());
    assert_eq!(table, whole);
    assert!(whole.len() > 150);
}

/// `begin_daylight` sets a table up as `begin` does from the same events'
/// daylight, checks the interval before the daylight's error, and begins
/// no step in a polar night.
#[test]
fn begin_daylight_is_begin_with_the_daylight_given() {
    let site = Site::new(11.9683f64, 8.4261).unwrap(); // Kano
    let opts = Options::default();
    let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    let start = solar_day_start(2026, 6, 21, site.longitude_deg()).unwrap();
    let ev = find(start, sun).unwrap();
    let mut by_events = DayTable::<361>::empty(UtcTime::MIDNIGHT_2000);
    by_events.begin(&ev, 4).unwrap();
    let mut given = DayTable::<361>::empty(UtcTime::MIDNIGHT_2000);
    given
        .begin_daylight(ev.window_start, &ev.daylight(), 4)
        .unwrap();
    assert_eq!(given, by_events);
    assert!(given.first_time() >= ev.sunrise.unwrap());
    // An invalid interval first, then the daylight's error.
    let failed = Err(GeometryError::NotFinite);
    assert_eq!(
        given.begin_daylight(start, &failed, 7),
        Err(GeometryError::InvalidInterval)
    );
    assert_eq!(
        given.begin_daylight(start, &failed, 4),
        Err(GeometryError::NotFinite)
    );
    // Polar night: nothing to compute, complete at once.
    given.begin_daylight(start, &Ok(None), 4).unwrap();
    let mut calls = 0;
    let mut counted = |t: &UtcTime| {
        calls += 1;
        sun(t)
    };
    assert!(given.fill(&Limits::upward(), &mut counted, 1).unwrap());
    assert!(given.is_empty());
    assert_eq!(calls, 0);
}
