//! Nanoseconds per sun position: every algorithm of the crate in `f32` and
//! `f64`, side by side with the `solar-positioning` crate's SPA and Grena3.
//!
//! Group `head_to_head_f64` measures the three comparisons back to
//! back; groups `sun_algos_f64` and `sun_algos_f32` list every algorithm.
//! Each measured iteration computes the positions of the same fixed set of
//! 64 instants (2020–2022, inside every algorithm's validity range) and
//! sites (pseudo-random latitudes and longitudes, sea level), geometric (no
//! refraction), ΔT given. Divide the reported time by 64 for ns per
//! position (criterion also prints the throughput in positions per second).
//!
//! Run: `cargo bench -p sun_algos --bench positions -- --warm-up-time 1 --measurement-time 2`
//!
//! Instruction counts: with `SPA_CALLGRIND_ROUNDS=n` in the environment the
//! binary skips criterion and computes `n` rounds of the 64 cases with our
//! `spa` in `f64` (or `f32` with `SPA_CALLGRIND_F32=1`), for
//! `valgrind --tool=callgrind`: instructions per position are
//! (Ir(n) − Ir(0)) / (64 n). The binary is the one
//! `cargo bench -p sun_algos --bench positions --no-run` names.

use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};
use solar_positioning::{time::JulianDate, Location, SolarPositions};
use std::hint::black_box;
use sun_algos::{Algorithm, Float, Options, Site, UtcTime};

const N: usize = 64;
const DELTA_T_S: f64 = 69.2;

/// One instant and site in the native types of both crates.
struct Case {
    time: UtcTime,
    lat: f64,
    lon: f64,
    jd: JulianDate,
}

/// The fixed cases: a small linear congruential generator (Knuth's MMIX
/// constants) so every run measures the same inputs.
fn cases() -> Vec<Case> {
    let mut state: u64 = 0x5eed_2024;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let start = UtcTime::from_ymd_hms(2020, 1, 1, 0, 0, 0).unwrap();
    (0..N)
        .map(|_| {
            let secs = (next() * 3.0 * 365.0 * 86_400.0) as i64;
            let time = start.add_seconds(secs).unwrap();
            let (y, mo, d) = time.ymd();
            let (h, mi, s, _) = time.hms_milli();
            let jd = JulianDate::from_utc(
                y,
                u32::from(mo),
                u32::from(d),
                u32::from(h),
                u32::from(mi),
                f64::from(s),
                DELTA_T_S,
            )
            .unwrap();
            Case {
                time,
                lat: next() * 160.0 - 80.0,
                lon: next() * 360.0 - 180.0,
                jd,
            }
        })
        .collect()
}

fn ours<T: Float>(c: &mut Criterion, cases: &[Case], float: &str) {
    let sites: Vec<Site<T>> = cases
        .iter()
        .map(|k| Site::new(T::from_f64(k.lat), T::from_f64(k.lon)).unwrap())
        .collect();
    let opts = Options {
        delta_t_s: Some(T::from_f64(DELTA_T_S)),
        ..Options::default()
    };
    let mut group = c.benchmark_group(format!("sun_algos_{float}"));
    group.throughput(Throughput::Elements(N as u64));
    for alg in Algorithm::ALL {
        group.bench_function(BenchmarkId::from_parameter(alg.name()), |b| {
            b.iter(|| {
                for (k, site) in cases.iter().zip(&sites) {
                    let p = alg.position(black_box(&k.time), black_box(site), &opts);
                    black_box(p.ok());
                }
            })
        });
    }
    group.finish();
}

/// One round of the cases through the `solar-positioning` crate.
fn run_theirs(model: &SolarPositions, cases: &[Case]) {
    for k in cases {
        let loc = Location {
            latitude: k.lat,
            longitude: k.lon,
        };
        let p = model.at_from_julian(black_box(k.jd), black_box(loc), 0.0, None);
        black_box(p.ok());
    }
}

/// One round of the cases through one of our algorithms.
fn run_ours(alg: Algorithm, cases: &[Case], sites: &[Site<f64>], opts: &Options<f64>) {
    for (k, site) in cases.iter().zip(sites) {
        let p = alg.position(black_box(&k.time), black_box(site), opts);
        black_box(p.ok());
    }
}

/// The comparisons measured back to back (each pair within
/// seconds of each other, so a busy machine affects both alike): our `spa`
/// against their SPA, our `grena-2012-3` and `psa-2020` against their Grena3.
fn head_to_head(c: &mut Criterion, cases: &[Case]) {
    let sites: Vec<Site<f64>> = cases
        .iter()
        .map(|k| Site::new(k.lat, k.lon).unwrap())
        .collect();
    let opts = Options {
        delta_t_s: Some(DELTA_T_S),
        ..Options::default()
    };
    let spa = SolarPositions::new();
    let grena3 = SolarPositions::grena3();
    let mut group = c.benchmark_group("head_to_head_f64");
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("solar-positioning spa", |b| {
        b.iter(|| run_theirs(&spa, cases))
    });
    group.bench_function("sun_algos spa", |b| {
        b.iter(|| run_ours(Algorithm::Spa, cases, &sites, &opts))
    });
    group.bench_function("solar-positioning grena3", |b| {
        b.iter(|| run_theirs(&grena3, cases))
    });
    group.bench_function("sun_algos grena-2012-3", |b| {
        b.iter(|| run_ours(Algorithm::Grena2012No3, cases, &sites, &opts))
    });
    group.bench_function("sun_algos psa-2020", |b| {
        b.iter(|| run_ours(Algorithm::Psa2020, cases, &sites, &opts))
    });
    group.finish();
}

fn benches(c: &mut Criterion) {
    let cases = cases();
    head_to_head(c, &cases);
    ours::<f64>(c, &cases, "f64");
    ours::<f32>(c, &cases, "f32");
}

/// `rounds` rounds of the cases through our `spa` (see the module docs).
fn callgrind_rounds<T: Float>(cases: &[Case], rounds: usize) {
    let sites: Vec<Site<T>> = cases
        .iter()
        .map(|k| Site::new(T::from_f64(k.lat), T::from_f64(k.lon)).unwrap())
        .collect();
    let opts = Options {
        delta_t_s: Some(T::from_f64(DELTA_T_S)),
        ..Options::default()
    };
    for _ in 0..rounds {
        for (k, site) in cases.iter().zip(&sites) {
            let p = Algorithm::Spa.position(black_box(&k.time), black_box(site), &opts);
            black_box(p.ok());
        }
    }
}

criterion_group!(positions, benches);

fn main() {
    if let Some(rounds) = std::env::var("SPA_CALLGRIND_ROUNDS")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        let cases = cases();
        if std::env::var_os("SPA_CALLGRIND_F32").is_some() {
            callgrind_rounds::<f32>(&cases, rounds);
        } else {
            callgrind_rounds::<f64>(&cases, rounds);
        }
        return;
    }
    positions();
    Criterion::default().configure_from_args().final_summary();
}
