//! The Arduino Uno bench: the ATmega328P image (`avr_tracker`, board
//! module `boards/uno/src/lib.rs`, loop `src/servo_tracker/mod.rs`:
//! Chowdhury et al.'s (2019) closed-loop tracker) under simavr, with
//!
//! - a DS3231 model on the TWI (valid, lost power, or absent), or for the
//!   `ds1302` build ([`UnoBench::ds1302`]) a DS1302 model
//!   ([`crate::models::ds1302`]) on PC1 (CE), PC2 (I/O, open drain with a
//!   10 kΩ pull-up) and PC3 (SCLK): PORTC is watched like PORTB and PORTD
//!   (below), each write goes to the model at its cycle, and the bench drives
//!   PC2 with the line's level again before the next instruction, and at the
//!   cycle a data bit the chip outputs appears (tCDD after the falling edge);
//! - per axis a FEETECH FS5106R continuous-rotation servo model
//!   ([`crate::models::fs5106r`]) driven by the Timer1 pulses on its pin —
//!   servo C (azimuth) on OC1B = PB2, servo A (tilt) on OC1A = PB1 — turning
//!   a YMT22 quadrature encoder model ([`crate::models::quadrature`], 300
//!   lines, 1,200 counts a turn, on the output shaft: 0.3° a count) whose
//!   channels the bench drives on PD4/PD5 (encoder C, A/B) and PD6/PD7
//!   (encoder A), each edge at the CPU cycle the model gives for it;
//! - per axis a home switch following the model's shaft: closed (pin
//!   driven low; the image enables the pull-ups) at or below −180° (C, PB0)
//!   and −90° (A, PB4), and a hard stop 1° below the switch that holds the
//!   shaft;
//! - the panel voltage on ADC0 (PC0): the open-circuit voltage of the
//!   panel facing where the MODEL's shafts point ([`crate::models::panel`])
//!   against SPA's sun at the emulated UTC where the bench stands
//!   ([`UnoBench::site`], Kano by default), through the 10 kΩ/10 kΩ
//!   divider, AVcc 5,000 mV; set at every service step (at most 1 ms of CPU
//!   time, 60 emulated ms apart);
//! - the log read from USART0; bytes can be typed on its RX too
//!   ([`UnoBench::type_at`], [`UnoBench::bytes_at`]) for an image that
//!   reads a console there (`avr_tracker` reads none: its settings come
//!   from the EEPROM);
//! - the EEPROM loaded before the first instruction ([`UnoBench::eeprom`],
//!   as a programmer would; erased by default) and read back at the end
//!   ([`UnoRun::eeprom`]);
//! - power cuts ([`UnoBench::reset_at`]): the chip restarts with its RAM
//!   repainted and its EEPROM kept; the servos, encoders, switches and the
//!   DS3231 are outside the chip and keep their state (a shaft coasts out
//!   the last pulse's command, as the servo model does whenever its pulses
//!   stop, and the encoder counts it).
//!
//! The Uno's settings image (`avr_settings`: the configuration console
//! that writes the tracker's settings into the EEPROM) runs on the same
//! bench ([`UnoBench::settings`]), its clock at 1:1.
//!
//! Typing and power cuts are the Mega bench's ([`crate::script`]): same
//! pacing (simavr's USART at the baud rate the image set, never faster),
//! same lines in the run (`> LINE`, `> (N bytes)`, `# power cut`).
//!
//! **Two clocks.** The emulation build advances its millisecond clock by
//! the `timescale <N>` it logs at boot per 1 ms of CPU time
//! (`boards/avr/src/millis.rs`): emulated time = N × CPU time. The RTC
//! model, the sun, the panel, the schedule, the stall injection's start
//! and length, and every UTC in a run are emulated time. The servo physics
//! run in CPU time: the pulses are timed in CPU cycles by Timer1 (16 per
//! µs, 50 Hz frames), and the image's position loop runs once per Timer0
//! millisecond of CPU time, so a real servo turns in real time relative to
//! the loop that closes on its encoder. Seen on the emulated clock a move
//! is N times faster than on a board (the FS5106R's 570 °/s is 34,200
//! emulated °/s at 60×), and the firmware's monotonic durations (the 5 s
//! stall timeout, the 60 s retry) are N times shorter in servo time; the
//! loop's behaviour per frame, per count and per pulse is the board's. The
//! board build (the ELF a user flashes) logs no timescale and runs at N = 1
//! ([`crate::mega::timescale_of`] tells the builds apart by their flash):
//! there the two clocks are one, and every duration is the board's.
//!
//! **Pulses.** ATmega328P §15.9.3 ("Fast PWM Mode") and Table 15-5: in
//! mode 14 (TOP = ICR1) OCR1x is double-buffered and updated at BOTTOM, so
//! each frame's pulse is `OCR1x + 1` Timer1 counts from BOTTOM, with the
//! OCR1x value in force at BOTTOM. simavr 1.6 applies an OCR1x write at
//! once instead (`avr_timer_write_ocr` reconfigures the compare timer in
//! the middle of a frame), which on its pin makes extra short pulses and
//! frames without a falling edge whenever the image changes the speed
//! during or just after a pulse; no servo on a board sees those. So the
//! bench finds Timer1's BOTTOM from the first rising edge on PB1/PB2, stops
//! the CPU at every BOTTOM (`Sim::stop_at`), reads TCCR1A/TCCR1B/ICR1/
//! OCR1A/OCR1B from the data space and gives each servo the datasheet's
//! pulse: width `(OCR1x + 1) · 0.5 µs`, taken by the servo at its falling
//! edge (`BOTTOM + width`: a servo's pulse decoder knows the width then).
//! The pins are watched too, and the pulses simavr puts on them that do not
//! match a datasheet pulse are counted ([`UnoRun::pin_pulses_unlike_datasheet`]).
//! Knowing each frame's pulses at its BOTTOM, the bench computes the
//! servo's motion up to the next BOTTOM exactly (piecewise constant speed,
//! [`crate::models::fs5106r::Fs5106r::segments_to`]) and with it the time
//! of every encoder edge and switch change before the CPU gets there.
//!
//! **Pins the image pulls up.** simavr re-applies an input's pull-up on
//! every write to its port register (`avr_ioport_update_irqs`), including
//! the writes its own timer makes to drive OC1A/OC1B, which would override
//! a level the bench drives low. PORTB and PORTD are watched
//! (`Sim::watch_port`: `run_until` returns right after such a write) and
//! the bench drives its pins again before the next instruction.
//!
//! **Decoded pose.** Per axis: `angle = home angle + (model count − count
//! at which the switch closes, coming down) × 0.3°`, the model count being
//! the one on the pins. The encoder disc's phase to the switch is a bench
//! setting ([`UnoBench::encoder_phase_deg`], default half a count, so that
//! the switch closes in the middle of a count rather than on an edge).

use std::cell::RefCell;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::{Duration, Instant};

use drivers::encoder::QuadratureDecoder;
use sun_algos::{Algorithm, Options, Site, UtcTime};

use crate::log::{parse_line, Event, LineAssembler};
use crate::mega::{timescale_of, LogLine, Rtc, F_CPU, PAINT};
use crate::models::ds1302::{self, Ds1302};
use crate::models::ds3231::Ds3231;
use crate::models::fs5106r::{Fs5106r, Segment};
use crate::models::panel::{self, Divider, PvPanel, Sky};
use crate::models::quadrature::QuadratureEncoder;
use crate::script::Script;
use crate::sim::{CpuState, RamUse, Sim};
use crate::twi::{EmuClock, TwiBus};

/// First data-space address of the ATmega328P's RAM.
pub const RAM_START: u16 = 0x100;
/// Longest CPU-cycle step between two services of the log, the RTC's
/// clock, the panel voltage and the slot snapshots (1 ms of CPU time, 60
/// emulated ms at 60×).
pub const SERVICE_CYCLES: u64 = 16_000;
/// One Timer1 count at clk/8, µs: the servo signal's resolution.
pub const PULSE_STEP_US: f64 = 0.5;
/// Kano, Nigeria (the image's stored site, and where the bench stands by
/// default), degrees north.
pub const SITE_LAT_DEG: f64 = 11.9683;
/// The stored site's longitude, degrees east.
pub const SITE_LON_DEG: f64 = 8.4261;
/// The panel's ADC reference, AVcc, mV (an Uno's 5 V).
pub const AVCC_MV: u32 = 5_000;
/// ADC channel of the panel voltage (A0 = PC0).
pub const PANEL_CHANNEL: u8 = 0;
/// The C axis's home switch closes at or below this angle, degrees.
pub const SWITCH_C_DEG: f64 = -180.0;
/// The A axis's home switch closes at or below this angle, degrees.
pub const SWITCH_A_DEG: f64 = -90.0;
/// The hard stop sits this far below each switch, degrees.
pub const HARD_STOP_BELOW_DEG: f64 = 1.0;
/// Default power-on shaft angles (C, A), degrees.
pub const DEFAULT_START_DEG: (f64, f64) = (0.0, 20.0);
/// Default phase of each encoder disc at shaft angle 0: half a count of
/// the YMT22 (0.15°), so that each switch angle lies mid-count.
pub const DEFAULT_ENCODER_PHASE_DEG: f64 = 0.15;
/// The ATmega328P's EEPROM, bytes (datasheet §8.4).
pub const EEPROM_LEN: usize = 1024;
/// Set-point slot when the image's `config step_s=` line is not seen, s.
pub const DEFAULT_STEP_S: i64 = 240;

// ATmega328P data-space addresses of Timer1 (datasheet §36 "Register
// Summary"): TCCR1A, TCCR1B, ICR1L/H, OCR1AL/H, OCR1BL/H.
const TCCR1A: u16 = 0x80;
const TCCR1B: u16 = 0x81;
const ICR1L: u16 = 0x86;
const OCR1AL: u16 = 0x88;
const OCR1BL: u16 = 0x8A;
/// Timer1's prescaler when CS12:0 = 010 (clk/8).
const TIMER1_PRESCALE: u64 = 8;
// Port C (datasheet §36): PORTC; the DS1302's pins on it
// (`boards/uno/src/lib.rs`): CE PC1, I/O PC2, SCLK PC3.
const PORTC: u16 = 0x28;
const DS1302_CE: u8 = 1;
const DS1302_IO: u8 = 2;
const DS1302_SCLK: u8 = 3;

/// One of the two axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// C (azimuth): servo on OC1B = PB2, encoder PD4/PD5, switch PB0.
    C,
    /// A (tilt): servo on OC1A = PB1, encoder PD6/PD7, switch PB4.
    A,
}

impl Axis {
    fn index(self) -> usize {
        match self {
            Axis::C => 0,
            Axis::A => 1,
        }
    }
}

/// One servo pulse as the servo model got it (the datasheet's, see the
/// module notes), or one seen on the pin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pulse {
    /// CPU cycle of the rising edge (Timer1's BOTTOM).
    pub cycle: u64,
    /// Emulated UTC of the rising edge, Unix seconds.
    pub utc_s: f64,
    /// High time, µs.
    pub width_us: f64,
}

/// The decoded pose at the end of a set-point slot (just before the next
/// slot starts).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlotPose {
    /// The slot's start, Unix seconds (UTC, a multiple of the step).
    pub slot_utc_s: i64,
    /// Decoded C angle, degrees.
    pub c_deg: f64,
    /// Decoded A angle, degrees.
    pub a_deg: f64,
    /// The model's shaft angles then (C, A), degrees.
    pub shaft_deg: (f64, f64),
}

/// One sample of the panel model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PanelSample {
    /// Emulated UTC, Unix seconds.
    pub utc_s: f64,
    /// The modelled panel voltage (open circuit, before the divider), mV.
    pub panel_mv: f64,
}

/// A home switch changing state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchChange {
    /// Emulated UTC, Unix seconds.
    pub utc_s: f64,
    /// True when it closed (pin driven low).
    pub closed: bool,
}

/// What one axis's models did over a run.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisRecord {
    /// The model's shaft angle at the end, degrees.
    pub final_deg: f64,
    /// The decoded angle at the end, degrees.
    pub decoded_deg: f64,
    /// The model count on the pins at the end.
    pub count: i64,
    /// The count at which the switch closes coming down.
    pub switch_count: i64,
    /// Encoder edges driven on the pins.
    pub edges: u64,
    /// Edges that changed no channel or both (the model must give none).
    pub illegal_transitions: u64,
    /// Edges after which `drivers::encoder::QuadratureDecoder`, fed the
    /// levels on the pins, disagreed with the model's count.
    pub decoder_mismatches: u64,
    /// Times the shaft reached the hard stop.
    pub hard_stop_hits: u64,
    /// Switch changes.
    pub switch_changes: Vec<SwitchChange>,
    /// Every encoder edge: emulated UTC (Unix seconds) and the count after
    /// it.
    pub edge_log: Vec<(f64, i64)>,
    /// Pulses the servo got.
    pub pulses: Vec<Pulse>,
}

/// Builder and runner of the Uno bench.
#[derive(Debug, Clone)]
pub struct UnoBench {
    elf: PathBuf,
    start_unix_s: i64,
    rtc: Rtc,
    echo: bool,
    log_file: Option<PathBuf>,
    start_deg: (f64, f64),
    encoder_phase_deg: f64,
    /// (axis, from emulated UTC, for emulated seconds).
    stalls: Vec<(Axis, f64, f64)>,
    /// Where the bench stands (the panel model's sun): latitude, longitude.
    site: (f64, f64),
    /// Console input (USART0) and power cuts.
    script: Script,
    /// EEPROM contents from address 0 before the first instruction.
    eeprom: Option<Vec<u8>>,
    /// Emulated ms per CPU ms until the image logs `timescale <N>`;
    /// `None`: [`timescale_of`] the ELF.
    timescale: Option<f64>,
    /// Echo the decoded pose with each line (not for the settings image).
    show_pose: bool,
    /// A DS1302 on PC1–PC3 instead of the DS3231 (the `ds1302` build),
    /// held to this column of its AC timing.
    ds1302: Option<ds1302::Supply>,
}

/// The outcome of a Uno run.
#[derive(Debug, Clone)]
pub struct UnoRun {
    /// Log lines; `c_deg`/`a_deg` are the decoded pose when the line
    /// completed, `c_start_deg`/`a_start_deg` when its first bytes came.
    pub lines: Vec<LogLine>,
    /// The decoded pose at the end of every slot the run passed.
    pub slot_poses: Vec<SlotPose>,
    /// The C axis's models (index 0) and the A axis's (index 1).
    pub axes: [AxisRecord; 2],
    /// The panel model every emulated second.
    pub panel: Vec<PanelSample>,
    /// Pulses simavr put on PB2 and PB1 (C, A) whose rise or width is not
    /// one of the datasheet's pulses (within a Timer1 count): the cost of
    /// simavr's unbuffered OCR1x, see the module notes.
    pub pin_pulses_unlike_datasheet: (u64, u64),
    /// Pulses seen on PB2 and PB1 (C, A).
    pub pin_pulses: (u64, u64),
    /// The slot length the image stated (`config step_s=`), s.
    pub step_s: i64,
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
    /// The EEPROM at the end of the run ([`EEPROM_LEN`] bytes).
    pub eeprom: Vec<u8>,
    /// The clock chip at the end of the run (`None` when absent).
    pub rtc: Option<RtcEnd>,
    /// The DS1302 model at the end of the run, with every transfer it saw,
    /// the contentions on I/O and the timing it measured (`None` without
    /// one).
    pub ds1302: Option<Ds1302>,
}

/// The clock chip's model at the end of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RtcEnd {
    /// The time it shows, Unix seconds.
    pub unix_s: i64,
    /// Its lost-power flag (DS3231: OSF set, lost power and not set since;
    /// DS1302: CH set, the oscillator stopped).
    pub osf: bool,
    /// Times the image wrote its seconds register (set the time).
    pub time_writes: u32,
}

/// The image's `day_energy` against the bench's own integral.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyCheck {
    /// What the image logged, V·h.
    pub logged_vh: f64,
    /// The trapezoid rule over the panel model's per-second samples in
    /// `[from_utc_s, to_utc_s)`, V·h.
    pub model_vh: f64,
    /// Start of the span: the day's first set-point slot.
    pub from_utc_s: i64,
    /// End of the span: the start of the slot the `day_energy` line came
    /// in (the first night slot).
    pub to_utc_s: i64,
    /// Samples summed.
    pub samples: usize,
}

impl EnergyCheck {
    /// `logged / model − 1`.
    pub fn relative_error(&self) -> f64 {
        self.logged_vh / self.model_vh - 1.0
    }
}

impl UnoRun {
    /// The decoded pose at the end of the slot that starts at `slot_utc_s`.
    pub fn pose_at_slot_end(&self, slot_utc_s: i64) -> Option<(f64, f64)> {
        self.slot_poses
            .iter()
            .find(|p| p.slot_utc_s == slot_utc_s)
            .map(|p| (p.c_deg, p.a_deg))
    }

    /// The log as the image sent it, each `setpoint` line followed by the
    /// bench's `axes utc=<its utc> c=<deg> a=<deg>` line: the pose decoded
    /// from the encoder models at the end of that set-point's slot (4
    /// decimals; the shape of the QEMU board's `axes` lines, for
    /// `tests/expected/check_setpoints.py`). A set-point whose slot the run
    /// did not finish has none.
    pub fn log_with_axes(&self) -> String {
        let mut out = String::new();
        for l in &self.lines {
            out.push_str(&l.text);
            out.push('\n');
            if let Event::SetPoint { unix_s, .. } = l.event {
                if let Some((c, a)) = self.pose_at_slot_end(unix_s) {
                    out.push_str(&format!(
                        "axes utc={} c={c:.4} a={a:.4}\n",
                        crate::log::format_utc(unix_s)
                    ));
                }
            }
        }
        out
    }

    /// The first `day_energy vh=` line and the bench's trapezoid over the
    /// same daylight: from the first `setpoint` slot before that line to
    /// the start of the slot the line came in (the image sums the ticks
    /// whose slot has the sun up: from the first daylight slot's start to
    /// the first night slot's). The bench's samples are the panel model at
    /// each emulated second (not the ADC codes).
    pub fn energy_check(&self) -> Option<EnergyCheck> {
        let (i, line) = self
            .lines
            .iter()
            .enumerate()
            .find(|(_, l)| l.text.starts_with("day_energy "))?;
        let logged_vh: f64 = line.text.strip_prefix("day_energy vh=")?.parse().ok()?;
        let from_utc_s = self.lines[..i].iter().find_map(|l| match l.event {
            Event::SetPoint { unix_s, .. } => Some(unix_s),
            _ => None,
        })?;
        let to_utc_s = (line.utc_s.floor() as i64).div_euclid(self.step_s) * self.step_s;
        let samples: Vec<(f64, f64)> = self
            .panel
            .iter()
            .filter(|s| s.utc_s >= from_utc_s as f64 && s.utc_s < to_utc_s as f64)
            .map(|s| (s.utc_s, s.panel_mv / 1_000.0))
            .collect();
        Some(EnergyCheck {
            logged_vh,
            model_vh: panel::trapezoid_vh(&samples),
            from_utc_s,
            to_utc_s,
            samples: samples.len(),
        })
    }
}

/// The panel normal of pose (c, a) on the firmware's level mount, in
/// (west, south, up): `(sin c·sin a, −cos c·sin a, cos a)` (Choi et al.,
/// portable tracker, eq. 15–17 with the identity attitude, as
/// `src/servo_tracker/mod.rs` states it).
pub fn panel_normal(c_deg: f64, a_deg: f64) -> [f64; 3] {
    let (c, a) = (c_deg.to_radians(), a_deg.to_radians());
    [c.sin() * a.sin(), -c.cos() * a.sin(), a.cos()]
}

/// The direction of the sun at `zenith_deg`, `azimuth_deg` (east of
/// north) in (west, south, up).
pub fn sun_direction(zenith_deg: f64, azimuth_deg: f64) -> [f64; 3] {
    let (z, az) = (zenith_deg.to_radians(), azimuth_deg.to_radians());
    [-z.sin() * az.sin(), -z.sin() * az.cos(), z.cos()]
}

/// SPA (sun_algos, `f64`, geometric) at the image's default site, Kano:
/// (zenith, azimuth), degrees.
pub fn kano_spa(unix_s: f64) -> Option<(f64, f64)> {
    spa(SITE_LAT_DEG, SITE_LON_DEG, unix_s)
}

/// SPA (sun_algos, `f64`, geometric, no elevation) at `lat_deg` north,
/// `lon_deg` east, at the whole second of `unix_s`: (zenith, azimuth),
/// degrees. `None` for a site or time SPA refuses.
pub fn spa(lat_deg: f64, lon_deg: f64, unix_s: f64) -> Option<(f64, f64)> {
    let site = Site::new(lat_deg, lon_deg).ok()?;
    let whole = unix_s.floor();
    let t = UtcTime::from_unix_seconds(whole as i64).ok()?;
    let p = Algorithm::Spa
        .position(&t, &site, &Options::default())
        .ok()?;
    Some((p.zenith_deg, p.azimuth_deg))
}

/// What the bench puts on a pin.
#[derive(Debug, Clone, Copy, PartialEq)]
enum PinKind {
    /// The encoder's channels after an edge, and the count there.
    Edge { count: i64, a: bool, b: bool },
    /// The switch closes (true) or opens.
    Switch(bool),
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct PinEvent {
    cycle: u64,
    kind: PinKind,
}

/// One axis: servo, encoder, switch and hard stop, and what is on its pins.
struct AxisModel {
    servo: Fs5106r,
    encoder: QuadratureEncoder,
    switch_deg: f64,
    stop_deg: f64,
    /// PORTD bits of channels A and B, PORTB bit of the switch.
    bit_a: u8,
    bit_b: u8,
    bit_switch: u8,
    /// Stalls registered in the servo (CPU s), to register again when the
    /// model is rebuilt at the hard stop.
    stalls_cpu: Vec<(f64, f64)>,
    /// Stalls not yet registered: (emulated s since power-on, length).
    stalls_emu: Vec<(f64, f64)>,
    /// The motion from the last BOTTOM to the next.
    plan: Vec<Segment>,
    queue: VecDeque<PinEvent>,
    /// On the pins now.
    count: i64,
    levels: (bool, bool),
    closed: bool,
    decoder: QuadratureDecoder,
    start_count: i64,
    record: AxisRecord,
}

impl AxisModel {
    fn new(
        start_deg: f64,
        switch_deg: f64,
        phase_deg: f64,
        (bit_a, bit_b, bit_switch): (u8, u8, u8),
    ) -> Self {
        let stop_deg = switch_deg - HARD_STOP_BELOW_DEG;
        let start_deg = start_deg.max(stop_deg);
        let encoder = QuadratureEncoder::ymt22().with_offset_deg(phase_deg);
        let count = encoder.count_at(start_deg);
        let levels = encoder.levels_at(start_deg);
        // The count holding the angles just below the switch angle: the
        // one the shaft is in as the switch closes on the way down.
        let switch_count = encoder.count_at(switch_deg - 1e-9);
        AxisModel {
            servo: Fs5106r::at_6v(start_deg, 0.0),
            encoder,
            switch_deg,
            stop_deg,
            bit_a,
            bit_b,
            bit_switch,
            stalls_cpu: Vec::new(),
            stalls_emu: Vec::new(),
            plan: Vec::new(),
            queue: VecDeque::new(),
            count,
            levels,
            closed: start_deg <= switch_deg,
            decoder: QuadratureDecoder::new(levels.0, levels.1),
            start_count: count,
            record: AxisRecord {
                final_deg: start_deg,
                decoded_deg: f64::NAN,
                count,
                switch_count,
                edges: 0,
                illegal_transitions: 0,
                decoder_mismatches: 0,
                hard_stop_hits: 0,
                switch_changes: Vec::new(),
                edge_log: Vec::new(),
                pulses: Vec::new(),
            },
        }
    }

    /// The decoded angle of the count on the pins.
    fn decoded_deg(&self) -> f64 {
        self.switch_deg
            + (self.count - self.record.switch_count) as f64 * self.encoder.deg_per_count()
    }

    /// The shaft angle at CPU time `t_s` (within the current plan; its
    /// ends outside it).
    fn angle_at(&self, t_s: f64) -> f64 {
        match self.plan.iter().find(|g| t_s <= g.t1_s) {
            Some(g) => g.angle_at(t_s.max(g.t0_s)),
            None => self
                .plan
                .last()
                .map_or(self.servo.angle_deg(), |g| g.angle1_deg()),
        }
    }

    /// Drives the bench's pins with what it holds now.
    fn drive_port(&self, sim: &mut Sim, port: char) {
        match port {
            'D' => {
                sim.set_pin('D', self.bit_a, self.levels.0);
                sim.set_pin('D', self.bit_b, self.levels.1);
            }
            'B' => sim.set_pin('B', self.bit_switch, !self.closed),
            _ => {}
        }
    }

    /// Registers the stalls that start within an emulated minute of
    /// `emu_s` (the cycle → emulated time map is settled by then).
    fn register_stalls(&mut self, emu_s: f64, cpu_s: f64, scale: f64) {
        let mut i = 0;
        while i < self.stalls_emu.len() {
            let (from, len) = self.stalls_emu[i];
            if from - emu_s > 60.0 {
                i += 1;
                continue;
            }
            self.stalls_emu.swap_remove(i);
            let a = cpu_s + (from - emu_s) / scale;
            let b = a + len / scale;
            self.servo.add_stall(a, b);
            self.stalls_cpu.push((a, b));
        }
    }

    /// Moves the model on to CPU time `to_s`, turning its motion into pin
    /// events (timed at `F_CPU`) and holding the shaft at the hard stop.
    fn advance_plan(&mut self, to_s: f64) {
        let f = f64::from(F_CPU);
        let cycle = |t: f64| (t * f).round().max(0.0) as u64;
        for mut seg in self.servo.segments_to(to_s) {
            let mut hit = false;
            if seg.speed_deg_s < 0.0 && seg.angle1_deg() < self.stop_deg {
                let t_hit = if seg.angle0_deg <= self.stop_deg {
                    seg.t0_s
                } else {
                    seg.t0_s + (self.stop_deg - seg.angle0_deg) / seg.speed_deg_s
                };
                seg.t1_s = t_hit.clamp(seg.t0_s, seg.t1_s);
                hit = true;
            }
            let mut events: Vec<PinEvent> = self
                .encoder
                .timed_edges(&seg)
                .into_iter()
                .map(|(t, e)| PinEvent {
                    cycle: cycle(t),
                    kind: PinKind::Edge {
                        count: e.count,
                        a: e.a,
                        b: e.b,
                    },
                })
                .collect();
            let (a0, a1) = (seg.angle0_deg, seg.angle1_deg());
            if (a0 <= self.switch_deg) != (a1 <= self.switch_deg) && seg.speed_deg_s != 0.0 {
                let t =
                    (seg.t0_s + (self.switch_deg - a0) / seg.speed_deg_s).clamp(seg.t0_s, seg.t1_s);
                events.push(PinEvent {
                    cycle: cycle(t),
                    kind: PinKind::Switch(a1 <= self.switch_deg),
                });
                // Stable: a switch at an edge's cycle follows the edge.
                events.sort_by_key(|e| e.cycle);
            }
            self.queue.extend(events);
            self.plan.push(seg);
            if hit {
                // Held at the stop until a pulse says otherwise: the
                // command in force pushes down, and nothing changes it
                // before the next pulse (a fall at or after `to_s`).
                self.record.hard_stop_hits += 1;
                let t_hit = seg.t1_s;
                self.servo = Fs5106r::at_6v(self.stop_deg, t_hit);
                for &(a, b) in &self.stalls_cpu {
                    self.servo.add_stall(a, b);
                }
                if to_s > t_hit {
                    self.plan.push(Segment {
                        t0_s: t_hit,
                        t1_s: to_s,
                        angle0_deg: self.stop_deg,
                        speed_deg_s: 0.0,
                    });
                }
                break;
            }
        }
        self.servo.advance_to(to_s);
    }

    /// No pulse follows (Timer1 stopped: a power cut, or the image turned
    /// it off): the servo runs out the last pulse's command and stops
    /// (`Fs5106r`'s signal timeout). Plans the motion to that end.
    fn signal_lost(&mut self) {
        if let Some(end) = self.servo.command_end_s() {
            self.advance_plan(end);
        }
    }

    /// Puts one event on the pins.
    fn apply(&mut self, sim: &mut Sim, ev: PinEvent, utc_s: f64) {
        match ev.kind {
            PinKind::Edge { count, a, b } => {
                let changed = u8::from(a != self.levels.0) + u8::from(b != self.levels.1);
                if changed != 1 {
                    self.record.illegal_transitions += 1;
                }
                if a != self.levels.0 {
                    sim.set_pin('D', self.bit_a, a);
                }
                if b != self.levels.1 {
                    sim.set_pin('D', self.bit_b, b);
                }
                self.levels = (a, b);
                self.decoder.update(a, b);
                self.count = count;
                self.record.edges += 1;
                self.record.edge_log.push((utc_s, count));
                if self.start_count + i64::from(self.decoder.count()) != count {
                    self.record.decoder_mismatches += 1;
                }
            }
            PinKind::Switch(closed) => {
                sim.set_pin('B', self.bit_switch, !closed);
                self.closed = closed;
                self.record
                    .switch_changes
                    .push(SwitchChange { utc_s, closed });
            }
        }
    }
}

/// Prints a line of the run as `<utc> c=<deg> a=<deg> | <text>`, or
/// `<utc> | <text>` without the pose.
fn show(line: &LogLine, pose: bool) {
    let utc = crate::log::format_utc(line.utc_s.floor() as i64);
    if pose {
        println!(
            "{utc} c={:.3} a={:.3} | {}",
            line.c_deg, line.a_deg, line.text
        );
    } else {
        println!("{utc} | {}", line.text);
    }
}

/// Rising/falling edges of one servo pin into pulses.
#[derive(Debug, Default)]
struct PulseDecoder {
    rise: Option<u64>,
    pulses: Vec<(u64, u64)>,
}

impl PulseDecoder {
    fn observe(&mut self, cycle: u64, high: bool) {
        if high {
            if self.rise.is_none() {
                self.rise = Some(cycle);
            }
        } else if let Some(r) = self.rise.take() {
            self.pulses.push((r, cycle - r));
        }
    }

    /// The chip reset: a pulse in progress ended unseen (simavr drops
    /// the pin's level without telling its watchers).
    fn cut(&mut self) {
        self.rise = None;
    }
}

/// Pulses of `seen` (rise cycle, width in cycles) that match no pulse of
/// `datasheet` within a Timer1 count (8 cycles) of rise and width.
fn unlike(seen: &[(u64, u64)], datasheet: &[Pulse]) -> u64 {
    let tol = TIMER1_PRESCALE;
    let mut j = 0;
    let mut n = 0;
    for &(rise, width) in seen {
        while j < datasheet.len() && datasheet[j].cycle + tol < rise {
            j += 1;
        }
        let ok = datasheet.get(j).is_some_and(|p| {
            let w = (p.width_us / 1e6 * f64::from(F_CPU)).round() as u64;
            p.cycle.abs_diff(rise) <= tol && w.abs_diff(width) <= tol
        });
        if !ok {
            n += 1;
        }
    }
    n
}

/// Cycle → emulated time: `base_s + (cycle − base_cycle) / F_CPU × scale`.
#[derive(Debug, Clone, Copy)]
struct TimeMap {
    base_cycle: u64,
    base_s: f64,
    scale: f64,
}

impl TimeMap {
    fn emu_s(&self, cycle: u64) -> f64 {
        self.base_s + (cycle as f64 - self.base_cycle as f64) / f64::from(F_CPU) * self.scale
    }
}

/// Timer1 as the datasheet runs it, read at a BOTTOM: the frame and the
/// two pulses.
struct Frame {
    period_cycles: u64,
    /// (OC1A = servo A, OC1B = servo C) widths in cycles, `None` without a
    /// pulse (channel disconnected).
    widths: (Option<u64>, Option<u64>),
}

/// Reads Timer1's registers; `None` unless it runs in mode 14 at clk/8.
fn read_frame(sim: &Sim) -> Option<Frame> {
    let a = sim.peek(TCCR1A);
    let b = sim.peek(TCCR1B);
    let wgm = (a & 0b11) | ((b >> 1) & 0b1100);
    if wgm != 14 || b & 0b111 != 0b010 {
        return None;
    }
    let r16 = |lo: u16| u64::from(sim.peek(lo)) | u64::from(sim.peek(lo + 1)) << 8;
    let top = r16(ICR1L);
    let period_cycles = (top + 1) * TIMER1_PRESCALE;
    // COM1x = 10: clear on compare match, set at BOTTOM (Table 15-3).
    let width = |com: u8, ocr: u64| (com == 0b10).then(|| (ocr + 1).min(top + 1) * TIMER1_PRESCALE);
    Some(Frame {
        period_cycles,
        widths: (
            width((a >> 6) & 0b11, r16(OCR1AL)),
            width((a >> 4) & 0b11, r16(OCR1BL)),
        ),
    })
}

/// CPU time of `cycle`, ns.
fn cycle_ns(cycle: u64) -> f64 {
    cycle as f64 * (1e9 / f64::from(F_CPU))
}

/// The first cycle at or after CPU time `t_ns`.
fn ns_cycle(t_ns: f64) -> u64 {
    (t_ns * f64::from(F_CPU) / 1e9).ceil().max(0.0) as u64
}

/// The DS1302's side of port C: the MCU's pins as last seen and the
/// model (`None`: no chip fitted, the I/O line only pulled up).
struct Ds1302Port {
    pins: ds1302::Pins,
    chip: Option<Ds1302>,
}

impl Ds1302Port {
    fn line_high(&self) -> bool {
        ds1302::line_high(self.pins.io, self.chip.as_ref().and_then(Ds1302::driving))
    }

    /// What the image did on port C since the last service, in cycle
    /// order: `levels` (cycle, the port's levels: CE and SCLK are outputs,
    /// so their bits are the levels driven) and `ddr` (cycle, DDRC: PC2
    /// driven or released), with PC2's PORTC bit as it is now (0 for an
    /// open-drain pin; `run_until` returns after each watched change, so
    /// this is its value after the last one); then the data bit due by
    /// `now`. Drives PC2 with the line's level again (simavr keeps an
    /// input's PIN bit as last set, and an output's PORT value after a
    /// release).
    fn service(
        &mut self,
        sim: &mut Sim,
        levels: &[(u64, u8)],
        ddr: &[(u64, u8)],
        now: u64,
        emu_at: &dyn Fn(u64) -> f64,
    ) {
        let port_high = sim.peek(PORTC) & 1 << DS1302_IO != 0;
        let mut events: Vec<(u64, bool, u8)> = levels
            .iter()
            .map(|&(c, v)| (c, true, v))
            .chain(ddr.iter().map(|&(c, v)| (c, false, v)))
            .collect();
        events.sort_by_key(|e| e.0);
        for &(cycle, is_levels, value) in &events {
            if is_levels {
                self.pins.ce = value & 1 << DS1302_CE != 0;
                self.pins.sclk = value & 1 << DS1302_SCLK != 0;
            } else {
                self.pins.io.output = value & 1 << DS1302_IO != 0;
            }
            self.pins.io.high = port_high;
            if let Some(chip) = self.chip.as_mut() {
                chip.pins(cycle_ns(cycle), emu_at(cycle), self.pins);
            }
        }
        let before = self.line_high();
        if let Some(chip) = self.chip.as_mut() {
            chip.advance(cycle_ns(now));
        }
        if !events.is_empty() || self.line_high() != before {
            sim.set_pin('C', DS1302_IO, self.line_high());
        }
    }

    /// The MCU lost power: its pins float (CE and SCLK pulled down by the
    /// chip's 40 kΩ), the chip runs on its battery.
    fn mcu_reset(&mut self, sim: &mut Sim, now: u64, emu_s: f64) {
        self.pins = ds1302::Pins::default();
        if let Some(chip) = self.chip.as_mut() {
            chip.mcu_reset(cycle_ns(now), emu_s);
        }
        sim.set_pin('C', DS1302_IO, self.line_high());
    }
}

impl UnoBench {
    /// The ATmega328P image at `elf`; defaults: start 2026-06-21T05:00Z,
    /// RTC valid, shafts at C 0°, A 20°, encoder phase half a count, no
    /// stall, standing at Kano, nothing typed, no power cut.
    pub fn new(elf: impl AsRef<Path>) -> Self {
        UnoBench {
            elf: elf.as_ref().to_path_buf(),
            start_unix_s: crate::mega::DEFAULT_START,
            rtc: Rtc::Valid,
            echo: false,
            log_file: None,
            start_deg: DEFAULT_START_DEG,
            encoder_phase_deg: DEFAULT_ENCODER_PHASE_DEG,
            stalls: Vec::new(),
            site: (SITE_LAT_DEG, SITE_LON_DEG),
            script: Script::default(),
            eeprom: None,
            timescale: None,
            show_pose: true,
            ds1302: None,
        }
    }

    /// The image is a `ds1302` build (`build_avr_uno_ds1302_emu`): a DS1302
    /// on PC1–PC3 instead of the DS3231 (none on the TWI), in the state
    /// [`UnoBench::rtc`] says (valid: running at the start time, WP set;
    /// lost power: CH and WP set, 2000-01-01; absent: nothing drives I/O,
    /// which reads high), held to the 5 V column of its AC timing.
    pub fn ds1302(self) -> Self {
        self.ds1302_supply(ds1302::Supply::V5_0)
    }

    /// [`UnoBench::ds1302`] held to `supply`'s column of the AC timing.
    pub fn ds1302_supply(mut self, supply: ds1302::Supply) -> Self {
        self.ds1302 = Some(supply);
        self
    }

    /// The Uno's settings image (`avr_settings`: the configuration console
    /// on USART0 that writes the settings into the EEPROM) at `elf`: the
    /// same bench, with the clock at 1:1 (the image logs no `timescale`:
    /// emulated time is CPU time). It drives no servo; the models stand
    /// still.
    pub fn settings(elf: impl AsRef<Path>) -> Self {
        UnoBench {
            show_pose: false,
            ..Self::new(elf).timescale(1.0)
        }
    }

    /// Timescale to assume until the image logs `timescale <N>` (by
    /// default [`timescale_of`] the ELF: 60 for the tracker's emulation
    /// build, 1 for a board build).
    pub fn timescale(mut self, n: f64) -> Self {
        self.timescale = Some(n);
        self
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

    /// Shaft angles at power-on (C, A), degrees (not below the hard stops).
    pub fn start_angles(mut self, c_deg: f64, a_deg: f64) -> Self {
        self.start_deg = (c_deg, a_deg);
        self
    }

    /// Phase of both encoder discs: the disc angle at shaft angle 0,
    /// degrees (a count is 0.3°).
    pub fn encoder_phase_deg(mut self, deg: f64) -> Self {
        self.encoder_phase_deg = deg;
        self
    }

    /// Holds `axis`'s shaft from emulated UTC `from_unix_s` for
    /// `duration_s` emulated seconds (a jammed axis): the servo model's
    /// stall interval, whatever the pulses say.
    pub fn stall(mut self, axis: Axis, from_unix_s: f64, duration_s: f64) -> Self {
        self.stalls.push((axis, from_unix_s, duration_s));
        self
    }

    /// Where the bench stands: the sun the panel model sees is SPA's at
    /// `lat_deg` north, `lon_deg` east (Kano by default), whatever site the
    /// image is configured for.
    pub fn site(mut self, lat_deg: f64, lon_deg: f64) -> Self {
        self.site = (lat_deg, lon_deg);
        self
    }

    /// Types `line` (and an end of line, `\n`) on the console, USART0, at
    /// emulated `minute`; the run's lines show it as `> line` (see
    /// [`crate::script`] for the pacing).
    pub fn type_at(mut self, minute: f64, line: &str) -> Self {
        self.script.type_line(minute, line);
        self
    }

    /// Sends `bytes` as they are on the console at emulated `minute` (noise,
    /// a flood); the run's lines show `> (N bytes)`.
    pub fn bytes_at(mut self, minute: f64, bytes: Vec<u8>) -> Self {
        self.script.bytes(minute, bytes);
        self
    }

    /// Cuts the power at emulated `minute` and turns it on again
    /// ([`Sim::power_cycle`]: RAM repainted, EEPROM kept); the servos,
    /// encoders and switches keep their state, the DS3231 runs on its
    /// battery; the run's lines show `# power cut`. The image boots (and
    /// homes) again.
    pub fn reset_at(mut self, minute: f64) -> Self {
        self.script.reset(minute);
        self
    }

    /// The EEPROM holds `bytes` from address 0 at power-on (at most
    /// [`EEPROM_LEN`]; the rest erased, 0xFF), as after `avrdude -U
    /// eeprom:w:…` ([`crate::ihex::parse`] reads such a file). By default
    /// it is all erased. A power cut keeps what the image wrote since.
    pub fn eeprom(mut self, bytes: Vec<u8>) -> Self {
        self.eeprom = Some(bytes);
        self
    }

    /// Runs for `minutes` of emulated time.
    pub fn run_minutes(&self, minutes: f64) -> Result<UnoRun, String> {
        let wall_start = Instant::now();
        let mut sim = Sim::new("atmega328p", F_CPU, &self.elf)?;
        let (_, static_end) = crate::sim::static_ram(&self.elf)?;
        let ram_top = sim.ramend() + 1;
        sim.paint_ram(static_end, ram_top, PAINT);
        if let Some(bytes) = &self.eeprom {
            if bytes.len() > EEPROM_LEN {
                return Err(format!(
                    "EEPROM image of {} bytes: the ATmega328P has {EEPROM_LEN}",
                    bytes.len()
                ));
            }
            sim.write_eeprom(0, bytes)?;
        }
        sim.attach_uart('0')?;
        sim.watch_pin('B', 1)?;
        sim.watch_pin('B', 2)?;
        sim.watch_port('B')?;
        sim.watch_port('D')?;
        sim.set_avcc_mv(AVCC_MV);
        sim.set_adc_mv(PANEL_CHANNEL, 0);
        if std::env::var_os("SUNTRACKER_EMU_PROFILE").is_some() {
            sim.enable_profile();
        }

        let clock = EmuClock::new();
        let bus = Rc::new(RefCell::new(TwiBus::new(clock.clone())));
        let rtc = match (self.rtc, self.ds1302) {
            (_, Some(_)) | (Rtc::Absent, None) => None,
            (Rtc::Valid, None) => Some(Ds3231::running(self.start_unix_s)),
            (Rtc::LostPower, None) => Some(Ds3231::lost_power()),
        }
        .map(|d| Rc::new(RefCell::new(d)));
        let mut ds1302 = self.ds1302.map(|v| Ds1302Port {
            pins: ds1302::Pins::default(),
            chip: match self.rtc {
                Rtc::Valid => Some(Ds1302::running(self.start_unix_s).supply(v)),
                Rtc::LostPower => Some(Ds1302::lost_power().supply(v)),
                Rtc::Absent => None,
            },
        });
        if self.ds1302.is_some() {
            sim.watch_port('C')?;
            sim.watch_direction('C')?;
            sim.set_pin('C', DS1302_IO, true);
        }
        if let Some(r) = &rtc {
            bus.borrow_mut().attach(Box::new(r.clone()));
        }
        sim.attach_twi(bus.clone())?;

        let phase = self.encoder_phase_deg;
        let mut axes = [
            AxisModel::new(self.start_deg.0, SWITCH_C_DEG, phase, (4, 5, 0)),
            AxisModel::new(self.start_deg.1, SWITCH_A_DEG, phase, (6, 7, 4)),
        ];
        let start = self.start_unix_s as f64;
        for &(axis, from, len) in &self.stalls {
            axes[axis.index()].stalls_emu.push((from - start, len));
        }
        for ax in &axes {
            ax.drive_port(&mut sim, 'D');
            ax.drive_port(&mut sim, 'B');
        }

        // Emulated seconds = base_s + (cycle − base_cycle) / F_CPU × scale;
        // the scale changes once, when the image logs it.
        let f = f64::from(F_CPU);
        let mut scale = match self.timescale {
            Some(n) => n,
            None => timescale_of(&self.elf)?,
        };
        let (mut base_cycle, mut base_s) = (0u64, 0.0f64);
        let end_emu_s = minutes * 60.0;
        let mut step_s = DEFAULT_STEP_S;
        let mut next_bottom: Option<u64> = None;
        let mut seen_c = PulseDecoder::default();
        let mut seen_a = PulseDecoder::default();
        let mut log = LineAssembler::default();
        let mut lines = Vec::new();
        let mut line_start_pose = (f64::NAN, f64::NAN);
        let mut slot_poses = Vec::new();
        let mut next_slot_end: Option<i64> = None;
        let mut panel_samples = Vec::new();
        let mut last_sample_s: Option<i64> = None;
        let mut sun: Option<(i64, Option<(f64, f64)>)> = None;
        let panel_model = PvPanel::UXCELL_6V_065W;
        let divider = Divider::TEN_K_TEN_K;
        let mut cpu = CpuState::Running;
        let mut script = self.script.player();
        let site = self.site;
        loop {
            let now = sim.cycle();
            let map = TimeMap {
                base_cycle,
                base_s,
                scale,
            };
            let emu_at = |cycle: u64| map.emu_s(cycle);
            let now_emu = emu_at(now);
            let now_utc = start + now_emu;
            let t_cpu = now as f64 / f;

            // Servo pins: simavr's pulses (the first one syncs the frames).
            for (cycle, high) in sim.pin_changes('B', 2) {
                seen_c.observe(cycle, high);
                if high && next_bottom.is_none() {
                    next_bottom = Some(cycle);
                }
            }
            for (cycle, high) in sim.pin_changes('B', 1) {
                seen_a.observe(cycle, high);
                if high && next_bottom.is_none() {
                    next_bottom = Some(cycle);
                }
            }
            // The image wrote a port: drive the bench's pins again.
            for port in ['B', 'D'] {
                if !sim.port_changes(port).is_empty() {
                    for ax in &axes {
                        ax.drive_port(&mut sim, port);
                    }
                }
            }
            // Timer1's BOTTOM: this frame's pulses, the motion to the next.
            if let Some(b) = next_bottom.filter(|&b| b <= now) {
                match read_frame(&sim) {
                    Some(frame) => {
                        let t_b = b as f64 / f;
                        let t_next = (b + frame.period_cycles) as f64 / f;
                        let utc_b = start + emu_at(b);
                        let widths = [frame.widths.1, frame.widths.0];
                        for (ax, width) in axes.iter_mut().zip(widths) {
                            ax.register_stalls(now_emu, t_cpu, scale);
                            ax.plan.clear();
                            if let Some(w) = width {
                                let width_us = w as f64 * 1e6 / f;
                                let fall = t_b + w as f64 / f;
                                ax.advance_plan(fall);
                                ax.servo.pulse(fall, width_us);
                                ax.record.pulses.push(Pulse {
                                    cycle: b,
                                    utc_s: utc_b,
                                    width_us,
                                });
                            }
                            ax.advance_plan(t_next);
                        }
                        next_bottom = Some(b + frame.period_cycles);
                    }
                    // Timer1 stopped or set up otherwise: no pulses until
                    // a pin rises again.
                    None => {
                        next_bottom = None;
                        for ax in &mut axes {
                            ax.signal_lost();
                        }
                    }
                }
            }
            // The pin events that are due.
            loop {
                let (i, cycle) = match (axes[0].queue.front(), axes[1].queue.front()) {
                    (Some(c), Some(a)) if a.cycle < c.cycle => (1, a.cycle),
                    (Some(c), _) => (0, c.cycle),
                    (None, Some(a)) => (1, a.cycle),
                    (None, None) => break,
                };
                if cycle > now {
                    break;
                }
                let ev = axes[i].queue.pop_front().expect("front");
                let utc = start + emu_at(ev.cycle);
                axes[i].apply(&mut sim, ev, utc);
            }
            // The DS1302: the image's writes to PORTC, the bits it outputs.
            if let Some(ds) = ds1302.as_mut() {
                let levels = sim.port_changes('C');
                let ddr = sim.direction_changes('C');
                ds.service(&mut sim, &levels, &ddr, now, &emu_at);
            }

            // The log.
            let bytes = sim.uart_take('0');
            if !bytes.is_empty() {
                let pose = (axes[0].decoded_deg(), axes[1].decoded_deg());
                if !log.has_partial() {
                    line_start_pose = pose;
                }
                for text in log.push(&bytes) {
                    let event = parse_line(&text);
                    if let Event::Timescale(n) = event {
                        if n > 0.0 {
                            base_s = now_emu;
                            base_cycle = now;
                            scale = n;
                        }
                    }
                    if let Some(s) = text
                        .strip_prefix("config ")
                        .and_then(|r| r.split_whitespace().find_map(|w| w.strip_prefix("step_s=")))
                        .and_then(|v| v.parse::<i64>().ok())
                        .filter(|&s| s > 0)
                    {
                        step_s = s;
                    }
                    let line = LogLine {
                        utc_s: now_utc,
                        text,
                        event,
                        c_deg: pose.0,
                        a_deg: pose.1,
                        c_start_deg: line_start_pose.0,
                        a_start_deg: line_start_pose.1,
                    };
                    if self.echo {
                        show(&line, self.show_pose);
                    }
                    lines.push(line);
                    line_start_pose = pose;
                }
            }

            // Typed input and power cuts, after the image's lines so far.
            let due = script.service(&mut sim, now_emu, RAM_START, PAINT);
            if due.power_cut {
                if let Some(ds) = ds1302.as_mut() {
                    ds.mcu_reset(&mut sim, now, now_emu);
                }
                log = LineAssembler::default();
                next_bottom = None;
                seen_c.cut();
                seen_a.cut();
                for ax in &mut axes {
                    ax.signal_lost();
                    // The reset cleared PINB and PIND.
                    ax.drive_port(&mut sim, 'B');
                    ax.drive_port(&mut sim, 'D');
                }
            }
            for text in due.lines {
                let pose = (axes[0].decoded_deg(), axes[1].decoded_deg());
                let line = LogLine {
                    utc_s: now_utc,
                    event: parse_line(&text),
                    text,
                    c_deg: pose.0,
                    a_deg: pose.1,
                    c_start_deg: pose.0,
                    a_start_deg: pose.1,
                };
                if self.echo {
                    show(&line, self.show_pose);
                }
                lines.push(line);
            }

            // Slot ends: the decoded pose before the RTC shows the next
            // slot (the clock below is set after this).
            let utc_whole = now_utc.floor() as i64;
            let slot_end =
                *next_slot_end.get_or_insert_with(|| (utc_whole.div_euclid(step_s) + 1) * step_s);
            if utc_whole >= slot_end {
                slot_poses.push(SlotPose {
                    slot_utc_s: slot_end - step_s,
                    c_deg: axes[0].decoded_deg(),
                    a_deg: axes[1].decoded_deg(),
                    shaft_deg: (axes[0].angle_at(t_cpu), axes[1].angle_at(t_cpu)),
                });
                next_slot_end = Some((utc_whole.div_euclid(step_s) + 1) * step_s);
            }
            // The panel: the model's pose against the sun of this second.
            let sun_now = match sun {
                Some((s, z)) if s == utc_whole => z,
                _ => {
                    let z = spa(site.0, site.1, utc_whole as f64);
                    sun = Some((utc_whole, z));
                    z
                }
            };
            let panel_mv = sun_now.map_or(0.0, |(z, az)| {
                let n = panel_normal(axes[0].angle_at(t_cpu), axes[1].angle_at(t_cpu));
                let theta = panel::incidence_deg(n, sun_direction(z, az));
                panel::panel_mv(&panel_model, &Sky::STC_BEAM, theta, 90.0 - z)
            });
            sim.set_adc_mv(PANEL_CHANNEL, divider.pin_mv(panel_mv));
            if last_sample_s != Some(utc_whole) {
                last_sample_s = Some(utc_whole);
                panel_samples.push(PanelSample {
                    utc_s: now_utc,
                    panel_mv,
                });
            }
            clock.set_s(now_emu);

            if cpu != CpuState::Running {
                break;
            }
            if now_emu >= end_emu_s {
                break;
            }
            // On to the next thing that must happen at its cycle.
            let mut target = now + SERVICE_CYCLES;
            if let Some(b) = next_bottom {
                target = target.min(b);
            }
            for ax in &axes {
                if let Some(e) = ax.queue.front() {
                    target = target.min(e.cycle);
                }
            }
            let chip = ds1302.as_ref().and_then(|d| d.chip.as_ref());
            if let Some(t) = chip.and_then(Ds1302::next_change_ns) {
                target = target.min(ns_cycle(t));
            }
            let end_cycle = base_cycle as f64 + (end_emu_s - base_s) / scale * f;
            target = target.min(end_cycle.ceil().max(now as f64 + 1.0) as u64);
            sim.stop_at(target);
            cpu = sim.run_until(target.max(now + 1));
        }
        let emulated_s = TimeMap {
            base_cycle,
            base_s,
            scale,
        }
        .emu_s(sim.cycle());
        let t_end = sim.cycle() as f64 / f;
        if let Some(p) = sim.profile() {
            // Top addresses by cycles (the sleep is counted at the SLEEP's
            // address), for `avr-addr2line -f -e ELF`.
            let mut v: Vec<_> = p.iter().map(|(a, c)| (*c, *a)).collect();
            v.sort_unstable_by(|a, b| b.cmp(a));
            for (c, a) in v.iter().take(400) {
                eprintln!("profile {a:#x} {c}");
            }
        }
        let records = axes.map(|ax| {
            let mut r = ax.record.clone();
            r.final_deg = ax.angle_at(t_end);
            r.count = ax.count;
            r.decoded_deg = ax.decoded_deg();
            r
        });
        let pin_pulses_unlike_datasheet = (
            unlike(&seen_c.pulses, &records[0].pulses),
            unlike(&seen_a.pulses, &records[1].pulses),
        );
        let pin_pulses = (seen_c.pulses.len() as u64, seen_a.pulses.len() as u64);
        let run = UnoRun {
            lines,
            slot_poses,
            axes: records,
            panel: panel_samples,
            pin_pulses_unlike_datasheet,
            pin_pulses,
            step_s,
            start_unix_s: self.start_unix_s,
            emulated_s,
            timescale: scale,
            cycles: sim.cycle(),
            wall: wall_start.elapsed(),
            cpu,
            ram: RamUse::measure(&sim, RAM_START, static_end, PAINT),
            eeprom: sim.read_eeprom(0, EEPROM_LEN).unwrap_or_default(),
            rtc: rtc
                .map(|r| {
                    let r = r.borrow();
                    RtcEnd {
                        unix_s: r.unix_at(emulated_s),
                        osf: r.osf(),
                        time_writes: r.time_writes,
                    }
                })
                .or(ds1302
                    .as_ref()
                    .and_then(|d| d.chip.as_ref())
                    .map(|d| RtcEnd {
                        unix_s: d.unix_at(emulated_s),
                        osf: d.halted(),
                        time_writes: d.time_writes,
                    })),
            ds1302: ds1302.and_then(|d| d.chip),
        };
        if let Some(p) = &self.log_file {
            std::fs::write(p, run.log_with_axes()).map_err(|e| format!("{}: {e}", p.display()))?;
        }
        Ok(run)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::fs5106r::FRAME_S;

    #[test]
    fn normal_of_the_sun_branch_points_at_the_sun() {
        // c = 180° − azimuth, a = −zenith (the firmware's south branch)
        // and c = −azimuth, a = +zenith (north) both face the sun.
        for (z, az) in [(30.0, 100.0), (75.5, 250.0), (5.0, 180.0), (89.0, 85.0)] {
            let s = sun_direction(z, az);
            for (c, a) in [(180.0 - az, -z), (-az, z)] {
                let theta = panel::incidence_deg(panel_normal(c, a), s);
                assert!(theta < 1e-9, "z {z} az {az}: {theta}");
            }
        }
        // Flat faces up: the incidence is the zenith angle.
        let theta = panel::incidence_deg(panel_normal(37.0, 0.0), sun_direction(40.0, 123.0));
        assert!((theta - 40.0).abs() < 1e-9);
        // The same frame as the library's forward kinematics.
        let n = suntracker::attitude::MountAttitude::<f64>::level().normal_xyz(
            &suntracker::attitude::Pose {
                gamma_deg: 40.0,
                alpha_deg: -25.0,
            },
        );
        let m = panel_normal(40.0, -25.0);
        for k in 0..3 {
            assert!((n[k] - m[k]).abs() < 1e-12, "{n:?} {m:?}");
        }
    }

    #[test]
    fn plan_times_edges_and_the_switch_and_stops_at_the_hard_stop() {
        // C at −178°, full speed down (700 µs) from t = 0 for one frame
        // hold (60 ms): 570 °/s would take it 34°, the stop holds at −181°.
        let mut ax = AxisModel::new(-178.0, SWITCH_C_DEG, 0.15, (4, 5, 0));
        ax.servo.pulse(0.0, 700.0);
        ax.advance_plan(FRAME_S);
        assert_eq!(ax.record.hard_stop_hits, 1);
        assert!((ax.servo.angle_deg() - -181.0).abs() < 1e-12);
        assert!((ax.angle_at(FRAME_S) - -181.0).abs() < 1e-12);
        // Edges: from −178° (disc −177.85°: count −593) to −181° (disc
        // −180.85°: count −603), ten counts down; one switch closing at
        // −180° after 2°/570 °/s = 3.509 ms.
        let edges: Vec<_> = ax
            .queue
            .iter()
            .filter(|e| matches!(e.kind, PinKind::Edge { .. }))
            .collect();
        assert_eq!(edges.len(), 10);
        let switch: Vec<_> = ax
            .queue
            .iter()
            .filter_map(|e| match e.kind {
                PinKind::Switch(c) => Some((e.cycle, c)),
                _ => None,
            })
            .collect();
        let expect = (2.0 / 570.0 * 16e6_f64).round() as u64;
        assert_eq!(switch.len(), 1);
        assert!(switch[0].1);
        assert!(
            switch[0].0.abs_diff(expect) <= 1,
            "{} vs {expect}",
            switch[0].0
        );
        // The switch closes in count −600 (disc −179.85°), as the bench's
        // reference says.
        assert_eq!(ax.record.switch_count, -600);
        // The last edge enters count −603 at disc −180.6° (shaft −180.75°).
        match ax.queue.back().map(|e| e.kind) {
            Some(PinKind::Edge { count, .. }) => assert_eq!(count, -603),
            other => panic!("{other:?}"),
        }
        // Held: nothing more while the command still pushes down.
        ax.queue.clear();
        ax.plan.clear();
        ax.advance_plan(2.0 * FRAME_S);
        assert!(ax.queue.is_empty());
        assert!((ax.servo.angle_deg() - -181.0).abs() < 1e-12);
        // A pulse up moves it off the stop again.
        ax.servo.pulse(2.0 * FRAME_S, 2_300.0);
        ax.advance_plan(3.0 * FRAME_S);
        assert!(ax.servo.angle_deg() > -181.0 + 570.0 * 0.019);
    }

    #[test]
    fn datasheet_pulses_match_what_the_pin_showed() {
        let ds = [
            Pulse {
                cycle: 1_000,
                utc_s: 0.0,
                width_us: 1_500.0,
            },
            Pulse {
                cycle: 321_000,
                utc_s: 0.0,
                width_us: 1_520.0,
            },
        ];
        // Same rise and width (within 8 cycles): matched; a short extra
        // pulse and a long one (no fall in the frame): not.
        let seen = [(1_004, 24_000), (321_000, 24_320), (330_000, 3_000)];
        assert_eq!(unlike(&seen, &ds), 1);
        let seen = [(1_000, 24_000 + 320_000)];
        assert_eq!(unlike(&seen, &ds), 1);
    }
}
