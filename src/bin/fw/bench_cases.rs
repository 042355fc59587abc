//! The workload of the speed benches, the same on every target: sun
//! positions in `f32` for fixed instants and sites, and a whole day table.
// Shared by several images; each uses a part.
#![allow(dead_code)]

use sun_algos::{Algorithm, Options, Site, UtcTime};

/// Instants and sites of the per-position measurement: Kano (seed
/// jimoh-2019's site), Tromsø and Sydney over 2026; all inside every
/// measured algorithm's validity range.
pub const CASES: [(i32, u8, u8, u8, u8, f32, f32); 6] = [
    (2026, 3, 20, 12, 0, 11.9683, 8.4261),
    (2026, 6, 21, 7, 30, 11.9683, 8.4261),
    (2026, 12, 21, 16, 45, 11.9683, 8.4261),
    (2026, 6, 21, 11, 0, 69.65, 18.96),
    (2026, 9, 23, 2, 15, -33.8688, 151.2093),
    (2026, 1, 15, 23, 50, -33.8688, 151.2093),
];

/// ΔT for 2026 (seconds), fixed so that no ΔT model runs inside the timing.
pub const DELTA_T_S: f32 = 69.2;

/// Minutes between two set-points of a day table (seed jimoh-2019: 4 min).
pub const DAY_TABLE_STEP_MIN: u16 = 4;

/// Number of set-points in a whole 24-hour table at that step.
pub const DAY_TABLE_LEN: u16 = 24 * 60 / DAY_TABLE_STEP_MIN;

/// One prepared input of a measurement.
pub struct Case {
    pub time: UtcTime,
    pub site: Site<f32>,
}

/// The `index`-th case, `None` past the end or for an invalid entry.
pub fn case(index: usize) -> Option<Case> {
    let &(y, mo, d, h, mi, lat, lon) = CASES.get(index)?;
    let time = UtcTime::from_ymd_hms(y, mo, d, h, mi, 0).ok()?;
    let site = Site::new(lat, lon).ok()?;
    Some(Case { time, site })
}

/// Options of every measured computation: fixed ΔT, geometric position.
pub fn options() -> Options<f32> {
    Options {
        delta_t_s: Some(DELTA_T_S),
        ..Options::default()
    }
}

/// Computes one position (inlined, so that a constant `algorithm` selects
/// one algorithm at compile time and the others are not linked); the result goes through `black_box` so that the
/// optimiser cannot drop the work. Returns the zenith, or NaN on an error.
#[inline(always)]
pub fn one_position(algorithm: Algorithm, case: &Case, options: &Options<f32>) -> f32 {
    let p = algorithm.position(
        core::hint::black_box(&case.time),
        core::hint::black_box(&case.site),
        options,
    );
    core::hint::black_box(match p {
        Ok(p) => p.zenith_deg,
        Err(_) => f32::NAN,
    })
}

/// Computes a whole day table (every `DAY_TABLE_STEP_MIN` minutes from 00:00
/// UTC of 2026-06-21 at Kano) with `algorithm`; returns how many set-points
/// had the sun above the horizon (errors count as below).
#[inline(always)]
pub fn day_table(algorithm: Algorithm, options: &Options<f32>) -> u16 {
    let Ok(site) = Site::new(11.9683f32, 8.4261) else {
        return 0;
    };
    let Ok(start) = UtcTime::from_ymd_hms(2026, 6, 21, 0, 0, 0) else {
        return 0;
    };
    let mut above = 0;
    for i in 0..DAY_TABLE_LEN {
        let Ok(t) = start.add_seconds(i64::from(i) * i64::from(DAY_TABLE_STEP_MIN) * 60) else {
            continue;
        };
        if let Ok(p) = algorithm.position(core::hint::black_box(&t), &site, options) {
            if p.zenith_deg < 90.0 {
                above += 1;
            }
        }
    }
    core::hint::black_box(above)
}
