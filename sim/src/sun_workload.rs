//! The workload of the speed-bench images (`avr_bench` on the ATmega328P
//! and ATmega2560, `qemu_bench` on the Cortex-M4F), the same on every
//! target: sun positions in `f32` for fixed instants and sites, and a whole
//! day table. Each image measures it with its own cycle or instruction
//! counter.

use sun_algos::{Algorithm, Options, Site, UtcTime};

/// Instants and sites of the per-position measurement: Kano (Jimoh &
/// Aliyu's (2019) site), Tromsø and Sydney over 2026; all inside every
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

/// Minutes between two set-points of a day table (Jimoh & Aliyu 2019: 4 min).
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

/// The measured algorithms, chosen at compile time as the firmware
/// chooses its own (`suntracker::sun::BuiltInAlgorithm`): each gets one out-of-line copy,
/// and no other algorithm is linked.
pub use suntracker::sun::{BuiltInAlgorithm as Measured, Michalsky, Psa2020};

/// `grena-2012-3` (Grena 2012, algorithm 3), the third algorithm the
/// speed benches measure.
pub struct Grena2012No3;

impl Measured for Grena2012No3 {
    const ALGORITHM: Algorithm = Algorithm::Grena2012No3;
}

/// One position with `A`'s algorithm; the zenith, or NaN on an error.
#[inline(never)]
pub fn zenith_deg<A: Measured>(time: &UtcTime, site: &Site<f32>, options: &Options<f32>) -> f32 {
    match A::ALGORITHM.position(time, site, options) {
        Ok(p) => p.zenith_deg,
        Err(_) => f32::NAN,
    }
}

/// Computes one position; the inputs and the result go through
/// `black_box` so that the optimiser cannot drop or hoist the work.
pub fn one_position<A: Measured>(case: &Case, options: &Options<f32>) -> f32 {
    core::hint::black_box(zenith_deg::<A>(
        core::hint::black_box(&case.time),
        core::hint::black_box(&case.site),
        options,
    ))
}

/// Which 4-minute slots of the measured day have the sun above the horizon.
pub type DaylightMask = [u8; (DAY_TABLE_LEN as usize).div_ceil(8)];

fn day_site_start() -> Option<(Site<f32>, UtcTime)> {
    // 2026-06-21T00:00Z, evaluated at compile time (the calendar functions
    // are `const`), so that the measured tables hold no date arithmetic.
    const START: Option<UtcTime> = match sun_algos::time::Date::new(2026, 6, 21) {
        Ok(date) => match UtcTime::from_date_ms(date, 0) {
            Ok(t) => Some(t),
            Err(_) => None,
        },
        Err(_) => None,
    };
    Some((Site::new(11.9683f32, 8.4261).ok()?, START?))
}

fn slot_time(start: &UtcTime, i: u16) -> Option<UtcTime> {
    start
        .add_seconds(i64::from(i) * i64::from(DAY_TABLE_STEP_MIN) * 60)
        .ok()
}

/// Computes a table of set-points every `DAY_TABLE_STEP_MIN` minutes over
/// 2026-06-21 (UTC) at Kano with `A`'s algorithm, and returns how many it
/// computed.
///
/// With `daylight_only == false`: all 360 slots of the 24 hours; marks in
/// `mask` the slots with the sun above the horizon. With `true`: only the
/// marked slots, i.e. the table of Jimoh & Aliyu's (2019) step 7 from sunrise to
/// sunset, which the scheduler stores.
#[inline(never)]
pub fn table<A: Measured>(
    options: &Options<f32>,
    mask: &mut DaylightMask,
    daylight_only: bool,
) -> u16 {
    let Some((site, start)) = day_site_start() else {
        return 0;
    };
    let mut n = 0;
    for i in 0..DAY_TABLE_LEN {
        let Some(byte) = mask.get_mut(usize::from(i / 8)) else {
            continue;
        };
        let bit = 1 << (i % 8);
        if daylight_only && *byte & bit == 0 {
            continue;
        }
        let Some(t) = slot_time(&start, i) else {
            continue;
        };
        let zenith_deg = zenith_deg::<A>(core::hint::black_box(&t), &site, options);
        n += 1;
        if !daylight_only && zenith_deg < 90.0 {
            *byte |= bit;
        }
    }
    core::hint::black_box(n)
}
