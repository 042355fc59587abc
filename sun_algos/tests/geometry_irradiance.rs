//! Irradiance and daily energy: the integration against a closed form, and
//! the dual-axis gain at the Doha site of Chowdhury et al. (2019).

use sun_algos::geometry::events::solar_day_start;
use sun_algos::geometry::incidence::Surface;
use sun_algos::geometry::irradiance::{
    clear_sky_day_energy_wh_m2, clear_sky_on_plane, extraterrestrial_normal_w_m2, trapezoid_wh_m2,
    Mount,
};
use sun_algos::geometry::simple::{declination_deg, position};
use sun_algos::{Algorithm, Options, Site};

#[test]
fn trapezoid_matches_daily_extraterrestrial_closed_form() {
    // Duffie & Beckman eq 1.10.3: H0 = (24/π) G_on (cos φ cos δ sin ω_s +
    // (π ω_s/180) sin φ sin δ) Wh/m² on a horizontal plane. Integrating
    // G_on cos θz of the same sun (Jimoh & Aliyu's model: δ fixed over the
    // UT day) by the trapezoid rule at 1 min must agree within 0.05 %.
    let (lat, lon) = (25.37463f64, 0.0f64);
    let start = sun_algos::UtcTime::from_ymd_hms(2016, 3, 21, 0, 0, 0).unwrap();
    let n = start.day_of_year();
    let gon: f64 = extraterrestrial_normal_w_m2(n);
    let samples = (0..=1440).map(|m| {
        let t = start.add_seconds(m * 60).unwrap();
        let p = position(&t, lat, lon);
        let c = p.zenith_deg.to_radians().cos().max(0.0);
        ((m * 60) as f64, gon * c)
    });
    let e = trapezoid_wh_m2(samples);
    let d: f64 = declination_deg(n);
    let (sp, cp) = lat.to_radians().sin_cos();
    let (sd, cd) = d.to_radians().sin_cos();
    let ws = (-(sp / cp) * (sd / cd)).acos();
    let h0 = 24.0 / std::f64::consts::PI * gon * (cp * cd * ws.sin() + ws * sp * sd);
    assert!((e - h0).abs() / h0 < 5e-4, "{e} vs {h0}");
}

#[test]
fn dual_axis_beam_is_never_beaten() {
    // With the surface normal on the sun the beam term is I_B, the largest
    // any orientation can get (cos θ ≤ 1).
    let site = Site::new(25.37463f64, 51.49128).unwrap();
    let start = solar_day_start(2016, 7, 10, 51.49128).unwrap();
    let opts = Options::default();
    for m in 0..288 {
        let t = start.add_seconds(m * 300).unwrap();
        let p = Algorithm::Spa.position(&t, &site, &opts).unwrap();
        let dual = clear_sky_on_plane(&p, &Surface::facing(&p), t.day_of_year(), 0.2);
        for mount in [
            Mount::fixed_latitude_tilt(25.37463),
            Mount::HorizontalNorthSouthAxis {
                max_rotation_deg: 90.0,
            },
        ] {
            let other = clear_sky_on_plane(&p, &mount.surface(&p), t.day_of_year(), 0.2);
            assert!(dual.beam_w_m2 >= other.beam_w_m2 - 1e-9);
        }
    }
}

/// Daily clear-sky energy on the three mounts, Wh/m², recomputed without
/// this crate by the script `sun_algos/tests/data/make_irradiance_gain_fixture.py`
/// (run from the repository root, its output redirected to
/// `sun_algos/tests/data/doha_clear_sky_energy_pvlib.csv`): pvlib 0.16.1 SPA
/// positions, Masters' ASHRAE clear-day fits written out in numpy, pvlib's
/// Kasten–Young air mass, single-axis tracker angles (`tracking.singleaxis`)
/// and isotropic plane-of-array total (`irradiance.get_total_irradiance`),
/// the same 300 s trapezoid grid (the script's docstring names each source).
const PVLIB: &str = include_str!("data/doha_clear_sky_energy_pvlib.csv");

#[test]
fn doha_gain_on_the_papers_simulation_days() {
    // Chowdhury et al. (2019) measured +13.9 % (open-circuit voltage-hours, a
    // cloudy-intermittent day, panel fixed at 81° to the zenith) for its
    // dual-axis tracker over the fixed panel in Doha. Our model is a
    // different quantity: the gain is the ratio of clear-sky plane-of-array
    // energies over the 24 h from local mean midnight (ASHRAE clear day,
    // isotropic sky, albedo 0.2), dual axis over a latitude-tilt fixed panel
    // and over a horizontal north–south single axis, on the paper's three
    // simulation days of 2016. Each energy must match the independent pvlib
    // computation to 1e-6 relative and each gain to 0.0001 percentage point;
    // the old 10–80 % (fixed) and 0–40 % (single) bands let through e.g. a
    // diffuse or albedo term dropped, or the wrong day of year in A, k, C.
    // (Both sides sample the same instants; SPA against pvlib's SPA differs
    // by < 0.0003° in direction; they agree to 2e-7 here. The fixture is
    // printed to 0.0001 Wh/m², about 1e-8.)
    let (lat, lon) = (25.37463f64, 51.49128f64);
    let site = Site::new(lat, lon).unwrap();
    let mounts = [
        Mount::fixed_latitude_tilt(lat),
        Mount::HorizontalNorthSouthAxis {
            max_rotation_deg: 90.0,
        },
        Mount::DualAxis,
    ];
    let mut n = 0;
    for line in PVLIB.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let want: Vec<f64> = f[1..].iter().map(|v| v.parse().unwrap()).collect();
        let (m, d) = (f[0][5..7].parse().unwrap(), f[0][8..10].parse().unwrap());
        let start = solar_day_start(2016, m, d, lon).unwrap();
        let got = clear_sky_day_energy_wh_m2(&start, 300, &mounts, 0.2, |t| {
            Algorithm::Spa.position(t, &site, &Options::default())
        })
        .unwrap();
        for (g, w) in got.iter().zip(&want) {
            assert!((g / w - 1.0).abs() < 1e-6, "{line}: {got:?}");
        }
        let [fixed, single, dual] = got;
        for (g, w) in [
            (dual / fixed - 1.0, want[2] / want[0] - 1.0),
            (dual / single - 1.0, want[2] / want[1] - 1.0),
        ] {
            assert!((g - w).abs() < 1e-6, "{line}: gain {g} vs {w}");
        }
        println!(
            "{}: gain over fixed {:.4} %, over single axis {:.4} %",
            f[0],
            100.0 * (dual / fixed - 1.0),
            100.0 * (dual / single - 1.0)
        );
        n += 1;
    }
    assert_eq!(n, 3);
}
