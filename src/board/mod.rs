//! Board layers: embedded-hal 1.0 / embedded-io implementations over a
//! chip's peripheral access crate, so that the `drivers` crate runs on it
//! unchanged.

#[cfg(target_arch = "avr")]
pub mod avr;

pub mod chowdhury2019;
pub mod chowdhury2019_settings;
pub mod li2022;

// The Arduino Mega 2560 tracker (ATmega2560 builds: `--cfg avr_atmega2560`).
// Each board module's docs are its own (an outer doc here would make rustdoc
// resolve the module's links in this scope).
#[cfg(all(target_arch = "avr", avr_atmega2560))]
#[allow(unsafe_code)]
pub mod mega2560;

// The Arduino Uno tracker (ATmega328P builds: no `avr_atmega2560` cfg).
#[cfg(all(target_arch = "avr", not(avr_atmega2560)))]
#[allow(unsafe_code)]
pub mod uno;

// QEMU's `mps2-an386` (Cortex-M4F): the `qemu_tracker` image.
#[cfg(all(target_arch = "arm", target_os = "none"))]
#[allow(unsafe_code)]
pub mod mps2_an386;

// The STM32F411CEU6 "Black Pill" tracker (feature `stm32f411`, Cortex-M
// builds).
#[cfg(all(feature = "stm32f411", target_arch = "arm", target_os = "none"))]
pub mod stm32f411;

// The log over defmt (feature `defmt`) of the Cortex-M images.
#[cfg(all(feature = "defmt", target_arch = "arm", target_os = "none"))]
pub mod defmt_log;
