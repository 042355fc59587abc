//! A tilted mount seen by an ADXL345 (0x53) and a QMC5883L (0x0D) on one
//! I2C bus: the bus bytes both chips would return, made from a known mount
//! rotation (Choi et al. (portable tracker) eq. 12: `T = Rz(γ0)·Rx(α0)·Ry(β0)`,
//! tracker → horizontal; horizontal X west, Y south, Z up). Gravity and the
//! Earth's field are expressed in the tracker frame with `Tᵀ`, scaled by
//! the datasheets (ADXL345 full resolution 3.9 mg/LSB; QMC5883L 8 G range
//! 3000 LSB/G) and rounded to counts.
#![allow(dead_code)]

use drivers::compass::calibration::Calibration;
use drivers::compass::qmc5883l::{Config as QmcConfig, Qmc5883l};
use drivers::tilt::adxl345::ADDRESS_ALT_LOW;
use drivers::tilt::Adxl345;
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};
use suntracker::hw::MountSensorsHw;

pub const ACC: u8 = ADDRESS_ALT_LOW;
pub const MAG: u8 = 0x0D;
pub const G_PER_LSB: f64 = 0.0039;
pub const LSB_PER_GAUSS: f64 = 3000.0;

/// Truth: tilted 4° about x, −6° about y, turned 25° about the vertical.
pub const ALPHA0: f64 = 4.0;
pub const BETA0: f64 = -6.0;
pub const GAMMA0: f64 = 25.0;
/// Magnetic declination used for the field, east positive.
pub const DECL: f64 = 1.5;

pub type Mat = [[f64; 3]; 3];

pub fn rx(d: f64) -> Mat {
    let (s, c) = d.to_radians().sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}
pub fn ry(d: f64) -> Mat {
    let (s, c) = d.to_radians().sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}
pub fn rz(d: f64) -> Mat {
    let (s, c) = d.to_radians().sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}
pub fn mul(a: &Mat, b: &Mat) -> Mat {
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}
/// `mᵀ·v`: horizontal → tracker.
pub fn to_tracker(m: &Mat, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|j| (0..3).map(|i| m[i][j] * v[i]).sum())
}

pub fn t_matrix() -> Mat {
    mul(&mul(&rz(GAMMA0), &rx(ALPHA0)), &ry(BETA0))
}

/// "Up" in the tracker frame: an accelerometer at rest reads +1 g there.
pub fn up_tracker() -> [f64; 3] {
    to_tracker(&t_matrix(), [0.0, 0.0, 1.0])
}

/// The field near Kano: 0.34 G horizontal toward magnetic north (north =
/// −Y, east = −X, turned `DECL` east), 0.03 G down (−Z).
pub fn field_tracker() -> [f64; 3] {
    let d = DECL.to_radians();
    let h = 0.34;
    to_tracker(&t_matrix(), [-h * d.sin(), -h * d.cos(), -0.03])
}

pub fn le_counts(v: [f64; 3], per_unit: f64) -> Vec<u8> {
    v.iter()
        .flat_map(|c| ((c * per_unit).round() as i16).to_le_bytes())
        .collect()
}

pub fn acc_read() -> I2c {
    I2c::write_read(ACC, vec![0x32], le_counts(up_tracker(), 1.0 / G_PER_LSB))
}

/// QMC5883L: status 06h with DRDY, then the six data bytes from 00h.
pub fn mag_read() -> [I2c; 2] {
    [
        I2c::write_read(MAG, vec![0x06], vec![0x01]),
        I2c::write_read(MAG, vec![0x00], le_counts(field_tracker(), LSB_PER_GAUSS)),
    ]
}

pub fn init() -> Vec<I2c> {
    vec![
        // ADXL345: DEVID, full resolution ±2 g, 100 Hz, measure.
        I2c::write_read(ACC, vec![0x00], vec![0xE5]),
        I2c::write(ACC, vec![0x31, 0x08]),
        I2c::write(ACC, vec![0x2C, 0x0A]),
        I2c::write(ACC, vec![0x2D, 0x08]),
        // QMC5883L: chip ID, SET/RESET period, continuous 10 Hz 8 G OSR 512.
        I2c::write_read(MAG, vec![0x0D], vec![0xFF]),
        I2c::write(MAG, vec![0x0B, 0x01]),
        I2c::write(MAG, vec![0x09, 0x11]),
    ]
}

pub type Sensors = MountSensorsHw<Adxl345<I2cMock>, Qmc5883l<I2cMock>>;

pub fn sensors(bus: &I2cMock) -> Sensors {
    let mut acc = Adxl345::new(bus.clone(), ACC);
    acc.init().unwrap();
    let mag = Qmc5883l::new(bus.clone(), QmcConfig::default()).unwrap();
    MountSensorsHw::new(acc, mag, Calibration::IDENTITY, DECL as f32)
}
