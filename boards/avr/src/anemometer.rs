//! An anemometer pulse counter on an external interrupt (ATmega2560
//! datasheet §15 / ATmega328P §12 "External Interrupts": EICRA/EICRB sense
//! control, EIMSK, EIFR).
//!
//! The reed switch or Hall sensor pulls the INTn pin low once per pulse; the
//! falling edge interrupt counts it. One counter for the board: a tracker has
//! one anemometer. Debounce is the sensor's business (a reed switch needs an
//! RC filter; at 50 m/s a usual cup anemometer gives under 100 Hz).

use core::cell::Cell;

use avr_device::interrupt::{self, Mutex};

use super::chip;

/// Pulses since the last [`Anemometer::take_pulses`].
static PULSES: Mutex<Cell<u16>> = Mutex::new(Cell::new(0));

/// External interrupt lines: INT0, INT1 on both chips (Uno D2, D3 = PD2,
/// PD3; Mega D21, D20 = PD0, PD1, shared with the TWI); INT2..INT7 on the
/// 2560 only (Mega D19, D18 = PD2, PD3; D2, D3 = PE4, PE5; PE6, PE7 not on
/// the Mega's headers).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExtInt {
    /// INT0.
    Int0,
    /// INT1.
    Int1,
    /// INT2 (ATmega2560).
    #[cfg(avr_atmega2560)]
    Int2,
    /// INT3 (ATmega2560).
    #[cfg(avr_atmega2560)]
    Int3,
    /// INT4 (ATmega2560).
    #[cfg(avr_atmega2560)]
    Int4,
    /// INT5 (ATmega2560).
    #[cfg(avr_atmega2560)]
    Int5,
    /// INT6 (ATmega2560).
    #[cfg(avr_atmega2560)]
    Int6,
    /// INT7 (ATmega2560).
    #[cfg(avr_atmega2560)]
    Int7,
}

impl ExtInt {
    fn index(self) -> u8 {
        self as u8
    }
}

/// The pulse counter. Bind the line's vector with
/// `avr_board_interrupts!(intN)` for the same N; the pin is left as the
/// image set it (an input; add a pull-up for a reed switch).
pub struct Anemometer {
    exint: chip::EXINT,
    line: ExtInt,
}

/// ISCn1:ISCn0 = 0b10: the falling edge of INTn raises the interrupt.
const ISC_FALLING: u8 = 0b10;

impl Anemometer {
    /// Takes the external interrupt unit and arms `line` on falling edges,
    /// count zero.
    pub fn new(exint: chip::EXINT, line: ExtInt) -> Self {
        let n = line.index();
        let mask = 1u8 << n;
        interrupt::free(|cs| {
            PULSES.borrow(cs).set(0);
            // Disarm while the sense changes (a change may raise the flag).
            // SAFETY (all `bits` below): EIMSK, EIFR, EICRA and EICRB hold
            // one bit per line or two sense bits per line; every pattern is
            // valid, and only this line's bits change.
            exint
                .eimsk()
                .modify(|r, w| unsafe { w.bits(r.bits() & !mask) });
            let shift = 2 * (n % 4);
            let sense = |bits: u8| (bits & !(0b11 << shift)) | ISC_FALLING << shift;
            if n < 4 {
                exint
                    .eicra()
                    .modify(|r, w| unsafe { w.bits(sense(r.bits())) });
            } else {
                #[cfg(avr_atmega2560)]
                exint
                    .eicrb()
                    .modify(|r, w| unsafe { w.bits(sense(r.bits())) });
            }
            // Clear a stale flag (write 1), then arm.
            exint.eifr().write(|w| unsafe { w.bits(mask) });
            exint
                .eimsk()
                .modify(|r, w| unsafe { w.bits(r.bits() | mask) });
        });
        Anemometer { exint, line }
    }

    /// Pulses since the last call (or since [`Anemometer::new`]), and the
    /// count reset to zero, in one critical section: no pulse is counted
    /// twice or lost between the read and the reset. Saturates at 65,535.
    pub fn take_pulses(&mut self) -> u16 {
        interrupt::free(|cs| PULSES.borrow(cs).replace(0))
    }

    /// Disarms the line and gives the unit back.
    pub fn release(self) -> chip::EXINT {
        let mask = 1u8 << self.line.index();
        // SAFETY: as in `new`.
        self.exint
            .eimsk()
            .modify(|r, w| unsafe { w.bits(r.bits() & !mask) });
        self.exint
    }
}

/// The INTn handler's work; bound by `avr_board_interrupts!`.
#[inline(always)]
pub fn on_anemometer_edge() {
    interrupt::free(|cs| {
        let count = PULSES.borrow(cs);
        count.set(count.get().saturating_add(1));
    });
}
