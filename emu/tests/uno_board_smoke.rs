//! The ATmega328P board self-test (`boards/avr/src/bin/avr_board_selftest.rs` built
//! with `-p suntracker-uno`) in simavr: the Uno servo tracker's board parts
//! (`boards/avr/src/{pwm,adc,pcint}.rs`) measured from outside.
//!
//! - Servo PWM: both Timer1 outputs' pulses decoded from their pins (PB1 =
//!   OC1A, PB2 = OC1B), widths and period in CPU cycles, against the
//!   datasheet arithmetic (ATmega328P §15.9.3, fast PWM mode 14 at clk/8:
//!   a frame of TOP + 1 = 16 MHz / (8 · 50 Hz) = 40,000 counts of 0.5 µs;
//!   the pin high for OCR1x + 1 counts) within one Timer1 count: 1,500 µs on
//!   OC1A, 1,750 µs on OC1B; the first pulse on each pin a whole one.
//! - ADC: a voltage on ADC0 (`Sim::set_adc_mv`, AVcc = 5,000 mV), the
//!   logged code against §24.7 `ADC = Vin·1024/Vref` (floored) and against
//!   simavr's `mV·1023/Vref` (`models::panel`, emu/README.md), which is one
//!   code lower at some inputs.
//! - Encoders: once the self-test says its encoder pins are inputs, the
//!   harness drives PD4/PD5 (encoder C) and PD6/PD7 (encoder A) with the
//!   YMT22 model's edges (`models::quadrature`, 300 lines, on the FS5106R
//!   model's full speed, 570 °/s = 1,900 edges/s, then ten times that):
//!   C forward, A backward; the counts the self-test logs a second later
//!   must be the model's `count_at` of the final shaft angles, without
//!   errors.
//! - The encoders' pin-change handler, stepped one instruction at a time in
//!   simavr: its cycles for one edge and for both encoders at once, within
//!   the figures the board layer's notes give from the disassembly.
//!
//! The ELF: `$SUNTRACKER_EMU_ELF_SELFTEST_UNO`, else
//! `$CARGO_TARGET_DIR/avr-none/release/avr_board_selftest.elf` (or
//! `target/…` at the repository root), built by
//! `cargo +nightly build --release --target avr-none -Z build-std=core -p suntracker-avr --bin avr_board_selftest`.
//! Skipped when absent.

use std::path::{Path, PathBuf};

use suntracker_emu::log::LineAssembler;
use suntracker_emu::models::fs5106r::{Segment, ServoSpec};
use suntracker_emu::models::panel::{adc_code, simavr_adc_code};
use suntracker_emu::models::quadrature::QuadratureEncoder;
use suntracker_emu::sim::{CpuState, Sim};

const F_CPU: u32 = 16_000_000;
/// Timer1 prescaler (clk/8) and frame rate.
const PRESCALE: u64 = 8;
const FRAME_HZ: u64 = 50;
/// Cycles per Timer1 count: the measurement's tolerance.
const COUNT_CYCLES: u64 = PRESCALE;
/// AVcc, the ADC reference, mV.
const AVCC_MV: u32 = 5_000;
/// Service step of the run loop: 1 ms of CPU time.
const SERVICE_CYCLES: u64 = 16_000;
/// The self-test runs about 4.5 s of CPU time; stop at 10 s whatever happens.
const MAX_CYCLES: u64 = 10 * F_CPU as u64;
/// The line after which the encoder pins are inputs, counting for 1 s.
const COUNTING_LINE: &str = "encoders: inputs, counting for 1000 ms";
/// Edges start this long after that line.
const EDGES_AFTER_S: f64 = 0.010;

fn selftest_elf() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("SUNTRACKER_EMU_ELF_SELFTEST_UNO") {
        return Some(PathBuf::from(p));
    }
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../target")));
    let p = target.join("avr-none/release/avr_board_selftest.elf");
    p.is_file().then_some(p)
}

/// One level change the harness makes on a PORTD pin.
#[derive(Debug, Clone, Copy)]
struct PinEdge {
    cycle: u64,
    bit: u8,
    high: bool,
}

/// The shaft motion of one encoder as constant-speed pieces; its edges on
/// pins (`a_bit`, `b_bit`) of PORTD from `start_cycle` on, and the count
/// the model gives at the end (the encoder starts at angle 0, levels 00).
fn encoder_edges(
    pieces: &[Segment],
    a_bit: u8,
    b_bit: u8,
    start_cycle: u64,
) -> (Vec<PinEdge>, i64) {
    let enc = QuadratureEncoder::ymt22();
    let mut levels = enc.levels_at(0.0);
    assert_eq!(levels, (false, false));
    let mut out = Vec::new();
    let mut angle_deg = 0.0;
    for piece in pieces {
        assert!((piece.angle0_deg - angle_deg).abs() < 1e-9, "pieces join");
        for (t_s, e) in enc.timed_edges(piece) {
            let cycle = start_cycle + (t_s * f64::from(F_CPU)).round() as u64;
            // One channel changes per edge.
            if e.a != levels.0 {
                out.push(PinEdge {
                    cycle,
                    bit: a_bit,
                    high: e.a,
                });
            }
            if e.b != levels.1 {
                out.push(PinEdge {
                    cycle,
                    bit: b_bit,
                    high: e.b,
                });
            }
            levels = (e.a, e.b);
        }
        angle_deg = piece.angle1_deg();
    }
    (out, enc.count_at(angle_deg))
}

/// A constant-speed piece from `t0_s` to `t1_s` starting at `angle0_deg`.
fn piece(t0_s: f64, t1_s: f64, angle0_deg: f64, speed_deg_s: f64) -> Segment {
    Segment {
        t0_s,
        t1_s,
        angle0_deg,
        speed_deg_s,
    }
}

/// The shaft motions: encoder C forward at the FS5106R's full speed, then
/// ten times faster; encoder A the same backward, its first piece half an
/// edge later so that the two encoders' edges interleave.
fn motions() -> (Vec<Segment>, Vec<Segment>) {
    let spec = ServoSpec::FS5106R_6V;
    let full_deg_s = spec.no_load_speed_deg_s(spec.max_pulse_us);
    assert!((full_deg_s - 570.0).abs() < 1e-9, "95 rpm = 570 °/s");
    let half_edge_s = 0.5 * 0.3 / full_deg_s;
    let c1 = piece(0.0, 0.2005, 0.0, full_deg_s);
    let c2 = piece(0.25, 0.30, c1.angle1_deg(), 10.0 * full_deg_s);
    let a1 = piece(half_edge_s, 0.1508, 0.0, -full_deg_s);
    let a2 = piece(0.25, 0.30, a1.angle1_deg(), -10.0 * full_deg_s);
    (vec![c1, c2], vec![a1, a2])
}

/// What a run of the self-test gave.
struct Outcome {
    /// Log lines with the cycle by which each was complete (1 ms steps).
    lines: Vec<(u64, String)>,
    /// Level transitions of PB1 (OC1A) and PB2 (OC1B): (cycle, high).
    oc1a: Vec<(u64, bool)>,
    oc1b: Vec<(u64, bool)>,
    /// Counts the model gives for the edges driven: (C, A).
    expected_counts: Option<(i64, i64)>,
    /// Edges driven per encoder, and the cycles of the first and last.
    edges: (usize, usize, u64, u64),
    cpu: CpuState,
}

impl Outcome {
    fn line(&self, prefix: &str) -> Option<&(u64, String)> {
        self.lines.iter().find(|(_, l)| l.starts_with(prefix))
    }
}

/// Keeps only the changes of level (simavr reports every drive of a pin).
fn transitions(raw: &[(u64, bool)]) -> Vec<(u64, bool)> {
    let mut level = false;
    let mut out = Vec::new();
    for &(cycle, high) in raw {
        if high != level {
            out.push((cycle, high));
            level = high;
        }
    }
    out
}

/// Pulses (rise cycle, width in cycles) of a pin's transitions.
fn pulses(transitions: &[(u64, bool)]) -> Vec<(u64, u64)> {
    transitions
        .windows(2)
        .filter(|w| w[0].1 && !w[1].1)
        .map(|w| (w[0].0, w[1].0 - w[0].0))
        .collect()
}

fn run(elf: &Path, adc0_mv: u32, drive_encoders: bool) -> Outcome {
    let mut sim = Sim::new("atmega328p", F_CPU, elf).unwrap();
    sim.attach_uart('0').unwrap();
    sim.watch_pin('B', 1).unwrap();
    sim.watch_pin('B', 2).unwrap();
    sim.set_avcc_mv(AVCC_MV);
    sim.set_adc_mv(0, adc0_mv);
    let mut log = LineAssembler::default();
    let mut out = Outcome {
        lines: Vec::new(),
        oc1a: Vec::new(),
        oc1b: Vec::new(),
        expected_counts: None,
        edges: (0, 0, 0, 0),
        cpu: CpuState::Running,
    };
    let mut raw_a = Vec::new();
    let mut raw_b = Vec::new();
    let mut schedule: Vec<PinEdge> = Vec::new();
    let mut next = 0usize;
    while sim.cycle() < MAX_CYCLES {
        let mut target = sim.cycle() + SERVICE_CYCLES;
        if let Some(e) = schedule.get(next) {
            target = target.min(e.cycle);
            sim.stop_at(e.cycle);
        }
        out.cpu = sim.run_until(target);
        while let Some(e) = schedule.get(next) {
            if e.cycle > sim.cycle() {
                break;
            }
            sim.set_pin('D', e.bit, e.high);
            next += 1;
        }
        raw_a.extend(sim.pin_changes('B', 1));
        raw_b.extend(sim.pin_changes('B', 2));
        let bytes = sim.uart_take('0');
        for line in log.push(&bytes) {
            if drive_encoders && line == COUNTING_LINE && schedule.is_empty() {
                let start = sim.cycle() + (EDGES_AFTER_S * f64::from(F_CPU)) as u64;
                let (c, a) = motions();
                let (c_edges, c_count) = encoder_edges(&c, 4, 5, start);
                let (a_edges, a_count) = encoder_edges(&a, 6, 7, start);
                out.expected_counts = Some((c_count, a_count));
                out.edges.0 = c_edges.len();
                out.edges.1 = a_edges.len();
                schedule = c_edges.into_iter().chain(a_edges).collect();
                schedule.sort_by_key(|e| e.cycle);
                out.edges.2 = schedule.first().map_or(0, |e| e.cycle);
                out.edges.3 = schedule.last().map_or(0, |e| e.cycle);
            }
            out.lines.push((sim.cycle(), line));
        }
        if out.cpu != CpuState::Running {
            break;
        }
    }
    assert_eq!(next, schedule.len(), "every edge driven");
    out.oc1a = transitions(&raw_a);
    out.oc1b = transitions(&raw_b);
    for (cycle, line) in &out.lines {
        println!("  {:>9.3} ms  {line}", *cycle as f64 / 16_000.0);
    }
    out
}

/// A number after `key` in `line`.
fn field(line: &str, key: &str) -> i64 {
    let rest = &line[line.find(key).unwrap_or_else(|| panic!("{key} in {line}")) + key.len()..];
    let end = rest
        .find(|c: char| !(c == '-' || c.is_ascii_digit()))
        .unwrap_or(rest.len());
    rest[..end].parse().unwrap()
}

/// Pulse width of a servo pulse in CPU cycles from the datasheet
/// arithmetic: duty = round(pulse · (TOP + 1) / 20,000 µs) counts,
/// OCR1x = duty − 1, high for OCR1x + 1 counts of 8 cycles.
fn expected_width_cycles(pulse_us: u64) -> (u64, u64) {
    let top_plus_1 = u64::from(F_CPU) / (PRESCALE * FRAME_HZ);
    assert_eq!(top_plus_1, 40_000);
    let frame_us = 1_000_000 / FRAME_HZ;
    let duty = (pulse_us * top_plus_1 + frame_us / 2) / frame_us;
    let ocr = duty - 1;
    ((ocr + 1) * PRESCALE, top_plus_1 * PRESCALE)
}

fn check_pulses(name: &str, trans: &[(u64, bool)], after_cycle: u64, pulse_us: u64) {
    let (width, frame) = expected_width_cycles(pulse_us);
    // The ideal pulse, µs × 16 cycles: the Timer1 arithmetic is exact here.
    assert_eq!(width, pulse_us * 16);
    let all = pulses(trans);
    let later: Vec<(u64, u64)> = all.iter().copied().filter(|p| p.0 > after_cycle).collect();
    assert!(later.len() >= 100, "{name}: {} pulses", later.len());
    let (min, max) = later
        .iter()
        .fold((u64::MAX, 0), |(lo, hi), p| (lo.min(p.1), hi.max(p.1)));
    println!(
        "{name}: {} pulses after the log line, width {:.4}–{:.4} µs (expected {pulse_us} µs ± 0.5)",
        later.len(),
        min as f64 / 16.0,
        max as f64 / 16.0
    );
    assert!(
        min + COUNT_CYCLES >= width && max <= width + COUNT_CYCLES,
        "{name}: widths {min}..{max} cycles, expected {width} ± {COUNT_CYCLES}"
    );
    // Sharper: simavr reports each edge after the instruction it falls in
    // (a few cycles late at most, either edge), so single widths scatter by
    // a cycle or two; their mean must be the exact width within 2 cycles,
    // a quarter of a count (one count more or less, OCR1x = duty or the
    // max duty TOP instead of TOP + 1 for long pulses, shifts it by 8).
    let mean = later.iter().map(|p| p.1 as f64).sum::<f64>() / later.len() as f64;
    println!("{name}: mean width {:.4} µs", mean / 16.0);
    assert!(
        (mean - width as f64).abs() <= 2.0,
        "{name}: mean width {mean} cycles, expected {width}"
    );
    let periods: Vec<u64> = later.windows(2).map(|w| w[1].0 - w[0].0).collect();
    let (pmin, pmax) = periods
        .iter()
        .fold((u64::MAX, 0), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    println!(
        "{name}: period {:.4}–{:.4} µs (expected 20,000)",
        pmin as f64 / 16.0,
        pmax as f64 / 16.0
    );
    assert!(
        pmin + COUNT_CYCLES >= frame && pmax <= frame + COUNT_CYCLES,
        "{name}: periods {pmin}..{pmax} cycles, expected {frame}"
    );
}

#[test]
fn uno_board_parts_pwm_adc_encoders() {
    let Some(elf) = selftest_elf() else {
        println!("skipped: avr_board_selftest.elf (ATmega328P) not built (SUNTRACKER_EMU_ELF_SELFTEST_UNO not set)");
        return;
    };
    // 3,300 mV: §24.7 gives floor(3300 · 1024 / 5000) = floor(675.84) = 675,
    // simavr floor(3300 · 1023 / 5000) = floor(675.18) = 675: the same.
    let adc0_mv = 3_300;
    let run = run(&elf, adc0_mv, true);
    // The program ran to its end (interrupts off, sleep).
    assert_eq!(run.cpu, CpuState::Done, "self-test did not end");
    assert_eq!(
        run.line("suntracker ").map(|l| l.1.as_str()),
        Some("suntracker 0.1.0 board selftest on atmega328p")
    );
    // Every self-checked line passed (the TWI line expects the NACK of a
    // bus with no device, as here).
    for (_, l) in &run.lines {
        assert!(!l.ends_with(" FAIL"), "{l}");
    }
    assert!(run.line("selftest done").is_some());

    // PWM.
    let (pwm_cycle, pwm_line) = run.line("pwm: ").expect("pwm line").clone();
    assert_eq!(
        pwm_line,
        "pwm: Timer1 TOP=39999 max_duty=40000 OC1A(PB1)=1500 us OC1B(PB2)=1750 us, out of range refused ok"
    );
    // A new compare value is in place from the next frame on (§15.9.3:
    // OCR1x is updated at BOTTOM): check the pulses that begin more than
    // a frame after the line.
    let after = pwm_cycle + u64::from(F_CPU) / FRAME_HZ;
    check_pulses("OC1A (PB1)", &run.oc1a, after, 1_500);
    check_pulses("OC1B (PB2)", &run.oc1b, after, 1_750);
    // Start-up: each pin's first level change is the rise of a whole pulse
    // (neutral 1,500 µs, or OC1B's 1,750 µs where simavr applies the new
    // compare value at once), no spike before it.
    for (name, trans, widths) in [
        ("OC1A", &run.oc1a, &[1_500u64][..]),
        ("OC1B", &run.oc1b, &[1_500, 1_750][..]),
    ] {
        assert!(trans[0].1, "{name}: first change is a rise");
        let first = pulses(trans)[0].1;
        assert!(
            widths
                .iter()
                .any(|&us| first.abs_diff(us * 16) <= COUNT_CYCLES),
            "{name}: first pulse {first} cycles"
        );
        println!(
            "{name}: first pulse at {:.3} ms, {:.4} µs",
            trans[0].0 as f64 / 16_000.0,
            first as f64 / 16.0
        );
    }

    // ADC.
    let (_, adc_line) = run.line("adc: ").expect("adc line");
    let code = field(adc_line, "code=");
    let datasheet = adc_code(f64::from(adc0_mv), f64::from(AVCC_MV));
    assert_eq!(datasheet, 675);
    assert_eq!(code, i64::from(datasheet), "{adc_line}");
    assert_eq!(code, i64::from(simavr_adc_code(adc0_mv, AVCC_MV)));
    println!("ADC0 at {adc0_mv} mV: code {code} (§24.7: {datasheet})");

    // Encoders: the self-driven check passed (no FAIL above), then the
    // harness's edges.
    let (c_count, a_count) = run.expected_counts.expect("counting line seen");
    let (_, enc_line) = run.line("encoders: after").expect("encoder counts");
    println!(
        "encoders: drove {} edges on C, {} on A over {:.1} ms; model counts C {c_count}, A {a_count}; {enc_line}",
        run.edges.0,
        run.edges.1,
        (run.edges.3 - run.edges.2) as f64 / 16_000.0
    );
    assert_eq!(c_count, run.edges.0 as i64, "C: forward, one count an edge");
    assert_eq!(a_count, -(run.edges.1 as i64), "A: backward");
    let logged: Vec<i64> = ["C count=", "A count="]
        .iter()
        .map(|k| field(enc_line, k))
        .collect();
    assert_eq!(logged, [c_count, a_count], "{enc_line}");
    assert_eq!(
        enc_line.matches("errors=0").count(),
        2,
        "no illegal transitions: {enc_line}"
    );
}

/// The PCINT2 vector's byte address on the ATmega328P (vector 5, 4 bytes
/// each; datasheet §11.1 "Interrupt Vectors in ATmega328P").
const PCINT2_VECTOR: u32 = 5 * 4;

/// Cycles of the PCINT2 handler in simavr for one pin change of `edges`:
/// from the handler's first instruction (the one after the vector's JMP)
/// to the end of its RETI (the stack pointer back where it was before the
/// interrupt). Steps one instruction at a time (`run_until(cycle + 1)`).
fn handler_cycles(sim: &mut Sim, edges: &[(u8, bool)]) -> u64 {
    let t = sim.cycle() + 50_000;
    sim.stop_at(t);
    sim.run_until(t);
    for &(bit, high) in edges {
        sim.set_pin('D', bit, high);
    }
    let mut vector_sp = None;
    let mut start = None;
    for _ in 0..10_000 {
        sim.run_until(sim.cycle() + 1);
        let (pc, sp) = sim.pc_sp();
        match (vector_sp, start) {
            // At the vector: the return address is on the stack.
            (None, _) if pc == PCINT2_VECTOR => vector_sp = Some(sp),
            (Some(_), None) => start = Some(sim.cycle()),
            (Some(v), Some(s)) if sp == v + 2 => return sim.cycle() - s,
            _ => {}
        }
    }
    panic!("PCINT2 handler not seen");
}

#[test]
fn encoder_handler_cycles_in_simavr() {
    let Some(elf) = selftest_elf() else {
        println!("skipped: avr_board_selftest.elf (ATmega328P) not built");
        return;
    };
    let mut sim = Sim::new("atmega328p", F_CPU, &elf).unwrap();
    sim.attach_uart('0').unwrap();
    let mut log = LineAssembler::default();
    let mut counting = false;
    while !counting && sim.cycle() < MAX_CYCLES {
        sim.run_until(sim.cycle() + SERVICE_CYCLES);
        counting = log
            .push(&sim.uart_take('0'))
            .iter()
            .any(|l| l == COUNTING_LINE);
    }
    assert!(counting);
    // From levels 00 on both: C forward (PD4 A rises), A backward (PD7 B
    // rises), then both at once (PD5, PD6: C forward, A backward).
    let c = handler_cycles(&mut sim, &[(4, true)]);
    let a = handler_cycles(&mut sim, &[(7, true)]);
    let both = handler_cycles(&mut sim, &[(5, true), (6, true)]);
    println!("PCINT2 handler in simavr: C edge {c} cycles, A edge {a}, both at once {both} (first instruction to return)");
    // The board layer's notes (boards/avr/src/lib.rs), counted by hand from
    // the disassembly: 202–204 cycles for one encoder's edge, 314–315 for
    // both; simavr charges the instruction set manual's cycles.
    assert!(c <= 204 && a <= 204, "one edge: C {c}, A {a} cycles");
    assert!(both <= 315, "both: {both} cycles");
    // And the counts moved: C +2, A −2 (levels now 11 and 11).
    let mut counted = false;
    while sim.cycle() < MAX_CYCLES && !counted {
        sim.run_until(sim.cycle() + SERVICE_CYCLES);
        for l in log.push(&sim.uart_take('0')) {
            if l.starts_with("encoders: after") {
                assert_eq!(
                    l,
                    "encoders: after 1000 ms C count=2 errors=0, A count=-2 errors=0"
                );
                counted = true;
            }
        }
    }
    assert!(counted);
}

#[test]
fn adc_code_is_simavrs_one_below_the_datasheet_at_2500_mv() {
    let Some(elf) = selftest_elf() else {
        println!("skipped: avr_board_selftest.elf (ATmega328P) not built");
        return;
    };
    // 2,500 mV: §24.7 floor(2500 · 1024 / 5000) = 512; simavr
    // floor(2500 · 1023 / 5000) = floor(511.5) = 511 (emu/README.md).
    let run = run(&elf, 2_500, false);
    let (_, adc_line) = run.line("adc: ").expect("adc line");
    let code = field(adc_line, "code=");
    assert_eq!(adc_code(2_500.0, f64::from(AVCC_MV)), 512);
    assert_eq!(code, i64::from(simavr_adc_code(2_500, AVCC_MV)));
    assert_eq!(code, 511, "{adc_line}");
    // Without edges from outside the counts stay 0.
    let (_, enc_line) = run.line("encoders: after").expect("encoder counts");
    assert_eq!(
        enc_line,
        "encoders: after 1000 ms C count=0 errors=0, A count=0 errors=0"
    );
}
