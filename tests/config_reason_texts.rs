//! The texts of the configuration's ranges and rules (`Reason::text`), as
//! the console prints them after `error <key>: `. They are the product's
//! documented replies, written out here as they were before the texts were
//! built from `config::ranges`; a change to a range that changes a reply
//! fails this test.

use suntracker::config::Reason;

/// The documented text of each reason; a `match` without a wildcard, so a
/// new reason does not compile until its text is written here.
fn expected(r: Reason) -> &'static str {
    match r {
        Reason::CountsPerMotorRev => {
            "1...16,777,216 full steps or encoder counts per motor revolution"
        }
        Reason::Microsteps => "1...256 microsteps per full step",
        Reason::GearRatio => "1...10,000 motor revolutions per axis revolution",
        Reason::CountsPerDeg => {
            "counts * microsteps * gear / 360 must be 1...1,000,000 counts per degree"
        }
        Reason::LimitDeg => "-360...360 deg",
        Reason::AboveMinDeg => "must be above min_deg",
        Reason::HomeNearMinDeg => {
            "min_deg - 5 deg ... min_deg + 10 deg and at most max_deg: \
             the switch is at the low end of the travel"
        }
        Reason::Deg0To5 => "0...5 deg",
        Reason::SpeedDegS => "0.01...30 deg/s",
        Reason::Latitude => "-90...90 deg",
        Reason::Deg180 => "-180...180 deg",
        Reason::ElevationM => "-500...10,000 m",
        Reason::TableStepS => "60...43,200 s",
        Reason::WholeMinutesOfDay => "whole minutes dividing a day (86,400 s)",
        Reason::S0To3600 => "0...3,600 s",
        Reason::S1To3600 => "1...3,600 s",
        Reason::S1To86400 => "1...86,400 s",
        Reason::S0To86400 => "0...86,400 s",
        Reason::StowHz => "0.1...1,000 Hz",
        Reason::S0To600 => "0...600 s",
        Reason::MaxDeviationDeg => "0.1...45 deg",
        Reason::S1To600 => "1...600 s",
        Reason::MaxRetries => "0...20",
        Reason::BelowMaxDeviation => "must be below safety.max_deviation_deg",
        Reason::TiltOffsetDeg => "-45...45 deg",
        Reason::StatusMin => "0...1,440 min (0: no periodic status line)",
    }
}

#[test]
fn every_reason_prints_its_documented_text() {
    assert_eq!(Reason::ALL.len(), 26);
    let mut wrong = Vec::new();
    for &r in Reason::ALL {
        let text = r.text();
        println!("{text}");
        if text != expected(r) {
            wrong.push(format!("{text:?} (expected {:?})", expected(r)));
        }
        // The other ways of reading a reason agree with `text`.
        assert_eq!(format!("{r}"), text.as_str());
        assert_eq!(format!("{r:?}"), text.as_str());
        assert_eq!(r == expected(r), text == expected(r));
    }
    assert!(wrong.is_empty(), "texts changed:\n{}", wrong.join("\n"));
}

#[test]
fn reasons_are_distinct() {
    for (i, &a) in Reason::ALL.iter().enumerate() {
        for &b in &Reason::ALL[i + 1..] {
            assert_ne!(a.text(), b.text());
        }
    }
}
