//! Links libgcc's 32-bit division and avr-libc's `memcpy`/`memset` into
//! this board's AVR images (see `boards/avr/asm_runtime.rs`).

include!("../avr/asm_runtime.rs");

fn main() {
    link_avr_asm_runtime();
    // The example `library_firmware` is built to measure the library's
    // firmware loop on this board's parts, which does not fit the
    // ATmega328P's 32 KB yet: its link gets the 128 KB of program memory
    // the avr5 linker script knows by default (avr-gcc's device settings
    // give the part's 32 KB). The images flashed keep the part's limit.
    println!("cargo:rustc-link-arg-examples=-Wl,--defsym=__TEXT_REGION_LENGTH__=131072");
}
