//! Analog Devices ADXL345 three-axis accelerometer (I²C address 0x53 with
//! ALT ADDRESS low), after the ADI *ADXL345* datasheet (Rev. G):
//!
//! - "Register Map" (Table 19): 00h DEVID = E5h; 2Ch BW_RATE (reset 0Ah);
//!   2Dh POWER_CTL (bit 3 Measure; reset 00h, standby); 31h DATA_FORMAT
//!   (bit 3 FULL_RES, bit 2 Justify, bits 1:0 range ±2/4/8/16 g);
//!   32h–37h DATAX0…DATAZ1, two's complement, LSB first.
//! - Table 1 / "Register 0x31": full resolution keeps 3.9 mg/LSB (256
//!   LSB/g) at every range; 10-bit mode has 256/128/64/32 LSB/g at
//!   ±2/4/8/16 g; left-justified data (Justify) is not modelled.
//! - "Serial Communications, I²C": multiple-byte reads and writes
//!   auto-increment the register address.
//!
//! Readings: +1 g along "up" in the sensor frame of [`super::mount::Mount`]
//! (an accelerometer at rest measures the reaction to gravity).

use super::mount::Mount;
use crate::twi::{I2cDevice, RegisterPointer};

/// Seven-bit address (ALT ADDRESS low).
pub const ADDRESS: u8 = 0x53;
const LEN: u8 = 0x3A;

/// The ADXL345 model.
#[derive(Debug, Clone)]
pub struct Adxl345 {
    regs: [u8; LEN as usize],
    ptr: RegisterPointer,
    accel_g: [f64; 3],
}

impl Adxl345 {
    /// A chip at rest on `mount`.
    pub fn new(mount: &Mount) -> Self {
        let mut regs = [0u8; LEN as usize];
        regs[0x00] = 0xE5;
        regs[0x2C] = 0x0A;
        regs[0x30] = 0x02; // INT_SOURCE: Watermark is set at reset
        Adxl345 {
            regs,
            ptr: RegisterPointer::default(),
            accel_g: mount.gravity_g(),
        }
    }

    fn lsb_per_g(&self) -> (f64, f64) {
        let f = self.regs[0x31];
        let range_g = f64::from(2u8 << (f & 0b11));
        let lsb = if f & 0x08 != 0 {
            256.0
        } else {
            256.0 / f64::from(1u8 << (f & 0b11))
        };
        (lsb, range_g)
    }

    fn sample(&mut self) {
        let measuring = self.regs[0x2D] & 0x08 != 0;
        let (lsb, range) = self.lsb_per_g();
        for (i, a) in self.accel_g.iter().enumerate() {
            let c = if measuring {
                (a.clamp(-range, range) * lsb).round() as i16
            } else {
                0
            };
            let [lo, hi] = c.to_le_bytes();
            self.regs[0x32 + 2 * i] = lo;
            self.regs[0x33 + 2 * i] = hi;
        }
    }
}

impl I2cDevice for Adxl345 {
    fn address(&self) -> u8 {
        ADDRESS
    }

    fn start(&mut self, read: bool, _now_s: f64) -> bool {
        self.sample();
        self.ptr.start(read);
        true
    }

    fn write(&mut self, byte: u8, _now_s: f64) -> bool {
        let Some(r) = self.ptr.write(byte, LEN) else {
            return true;
        };
        // Read-only: DEVID, ACT_TAP_STATUS, INT_SOURCE, data, FIFO_STATUS.
        if !matches!(r, 0x00 | 0x2B | 0x30 | 0x32..=0x37 | 0x39) {
            if let Some(reg) = self.regs.get_mut(usize::from(r)) {
                *reg = byte;
            }
        }
        true
    }

    fn read(&mut self, _now_s: f64) -> u8 {
        let r = self.ptr.read(LEN);
        self.regs.get(usize::from(r)).copied().unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::mount::{Field, Mount};
    use super::super::qmc5883l::Qmc5883l;
    use super::*;
    use crate::twi::{EmuClock, HostI2c, TwiBus};
    use std::cell::RefCell;
    use std::rc::Rc;
    use suntracker::attitude::MountAttitude;
    use suntracker::hw::{AxisAngles, MountSensorsHw};
    use suntracker::ports::AttitudeSensor;

    fn bus_with(mount: &Mount, field: &Field) -> (HostI2c, EmuClock) {
        let clock = EmuClock::new();
        let bus = Rc::new(RefCell::new(TwiBus::new(clock.clone())));
        bus.borrow_mut().attach(Box::new(Adxl345::new(mount)));
        bus.borrow_mut()
            .attach(Box::new(Qmc5883l::new(mount, field)));
        (HostI2c { bus }, clock)
    }

    #[test]
    fn devid_and_scale() {
        let mut a = Adxl345::new(&Mount::level());
        a.start(false, 0.0);
        a.write(0x00, 0.0);
        a.start(true, 0.0);
        assert_eq!(a.read(0.0), 0xE5);
        // Standby: zero data.
        a.start(false, 0.0);
        a.write(0x32, 0.0);
        a.start(true, 0.0);
        assert_eq!([a.read(0.0), a.read(0.0)], [0, 0]);
        // Full resolution, measure: +1 g on Z = 256 counts.
        for (r, v) in [(0x31, 0x08), (0x2D, 0x08)] {
            a.start(false, 0.0);
            a.write(r, 0.0);
            a.write(v, 0.0);
        }
        a.start(false, 0.0);
        a.write(0x32, 0.0);
        a.start(true, 0.0);
        let d: Vec<u8> = (0..6).map(|_| a.read(0.0)).collect();
        assert_eq!(i16::from_le_bytes([d[4], d[5]]), 256);
        assert_eq!(i16::from_le_bytes([d[0], d[1]]), 0);
    }

    /// The drivers the firmware runs (ADXL345 → axis angles → mount tilt;
    /// QMC5883L → tilt-compensated true heading; `MountAttitude::from_sensors`)
    /// give back the mount the models were built for.
    fn round_trip(tilt_deg: f64, heading_deg: f64) {
        let field = Field::kano_2026();
        let mount = Mount::tilted(tilt_deg, heading_deg);
        let (i2c, clock) = bus_with(&mount, &field);
        let mut accel = drivers::tilt::Adxl345::new(i2c.clone(), ADDRESS);
        accel.init().unwrap();
        let compass = drivers::compass::qmc5883l::Qmc5883l::new(
            i2c.clone(),
            drivers::compass::qmc5883l::Config::default(),
        )
        .unwrap();
        let (tx, ty) = accel.axis_angles_deg().unwrap();
        let want = mount.attitude.to_sensors();
        assert!(
            (f64::from(tx) - want.0).abs() < 0.1,
            "θx {tx} vs {}",
            want.0
        );
        assert!(
            (f64::from(ty) - want.1).abs() < 0.1,
            "θy {ty} vs {}",
            want.1
        );
        clock.set_s(1.0); // a sample is ready 1/ODR after the mode write
        let mut sensors = MountSensorsHw::new(
            accel,
            compass,
            drivers::compass::calibration::Calibration::IDENTITY,
            field.declination_deg as f32,
        );
        let r: suntracker::ports::AttitudeReading<f64> = sensors.read().unwrap();
        let back =
            MountAttitude::from_sensors(r.theta_x_deg, r.theta_y_deg, r.heading_deg).unwrap();
        assert!((back.alpha0_deg - tilt_deg).abs() < 0.1, "{back:?}");
        assert!(back.beta0_deg.abs() < 0.1, "{back:?}");
        let dg = suntracker::attitude::wrap180(back.gamma0_deg - mount.attitude.gamma0_deg);
        assert!(dg.abs() < 0.15, "{back:?} vs {:?}", mount.attitude);
    }

    #[test]
    fn drivers_read_back_a_level_north_facing_mount() {
        round_trip(0.0, 0.0);
        // Level: θx = θy = 90°, true heading of +y = 180° (south).
        let (tx, ty, h) = Mount::level().attitude.to_sensors();
        assert!((tx - 90.0).abs() < 1e-9 && (ty - 90.0).abs() < 1e-9);
        assert!((h - 180.0).abs() < 1e-9);
    }

    #[test]
    fn drivers_read_back_tilt_7_heading_20() {
        round_trip(7.0, 20.0);
        round_trip(-12.0, 250.0);
    }

    #[test]
    fn kano_field_is_plausible() {
        // WMM2025 at Kano, 2026: about 34,000 nT horizontal, dip ~ +5°,
        // declination ~ +1° (NOAA calculator gives similar values).
        let f = Field::kano_2026();
        let h = (f.xyz_gauss[0].powi(2) + f.xyz_gauss[1].powi(2)).sqrt();
        assert!((0.30..0.38).contains(&h), "H = {h} G");
        assert!(f.declination_deg.abs() < 3.0, "D = {}", f.declination_deg);
    }
}
