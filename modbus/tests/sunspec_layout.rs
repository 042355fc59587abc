//! The map's layout against the SunSpec Alliance's model definitions.
//!
//! `tests/data/sunspec_points.tsv` is written by
//! `modbus/sunspec/expected_points.py` from the JSON models that the
//! `pysunspec2` package ships (SunSpec Information Model Reference: model 1
//! Common, model 601 Tracker Controller, model 305 GPS) and from the vendor
//! model's definition `modbus/sunspec/model_64201.json`; nothing in it is
//! taken from this crate.

mod common;

use suntracker_modbus::sunspec::{
    alarm, m1, m305, m601, m64201, Control, SunSpecMap, DGR_SF, WND_SPD_SF,
};
use suntracker_modbus::{Exception, RegisterMap};

struct Row {
    model: u16,
    point: String,
    offset: u16,
    size: u16,
    ty: String,
    sf: String,
    access: String,
    symbols: String,
}

fn rows() -> Vec<Row> {
    let text = include_str!("data/sunspec_points.tsv");
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let c: Vec<&str> = l.split('\t').collect();
            assert_eq!(c.len(), 9, "{l}");
            Row {
                model: c[0].parse().unwrap(),
                point: c[1].to_string(),
                offset: c[2].parse().unwrap(),
                size: c[3].parse().unwrap(),
                ty: c[4].to_string(),
                sf: c[5].to_string(),
                access: c[7].to_string(),
                symbols: c[8].to_string(),
            }
        })
        .collect()
}

/// Each point's offset and size as this crate has them, by the models' names.
const OURS: &[(u16, &str, u16, u16)] = &[
    (1, "ID", 0, 1),
    (1, "L", 1, 1),
    (1, "Mn", m1::MN, 16),
    (1, "Md", m1::MD, 16),
    (1, "Opt", m1::OPT, 8),
    (1, "Vr", m1::VR, 8),
    (1, "SN", m1::SN, 16),
    (1, "DA", m1::DA, 1),
    (1, "Pad", m1::PAD, 1),
    (601, "ID", 0, 1),
    (601, "L", 1, 1),
    (601, "Nam", m601::NAM, 8),
    (601, "Typ", m601::TYP, 1),
    (601, "DtLoc", m601::DT_LOC, 5),
    (601, "TmLoc", m601::TM_LOC, 3),
    (601, "Day", m601::DAY, 1),
    (601, "GlblElCtl", m601::GLBL_EL_CTL, 2),
    (601, "GlblAzCtl", m601::GLBL_AZ_CTL, 2),
    (601, "GlblCtl", m601::GLBL_CTL, 1),
    (601, "GlblAlm", m601::GLBL_ALM, 1),
    (601, "Dgr_SF", m601::DGR_SF, 1),
    (601, "N", m601::N, 1),
    (601, "tracker.Id", m601::TRK_ID, 8),
    (601, "tracker.ElTrgt", m601::EL_TRGT, 2),
    (601, "tracker.AzTrgt", m601::AZ_TRGT, 2),
    (601, "tracker.ElPos", m601::EL_POS, 2),
    (601, "tracker.AzPos", m601::AZ_POS, 2),
    (601, "tracker.ElCtl", m601::EL_CTL, 2),
    (601, "tracker.AzCtl", m601::AZ_CTL, 2),
    (601, "tracker.Ctl", m601::CTL, 1),
    (601, "tracker.Alm", m601::ALM, 1),
    (305, "ID", 0, 1),
    (305, "L", 1, 1),
    (305, "Tm", m305::TM, 6),
    (305, "Date", m305::DATE, 4),
    (305, "Loc", m305::LOC, 20),
    (305, "Lat", m305::LAT, 2),
    (305, "Long", m305::LONG, 2),
    (305, "Alt", m305::ALT, 2),
    (64201, "ID", 0, 1),
    (64201, "L", 1, 1),
    (64201, "Mode", m64201::MODE, 1),
    (64201, "StowRsn", m64201::STOW_RSN, 1),
    (64201, "WndSpd", m64201::WND_SPD, 1),
    (64201, "WndSpd_SF", m64201::WND_SPD_SF, 1),
    (64201, "Flt", m64201::FLT, 2),
    (64201, "FwMaj", m64201::FW_MAJ, 1),
    (64201, "FwMin", m64201::FW_MIN, 1),
    (64201, "FwPat", m64201::FW_PAT, 1),
    (64201, "Stow", m64201::STOW, 1),
    (64201, "Flt2", m64201::FLT2, 1),
    (64201, "ClrFlt", m64201::CLR_FLT, 1),
];

#[test]
fn every_point_at_its_offset() {
    let rows = rows();
    let points: Vec<&Row> = rows.iter().filter(|r| r.point != "(L)").collect();
    assert_eq!(
        points.len(),
        OURS.len(),
        "every point of the models, no other"
    );
    for r in &points {
        let ours = OURS.iter().find(|o| o.0 == r.model && o.1 == r.point);
        let &(_, _, offset, size) =
            ours.unwrap_or_else(|| panic!("{} {} missing", r.model, r.point));
        assert_eq!(
            (offset, size),
            (r.offset, r.size),
            "{} {}",
            r.model,
            r.point
        );
    }
}

#[test]
fn model_lengths() {
    let len = |model| {
        rows()
            .into_iter()
            .find(|r| r.model == model && r.point == "(L)")
            .unwrap()
            .offset
    };
    assert_eq!(m1::LEN, len(1));
    // 601: the fixed block and one tracker block.
    assert_eq!(m601::LEN, len(601));
    assert_eq!(m601::FIXED_LEN + 2, m601::TRK_ID);
    assert_eq!(m305::LEN, len(305));
    assert_eq!(m64201::LEN, len(64201));
}

#[test]
fn the_models_follow_one_another() {
    for gps in [false, true] {
        let map = SunSpecMap::new(common::Demo::new(1, gps), gps);
        assert_eq!(map.common_addr(), 40002);
        assert_eq!(map.tracker_addr(), map.common_addr() + 2 + m1::LEN);
        let after_tracker = map.tracker_addr() + 2 + m601::LEN;
        assert_eq!(map.gps_addr(), gps.then_some(after_tracker));
        assert_eq!(
            map.vendor_addr(),
            if gps {
                after_tracker + 2 + m305::LEN
            } else {
                after_tracker
            }
        );
        assert_eq!(map.end_addr(), map.vendor_addr() + 2 + m64201::LEN);
    }
}

fn row(model: u16, point: &str) -> Row {
    rows()
        .into_iter()
        .find(|r| r.model == model && r.point == point)
        .unwrap()
}

#[test]
fn types_scale_factors_and_symbols() {
    // Every angle is an int32 scaled by Dgr_SF (a sunssf point), which we set to -2 (`_cdeg`).
    for p in [
        "GlblElCtl",
        "GlblAzCtl",
        "tracker.ElTrgt",
        "tracker.AzTrgt",
        "tracker.ElPos",
        "tracker.AzPos",
    ] {
        let r = row(601, p);
        assert_eq!((r.ty.as_str(), r.sf.as_str()), ("int32", "Dgr_SF"), "{p}");
    }
    assert_eq!(row(601, "Dgr_SF").ty, "sunssf");
    assert_eq!(DGR_SF, -2);
    // GPS: degrees × 10⁻⁷ (`_e7deg`), metres.
    assert_eq!(row(305, "Lat").sf, "-7");
    assert_eq!(row(305, "Long").sf, "-7");
    assert_eq!(row(64201, "WndSpd").sf, "WndSpd_SF");
    assert_eq!(WND_SPD_SF, -1);
    // Enumerations and bits.
    let ctl = format!(
        "Automatic={},Manual={},Calibrate={}",
        Control::Automatic as u16,
        Control::Manual as u16,
        Control::Calibrate as u16
    );
    assert_eq!(row(601, "GlblCtl").symbols, ctl);
    assert_eq!(row(601, "tracker.Ctl").symbols, ctl);
    let bits = |b: u16| b.trailing_zeros();
    let alm = format!(
        "SetPoint={},ObsEl={},ObsAz={}",
        bits(alarm::SET_POINT),
        bits(alarm::OBS_EL),
        bits(alarm::OBS_AZ)
    );
    assert_eq!(row(601, "GlblAlm").symbols, alm);
    assert_eq!(row(601, "tracker.Alm").symbols, alm);
    assert!(row(601, "Typ")
        .symbols
        .split(',')
        .any(|s| s == format!("Dual={}", m601::TYP_DUAL)));
}

#[test]
fn writable_exactly_where_the_models_say() {
    let rows = rows();
    for r in rows.iter().filter(|r| r.point != "(L)") {
        let mut map = SunSpecMap::new(common::Demo::new(1, true), true);
        let base = match r.model {
            1 => map.common_addr(),
            601 => map.tracker_addr(),
            305 => map.gps_addr().unwrap(),
            _ => map.vendor_addr(),
        };
        // A value every writable point takes: 1.
        let mut values = vec![0_u8; usize::from(r.size) * 2];
        let last = values.len() - 1;
        values[last] = 1;
        let result = map.write(base + r.offset, &values, false);
        if r.access == "RW" {
            assert_eq!(result, Ok(()), "{} {}", r.model, r.point);
        } else {
            assert_eq!(
                result,
                Err(Exception::IllegalDataAddress),
                "{} {}",
                r.model,
                r.point
            );
        }
    }
}
