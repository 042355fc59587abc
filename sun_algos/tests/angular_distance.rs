//! `SunPosition::angular_distance_deg`, the metric of every accuracy test,
//! against hand-computed pairs.
//!
//! Expected values: exact by construction where the geometry gives them
//! (same azimuth, zenith, horizon, antipodes), otherwise the haversine
//! formula `d = 2 asin √(sin²(Δh/2) + cos h1 cos h2 sin²(ΔA/2))` (h = 90° −
//! zenith) evaluated with mpmath 1.3.0 at 40 significant digits, e.g.
//! `degrees(2*asin(sqrt(sin((p2-p1)/2)**2 + cos(p1)*cos(p2)*sin(dl/2)**2)))`,
//! cross-checked by the spherical law of cosines where it is well
//! conditioned (first pair: cos d = cos 30° cos 60° = √3/4).

use sun_algos::SunPosition;

fn d(z1: f64, a1: f64, z2: f64, a2: f64) -> f64 {
    let p = SunPosition::new(z1, a1, false);
    let q = SunPosition::new(z2, a2, false);
    let pq = p.angular_distance_deg(&q);
    // The metric is symmetric, bit for bit up to rounding.
    let qp = q.angular_distance_deg(&p);
    assert!((pq - qp).abs() <= 1e-13 * pq.max(1.0), "{pq} {qp}");
    pq
}

#[test]
fn general_pairs() {
    // cos d = cos 30° cos 60° + sin 30° sin 60° cos 90° = √3/4.
    let got = d(30.0, 0.0, 60.0, 90.0);
    assert!((got - 64.341_093_726_744_72).abs() < 1e-12, "{got}");
    // No symmetry to lean on.
    let got = d(12.5, 33.3, 71.2, 250.7);
    assert!((got - 81.265_431_025_629_44).abs() < 1e-12, "{got}");
    // Same azimuth: the zenith difference.
    let got = d(10.0, 45.0, 70.5, 45.0);
    assert!((got - 60.5).abs() < 1e-12, "{got}");
}

#[test]
fn across_the_azimuth_wrap() {
    // 359.5° and 0.5° are 1° apart in azimuth, not 359°.
    let got = d(60.0, 359.5, 40.0, 0.5);
    assert!((got - 20.014_198_255_196_37).abs() < 1e-12, "{got}");
    // On the horizon the distance is the azimuth difference: 2°.
    let got = d(90.0, 359.0, 90.0, 1.0);
    assert!((got - 2.0).abs() < 1e-12, "{got}");
    // Near the horizon: 2 asin(sin 89.9° sin 0.01°), mpmath.
    let got = d(89.9, 359.99, 89.9, 0.01);
    assert!((got - 0.019_999_969_538_265_44).abs() < 1e-13, "{got}");
    // 360° is 0°.
    assert!(d(50.0, 360.0, 50.0, 0.0) < 1e-12);
}

#[test]
fn at_the_zenith_azimuth_does_not_matter() {
    assert!(d(0.0, 0.0, 0.0, 237.0) < 1e-12);
    // From the zenith the distance is the other point's zenith angle.
    let got = d(0.0, 123.0, 37.25, 300.0);
    assert!((got - 37.25).abs() < 1e-12, "{got}");
    // Two points 0.001° from the zenith on opposite sides: 0.002°.
    let got = d(0.001, 0.0, 0.001, 180.0);
    assert!((got - 0.002).abs() < 1e-15, "{got}");
}

#[test]
fn antipodal_points() {
    assert!((d(90.0, 10.0, 90.0, 190.0) - 180.0).abs() < 1e-12);
    assert!((d(30.0, 10.0, 150.0, 190.0) - 180.0).abs() < 1e-12);
    // Zenith and nadir, whatever the azimuths.
    assert!((d(0.0, 17.0, 180.0, 291.0) - 180.0).abs() < 1e-12);
    // 1e-4° short of antipodal, where acos(dot) is ill-conditioned too.
    let got = d(90.0, 0.0, 90.0, 179.9999);
    assert!((got - 179.9999).abs() < 1e-9, "{got}");
}

#[test]
fn tiny_angles_keep_their_precision() {
    // acos of the dot product cannot resolve these: at 1.2e-8 rad,
    // 1 − cos d ≈ 7.6e-17 is below half an ulp of 1, so acos would return
    // 0 or ~8.5e-7°. The atan2 form keeps ~8 significant digits here (the
    // inputs themselves carry ~1e-8 relative rounding).
    // 2 asin(sin 45° sin(0.5e-6°)) = 7.0710678118654752e-7° (mpmath).
    let got = d(45.0, 100.0, 45.0, 100.000_001);
    assert!(
        (got / 7.071_067_811_865_475e-7 - 1.0).abs() < 1e-6,
        "{got:e}"
    );
    // Same azimuth, zenith 1e-7° apart.
    let got = d(20.0, 45.0, 20.000_000_1, 45.0);
    assert!((got / 1e-7 - 1.0).abs() < 1e-6, "{got:e}");
    // Identical positions: exactly nothing.
    assert_eq!(d(33.3, 222.2, 33.3, 222.2), 0.0);
}

#[test]
fn f32_general_pair() {
    let p = SunPosition::new(30.0f32, 0.0, false);
    let q = SunPosition::new(60.0f32, 90.0, false);
    let got = p.angular_distance_deg(&q);
    assert!((got - 64.341_095).abs() < 1e-4, "{got}");
    // Near the wrap in f32: 2° on the horizon.
    let got = SunPosition::new(90.0f32, 359.0, false)
        .angular_distance_deg(&SunPosition::new(90.0f32, 1.0, false));
    assert!((got - 2.0).abs() < 1e-4, "{got}");
}
