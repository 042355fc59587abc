//! A millisecond clock on Timer0 (ATmega2560 datasheet §16 / ATmega328P
//! §14 "8-bit Timer/Counter0 with PWM": "Clear Timer on Compare Match (CTC)
//! Mode", TCCR0A/TCCR0B/OCR0A/TIMSK0) and idle sleep between ticks
//! (ATmega2560 §11 / ATmega328P §9 "Power Management and Sleep Modes":
//! "Idle Mode", SMCR).
//!
//! CTC with prescaler 64 and OCR0A = 249: 16 MHz / 64 / 250 = exactly
//! 1 kHz, the compare-match A interrupt adds one to a 64-bit count
//! ([`MS_PER_TICK`] in an emulator build). The
//! count only ever goes up by one per tick (never set, never stepped; it
//! wraps after 584 million years). Timer0 is then taken: its PWM outputs
//! (OC0A/OC0B) are unavailable.

use core::cell::Cell;

use avr_device::interrupt::{self, Mutex};

use super::chip;

/// Milliseconds since [`Millis::start`].
static MILLIS: Mutex<Cell<u64>> = Mutex::new(Cell::new(0));

/// Milliseconds the count advances per 1 kHz tick: 1 on a board. An image
/// built for the emulator harness with the environment variable
/// `SUNTRACKER_EMU_MS_PER_TICK=N` (see `.ci/firmware_env.sh`) advances `N`
/// per tick instead, so that an emulated day passes in 1/N of the CPU time;
/// nothing else in the image changes. In such a build on the ATmega2560 the
/// harness can hold PL0 (Mega D49, unused by the tracker) high to run the
/// clock at 1 ms per tick while the motors move (see [`on_timer0_compare`]).
pub const MS_PER_TICK: u64 = ms_per_tick(option_env!("SUNTRACKER_EMU_MS_PER_TICK"));

const fn ms_per_tick(text: Option<&str>) -> u64 {
    let Some(text) = text else { return 1 };
    let bytes = text.as_bytes();
    let mut value = 0u64;
    let mut i = 0;
    while i < bytes.len() {
        let d = bytes[i];
        assert!(
            d.is_ascii_digit(),
            "SUNTRACKER_EMU_MS_PER_TICK: digits only"
        );
        value = value * 10 + (d - b'0') as u64;
        assert!(value <= 1000, "SUNTRACKER_EMU_MS_PER_TICK: at most 1000");
        i += 1;
    }
    assert!(value >= 1, "SUNTRACKER_EMU_MS_PER_TICK: at least 1");
    value
}

/// Compare value for 1 kHz: 16 MHz / 64 / (249 + 1).
const OCR0A_1KHZ: u8 = 249;

/// The running Timer0 tick. The vector is bound by
/// `avr_board_interrupts!(timer0)`; [`millis`] advances once interrupts
/// are enabled.
pub struct Millis {
    tc0: chip::TC0,
}

impl Millis {
    /// Takes Timer0 and starts the 1 kHz tick from 0 ms.
    pub fn start(tc0: chip::TC0) -> Self {
        interrupt::free(|cs| MILLIS.borrow(cs).set(0));
        tc0.tccr0a().write(|w| w.wgm0().ctc());
        tc0.ocr0a().write(|w| w.set(OCR0A_1KHZ));
        tc0.tcnt0().write(|w| w.set(0));
        tc0.timsk0().write(|w| w.ocie0a().set_bit());
        tc0.tccr0b().write(|w| w.cs0().prescale_64());
        Millis { tc0 }
    }

    /// Milliseconds since [`Millis::start`] (same as [`millis`]).
    pub fn now_ms(&self) -> u64 {
        millis()
    }

    /// Stops the tick and gives Timer0 back; [`millis`] then stands still.
    pub fn stop(self) -> chip::TC0 {
        self.tc0.tccr0b().write(|w| w.cs0().no_clock());
        self.tc0.timsk0().write(|w| w.ocie0a().clear_bit());
        self.tc0
    }
}

/// Milliseconds since the tick started, read in a critical section (the
/// eight bytes cannot tear against the interrupt). 0 before the start.
pub fn millis() -> u64 {
    interrupt::free(|cs| MILLIS.borrow(cs).get())
}

/// The TIMER0_COMPA handler's work; bound by `avr_board_interrupts!`.
#[inline(always)]
pub fn on_timer0_compare() {
    let step_ms = if MS_PER_TICK != 1 && emu_real_time_requested() {
        1
    } else {
        MS_PER_TICK
    };
    interrupt::free(|cs| {
        let count = MILLIS.borrow(cs);
        count.set(count.get().wrapping_add(step_ms));
    });
}

/// Emulator builds only (the caller tests [`MS_PER_TICK`], a constant, so a
/// board image has no trace of this): the harness holds PL0 high while the
/// stepper coils are driven, so that motion (56 steps/s, one step per loop
/// pass at most) runs in real time while the rest of the day is compressed.
#[cfg(avr_atmega2560)]
#[inline(always)]
fn emu_real_time_requested() -> bool {
    // SAFETY: a read of the PINL input register, which has no side effect.
    let pinl = unsafe { (*chip::PORTL::ptr()).pinl().read().bits() };
    pinl & 1 != 0
}

#[cfg(not(avr_atmega2560))]
#[inline(always)]
fn emu_real_time_requested() -> bool {
    false
}

/// Sleeps in idle mode until the next interrupt (at most 1 ms while the
/// tick runs; a received byte also wakes): for a main loop with nothing to
/// do. Returns at once, without sleeping, while interrupts are disabled
/// (nothing could wake the CPU). Interrupt flags that rise between the
/// caller's last check and the SLEEP instruction are served on wake-up, so
/// a loop never misses work, at worst it waits one tick longer.
pub fn sleep_until_interrupt(cpu: &chip::CPU) {
    if !interrupt::is_enabled() {
        return;
    }
    cpu.smcr().write(|w| w.sm().idle().se().set_bit());
    avr_device::asm::sleep();
    cpu.smcr().write(|w| w.se().clear_bit());
}
