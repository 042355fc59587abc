//! `sim::scenario`: every event, every error kind, comments, CRLF, spacing,
//! line numbers and the order of minutes.

use sim::scenario::{
    parse_all, parse_line, Command, Event, RtcState, ScenarioError, ScenarioErrorKind,
    ScenarioLine, ScenarioParser, SwitchState, Token, MAX_TOKEN_LEN,
};
use suntracker::safety::AxisId;

fn event(line: &str) -> Event {
    match parse_line(line) {
        Ok(Some(l)) => l.event,
        other => panic!("{line:?}: {other:?}"),
    }
}

fn kind(line: &str) -> ScenarioErrorKind {
    match parse_line(line) {
        Err(e) => {
            assert_eq!(e.line, None);
            e.kind
        }
        other => panic!("{line:?} should fail: {other:?}"),
    }
}

/// The error message of a one-line parse (no line number).
fn message(line: &str) -> String {
    parse_line(line).unwrap_err().to_string()
}

#[test]
fn every_event_parses() {
    use AxisId::{A, C};
    let cases: Vec<(&str, Event)> = vec![
        ("0,wind_hz,2.5", Event::WindHz(2.5)),
        ("0,wind_hz,0", Event::WindHz(0.0)),
        ("0,wind_hz,1e2", Event::WindHz(100.0)),
        ("0,clock_step_s,-3600", Event::ClockStep { seconds: -3600 }),
        ("0,clock_step_s,86400", Event::ClockStep { seconds: 86_400 }),
        (
            "0,clock_step_s,-9223372036854775808",
            Event::ClockStep { seconds: i64::MIN },
        ),
        ("0,gps,off", Event::Gps(false)),
        ("0,gps,on", Event::Gps(true)),
        (
            "0,gps_position,11.9683,8.4261",
            Event::GpsPosition {
                lat_deg: 11.9683,
                lon_deg: 8.4261,
            },
        ),
        (
            "0,gps_position,91,-200.5",
            Event::GpsPosition {
                lat_deg: 91.0,
                lon_deg: -200.5,
            },
        ),
        (
            "0,gps_date,2006-04-16",
            Event::GpsDate {
                year: 2006,
                month: 4,
                day: 16,
            },
        ),
        (
            "0,gps_date,2024-02-29",
            Event::GpsDate {
                year: 2024,
                month: 2,
                day: 29,
            },
        ),
        ("0,rtc,lost_power", Event::Rtc(RtcState::LostPower)),
        ("0,rtc,bus_error", Event::Rtc(RtcState::BusError)),
        ("0,rtc,ok", Event::Rtc(RtcState::Ok)),
        (
            "0,limit_switch,C,stuck_closed",
            Event::LimitSwitch(C, SwitchState::StuckClosed),
        ),
        (
            "0,limit_switch,A,stuck_open",
            Event::LimitSwitch(A, SwitchState::StuckOpen),
        ),
        (
            "0,limit_switch,A,ok",
            Event::LimitSwitch(A, SwitchState::Ok),
        ),
        ("0,motor,C,stalled", Event::Motor(C, true)),
        ("0,motor,A,ok", Event::Motor(A, false)),
        ("0,encoder,A,failed", Event::Encoder(A, true)),
        ("0,encoder,C,ok", Event::Encoder(C, false)),
        ("0,obstruction,A,on", Event::Obstruction(A, true)),
        ("0,obstruction,C,off", Event::Obstruction(C, false)),
        ("0,hall,C,failed", Event::Hall(C, true)),
        ("0,hall,A,ok", Event::Hall(A, false)),
        ("0,attitude_sensor,failed", Event::AttitudeSensor(true)),
        ("0,attitude_sensor,ok", Event::AttitudeSensor(false)),
        ("0,power_cycle", Event::PowerCycle),
        ("0,command,stow", Event::Command(Command::Stow)),
        ("0,command,resume", Event::Command(Command::Resume)),
        ("0,command,home", Event::Command(Command::Home)),
        ("0,command,clear", Event::Command(Command::Clear)),
    ];
    for (line, expected) in cases {
        assert_eq!(event(line), expected, "{line}");
        // Display writes the file syntax back, and it parses to the same.
        let shown = ScenarioLine {
            minute: 7,
            event: expected,
        }
        .to_string();
        assert_eq!(
            parse_line(&shown),
            Ok(Some(ScenarioLine {
                minute: 7,
                event: expected
            })),
            "{shown}"
        );
    }
    // -0 Hz is 0 Hz.
    assert!(matches!(event("0,wind_hz,-0"), Event::WindHz(hz) if hz.is_sign_positive()));
}

#[test]
fn minutes_from_zero_to_u32_max() {
    assert_eq!(parse_line("0,power_cycle").unwrap().unwrap().minute, 0);
    assert_eq!(
        parse_line("1440,power_cycle").unwrap().unwrap().minute,
        1440
    );
    assert_eq!(parse_line("007,power_cycle").unwrap().unwrap().minute, 7);
    let max = format!("{},power_cycle", u32::MAX);
    assert_eq!(parse_line(&max).unwrap().unwrap().minute, u32::MAX);
}

#[test]
fn blank_and_comment_lines_are_skipped() {
    for line in [
        "",
        "   ",
        "\t",
        "\r",
        "# a comment",
        "   # indented, with, commas",
        "#",
    ] {
        assert_eq!(parse_line(line), Ok(None), "{line:?}");
    }
    assert_eq!(event("5,gps,off # receiver unplugged"), Event::Gps(false));
    assert_eq!(event("5,power_cycle#no space"), Event::PowerCycle);
    // A comment hides everything after it, including extra fields.
    assert_eq!(event("5,gps,on # ,extra,fields"), Event::Gps(true));
}

#[test]
fn whitespace_and_crlf_are_accepted() {
    let expected = Some(ScenarioLine {
        minute: 12,
        event: Event::LimitSwitch(AxisId::C, SwitchState::StuckOpen),
    });
    for line in [
        "12,limit_switch,C,stuck_open",
        "12,limit_switch,C,stuck_open\r",
        "  12 , limit_switch ,\tC\t, stuck_open  ",
        "\t12,limit_switch,C,stuck_open # why\r",
    ] {
        assert_eq!(parse_line(line), Ok(expected), "{line:?}");
    }
}

#[test]
fn bad_minutes() {
    for (line, text) in [
        ("1.5,power_cycle", "1.5"),
        ("-1,power_cycle", "-1"),
        ("+1,power_cycle", "+1"),
        ("x,power_cycle", "x"),
        (",power_cycle", ""),
        ("4294967296,power_cycle", "4294967296"),
        ("1 2,power_cycle", "1 2"),
        ("wind_hz,3", "wind_hz"),
    ] {
        assert_eq!(
            kind(line),
            ScenarioErrorKind::BadMinute(Token::new(text)),
            "{line}"
        );
    }
    assert_eq!(
        message("1.5,power_cycle"),
        "minute must be a whole number from 0 to 4294967295, got '1.5'"
    );
}

#[test]
fn missing_and_unknown_events() {
    for line in ["5", "5,", "5, ,3", "  5  # only a minute"] {
        assert_eq!(kind(line), ScenarioErrorKind::MissingEvent, "{line:?}");
    }
    assert_eq!(message("5"), "missing event after the minute");
    assert_eq!(
        kind("7,wnd_hz,3"),
        ScenarioErrorKind::UnknownEvent(Token::new("wnd_hz"))
    );
    assert_eq!(message("7,wnd_hz,3"), "unknown event 'wnd_hz'");
    // Names are case-sensitive.
    assert_eq!(
        kind("7,Wind_Hz,3"),
        ScenarioErrorKind::UnknownEvent(Token::new("Wind_Hz"))
    );
    // Long text is cut in the error (at a character boundary) and marked.
    let long = format!("7,{}", "é".repeat(40));
    let ScenarioErrorKind::UnknownEvent(token) = kind(&long) else {
        panic!()
    };
    assert!(token.is_truncated());
    assert!(token.as_str().len() <= MAX_TOKEN_LEN);
    assert_eq!(token.as_str(), "é".repeat(MAX_TOKEN_LEN / 2));
    assert_eq!(
        message(&long),
        format!("unknown event '{}...'", "é".repeat(MAX_TOKEN_LEN / 2))
    );
}

#[test]
fn wrong_argument_counts() {
    let cases: [(&str, &str, usize, usize); 16] = [
        ("0,wind_hz", "wind_hz", 1, 0),
        ("0,wind_hz,1,2", "wind_hz", 1, 2),
        ("0,clock_step_s", "clock_step_s", 1, 0),
        ("0,gps", "gps", 1, 0),
        ("0,gps_position,1", "gps_position", 2, 1),
        ("0,gps_position,1,2,3", "gps_position", 2, 3),
        ("0,gps_date", "gps_date", 1, 0),
        ("0,rtc,ok,ok", "rtc", 1, 2),
        ("0,limit_switch,C", "limit_switch", 2, 1),
        ("0,motor,stalled", "motor", 2, 1),
        ("0,encoder,A,failed,now", "encoder", 2, 3),
        ("0,attitude_sensor", "attitude_sensor", 1, 0),
        ("0,power_cycle,now", "power_cycle", 0, 1),
        ("0,power_cycle,", "power_cycle", 0, 1),
        ("0,command", "command", 1, 0),
        ("0,command,stow,a,b,c,d,e", "command", 1, 6),
    ];
    for (line, event, expected, found) in cases {
        assert_eq!(
            kind(line),
            ScenarioErrorKind::ArgumentCount {
                event,
                expected,
                found
            },
            "{line}"
        );
    }
    assert_eq!(message("0,wind_hz,1,2"), "wind_hz takes 1 argument, got 2");
    assert_eq!(
        message("0,gps_position,1"),
        "gps_position takes 2 arguments, got 1"
    );
    assert_eq!(
        message("0,power_cycle,now"),
        "power_cycle takes 0 arguments, got 1"
    );
}

#[test]
fn bad_values() {
    let cases: [(&str, &str, &str); 28] = [
        ("0,wind_hz,-1", "wind_hz", "-1"),
        ("0,wind_hz,inf", "wind_hz", "inf"),
        ("0,wind_hz,NaN", "wind_hz", "NaN"),
        ("0,wind_hz,fast", "wind_hz", "fast"),
        ("0,wind_hz,", "wind_hz", ""),
        ("0,clock_step_s,1.5", "clock_step_s", "1.5"),
        (
            "0,clock_step_s,9223372036854775808",
            "clock_step_s",
            "9223372036854775808",
        ),
        ("0,gps,maybe", "gps", "maybe"),
        ("0,gps,ON", "gps", "ON"),
        ("0,gps_position,north,8", "gps_position", "north"),
        ("0,gps_position,12,inf", "gps_position", "inf"),
        ("0,gps_position,1e999,0", "gps_position", "1e999"),
        ("0,gps_date,2025-02-29", "gps_date", "2025-02-29"),
        ("0,gps_date,2025-13-01", "gps_date", "2025-13-01"),
        ("0,gps_date,2025-04-31", "gps_date", "2025-04-31"),
        ("0,gps_date,0000-01-01", "gps_date", "0000-01-01"),
        ("0,gps_date,2025-1-01", "gps_date", "2025-1-01"),
        ("0,gps_date,2025-01-01-01", "gps_date", "2025-01-01-01"),
        ("0,gps_date,20250101", "gps_date", "20250101"),
        ("0,gps_date,2025-+1-01", "gps_date", "2025-+1-01"),
        ("0,rtc,broken", "rtc", "broken"),
        ("0,limit_switch,B,ok", "limit_switch", "B"),
        ("0,limit_switch,C,stuck", "limit_switch", "stuck"),
        ("0,motor,c,ok", "motor", "c"),
        ("0,motor,C,failed", "motor", "failed"),
        ("0,encoder,A,stalled", "encoder", "stalled"),
        ("0,attitude_sensor,stalled", "attitude_sensor", "stalled"),
        ("0,command,go", "command", "go"),
    ];
    for (line, event, value) in cases {
        match kind(line) {
            ScenarioErrorKind::BadValue {
                event: e, value: v, ..
            } => {
                assert_eq!((e, v.as_str()), (event, value), "{line}");
            }
            other => panic!("{line}: {other:?}"),
        }
    }
    assert_eq!(
        message("0,wind_hz,-3"),
        "wind_hz: bad value '-3', expected a finite number >= 0 (Hz)"
    );
    assert_eq!(
        message("0,motor,B,ok"),
        "motor: bad value 'B', expected axis C or A"
    );
    assert_eq!(
        message("0,gps_date,2025-02-29"),
        "gps_date: bad value '2025-02-29', expected a calendar date YYYY-MM-DD"
    );
}

#[test]
fn parser_numbers_lines_and_refuses_minutes_going_backwards() {
    let mut p = ScenarioParser::new();
    assert_eq!(p.line_number(), 0);
    assert!(p.parse_next("# header").unwrap().is_none());
    assert!(p.parse_next("10,gps,off").unwrap().is_some());
    assert!(p.parse_next("10,gps,on").unwrap().is_some(), "same minute");
    let e = p.parse_next("9,power_cycle").unwrap_err();
    assert_eq!(
        e,
        ScenarioError {
            line: Some(4),
            kind: ScenarioErrorKind::MinuteBackwards {
                minute: 9,
                previous_minute: 10
            }
        }
    );
    assert_eq!(
        e.to_string(),
        "line 4: minute 9 comes after minute 10 (minutes must not go backwards)"
    );
    // The bad line does not move the order on; a later good one is fine.
    assert!(p.parse_next("").unwrap().is_none());
    assert!(p.parse_next("10,power_cycle").unwrap().is_some());
    let e = p.parse_next("11,wnd_hz,3").unwrap_err();
    assert_eq!(e.line, Some(7));
    assert_eq!(e.to_string(), "line 7: unknown event 'wnd_hz'");
}

#[test]
fn parse_all_keeps_file_order_and_reports_line_numbers() {
    let text = "# scenario: a windy afternoon\r\n\
                \r\n\
                0, wind_hz, 2.5\r\n\
                60,clock_step_s,-3600 # bad sync\r\n\
                60,rtc,lost_power\r\n\
                60,command,stow\r\n\
                x,power_cycle\r\n\
                120,gps,off\n\
                100,gps,on\n\
                130,motor,A,stalled";
    let items: Vec<_> = parse_all(text).collect();
    let line = |minute, event| Ok(ScenarioLine { minute, event });
    assert_eq!(
        items,
        vec![
            line(0, Event::WindHz(2.5)),
            line(60, Event::ClockStep { seconds: -3600 }),
            line(60, Event::Rtc(RtcState::LostPower)),
            line(60, Event::Command(Command::Stow)),
            Err((
                7,
                ScenarioError {
                    line: Some(7),
                    kind: ScenarioErrorKind::BadMinute(Token::new("x"))
                }
            )),
            line(120, Event::Gps(false)),
            Err((
                9,
                ScenarioError {
                    line: Some(9),
                    kind: ScenarioErrorKind::MinuteBackwards {
                        minute: 100,
                        previous_minute: 120
                    }
                }
            )),
            line(130, Event::Motor(AxisId::A, true)),
        ]
    );
    assert_eq!(
        items[4].as_ref().unwrap_err().1.to_string(),
        "line 7: minute must be a whole number from 0 to 4294967295, got 'x'"
    );
    // Collecting into a Result stops at the first error.
    let first: Result<Vec<_>, _> = parse_all(text).collect();
    assert_eq!(first.unwrap_err().0, 7);
    assert_eq!(parse_all("").count(), 0);
    assert_eq!(parse_all("# only\n\n#comments\r\n").count(), 0);
}
