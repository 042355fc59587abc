//! The watchdog (ATmega2560 datasheet §12 / ATmega328P §10 "System Control
//! and Reset": "Watchdog Timer", WDTCSR and its timed sequence, MCUSR.WDRF).
//!
//! Nothing here runs unless the image calls [`Watchdog::enable`]: the
//! watchdog stays off (unless the WDTON fuse forces it on).

use avr_device::interrupt;

use super::chip;

/// The watchdog in system-reset mode with a ~2 s timeout.
pub struct Watchdog {
    wdt: chip::WDT,
}

impl Watchdog {
    /// Starts the watchdog: reset after 256K cycles of its 128 kHz
    /// oscillator (WDP = 0b0111), 2.0 s nominal; the oscillator's spread
    /// over voltage and temperature (datasheet "Watchdog Oscillator") makes
    /// it roughly 1.6–2.4 s. Feed it more often than once a second.
    ///
    /// Clears MCUSR.WDRF first: while it is set WDE cannot be cleared, and
    /// a later [`Watchdog::disable`] would not work.
    pub fn enable(wdt: chip::WDT, cpu: &chip::CPU) -> Self {
        interrupt::free(|_| {
            avr_device::asm::wdr();
            cpu.mcusr().modify(|_, w| w.wdrf().clear_bit());
            // Timed sequence: WDCE + WDE, then within four cycles the new
            // prescaler with WDE (interrupts are off here).
            wdt.wdtcsr().write(|w| w.wdce().set_bit().wde().set_bit());
            wdt.wdtcsr()
                .write(|w| w.wde().set_bit().wdpl().cycles_256k().wdph().clear_bit());
        });
        Watchdog { wdt }
    }

    /// Restarts the timeout (WDR instruction).
    #[inline(always)]
    pub fn feed(&mut self) {
        avr_device::asm::wdr();
    }

    /// Stops the watchdog and gives it back.
    pub fn disable(self) -> chip::WDT {
        interrupt::free(|_| {
            avr_device::asm::wdr();
            self.wdt
                .wdtcsr()
                .write(|w| w.wdce().set_bit().wde().set_bit());
            self.wdt.wdtcsr().write(|w| w.wde().clear_bit());
        });
        self.wdt
    }
}
