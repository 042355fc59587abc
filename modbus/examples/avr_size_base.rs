//! The baseline of `avr_size`: the same loop of `black_box` bytes and
//! time stamps, without the receiver, the server and the map.
#![cfg_attr(target_arch = "avr", no_std, no_main)]

#[cfg(target_arch = "avr")]
mod avr {
    use core::hint::black_box;

    #[no_mangle]
    pub extern "C" fn main() -> ! {
        loop {
            let (byte, t) = black_box((0_u8, 0_u32));
            black_box((byte, t));
        }
    }

    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo) -> ! {
        loop {}
    }
}

#[cfg(not(target_arch = "avr"))]
fn main() {}
