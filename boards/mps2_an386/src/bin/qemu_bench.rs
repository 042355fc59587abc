//! Cortex-M4F speed bench under QEMU (`mps2-an386`): instructions per sun
//! position in `f32`.
//!
//! Method: QEMU started with `-icount shift=0` advances its virtual clock by
//! exactly 1 ns per executed instruction. SysTick runs from the board's
//! 25 MHz CPU clock on that virtual clock, so one SysTick count is 40
//! instructions; the bench counts SysTick over many positions (a whole day
//! table, 360 positions) and reports instructions = counts × 40. QEMU does
//! not model the DWT cycle counter or pipeline timing: these are executed
//! instructions, a lower bound for cycles on a real Cortex-M4 (about 1–1.5
//! cycles per instruction with FPU code from zero-wait-state memory).
//!
//! ```text
//! cargo build --release --target thumbv7em-none-eabihf --bin qemu_bench
//! qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -monitor none \
//!   -serial null -icount shift=0 -semihosting-config enable=on,target=native \
//!   -kernel target/thumbv7em-none-eabihf/release/qemu_bench
//! ```
#![no_std]
#![no_main]

// The board crate's interrupt vectors (`__INTERRUPTS`): nothing else of it
// is used here.
use suntracker_mps2_an386 as _;

mod firmware {
    use cortex_m::peripheral::{syst::SystClkSource, SYST};
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hio};
    use sim::sun_workload as cases;
    use sun_algos::{Algorithm, Options};
    use suntracker::log::Sink;

    /// Instructions per SysTick count: 1 ns per instruction (`-icount
    /// shift=0`) at a 25 MHz SysTick clock.
    const INSTRUCTIONS_PER_TICK: u32 = 40;

    struct Semihosting(Option<hio::HostStream>);

    impl Sink for Semihosting {
        fn put(&mut self, bytes: &[u8]) {
            if let Some(s) = self.0.as_mut() {
                let _ = s.write_all(bytes);
            }
        }
    }

    /// SysTick counts (it counts down, 24 bits) spent in `work`.
    fn ticks<R>(syst: &mut SYST, work: impl FnOnce() -> R) -> u32 {
        syst.clear_current();
        let start = SYST::get_current();
        core::hint::black_box(work());
        let end = SYST::get_current();
        start.wrapping_sub(end) & 0x00FF_FFFF
    }

    macro_rules! bench_one {
        ($out:expr, $syst:expr, $algorithm:ty, $options:expr) => {{
            let out: &mut Semihosting = $out;
            let syst: &mut SYST = $syst;
            let options: &Options<f32> = $options;
            let algorithm: Algorithm = <$algorithm as cases::Measured>::ALGORITHM;
            let mut mask: cases::DaylightMask = [0; 45];
            for (label, daylight_only) in [("day_table ", false), ("daylight_table ", true)] {
                let mut n = 0;
                let t = ticks(syst, || {
                    n = cases::table::<$algorithm>(options, &mut mask, daylight_only)
                });
                let instructions = t.saturating_mul(INSTRUCTIONS_PER_TICK);
                if !daylight_only {
                    out.text("position ");
                    out.text(algorithm.name());
                    out.text(" f32 instructions_per_position=");
                    out.u32(instructions.checked_div(u32::from(n)).unwrap_or(0));
                    out.text("\n");
                }
                out.text(label);
                out.text(algorithm.name());
                out.text(" f32 points=");
                out.u32(u32::from(n));
                out.text(" instructions=");
                out.u32(instructions);
                out.text("\n");
            }
        }};
    }

    #[entry]
    fn main() -> ! {
        let mut out = Semihosting(hio::hstdout().ok());
        if let Some(cp) = cortex_m::Peripherals::take() {
            let mut syst = cp.SYST;
            syst.set_clock_source(SystClkSource::Core);
            syst.set_reload(0x00FF_FFFF);
            syst.clear_current();
            syst.enable_counter();
            out.text(suntracker::BANNER);
            out.text(" qemu_bench on mps2-an386 (run with -icount shift=0)\n");
            let options = cases::options();
            bench_one!(&mut out, &mut syst, cases::Psa2020, &options);
            bench_one!(&mut out, &mut syst, cases::Michalsky, &options);
            bench_one!(&mut out, &mut syst, cases::Grena2012No3, &options);
        }
        out.text("qemu_bench done\n");
        debug::exit(debug::EXIT_SUCCESS);
        #[allow(clippy::empty_loop)]
        loop {}
    }

    #[panic_handler]
    fn panic(_info: &core::panic::PanicInfo) -> ! {
        debug::exit(debug::EXIT_FAILURE);
        #[allow(clippy::empty_loop)]
        loop {}
    }
}
