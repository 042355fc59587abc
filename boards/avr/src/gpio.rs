//! Port bits as embedded-hal 1.0 pins (ATmega2560 / ATmega328P datasheet
//! §13 "I/O-Ports": "Configuring the Pin", "Toggling the Pin", register
//! description of PORTx, DDRx, PINx).
//!
//! A pin is a port plus a bit number, both in its type
//! (`OutputPin<'_, chip::PORTB, 7>` is PB7, the Mega's LED on D13); it
//! borrows the port, so the image keeps the port peripheral and hands out
//! several pins of it. Level changes write the bit's mask to PINx, which
//! toggles only that PORTx bit in one store: no read-modify-write of PORTx,
//! so pins of one port used in the main loop and in an interrupt never
//! undo each other's writes. Direction changes (DDRx) are read-modify-write
//! with interrupts off (SREG saved, `cli`, SREG restored, written out rather
//! than as an `interrupt::free` closure, which opt-level "z" keeps as a call).

use core::convert::Infallible;
use core::marker::PhantomData;

use avr_device::interrupt;
use embedded_hal::digital::ErrorType;

use super::chip;

/// An I/O port: its PINx, DDRx and PORTx registers.
pub trait Port {
    /// Reads PINx (the pin levels).
    fn pin(&self) -> u8;
    /// Writes PINx: each 1 bit toggles that PORTx bit.
    fn toggle(&self, mask: u8);
    /// Reads PORTx (output levels / pull-ups).
    fn port(&self) -> u8;
    /// Sets (`on`) or clears the `mask` bits of DDRx, atomically.
    fn set_ddr(&self, mask: u8, on: bool);
    /// Sets (`on`) or clears the `mask` bits of PORTx, atomically.
    fn set_port(&self, mask: u8, on: bool);
}

fn with_bits(value: u8, mask: u8, on: bool) -> u8 {
    if on {
        value | mask
    } else {
        value & !mask
    }
}

macro_rules! port {
    ($($port:ident: $pin:ident, $ddr:ident, $out:ident;)*) => {$(
        impl Port for chip::$port {
            #[inline(always)]
            fn pin(&self) -> u8 {
                self.$pin().read().bits()
            }
            #[inline(always)]
            fn toggle(&self, mask: u8) {
                // SAFETY: the eight bits of PINx are eight independent pins;
                // every pattern is a valid write (1 toggles, 0 leaves).
                self.$pin().write(|w| unsafe { w.bits(mask) });
            }
            #[inline(always)]
            fn port(&self) -> u8 {
                self.$out().read().bits()
            }
            #[inline(always)]
            fn set_ddr(&self, mask: u8, on: bool) {
                let irq = interrupt::disable_save();
                // SAFETY: every DDRx pattern is valid (one direction bit
                // per pin).
                self.$ddr()
                    .modify(|r, w| unsafe { w.bits(with_bits(r.bits(), mask, on)) });
                // SAFETY: restores the flag saved just above, nothing nested.
                unsafe { interrupt::restore(irq) };
            }
            #[inline(always)]
            fn set_port(&self, mask: u8, on: bool) {
                let irq = interrupt::disable_save();
                // SAFETY: every PORTx pattern is valid (one level or pull-up
                // bit per pin).
                self.$out()
                    .modify(|r, w| unsafe { w.bits(with_bits(r.bits(), mask, on)) });
                // SAFETY: restores the flag saved just above, nothing nested.
                unsafe { interrupt::restore(irq) };
            }
        }
    )*};
}

port! {
    PORTB: pinb, ddrb, portb;
    PORTC: pinc, ddrc, portc;
    PORTD: pind, ddrd, portd;
}
#[cfg(avr_atmega2560)]
port! {
    PORTA: pina, ddra, porta;
    PORTE: pine, ddre, porte;
    PORTF: pinf, ddrf, portf;
    PORTG: ping, ddrg, portg;
    PORTH: pinh, ddrh, porth;
    PORTJ: pinj, ddrj, portj;
    PORTK: pink, ddrk, portk;
    PORTL: pinl, ddrl, portl;
}

/// The bit mask of bit `BIT`; a `BIT` over 7 fails to compile.
struct Mask<const BIT: u8>;
impl<const BIT: u8> Mask<BIT> {
    const VALUE: u8 = {
        assert!(BIT < 8, "a port has bits 0..=7");
        1 << BIT
    };
}

/// A push-pull output on bit `BIT` of port `P`.
pub struct OutputPin<'p, P: Port, const BIT: u8> {
    port: &'p P,
    _bit: PhantomData<Mask<BIT>>,
}

impl<'p, P: Port, const BIT: u8> OutputPin<'p, P, BIT> {
    /// Makes the bit an output at level `high`. The level is written before
    /// the direction, so the pin never glitches to the other level.
    pub fn new(port: &'p P, high: bool) -> Self {
        port.set_port(Mask::<BIT>::VALUE, high);
        port.set_ddr(Mask::<BIT>::VALUE, true);
        OutputPin {
            port,
            _bit: PhantomData,
        }
    }

    fn is_set(&self) -> bool {
        self.port.port() & Mask::<BIT>::VALUE != 0
    }

    fn set(&mut self, high: bool) {
        if self.is_set() != high {
            self.port.toggle(Mask::<BIT>::VALUE);
        }
    }
}

impl<P: Port, const BIT: u8> ErrorType for OutputPin<'_, P, BIT> {
    type Error = Infallible;
}

impl<P: Port, const BIT: u8> embedded_hal::digital::OutputPin for OutputPin<'_, P, BIT> {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.set(false);
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.set(true);
        Ok(())
    }
}

impl<P: Port, const BIT: u8> embedded_hal::digital::StatefulOutputPin for OutputPin<'_, P, BIT> {
    fn is_set_high(&mut self) -> Result<bool, Infallible> {
        Ok(self.is_set())
    }
    fn is_set_low(&mut self) -> Result<bool, Infallible> {
        Ok(!self.is_set())
    }
    /// One write to PINx.
    fn toggle(&mut self) -> Result<(), Infallible> {
        self.port.toggle(Mask::<BIT>::VALUE);
        Ok(())
    }
}

/// An input on bit `BIT` of port `P`, with or without the internal pull-up
/// (20–50 kΩ, datasheet "DC Characteristics").
pub struct InputPin<'p, P: Port, const BIT: u8> {
    port: &'p P,
    _bit: PhantomData<Mask<BIT>>,
}

impl<'p, P: Port, const BIT: u8> InputPin<'p, P, BIT> {
    /// Makes the bit an input, the pull-up on if `pull_up`.
    pub fn new(port: &'p P, pull_up: bool) -> Self {
        port.set_ddr(Mask::<BIT>::VALUE, false);
        port.set_port(Mask::<BIT>::VALUE, pull_up);
        InputPin {
            port,
            _bit: PhantomData,
        }
    }
}

impl<P: Port, const BIT: u8> ErrorType for InputPin<'_, P, BIT> {
    type Error = Infallible;
}

impl<P: Port, const BIT: u8> embedded_hal::digital::InputPin for InputPin<'_, P, BIT> {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(self.port.pin() & Mask::<BIT>::VALUE != 0)
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        Ok(self.port.pin() & Mask::<BIT>::VALUE == 0)
    }
}

/// An open-drain line on bit `BIT` of port `P`, both `OutputPin` and
/// `InputPin` (e.g. the DS1302's I/O line in `drivers::rtc::Ds1302`):
/// `set_low` drives low (DDR 1, PORT 0); `set_high` releases the line (DDR
/// 0) so that `is_high` reads what the line's pull-up or the device drives.
/// PORTx stays 0 unless `pull_up` asked for the internal pull-up while
/// released (not for the DS1302: its 40 kΩ pull-down and the internal
/// 20–50 kΩ pull-up would leave the level undefined; fit 10 kΩ).
pub struct OpenDrainPin<'p, P: Port, const BIT: u8> {
    port: &'p P,
    pull_up: bool,
    _bit: PhantomData<Mask<BIT>>,
}

impl<'p, P: Port, const BIT: u8> OpenDrainPin<'p, P, BIT> {
    /// A released (high) line.
    pub fn new(port: &'p P, pull_up: bool) -> Self {
        let mut pin = OpenDrainPin {
            port,
            pull_up,
            _bit: PhantomData,
        };
        pin.release();
        pin
    }

    fn release(&mut self) {
        self.port.set_ddr(Mask::<BIT>::VALUE, false);
        if self.pull_up {
            self.port.set_port(Mask::<BIT>::VALUE, true);
        }
    }

    fn drive_low(&mut self) {
        // PORT to 0 first: an input with PORT 1 turning output would drive
        // high for a moment.
        self.port.set_port(Mask::<BIT>::VALUE, false);
        self.port.set_ddr(Mask::<BIT>::VALUE, true);
    }
}

impl<P: Port, const BIT: u8> ErrorType for OpenDrainPin<'_, P, BIT> {
    type Error = Infallible;
}

impl<P: Port, const BIT: u8> embedded_hal::digital::OutputPin for OpenDrainPin<'_, P, BIT> {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.drive_low();
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.release();
        Ok(())
    }
}

impl<P: Port, const BIT: u8> embedded_hal::digital::InputPin for OpenDrainPin<'_, P, BIT> {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(self.port.pin() & Mask::<BIT>::VALUE != 0)
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        Ok(self.port.pin() & Mask::<BIT>::VALUE == 0)
    }
}

/// A push-pull output whose bit is kept at run time ([`OutputPin::erase`]),
/// so that pins of one port share one type (the four inputs of an H-bridge
/// in `drivers::stepper::hbridge::BridgePins`).
pub struct PortOutputPin<'p, P: Port> {
    port: &'p P,
    mask: u8,
}

impl<'p, P: Port, const BIT: u8> OutputPin<'p, P, BIT> {
    /// The same pin with its bit kept at run time.
    pub fn erase(self) -> PortOutputPin<'p, P> {
        PortOutputPin {
            port: self.port,
            mask: Mask::<BIT>::VALUE,
        }
    }
}

impl<P: Port> PortOutputPin<'_, P> {
    fn is_set(&self) -> bool {
        self.port.port() & self.mask != 0
    }
    fn set(&mut self, high: bool) {
        if self.is_set() != high {
            self.port.toggle(self.mask);
        }
    }
}

impl<P: Port> ErrorType for PortOutputPin<'_, P> {
    type Error = Infallible;
}

impl<P: Port> embedded_hal::digital::OutputPin for PortOutputPin<'_, P> {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.set(false);
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.set(true);
        Ok(())
    }
}

/// An input whose bit is kept at run time ([`InputPin::erase`]), so that
/// switches of one port share one type (`drivers::stepper::LimitSwitches`).
pub struct PortInputPin<'p, P: Port> {
    port: &'p P,
    mask: u8,
}

impl<'p, P: Port, const BIT: u8> InputPin<'p, P, BIT> {
    /// The same pin with its bit kept at run time.
    pub fn erase(self) -> PortInputPin<'p, P> {
        PortInputPin {
            port: self.port,
            mask: Mask::<BIT>::VALUE,
        }
    }
}

impl<P: Port> ErrorType for PortInputPin<'_, P> {
    type Error = Infallible;
}

impl<P: Port> embedded_hal::digital::InputPin for PortInputPin<'_, P> {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(self.port.pin() & self.mask != 0)
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        Ok(self.port.pin() & self.mask == 0)
    }
}
