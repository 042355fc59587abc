//! Links libgcc's 32-bit division into this board's AVR images (see
//! `boards/avr/libgcc_division.rs`).

include!("../avr/libgcc_division.rs");

fn main() {
    link_avr_division();
}
