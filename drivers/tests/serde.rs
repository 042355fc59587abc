//! The `serde` feature: round trips through a real format (JSON, by
//! serde_json) for the public plain-data types, the serialized form of
//! `DateTime`, and its validation when deserialized.
#![cfg(feature = "serde")]

use core::fmt::Debug;

use drivers::compass::calibration::{Calibration, CalibrationError};
use drivers::compass::heading::HeadingError;
use drivers::compass::wmm::{MagneticElements, WmmCoefficient, WmmError, WmmModel};
use drivers::compass::{hmc5883l, qmc5883l, DeclinationSource, Vector3};
use drivers::encoder::{QuadratureDecoder, Transition};
use drivers::gps::{
    parse_sentence, AssemblerStats, FixFusion, FixQuality, GpsDecoder, GpsFix, GpsStats,
    ParseError, Reject, Sentence,
};
use drivers::servo::{PositionController, ServoConfig};
use drivers::stepper::ramp::{Ramp, RampError};
use drivers::stepper::{hbridge, step_dir, Direction, Event, Limit};
use drivers::tilt::adxl345::Acceleration;
use drivers::tilt::modbus::{Exception, Timeout};
use drivers::tilt::{Inclination, MountTilt, MountTiltError};
use drivers::time::{DateTime, DateTimeError};
use serde::de::DeserializeOwned;
use serde::Serialize;

/// Serializes to JSON and back; the value must come back equal.
fn round_trip<T: Serialize + DeserializeOwned + PartialEq + Debug>(value: &T) -> String {
    let json = serde_json::to_string(value).unwrap();
    let back: T = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{json}: {e}"));
    assert_eq!(&back, value, "{json}");
    json
}

fn dt(y: u16, mo: u8, d: u8, h: u8, mi: u8, s: u8, ms: u16) -> DateTime {
    DateTime::new(y, mo, d, h, mi, s)
        .unwrap()
        .with_millis(ms)
        .unwrap()
}

#[test]
fn datetime_is_its_seven_fields() {
    let t = dt(2024, 2, 29, 12, 34, 56, 789);
    assert_eq!(
        round_trip(&t),
        r#"{"year":2024,"month":2,"day":29,"hour":12,"minute":34,"second":56,"millis":789}"#
    );
    for t in [
        dt(1, 1, 1, 0, 0, 0, 0),
        dt(9999, 12, 31, 23, 59, 59, 999),
        dt(2000, 2, 29, 0, 0, 0, 1),
        dt(1999, 12, 31, 23, 59, 59, 0),
    ] {
        round_trip(&t);
    }
    // Every day of 2023..=2024 at a changing time.
    let mut s = DateTime::new(2023, 1, 1, 0, 0, 0).unwrap().unix_seconds();
    let end = DateTime::new(2025, 1, 1, 0, 0, 0).unwrap().unix_seconds();
    while s < end {
        round_trip(&DateTime::from_unix_seconds(s).unwrap());
        s += 86_400 + 3_607;
    }
}

#[test]
fn invalid_datetimes_are_deserialization_errors() {
    let cases = [
        // 2023 is not a leap year.
        (
            r#"{"year":2023,"month":2,"day":29,"hour":0,"minute":0,"second":0,"millis":0}"#,
            "day is 0 or past the end of the month",
        ),
        (
            r#"{"year":0,"month":1,"day":1,"hour":0,"minute":0,"second":0,"millis":0}"#,
            "year outside 1..=9999",
        ),
        (
            r#"{"year":2024,"month":13,"day":1,"hour":0,"minute":0,"second":0,"millis":0}"#,
            "month outside 1..=12",
        ),
        (
            r#"{"year":2024,"month":1,"day":1,"hour":24,"minute":0,"second":0,"millis":0}"#,
            "hour outside 0..=23",
        ),
        (
            r#"{"year":2024,"month":1,"day":1,"hour":0,"minute":60,"second":0,"millis":0}"#,
            "minute outside 0..=59",
        ),
        // A leap second.
        (
            r#"{"year":2016,"month":12,"day":31,"hour":23,"minute":59,"second":60,"millis":0}"#,
            "second outside 0..=59",
        ),
        (
            r#"{"year":2024,"month":1,"day":1,"hour":0,"minute":0,"second":0,"millis":1000}"#,
            "milliseconds outside 0..=999",
        ),
    ];
    for (json, message) in cases {
        let err = serde_json::from_str::<DateTime>(json).unwrap_err();
        assert!(err.to_string().contains(message), "{json}: {err}");
    }
    // Out of the fields' types, or missing.
    assert!(serde_json::from_str::<DateTime>(
        r#"{"year":70000,"month":1,"day":1,"hour":0,"minute":0,"second":0,"millis":0}"#
    )
    .is_err());
    assert!(serde_json::from_str::<DateTime>(r#"{"year":2024,"month":1,"day":1}"#).is_err());
    // Inside a fix, too.
    let fix = r#"{"utc":{"year":2024,"month":4,"day":31,"hour":0,"minute":0,"second":0,"millis":0},"utc_received_ms":5,"latitude_deg":null,"longitude_deg":null,"altitude_m":null,"quality":"Invalid","satellites":null}"#;
    assert!(serde_json::from_str::<GpsFix>(fix).is_err());
}

#[test]
fn gps_types_round_trip() {
    // u-blox NEO-6 protocol specification's GGA example and an RMC of the
    // same epoch (checksum computed with Python).
    let gga =
        parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B")
            .unwrap();
    let rmc =
        parse_sentence("$GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54")
            .unwrap();
    round_trip(&gga);
    round_trip(&rmc);
    round_trip(&Sentence::Other);
    let mut fusion = FixFusion::new(2_000);
    fusion.update(&gga, 10);
    let fix = fusion.update(&rmc, 20).unwrap();
    assert!(fix.has_position() && fix.utc.is_some());
    round_trip(&fix);
    round_trip(&GpsFix::NONE);
    for q in [FixQuality::Invalid, FixQuality::Rtk, FixQuality::Simulation] {
        round_trip(&q);
    }
    let mut decoder = GpsDecoder::new(2_000);
    for &b in b"$GPGSV,1,1,00*79\r\n$GPGSV,1,1,00*7A\r\nx\n" {
        decoder.push(b, 0);
    }
    let stats: GpsStats = decoder.stats();
    assert_eq!(stats.rejected_checksum, 1);
    round_trip(&stats);
    round_trip(&AssemblerStats {
        overflow: 3,
        ..AssemblerStats::default()
    });
    round_trip(&Reject::BadChecksum);
    round_trip(&ParseError);
}

#[test]
fn readings_round_trip() {
    round_trip(&Vector3::new(0.25, -0.125, 1e-7));
    round_trip(&qmc5883l::RawField {
        x: i16::MIN,
        y: 0,
        z: i16::MAX,
    });
    round_trip(&qmc5883l::Status {
        data_ready: true,
        overflow: false,
        data_skipped: true,
    });
    round_trip(&hmc5883l::RawField {
        x: -4096,
        y: 1,
        z: 2,
    });
    round_trip(&hmc5883l::Status {
        ready: true,
        locked: false,
    });
    round_trip(&Acceleration {
        x_g: 0.0039,
        y_g: -1.0,
        z_g: 0.5,
    });
    round_trip(&Inclination {
        roll_deg: 12.5,
        pitch_deg: -3.25,
    });
    round_trip(&MountTilt {
        alpha0_deg: 35.26,
        beta0_deg: 30.0,
    });
    let elements: MagneticElements = WmmModel::wmm2025()
        .field(47.0_f64, 8.0, 0.5, 2026.5)
        .unwrap();
    round_trip(&elements);
    round_trip(&WmmCoefficient {
        n: 1,
        m: 0,
        g_tenth_nt: -293_518,
        h_tenth_nt: 0,
        g_dot_tenth_nt_per_yr: 120,
        h_dot_tenth_nt_per_yr: 0,
    });
    let mut decoder = QuadratureDecoder::new(false, false);
    decoder.update(true, false);
    round_trip(&decoder);
    round_trip(&Transition::Illegal);
}

#[test]
fn configurations_and_calibration_round_trip() {
    round_trip(&qmc5883l::Config::default());
    round_trip(&qmc5883l::Config {
        rate: qmc5883l::DataRate::Hz200,
        range: qmc5883l::Range::Gauss2,
        oversampling: qmc5883l::OverSampling::X64,
    });
    round_trip(&hmc5883l::Config {
        averaging: hmc5883l::Averaging::X2,
        rate: hmc5883l::DataRate::Hz0_75,
        gain: hmc5883l::Gain::Ga8_1,
    });
    let ramp = Ramp {
        start_speed_sps: 100,
        max_speed_sps: 1_000,
        accel_sps2: 10_000,
    };
    round_trip(&ramp);
    round_trip(&hbridge::Config {
        mode: hbridge::StepMode::Half,
        ramp,
        settle_us: 20_000,
        release_when_idle: true,
    });
    round_trip(&step_dir::Config {
        ramp,
        timing: step_dir::PulseTiming::DRV8825,
        invert_dir: true,
        enable_active_low: true,
        settle_us: 0,
    });
    round_trip(&ServoConfig::STANDARD_50HZ);
    round_trip(&PositionController {
        kp_per_count: 0.01,
        deadband_counts: 2,
        max_speed: 0.8,
        min_speed: 0.1,
    });
    round_trip(&Timeout::default());
    round_trip(&DeclinationSource::Wmm2025);
    round_trip(&DeclinationSource::Fixed {
        declination_deg: -2.75,
    });
    round_trip(&Calibration::IDENTITY);
    let cal = Calibration {
        offset: Vector3::new(0.05, -0.02, 0.1),
        scale: Vector3::new(1.25, 1.0, 0.833_333_3),
    };
    let json = round_trip(&cal);
    assert!(
        json.contains(r#""offset":{"x":0.05,"y":-0.02,"z":0.1}"#),
        "{json}"
    );
    for e in [Direction::Forward, Direction::Backward] {
        round_trip(&e);
    }
    round_trip(&Event::LimitReached(Limit::Min));
    round_trip(&Event::Arrived);
}

#[test]
fn plain_error_values_round_trip() {
    round_trip(&DateTimeError::Millis);
    round_trip(&HeadingError::NoHorizontalField);
    round_trip(&CalibrationError::SpanTooSmall);
    round_trip(&WmmError::DateOutsideModel);
    round_trip(&MountTiltError::Inconsistent);
    round_trip(&RampError::PulseTooLong);
    round_trip(&Exception::Other(0x0B));
    round_trip(&Exception::ServerDeviceBusy);
}
