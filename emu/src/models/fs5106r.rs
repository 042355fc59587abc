//! FEETECH FS5106R continuous-rotation servo (Chowdhury et al.'s (2019) axis
//! drive): the pulse width sets the output shaft's speed. The model, its
//! figures and their sources are `sim::servo` (the host tests' servo plants
//! use its pulse-to-speed law too); the Uno bench takes the pulses it
//! decodes from the pin to [`Fs5106r::pulse`] and times the encoder edges
//! on [`Fs5106r::segments_to`].

pub use sim::servo::{Fs5106r, Segment, ServoSpec, FRAME_S};

#[cfg(test)]
mod tests {
    use super::*;

    /// 95 rpm (Chowdhury et al. 2019, FEETECH) in °/s: 95 × 360 / 60.
    const FULL_DEG_S: f64 = 570.0;

    /// Drives `servo` with `width_us` pulses every 20 ms over `[from, to)`.
    fn drive(servo: &mut Fs5106r, width_us: f64, from_s: f64, to_s: f64) {
        let frames = ((to_s - from_s) / FRAME_S).round() as i64;
        for k in 0..frames {
            servo.pulse(from_s + k as f64 * FRAME_S, width_us);
        }
        servo.advance_to(to_s);
    }

    fn within(actual: f64, expected: f64, rel: f64) -> bool {
        (actual - expected).abs() <= rel * expected.abs()
    }

    #[test]
    fn dead_band_gives_no_motion() {
        for width in [1_500.0, 1_497.0, 1_503.0, 1_496.0, 1_504.0] {
            let mut s = Fs5106r::at_6v(12.5, 0.0);
            drive(&mut s, width, 0.0, 30.0);
            assert_eq!(s.angle_deg(), 12.5, "{width} µs");
            assert_eq!(s.pulses, 1_500);
        }
        // Just outside it, it creeps.
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut s, 1_505.0, 0.0, 30.0);
        assert!(s.angle_deg() > 0.0);
    }

    #[test]
    fn full_pulse_is_95_rpm() {
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut s, 2_300.0, 0.0, 60.0);
        // 95 revolutions in a minute.
        assert!(
            within(s.angle_deg(), 95.0 * 360.0, 0.01),
            "{}",
            s.angle_deg()
        );
        assert!(within(s.speed_deg_s(59.99), FULL_DEG_S, 0.01));
        // Wider than the range: saturated, not faster.
        let mut w = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut w, 2_500.0, 0.0, 60.0);
        assert!(within(w.angle_deg(), 95.0 * 360.0, 0.01));
    }

    #[test]
    fn narrow_pulse_reverses() {
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut s, 700.0, 0.0, 60.0);
        assert!(
            within(s.angle_deg(), -95.0 * 360.0, 0.01),
            "{}",
            s.angle_deg()
        );
        // Symmetric about neutral.
        let mut a = Fs5106r::at_6v(0.0, 0.0);
        let mut b = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut a, 1_700.0, 0.0, 10.0);
        drive(&mut b, 1_300.0, 0.0, 10.0);
        assert!(a.angle_deg() > 0.0);
        assert_eq!(a.angle_deg(), -b.angle_deg());
    }

    #[test]
    fn speed_rises_with_the_offset() {
        let spec = ServoSpec::FS5106R_6V;
        let mut last = 0.0;
        for w in (1_505..=2_300).step_by(5) {
            let v = spec.no_load_speed_deg_s(f64::from(w));
            assert!(v > last, "{w}");
            last = v;
        }
    }

    #[test]
    fn half_load_halves_speed() {
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        s.set_load(0.0, 0.5);
        drive(&mut s, 2_300.0, 0.0, 60.0);
        assert!(
            within(s.angle_deg(), 95.0 * 360.0 / 2.0, 0.01),
            "{}",
            s.angle_deg()
        );
        // Load changed mid-way: 30 s at full, 30 s at half.
        let mut t = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut t, 2_300.0, 0.0, 30.0);
        t.set_load(30.0, 0.5);
        drive(&mut t, 2_300.0, 30.0, 60.0);
        assert!(
            within(t.angle_deg(), FULL_DEG_S * 30.0 * 1.5, 0.01),
            "{}",
            t.angle_deg()
        );
    }

    #[test]
    fn stall_stops_the_shaft_for_its_interval() {
        // Full speed for 12 minutes, stalled for ten of them (60 s – 660 s).
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        s.add_stall(60.0, 660.0);
        drive(&mut s, 2_300.0, 0.0, 60.0);
        let at_stall = s.angle_deg();
        drive(&mut s, 2_300.0, 60.0, 660.0);
        assert_eq!(s.angle_deg(), at_stall);
        drive(&mut s, 2_300.0, 660.0, 720.0);
        assert!(
            within(s.angle_deg(), FULL_DEG_S * 120.0, 0.01),
            "{}",
            s.angle_deg()
        );
    }

    #[test]
    fn signal_loss_stops_the_shaft() {
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        drive(&mut s, 2_300.0, 0.0, 10.0);
        let at_loss = s.advance_to(10.0);
        // The last pulse (9.98 s) holds for three frames, then nothing.
        let stopped = s.advance_to(11.0);
        assert!(stopped > at_loss);
        assert!(stopped - at_loss < FULL_DEG_S * 3.0 * FRAME_S);
        assert_eq!(s.advance_to(3_600.0), stopped);
        assert_eq!(s.speed_deg_s(3_600.0), 0.0);
        // And it starts again with the next pulse.
        s.pulse(3_600.0, 2_300.0);
        assert!(s.advance_to(3_600.02) > stopped);
    }

    #[test]
    fn integration_is_exact_between_events() {
        // One pulse, one stall inside its hold: 10 ms moving, 20 ms
        // stalled, 30 ms moving, then the hold (60 ms) ends.
        let mut s = Fs5106r::at_6v(0.0, 0.0);
        s.add_stall(0.010, 0.030);
        s.pulse(0.0, 2_300.0);
        let segs = s.segments_to(1.0);
        let cuts: Vec<f64> = segs.iter().map(|g| g.t0_s).collect();
        assert_eq!(cuts, vec![0.0, 0.010, 0.030, 0.060]);
        assert_eq!(segs[1].speed_deg_s, 0.0);
        assert_eq!(segs[3].speed_deg_s, 0.0);
        let end = s.advance_to(1.0);
        assert!((end - FULL_DEG_S * 0.040).abs() < 1e-9, "{end}");
        // Stepping in small increments gives the same angle.
        let mut t = Fs5106r::at_6v(0.0, 0.0);
        t.add_stall(0.010, 0.030);
        t.pulse(0.0, 2_300.0);
        for k in 1..=1_000 {
            t.advance_to(k as f64 * 0.001);
        }
        assert!((t.angle_deg() - end).abs() < 1e-9);
        // Segment timing.
        let g = segs[0];
        let t_half = g
            .time_at(g.angle0_deg + FULL_DEG_S * 0.005)
            .expect("inside");
        assert!((t_half - 0.005).abs() < 1e-12);
        assert_eq!(segs[1].time_at(0.0), None);
    }
}
