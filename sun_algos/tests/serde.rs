//! The `serde` feature: every plain-data type round trips through JSON, and
//! the types with validated fields reject invalid values on the way in.
#![cfg(feature = "serde")]

use serde::de::DeserializeOwned;
use serde::Serialize;
use sun_algos::geometry::day_table::{capacity_for_interval, DayTable, Entry};
use sun_algos::geometry::events::{self, DayKind};
use sun_algos::geometry::irradiance::{self, Mount};
use sun_algos::geometry::optimum::{self, Limits};
use sun_algos::geometry::{GeometryError, Surface};
use sun_algos::{grena2012, psa, spa};
use sun_algos::{Algorithm, Atmosphere, Error, Options, Site, SunPosition, UtcTime};

fn round_trip<V>(v: &V) -> String
where
    V: Serialize + DeserializeOwned + PartialEq + core::fmt::Debug,
{
    let text = serde_json::to_string(v).unwrap();
    let back: V = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
    assert_eq!(&back, v, "{text}");
    text
}

/// The deserializer's error for `text`, which must be rejected.
fn rejected<V: DeserializeOwned + core::fmt::Debug>(text: &str) -> String {
    match serde_json::from_str::<V>(text) {
        Ok(v) => panic!("{text} accepted as {v:?}"),
        Err(e) => e.to_string(),
    }
}

fn kano() -> Site<f64> {
    Site::with_elevation(11.9683, 8.4261, 480.0).unwrap()
}

#[test]
fn validated_inputs_round_trip_and_reject_invalid_values() {
    let text = round_trip(&kano());
    assert_eq!(
        text,
        r#"{"latitude_deg":11.9683,"longitude_deg":8.4261,"elevation_m":480.0}"#
    );
    round_trip(&Site::new(-33.9f32, 18.4).unwrap());
    // Elevation may be left out: sea level.
    let s: Site<f64> = serde_json::from_str(r#"{"latitude_deg":1.0,"longitude_deg":2.0}"#).unwrap();
    assert_eq!(s, Site::new(1.0, 2.0).unwrap());
    // Each check of Site::with_elevation, with its message.
    for (text, why) in [
        (
            r#"{"latitude_deg":90.5,"longitude_deg":0.0}"#,
            Error::LatitudeOutOfRange,
        ),
        (
            r#"{"latitude_deg":0.0,"longitude_deg":-180.5}"#,
            Error::LongitudeOutOfRange,
        ),
        (
            r#"{"latitude_deg":0.0,"longitude_deg":0.0,"elevation_m":-600.0}"#,
            Error::ElevationOutOfRange,
        ),
    ] {
        let e = rejected::<Site<f64>>(text);
        assert!(e.starts_with(&why.to_string()), "{text}: {e}");
    }
    rejected::<Site<f64>>(r#"{"latitude_deg":null,"longitude_deg":0.0}"#);

    let text = round_trip(&Atmosphere::new(1010.0f64, 25.0).unwrap());
    assert_eq!(text, r#"{"pressure_hpa":1010.0,"temperature_c":25.0}"#);
    round_trip(&Atmosphere::<f32>::standard());
    for (text, why) in [
        (
            r#"{"pressure_hpa":0.0,"temperature_c":10.0}"#,
            Error::PressureOutOfRange,
        ),
        (
            r#"{"pressure_hpa":2500.0,"temperature_c":10.0}"#,
            Error::PressureOutOfRange,
        ),
        (
            r#"{"pressure_hpa":1000.0,"temperature_c":-120.0}"#,
            Error::TemperatureOutOfRange,
        ),
    ] {
        let e = rejected::<Atmosphere<f64>>(text);
        assert!(e.starts_with(&why.to_string()), "{text}: {e}");
    }

    let opts = Options {
        delta_t_s: Some(69.2f64),
        atmosphere: Some(Atmosphere::new(820.0, 11.0).unwrap()),
        allow_out_of_range: true,
    };
    round_trip(&opts);
    round_trip(&Options::<f32>::default());
    // `allow_out_of_range` may be left out; the Options of an empty object
    // are the defaults.
    assert_eq!(
        serde_json::from_str::<Options<f64>>("{}").unwrap(),
        Options::default()
    );
    // A nested invalid atmosphere is rejected with the options.
    let e = rejected::<Options<f64>>(
        r#"{"delta_t_s":null,"atmosphere":{"pressure_hpa":-1.0,"temperature_c":0.0}}"#,
    );
    assert!(e.starts_with(&Error::PressureOutOfRange.to_string()), "{e}");
}

#[test]
fn utc_time_round_trips_as_date_and_millisecond() {
    let t = UtcTime::from_ymd_hms_milli(2026, 6, 21, 12, 0, 0, 5).unwrap();
    let text = round_trip(&t);
    assert_eq!(
        text,
        r#"{"date":{"year":2026,"month":6,"day":21},"ms_of_day":43200005}"#
    );
    for t in [
        UtcTime::MIDNIGHT_2000,
        UtcTime::from_ymd_hms(-4000, 1, 1, 0, 0, 0).unwrap(),
        UtcTime::from_ymd_hms_milli(8000, 12, 31, 23, 59, 59, 999).unwrap(),
        UtcTime::from_ymd_hms(2024, 2, 29, 6, 30, 0).unwrap(),
    ] {
        round_trip(&t);
    }
    for (text, why) in [
        // Past the last millisecond of the day.
        (
            r#"{"date":{"year":2026,"month":6,"day":21},"ms_of_day":86400000}"#,
            Error::InvalidTime.to_string(),
        ),
        // A Date, but outside UtcTime's years.
        (
            r#"{"date":{"year":8001,"month":1,"day":1},"ms_of_day":0}"#,
            Error::InvalidDate.to_string(),
        ),
        (
            r#"{"date":{"year":-4001,"month":12,"day":31},"ms_of_day":0}"#,
            Error::InvalidDate.to_string(),
        ),
        // Not a date (the Date's own check).
        (
            r#"{"date":{"year":2023,"month":2,"day":29},"ms_of_day":0}"#,
            sun_algos::time::DateError::Day.to_string(),
        ),
    ] {
        let e = rejected::<UtcTime>(text);
        assert!(e.starts_with(&why), "{text}: {e}");
    }
    rejected::<UtcTime>(r#"{"date":{"year":2026,"month":6,"day":21}}"#);
    rejected::<UtcTime>(r#""2026-06-21T12:00:00Z""#);
}

#[test]
fn results_round_trip() {
    let t = UtcTime::from_ymd_hms(2026, 3, 20, 12, 0, 0).unwrap();
    let site = kano();
    let opts = Options {
        atmosphere: Some(Atmosphere::standard()),
        ..Options::default()
    };
    for a in Algorithm::ALL {
        // Algorithms by their command-line names.
        let text = round_trip(&a);
        assert_eq!(text, format!("\"{}\"", a.name()));
        let p = a
            .position(
                &t,
                &site,
                &Options {
                    allow_out_of_range: true,
                    ..opts
                },
            )
            .unwrap();
        round_trip(&p);
    }
    rejected::<Algorithm>(r#""psa""#);
    round_trip(&SunPosition::new(30.0f32, 200.0, false));
    for v in [psa::Variant::Psa2001, psa::Variant::Modified] {
        round_trip(&v);
    }
    for v in [grena2012::Variant::No1, grena2012::Variant::No5] {
        round_trip(&v);
    }
    round_trip(&spa::intermediate(&t, &site, &opts).unwrap());
    round_trip(&spa::rise_transit_set(&t, &site, &opts).unwrap());
    round_trip(&spa::RiseSet::<f64>::AlwaysBelow);

    // Errors of both kinds.
    for e in [
        Error::InvalidDate,
        Error::NotFinite,
        Error::OutOfValidityRange {
            algorithm: Algorithm::Psa2020,
            year: 2060,
        },
    ] {
        round_trip(&e);
    }
    for e in [
        GeometryError::Position(Error::LatitudeOutOfRange),
        GeometryError::InvalidInterval,
        GeometryError::CapacityExceeded {
            needed: 400,
            capacity: 361,
        },
    ] {
        round_trip(&e);
    }

    // Geometry results.
    let sun = Algorithm::Spa
        .position(&t, &site, &Options::default())
        .unwrap();
    round_trip(&Surface::new(30.0f64, 180.0).unwrap());
    round_trip(&optimum::best_within(&sun, &Limits::upward()).unwrap());
    round_trip(&events::simple(11.9683f64, 79).unwrap());
    round_trip(&DayKind::PolarNight);
    round_trip(&events::for_algorithm(Algorithm::Spa, (2026, 3, 20), &site, &opts).unwrap());
    round_trip(&events::spa((2026, 3, 20), &site, &opts).unwrap());
    round_trip(&irradiance::ashrae_coefficients::<f64>(79));
    let flat = Surface::new(0.0f64, 180.0).unwrap();
    round_trip(&irradiance::clear_sky_on_plane(&sun, &flat, 79, 0.2));
    for m in [
        Mount::fixed_latitude_tilt(11.9683f64),
        Mount::HorizontalNorthSouthAxis {
            max_rotation_deg: 60.0,
        },
        Mount::DualAxis,
    ] {
        round_trip(&m);
    }
}

#[test]
fn limits_and_entries_are_validated() {
    let lim = Limits::new(5.0f64, 85.0, 60.0, 300.0).unwrap();
    let text = round_trip(&lim);
    assert_eq!(
        text,
        r#"{"slope_min_deg":5.0,"slope_max_deg":85.0,"azimuth_min_deg":60.0,"azimuth_max_deg":300.0}"#
    );
    round_trip(&Limits::<f32>::unconstrained());
    for text in [
        // Slopes out of order, beyond 180°, an azimuth arc over 360°.
        r#"{"slope_min_deg":50.0,"slope_max_deg":10.0,"azimuth_min_deg":0.0,"azimuth_max_deg":360.0}"#,
        r#"{"slope_min_deg":0.0,"slope_max_deg":190.0,"azimuth_min_deg":0.0,"azimuth_max_deg":360.0}"#,
        r#"{"slope_min_deg":0.0,"slope_max_deg":90.0,"azimuth_min_deg":0.0,"azimuth_max_deg":400.0}"#,
    ] {
        let e = rejected::<Limits<f64>>(text);
        assert!(
            e.starts_with(&GeometryError::InvalidLimits.to_string()),
            "{text}: {e}"
        );
    }

    let entry = Entry::from_surface(&Surface::new(45.12f64, 180.0).unwrap());
    let text = round_trip(&entry);
    assert_eq!(text, r#"{"slope_cdeg":4512,"azimuth_cdeg":18000}"#);
    for text in [
        r#"{"slope_cdeg":0,"azimuth_cdeg":36000}"#,
        r#"{"slope_cdeg":18001,"azimuth_cdeg":0}"#,
        r#"{"slope_cdeg":-18001,"azimuth_cdeg":0}"#,
    ] {
        rejected::<Entry>(text);
    }
    // The extremes from_surface gives are accepted.
    for text in [
        r#"{"slope_cdeg":18000,"azimuth_cdeg":35999}"#,
        r#"{"slope_cdeg":-18000,"azimuth_cdeg":0}"#,
    ] {
        serde_json::from_str::<Entry>(text).unwrap();
    }
}

#[test]
fn day_tables_round_trip_and_reject_impossible_tables() {
    const N: usize = capacity_for_interval(30);
    let site = kano();
    let opts = Options::default();
    let ev = events::for_algorithm(Algorithm::Spa, (2026, 6, 21), &site, &opts).unwrap();
    let table: DayTable<N> = DayTable::compute(&ev, 30, &Limits::upward(), |t| {
        Algorithm::Spa.position(t, &site, &opts)
    })
    .unwrap();
    assert!(table.len() > 20);
    let text = round_trip(&table);
    let back: DayTable<N> = serde_json::from_str(&text).unwrap();
    assert!(back.is_complete());
    assert_eq!(
        back.iter().collect::<Vec<_>>(),
        table.iter().collect::<Vec<_>>()
    );
    round_trip(&DayTable::<N>::empty(UtcTime::MIDNIGHT_2000));

    let first = r#"{"date":{"year":2026,"month":6,"day":21},"ms_of_day":19800000}"#;
    let e = r#"{"slope_cdeg":100,"azimuth_cdeg":9000}"#;
    // An interval that does not divide the day.
    let msg = rejected::<DayTable<N>>(&format!(
        r#"{{"first":{first},"interval_min":7,"needed":1,"entries":[{e}]}}"#
    ));
    assert!(
        msg.starts_with(&GeometryError::InvalidInterval.to_string()),
        "{msg}"
    );
    // More entries needed than the table holds.
    let msg = rejected::<DayTable<N>>(&format!(
        r#"{{"first":{first},"interval_min":30,"needed":{},"entries":[]}}"#,
        N + 1
    ));
    assert!(msg.starts_with("day needs"), "{msg}");
    // More entries than needed, more entries than N, an invalid entry.
    rejected::<DayTable<N>>(&format!(
        r#"{{"first":{first},"interval_min":30,"needed":1,"entries":[{e},{e}]}}"#
    ));
    let many = vec![e; N + 1].join(",");
    rejected::<DayTable<N>>(&format!(
        r#"{{"first":{first},"interval_min":30,"needed":{N},"entries":[{many}]}}"#
    ));
    rejected::<DayTable<N>>(&format!(
        r#"{{"first":{first},"interval_min":30,"needed":1,"entries":[{{"slope_cdeg":0,"azimuth_cdeg":40000}}]}}"#
    ));
    // A partly filled table (needed > len) is a valid state: not complete.
    let partial: DayTable<N> = serde_json::from_str(&format!(
        r#"{{"first":{first},"interval_min":30,"needed":3,"entries":[{e}]}}"#
    ))
    .unwrap();
    assert!(!partial.is_complete());
    assert_eq!(partial.len(), 1);
}
