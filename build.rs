//! Build script of the `suntracker` package:
//! - puts the selected board's memory map where the root `memory.x` (which
//!   `link.x` of cortex-m-rt includes) looks for it;
//! - turns `data/postal_codes.csv` into the sorted no_std postal-code table
//!   `$OUT_DIR/postal_table.rs` (format in `src/site/postal.rs`);
//! - on AVR, links avr-gcc's assembler 32-bit division (libgcc's
//!   `__udivmodsi4`, 68 B, and `__divmodsi4`) in place of compiler_builtins'
//!   generic Rust one (weak symbols, 1.2 KB): LLVM's AVR back end calls
//!   these with libgcc's own register convention, which compiler_builtins
//!   copies. Linking all of libgcc with `--whole-archive` (as avr-libc's
//!   libm is) fails on libgcc's duplicate fixed-point aliases, so only the
//!   two members are taken out of it.

use std::env;
use std::fmt::Write as _;
use std::fs;
use std::path::PathBuf;

#[path = "src/site/key.rs"]
#[allow(dead_code)]
mod key;

const POSTAL_CSV: &str = "data/postal_codes.csv";

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let target = env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumb") {
        // cortex-m-rt's link.x does `INCLUDE memory.x`; the linker looks in
        // its working directory (the package root) first, then on the
        // search path. The root memory.x only does `INCLUDE board_memory.x`,
        // so the map is the one written here: the board feature's, QEMU's
        // by default. The root file goes to OUT_DIR too, for a linker that
        // runs elsewhere (the package built as a dependency).
        let memory = match env::var_os("CARGO_FEATURE_STM32F411") {
            Some(_) => "boards/stm32f411/memory.x",
            None => "boards/mps2_an386/memory.x",
        };
        fs::copy(memory, out.join("board_memory.x")).expect("copy the board map to OUT_DIR");
        fs::copy("memory.x", out.join("memory.x")).expect("copy memory.x to OUT_DIR");
        println!("cargo:rustc-link-search={}", out.display());
    }
    if target.starts_with("avr") {
        link_libgcc_division(&out);
    }
    println!("cargo:rerun-if-changed=boards");
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/site/key.rs");
    println!("cargo:rerun-if-changed={POSTAL_CSV}");
    let csv = fs::read_to_string(POSTAL_CSV).expect("read data/postal_codes.csv");
    let table = postal_table(&csv).unwrap_or_else(|e| panic!("{POSTAL_CSV}: {e}"));
    fs::write(out.join("postal_table.rs"), table).expect("write postal_table.rs");
}

/// The `-C target-cpu=` of this build (the AVR part: its libgcc multilib);
/// the last one given wins, as for rustc (boards/mega2560's config adds its
/// own after the root's).
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

/// Coordinate in units of 1e-4 degree, checked to fit 24 bits.
fn scaled(text: &str, limit: f64, what: &str, line: usize) -> Result<i32, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("line {line}: {what} {text:?} is not a number"))?;
    if !v.is_finite() || v.abs() > limit {
        return Err(format!("line {line}: {what} {v} outside ±{limit}"));
    }
    Ok((v * 1e4).round() as i32)
}

fn postal_table(csv: &str) -> Result<String, String> {
    let mut rows: Vec<(u64, i32, i32, String, String)> = Vec::new();
    for (i, raw) in csv.lines().enumerate() {
        let line = i + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let f: Vec<&str> = l.split(',').collect();
        if f.len() != 5 {
            return Err(format!(
                "line {line}: expected 5 columns, found {}",
                f.len()
            ));
        }
        if f[0] == "country" {
            continue; // header
        }
        let (country, code, place) = (f[0].trim(), f[1].trim(), f[2].trim());
        let k = key::pack(country.as_bytes(), code.as_bytes())
            .map_err(|e| format!("line {line}: {e:?} in {country:?} {code:?}"))?;
        let lat = scaled(f[3], 90.0, "latitude", line)?;
        let lon = scaled(f[4], 180.0, "longitude", line)?;
        rows.push((k, lat, lon, format!("{country}:{code}"), place.to_string()));
    }
    rows.sort_by_key(|r| r.0);
    for w in rows.windows(2) {
        if w[0].0 == w[1].0 {
            return Err(format!("duplicate postal code {}", w[1].3));
        }
    }
    let n = rows.len();
    let mut s = String::new();
    writeln!(
        s,
        "// Generated by build.rs from {POSTAL_CSV}; do not edit."
    )
    .unwrap();
    writeln!(s, "/// Number of entries.\npub const LEN: usize = {n};").unwrap();
    writeln!(
        s,
        "/// Keys (see `key.rs`), ascending; in program memory on AVR.\n#[cfg_attr(target_arch = \"avr\", link_section = \".progmem.data\")]\npub static KEYS: [u64; {n}] = ["
    )
    .unwrap();
    for r in &rows {
        writeln!(s, "    0x{:016x}, // {}", r.0, r.3).unwrap();
    }
    writeln!(s, "];").unwrap();
    writeln!(
        s,
        "/// Latitude and longitude, 1e-4 degree, little-endian 24-bit each; in\n/// program memory on AVR.\n#[cfg_attr(target_arch = \"avr\", link_section = \".progmem.data\")]\npub static COORDS: [[u8; 6]; {n}] = ["
    )
    .unwrap();
    for r in &rows {
        let a = r.1.to_le_bytes();
        let b = r.2.to_le_bytes();
        writeln!(
            s,
            "    [{}, {}, {}, {}, {}, {}],",
            a[0], a[1], a[2], b[0], b[1], b[2]
        )
        .unwrap();
    }
    writeln!(s, "];").unwrap();
    writeln!(
        s,
        "/// Place names (linked only when used).\npub static PLACES: [&str; {n}] = ["
    )
    .unwrap();
    for r in &rows {
        writeln!(s, "    {:?},", r.4).unwrap();
    }
    writeln!(s, "];").unwrap();
    Ok(s)
}
