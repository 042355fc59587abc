//! Self-test of the AVR board layer (`suntracker_avr`) under simavr,
//! for the ATmega2560 (also builds for the ATmega328P): the Timer0
//! millisecond clock against a busy `DelayNs` of 100 ms, idle sleep between
//! ticks, the interrupt-driven USART0 (this log; an empty receive ring), a
//! `drivers::rtc::Ds3231` read over the TWI (no device in plain simavr: a
//! NoAcknowledge error, in bounded time), an output pin, the anemometer
//! counter on INT4 (INT0 on the 328P) fed by toggling its own pin (external
//! interrupts fire on output pins too, datasheet "External Interrupts"), and
//! the watchdog fed for 2.5 s.
//!
//! On the ATmega328P it also tests the Uno servo tracker's parts, before the
//! watchdog: the Timer1 servo PWM (OC1A = PB1 at 1,500 µs and OC1B = PB2 at
//! 1,750 µs through `drivers::servo::ContinuousServo`, left running to the
//! end), one ADC0 conversion (its code logged), and the two pin-change
//! encoders: first fed by driving their own pins (pin-change interrupts
//! fire on output pins too, ATmega328P §12 "External Interrupts"), then
//! inputs for 1 s, their counts logged. `emu/tests/uno_board_smoke.rs`
//! measures the pulses, puts a voltage on ADC0 and drives the encoder pins
//! during that second.
//!
//! Build and run (ATmega2560):
//! `RUSTFLAGS="$AVR_MEGA_RUSTFLAGS" cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-avr --bin avr_board_selftest --target-dir target/mega`,
//! then `simavr -m atmega2560 -f 16000000 target/mega/avr-none/release/avr_board_selftest.elf`.
//! ATmega328P: `cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-avr --bin avr_board_selftest`
//! (`target/avr-none/release/avr_board_selftest.elf`, `simavr -m atmega328p -f 16000000 …`).
#![no_std]
#![no_main]
// Interrupt handlers (`avr_board_interrupts!`) use the avr-interrupt ABI,
// unstable: AVR builds are nightly anyway.
#![feature(abi_avr_interrupt)]

mod firmware {
    use embedded_hal::delay::DelayNs;
    use embedded_hal::digital::{OutputPin as _, StatefulOutputPin as _};
    use embedded_hal::i2c::{Error as _, ErrorKind, NoAcknowledgeSource};
    use embedded_io::{Read as _, ReadReady as _, Write as _};
    use suntracker::log::Sink;
    use suntracker_avr::{
        chip, millis, sleep_until_interrupt, Anemometer, Delay, ExtInt, I2c, Millis, OutputPin,
        Port as _, TwiError, Usart0, Watchdog,
    };

    #[cfg(avr_atmega2560)]
    suntracker_avr::avr_board_interrupts!(timer0, usart0, int4);
    #[cfg(not(avr_atmega2560))]
    suntracker_avr::avr_board_interrupts!(timer0, usart0, int0, pcint2);

    #[cfg(avr_atmega2560)]
    const CHIP: &str = "atmega2560";
    #[cfg(not(avr_atmega2560))]
    const CHIP: &str = "atmega328p";

    /// The LED pin: PB7 (Mega D13) / PB5 (Uno D13).
    #[cfg(avr_atmega2560)]
    const LED_BIT: u8 = 7;
    #[cfg(not(avr_atmega2560))]
    const LED_BIT: u8 = 5;

    const BAUD_HZ: u32 = 115_200;
    const DELAY_MS: u32 = 100;
    const SLEEPS: u32 = 10;
    const ANEMOMETER_PULSES: u8 = 3;
    const WATCHDOG_RUN_MS: u64 = 2_500;
    const WATCHDOG_FEED_MS: u64 = 500;

    fn ms_since(start_ms: u64) -> u32 {
        u32::try_from(millis().saturating_sub(start_ms)).unwrap_or(u32::MAX)
    }

    fn kind_name(kind: ErrorKind) -> &'static str {
        match kind {
            ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address) => "NoAcknowledge(Address)",
            ErrorKind::NoAcknowledge(NoAcknowledgeSource::Data) => "NoAcknowledge(Data)",
            ErrorKind::NoAcknowledge(NoAcknowledgeSource::Unknown) => "NoAcknowledge(Unknown)",
            ErrorKind::ArbitrationLoss => "ArbitrationLoss",
            ErrorKind::Bus => "Bus",
            ErrorKind::Overrun => "Overrun",
            _ => "Other",
        }
    }

    #[cfg(avr_atmega2560)]
    const RTC_READ: &str = "twi: drivers Ds3231::datetime";
    #[cfg(not(avr_atmega2560))]
    const RTC_READ: &str = "twi: I2c::write_read(0x68, [0x00], 7 bytes)";

    /// Reads the DS3231's time; `Err(None)` for a device (not bus) error.
    #[cfg(avr_atmega2560)]
    fn rtc_read(i2c: I2c) -> Result<(), Option<TwiError>> {
        let mut rtc = drivers::rtc::Ds3231::new(i2c);
        match drivers::rtc::Clock::datetime(&mut rtc) {
            Ok(_) => Ok(()),
            Err(drivers::rtc::Ds3231Error::Comm(e)) => Err(Some(e)),
            Err(_) => Err(None),
        }
    }

    /// Reads the DS3231's seven time registers.
    #[cfg(not(avr_atmega2560))]
    fn rtc_read(mut i2c: I2c) -> Result<(), Option<TwiError>> {
        use embedded_hal::i2c::I2c as _;
        let mut registers = [0u8; 7];
        i2c.write_read(0x68, &[0x00], &mut registers).map_err(Some)
    }

    fn hex(byte: u8) -> [u8; 2] {
        const DIGITS: &[u8; 16] = b"0123456789abcdef";
        let digit = |n: u8| DIGITS.get(usize::from(n & 0x0F)).copied().unwrap_or(b'?');
        [digit(byte >> 4), digit(byte)]
    }

    fn check(out: &mut Usart0, ok: bool) {
        out.text(if ok { " ok\n" } else { " FAIL\n" });
    }

    #[no_mangle]
    pub extern "C" fn main() -> ! {
        let Some(dp) = chip::Peripherals::take() else {
            halt()
        };
        let mut out = Usart0::new(dp.USART0, BAUD_HZ);
        out.text(suntracker::BANNER);
        out.text(" board selftest on ");
        out.text(CHIP);
        out.text("\n");

        // Timer0 clock and a busy delay.
        let _clock = Millis::start(dp.TC0);
        // SAFETY: every handler bound above has its part set up (Timer0,
        // USART0 now; the anemometer arms its line itself, later); no
        // critical section is open.
        unsafe { avr_device::interrupt::enable() };
        let mut delay = Delay::new();
        let start_ms = millis();
        delay.delay_ms(DELAY_MS);
        let delay_ms = ms_since(start_ms);
        out.text("delay: DelayNs::delay_ms(100) took ");
        out.u32(delay_ms);
        out.text(" ms of Timer0 millis");
        check(&mut out, (DELAY_MS..=DELAY_MS + 2).contains(&delay_ms));

        let start_ms = millis();
        for _ in 0..SLEEPS {
            sleep_until_interrupt(&dp.CPU);
        }
        let slept_ms = ms_since(start_ms);
        out.text("sleep: 10 idle sleeps took ");
        out.u32(slept_ms);
        out.text(" ms");
        check(&mut out, (SLEEPS - 1..=SLEEPS + 1).contains(&slept_ms));

        // USART0 receive side: nothing arrives in simavr.
        let ready = out.read_ready().unwrap_or(true);
        out.text("usart0: rx ready=");
        out.text(if ready { "yes" } else { "no" });
        out.text(" waiting=");
        out.u32(out.rx_waiting() as u32);
        out.text(" dropped=");
        out.u32(u32::from(out.rx_dropped()));
        check(&mut out, !ready);
        let _ = out.write_all(b"usart0: embedded_io::Write ok\n");

        // The drivers crate's DS3231 on the TWI (on the 328P a plain
        // register read: the DS3231 driver's chrono tables alone take 1.2 KB
        // of its 2 KB RAM, see the board layer's notes).
        let start_ms = millis();
        let result = rtc_read(I2c::new(dp.TWI));
        let took_ms = ms_since(start_ms);
        out.text(RTC_READ);
        out.text(" -> ");
        let expected = match result {
            Ok(()) => {
                out.text("answered");
                false
            }
            Err(Some(e)) => {
                out.text("I2C error ");
                out.text(kind_name(e.kind()));
                if let TwiError::Bus(status) = e {
                    out.text(" (TWSR status 0x");
                    out.put(&hex(status));
                    out.text(")");
                }
                e.kind() == ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
            }
            Err(None) => {
                out.text("device error");
                false
            }
        };
        out.text(" in ");
        out.u32(took_ms);
        out.text(" ms");
        check(&mut out, expected && took_ms < 50);

        // An output pin: PB7 / PB5.
        let portb = dp.PORTB;
        let mut led = OutputPin::<_, LED_BIT>::new(&portb, false);
        let mut levels = [false; 4];
        let _ = led.toggle();
        levels[0] = led.is_set_high().unwrap_or(false);
        levels[1] = portb.pin() & (1 << LED_BIT) != 0;
        let _ = led.set_low();
        levels[2] = led.is_set_high().unwrap_or(true);
        let _ = led.set_high();
        levels[3] = portb.pin() & (1 << LED_BIT) != 0;
        out.text("gpio: PB");
        out.u32(u32::from(LED_BIT));
        out.text(" toggle->");
        for (i, level) in levels.iter().enumerate() {
            if i > 0 {
                out.text(",");
            }
            out.text(if *level { "high" } else { "low" });
        }
        check(&mut out, levels == [true, true, false, true]);

        // The anemometer, pulsed by driving its own pin.
        #[cfg(avr_atmega2560)]
        let (pulse_port, pulse_bit, line) = (dp.PORTE, 4u8, ExtInt::Int4);
        #[cfg(not(avr_atmega2560))]
        let (pulse_port, pulse_bit, line) = (dp.PORTD, 2u8, ExtInt::Int0);
        let mask = 1u8 << pulse_bit;
        pulse_port.set_port(mask, true);
        pulse_port.set_ddr(mask, true);
        let mut anemometer = Anemometer::new(dp.EXINT, line);
        for _ in 0..ANEMOMETER_PULSES {
            pulse_port.set_port(mask, false);
            delay.delay_us(100);
            pulse_port.set_port(mask, true);
            delay.delay_us(100);
        }
        let pulses = anemometer.take_pulses();
        let after = anemometer.take_pulses();
        out.text("anemometer: 3 falling edges -> ");
        out.u32(u32::from(pulses));
        out.text(" pulses, then ");
        out.u32(u32::from(after));
        check(
            &mut out,
            pulses == u16::from(ANEMOMETER_PULSES) && after == 0,
        );

        // The Uno servo tracker's parts; the PWM runs on to the end.
        #[cfg(not(avr_atmega2560))]
        let _pwm = uno_parts::pwm(&mut out, dp.TC1, &portb);
        #[cfg(not(avr_atmega2560))]
        uno_parts::adc(&mut out, dp.ADC);
        #[cfg(not(avr_atmega2560))]
        uno_parts::encoders(
            &mut out,
            anemometer.release(),
            &pulse_port,
            &mut delay,
            &dp.CPU,
        );

        // The watchdog, fed every 0.5 s for 2.5 s (a reset would restart
        // the log from the banner).
        let mut watchdog = Watchdog::enable(dp.WDT, &dp.CPU);
        let start_ms = millis();
        let mut fed_ms = start_ms;
        while millis().saturating_sub(start_ms) < WATCHDOG_RUN_MS {
            if millis().saturating_sub(fed_ms) >= WATCHDOG_FEED_MS {
                watchdog.feed();
                fed_ms = millis();
            }
            sleep_until_interrupt(&dp.CPU);
        }
        let _wdt = watchdog.disable();
        out.text("watchdog: fed for ");
        out.u32(ms_since(start_ms));
        out.text(" ms without reset");
        check(&mut out, true);

        let mut buf = [0u8; 4];
        avr_device::interrupt::disable();
        let blocked = out.read(&mut buf).is_err();
        out.text("usart0: read with interrupts off and no data -> error");
        check(&mut out, blocked);

        out.text("selftest done\n");
        out.flush_all();
        halt()
    }

    /// ATmega328P: the Uno servo tracker's board parts.
    #[cfg(not(avr_atmega2560))]
    mod uno_parts {
        use drivers::encoder::SharedEncoder;
        use drivers::servo::{ContinuousServo, ServoConfig};
        use embedded_hal::delay::DelayNs;
        use embedded_hal::pwm::SetDutyCycle;
        use suntracker::log::Sink;
        use suntracker_avr::{
            chip, millis, sleep_until_interrupt, Adc, AdcError, Delay, PinChangeEncoders, Port,
            PulseWidth, PwmError, Timer1Pwm, Usart0, ADC_CHANNELS, FRAME_TOP, FRAME_US, MAX_DUTY,
        };

        use super::check;

        /// The FS5106R's pulses (FEETECH's control range): 700 / 1,500 /
        /// 2,300 µs, 50 Hz.
        const FS5106R: ServoConfig = ServoConfig {
            period_us: FRAME_US,
            min_pulse_us: 700,
            neutral_us: 1_500,
            max_pulse_us: 2_300,
        };
        /// OC1B's pulse after the start: 1,750 µs (half speed forward).
        const OC1B_PULSE_US: u32 = 1_750;
        /// The ADC input the harness feeds.
        const ADC_CHANNEL: u8 = 0;
        /// Polls before the self-test gives up on a conversion (one takes
        /// 25 ADC clocks at most, 3,200 CPU cycles; a poll takes more than
        /// 4).
        const ADC_MAX_POLLS: u32 = 10_000;
        /// Edges the self-test drives on its own pins: C forward, A
        /// backward (multiples of 4: both end at levels 00, where they
        /// started).
        const OWN_EDGES_C: u8 = 12;
        const OWN_EDGES_A: u8 = 8;
        /// The encoders' bits in PORTD: C on PD4/PD5, A on PD6/PD7.
        const C_A: u8 = 1 << 4;
        const C_B: u8 = 1 << 5;
        const A_A: u8 = 1 << 6;
        const A_B: u8 = 1 << 7;
        /// How long the encoders count external edges.
        const COUNT_WINDOW_MS: u64 = 1_000;

        /// Starts the 50 Hz frames at neutral on both channels, then
        /// OC1B at 1,750 µs, through the servo driver.
        pub fn pwm(out: &mut Usart0, tc1: chip::TC1, portb: &chip::PORTB) -> Timer1Pwm {
            let pwm = Timer1Pwm::start(
                tc1,
                portb,
                PulseWidth::NEUTRAL_1500_US,
                PulseWidth::NEUTRAL_1500_US,
            );
            let refused_pulses = PulseWidth::from_us(0) == Err(PwmError::PulseOutOfRange)
                && PulseWidth::from_us(FRAME_US + 1) == Err(PwmError::PulseOutOfRange);
            let (mut oc1a, oc1b) = pwm.channels();
            let refused_duty = oc1a.set_duty_cycle(MAX_DUTY + 1) == Err(PwmError::DutyOutOfRange);
            let max_duty = oc1a.max_duty_cycle();
            let servo_a = ContinuousServo::new(oc1a, FS5106R);
            let servo_b = ContinuousServo::new(oc1b, FS5106R)
                .and_then(|mut s| s.set_pulse_us(OC1B_PULSE_US).map(|()| s));
            let pulse_a = servo_a.as_ref().map_or(0, |s| s.pulse_us());
            let pulse_b = servo_b.as_ref().map_or(0, |s| s.pulse_us());
            out.text("pwm: Timer1 TOP=");
            out.u32(u32::from(FRAME_TOP));
            out.text(" max_duty=");
            out.u32(u32::from(max_duty));
            out.text(" OC1A(PB1)=");
            out.u32(pulse_a);
            out.text(" us OC1B(PB2)=");
            out.u32(pulse_b);
            out.text(" us, out of range refused");
            check(
                out,
                refused_pulses
                    && refused_duty
                    && max_duty == MAX_DUTY
                    && pulse_a == FS5106R.neutral_us
                    && pulse_b == OC1B_PULSE_US,
            );
            pwm
        }

        /// One conversion of ADC0, its code logged; a channel out of range
        /// and a start while busy refused.
        pub fn adc(out: &mut Usart0, adc: chip::ADC) {
            let mut adc = Adc::new(adc);
            let refused = adc.start(ADC_CHANNELS) == Err(AdcError::NoSuchChannel(ADC_CHANNELS));
            let started = adc.start(ADC_CHANNEL).is_ok();
            let busy = adc.start(ADC_CHANNEL) == Err(AdcError::Busy) && adc.is_busy();
            let mut code = None;
            let mut polls = 0u32;
            while code.is_none() && polls < ADC_MAX_POLLS {
                code = adc.poll();
                polls += 1;
            }
            let once = adc.poll().is_none();
            out.text("adc: ADC0 code=");
            match code {
                Some(c) => out.u32(u32::from(c)),
                None => out.text("none"),
            }
            out.text(", channel 8 refused, start while busy refused");
            check(out, refused && started && busy && code.is_some() && once);
            let _ = adc.release();
        }

        fn counts(out: &mut Usart0, c: &SharedEncoder, a: &SharedEncoder) {
            out.text("C count=");
            out.i32(c.count());
            out.text(" errors=");
            out.u32(c.errors());
            out.text(", A count=");
            out.i32(a.count());
            out.text(" errors=");
            out.u32(a.errors());
        }

        /// The pin of encoder channel pair (`a_bit`, `b_bit`) that one step
        /// from Gray state `k` (0..3: 00, 10, 11, 01) toggles: forward, A
        /// from an even state, B from an odd one; backward the other.
        fn step_bit(k: u8, forward: bool, a_bit: u8, b_bit: u8) -> u8 {
            if (k % 2 == 0) == forward {
                a_bit
            } else {
                b_bit
            }
        }

        /// Feeds both encoders from their own pins, then counts external
        /// edges for [`COUNT_WINDOW_MS`].
        pub fn encoders(
            out: &mut Usart0,
            exint: chip::EXINT,
            portd: &chip::PORTD,
            delay: &mut Delay,
            cpu: &chip::CPU,
        ) {
            let encoders = PinChangeEncoders::start(&exint, portd, false);
            let (c, a) = (encoders.encoder_c(), encoders.encoder_a());
            let pins = C_A | C_B | A_A | A_B;
            // Outputs at the present (input) levels, 00 after reset.
            portd.set_port(pins, false);
            portd.set_ddr(pins, true);
            for step in 0..OWN_EDGES_C.max(OWN_EDGES_A) {
                let mut toggle = 0u8;
                if step < OWN_EDGES_C {
                    toggle |= step_bit(step % 4, true, C_A, C_B);
                }
                if step < OWN_EDGES_A {
                    // Backward from state 0 - step.
                    toggle |= step_bit((4 - step % 4) % 4, false, A_A, A_B);
                }
                // One write: both encoders' edges in one interrupt.
                portd.toggle(toggle);
                delay.delay_us(20);
            }
            let own_ok = c.count() == i32::from(OWN_EDGES_C)
                && a.count() == -i32::from(OWN_EDGES_A)
                && c.errors() == 0
                && a.errors() == 0
                && portd.pin() & pins == 0;
            out.text("encoders: own pins PD4/PD5 +");
            out.u32(u32::from(OWN_EDGES_C));
            out.text(", PD6/PD7 -");
            out.u32(u32::from(OWN_EDGES_A));
            out.text(" -> ");
            counts(out, c, a);
            check(out, own_ok);
            // Inputs again (no pull-up: the harness drives the levels),
            // counts from zero.
            portd.set_ddr(pins, false);
            c.set_count(0);
            a.set_count(0);
            out.text("encoders: inputs, counting for 1000 ms\n");
            let start_ms = millis();
            while millis().saturating_sub(start_ms) < COUNT_WINDOW_MS {
                sleep_until_interrupt(cpu);
            }
            out.text("encoders: after 1000 ms ");
            counts(out, c, a);
            out.text("\n");
            encoders.stop(&exint);
        }
    }

    /// Interrupts off, sleep: simavr ends the simulation there.
    fn halt() -> ! {
        loop {
            avr_device::interrupt::disable();
            avr_device::asm::sleep();
        }
    }

    #[panic_handler]
    fn panic(_info: &core::panic::PanicInfo) -> ! {
        // SAFETY: the program is over; nothing else uses USART0 any more.
        let usart = unsafe { chip::USART0::steal() };
        let mut out = Usart0::new(usart, BAUD_HZ);
        out.text("panic\n");
        out.flush_all();
        halt()
    }
}
