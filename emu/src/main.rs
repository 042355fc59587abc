//! `suntracker-emu`: run a suntracker AVR image under simavr with the
//! peripheral models and print its log. See `emu/README.md`.

use std::path::PathBuf;
use std::process::ExitCode;

use suntracker_emu::log::{format_utc, parse_utc};
use suntracker_emu::models::nmea::{parse_log, GpsFeed};
use suntracker_emu::uno::{Axis, UnoBench};
use suntracker_emu::{MegaBench, Rtc, WindProfile};

const HELP: &str = "\
suntracker-emu: run a suntracker firmware image under simavr with models of
its peripherals (DS3231, QMC5883L, ADXL345, two H-bridge steppers with end
switches, GPS on USART1, anemometer on INT4) and print the board's log.

USAGE:
  suntracker-emu --image mega|uno|uno-settings|qemu [OPTIONS]

OPTIONS:
  --image NAME          mega (ATmega2560) or uno (ATmega328P: DS3231, two
                        FS5106R servos turning YMT22 encoders, home
                        switches, the panel voltage on ADC0; the GPS, mount
                        and wind options do not apply); uno-settings: the
                        Uno's settings image (its configuration console on
                        USART0, the DS3231, the EEPROM; clock 1:1, emulated
                        time = CPU time); qemu runs in QEMU, not here:
                        python3 .ci/qemu_gps.py ELF
  --elf PATH            the ELF (default: $CARGO_TARGET_DIR or target, then
                        /mega-emu/avr-none/release/avr_mega_tracker.elf,
                        /uno-emu/avr-none/release/avr_tracker.elf or
                        /uno-emu/avr-none/release/avr_settings.elf). An
                        emulation build (it holds the text `timescale `)
                        runs at 60x until it logs its timescale; a board
                        build, the ELF a user flashes (e.g.
                        /mega/avr-none/release/avr_mega_tracker.elf), at
                        1:1: emulated time = CPU time
  --nmea FILE           feed this recorded NMEA log on USART1 (default: a
                        generated Kano fix, 11.9683 N 8.4261 E, 480 m)
  --no-gps              keep USART1 silent
  --gps-period-s S      seconds between two epochs of the generated fix
                        (default 30; 1 as most receivers send them)
  --start UTC           power-on time, YYYY-MM-DDTHH:MM:SSZ (default: the
                        first NMEA time, else 2026-06-21T05:00:00Z)
  --rtc valid|lost|absent   DS3231 state at power-on (default valid)
  --ds1302              uno, uno-settings: the `ds1302` build (default ELF
                        /uno-ds1302-emu/avr-none/release/…): a DS1302 on
                        PC1-PC3 instead of the DS3231, in the --rtc state
                        (lost: clock halted, 2000-01-01)
  --dc                  mega: the `dc` build (default ELF
                        /mega-dc-emu/avr-none/release/avr_mega_tracker.elf):
                        DC gear motors on IBT-2 bridges with Hall encoders
                        (models/ibt2.rs) instead of the steppers
  --minutes N           emulated minutes to run (default 1440; uno-settings
                        5)
  --tilt-deg X          mount tilt about the tracker's x axis (default 0)
  --heading-deg Y       azimuth the mount faces, east of north (default 0)
  --gale-at UTC         40 Hz anemometer pulses for 10 minutes from UTC
  --log OUT             also write the log lines to OUT (uno: at the end, as
                        the image sent them, each set-point followed by an
                        `axes utc=… c=… a=…` line: the pose decoded from
                        the encoder models at the end of its slot)
  --stall c|a:UTC:MIN   uno: hold that axis's shaft from UTC for MIN
                        emulated minutes (a jammed servo); repeatable
  --start-deg C,A       uno: shaft angles at power-on (default 0,20)
  --site LAT,LON        uno: where the bench stands, degrees north, east: the
                        sun its panel model sees (default Kano, 11.9683,
                        8.4261), whatever site the image is set for
  --type MINUTE:LINE    mega, uno-settings: type LINE on the console
                        (USART0, 115200 baud) at emulated MINUTE (a
                        decimal); repeatable. The log shows `> LINE` and
                        the console's replies (refused for uno: the
                        tracker image reads no console)
  --reset-at MINUTE     cut the power at emulated MINUTE and turn it on
                        again: the chip resets, its RAM is lost, its EEPROM
                        is kept, the DS3231 runs on, the axes stay put (uno:
                        the servos, encoders and switches keep their state;
                        the image homes again); the log shows `# power
                        cut`. Repeatable
  --eeprom FILE         uno, uno-settings: the EEPROM at power-on, an Intel
                        HEX file (as for avrdude -U eeprom:w:FILE:i;
                        records 00 and 01); default all erased (0xFF)
  --eeprom-out FILE     uno, uno-settings: write the EEPROM at the end of
                        the run to FILE, Intel HEX (1,024 bytes)
  --modbus-pty PATH     mega: a pseudo-terminal linked at PATH bridged to
                        the RS-485 port (USART2, the image's Modbus RTU
                        server, 19200 8E1 by default) for a Modbus master
                        (pysunspec2, mbpoll) to open; while a client holds
                        it open the run is at real time (an emulation build
                        at 1:1) and paced to the wall clock, never ahead of
                        it by more than 2 ms. SIGTERM or SIGINT ends the run
                        with its summary (exit 0)
  --quiet               do not print the log lines
  -h, --help            this text

Exit status: 0 if the image ran for the whole span, 1 if it stopped or
crashed early, 2 for usage errors or an unsupported image.";

/// The images the harness runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Image {
    /// The ATmega2560 tracker (`avr_mega_tracker`).
    Mega,
    /// The ATmega328P tracker (`avr_tracker`).
    Uno,
    /// The ATmega328P settings image (`avr_settings`).
    UnoSettings,
}

fn main() -> ExitCode {
    match run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("suntracker-emu: {e}");
            ExitCode::from(2)
        }
    }
}

fn run() -> Result<ExitCode, String> {
    use lexopt::prelude::*;
    let mut image = None::<String>;
    let mut elf = None::<PathBuf>;
    let mut nmea = None::<PathBuf>;
    let mut no_gps = false;
    let mut start = None::<i64>;
    let mut minutes = None::<f64>;
    let mut tilt = 0.0;
    let mut heading = 0.0;
    let mut log = None::<PathBuf>;
    let mut quiet = false;
    let mut rtc = Rtc::Valid;
    let mut gale = None::<i64>;
    let mut typed: Vec<(f64, String)> = Vec::new();
    let mut resets: Vec<f64> = Vec::new();
    let mut stalls: Vec<(Axis, i64, f64)> = Vec::new();
    let mut start_deg = None::<(f64, f64)>;
    let mut eeprom = None::<PathBuf>;
    let mut ds1302 = false;
    let mut dc = false;
    let mut eeprom_out = None::<PathBuf>;
    let mut site = None::<(f64, f64)>;
    let mut modbus_pty = None::<PathBuf>;
    let mut gps_period_s = None::<f64>;
    let mut p = lexopt::Parser::from_env();
    let err = |e: lexopt::Error| e.to_string();
    let utc = |s: String| parse_utc(&s).ok_or(format!("bad time {s}, want YYYY-MM-DDTHH:MM:SSZ"));
    while let Some(arg) = p.next().map_err(err)? {
        match arg {
            Long("image") => image = Some(p.value().map_err(err)?.string().map_err(err)?),
            Long("elf") => elf = Some(p.value().map_err(err)?.into()),
            Long("nmea") => nmea = Some(p.value().map_err(err)?.into()),
            Long("no-gps") => no_gps = true,
            Long("start") => start = Some(utc(p.value().map_err(err)?.string().map_err(err)?)?),
            Long("minutes") => minutes = Some(p.value().map_err(err)?.parse().map_err(err)?),
            Long("tilt-deg") => tilt = p.value().map_err(err)?.parse().map_err(err)?,
            Long("heading-deg") => heading = p.value().map_err(err)?.parse().map_err(err)?,
            Long("log") => log = Some(p.value().map_err(err)?.into()),
            Long("quiet") => quiet = true,
            Long("type") => {
                let v = p.value().map_err(err)?.string().map_err(err)?;
                let (minute, line) = v
                    .split_once(':')
                    .ok_or(format!("--type {v}: want MINUTE:LINE"))?;
                let minute: f64 = minute
                    .parse()
                    .ok()
                    .filter(|m: &f64| m.is_finite() && *m >= 0.0)
                    .ok_or(format!("--type {v}: MINUTE must be a number >= 0"))?;
                typed.push((minute, line.to_string()));
            }
            Long("reset-at") => {
                let v = p.value().map_err(err)?.string().map_err(err)?;
                let minute: f64 = v
                    .parse()
                    .ok()
                    .filter(|m: &f64| m.is_finite() && *m >= 0.0)
                    .ok_or(format!("--reset-at {v}: want a minute >= 0"))?;
                resets.push(minute);
            }
            Long("stall") => {
                let v = p.value().map_err(err)?.string().map_err(err)?;
                let bad = || format!("--stall {v}: want c|a:YYYY-MM-DDTHH:MM:SSZ:MINUTES");
                let (axis, rest) = v.split_once(':').ok_or_else(bad)?;
                let (at, minutes) = rest.rsplit_once(':').ok_or_else(bad)?;
                let axis = match axis {
                    "c" | "C" => Axis::C,
                    "a" | "A" => Axis::A,
                    _ => return Err(bad()),
                };
                let at = parse_utc(at).ok_or_else(bad)?;
                let minutes: f64 = minutes
                    .parse()
                    .ok()
                    .filter(|m: &f64| m.is_finite() && *m > 0.0)
                    .ok_or_else(bad)?;
                stalls.push((axis, at, minutes));
            }
            Long("start-deg") => {
                let v = p.value().map_err(err)?.string().map_err(err)?;
                let pair = v.split_once(',').and_then(|(c, a)| {
                    let c: f64 = c.trim().parse().ok()?;
                    let a: f64 = a.trim().parse().ok()?;
                    (c.is_finite() && a.is_finite()).then_some((c, a))
                });
                start_deg = Some(pair.ok_or(format!("--start-deg {v}: want C,A in degrees"))?);
            }
            Long("gps-period-s") => {
                let v = p.value().map_err(err)?.string().map_err(err)?;
                gps_period_s = Some(
                    v.parse()
                        .ok()
                        .filter(|s: &f64| s.is_finite() && *s >= 1.0)
                        .ok_or(format!("--gps-period-s {v}: want seconds >= 1"))?,
                );
            }
            Long("modbus-pty") => modbus_pty = Some(p.value().map_err(err)?.into()),
            Long("eeprom") => eeprom = Some(p.value().map_err(err)?.into()),
            Long("eeprom-out") => eeprom_out = Some(p.value().map_err(err)?.into()),
            Long("site") => {
                let v = p.value().map_err(err)?.string().map_err(err)?;
                let pair = v.split_once(',').and_then(|(lat, lon)| {
                    let lat: f64 = lat.trim().parse().ok()?;
                    let lon: f64 = lon.trim().parse().ok()?;
                    ((-90.0..=90.0).contains(&lat) && (-180.0..=180.0).contains(&lon))
                        .then_some((lat, lon))
                });
                site =
                    Some(pair.ok_or(format!("--site {v}: want LAT,LON in degrees (north, east)"))?);
            }
            Long("gale-at") => gale = Some(utc(p.value().map_err(err)?.string().map_err(err)?)?),
            Long("rtc") => {
                rtc = match p.value().map_err(err)?.string().map_err(err)?.as_str() {
                    "valid" => Rtc::Valid,
                    "lost" => Rtc::LostPower,
                    "absent" => Rtc::Absent,
                    other => return Err(format!("--rtc {other}: want valid, lost or absent")),
                }
            }
            Long("ds1302") => ds1302 = true,
            Long("dc") => dc = true,
            Short('h') | Long("help") => {
                println!("{HELP}");
                return Ok(ExitCode::SUCCESS);
            }
            _ => return Err(arg.unexpected().to_string()),
        }
    }
    let image = match image.as_deref() {
        Some("mega") => Image::Mega,
        Some("uno") => Image::Uno,
        Some("uno-settings") => Image::UnoSettings,
        Some("qemu") => {
            eprintln!(
                "suntracker-emu: --image qemu: the QEMU image runs under QEMU, fed by \
                 .ci/qemu_gps.py (same --nmea, --start, --minutes, --log, --no-gps options)"
            );
            return Ok(ExitCode::from(2));
        }
        Some(other) => {
            return Err(format!(
                "--image {other}: want mega, uno, uno-settings or qemu"
            ))
        }
        None => return Err("--image is required (see --help)".into()),
    };
    let elf = elf.unwrap_or_else(|| {
        let target = std::env::var_os("CARGO_TARGET_DIR")
            .map_or_else(|| PathBuf::from("target"), PathBuf::from);
        target.join(match (image, ds1302) {
            (Image::Mega, _) if dc => "mega-dc-emu/avr-none/release/avr_mega_tracker.elf",
            (Image::Mega, _) => "mega-emu/avr-none/release/avr_mega_tracker.elf",
            (Image::Uno, false) => "uno-emu/avr-none/release/avr_tracker.elf",
            (Image::UnoSettings, false) => "uno-emu/avr-none/release/avr_settings.elf",
            (Image::Uno, true) => "uno-ds1302-emu/avr-none/release/avr_tracker.elf",
            (Image::UnoSettings, true) => "uno-ds1302-emu/avr-none/release/avr_settings.elf",
        })
    });
    let minutes = minutes.unwrap_or(match image {
        Image::UnoSettings => 5.0,
        _ => 1440.0,
    });
    if image != Image::Uno && (!stalls.is_empty() || start_deg.is_some() || site.is_some()) {
        return Err("--stall, --start-deg and --site: --image uno only".into());
    }
    if image != Image::Mega && modbus_pty.is_some() {
        return Err("--modbus-pty: --image mega only".into());
    }
    if image != Image::Mega && dc {
        return Err("--dc: --image mega only".into());
    }
    if image == Image::Mega && ds1302 {
        return Err("--ds1302: --image uno or uno-settings only".into());
    }
    if image == Image::Mega && (eeprom.is_some() || eeprom_out.is_some()) {
        return Err("--eeprom and --eeprom-out: --image uno or uno-settings only".into());
    }
    if image == Image::Uno && !typed.is_empty() {
        return Err(
            "--type: not for --image uno (the tracker image reads no console; its settings \
             come from the EEPROM: --image uno-settings types them)"
                .into(),
        );
    }
    if image != Image::Mega {
        let settings = image == Image::UnoSettings;
        let start = start.unwrap_or(suntracker_emu::mega::DEFAULT_START);
        let mut bench = if settings {
            UnoBench::settings(&elf)
        } else {
            UnoBench::new(&elf)
        }
        .start(start)
        .rtc(rtc)
        .echo(!quiet)
        .log_to(log);
        if ds1302 {
            bench = bench.ds1302();
        }
        if let Some((c, a)) = start_deg {
            bench = bench.start_angles(c, a);
        }
        if let Some((lat, lon)) = site {
            bench = bench.site(lat, lon);
        }
        for (axis, at, minutes) in stalls {
            bench = bench.stall(axis, at as f64, minutes * 60.0);
        }
        for (minute, line) in &typed {
            bench = bench.type_at(*minute, line);
        }
        for minute in &resets {
            bench = bench.reset_at(*minute);
        }
        if let Some(path) = &eeprom {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
            let bytes = suntracker_emu::ihex::parse(&text)
                .map_err(|e| format!("--eeprom {}: {e}", path.display()))?;
            bench = bench.eeprom(bytes);
        }
        let run = bench.run_minutes(minutes)?;
        if let Some(path) = &eeprom_out {
            std::fs::write(path, suntracker_emu::ihex::encode(&run.eeprom))
                .map_err(|e| format!("{}: {e}", path.display()))?;
        }
        if let Some(r) = &run.rtc {
            let (chip, flag) = if ds1302 {
                ("DS1302", "clock halt")
            } else {
                ("DS3231", "oscillator-stop flag")
            };
            eprintln!(
                "suntracker-emu: {chip} at the end: {} ({flag} {}), time set {} times",
                format_utc(r.unix_s),
                if r.osf { "set" } else { "clear" },
                r.time_writes
            );
        }
        if let Some(d) = &run.ds1302 {
            eprintln!(
                "suntracker-emu: DS1302: {} transfers, {} contentions on I/O, {} timing violations ({:?} V column)",
                d.transfers.len(),
                d.contentions,
                d.violation_count,
                d.supply_column()
            );
            for v in d.violations.iter().take(5) {
                eprintln!(
                    "suntracker-emu: DS1302: {} {:.1} ns at {:.1} ns CPU time",
                    v.rule.symbol(),
                    v.measured_ns,
                    v.at_ns
                );
            }
            eprintln!(
                "suntracker-emu: DS1302: shortest times the image gave: {}",
                d.shortest_summary()
            );
        }
        let ok = if run.cpu == suntracker_emu::sim::CpuState::Running {
            ExitCode::SUCCESS
        } else {
            ExitCode::from(1)
        };
        if settings {
            eprintln!(
                "suntracker-emu: {} from {}: {:.2} emulated min at 1:1 ({} cycles) in {:.2} s wall; \
                 {} log lines; cpu {:?}",
                elf.display(),
                format_utc(start),
                run.emulated_s / 60.0,
                run.cycles,
                run.wall.as_secs_f64(),
                run.lines.len(),
                run.cpu
            );
            eprintln!("suntracker-emu: {}", run.ram.summary());
            return Ok(ok);
        }
        let [c, a] = &run.axes;
        eprintln!(
            "suntracker-emu: {} from {}: {:.1} emulated min ({} cycles, timescale {}) in {:.2} s wall; \
             {} log lines; decoded C {:.2}° A {:.2}° (shafts {:.3}° {:.3}°); encoder edges C {} A {}, \
             illegal transitions C {} A {}; hard-stop hits C {} A {}; servo pulses C {} A {} \
             (on the pins {} {}, unlike the datasheet's {} {}); cpu {:?}",
            elf.display(),
            format_utc(start),
            run.emulated_s / 60.0,
            run.cycles,
            run.timescale,
            run.wall.as_secs_f64(),
            run.lines.len(),
            c.decoded_deg,
            a.decoded_deg,
            c.final_deg,
            a.final_deg,
            c.edges,
            a.edges,
            c.illegal_transitions + c.decoder_mismatches,
            a.illegal_transitions + a.decoder_mismatches,
            c.hard_stop_hits,
            a.hard_stop_hits,
            c.pulses.len(),
            a.pulses.len(),
            run.pin_pulses.0,
            run.pin_pulses.1,
            run.pin_pulses_unlike_datasheet.0,
            run.pin_pulses_unlike_datasheet.1,
            run.cpu
        );
        if let Some(e) = run.energy_check() {
            eprintln!(
                "suntracker-emu: day_energy {:.3} V·h logged, {:.3} V·h by the panel model's \
                 trapezoid {} to {} ({} samples): {:+.3} %",
                e.logged_vh,
                e.model_vh,
                format_utc(e.from_utc_s),
                format_utc(e.to_utc_s),
                e.samples,
                100.0 * e.relative_error()
            );
        }
        eprintln!("suntracker-emu: {}", run.ram.summary());
        return Ok(ok);
    }
    let default_start = suntracker_emu::mega::DEFAULT_START;
    let (feed, first) = match (&nmea, no_gps) {
        (_, true) => (GpsFeed::Silent, None),
        (Some(path), false) => {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
            let epochs = parse_log(&text, start.unwrap_or(default_start).div_euclid(86_400));
            let first = epochs.first().map(|e| e.unix_s);
            (GpsFeed::Recorded(epochs), first)
        }
        (None, false) => (GpsFeed::kano(), None),
    };
    let feed = match (feed, gps_period_s) {
        (GpsFeed::Generated { site, fix, .. }, Some(period_s)) => GpsFeed::Generated {
            site,
            fix,
            period_s,
        },
        (_, Some(_)) => {
            return Err(
                "--gps-period-s: for the generated fix only (not with --nmea or --no-gps)".into(),
            )
        }
        (feed, None) => feed,
    };
    let start = start.or(first).unwrap_or(default_start);
    let wind = gale.map_or_else(WindProfile::calm, |t| WindProfile::gust(t, 10, 40.0));
    let mut bench = MegaBench::mega(&elf);
    if dc {
        bench = bench.dc_drives();
    }
    for (minute, line) in &typed {
        bench = bench.type_at(*minute, line);
    }
    for minute in &resets {
        bench = bench.reset_at(*minute);
    }
    if let Some(path) = modbus_pty {
        suntracker_emu::pty::install_stop_handler();
        bench = bench.modbus_pty(path);
    }
    let run = bench
        .start(start)
        .rtc(rtc)
        .gps(feed)
        .wind(wind)
        .mount(tilt, heading)
        .echo(!quiet)
        .log_to(log)
        .run_minutes(minutes)?;
    let emulated_s = run.emulated_s;
    eprintln!(
        "suntracker-emu: {} from {}: {:.1} emulated min ({} cycles, timescale {}, {:.0} s of it real time) in {:.2} s wall; \
         {} log lines; final C {:.3}° A {:.3}°; illegal steps C {} A {}; GPS epochs {}; wind pulses {}; cpu {:?}",
        elf.display(),
        format_utc(start),
        emulated_s / 60.0,
        run.cycles,
        run.timescale,
        run.real_time_s,
        run.wall.as_secs_f64(),
        run.lines.len(),
        run.final_angles.0,
        run.final_angles.1,
        run.illegal_steps.0.len(),
        run.illegal_steps.1.len(),
        run.gps_epochs,
        run.wind_pulses,
        run.cpu
    );
    if let Some((paced_s, behind_s)) = run.paced {
        eprintln!(
            "suntracker-emu: Modbus pseudo-terminal: {paced_s:.1} emulated s paced to the wall clock, \
             at most {:.1} ms behind it{}",
            behind_s * 1e3,
            if suntracker_emu::pty::stop_requested() {
                "; stopped by a signal"
            } else {
                ""
            }
        );
    }
    if std::env::var_os("SUNTRACKER_EMU_TRACE").is_some() {
        // Motion starts and minute samples, then switch changes.
        for t in &run.angle_trace {
            eprintln!(
                "suntracker-emu: trace {} C {:.3} A {:.3}",
                format_utc(t.utc_s.floor() as i64),
                t.c_deg,
                t.a_deg
            );
        }
        for g in &run.time_segments {
            eprintln!(
                "suntracker-emu: timescale {} from {}",
                g.timescale,
                format_utc(start + g.emu_s.floor() as i64)
            );
        }
        for e in &run.switch_events {
            eprintln!(
                "suntracker-emu: switch {} {} {}",
                format_utc(e.utc_s.floor() as i64),
                ["C home", "A home", "C max", "A max"][e.switch.min(3)],
                if e.closed { "closed" } else { "open" }
            );
        }
    }
    for (axis, steps) in [("C", &run.illegal_steps.0), ("A", &run.illegal_steps.1)] {
        for s in steps.iter().take(5) {
            let at = run.emu_s_at(s.cycle);
            eprintln!(
                "suntracker-emu: illegal coil sequence on {axis} at {}: {:04b} -> {:04b} (IN4..IN1)",
                format_utc(start + at as i64),
                s.from,
                s.to
            );
        }
    }
    eprintln!("suntracker-emu: {}", run.ram.summary());
    Ok(if run.cpu == suntracker_emu::sim::CpuState::Running {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
