//! Two quadrature encoders on pin-change interrupts (ATmega328P datasheet
//! §12 "External Interrupts": "Pin Change Interrupt Timing", register
//! description of PCICR, PCIFR, PCMSK2; ATmega2560 §15), counted ×4 by
//! `drivers::encoder::SharedEncoder` (Chowdhury et al. 2019: YMT22 optical
//! encoders on the two servo shafts).
//!
//! | encoder | channel | ATmega328P pin | Uno header | ATmega2560 pin | Mega header | PCINT |
//! |---|---|---|---|---|---|---|
//! | C (azimuth) | A | PD4 | D4 | PK4 | A12 | 20 |
//! | C (azimuth) | B | PD5 | D5 | PK5 | A13 | 21 |
//! | A (tilt) | A | PD6 | D6 | PK6 | A14 | 22 |
//! | A (tilt) | B | PD7 | D7 | PK7 | A15 | 23 |
//!
//! Why these pins: all four are in one pin-change group (PCINT23:16, one
//! vector, PCINT2), and in one port, so a single read of PIND (PINK on the
//! 2560) gives both channels of both encoders at the same instant — the
//! decoder never pairs an A level with a B level read at another time. On
//! the Uno the rest of PORTD is taken or kept: PD0/PD1 the USART0 log,
//! PD2/PD3 (D2/D3) INT0/INT1 for the anemometer or other edge counters
//! ([`super::Anemometer`]); they stay out of PCMSK2, so their edges never
//! enter this handler. PD5/PD6 are Timer0's OC0B/OC0A, unused (Timer0 runs
//! the millisecond clock with its outputs disconnected); PD6/PD7 are the
//! analog comparator's inputs, unused. That leaves D8 (PB0), D11 and D12
//! for the home switches (D13 carries the LED), D9/D10 for the servos
//! ([`super::Timer1Pwm`]), A0 for the panel voltage ([`super::Adc`]), A4/A5
//! for the I²C bus and A1–A3 free.
//!
//! Any change of an enabled pin sets PCIF2 and, with PCIE2 on, runs
//! [`on_encoder_pin_change`] (bound by `avr_board_interrupts!(pcint2)`):
//! one read of the pin register, then `SharedEncoder::update` for each
//! encoder whose two bits changed since the last read.
//! Changes that happen while the handler is pending merge into one
//! interrupt: two edges of one encoder closer together than the interrupt
//! latency plus the handler's read show as both channels changed, which the
//! decoder counts as an error ([`SharedEncoder::errors`]) instead of a
//! count. The board layer's notes give the handler's cycle count and the
//! edge rate it keeps up with.

use core::cell::Cell;

use avr_device::interrupt::{self, Mutex};
use drivers::encoder::SharedEncoder;

use super::{chip, Port};

/// Encoder C (azimuth): channel A on bit 4, B on bit 5.
static ENCODER_C: SharedEncoder = SharedEncoder::new();
/// Encoder A (tilt): channel A on bit 6, B on bit 7.
static ENCODER_A: SharedEncoder = SharedEncoder::new();
/// The pin register as the handler (or [`PinChangeEncoders::start`]) last
/// read it: an encoder whose two bits did not change is not fed, which
/// halves the handler's time for the usual single edge.
static LAST_PINS: Mutex<Cell<u8>> = Mutex::new(Cell::new(0));

/// The port of the PCINT23:16 group: PORTD on the ATmega328P.
#[cfg(not(avr_atmega2560))]
pub type EncoderPort = chip::PORTD;
/// The port of the PCINT23:16 group: PORTK on the ATmega2560.
#[cfg(avr_atmega2560)]
pub type EncoderPort = chip::PORTK;

const C_A: u8 = 1 << 4;
const C_B: u8 = 1 << 5;
const A_A: u8 = 1 << 6;
const A_B: u8 = 1 << 7;
/// The four encoder bits, as PCMSK2 bits (PCINT20..23) and port bits.
const ENCODER_PINS: u8 = C_A | C_B | A_A | A_B;
/// PCIE2 in PCICR's `pcie` field, PCIF2 in PCIFR's `pcif` field.
const GROUP_2: u8 = 1 << 2;

/// Both encoders' channel levels from one read of the pin register; only
/// an encoder whose bits changed since the last read is fed (an unchanged
/// pair would decode "no change").
#[inline(always)]
fn feed(pins: u8) {
    let changed = interrupt::free(|cs| LAST_PINS.borrow(cs).replace(pins)) ^ pins;
    if changed & (C_A | C_B) != 0 {
        ENCODER_C.update(pins & C_A != 0, pins & C_B != 0);
    }
    if changed & (A_A | A_B) != 0 {
        ENCODER_A.update(pins & A_A != 0, pins & A_B != 0);
    }
}

/// The two encoders, counting from [`PinChangeEncoders::start`] on.
pub struct PinChangeEncoders {
    _armed: (),
}

impl PinChangeEncoders {
    /// Makes the four pins inputs (with the internal pull-up if `pull_up`,
    /// for open-collector outputs), takes both encoders' present levels as
    /// their state (`SharedEncoder::set_levels`, no count) and arms
    /// PCINT20..23. Counts are not reset (they start at 0 after a reset;
    /// `SharedEncoder::set_count` redefines them). Bind the vector with
    /// `avr_board_interrupts!(pcint2)`.
    ///
    /// The levels are read after the pins are enabled and a stale PCIF2 is
    /// cleared: an edge after the read raises the flag, and the handler
    /// reads the new levels once interrupts are on; none is lost.
    pub fn start(exint: &chip::EXINT, port: &EncoderPort, pull_up: bool) -> Self {
        port.set_ddr(ENCODER_PINS, false);
        port.set_port(ENCODER_PINS, pull_up);
        interrupt::free(|cs| {
            exint
                .pcicr()
                .modify(|r, w| w.pcie().set(r.pcie().bits() & !GROUP_2));
            exint
                .pcmsk2()
                .modify(|r, w| w.pcint().set(r.pcint().bits() | ENCODER_PINS));
            exint.pcifr().write(|w| w.pcif().set(GROUP_2));
            let pins = port.pin();
            ENCODER_C.set_levels(pins & C_A != 0, pins & C_B != 0);
            ENCODER_A.set_levels(pins & A_A != 0, pins & A_B != 0);
            LAST_PINS.borrow(cs).set(pins);
            exint
                .pcicr()
                .modify(|r, w| w.pcie().set(r.pcie().bits() | GROUP_2));
        });
        PinChangeEncoders { _armed: () }
    }

    /// Encoder C (azimuth; bits 4/5: Uno D4/D5, Mega A12/A13), for
    /// `suntracker::hw::ServoAxis` (`EncoderCount`).
    pub fn encoder_c(&self) -> &'static SharedEncoder {
        &ENCODER_C
    }

    /// Encoder A (tilt; bits 6/7: Uno D6/D7, Mega A14/A15).
    pub fn encoder_a(&self) -> &'static SharedEncoder {
        &ENCODER_A
    }

    /// Disarms the four pins (PCIE2 too when no other PCINT23:16 pin is
    /// enabled); the counts stand still.
    pub fn stop(self, exint: &chip::EXINT) {
        interrupt::free(|_| {
            exint
                .pcmsk2()
                .modify(|r, w| w.pcint().set(r.pcint().bits() & !ENCODER_PINS));
            if exint.pcmsk2().read().pcint().bits() == 0 {
                exint
                    .pcicr()
                    .modify(|r, w| w.pcie().set(r.pcie().bits() & !GROUP_2));
            }
        });
    }
}

/// The PCINT2 handler's work; bound by `avr_board_interrupts!(pcint2)`.
#[inline(always)]
pub fn on_encoder_pin_change() {
    // SAFETY: a read of the port's input register (PIND / PINK), which has
    // no side effect; the port's other registers are not touched.
    let port = unsafe { &*EncoderPort::ptr() };
    #[cfg(not(avr_atmega2560))]
    let pins = port.pind().read().bits();
    #[cfg(avr_atmega2560)]
    let pins = port.pink().read().bits();
    feed(pins);
}
