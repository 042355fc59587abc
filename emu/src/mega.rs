//! The bench: one ATmega2560 image under simavr with every model attached,
//! run for a span of emulated time.
//!
//! Time compression: the emulation build of the image advances its Timer0
//! millisecond clock by `EMU_MS_PER_TICK` ms per Timer0 interrupt (one per
//! ms of CPU time) and logs `timescale <N>` at boot; emulated time =
//! N × CPU time (N = 60 until the line is seen). The board build (the ELF a
//! user flashes) advances it 1 ms per tick and logs no timescale: emulated
//! time is CPU time ([`timescale_of`] tells the two apart). Every model
//! runs on emulated time.
//!
//! Real time during motion: the image's 56 steps/s take one loop pass per
//! step, and under 60× the loop gets 1/60 of the CPU per emulated second
//! (16.7 Timer0 ticks): the axes would crawl. So the bench holds PL0 high
//! (the emulation build then advances its clock 1 ms per tick, see
//! `boards/avr/src/millis.rs`) while any coil is driven and for
//! [`REAL_TIME_HOLD_S`] after, and while a GPS epoch is on the wire (at 60×
//! its 145 ms would take 8.7 emulated s, and the image, which stamps a fix
//! when it decodes it, would see GPS time seconds late), and compresses
//! the rest of the day. Every switch of scale is a new segment of the
//! cycle → emulated-time map ([`Run::time_segments`]).
//!
//! Sampling: PORTA is watched through simavr's port IRQ, so the stepper
//! decoders see every single pin write (with its cycle). Switch levels,
//! the anemometer, the GPS queue and the log are serviced every
//! `SERVICE_CYCLES` CPU cycles (64 µs of CPU time, 3.84 ms emulated at
//! 60×) and at once after every PORTA write (so the switches follow the
//! decoded angle without delay).

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::{Duration, Instant};

use crate::log::{parse_line, Event, LineAssembler};
use crate::models::adxl345::Adxl345;
use crate::models::ds3231::Ds3231;
use crate::models::ibt2::DcAxisModel;
use crate::models::linear::{self, LinearAxisModel, LinearEvent, LinearFeedback};
use crate::models::modbus_master::{self, ModbusMaster, Step};
use crate::models::mount::{Field, Mount};
use crate::models::nmea::{GpsFeed, NmeaFeeder};
use crate::models::qmc5883l::Qmc5883l;
use crate::models::servo_axis::ServoAxisModel;
use crate::models::stepper::{AxisGeometry, IllegalStep, StepperDecoder};
use crate::models::wind::{Anemometer, WindProfile};
use crate::script::Script;
use crate::sim::{CpuState, RamUse, Sim};
use crate::twi::{EmuClock, TwiBus};

/// CPU clock of the Mega.
pub const F_CPU: u32 = 16_000_000;
/// CPU cycles between two services of the slow models.
pub const SERVICE_CYCLES: u64 = 1024;
/// Seconds a byte takes on the GPS port (10 bits at 9600 baud); epochs are
/// sent at real time, so this is emulated time too.
pub const GPS_BYTE_S: f64 = 10.0 / 9600.0;
/// Emulated seconds of real time kept after a GPS epoch's last byte.
pub const GPS_END_MARGIN_S: f64 = 0.05;
/// CPU cycles between two services of the slow models at real time (one
/// emulated ms; at 60× [`SERVICE_CYCLES`] is 3.84 emulated ms).
pub const REAL_TIME_SERVICE_CYCLES: u64 = 16_000;
/// With a servo axis ([`MegaBench::servo_a`]), a pass awake longer than
/// this (5 ms of CPU time) runs on at real time. The controller judges a
/// servo axis's stall at the first tick 500 ms after its command
/// (`suntracker::controller::STALL_MIN_WAIT_MS`), and the servo starts in
/// the pass after the tick that commands it: a tracking tick of 56 ms of
/// CPU counted at 60× is 3.4 emulated s, and the image then runs the next
/// tick straight after it, before the servo has had a frame. On a board
/// the tick takes its 56 ms. The first 5 ms of a pass are still
/// compressed (300 emulated ms at 60×), so that the many short passes
/// cost no more time than before.
pub const SERVO_AWAKE_REAL_CYCLES: u64 = 80_000;
/// Default timescale of an emulation build before the image says
/// otherwise.
pub const DEFAULT_TIMESCALE: f64 = 60.0;

/// The text an emulation build logs its timescale with
/// (`boards/mega2560/src/lib.rs`, `boards/uno/src/lib.rs`: `timescale <N>`,
/// behind `if MS_PER_TICK != 1`, a constant, so a board build's flash holds
/// no trace of it).
const TIMESCALE_TEXT: &[u8] = b"timescale ";

/// The timescale to assume for the image at `elf` until it logs one:
/// [`DEFAULT_TIMESCALE`] when the file holds the text `timescale ` (an
/// emulation build, `SUNTRACKER_EMU_MS_PER_TICK` set), else 1 (a board
/// build: 1 ms per Timer0 tick, emulated time = CPU time).
pub fn timescale_of(elf: &Path) -> Result<f64, String> {
    let bytes = std::fs::read(elf).map_err(|e| format!("{}: {e}", elf.display()))?;
    Ok(timescale_of_bytes(&bytes))
}

/// [`timescale_of`] an ELF's bytes.
pub fn timescale_of_bytes(elf: &[u8]) -> f64 {
    if elf
        .windows(TIMESCALE_TEXT.len())
        .any(|w| w == TIMESCALE_TEXT)
    {
        DEFAULT_TIMESCALE
    } else {
        1.0
    }
}
/// Emulated seconds the bench stays at real time after the last coil is
/// released (the tracker's moves come in bursts: homing, back-off, the
/// next set-point).
pub const REAL_TIME_HOLD_S: f64 = 2.0;
/// How far a paced run ([`MegaBench::modbus_pty`] with a client attached)
/// may run ahead of the wall clock before it sleeps.
pub const PACE_SLACK: Duration = Duration::from_millis(2);

/// One piece of the cycle → emulated-time map: from `cycle` on, emulated
/// time runs `timescale` × CPU time from `emu_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeSegment {
    /// First CPU cycle of the segment.
    pub cycle: u64,
    /// Emulated seconds since power-on at that cycle.
    pub emu_s: f64,
    /// Emulated ms per CPU ms in the segment.
    pub timescale: f64,
}

impl TimeSegment {
    /// Emulated seconds since power-on at `cycle` (at or after the start).
    pub fn emu_s_at(&self, cycle: u64) -> f64 {
        self.emu_s + cycle.saturating_sub(self.cycle) as f64 / f64::from(F_CPU) * self.timescale
    }
}

/// The state of the DS3231 at power-on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rtc {
    /// Kept time on its battery: shows the bench's start time, OSF clear.
    Valid,
    /// Lost power: OSF set, time 2000-01-01.
    LostPower,
    /// Not fitted (no device at 0x68).
    Absent,
}

/// A log line with the emulated time it completed at and the decoded axis
/// angles at that moment.
#[derive(Debug, Clone, PartialEq)]
pub struct LogLine {
    /// Emulated UTC, Unix seconds (fractional).
    pub utc_s: f64,
    /// The text.
    pub text: String,
    /// Parsed shape.
    pub event: Event,
    /// C axis angle when the line completed, degrees.
    pub c_deg: f64,
    /// A axis angle when the line completed, degrees.
    pub a_deg: f64,
    /// C axis angle when the line's first byte arrived, degrees.
    pub c_start_deg: f64,
    /// A axis angle when the line's first byte arrived, degrees.
    pub a_start_deg: f64,
}

impl LogLine {
    /// A line of the harness itself (`> typed`, `# power cut`, `# modbus
    /// …`) at `utc_s`, the axes at `(c, a)` degrees.
    fn harness(utc_s: f64, text: String, (c_deg, a_deg): (f64, f64)) -> Self {
        LogLine {
            utc_s,
            event: parse_line(&text),
            text,
            c_deg,
            a_deg,
            c_start_deg: c_deg,
            a_start_deg: a_deg,
        }
    }
}

/// A switch changing state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchEvent {
    /// Emulated UTC, Unix seconds.
    pub utc_s: f64,
    /// 0 C home (PC0), 1 A home (PC1), 2 C max (PC2), 3 A max (PC3).
    pub switch: usize,
    /// True when it closed (pin driven low).
    pub closed: bool,
}

/// One recorded axis motion sample (at the first write after a pause, and
/// when motion stops): emulated UTC and both angles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleSample {
    /// Emulated UTC, Unix seconds.
    pub utc_s: f64,
    /// C axis angle.
    pub c_deg: f64,
    /// A axis angle.
    pub a_deg: f64,
}

/// The outcome of a run.
#[derive(Debug, Clone)]
pub struct Run {
    /// Log lines.
    pub lines: Vec<LogLine>,
    /// Final C, A axis angles, degrees.
    pub final_angles: (f64, f64),
    /// Illegal coil sequences, per axis (C, A).
    pub illegal_steps: (Vec<IllegalStep>, Vec<IllegalStep>),
    /// Emulated UTC (Unix seconds) of every half-step each axis took (C,
    /// A): a coil change that moved the rotor.
    pub step_times: (Vec<f64>, Vec<f64>),
    /// Axis angles each time an axis's coil pattern changed after at least
    /// 1 emulated second without change, each time both bridges were
    /// released (a move ended), and every emulated minute.
    pub angle_trace: Vec<AngleSample>,
    /// Switch changes (the power-on levels are not listed).
    pub switch_events: Vec<SwitchEvent>,
    /// Minimum angles reached (C, A).
    pub min_angles: (f64, f64),
    /// Wall-clock time of the run.
    pub wall: Duration,
    /// CPU cycles simulated.
    pub cycles: u64,
    /// Compressed timescale (from the log, or the default).
    pub timescale: f64,
    /// Emulated seconds the run covered.
    pub emulated_s: f64,
    /// Emulated seconds spent at real time (motion).
    pub real_time_s: f64,
    /// The cycle → emulated-time map, in order.
    pub time_segments: Vec<TimeSegment>,
    /// Emulated UTC at the start, Unix seconds.
    pub start_unix_s: i64,
    /// How the CPU ended: `Running` when the span was reached.
    pub cpu: CpuState,
    /// Anemometer falling edges sent.
    pub wind_pulses: u64,
    /// GPS epochs sent.
    pub gps_epochs: u32,
    /// Times the firmware wrote the DS3231's seconds register.
    pub rtc_time_writes: u32,
    /// TWI transactions (START + address) per 7-bit address seen.
    pub twi_starts: Vec<(u8, u32)>,
    /// RAM: static, the stack's peak (painted and lowest SP), untouched.
    pub ram: RamUse,
    /// The Modbus master on USART2 after the run: its transactions, with
    /// what the pins did ([`MegaBench::modbus_at`]).
    pub modbus: ModbusMaster,
    /// With [`MegaBench::modbus_pty`]: emulated seconds run paced (a
    /// client attached), and the most the emulation fell behind the wall
    /// clock then (it is never ahead by more than [`PACE_SLACK`]).
    pub paced: Option<(f64, f64)>,
    /// The longest the CPU ran without sleeping (a loop pass with the
    /// interrupts inside it), CPU seconds at the part's 16 MHz, and the
    /// emulated UTC (Unix seconds) it ended at.
    pub longest_awake: Option<(f64, f64)>,
    /// Every pass awake longer than 10 ms of CPU time, in order: its CPU
    /// seconds and the emulated UTC it ended at.
    pub long_passes: Vec<(f64, f64)>,
    /// With [`MegaBench::dc_drives`]: the emulated UTC (Unix seconds) of
    /// each rise of a motor's current above [`DC_CURRENT_MARK_A`] (C, A;
    /// a linear A axis's ([`MegaBench::linear_a`]) above
    /// [`linear::CURRENT_MARK_A`]).
    pub current_rises: (Vec<f64>, Vec<f64>),
}

impl Run {
    /// Emulated seconds since power-on at CPU cycle `cycle`.
    pub fn emu_s_at(&self, cycle: u64) -> f64 {
        self.time_segments
            .iter()
            .rev()
            .find(|s| s.cycle <= cycle)
            .or(self.time_segments.first())
            .map_or(0.0, |s| s.emu_s_at(cycle))
    }

    /// Parsed events with their lines.
    pub fn events(&self) -> impl Iterator<Item = &LogLine> {
        self.lines.iter().filter(|l| l.event != Event::Other)
    }

    /// The modes logged, in order.
    pub fn modes(&self) -> Vec<(f64, String)> {
        self.lines
            .iter()
            .filter_map(|l| match &l.event {
                Event::Mode(m) => Some((l.utc_s, m.clone())),
                _ => None,
            })
            .collect()
    }
}

/// Prints a log line (`echo`) and writes it to the log file, each as
/// `<utc> c=<deg> a=<deg> | <text>`.
fn show_line(line: &LogLine, echo: bool, file: Option<&mut std::fs::File>) {
    if !echo && file.is_none() {
        return;
    }
    let s = format!(
        "{} c={:.3} a={:.3} | {}",
        crate::log::format_utc(line.utc_s.floor() as i64),
        line.c_deg,
        line.a_deg,
        line.text
    );
    if echo {
        println!("{s}");
    }
    if let Some(f) = file {
        use std::io::Write as _;
        let _ = writeln!(f, "{s}");
    }
}

/// Builder and runner.
#[derive(Debug, Clone)]
pub struct MegaBench {
    elf: PathBuf,
    start_unix_s: i64,
    rtc: Rtc,
    gps: GpsFeed,
    wind: WindProfile,
    mount: Mount,
    field: Field,
    power_on: (f64, f64),
    /// The C axis turns without end ([`MegaBench::continuous_c`]).
    continuous_c: bool,
    echo: bool,
    log_file: Option<PathBuf>,
    /// Timescale until the image logs one; `None`: [`timescale_of`] the ELF.
    timescale: Option<f64>,
    /// Console input (USART0) and power cuts.
    script: Script,
    /// The weather contacts (PC4 snow, PC5 hail, PC6 the plant's stow
    /// contact): from each emulated minute, closed (low) or open (high,
    /// the image's pull-up); open until told.
    contacts: Vec<(f64, Contact, bool)>,
    /// The motor supply on ADC0 behind the board's 100 kΩ / 10 kΩ
    /// divider, mV from each emulated minute (12,000 until told).
    supply: Vec<(f64, u32)>,
    /// The pyranometer on ADC1 (2 mV per W/m²), W/m² from each emulated
    /// minute (0 until told).
    irradiance: Vec<(f64, u32)>,
    /// A Modbus RTU master on USART2 ([`MegaBench::modbus_at`]).
    modbus: ModbusMaster,
    /// A pseudo-terminal bridged to USART2 ([`MegaBench::modbus_pty`]).
    modbus_pty: Option<PathBuf>,
    /// DC gear motors on IBT-2 bridges instead of steppers
    /// ([`MegaBench::dc_drives`]).
    dc: bool,
    /// Obstacles in a DC axis's way: from each emulated minute, axis (0 C,
    /// 1 A) and the angle it holds the axis at coming from below (`None`:
    /// gone).
    obstacles: Vec<(f64, usize, Option<f64>)>,
    /// The A axis a linear actuator ([`MegaBench::linear_a`]): its
    /// feedback and the rod's extension at power-on, mm.
    linear_a: Option<(LinearFeedback, f64)>,
    /// The A axis a servo on its encoder ([`MegaBench::servo_a`]): its
    /// gear, servo turns per axis turn.
    servo_a: Option<f64>,
}

/// The current the DC axes' rises are recorded above ([`Run::current_rises`]),
/// A: the `dc` image's obstruction limit (`boards/mega2560/src/dc.rs`,
/// 55 % of the motor's 5.5 A stall current at 12 V).
pub const DC_CURRENT_MARK_A: f64 = 3.0;

/// The board's supply divider (`boards/mega2560`'s `SUPPLY_ADC`): the pin
/// sees 10/110 of the supply.
fn supply_pin_mv(supply_mv: u32) -> u32 {
    supply_mv * 10 / 110
}

/// A weather contact of the ATmega2560 board (`boards/mega2560`'s pin
/// table).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Contact {
    /// The snow switch, PC4 (D33).
    Snow,
    /// The hail warning contact, PC5 (D32).
    Hail,
    /// The plant's stow contact, PC6 (D31).
    PlantStow,
}

impl Contact {
    /// Its bit of port C.
    fn bit(self) -> u8 {
        match self {
            Contact::Snow => 4,
            Contact::Hail => 5,
            Contact::PlantStow => 6,
        }
    }
}

/// The byte the free RAM is painted with before a run.
pub const PAINT: u8 = 0xA5;
/// First data-space address of the ATmega2560's RAM (after the I/O space).
pub const RAM_START: u16 = 0x200;

/// Default start: 2026-06-21T05:00:00Z.
pub const DEFAULT_START: i64 = 1_782_018_000;

impl MegaBench {
    /// The ATmega2560 image at `elf`, defaults: start 2026-06-21T05:00Z,
    /// RTC valid, GPS silent, calm, level north-facing mount, Kano field,
    /// power-on angles C = 30°, A = 20°.
    pub fn mega(elf: impl AsRef<Path>) -> Self {
        MegaBench {
            elf: elf.as_ref().to_path_buf(),
            start_unix_s: DEFAULT_START,
            rtc: Rtc::Valid,
            gps: GpsFeed::Silent,
            wind: WindProfile::calm(),
            mount: Mount::level(),
            field: Field::kano_2026(),
            power_on: (30.0, 20.0),
            continuous_c: false,
            echo: false,
            log_file: None,
            timescale: None,
            script: Script::default(),
            contacts: Vec::new(),
            supply: Vec::new(),
            irradiance: Vec::new(),
            modbus: ModbusMaster::default(),
            modbus_pty: None,
            dc: false,
            obstacles: Vec::new(),
            linear_a: None,
            servo_a: None,
        }
    }

    /// DC axes (`axis.X.drive` 2, the `dc` image's own): DC gear motors (slew drives) on IBT-2
    /// modules with Hall encoders ([`crate::models::ibt2`]), the switches
    /// where the steppers' are; no stepper decoding. The bench runs at real
    /// time while a motor is driven or turns (and [`REAL_TIME_HOLD_S`]
    /// after), stepping the motors every emulated ms and putting each Hall
    /// edge on port K at its cycle.
    pub fn dc_drives(mut self) -> Self {
        self.dc = true;
        self
    }

    /// Makes the A axis a LINAK LA12 linear actuator on its IBT-2
    /// module ([`crate::models::linear`]; implies [`MegaBench::dc_drives`],
    /// the C axis a DC gear motor): read by its potentiometer on ADC5
    /// ([`LinearFeedback::Pot`]) or its dual Hall pair on PK6/PK7
    /// ([`LinearFeedback::Hall`]), the home switch (PC1) closed at the
    /// retracted end, PC3 open; the rod at `start_extension_mm` (0..=100)
    /// at power-on (the A power-on angle is not used). The A angles the run
    /// reports are the mounting's (`sim::linear_drive::LA12_TILT_MOUNT`,
    /// −92.0° retracted … −6.13° extended). The run fails with an error
    /// when the extension is outside the stroke.
    pub fn linear_a(mut self, feedback: LinearFeedback, start_extension_mm: f64) -> Self {
        self.dc = true;
        self.linear_a = Some((feedback, start_extension_mm));
        self
    }

    /// Makes the A axis an FS5106R continuous servo on its YMT22 encoder
    /// ([`crate::models::servo_axis`]; implies [`MegaBench::dc_drives`],
    /// the C axis a DC gear motor): the servo on OC3C (D3) turning the
    /// axis through `gear`:1, the encoder on PK6/PK7, the home switch
    /// (PC1) closed at and below −90°, PC3 at and above +91°, a hard stop
    /// at −92°; at the A power-on angle. Obstacles are not modelled on it:
    /// the run fails with an error when one is set on the A axis, or when
    /// [`MegaBench::linear_a`] is set too.
    pub fn servo_a(mut self, gear: f64) -> Self {
        self.dc = true;
        self.servo_a = Some(gear);
        self
    }

    /// From emulated `minute`, an obstacle holds DC axis `axis` (0 C, 1 A)
    /// at `deg` when it comes from below; `None` takes it away. On a
    /// linear A axis ([`MegaBench::linear_a`]) it is an obstruction at the
    /// extension of that angle (the run fails with an error if it is
    /// outside the stroke's angles), in the rod's way once the rod has been
    /// at or below it.
    pub fn obstacle_at(mut self, minute: f64, axis: usize, deg: Option<f64>) -> Self {
        self.obstacles.push((minute, axis, deg));
        self.obstacles.sort_by(|a, b| a.0.total_cmp(&b.0));
        self
    }

    /// Puts `step` on the RS-485 bus (USART2, DE on PH3) at emulated
    /// `minute`, a Modbus RTU master's request (or noise), shown in the
    /// run's lines as `# modbus <label>` ([`ModbusMaster`]; the run's
    /// [`Run::modbus`] holds each transaction and what the pins did). The
    /// bench runs at real time from the request until the transaction is
    /// over.
    pub fn modbus_at(mut self, minute: f64, step: Step, label: &str) -> Self {
        self.modbus.at(minute, step, label);
        self
    }

    /// Bridges USART2 to a new pseudo-terminal linked at `path`
    /// ([`crate::pty::ModbusPty`]): what a client writes goes to the
    /// image's receiver, what the image sends to the client. While a client
    /// holds it open the bench runs at real time (an emulation build: PL0
    /// held high) and no faster than the wall clock.
    pub fn modbus_pty(mut self, path: PathBuf) -> Self {
        self.modbus_pty = Some(path);
        self
    }

    /// What the pyranometer reads from emulated `minute`, W/m² (the board's
    /// 2 mV per W/m² on ADC1).
    pub fn irradiance_at(mut self, minute: f64, w_m2: u32) -> Self {
        self.irradiance.push((minute, w_m2));
        self.irradiance.sort_by(|a, b| a.0.total_cmp(&b.0));
        self
    }

    /// The motor supply the board's divider sees, and the DC models'
    /// motors run on, from emulated `minute`,
    /// mV (0: the divider come loose, the ADC at its rail).
    pub fn supply_at(mut self, minute: f64, supply_mv: u32) -> Self {
        self.supply.push((minute, supply_mv));
        self.supply.sort_by(|a, b| a.0.total_cmp(&b.0));
        self
    }

    /// Closes (`true`: the pin low) or opens (`false`: high) a weather
    /// contact at emulated `minute`.
    pub fn contact_at(mut self, minute: f64, contact: Contact, closed: bool) -> Self {
        self.contacts.push((minute, contact, closed));
        self.contacts.sort_by(|a, b| a.0.total_cmp(&b.0));
        self
    }

    /// Types `line` (and an end of line) on the console, USART0, at
    /// emulated `minute`; the harness log shows it as `> line` (see
    /// [`crate::script`] for the pacing).
    pub fn type_at(mut self, minute: f64, line: &str) -> Self {
        self.script.type_line(minute, line);
        self
    }

    /// Sends `bytes` as they are on the console at emulated `minute` (noise,
    /// a flood); the harness log shows `> (N bytes)`.
    pub fn bytes_at(mut self, minute: f64, bytes: Vec<u8>) -> Self {
        self.script.bytes(minute, bytes);
        self
    }

    /// Cuts the power at emulated `minute` and turns it on again
    /// ([`Sim::power_cycle`]: the EEPROM keeps its contents, the DS3231
    /// runs on its battery, the axes stay where they are, the switches and
    /// the anemometer input are driven again); the harness log shows
    /// `# power cut`.
    pub fn reset_at(mut self, minute: f64) -> Self {
        self.script.reset(minute);
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

    /// The GPS feed.
    pub fn gps(mut self, feed: GpsFeed) -> Self {
        self.gps = feed;
        self
    }

    /// The wind.
    pub fn wind(mut self, profile: WindProfile) -> Self {
        self.wind = profile;
        self
    }

    /// The mount (see [`Mount::tilted`]).
    pub fn mount(mut self, tilt_deg: f64, heading_deg: f64) -> Self {
        self.mount = Mount::tilted(tilt_deg, heading_deg);
        self
    }

    /// The Earth's field at the tracker (the compass model's input; Kano's
    /// by default): where the tracker physically stands, whatever site its
    /// configuration names.
    pub fn field(mut self, field: Field) -> Self {
        self.field = field;
        self
    }

    /// A C axis that turns without end (a slip ring): no max-end switch,
    /// the home switch an index cam passed once a turn
    /// ([`AxisGeometry::c_axis_continuous`]).
    pub fn continuous_c(mut self) -> Self {
        self.continuous_c = true;
        self
    }

    /// Axis angles at power-on (C, A), degrees.
    pub fn power_on_angles(mut self, c_deg: f64, a_deg: f64) -> Self {
        self.power_on = (c_deg, a_deg);
        self
    }

    /// Timescale to assume until the image logs `timescale <N>` (by
    /// default [`timescale_of`] the ELF: 60 for an emulation build, 1 for a
    /// board build or the self-test).
    pub fn timescale(mut self, n: f64) -> Self {
        self.timescale = Some(n);
        self
    }

    /// Print each log line to stdout as it completes.
    pub fn echo(mut self, on: bool) -> Self {
        self.echo = on;
        self
    }

    /// Also write the log lines to a file.
    pub fn log_to(mut self, path: Option<PathBuf>) -> Self {
        self.log_file = path;
        self
    }

    /// Runs for `minutes` of emulated time.
    pub fn run_minutes(&self, minutes: f64) -> Result<Run, String> {
        let wall_start = Instant::now();
        let mut sim = Sim::new("atmega2560", F_CPU, &self.elf)?;
        // Stack painting: everything between the end of the static RAM and
        // RAMEND; what is left of the pattern at the end was never used.
        let (_, static_end) = crate::sim::static_ram(&self.elf)?;
        let ram_top = sim.ramend() + 1;
        sim.paint_ram(static_end, ram_top, PAINT);
        sim.attach_uart('0')?;
        sim.attach_uart('1')?;
        sim.attach_uart(modbus_master::UART)?;
        // The RS-485 port, when something is on the bus.
        let rs485 = !self.modbus.is_empty() || self.modbus_pty.is_some();
        if rs485 {
            sim.watch_pin(modbus_master::DE_PIN.0, modbus_master::DE_PIN.1)?;
            // TXC2 (UCSR2A bit 6) requested as the chip does when its
            // interrupt is enabled with the flag set (`Sim::fire_on_enable`).
            sim.fire_on_enable(modbus_master::UCSR2A, 6)?;
        }
        sim.watch_port('A')?;
        let mut master = self.modbus.clone();
        let mut pty = match &self.modbus_pty {
            Some(p) => Some(crate::pty::ModbusPty::open(p)?),
            None => None,
        };
        // While a client holds the terminal: (emulated s, wall instant)
        // when pacing began.
        let mut pace: Option<(f64, Instant)> = None;
        // Emulated s paced in earlier stretches, in this one; the most
        // behind the wall clock.
        let (mut paced_done_s, mut paced_s, mut behind_s) = (0.0f64, 0.0f64, 0.0f64);
        let mut shown_modbus = 0usize;
        if std::env::var_os("SUNTRACKER_EMU_PROFILE").is_some() {
            sim.enable_profile();
        }

        let clock = EmuClock::new();
        let bus = Rc::new(RefCell::new(TwiBus::new(clock.clone())));
        let rtc = match self.rtc {
            Rtc::Valid => Some(Ds3231::running(self.start_unix_s)),
            Rtc::LostPower => Some(Ds3231::lost_power()),
            Rtc::Absent => None,
        }
        .map(|d| Rc::new(RefCell::new(d)));
        if let Some(r) = &rtc {
            bus.borrow_mut().attach(Box::new(r.clone()));
        }
        bus.borrow_mut()
            .attach(Box::new(Qmc5883l::new(&self.mount, &self.field)));
        bus.borrow_mut().attach(Box::new(Adxl345::new(&self.mount)));
        sim.attach_twi(bus.clone())?;

        let c_geometry = if self.continuous_c {
            AxisGeometry::c_axis_continuous()
        } else {
            AxisGeometry::c_axis()
        };
        let mut c_axis = StepperDecoder::new(c_geometry, self.power_on.0);
        let mut a_axis = StepperDecoder::new(AxisGeometry::a_axis(), self.power_on.1);
        let mut dc = match (self.dc, self.linear_a, self.servo_a) {
            (false, _, _) => None,
            (true, None, Some(gear)) => {
                let mut c = DcAxisModel::c_axis(self.power_on.0);
                c.current_mark_a = DC_CURRENT_MARK_A;
                let a = ServoAxisModel::a_axis(self.power_on.1, gear);
                Some([BridgeAxis::Dc(c), BridgeAxis::Servo(a)])
            }
            (true, None, None) => Some(
                [
                    DcAxisModel::c_axis(self.power_on.0),
                    DcAxisModel::a_axis(self.power_on.1),
                ]
                .map(|mut m| {
                    m.current_mark_a = DC_CURRENT_MARK_A;
                    BridgeAxis::Dc(m)
                }),
            ),
            (true, Some(_), Some(_)) => {
                return Err("the A axis is a linear actuator or a servo, not both".into())
            }
            (true, Some((feedback, start_mm)), None) => {
                let mut c = DcAxisModel::c_axis(self.power_on.0);
                c.current_mark_a = DC_CURRENT_MARK_A;
                let mut a = LinearAxisModel::a_axis(feedback, start_mm)
                    .map_err(|e| format!("linear A axis: {e}"))?;
                a.current_mark_a = linear::CURRENT_MARK_A;
                Some([BridgeAxis::Dc(c), BridgeAxis::Linear(a)])
            }
        };
        // The obstacles, on a linear A axis at the extension of their
        // angle; none on a servo axis, whose model has no load.
        if self.servo_a.is_some() && self.obstacles.iter().any(|&(_, axis, _)| axis == 1) {
            return Err("an obstacle on the servo A axis: not modelled".into());
        }
        let obstacles = match &dc {
            Some([_, BridgeAxis::Linear(a)]) => self
                .obstacles
                .iter()
                .map(|&(minute, axis, deg)| match (axis, deg) {
                    (1, Some(deg)) => a
                        .extension_at_deg(deg)
                        .map(|mm| (minute, axis, Some(mm)))
                        .map_err(|e| format!("obstacle at minute {minute}, linear A axis: {e}")),
                    _ => Ok((minute, axis, deg)),
                })
                .collect::<Result<Vec<_>, String>>()?,
            _ => self.obstacles.clone(),
        };
        // The axes' angles: the DC models' or the decoded steppers'.
        macro_rules! angles {
            () => {
                match &dc {
                    Some([c, a]) => (c.angle_deg(), a.angle_deg()),
                    None => (c_axis.angle_deg(), a_axis.angle_deg()),
                }
            };
        }
        // The DC axes' Hall levels: driven at power-on and after a reset.
        let mut hall_driven = false;
        let mut timescale = match self.timescale {
            Some(n) => n,
            None => timescale_of(&self.elf)?,
        };
        let mut gps = NmeaFeeder::new(self.gps.clone(), self.start_unix_s, GPS_BYTE_S);
        let mut wind = Anemometer::new(self.wind.clone());
        let mut log = LineAssembler::default();
        let mut lines = Vec::new();
        let mut trace = Vec::new();
        let mut step_times: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        let mut log_file = match &self.log_file {
            Some(p) => Some(std::fs::File::create(p).map_err(|e| format!("{}: {e}", p.display()))?),
            None => None,
        };

        // Emulated seconds since power-on at a CPU cycle: piecewise, a new
        // segment when the image tells its timescale and at every switch
        // to and from real time.
        let mut segments = vec![TimeSegment {
            cycle: 0,
            emu_s: 0.0,
            timescale,
        }];
        let mut compressed = timescale;
        let mut real_time = false;
        // The cycle the bench last switched to real time.
        let mut real_since = 0u64;
        let mut real_time_s = 0.0;
        let mut coils = 0u8;
        let mut coils_off_emu = 0.0f64;
        // When the GPS epoch on the wire ends. An epoch is sent at real
        // time (its 139 bytes take 145 ms at 9600 baud): under 60× they
        // would take 8.7 emulated s, and a loop pass that ran long would
        // then decode the RMC seconds after its instant, all of it inside
        // the image's 1.5 s freshness window.
        let mut gps_end_utc = f64::NEG_INFINITY;
        sim.set_pin('L', 0, false);

        let end_emu_s = minutes * 60.0;
        let mut switches = [None::<bool>; 4];
        let mut contacts = [None::<bool>; 3];
        let mut supply_pin = None::<u32>;
        let mut irradiance_pin = None::<u32>;
        sim.set_avcc_mv(5_000);
        let mut switch_events = Vec::new();
        let mut line_start = None::<(f64, f64)>;
        let mut wind_level = None::<bool>;
        let mut last_change_emu = [f64::NEG_INFINITY; 2];
        let mut last_trace_min = -1i64;
        let mut min_angles = angles!();
        let mut cpu = CpuState::Running;
        let mut script = self.script.player();
        loop {
            let now_cycle = sim.cycle();
            let now_emu = segments[segments.len() - 1].emu_s_at(now_cycle);
            if now_emu >= end_emu_s {
                break;
            }
            clock.set_s(now_emu);
            let utc = self.start_unix_s as f64 + now_emu;
            // Lines of the harness itself (typed input, power cuts), shown
            // in the log in order with the image's.
            let due = script.service(&mut sim, now_emu, RAM_START, PAINT);
            if due.power_cut {
                log = LineAssembler::default();
                line_start = None;
                // The bridges' inputs fall with the chip, and the image
                // that boots knows nothing of the rotors' phases.
                c_axis.power_cut(now_cycle);
                a_axis.power_cut(now_cycle);
                if coils != 0 {
                    coils = 0;
                    coils_off_emu = now_emu;
                }
                // The reset cleared the PINx registers: drive the switch,
                // anemometer and real-time levels again.
                switches = [None; 4];
                contacts = [None; 3];
                hall_driven = false;
                supply_pin = None;
                irradiance_pin = None;
                sim.set_pin('L', 0, real_time);
                if let Some(l) = wind_level {
                    sim.set_pin('E', 4, l);
                }
            }
            for text in due.lines {
                let line = LogLine::harness(utc, text, angles!());
                show_line(&line, self.echo, log_file.as_mut());
                lines.push(line);
            }

            // Switches from the decoded angles: PC0 C home, PC1 A home,
            // PC2 C max, PC3 A max; active low.
            let levels = match &dc {
                Some([c, a]) => [
                    !c.home_closed(),
                    !a.home_closed(),
                    !c.max_closed(),
                    !a.max_closed(),
                ],
                None => [
                    !c_axis.home_closed(),
                    !a_axis.home_closed(),
                    !c_axis.max_closed(),
                    !a_axis.max_closed(),
                ],
            };
            for (i, l) in levels.iter().enumerate() {
                if switches[i] != Some(*l) {
                    if switches[i].is_some() {
                        switch_events.push(SwitchEvent {
                            utc_s: utc,
                            switch: i,
                            closed: !*l,
                        });
                    }
                    sim.set_pin('C', i as u8, *l);
                    switches[i] = Some(*l);
                }
            }
            if wind_level.is_none() {
                sim.set_pin('E', 4, true);
                wind_level = Some(true);
            }
            // The supply: its latest scheduled level, 12 V before any.
            let supply_mv = self
                .supply
                .iter()
                .rfind(|(m, _)| now_emu >= m * 60.0)
                .map_or(12_000, |(_, mv)| *mv);
            if supply_pin != Some(supply_pin_mv(supply_mv)) {
                sim.set_adc_mv(0, supply_pin_mv(supply_mv));
                supply_pin = Some(supply_pin_mv(supply_mv));
                // The DC motors run on the supply the divider measures (a
                // divider come loose leaves them theirs).
                if let (Some(models), true) = (dc.as_mut(), supply_mv > 0) {
                    for m in models.iter_mut() {
                        m.set_supply_v(f64::from(supply_mv) / 1_000.0);
                    }
                }
            }
            let w_m2 = self
                .irradiance
                .iter()
                .rfind(|(m, _)| now_emu >= m * 60.0)
                .map_or(0, |(_, w)| *w);
            if irradiance_pin != Some(w_m2 * 2) {
                sim.set_adc_mv(1, w_m2 * 2);
                irradiance_pin = Some(w_m2 * 2);
            }
            // The weather contacts: each at its latest scheduled level
            // (open before any), driven when it changes or after a reset.
            for (i, c) in [Contact::Snow, Contact::Hail, Contact::PlantStow]
                .into_iter()
                .enumerate()
            {
                let closed = self
                    .contacts
                    .iter()
                    .rfind(|(m, k, _)| *k == c && now_emu >= m * 60.0)
                    .is_some_and(|(_, _, closed)| *closed);
                if contacts[i] != Some(closed) {
                    sim.set_pin('C', c.bit(), !closed);
                    contacts[i] = Some(closed);
                }
            }
            if let Some(l) = wind.advance(utc) {
                sim.set_pin('E', 4, l);
                wind_level = Some(l);
            }
            if let Some(text) = gps.poll(utc, sim.uart_pending('1') == 0) {
                gps_end_utc = utc + text.len() as f64 * GPS_BYTE_S;
                sim.uart_send('1', text.as_bytes());
            }

            // Bytes still queued: they reach simavr's 64-byte receive FIFO
            // only as it empties, so the epoch ends at least a FIFO's worth
            // of bytes (67 ms) after the queue is empty.
            if sim.uart_pending('1') > 0 {
                gps_end_utc = gps_end_utc.max(utc + 64.0 * GPS_BYTE_S);
            }
            // The DC axes: their bridges as the registers set them, the
            // obstacles, the Hall levels (a linear axis's Hall levels or
            // wiper); "coils" while a motor is driven or turns.
            let dc_outputs = dc.as_mut().map(|models| {
                for (k, m) in models.iter_mut().enumerate() {
                    let obstacle = obstacles
                        .iter()
                        .rfind(|(min, ax, _)| *ax == k && now_emu >= min * 60.0)
                        .and_then(|(_, _, at)| *at);
                    m.set_obstacle(obstacle);
                    if !hall_driven {
                        m.drive_inputs(&mut sim);
                    }
                }
                hall_driven = true;
                let outputs = [models[0].output(&sim), models[1].output(&sim)];
                let active = models[0].active(outputs[0]) || models[1].active(outputs[1]);
                if active {
                    coils = 1;
                } else if coils != 0 {
                    coils = 0;
                    coils_off_emu = now_emu;
                    trace.push(AngleSample {
                        utc_s: utc,
                        c_deg: models[0].angle_deg(),
                        a_deg: models[1].angle_deg(),
                    });
                }
                (outputs, active)
            });
            // Real time while a coil is driven and REAL_TIME_HOLD_S after,
            // and while a GPS epoch is on the wire.
            let attached = pty.as_mut().is_some_and(|p| p.attached());
            // With a servo axis, also while a pass has been awake longer
            // than SERVO_AWAKE_REAL_CYCLES (see the constant).
            let long_pass = self.servo_a.is_some()
                && sim
                    .awake_since()
                    .is_some_and(|from| now_cycle.saturating_sub(from) > SERVO_AWAKE_REAL_CYCLES);
            let want_real = coils != 0
                || now_emu - coils_off_emu < REAL_TIME_HOLD_S
                || utc < gps_end_utc + GPS_END_MARGIN_S
                || master.wants_real_time(now_emu)
                || attached
                || long_pass;
            if want_real != real_time && compressed > 1.0 {
                real_time = want_real;
                if real_time {
                    real_time_s -= now_emu;
                } else {
                    real_time_s += now_emu;
                }
                timescale = if real_time { 1.0 } else { compressed };
                real_since = now_cycle;
                segments.push(TimeSegment {
                    cycle: now_cycle,
                    emu_s: now_emu,
                    timescale,
                });
                sim.set_pin('L', 0, real_time);
            }

            // At real time the models are serviced every REAL_TIME_SERVICE_CYCLES
            // (1 emulated ms; PORTA writes still stop the run at once).
            let span = if real_time {
                REAL_TIME_SERVICE_CYCLES
            } else {
                SERVICE_CYCLES
            };
            cpu = match (dc.as_mut(), dc_outputs) {
                (Some(models), Some((outputs, true))) if timescale <= 1.0 => {
                    run_dc_span(&mut sim, models, outputs, now_cycle, span)
                }
                _ => sim.run_until(now_cycle + span),
            };
            let after_emu = segments[segments.len() - 1].emu_s_at(sim.cycle());
            if let Some(p) = pty.as_mut() {
                // The bridge: the client's bytes to USART2 as they come
                // (a request is one write), the image's back.
                p.pass(&mut sim);
                // Paced: never ahead of the wall clock since pacing began.
                match (attached, pace) {
                    (true, None) => pace = Some((after_emu, Instant::now())),
                    (true, Some((emu0, wall0))) => {
                        let due = wall0 + Duration::from_secs_f64((after_emu - emu0).max(0.0));
                        let now = Instant::now();
                        if due > now + PACE_SLACK {
                            std::thread::sleep(due - now);
                        } else if now > due {
                            behind_s = behind_s.max((now - due).as_secs_f64());
                        }
                        paced_s = after_emu - emu0;
                    }
                    (false, Some(_)) => {
                        paced_done_s += paced_s;
                        paced_s = 0.0;
                        pace = None;
                    }
                    (false, None) => {}
                }
                if crate::pty::stop_requested() {
                    break;
                }
            } else if rs485 {
                let real_for = if compressed <= 1.0 {
                    Some(u64::MAX)
                } else if real_time {
                    Some(sim.cycle().saturating_sub(real_since))
                } else {
                    None
                };
                master.service(&mut sim, after_emu, real_for);
                // The harness's own lines: each transaction when it ends.
                for t in &master.transactions[shown_modbus..] {
                    let line = LogLine::harness(
                        self.start_unix_s as f64 + after_emu,
                        format!("# modbus {}", t.summary()),
                        angles!(),
                    );
                    show_line(&line, self.echo, log_file.as_mut());
                    lines.push(line);
                }
                shown_modbus = master.transactions.len();
            }
            let port_a = sim.port_changes('A');
            if let Some(models) = &dc {
                min_angles.0 = min_angles.0.min(models[0].angle_deg());
                min_angles.1 = min_angles.1.min(models[1].angle_deg());
            }
            for (cycle, value) in port_a.into_iter().filter(|_| dc.is_none()) {
                let t = segments[segments.len() - 1].emu_s_at(cycle);
                for (k, (axis, bits)) in [(&mut c_axis, value & 0x0F), (&mut a_axis, value >> 4)]
                    .into_iter()
                    .enumerate()
                {
                    let before = axis.half_steps();
                    axis.observe(cycle, bits);
                    if axis.half_steps() != before {
                        step_times[k].push(self.start_unix_s as f64 + t);
                        if t - last_change_emu[k] > 1.0 {
                            trace.push(AngleSample {
                                utc_s: self.start_unix_s as f64 + t,
                                c_deg: f64::NAN,
                                a_deg: f64::NAN,
                            });
                        }
                        last_change_emu[k] = t;
                    }
                }
                if let Some(s) = trace.last_mut() {
                    if s.c_deg.is_nan() {
                        s.c_deg = c_axis.angle_deg();
                        s.a_deg = a_axis.angle_deg();
                    }
                }
                min_angles.0 = min_angles.0.min(c_axis.angle_deg());
                min_angles.1 = min_angles.1.min(a_axis.angle_deg());
                if value != 0 {
                    coils = value;
                } else if coils != 0 {
                    // Both bridges released: the move has ended here.
                    coils = 0;
                    coils_off_emu = t;
                    trace.push(AngleSample {
                        utc_s: self.start_unix_s as f64 + t,
                        c_deg: c_axis.angle_deg(),
                        a_deg: a_axis.angle_deg(),
                    });
                }
            }
            let minute = (now_emu / 60.0) as i64;
            if minute != last_trace_min {
                last_trace_min = minute;
                let (c_deg, a_deg) = angles!();
                trace.push(AngleSample {
                    utc_s: utc,
                    c_deg,
                    a_deg,
                });
            }

            let bytes = sim.uart_take('0');
            if !bytes.is_empty() {
                let start_angles = line_start.unwrap_or(angles!());
                let t = segments[segments.len() - 1].emu_s_at(sim.cycle());
                for text in log.push(&bytes) {
                    let event = parse_line(&text);
                    if let Event::Timescale(n) = event {
                        if n > 0.0 && n != compressed {
                            compressed = n;
                            if !real_time {
                                timescale = n;
                                segments.push(TimeSegment {
                                    cycle: sim.cycle(),
                                    emu_s: t,
                                    timescale,
                                });
                            }
                        }
                    }
                    let st = line_start.take().unwrap_or(start_angles);
                    let line = LogLine {
                        utc_s: self.start_unix_s as f64 + t,
                        text,
                        event,
                        c_deg: angles!().0,
                        a_deg: angles!().1,
                        c_start_deg: st.0,
                        a_start_deg: st.1,
                    };
                    show_line(&line, self.echo, log_file.as_mut());
                    lines.push(line);
                }
                // A partial line is left: it started in this batch.
                if log.has_partial() && line_start.is_none() {
                    line_start = Some(start_angles);
                }
            }
            if cpu != CpuState::Running {
                break;
            }
        }
        let twi_starts = bus
            .borrow()
            .starts
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
            .map(|(a, n)| (a as u8, *n))
            .collect();
        if std::env::var_os("SUNTRACKER_EMU_PC").is_some() {
            let (pc, sp) = sim.pc_sp();
            eprintln!(
                "suntracker-emu: pc {pc:#x} sp {sp:#x}; lowest sp {:#x} at pc {:#x}",
                sim.min_sp(),
                sim.min_sp_pc()
            );
            // Every 3-byte window of the stack at that point read as a
            // return address (a `call` on the ATmega2560 pushes the word
            // address's 22 bits high byte deepest): those in flash, as byte
            // addresses, for `avr-addr2line -f -e ELF`.
            if let Some(stack) = sim.min_sp_stack() {
                let mut found = Vec::new();
                for (i, w) in stack.windows(3).enumerate() {
                    let word = u32::from(w[0]) << 16 | u32::from(w[1]) << 8 | u32::from(w[2]);
                    if word != 0 && word < 0x20000 {
                        found.push(format!("+{i}:{:#x}", word * 2));
                    }
                }
                eprintln!(
                    "suntracker-emu: stack return address candidates {}",
                    found.join(" ")
                );
            }
        }
        if let Some(p) = sim.profile() {
            // Top addresses by cycles, for `avr-addr2line -f -e ELF`.
            let mut v: Vec<_> = p.iter().map(|(a, c)| (*c, *a)).collect();
            v.sort_unstable_by(|a, b| b.cmp(a));
            for (c, a) in v.iter().take(400) {
                eprintln!("profile {a:#x} {c}");
            }
        }
        let pass = |(cycles, end): (u64, u64)| {
            let at = segments
                .iter()
                .rev()
                .find(|s| s.cycle <= end)
                .map_or(0.0, |s| s.emu_s_at(end));
            (
                cycles as f64 / f64::from(F_CPU),
                self.start_unix_s as f64 + at,
            )
        };
        let longest_awake = sim.longest_awake().map(pass);
        let rises = |k: usize| -> Vec<f64> {
            dc.as_ref().map_or_else(Vec::new, |m| {
                m[k].crossings()
                    .iter()
                    .map(|&c| {
                        let at = segments
                            .iter()
                            .rev()
                            .find(|s| s.cycle <= c)
                            .map_or(0.0, |s| s.emu_s_at(c));
                        self.start_unix_s as f64 + at
                    })
                    .collect()
            })
        };
        let current_rises = (rises(0), rises(1));
        let long_passes = sim.long_awake().iter().copied().map(pass).collect();
        Ok(Run {
            ram: RamUse::measure(&sim, RAM_START, static_end, PAINT),
            lines,
            final_angles: angles!(),
            illegal_steps: (c_axis.illegal.clone(), a_axis.illegal.clone()),
            step_times: (
                std::mem::take(&mut step_times[0]),
                std::mem::take(&mut step_times[1]),
            ),
            switch_events,
            angle_trace: trace,
            min_angles,
            wall: wall_start.elapsed(),
            cycles: sim.cycle(),
            timescale: compressed,
            emulated_s: segments[segments.len() - 1].emu_s_at(sim.cycle()),
            real_time_s: if real_time {
                real_time_s + segments[segments.len() - 1].emu_s_at(sim.cycle())
            } else {
                real_time_s
            },
            time_segments: segments,
            start_unix_s: self.start_unix_s,
            cpu,
            wind_pulses: wind.pulses,
            gps_epochs: gps.epochs_sent,
            rtc_time_writes: rtc.map_or(0, |r| r.borrow().time_writes),
            twi_starts,
            longest_awake,
            long_passes,
            current_rises,
            modbus: master,
            paced: self
                .modbus_pty
                .is_some()
                .then_some((paced_done_s + paced_s, behind_s)),
        })
    }
}

/// A motor-driven axis of the bench ([`MegaBench::dc_drives`]): a DC gear
/// motor, or (the A axis) a linear actuator ([`MegaBench::linear_a`]) or
/// a servo on its encoder ([`MegaBench::servo_a`]).
#[derive(Debug, Clone)]
enum BridgeAxis {
    Dc(DcAxisModel),
    Linear(LinearAxisModel),
    Servo(ServoAxisModel),
}

/// What the image's registers command an axis's drive: a bridge's output,
/// or a servo's pulse (µs; `None`: no pulse).
#[derive(Debug, Clone, Copy, PartialEq)]
enum DriveInput {
    Bridge(drivers::dc_motor::Output),
    Pulse(Option<f64>),
}

impl BridgeAxis {
    /// The axis angle, degrees.
    fn angle_deg(&self) -> f64 {
        match self {
            BridgeAxis::Dc(m) => m.angle_deg(),
            BridgeAxis::Linear(m) => m.angle_deg(),
            BridgeAxis::Servo(m) => m.angle_deg(),
        }
    }

    fn home_closed(&self) -> bool {
        match self {
            BridgeAxis::Dc(m) => m.home_closed(),
            BridgeAxis::Linear(m) => m.home_closed(),
            BridgeAxis::Servo(m) => m.home_closed(),
        }
    }

    fn max_closed(&self) -> bool {
        match self {
            BridgeAxis::Dc(m) => m.max_closed(),
            BridgeAxis::Linear(m) => m.max_closed(),
            BridgeAxis::Servo(m) => m.max_closed(),
        }
    }

    /// The drive's command as the image's registers set it.
    fn output(&self, sim: &Sim) -> DriveInput {
        match self {
            BridgeAxis::Dc(m) => DriveInput::Bridge(m.wiring.output(sim)),
            BridgeAxis::Linear(m) => DriveInput::Bridge(m.wiring.output(sim)),
            BridgeAxis::Servo(m) => DriveInput::Pulse(m.wiring.pulse_us(sim)),
        }
    }

    /// The bench must step the axis under `input`.
    fn active(&self, input: DriveInput) -> bool {
        match (self, input) {
            (BridgeAxis::Dc(m), DriveInput::Bridge(o)) => m.active(o),
            (BridgeAxis::Linear(m), DriveInput::Bridge(o)) => m.active(o),
            (BridgeAxis::Servo(m), DriveInput::Pulse(w)) => m.active(w),
            _ => false,
        }
    }

    /// The motor supply (the linear actuator's figures are at 12 V).
    fn set_supply_v(&mut self, supply_v: f64) {
        if let BridgeAxis::Dc(m) = self {
            m.motor.set_supply_v(supply_v);
        }
    }

    /// An obstacle: an angle on a DC axis, an extension (mm) on a linear
    /// one.
    fn set_obstacle(&mut self, at: Option<f64>) {
        match self {
            BridgeAxis::Dc(m) => m.set_obstacle(at),
            BridgeAxis::Linear(m) => m.set_obstacle_mm(at),
            BridgeAxis::Servo(_) => {}
        }
    }

    /// The CPU cycles the current rose above its mark at.
    fn crossings(&self) -> &[u64] {
        match self {
            BridgeAxis::Dc(m) => &m.crossings,
            BridgeAxis::Linear(m) => &m.crossings,
            BridgeAxis::Servo(_) => &[],
        }
    }

    /// Port K's bits of the Hall pair or encoder channels (A, B).
    fn hall_bits(&self) -> (u8, u8) {
        match self {
            BridgeAxis::Dc(m) => m.wiring.hall_bits,
            BridgeAxis::Linear(m) => m.wiring.hall_bits,
            BridgeAxis::Servo(m) => m.wiring.encoder_bits,
        }
    }

    /// Drives the feedback the image reads as it is now (at power-on and
    /// after a reset): the Hall levels, or a linear axis's wiper.
    fn drive_inputs(&mut self, sim: &mut Sim) {
        let event = match self {
            BridgeAxis::Dc(m) => {
                let (a, b) = m.hall_levels();
                PinEvent::Hall(a, b)
            }
            BridgeAxis::Linear(m) => m.inputs_now().into(),
            BridgeAxis::Servo(m) => {
                let (a, b) = m.encoder_levels();
                PinEvent::Hall(a, b)
            }
        };
        self.apply(sim, event);
    }

    /// Puts `event` on the image's pins.
    fn apply(&self, sim: &mut Sim, event: PinEvent) {
        match event {
            PinEvent::Hall(a, b) => {
                let (bit_a, bit_b) = self.hall_bits();
                sim.set_pin('K', bit_a, a);
                sim.set_pin('K', bit_b, b);
            }
            PinEvent::AdcMv(channel, mv) => sim.set_adc_mv(channel, mv),
        }
    }

    /// The current sense: its ADC channel and the IS voltage, mV (a
    /// servo has none).
    fn sense(&self) -> Option<(u8, u32)> {
        match self {
            BridgeAxis::Dc(m) => Some((m.wiring.sense_channel, m.sense_mv())),
            BridgeAxis::Linear(m) => Some((m.wiring.sense_channel, m.sense_mv())),
            BridgeAxis::Servo(_) => None,
        }
    }

    /// Steps the axis under `output` over `span` cycles from `cycle0`:
    /// what to put on the pins, with the cycle of each.
    fn advance(&mut self, input: DriveInput, cycle0: u64, span: u64) -> Vec<(u64, PinEvent)> {
        let hall = |(c, a, b): (u64, bool, bool)| (c, PinEvent::Hall(a, b));
        match (self, input) {
            (BridgeAxis::Dc(m), DriveInput::Bridge(o)) => m
                .advance(o, cycle0, span, F_CPU)
                .into_iter()
                .map(hall)
                .collect(),
            (BridgeAxis::Linear(m), DriveInput::Bridge(o)) => m
                .advance(o, cycle0, span, F_CPU)
                .into_iter()
                .map(|(c, e)| (c, e.into()))
                .collect(),
            (BridgeAxis::Servo(m), DriveInput::Pulse(w)) => m
                .advance(w, cycle0, span, F_CPU)
                .into_iter()
                .map(hall)
                .collect(),
            _ => Vec::new(),
        }
    }
}

/// What a bridge axis puts on the image's pins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PinEvent {
    /// The Hall pair's levels (A, B) on its port K bits.
    Hall(bool, bool),
    /// A voltage on an ADC channel, mV.
    AdcMv(u8, u32),
}

impl From<LinearEvent> for PinEvent {
    fn from(e: LinearEvent) -> Self {
        match e {
            LinearEvent::Hall(a, b) => PinEvent::Hall(a, b),
            LinearEvent::PotMv(mv) => PinEvent::AdcMv(linear::POT_ADC_CHANNEL, mv),
        }
    }
}

/// Runs the CPU for `span` cycles from `cycle0` with the DC models stepped
/// over the same span under `outputs` (the bridges as the registers set
/// them at its start): each Hall edge is put on port K at its cycle (a
/// linear axis's wiper on its ADC input at the end of each model step), the
/// current sense on its ADC input at the start (the models' current at the
/// span's end: the CPU reads a value at most one emulated ms early).
fn run_dc_span(
    sim: &mut Sim,
    models: &mut [BridgeAxis; 2],
    outputs: [DriveInput; 2],
    cycle0: u64,
    span: u64,
) -> CpuState {
    let mut events: Vec<(u64, u8, PinEvent)> = Vec::new();
    for (k, m) in models.iter_mut().enumerate() {
        events.extend(
            m.advance(outputs[k], cycle0, span)
                .into_iter()
                .map(|(c, e)| (c, k as u8, e)),
        );
        if let Some((channel, mv)) = m.sense() {
            sim.set_adc_mv(channel, mv);
        }
    }
    events.sort_by_key(|e| e.0);
    for (cycle, k, event) in events {
        let cpu = run_to(sim, cycle);
        if cpu != CpuState::Running {
            return cpu;
        }
        models[usize::from(k)].apply(sim, event);
    }
    run_to(sim, cycle0 + span)
}

/// Runs the CPU to `cycle` (asleep too: [`Sim::stop_at`]), past the watched
/// port writes that stop [`Sim::run_until`] early.
fn run_to(sim: &mut Sim, cycle: u64) -> CpuState {
    while sim.cycle() < cycle {
        sim.stop_at(cycle);
        let cpu = sim.run_until(cycle);
        if cpu != CpuState::Running {
            return cpu;
        }
    }
    CpuState::Running
}
