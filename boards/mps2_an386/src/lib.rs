//! QEMU's `mps2-an386` board (Cortex-M4F, 25 MHz): everything about this
//! board in one place, turned into the parts of [`suntracker::firmware::Firmware`].
//! The image (`boards/mps2_an386/src/bin/qemu_tracker.rs`) binds the SysTick and interrupt
//! vectors to [`on_systick`] and [`on_interrupt`] and calls [`run`].
//!
//! | part | here |
//! |---|---|
//! | emulator gate | CMSDK APB UART1 at 0x4000_5000, polled |
//! | GPS port | CMSDK APB UART0 at 0x4000_4000 (ARM DDI 0479), 9600 baud, receive interrupt (IRQ 0) into a 512-byte ring |
//! | console (input) | CMSDK APB UART2 at 0x4000_6000, 115200 baud, receive interrupt (IRQ 4) into a [`CONSOLE_RING_LEN`]-byte ring, read by [`Platform::console_read`]; the replies go to the log |
//! | RS-485 (Modbus RTU server) | CMSDK APB UART3 at 0x4000_7000 (QEMU's fourth `-serial`), `modbus.baud` (19,200), receive interrupt (IRQ 18) into a [`MODBUS_RING_LEN`]-byte ring of bytes with their µs stamps, served by [`suntracker::sunspec::ModbusPort`] after each pass; the driver enable on GPIO0 pin 0 (unimplemented in QEMU: its writes are dropped) |
//! | log | semihosting (`SYS_WRITE` to `:tt`) |
//! | configuration storage | a host file through semihosting, [`CONFIG_FILE`] in QEMU's working directory ([`SemihostingFile`]; why: below) |
//! | monotonic ms | SysTick (ARMv7-M ARM B3.3) on the 25 MHz core clock, one interrupt every 500 ms, the count in between |
//! | UTC clock | no RTC chip: [`SoftRtc`], a clock on the monotonic clock that reports lost power until GPS or the console's `time set` sets it, and loses the time at every restart |
//! | axis drives | [`mount::StepperModel`]: ideal steppers in whole steps (QEMU has no motors), advanced by the elapsed monotonic time in [`suntracker::firmware::Motion::service`] |
//! | attitude | none: a level mount facing north |
//! | anemometer | none: zero pulses (calm) |
//! | watchdog | CMSDK APB watchdog at 0x4000_8000, 10 s (QEMU models it on the an386, but resets at the first timeout, with the NMI: run QEMU with `-no-reboot`, and a reset ends the run) |
//! | sleep | `wfi` between passes, unless a receive ring holds bytes |
//!
//! The interrupt numbers are QEMU's wiring of the an386 (`hw/arm/mps2.c`,
//! `uartirq[] = {0, 2, 4, 18, 20}`: UART*n*'s receive interrupt, its
//! transmit interrupt the next number). QEMU connects UART0, UART1, UART2
//! and UART3 to its first, second, third and fourth `-serial` in that
//! order.
//!
//! # Emulated time: the gate
//!
//! QEMU runs the image with `-icount shift=5,sleep=off`: every instruction
//! takes 32 ns of emulated time (≈ the an386's 25 MHz), and while the core
//! sleeps in `wfi` the emulated clock jumps to the next timer deadline, so
//! an idle day passes in seconds. The host cannot know when that happens,
//! so the board asks it: once every controller tick ([`GATE_MS`], 10 s) it stops
//! SysTick (the firmware's clock then stands still), writes `T<monotonic
//! ms>` on UART1 and polls UART1 for the host's answer: `<n>` or
//! `<n>,<m>`, the number of GPS bytes the host has just written into UART0
//! and of console bytes it has just written into UART2 (none when `,<m>`
//! is left out), or `stop`. It waits (busy: the receive interrupts fill the
//! rings) until those bytes are in, then restarts SysTick. The core never
//! sleeps in a gate: QEMU's watchdog
//! cannot be paused (its CONTROL register does not stop the counter), and
//! a `wfi` would let the emulated clock jump to its deadline; the busy
//! wait costs the watchdog some emulated microseconds per gate, nothing
//! the firmware's clock sees. The answer may carry two more numbers,
//! `<n>,<m>,<p>,<k>`: `p` > 0 asks the image to gate again `p` emulated ms
//! later (instead of at the next [`GATE_MS`]) and not to sleep in `wfi`
//! until an answer without it (the host paces the emulation to its wall
//! clock while a Modbus master is attached; a `wfi` would let the clock
//! jump to the next SysTick), and `k` counts the Modbus request bytes the
//! host has written into UART3, waited for as the others (they then all
//! carry the instant of the gate: one frame). So the NMEA of an epoch arrives at the emulated
//! instant its UTC says, and a console line at the instant the host chose,
//! whatever the host's scheduling, and a run is
//! repeatable. On `stop` the image writes an `end …` summary and exits
//! through semihosting with the firmware's status: success when no fault
//! is active. The host side is `.ci/qemu_gps.py` (the Cortex-M runner of
//! `.cargo/config.toml`; its `--type MINUTE:LINE` types a console line at
//! the gate of that emulated minute). (Semihosting `SYS_READC` would do for
//! the answer, but QEMU 7.2 does not resume a core blocked in it.)
//!
//! # Configuration storage: a host file
//!
//! The console's `save` and `load`, and the load at boot, go through a
//! [`ConfigStore`] over [`SemihostingFile`]: the two 256-byte slots are the
//! first 512 bytes of the host file [`CONFIG_FILE`], opened through
//! semihosting (`SYS_OPEN` "r+b", created with "w+b" when missing) and read
//! and written with `SYS_SEEK`, `SYS_READ` and `SYS_WRITE` (ARM semihosting
//! specification, "Semihosting operations"). A file rather than RAM: RAM
//! would survive nothing, so `config source=stored` could never be seen and
//! the boot load never run on a stored copy; the file survives a QEMU
//! restart as a board's flash or EEPROM survives a power cycle, and a run
//! can be started on a file another run saved (`.ci/qemu_gps.py
//! --config-file`). Bytes past the file's end read as 0xFF (erased). The
//! script runs QEMU in a fresh directory, so a run without
//! `--config-file` starts from an empty file: `config source=defaults`.
//! Each semihosting call stops the emulated core until the host has done
//! it, so a save takes no emulated time.
//!
//! At boot the image loads the stored configuration; when a slot is good
//! (and the controller takes it) it is used and the `config` line says
//! `source=stored`; else the board's own configuration (the defaults with
//! the simulated axes' gear) is used: `source=defaults`.
//!
//! Free-form lines besides the log's (`suntracker::log`): `config source=stored|defaults
//! step_s=… tick_ms=… gate_ms=… axis_step_deg=…` after the boot line,
//! `axes utc=<set-point utc> c=<deg> a=<deg>` (where the simulated axes
//! were when the set-point of that utc ended: at the next set-point, or
//! when tracking stopped), `axes mode=service c=<deg> a=<deg>` (where they
//! were when the service lock began, when it ended, and at the end of a
//! run under it), and the closing `end ms=… ticks=… setpoints=…
//! faults_active=… …`.
#![no_std]

pub mod mount;

use core::cell::RefCell;
use core::convert::Infallible;
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::interrupt::{InterruptNumber, Mutex};
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::{NVIC, SYST};
use cortex_m_semihosting::{debug, hio, syscall};
use drivers::rtc::Clock as RtcClock;
use drivers::time::DateTime;
use sun_algos::time::div_rem_u64;
use sun_algos::UtcTime;

use mount::StepperModel;
use suntracker::config::Config;
use suntracker::console::RxRing;
use suntracker::controller::{AttitudeSource, Controller, ControllerOptions};
use suntracker::firmware::{AppConfig, ConfigPersist, Firmware, Platform};
use suntracker::log::Sink;
use suntracker::motion::FeedbackMode;
use suntracker::persist::{ConfigStore, SLOT_LEN};
use suntracker::ports::Storage;
use suntracker::safety::Mode;
use suntracker::sunspec::ModbusPort;
use suntracker::time::{datetime_from_utc, utc_from_datetime};
use suntracker_modbus::sunspec::Identity;
use suntracker_modbus::StampedRing;

/// Board name in the boot line.
pub const BOARD: &str = "mps2-an386";
/// Core clock, Hz (the an386's SYSCLK).
pub const CORE_HZ: u32 = 25_000_000;
/// SysTick interrupt period, ms (reload 12,499,999 < 2^24).
pub const SYSTICK_MS: u32 = 500;
/// Controller tick period, ms: 10 s, so that one GPS epoch a tick (the
/// loop trusts GPS time for 1.5 s, and this board has no RTC to carry it)
/// costs QEMU a tenth of a 1 Hz stream (see [`GATE_MS`]).
pub const TICK_MS: u32 = 10_000;
/// Emulated milliseconds between two gates (one GPS epoch each): one per
/// controller tick, at its instant. QEMU's UART takes about 10,000 bytes a
/// wall second (one per main-loop turn), so a whole 1 Hz day (12 MB of
/// NMEA) would take twenty minutes; one epoch every 10 s takes two.
pub const GATE_MS: u64 = TICK_MS as u64;
/// [`GATE_MS`] as the 32-bit divisor of [`div_rem_u64`].
const GATE_MS_U32: u32 = TICK_MS;
/// Day-table capacity: Jimoh & Aliyu's (2019) 4-minute table of a polar day,
/// both solar midnights included: 1440 / 4 + 1 = 361 entries
/// (`capacity_for_interval`). 360 refused every polar day whose solar
/// midnight falls on a 4-minute step (a whole-degree longitude: 90° N 0° E
/// in June) with `schedule_failed`.
pub const TABLE_LEN: usize = sun_algos::geometry::day_table::capacity_for_interval(4);
/// GPS baud rate (NEO-6M and kin).
pub const GPS_BAUD_HZ: u32 = 9_600;
/// Console baud rate (QEMU's UART model moves bytes at its own pace; the
/// divider is set as on hardware).
pub const CONSOLE_BAUD_HZ: u32 = 115_200;
/// Watchdog timeout, ms.
pub const WATCHDOG_MS: u32 = 10_000;
/// GPS receive ring, bytes.
pub const GPS_RING_LEN: usize = 512;
/// Console receive ring, bytes: the most the host may type at one gate
/// (`.ci/qemu_gps.py` sends at most this many a gate and keeps the rest
/// for the next), three console lines of the longest
/// ([`suntracker::console::LINE_LEN`]).
pub const CONSOLE_RING_LEN: usize = 256;
/// The configuration file, in QEMU's working directory (NUL-terminated
/// for `SYS_OPEN`).
pub const CONFIG_FILE: &str = "suntracker-config.bin";
const CONFIG_FILE_C: &[u8] = b"suntracker-config.bin\0";

/// Model 1's and model 601's names of this image.
const MODBUS_IDENTITY: Identity<'static> = Identity {
    manufacturer: "suntracker",
    model: BOARD,
    options: "qemu",
    version: env!("CARGO_PKG_VERSION"),
    serial: "0",
    controller_name: "suntracker",
    tracker_name: "tracker-1",
};

/// Homing chunk: the fine approach (chunk/50) is one step.
const HOMING_CHUNK_DEG: f32 = 0.9;

const UART0: usize = 0x4000_4000;
/// The emulator gate's line (QEMU's second `-serial`).
const UART1: usize = 0x4000_5000;
/// The console (QEMU's third `-serial`).
const UART2: usize = 0x4000_6000;
/// The RS-485 port of the Modbus server (QEMU's fourth `-serial`).
const UART3: usize = 0x4000_7000;
/// CMSDK AHB GPIO0 (ARM DDI 0479): the RS-485 transceiver's driver
/// enable on [`DE_PIN`]. QEMU 7.2 leaves the an386's GPIO unimplemented
/// (its writes are dropped, its reads 0): the switching stays in the code
/// as on a board with a transceiver.
const GPIO0: usize = 0x4001_0000;
const GPIO_DATAOUT: usize = 0x04;
const GPIO_OUTENSET: usize = 0x10;
/// GPIO0 pin of the RS-485 driver enable.
const DE_PIN: u32 = 1 << 0;
const UART_DATA: usize = 0x00;
const UART_STATE: usize = 0x04;
const UART_CTRL: usize = 0x08;
const UART_INTCLEAR: usize = 0x0C;
const UART_BAUDDIV: usize = 0x10;
const STATE_TX_FULL: u32 = 1 << 0;
const STATE_RX_FULL: u32 = 1 << 1;
const CTRL_TX_EN: u32 = 1 << 0;
const CTRL_RX_EN: u32 = 1 << 1;
const CTRL_RX_INTEN: u32 = 1 << 3;
const INT_RX: u32 = 1 << 1;

const WDOG: usize = 0x4000_8000;
const WDOG_LOAD: usize = 0x00;
const WDOG_CONTROL: usize = 0x08;
const WDOG_INTCLR: usize = 0x0C;
const WDOG_LOCK: usize = 0xC00;
const WDOG_UNLOCK_KEY: u32 = 0x1ACC_E551;
const WDOG_INTEN_RESEN: u32 = 0b11;

fn reg_write(addr: usize, value: u32) {
    // SAFETY: every caller passes a documented 32-bit register of this
    // board's UARTs or watchdog (ARM DDI 0479), whose writes have no
    // effect on memory the program uses.
    unsafe { core::ptr::write_volatile(addr as *mut u32, value) }
}

fn reg_read(addr: usize) -> u32 {
    // SAFETY: as in `reg_write`; reads of these registers have no side
    // effect but DATA's, which only the receive paths read.
    unsafe { core::ptr::read_volatile(addr as *const u32) }
}

/// The an386's interrupt lines the board uses.
#[derive(Clone, Copy)]
#[repr(u16)]
enum Irq {
    /// UART0 receive (QEMU `hw/arm/mps2.c`: UART0 RX is IRQ 0).
    GpsRx0 = 0,
    /// UART2 receive (QEMU `hw/arm/mps2.c`: UART2 RX is IRQ 4).
    ConsoleRx2 = 4,
    /// UART3 receive (QEMU `hw/arm/mps2.c`: UART3 RX is IRQ 18).
    Rs485Rx3 = 18,
}

// SAFETY: `number` returns a valid interrupt number of this board.
unsafe impl InterruptNumber for Irq {
    fn number(self) -> u16 {
        self as u16
    }
}

/// Received bytes of one UART, filled by its receive interrupt
/// (`suntracker::console::RxRing`: a full ring marks its gaps for the
/// reader).
struct Ring<const N: usize> {
    ring: RxRing<N>,
    /// Bytes received since boot (the gate counts them).
    received: u32,
}

impl<const N: usize> Ring<N> {
    const fn new() -> Self {
        Ring {
            ring: RxRing::new(),
            received: 0,
        }
    }

    fn push(&mut self, b: u8) {
        self.received = self.received.wrapping_add(1);
        self.ring.push(b);
    }

    /// Moves the oldest bytes into `out`; how many.
    fn pop_into(&mut self, out: &mut [u8]) -> usize {
        self.ring.pop_into(out)
    }

    /// (bytes received since boot, bytes in the ring, bytes lost).
    fn counts(&self) -> (u32, usize, u32) {
        (
            self.received,
            self.ring.len(),
            u32::from(self.ring.dropped()),
        )
    }

    /// Everything the receive data register holds now, into the ring.
    fn drain_uart(&mut self, uart: usize) {
        while reg_read(uart + UART_STATE) & STATE_RX_FULL != 0 {
            self.push(reg_read(uart + UART_DATA) as u8);
        }
    }
}

static RX: Mutex<RefCell<Ring<GPS_RING_LEN>>> = Mutex::new(RefCell::new(Ring::new()));
static CONSOLE_RX: Mutex<RefCell<Ring<CONSOLE_RING_LEN>>> = Mutex::new(RefCell::new(Ring::new()));
/// The RS-485 port's received bytes, each with the µs it arrived at
/// ([`monotonic_us`], read in the receive interrupt).
static MODBUS_RX: Mutex<RefCell<StampedRing<MODBUS_RING_LEN>>> =
    Mutex::new(RefCell::new(StampedRing::new()));

/// Bytes of the RS-485 port with their arrival times: a whole frame (256
/// bytes) fits.
pub const MODBUS_RING_LEN: usize = 256;

/// SysTick periods since start.
static PERIODS: AtomicU32 = AtomicU32::new(0);

/// The SysTick exception: one more period.
pub fn on_systick() {
    PERIODS.fetch_add(1, Ordering::Relaxed);
}

/// NMI's number in cortex-m-rt's `DefaultHandler` argument (IPSR − 16).
const NMI_IRQN: i16 = -14;

/// Interrupt lines of the an386's NVIC: QEMU builds it with 32
/// (`hw/arm/mps2.c`, `num-irq` for the AN385 and AN386 images).
pub const IRQ_LINES: usize = 32;

extern "C" {
    /// cortex-m-rt's default handler, or the image's `#[exception]
    /// DefaultHandler`.
    fn DefaultHandler();
}

/// The interrupt part of the vector table (cortex-m-rt's `device` feature
/// places it after the exceptions): the an386's [`IRQ_LINES`] lines, each to
/// `DefaultHandler`, which passes the line to [`on_interrupt`]. Without it
/// cortex-m-rt would fill 240 lines (ARMv7-M's most), 832 bytes more.
#[link_section = ".vector_table.interrupts"]
#[no_mangle]
#[used]
pub static __INTERRUPTS: [unsafe extern "C" fn(); IRQ_LINES] = [DefaultHandler; IRQ_LINES];

/// A device interrupt or an exception without its own handler, `irqn` as
/// cortex-m-rt's `DefaultHandler` gives it. The watchdog's first timeout
/// (NMI) ends the run with failure, where the chip would reset at the
/// second one.
pub fn on_interrupt(irqn: i16) {
    if irqn == NMI_IRQN {
        let mut out = Semihosting(hio::hstdout().ok());
        out.text("watchdog timeout\n");
        debug::exit(debug::EXIT_FAILURE);
    }
    if irqn == Irq::GpsRx0 as i16 {
        reg_write(UART0 + UART_INTCLEAR, INT_RX);
        cortex_m::interrupt::free(|cs| {
            // Never borrowed elsewhere inside a critical section: the
            // `Err` arm (no panic path) is not taken.
            if let Ok(mut r) = RX.borrow(cs).try_borrow_mut() {
                r.drain_uart(UART0);
            }
        });
    }
    if irqn == Irq::Rs485Rx3 as i16 {
        reg_write(UART3 + UART_INTCLEAR, INT_RX);
        let t_us = monotonic_us();
        cortex_m::interrupt::free(|cs| {
            if let Ok(mut r) = MODBUS_RX.borrow(cs).try_borrow_mut() {
                while reg_read(UART3 + UART_STATE) & STATE_RX_FULL != 0 {
                    r.push(reg_read(UART3 + UART_DATA) as u8, t_us);
                }
            }
        });
    }
    if irqn == Irq::ConsoleRx2 as i16 {
        reg_write(UART2 + UART_INTCLEAR, INT_RX);
        cortex_m::interrupt::free(|cs| {
            if let Ok(mut r) = CONSOLE_RX.borrow(cs).try_borrow_mut() {
                r.drain_uart(UART2);
            }
        });
    }
}

/// UART0 as the GPS port: reads the receive ring.
pub struct GpsUart;

impl GpsUart {
    fn start() -> Self {
        // 9600 baud from the 25 MHz clock (BAUDDIV = 25e6 / 9600 = 2604).
        reg_write(UART0 + UART_BAUDDIV, CORE_HZ / GPS_BAUD_HZ);
        reg_write(UART0 + UART_CTRL, CTRL_TX_EN | CTRL_RX_EN | CTRL_RX_INTEN);
        reg_write(UART1 + UART_BAUDDIV, 16);
        reg_write(UART1 + UART_CTRL, CTRL_TX_EN | CTRL_RX_EN);
        // SAFETY: the handler (`on_interrupt`) only touches the ring,
        // through a critical section.
        unsafe { NVIC::unmask(Irq::GpsRx0) };
        GpsUart
    }
}

impl embedded_io::ErrorType for GpsUart {
    type Error = Infallible;
}

impl embedded_io::Read for GpsUart {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        Ok(cortex_m::interrupt::free(|cs| {
            RX.borrow(cs)
                .try_borrow_mut()
                .map_or(0, |mut r| r.pop_into(buf))
        }))
    }
}

impl embedded_io::ReadReady for GpsUart {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(cortex_m::interrupt::free(|cs| {
            RX.borrow(cs).try_borrow().is_ok_and(|r| !r.ring.is_empty())
        }))
    }
}

/// Starts UART2's receiver and its interrupt (the console).
fn start_console() {
    reg_write(UART2 + UART_BAUDDIV, CORE_HZ / CONSOLE_BAUD_HZ);
    reg_write(UART2 + UART_CTRL, CTRL_RX_EN | CTRL_RX_INTEN);
    // SAFETY: the handler (`on_interrupt`) only touches the console ring,
    // through a critical section.
    unsafe { NVIC::unmask(Irq::ConsoleRx2) };
}

/// (bytes received since boot, bytes in the ring, bytes lost) of the GPS
/// ring.
fn rx_counts() -> (u32, usize, u32) {
    cortex_m::interrupt::free(|cs| RX.borrow(cs).try_borrow().map_or((0, 0, 0), |r| r.counts()))
}

/// The same for the console ring.
fn console_counts() -> (u32, usize, u32) {
    cortex_m::interrupt::free(|cs| {
        CONSOLE_RX
            .borrow(cs)
            .try_borrow()
            .map_or((0, 0, 0), |r| r.counts())
    })
}

/// The semihosting console as the log.
pub struct Semihosting(Option<hio::HostStream>);

impl Sink for Semihosting {
    fn put(&mut self, bytes: &[u8]) {
        if let Some(s) = self.0.as_mut() {
            let _ = s.write_all(bytes);
        }
    }
}

/// Milliseconds since SysTick started, from the periods counted and the
/// current count; may read up to one period low while a wrap's interrupt
/// is pending (callers keep their own maximum).
fn monotonic_ms() -> u64 {
    let reload = u64::from(SYST::get_reload() & 0x00FF_FFFF) + 1;
    loop {
        let p1 = PERIODS.load(Ordering::Relaxed);
        let cvr = u64::from(SYST::get_current());
        let p2 = PERIODS.load(Ordering::Relaxed);
        if p1 == p2 {
            // Under 2^24 counts (SysTick is 24 bits), CORE_HZ / 1000 of
            // them a millisecond: a 32-bit division (a u64 one would link
            // the 64-bit division routine).
            let counts = u32::try_from(reload.saturating_sub(cvr)).unwrap_or(u32::MAX);
            let in_period = u64::from(counts / (CORE_HZ / 1000));
            break u64::from(p1) * u64::from(SYSTICK_MS) + in_period;
        }
    }
}

/// Microseconds since SysTick started, wrapping at 2^32 (71 minutes): the
/// time stamps of the RS-485 port's bytes. A wrap whose interrupt is still
/// pending (read from an interrupt handler of SysTick's priority) counts.
fn monotonic_us() -> u32 {
    let reload = (SYST::get_reload() & 0x00FF_FFFF) + 1;
    loop {
        let p1 = PERIODS.load(Ordering::Relaxed);
        let pending1 = cortex_m::peripheral::SCB::is_pendst_pending();
        let cvr = SYST::get_current();
        let pending2 = cortex_m::peripheral::SCB::is_pendst_pending();
        let p2 = PERIODS.load(Ordering::Relaxed);
        if p1 == p2 && pending1 == pending2 {
            let periods = p1.wrapping_add(u32::from(pending1));
            let in_period_us = reload.saturating_sub(cvr) / (CORE_HZ / 1_000_000);
            break periods
                .wrapping_mul(SYSTICK_MS * 1000)
                .wrapping_add(in_period_us);
        }
    }
}

/// The RS-485 port (UART3) as the Modbus server's line
/// ([`suntracker::sunspec::ModbusLine`]).
pub struct Rs485;

impl Rs485 {
    /// Starts UART3 at `baud` (the configuration's `modbus.baud`; QEMU's
    /// UART moves bytes at its own pace, the divider is set as on
    /// hardware; its model has no parity), its receive interrupt, and the
    /// driver-enable pin, released (receiving).
    fn start(baud: u32) -> Self {
        reg_write(UART3 + UART_BAUDDIV, CORE_HZ / baud.max(1200));
        reg_write(UART3 + UART_CTRL, CTRL_TX_EN | CTRL_RX_EN | CTRL_RX_INTEN);
        reg_write(GPIO0 + GPIO_OUTENSET, DE_PIN);
        reg_write(GPIO0 + GPIO_DATAOUT, 0);
        // SAFETY: the handler (`on_interrupt`) only touches the Modbus
        // ring, through a critical section.
        unsafe { NVIC::unmask(Irq::Rs485Rx3) };
        Rs485
    }

    /// (bytes received since boot, bytes in the ring).
    fn counts() -> (u32, usize) {
        cortex_m::interrupt::free(|cs| {
            MODBUS_RX
                .borrow(cs)
                .try_borrow()
                .map_or((0, 0), |r| (r.received(), r.len()))
        })
    }
}

impl suntracker::sunspec::ModbusLine for Rs485 {
    fn receive(&mut self) -> Option<(u8, u32)> {
        cortex_m::interrupt::free(|cs| {
            MODBUS_RX
                .borrow(cs)
                .try_borrow_mut()
                .ok()
                .and_then(|mut r| r.pop())
        })
    }
    fn now_us(&mut self) -> u32 {
        monotonic_us()
    }
    fn send(&mut self, frame: &[u8]) {
        // Driver on, the frame, driver off once the transmitter has taken
        // the last byte (QEMU's UART passes each byte on at once; on a
        // chip the release waits for the shift register to empty).
        reg_write(GPIO0 + GPIO_DATAOUT, DE_PIN);
        for &b in frame {
            while reg_read(UART3 + UART_STATE) & STATE_TX_FULL != 0 {}
            reg_write(UART3 + UART_DATA, u32::from(b));
        }
        while reg_read(UART3 + UART_STATE) & STATE_TX_FULL != 0 {}
        reg_write(GPIO0 + GPIO_DATAOUT, 0);
    }
}

/// The UTC clock of a board without an RTC chip: a clock kept on the
/// monotonic clock. It reports lost power (the loop does not trust it)
/// until it is set — by GPS time, which the loop writes to its RTC, or by
/// the console's `time set` — and then runs on SysTick; a restart loses it.
/// QEMU's crystal is exact, so it never drifts from GPS.
pub struct SoftRtc {
    /// The instant set and the monotonic ms it was set at.
    set: Option<(UtcTime, u64)>,
    /// The largest monotonic reading so far (never go back).
    last_ms: u64,
}

impl SoftRtc {
    /// A clock that has never been set.
    pub const fn new() -> Self {
        SoftRtc {
            set: None,
            last_ms: 0,
        }
    }

    fn now_ms(&mut self) -> u64 {
        self.last_ms = self.last_ms.max(monotonic_ms());
        self.last_ms
    }
}

impl Default for SoftRtc {
    fn default() -> Self {
        Self::new()
    }
}

/// Why [`SoftRtc`] has no time to give.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SoftRtcError {
    /// Never set since the restart.
    NotSet,
    /// The time set plus the time run is outside the calendar's range.
    OutOfRange,
}

impl RtcClock for SoftRtc {
    type Error = SoftRtcError;
    fn datetime(&mut self) -> Result<DateTime, SoftRtcError> {
        let now = self.now_ms();
        let (t, at) = self.set.ok_or(SoftRtcError::NotSet)?;
        let elapsed =
            i64::try_from(now.saturating_sub(at)).map_err(|_| SoftRtcError::OutOfRange)?;
        let t = t
            .add_millis(elapsed)
            .map_err(|_| SoftRtcError::OutOfRange)?;
        datetime_from_utc(&t).map_err(|_| SoftRtcError::OutOfRange)
    }
    fn set_datetime(&mut self, utc: &DateTime) -> Result<(), SoftRtcError> {
        let t = utc_from_datetime(utc).map_err(|_| SoftRtcError::OutOfRange)?;
        let now = self.now_ms();
        self.set = Some((t, now));
        Ok(())
    }
    fn lost_power(&mut self) -> Result<bool, SoftRtcError> {
        Ok(self.set.is_none())
    }
}

/// The configuration's storage: the first `2 × SLOT_LEN` bytes of the host
/// file [`CONFIG_FILE`] through semihosting (module docs). Bytes past the
/// file's end read as 0xFF, the erased value.
pub struct SemihostingFile {
    /// The semihosting file handle, `None` when the file could not be
    /// opened or created (every access then fails).
    handle: Option<usize>,
}

/// Errors of [`SemihostingFile`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileError {
    /// The file could not be opened or created.
    NotOpen,
    /// An access beyond the two slots.
    OutOfRange,
    /// `SYS_SEEK` failed.
    Seek,
    /// `SYS_READ` failed.
    Read,
    /// `SYS_WRITE` wrote less than asked.
    Write,
}

/// The semihosting `SYS_OPEN` / `SYS_READ` / `SYS_WRITE` error return.
const SH_FAILED: usize = usize::MAX;

impl SemihostingFile {
    /// Opens [`CONFIG_FILE`] for reading and writing, creating it (empty)
    /// when it does not exist.
    pub fn open() -> Self {
        let open = |mode: usize| {
            // SAFETY: SYS_OPEN reads the NUL-terminated name (length
            // without the NUL) and writes nothing to target memory.
            let h =
                unsafe { syscall!(OPEN, CONFIG_FILE_C.as_ptr(), mode, CONFIG_FILE_C.len() - 1) };
            (h != SH_FAILED).then_some(h)
        };
        let handle = open(cortex_m_semihosting::nr::open::RW_BINARY)
            .or_else(|| open(cortex_m_semihosting::nr::open::RW_TRUNC_BINARY));
        SemihostingFile { handle }
    }

    /// True when the file is open.
    pub fn is_open(&self) -> bool {
        self.handle.is_some()
    }

    /// The handle, positioned at `offset`, for an access of `len` bytes
    /// inside the two slots.
    fn seek(&self, offset: usize, len: usize) -> Result<usize, FileError> {
        let h = self.handle.ok_or(FileError::NotOpen)?;
        if offset.checked_add(len).is_none_or(|end| end > 2 * SLOT_LEN) {
            return Err(FileError::OutOfRange);
        }
        // SAFETY: SYS_SEEK takes the handle and an absolute position; it
        // touches no target memory. 0 is success.
        let r = unsafe { syscall!(SEEK, h, offset) };
        if r != 0 {
            return Err(FileError::Seek);
        }
        Ok(h)
    }
}

impl Storage for SemihostingFile {
    type Error = FileError;

    /// Two slots.
    fn capacity(&self) -> usize {
        2 * SLOT_LEN
    }

    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), FileError> {
        let h = self.seek(offset, buf.len())?;
        // SAFETY: SYS_READ writes at most `buf.len()` bytes into `buf`,
        // which is ours for the call; it returns how many it did NOT read.
        let left = unsafe { syscall!(READ, h, buf.as_mut_ptr(), buf.len()) };
        if left > buf.len() {
            return Err(FileError::Read);
        }
        // A short read is the file's end: erased bytes.
        let got = buf.len() - left;
        if let Some(rest) = buf.get_mut(got..) {
            rest.fill(0xFF);
        }
        Ok(())
    }

    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), FileError> {
        let h = self.seek(offset, data.len())?;
        // SAFETY: SYS_WRITE only reads `data.len()` bytes of `data`; it
        // returns how many it did NOT write.
        let left = unsafe { syscall!(WRITE, h, data.as_ptr(), data.len()) };
        if left != 0 {
            return Err(FileError::Write);
        }
        Ok(())
    }
}

/// The configuration store the console's `save` and `load` use (its save
/// stepped from the loop: one semihosting call a pass).
type Store = ConfigStore<SemihostingFile>;

/// Monotonic clock, watchdog, sleep, console, storage and the emulator gate.
struct Board {
    syst: SYST,
    last_ms: u64,
    next_gate_ms: u64,
    log: Semihosting,
    stop: bool,
    /// The host paces the emulation to its wall clock (a Modbus client is
    /// attached): the next gate this many emulated ms after the last, and
    /// no `wfi` between passes (see the module documentation).
    pace_ms: Option<u32>,
    store: &'static mut Store,
}

impl Board {
    fn start(mut syst: SYST, store: &'static mut Store) -> Self {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(CORE_HZ / 1000 * SYSTICK_MS - 1);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        // The watchdog: unlock, load, interrupt (NMI) and reset on timeout.
        reg_write(WDOG + WDOG_LOCK, WDOG_UNLOCK_KEY);
        reg_write(WDOG + WDOG_LOAD, CORE_HZ / 1000 * WATCHDOG_MS);
        reg_write(WDOG + WDOG_CONTROL, WDOG_INTEN_RESEN);
        reg_write(WDOG + WDOG_LOCK, 0);
        Board {
            syst,
            last_ms: 0,
            next_gate_ms: 0,
            log: Semihosting(hio::hstdout().ok()),
            stop: false,
            pace_ms: None,
            store,
        }
    }

    /// Lets the host put the GPS bytes and the console bytes of this
    /// instant into UART0 and UART2 while the emulated clock stands still
    /// (see the module documentation).
    fn gate(&mut self, now_ms: u64) {
        self.syst.disable_counter();
        // Counted from before the request: the bytes may come in (receive
        // interrupts) while the answer is read.
        let (gps_start, _, _) = rx_counts();
        let (console_start, _, _) = console_counts();
        let (modbus_start, _) = Rs485::counts();
        let mut req = GateLine;
        req.text("T");
        put_u64(&mut req, now_ms);
        req.text("\n");
        // [GPS bytes, console bytes, pace ms, Modbus bytes]; the answer's
        // numbers in that order.
        let mut counts: [u32; 4] = [0; 4];
        let mut field = 0;
        let mut digits = 0;
        loop {
            // Busy-waits: no timer runs, so the emulated clock the firmware
            // sees stands still however long the host takes.
            while reg_read(UART1 + UART_STATE) & STATE_RX_FULL == 0 {}
            match reg_read(UART1 + UART_DATA) as u8 {
                c @ b'0'..=b'9' => {
                    if let Some(n) = counts.get_mut(field) {
                        *n = n.saturating_mul(10).saturating_add(u32::from(c - b'0'));
                    }
                    digits += 1;
                }
                b',' => field += 1,
                b'\n' if digits > 0 || self.stop => break,
                b's' => self.stop = true,
                _ => {}
            }
        }
        let [gps, console, pace_ms, modbus] = counts;
        self.pace_ms = (pace_ms > 0).then_some(pace_ms);
        // Busy as well (a `wfi` here would let QEMU jump the emulated
        // clock to the watchdog's deadline): the receive interrupts fill
        // the rings meanwhile. Console bytes beyond the ring's room are
        // counted as received (and lost), so this ends either way. The
        // Modbus ring only when bytes come (the stack depth at which an
        // interrupt lands here is then that of a run without them).
        while rx_counts().0.wrapping_sub(gps_start) < gps
            || console_counts().0.wrapping_sub(console_start) < console
            || (modbus > 0 && Rs485::counts().0.wrapping_sub(modbus_start) < modbus)
        {}
        self.syst.enable_counter();
    }
}

/// UART1's transmit side, where the gate's requests go.
struct GateLine;

impl Sink for GateLine {
    fn put(&mut self, bytes: &[u8]) {
        for &b in bytes {
            while reg_read(UART1 + UART_STATE) & STATE_TX_FULL != 0 {}
            reg_write(UART1 + UART_DATA, u32::from(b));
        }
    }
}

impl Platform for Board {
    fn now_ms(&mut self) -> u64 {
        // A wrap whose interrupt has not run yet reads as the period's
        // start: never go back.
        self.last_ms = self.last_ms.max(monotonic_ms());
        self.last_ms
    }
    fn take_wind_pulses(&mut self) -> u32 {
        0
    }
    fn feed_watchdog(&mut self) {
        reg_write(WDOG + WDOG_LOCK, WDOG_UNLOCK_KEY);
        reg_write(WDOG + WDOG_INTCLR, 1);
        reg_write(WDOG + WDOG_LOCK, 0);
    }
    fn wait_for_interrupt(&mut self) {
        // Bytes still in a ring (more than a pass reads), or the host
        // pacing the emulation (a `wfi` would let the emulated clock jump
        // to the next SysTick, 500 ms): no sleep.
        if rx_counts().1 == 0
            && console_counts().1 == 0
            && Rs485::counts().1 == 0
            && self.pace_ms.is_none()
        {
            cortex_m::asm::wfi();
        }
        let now = self.now_ms();
        if now >= self.next_gate_ms {
            self.gate(now);
            self.next_gate_ms = match self.pace_ms {
                Some(p) => now + u64::from(p),
                None => {
                    let into_gate = div_rem_u64(now, GATE_MS_U32).map_or(0, |(_, r)| u64::from(r));
                    now - into_gate + GATE_MS
                }
            };
        }
    }
    fn console_read(&mut self, buf: &mut [u8]) -> usize {
        cortex_m::interrupt::free(|cs| {
            CONSOLE_RX
                .borrow(cs)
                .try_borrow_mut()
                .map_or(0, |mut r| r.pop_into(buf))
        })
    }
    fn console_lost_lines(&mut self) -> u8 {
        cortex_m::interrupt::free(|cs| {
            CONSOLE_RX
                .borrow(cs)
                .try_borrow_mut()
                .map_or(0, |mut r| r.ring.take_lost_lines())
        })
    }
    fn config_store(&mut self) -> Option<&mut dyn ConfigPersist> {
        Some(&mut *self.store)
    }
}

fn put_u64(out: &mut dyn Sink, v: u64) {
    let (hi, lo) = div_rem_u64(v, 1_000_000_000).unwrap_or((0, 0));
    if hi > 0 {
        out.u32(hi as u32);
        out.u32_padded(lo, 9);
    } else {
        out.u32(lo);
    }
}

/// No attitude sensors (`Infallible`): the mount is level, as configured
/// (`AttitudeSource::Fixed`).
type Tracker = Firmware<f32, SoftRtc, GpsUart, StepperModel, Infallible, Semihosting, TABLE_LEN>;

/// The word the free RAM is painted with at start-up.
const STACK_PAINT: u32 = 0xA5A5_A5A5;
/// Bytes under the stack pointer left unpainted at start-up (the frame
/// that paints).
const PAINT_GAP_B: usize = 256;

extern "C" {
    /// cortex-m-rt (`link.x`): the first byte after the static RAM.
    static mut __sheap: u32;
    /// cortex-m-rt (`link.x`): the initial stack pointer, top of RAM.
    static _stack_start: u32;
}

/// Stack painting, measured rather than estimated: fills the RAM between
/// the end of the static RAM and [`PAINT_GAP_B`] under the stack pointer
/// with [`STACK_PAINT`]; [`stack_peak_bytes`] then finds how deep the stack
/// went. (No heap: the RAM after `__sheap` is the stack's.)
fn paint_stack() {
    let from = core::ptr::addr_of_mut!(__sheap) as usize;
    let sp = cortex_m::register::msp::read() as usize;
    let to = sp.saturating_sub(PAINT_GAP_B) & !3;
    let mut p = from;
    while p < to {
        // SAFETY: word-aligned addresses between the end of the static RAM
        // and below the live stack: RAM nothing else uses.
        unsafe { core::ptr::write_volatile(p as *mut u32, STACK_PAINT) };
        p += 4;
    }
}

/// The deepest the stack has been since [`paint_stack`]: from the top of
/// RAM down to the lowest word no longer holding the paint.
fn stack_peak_bytes() -> u32 {
    let from = core::ptr::addr_of_mut!(__sheap) as usize;
    let top = core::ptr::addr_of!(_stack_start) as usize;
    let mut p = from;
    // SAFETY: reads of RAM words between the static RAM and the stack top.
    while p < top && unsafe { core::ptr::read_volatile(p as *const u32) } == STACK_PAINT {
        p += 4;
    }
    u32::try_from(top.saturating_sub(p)).unwrap_or(u32::MAX)
}

/// The board's own configuration: the defaults with the simulated axes'
/// mechanics (also what the console's `defaults` restores).
fn board_config() -> Config {
    let mut config = Config::default();
    for ax in config.axes.iter_mut() {
        ax.counts_per_motor_rev = mount::STEPS_PER_MOTOR_REV;
        ax.microsteps = 1;
        ax.gear_ratio = mount::GEAR_RATIO as f32;
        ax.backlash_deg = 0.0;
        ax.max_speed_deg_s = mount::SPEED_DEG_S as f32;
        // Open loop: every set-point is driven to the nearest step.
        ax.deadband_deg = 0.0;
    }
    config
}

/// Where the configuration in force came from.
#[derive(Clone, Copy, PartialEq, Eq)]
enum ConfigSource {
    /// A good stored copy.
    Stored,
    /// The board's own: no good stored copy.
    Defaults,
    /// The board's own: the stored copy was good but the controller
    /// refused it (a table step its day table cannot hold).
    StoredRefused,
}

/// The configuration to start with: the stored one when a slot is good and
/// the controller takes it, else the board's own. Not inlined: the loaded
/// copies stay out of `run`'s frame, which is on the stack for good.
#[inline(never)]
fn boot_config(store: &mut Store) -> (Config, ConfigSource) {
    let mut config = board_config();
    let source = if store.load_into(&mut config).defaults {
        ConfigSource::Defaults
    } else if Controller::<
        f32,
        suntracker::sun::BoardSource<f32>,
        StepperModel,
        Infallible,
        TABLE_LEN,
    >::check(&config)
    .is_ok()
    {
        return (config, ConfigSource::Stored);
    } else {
        ConfigSource::StoredRefused
    };
    (board_config(), source)
}

/// Starts the tracker; returns only through semihosting exit (when the host
/// says `stop`).
pub fn run() -> ! {
    paint_stack();
    let Some(cp) = cortex_m::Peripherals::take() else {
        debug::exit(debug::EXIT_FAILURE);
        halt()
    };
    // The store in static RAM (its staged record stays off the stack).
    let Some(store) = cortex_m::singleton!(: Store = ConfigStore::new(SemihostingFile::open()))
    else {
        debug::exit(debug::EXIT_FAILURE);
        halt()
    };
    let (config, source) = boot_config(store);
    let mut board = Board::start(cp.SYST, store);
    let gps = GpsUart::start();
    start_console();
    let mut rs485 = Rs485::start(config.modbus.baud);
    let [c, a] = config.axes;
    // Power-on angles, steps above the home switches (the fine homing
    // approach then lands on the switch to the step).
    let plants = [
        StepperModel::new(c.home_deg, c.max_deg, 10_556),
        StepperModel::new(a.home_deg, a.max_deg, 6_111),
    ];
    let options = ControllerOptions {
        feedback: FeedbackMode::OpenLoop,
        attitude: AttitudeSource::Fixed(suntracker::attitude::MountAttitude::level()),
        homing_chunk_deg: HOMING_CHUNK_DEG,
        ..ControllerOptions::default()
    };
    let Some(slot) = cortex_m::singleton!(: Option<Tracker> = None) else {
        debug::exit(debug::EXIT_FAILURE);
        halt()
    };
    let log = Semihosting(hio::hstdout().ok());
    let fw = match Tracker::new(
        AppConfig {
            tick_ms: TICK_MS,
            defaults: board_config,
            ..AppConfig::new(BOARD)
        },
        config,
        options,
        SoftRtc::new(),
        gps,
        plants,
        None,
        log,
    ) {
        Ok(fw) => slot.insert(fw),
        Err(_) => {
            board.log.text("halt: configuration refused\n");
            debug::exit(debug::EXIT_FAILURE);
            halt()
        }
    };
    if !board.store.storage().is_open() {
        board.log.text("config storage unavailable: ");
        board.log.text(CONFIG_FILE);
        board.log.text(" could not be opened\n");
    }
    if source == ConfigSource::StoredRefused {
        board
            .log
            .text("config stored copy refused by the controller: defaults in force\n");
    }
    board.log.text(match source {
        ConfigSource::Stored => "config source=stored",
        ConfigSource::Defaults | ConfigSource::StoredRefused => "config source=defaults",
    });
    board.log.text(" step_s=");
    board
        .log
        .u32(fw.controller().scheduler().config().table_step_s);
    board.log.text(" tick_ms=");
    board.log.u32(TICK_MS);
    board.log.text(" gate_ms=");
    put_u64(&mut board.log, GATE_MS);
    board.log.text(" axis_step_deg=");
    board.log.fixed(mount::STEP_DEG, 3);
    board.log.text("\n");
    // The Modbus server on UART3, with model 305: this board has a GPS.
    // In static RAM, as the tracker: its 256-byte frame buffer stays out
    // of `run`'s frame, which is on the stack for good.
    let Some(modbus) = cortex_m::singleton!(: ModbusPort = ModbusPort::new(MODBUS_IDENTITY, true))
    else {
        debug::exit(debug::EXIT_FAILURE);
        halt()
    };
    // The first epoch before the first pass.
    board.gate(0);
    board.next_gate_ms = GATE_MS;
    let mut tracking = false;
    let mut in_service = false;
    loop {
        let applied = fw.controller().scheduler().applied().map(|e| e.time);
        if board.stop {
            if let (true, Some(t)) = (tracking, applied) {
                axes_line(fw, &mut board.log, &t);
            }
            if in_service {
                held_axes_line(fw, &mut board.log);
            }
            let status = end_line(fw, &mut board);
            debug::exit(status);
            halt()
        }
        let setpoints = fw.stats().setpoints;
        let ticked = fw.poll(&mut board);
        let now_ms = board.now_ms();
        modbus.poll(fw, &mut rs485, now_ms);
        if ticked {
            let now_tracking = fw.last_report().is_some_and(|r| r.mode == Mode::Tracking);
            let ended = fw.stats().setpoints != setpoints || (tracking && !now_tracking);
            if let (true, Some(t)) = (ended && tracking, applied) {
                axes_line(fw, &mut board.log, &t);
            }
            tracking = now_tracking;
            let now_service = fw.last_report().is_some_and(|r| r.mode == Mode::Service);
            if now_service != in_service {
                held_axes_line(fw, &mut board.log);
                in_service = now_service;
            }
        }
        board.wait_for_interrupt();
    }
}

/// `axes utc=<set-point utc> c=<deg> a=<deg>`: where the plants are.
fn axes_line(fw: &Tracker, out: &mut Semihosting, t: &UtcTime) {
    let [c, a] = fw.controller().axes();
    out.text("axes utc=");
    out.utc(t);
    out.text(" c=");
    out.fixed(c.drive().output_deg(), 4);
    out.text(" a=");
    out.fixed(a.drive().output_deg(), 4);
    out.text("\n");
}

/// `axes mode=service c=<deg> a=<deg>`: where the plants are when the
/// service lock begins, when it ends and when the run stops under it (the
/// same angles each time: nothing moved under it).
fn held_axes_line(fw: &Tracker, out: &mut Semihosting) {
    let [c, a] = fw.controller().axes();
    out.text("axes mode=service c=");
    out.fixed(c.drive().output_deg(), 4);
    out.text(" a=");
    out.fixed(a.drive().output_deg(), 4);
    out.text("\n");
}

/// The closing summary; the status is success when no fault is active.
fn end_line(fw: &Tracker, board: &mut Board) -> debug::ExitStatus {
    let now = board.now_ms();
    let s = fw.stats();
    let f = fw.controller().faults();
    let active = f.active_count() as u32;
    let (received, _, overruns) = rx_counts();
    let out = &mut board.log;
    out.text("end ms=");
    put_u64(out, now);
    out.text(" ticks=");
    out.u32(s.ticks);
    out.text(" setpoints=");
    out.u32(s.setpoints);
    out.text(" faults_active=");
    out.u32(active);
    out.text(" late_ticks=");
    out.u32(s.late_ticks);
    out.text(" gps_bytes=");
    out.u32(received);
    out.text(" gps_overruns=");
    out.u32(overruns);
    out.text(" drive_errors=");
    out.u32(s.drive_errors);
    out.text(" stack_peak_b=");
    out.u32(stack_peak_bytes());
    out.text("\n");
    if active == 0 {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    }
}

/// Stops here (after a semihosting exit QEMU has already ended).
pub fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

/// The image's panic handler: says so and exits with failure.
pub fn on_panic() -> ! {
    let mut out = Semihosting(hio::hstdout().ok());
    out.text("panic\n");
    debug::exit(debug::EXIT_FAILURE);
    halt()
}
