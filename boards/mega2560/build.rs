//! Links libgcc's 32-bit division and avr-libc's `memcpy`/`memset` into
//! this board's AVR images (see `boards/avr/asm_runtime.rs`).

include!("../avr/asm_runtime.rs");

fn main() {
    link_avr_asm_runtime();
}
