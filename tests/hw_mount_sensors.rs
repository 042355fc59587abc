//! The portable mount's attitude from real sensor drivers on one mocked I2C
//! bus (ADXL345 accelerometer at 0x53, QMC5883L magnetometer at 0x0D),
//! through `hw::MountSensorsHw`, alone and inside the controller.
//!
//! The bus bytes are made here from a known mount rotation (Choi et al.,
//! portable tracker, eq. 12: `T = Rz(γ0)·Rx(α0)·Ry(β0)`, tracker → horizontal,
//! horizontal X west, Y south, Z up): gravity and the Earth's field are
//! expressed in the tracker frame with `Tᵀ`, then scaled by the datasheets
//! (ADXL345 full resolution 3.9 mg/LSB; QMC5883L 8 G range 3000 LSB/G) and
//! rounded to counts (`common::mount`). The chain must give back
//! the rotation.

mod common;

use drivers::compass::calibration::Calibration;
use drivers::compass::qmc5883l::{Config as QmcConfig, Qmc5883l};
use embedded_hal::i2c::{ErrorKind, NoAcknowledgeSource};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};
use sim::plant::MotorPlant;
use sun_algos::{Algorithm, Options, Site, UtcTime};
use suntracker::attitude::MountAttitude;
use suntracker::config::Config;
use suntracker::controller::{AttitudeSource, Controller, ControllerOptions, TickInputs};
use suntracker::hw::{MountSensorError, MountSensorsHw};
use suntracker::ports::{AttitudeReading, AttitudeSensor};
use suntracker::safety::{Fault, Sensor};
use suntracker::sun::AlgorithmSource;

use std::collections::VecDeque;

use drivers::tilt::modbus::Timeout;
use drivers::tilt::WitInclinometer;
use embedded_hal_mock::eh1::delay::NoopDelay;
use embedded_hal_mock::eh1::digital::{Mock as PinMock, State, Transaction as Pin};

use common::mount::*;

fn nack() -> ErrorKind {
    ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
}

#[test]
fn raw_bus_bytes_give_back_the_mount_rotation() {
    let mut tx = init();
    tx.push(acc_read());
    tx.extend(mag_read());
    let mut bus = I2cMock::new(&tx);
    let mut s = sensors(&bus);
    let r: AttitudeReading<f64> = s.read().unwrap();
    // θx, θy: cos θ = the x, y components of "up" (Choi et al. eq. 4–6).
    let up = up_tracker();
    assert!((r.theta_x_deg - up[0].acos().to_degrees()).abs() < 0.3);
    assert!((r.theta_y_deg - up[1].acos().to_degrees()).abs() < 0.3);
    // Heading of the +y axis: 180° − γ0 (Choi et al. eq. 10–11).
    assert!((r.heading_deg - (180.0 - GAMMA0)).abs() < 0.3, "{r:?}");
    let m = MountAttitude::from_sensors(r.theta_x_deg, r.theta_y_deg, r.heading_deg).unwrap();
    assert!((m.alpha0_deg - ALPHA0).abs() < 0.3, "{m:?}");
    assert!((m.beta0_deg - BETA0).abs() < 0.3, "{m:?}");
    assert!((m.gamma0_deg - GAMMA0).abs() < 0.3, "{m:?}");
    bus.done();
}

#[test]
fn sensor_errors_are_typed() {
    let mut tx = init();
    tx.push(I2c::write_read(ACC, vec![0x32], vec![0; 6]).with_error(nack()));
    // Free fall: all zero counts.
    tx.push(I2c::write_read(ACC, vec![0x32], vec![0; 6]));
    // Compass not ready (DRDY clear).
    tx.push(acc_read());
    tx.push(I2c::write_read(MAG, vec![0x06], vec![0x00]));
    let mut bus = I2cMock::new(&tx);
    let mut s = sensors(&bus);
    assert!(matches!(
        AttitudeSensor::<f64>::read(&mut s),
        Err(MountSensorError::Tilt(_))
    ));
    assert!(matches!(
        AttitudeSensor::<f64>::read(&mut s),
        Err(MountSensorError::Tilt(_))
    ));
    assert!(matches!(
        AttitudeSensor::<f64>::read(&mut s),
        Err(MountSensorError::Compass(_))
    ));
    bus.done();
}

type MeasuringController = Controller<f64, AlgorithmSource<f64>, MotorPlant, Sensors, 360>;

/// The controller at Kano with the mocked sensors on `bus` and two
/// encoder-fed stepper plants (C −180…180°, A −90…90°).
fn measuring_controller(bus: &I2cMock, options: ControllerOptions<f64>) -> MeasuringController {
    let plant = |switch: f64, max: f64| {
        MotorPlant::stepper(1.8, 16, 100.0, 0.0, 2.0, Some(4096), switch, max, 0.0)
    };
    let source = AlgorithmSource {
        algorithm: Algorithm::Psa2020,
        site: Site::with_elevation(11.9683, 8.4261, 480.0).unwrap(),
        options: Options::default(),
    };
    Controller::new(
        Config::default(),
        options,
        source,
        [plant(-180.0, 180.0), plant(-90.0, 90.0)],
        Some(sensors(bus)),
    )
    .unwrap()
}

#[test]
fn controller_measures_the_mount_and_recovers_from_a_nack() {
    const SAMPLES: u8 = 4;
    let mut bus = I2cMock::new(&init());
    let mut ctrl = measuring_controller(
        &bus,
        ControllerOptions {
            attitude: AttitudeSource::Sensors,
            sensor_samples: SAMPLES,
            ..ControllerOptions::default()
        },
    );
    let good_tick = || {
        let mut v = Vec::new();
        for _ in 0..SAMPLES {
            v.push(acc_read());
            v.extend(mag_read());
        }
        v
    };
    let fault = Fault::I2cError(Sensor::Compass);
    let now = UtcTime::from_ymd_hms(2026, 3, 20, 10, 0, 0).unwrap();
    let tick = |ctrl: &mut MeasuringController, k: i64| {
        ctrl.tick(&TickInputs {
            now_ms: suntracker::time::monotonic::from_board_ms((k as u64) * 60_000),
            now: now.add_seconds(60 * k).unwrap(),
            time_valid: true,
            gps_fix: true,
            gps_time_implausible: false,
            gps_time_unstable: false,
            gps_position_unstable: false,
            wind_pulses: 0,
            wind_interval_ms: 60_000,
            stow_inputs: Default::default(),
        })
    };

    // 1. Four good samples: the measured attitude.
    bus.update_expectations(&good_tick());
    tick(&mut ctrl, 0);
    let m = ctrl.attitude();
    assert!((m.alpha0_deg - ALPHA0).abs() < 0.3, "{m:?}");
    assert!((m.beta0_deg - BETA0).abs() < 0.3, "{m:?}");
    assert!((m.gamma0_deg - GAMMA0).abs() < 0.3, "{m:?}");
    assert!(!ctrl.faults().is_active(fault));

    // 2. The accelerometer NACKs once: fault raised, last attitude kept.
    let mut tx = vec![I2c::write_read(ACC, vec![0x32], vec![0; 6]).with_error(nack())];
    for _ in 1..SAMPLES {
        tx.push(acc_read());
        tx.extend(mag_read());
    }
    bus.update_expectations(&tx);
    tick(&mut ctrl, 1);
    assert!(ctrl.faults().is_active(fault));
    assert_eq!(ctrl.attitude(), m);

    // 3. Good again: recovered.
    bus.update_expectations(&good_tick());
    tick(&mut ctrl, 2);
    assert!(!ctrl.faults().is_active(fault));
    assert_eq!(ctrl.faults().recovered, ctrl.faults().raised);
    bus.done();
}

/// The QMC5883L measures at 10 Hz: a reading faster than that finds DRDY
/// clear (datasheet "Status Register": DRDY is set when data is ready and
/// cleared once read). That is not a bus fault: the samples that came are
/// averaged; a reading with none keeps the last attitude and is retried at
/// the next tick; only a compass that never has a sample
/// (`ATTITUDE_NOT_READY_LIMIT` readings in a row) is a fault, a timeout.
#[test]
fn a_compass_without_a_new_sample_is_read_again_not_a_fault() {
    use suntracker::controller::ATTITUDE_NOT_READY_LIMIT;
    const SAMPLES: u8 = 4;
    let mut bus = I2cMock::new(&init());
    let mut ctrl = measuring_controller(
        &bus,
        ControllerOptions {
            attitude: AttitudeSource::Sensors,
            sensor_samples: SAMPLES,
            attitude_every_ms: 10_000,
            ..ControllerOptions::default()
        },
    );
    let now = UtcTime::from_ymd_hms(2026, 3, 20, 10, 0, 0).unwrap();
    // Ticks one second apart.
    let tick = |ctrl: &mut MeasuringController, k: i64| {
        ctrl.tick(&TickInputs {
            now_ms: suntracker::time::monotonic::from_board_ms((k as u64) * 1_000),
            now: now.add_seconds(k).unwrap(),
            time_valid: true,
            gps_fix: true,
            gps_time_implausible: false,
            gps_time_unstable: false,
            gps_position_unstable: false,
            wind_pulses: 0,
            wind_interval_ms: 1_000,
            stow_inputs: Default::default(),
        })
    };
    let not_ready = || vec![acc_read(), I2c::write_read(MAG, vec![0x06], vec![0x00])];
    let bus_fault = Fault::I2cError(Sensor::Compass);
    let stalled = Fault::SensorTimeout(Sensor::Compass);

    // 1. One sample, then DRDY clear: the reading stops there and the one
    //    sample is the attitude; no fault.
    let mut tx = vec![acc_read()];
    tx.extend(mag_read());
    tx.extend(not_ready());
    bus.update_expectations(&tx);
    tick(&mut ctrl, 0);
    let m = ctrl.attitude();
    assert!((m.gamma0_deg - GAMMA0).abs() < 0.3, "{m:?}");
    assert!(!ctrl.faults().is_active(bus_fault));

    // 2. Due again at 10 s, no sample: kept, not a fault, and read again at
    //    the very next tick (not 10 s later), where a sample comes.
    bus.update_expectations(&not_ready());
    tick(&mut ctrl, 10);
    assert_eq!(ctrl.attitude(), m);
    assert!(!ctrl.faults().is_active(bus_fault));
    assert!(!ctrl.faults().is_active(stalled));
    let mut tx = vec![acc_read()];
    tx.extend(mag_read());
    tx.extend(not_ready());
    bus.update_expectations(&tx);
    tick(&mut ctrl, 11);
    assert!(!ctrl.faults().is_active(stalled));

    // 3. A compass that stops measuring: after the limit, timeout_compass;
    //    cleared by the next sample.
    for k in 0..i64::from(ATTITUDE_NOT_READY_LIMIT) {
        assert!(
            !ctrl.faults().is_active(stalled),
            "raised after {k} readings"
        );
        bus.update_expectations(&not_ready());
        tick(&mut ctrl, 21 + k);
    }
    assert!(ctrl.faults().is_active(stalled));
    assert!(!ctrl.faults().is_active(bus_fault));
    let mut tx = vec![acc_read()];
    tx.extend(mag_read());
    tx.extend(not_ready());
    bus.update_expectations(&tx);
    tick(&mut ctrl, 21 + i64::from(ATTITUDE_NOT_READY_LIMIT));
    assert!(!ctrl.faults().is_active(stalled));
    bus.done();
}

// ------------------------------------------------ WitMotion over RS-485

/// CRC-16/MODBUS (reflected polynomial 0xA001, initial 0xFFFF), bit by bit;
/// transmitted low byte first.
fn crc16(frame: &[u8]) -> [u8; 2] {
    let mut crc: u16 = 0xFFFF;
    for &b in frame {
        crc ^= u16::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xA001
            } else {
                crc >> 1
            };
        }
    }
    crc.to_le_bytes()
}

/// An RS-485 port: records what is written, answers from `rx`.
#[derive(Debug, Default)]
struct Rs485 {
    written: Vec<u8>,
    rx: VecDeque<u8>,
}

impl embedded_io::ErrorType for Rs485 {
    type Error = std::convert::Infallible;
}
impl embedded_io::Read for Rs485 {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        let n = buf.len().min(self.rx.len());
        for b in buf.iter_mut().take(n) {
            *b = self.rx.pop_front().unwrap_or(0);
        }
        Ok(n)
    }
}
impl embedded_io::ReadReady for Rs485 {
    fn read_ready(&mut self) -> Result<bool, Self::Error> {
        Ok(!self.rx.is_empty())
    }
}
impl embedded_io::Write for Rs485 {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        self.written.extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// WitMotion angle register: angle / 180° × 32768, two's complement.
fn wit_raw(deg: f64) -> [u8; 2] {
    ((deg / 180.0 * 32768.0).round() as i16).to_be_bytes()
}

#[test]
fn witmotion_inclinometer_and_qmc5883l_give_back_the_mount_rotation() {
    // The request of roll and pitch: address 0x50, function 3, registers
    // 0x3D..0x3E. Its CRC 0x4658 is the value the drivers' tests computed
    // with Python, and ours agrees.
    let mut request = vec![0x50, 0x03, 0x00, 0x3D, 0x00, 0x02];
    assert_eq!(crc16(&request), [0x58, 0x46]);
    request.extend(crc16(&request));
    // Roll and pitch (Z-Y-X convention) of the tilted mount: "up" in the
    // sensor frame is (−sin pitch, cos pitch sin roll, cos pitch cos roll).
    let up = up_tracker();
    let pitch = (-up[0]).asin().to_degrees();
    let roll = up[1].atan2(up[2]).to_degrees();
    let mut response = vec![0x50, 0x03, 0x04];
    response.extend(wit_raw(roll));
    response.extend(wit_raw(pitch));
    response.extend(crc16(&response));

    let port = Rs485 {
        written: Vec::new(),
        rx: response.into_iter().collect(),
    };
    // The transceiver's driver-enable pin: high to send, low to listen.
    let mut de = PinMock::new(&[Pin::set(State::High), Pin::set(State::Low)]);
    let incl = WitInclinometer::new(port, de.clone(), NoopDelay::new(), 0x50, Timeout::default());
    let mut tx = vec![
        I2c::write_read(MAG, vec![0x0D], vec![0xFF]),
        I2c::write(MAG, vec![0x0B, 0x01]),
        I2c::write(MAG, vec![0x09, 0x11]),
    ];
    tx.extend(mag_read());
    let mut bus = I2cMock::new(&tx);
    let mag = Qmc5883l::new(bus.clone(), QmcConfig::default()).unwrap();
    let mut s = MountSensorsHw::new(incl, mag, Calibration::IDENTITY, DECL as f32);

    let r: AttitudeReading<f64> = s.read().unwrap();
    let m = MountAttitude::from_sensors(r.theta_x_deg, r.theta_y_deg, r.heading_deg).unwrap();
    // 16-bit angles (0.0055°) and 3000 LSB/G: well inside 0.05°.
    assert!((m.alpha0_deg - ALPHA0).abs() < 0.05, "{m:?}");
    assert!((m.beta0_deg - BETA0).abs() < 0.05, "{m:?}");
    assert!((m.gamma0_deg - GAMMA0).abs() < 0.1, "{m:?}");

    let (incl, _mag) = s.destroy();
    let (port, _, _) = incl.destroy();
    assert_eq!(port.written, request);
    de.done();
    bus.done();
}

/// A board that probes for one of two tilt sensors hands the loop whichever
/// answered: `EitherTilt` reads through to it and tags its error.
#[test]
fn either_tilt_reads_the_sensor_it_holds() {
    use suntracker::hw::{AxisAngles, EitherTilt, EitherTiltError};
    struct Fixed(Result<(f32, f32), u8>);
    impl AxisAngles for Fixed {
        type Error = u8;
        fn axis_angles_deg(&mut self) -> Result<(f32, f32), u8> {
            self.0
        }
    }
    let mut first: EitherTilt<Fixed, Fixed> = EitherTilt::First(Fixed(Ok((80.0, 95.0))));
    assert_eq!(first.axis_angles_deg(), Ok((80.0, 95.0)));
    let mut second: EitherTilt<Fixed, Fixed> = EitherTilt::Second(Fixed(Err(7)));
    assert_eq!(second.axis_angles_deg(), Err(EitherTiltError::Second(7)));
    let mut first_err: EitherTilt<Fixed, Fixed> = EitherTilt::First(Fixed(Err(3)));
    assert_eq!(first_err.axis_angles_deg(), Err(EitherTiltError::First(3)));
}
