//! A thin, owned wrapper around simavr (through `simavr-ffi`, the simavr
//! build that `avr-tester` 0.6 runs on).
//!
//! Why not `avr_tester::AvrTester` itself: its `run()` panics as soon as the
//! CPU sleeps (`AvrState::Sleeping`), and the suntracker images idle-sleep
//! between Timer0 ticks; and neither it nor `avr-simulator` exposes the I/O
//! port IRQs, which the stepper decoder needs to see every single pin write.
//! The TWI message protocol used here is simavr's (`avr_twi.h`:
//! START/ADDR/ACK/WRITE/READ/STOP bits in a 32-bit IRQ value), the same one
//! `avr_tester::TwiPacket` decodes.
//!
//! Everything the firmware drives out (USART bytes, TWI messages, PORTA
//! writes) arrives through simavr IRQ callbacks, during `avr_run`; the
//! callbacks only push into shared queues / models, which the harness reads
//! between instructions.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::ffi::CString;
use std::path::Path;
use std::ptr::NonNull;
use std::rc::Rc;

use simavr_ffi as ffi;

use crate::twi::TwiBus;

fn ioctl_code(a: u8, b: u8, c: u8, d: u8) -> u32 {
    u32::from_be_bytes([a, b, c, d])
}

/// CPU state after a run step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CpuState {
    /// Executing (or sleeping with interrupts enabled: simavr then skips
    /// to the next timer event, which is what we want).
    Running,
    /// Sleeping with interrupts off, or the program ended.
    Done,
    /// Invalid instruction or similar.
    Crashed,
    /// The chip reset (the watchdog expired): simavr restarts its cycle
    /// count, so the run cannot go on in step with emulated time.
    Reset,
}

/// The receive side of one USART as seen from outside (bytes the AVR sent).
struct UartState {
    /// Bytes the AVR sent, each with the cycle its UDRn write raised the
    /// output IRQ at (simavr sends a byte the instant it is written).
    from_avr: VecDeque<(u64, u8)>,
    to_avr: VecDeque<u8>,
    xon: bool,
    avr: NonNull<ffi::avr_t>,
    /// Cycles before the last power cycle ([`Sim::power_cycle`]).
    base: Rc<std::cell::Cell<u64>>,
}

struct UartHandle {
    state: Box<RefCell<UartState>>,
    input: NonNull<ffi::avr_irq_t>,
}

/// Callback state of a port watch: the value of its IRQ (the port's levels
/// as driven, or DDRx) at each change.
struct PortWatch {
    changes: RefCell<Vec<(u64, u8)>>,
    /// Set by every write, cleared by the run loop: lets `run_until`
    /// return at once so that switches follow the motion without delay.
    flag: std::rc::Rc<std::cell::Cell<bool>>,
    avr: NonNull<ffi::avr_t>,
    /// Cycles before the last power cycle ([`Sim::power_cycle`]).
    base: Rc<std::cell::Cell<u64>>,
}

/// Level changes of one pin (a timer's compare output drives the pin's own
/// IRQ, not the port's PIN_ALL one).
struct PinWatch {
    changes: RefCell<Vec<(u64, bool)>>,
    avr: NonNull<ffi::avr_t>,
    base: Rc<std::cell::Cell<u64>>,
}

struct TwiHandle {
    bus: Rc<RefCell<TwiBus>>,
    input: NonNull<ffi::avr_irq_t>,
}

/// One simulated AVR.
pub struct Sim {
    avr: NonNull<ffi::avr_t>,
    uarts: Vec<(char, UartHandle)>,
    /// Port watches: (port, simavr IRQ: `IOPORT_IRQ_PIN_ALL` or
    /// `IOPORT_IRQ_DIRECTION_ALL`).
    ports: Vec<((char, u32), Box<PortWatch>)>,
    pins: Vec<((char, u8), Box<PinWatch>)>,
    twi: Option<Box<TwiHandle>>,
    port_flag: std::rc::Rc<std::cell::Cell<bool>>,
    tx_pending: bool,
    /// The lowest stack pointer seen after an instruction.
    min_sp: u16,
    /// The high byte of the stack pointer was written and the low byte
    /// not yet ([`sp_write_half`]): the pointer is between two values.
    sp_half_written: bool,
    /// The program counter (byte address) when it was seen.
    min_sp_pc: u32,
    /// The stack's bytes above [`Sim::min_sp`] when it was reached (kept
    /// only with `SUNTRACKER_EMU_PC` set: the return addresses of the
    /// deepest call chain, for `avr-addr2line`).
    min_sp_stack: Option<Vec<u8>>,
    /// Cycles run before the last power cycle: [`Sim::cycle`] counts on
    /// across it (simavr's own count restarts at 0).
    cycle_base: Rc<std::cell::Cell<u64>>,
    /// Cycles spent per program-counter address (byte address), when
    /// profiling ([`Sim::enable_profile`]).
    profile: Option<std::collections::HashMap<u32, u64>>,
    /// The cycle the CPU last woke at, while it is awake.
    awake_from: Option<u64>,
    /// The longest stretch awake: its cycles and the cycle it ended at.
    longest_awake: Option<(u64, u64)>,
    /// Every stretch awake longer than [`LONG_AWAKE_CYCLES`] (cycles, end
    /// cycle), the first [`LONG_AWAKE_KEPT`].
    long_awake: Vec<(u64, u64)>,
    /// Interrupt vectors that fire when enabled with their flag already
    /// set ([`Sim::fire_on_enable`]).
    fire_on_enable: Vec<NonNull<ffi::avr_int_vector_t>>,
    _firmware: Box<ffi::elf_firmware_t>,
}

unsafe extern "C" fn quiet_logger(
    _: *mut ffi::avr_t,
    _: std::os::raw::c_int,
    _: *const std::os::raw::c_char,
    _: *mut ffi::__va_list_tag,
) {
}

/// A stretch awake longer than this is listed ([`Sim::long_awake`]):
/// 160,000 cycles, 10 ms at 16 MHz.
pub const LONG_AWAKE_CYCLES: u64 = 160_000;
/// How many such stretches are kept.
pub const LONG_AWAKE_KEPT: usize = 10_000;

/// simavr's default `sleep` callback usleep()s to keep the simulation in
/// step with wall time; the harness wants it as fast as possible.
unsafe extern "C" fn no_sleep(_: *mut ffi::avr_t, _: ffi::avr_cycle_count_t) {}

/// A simavr cycle timer that does nothing: [`Sim::stop_at`].
unsafe extern "C" fn stop_timer(
    _: *mut ffi::avr_t,
    _: ffi::avr_cycle_count_t,
    _: *mut std::ffi::c_void,
) -> ffi::avr_cycle_count_t {
    0
}

unsafe extern "C" fn on_uart_output(
    _: *mut ffi::avr_irq_t,
    value: u32,
    param: *mut std::ffi::c_void,
) {
    let state = unsafe { &*(param as *const RefCell<UartState>) };
    if let Ok(mut s) = state.try_borrow_mut() {
        let cycle = s.base.get() + unsafe { s.avr.as_ref().cycle };
        s.from_avr.push_back((cycle, value as u8));
    }
}

unsafe extern "C" fn on_uart_xon(_: *mut ffi::avr_irq_t, _: u32, param: *mut std::ffi::c_void) {
    let state = unsafe { &*(param as *const RefCell<UartState>) };
    if let Ok(mut s) = state.try_borrow_mut() {
        s.xon = true;
    }
}

unsafe extern "C" fn on_uart_xoff(_: *mut ffi::avr_irq_t, _: u32, param: *mut std::ffi::c_void) {
    let state = unsafe { &*(param as *const RefCell<UartState>) };
    if let Ok(mut s) = state.try_borrow_mut() {
        s.xon = false;
    }
}

unsafe extern "C" fn on_port_all(_: *mut ffi::avr_irq_t, value: u32, param: *mut std::ffi::c_void) {
    let watch = unsafe { &*(param as *const PortWatch) };
    let cycle = watch.base.get() + unsafe { watch.avr.as_ref().cycle };
    watch.changes.borrow_mut().push((cycle, value as u8));
    watch.flag.set(true);
}

unsafe extern "C" fn on_pin(_: *mut ffi::avr_irq_t, value: u32, param: *mut std::ffi::c_void) {
    let watch = unsafe { &*(param as *const PinWatch) };
    let cycle = watch.base.get() + unsafe { watch.avr.as_ref().cycle };
    watch.changes.borrow_mut().push((cycle, value & 1 != 0));
}

unsafe extern "C" fn on_twi_output(
    _: *mut ffi::avr_irq_t,
    value: u32,
    param: *mut std::ffi::c_void,
) {
    let handle = unsafe { &*(param as *const TwiHandle) };
    let [_, msg, addr, data] = value.to_le_bytes();
    let reply = handle.bus.borrow_mut().message(msg, addr, data);
    if let Some((msg, addr, data)) = reply {
        let v = u32::from_le_bytes([0, msg, addr, data]);
        unsafe { ffi::avr_raise_irq(handle.input.as_ptr(), v) };
    }
}

impl Sim {
    /// Loads `elf` into a fresh `mcu` (e.g. "atmega2560") at `frequency` Hz.
    pub fn new(mcu: &str, frequency: u32, elf: &Path) -> Result<Sim, String> {
        if !elf.is_file() {
            return Err(format!("no ELF at {}", elf.display()));
        }
        let c_mcu = CString::new(mcu).map_err(|e| e.to_string())?;
        unsafe { ffi::avr_global_logger_set(Some(quiet_logger)) };
        let avr = NonNull::new(unsafe { ffi::avr_make_mcu_by_name(c_mcu.as_ptr()) })
            .ok_or_else(|| format!("simavr has no MCU {mcu}"))?;
        if unsafe { ffi::avr_init(avr.as_ptr()) } != 0 {
            return Err("avr_init failed".into());
        }
        // SAFETY: zeroed is the documented initial state of elf_firmware_t.
        let mut firmware: Box<ffi::elf_firmware_t> = Box::new(unsafe { std::mem::zeroed() });
        firmware.frequency = frequency;
        for (dst, src) in firmware.mmcu.iter_mut().zip(mcu.bytes()) {
            *dst = src as _;
        }
        let c_path = CString::new(elf.display().to_string()).map_err(|e| e.to_string())?;
        let c_name = CString::new("suntracker-emu").map_err(|e| e.to_string())?;
        // sim_setup_firmware exits the process on a bad file; checked above.
        unsafe {
            ffi::sim_setup_firmware(c_path.as_ptr(), 0, &mut *firmware, c_name.as_ptr());
            ffi::avr_load_firmware(avr.as_ptr(), &mut *firmware);
            (*avr.as_ptr()).frequency = frequency;
            (*avr.as_ptr()).sleep = Some(no_sleep);
        }
        Ok(Sim {
            avr,
            uarts: Vec::new(),
            ports: Vec::new(),
            twi: None,
            pins: Vec::new(),
            port_flag: Default::default(),
            tx_pending: false,
            min_sp: u16::MAX,
            sp_half_written: false,
            min_sp_pc: 0,
            min_sp_stack: std::env::var_os("SUNTRACKER_EMU_PC").map(|_| Vec::new()),
            awake_from: None,
            longest_awake: None,
            long_awake: Vec::new(),
            cycle_base: Rc::new(std::cell::Cell::new(0)),
            profile: None,
            fire_on_enable: Vec::new(),
            _firmware: firmware,
        })
    }

    fn getirq(&self, ctl: u32, n: u32) -> Option<NonNull<ffi::avr_irq_t>> {
        NonNull::new(unsafe { ffi::avr_io_getirq(self.avr.as_ptr(), ctl, n as _) })
    }

    /// Attaches to USART `id` ('0', '1', ...): detaches it from simavr's
    /// stdout and collects what the AVR sends.
    pub fn attach_uart(&mut self, id: char) -> Result<(), String> {
        let mut flags: u32 = 0;
        let get = ioctl_code(b'u', b'a', b'g', id as u8);
        let set = ioctl_code(b'u', b'a', b's', id as u8);
        if unsafe { ffi::avr_ioctl(self.avr.as_ptr(), get, &mut flags as *mut u32 as *mut _) } != 0
        {
            return Err(format!("no USART{id}"));
        }
        // Not to stdout, and no usleep() when the firmware polls the status.
        flags &= !(ffi::AVR_UART_FLAG_STDIO | ffi::AVR_UART_FLAG_POLL_SLEEP);
        unsafe { ffi::avr_ioctl(self.avr.as_ptr(), set, &mut flags as *mut u32 as *mut _) };
        let irq = ioctl_code(b'u', b'a', b'r', id as u8);
        let state = Box::new(RefCell::new(UartState {
            from_avr: VecDeque::new(),
            to_avr: VecDeque::new(),
            xon: true,
            avr: self.avr,
            base: self.cycle_base.clone(),
        }));
        let p = &*state as *const RefCell<UartState> as *mut std::ffi::c_void;
        let out = self.getirq(irq, ffi::UART_IRQ_OUTPUT).ok_or("uart irq")?;
        let xon = self.getirq(irq, ffi::UART_IRQ_OUT_XON).ok_or("uart irq")?;
        let xoff = self.getirq(irq, ffi::UART_IRQ_OUT_XOFF).ok_or("uart irq")?;
        let input = self.getirq(irq, ffi::UART_IRQ_INPUT).ok_or("uart irq")?;
        unsafe {
            ffi::avr_irq_register_notify(out.as_ptr(), Some(on_uart_output), p);
            ffi::avr_irq_register_notify(xon.as_ptr(), Some(on_uart_xon), p);
            ffi::avr_irq_register_notify(xoff.as_ptr(), Some(on_uart_xoff), p);
        }
        self.uarts.push((id, UartHandle { state, input }));
        Ok(())
    }

    fn uart(&self, id: char) -> &UartHandle {
        &self
            .uarts
            .iter()
            .find(|(i, _)| *i == id)
            .expect("USART attached")
            .1
    }

    /// Bytes the AVR sent on USART `id` since the last call.
    pub fn uart_take(&mut self, id: char) -> Vec<u8> {
        let mut s = self.uart(id).state.borrow_mut();
        if s.from_avr.is_empty() {
            return Vec::new();
        }
        s.from_avr.drain(..).map(|(_, b)| b).collect()
    }

    /// [`Sim::uart_take`] with the cycle each byte was written to UDRn at
    /// (simavr raises the output at the write; the byte's frame on the line
    /// follows, one character time, `cycles_per_byte`, from then).
    pub fn uart_take_timed(&mut self, id: char) -> Vec<(u64, u8)> {
        let mut s = self.uart(id).state.borrow_mut();
        s.from_avr.drain(..).collect()
    }

    /// Makes simavr time USART `id`'s line from its registers as they are
    /// now. simavr computes a USART's character time only when UBRRnL is
    /// written (`avr_uart_baud_write`, reading U2Xn, UCSZn and USBSn then);
    /// the chip's baud generator follows U2Xn at once (ATmega2560 datasheet
    /// §22.3.2, "Double Speed Operation"). An image that writes UBRRn before
    /// it sets U2Xn runs at the rate it asked on a board, but at half of it
    /// under simavr. This replays the UBRRnL write through simavr's own
    /// handler with the value in the register. An unknown USART: nothing.
    pub fn retime_uart(&mut self, id: char) {
        // UBRRnL of the ATmega2560's USART0–3 (datasheet §33, register
        // summary).
        let ubrrl: u16 = match id {
            '0' => 0xC4,
            '1' => 0xCC,
            '2' => 0xD4,
            '3' => 0x134,
            _ => return,
        };
        let value = self.peek(ubrrl);
        // SAFETY: `io` is simavr's table of I/O write handlers, indexed by
        // data address − 32; the handler and its parameter are simavr's.
        unsafe {
            let avr = self.avr.as_ptr();
            let slot = usize::from(ubrrl - 32);
            if let Some(w) = (*avr).io.get(slot) {
                if let Some(c) = w.w.c {
                    c(avr, ubrrl, value, w.w.param);
                }
            }
        }
    }

    /// Makes the interrupt whose flag is bit `bit` of the I/O register at
    /// data address `flag_reg` fire when its enable bit is set while the
    /// flag already is, as the chip does (an interrupt is requested while
    /// flag and enable are both set: ATmega2560 datasheet §7.8 "Reset and
    /// Interrupt Handling"). simavr requests an interrupt only when the flag
    /// is raised (`avr_raise_interrupt`), so one enabled after its flag
    /// never fires — e.g. TXCn, which simavr raises at the same tick as
    /// UDREn after a frame's last byte (it has no transmit double buffer),
    /// before the UDRE interrupt can enable TXCIEn. Checked after every
    /// instruction. Errors when no vector has that flag.
    pub fn fire_on_enable(&mut self, flag_reg: u16, bit: u8) -> Result<(), String> {
        let table = unsafe { &self.avr.as_ref().interrupts };
        let found = table
            .vector
            .iter()
            .take(usize::from(table.vector_count))
            .filter_map(|v| NonNull::new(*v))
            .find(|v| {
                let r = unsafe { &v.as_ref().raised };
                r.reg() == u32::from(flag_reg) && r.bit() == u32::from(bit)
            })
            .ok_or_else(|| format!("no interrupt flagged at {flag_reg:#x} bit {bit}"))?;
        self.fire_on_enable.push(found);
        Ok(())
    }

    fn regbit(&self, r: &ffi::avr_regbit_t) -> bool {
        r.reg() != 0 && (u32::from(self.peek(r.reg() as u16)) >> r.bit()) & r.mask() != 0
    }

    /// [`Sim::fire_on_enable`]'s check.
    fn raise_enabled_flags(&mut self) {
        for v in &self.fire_on_enable {
            let vec = unsafe { v.as_ref() };
            if vec.pending() == 0 && self.regbit(&vec.enable) && self.regbit(&vec.raised) {
                unsafe { ffi::avr_raise_interrupt(self.avr.as_ptr(), v.as_ptr()) };
            }
        }
    }

    /// Queues bytes for the AVR's receiver on USART `id`.
    pub fn uart_send(&mut self, id: char, bytes: &[u8]) {
        self.uart(id).state.borrow_mut().to_avr.extend(bytes);
        self.tx_pending = true;
    }

    /// Bytes still queued for USART `id`.
    pub fn uart_pending(&self, id: char) -> usize {
        self.uart(id).state.borrow().to_avr.len()
    }

    /// Pushes queued bytes into simavr's receive FIFO while it says XON
    /// (simavr then delivers them at the programmed baud rate).
    fn flush_uarts(&mut self) {
        let mut pending = false;
        for (_, u) in &self.uarts {
            loop {
                let byte = {
                    let mut s = u.state.borrow_mut();
                    if !s.xon {
                        break;
                    }
                    match s.to_avr.pop_front() {
                        Some(b) => b,
                        None => break,
                    }
                };
                unsafe { ffi::avr_raise_irq(u.input.as_ptr(), u32::from(byte)) };
            }
            pending |= !u.state.borrow().to_avr.is_empty();
        }
        self.tx_pending = pending;
    }

    /// Connects the TWI (TWI0) to `bus`.
    pub fn attach_twi(&mut self, bus: Rc<RefCell<TwiBus>>) -> Result<(), String> {
        let ctl = ioctl_code(b't', b'w', b'i', 0);
        let input = self.getirq(ctl, ffi::TWI_IRQ_INPUT).ok_or("no TWI")?;
        let output = self.getirq(ctl, ffi::TWI_IRQ_OUTPUT).ok_or("no TWI")?;
        let handle = Box::new(TwiHandle { bus, input });
        let p = &*handle as *const TwiHandle as *mut std::ffi::c_void;
        unsafe { ffi::avr_irq_register_notify(output.as_ptr(), Some(on_twi_output), p) };
        self.twi = Some(handle);
        Ok(())
    }

    /// Records every change of the levels of port `port` ('A', ...) as the
    /// port drives them (`(PINx & ~DDRx) | (PORTx & DDRx)`), with the cycle
    /// it happened at: one entry per PORTx/DDRx/PINx write that changes
    /// them (simavr filters the IRQ: a write that leaves the levels as they
    /// were is not reported, nor is a direction change that does not change
    /// a level; [`Sim::watch_direction`] sees those). `run_until` returns
    /// right after each.
    pub fn watch_port(&mut self, port: char) -> Result<(), String> {
        self.watch_port_irq(port, ffi::IOPORT_IRQ_PIN_ALL)
    }

    /// Records every change of DDRx of port `port`, with the cycle it
    /// happened at (an open-drain pin drives and releases its line through
    /// DDRx alone); `run_until` returns right after each, as for
    /// [`Sim::watch_port`].
    pub fn watch_direction(&mut self, port: char) -> Result<(), String> {
        self.watch_port_irq(port, ffi::IOPORT_IRQ_DIRECTION_ALL)
    }

    fn watch_port_irq(&mut self, port: char, which: u32) -> Result<(), String> {
        let ctl = ioctl_code(b'i', b'o', b'g', port as u8);
        let irq = self
            .getirq(ctl, which)
            .ok_or_else(|| format!("no port {port}"))?;
        let watch = Box::new(PortWatch {
            changes: RefCell::new(Vec::new()),
            flag: self.port_flag.clone(),
            avr: self.avr,
            base: self.cycle_base.clone(),
        });
        let p = &*watch as *const PortWatch as *mut std::ffi::c_void;
        unsafe { ffi::avr_irq_register_notify(irq.as_ptr(), Some(on_port_all), p) };
        self.ports.push(((port, which), watch));
        Ok(())
    }

    /// Records every level change of pin `Pxn`, including those a timer's
    /// compare output makes (PWM), with the cycle it happened at.
    pub fn watch_pin(&mut self, port: char, pin: u8) -> Result<(), String> {
        let ctl = ioctl_code(b'i', b'o', b'g', port as u8);
        let irq = self
            .getirq(ctl, u32::from(pin))
            .ok_or_else(|| format!("no pin P{port}{pin}"))?;
        let watch = Box::new(PinWatch {
            changes: RefCell::new(Vec::new()),
            avr: self.avr,
            base: self.cycle_base.clone(),
        });
        let p = &*watch as *const PinWatch as *mut std::ffi::c_void;
        unsafe { ffi::avr_irq_register_notify(irq.as_ptr(), Some(on_pin), p) };
        self.pins.push(((port, pin), watch));
        Ok(())
    }

    /// Level changes of a watched pin since the last call: (cycle, high).
    pub fn pin_changes(&mut self, port: char, pin: u8) -> Vec<(u64, bool)> {
        self.pins
            .iter()
            .find(|(k, _)| *k == (port, pin))
            .map(|(_, w)| std::mem::take(&mut *w.changes.borrow_mut()))
            .unwrap_or_default()
    }

    /// Port level changes recorded since the last call ([`Sim::watch_port`]):
    /// (cycle, driven value).
    pub fn port_changes(&mut self, port: char) -> Vec<(u64, u8)> {
        self.take_port_irq(port, ffi::IOPORT_IRQ_PIN_ALL)
    }

    /// DDRx changes recorded since the last call ([`Sim::watch_direction`]):
    /// (cycle, DDRx).
    pub fn direction_changes(&mut self, port: char) -> Vec<(u64, u8)> {
        self.take_port_irq(port, ffi::IOPORT_IRQ_DIRECTION_ALL)
    }

    fn take_port_irq(&mut self, port: char, which: u32) -> Vec<(u64, u8)> {
        self.ports
            .iter()
            .find(|(k, _)| *k == (port, which))
            .map(|(_, w)| std::mem::take(&mut *w.changes.borrow_mut()))
            .unwrap_or_default()
    }

    /// Drives input pin `Pxn` from outside (a switch, a sensor output).
    pub fn set_pin(&mut self, port: char, pin: u8, high: bool) {
        let ctl = ioctl_code(b'i', b'o', b'g', port as u8);
        if let Some(irq) = self.getirq(ctl, u32::from(pin)) {
            unsafe { ffi::avr_raise_irq(irq.as_ptr(), u32::from(high)) };
        }
    }

    /// Makes the run stop at `cycle` even while the CPU sleeps: simavr
    /// moves a sleeping CPU straight to its next timer event (a Timer0 tick
    /// can be 1 ms away), so `run_until(cycle)` alone may return well past
    /// `cycle`. This registers a simavr cycle timer that does nothing at
    /// `cycle` (`avr_cycle_timer_register`), which the sleep stops at (one
    /// cycle after it, as simavr counts a sleep). For inputs that must change
    /// at a given cycle: `stop_at(c)`, `run_until(c)`, then
    /// [`Sim::set_pin`]. One stop is pending at a time (a new call replaces
    /// it); a cycle not in the future is ignored.
    pub fn stop_at(&mut self, cycle: u64) {
        let now = self.cycle();
        if cycle > now {
            unsafe {
                ffi::avr_cycle_timer_register(
                    self.avr.as_ptr(),
                    cycle - now,
                    Some(stop_timer),
                    std::ptr::null_mut(),
                )
            };
        }
    }

    /// Puts `millivolts` on ADC input `channel` (0 = ADC0/PC0 … 7 on the
    /// ATmega328P): simavr's `ADC_IRQ_ADC0 + channel` input IRQ of the
    /// ADC module (`avr_adc.h`, ioctl `AVR_IOCTL_ADC_GETIRQ` = 'a','d','c','0'),
    /// whose values are millivolts. The level holds until the next call;
    /// each conversion the firmware starts reads it. simavr stores 16 bits:
    /// values above 65,535 mV are clamped there. It scales by its reference
    /// (`mV · 1023 / Vref`): with REFS = AVcc that is `avr_t::avcc`, which an
    /// ELF without a `.mmcu` voltage leaves 0 (simavr then uses 3,300 mV),
    /// so set it with [`Sim::set_avcc_mv`]. Nothing happens on a part
    /// without an ADC. Panics on a channel above 15 (the IRQs after the 16
    /// inputs are the temperature sensor and the triggers).
    pub fn set_adc_mv(&mut self, channel: u8, millivolts: u32) {
        assert!(channel < 16, "ADC channel {channel}");
        let ctl = ioctl_code(b'a', b'd', b'c', b'0');
        if let Some(irq) = self.getirq(ctl, ffi::ADC_IRQ_ADC0 + u32::from(channel)) {
            unsafe { ffi::avr_raise_irq(irq.as_ptr(), millivolts.min(u32::from(u16::MAX))) };
        }
    }

    /// Sets the analog supply AVcc, mV: the ADC's reference when the
    /// firmware selects AVcc (REFS = 01 on the ATmega328P; 5,000 on an Uno).
    pub fn set_avcc_mv(&mut self, millivolts: u32) {
        unsafe { (*self.avr.as_ptr()).avcc = millivolts };
    }

    /// Fills data memory `[from, to)` (data-space addresses, e.g. from the
    /// end of `.bss` to RAMEND + 1) with `pattern` before the run: what
    /// the stack never reaches keeps it ([`Sim::count_untouched`]).
    pub fn paint_ram(&mut self, from: u16, to: u16, pattern: u8) {
        let avr = unsafe { self.avr.as_ref() };
        let end = usize::from(to).min(usize::from(avr.ramend) + 1);
        for a in usize::from(from)..end {
            unsafe { *avr.data.add(a) = pattern };
        }
    }

    /// Bytes of `[from, to)` that still hold `pattern`, counted upwards
    /// from `from` (the end of `.bss`) to the first byte that does not:
    /// the stack grows down from RAMEND, so this is the RAM it never
    /// reached.
    pub fn count_untouched(&self, from: u16, to: u16, pattern: u8) -> u16 {
        let avr = unsafe { self.avr.as_ref() };
        let end = usize::from(to).min(usize::from(avr.ramend) + 1);
        let mut n = 0u16;
        for a in usize::from(from)..end {
            if unsafe { *avr.data.add(a) } != pattern {
                break;
            }
            n += 1;
        }
        n
    }

    /// Writes `bytes` into the EEPROM from address `offset` (simavr's
    /// `AVR_IOCTL_EEPROM_SET`), e.g. before the first instruction, as a
    /// programmer would (`avrdude -U eeprom:w:…`). A fresh part's EEPROM is
    /// erased (every byte 0xFF, simavr's `avr_eeprom_init`). Errors when the
    /// part has no EEPROM or the bytes do not fit.
    pub fn write_eeprom(&mut self, offset: u16, bytes: &[u8]) -> Result<(), String> {
        if bytes.is_empty() {
            return Ok(());
        }
        let size = u32::try_from(bytes.len()).map_err(|e| e.to_string())?;
        let mut copy = bytes.to_vec();
        let mut desc = ffi::avr_eeprom_desc_t {
            ee: copy.as_mut_ptr(),
            offset,
            size,
        };
        let ctl = ioctl_code(b'e', b'e', b's', b'p');
        let r = unsafe {
            ffi::avr_ioctl(
                self.avr.as_ptr(),
                ctl,
                &mut desc as *mut ffi::avr_eeprom_desc_t as *mut _,
            )
        };
        if r != 0 {
            return Err(format!(
                "EEPROM: {} bytes at {offset} do not fit (or no EEPROM)",
                bytes.len()
            ));
        }
        Ok(())
    }

    /// `len` bytes of the EEPROM from address `offset` (simavr's
    /// `AVR_IOCTL_EEPROM_GET`); `None` beyond its end or without one.
    pub fn read_eeprom(&self, offset: u16, len: usize) -> Option<Vec<u8>> {
        let mut out = vec![0u8; len];
        if len == 0 {
            return Some(out);
        }
        let mut desc = ffi::avr_eeprom_desc_t {
            ee: out.as_mut_ptr(),
            offset,
            size: u32::try_from(len).ok()?,
        };
        let ctl = ioctl_code(b'e', b'e', b'g', b'p');
        let r = unsafe {
            ffi::avr_ioctl(
                self.avr.as_ptr(),
                ctl,
                &mut desc as *mut ffi::avr_eeprom_desc_t as *mut _,
            )
        };
        (r == 0).then_some(out)
    }

    /// Cuts the power and turns it on again, as a supply that drops out
    /// would: the CPU and every peripheral reset, RAM is filled with
    /// `ram_pattern` (its contents after a power cut are undefined; the
    /// start-up code must not rely on them), bytes queued for the USARTs
    /// are lost; the EEPROM (and the flash) keep their contents, and the
    /// models outside the chip keep their state. [`Sim::cycle`] counts on.
    /// `ram_start` is the part's first RAM address (after its I/O space).
    pub fn power_cycle(&mut self, ram_start: u16, ram_pattern: u8) {
        let raw = unsafe { self.avr.as_ref().cycle };
        self.cycle_base.set(self.cycle_base.get() + raw);
        unsafe { ffi::avr_reset(self.avr.as_ptr()) };
        let top = self.ramend() + 1;
        self.paint_ram(ram_start, top, ram_pattern);
        for (_, u) in &self.uarts {
            u.state.borrow_mut().to_avr.clear();
        }
        self.tx_pending = false;
    }

    /// Program counter (byte address) and stack pointer now.
    pub fn pc_sp(&self) -> (u32, u16) {
        let avr = unsafe { self.avr.as_ref() };
        let sp = unsafe { u16::from(*avr.data.add(0x5D)) | u16::from(*avr.data.add(0x5E)) << 8 };
        (avr.pc, sp)
    }

    /// The program word at byte address `pc` (0 beyond the flash).
    fn flash_word(&self, pc: u32) -> u16 {
        let avr = unsafe { self.avr.as_ref() };
        let Ok(at) = usize::try_from(pc) else {
            return 0;
        };
        if at.saturating_add(1) > avr.flashend as usize {
            return 0;
        }
        // SAFETY: `at + 1 <= flashend`, inside simavr's flash buffer.
        unsafe { u16::from(*avr.flash.add(at)) | u16::from(*avr.flash.add(at + 1)) << 8 }
    }

    /// A byte of the data space (registers at 0–31, I/O, RAM).
    pub fn peek(&self, addr: u16) -> u8 {
        unsafe { *self.avr.as_ref().data.add(usize::from(addr)) }
    }

    /// The lowest stack pointer seen so far (after any instruction the
    /// harness ran, interrupt entries included): the stack's real peak,
    /// which painting can miss when a frame is reserved but not all written.
    pub fn min_sp(&self) -> u16 {
        self.min_sp
    }

    /// The program counter (byte address) at [`Sim::min_sp`]: where the
    /// stack peaked (`avr-addr2line -f -e ELF 0x…`).
    pub fn min_sp_pc(&self) -> u32 {
        self.min_sp_pc
    }

    /// The stack's bytes above the lowest stack pointer when it was
    /// reached, from `min_sp + 1` up (only with `SUNTRACKER_EMU_PC` set).
    pub fn min_sp_stack(&self) -> Option<&[u8]> {
        self.min_sp_stack.as_deref()
    }

    /// RAMEND of the MCU (data-space address of the last RAM byte).
    pub fn ramend(&self) -> u16 {
        unsafe { self.avr.as_ref().ramend }
    }

    /// Starts counting the cycles of every instruction by its address
    /// (sleep counted at the SLEEP's address): see [`Sim::profile`].
    pub fn enable_profile(&mut self) {
        self.profile = Some(std::collections::HashMap::new());
    }

    /// Cycles per byte address since [`Sim::enable_profile`], or `None`.
    pub fn profile(&self) -> Option<&std::collections::HashMap<u32, u64>> {
        self.profile.as_ref()
    }

    /// CPU cycles since the emulation started (counting on across
    /// [`Sim::power_cycle`]).
    pub fn cycle(&self) -> u64 {
        self.cycle_base.get() + unsafe { self.avr.as_ref().cycle }
    }

    /// The longest stretch the CPU ran without sleeping so far: its length
    /// in cycles and the cycle it ended at (a firmware that never slept
    /// has none).
    pub fn longest_awake(&self) -> Option<(u64, u64)> {
        self.longest_awake
    }

    /// The cycle the CPU woke at, while it is awake (`None` asleep).
    pub fn awake_since(&self) -> Option<u64> {
        self.awake_from
    }

    /// The stretches awake longer than [`LONG_AWAKE_CYCLES`], in order:
    /// (cycles, the cycle each ended at).
    pub fn long_awake(&self) -> &[(u64, u64)] {
        &self.long_awake
    }

    /// Runs instructions until the cycle counter reaches `cycle`, a watched
    /// port was written, or the program stops. Sleeping counts as running:
    /// simavr advances the clock to the next timer event.
    pub fn run_until(&mut self, cycle: u64) -> CpuState {
        self.port_flag.set(false);
        while self.cycle() < cycle && !self.port_flag.get() {
            if self.tx_pending {
                self.flush_uarts();
            }
            let before = self.cycle();
            let pc_before = unsafe { self.avr.as_ref().pc };
            let state = unsafe { ffi::avr_run(self.avr.as_ptr()) } as u32;
            if !self.fire_on_enable.is_empty() {
                self.raise_enabled_flags();
            }
            if self.cycle() < before {
                return CpuState::Reset;
            }
            let spent = self.cycle() - before;
            if let Some(p) = self.profile.as_mut() {
                *p.entry(pc_before).or_insert(0) += spent;
            }
            // Awake stretches: from the call in which the CPU woke to the
            // one whose instruction put it to sleep (interrupt handlers
            // inside a stretch count as part of it).
            match (state == ffi::cpu_Sleeping, self.awake_from) {
                (true, Some(from)) => {
                    let len = self.cycle().saturating_sub(from);
                    if self.longest_awake.is_none_or(|(l, _)| len > l) {
                        self.longest_awake = Some((len, self.cycle()));
                    }
                    if len > LONG_AWAKE_CYCLES && self.long_awake.len() < LONG_AWAKE_KEPT {
                        self.long_awake.push((len, self.cycle()));
                    }
                    self.awake_from = None;
                }
                (false, None) => self.awake_from = Some(before),
                _ => {}
            }
            match sp_write_half(self.flash_word(pc_before)) {
                Some(SpHalf::High) => self.sp_half_written = true,
                Some(SpHalf::Low) => self.sp_half_written = false,
                None => {}
            }
            let (pc, sp) = self.pc_sp();
            if sp < self.min_sp && !self.sp_half_written {
                self.min_sp = sp;
                self.min_sp_pc = pc;
                if self.min_sp_stack.is_some() {
                    let top = self.ramend();
                    let bytes = (sp.saturating_add(1)..=top).map(|a| self.peek(a)).collect();
                    self.min_sp_stack = Some(bytes);
                }
            }
            match state {
                ffi::cpu_Running | ffi::cpu_Sleeping | ffi::cpu_Step | ffi::cpu_StepDone => {}
                ffi::cpu_Crashed => return CpuState::Crashed,
                _ => return CpuState::Done,
            }
        }
        CpuState::Running
    }
}

/// Static RAM of an AVR ELF: the data-space range `[start, end)` that the
/// allocated sections in RAM (`.data`, `.bss`, `.noinit`) cover, read from
/// the ELF32 section headers (data addresses carry avr-gcc's 0x800000
/// offset).
/// Which half of the stack pointer an instruction writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SpHalf {
    /// `out 0x3e, Rr`: SPH.
    High,
    /// `out 0x3d, Rr`: SPL.
    Low,
}

/// The half of the stack pointer the instruction `word` writes, if it is
/// an `OUT` to SPH or SPL (`1011 1AAr rrrr AAAA`, I/O address 0x3E or
/// 0x3D: Microchip, *AVR Instruction Set Manual*, "OUT"; the stack pointer
/// at I/O 0x3E:0x3D, ATmega2560 data sheet §7.6). A frame is reserved by
/// writing SPH, SREG, then SPL, interrupts held off in between: after the
/// first write the pointer holds the new high byte beside the old low
/// byte, up to 255 B below both values, and nothing is pushed there. The
/// peak is not taken from that instant.
fn sp_write_half(word: u16) -> Option<SpHalf> {
    if word & 0xF800 != 0xB800 {
        return None;
    }
    match ((word >> 5) & 0x30) | (word & 0x0F) {
        0x3E => Some(SpHalf::High),
        0x3D => Some(SpHalf::Low),
        _ => None,
    }
}

/// RAM of a run: the static RAM from the ELF, the stack's peak measured
/// two ways, and what was never touched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RamUse {
    /// Static RAM of the image: `.data` + `.bss` (+ `.noinit`), bytes.
    pub static_bytes: u16,
    /// Peak stack, bytes, by painting: the RAM between the end of `.bss`
    /// and RAMEND is filled with a pattern before the run; this is the
    /// part of it the run overwrote (from RAMEND down).
    pub stack_painted_bytes: u16,
    /// Peak stack, bytes, from the lowest stack pointer the run reached
    /// (RAMEND − SP): counts frames that were reserved but not all
    /// written, which painting misses. At least `stack_painted_bytes`.
    pub stack_sp_bytes: u16,
    /// Painted bytes still intact above the end of `.bss`.
    pub free_bytes: u16,
    /// The MCU's RAM, bytes.
    pub total_bytes: u16,
}

impl RamUse {
    /// Measures the run so far: `ram_start` is the part's first RAM address,
    /// `static_end` the end of its static RAM, painted with `pattern` from
    /// there to RAMEND before the run.
    pub fn measure(sim: &Sim, ram_start: u16, static_end: u16, pattern: u8) -> Self {
        let top = sim.ramend() + 1;
        let free_bytes = sim.count_untouched(static_end, top, pattern);
        RamUse {
            static_bytes: static_end - ram_start,
            stack_painted_bytes: top - static_end - free_bytes,
            stack_sp_bytes: (top - 1).saturating_sub(sim.min_sp()),
            free_bytes,
            total_bytes: top - ram_start,
        }
    }

    /// Bytes left between the static RAM and the deepest stack (negative:
    /// the stack ran into the static RAM).
    pub fn headroom_bytes(&self) -> i32 {
        i32::from(self.total_bytes) - i32::from(self.static_bytes) - i32::from(self.stack_sp_bytes)
    }

    /// One line: `RAM N B: static …, stack peak … (lowest stack pointer; …
    /// by painting), never touched …`.
    pub fn summary(&self) -> String {
        format!(
            "RAM {} B: static {} B (.data + .bss), stack peak {} B (lowest stack pointer; {} B by painting), \
             never touched {} B{}",
            self.total_bytes,
            self.static_bytes,
            self.stack_sp_bytes,
            self.stack_painted_bytes,
            self.free_bytes,
            if self.headroom_bytes() < 0 {
                " — STACK OVERFLOW into the static RAM"
            } else {
                ""
            }
        )
    }

    /// Panics unless static RAM and the deepest stack leave `headroom`
    /// bytes of the part's RAM free (a test's stack budget).
    pub fn assert_headroom(&self, name: &str, headroom: u16) {
        assert!(
            self.headroom_bytes() >= i32::from(headroom),
            "{name}: static {} B + stack {} B leaves less than {headroom} B of {} B",
            self.static_bytes,
            self.stack_sp_bytes,
            self.total_bytes
        );
    }
}

pub fn static_ram(elf: &Path) -> Result<(u16, u16), String> {
    let b = std::fs::read(elf).map_err(|e| format!("{}: {e}", elf.display()))?;
    let u16_at = |o: usize| b.get(o..o + 2).map(|s| u16::from_le_bytes([s[0], s[1]]));
    let u32_at = |o: usize| {
        b.get(o..o + 4)
            .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
    };
    if b.get(0..4) != Some(&b"\x7fELF"[..]) || b.get(4) != Some(&1) || b.get(5) != Some(&1) {
        return Err(format!("{}: not a little-endian ELF32", elf.display()));
    }
    let bad = || format!("{}: truncated ELF", elf.display());
    let shoff = u32_at(0x20).ok_or_else(bad)? as usize;
    let shentsize = usize::from(u16_at(0x2E).ok_or_else(bad)?);
    let shnum = usize::from(u16_at(0x30).ok_or_else(bad)?);
    let (mut start, mut end) = (u32::MAX, 0u32);
    for i in 0..shnum {
        let h = shoff + i * shentsize;
        let flags = u32_at(h + 8).ok_or_else(bad)?;
        let addr = u32_at(h + 12).ok_or_else(bad)?;
        let size = u32_at(h + 20).ok_or_else(bad)?;
        // SHF_ALLOC, in the data space, not empty.
        if flags & 2 != 0 && (0x80_0000..0x81_0000).contains(&addr) && size > 0 {
            start = start.min(addr - 0x80_0000);
            end = end.max(addr - 0x80_0000 + size);
        }
    }
    if end == 0 {
        return Err(format!("{}: no sections in RAM", elf.display()));
    }
    Ok((start as u16, end as u16))
}

impl Drop for Sim {
    fn drop(&mut self) {
        unsafe { ffi::avr_terminate(self.avr.as_ptr()) };
    }
}

/// An ELF file as a scenario ran it: what a user compares with the file
/// they flash (`sha256sum`), and whether it is the board build.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ElfIdentity {
    /// The path it was read from.
    pub path: std::path::PathBuf,
    /// Its length, bytes.
    pub len: usize,
    /// SHA-256 of the whole file, lowercase hex (as `sha256sum` prints it).
    pub sha256_hex: String,
    /// No emulation-build time scale in it ([`crate::mega::timescale_of`]
    /// is 1): the build a user flashes, not a `SUNTRACKER_EMU_MS_PER_TICK`
    /// one.
    pub board_build: bool,
}

impl ElfIdentity {
    /// Reads the file at `path`.
    pub fn of(path: &Path) -> Result<Self, String> {
        use sha2::{Digest, Sha256};
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let sha256_hex = Sha256::digest(&bytes)
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        Ok(ElfIdentity {
            path: path.to_path_buf(),
            len: bytes.len(),
            sha256_hex,
            board_build: crate::mega::timescale_of_bytes(&bytes) == 1.0,
        })
    }
}

impl ElfIdentity {
    /// [`ElfIdentity::of`] the file at `path`, which must be a board build:
    /// an error for an emulation build.
    pub fn of_board_build(path: &Path) -> Result<Self, String> {
        let id = Self::of(path)?;
        if id.board_build {
            Ok(id)
        } else {
            Err(format!(
                "{}: an emulation build (it holds the text `timescale `), not the ELF a user flashes",
                path.display()
            ))
        }
    }
}

impl std::fmt::Display for ElfIdentity {
    /// `flashed ELF sha256=<hex> bytes=<len> path=<path>`: the line
    /// `.ci/run` compares with `sha256sum` of the release ELF.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "flashed ELF sha256={} bytes={} path={}",
            self.sha256_hex,
            self.len,
            self.path.display()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_writes_of_the_stack_pointer_halves_are_seen_as_such() {
        // A prologue's words as avr-objdump prints them (little-endian):
        // `de bf` out 0x3e, r29; `0f be` out 0x3f, r0; `cd bf` out 0x3d,
        // r28; `de b7` in r29, 0x3e; `f8 94` cli.
        assert_eq!(sp_write_half(0xBFDE), Some(SpHalf::High));
        assert_eq!(sp_write_half(0xBFCD), Some(SpHalf::Low));
        assert_eq!(sp_write_half(0xBE0F), None);
        assert_eq!(sp_write_half(0xB7DE), None);
        assert_eq!(sp_write_half(0x94F8), None);
    }

    #[test]
    fn elf_identity_is_sha256_and_tells_the_builds_apart() {
        let dir = std::env::temp_dir().join(format!("suntracker-emu-id-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // FIPS 180-2, Appendix B.1: SHA-256("abc").
        let board = dir.join("board.elf");
        std::fs::write(&board, b"abc").unwrap();
        let id = ElfIdentity::of_board_build(&board).unwrap();
        assert_eq!(
            id.sha256_hex,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!((id.len, id.board_build), (3, true));
        assert_eq!(
            id.to_string(),
            format!(
                "flashed ELF sha256={} bytes=3 path={}",
                id.sha256_hex,
                board.display()
            )
        );
        // The text only an emulation build logs, anywhere in the file.
        let emu = dir.join("emu.elf");
        std::fs::write(&emu, b"\x7fELF..timescale \x00").unwrap();
        assert!(!ElfIdentity::of(&emu).unwrap().board_build);
        assert!(ElfIdentity::of_board_build(&emu).is_err());
        assert_eq!(crate::mega::timescale_of(&emu).unwrap(), 60.0);
        assert_eq!(crate::mega::timescale_of(&board).unwrap(), 1.0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
