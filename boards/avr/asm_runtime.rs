// Shared by the build scripts of the AVR board crates (boards/avr,
// boards/uno, boards/mega2560), each of which `include!`s it: a build
// script's link arguments reach only its own package's images.
//
// Links hand-written assembler routines of the AVR toolchain in place of
// compiler_builtins' generic Rust ones, which are weak symbols:
// - avr-gcc's 32-bit division (libgcc's `__udivmodsi4`, 68 B, and
//   `__divmodsi4`) instead of 1.2 KB: LLVM's AVR back end calls these with
//   libgcc's own register convention, which compiler_builtins copies;
// - avr-libc's `memcpy` (18 B) and `memset` (14 B) instead of 384 B and
//   138 B (plus an 18 B weak alias each): plain C functions of the avr-gcc
//   calling convention, which LLVM's AVR back end follows.
// Linking all of libgcc with `--whole-archive` (as avr-libc's libm is)
// fails on libgcc's duplicate fixed-point aliases, and a weak definition
// already present never pulls a member out of an archive, so only these
// members are taken out and linked as objects.

use std::env;
use std::fs;

/// Links libgcc's division and avr-libc's memory routines when building
/// for AVR (no-op on other targets: `cargo clippy` of the workspace on the
/// host).
fn link_avr_asm_runtime() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=../avr/asm_runtime.rs");
    if env::var("TARGET").unwrap_or_default().starts_with("avr") {
        let out = std::path::PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
        let cpu = target_cpu().unwrap_or_else(|| "atmega328p".to_string());
        // `__divmodsi4` negates through `__negsi2`: objects come after
        // `-lgcc` on the link line, so it is taken out too.
        let libgcc = ["_udivmodsi4.o", "_divmodsi4.o", "_negsi2.o"];
        link_members(&out, &cpu, "-print-libgcc-file-name", "libgcc", &libgcc);
        let libc = ["memcpy.o", "memset.o"];
        link_members(&out, &cpu, "-print-file-name=libc.a", "libc", &libc);
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

/// Extracts `members` of the archive avr-gcc names with `print_arg` for
/// this part into `out` and links them as objects (strong symbols over
/// compiler_builtins' weak ones).
fn link_members(out: &std::path::Path, cpu: &str, print_arg: &str, name: &str, members: &[&str]) {
    use std::process::Command;
    let archive = Command::new("avr-gcc")
        .arg(format!("-mmcu={cpu}"))
        .arg(print_arg)
        .output()
        .expect("avr-gcc (Debian gcc-avr) links the AVR images: run it to find its libraries");
    let archive = String::from_utf8(archive.stdout).expect("library path is UTF-8");
    let archive = archive.trim();
    let dir = out.join(format!("{name}-{cpu}"));
    fs::create_dir_all(&dir).expect("create the member directory");
    let status = Command::new("avr-ar")
        .current_dir(&dir)
        .arg("x")
        .arg(archive)
        .args(members)
        .status()
        .expect("avr-ar (Debian binutils-avr) extracts the library members");
    assert!(status.success(), "avr-ar x {archive} {members:?} failed");
    for m in members {
        println!("cargo:rustc-link-arg={}", dir.join(m).display());
    }
}
