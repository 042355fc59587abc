//! The ATmega2560's RS-485 port for a Modbus RTU server: USART2 (RXD2 PH0,
//! TXD2 PH1) with the transceiver's driver enable on PH3, and Timer/Counter5
//! free-running as the line's microsecond clock (ATmega2560 datasheet §22
//! "USART": "Parity Generator", "Frame Formats", "Transmitter Flags and
//! Interrupts" (UDREn, TXCn), "Receiver Error Flags" (FEn, DORn, UPEn),
//! UCSRnA/B/C; §17 "16-bit Timer/Counter": "Normal Mode", "Accessing 16-bit
//! Registers").
//!
//! **Half duplex, no copy of the reply.** The port either receives or
//! sends, as the bus does: a master waits for the reply before it speaks
//! again (Modbus over Serial Line, §2.5.1). While receiving, the receive
//! interrupt puts each byte with its arrival time (a 16-bit stamp of Timer5
//! in 16 µs units) into a ring of [`RX_ENTRIES`]; the Modbus port takes
//! them each pass and frames them. A reply is sent from where the port built
//! it, its receive buffer (`ModbusLine::send`: the port leaves those bytes
//! alone while the line is busy): the receiver off and the ring emptied
//! (what is in it then is not for us: the master waits for our reply), the
//! driver enable high, and the bytes moved to the transmitter by the
//! data-register-empty interrupt (no gap between them, whatever the main
//! loop does); the transmit-complete interrupt, once the last stop bit has
//! left, releases the driver enable and turns the receiver on again. With
//! /RE tied to DE the transceiver gives no echo either. No second 256-byte
//! buffer: on this part's 8 KB of RAM that mattered.
//!
//! **Times.** Timer5 counts at 16 MHz / 256, 16 µs a count, and wraps every
//! 1.05 s; the receive interrupt stamps each byte with the count. The line
//! ([`Rs485`]) extends the count to 32 bits each time it is read (the
//! Modbus port reads it every pass, far more often than once a second) and
//! dates each byte back from the present by its stamp's age, so a byte read
//! within 1.05 s of its arrival has its true time to 16 µs, which the frame
//! layer's 1.5- and 3.5-character silences (859 µs and 2 ms at 19,200 baud)
//! need. Timer5 runs on the CPU clock, also in an emulator build whose
//! millisecond clock is scaled.
//!
//! **Errors.** A byte with a framing or parity error, one the hardware
//! overran, and one the full ring cannot take are dropped and counted: the
//! frame then misses a byte, and the frame layer drops it (the gap, or the
//! CRC), as the specification asks of a frame with a parity error.

use core::cell::RefCell;

use avr_device::interrupt::{self, Mutex};

use super::{chip, CPU_HZ};

/// Receive ring entries (bytes waiting with their stamps): 32 bytes are
/// 17 ms of the line at 19,200 baud, more than any request a master sends
/// to read (8 bytes) or to write the tracker's controls (at most 21).
pub const RX_ENTRIES: usize = 32;
/// Microseconds a Timer5 count (prescaler 256 at 16 MHz).
pub const US_PER_COUNT: u32 = 256 / (CPU_HZ / 1_000_000);
/// The driver-enable pin's bit in port H (PH3, Mega D6).
const DE_BIT: u8 = 1 << 3;

/// The reply being sent: where its bytes are.
#[derive(Clone, Copy)]
struct Reply(*const u8);

// SAFETY: the pointer is only read, by the data-register-empty interrupt,
// while the reply it points into stays in place and unchanged (`send`).
unsafe impl Send for Reply {}

/// What the interrupts and the line share.
struct Line {
    /// Receiving: three bytes an entry, the byte and its stamp.
    ring: [u8; RX_ENTRIES * 3],
    head: u8,
    len: u8,
    /// Sending: the reply, its length and the next byte's index.
    reply: Reply,
    reply_len: u16,
    next: u16,
    sending: bool,
    /// Bytes dropped (errors, overrun, a full ring) since start.
    dropped: u16,
}

static LINE: Mutex<RefCell<Line>> = Mutex::new(RefCell::new(Line {
    ring: [0; RX_ENTRIES * 3],
    head: 0,
    len: 0,
    reply: Reply(core::ptr::null()),
    reply_len: 0,
    next: 0,
    sending: false,
    dropped: 0,
}));

/// Parity of the line (Modbus over Serial Line §2.5.1: even by default; no
/// parity takes two stop bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Parity {
    /// No parity, two stop bits.
    None,
    /// Odd parity, one stop bit.
    Odd,
    /// Even parity, one stop bit.
    Even,
}

impl Parity {
    /// The configuration's `modbus.parity` code: 0 none, 1 odd, 2 even
    /// (anything else even, the default).
    pub fn from_code(code: u8) -> Self {
        match code {
            0 => Parity::None,
            1 => Parity::Odd,
            _ => Parity::Even,
        }
    }
}

/// The RS-485 port: USART2, the driver enable on PH3, Timer5's count.
pub struct Rs485 {
    usart: chip::USART2,
    _tc5: chip::TC5,
    /// The 32-bit count: the high half counts Timer5's wraps seen.
    high: u16,
    last_count: u16,
}

impl Rs485 {
    /// Starts the port at `baud` and `parity`: Timer5 free-running, PH3 an
    /// output driven low (receiving), USART2 receiving with its interrupt.
    /// Needs the vectors of `avr_board_interrupts!(usart2)`.
    pub fn new(
        usart: chip::USART2,
        tc5: chip::TC5,
        porth: &chip::PORTH,
        baud: u32,
        parity: Parity,
    ) -> Self {
        tc5.tccr5a().reset();
        tc5.tccr5b().write(|w| w.cs5().prescale_256());
        // SAFETY (both writes): every bit pattern of PORTH and DDRH is valid;
        // only PH3's bit changes, with interrupts off.
        interrupt::free(|_| {
            porth
                .porth()
                .modify(|r, w| unsafe { w.bits(r.bits() & !DE_BIT) });
            porth
                .ddrh()
                .modify(|r, w| unsafe { w.bits(r.bits() | DE_BIT) });
        });
        // Double speed and the frame format before the rate: the chip does
        // not mind the order, simavr computes a byte's time when UBRR is
        // written, from the bits set then (written after, U2X would leave
        // its bytes at half the rate, 2 characters apart: every frame
        // broken by the 1.5-character rule).
        usart.ucsr2a().write(|w| w.u2x2().set_bit());
        usart.ucsr2c().write(|w| {
            let w = w.ucsz2().chr8();
            match parity {
                Parity::None => w.usbs2().set_bit().upm2().disabled(),
                Parity::Odd => w.upm2().parity_odd(),
                Parity::Even => w.upm2().parity_even(),
            }
        });
        usart
            .ubrr2()
            .write(|w| w.set(super::serial::ubrr_u2x(baud)));
        usart
            .ucsr2b()
            .write(|w| w.txen2().set_bit().rxen2().set_bit().rxcie2().set_bit());
        Rs485 {
            usart,
            _tc5: tc5,
            high: 0,
            last_count: 0,
        }
    }

    /// Timer5's count; read with interrupts off (the receive interrupt's
    /// read of the same 16-bit register shares the TEMP byte).
    fn count() -> u16 {
        interrupt::free(|_| timer5_count())
    }

    /// A reply is being sent (the driver enable is high).
    pub fn sending(&self) -> bool {
        interrupt::free(|cs| LINE.borrow(cs).try_borrow().map_or(false, |l| l.sending))
    }

    /// The 32-bit count of `count` (the present), its wraps counted.
    fn extend(&mut self, count: u16) -> u32 {
        if count < self.last_count {
            self.high = self.high.wrapping_add(1);
        }
        self.last_count = count;
        (u32::from(self.high) << 16) | u32::from(count)
    }
}

/// Timer5's count (TCNT5L first, then the high byte from TEMP).
#[inline(always)]
fn timer5_count() -> u16 {
    // SAFETY: a read of TCNT5, which has no side effect but on TEMP; every
    // reader runs with interrupts off.
    let tc5 = unsafe { chip::TC5::steal() };
    tc5.tcnt5().read().bits()
}

impl suntracker::sunspec::ModbusLine for Rs485 {
    fn receive(&mut self) -> Option<(u8, u32)> {
        let (byte, stamp, now) = interrupt::free(|cs| {
            let mut line = LINE.borrow(cs).try_borrow_mut().ok()?;
            if line.sending || line.len == 0 {
                return None;
            }
            let at = usize::from(line.head) * 3;
            let &[byte, lo, hi] = line.ring.get(at..at + 3)? else {
                return None;
            };
            let stamp = u16::from_le_bytes([lo, hi]);
            line.head = (line.head + 1) % RX_ENTRIES as u8;
            line.len -= 1;
            Some((byte, stamp, timer5_count()))
        })?;
        let now32 = self.extend(now);
        let age = u32::from(now.wrapping_sub(stamp));
        Some((byte, now32.wrapping_sub(age).wrapping_mul(US_PER_COUNT)))
    }

    fn now_us(&mut self) -> u32 {
        let count = Self::count();
        self.extend(count).wrapping_mul(US_PER_COUNT)
    }

    fn send(&mut self, frame: &[u8]) {
        let Ok(n) = u16::try_from(frame.len()) else {
            return;
        };
        interrupt::free(|cs| {
            let Ok(mut line) = LINE.borrow(cs).try_borrow_mut() else {
                return;
            };
            if line.sending || n == 0 {
                return;
            }
            // The interrupt reads the reply where it is: the Modbus port
            // leaves it unchanged while `busy` says so, and the board keeps
            // the port in place (a local of its loop, which never returns).
            line.reply = Reply(frame.as_ptr());
            line.reply_len = n;
            line.next = 0;
            line.head = 0;
            line.len = 0;
            line.sending = true;
            // Receiver off, the transmit-complete flag cleared (written 1),
            // the driver on, then the data-register-empty interrupt moves
            // the bytes.
            self.usart
                .ucsr2a()
                .write(|w| w.u2x2().set_bit().txc2().set_bit());
            self.usart
                .ucsr2b()
                .write(|w| w.txen2().set_bit().udrie2().set_bit());
            // SAFETY: PORTH's output register, every bit pattern valid;
            // only PH3's bit changes, in this critical section.
            let porth = unsafe { chip::PORTH::steal() };
            porth
                .porth()
                .modify(|r, w| unsafe { w.bits(r.bits() | DE_BIT) });
        });
    }

    fn busy(&mut self) -> bool {
        self.sending()
    }
}

/// USART2 receive complete: the byte and its stamp into the ring.
#[inline(always)]
pub fn on_usart2_rx() {
    // SAFETY: the receive path's registers; UDR2 read once here.
    let usart = unsafe { chip::USART2::steal() };
    let status = usart.ucsr2a().read();
    let byte = usart.udr2().read().bits();
    let stamp = timer5_count();
    interrupt::free(|cs| {
        let Ok(mut line) = LINE.borrow(cs).try_borrow_mut() else {
            return;
        };
        let bad =
            status.fe2().bit_is_set() || status.dor2().bit_is_set() || status.upe2().bit_is_set();
        if line.sending || bad || usize::from(line.len) >= RX_ENTRIES {
            line.dropped = line.dropped.wrapping_add(1);
            return;
        }
        let at = ((usize::from(line.head) + usize::from(line.len)) % RX_ENTRIES) * 3;
        if let Some([b, lo, hi]) = line.ring.get_mut(at..at + 3) {
            [*lo, *hi] = stamp.to_le_bytes();
            *b = byte;
            line.len += 1;
        }
    });
}

/// USART2 data register empty: the reply's next byte; with the last, the
/// transmit-complete interrupt armed in place of this one.
#[inline(always)]
pub fn on_usart2_udre() {
    // SAFETY: the transmit path's registers, owned by the send under way.
    let usart = unsafe { chip::USART2::steal() };
    interrupt::free(|cs| {
        let Ok(mut line) = LINE.borrow(cs).try_borrow_mut() else {
            return;
        };
        if line.next < line.reply_len {
            // SAFETY: `next` < the reply's length, and the reply stays in
            // place and unchanged while `sending` (see `send`).
            let byte = unsafe { line.reply.0.add(usize::from(line.next)).read() };
            line.next += 1;
            if line.next == line.reply_len {
                // The last byte: the transmit-complete flag cleared (it may
                // be set if the line ran idle before this interrupt) and its
                // interrupt on, this one off, before the byte goes in; the
                // flag then rises when this byte's stop bit is out. (Not
                // armed afterwards: simavr raises an interrupt only at the
                // flag's rise, not when its enable comes on later.)
                usart
                    .ucsr2a()
                    .write(|w| w.u2x2().set_bit().txc2().set_bit());
                usart
                    .ucsr2b()
                    .write(|w| w.txen2().set_bit().txcie2().set_bit());
            }
            usart.udr2().write(|w| w.set(byte));
        } else {
            // Nothing to send (cannot happen: `send` starts no empty
            // reply): let the transmit-complete interrupt end the send.
            usart
                .ucsr2b()
                .write(|w| w.txen2().set_bit().txcie2().set_bit());
        }
    });
}

/// USART2 transmit complete (the last stop bit out): the driver released,
/// the receiver on again with an empty ring.
#[inline(always)]
pub fn on_usart2_tx() {
    // SAFETY: the port's registers and PORTH's output register (every bit
    // pattern valid; only PH3's bit changes, with interrupts off); the send
    // under way has ended.
    let usart = unsafe { chip::USART2::steal() };
    let porth = unsafe { chip::PORTH::steal() };
    interrupt::free(|cs| {
        porth
            .porth()
            .modify(|r, w| unsafe { w.bits(r.bits() & !DE_BIT) });
        usart
            .ucsr2b()
            .write(|w| w.txen2().set_bit().rxen2().set_bit().rxcie2().set_bit());
        if let Ok(mut line) = LINE.borrow(cs).try_borrow_mut() {
            line.sending = false;
            line.reply = Reply(core::ptr::null());
            line.head = 0;
            line.len = 0;
        }
    });
}
