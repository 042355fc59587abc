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
//! The ATmega2560 has the same servo frames on Timer3 (`Timer3Pwm`, the
//! same registers numbered 3: §17): OC3A = PE3 (Mega D5) and OC3C = PE5
//! (Mega D3), where the Mega's servo axes take them (Timer1 drives its DC
//! bridges at 20 kHz there). OC3B = PE4 (D2) is INT4, the anemometer's
//! input, and stays disconnected. `Timer3Pwm::start_with` can leave an
//! output disconnected until its servo is built: a board that has no servo
//! on it sends no pulse.
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

/// WGMn1:n0 of mode 14 (TCCRnA).
const WGM_14_LOW: u8 = 0b10;
/// WGMn3:n2 of mode 14 (TCCRnB).
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

/// A 16-bit timer running 50 Hz servo frames on two of its outputs, and
/// those outputs as channels: `$timer` takes `$tc` and drives the `$port`
/// bits `$a_bit` and `$b_bit` (`$a` and `$b`, compare registers `$ocr_a`,
/// `$ocr_b`, output modes `$com_a`, `$com_b`, force bits `$foc_a`,
/// `$foc_b`). The timers share the register layout (ATmega2560 §17.11
/// "Register Description": TCCRnA/B/C, TCNTn, OCRnx, ICRn, TIMSKn), so one
/// body serves Timer1 and Timer3.
macro_rules! servo_timer {
    (
        $timer:ident, $either:ident, $tc:ident, $port:ident, $doc:literal,
        regs: $tccra:ident, $tccrb:ident, $tccrc:ident, $icr:ident, $tcnt:ident, $timsk:ident, $wgm:ident, $cs:ident;
        $a:ident: $ocr_a:ident, $com_a:ident, $foc_a:ident, $a_bit:literal, $a_pin:literal;
        $b:ident: $ocr_b:ident, $com_b:ident, $foc_b:ident, $b_bit:literal, $b_pin:literal;
    ) => {
        #[doc = $doc]
        pub struct $timer {
            tc: chip::$tc,
        }

        impl $timer {
            /// Takes the timer and starts the frames, the first output at
            /// `a` and the second at `b` from the first pulse (see the
            /// module notes). Makes both pins outputs (port bits low
            /// first).
            pub fn start(tc: chip::$tc, port: &chip::$port, a: PulseWidth, b: PulseWidth) -> Self {
                Self::start_with(tc, port, Some(a), Some(b))
            }

            /// [`Self::start`] with an output left disconnected (`None`:
            /// its pin an output held low, no pulse, until its channel is
            /// given a duty): a servo that gets no pulse stays still.
            pub fn start_with(
                tc: chip::$tc,
                port: &chip::$port,
                a: Option<PulseWidth>,
                b: Option<PulseWidth>,
            ) -> Self {
                let mask: u8 = (1 << $a_bit) | (1 << $b_bit);
                // Stopped, normal mode, pins not connected to the timer.
                tc.$tccrb().reset();
                tc.$tccra().reset();
                tc.$timsk().reset();
                // The pins low while the port drives them.
                port.set_port(mask, false);
                // Compare-output latches cleared: in normal mode with COMnx =
                // "clear on compare match", a forced match clears them.
                tc.$tccra()
                    .write(|w| w.$com_a().match_clear().$com_b().match_clear());
                tc.$tccrc().write(|w| w.$foc_a().set_bit().$foc_b().set_bit());
                // Frame and first pulses, written straight into ICRn / OCRnx
                // (no double buffering in normal mode).
                tc.$icr().write(|w| w.set(FRAME_TOP));
                let counts = |p: Option<PulseWidth>| p.map_or(0, |p| p.counts - 1);
                tc.$ocr_a().write(|w| w.set(counts(a)));
                tc.$ocr_b().write(|w| w.set(counts(b)));
                tc.$tcnt().write(|w| w.set(0));
                // Mode 14, the given outputs connected (low: latches clear),
                // pins outputs, then the clock.
                tc.$tccra().write(|w| {
                    let w = w.$wgm().set(WGM_14_LOW);
                    let w = if a.is_some() {
                        w.$com_a().match_clear()
                    } else {
                        w.$com_a().disconnected()
                    };
                    if b.is_some() {
                        w.$com_b().match_clear()
                    } else {
                        w.$com_b().disconnected()
                    }
                });
                port.set_ddr(mask, true);
                tc.$tccrb()
                    .write(|w| w.$wgm().set(WGM_14_HIGH).$cs().prescale_8());
                $timer { tc }
            }

            /// The two channels, each borrowing the timer.
            pub fn channels(&self) -> ($a<'_>, $b<'_>) {
                ($a { tc: &self.tc }, $b { tc: &self.tc })
            }

            /// Stops the timer and gives it back: the pins show the port's
            /// bits again (outputs, low), i.e. no pulses (an FS5106R stops
            /// on a lost signal).
            pub fn release(self) -> chip::$tc {
                self.tc.$tccrb().reset();
                self.tc.$tccra().reset();
                self.tc
            }
        }

        channel!($tc, $tccra, $a, $ocr_a, $com_a, $a_pin);
        channel!($tc, $tccra, $b, $ocr_b, $com_b, $b_pin);

        #[doc = concat!("Either channel of [`", stringify!($timer), "`], so that two servo axes on its two outputs are of one type.")]
        pub enum $either<'t> {
            #[doc = concat!("The ", stringify!($a), " output (", $a_pin, ").")]
            $a($a<'t>),
            #[doc = concat!("The ", stringify!($b), " output (", $b_pin, ").")]
            $b($b<'t>),
        }

        impl ErrorType for $either<'_> {
            type Error = PwmError;
        }

        impl SetDutyCycle for $either<'_> {
            fn max_duty_cycle(&self) -> u16 {
                MAX_DUTY
            }
            fn set_duty_cycle(&mut self, duty: u16) -> Result<(), PwmError> {
                match self {
                    $either::$a(ch) => ch.set_duty_cycle(duty),
                    $either::$b(ch) => ch.set_duty_cycle(duty),
                }
            }
        }
    };
}

macro_rules! channel {
    ($tc:ident, $tccra:ident, $name:ident, $ocr:ident, $com:ident, $pin:literal) => {
        #[doc = concat!("The ", stringify!($name), " output (", $pin, ") as a PWM channel: duty `d` of [`MAX_DUTY`] is a pulse of `d` counts (0.5 µs each) per 20 ms frame.")]
        pub struct $name<'t> {
            tc: &'t chip::$tc,
        }

        impl ErrorType for $name<'_> {
            type Error = PwmError;
        }

        impl SetDutyCycle for $name<'_> {
            fn max_duty_cycle(&self) -> u16 {
                MAX_DUTY
            }

            /// 1..=[`MAX_DUTY`]: OCRnx = duty − 1, from the next frame;
            /// 0: the pin disconnected from the timer (low) at once, a
            /// pulse under way cut short. Above [`MAX_DUTY`]: an error,
            /// nothing changed.
            fn set_duty_cycle(&mut self, duty: u16) -> Result<(), PwmError> {
                if duty > MAX_DUTY {
                    return Err(PwmError::DutyOutOfRange);
                }
                if duty == 0 {
                    interrupt::free(|_| {
                        self.tc.$tccra().modify(|_, w| w.$com().disconnected());
                    });
                    return Ok(());
                }
                self.tc.$ocr().write(|w| w.set(duty - 1));
                if self.tc.$tccra().read().$com().is_disconnected() {
                    interrupt::free(|_| {
                        self.tc.$tccra().modify(|_, w| w.$com().match_clear());
                    });
                }
                Ok(())
            }
        }
    };
}

#[cfg(not(avr_atmega2560))]
servo_timer!(
    Timer1Pwm, Timer1Channel, TC1, PORTB, "Timer1 running 50 Hz servo frames on OC1A (PB1, Uno D9) and OC1B (PB2, Uno D10).",
    regs: tccr1a, tccr1b, tccr1c, icr1, tcnt1, timsk1, wgm1, cs1;
    Oc1a: ocr1a, com1a, foc1a, 1, "PB1, Uno D9";
    Oc1b: ocr1b, com1b, foc1b, 2, "PB2, Uno D10";
);
#[cfg(avr_atmega2560)]
servo_timer!(
    Timer1Pwm, Timer1Channel, TC1, PORTB, "Timer1 running 50 Hz servo frames on OC1A (PB5, Mega D11) and OC1B (PB6, Mega D12).",
    regs: tccr1a, tccr1b, tccr1c, icr1, tcnt1, timsk1, wgm1, cs1;
    Oc1a: ocr1a, com1a, foc1a, 5, "PB5, Mega D11";
    Oc1b: ocr1b, com1b, foc1b, 6, "PB6, Mega D12";
);
// OC3B (PE4, Mega D2) is INT4, the anemometer's input: it stays
// disconnected (COM3B = 0).
#[cfg(avr_atmega2560)]
servo_timer!(
    Timer3Pwm, Timer3Channel, TC3, PORTE, "Timer3 running 50 Hz servo frames on OC3A (PE3, Mega D5) and OC3C (PE5, Mega D3); OC3B (PE4, D2) stays disconnected.",
    regs: tccr3a, tccr3b, tccr3c, icr3, tcnt3, timsk3, wgm3, cs3;
    Oc3a: ocr3a, com3a, foc3a, 3, "PE3, Mega D5";
    Oc3c: ocr3c, com3c, foc3c, 5, "PE5, Mega D3";
);
