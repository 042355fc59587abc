//! Puts this board's memory map (`memory.x` beside this file) where
//! cortex-m-rt's `link.x` finds it: `INCLUDE memory.x` finds the
//! repository's root `memory.x` when the linker runs there, which includes
//! `board_memory.x`, or else `memory.x` on the search path; both are this
//! board's map, written to OUT_DIR. Also `device.x`, which cortex-m-rt's
//! `device` feature includes: this board names no interrupt handler of its
//! own (every line goes to `DefaultHandler`, see `__INTERRUPTS` in lib.rs).

use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    for name in ["memory.x", "board_memory.x"] {
        fs::copy("memory.x", out.join(name)).expect("copy memory.x to OUT_DIR");
    }
    fs::write(
        out.join("device.x"),
        "/* mps2-an386: every interrupt line goes to DefaultHandler (lib.rs, __INTERRUPTS). */\n",
    )
    .expect("write device.x to OUT_DIR");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
}
