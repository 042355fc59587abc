//! Configuration ranges: every field is checked and the error names it.

use suntracker::config::{ranges, AxisConfig, Config, ConfigError, Reason, PAYLOAD_LEN};
use suntracker::plan::ScheduleConfig;
use suntracker::safety::OperatorHold;

fn field_of(c: &Config) -> Option<String> {
    c.validate()
        .err()
        .map(|e: ConfigError| e.field.name().to_string())
}

#[test]
fn defaults_validate() {
    assert_eq!(Config::default().validate(), Ok(()));
    assert!(Config::default().is_valid());
}

#[test]
fn huge_gear_ratio_is_rejected_by_name() {
    // Formerly accepted: a gear ratio of 1e30 overflowed the axis counts.
    let mut c = Config::default();
    c.axes[0].gear_ratio = 1e30;
    assert!(!c.is_valid());
    assert_eq!(field_of(&c).as_deref(), Some("axis.c.gear_ratio"));
    let mut c = Config::default();
    c.axes[1].gear_ratio = f32::NAN;
    assert_eq!(field_of(&c).as_deref(), Some("axis.a.gear_ratio"));
}

#[test]
fn counts_per_degree_product_is_bounded() {
    // Each factor in range, the product not: 2^24 × 256 × 10,000 / 360.
    let mut c = Config::default();
    let a = &mut c.axes[1];
    a.counts_per_motor_rev = ranges::COUNTS_PER_MOTOR_REV.1;
    a.microsteps = ranges::MICROSTEPS.1;
    a.gear_ratio = ranges::GEAR_RATIO.1;
    assert_eq!(field_of(&c).as_deref(), Some("axis.a.counts_per_deg"));
    // A bare 200-step motor: 0.56 counts per degree, coarser than 1°.
    let a = &mut c.axes[1];
    a.counts_per_motor_rev = 200;
    a.microsteps = 1;
    a.gear_ratio = 1.0;
    assert_eq!(field_of(&c).as_deref(), Some("axis.a.counts_per_deg"));
    // The same with 2 microsteps: 1.1 counts per degree.
    c.axes[1].microsteps = 2;
    assert_eq!(c.validate(), Ok(()));
}

type Mutate = fn(&mut Config);

/// One value just outside each range (or breaking a rule between fields),
/// the key that must be named and the reason its error must give: the range
/// of the field's doc comment, or the rule.
const OUT_OF_RANGE: &[(&str, Reason, Mutate)] = &[
    ("site.lat_deg", Reason::Latitude, |c| {
        c.site.latitude_deg = 90.5
    }),
    ("site.lat_deg", Reason::Latitude, |c| {
        c.site.latitude_deg = f32::NAN
    }),
    ("site.lon_deg", Reason::Deg180, |c| {
        c.site.longitude_deg = -180.5
    }),
    ("site.elevation_m", Reason::ElevationM, |c| {
        c.site.elevation_m = 10_001.0
    }),
    ("site.elevation_m", Reason::ElevationM, |c| {
        c.site.elevation_m = -501.0
    }),
    ("schedule.table_step_s", Reason::TableStepS, |c| {
        c.schedule.table_step_s = 0
    }),
    ("schedule.table_step_s", Reason::WholeMinutesOfDay, |c| {
        c.schedule.table_step_s = 90
    }),
    ("schedule.table_step_s", Reason::TableStepS, |c| {
        c.schedule.table_step_s = 86_400
    }),
    ("schedule.table_step_s", Reason::WholeMinutesOfDay, |c| {
        c.schedule.table_step_s = 420
    }),
    ("schedule.hold_s", Reason::S0To3600, |c| {
        c.schedule.hold_s = 3_601
    }),
    ("schedule.recheck_s", Reason::S1To3600, |c| {
        c.schedule.recheck_s = 0
    }),
    ("schedule.recheck_s", Reason::S1To3600, |c| {
        c.schedule.recheck_s = 3_601
    }),
    ("schedule.max_tick_gap_s", Reason::S1To86400, |c| {
        c.schedule.max_tick_gap_s = 0
    }),
    ("schedule.max_tick_gap_s", Reason::S1To86400, |c| {
        c.schedule.max_tick_gap_s = 86_401
    }),
    ("schedule.max_backward_s", Reason::S0To86400, |c| {
        c.schedule.max_backward_s = u32::MAX
    }),
    (
        "axis.c.counts_per_motor_rev",
        Reason::CountsPerMotorRev,
        |c| c.axes[0].counts_per_motor_rev = 0,
    ),
    (
        "axis.c.counts_per_motor_rev",
        Reason::CountsPerMotorRev,
        |c| c.axes[0].counts_per_motor_rev = 16_777_217,
    ),
    ("axis.a.microsteps", Reason::Microsteps, |c| {
        c.axes[1].microsteps = 0
    }),
    ("axis.a.microsteps", Reason::Microsteps, |c| {
        c.axes[1].microsteps = 257
    }),
    ("axis.c.gear_ratio", Reason::GearRatio, |c| {
        c.axes[0].gear_ratio = 0.5
    }),
    ("axis.c.gear_ratio", Reason::GearRatio, |c| {
        c.axes[0].gear_ratio = 10_001.0
    }),
    ("axis.c.gear_ratio", Reason::GearRatio, |c| {
        c.axes[0].gear_ratio = f32::INFINITY
    }),
    ("axis.a.counts_per_deg", Reason::CountsPerDeg, |c| {
        c.axes[1].counts_per_motor_rev = 200;
        c.axes[1].microsteps = 1;
        c.axes[1].gear_ratio = 1.0;
    }),
    ("axis.c.min_deg", Reason::LimitDeg, |c| {
        c.axes[0].min_deg = -361.0
    }),
    ("axis.c.max_deg", Reason::LimitDeg, |c| {
        c.axes[0].max_deg = 361.0
    }),
    ("axis.a.max_deg", Reason::AboveMinDeg, |c| {
        c.axes[1].max_deg = -90.0
    }),
    ("axis.a.min_deg", Reason::LimitDeg, |c| {
        c.axes[1].min_deg = f32::NEG_INFINITY
    }),
    ("axis.c.home_deg", Reason::HomeNearMinDeg, |c| {
        c.axes[0].home_deg = -185.5
    }),
    ("axis.c.home_deg", Reason::HomeNearMinDeg, |c| {
        c.axes[0].home_deg = -169.5
    }),
    ("axis.a.home_deg", Reason::HomeNearMinDeg, |c| {
        c.axes[1].home_deg = 90.0
    }),
    ("axis.a.home_deg", Reason::HomeNearMinDeg, |c| {
        c.axes[1].max_deg = -85.0;
        c.axes[1].home_deg = -84.0;
    }),
    ("axis.a.backlash_deg", Reason::Deg0To5, |c| {
        c.axes[1].backlash_deg = -0.1
    }),
    ("axis.a.backlash_deg", Reason::Deg0To5, |c| {
        c.axes[1].backlash_deg = 5.5
    }),
    ("axis.c.max_speed_deg_s", Reason::SpeedDegS, |c| {
        c.axes[0].max_speed_deg_s = 0.0
    }),
    ("axis.c.max_speed_deg_s", Reason::SpeedDegS, |c| {
        c.axes[0].max_speed_deg_s = 31.0
    }),
    ("axis.a.deadband_deg", Reason::Deg0To5, |c| {
        c.axes[1].deadband_deg = -0.01
    }),
    ("axis.a.deadband_deg", Reason::Deg0To5, |c| {
        c.axes[1].deadband_deg = 5.5
    }),
    ("axis.c.deadband_deg", Reason::BelowMaxDeviation, |c| {
        c.axes[0].deadband_deg = 1.0;
        c.safety.max_deviation_deg = 1.0;
    }),
    ("wind.stow_hz", Reason::StowHz, |c| {
        c.wind.threshold_hz = 0.0
    }),
    ("wind.stow_hz", Reason::StowHz, |c| {
        c.wind.threshold_hz = 1_001.0
    }),
    ("wind.stow_hz", Reason::StowHz, |c| {
        c.wind.threshold_hz = f32::NAN
    }),
    ("wind.hold_s", Reason::S0To600, |c| c.wind.hold_s = 601),
    ("wind.release_s", Reason::S0To86400, |c| {
        c.wind.release_s = 86_401
    }),
    ("safety.max_deviation_deg", Reason::MaxDeviationDeg, |c| {
        c.safety.max_deviation_deg = 0.05
    }),
    ("safety.max_deviation_deg", Reason::MaxDeviationDeg, |c| {
        c.safety.max_deviation_deg = 46.0
    }),
    ("safety.stall_timeout_s", Reason::S1To600, |c| {
        c.safety.stall_timeout_s = 0
    }),
    ("safety.stall_timeout_s", Reason::S1To600, |c| {
        c.safety.stall_timeout_s = 601
    }),
    ("safety.sensor_timeout_s", Reason::S1To3600, |c| {
        c.safety.sensor_timeout_s = 0
    }),
    ("safety.sensor_timeout_s", Reason::S1To3600, |c| {
        c.safety.sensor_timeout_s = 3_601
    }),
    ("safety.max_retries", Reason::MaxRetries, |c| {
        c.safety.max_retries = 21
    }),
    ("calibration.declination_deg", Reason::Deg180, |c| {
        c.calibration.declination_deg = 181.0
    }),
    ("calibration.heading_offset_deg", Reason::Deg180, |c| {
        c.calibration.heading_offset_deg = -181.0
    }),
    (
        "calibration.tilt_x_offset_deg",
        Reason::TiltOffsetDeg,
        |c| c.calibration.tilt_x_offset_deg = 46.0,
    ),
    (
        "calibration.tilt_y_offset_deg",
        Reason::TiltOffsetDeg,
        |c| c.calibration.tilt_y_offset_deg = f32::NAN,
    ),
    ("log.status_min", Reason::StatusMin, |c| {
        c.log.status_every_min = 1_441
    }),
];

#[test]
fn every_field_out_of_range_is_named_with_its_reason() {
    for (key, reason, mutate) in OUT_OF_RANGE {
        let mut c = Config::default();
        mutate(&mut c);
        let e = c.validate().expect_err(key);
        assert_eq!(e.field, *key, "{e:?}");
        assert_eq!(e.reason, *reason, "{key}");
        assert_eq!(e.to_string(), format!("{key}: {}", e.reason));
        assert!(!c.is_valid());
        // Never stored nor loaded.
        let mut buf = [0u8; PAYLOAD_LEN];
        let n = c.encode(&mut buf).unwrap();
        assert_eq!(Config::decode(&buf[..n]), None, "{key}");
    }
}

#[test]
fn an_axis_alone_is_checked_under_its_own_keys() {
    let mut a: AxisConfig = Config::default().axes[1];
    assert_eq!(a.validate(1), Ok(()));
    a.backlash_deg = 6.0;
    let e = a.validate(1).unwrap_err();
    assert_eq!(
        (e.field.name().to_string().as_str(), e.reason),
        ("axis.a.backlash_deg", Reason::Deg0To5)
    );
    // Any axis but 0 is the A axis; 0 the C axis.
    assert_eq!(a.validate(7), Err(e));
    let e = a.validate(0).unwrap_err();
    assert_eq!(e.field.name().to_string(), "axis.c.backlash_deg");
    // The deadband's relation to safety.max_deviation_deg is the whole
    // configuration's rule, not the axis's.
    let mut a: AxisConfig = Config::default().axes[0];
    a.deadband_deg = 4.0;
    assert_eq!(a.validate(0), Ok(()));
}

/// The ends of every range are valid.
const EXTREMES: &[Mutate] = &[
    |c| c.site.latitude_deg = -90.0,
    |c| c.site.latitude_deg = 90.0,
    |c| c.site.longitude_deg = 180.0,
    |c| c.site.elevation_m = -500.0,
    |c| c.site.elevation_m = 10_000.0,
    |c| c.schedule.table_step_s = 60,
    |c| c.schedule.table_step_s = 43_200,
    |c| c.schedule.hold_s = 0,
    |c| c.schedule.hold_s = 3_600,
    |c| c.schedule.recheck_s = 1,
    |c| c.schedule.max_tick_gap_s = 86_400,
    |c| c.schedule.max_backward_s = 0,
    |c| c.schedule.max_backward_s = 86_400,
    |c| {
        c.axes[0].counts_per_motor_rev = 360;
        c.axes[0].microsteps = 1;
        c.axes[0].gear_ratio = 1.0;
    },
    |c| {
        c.axes[0].counts_per_motor_rev = 16_777_216;
        c.axes[0].microsteps = 1;
        c.axes[0].gear_ratio = 21.0;
    },
    |c| {
        c.axes[1].counts_per_motor_rev = 1;
        c.axes[1].microsteps = 256;
        c.axes[1].gear_ratio = 10_000.0;
    },
    |c| {
        c.axes[0].min_deg = -360.0;
        c.axes[0].max_deg = 360.0;
        c.axes[0].home_deg = -365.0;
    },
    |c| c.axes[1].home_deg = -80.0,
    |c| c.axes[1].backlash_deg = 5.0,
    |c| c.axes[1].max_speed_deg_s = 0.01,
    |c| c.axes[1].max_speed_deg_s = 30.0,
    |c| c.axes[1].deadband_deg = 0.0,
    |c| {
        c.axes[1].deadband_deg = 5.0;
        c.safety.max_deviation_deg = 5.5;
    },
    |c| c.wind.threshold_hz = 0.1,
    |c| c.wind.threshold_hz = 1_000.0,
    |c| c.wind.hold_s = 600,
    |c| c.wind.release_s = 86_400,
    |c| {
        c.safety.max_deviation_deg = 0.1;
        c.axes[0].deadband_deg = 0.0;
        c.axes[1].deadband_deg = 0.05;
    },
    |c| c.safety.max_deviation_deg = 45.0,
    |c| c.safety.stall_timeout_s = 600,
    |c| c.safety.sensor_timeout_s = 3_600,
    |c| c.safety.max_retries = 0,
    |c| c.safety.max_retries = 20,
    |c| c.calibration.declination_deg = -180.0,
    |c| c.calibration.heading_offset_deg = 180.0,
    |c| c.calibration.tilt_x_offset_deg = -45.0,
    |c| c.calibration.tilt_y_offset_deg = 45.0,
];

#[test]
fn ends_of_every_range_validate() {
    for (i, mutate) in EXTREMES.iter().enumerate() {
        let mut c = Config::default();
        mutate(&mut c);
        assert_eq!(c.validate(), Ok(()), "extreme {i}");
        let mut buf = [0u8; PAYLOAD_LEN];
        let n = c.encode(&mut buf).unwrap();
        assert_eq!(Config::decode(&buf[..n]), Some(c), "extreme {i}");
    }
}

#[test]
fn the_controller_refuses_a_configuration_out_of_range() {
    use sim::plant::MotorPlant;
    use sim::sensors::MountSensors;
    use suntracker::controller::{Controller, ControllerError, ControllerOptions};
    use suntracker::sun::AlgorithmSource;
    let mut config = Config::default();
    config.axes[0].gear_ratio = 1e30;
    let source = AlgorithmSource {
        algorithm: sun_algos::Algorithm::Psa2020,
        site: sun_algos::Site::new(11.9683, 8.4261).unwrap(),
        options: sun_algos::Options::default(),
    };
    let plant = || MotorPlant::stepper(1.8, 16, 100.0, 0.2, 2.0, None, -90.0, 90.0, 0.0);
    let r: Result<Controller<f64, _, _, MountSensors, 361>, _> = Controller::new(
        config,
        ControllerOptions::default(),
        source,
        [plant(), plant()],
        None,
    );
    match r {
        Err(ControllerError::Config(e)) => assert_eq!(e.field, "axis.c.gear_ratio"),
        Err(e) => panic!("{e:?}"),
        Ok(_) => panic!("accepted a gear ratio of 1e30"),
    }
}

#[test]
fn defaults_from_the_key_table_are_the_documented_constant() {
    // `Config::default` writes each key from a table built out of
    // `Config::DEFAULT`: every field (and the hold, none) comes out as the
    // constant's, and the documented values are in it.
    let d = Config::default();
    assert_eq!(d, Config::DEFAULT);
    assert_eq!(d.schedule, ScheduleConfig::default());
    assert_eq!(d.hold, OperatorHold::default());
    // Jimoh & Aliyu (2019): Kano, 4-minute table, 2-minute hold, 30 s
    // re-check; 1.8° steppers (200 steps) with 16 microsteps, 100:1 gear.
    assert_eq!(
        (
            d.site.latitude_deg,
            d.site.longitude_deg,
            d.site.elevation_m
        ),
        (11.9683, 8.4261, 480.0)
    );
    assert_eq!(
        (
            d.schedule.table_step_s,
            d.schedule.hold_s,
            d.schedule.recheck_s
        ),
        (240, 120, 30)
    );
    for a in &d.axes {
        assert_eq!(
            (a.counts_per_motor_rev, a.microsteps, a.gear_ratio),
            (200, 16, 100.0)
        );
    }
    assert_eq!((d.axes[1].min_deg, d.axes[1].max_deg), (-90.0, 90.0));
    assert_eq!((d.safety.max_retries, d.log.status_every_min), (3, 10));
}
