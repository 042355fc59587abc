//! Simulation: plant and sensor models for host runs and the QEMU image.

pub mod plant;
pub mod rng;
pub mod sensors;
