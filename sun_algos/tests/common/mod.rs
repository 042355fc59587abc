//! Shared harness of the accuracy tests: the reference tables of
//! `tests/data/` (geometric topocentric sun positions from skyfield + JPL
//! DE421, and NREL SPA after 2052; see ../shared/reference/make_reference.py)
//! and the error statistics of an algorithm against them.

#![allow(dead_code)]

use std::path::PathBuf;

use sun_algos::{Algorithm, Float, Options, Site, SunPosition, UtcTime};

/// One row of a reference table.
#[derive(Debug, Clone)]
pub struct Row {
    pub utc: String,
    pub time: UtcTime,
    pub latitude_deg: f64,
    pub longitude_deg: f64,
    pub delta_t_s: f64,
    pub zenith_deg: f64,
    pub azimuth_deg: f64,
}

/// Reads `tests/data/<name>` (columns utc,latitude,longitude,delta_t,zenith,azimuth).
pub fn load(name: &str) -> Vec<Row> {
    let path: PathBuf = [env!("CARGO_MANIFEST_DIR"), "tests", "data", name]
        .iter()
        .collect();
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    assert_eq!(
        header,
        [
            "utc",
            "latitude",
            "longitude",
            "delta_t",
            "zenith",
            "azimuth"
        ],
        "{name}"
    );
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let num = |i: usize| -> f64 { f[i].parse().unwrap_or_else(|e| panic!("{l}: {e}")) };
            Row {
                utc: f[0].to_string(),
                time: f[0].parse().unwrap_or_else(|e| panic!("{l}: {e:?}")),
                latitude_deg: num(1),
                longitude_deg: num(2),
                delta_t_s: num(3),
                zenith_deg: num(4),
                azimuth_deg: num(5),
            }
        })
        .collect()
}

/// Error statistics of one algorithm and float type on one table.
#[derive(Debug, Clone, Copy)]
pub struct Stats {
    /// Rows with the reference sun above the horizon.
    pub rows: usize,
    /// Largest angular distance, degrees.
    pub max_deg: f64,
    /// Mean angular distance, degrees.
    pub mean_deg: f64,
}

/// Angular distance (degrees) between our geometric position and the
/// reference for every row with the reference zenith below 90°, rows
/// filtered by `keep`; ΔT is the row's.
pub fn stats<T: Float>(algorithm: Algorithm, rows: &[Row], keep: impl Fn(&Row) -> bool) -> Stats {
    let mut max_deg: f64 = 0.0;
    let mut sum = 0.0;
    let mut n = 0usize;
    let mut worst = String::new();
    for r in rows.iter().filter(|r| r.zenith_deg < 90.0 && keep(r)) {
        let site = Site::new(T::from_f64(r.latitude_deg), T::from_f64(r.longitude_deg))
            .unwrap_or_else(|e| panic!("{}: {e}", r.utc));
        let opts = Options {
            delta_t_s: Some(T::from_f64(r.delta_t_s)),
            ..Options::default()
        };
        let p = algorithm
            .position(&r.time, &site, &opts)
            .unwrap_or_else(|e| panic!("{} {}: {e}", algorithm.name(), r.utc));
        assert!(!p.refracted);
        let ours = SunPosition::new(p.zenith_deg.to_f64(), p.azimuth_deg.to_f64(), false);
        let reference = SunPosition::new(r.zenith_deg, r.azimuth_deg, false);
        let d = ours.angular_distance_deg(&reference);
        assert!(d.is_finite(), "{} {}", algorithm.name(), r.utc);
        if d > max_deg {
            max_deg = d;
            worst = format!("{} lat {} lon {}", r.utc, r.latitude_deg, r.longitude_deg);
        }
        sum += d;
        n += 1;
    }
    assert!(n > 0, "no rows");
    let s = Stats {
        rows: n,
        max_deg,
        mean_deg: sum / n as f64,
    };
    println!(
        "{:<22} {:<4} rows {:>5}  max {:.5}°  mean {:.5}°  (worst {worst})",
        algorithm.name(),
        core::any::type_name::<T>(),
        s.rows,
        s.max_deg,
        s.mean_deg
    );
    s
}
