//! Panel voltage on ADC0 (PC0): the open-circuit voltage of Chowdhury et
//! al.'s (2019) small PV panel as a function of the angle of incidence of
//! the sun on it, through a resistor divider into the ATmega328P's 10-bit
//! ADC; and the trapezoid rule the paper integrates it with ("area under the
//! voltage-time curve", V·h).
//!
//! **Open-circuit voltage.** The single-diode model (Duffie & Beckman,
//! *Solar Engineering of Thermal Processes*, chapter "Photovoltaic
//! Converters"; De Soto, Klein & Beckman, "Improvement and validation of a
//! model for photovoltaic array performance", *Solar Energy* 80 (2006)
//! 78–88) gives, with the shunt resistance taken as infinite and the
//! short-circuit current proportional to the irradiance G,
//! `Voc = n·Ns·(kT/q)·ln(Isc/I0 + 1)`, hence at one cell temperature
//!
//! ```text
//! Voc(G) = Voc_stc + n·Ns·(kT/q)·ln(G / 1000 W/m²)
//! ```
//!
//! with `G = G_beam·cos θ + G_diffuse` on the panel (θ the angle between
//! the panel normal and the sun; the beam term is 0 for θ ≥ 90°, and
//! everything is 0 with the sun below the horizon), clamped at 0 V where
//! the logarithm would take it below.
//!
//! Parameters ([`PvPanel::UXCELL_6V_065W`]):
//!
//! - the panel: Chowdhury et al. 2019, Figure 2: "Uxcell Poly Mini Solar
//!   Panel, 6 V, 120 mA, 0.65 W, 120 × 56 mm" (polycrystalline). 0.65 W /
//!   6 V = 108 mA = 0.9 × 120 mA, the maximum-power to short-circuit
//!   current ratio of a crystalline cell, so 6 V is read as the voltage at
//!   maximum power and 120 mA as the short-circuit current;
//! - **Ns = 12 cells** in series: 6 V at ≈ 0.5 V per crystalline-silicon
//!   cell at maximum power;
//! - **Voc_stc = 7.2 V**: 12 × 0.6 V, the open-circuit voltage of a
//!   crystalline-silicon cell at STC (Vmp/Voc ≈ 0.83);
//! - **n = 1.3**: the diode ideality Villalva, Gazoli & Filho ("Comprehensive
//!   approach to modeling and simulation of photovoltaic arrays", IEEE
//!   Trans. Power Electronics 24 (2009) 1198–1208) fit for a
//!   multicrystalline module (KC200GT);
//! - **T = 25 °C** (298.15 K), the STC cell temperature (IEC 60904-3 STC:
//!   1000 W/m², AM1.5, 25 °C); Voc's temperature coefficient is not
//!   modelled. kT/q = 25.69 mV with the SI (2019) exact k and q.
//!
//! **Divider and ADC.** The paper feeds the panel "through a voltage divider
//! network" keeping the pin below 5 V without giving its values;
//! [`Divider::TEN_K_TEN_K`] (10 kΩ over 10 kΩ) halves the voltage (pin
//! below AVcc up to a 10 V panel) with a 5 kΩ source impedance, under the
//! "10 kΩ or less" the ATmega328P datasheet's Analog Input Circuitry
//! subsection asks for. ADC: ATmega328P datasheet §24.7 "ADC Conversion
//! Result", single ended: `ADC = Vin·1024 / Vref`, 10 bits, here with
//! Vref = AVcc = 5.0 V ([`adc_code`], floor, clamped to 0…1023). simavr
//! computes `mV·1023 / Vref_mV` instead (`avr_adc.c`), one code lower at
//! most ([`simavr_adc_code`]); feed it with `Sim::set_adc_mv` after
//! `Sim::set_avcc_mv(5000)`.

/// Boltzmann constant, J/K (SI 2019, exact).
pub const BOLTZMANN_J_PER_K: f64 = 1.380649e-23;
/// Elementary charge, C (SI 2019, exact).
pub const ELEMENTARY_CHARGE_C: f64 = 1.602176634e-19;
/// STC irradiance, W/m².
pub const STC_IRRADIANCE_W_M2: f64 = 1_000.0;
/// STC cell temperature, K (25 °C).
pub const STC_CELL_TEMP_K: f64 = 298.15;
/// The Uno's ADC reference: AVcc = 5.0 V, in mV.
pub const AVCC_MV: f64 = 5_000.0;
/// Largest 10-bit conversion result.
pub const ADC_MAX: u16 = 1_023;

/// A PV panel's open-circuit behaviour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PvPanel {
    /// Open-circuit voltage at STC (1000 W/m², 25 °C), V.
    pub voc_stc_v: f64,
    /// Cells in series, Ns.
    pub cells_in_series: u32,
    /// Diode ideality factor, n.
    pub ideality: f64,
    /// Cell temperature, K.
    pub cell_temp_k: f64,
}

impl PvPanel {
    /// Chowdhury et al.'s (2019) uxcell 6 V / 120 mA / 0.65 W poly panel (see
    /// the module documentation for each figure).
    pub const UXCELL_6V_065W: PvPanel = PvPanel {
        voc_stc_v: 7.2,
        cells_in_series: 12,
        ideality: 1.3,
        cell_temp_k: STC_CELL_TEMP_K,
    };

    /// Thermal voltage kT/q at the cell temperature, V.
    pub fn thermal_voltage_v(&self) -> f64 {
        BOLTZMANN_J_PER_K * self.cell_temp_k / ELEMENTARY_CHARGE_C
    }

    /// Open-circuit voltage at plane-of-array irradiance `g_w_m2`, V
    /// (0 for no irradiance; never negative).
    pub fn voc_v(&self, g_w_m2: f64) -> f64 {
        if g_w_m2.is_nan() || g_w_m2 <= 0.0 {
            return 0.0;
        }
        let slope = self.ideality * f64::from(self.cells_in_series) * self.thermal_voltage_v();
        (self.voc_stc_v + slope * (g_w_m2 / STC_IRRADIANCE_W_M2).ln()).max(0.0)
    }
}

/// The light on the panel's site.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sky {
    /// Beam irradiance on a surface normal to the sun, W/m².
    pub beam_w_m2: f64,
    /// Diffuse irradiance on the panel whatever its pose, W/m² (0: beam
    /// only).
    pub diffuse_w_m2: f64,
}

impl Sky {
    /// STC beam, no diffuse: a panel facing the sun sees 1000 W/m².
    pub const STC_BEAM: Sky = Sky {
        beam_w_m2: STC_IRRADIANCE_W_M2,
        diffuse_w_m2: 0.0,
    };
}

/// Angle between the panel normal and the direction of the sun, degrees
/// (any common frame; the vectors need not be unit length).
pub fn incidence_deg(normal: [f64; 3], sun: [f64; 3]) -> f64 {
    let dot: f64 = normal.iter().zip(sun).map(|(a, b)| a * b).sum();
    let norm = |v: [f64; 3]| v.iter().map(|c| c * c).sum::<f64>().sqrt();
    (dot / (norm(normal) * norm(sun)))
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

/// Irradiance on the panel, W/m²: `beam·max(cos θ, 0) + diffuse`, or 0
/// with the sun at or below the horizon.
pub fn plane_irradiance_w_m2(sky: &Sky, incidence_deg: f64, sun_elevation_deg: f64) -> f64 {
    if sun_elevation_deg.is_nan() || sun_elevation_deg <= 0.0 {
        return 0.0;
    }
    sky.beam_w_m2 * incidence_deg.to_radians().cos().max(0.0) + sky.diffuse_w_m2
}

/// The panel's open-circuit voltage, mV, for the sun at `incidence_deg`
/// from its normal and `sun_elevation_deg` above the horizon.
pub fn panel_mv(panel: &PvPanel, sky: &Sky, incidence_deg: f64, sun_elevation_deg: f64) -> f64 {
    1_000.0 * panel.voc_v(plane_irradiance_w_m2(sky, incidence_deg, sun_elevation_deg))
}

/// A two-resistor divider: the panel across `r_top + r_bottom`, the ADC
/// pin across `r_bottom`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Divider {
    /// Panel + to the pin, Ω.
    pub r_top_ohm: f64,
    /// Pin to ground, Ω.
    pub r_bottom_ohm: f64,
}

impl Divider {
    /// 10 kΩ over 10 kΩ: ratio ½, 5 kΩ seen by the ADC.
    pub const TEN_K_TEN_K: Divider = Divider {
        r_top_ohm: 10_000.0,
        r_bottom_ohm: 10_000.0,
    };

    /// Vout / Vin.
    pub fn ratio(&self) -> f64 {
        self.r_bottom_ohm / (self.r_top_ohm + self.r_bottom_ohm)
    }

    /// Pin voltage for `panel_mv` (the ADC's input current neglected).
    pub fn out_mv(&self, panel_mv: f64) -> f64 {
        panel_mv * self.ratio()
    }

    /// Pin voltage rounded to whole mV, for `Sim::set_adc_mv`.
    pub fn pin_mv(&self, panel_mv: f64) -> u32 {
        self.out_mv(panel_mv)
            .round()
            .clamp(0.0, f64::from(u32::MAX)) as u32
    }

    /// Panel voltage a conversion result stands for, mV (the firmware's
    /// inverse: `code · Vref / 1024 / ratio`).
    pub fn panel_mv_of_code(&self, code: u16, vref_mv: f64) -> f64 {
        f64::from(code) * vref_mv / 1_024.0 / self.ratio()
    }
}

/// ATmega328P single-ended conversion result (datasheet §24.7):
/// `floor(Vin·1024 / Vref)`, clamped to 0…1023.
pub fn adc_code(vin_mv: f64, vref_mv: f64) -> u16 {
    if vin_mv.is_nan() || vin_mv <= 0.0 {
        return 0;
    }
    (vin_mv * 1_024.0 / vref_mv).floor().min(f64::from(ADC_MAX)) as u16
}

/// What simavr returns for the same input (`avr_adc.c`: integer
/// `mV·1023 / Vref_mV`, clipped to 1023).
pub fn simavr_adc_code(pin_mv: u32, vref_mv: u32) -> u16 {
    if vref_mv == 0 {
        return ADC_MAX;
    }
    (u64::from(pin_mv) * 1_023 / u64::from(vref_mv)).min(u64::from(ADC_MAX)) as u16
}

/// Trapezoid rule over `(unix_s, volts)` samples in time order: the area
/// under the voltage-time curve in V·h (Chowdhury et al.'s (2019) AUC).
/// Fewer than two samples give 0.
pub fn trapezoid_vh(samples: &[(f64, f64)]) -> f64 {
    samples
        .windows(2)
        .map(|w| (w[1].0 - w[0].0) * (w[0].1 + w[1].1) / 2.0)
        .sum::<f64>()
        / 3_600.0
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: PvPanel = PvPanel::UXCELL_6V_065W;

    #[test]
    fn facing_the_sun_gives_voc_at_the_irradiance() {
        // STC: the rated Voc.
        assert!((panel_mv(&P, &Sky::STC_BEAM, 0.0, 60.0) - 7_200.0).abs() < 1e-9);
        // 800 W/m²: 7.2 V + 1.3 · 12 · 25.69258 mV · ln 0.8 = 7.110563 V
        // (kT/q = 1.380649e-23 · 298.15 / 1.602176634e-19 = 25.69258 mV).
        let sky = Sky {
            beam_w_m2: 800.0,
            diffuse_w_m2: 0.0,
        };
        assert!((panel_mv(&P, &sky, 0.0, 45.0) - 7_110.563).abs() < 0.01);
        assert!((P.thermal_voltage_v() - 0.025_692_58).abs() < 1e-8);
        // cos 60° = ½: 500 W/m² on the panel → 6.922184 V.
        assert!((panel_mv(&P, &Sky::STC_BEAM, 60.0, 45.0) - 6_922.184).abs() < 0.01);
    }

    #[test]
    fn edge_on_behind_or_night_gives_zero() {
        assert_eq!(panel_mv(&P, &Sky::STC_BEAM, 90.0, 30.0), 0.0);
        assert_eq!(panel_mv(&P, &Sky::STC_BEAM, 135.0, 30.0), 0.0);
        let hazy = Sky {
            beam_w_m2: 900.0,
            diffuse_w_m2: 100.0,
        };
        assert_eq!(panel_mv(&P, &hazy, 0.0, -0.5), 0.0);
        assert_eq!(panel_mv(&P, &hazy, 0.0, 0.0), 0.0);
        // Diffuse light alone still gives a voltage: 100 W/m² →
        // 7.2 V + 0.400804 V · ln 0.1 = 6.277114 V.
        assert!((panel_mv(&P, &hazy, 120.0, 10.0) - 6_277.114).abs() < 0.01);
        assert_eq!(P.voc_v(0.0), 0.0);
        assert_eq!(P.voc_v(1e-12), 0.0);
    }

    #[test]
    fn voltage_falls_with_incidence() {
        let mut last = f64::INFINITY;
        for k in 0..=180 {
            let theta = f64::from(k) * 0.5;
            let v = panel_mv(&P, &Sky::STC_BEAM, theta, 40.0);
            assert!(v <= last, "{theta}°");
            if v > 0.0 {
                assert!(v < last, "{theta}°");
            }
            last = v;
        }
    }

    #[test]
    fn incidence_of_vectors() {
        assert!((incidence_deg([0.0, 0.0, 1.0], [0.0, 0.0, 2.0])).abs() < 1e-12);
        assert!((incidence_deg([0.0, 0.0, 1.0], [1.0, 0.0, 1.0]) - 45.0).abs() < 1e-12);
        assert!((incidence_deg([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]) - 90.0).abs() < 1e-12);
    }

    #[test]
    fn adc_codes_at_known_voltages() {
        // 1024 · Vin / 5000 mV, floored.
        assert_eq!(adc_code(0.0, AVCC_MV), 0);
        assert_eq!(adc_code(-5.0, AVCC_MV), 0);
        assert_eq!(adc_code(1_000.0, AVCC_MV), 204); // 204.8
        assert_eq!(adc_code(2_500.0, AVCC_MV), 512);
        assert_eq!(adc_code(3_300.0, AVCC_MV), 675); // 675.84
        assert_eq!(adc_code(4_995.0, AVCC_MV), 1_022); // 1022.98
        assert_eq!(adc_code(4_999.0, AVCC_MV), 1_023); // 1023.80
        assert_eq!(adc_code(5_000.0, AVCC_MV), 1_023); // 1024 → clamped
        assert_eq!(adc_code(7_000.0, AVCC_MV), 1_023);
        // simavr: 1023 · mV / 5000.
        assert_eq!(simavr_adc_code(2_500, 5_000), 511); // 511.5
        assert_eq!(simavr_adc_code(1_000, 5_000), 204); // 204.6
        assert_eq!(simavr_adc_code(5_000, 5_000), 1_023);
        assert_eq!(simavr_adc_code(6_000, 5_000), 1_023);
        // The panel at STC through 10k/10k: 3600 mV on the pin → 737.28.
        let d = Divider::TEN_K_TEN_K;
        let pin = d.pin_mv(panel_mv(&P, &Sky::STC_BEAM, 0.0, 50.0));
        assert_eq!(pin, 3_600);
        assert_eq!(adc_code(f64::from(pin), AVCC_MV), 737);
        assert!((d.panel_mv_of_code(737, AVCC_MV) - 7_197.27).abs() < 0.01);
    }

    #[test]
    fn trapezoid_of_constant_and_ramp() {
        // 6 V for two hours, uneven samples: 12 V·h.
        let t0 = 1_700_000_000.0;
        let constant = [
            (t0, 6.0),
            (t0 + 100.0, 6.0),
            (t0 + 4_000.0, 6.0),
            (t0 + 7_200.0, 6.0),
        ];
        assert!((trapezoid_vh(&constant) - 12.0).abs() < 1e-12);
        // 0 → 6 V linearly over three hours: ½ · 6 V · 3 h = 9 V·h (the
        // rule is exact on a line, whatever the sampling).
        let ramp: Vec<(f64, f64)> = [0.0, 1.0, 500.0, 3_600.0, 9_000.0, 10_800.0]
            .iter()
            .map(|&s| (t0 + s, 6.0 * s / 10_800.0))
            .collect();
        assert!((trapezoid_vh(&ramp) - 9.0).abs() < 1e-12);
        assert_eq!(trapezoid_vh(&[]), 0.0);
        assert_eq!(trapezoid_vh(&[(t0, 5.0)]), 0.0);
    }
}
