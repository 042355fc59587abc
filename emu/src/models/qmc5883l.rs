//! QST QMC5883L three-axis magnetometer (I²C address 0x0D), after the QST
//! *QMC5883L 3-Axis Magnetic Sensor* datasheet (Rev. C):
//!
//! - §9.2 register map: 00h–05h data output X, Y, Z, LSB first, two's
//!   complement; 06h status (bit 0 DRDY, bit 1 OVL, bit 2 DOR); 07h–08h
//!   temperature; 09h control 1 (`OSR[7:6] RNG[5:4] ODR[3:2] MODE[1:0]`);
//!   0Ah control 2 (bit 7 SOFT_RST, bit 6 ROL_PNT, bit 0 INT_ENB); 0Bh
//!   SET/RESET period (recommended 01h); 0Dh chip ID, reads FFh.
//! - §9.2.3: DRDY "is set when all three axis data is ready … in the
//!   continuous measurement mode. It is reset to 0 by reading any data
//!   register"; OVL when an axis exceeds the range.
//! - §9.2.4: RNG 00 = ±2 G (12,000 LSB/G), 01 = ±8 G (3,000 LSB/G).
//! - §9.2.5: with ROL_PNT the pointer rolls from 06h back to 00h; otherwise
//!   it increments through the map.
//!
//! Readings: the field of [`super::mount::Field`] in the sensor frame of
//! [`super::mount::Mount`]; a new sample every 1/ODR of emulated time.

use super::mount::{Field, Mount};
use crate::twi::{I2cDevice, RegisterPointer};

/// Seven-bit address.
pub const ADDRESS: u8 = 0x0D;
const LEN: u8 = 0x0E;

/// The QMC5883L model.
#[derive(Debug, Clone)]
pub struct Qmc5883l {
    regs: [u8; LEN as usize],
    ptr: RegisterPointer,
    field_gauss: [f64; 3],
    /// Emulated time of the next sample (continuous mode).
    next_sample_s: f64,
    drdy: bool,
}

impl Qmc5883l {
    /// A chip on `mount` in `field`.
    pub fn new(mount: &Mount, field: &Field) -> Self {
        let mut q = Qmc5883l {
            regs: [0; LEN as usize],
            ptr: RegisterPointer::default(),
            field_gauss: mount.to_sensor(&field.xyz_gauss),
            next_sample_s: f64::INFINITY,
            drdy: false,
        };
        q.reset();
        q
    }

    fn reset(&mut self) {
        self.regs = [0; LEN as usize];
        self.regs[0x0D] = 0xFF;
        self.drdy = false;
        self.next_sample_s = f64::INFINITY;
    }

    fn continuous(&self) -> bool {
        self.regs[0x09] & 0b11 == 0b01
    }

    fn period_s(&self) -> f64 {
        match (self.regs[0x09] >> 2) & 0b11 {
            0 => 0.1,
            1 => 0.02,
            2 => 0.01,
            _ => 0.005,
        }
    }

    /// Counts per gauss of the selected range.
    pub fn lsb_per_gauss(&self) -> f64 {
        if (self.regs[0x09] >> 4) & 0b11 == 0 {
            12_000.0
        } else {
            3_000.0
        }
    }

    fn update(&mut self, now_s: f64) {
        if !self.continuous() || now_s < self.next_sample_s {
            return;
        }
        let k = self.lsb_per_gauss();
        let mut ovl = false;
        for (i, g) in self.field_gauss.iter().enumerate() {
            let c = (g * k).round();
            if !(-32768.0..=32767.0).contains(&c) {
                ovl = true;
            }
            let [lo, hi] = (c.clamp(-32768.0, 32767.0) as i16).to_le_bytes();
            self.regs[2 * i] = lo;
            self.regs[2 * i + 1] = hi;
        }
        let dor = self.drdy; // previous sample never read
        self.drdy = true;
        self.regs[0x06] = 1 | if ovl { 2 } else { 0 } | if dor { 4 } else { 0 };
        let p = self.period_s();
        self.next_sample_s = now_s + p;
    }
}

impl I2cDevice for Qmc5883l {
    fn address(&self) -> u8 {
        ADDRESS
    }

    fn start(&mut self, read: bool, now_s: f64) -> bool {
        self.update(now_s);
        self.ptr.start(read);
        true
    }

    fn write(&mut self, byte: u8, now_s: f64) -> bool {
        let Some(r) = self.ptr.write(byte, LEN) else {
            return true;
        };
        match r {
            0x09 => {
                let was = self.continuous();
                self.regs[0x09] = byte;
                if self.continuous() && !was {
                    self.next_sample_s = now_s + self.period_s();
                }
            }
            0x0A => {
                if byte & 0x80 != 0 {
                    self.reset();
                } else {
                    self.regs[0x0A] = byte;
                }
            }
            0x0B => self.regs[0x0B] = byte,
            _ => {} // data, status, chip ID: read-only
        }
        true
    }

    fn read(&mut self, _now_s: f64) -> u8 {
        let r = self.ptr.read(LEN);
        if self.regs[0x0A] & 0x40 != 0 && r == 0x06 {
            self.ptr.pointer = 0;
        }
        let v = self.regs[usize::from(r)];
        if r <= 0x05 {
            self.drdy = false;
            self.regs[0x06] &= !0x01;
        }
        v
    }
}
