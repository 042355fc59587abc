//! Peripheral models, each after its datasheet.

pub mod adxl345;
pub mod bcd_clock;
pub mod ds1302;
pub mod ds3231;
pub mod fs5106r;
pub mod ibt2;
pub mod linear;
pub mod modbus_master;
pub mod mount;
pub mod nmea;
pub mod panel;
pub mod qmc5883l;
pub mod quadrature;
pub mod servo_axis;
pub mod stepper;
pub mod wind;
