//! The Arduino Mega 2560 tracker (Li et al.'s (2022) build): everything about
//! this board in one place — pins, devices, configuration — turned into the
//! parts of [`suntracker::firmware::Firmware`]. An image binds the interrupt vectors
//! (`timer0, usart1, int4`; the log's USART0 only sends) and calls [`run`],
//! as `avr_mega_tracker` does. LLVM reads stack-passed arguments one byte
//! low on this 3-byte-PC chip: a function whose arguments do not all fit
//! the registers (r8–r25) gets garbage (`Site::<f64>::with_elevation` did,
//! and start-up was refused: `halt: site refused`); such functions are
//! inlined. `.ci/avr_codegen_check.py` scans every image for a function
//! reading its stack arguments (only libm's `k_sin` is left, harmless: see
//! the script) and for the other pattern found here, r0 overwritten between
//! a MUL and the read of its product.
//!
//! | function | pin | Mega header |
//! |---|---|---|
//! | log and console, 115200 8N1 | USART0 TXD0/RXD0 (PE1/PE0) | D1/D0 (USB) |
//! | GPS NMEA in, 9600 8N1 | USART1 RXD1/TXD1 (PD2/PD3) | D19/D18 |
//! | I²C 100 kHz: DS3231 0x68, QMC5883L 0x0D, ADXL345 0x53 | SDA/SCL (PD1/PD0) | D20/D21 |
//! | C axis (azimuth rotation γ) H-bridge IN1–IN4 | PA0–PA3 | D22–D25 |
//! | A axis (tilt α) H-bridge IN1–IN4 | PA4–PA7 | D26–D29 |
//! | C home switch (low end, to GND, pull-up) | PC0 | D37 |
//! | A home switch (low end, to GND, pull-up) | PC1 | D36 |
//! | C high-end limit switch (to GND, pull-up) | PC2 | D35 |
//! | A high-end limit switch (to GND, pull-up) | PC3 | D34 |
//! | anemometer reed contact (to GND, pull-up; falling edge) | INT4 (PE4) | D2 |
//! | snow switch or sensor contact (to GND when snow, pull-up) | PC4 | D33 |
//! | hail warning contact (to GND while a warning is on, pull-up) | PC5 | D32 |
//! | plant stow contact (active level `stow.external_active`; pull-up) | PC6 | D31 |
//! | motor supply through a 100 kΩ / 10 kΩ divider (0–55 V) | ADC0 (PF0) | A0 |
//! | horizontal pyranometer or reference cell, amplified to 2 mV per W/m² (0–2.5 V) | ADC1 (PF1) | A1 |
//! | RS-485 transceiver (MAX485 or kin) RO/DI: the Modbus RTU server, `modbus.baud` and `modbus.parity` (19,200 8E1) | USART2 RXD2/TXD2 (PH0/PH1) | D17/D16 |
//! | RS-485 transceiver DE and /RE tied (high while a reply is sent) | PH3 | D6 |
//!
//! Wiring sketch (one axis; the other is the same on the next four pins):
//!
//! ```text
//!  Mega D22 ─ IN1 ┐                ┌ OUT1 ─ coil A+
//!  Mega D23 ─ IN2 ├ L298N H-bridge ┤ OUT2 ─ coil A−      200-step motor
//!  Mega D24 ─ IN3 │  (+12 V motor) │ OUT3 ─ coil B+      → 50:1 worm → C axis
//!  Mega D25 ─ IN4 ┘                └ OUT4 ─ coil B−
//!  Mega D37 ─┬─ home switch (closed at the low stop) ─ GND
//!  Mega D35 ─┴─ limit switch (closed at the high stop) ─ GND
//!  Mega D20/D21 ─ SDA/SCL ─ DS3231 · QMC5883L · ADXL345 (3.3 V modules with level shifters)
//!  Mega D19 ─ GPS TX      Mega D2 ─ anemometer reed ─ GND
//!  Mega D17 ─ RO ┐ MAX485 ┌ A ─ RS-485 bus (the plant's Modbus master)
//!  Mega D16 ─ DI │        │
//!  Mega D6 ─ DE,/RE ┘     └ B
//! ```
//!
//! Each axis is a stepper, a DC gear motor (slew drive), a DC motor moved
//! by time or a linear actuator driven through an IBT-2 (BTS7960) module,
//! or a continuous servo closed on its encoder, as its configuration says
//! (`axis.c.drive`, `axis.a.drive`: [`axes`]; read at power-on). The DC
//! and linear axes' pins, wiring and figures are in [`dc`], the servos'
//! in [`servo`]; a DC axis takes two of its stepper bridge's pins above as
//! its enables. The
//! cargo feature `dc` only changes the board's own configuration (the one
//! `defaults` restores and a board without a saved one runs): both axes
//! DC ([`dc::dc_config`]).
//!
//! Drives and axes: Li et al.'s (2022) mechanics, [`suntracker::mechanics`] (200-step
//! motors, full step, 50:1 worms, 0.036° a step, C −180…+180°, A −90…+90°,
//! homed at the low ends, open loop).
//!
//! The QMC5883L and the ADXL345 are probed at power-on; when both answer,
//! the mount's attitude is measured every 10 s (Choi et al. (portable tracker))
//! with the WMM2025 declination of the site; else a level mount facing
//! north is assumed and fault `timeout_inclinometer` says so.
//!
//! The Modbus RTU server ([`suntracker::sunspec::ModbusPort`], the SunSpec
//! map with model 305: this board has a GPS) is served after each pass of
//! the loop on USART2 ([`suntracker_avr::Rs485`]: bytes stamped in the
//! receive interrupt, the reply sent by interrupts with the driver enable
//! around it). Its baud rate and parity are read at power-on.
#![no_std]

use core::cell::RefCell;

pub mod axes;
pub mod dc;
pub mod servo;

use drivers::compass::calibration::Calibration;
use drivers::compass::qmc5883l::{Config as QmcConfig, Qmc5883l};
use drivers::rtc::Ds3231;
use drivers::tilt::adxl345::Adxl345;

use embedded_hal::digital::InputPin as _;
use suntracker::config::Config;
use suntracker::controller::{ControllerError, ControllerOptions};
use suntracker::firmware::{AppConfig, ConfigPersist, Firmware, Platform, StartError};
use suntracker::hw::MountSensorsHw;
use suntracker::log::Sink;
use suntracker::mechanics;
use suntracker::panel::{Divider, PanelAdc};
use suntracker::persist::{ConfigStore, EepromStorage};
use suntracker::safety::{Reading, StowInputs};
use suntracker::sunspec::ModbusPort;
use suntracker_avr::eeprom::Eeprom;
use suntracker_avr::{
    chip, millis, sleep_until_interrupt, Anemometer, ExtInt, I2c, InputPin, Millis, Parity,
    PortInputPin, Rs485, SharedI2c, Usart0, Usart1, Watchdog, MS_PER_TICK,
};
use suntracker_avr::{Adc, ADC_MAX_CODE};
use suntracker_modbus::sunspec::Identity;

/// Board name in the boot line.
pub const BOARD: &str = "mega2560";
/// Log serial.
pub const LOG_BAUD_HZ: u32 = 115_200;
/// GPS receivers' default rate (NEO-6M and kin).
pub const GPS_BAUD_HZ: u32 = 9_600;
/// ADXL345 address with SDO low (datasheet "Serial Communications", I²C).
pub const ADXL345_ADDRESS: u8 = 0x53;
/// Day-table capacity 0: the real-time scheduler (`suntracker::plan`, after
/// Chowdhury et al. 2019): one sun position per 4-minute slot of Jimoh &
/// Aliyu's (2019) flowchart as it falls due, and the coming sunrise found slot
/// by slot at night. No day table in RAM (960 B at 240 entries) and no event
/// search in flash (18 KB with the table's code); a day of any length, polar
/// days included, is tracked.
pub const TABLE_LEN: usize = 0;
/// Sun positions computed per tick while a day is planned (see `run`).
pub const PLAN_POSITIONS_PER_TICK: u16 = 4;
/// Attitude sensors read every this many ms (see `run`).
pub const ATTITUDE_EVERY_MS: u32 = 10_000;
/// The motor supply's ADC channel (A0).
pub const SUPPLY_CHANNEL: u8 = 0;
/// The pyranometer's ADC channel (A1).
pub const PYRANOMETER_CHANNEL: u8 = 1;
/// The pyranometer's output, mV per W/m² (an amplified sensor: 0–2.5 V for
/// 0–1,250 W/m²; another sensor, another constant).
pub const PYRANOMETER_MV_PER_W_M2: u32 = 2;
/// The pyranometer's ADC: straight to the pin, AVcc reference, 10 bits.
pub const PYRANOMETER_ADC: PanelAdc = PanelAdc {
    vref_mv: 5_000,
    bits: 10,
    divider: Divider {
        r_top_ohm: 0,
        r_bottom_ohm: 1,
    },
};
/// The supply's divider and the ADC in front of it: 100 kΩ over 10 kΩ,
/// AVcc (5 V) reference, 10 bits: 0–55 V, 54 mV a code.
pub const SUPPLY_ADC: PanelAdc = PanelAdc {
    vref_mv: 5_000,
    bits: 10,
    divider: Divider {
        r_top_ohm: 100_000,
        r_bottom_ohm: 10_000,
    },
};

/// Model 1's and model 601's names of this image.
const MODBUS_IDENTITY: Identity<'static> = Identity {
    manufacturer: "suntracker",
    model: BOARD,
    options: "avr",
    version: env!("CARGO_PKG_VERSION"),
    serial: "0",
    controller_name: "suntracker",
    tracker_name: "tracker-1",
};

/// Monotonic clock, anemometer, watchdog, sleep, console input, the
/// weather contacts and the configuration's EEPROM of the board.
struct MegaPlatform<'p> {
    _millis: Millis,
    anemometer: Anemometer,
    /// Snow (PC4), hail (PC5), the plant's stow contact (PC6).
    stow_pins: [PortInputPin<'p, chip::PORTC>; 3],
    /// The ADC, the channel its conversion runs on, and the last readings
    /// of the supply and the pyranometer.
    /// Shared with the DC axes' current sense.
    adc: &'p RefCell<Adc>,
    adc_channel: u8,
    supply: Option<Reading>,
    irradiance: Option<Reading>,
    watchdog: Watchdog,
    cpu: chip::CPU,
    store: ConfigStore<EepromStorage<Eeprom>>,
}

impl Platform for MegaPlatform<'_> {
    fn console_read(&mut self, buf: &mut [u8]) -> usize {
        Usart0::take_received(buf)
    }
    fn console_lost_lines(&mut self) -> u8 {
        Usart0::take_lost_lines()
    }
    fn config_store(&mut self) -> Option<&mut dyn ConfigPersist> {
        Some(&mut self.store)
    }
    fn now_ms(&mut self) -> u64 {
        millis()
    }
    fn take_wind_pulses(&mut self) -> u32 {
        u32::from(self.anemometer.take_pulses())
    }
    fn stow_inputs(&mut self) -> StowInputs {
        // Snow and hail are contacts closing to ground: on while low. The
        // plant's contact is passed as its level (the configuration says
        // which one is active).
        let [snow, hail, plant] = &mut self.stow_pins;
        // Never held here: the motors' sense reads it inside the pass's
        // drive service only.
        let Ok(mut adc) = self.adc.try_borrow_mut() else {
            return StowInputs {
                snow: snow.is_low().ok(),
                hail: hail.is_low().ok(),
                external_high: plant.is_high().ok(),
                supply_mv: self.supply,
                irradiance_w_m2: self.irradiance,
            };
        };
        // The supply and the pyranometer in turn: the conversion started a
        // tick ago read, the other channel's started (neither waits). A
        // supply code at a rail is no supply's; the pyranometer's output
        // never reaches full scale (2.5 V of 5).
        if let Some(code) = adc.poll() {
            let reading = |v: Option<u32>| match v {
                Some(v) if code != ADC_MAX_CODE => {
                    Reading::Value(u16::try_from(v).unwrap_or(u16::MAX))
                }
                _ => Reading::Impossible,
            };
            if self.adc_channel == SUPPLY_CHANNEL {
                let mv = SUPPLY_ADC.panel_mv(code).ok().filter(|_| code != 0);
                self.supply = Some(reading(mv));
            } else {
                let mv = PYRANOMETER_ADC.panel_mv(code).ok();
                self.irradiance = Some(reading(mv.map(|mv| mv / PYRANOMETER_MV_PER_W_M2)));
            }
        }
        self.adc_channel = if self.adc_channel == SUPPLY_CHANNEL {
            PYRANOMETER_CHANNEL
        } else {
            SUPPLY_CHANNEL
        };
        let _ = adc.start(self.adc_channel);
        StowInputs {
            snow: snow.is_low().ok(),
            hail: hail.is_low().ok(),
            external_high: plant.is_high().ok(),
            supply_mv: self.supply,
            irradiance_w_m2: self.irradiance,
        }
    }
    fn feed_watchdog(&mut self) {
        self.watchdog.feed();
    }
    fn wait_for_interrupt(&mut self) {
        sleep_until_interrupt(&self.cpu);
    }
}

/// Starts the tracker on the board's peripherals; never returns. A
/// configuration the controller refuses (none: it is the board's own) is
/// reported on the log and the board then only feeds nothing: the watchdog
/// resets it.
pub fn run(dp: chip::Peripherals) -> ! {
    let chip::Peripherals {
        USART0,
        USART1,
        USART2,
        TC0,
        TC5,
        WDT,
        CPU,
        PORTA,
        PORTC,
        PORTE,
        PORTH,
        EXINT,
        TWI,
        EEPROM,
        ADC,
        TC1,
        TC3,
        TC4,
        PORTB,
        PORTK,
        ..
    } = dp;
    run_tracker(Parts {
        usart0: USART0,
        usart1: USART1,
        usart2: USART2,
        tc0: TC0,
        tc5: TC5,
        wdt: WDT,
        cpu: CPU,
        porta: PORTA,
        portc: PORTC,
        porte: PORTE,
        porth: PORTH,
        exint: EXINT,
        twi: TWI,
        eeprom: EEPROM,
        adc: ADC,
        tc1: TC1,
        tc3: TC3,
        tc4: TC4,
        portb: PORTB,
        portk: PORTK,
    })
}

/// The peripherals the tracker uses besides the EEPROM.
struct Parts {
    usart0: chip::USART0,
    usart1: chip::USART1,
    usart2: chip::USART2,
    tc0: chip::TC0,
    tc5: chip::TC5,
    wdt: chip::WDT,
    cpu: chip::CPU,
    porta: chip::PORTA,
    portc: chip::PORTC,
    porte: chip::PORTE,
    porth: chip::PORTH,
    exint: chip::EXINT,
    twi: chip::TWI,
    eeprom: chip::EEPROM,
    adc: chip::ADC,
    tc1: chip::TC1,
    tc3: chip::TC3,
    tc4: chip::TC4,
    portb: chip::PORTB,
    portk: chip::PORTK,
}

/// The configuration at power-on: the copy saved in the EEPROM (console
/// `save`), else the board's own (Li et al.'s (2022) mechanics, Kano); the log
/// says which. A saved copy whose axes are of a kind this image does not
/// build (saved by another image) is not used either: the log says so. Not
/// inlined: the slots read (two 256-byte buffers) leave the stack before
/// the loop starts, and so does the choice (a second configuration in the
/// frame of its caller was 227 B more on the start-up stack).
#[inline(never)]
fn stored_config(store: &mut ConfigStore<EepromStorage<Eeprom>>, log: &mut Usart0) -> Config {
    let mut config = board_config();
    if store.load_into(&mut config).defaults {
        log.flash(suntracker::flash_str!("config source=defaults\n"));
    } else if config.check_drives(axes::DRIVES).is_err() {
        log.flash(suntracker::flash_str!(
            "config refused: axis drive not on this board; config source=defaults\n"
        ));
    } else {
        log.flash(suntracker::flash_str!("config source=stored\n"));
        return config;
    }
    board_config()
}

// Not inlined into `run`, whose frame would otherwise hold the moved-from
// peripherals' place (nothing: they are zero-sized) and any temporaries.
#[inline(never)]
fn run_tracker(dp: Parts) -> ! {
    // The log port is also the console: its receive ring is read by the
    // platform (`console_read`), the log writes through the port's value.
    let mut log = Usart0::new(dp.usart0, LOG_BAUD_HZ);
    let gps = Usart1::new(dp.usart1, GPS_BAUD_HZ);
    let millis_clock = Millis::start(dp.tc0);
    if MS_PER_TICK != 1 {
        // Emulator builds only: the harness reads the time scale here.
        log.flash(suntracker::flash_str!("timescale "));
        log.u32(MS_PER_TICK as u32);
        log.flash(suntracker::flash_str!("\n"));
    }
    let watchdog = Watchdog::enable(dp.wdt, &dp.cpu);

    // Motors and switches.
    let porta = dp.porta;
    let portc = dp.portc;
    // The DC motors' timers (duty 0), the servos' (no pulse) and the
    // encoders' pin-change interrupt, whatever the axes' kinds (before the
    // anemometer takes the external-interrupt block).
    let dc_parts = dc::DcParts::start(
        dc::MotorTimers {
            tc1: dp.tc1,
            tc3: dp.tc3,
            tc4: dp.tc4,
        },
        dp.adc,
        &dp.portb,
        &dp.porte,
        &dp.porth,
        &dp.portk,
        &dp.exint,
    );
    let anemometer = Anemometer::new(dp.exint, ExtInt::Int4);
    // The reed contact to ground needs the pull-up of PE4.
    let porte = dp.porte;
    let _wind_pin = InputPin::<_, 4>::new(&porte, true);

    // Interrupts on before any bus or port traffic that waits for them.
    // SAFETY: every part the vectors touch is set up above.
    unsafe { avr_device::interrupt::enable() };

    // The I²C devices.
    let bus = RefCell::new(I2c::new(dp.twi));
    let dc_board = dc::DcBoard {
        parts: &dc_parts,
        porta: &porta,
        portc: &portc,
    };
    let mut platform = MegaPlatform {
        _millis: millis_clock,
        anemometer,
        stow_pins: [
            InputPin::<_, 4>::new(&portc, true).erase(),
            InputPin::<_, 5>::new(&portc, true).erase(),
            InputPin::<_, 6>::new(&portc, true).erase(),
        ],
        adc: &dc_parts.adc,
        adc_channel: SUPPLY_CHANNEL,
        supply: None,
        irradiance: None,
        watchdog,
        cpu: dp.cpu,
        store: ConfigStore::new(Eeprom::storage(dp.eeprom)),
    };
    let mut firmware = build_firmware(&dc_board, &bus, &mut platform.store, gps, log);
    // Run it where it is, inside the result: moving it out would put a
    // second copy of its kilobytes on the stack.
    match &mut firmware {
        Ok(fw) => serve(fw, &mut platform, dp.usart2, dp.tc5, &dp.porth),
        // The board's own configuration was checked above; the scheduler's
        // intervals are the defaults. Nothing is driven; the watchdog,
        // no longer fed, resets the board.
        Err(e) => {
            // The log port went into the firmware that was not made: take
            // it again to say why.
            // SAFETY: the `Usart0` that owned it was dropped with the error.
            let mut log = Usart0::new_tx_only(unsafe { chip::USART0::steal() }, LOG_BAUD_HZ);
            let why = match e {
                StartError::Site(_) => "site refused",
                StartError::Controller(ControllerError::Config(_)) => "configuration refused",
                StartError::Controller(ControllerError::Schedule(_)) => "schedule refused",
            };
            halt(&mut log, why)
        }
    }
}

/// The mount's attitude sensors of this board.
type MegaSensors<'b> = MountSensorsHw<Adxl345<SharedI2c<'b>>, Qmc5883l<SharedI2c<'b>>>;

/// The firmware loop on this board's parts.
type MegaFirmware<'p, 'b> =
    Firmware<f32, Ds3231<SharedI2c<'b>>, Usart1, MegaDrive<'p>, MegaSensors<'b>, Usart0, TABLE_LEN>;

/// The axes' drive: each a stepper or a DC motor, by its configuration.
type MegaDrive<'p> = axes::MegaAxis<'p>;

/// The firmware on the board's axes, devices and stored configuration (the
/// log says where it came from; a configuration the checks refuse halts).
/// Not inlined: the configuration is read here, the axes and the sensors
/// are built in [`assemble_firmware`], and the firmware is written straight
/// into the caller's place for it; these frames then leave the stack (inlined
/// into `run_tracker`, some 800 bytes stayed under every call of the loop).
/// The store's read (its slot buffers and the record's checks, the deepest
/// stack at power-on) runs with only the configuration in this frame.
#[inline(never)]
fn build_firmware<'p, 'b>(
    // The axes' ports and motor parts in one argument: with one more, the
    // configuration below was passed to `assemble_firmware` as a copy on
    // the stack (207 B on the deepest stack, at start-up).
    board: &'p dc::DcBoard<'p>,
    bus: &'b RefCell<I2c>,
    store: &mut ConfigStore<EepromStorage<Eeprom>>,
    gps: Usart1,
    mut log: Usart0,
) -> Result<MegaFirmware<'p, 'b>, StartError> {
    let config = stored_config(store, &mut log);
    if config.validate().is_err() {
        halt(&mut log, "configuration refused");
    }
    assemble_firmware(board, bus, config, gps, log)
}

/// The firmware on the board's axes and devices with `config`. Not
/// inlined: see [`build_firmware`].
#[inline(never)]
fn assemble_firmware<'p, 'b>(
    board: &'p dc::DcBoard<'p>,
    bus: &'b RefCell<I2c>,
    config: Config,
    gps: Usart1,
    mut log: Usart0,
) -> Result<MegaFirmware<'p, 'b>, StartError> {
    let axes = mega_axes(board, &config, &mut log);
    let rtc = Ds3231::new(SharedI2c::new(bus));
    let sensors = attitude_sensors(bus, &mut log);
    Firmware::new(
        app_config(),
        config,
        controller_options(&config.axes),
        rtc,
        gps,
        axes,
        sensors,
        log,
    )
}

/// The loop: its pass, the Modbus port's (at most one request served),
/// then sleep until the next interrupt. The RS-485 port (USART2, Timer5,
/// its driver enable on PH3) and the Modbus port start here, at the
/// configured rate and parity. Not inlined: the Modbus port's buffers
/// (369 B) are on the stack only once the firmware is built, not under
/// its building too (the deepest stack at power-on).
#[inline(never)]
fn serve(
    fw: &mut MegaFirmware<'_, '_>,
    platform: &mut MegaPlatform<'_>,
    usart2: chip::USART2,
    tc5: chip::TC5,
    porth: &chip::PORTH,
) -> ! {
    let modbus_config = fw.controller().config().modbus;
    let mut rs485 = Rs485::new(
        usart2,
        tc5,
        porth,
        modbus_config.baud,
        Parity::from_code(modbus_config.parity),
    );
    let mut modbus = ModbusPort::new(MODBUS_IDENTITY, true);
    loop {
        fw.poll(platform);
        let now_ms = platform.now_ms();
        modbus.poll(fw, &mut rs485, now_ms);
        platform.wait_for_interrupt();
    }
}

#[cfg(feature = "dc")]
use dc::dc_config as board_config;
/// The board's own configuration: Li et al.'s (2022) mechanics (steppers),
/// or with the `dc` feature the same axes on the slew drives
/// ([`dc::dc_config`]).
#[cfg(not(feature = "dc"))]
use mechanics::config as board_config;

/// The loop's settings: this board's name and its own configuration.
/// Not inlined, as [`controller_options`].
#[inline(never)]
fn app_config() -> AppConfig {
    AppConfig {
        defaults: board_config,
        drives: axes::DRIVES,
        ..AppConfig::new(BOARD)
    }
}

/// The controller's options for this board. Not inlined: built in
/// `run_tracker`'s frame of kilobytes, each field would be stored beyond
/// the 63 bytes `ldd`/`std` reach from the frame pointer, 12 bytes more
/// each.
#[inline(never)]
fn controller_options(axes: &[suntracker::config::AxisConfig; 2]) -> ControllerOptions<f32> {
    // A sun position costs about 45,000 cycles here (psa-2020 in f32):
    // planning a day (some 370 positions, about a second) is spread over
    // ticks, four positions (11 ms) per tick, so that the loop keeps serving
    // the motors, the GPS ring and the watchdog; tracking starts about 90 s
    // after the time is trusted. The attitude (four readings of each sensor
    // and their trigonometry, about 10 ms) is read every 10 s, not every
    // tick: the mount does not move in between. With a DC axis the
    // controller corrects each axis from its count, with a timed axis it
    // re-homes after every stow too ([`mechanics::options_for_drives`]).
    let options = ControllerOptions {
        plan_positions_per_tick: PLAN_POSITIONS_PER_TICK,
        attitude_every_ms: ATTITUDE_EVERY_MS,
        ..mechanics::controller_options()
    };
    mechanics::options_for_drives(options, axes)
}

/// Both axes, each of the kind its configuration names ([`axes::axis`]),
/// each built in its place in the array (the board halted when one is
/// refused). Not inlined, as [`attitude_sensors`].
#[inline(never)]
fn mega_axes<'p>(
    board: &'p dc::DcBoard<'p>,
    config: &Config,
    log: &mut Usart0,
) -> [axes::MegaAxis<'p>; 2] {
    let calibration_mv = config.supply.calibration_mv;
    let [c, a] = &config.axes;
    [
        axes::axis(board, 0, c, calibration_mv, log),
        axes::axis(board, 1, a, calibration_mv, log),
    ]
}

/// The mount's attitude sensors on the I²C bus (ADXL345 and QMC5883L), or
/// none when either does not answer (the log says so). Not inlined: its
/// temporaries would otherwise sit in `run_tracker`'s frame of kilobytes,
/// beyond the 63 bytes `ldd`/`std` reach from the frame pointer, where each
/// use costs 8–12 bytes more.
#[inline(never)]
fn attitude_sensors<'b>(
    bus: &'b RefCell<I2c>,
    log: &mut Usart0,
) -> Option<MountSensorsHw<Adxl345<SharedI2c<'b>>, Qmc5883l<SharedI2c<'b>>>> {
    let compass = Qmc5883l::new(SharedI2c::new(bus), QmcConfig::default());
    let mut tilt = Adxl345::new(SharedI2c::new(bus), ADXL345_ADDRESS);
    match (compass, tilt.init()) {
        (Ok(compass), Ok(())) => Some(MountSensorsHw::new(
            tilt,
            compass,
            Calibration::IDENTITY,
            0.0,
        )),
        _ => {
            log.flash(suntracker::flash_str!(
                "attitude sensors absent: level mount facing north\n"
            ));
            None
        }
    }
}

/// An axis's configuration refused by its drive: says so and stops
/// ([`halt`]).
fn refused(log: &mut Usart0) -> ! {
    halt(log, "axis configuration refused")
}

/// Says why and stops: the watchdog, no longer fed, resets the board.
fn halt(log: &mut Usart0, why: &str) -> ! {
    log.flash(suntracker::flash_str!("halt: "));
    log.text(why);
    log.flash(suntracker::flash_str!("\n"));
    log.flush_all();
    loop {
        avr_device::asm::sleep();
    }
}
