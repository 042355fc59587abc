//! Motor-bridge PWM at 20 kHz on the ATmega2560's 16-bit Timer1 and Timer4
//! (ATmega2560 datasheet §17 "16-bit Timer/Counter (Timer/Counter 1, 3, 4,
//! and 5)"): fast PWM mode 14 (WGM3:0 = 1110, TOP = ICRn; §17.9.3 "Fast
//! PWM Mode", Table 17-2 "Waveform Generation Mode Bit Description"), no
//! prescaler (CSn2:0 = 001, Table 17-6), outputs non-inverting ("Clear OCnx
//! on compare match, set OCnx at BOTTOM", Table 17-4), each an
//! `embedded_hal::pwm::SetDutyCycle` channel for a BTS7960's RPWM or LPWM
//! input (`drivers::dc_motor::bts7960`).
//!
//! Frequency: `f = f_clk / (N · (1 + TOP))` (§17.9.3) = 16 MHz / (1 · 800)
//! = 20 kHz with TOP = [`MOTOR_PWM_TOP`] = 799: above hearing, and under the
//! 25 kHz the BTS 7960 data sheet gives as its PWM capability (Infineon,
//! *BTS 7960 High Current PN Half Bridge*, Rev. 1.1, "Features": "PWM
//! capability of up to 25 kHz combined with active freewheeling").
//!
//! Duty: the pin is high for OCRnx + 1 of the TOP + 1 counts of a period
//! (OCRnx = TOP: constant high), so the channels report a max duty of
//! [`MOTOR_MAX_DUTY`] = 800 and write OCRnx = duty − 1. Duty 0 disconnects
//! the pin from the timer (COMnx = 0): it then shows its PORT bit, low
//! (OCRnx = 0 would leave a one-count spike every period). New duties take
//! effect at the next period (OCRnx is double-buffered in this mode).
//!
//! | timer | channel | pin | Mega header |
//! |---|---|---|---|
//! | Timer1 | OC1A | PB5 | D11 |
//! | Timer1 | OC1B | PB6 | D12 |
//! | Timer4 | OC4B | PH4 | D7 |
//! | Timer4 | OC4C | PH5 | D8 |
//!
//! Timer4's OC4A (PH3, D6) stays disconnected (COM4A = 0): the pin keeps
//! its port function (the RS-485 driver enable of [`super::Rs485`]).
//! The channels' COMnx writes run with interrupts off (a read-modify-write
//! of TCCRnA, which no handler of this layer touches either).

use avr_device::interrupt;
use embedded_hal::pwm::{ErrorKind, ErrorType, SetDutyCycle};

use super::{chip, Port as _};

/// TOP = ICRn: 800 counts of 62.5 ns, a 50 µs (20 kHz) period.
pub const MOTOR_PWM_TOP: u16 = 799;
/// The channels' max duty: TOP + 1 counts (constant high).
pub const MOTOR_MAX_DUTY: u16 = MOTOR_PWM_TOP + 1;

/// WGMn1:0 of mode 14 (TCCRnA).
const WGM_14_LOW: u8 = 0b10;
/// WGMn3:2 of mode 14 (TCCRnB).
const WGM_14_HIGH: u8 = 0b11;

/// A duty above [`MOTOR_MAX_DUTY`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MotorDutyOutOfRange;

impl embedded_hal::pwm::Error for MotorDutyOutOfRange {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Other
    }
}

/// One of the four motor PWM outputs, borrowing its timer.
pub struct MotorPwm<'t> {
    channel: Channel<'t>,
}

enum Channel<'t> {
    Oc1a(&'t chip::TC1),
    Oc1b(&'t chip::TC1),
    Oc4b(&'t chip::TC4),
    Oc4c(&'t chip::TC4),
}

macro_rules! motor_timer {
    (
        $timer:ident, $tc:ident, $port:ident, $doc:literal,
        $tccra:ident, $tccrb:ident, $timsk:ident, $icr:ident, $tcnt:ident, $wgm:ident, $cs:ident,
        $mask:expr, ($first:ident, $second:ident)
    ) => {
        #[doc = $doc]
        pub struct $timer {
            tc: chip::$tc,
        }

        impl $timer {
            /// Takes the timer and starts it with both channels at duty 0
            /// (pins disconnected, driven low by the port).
            pub fn start(tc: chip::$tc, port: &chip::$port) -> Self {
                tc.$tccrb().reset();
                tc.$tccra().reset();
                tc.$timsk().reset();
                port.set_port($mask, false);
                port.set_ddr($mask, true);
                tc.$icr().write(|w| w.set(MOTOR_PWM_TOP));
                tc.$tcnt().write(|w| w.set(0));
                tc.$tccra().write(|w| w.$wgm().set(WGM_14_LOW));
                tc.$tccrb()
                    .write(|w| w.$wgm().set(WGM_14_HIGH).$cs().direct());
                $timer { tc }
            }

            /// The two channels, each borrowing the timer.
            pub fn channels(&self) -> (MotorPwm<'_>, MotorPwm<'_>) {
                (
                    MotorPwm {
                        channel: Channel::$first(&self.tc),
                    },
                    MotorPwm {
                        channel: Channel::$second(&self.tc),
                    },
                )
            }
        }
    };
}

motor_timer!(
    Timer1MotorPwm,
    TC1,
    PORTB,
    "Timer1 at 20 kHz on OC1A (PB5, D11) and OC1B (PB6, D12).",
    tccr1a,
    tccr1b,
    timsk1,
    icr1,
    tcnt1,
    wgm1,
    cs1,
    (1 << 5) | (1 << 6),
    (Oc1a, Oc1b)
);

motor_timer!(
    Timer4MotorPwm,
    TC4,
    PORTH,
    "Timer4 at 20 kHz on OC4B (PH4, D7) and OC4C (PH5, D8).",
    tccr4a,
    tccr4b,
    timsk4,
    icr4,
    tcnt4,
    wgm4,
    cs4,
    (1 << 4) | (1 << 5),
    (Oc4b, Oc4c)
);

/// Writes `duty` (checked: 1..=max) or disconnects the pin (0).
macro_rules! set_duty {
    ($tc:expr, $tccra:ident, $ocr:ident, $com:ident, $duty:expr) => {{
        let tc = $tc;
        if $duty == 0 {
            interrupt::free(|_| {
                tc.$tccra().modify(|_, w| w.$com().disconnected());
            });
        } else {
            tc.$ocr().write(|w| w.set($duty - 1));
            if tc.$tccra().read().$com().is_disconnected() {
                interrupt::free(|_| {
                    tc.$tccra().modify(|_, w| w.$com().match_clear());
                });
            }
        }
    }};
}

impl ErrorType for MotorPwm<'_> {
    type Error = MotorDutyOutOfRange;
}

impl SetDutyCycle for MotorPwm<'_> {
    fn max_duty_cycle(&self) -> u16 {
        MOTOR_MAX_DUTY
    }

    /// 1..=[`MOTOR_MAX_DUTY`]: OCRnx = duty − 1 from the next period; 0:
    /// the pin disconnected (low) at once. Above: an error, nothing changed.
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), MotorDutyOutOfRange> {
        if duty > MOTOR_MAX_DUTY {
            return Err(MotorDutyOutOfRange);
        }
        match self.channel {
            Channel::Oc1a(tc) => set_duty!(tc, tccr1a, ocr1a, com1a, duty),
            Channel::Oc1b(tc) => set_duty!(tc, tccr1a, ocr1b, com1b, duty),
            Channel::Oc4b(tc) => set_duty!(tc, tccr4a, ocr4b, com4b, duty),
            Channel::Oc4c(tc) => set_duty!(tc, tccr4a, ocr4c, com4c, duty),
        }
        Ok(())
    }
}
