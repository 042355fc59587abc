//! Peripheral models, each after its datasheet.

pub mod adxl345;
pub mod ds3231;
pub mod mount;
pub mod nmea;
pub mod qmc5883l;
pub mod stepper;
pub mod wind;
