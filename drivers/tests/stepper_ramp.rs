//! Ramp profile of the planner: accelerate / cruise / decelerate, exact step
//! count, against the kinematics of uniform acceleration computed here in f64.

use drivers::stepper::planner::{Due, Planner};
use drivers::stepper::ramp::{isqrt, isqrt32, Ramp, RampError};
use drivers::stepper::Direction;

const RAMP: Ramp = Ramp {
    start_speed_sps: 200,
    max_speed_sps: 2_000,
    accel_sps2: 4_000,
};

/// Runs a planner with a 1 µs poll clock; returns the step times and positions.
fn run(p: &mut Planner, limit_us: u64) -> Vec<(u64, i32)> {
    let mut steps = Vec::new();
    let mut now = 0u64;
    while now < limit_us {
        match p.due(now) {
            Due::Idle => break,
            Due::Wait => now += 1,
            Due::Step(_) => {
                p.stepped(now);
                steps.push((now, p.position()));
            }
        }
    }
    steps
}

#[test]
fn isqrt_by_hand() {
    assert_eq!(
        [0, 1, 3, 4, 15, 16, 30_000, u64::MAX].map(isqrt),
        [0, 1, 1, 2, 3, 4, 173, 4_294_967_295]
    );
}

#[test]
fn trapezoid_monotone_and_exact() {
    let mut p = Planner::new(RAMP).unwrap();
    p.move_to(2_000);
    let steps = run(&mut p, 10_000_000);
    assert_eq!(steps.len(), 2_000, "total steps exact");
    assert_eq!(p.position(), 2_000);
    assert!(steps.windows(2).all(|w| w[1].1 == w[0].1 + 1));
    let iv: Vec<u64> = steps.windows(2).map(|w| w[1].0 - w[0].0).collect();
    // Cruise interval: 1e6 / 2000 = 500 µs.
    let first_cruise = iv.iter().position(|&i| i == 500).unwrap();
    let last_cruise = iv.iter().rposition(|&i| i == 500).unwrap();
    assert!(
        iv[..first_cruise].windows(2).all(|w| w[1] <= w[0]),
        "accelerating"
    );
    assert!(
        iv[first_cruise..=last_cruise].iter().all(|&i| i == 500),
        "cruise"
    );
    assert!(
        iv[last_cruise..].windows(2).all(|w| w[1] >= w[0]),
        "decelerating"
    );
    // Uniform acceleration from 200 to 2000 steps/s at 4000 steps/s²:
    // distance (v² − v0²) / 2a = (4e6 − 4e4) / 8000 = 495 steps.
    assert!(
        (first_cruise as i64 - 495).abs() <= 1,
        "accel steps {first_cruise}"
    );
    assert!(((iv.len() - 1 - last_cruise) as i64 - 495).abs() <= 1);
    assert_eq!(RAMP.cruise_level(), 495);
    // Time to cruise: (v − v0) / a = 0.45 s; the per-step rounding to whole µs
    // keeps it within 1 %.
    let t_acc = steps[first_cruise].0 as f64 * 1e-6;
    assert!((t_acc - 0.45).abs() < 0.0045, "t_acc {t_acc}");
    // Symmetric: interval k from the start equals interval k from the end.
    assert!(iv.iter().zip(iv.iter().rev()).all(|(a, b)| a == b));
    println!(
        "ramp: first interval {} µs, cruise 500 µs from step {first_cruise}, total {:.4} s",
        iv[0],
        steps.last().unwrap().0 as f64 * 1e-6
    );
}

#[test]
fn short_move_is_a_triangle() {
    let mut p = Planner::new(RAMP).unwrap();
    p.move_to(-100);
    let steps = run(&mut p, 10_000_000);
    assert_eq!(steps.len(), 100);
    assert_eq!(p.position(), -100);
    let iv: Vec<u64> = steps.windows(2).map(|w| w[1].0 - w[0].0).collect();
    let min = *iv.iter().min().unwrap();
    // Peak level 50: v = sqrt(200² + 2·4000·50) = sqrt(440000) = 663 steps/s -> 1508 µs.
    assert_eq!(min, 1_508);
    let k = iv.iter().position(|&i| i == min).unwrap();
    assert!(iv[..=k].windows(2).all(|w| w[1] <= w[0]));
    assert!(iv[k..].windows(2).all(|w| w[1] >= w[0]));
}

#[test]
fn stop_decelerates_along_the_ramp() {
    let mut p = Planner::new(RAMP).unwrap();
    p.move_to(10_000);
    let mut now = 0;
    let mut n = 0;
    while n < 1_000 {
        if let Due::Step(Direction::Forward) = p.due(now) {
            p.stepped(now);
            n += 1;
        }
        now += 1;
    }
    p.stop();
    // At cruise the stopping distance is the cruise level, 495 steps.
    assert_eq!(p.target(), 1_000 + 495);
    let steps = run(&mut p, 100_000_000);
    assert_eq!(steps.len(), 495);
    let iv: Vec<u64> = steps.windows(2).map(|w| w[1].0 - w[0].0).collect();
    assert!(iv.windows(2).all(|w| w[1] >= w[0]), "only decelerating");
}

#[test]
fn reversal_stops_first_then_returns() {
    let mut p = Planner::new(RAMP).unwrap();
    p.move_to(1_000);
    let mut now = 0;
    let mut n = 0;
    while n < 300 {
        if let Due::Step(_) = p.due(now) {
            p.stepped(now);
            n += 1;
        }
        now += 1;
    }
    p.move_to(0);
    assert_eq!(p.target(), 0);
    let mut positions = vec![p.position()];
    while now < 100_000_000 {
        match p.due(now) {
            Due::Idle => break,
            Due::Wait => now += 1,
            Due::Step(_) => {
                p.stepped(now);
                positions.push(p.position());
            }
        }
    }
    assert_eq!(p.position(), 0);
    let peak = positions
        .iter()
        .position(|&x| x == *positions.iter().max().unwrap())
        .unwrap();
    assert!(peak > 0, "kept going forward while decelerating");
    assert!(positions[..=peak].windows(2).all(|w| w[1] == w[0] + 1));
    assert!(positions[peak..].windows(2).all(|w| w[1] == w[0] - 1));
}

#[test]
fn bad_ramps() {
    let z = Ramp {
        accel_sps2: 0,
        ..RAMP
    };
    assert_eq!(Planner::new(z).err(), Some(RampError::Zero));
    let f = Ramp {
        max_speed_sps: 65_536,
        ..RAMP
    };
    assert_eq!(Planner::new(f).err(), Some(RampError::TooFast));
    let fastest = Ramp {
        max_speed_sps: 65_535,
        ..RAMP
    };
    assert!(Planner::new(fastest).is_ok());
}

/// The 32-bit root and the 32-bit fast path of `speed_sps` agree with the
/// 64-bit definition: every root up to 2²⁰ and around every perfect square
/// to 65,535², and the speeds of ramps whose v² fits in 32 bits or not.
#[test]
fn the_32_bit_path_equals_the_64_bit_definition() {
    for n in 0u32..(1 << 20) {
        assert_eq!(u64::from(isqrt32(n)), isqrt(u64::from(n)), "{n}");
    }
    for r in (1u32..=65_535).step_by(7) {
        for n in [r * r - 1, r * r, r * r + 1] {
            assert_eq!(u64::from(isqrt32(n)), isqrt(u64::from(n)), "{n}");
        }
    }
    assert_eq!(isqrt32(u32::MAX), 65_535);
    let ramps = [
        Ramp {
            start_speed_sps: 20,
            max_speed_sps: 56,
            accel_sps2: 100,
        },
        Ramp {
            start_speed_sps: 100,
            max_speed_sps: 1_000,
            accel_sps2: 10_000,
        },
        Ramp {
            start_speed_sps: 1_000,
            max_speed_sps: 60_000,
            accel_sps2: 50_000,
        },
        // The fastest ramp `validate` accepts: v² overflows 32 bits from
        // level 2,147 on.
        Ramp {
            start_speed_sps: 1,
            max_speed_sps: 65_535,
            accel_sps2: 1_000_000,
        },
        // v0² alone is 65,535², the most that fits.
        Ramp {
            start_speed_sps: 65_535,
            max_speed_sps: 65_535,
            accel_sps2: u32::MAX,
        },
    ];
    for r in ramps {
        for level in (0u32..5_000).chain([u32::MAX / 4, u32::MAX]) {
            let v0 = u128::from(r.start_speed_sps);
            let v2 = v0 * v0 + 2 * u128::from(r.accel_sps2) * u128::from(level);
            // Beyond u64 the root is far above any maximum speed.
            let v2 = u64::try_from(v2).unwrap_or(u64::MAX);
            let want = isqrt(v2).min(u64::from(r.max_speed_sps)).max(1);
            assert_eq!(u64::from(r.speed_sps(level)), want, "{r:?} level {level}");
        }
    }
}
