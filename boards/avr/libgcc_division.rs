// Shared by the build scripts of the AVR board crates (boards/avr,
// boards/uno, boards/mega2560), each of which `include!`s it: a build
// script's link arguments reach only its own package's images.
//
// Links avr-gcc's assembler 32-bit division (libgcc's `__udivmodsi4`, 68 B,
// and `__divmodsi4`) in place of compiler_builtins' generic Rust one (weak
// symbols, 1.2 KB): LLVM's AVR back end calls these with libgcc's own
// register convention, which compiler_builtins copies. Linking all of
// libgcc with `--whole-archive` (as avr-libc's libm is) fails on libgcc's
// duplicate fixed-point aliases, so only the two members are taken out of
// it.

use std::env;
use std::fs;

/// Links libgcc's division when building for AVR (no-op on other targets:
/// `cargo clippy` of the workspace on the host).
fn link_avr_division() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=../avr/libgcc_division.rs");
    if env::var("TARGET").unwrap_or_default().starts_with("avr") {
        let out = std::path::PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
        link_libgcc_division(&out);
    }
}

/// The `-C target-cpu=` of this build (the AVR part: its libgcc multilib);
/// the last one given wins, as for rustc (the Mega's .cargo/config.toml
/// adds its own after the root's).
fn target_cpu() -> Option<String> {
    let flags = env::var("CARGO_ENCODED_RUSTFLAGS").unwrap_or_default();
    let mut args = flags.split('\x1f');
    let mut cpu = None;
    while let Some(a) = args.next() {
        let value = match a.strip_prefix("-C") {
            Some("") => args.next().unwrap_or_default(),
            Some(rest) => rest,
            None => continue,
        };
        if let Some(c) = value.strip_prefix("target-cpu=") {
            cpu = Some(c.to_string());
        }
    }
    cpu
}

/// Extracts libgcc's 32-bit division members for this part into `out` and
/// links them as objects (strong symbols over compiler_builtins' weak ones).
fn link_libgcc_division(out: &std::path::Path) {
    use std::process::Command;
    let cpu = target_cpu().unwrap_or_else(|| "atmega328p".to_string());
    let libgcc = Command::new("avr-gcc")
        .arg(format!("-mmcu={cpu}"))
        .arg("-print-libgcc-file-name")
        .output()
        .expect("avr-gcc (Debian gcc-avr) links the AVR images: run it to find libgcc");
    let libgcc = String::from_utf8(libgcc.stdout).expect("libgcc path is UTF-8");
    let libgcc = libgcc.trim();
    let dir = out.join(format!("libgcc-{cpu}"));
    fs::create_dir_all(&dir).expect("create the libgcc member directory");
    // `__divmodsi4` negates through `__negsi2`: objects come after `-lgcc`
    // on the link line, so it is taken out too.
    let members = ["_udivmodsi4.o", "_divmodsi4.o", "_negsi2.o"];
    let status = Command::new("avr-ar")
        .current_dir(&dir)
        .arg("x")
        .arg(libgcc)
        .args(members)
        .status()
        .expect("avr-ar (Debian binutils-avr) extracts libgcc's division");
    assert!(status.success(), "avr-ar x {libgcc} {members:?} failed");
    for m in members {
        println!("cargo:rustc-link-arg={}", dir.join(m).display());
    }
}
