//! ATmega328P speed bench: CPU cycles per sun position in `f32`.
//!
//! Method: Timer1 runs free at clk/1 (prescaler 1, so one count per CPU
//! cycle at 16 MHz); its overflow interrupt extends it to 32 bits. Each
//! measurement clears the counter, runs the work, disables interrupts, reads
//! `overflows · 65536 + TCNT1` (plus one overflow still pending in TOV1)
//! and stops the timer, minus the cost of an empty measurement
//! (calibrated once at boot). simavr simulates Timer1 cycle by cycle, so the
//! figures are exact for the simulated part; the overflow handler's own
//! ~40 cycles per 65,536 (0.06 %) are included in long measurements.
//!
//! The same source builds for the ATmega2560 with `--cfg avr_atmega2560`
//! in the compiler flags (see `.ci/firmware_env.sh`); there `call`/`ret`
//! cost one cycle more (3-byte program counter).
//!
//! `cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-avr --bin avr_bench`
//! then `simavr -m atmega328p -f 16000000 target/avr-none/release/avr_bench.elf`;
//! `.ci/avr_cycles.sh` runs it and checks the budgets.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

#[cfg(avr_atmega2560)]
use avr_device::atmega2560 as chip;
#[cfg(not(avr_atmega2560))]
use avr_device::atmega328p as chip;

mod firmware {
    use crate::chip;
    use avr_device::interrupt::Mutex;
    use core::cell::Cell;
    use sim::sun_workload as cases;
    use sun_algos::{Algorithm, Options};
    use suntracker::log::Sink;
    use suntracker_avr::Usart0;

    /// The log's rate (USART0, 8N1).
    const BAUD_HZ: u32 = 115_200;

    #[cfg(not(avr_atmega2560))]
    const CHIP_LINE: &str = " avr_bench on atmega328p @ 16 MHz (Timer1 clk/1)\n";
    #[cfg(avr_atmega2560)]
    const CHIP_LINE: &str = " avr_bench on atmega2560 @ 16 MHz (Timer1 clk/1)\n";

    /// Timer1 overflows since the measurement started.
    static OVERFLOWS: Mutex<Cell<u16>> = Mutex::new(Cell::new(0));

    #[cfg_attr(not(avr_atmega2560), avr_device::interrupt(atmega328p))]
    #[cfg_attr(avr_atmega2560, avr_device::interrupt(atmega2560))]
    fn TIMER1_OVF() {
        avr_device::interrupt::free(|cs| {
            let c = OVERFLOWS.borrow(cs);
            c.set(c.get().wrapping_add(1));
        });
    }

    /// Timer1 as a 32-bit cycle counter.
    struct CycleCounter {
        tc1: chip::TC1,
        overhead: u32,
    }

    impl CycleCounter {
        fn new(tc1: chip::TC1) -> Self {
            tc1.tccr1a().reset();
            tc1.tccr1b().reset();
            tc1.timsk1().write(|w| w.toie1().set_bit());
            let mut c = CycleCounter { tc1, overhead: 0 };
            c.overhead = c.measure(|| ());
            c
        }

        /// Cycles spent in `work`, net of the measurement's own cost.
        fn measure<R>(&mut self, work: impl FnOnce() -> R) -> u32 {
            avr_device::interrupt::free(|cs| OVERFLOWS.borrow(cs).set(0));
            self.tc1.tcnt1().write(|w| w.set(0));
            self.tc1.tifr1().write(|w| w.tov1().set_bit());
            // SAFETY: the only interrupt enabled is the overflow counter,
            // whose state is behind a critical-section mutex.
            unsafe { avr_device::interrupt::enable() };
            self.tc1.tccr1b().write(|w| w.cs1().direct());
            core::hint::black_box(work());
            // Read the count while the timer runs (simavr updates TCNT1 only
            // for a running timer), with interrupts off; an overflow that
            // happened but is not yet counted shows as a pending TOV1 flag
            // with a small count.
            avr_device::interrupt::disable();
            let low = self.tc1.tcnt1().read().bits();
            let pending = self.tc1.tifr1().read().tov1().bit_is_set() && low < 0x8000;
            self.tc1.tccr1b().write(|w| w.cs1().no_clock());
            let counted = avr_device::interrupt::free(|cs| OVERFLOWS.borrow(cs).get());
            let high = u32::from(counted) + u32::from(pending);
            let low = u32::from(low);
            (high << 16 | low).saturating_sub(self.overhead)
        }
    }

    /// Per-position cycles (mean and max over the cases) and the cycles of a
    /// whole day table, for one algorithm.
    /// A macro, not a function: each expansion has its own closures, so the
    /// algorithm stays a compile-time constant inside the measured code.
    macro_rules! bench_one {
        ($out:expr, $counter:expr, $algorithm:ty, $options:expr) => {{
            let out: &mut Usart0 = $out;
            let counter: &mut CycleCounter = $counter;
            let options: &Options<f32> = $options;
            let algorithm: Algorithm = <$algorithm as cases::Measured>::ALGORITHM;
            let mut total: u32 = 0;
            let mut max: u32 = 0;
            let mut n: u32 = 0;
            let mut index = 0;
            while let Some(case) = cases::case(index) {
                let c = counter.measure(|| cases::one_position::<$algorithm>(&case, options));
                total = total.saturating_add(c);
                max = max.max(c);
                n += 1;
                index += 1;
            }
            out.text("position ");
            out.text(algorithm.name());
            out.text(" f32 cycles_mean=");
            out.u32(total.checked_div(n).unwrap_or(0));
            out.text(" cycles_max=");
            out.u32(max);
            out.text("\n");
            let mut mask: cases::DaylightMask = [0; 45];
            for (label, daylight_only) in [("day_table ", false), ("daylight_table ", true)] {
                let mut n = 0;
                let c = counter
                    .measure(|| n = cases::table::<$algorithm>(options, &mut mask, daylight_only));
                out.text(label);
                out.text(algorithm.name());
                out.text(" f32 points=");
                out.u32(u32::from(n));
                out.text(" cycles=");
                out.u32(c);
                out.text(" ms=");
                out.u32(c / 16_000);
                out.text("\n");
            }
        }};
    }

    #[no_mangle]
    pub extern "C" fn main() -> ! {
        // SAFETY: taken once, at the start of the only thread.
        let dp = unsafe { chip::Peripherals::steal() };
        let mut out = Usart0::new_tx_only(dp.USART0, BAUD_HZ);
        let mut counter = CycleCounter::new(dp.TC1);
        out.text(suntracker::BANNER);
        out.text(CHIP_LINE);
        out.text("calibration overhead_cycles=");
        out.u32(counter.overhead);
        out.text("\n");
        let options = cases::options();
        // One call site per algorithm, each with a constant algorithm, so
        // that only the measured algorithms are linked (see `cases`).
        bench_one!(&mut out, &mut counter, cases::Psa2020, &options);
        bench_one!(&mut out, &mut counter, cases::Michalsky, &options);
        bench_one!(&mut out, &mut counter, cases::Grena2012No3, &options);
        out.text("avr_bench done\n");
        halt(&mut out)
    }

    #[panic_handler]
    fn panic(_info: &core::panic::PanicInfo) -> ! {
        // SAFETY: the program is over; nothing else uses USART0 any more.
        let usart = unsafe { chip::USART0::steal() };
        let mut out = Usart0::new_tx_only(usart, BAUD_HZ);
        out.text("panic\n");
        halt(&mut out)
    }

    /// Sends what is queued, then sleeps with interrupts off: simavr ends
    /// the simulation there.
    fn halt(out: &mut Usart0) -> ! {
        out.flush_all();
        loop {
            avr_device::interrupt::disable();
            avr_device::asm::sleep();
        }
    }
}
