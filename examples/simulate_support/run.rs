//! The `simulate` tool: arguments, the simulated world (plants, sensors,
//! RTC, GPS receiver, wind), the scenario and fault events, the trace, the
//! figure and the summary. `examples/simulate.rs` calls [`run`]; so do
//! `tests/simulate_scenarios.rs` and `tests/host_tools_cli.rs`.

use std::cell::Cell;
use std::fmt::Write as _;
use std::fs::File;
use std::io::{BufWriter, Write};

use drivers::gps::GpsDecoder;
use sim::dc_drive::{
    worm_slew_motor, DcDrive, DcDriveSpec, SimTimedAxis, WORM_SLEW_GEAR_RATIO, WORM_SLEW_LOOP,
};
use sim::dc_motor::MotorSpec;
use sim::gps::{GpsReceiverModel, EPOCH_BUF_LEN};
use sim::linear_drive::{
    la12_tilt_axis_config, la12_tilt_spec, FeedbackKind, LinearDrive, SlewTilt,
};
use sim::plant::{Injected, MotorPlant, SimAxis};
use sim::rng::SplitMix64;
use sim::rtc::SimRtc;
use sim::scenario::{parse_all, Command, Event, RtcState, SwitchState};
use sim::sensors::{Anemometer, MountSensors, SensorAccuracy};
use sun_algos::geometry::irradiance::clear_sky_beam_normal_w_m2;
use sun_algos::{Algorithm, Options, Site, UtcTime};
use suntracker::attitude::{angle_between_deg, sun_vector_xyz, MountAttitude, Pose};
use suntracker::config::Config;
use suntracker::controller::{AttitudeSource, Controller, ControllerOptions};
use suntracker::motion::FeedbackMode;
use suntracker::persist::{ConfigStore, MemStorage};
use suntracker::safety::{clear_sky_ghi_w_m2, Mode, Reading, StowInputs};
use suntracker::site::{follow_gps_site, site_from_config};
use suntracker::sun::SharedSiteSource;
use suntracker::sun::{AlgorithmSource, PositionSource};
use suntracker::time::window::DateWindow;
use suntracker::time::{monotonic, TimeConfig, TimeKeeper};

use super::schedule::{self, Action, Kind, Timed, Window};

#[path = "../common/cli.rs"]
pub mod cli;
#[path = "svg.rs"]
pub mod svg;

use cli::Parsed;

/// The header of `--trace`.
pub const TRACE_HEADER: &str = "minute,utc,mode,homing,faults,target_c_deg,target_a_deg,axis_c_deg,axis_a_deg,sun_zenith_deg,sun_azimuth_deg,pointing_error_deg,wind_hz,panel_slope_deg,panel_azimuth_deg,irradiance_w_m2,supply_mv";

/// `--weather`: an overcast day's global irradiance, a fraction of the
/// clear sky's (heavy stratus lets through a fifth to a third).
const OVERCAST_GHI_FRACTION: f64 = 0.25;
/// `--weather`: a clear day's diffuse irradiance, a fraction of the clear
/// sky's global (about a tenth under a clean sky).
const CLEAR_DIFFUSE_FRACTION: f64 = 0.1;

/// `--faults`: `overcast.ratio` for the run's overcast days (the
/// configuration's default 0 turns the mode off), as an installer with a
/// pyranometer would set it.
const FAULTS_OVERCAST_RATIO: f32 = 0.3;

/// The program name in messages.
pub const TOOL: &str = "simulate";

/// The synopsis of `--help`.
pub const USAGE: &str = "[--lat DEG] [--lon DEG] [--start YYYY-MM-DD] [--days N] \
[--drive stepper|servo|dc-hall|timed|linear-hall|linear-pot] [--c-axis limited|continuous] [--supply regulated|battery] [--feedback encoder|sensors] [--mount level|portable] [--faults] [--weather] [--overcast-ratio R] [--seed N] \
[--scenario FILE] [--trace OUT.csv] [--svg OUT.svg]";

/// The text of `--help`.
pub fn help() -> cli::Help {
    use cli::opt;
    cli::Help {
        tool: TOOL,
        synopsis: USAGE,
        about: "\
Runs the whole tracker (controller, axes, safety, time keeper) minute by minute against the plant
and sensor models of sim. Every minute the GPS receiver model writes an NMEA epoch that
goes through the GPS decoder and the time keeper (over a simulated RTC) to the controller. Prints a
summary: pointing error while tracking, clear-sky energy against ideal and fixed panels, faults,
stow times; its last line holds the figures as key=value.",
        options: vec![
            opt("--lat DEG", "site latitude, degrees north (south negative)", "11.9683 (Kano)"),
            opt("--lon DEG", "site longitude, degrees east (west negative)", "8.4261 (Kano)"),
            opt("--start YYYY-MM-DD", "first day of the run (00:00 UTC)", "2026-01-01"),
            opt("--days N", "length of the run in days, 1 to 3660", "1"),
            opt(
                "--drive KIND",
                "axis drives: stepper (steppers through a gear), servo (servos on output \
                 encoders), dc-hall (DC gear motors with motor-shaft Hall encoders), timed (the \
                 same motors run by time with no feedback; sim::dc_drive), linear-hall or \
                 linear-pot (the C axis as dc-hall, the A axis a linear actuator: the LA12's motor \
                 on a dual Hall pair, or a LINAK LA12 on its potentiometer; sim::linear_drive)",
                "stepper",
            ),
            opt(
                "--supply regulated|battery",
                "the DC motors' supply: a regulated 12 V, or a 12 V lead-acid battery at a new \
                 charge each day (11.9 to 12.7 V)",
                "regulated",
            ),
            opt(
                "--feedback encoder|sensors",
                "closed loop on output encoders, or open loop with the attitude sensors",
                "encoder",
            ),
            opt(
                "--mount level|portable",
                "a level mount, or one tilted and turned (read by the attitude sensors)",
                "level",
            ),
            opt(
                "--c-axis limited|continuous",
                "the C axis between its limits (−180…180°), or turning without end on a slip \
                 ring (axis.c.continuous on; stepper and servo drives: no end stops, the home \
                 switch an index cam, the encoder absolute within a turn)",
                "limited",
            ),
            opt(
                "--weather",
                "a sky of clear and overcast days (three in ten overcast, on their own random \
                 stream): the pyranometer reads a quarter of the clear sky's irradiance on an \
                 overcast day, all of it diffuse; a line reports the energy on the panel with \
                 the diffuse light (isotropic sky) and the motor moves a day",
                "off",
            ),
            opt(
                "--overcast-ratio R",
                "overcast.ratio for the run, 0 to 1 (the overcast mode; 0: off)",
                "the configuration's (0)",
            ),
            opt(
                "--faults",
                "add random daily conditions, yearly field incidents (a technician clears a \
                 safe stop the next morning) and weather days: snow, hail warnings, the plant's \
                 stow contact, a low supply and overcast days, a handful of each a year, with \
                 supply.stow_mv 11500, supply.resume_mv 12200 and overcast.ratio 0.3 for the run \
                 (where not set otherwise)",
                "off",
            ),
            opt("--seed N", "seed of the random sensor errors and faults", "1"),
            opt(
                "--scenario FILE",
                "replay the timed events of FILE (format: sim::scenario; examples in \
                 tests/scenarios/)",
                "none",
            ),
            opt("--trace OUT.csv", "write one CSV row per minute", "none"),
            opt(
                "--svg OUT.svg",
                "draw the run: pointing error while tracking, the controller's mode, the active faults",
                "none",
            ),
        ],
        algorithms: false,
        notes: "\
A run starting before 2026-01-01 (the firmware's date floor) uses a date window starting on the
run's first day, so that its dates are trusted; a run outside psa-2020's 2020-2050 lets the
algorithm extrapolate. Bad arguments or a malformed scenario exit with code 2.",
    }
}

/// Wind speed of the calm default and of a random gale, m/s.
const CALM_M_S: f64 = 4.0;
const GALE_M_S: f64 = 22.0;
/// Fix stale after this long in the decoder (as on the Black Pill board).
const GPS_STALE_MS: u32 = 10_000;
/// The site follows GPS when it moved more than this.
const SITE_MIN_MOVE_DEG: f64 = 0.01;
/// Technician visits: at this local solar time (minutes after midnight).
const TECHNICIAN_MINUTE_OF_DAY: i64 = 8 * 60;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Drive {
    Stepper,
    Servo,
    DcHall,
    Timed,
    LinearHall,
    LinearPot,
}

impl Drive {
    fn name(self) -> &'static str {
        match self {
            Drive::Stepper => "stepper",
            Drive::Servo => "servo",
            Drive::DcHall => "dc-hall",
            Drive::Timed => "timed",
            Drive::LinearHall => "linear-hall",
            Drive::LinearPot => "linear-pot",
        }
    }
}

/// The DC motors' supply.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Supply {
    /// A regulated 12 V.
    Regulated,
    /// A 12 V lead-acid battery, a new charge each day.
    Battery,
}

#[derive(Debug, Clone)]
pub struct Args {
    lat: f64,
    lon: f64,
    start: UtcTime,
    days: u32,
    drive: Drive,
    supply: Supply,
    encoder: bool,
    portable: bool,
    /// The C axis turns without end (`--c-axis continuous`).
    continuous_c: bool,
    faults: bool,
    /// A sky of clear and overcast days (`--weather`).
    weather: bool,
    /// `overcast.ratio` for the run (`--overcast-ratio`).
    overcast_ratio: Option<f32>,
    seed: u64,
    scenario: Option<String>,
    trace: Option<String>,
    svg: Option<String>,
}

/// Parses the arguments (without the program name).
pub fn parse_args(args: &[String]) -> Result<Parsed<Args>, String> {
    use cli::{Long, Short};
    let mut a = Args {
        lat: 11.9683,
        lon: 8.4261,
        start: UtcTime::from_ymd_hms(2026, 1, 1, 0, 0, 0).map_err(|e| e.to_string())?,
        days: 1,
        drive: Drive::Stepper,
        supply: Supply::Regulated,
        encoder: true,
        portable: false,
        continuous_c: false,
        faults: false,
        weather: false,
        overcast_ratio: None,
        seed: 1,
        scenario: None,
        trace: None,
        svg: None,
    };
    let mut p = cli::parser(args);
    while let Some(arg) = p.next().map_err(cli::error)? {
        match arg {
            Short('h') | Long("help") => return Ok(Parsed::Help),
            Long("lat") => a.lat = cli::number(&mut p, "--lat")?,
            Long("lon") => a.lon = cli::number(&mut p, "--lon")?,
            Long("start") => {
                let (y, m, d) = cli::date(&mut p, "--start")?;
                a.start =
                    UtcTime::from_ymd_hms(y, m, d, 0, 0, 0).map_err(|e| format!("--start: {e}"))?;
            }
            Long("days") => {
                a.days = cli::value(&mut p, "--days", "1..3660", |v| {
                    v.parse::<u32>().ok().filter(|n| (1..=3660).contains(n))
                })?
            }
            Long("drive") => {
                a.drive = cli::choice(
                    &mut p,
                    "--drive",
                    &[
                        ("stepper", Drive::Stepper),
                        ("servo", Drive::Servo),
                        ("dc-hall", Drive::DcHall),
                        ("timed", Drive::Timed),
                        ("linear-hall", Drive::LinearHall),
                        ("linear-pot", Drive::LinearPot),
                    ],
                )?
            }
            Long("supply") => {
                a.supply = cli::choice(
                    &mut p,
                    "--supply",
                    &[
                        ("regulated", Supply::Regulated),
                        ("battery", Supply::Battery),
                    ],
                )?
            }
            Long("feedback") => {
                a.encoder = cli::choice(
                    &mut p,
                    "--feedback",
                    &[("encoder", true), ("sensors", false)],
                )?
            }
            Long("mount") => {
                a.portable =
                    cli::choice(&mut p, "--mount", &[("level", false), ("portable", true)])?
            }
            Long("c-axis") => {
                a.continuous_c = cli::choice(
                    &mut p,
                    "--c-axis",
                    &[("limited", false), ("continuous", true)],
                )?
            }
            Long("faults") => a.faults = true,
            Long("weather") => a.weather = true,
            Long("overcast-ratio") => {
                a.overcast_ratio = Some(cli::value(&mut p, "--overcast-ratio", "0..1", |v| {
                    v.parse::<f32>().ok().filter(|r| (0.0..=1.0).contains(r))
                })?)
            }
            Long("seed") => {
                a.seed = cli::value(&mut p, "--seed", "an integer 0..2^64", |v| v.parse().ok())?
            }
            Long("scenario") => a.scenario = Some(cli::text(&mut p, "--scenario")?),
            Long("trace") => a.trace = Some(cli::text(&mut p, "--trace")?),
            Long("svg") => a.svg = Some(cli::text(&mut p, "--svg")?),
            other => return Err(cli::unexpected(other)),
        }
    }
    if a.days == 0 || a.days > 3660 {
        return Err("--days 1..3660".into());
    }
    if a.continuous_c
        && matches!(
            a.drive,
            Drive::DcHall | Drive::Timed | Drive::LinearHall | Drive::LinearPot
        )
    {
        return Err("--c-axis continuous: with --drive stepper or servo".into());
    }
    Site::new(a.lat, a.lon).map_err(|e| format!("site: {e}"))?;
    Ok(Parsed::Run(a))
}

/// A run's seeded draws from `--seed`'s generator, in the order drawn: the
/// attitude sensors' errors and noise seed, then with `--faults` the daily
/// conditions, the incidents and the weather days (`schedule::weather`).
/// The battery's charge and the sky of `--weather` have streams of their
/// own.
pub struct Draws {
    pub accuracy: SensorAccuracy,
    pub sensor_seed: u64,
    pub windows: Vec<Window>,
    pub incidents: Vec<Timed>,
    pub weather: Vec<Window>,
}

/// The draws of a run of `days` at longitude `lon_deg`.
pub fn draws(seed: u64, days: u32, lon_deg: f64, faults: bool) -> Draws {
    let mut rng = SplitMix64::new(seed);
    let accuracy = SensorAccuracy::li_2022(&mut rng);
    let sensor_seed = rng.next_u64();
    let (windows, incidents, weather) = if faults {
        let windows = schedule::daily(days, &mut rng);
        let incidents = schedule::incidents(days, &mut rng);
        let weather = schedule::weather(days, lon_deg, &windows, &mut rng);
        (windows, incidents, weather)
    } else {
        Default::default()
    };
    Draws {
        accuracy,
        sensor_seed,
        windows,
        incidents,
        weather,
    }
}

/// Reads and parses a scenario file; every bad line is reported.
pub fn load_scenario(path: &str) -> Result<Vec<Timed>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut events = Vec::new();
    let mut errors = Vec::new();
    for item in parse_all(&text) {
        match item {
            Ok(l) => events.push(Timed {
                minute: l.minute,
                action: Action::Event(l.event),
            }),
            Err((_, e)) => errors.push(format!("{path}: {e}")),
        }
    }
    if errors.is_empty() {
        Ok(events)
    } else {
        Err(errors.join("\n"))
    }
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

/// Pulses counted in one minute at `hz`.
fn pulses_per_minute(hz: f64) -> u32 {
    let p = (hz.max(0.0) * 60.0).round();
    if p.is_finite() && p < f64::from(u32::MAX) {
        p as u32
    } else {
        u32::MAX
    }
}

/// ISO 8601 to the second.
fn iso(t: &UtcTime) -> String {
    let (y, mo, d) = t.ymd();
    let (h, mi, s, _) = t.hms_milli();
    format!("{y:04}-{mo:02}-{d:02}T{h:02}:{mi:02}:{s:02}Z")
}

/// The injected conditions that scenario events set (the random daily
/// windows of `--faults` add to them).
#[derive(Debug, Clone)]
struct World {
    wind_hz: Option<f64>,
    gps_on: bool,
    switch: [SwitchState; 2],
    stalled: [bool; 2],
    obstructed: [bool; 2],
    encoder_failed: [bool; 2],
    attitude_failed: bool,
    /// The snow, hail and plant-stow inputs (`on` = active).
    snow: bool,
    hail: bool,
    stow_input: bool,
    /// What the supply input reads instead of the supply model, mV (0:
    /// the ADC at its rail).
    supply_reading_mv: Option<u16>,
    /// What the pyranometer reads instead of the clear sky, W/m² (0: the
    /// ADC at its rail).
    irradiance_w_m2: Option<u16>,
}

type Ctl<'a, P> = Controller<f64, SharedSiteSource<'a, f64>, P, MountSensors, 1441>;

/// Runs the tool with `args` (without the program name); the summary goes
/// to `out`, errors to `err`. Returns the exit code (2 for bad input).
pub fn run(args: &[String], out: &mut dyn Write, err: &mut dyn Write) -> u8 {
    let args = match parse_args(args) {
        Ok(Parsed::Run(a)) => a,
        Ok(Parsed::Help) => return cli::print_help(&help(), out),
        Err(e) => return cli::usage_error(TOOL, &e, err),
    };
    match simulate(&args, out, err) {
        Ok(()) => 0,
        Err(e) => cli::usage_error(TOOL, &e, err),
    }
}

fn simulate(args: &Args, out: &mut dyn Write, err: &mut dyn Write) -> Result<(), String> {
    match args.drive {
        Drive::Stepper | Drive::Servo => simulate_with(args, out, err, motor_plants),
        Drive::DcHall => simulate_with(args, out, err, dc_plants),
        Drive::Timed => simulate_with(args, out, err, timed_plants),
        Drive::LinearHall | Drive::LinearPot => simulate_with(args, out, err, linear_plants),
    }
}

/// The bridge of both DC drive kinds: no ramp for the timed drive (its run
/// times assume full duty at once), 2 ‰/ms otherwise; braking at rest.
fn dc_bridge(ramp_permille_per_ms: u16) -> drivers::dc_motor::Config {
    drivers::dc_motor::Config {
        ramp_permille_per_ms,
        rest: drivers::dc_motor::RestMode::Brake,
    }
}

/// The supply at which the timed drive's speeds are calibrated, V: the
/// regulated 12 V, or the middle of the battery's range.
fn calibration_supply_v(supply: Supply) -> f64 {
    match supply {
        Supply::Regulated => 12.0,
        Supply::Battery => 12.3,
    }
}

/// The timed axes' calibrated speed, °/s: [`worm_slew_motor`]'s no-load
/// speed through the gears at `calibration_supply_v` (the model's load is
/// friction alone, the same both ways), what timing a sweep each way on the
/// installed axis measures.
fn timed_speed_deg_s(supply: Supply) -> f32 {
    let calibrated = MotorSpec {
        supply_v: calibration_supply_v(supply),
        ..worm_slew_motor()
    };
    (calibrated.no_load_motor_rad_s() / calibrated.gear_ratio).to_degrees() as f32
}

/// The timed axes: the same motor as `dc_spec`'s, run at full duty for the
/// time a move takes at the axes' calibrated speeds (`max_speed_deg_s`
/// forward, `back_speed_deg_s` backward: [`timed_speed_deg_s`]), built as a
/// board builds them from the configuration
/// ([`suntracker::mechanics::timed_runs`]: the current watch of the axis's
/// keys, which are `WORM_SLEW_LOOP`'s), with the motor's lag.
fn timed_plants(args: &Args, config: &Config) -> Result<[DcDrive<SimTimedAxis>; 2], String> {
    // The board measures the motor supply (sim::dc_drive::supply_adc_mv)
    // and scales each run by calibration / measured supply: the speeds are
    // calibrated at the supply model's calibration voltage
    // (`supply.calibration_mv`). The motor's braked time constant with the
    // panels is 0.12 s (WORM_SLEW_LOOP's documentation).
    let calibration_mv = (calibration_supply_v(args.supply) * 1_000.0).round() as u16;
    let [c, a] = config
        .axes
        .map(|ax| suntracker::mechanics::timed_runs(&ax, calibration_mv, 120));
    // One spec drives both axes: their run settings must agree.
    if c != a {
        return Err("the timed axes need the same speeds and current watch".into());
    }
    let spec = DcDriveSpec {
        motor: worm_slew_motor(),
        bridge: dc_bridge(0),
        firmware: c,
    };
    dc_drives(spec, config)
}

/// Both axes of `config` on DC drives of `spec`, at the start angles of
/// `motor_plants` (C 10°, A 20°), switches at the lower soft limits.
fn dc_drives<A: sim::dc_drive::FirmwareAxis>(
    spec: DcDriveSpec<A::Config>,
    config: &Config,
) -> Result<[DcDrive<A>; 2], String> {
    let plant = |ax: &suntracker::config::AxisConfig, start: f64| {
        DcDrive::new(
            spec,
            ax,
            f64::from(ax.min_deg),
            f64::from(ax.max_deg),
            start,
        )
        .map_err(|e| format!("DC axis: {e:?}"))
    };
    Ok([plant(&config.axes[0], 10.0)?, plant(&config.axes[1], 20.0)?])
}

/// Servo: encoder of 2^14 counts on the output, no gear, no microsteps.
const SERVO_CPR: u32 = 1 << 14;

/// The stepper or servo plants of the axes of `config`.
fn motor_plants(args: &Args, config: &Config) -> Result<[MotorPlant; 2], String> {
    let encoder = if args.encoder { Some(1u32 << 16) } else { None };
    let plant = |min: f64, max: f64, start: f64| match args.drive {
        Drive::Servo => MotorPlant::servo(SERVO_CPR, 2.0, min, max, start),
        _ => MotorPlant::stepper(1.8, 16, 100.0, 0.2, 2.0, encoder, min, max, start),
    };
    let [c, a] = config.axes;
    let mut c_plant = plant(f64::from(c.min_deg), f64::from(c.max_deg), 10.0);
    if c.continuous != 0 {
        c_plant.make_continuous();
    }
    Ok([
        c_plant,
        plant(f64::from(a.min_deg), f64::from(a.max_deg), 20.0),
    ])
}

/// The DC axis: `sim::dc_drive`'s worm slew axis on a BTS7960 with a
/// 2 ‰/ms duty ramp, its loop and watch `WORM_SLEW_LOOP`.
fn dc_spec() -> DcDriveSpec<suntracker::hw::DcAxisConfig> {
    DcDriveSpec {
        motor: worm_slew_motor(),
        bridge: dc_bridge(2),
        firmware: WORM_SLEW_LOOP,
    }
}

/// The DC plants of the axes of `config`.
fn dc_plants(_: &Args, config: &Config) -> Result<[DcDrive; 2], String> {
    dc_drives(dc_spec(), config)
}

/// The C axis as `dc_plants`'s; the A axis an LA12 on `la12_tilt_spec`'s
/// mount, 20 mm out.
fn linear_plants(args: &Args, config: &Config) -> Result<[SlewTilt; 2], String> {
    let [c, _] = dc_drives(dc_spec(), config)?;
    let spec = la12_tilt_spec(linear_feedback(args.drive), args.seed);
    let a = LinearDrive::new(spec, &config.axes[1], 20.0)?;
    Ok([SlewTilt::Slew(c), SlewTilt::Tilt(a)])
}

/// The feedback of a linear drive kind.
fn linear_feedback(drive: Drive) -> FeedbackKind {
    if drive == Drive::LinearPot {
        FeedbackKind::Pot
    } else {
        FeedbackKind::Hall
    }
}

fn simulate_with<P: SimAxis>(
    args: &Args,
    out: &mut dyn Write,
    err: &mut dyn Write,
    make_plants: fn(&Args, &Config) -> Result<[P; 2], String>,
) -> Result<(), String> {
    // The scenario is parsed before anything runs.
    let scenario = match &args.scenario {
        Some(p) => load_scenario(p)?,
        None => Vec::new(),
    };
    let mut trace = match &args.trace {
        Some(p) => {
            let f = File::create(p).map_err(|e| format!("{p}: {e}"))?;
            let mut w = BufWriter::new(f);
            writeln!(w, "{TRACE_HEADER}").map_err(|e| format!("{p}: {e}"))?;
            Some(w)
        }
        None => None,
    };
    // The figure's file is created now, so that a bad path fails before
    // the run.
    let mut figure = match &args.svg {
        Some(p) => Some((
            File::create(p).map_err(|e| format!("{p}: {e}"))?,
            svg::Recorder::new(args.days * 1440),
        )),
        None => None,
    };
    let io_err = |e: std::io::Error| format!("write: {e}");

    let draws = draws(args.seed, args.days, args.lon, args.faults);
    let site = Site::new(args.lat, args.lon).map_err(|e| e.to_string())?;
    let algorithm = Algorithm::Psa2020;
    let mut truth_sun = AlgorithmSource {
        algorithm,
        site,
        options: Options {
            allow_out_of_range: true,
            ..Options::default()
        },
    };
    let end = args
        .start
        .add_seconds(i64::from(args.days) * 86_400)
        .map_err(|e| e.to_string())?;
    // The controller's algorithm as in the firmware (no extrapolation),
    // except for runs outside psa-2020's range.
    let in_range = args.start.ymd().0 >= 2020 && end.ymd().0 < 2050;
    let ctl_options = Options {
        allow_out_of_range: !in_range,
        ..Options::default()
    };
    let firmware_window = DateWindow::firmware();
    let window = if firmware_window.contains(&args.start) {
        firmware_window
    } else {
        DateWindow::starting(&args.start)
    };
    let time_config = TimeConfig {
        window,
        ..TimeConfig::default()
    };

    let mut config = Config::default();
    config.site.latitude_deg = args.lat as f32;
    config.site.longitude_deg = args.lon as f32;
    // Set-points every minute; Jimoh & Aliyu's 2-minute hold would skip them.
    config.schedule.table_step_s = 60;
    config.schedule.hold_s = 30;
    for ax in config.axes.iter_mut() {
        ax.deadband_deg = 0.02;
    }
    if args.faults {
        // The weather days' stows: the supply watch and the overcast mode,
        // off by default, on for the run.
        if config.supply.stow_mv == 0 {
            config.supply.stow_mv = schedule::SUPPLY_STOW_MV;
            config.supply.resume_mv = schedule::SUPPLY_RESUME_MV;
        }
        if config.overcast.ratio == 0.0 {
            config.overcast.ratio = FAULTS_OVERCAST_RATIO;
        }
    }
    if let Some(r) = args.overcast_ratio {
        config.overcast.ratio = r;
    }
    config.axes[0].continuous = u8::from(args.continuous_c);
    match args.drive {
        Drive::Servo => {
            for ax in config.axes.iter_mut() {
                ax.counts_per_motor_rev = SERVO_CPR;
                ax.microsteps = 1;
                ax.gear_ratio = 1.0;
                ax.backlash_deg = 0.0;
            }
        }
        Drive::DcHall | Drive::Timed | Drive::LinearHall | Drive::LinearPot => {
            // Hall counts: 64 per motor turn, 7,875:1 (dc_spec); the timed
            // drive's counts are the same scale, run by time.
            for ax in config.axes.iter_mut() {
                ax.counts_per_motor_rev = 64;
                ax.microsteps = 1;
                ax.gear_ratio = WORM_SLEW_GEAR_RATIO;
                ax.backlash_deg = 0.0;
                ax.max_speed_deg_s = 7.0;
            }
            if args.drive == Drive::Timed {
                // The calibrated speed both ways.
                let speed = timed_speed_deg_s(args.supply);
                for ax in config.axes.iter_mut() {
                    ax.max_speed_deg_s = speed;
                    ax.back_speed_deg_s = speed;
                }
            }
        }
        Drive::Stepper => {}
    }
    if matches!(args.drive, Drive::LinearHall | Drive::LinearPot) {
        // The A axis in degrees of tilt, its limits the stroke's ends.
        config.axes[1] = la12_tilt_axis_config(linear_feedback(args.drive))
            .map_err(|e| format!("A axis: {e}"))?;
    }
    let (run_supply, run_overcast_ratio) = (config.supply, config.overcast.ratio);
    // The configuration as stored on the board: a power cycle reloads it.
    let mut store = ConfigStore::new(MemStorage::<{ 2 * suntracker::persist::SLOT_LEN }>::new());
    store
        .save(&config)
        .map_err(|e| format!("configuration not stored: {e:?}"))?;
    let stored_site = site_from_config(&config.site).map_err(|e| e.to_string())?;

    let plants = make_plants(args, &config)?;
    let truth = if args.portable {
        MountAttitude {
            alpha0_deg: 6.0,
            beta0_deg: -4.0,
            gamma0_deg: 25.0,
        }
    } else {
        MountAttitude::level()
    };
    let sensors = MountSensors::new(truth, draws.accuracy, draws.sensor_seed);
    // The timed drive has no feedback: open loop, re-homed every night
    // and after every stow.
    let timed = args.drive == Drive::Timed;
    let use_sensors = args.portable || !args.encoder;
    let options = ControllerOptions {
        feedback: if args.encoder && !timed {
            FeedbackMode::ClosedLoop
        } else {
            FeedbackMode::OpenLoop
        },
        rehome_after_stow: timed,
        attitude: if use_sensors {
            AttitudeSource::Sensors
        } else {
            AttitudeSource::Fixed(MountAttitude::level())
        },
        ..ControllerOptions::default()
    };
    let site_cell = Cell::new(stored_site);
    let new_controller = |config: Config, plants: [P; 2], sensors: Option<MountSensors>| {
        let source = SharedSiteSource {
            algorithm,
            site: &site_cell,
            options: ctl_options,
        };
        Controller::new(config, options, source, plants, sensors)
            .map_err(|e| format!("controller: {e:?}"))
    };
    let mut ctl: Ctl<P> = new_controller(config, plants, Some(sensors))?;

    let Draws {
        windows,
        incidents,
        weather,
        ..
    } = draws;
    // Scenario events first (file order within a minute), then incidents.
    let mut events = scenario;
    events.extend(incidents);
    events.sort_by_key(|t| t.minute);
    let minutes = args.days * 1440;
    let ignored = events.iter().filter(|t| t.minute >= minutes).count();
    if ignored > 0 {
        writeln!(
            err,
            "simulate: {ignored} event(s) after the end of the run ignored"
        )
        .map_err(io_err)?;
    }

    // The world.
    let anemometer = Anemometer { hz_per_m_s: 1.43 };
    let mut world = World {
        wind_hz: None,
        gps_on: true,
        switch: [SwitchState::Ok; 2],
        stalled: [false; 2],
        obstructed: [false; 2],
        encoder_failed: [false; 2],
        attitude_failed: false,
        snow: false,
        hail: false,
        stow_input: false,
        supply_reading_mv: None,
        irradiance_w_m2: None,
    };
    let mut receiver =
        GpsReceiverModel::new(args.lat, args.lon, f64::from(config.site.elevation_m));
    let mut keeper = TimeKeeper::new(SimRtc::new(args.start), time_config);
    let mut decoder = GpsDecoder::new(GPS_STALE_MS);
    let mut boot_minute = 0u32;
    let mut power_cycles = 0u32;
    let (mut prior_raised, mut prior_recovered) = (0u32, 0u32);
    let mut technician_at: Option<u32> = None;
    let mut technician_clears = 0u32;
    let mut epoch_errors = 0u32;

    let fixed_tilt = args.lat.abs();
    let fixed_normal = {
        // Tilted at |latitude| toward the equator: facing south (azimuth
        // 180°) in the north, north in the south.
        let az = if args.lat >= 0.0 { 180.0 } else { 0.0 };
        sun_vector_xyz(90.0 - fixed_tilt, az)
    };

    let mut errors: Vec<f64> = Vec::with_capacity(minutes as usize / 2);
    let (mut e_act, mut e_ideal, mut e_fixed) = (0.0f64, 0.0f64, 0.0f64);
    let (mut wind_min, mut cmd_min, mut wait_min, mut stop_min, mut home_min) = (0u32, 0, 0, 0, 0);
    let mut sched_errors = 0u32;
    // Minutes in each mode and times it was entered (svg::MODES's order).
    let (mut mode_min, mut mode_entries) = ([0u32; svg::MODES.len()], [0u32; svg::MODES.len()]);
    // Swings to another branch: the sun's elevation as each began; and
    // the minutes in tracking with the panel more than 1° off the sun,
    // once the first set-point after homing, a night or a stow was
    // reached (`settled`: the move to it is not tracking's error).
    let mut unwind_elevations_deg: Vec<f64> = Vec::new();
    let mut last_mode: Option<Mode> = None;
    let mut tracking_off_1deg_min = 0u32;
    let mut settled = false;
    let mut last_raised = 0u32;
    let mut next_event = 0usize;
    let mut row = String::with_capacity(256);
    let mut buf = [0u8; EPOCH_BUF_LEN];
    // The wind over the minute before the tick: the anemometer pulses
    // counted at tick m are those of minutes m-1..m, so a wind that starts
    // at minute m is first counted at tick m + 1.
    let mut counted_hz: Option<f64> = None;
    // The battery's charge: its own random stream, so that the other
    // draws (and every run without DC motors) stay as they are. Open-circuit
    // voltages of a 12 V lead-acid battery from 20 % charge (11.9 V) to full
    // (12.7 V), a new one each day.
    let mut supply_rng = SplitMix64::new(args.seed ^ 0x5355_5050_4c59);
    // The motor supply the trace reports: the regulated 12 V, or the
    // battery's voltage of the day.
    let mut supply_v = 12.0;
    // The sky of `--weather`: a day overcast three times in ten, on its own
    // random stream; the energy on the panel with the diffuse light (an
    // isotropic sky: B. Y. H. Liu and R. C. Jordan (1960)); the motor moves
    // (ticks whose target differs from the last one).
    let mut sky_rng = SplitMix64::new(args.seed ^ 0x534b_5944_4159);
    let mut overcast_day = false;
    let (mut overcast_days, mut overcast_min, mut moves) = (0u32, 0u32, 0u32);
    let mut e_sky = 0.0f64;
    let mut last_target: Option<Pose<f64>> = None;
    for m in 0..minutes {
        if args.weather && m % 1440 == 0 {
            overcast_day = sky_rng.uniform(0.0, 1.0) < 0.3;
            overcast_days += u32::from(overcast_day);
        }
        if args.supply == Supply::Battery && m % 1440 == 0 {
            let v = supply_rng.uniform(11.9, 12.7);
            supply_v = v;
            for ax in ctl.axes_mut().iter_mut() {
                ax.drive_mut().set_supply_v(v);
            }
        }
        let now = args
            .start
            .add_seconds(i64::from(m) * 60)
            .map_err(|e| e.to_string())?;
        keeper.rtc_mut().advance(now);
        // Scenario and incident events of this minute, in order.
        while let Some(t) = events.get(next_event).filter(|t| t.minute <= m) {
            next_event += 1;
            match t.action {
                Action::GpsDateTrue => receiver.date_override = None,
                Action::GpsPositionTrue => receiver.position_override = None,
                Action::Event(e) => match e {
                    Event::WindHz(hz) => world.wind_hz = Some(hz),
                    Event::ClockStep { seconds } => {
                        keeper.rtc_mut().step_s(seconds);
                        receiver.time_offset_s = receiver.time_offset_s.saturating_add(seconds);
                    }
                    Event::Gps(on) => world.gps_on = on,
                    Event::GpsPosition { lat_deg, lon_deg } => {
                        receiver.position_override = Some((lat_deg, lon_deg))
                    }
                    Event::GpsDate { year, month, day } => {
                        receiver.date_override = Some((year, month, day))
                    }
                    Event::Rtc(RtcState::LostPower) => keeper.rtc_mut().power_loss(),
                    Event::Rtc(RtcState::BusError) => keeper.rtc_mut().bus_error = true,
                    Event::Rtc(RtcState::Ok) => keeper.rtc_mut().bus_error = false,
                    Event::LimitSwitch(ax, s) => world.switch[ax.index()] = s,
                    Event::Motor(ax, on) => world.stalled[ax.index()] = on,
                    Event::Encoder(ax, on) | Event::Hall(ax, on) => {
                        world.encoder_failed[ax.index()] = on
                    }
                    Event::Obstruction(ax, on) => world.obstructed[ax.index()] = on,
                    Event::AttitudeSensor(on) => world.attitude_failed = on,
                    Event::Snow(on) => world.snow = on,
                    Event::Hail(on) => world.hail = on,
                    Event::StowInput(on) => world.stow_input = on,
                    Event::SupplyMv(mv) => world.supply_reading_mv = mv,
                    Event::Irradiance(w) => world.irradiance_w_m2 = w,
                    Event::Set(key, value) => {
                        // As typed on the console: in force, not saved.
                        let mut config = *ctl.config();
                        let number = suntracker::console::Decimal::parse(value.as_str())
                            .map_err(|e| format!("set {}: {e:?}", key.name()))?;
                        suntracker::console::apply_set(
                            &mut config,
                            key,
                            number,
                            suntracker::config::DriveSet::ALL,
                        )
                        .map_err(|e| format!("set {}: {e:?}", key.name()))?;
                        ctl.reconfigure(config)
                            .map_err(|e| format!("set {}: {e:?}", key.name()))?;
                    }
                    Event::Command(c) => {
                        match c {
                            Command::Stow => ctl.command_stow(true),
                            Command::Resume => {
                                ctl.command_stow(false);
                                ctl.manual(None);
                            }
                            Command::Home => ctl.rehome(),
                            Command::Clear => ctl.reset_faults(),
                            Command::ServiceOn => ctl.service(true),
                            Command::ServiceOff => ctl.service(false),
                        }
                        // The operator's hold is saved with the stored
                        // configuration, as the firmware's console does: a
                        // power cycle restores it.
                        let mut stored = store.load().config;
                        if stored.hold != ctl.hold() {
                            stored.hold = ctl.hold();
                            store
                                .save(&stored)
                                .map_err(|e| format!("operator hold not stored: {e:?}"))?;
                        }
                    }
                    Event::PowerCycle => {
                        // RAM is lost; the axes, the RTC and the receiver
                        // keep their state.
                        prior_raised = prior_raised.saturating_add(ctl.faults().raised);
                        prior_recovered = prior_recovered.saturating_add(ctl.faults().recovered);
                        let axes = ctl.axes();
                        let plants = [axes[0].drive().clone(), axes[1].drive().clone()];
                        let sensors = ctl.sensors_mut().map(|s| s.clone());
                        let loaded = store.load();
                        if loaded.defaults {
                            return Err("stored configuration lost".into());
                        }
                        site_cell
                            .set(site_from_config(&loaded.config.site).map_err(|e| e.to_string())?);
                        ctl = new_controller(loaded.config, plants, sensors)?;
                        let rtc = std::mem::replace(
                            &mut keeper,
                            TimeKeeper::new(SimRtc::new(now), time_config),
                        )
                        .destroy();
                        keeper = TimeKeeper::new(rtc, time_config);
                        decoder = GpsDecoder::new(GPS_STALE_MS);
                        boot_minute = m;
                        power_cycles += 1;
                    }
                },
            }
        }
        // The firmware's 32-bit monotonic clock: a long run wraps it as a
        // board does every 49.7 days.
        let now_ms = monotonic::from_board_ms(u64::from(m - boot_minute) * 60_000);
        // Random daily conditions of --faults.
        let active = |k: &dyn Fn(Kind) -> bool| {
            windows
                .iter()
                .any(|e| k(e.kind) && e.from <= m && m < e.until)
        };
        for w in windows.iter().filter(|w| w.from == m) {
            match w.kind {
                Kind::RtcPowerLoss => keeper.rtc_mut().power_loss(),
                Kind::CommandStow => ctl.command_stow(true),
                _ => {}
            }
        }
        if windows
            .iter()
            .any(|w| w.kind == Kind::CommandStow && w.until == m)
        {
            ctl.command_stow(false);
        }
        let wind_hz = match world.wind_hz {
            Some(hz) => hz,
            None if active(&|k| k == Kind::Wind) => GALE_M_S * anemometer.hz_per_m_s,
            None => CALM_M_S * anemometer.hz_per_m_s,
        };
        receiver.fix = world.gps_on && !active(&|k| k == Kind::GpsLost);
        // The weather days of --faults: the stow inputs, the supply input
        // (what it reads, as a scenario's `supply_mv` sets it: the motors
        // keep the model's supply) and the sky.
        let weather_on = |k: Kind| weather.iter().any(|w| w.kind == k && w.covers(m));
        let sky_factor = schedule::sky_fraction(&weather, m)
            .unwrap_or(1.0)
            .min(if overcast_day {
                OVERCAST_GHI_FRACTION
            } else {
                1.0
            });
        // A technician comes by the morning after a safe stop and clears it
        // once the hardware is repaired (the injected cause is gone).
        if args.faults {
            if let Some(at) = technician_at.filter(|at| *at <= m) {
                let hardware_ok = world.switch == [SwitchState::Ok; 2]
                    && world.stalled == [false; 2]
                    && world.obstructed == [false; 2]
                    && world.encoder_failed == [false; 2]
                    && !world.attitude_failed
                    && !active(&|k| {
                        matches!(
                            k,
                            Kind::CompassBus
                                | Kind::EncoderTimeout(_)
                                | Kind::Stall(_)
                                | Kind::SwitchStuck(_)
                        )
                    });
                if hardware_ok {
                    ctl.reset_faults();
                    technician_clears += 1;
                    technician_at = None;
                } else {
                    technician_at = Some(at + 1440);
                }
            }
        }
        if let Some(s) = ctl.sensors_mut() {
            s.failing = world.attitude_failed || active(&|k| k == Kind::CompassBus);
        }
        for i in 0..2 {
            let stalled = world.stalled[i] || active(&|k| k == Kind::Stall(i));
            let enc = world.encoder_failed[i] || active(&|k| k == Kind::EncoderTimeout(i));
            let stuck = world.switch[i] == SwitchState::StuckClosed
                || active(&|k| k == Kind::SwitchStuck(i));
            let slip = windows.iter().find_map(|e| match e.kind {
                Kind::Slip(ax, d) if ax == i && e.from == m => Some(d),
                _ => None,
            });
            if let Some(ax) = ctl.axes_mut().get_mut(i) {
                let p = ax.drive_mut();
                p.inject(Injected {
                    stalled,
                    obstructed: world.obstructed[i],
                    feedback_failed: enc,
                    switch_stuck_closed: stuck,
                    switch_stuck_open: world.switch[i] == SwitchState::StuckOpen,
                });
                if let Some(d) = slip {
                    p.slip(d);
                }
                p.begin_tick(60.0);
            }
        }
        // Time and site: receiver → NMEA → decoder → time keeper.
        match receiver.epoch(now, &mut buf) {
            Ok(n) => {
                for &b in buf.iter().take(n) {
                    decoder.push(b, now_ms);
                }
            }
            Err(_) => epoch_errors += 1,
        }
        let fix = decoder.current(now_ms);
        follow_gps_site(&site_cell, &fix, SITE_MIN_MOVE_DEG);
        let status = keeper.update(&fix, now_ms);
        let fallback = keeper
            .last_valid()
            .or_else(|| {
                keeper
                    .rtc_mut()
                    .reading_unix_s()
                    .and_then(|s| UtcTime::from_unix_seconds(s).ok())
            })
            .unwrap_or(args.start);
        let pulses = pulses_per_minute(counted_hz.unwrap_or(wind_hz));
        counted_hz = Some(wind_hz);
        let mut inputs = status.tick_inputs(now_ms, fallback, pulses, 60_000);
        // The stow inputs as pins: the plant's contact at its active level
        // while on.
        let active_high = ctl.config().stow.external_active != 0;
        // The supply input: the model's supply, or what a scenario or a
        // weather day makes it read (0: the ADC at its rail).
        let supply_mv = world
            .supply_reading_mv
            .or_else(|| schedule::supply_mv(&weather, m))
            .unwrap_or_else(|| (supply_v * 1000.0).round() as u16);
        // The horizontal pyranometer: the clear sky's global irradiance at
        // the true sun (B. Haurwitz (1945)), or what a scenario makes it
        // read.
        let true_zenith_deg = truth_sun.position(&now).ok().map(|s| s.zenith_deg);
        let irradiance_w_m2 = world.irradiance_w_m2.unwrap_or_else(|| {
            true_zenith_deg.map_or(0, |z| {
                (f64::from(clear_sky_ghi_w_m2(z as f32)) * sky_factor).round() as u16
            })
        });
        let reading = |v: u16, rail: bool| {
            if rail {
                Reading::Impossible
            } else {
                Reading::Value(v)
            }
        };
        inputs.stow_inputs = StowInputs {
            irradiance_w_m2: Some(reading(irradiance_w_m2, world.irradiance_w_m2 == Some(0))),
            snow: Some(world.snow || weather_on(Kind::Snow)),
            hail: Some(world.hail || weather_on(Kind::Hail)),
            external_high: Some((world.stow_input || weather_on(Kind::StowContact)) == active_high),
            supply_mv: Some(reading(supply_mv, supply_mv == 0)),
        };
        let report = ctl.tick(&inputs);

        if std::env::var_os("SIM_DEBUG").is_some() && ctl.faults().raised != last_raised {
            last_raised = ctl.faults().raised;
            let active: Vec<_> = ctl
                .faults()
                .active()
                .map(|a| (a.fault, a.recovery))
                .collect();
            writeln!(err, "{} fault raised; active {active:?}", inputs.now).map_err(io_err)?;
        }
        if report.schedule_error.is_some() {
            sched_errors += 1;
        }
        match report.mode {
            Mode::WindStow => wind_min += 1,
            Mode::CommandStow => cmd_min += 1,
            Mode::WaitForTime => wait_min += 1,
            Mode::SafeStop => stop_min += 1,
            _ => {}
        }
        if args.faults && report.mode == Mode::SafeStop && technician_at.is_none() {
            // Next 08:00 local solar time, at least an hour from now.
            let local = i64::from(m) + (args.lon / 15.0 * 60.0).round() as i64;
            let to_visit = (TECHNICIAN_MINUTE_OF_DAY - local).rem_euclid(1440);
            let wait = if to_visit < 60 {
                to_visit + 1440
            } else {
                to_visit
            };
            technician_at = Some(m + wait as u32);
        }
        if report.homing {
            home_min += 1;
        }
        // Truth: where the sun is and where the panel points now.
        let sun = truth_sun.position(&now).ok();
        let axes = ctl.axes();
        let pose = Pose {
            gamma_deg: axes[0].drive().output_deg(),
            alpha_deg: axes[1].drive().output_deg(),
        };
        let mut pointing = None;
        if report.mode == Mode::Unwind && last_mode != Some(Mode::Unwind) {
            unwind_elevations_deg.push(sun.map_or(f64::NAN, |s| s.elevation_deg()));
        }
        let i = svg::mode_index(report.mode);
        mode_min[i] += 1;
        if last_mode != Some(report.mode) {
            mode_entries[i] += 1;
        }
        last_mode = Some(report.mode);
        settled &= matches!(report.mode, Mode::Tracking | Mode::Unwind);
        if report.mode == Mode::Overcast {
            overcast_min += 1;
        }
        if let Some(t) = report.target {
            let moved = last_target.is_none_or(|l| {
                (l.gamma_deg - t.gamma_deg).abs() > 0.01 || (l.alpha_deg - t.alpha_deg).abs() > 0.01
            });
            moves += u32::from(moved);
            last_target = Some(t);
        }
        if let Some(sun) = sun.filter(|s| s.is_above_horizon()) {
            let s = sun_vector_xyz(sun.elevation_deg(), sun.azimuth_deg);
            let n = truth.normal_xyz(&pose);
            let err = angle_between_deg(&n, &s);
            if args.weather {
                // Clear: the beam and a tenth of the clear sky's global as
                // diffuse; overcast: no beam, the measured global all
                // diffuse. On the panel: the beam at its incidence, the
                // diffuse by the sky it sees, (1 + cos β) / 2.
                let ghi_cs = f64::from(clear_sky_ghi_w_m2(sun.zenith_deg as f32));
                let (dni, dhi) = if sky_factor < 1.0 {
                    (0.0, ghi_cs * sky_factor)
                } else {
                    (
                        clear_sky_beam_normal_w_m2(sun.zenith_deg, now.day_of_year()),
                        ghi_cs * CLEAR_DIFFUSE_FRACTION,
                    )
                };
                e_sky += dni * err.to_radians().cos().max(0.0) + dhi * (1.0 + n[2]) / 2.0;
            }
            if report.mode == Mode::Tracking {
                errors.push(err);
                pointing = Some(err);
                if err > 1.0 && settled {
                    tracking_off_1deg_min += 1;
                }
                settled |= err <= 1.0;
            }
            let beam = clear_sky_beam_normal_w_m2(sun.zenith_deg, now.day_of_year());
            e_ideal += beam;
            e_act += beam * err.to_radians().cos().max(0.0);
            let cos_fixed = angle_between_deg(&fixed_normal, &s)
                .to_radians()
                .cos()
                .max(0.0);
            e_fixed += beam * cos_fixed;
        }
        if let Some((_, rec)) = figure.as_mut() {
            rec.minute(
                m,
                report.mode,
                pointing,
                ctl.faults().active().map(|a| a.fault.name().as_str()),
            );
        }
        if let Some(w) = trace.as_mut() {
            row.clear();
            let names: Vec<&str> = ctl
                .faults()
                .active()
                .map(|a| a.fault.name().as_str())
                .collect();
            let opt = |v: Option<f64>| v.map(|x| format!("{x:.4}")).unwrap_or_default();
            // Where the panel faces (its normal in the horizontal frame:
            // X west, Y south, Z up): slope from horizontal, azimuth from
            // north through east.
            let n = truth.normal_xyz(&pose);
            let slope_deg = n[2].clamp(-1.0, 1.0).acos().to_degrees();
            let azimuth_deg = (-n[0]).atan2(-n[1]).to_degrees().rem_euclid(360.0);
            let _ = write!(
                row,
                "{m},{},{},{},{},{},{},{:.4},{:.4},{},{},{},{:.4},{slope_deg:.4},{azimuth_deg:.4},{irradiance_w_m2},{:.0}",
                iso(&inputs.now),
                report.mode.name(),
                u8::from(report.homing),
                names.join(";"),
                opt(report.target.map(|t| t.gamma_deg)),
                opt(report.target.map(|t| t.alpha_deg)),
                pose.gamma_deg,
                pose.alpha_deg,
                opt(sun.map(|s| s.zenith_deg)),
                opt(sun.map(|s| s.azimuth_deg)),
                opt(pointing),
                wind_hz,
                f64::from(supply_mv)
            );
            writeln!(w, "{row}").map_err(io_err)?;
        }
    }
    if let Some(w) = trace.as_mut() {
        w.flush().map_err(io_err)?;
    }
    if let (Some((mut file, rec)), Some(path)) = (figure.take(), &args.svg) {
        let title = format!(
            "{:.4} {} {:.4} {} from {}, {} day{}; {}, {}, {} mount; faults {}{}",
            args.lat.abs(),
            if args.lat >= 0.0 { 'N' } else { 'S' },
            args.lon.abs(),
            if args.lon >= 0.0 { 'E' } else { 'W' },
            iso(&args.start).get(..10).unwrap_or(""),
            args.days,
            if args.days == 1 { "" } else { "s" },
            args.drive.name(),
            if args.encoder { "encoder" } else { "sensors" },
            if args.portable { "portable" } else { "level" },
            if args.faults { "on" } else { "off" },
            match &args.scenario {
                Some(p) => format!(
                    "; scenario {}",
                    std::path::Path::new(p)
                        .file_name()
                        .map(|f| f.to_string_lossy().into_owned())
                        .unwrap_or_default()
                ),
                None => String::new(),
            },
        );
        let text =
            svg::draw(&rec.finish(), &args.start, &title).map_err(|e| format!("{path}: {e}"))?;
        file.write_all(text.as_bytes())
            .map_err(|e| format!("{path}: {e}"))?;
    }
    errors.sort_by(|a, b| a.total_cmp(b));
    let mean = if errors.is_empty() {
        0.0
    } else {
        errors.iter().sum::<f64>() / errors.len() as f64
    };
    let p95 = percentile(&errors, 0.95);
    let max = errors.last().copied().unwrap_or(0.0);
    let f = ctl.faults();
    let raised = prior_raised.saturating_add(f.raised);
    let recovered = prior_recovered.saturating_add(f.recovered);
    let unrecovered = f.active_count() as u32 + f.dropped;
    let travel: Vec<f64> = ctl.axes().iter().map(|a| a.drive().travel_deg()).collect();
    let p = |out: &mut dyn Write, s: String| writeln!(out, "{s}").map_err(io_err);
    p(
        out,
        format!(
            "site {:.4} {:.4}, {} days from {}, drive {}, feedback {}, mount {}, faults {}",
            args.lat,
            args.lon,
            args.days,
            args.start,
            args.drive.name(),
            if args.encoder { "encoder" } else { "sensors" },
            if args.portable { "portable" } else { "level" },
            if args.faults { "on" } else { "off" },
        ),
    )?;
    p(
        out,
        format!(
            "pointing error while tracking: mean {mean:.4} deg, p95 {p95:.4} deg, max {max:.3} deg over {} min",
            errors.len()
        ),
    )?;
    p(
        out,
        format!(
            "energy (clear-sky beam): tracker {:.1} kWh/m2, ideal {:.1}, fixed tilt {:.1} deg {:.1}",
            e_act / 60_000.0,
            e_ideal / 60_000.0,
            fixed_tilt,
            e_fixed / 60_000.0
        ),
    )?;
    p(
        out,
        format!(
            "faults: raised {raised}, recovered {recovered}, still active {}, injected events {}",
            f.active_count(),
            windows.len() + events.len()
        ),
    )?;
    p(
        out,
        format!(
            "stow: wind {:.1} h ({} stows), command {:.1} h, waiting for time {:.1} h, safe stop {:.1} h; homing {} min; scheduler errors {}",
            f64::from(wind_min) / 60.0,
            ctl.wind().stow_count,
            f64::from(cmd_min) / 60.0,
            f64::from(wait_min) / 60.0,
            f64::from(stop_min) / 60.0,
            home_min,
            sched_errors
        ),
    )?;
    let modes: Vec<String> = svg::MODES
        .iter()
        .zip(mode_min.iter().zip(mode_entries.iter()))
        .map(|(mode, (min, n))| format!("{} {min} / {n}", mode.name()))
        .collect();
    p(
        out,
        format!("modes (minutes / entries): {}", modes.join(", ")),
    )?;
    if args.faults {
        let spells = |pick: &dyn Fn(Kind) -> bool| {
            let ws: Vec<&Window> = weather.iter().filter(|w| pick(w.kind)).collect();
            let hours = ws.iter().map(|w| f64::from(w.until - w.from)).sum::<f64>() / 60.0;
            (ws.len(), hours)
        };
        let (snow, snow_h) = spells(&|k| k == Kind::Snow);
        let (hail, hail_h) = spells(&|k| k == Kind::Hail);
        let (contact, contact_h) = spells(&|k| k == Kind::StowContact);
        let (low, low_h) = spells(&|k| matches!(k, Kind::LowSupply(_)));
        let (overcast, _) = spells(&|k| matches!(k, Kind::Overcast(_)));
        p(
            out,
            format!(
                "weather days (--faults): snow {snow} ({snow_h:.1} h), hail {hail} ({hail_h:.1} h), stow contact {contact} ({contact_h:.1} h), low supply {low} ({low_h:.1} h), overcast {overcast} days; for the run supply.stow_mv {}, supply.resume_mv {}, overcast.ratio {}",
                run_supply.stow_mv, run_supply.resume_mv, run_overcast_ratio
            ),
        )?;
    }
    p(
        out,
        format!(
            "motor travel: C axis {:.0} deg, A axis {:.0} deg",
            travel.first().copied().unwrap_or(0.0),
            travel.get(1).copied().unwrap_or(0.0)
        ),
    )?;
    if args.weather {
        p(
            out,
            format!(
                "weather: {overcast_days} overcast days of {}; energy with diffuse light {:.1} kWh/m2; overcast mode {:.1} h; motor moves per day {:.0}",
                args.days,
                e_sky / 60.0 / 1000.0,
                f64::from(overcast_min) / 60.0,
                f64::from(moves) / f64::from(args.days.max(1)),
            ),
        )?;
    }
    let elevations: Vec<String> = unwind_elevations_deg
        .iter()
        .map(|e| format!("{e:.1}"))
        .collect();
    p(
        out,
        format!(
            "unwind: {} swings (sun elevation at each: {} deg); minutes tracking more than 1 deg off the sun: {tracking_off_1deg_min}; C axis {:.0} deg a day",
            unwind_elevations_deg.len(),
            if elevations.is_empty() {
                "none".to_string()
            } else {
                elevations.join(", ")
            },
            travel.first().copied().unwrap_or(0.0) / f64::from(args.days.max(1)),
        ),
    )?;
    p(
        out,
        format!(
            "time chain: RTC set from GPS {} times, GPS epochs not written {epoch_errors}, power cycles {power_cycles}, technician clears {technician_clears}",
            keeper.rtc_mut().sets,
        ),
    )?;
    let mut why: Vec<String> = f
        .active()
        .map(|a| {
            format!(
                "{} ({:?} after {} attempt{})",
                a.fault.name(),
                a.recovery,
                a.attempts,
                if a.attempts == 1 { "" } else { "s" }
            )
        })
        .collect();
    if f.dropped > 0 {
        why.push(format!("{} not recorded (list full)", f.dropped));
    }
    p(
        out,
        format!(
            "unrecovered at end: {}",
            if why.is_empty() {
                "none".to_string()
            } else {
                why.join(", ")
            }
        ),
    )?;
    let ratio = |x: f64| if e_ideal > 0.0 { x / e_ideal } else { 0.0 };
    let vs_fixed = if e_fixed > 0.0 { e_act / e_fixed } else { 0.0 };
    p(
        out,
        format!(
            "simulate: pointing_p95_deg={p95:.4} energy_vs_ideal={:.4} energy_vs_fixed={vs_fixed:.4} faults_raised={raised} faults_unrecovered={unrecovered} panics=0",
            ratio(e_act),
        ),
    )?;
    Ok(())
}
