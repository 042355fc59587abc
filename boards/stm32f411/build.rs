//! Puts this board's memory map (`memory.x` beside this file) where
//! cortex-m-rt's `link.x` finds it: `INCLUDE memory.x` finds the
//! repository's root `memory.x` when the linker runs there, which includes
//! `board_memory.x`, or else `memory.x` on the search path; both are this
//! board's map, written to OUT_DIR.

use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    for name in ["memory.x", "board_memory.x"] {
        fs::copy("memory.x", out.join(name)).expect("copy memory.x to OUT_DIR");
    }
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
}
