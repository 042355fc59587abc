//! Cortex-M4F firmware for QEMU's `mps2-an386` board.
//!
//! Boots through cortex-m-rt, prints over semihosting and exits with the
//! firmware's status, which QEMU returns as its own exit code.
//! `cargo run --release --target thumbv7em-none-eabihf --bin qemu_tracker`
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(all(target_arch = "arm", target_os = "none"))]
mod firmware {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hprintln};

    #[entry]
    fn main() -> ! {
        hprintln!("{} on qemu mps2-an386 (cortex-m4f): boot ok", suntracker::BANNER);
        debug::exit(debug::EXIT_SUCCESS);
        #[allow(clippy::empty_loop)]
        loop {}
    }

    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo) -> ! {
        hprintln!("panic: {}", info);
        debug::exit(debug::EXIT_FAILURE);
        #[allow(clippy::empty_loop)]
        loop {}
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    println!("{} on host: boot ok", suntracker::BANNER);
}
