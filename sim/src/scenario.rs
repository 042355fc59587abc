//! Scenario files for simulations: a timed list of weather, fault and
//! operator events, parsed one line at a time without allocation.
//!
//! # Format
//!
//! CSV, one event per line: `minute,event[,args]`, where `minute` (a whole
//! number, `u32`) counts simulated minutes from the start of the run.
//! `#` starts a comment (a whole line or the end of one); blank lines are
//! ignored; whitespace around fields and CR LF line ends are accepted.
//! Minutes must not go backwards; events on the same minute apply in file
//! order.
//!
//! ```text
//! # minute,event,args
//! 0,wind_hz,2.5            # anemometer pulse rate, Hz (finite, >= 0)
//! 60,clock_step_s,-3600    # the RTC and GPS time jump by S seconds
//! 90,gps,off               # gps,off|on
//! 95,gps_position,91,200   # reported latitude, longitude (finite, may be impossible)
//! 100,gps_date,2006-04-16  # reported date (a real calendar date)
//! 120,rtc,lost_power       # rtc,lost_power|bus_error|ok
//! 130,limit_switch,C,stuck_closed   # limit_switch,C|A,stuck_closed|stuck_open|ok
//! 140,motor,A,stalled      # motor,C|A,stalled|ok
//! 150,encoder,C,failed     # encoder,C|A,failed|ok
//! 152,obstruction,A,on     # obstruction,C|A,on|off (the axis is held where it is)
//! 155,hall,C,failed        # hall,C|A,failed|ok (the motor's Hall sensor)
//! 160,attitude_sensor,failed        # attitude_sensor,failed|ok
//! 162,snow,on              # snow,on|off (the snow input)
//! 164,hail,on              # hail,on|off (the hail warning input)
//! 166,stow_input,on        # stow_input,on|off (the plant's stow contact active)
//! 168,supply_mv,11200      # supply_mv,N: the supply input reads N mV (0: its ADC at the rail)
//! 169,supply_mv,model      # the supply model again (12 V, or the battery)
//! 170,set,supply.stow_mv,11500      # set,KEY,VALUE: as typed on the console
//! 172,irradiance_w_m2,150  # the pyranometer reads N W/m² (0: its ADC at the rail)
//! 175,irradiance,clear     # the clear sky's irradiance again
//! 170,power_cycle
//! 180,command,stow         # command,stow|resume|home|clear|service_on|service_off
//! ```
//!
//! Names and keywords are case-sensitive. [`parse_line`] parses one line on
//! its own; [`ScenarioParser`] also numbers lines and checks the order of
//! minutes; [`parse_all`] runs it over a whole text. Errors are typed
//! ([`ScenarioErrorKind`]) and print as e.g.
//! `line 7: unknown event 'wnd_hz'`.

use core::fmt;

use suntracker::safety::AxisId;

/// Most fields kept per line (minute, event and up to three arguments);
/// further fields are only counted, for the error message.
const MAX_FIELDS: usize = 5;
/// Most arguments kept per line.
const MAX_ARGS: usize = MAX_FIELDS - 2;

/// A limit switch's injected state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SwitchState {
    /// Reads closed whatever the axis position.
    StuckClosed,
    /// Reads open whatever the axis position.
    StuckOpen,
    /// Works.
    Ok,
}

/// The real-time clock's injected state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RtcState {
    /// Power loss: the time is reset and the lost-power flag set (once, at
    /// this minute; the clock keeps counting from the reset time).
    LostPower,
    /// Every bus transaction fails from now on.
    BusError,
    /// The bus works again (does not repair a lost time).
    Ok,
}

/// An operator command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    /// Stow the panel.
    Stow,
    /// Resume tracking.
    Resume,
    /// Home the axes.
    Home,
    /// Clear latched faults.
    Clear,
    /// The service lock on: nothing moves until `service_off`, across
    /// power cycles.
    ServiceOn,
    /// The service lock off: the axes home again and tracking follows.
    ServiceOff,
}

/// One scenario event.
///
/// The `bool` of a fault event is `true` when the fault is injected
/// (`stalled`, `failed`) and `false` for `ok`, like the plant's own fault
/// flags; only [`Event::Gps`] is `true` for `on`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Event {
    /// `wind_hz,F`: the anemometer's pulse rate, Hz (finite, ≥ 0).
    WindHz(f64),
    /// `clock_step_s,S`: the RTC and GPS time jump by S seconds.
    ClockStep {
        /// Size of the jump, seconds (either sign).
        seconds: i64,
    },
    /// `gps,off|on`: whether the receiver has a fix (`true` = on).
    Gps(bool),
    /// `gps_position,LAT,LON`: the receiver reports this position.
    GpsPosition {
        /// Reported latitude, degrees north positive (finite, maybe > 90).
        lat_deg: f64,
        /// Reported longitude, degrees east positive (finite, maybe > 180).
        lon_deg: f64,
    },
    /// `gps_date,YYYY-MM-DD`: the receiver reports this date (a valid
    /// calendar date) with its time of day, as with a week rollover.
    GpsDate {
        /// Year, 1..=9999.
        year: u16,
        /// Month, 1..=12.
        month: u8,
        /// Day of the month.
        day: u8,
    },
    /// `rtc,lost_power|bus_error|ok`.
    Rtc(RtcState),
    /// `limit_switch,C|A,stuck_closed|stuck_open|ok`.
    LimitSwitch(AxisId, SwitchState),
    /// `motor,C|A,stalled|ok`: `true` = stalled.
    Motor(AxisId, bool),
    /// `encoder,C|A,failed|ok`: `true` = failed.
    Encoder(AxisId, bool),
    /// `obstruction,C|A,on|off`: an obstacle holds the axis where it is
    /// (`true` = on); a DC motor pushing into it draws its stall current.
    Obstruction(AxisId, bool),
    /// `hall,C|A,failed|ok`: the motor's Hall sensor gives no more pulses
    /// (`true` = failed).
    Hall(AxisId, bool),
    /// `attitude_sensor,failed|ok`: `true` = failed.
    AttitudeSensor(bool),
    /// `snow,on|off`: the snow input reports snow (`true` = on).
    Snow(bool),
    /// `hail,on|off`: the hail warning input is active (`true` = on).
    Hail(bool),
    /// `stow_input,on|off`: the plant's stow contact is active (`true` =
    /// on), at the level the configuration calls active.
    StowInput(bool),
    /// `supply_mv,N|model`: the supply input reads N millivolts (0: an ADC
    /// at its rail, an impossible reading), or the supply model's again
    /// (`None`).
    SupplyMv(Option<u16>),
    /// `irradiance_w_m2,N` / `irradiance,clear`: the pyranometer reads N
    /// W/m² (0: its ADC at the rail, an impossible reading), or the clear
    /// sky's again (`None`).
    Irradiance(Option<u16>),
    /// `set,KEY,VALUE`: a configuration key set as the console's `set`
    /// does (its range checked there: a refused value is the run's error);
    /// the value's text, a number ([`suntracker::console::Decimal`]).
    Set(suntracker::config::Field, Token),
    /// `power_cycle`: the controller restarts.
    PowerCycle,
    /// `command,stow|resume|home|clear|service_on|service_off`.
    Command(Command),
}

/// One parsed line: an event and the minute it happens.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScenarioLine {
    /// Simulated minutes since the start of the run.
    pub minute: u32,
    /// What happens.
    pub event: Event,
}

/// Most bytes of offending text kept in an error.
pub const MAX_TOKEN_LEN: usize = 24;

/// A copy of (the start of) an offending field, so that errors own their
/// text and need neither a lifetime nor a heap.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Token {
    bytes: [u8; MAX_TOKEN_LEN],
    len: usize,
    truncated: bool,
}

impl Token {
    /// Copies `text`, cut at a character boundary to [`MAX_TOKEN_LEN`] bytes.
    pub fn new(text: &str) -> Self {
        let mut len = text.len().min(MAX_TOKEN_LEN);
        while !text.is_char_boundary(len) {
            len -= 1;
        }
        let mut bytes = [0; MAX_TOKEN_LEN];
        if let (Some(dest), Some(src)) = (bytes.get_mut(..len), text.as_bytes().get(..len)) {
            dest.copy_from_slice(src);
        }
        Token {
            bytes,
            len,
            truncated: len < text.len(),
        }
    }

    /// The kept text.
    pub fn as_str(&self) -> &str {
        self.bytes
            .get(..self.len)
            .and_then(|b| core::str::from_utf8(b).ok())
            .unwrap_or("")
    }

    /// Whether the original text was longer than what is kept.
    pub fn is_truncated(&self) -> bool {
        self.truncated
    }
}

impl fmt::Display for Token {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())?;
        if self.truncated {
            f.write_str("...")?;
        }
        Ok(())
    }
}

impl fmt::Debug for Token {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Token({:?}", self.as_str())?;
        if self.truncated {
            f.write_str(", truncated")?;
        }
        f.write_str(")")
    }
}

/// What is wrong with a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScenarioErrorKind {
    /// The first field is not a whole number in 0..=4294967295.
    BadMinute(Token),
    /// Nothing after the minute.
    MissingEvent,
    /// The event name is not one of the known events.
    UnknownEvent(Token),
    /// The event takes a different number of arguments.
    ArgumentCount {
        /// The event's name.
        event: &'static str,
        /// Arguments it takes.
        expected: usize,
        /// Arguments on the line.
        found: usize,
    },
    /// An argument is not an accepted value.
    BadValue {
        /// The event's name.
        event: &'static str,
        /// What is accepted.
        expected: &'static str,
        /// The offending argument.
        value: Token,
    },
    /// The minute is smaller than that of the event before it.
    MinuteBackwards {
        /// This line's minute.
        minute: u32,
        /// The minute of the previous event.
        previous_minute: u32,
    },
}

/// A scenario line that could not be parsed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ScenarioError {
    /// 1-based line number, when known ([`ScenarioParser`] sets it;
    /// [`parse_line`] does not).
    pub line: Option<usize>,
    /// What is wrong.
    pub kind: ScenarioErrorKind,
}

impl From<ScenarioErrorKind> for ScenarioError {
    fn from(kind: ScenarioErrorKind) -> Self {
        ScenarioError { line: None, kind }
    }
}

impl fmt::Display for ScenarioErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScenarioErrorKind::BadMinute(text) => write!(
                f,
                "minute must be a whole number from 0 to {}, got '{text}'",
                u32::MAX
            ),
            ScenarioErrorKind::MissingEvent => f.write_str("missing event after the minute"),
            ScenarioErrorKind::UnknownEvent(name) => write!(f, "unknown event '{name}'"),
            ScenarioErrorKind::ArgumentCount {
                event,
                expected,
                found,
            } => {
                let plural = if *expected == 1 { "" } else { "s" };
                write!(
                    f,
                    "{event} takes {expected} argument{plural}, got {found}"
                )
            }
            ScenarioErrorKind::BadValue {
                event,
                expected,
                value,
            } => write!(f, "{event}: bad value '{value}', expected {expected}"),
            ScenarioErrorKind::MinuteBackwards {
                minute,
                previous_minute,
            } => write!(
                f,
                "minute {minute} comes after minute {previous_minute} (minutes must not go backwards)"
            ),
        }
    }
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.line {
            write!(f, "line {line}: ")?;
        }
        write!(f, "{}", self.kind)
    }
}

/// The arguments of one line (the fields after the event name).
struct Args<'a> {
    fields: [&'a str; MAX_ARGS],
    count: usize,
}

impl<'a> Args<'a> {
    /// Exactly `N` arguments, or an [`ScenarioErrorKind::ArgumentCount`].
    fn exactly<const N: usize>(
        &self,
        event: &'static str,
    ) -> Result<[&'a str; N], ScenarioErrorKind> {
        let count_error = ScenarioErrorKind::ArgumentCount {
            event,
            expected: N,
            found: self.count,
        };
        if self.count != N {
            return Err(count_error);
        }
        self.fields
            .get(..N)
            .and_then(|s| <[&str; N]>::try_from(s).ok())
            .ok_or(count_error)
    }
}

/// A [`ScenarioErrorKind::BadValue`].
fn bad_value(event: &'static str, expected: &'static str, value: &str) -> ScenarioErrorKind {
    ScenarioErrorKind::BadValue {
        event,
        expected,
        value: Token::new(value),
    }
}

/// Looks `text` up in a keyword table.
fn keyword<T: Copy>(
    table: &[(&str, T)],
    event: &'static str,
    expected: &'static str,
    text: &str,
) -> Result<T, ScenarioErrorKind> {
    table
        .iter()
        .find(|(name, _)| *name == text)
        .map(|(_, value)| *value)
        .ok_or_else(|| bad_value(event, expected, text))
}

const AXES: [(&str, AxisId); 2] = [("C", AxisId::C), ("A", AxisId::A)];
const EXPECTED_AXIS: &str = "axis C or A";

fn axis(event: &'static str, text: &str) -> Result<AxisId, ScenarioErrorKind> {
    keyword(&AXES, event, EXPECTED_AXIS, text)
}

/// A finite `f64` (Rust's float syntax; `inf` and `NaN` are refused).
fn finite(
    event: &'static str,
    expected: &'static str,
    text: &str,
) -> Result<f64, ScenarioErrorKind> {
    text.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| bad_value(event, expected, text))
}

/// `n` ASCII digits.
fn digits(text: &str, n: usize) -> Option<u32> {
    if text.len() == n && text.bytes().all(|b| b.is_ascii_digit()) {
        text.parse().ok()
    } else {
        None
    }
}

/// `YYYY-MM-DD`, a valid proleptic-Gregorian date with year 1..=9999.
fn calendar_date(text: &str) -> Option<(u16, u8, u8)> {
    let mut parts = text.split('-');
    let year = u16::try_from(digits(parts.next()?, 4)?).ok()?;
    let month = u8::try_from(digits(parts.next()?, 2)?).ok()?;
    let day = u8::try_from(digits(parts.next()?, 2)?).ok()?;
    if parts.next().is_some() || year == 0 || !(1..=12).contains(&month) {
        return None;
    }
    let days = sun_algos::time::days_in_month(i32::from(year), month);
    (1..=days).contains(&day).then_some((year, month, day))
}

/// The event named `name` with its arguments.
fn parse_event(name: &str, args: &Args<'_>) -> Result<Event, ScenarioErrorKind> {
    let event = match name {
        "wind_hz" => {
            const EXPECTED: &str = "a finite number >= 0 (Hz)";
            let [text] = args.exactly("wind_hz")?;
            let hz = finite("wind_hz", EXPECTED, text)?;
            if hz < 0.0 {
                return Err(bad_value("wind_hz", EXPECTED, text));
            }
            // `+ 0.0` turns -0 into 0.
            Event::WindHz(hz + 0.0)
        }
        "clock_step_s" => {
            let [text] = args.exactly("clock_step_s")?;
            let seconds = text
                .parse::<i64>()
                .map_err(|_| bad_value("clock_step_s", "a whole number of seconds", text))?;
            Event::ClockStep { seconds }
        }
        "gps" => {
            let [text] = args.exactly("gps")?;
            Event::Gps(keyword(
                &[("on", true), ("off", false)],
                "gps",
                "on or off",
                text,
            )?)
        }
        "gps_position" => {
            const EXPECTED: &str = "a finite number of degrees";
            let [lat, lon] = args.exactly("gps_position")?;
            Event::GpsPosition {
                lat_deg: finite("gps_position", EXPECTED, lat)?,
                lon_deg: finite("gps_position", EXPECTED, lon)?,
            }
        }
        "gps_date" => {
            let [text] = args.exactly("gps_date")?;
            let (year, month, day) = calendar_date(text)
                .ok_or_else(|| bad_value("gps_date", "a calendar date YYYY-MM-DD", text))?;
            Event::GpsDate { year, month, day }
        }
        "rtc" => {
            let [text] = args.exactly("rtc")?;
            Event::Rtc(keyword(
                &[
                    ("lost_power", RtcState::LostPower),
                    ("bus_error", RtcState::BusError),
                    ("ok", RtcState::Ok),
                ],
                "rtc",
                "lost_power, bus_error or ok",
                text,
            )?)
        }
        "limit_switch" => {
            let [axis_text, state] = args.exactly("limit_switch")?;
            Event::LimitSwitch(
                axis("limit_switch", axis_text)?,
                keyword(
                    &[
                        ("stuck_closed", SwitchState::StuckClosed),
                        ("stuck_open", SwitchState::StuckOpen),
                        ("ok", SwitchState::Ok),
                    ],
                    "limit_switch",
                    "stuck_closed, stuck_open or ok",
                    state,
                )?,
            )
        }
        "motor" => {
            let [axis_text, state] = args.exactly("motor")?;
            Event::Motor(
                axis("motor", axis_text)?,
                keyword(
                    &[("stalled", true), ("ok", false)],
                    "motor",
                    "stalled or ok",
                    state,
                )?,
            )
        }
        "encoder" => {
            let [axis_text, state] = args.exactly("encoder")?;
            Event::Encoder(
                axis("encoder", axis_text)?,
                keyword(
                    &[("failed", true), ("ok", false)],
                    "encoder",
                    "failed or ok",
                    state,
                )?,
            )
        }
        "obstruction" => {
            let [axis_text, state] = args.exactly("obstruction")?;
            Event::Obstruction(
                axis("obstruction", axis_text)?,
                keyword(
                    &[("on", true), ("off", false)],
                    "obstruction",
                    "on or off",
                    state,
                )?,
            )
        }
        "hall" => {
            let [axis_text, state] = args.exactly("hall")?;
            Event::Hall(
                axis("hall", axis_text)?,
                keyword(
                    &[("failed", true), ("ok", false)],
                    "hall",
                    "failed or ok",
                    state,
                )?,
            )
        }
        "attitude_sensor" => {
            let [state] = args.exactly("attitude_sensor")?;
            Event::AttitudeSensor(keyword(
                &[("failed", true), ("ok", false)],
                "attitude_sensor",
                "failed or ok",
                state,
            )?)
        }
        "snow" | "hail" | "stow_input" => {
            // The event's name as a constant (errors keep it).
            let (event, make): (&'static str, fn(bool) -> Event) = match name {
                "snow" => ("snow", Event::Snow),
                "hail" => ("hail", Event::Hail),
                _ => ("stow_input", Event::StowInput),
            };
            let [state] = args.exactly(event)?;
            make(keyword(
                &[("on", true), ("off", false)],
                event,
                "on or off",
                state,
            )?)
        }
        "supply_mv" => {
            let [text] = args.exactly("supply_mv")?;
            if text == "model" {
                Event::SupplyMv(None)
            } else {
                Event::SupplyMv(Some(text.parse::<u16>().map_err(|_| {
                    bad_value("supply_mv", "millivolts 0 to 65535, or model", text)
                })?))
            }
        }
        "irradiance_w_m2" => {
            let [text] = args.exactly("irradiance_w_m2")?;
            Event::Irradiance(Some(
                text.parse::<u16>()
                    .map_err(|_| bad_value("irradiance_w_m2", "W/m² 0 to 65535", text))?,
            ))
        }
        "irradiance" => {
            let [text] = args.exactly("irradiance")?;
            keyword(
                &[("clear", Event::Irradiance(None))],
                "irradiance",
                "clear",
                text,
            )?
        }
        "set" => {
            let [key, value] = args.exactly("set")?;
            let field = suntracker::console::key_from_name(key)
                .ok_or_else(|| bad_value("set", "a configuration key", key))?;
            let number = Token::new(value);
            if number.truncated || suntracker::console::Decimal::parse(value).is_err() {
                return Err(bad_value("set", "a number", value));
            }
            Event::Set(field, number)
        }
        "power_cycle" => {
            let [] = args.exactly("power_cycle")?;
            Event::PowerCycle
        }
        "command" => {
            let [text] = args.exactly("command")?;
            Event::Command(keyword(
                &[
                    ("stow", Command::Stow),
                    ("resume", Command::Resume),
                    ("home", Command::Home),
                    ("clear", Command::Clear),
                    ("service_on", Command::ServiceOn),
                    ("service_off", Command::ServiceOff),
                ],
                "command",
                "stow, resume, home, clear, service_on or service_off",
                text,
            )?)
        }
        _ => return Err(ScenarioErrorKind::UnknownEvent(Token::new(name))),
    };
    Ok(event)
}

/// Parses one line on its own: `Ok(None)` for a blank or comment line.
/// The order of minutes is not checked (see [`ScenarioParser`]) and the
/// error's `line` is `None`.
pub fn parse_line(line: &str) -> Result<Option<ScenarioLine>, ScenarioError> {
    let content = line.split('#').next().unwrap_or("").trim();
    if content.is_empty() {
        return Ok(None);
    }
    let mut fields = [""; MAX_FIELDS];
    let mut count = 0usize;
    for (slot, field) in content.split(',').enumerate() {
        if let Some(dest) = fields.get_mut(slot) {
            *dest = field.trim();
        }
        count = count.saturating_add(1);
    }
    let [minute_text, name, a0, a1, a2] = fields;
    let minute = if !minute_text.is_empty() && minute_text.bytes().all(|b| b.is_ascii_digit()) {
        minute_text.parse::<u32>().ok()
    } else {
        None
    }
    .ok_or(ScenarioErrorKind::BadMinute(Token::new(minute_text)))?;
    if name.is_empty() {
        return Err(ScenarioErrorKind::MissingEvent.into());
    }
    let args = Args {
        fields: [a0, a1, a2],
        count: count.saturating_sub(2),
    };
    let event = parse_event(name, &args)?;
    Ok(Some(ScenarioLine { minute, event }))
}

/// Parses a scenario line by line: numbers the lines (from 1) and checks
/// that minutes do not go backwards.
#[derive(Debug, Clone, Default)]
pub struct ScenarioParser {
    line_number: usize,
    previous_minute: Option<u32>,
}

impl ScenarioParser {
    /// A parser before the first line.
    pub const fn new() -> Self {
        ScenarioParser {
            line_number: 0,
            previous_minute: None,
        }
    }

    /// Parses the next line of the file (`Ok(None)` for a blank or comment
    /// line); the error carries the line number.
    pub fn parse_next(&mut self, line: &str) -> Result<Option<ScenarioLine>, ScenarioError> {
        self.line_number = self.line_number.saturating_add(1);
        let at_line = |mut e: ScenarioError| {
            e.line = Some(self.line_number);
            e
        };
        let parsed = parse_line(line).map_err(at_line)?;
        if let Some(l) = parsed {
            if let Some(previous_minute) = self.previous_minute.filter(|p| l.minute < *p) {
                return Err(at_line(
                    ScenarioErrorKind::MinuteBackwards {
                        minute: l.minute,
                        previous_minute,
                    }
                    .into(),
                ));
            }
            self.previous_minute = Some(l.minute);
        }
        Ok(parsed)
    }

    /// Number of the last line given to [`ScenarioParser::parse_next`]
    /// (0 before the first).
    pub fn line_number(&self) -> usize {
        self.line_number
    }
}

/// Parses a whole scenario text: one item per event, in file order, or per
/// bad line `(1-based line number, error)`. Parsing goes on after an error;
/// a line with an error does not count for the order of minutes.
pub fn parse_all(
    text: &str,
) -> impl Iterator<Item = Result<ScenarioLine, (usize, ScenarioError)>> + '_ {
    let mut parser = ScenarioParser::new();
    text.lines()
        .filter_map(move |line| match parser.parse_next(line) {
            Ok(Some(l)) => Some(Ok(l)),
            Ok(None) => None,
            Err(e) => Some(Err((parser.line_number(), e))),
        })
}

impl fmt::Display for Event {
    /// The event as written in a scenario file, e.g. `motor,A,stalled`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let axis_name = |a: &AxisId| match a {
            AxisId::C => "C",
            AxisId::A => "A",
        };
        let fault = |failed: &bool, word: &'static str| if *failed { word } else { "ok" };
        match self {
            Event::WindHz(hz) => write!(f, "wind_hz,{hz}"),
            Event::ClockStep { seconds } => write!(f, "clock_step_s,{seconds}"),
            Event::Gps(on) => write!(f, "gps,{}", if *on { "on" } else { "off" }),
            Event::GpsPosition { lat_deg, lon_deg } => {
                write!(f, "gps_position,{lat_deg},{lon_deg}")
            }
            Event::GpsDate { year, month, day } => {
                write!(f, "gps_date,{year:04}-{month:02}-{day:02}")
            }
            Event::Rtc(state) => f.write_str(match state {
                RtcState::LostPower => "rtc,lost_power",
                RtcState::BusError => "rtc,bus_error",
                RtcState::Ok => "rtc,ok",
            }),
            Event::LimitSwitch(a, state) => {
                let state = match state {
                    SwitchState::StuckClosed => "stuck_closed",
                    SwitchState::StuckOpen => "stuck_open",
                    SwitchState::Ok => "ok",
                };
                write!(f, "limit_switch,{},{state}", axis_name(a))
            }
            Event::Motor(a, stalled) => {
                write!(f, "motor,{},{}", axis_name(a), fault(stalled, "stalled"))
            }
            Event::Encoder(a, failed) => {
                write!(f, "encoder,{},{}", axis_name(a), fault(failed, "failed"))
            }
            Event::Obstruction(a, on) => {
                let state = if *on { "on" } else { "off" };
                write!(f, "obstruction,{},{state}", axis_name(a))
            }
            Event::Hall(a, failed) => {
                write!(f, "hall,{},{}", axis_name(a), fault(failed, "failed"))
            }
            Event::AttitudeSensor(failed) => {
                write!(f, "attitude_sensor,{}", fault(failed, "failed"))
            }
            Event::Snow(on) | Event::Hail(on) | Event::StowInput(on) => {
                let name = match self {
                    Event::Snow(_) => "snow",
                    Event::Hail(_) => "hail",
                    _ => "stow_input",
                };
                write!(f, "{name},{}", if *on { "on" } else { "off" })
            }
            Event::SupplyMv(Some(mv)) => write!(f, "supply_mv,{mv}"),
            Event::SupplyMv(None) => f.write_str("supply_mv,model"),
            Event::Irradiance(Some(w)) => write!(f, "irradiance_w_m2,{w}"),
            Event::Irradiance(None) => f.write_str("irradiance,clear"),
            Event::Set(key, value) => write!(f, "set,{},{}", key.name(), value.as_str()),
            Event::PowerCycle => f.write_str("power_cycle"),
            Event::Command(c) => f.write_str(match c {
                Command::Stow => "command,stow",
                Command::Resume => "command,resume",
                Command::Home => "command,home",
                Command::Clear => "command,clear",
                Command::ServiceOn => "command,service_on",
                Command::ServiceOff => "command,service_off",
            }),
        }
    }
}

impl fmt::Display for ScenarioLine {
    /// The line as written in a scenario file, e.g. `120,rtc,lost_power`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{}", self.minute, self.event)
    }
}
