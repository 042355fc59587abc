//! The STM32F411CEU6 "Black Pill" tracker (WeAct v3 board, 25 MHz crystal):
//! everything about this board in one place — clocks, pins, devices,
//! configuration — turned into the parts of [`suntracker::firmware::Firmware`]. The
//! image (`boards/stm32f411/src/bin/blackpill_tracker.rs`) takes the peripherals and calls
//! [`run`]; the interrupt handlers (`SysTick`, `USART1`, `USART6`,
//! `EXTI9_5`) are bound here.
//!
//! | function | peripheral | Black Pill pin |
//! |---|---|---|
//! | log and console, 115200 8N1 (log out on TX; console lines in on RX, interrupt-driven) | USART6 TX, RX | A11 TX, A12 RX |
//! | GPS NMEA in, 9600 8N1 (receiver TX → A10) | USART1 RX, interrupt-driven | A10 |
//! | I²C 100 kHz: DS3231 0x68, QMC5883L 0x0D, ADXL345 0x53 (one bus, shared with `embedded_hal_bus::i2c::AtomicDevice`) | I2C1 | B6 SCL, B7 SDA |
//! | WitMotion RS-485 inclinometer, Modbus RTU 9600 8N1 | USART2 + MAX485 DE/RE | A2 TX (DI), A3 RX (RO), A1 DE+/RE |
//! | or, with the feature `modbus`: the plant's RS-485 bus, Modbus RTU server at `modbus.baud` and `modbus.parity` (`modbus_line`) | USART2 + MAX485 DE/RE, TIM5 the µs clock | A2 TX (DI), A3 RX (RO), A1 DE+/RE |
//! | C axis (azimuth rotation γ) H-bridge IN1–IN4 | GPIO push-pull | A4, A5, A6, A7 |
//! | A axis (tilt α) H-bridge IN1–IN4 | GPIO push-pull | B12, B13, B14, B15 |
//! | C home switch (low end, to GND, pull-up) | GPIO input | B0 |
//! | C max-end limit switch (to GND, pull-up) | GPIO input | B1 |
//! | A home switch (low end, to GND, pull-up) | GPIO input | B8 |
//! | A max-end limit switch (to GND, pull-up) | GPIO input | B9 |
//! | anemometer reed contact (to GND, pull-up; falling edge) | EXTI8 | A8 |
//! | snow switch or sensor contact (to GND when snow, pull-up) | GPIO input | B5 |
//! | hail warning contact (to GND while a warning is on, pull-up) | GPIO input | B10 |
//! | plant stow contact (active level `stow.external_active`; pull-up) | GPIO input | B3 (SWO, unused by SWD) |
//! | debug probe (ST-Link, CMSIS-DAP) | SWD | A13 SWDIO, A14 SWCLK |
//!
//! Wiring sketch (one axis; the A axis is the same on B12–B15, B8, B9):
//!
//! ```text
//!  A4 ─ IN1 ┐                ┌ OUT1 ─ coil A+
//!  A5 ─ IN2 ├ L298N H-bridge ┤ OUT2 ─ coil A−      200-step motor
//!  A6 ─ IN3 │  (+12 V motor, │ OUT3 ─ coil B+      → 50:1 worm → C axis
//!  A7 ─ IN4 ┘   GND to G)    └ OUT4 ─ coil B−
//!  B0 ─ home switch (closed at the low stop) ─ GND
//!  B1 ─ limit switch (closed at the high stop) ─ GND
//!  B6/B7 ─ SCL/SDA ─ DS3231 · QMC5883L · ADXL345 (3.3 V modules, 4.7 kΩ pull-ups to 3V3)
//!  A10 ─ GPS TX (3.3 V)         A8 ─ anemometer reed ─ GND
//!  A2 ─ DI ┐                    ┌ A ─ inclinometer A (RS-485 +)
//!  A3 ─ RO ├ MAX485 (3.3 V part)┤
//!  A1 ─ DE+/RE (tied together)  └ B ─ inclinometer B (RS-485 −)
//!  A11 ─ RX ┐ USB-serial adapter (3.3 V, 115200 8N1):
//!  A12 ─ TX ├ log out on A11, console lines in on A12
//!  GND ─ GND┘
//! ```
//!
//! A11 and A12 are also the F411's USB OTG FS pins (DM, DP), wired to the
//! board's USB-C socket: while the adapter is on them, power the board
//! from a USB charger or the 5V pin, not from a computer's USB port (whose
//! data lines would load the serial lines). USART6 has no other pins on
//! the 48-pin part (its PC6/PC7 are not bonded out).
//!
//! Clocks: the 25 MHz HSE through the PLL to a 100 MHz system clock (the
//! part's maximum; APB1 50 MHz). SysTick interrupts every millisecond: the
//! loop's monotonic clock and the latest wake-up from `wfi`. TIM5 is the
//! microsecond delay of the Modbus master's byte timeouts. The independent
//! watchdog (LSI, about 2 s; stopped while a debugger halts the core) is
//! fed only through [`Platform::feed_watchdog`], which the loop calls only
//! while its ticks come on time.
//!
//! Console: the configuration console of [`suntracker::console`] on the log's
//! port. The USART6 RXNE interrupt moves each byte typed into a
//! [`CONSOLE_RING_LEN`]-byte ring, which [`Platform::console_read`] hands
//! the loop (16 bytes a pass, a pass at least every millisecond: faster
//! than 115200 baud brings them); the replies go out on the log. Bytes the
//! ring had no room for, or the USART lost, are counted.
//!
//! Configuration storage: flash sectors 1 and 2 (16 KiB each at
//! 0x0800_4000 and 0x0800_8000), one slot each, through
//! [`crate::flash::ConfigSectors`]; boards/stm32f411/memory.x
//! keeps code out of them (`.text` from sector 3), and this module links
//! against that map's `_config_flash_start` / `_config_flash_end` and
//! checks them against the sectors' addresses at boot (storage off, with
//! a log line, should they differ). At boot the stored configuration is
//! loaded: a good copy the controller takes is used (`config
//! source=stored`), else the board's own ([`mechanics::config`], `config
//! source=defaults`). A `save` erases one sector, which stalls the CPU for
//! up to 800 ms (see [`suntracker::persist`]): the storage says so
//! ([`suntracker::persist::NorFlashStorage::in_code_flash`]), and the loop
//! erases only while both axes rest, so a `save` typed during a move is
//! done after it.
//!
//! With the `defmt` feature the log lines go out over RTT through defmt
//! (`defmt_log::DefmtLog`, a debug probe reads them) instead of
//! USART6 TX; the console still reads USART6 RX (A12).
//!
//! GPS reception is interrupt-driven: the USART1 RXNE interrupt moves each
//! byte into a 512-byte ring (half a second of NMEA at 9600 baud, several
//! times the longest tick), which [`GpsUart`] serves as
//! `embedded_io::{Read, ReadReady}`; no byte is lost while the loop sleeps
//! or ticks. Bytes the ring had no room for, and bytes the USART lost
//! (overrun, framing, noise, parity), are counted ([`GpsUart::dropped`]).
//!
//! Drives: 200 full steps per motor turn, full-step (two-phase-on)
//! sequence, 50:1 worm gear: 10,000 steps per axis turn, 0.036° a step;
//! 2°/s at most (56 steps/s) with a 100 steps/s² ramp from 20 steps/s, as on
//! the Arduino Mega. The C axis turns −180…+180° from its home switch at
//! −180°, the A axis −90…+90° from its home at −90°. The home switch is also
//! the driver's low-end limit (one input read by both); the max-end switch
//! stops the driver at the high end. Open loop (no encoder): homed at
//! power-on and at every end of day.
//!
//! **Every kind of axis** (feature `dc`, `cargo board-run-dc`): each axis
//! of the kind its configuration names, in place of the RS-485
//! inclinometer: a DC gear motor or slew drive on an IBT-2 bridge closed
//! on its Hall encoder or moved by time, a linear actuator on the bridge
//! closed on its Hall pulses or its potentiometer, a continuous servo on
//! its encoder, or a stepper on this image's pins (pins and figures in the
//! `dc` module, `src/dc.rs`).
//!
//! **The Modbus server** (feature `modbus`, `cargo board-run-modbus`): the
//! transceiver on USART2 serves the SunSpec map of
//! [`suntracker::sunspec::ModbusPort`] (models 1, 601, 305 and the vendor
//! model) to the plant's SCADA instead of polling the WitMotion
//! inclinometer: the three USARTs are taken (GPS, console, RS-485), so that
//! image's tilt comes from the ADXL345. The loop serves the port after each
//! pass; the replies go out by interrupts (`modbus_line`).
//!
//! Attitude sensors, probed at power-on, in this order: the WitMotion
//! inclinometer (one Modbus read of roll and pitch at address 0x50 over
//! RS-485; up to 100 ms when nothing answers), then an ADXL345 on I²C
//! (device ID 0xE5); the QMC5883L compass (chip ID 0xFF). With a tilt sensor
//! and the compass the mount's attitude is measured every tick (after Choi
//! et al., portable tracker) with the WMM2025 declination of the site in use;
//! else a level mount facing north is assumed and fault `timeout_inclinometer`
//! says so. The log then says which sensors answered.
//!
//! There is no simulated clock: without a trusted time (a DS3231 that lost
//! power or reads outside the firmware's window, and no GPS fix) the loop
//! waits stowed (`mode wait_for_time`).
#![no_std]

#[cfg(all(feature = "dc", feature = "modbus"))]
compile_error!("the `dc` and `modbus` features both take USART2's pins (A1-A3): build one of them");

#[cfg(feature = "dc")]
pub mod dc;
#[cfg(feature = "defmt")]
mod defmt_log;
pub mod flash;
mod mem;
#[cfg(feature = "modbus")]
pub mod modbus_line;

use core::cell::{Cell, RefCell};
use core::convert::Infallible;
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::interrupt::{free, Mutex};
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::NVIC;
use cortex_m_rt::exception;
use drivers::compass::calibration::Calibration;
use drivers::compass::qmc5883l::{Config as QmcConfig, Qmc5883l};
use drivers::rtc::Ds3231;
#[cfg(not(feature = "dc"))]
use drivers::stepper::hbridge::{BridgePins, HBridgeStepper};
#[cfg(not(feature = "dc"))]
use drivers::stepper::LimitSwitches;
use drivers::tilt::adxl345::Adxl345;
#[cfg(not(any(feature = "modbus", feature = "dc")))]
use drivers::tilt::modbus::Timeout;
#[cfg(not(any(feature = "modbus", feature = "dc")))]
use drivers::tilt::witmotion::{WitInclinometer, DEFAULT_ADDRESS as WIT_ADDRESS};
use embedded_hal_bus::i2c::AtomicDevice;
use embedded_hal_bus::util::AtomicCell;
use stm32f4xx_hal as hal;

use hal::gpio::{Edge, ErasedPin, ExtiPin, Input, PA8};
#[cfg(not(any(feature = "modbus", feature = "dc")))]
use hal::gpio::{Output, PA1};
use hal::i2c::{I2c, Mode as I2cMode};
use hal::pac::{self, interrupt, Interrupt};
use hal::prelude::*;
use hal::rcc::Config as RccConfig;
#[cfg(not(any(feature = "modbus", feature = "dc")))]
use hal::serial::Serial;
#[cfg(not(feature = "defmt"))]
use hal::serial::Tx;
use hal::serial::{Rx, RxListen};
#[cfg(not(any(feature = "modbus", feature = "dc")))]
use hal::timer::DelayUs;
use hal::watchdog::IndependentWatchdog;

use crate::flash::{ConfigSectors, SECTOR_LEN, WINDOW_OFFSET};
use suntracker::config::Config;
use suntracker::console::RxRing;
use suntracker::controller::Controller;
use suntracker::firmware::{AppConfig, ConfigPersist, Firmware, Platform};
#[cfg(not(any(feature = "modbus", feature = "dc")))]
use suntracker::hw::EitherTilt;
use suntracker::hw::MountSensorsHw;
#[cfg(not(feature = "dc"))]
use suntracker::hw::StepperAxis;
use suntracker::log::Sink;
use suntracker::mechanics;
#[cfg(not(feature = "dc"))]
use suntracker::mechanics::bridge_config;
use suntracker::motion::AxisDrive;
use suntracker::persist::{ConfigStore, NorFlashStorage};
use suntracker::ports::AttitudeSensor;
use suntracker::safety::StowInputs;
use suntracker::sun::BoardSource;
#[cfg(feature = "modbus")]
use suntracker::sunspec::ModbusPort;
#[cfg(feature = "modbus")]
use suntracker_modbus::sunspec::Identity;

/// Board name in the boot line.
pub const BOARD: &str = "stm32f411";
/// The Black Pill's crystal.
pub const HSE_HZ: u32 = 25_000_000;
/// System clock.
pub const SYSCLK_HZ: u32 = 100_000_000;
/// Log serial.
pub const LOG_BAUD_HZ: u32 = 115_200;
/// GPS receivers' default rate (NEO-6M and kin).
pub const GPS_BAUD_HZ: u32 = 9_600;
/// The WitMotion inclinometer's factory rate.
pub const INCLINOMETER_BAUD_HZ: u32 = 9_600;
/// ADXL345 address with SDO low (datasheet "Serial Communications", I²C).
pub const ADXL345_ADDRESS: u8 = 0x53;
/// Independent watchdog timeout.
pub const WATCHDOG_MS: u32 = 2_000;
/// Day-table capacity: Jimoh & Aliyu's (2019) 4-minute table of a polar day,
/// both solar midnights included: 1440 / 4 + 1 = 361 entries
/// (`capacity_for_interval`). 360 refused every polar day whose solar
/// midnight falls on a 4-minute step (a whole-degree longitude: 90° N 0° E
/// in June) with `schedule_failed`.
pub const TABLE_LEN: usize = sun_algos::geometry::day_table::capacity_for_interval(4);
/// GPS receive ring, bytes.
pub const GPS_RING_LEN: usize = 512;
/// Console receive ring, bytes: three lines of the longest
/// ([`suntracker::console::LINE_LEN`]) pasted at once, or 22 ms at 115200 baud
/// while a long pass (a day plan's step) keeps the loop away.
pub const CONSOLE_RING_LEN: usize = 256;
/// Model 1's and model 601's names of the `modbus` image.
#[cfg(feature = "modbus")]
const MODBUS_IDENTITY: Identity<'static> = Identity {
    manufacturer: "suntracker",
    model: BOARD,
    options: "blackpill",
    version: env!("CARGO_PKG_VERSION"),
    serial: "0",
    controller_name: "suntracker",
    tracker_name: "tracker-1",
};

/// USART2's frame for the Modbus server: `baud`, and `parity` (the
/// configuration's code: 0 none, 1 odd, 2 even) with one stop bit in the
/// 9-bit word (8 data bits and the parity bit), or none with two stop bits
/// (Modbus over Serial Line §2.5.1; RM0383 §19.3.7 "Parity control").
#[cfg(feature = "modbus")]
fn modbus_serial_config(baud: u32, parity: u8) -> hal::serial::Config {
    use hal::serial::config::StopBits;
    let config = hal::serial::Config::default().baudrate(baud.bps());
    match parity {
        0 => config
            .parity_none()
            .wordlength_8()
            .stopbits(StopBits::STOP2),
        1 => config.parity_odd().wordlength_9(),
        _ => config.parity_even().wordlength_9(),
    }
}

/// The drive kinds this image builds an axis of: steppers, or with the
/// `dc` feature every kind (`dc::DRIVES`).
#[cfg(not(feature = "dc"))]
pub const DRIVES: suntracker::config::DriveSet = suntracker::config::DriveSet::STEPPER;
#[cfg(feature = "dc")]
pub use dc::DRIVES;

/// The board's own configuration: Li et al.'s (2022) mechanics (steppers),
/// or with the `dc` feature the same axes on worm slew drives
/// ([`mechanics::worm_slew_config`]).
#[cfg(not(feature = "dc"))]
use mechanics::config as board_config;
#[cfg(feature = "dc")]
use mechanics::worm_slew_config as board_config;

/// One axis of this image: a stepper on its H-bridge, or with the `dc`
/// feature any kind (`dc::BlackPillAxis`).
#[cfg(not(feature = "dc"))]
type Axis<'a> = StepperAxis<hal::gpio::ErasedPin<hal::gpio::Output>, Switch<'a>, Switch<'a>>;
#[cfg(feature = "dc")]
type Axis<'a> = dc::BlackPillAxis<'a>;

/// Start of the flash (RM0383 §2.3 "Memory map"; the configuration
/// sectors are at offsets from it).
const FLASH_BASE: usize = 0x0800_0000;

// ---------------------------------------------------------------------------
// Interrupt-side state: each static is shared with one handler only.

/// Milliseconds since SysTick started (one increment per interrupt).
static MILLIS: Mutex<Cell<u64>> = Mutex::new(Cell::new(0));
/// Anemometer falling edges since the last [`Platform::take_wind_pulses`].
static WIND_PULSES: AtomicU32 = AtomicU32::new(0);
/// The anemometer input, for its EXTI pending bit.
static WIND_PIN: Mutex<RefCell<Option<PA8<Input>>>> = Mutex::new(RefCell::new(None));
/// The GPS receiver, owned by its interrupt handler once set up.
static GPS_RX: Mutex<RefCell<Option<Rx<pac::USART1>>>> = Mutex::new(RefCell::new(None));
/// Received GPS bytes not yet read by the loop.
static GPS_RING: Mutex<RefCell<RxRing<GPS_RING_LEN>>> = Mutex::new(RefCell::new(RxRing::new()));
/// The console's receiver (USART6 RX), owned by its interrupt handler once
/// set up.
static CONSOLE_RX: Mutex<RefCell<Option<Rx<pac::USART6>>>> = Mutex::new(RefCell::new(None));
/// Bytes typed on the console not yet read by the loop.
static CONSOLE_RING: Mutex<RefCell<RxRing<CONSOLE_RING_LEN>>> =
    Mutex::new(RefCell::new(RxRing::new()));

/// Most bytes one receive interrupt takes (the USART holds one; a few more
/// may arrive while the handler runs).
const RX_BURST: u32 = 8;

/// Moves what a USART has received into its ring.
fn receive<R, const N: usize>(rx: &Mutex<RefCell<Option<R>>>, ring: &Mutex<RefCell<RxRing<N>>>)
where
    R: hal::prelude::_embedded_hal_serial_nb_Read<u8>,
{
    free(|cs| {
        // Never borrowed elsewhere inside a critical section: the
        // `try_` forms only keep the panicking paths out.
        let (Ok(mut rx), Ok(mut ring)) = (
            rx.borrow(cs).try_borrow_mut(),
            ring.borrow(cs).try_borrow_mut(),
        ) else {
            return;
        };
        let Some(rx) = rx.as_mut() else {
            return;
        };
        for _ in 0..RX_BURST {
            match hal::prelude::_embedded_hal_serial_nb_Read::read(rx) {
                Ok(byte) => ring.push(byte),
                Err(hal::nb::Error::WouldBlock) => break,
                // The HAL read the data register, which clears the error
                // flag; the byte is lost.
                Err(hal::nb::Error::Other(_)) => ring.lose(),
            }
        }
    });
}

/// Moves the received GPS bytes into the ring.
// The vector binding of `#[interrupt]` is an `#[export_name]` item, which
// the `unsafe_code` lint counts; the handler itself has no unsafe code.
#[allow(unsafe_code)]
#[interrupt]
fn USART1() {
    receive(&GPS_RX, &GPS_RING);
}

/// Moves the bytes typed on the console into its ring.
// `#[export_name]` binding, as for `USART1`.
#[allow(unsafe_code)]
#[interrupt]
fn USART6() {
    receive(&CONSOLE_RX, &CONSOLE_RING);
}

/// Counts an anemometer pulse.
// `#[export_name]` binding, as for `USART1`.
#[allow(unsafe_code)]
#[interrupt]
fn EXTI9_5() {
    free(|cs| {
        if let Ok(mut pin) = WIND_PIN.borrow(cs).try_borrow_mut() {
            if let Some(pin) = pin.as_mut() {
                if pin.check_interrupt() {
                    pin.clear_interrupt_pending_bit();
                    WIND_PULSES.fetch_add(1, Ordering::Relaxed);
                }
            }
        }
    });
    // The C axis's Hall channel A (A9) shares the handler.
    #[cfg(feature = "dc")]
    dc::on_exti9();
}

/// The millisecond clock.
// `#[export_name]` binding, as for `USART1`.
#[allow(unsafe_code)]
#[exception]
fn SysTick() {
    free(|cs| {
        let ms = MILLIS.borrow(cs);
        ms.set(ms.get().wrapping_add(1));
    });
}

// defmt frames carry the millisecond clock (with the `defmt` feature).
#[cfg(feature = "defmt")]
defmt::timestamp!("{=u64:ms}", free(|cs| MILLIS.borrow(cs).get()));

// ---------------------------------------------------------------------------
// The loop's parts.

/// The GPS port: USART1's receive ring as `embedded_io`.
#[derive(Debug)]
pub struct GpsUart {
    _private: (),
}

impl GpsUart {
    /// Bytes lost so far: ring full, or a receive error (overrun, framing,
    /// noise, parity).
    pub fn dropped(&self) -> u32 {
        free(|cs| {
            GPS_RING
                .borrow(cs)
                .try_borrow()
                .map_or(0, |ring| u32::from(ring.dropped()))
        })
    }
}

impl embedded_io::ErrorType for GpsUart {
    type Error = Infallible;
}

impl embedded_io::ReadReady for GpsUart {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(free(|cs| {
            GPS_RING
                .borrow(cs)
                .try_borrow()
                .is_ok_and(|ring| !ring.is_empty())
        }))
    }
}

impl embedded_io::Read for GpsUart {
    /// Takes what the ring holds; with nothing there, sleeps until a byte
    /// arrives (the loop asks `read_ready` first and never waits here).
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        if buf.is_empty() {
            return Ok(0);
        }
        loop {
            let n = free(|cs| {
                GPS_RING
                    .borrow(cs)
                    .try_borrow_mut()
                    .map_or(0, |mut ring| ring.pop_into(buf))
            });
            if n > 0 {
                return Ok(n);
            }
            cortex_m::asm::wfi();
        }
    }
}

/// Bytes typed on the console that were lost so far: ring full, or a
/// receive error (overrun, framing, noise, parity).
pub fn console_dropped() -> u32 {
    free(|cs| {
        CONSOLE_RING
            .borrow(cs)
            .try_borrow()
            .map_or(0, |ring| u32::from(ring.dropped()))
    })
}

/// The log: USART6's transmit side, blocking byte by byte (87 µs a byte at
/// 115200 baud).
#[cfg(not(feature = "defmt"))]
pub struct LogUart(Tx<pac::USART6>);

/// The log sink of this build: USART6 TX, or defmt over RTT with the
/// `defmt` feature.
#[cfg(not(feature = "defmt"))]
pub type Log = LogUart;
/// The log sink of this build: USART6 TX, or defmt over RTT with the
/// `defmt` feature.
#[cfg(feature = "defmt")]
pub type Log = crate::defmt_log::DefmtLog;

#[cfg(not(feature = "defmt"))]
impl Sink for LogUart {
    fn put(&mut self, bytes: &[u8]) {
        for &b in bytes {
            // The only error of a transmit is none (it waits for TXE).
            let _ = hal::block!(hal::prelude::_embedded_hal_serial_nb_Write::write(
                &mut self.0,
                b
            ));
        }
    }
}

/// USART2 for the Modbus master, which drives the RS-485 direction pin
/// itself and waits for `flush` (transmission complete) before releasing
/// the bus.
#[cfg(not(any(feature = "modbus", feature = "dc")))]
pub struct Rs485 {
    serial: Serial<pac::USART2>,
}

#[cfg(not(any(feature = "modbus", feature = "dc")))]
impl embedded_io::ErrorType for Rs485 {
    type Error = hal::serial::Error;
}

#[cfg(not(any(feature = "modbus", feature = "dc")))]
impl embedded_io::Read for Rs485 {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        let Some(first) = buf.first_mut() else {
            return Ok(0);
        };
        *first = hal::block!(hal::prelude::_embedded_hal_serial_nb_Read::read(
            &mut self.serial
        ))?;
        Ok(1)
    }
}

#[cfg(not(any(feature = "modbus", feature = "dc")))]
impl embedded_io::ReadReady for Rs485 {
    fn read_ready(&mut self) -> Result<bool, Self::Error> {
        use hal::serial::RxISR;
        Ok(self.serial.is_rx_not_empty())
    }
}

#[cfg(not(any(feature = "modbus", feature = "dc")))]
impl embedded_io::Write for Rs485 {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        let Some(&first) = buf.first() else {
            return Ok(0);
        };
        hal::block!(hal::prelude::_embedded_hal_serial_nb_Write::write(
            &mut self.serial,
            first
        ))?;
        Ok(1)
    }
    fn flush(&mut self) -> Result<(), Self::Error> {
        embedded_io::Write::flush(&mut self.serial)
    }
}

/// A switch input read through a shared reference: the home switch is both
/// the axis's homing input and its driver's low-end limit.
#[derive(Clone, Copy)]
pub struct Switch<'a>(&'a ErasedPin<Input>);

impl embedded_hal::digital::ErrorType for Switch<'_> {
    type Error = Infallible;
}

impl embedded_hal::digital::InputPin for Switch<'_> {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(self.0.is_high())
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        Ok(self.0.is_low())
    }
}

/// The shared I²C bus. `AtomicDevice` rather than `RefCellDevice`: a
/// second user while the bus is taken gets an error, not a panic (there is
/// none: only the main loop talks I²C).
type Bus<'a> = AtomicDevice<'a, I2c<pac::I2C1>>;
/// The RS-485 inclinometer.
#[cfg(not(any(feature = "modbus", feature = "dc")))]
type Inclinometer = WitInclinometer<Rs485, PA1<Output>, DelayUs<pac::TIM5>>;
/// Whichever tilt sensor answered.
#[cfg(not(any(feature = "modbus", feature = "dc")))]
type Tilt<'a> = EitherTilt<Inclinometer, Adxl345<Bus<'a>>>;
/// The tilt sensor: USART2's transceiver serves the plant's Modbus bus.
#[cfg(any(feature = "modbus", feature = "dc"))]
type Tilt<'a> = Adxl345<Bus<'a>>;

/// The configuration's storage: flash sectors 1 and 2.
type Store = ConfigStore<NorFlashStorage<ConfigSectors>>;

/// Monotonic clock, anemometer, watchdog, sleep, console and configuration
/// storage of the board.
struct BlackPillPlatform {
    watchdog: IndependentWatchdog,
    store: Option<Store>,
    /// Snow (B5), hail (B10), the plant's stow contact (B3).
    stow_pins: [ErasedPin<Input>; 3],
}

impl Platform for BlackPillPlatform {
    fn console_read(&mut self, buf: &mut [u8]) -> usize {
        free(|cs| {
            CONSOLE_RING
                .borrow(cs)
                .try_borrow_mut()
                .map_or(0, |mut ring| ring.pop_into(buf))
        })
    }
    fn console_lost_lines(&mut self) -> u8 {
        free(|cs| {
            CONSOLE_RING
                .borrow(cs)
                .try_borrow_mut()
                .map_or(0, |mut ring| ring.take_lost_lines())
        })
    }
    fn config_store(&mut self) -> Option<&mut dyn ConfigPersist> {
        self.store.as_mut().map(|s| s as &mut dyn ConfigPersist)
    }
    fn now_ms(&mut self) -> u64 {
        free(|cs| MILLIS.borrow(cs).get())
    }
    fn take_wind_pulses(&mut self) -> u32 {
        WIND_PULSES.swap(0, Ordering::Relaxed)
    }
    fn stow_inputs(&mut self) -> StowInputs {
        // Snow and hail are contacts closing to ground: on while low. The
        // plant's contact is passed as its level (the configuration says
        // which one is active).
        let [snow, hail, plant] = &self.stow_pins;
        StowInputs {
            snow: Some(snow.is_low()),
            hail: Some(hail.is_low()),
            external_high: Some(plant.is_high()),
            // No supply divider nor pyranometer on this board's pins yet:
            // the supply watch and the overcast mode are off.
            supply_mv: None,
            irradiance_w_m2: None,
        }
    }
    fn feed_watchdog(&mut self) {
        self.watchdog.feed();
    }
    fn wait_for_interrupt(&mut self) {
        // SysTick wakes the core every millisecond at the latest.
        cortex_m::asm::wfi();
    }
}

/// Starts the tracker on the board's peripherals; never returns. Should the
/// controller refuse the board's own configuration (it does not), the log
/// says so and the board stops feeding the watchdog, which resets it.
pub fn run(dp: pac::Peripherals, cp: cortex_m::Peripherals) -> ! {
    let mut rcc = dp
        .RCC
        .freeze(RccConfig::hse(HSE_HZ.Hz()).sysclk(SYSCLK_HZ.Hz()));
    let gpioa = dp.GPIOA.split(&mut rcc);
    let gpiob = dp.GPIOB.split(&mut rcc);

    // The millisecond clock first: everything after may wait on it.
    let mut syst = cp.SYST;
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(rcc.clocks.hclk().raw() / 1000 - 1);
    syst.clear_current();
    syst.enable_counter();
    syst.enable_interrupt();

    // USART6: the log out on TX, the console in on RX (its interrupt
    // filling the console ring).
    let (log_tx, mut console_rx) =
        match dp
            .USART6
            .serial((gpioa.pa11, gpioa.pa12), LOG_BAUD_HZ.bps(), &mut rcc)
        {
            Ok(serial) => serial.split(),
            // 115200 baud from a 100 MHz APB2 is always valid.
            Err(_) => loop {
                cortex_m::asm::wfi();
            },
        };
    #[cfg(not(feature = "defmt"))]
    let mut log: Log = LogUart(log_tx);
    // The log goes over RTT; USART6 TX stays idle (high).
    #[cfg(feature = "defmt")]
    let _ = log_tx;
    #[cfg(feature = "defmt")]
    let mut log: Log = crate::defmt_log::DefmtLog::new();
    console_rx.listen();
    free(|cs| {
        if let Ok(mut slot) = CONSOLE_RX.borrow(cs).try_borrow_mut() {
            *slot = Some(console_rx);
        }
    });

    // From here on a hang (a stuck bus) resets the board.
    let mut watchdog = IndependentWatchdog::new(dp.IWDG);
    watchdog.stop_on_debug(&dp.DBGMCU, true);
    watchdog.start(WATCHDOG_MS.millis());

    // GPS: USART1 receive, its interrupt filling the ring.
    let mut gps_rx = match dp.USART1.rx(gpioa.pa10, GPS_BAUD_HZ.bps(), &mut rcc) {
        Ok(rx) => rx,
        Err(_) => halt(&mut log, "USART1 configuration refused"),
    };
    gps_rx.listen();
    free(|cs| {
        if let Ok(mut slot) = GPS_RX.borrow(cs).try_borrow_mut() {
            *slot = Some(gps_rx);
        }
    });

    // Anemometer: falling edges of A8 on EXTI8.
    let mut syscfg = dp.SYSCFG.constrain(&mut rcc);
    let mut exti = dp.EXTI;
    let mut wind = gpioa.pa8.into_pull_up_input();
    wind.make_interrupt_source(&mut syscfg);
    wind.trigger_on_edge(&mut exti, Edge::Falling);
    wind.enable_interrupt(&mut exti);
    wind.clear_interrupt_pending_bit();
    free(|cs| {
        if let Ok(mut slot) = WIND_PIN.borrow(cs).try_borrow_mut() {
            *slot = Some(wind);
        }
    });

    // SAFETY: unmasking cannot break a critical section (they disable all
    // interrupts with PRIMASK, not NVIC masks); the three handlers touch
    // only their statics above, through `free`, and those are set.
    #[allow(unsafe_code)]
    unsafe {
        NVIC::unmask(Interrupt::USART1);
        NVIC::unmask(Interrupt::USART6);
        NVIC::unmask(Interrupt::EXTI9_5);
    }

    // Motors and switches (the DC image's follow its configuration,
    // below).
    #[cfg(not(feature = "dc"))]
    let c_home = gpiob.pb0.into_pull_up_input().erase();
    let a_home = gpiob.pb8.into_pull_up_input().erase();
    // The DC image's bridge and stepper outputs low at once (`DcPinsIn`):
    // its axes take them as their kinds name once the configuration is
    // read (below).
    #[cfg(feature = "dc")]
    let dc_pins_in = dc::DcPinsIn {
        pa0: gpioa.pa0,
        pa1: gpioa.pa1,
        pa2: gpioa.pa2.into_push_pull_output(),
        pa3: gpioa.pa3.into_push_pull_output(),
        pa4: gpioa.pa4.into_push_pull_output(),
        pa5: gpioa.pa5.into_push_pull_output(),
        pa6: gpioa.pa6.into_push_pull_output(),
        pa7: gpioa.pa7.into_push_pull_output(),
        pa9: gpioa.pa9,
        pa15: gpioa.pa15,
        pb1: gpiob.pb1,
        pb4: gpiob.pb4,
        pb12: gpiob.pb12.into_push_pull_output(),
        pb13: gpiob.pb13.into_push_pull_output(),
        pb14: gpiob.pb14,
        pb15: gpiob.pb15.into_push_pull_output(),
    };
    #[cfg(not(feature = "dc"))]
    let c_max = gpiob.pb1.into_pull_up_input().erase();
    #[cfg(not(feature = "dc"))]
    let a_max = gpiob.pb9.into_pull_up_input().erase();
    #[cfg(not(feature = "dc"))]
    let c_pins = BridgePins {
        in1: gpioa.pa4.into_push_pull_output().erase(),
        in2: gpioa.pa5.into_push_pull_output().erase(),
        in3: gpioa.pa6.into_push_pull_output().erase(),
        in4: gpioa.pa7.into_push_pull_output().erase(),
    };
    #[cfg(not(feature = "dc"))]
    let a_pins = BridgePins {
        in1: gpiob.pb12.into_push_pull_output().erase(),
        in2: gpiob.pb13.into_push_pull_output().erase(),
        in3: gpiob.pb14.into_push_pull_output().erase(),
        in4: gpiob.pb15.into_push_pull_output().erase(),
    };
    #[cfg(not(feature = "dc"))]
    let c_limits = LimitSwitches {
        min: Some(Switch(&c_home)),
        max: Some(Switch(&c_max)),
        active_low: true,
    };
    #[cfg(not(feature = "dc"))]
    let a_limits = LimitSwitches {
        min: Some(Switch(&a_home)),
        max: Some(Switch(&a_max)),
        active_low: true,
    };
    #[cfg(not(feature = "dc"))]
    let axes = match (
        HBridgeStepper::new(c_pins, c_limits, bridge_config()),
        HBridgeStepper::new(a_pins, a_limits, bridge_config()),
    ) {
        (Ok(c), Ok(a)) => [
            StepperAxis::new(c, Switch(&c_home), true),
            StepperAxis::new(a, Switch(&a_home), true),
        ],
        _ => halt(&mut log, "stepper configuration refused"),
    };
    // The I²C devices on one bus.
    let bus = AtomicCell::new(I2c::new(
        dp.I2C1,
        (gpiob.pb6, gpiob.pb7),
        I2cMode::standard(100.kHz()),
        &mut rcc,
    ));
    let rtc = Ds3231::new(AtomicDevice::new(&bus));
    let compass = Qmc5883l::new(AtomicDevice::new(&bus), QmcConfig::default());

    // The tilt sensor: the RS-485 inclinometer if it answers, else an
    // ADXL345.
    #[cfg(not(any(feature = "modbus", feature = "dc")))]
    let de = gpioa.pa1.into_push_pull_output();
    #[cfg(not(any(feature = "modbus", feature = "dc")))]
    let delay = dp.TIM5.delay_us(&mut rcc);
    #[cfg(not(any(feature = "modbus", feature = "dc")))]
    let mut tilt: Option<Tilt<'_>> = None;
    #[cfg(not(any(feature = "modbus", feature = "dc")))]
    if let Ok(serial) =
        dp.USART2
            .serial((gpioa.pa2, gpioa.pa3), INCLINOMETER_BAUD_HZ.bps(), &mut rcc)
    {
        let mut wit =
            WitInclinometer::new(Rs485 { serial }, de, delay, WIT_ADDRESS, Timeout::default());
        if wit.read().is_ok() {
            log.text("tilt sensor: witmotion rs-485\n");
            tilt = Some(EitherTilt::First(wit));
        }
    }
    #[cfg(not(any(feature = "modbus", feature = "dc")))]
    if tilt.is_none() {
        let mut adxl = Adxl345::new(AtomicDevice::new(&bus), ADXL345_ADDRESS);
        if adxl.init().is_ok() {
            log.text("tilt sensor: adxl345\n");
            tilt = Some(EitherTilt::Second(adxl));
        }
    }
    #[cfg(any(feature = "modbus", feature = "dc"))]
    let tilt: Option<Tilt<'_>> = {
        let mut adxl = Adxl345::new(AtomicDevice::new(&bus), ADXL345_ADDRESS);
        match adxl.init() {
            Ok(()) => {
                log.text("tilt sensor: adxl345\n");
                Some(adxl)
            }
            Err(_) => None,
        }
    };
    let sensors = match (tilt, compass) {
        (Some(tilt), Ok(compass)) => Some(MountSensorsHw::new(
            tilt,
            compass,
            Calibration::IDENTITY,
            0.0,
        )),
        _ => {
            log.text("attitude sensors absent: level mount facing north\n");
            None
        }
    };

    // The configuration: the stored copy when it is good and the
    // controller takes it, else the board's own.
    // Read into the board's own, which stays when no stored copy is good.
    let mut store = config_store(dp.FLASH, &mut log);
    let mut config = board_config();
    let from_store = store
        .as_mut()
        .is_some_and(|s| !s.load_into(&mut config).defaults)
        && config.check_drives(DRIVES).is_ok()
        && controller_takes::<Axis<'_>, _>(&sensors, &config);
    if !from_store {
        config = board_config();
    }
    if config.validate().is_err() {
        halt(&mut log, "configuration refused");
    }
    #[cfg(not(feature = "dc"))]
    let options = mechanics::controller_options();
    #[cfg(feature = "dc")]
    let options = mechanics::options_for_drives(mechanics::controller_options(), &config.axes);
    // The DC image: the bridges' timers and pins, the Hall interrupts and
    // the ADC; each axis as its configuration names.
    #[cfg(feature = "dc")]
    let dc_pins = dc::DcPins::start(
        dc_pins_in,
        dp.TIM3,
        dp.TIM9,
        &mut syscfg,
        &mut exti,
        &mut rcc,
        &config.axes,
    );
    #[cfg(feature = "dc")]
    let c_home = dc::CHomeInput::start(gpiob.pb0, &config.axes[0]);
    #[cfg(feature = "dc")]
    let adc = RefCell::new(dc::Adc1::start(dp.ADC1, &dp.ADC_COMMON, &mut rcc));
    // SAFETY: as for the interrupts above: the Hall handlers touch only
    // their statics (`dc`), through `free`, and those are set.
    #[cfg(feature = "dc")]
    #[allow(unsafe_code)]
    unsafe {
        NVIC::unmask(Interrupt::EXTI4);
        NVIC::unmask(Interrupt::EXTI15_10);
    }

    #[cfg(feature = "dc")]
    let axes = match dc::axes(dc_pins, &c_home, Switch(&a_home), &adc, &config.axes) {
        Some(axes) => axes,
        None => halt(&mut log, "axis configuration refused"),
    };
    let mut platform = BlackPillPlatform {
        watchdog,
        store,
        stow_pins: [
            gpiob.pb5.into_pull_up_input().erase(),
            gpiob.pb10.into_pull_up_input().erase(),
            gpiob.pb3.into_pull_up_input().erase(),
        ],
    };
    // The Modbus server's port, its frame format from the configuration.
    #[cfg(feature = "modbus")]
    let (mut rs485, modbus) = {
        let settings = suntracker::sunspec::settings_of(&config.modbus);
        let modbus = match cortex_m::singleton!(
            : ModbusPort = ModbusPort::new(MODBUS_IDENTITY, true)
        ) {
            Some(port) => port,
            // Taken once: never reached.
            None => halt(&mut log, "Modbus port taken"),
        };
        let serial = match dp.USART2.serial(
            (gpioa.pa2, gpioa.pa3),
            modbus_serial_config(settings.baud, settings.parity),
            &mut rcc,
        ) {
            Ok(serial) => serial,
            Err(_) => halt(&mut log, "USART2 configuration refused"),
        };
        let line = modbus_line::Rs485Server::start(
            serial,
            gpioa.pa1.into_push_pull_output(),
            dp.TIM5.counter_us(&mut rcc),
        );
        // SAFETY: as for the interrupts above: the handler touches only
        // the line's static, through `free`, and it is set.
        #[allow(unsafe_code)]
        unsafe {
            NVIC::unmask(Interrupt::USART2);
        }
        (line, modbus)
    };
    let mut firmware = Firmware::<f32, _, _, _, _, _, TABLE_LEN>::new(
        AppConfig {
            defaults: board_config,
            drives: DRIVES,
            ..AppConfig::new(BOARD)
        },
        config,
        options,
        rtc,
        GpsUart { _private: () },
        axes,
        sensors,
        log,
    );
    // Run it where it is, inside the result: moving it out would copy its
    // kilobytes on the stack.
    match &mut firmware {
        Ok(fw) => {
            fw.log_mut().text(if from_store {
                "config source=stored\n"
            } else {
                "config source=defaults\n"
            });
            #[cfg(not(feature = "modbus"))]
            fw.run(&mut platform);
            #[cfg(feature = "modbus")]
            loop {
                fw.poll(&mut platform);
                let now_ms = platform.now_ms();
                modbus.poll(fw, &mut rs485, now_ms);
                platform.wait_for_interrupt();
            }
        }
        // The board's own configuration was checked above. Nothing is
        // driven; the watchdog, no longer fed, resets the board.
        Err(_) => loop {
            cortex_m::asm::wfi();
        },
    }
}

extern "C" {
    /// boards/stm32f411/memory.x: the first byte of the configuration
    /// sectors (an image without that map does not link).
    static _config_flash_start: u8;
    /// boards/stm32f411/memory.x: the first byte after them.
    static _config_flash_end: u8;
    /// cortex-m-rt (`link.x`): the start of `.text` (`.rodata` and the
    /// `.data` image follow it).
    static __stext: u8;
}

/// The configuration store on flash sectors 1 and 2, when the memory map
/// reserves exactly those sectors and the code lies after them (module
/// docs); `None`, said on the log, otherwise.
fn config_store(flash: pac::FLASH, log: &mut dyn Sink) -> Option<Store> {
    let start = core::ptr::addr_of!(_config_flash_start) as usize;
    let end = core::ptr::addr_of!(_config_flash_end) as usize;
    let text = core::ptr::addr_of!(__stext) as usize;
    let sectors = FLASH_BASE + WINDOW_OFFSET;
    if start != sectors || end != sectors + 2 * SECTOR_LEN || text < end {
        log.text("config storage off: the memory map does not keep flash sectors 1-2 free\n");
        return None;
    }
    match ConfigSectors::storage(flash) {
        Ok(storage) => Some(ConfigStore::new(storage)),
        Err(_) => {
            log.text("config storage off: flash sectors 1-2 refused\n");
            None
        }
    }
}

/// Whether the controller over axes of type `D` and these sensors accepts
/// `config` (the types are the board's; the value only names them).
fn controller_takes<D: AxisDrive, S: AttitudeSensor<f32>>(
    _sensors: &Option<S>,
    config: &Config,
) -> bool {
    Controller::<f32, BoardSource<f32>, D, S, TABLE_LEN>::check(config).is_ok()
}

/// Says why and stops: the watchdog, no longer fed, resets the board.
fn halt(log: &mut dyn Sink, why: &str) -> ! {
    log.text("halt: ");
    log.text(why);
    log.text("\n");
    loop {
        cortex_m::asm::wfi();
    }
}
