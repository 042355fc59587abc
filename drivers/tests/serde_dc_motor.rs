//! The `serde` feature for the DC-motor, Hall and actuator types: JSON
//! round trips (serde_json), as tests/serde.rs does for the older modules.
#![cfg(feature = "serde")]

use core::fmt::Debug;

use drivers::dc_motor::bts7960::SenseConfig;
use drivers::dc_motor::{Config, Output, RestMode};
use drivers::hall::{HallConfig, HallError, Watch};
use drivers::linear::{ActuatorGeometry, LinearError, PotCalibration, PulseScale};
use serde::de::DeserializeOwned;
use serde::Serialize;

fn round_trip<T: Serialize + DeserializeOwned + PartialEq + Debug>(value: &T) -> String {
    let json = serde_json::to_string(value).unwrap();
    let back: T = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{json}: {e}"));
    assert_eq!(&back, value, "{json}");
    json
}

#[test]
fn dc_motor_types() {
    let config = Config {
        ramp_permille_per_ms: 2,
        rest: RestMode::Brake,
    };
    assert_eq!(
        round_trip(&config),
        r#"{"ramp_permille_per_ms":2,"rest":"Brake"}"#
    );
    for o in [
        Output::Forward(1),
        Output::Backward(1_000),
        Output::Brake,
        Output::Coast,
    ] {
        round_trip(&o);
    }
    round_trip(&SenseConfig::DATASHEET_1K_5V);
}

#[test]
fn hall_types() {
    let config = HallConfig {
        stall_ms: 250,
        drive_threshold_permille: 100,
        max_idle_pulses: 2,
    };
    round_trip(&config);
    round_trip(&HallError::InvalidConfig);
    for w in [Watch::Normal, Watch::Stall, Watch::UnexpectedMotion] {
        round_trip(&w);
    }
}

#[test]
fn linear_types() {
    round_trip(&ActuatorGeometry {
        a_mm: 300.0,
        b_mm: 150.0,
        offset_deg: 75.0,
        retracted_mm: 245.0,
        stroke_mm: 100.0,
    });
    assert_eq!(round_trip(&PulseScale::new(2.5).unwrap()), "2.5");
    assert_eq!(
        round_trip(&PotCalibration::new(102, 921, 100.0).unwrap()),
        r#"{"retracted_counts":102,"extended_counts":921,"stroke_mm":100.0}"#
    );
    round_trip(&LinearError::OutsideStroke);
    // The checks of `new` apply on the way in: an error, not an unusable value.
    let zero = serde_json::from_str::<PulseScale>("0.0").unwrap_err();
    assert!(zero.to_string().contains("unusable"), "{zero}");
    let flat = r#"{"retracted_counts":5,"extended_counts":5,"stroke_mm":100.0}"#;
    assert!(serde_json::from_str::<PotCalibration>(flat).is_err());
}
