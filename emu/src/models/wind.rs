//! Cup anemometer on INT4 (PE4, Mega D2): a reed contact pulling the line
//! low once per pulse; the firmware counts falling edges. A profile gives
//! the pulse rate (emulated Hz) over emulated time since power-on.

/// Pulse rate over time.
#[derive(Debug, Clone, PartialEq)]
pub struct WindProfile {
    /// (from emulated UTC, Unix seconds; rate in Hz), sorted; the rate holds
    /// until the next entry. Before the first entry: calm.
    pub steps: Vec<(i64, f64)>,
}

impl WindProfile {
    /// No wind at all.
    pub fn calm() -> Self {
        WindProfile { steps: Vec::new() }
    }

    /// Calm, then `hz` from `from_unix_s` for `minutes` emulated minutes.
    pub fn gust(from_unix_s: i64, minutes: i64, hz: f64) -> Self {
        WindProfile {
            steps: vec![(from_unix_s, hz), (from_unix_s + minutes * 60, 0.0)],
        }
    }

    /// Rate at `unix_s`.
    pub fn rate_hz(&self, unix_s: f64) -> f64 {
        self.steps
            .iter()
            .rev()
            .find(|(t, _)| *t as f64 <= unix_s)
            .map_or(0.0, |s| s.1)
    }
}

/// Generates the pin level: low for the first half of each pulse period.
#[derive(Debug, Clone)]
pub struct Anemometer {
    profile: WindProfile,
    /// Phase in periods (fractional part: position in the current period).
    phase: f64,
    last_s: Option<f64>,
    /// Falling edges produced.
    pub pulses: u64,
    level: bool,
}

impl Anemometer {
    /// An anemometer following `profile`, line high (contact open).
    pub fn new(profile: WindProfile) -> Self {
        Anemometer {
            profile,
            phase: 0.0,
            last_s: None,
            pulses: 0,
            level: true,
        }
    }

    /// Advances to emulated UTC `unix_s`; returns the new pin level if it
    /// changed.
    pub fn advance(&mut self, unix_s: f64) -> Option<bool> {
        let dt = self.last_s.map_or(0.0, |l| (unix_s - l).max(0.0));
        self.last_s = Some(unix_s);
        let hz = self.profile.rate_hz(unix_s);
        if hz <= 0.0 {
            self.phase = 0.0;
            return (!self.level).then(|| {
                self.level = true;
                true
            });
        }
        self.phase += dt * hz;
        let low = self.phase.fract() < 0.5;
        if low == self.level {
            self.level = !low;
            if low {
                self.pulses += 1;
            }
            return Some(self.level);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forty_hz_for_ten_seconds_is_four_hundred_edges() {
        let mut a = Anemometer::new(WindProfile::gust(100, 1, 40.0));
        let mut t = 90.0;
        while t < 110.0 {
            a.advance(t);
            t += 0.001;
        }
        assert!((399..=401).contains(&a.pulses), "{}", a.pulses);
        assert_eq!(WindProfile::gust(100, 1, 40.0).rate_hz(200.0), 0.0);
    }
}
