//! Servo PWM on Timer1 (ATmega328P datasheet §15 "16-bit Timer/Counter1
//! with PWM" / ATmega2560 §17 "16-bit Timer/Counter (Timer/Counter 1, 3, 4,
//! and 5)"): fast PWM mode 14 (WGM13:0 = 1110, TOP = ICR1; ATmega328P
//! §15.9.3 "Fast PWM Mode", Table 15-5 "Waveform Generation Mode Bit
//! Description"), clk/8 (Table 15-6), OC1A and OC1B non-inverting ("Clear
//! OC1A/OC1B on Compare Match, set OC1A/OC1B at BOTTOM", Table 15-3), each
//! an `embedded_hal::pwm::SetDutyCycle` channel.
//!
//! Frame: `f = f_clk / (N · (1 + TOP))` (§15.9.3) = 16 MHz / (8 · 40,000)
//! = 50 Hz with TOP = [`FRAME_TOP`] = 39,999; one count is 0.5 µs.
//!
//! Duty: fast PWM sets the pin at BOTTOM and clears it at the compare match
//! that follows count OCR1x, so the pin is high for OCR1x + 1 counts of the
//! TOP + 1 counts of a frame; OCR1x = TOP gives a constant high (§15.9.3,
//! "the extreme values for the OCR1x"). The channels therefore report a
//! max duty of TOP + 1 = [`MAX_DUTY`] = 40,000 and write OCR1x = duty − 1:
//! duty `d` is a pulse of exactly `d` counts, `d / 40,000` of the frame, so
//! `drivers::servo::ContinuousServo`'s `duty = round(pulse · max_duty /
//! period)` = `2 · pulse_us` gives the pulse it was asked for, to the count
//! (1,500 µs → duty 3,000 → OCR1x 2,999 → 3,000 counts high = 1,500 µs).
//! The other reading, max duty TOP with OCR1x = duty, makes every pulse one
//! count (0.5 µs) too long; the TOP versus TOP + 1 scale alone is under
//! half a count for pulses below 10 ms and vanishes in the driver's
//! rounding.
//! Duty 0 disconnects the channel's pin from the timer (COM1x = 0: the pin
//! shows PORTB's bit, low): OCR1x = 0 would still give a one-count spike.
//!
//! Pins: OC1A = PB1 (Uno D9), OC1B = PB2 (Uno D10); on the ATmega2560
//! OC1A = PB5 (Mega D11), OC1B = PB6 (Mega D12). OC1C (ATmega2560 PB7) is
//! not used. Timer1 is then taken, ICP1 and its interrupts included.
//!
//! Start-up without a glitch: [`Timer1Pwm::start`] stops the timer, clears
//! both compare-output latches (a forced compare match in normal mode,
//! §15.11.3 "TCCR1C": FOC1x applies COM1x, here "clear"), writes ICR1 and
//! both compare values while the timer is stopped in normal mode (OCR1x is
//! double-buffered only in the PWM modes, §15.7 "Output Compare Units", so
//! the values are in place before the first frame), connects the pins (low:
//! the latches are clear) and only then starts the clock from TCNT1 = 0.
//! The first pulse on either pin is the neutral one the caller gave.
//!
//! New duties take effect at the next frame (OCR1x is updated at BOTTOM in
//! this mode, §15.9.3), never cutting a pulse in the middle. 16-bit
//! registers are written high byte first through the shared TEMP register
//! (§15.3 "Accessing 16-bit Registers"); no interrupt handler of the board
//! layer touches Timer1, so the channels need no critical section for it.

use avr_device::interrupt;
use embedded_hal::pwm::{ErrorKind, ErrorType, SetDutyCycle};

use super::{chip, Port as _};

/// Timer1 counts per µs: 16 MHz / 8 ([`super::CPU_HZ`] at clk/8).
pub const COUNTS_PER_US: u32 = super::CPU_HZ / 8 / 1_000_000;
/// The servo frame, µs (50 Hz).
pub const FRAME_US: u32 = 20_000;
/// TOP = ICR1 for a 20 ms frame: 20,000 µs · 2 counts/µs − 1.
pub const FRAME_TOP: u16 = (FRAME_US * COUNTS_PER_US - 1) as u16;
/// The channels' max duty: TOP + 1 counts, the whole frame (duty `d` is a
/// pulse of `d` counts; see the module notes).
pub const MAX_DUTY: u16 = FRAME_TOP + 1;

/// OC1A / OC1B bits of PORTB.
#[cfg(not(avr_atmega2560))]
const OC1A_BIT: u8 = 1;
#[cfg(not(avr_atmega2560))]
const OC1B_BIT: u8 = 2;
#[cfg(avr_atmega2560)]
const OC1A_BIT: u8 = 5;
#[cfg(avr_atmega2560)]
const OC1B_BIT: u8 = 6;
const PINS_MASK: u8 = (1 << OC1A_BIT) | (1 << OC1B_BIT);

/// WGM11:10 of mode 14 (TCCR1A).
const WGM_14_LOW: u8 = 0b10;
/// WGM13:12 of mode 14 (TCCR1B).
const WGM_14_HIGH: u8 = 0b11;

/// Errors of the Timer1 PWM.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PwmError {
    /// A duty above [`MAX_DUTY`].
    DutyOutOfRange,
    /// A pulse of 0 µs or longer than the 20 ms frame.
    PulseOutOfRange,
}

impl embedded_hal::pwm::Error for PwmError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Other
    }
}

/// A pulse width for [`Timer1Pwm::start`]: 1 to [`MAX_DUTY`] Timer1
/// counts (0.5 µs to 20 ms).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PulseWidth {
    counts: u16,
}

impl PulseWidth {
    /// The FS5106R's (and most servos') neutral pulse, 1,500 µs.
    pub const NEUTRAL_1500_US: PulseWidth = PulseWidth {
        counts: (1_500 * COUNTS_PER_US) as u16,
    };

    /// `pulse_us` µs (1 ..= 20,000).
    pub const fn from_us(pulse_us: u32) -> Result<Self, PwmError> {
        if pulse_us == 0 || pulse_us > FRAME_US {
            return Err(PwmError::PulseOutOfRange);
        }
        Ok(PulseWidth {
            counts: (pulse_us * COUNTS_PER_US) as u16,
        })
    }

    /// `counts` Timer1 counts of 0.5 µs (1 ..= [`MAX_DUTY`]).
    pub const fn from_counts(counts: u16) -> Result<Self, PwmError> {
        if counts == 0 || counts > MAX_DUTY {
            return Err(PwmError::PulseOutOfRange);
        }
        Ok(PulseWidth { counts })
    }

    /// The width in Timer1 counts (the channels' duty for it).
    pub const fn counts(self) -> u16 {
        self.counts
    }
}

/// Timer1 running 50 Hz servo frames on OC1A and OC1B.
pub struct Timer1Pwm {
    tc1: chip::TC1,
}

impl Timer1Pwm {
    /// Takes Timer1 and starts the frames, OC1A at `oc1a` and OC1B at
    /// `oc1b` from the first pulse (see the module notes). Makes both pins
    /// outputs (PORTB bits low first).
    pub fn start(tc1: chip::TC1, portb: &chip::PORTB, oc1a: PulseWidth, oc1b: PulseWidth) -> Self {
        // Stopped, normal mode, pins not connected to the timer.
        tc1.tccr1b().reset();
        tc1.tccr1a().reset();
        tc1.timsk1().reset();
        // The pins low while the port drives them.
        portb.set_port(PINS_MASK, false);
        // Compare-output latches cleared: in normal mode with COM1x =
        // "clear on compare match", a forced match clears them.
        tc1.tccr1a()
            .write(|w| w.com1a().match_clear().com1b().match_clear());
        tc1.tccr1c()
            .write(|w| w.foc1a().set_bit().foc1b().set_bit());
        // Frame and first pulses, written straight into ICR1 / OCR1x (no
        // double buffering in normal mode).
        tc1.icr1().write(|w| w.set(FRAME_TOP));
        tc1.ocr1a().write(|w| w.set(oc1a.counts - 1));
        tc1.ocr1b().write(|w| w.set(oc1b.counts - 1));
        tc1.tcnt1().write(|w| w.set(0));
        // Mode 14, pins connected (low: latches clear), outputs on, then
        // the clock.
        tc1.tccr1a().write(|w| {
            w.wgm1()
                .set(WGM_14_LOW)
                .com1a()
                .match_clear()
                .com1b()
                .match_clear()
        });
        portb.set_ddr(PINS_MASK, true);
        tc1.tccr1b()
            .write(|w| w.wgm1().set(WGM_14_HIGH).cs1().prescale_8());
        Timer1Pwm { tc1 }
    }

    /// The two channels, each borrowing the timer.
    pub fn channels(&mut self) -> (Oc1a<'_>, Oc1b<'_>) {
        (Oc1a { tc1: &self.tc1 }, Oc1b { tc1: &self.tc1 })
    }

    /// Stops the timer and gives it back: the pins show PORTB's bits again
    /// (outputs, low), i.e. no pulses (an FS5106R stops on a lost signal).
    pub fn release(self) -> chip::TC1 {
        self.tc1.tccr1b().reset();
        self.tc1.tccr1a().reset();
        self.tc1
    }
}

macro_rules! channel {
    ($name:ident, $ocr:ident, $com:ident, $pin:literal) => {
        #[doc = concat!("Timer1's ", stringify!($name), " output (", $pin, ") as a PWM channel: duty `d` of [`MAX_DUTY`] is a pulse of `d` counts (0.5 µs each) per 20 ms frame.")]
        pub struct $name<'t> {
            tc1: &'t chip::TC1,
        }

        impl ErrorType for $name<'_> {
            type Error = PwmError;
        }

        impl SetDutyCycle for $name<'_> {
            fn max_duty_cycle(&self) -> u16 {
                MAX_DUTY
            }

            /// 1..=[`MAX_DUTY`]: OCR1x = duty − 1, from the next frame;
            /// 0: the pin disconnected from the timer (low) at once, a
            /// pulse under way cut short. Above [`MAX_DUTY`]: an error,
            /// nothing changed.
            fn set_duty_cycle(&mut self, duty: u16) -> Result<(), PwmError> {
                if duty > MAX_DUTY {
                    return Err(PwmError::DutyOutOfRange);
                }
                if duty == 0 {
                    interrupt::free(|_| {
                        self.tc1.tccr1a().modify(|_, w| w.$com().disconnected());
                    });
                    return Ok(());
                }
                self.tc1.$ocr().write(|w| w.set(duty - 1));
                if self.tc1.tccr1a().read().$com().is_disconnected() {
                    interrupt::free(|_| {
                        self.tc1.tccr1a().modify(|_, w| w.$com().match_clear());
                    });
                }
                Ok(())
            }
        }
    };
}

#[cfg(not(avr_atmega2560))]
channel!(Oc1a, ocr1a, com1a, "PB1, Uno D9");
#[cfg(not(avr_atmega2560))]
channel!(Oc1b, ocr1b, com1b, "PB2, Uno D10");
#[cfg(avr_atmega2560)]
channel!(Oc1a, ocr1a, com1a, "PB5, Mega D11");
#[cfg(avr_atmega2560)]
channel!(Oc1b, ocr1b, com1b, "PB6, Mega D12");
