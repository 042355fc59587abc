//! The Arduino Uno bench: the ATmega328P image (`avr_tracker`, board
//! module `src/board/uno.rs`) under simavr with a DS3231 model on the TWI,
//! the log read from USART0, and both servo signals decoded from their
//! pins: OC1A = PB1 (tilt servo A), OC1B = PB2 (azimuth servo C).
//!
//! Time: the emulation build advances its millisecond clock by the
//! `timescale <N>` it logs at boot per 1 ms of CPU time (see
//! `src/board/avr/clock.rs`); emulated time = N × CPU time. The servo
//! pulses come from Timer1, which runs in CPU time: their widths are
//! measured in CPU cycles (16 per µs), so they are the widths a real
//! servo would see.
//!
//! Servo model: a positional hobby servo, 500 µs at 0° to 2,500 µs at 180°
//! (the board module's stated convention); the pose is decoded as
//! `c = 90° − servo C angle`, `a = −servo A angle`.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::{Duration, Instant};

use crate::bench::{LogLine, Rtc, DEFAULT_TIMESCALE, F_CPU, PAINT};
use crate::log::{parse_line, Event, LineAssembler};
use crate::models::ds3231::Ds3231;
use crate::sim::{CpuState, RamUse, Sim};
use crate::twi::{EmuClock, TwiBus};

/// First data-space address of the ATmega328P's RAM.
pub const RAM_START: u16 = 0x100;
/// CPU cycles between two services of the models and the log (1 ms of CPU
/// time, 60 emulated ms at 60×).
pub const SERVICE_CYCLES: u64 = 16_000;
/// Servo pulse at 0°, µs.
pub const PULSE_MIN_US: f64 = 500.0;
/// Servo pulse per degree, µs.
pub const PULSE_PER_DEG_US: f64 = 2000.0 / 180.0;
/// One Timer1 count at clk/8, µs: the servo signal's resolution.
pub const PULSE_STEP_US: f64 = 0.5;
/// The servo frame (50 Hz), µs.
pub const FRAME_US: f64 = 20_000.0;

/// One servo pulse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pulse {
    /// CPU cycle of the rising edge.
    pub cycle: u64,
    /// Emulated UTC of the rising edge, Unix seconds.
    pub utc_s: f64,
    /// High time, µs.
    pub width_us: f64,
}

/// Servo angle (0–180°) of a pulse width.
pub fn servo_deg(width_us: f64) -> f64 {
    (width_us - PULSE_MIN_US) / PULSE_PER_DEG_US
}

/// The pose (c, a) the two servo pulses command.
pub fn pose_deg(width_c_us: f64, width_a_us: f64) -> (f64, f64) {
    (90.0 - servo_deg(width_c_us), -servo_deg(width_a_us))
}

/// Builder and runner of the Uno bench.
#[derive(Debug, Clone)]
pub struct UnoBench {
    elf: PathBuf,
    start_unix_s: i64,
    rtc: Rtc,
    echo: bool,
    log_file: Option<PathBuf>,
}

/// The outcome of a Uno run.
#[derive(Debug, Clone)]
pub struct UnoRun {
    /// Log lines; `c_deg`/`a_deg` are the pose of the last complete pulses
    /// when the line completed (the start fields the same).
    pub lines: Vec<LogLine>,
    /// Servo C (azimuth, PB2) pulses.
    pub pulses_c: Vec<Pulse>,
    /// Servo A (tilt, PB1) pulses.
    pub pulses_a: Vec<Pulse>,
    /// Emulated UTC at the start, Unix seconds.
    pub start_unix_s: i64,
    /// Emulated seconds the run covered.
    pub emulated_s: f64,
    /// Timescale the image logged (or the default).
    pub timescale: f64,
    /// CPU cycles simulated.
    pub cycles: u64,
    /// Wall-clock time of the run.
    pub wall: Duration,
    /// How the CPU ended: `Running` when the span was reached.
    pub cpu: CpuState,
    /// RAM: static, the stack's peak (painted and lowest SP), untouched.
    pub ram: RamUse,
}

impl UnoRun {
    /// The width of servo `pulses`' first pulse that starts more than one
    /// frame after `utc_s` (a new compare value takes effect at the next
    /// frame), µs.
    pub fn width_after(pulses: &[Pulse], utc_s: f64, timescale: f64) -> Option<f64> {
        let frame_s = FRAME_US * 1e-6 * timescale;
        pulses
            .iter()
            .find(|p| p.utc_s > utc_s + frame_s)
            .map(|p| p.width_us)
    }

    /// The log as the image sent it, each `setpoint` line followed by the
    /// bench's `axes utc=<its utc> c=<deg> a=<deg>` line: the pose the
    /// servo pulses command after it, decoded from the pins (4 decimals;
    /// the shape of the QEMU board's `axes` lines, for
    /// `tests/expected/check_setpoints.py`).
    pub fn log_with_axes(&self) -> String {
        let mut out = String::new();
        for l in &self.lines {
            out.push_str(&l.text);
            out.push('\n');
            if let Event::SetPoint { unix_s, .. } = l.event {
                if let Some((c, a)) = self.pose_after(l.utc_s) {
                    out.push_str(&format!(
                        "axes utc={} c={c:.4} a={a:.4}\n",
                        crate::log::format_utc(unix_s)
                    ));
                }
            }
        }
        out
    }

    /// The pose commanded after `utc_s` (see [`UnoRun::width_after`]).
    pub fn pose_after(&self, utc_s: f64) -> Option<(f64, f64)> {
        let c = Self::width_after(&self.pulses_c, utc_s, self.timescale)?;
        let a = Self::width_after(&self.pulses_a, utc_s, self.timescale)?;
        Some(pose_deg(c, a))
    }
}

/// Rising/falling edges of one servo signal into pulses.
#[derive(Debug, Default)]
struct PulseDecoder {
    rise: Option<u64>,
    pulses: Vec<Pulse>,
}

impl PulseDecoder {
    fn observe(&mut self, cycle: u64, high: bool, utc_at: impl Fn(u64) -> f64) {
        if high {
            if self.rise.is_none() {
                self.rise = Some(cycle);
            }
        } else if let Some(r) = self.rise.take() {
            self.pulses.push(Pulse {
                cycle: r,
                utc_s: utc_at(r),
                width_us: (cycle - r) as f64 * 1e6 / f64::from(F_CPU),
            });
        }
    }
    fn last_width(&self) -> f64 {
        self.pulses.last().map_or(f64::NAN, |p| p.width_us)
    }
}

impl UnoBench {
    /// The ATmega328P image at `elf`; defaults: start 2026-06-21T05:00Z,
    /// RTC valid.
    pub fn new(elf: impl AsRef<Path>) -> Self {
        UnoBench {
            elf: elf.as_ref().to_path_buf(),
            start_unix_s: crate::bench::DEFAULT_START,
            rtc: Rtc::Valid,
            echo: false,
            log_file: None,
        }
    }

    /// Emulated UTC at power-on, Unix seconds.
    pub fn start(mut self, unix_s: i64) -> Self {
        self.start_unix_s = unix_s;
        self
    }

    /// The DS3231's state.
    pub fn rtc(mut self, rtc: Rtc) -> Self {
        self.rtc = rtc;
        self
    }

    /// Print each log line to stdout as it completes.
    pub fn echo(mut self, on: bool) -> Self {
        self.echo = on;
        self
    }

    /// Write [`UnoRun::log_with_axes`] to a file at the end of the run.
    pub fn log_to(mut self, path: Option<PathBuf>) -> Self {
        self.log_file = path;
        self
    }

    /// Runs for `minutes` of emulated time.
    pub fn run_minutes(&self, minutes: f64) -> Result<UnoRun, String> {
        let wall_start = Instant::now();
        let mut sim = Sim::new("atmega328p", F_CPU, &self.elf)?;
        let (_, static_end) = crate::sim::static_ram(&self.elf)?;
        let ram_top = sim.ramend() + 1;
        sim.paint_ram(static_end, ram_top, PAINT);
        sim.attach_uart('0')?;
        sim.watch_pin('B', 1)?;
        sim.watch_pin('B', 2)?;

        let clock = EmuClock::new();
        let bus = Rc::new(RefCell::new(TwiBus::new(clock.clone())));
        let rtc = match self.rtc {
            Rtc::Valid => Some(Ds3231::running(self.start_unix_s)),
            Rtc::LostPower => Some(Ds3231::lost_power()),
            Rtc::Absent => None,
        };
        if let Some(r) = rtc {
            bus.borrow_mut().attach(Box::new(Rc::new(RefCell::new(r))));
        }
        sim.attach_twi(bus.clone())?;

        // Emulated seconds = base_s + (cycle − base_cycle) / F_CPU × scale;
        // the scale changes once, when the image logs it.
        let mut scale = DEFAULT_TIMESCALE;
        let (mut base_cycle, mut base_s) = (0u64, 0.0f64);
        let start = self.start_unix_s as f64;
        let end_emu_s = minutes * 60.0;
        let mut servo_c = PulseDecoder::default();
        let mut servo_a = PulseDecoder::default();
        let mut log = LineAssembler::default();
        let mut lines = Vec::new();
        let mut cpu;
        loop {
            let emu_at =
                |cycle: u64| base_s + (cycle - base_cycle) as f64 / f64::from(F_CPU) * scale;
            let now_emu = emu_at(sim.cycle());
            if now_emu >= end_emu_s {
                cpu = CpuState::Running;
                break;
            }
            clock.set_s(now_emu);
            cpu = sim.run_until(sim.cycle() + SERVICE_CYCLES);
            let utc_at = |cycle: u64| start + emu_at(cycle);
            for (cycle, high) in sim.pin_changes('B', 2) {
                servo_c.observe(cycle, high, utc_at);
            }
            for (cycle, high) in sim.pin_changes('B', 1) {
                servo_a.observe(cycle, high, utc_at);
            }
            let bytes = sim.uart_take('0');
            if !bytes.is_empty() {
                let t = emu_at(sim.cycle());
                let (c, a) = pose_deg(servo_c.last_width(), servo_a.last_width());
                for text in log.push(&bytes) {
                    let event = parse_line(&text);
                    if let Event::Timescale(n) = event {
                        if n > 0.0 {
                            base_s = t;
                            base_cycle = sim.cycle();
                            scale = n;
                        }
                    }
                    let line = LogLine {
                        utc_s: start + t,
                        text,
                        event,
                        c_deg: c,
                        a_deg: a,
                        c_start_deg: c,
                        a_start_deg: a,
                    };
                    if self.echo {
                        println!(
                            "{} c={c:.3} a={a:.3} | {}",
                            crate::log::format_utc(line.utc_s.floor() as i64),
                            line.text
                        );
                    }
                    lines.push(line);
                }
            }
            if cpu != CpuState::Running {
                break;
            }
        }
        let emulated_s = base_s + (sim.cycle() - base_cycle) as f64 / f64::from(F_CPU) * scale;
        let run = UnoRun {
            lines,
            pulses_c: servo_c.pulses,
            pulses_a: servo_a.pulses,
            start_unix_s: self.start_unix_s,
            emulated_s,
            timescale: scale,
            cycles: sim.cycle(),
            wall: wall_start.elapsed(),
            cpu,
            ram: RamUse::measure(&sim, RAM_START, static_end, PAINT),
        };
        if let Some(p) = &self.log_file {
            std::fs::write(p, run.log_with_axes()).map_err(|e| format!("{}: {e}", p.display()))?;
        }
        Ok(run)
    }
}
