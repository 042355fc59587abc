//! Mount attitude and the two-axis (C-axis γ, A-axis α) pose that points the
//! panel at the sun, after J. Choi, I. Choy, S. Song, J. An, D. Lee and J. Kim,
//! "Portable sun tracking system with tilt and magnetic compensation"
//! (Choi et al., portable tracker; its text gives no year, and the work was
//! funded by a grant of 2013).
//!
//! # Frames (the paper's Fig. 3)
//! The horizontal frame XYZ has X toward **west**, Y toward **south** and Z
//! toward the **sky** (right-handed). The tracker frame xyz is fixed to the
//! mounting; at the home pose (α = γ = 0) the panel normal is the tracker's
//! z axis.
//!
//! The mount is reached from XYZ by a rotation γ0 about Z, then α0 about the
//! (new) x axis, then β0 about the (new) y axis (the paper's eq. 12):
//! `T = Rz(γ0)·Rx(α0)·Ry(β0)`, which maps tracker coordinates to horizontal
//! ones. A level mount with its y axis pointing south is the identity.
//!
//! The panel normal after turning the C axis by γ and then the A axis by α is
//! `n(γ, α) = Rz(γ)·Rx(α)·ẑ = (sin γ sin α, −cos γ sin α, cos α)` in tracker
//! coordinates (the paper's eq. 15–17).

use sun_algos::Float;

/// A 3-vector.
pub type Vec3<T> = [T; 3];
/// A 3×3 matrix, rows first.
pub type Mat3<T> = [[T; 3]; 3];

/// Why an attitude could not be formed from sensor readings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AttitudeError {
    /// An input was NaN or infinite.
    NotFinite,
    /// Tilt angles outside 0…180° or geometrically impossible together.
    InconsistentTilt,
    /// The sun direction has zero length.
    ZeroVector,
}

/// The rotation of the mounting relative to the horizontal frame (Choi et al.
/// eq. 12).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MountAttitude<T> {
    /// α0: rotation about the X axis, degrees.
    pub alpha0_deg: T,
    /// β0: rotation about the y axis (after α0), degrees.
    pub beta0_deg: T,
    /// γ0: rotation about the vertical Z axis, degrees.
    pub gamma0_deg: T,
}

/// A pose of the two axes: C-axis (vertical at home) γ and A-axis α, degrees.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Pose<T> {
    /// C-axis rotation γ, degrees.
    pub gamma_deg: T,
    /// A-axis rotation α, degrees.
    pub alpha_deg: T,
}

impl<T: Float> Pose<T> {
    /// Travel between this pose and `other`: both axes' degrees, summed
    /// (how [`MountAttitude::choose`] and the controller's look-ahead
    /// measure movement). Out of line on the AVR, where `choose` would hold
    /// two copies (120 B less on the ATmega2560, with the look-ahead's own copy gone).
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn travel_deg(&self, other: &Pose<T>) -> T {
        (self.gamma_deg - other.gamma_deg).abs() + (self.alpha_deg - other.alpha_deg).abs()
    }

    /// How far the panel normal sweeps, at most, when both axes turn from
    /// `other` to this pose together, degrees: the A axis's turn plus the
    /// C axis's turn on the cone of the larger tilt α (the normal
    /// `n(γ, α)` of Choi et al. eq. 15–17 moves `sin α` degrees per degree
    /// of γ; bounded here by `min(α in radians, 1)`, no sine needed). Small
    /// while the panel follows the sun, even where the C axis turns fast
    /// under a sun near the tracker's axis; large for a change of branch
    /// (half a turn of C with α changing sign) or a whole turn of C at a
    /// steep tilt.
    pub fn sweep_deg(&self, other: &Pose<T>) -> T {
        let tilt_deg = self.alpha_deg.abs().max(other.alpha_deg.abs());
        (self.gamma_deg - other.gamma_deg).abs() * tilt_deg.to_radians().min(T::ONE)
            + (self.alpha_deg - other.alpha_deg).abs()
    }

    /// True when turning from `other` to this pose is a swing rather than
    /// a move after the sun: the normal sweeps ([`Pose::sweep_deg`]) more
    /// than `margin_deg` beyond twice the angle between where the two poses
    /// point. A change of branch or a whole turn of C points the panel
    /// (nearly) the same way at both ends; a move after a sun that went on
    /// (a clock step, a long stow) sweeps about as far as the sun went.
    /// Out of line on the AVR (three callers).
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn swings_from(&self, other: &Pose<T>, margin_deg: T) -> bool {
        let half_deg = (self.sweep_deg(other) - margin_deg) * T::from_f64(0.5);
        // The normals closer than `half_deg`: cos of their angle above cos
        // of it (`half_deg` within 0…180°, where cos falls).
        half_deg > T::ZERO
            && dot(&panel_normal(self), &panel_normal(other))
                > half_deg.min(T::from_f64(180.0)).to_radians().cos()
    }
}

/// Mechanical ranges of the two axes, degrees (inclusive).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseLimits<T> {
    /// Lowest C-axis angle γ.
    pub gamma_min_deg: T,
    /// Highest C-axis angle γ.
    pub gamma_max_deg: T,
    /// Lowest A-axis angle α.
    pub alpha_min_deg: T,
    /// Highest A-axis angle α.
    pub alpha_max_deg: T,
}

impl<T: Float> PoseLimits<T> {
    /// Full turn on the C axis (−180…180°), ±90° on the A axis.
    pub fn full() -> Self {
        PoseLimits {
            gamma_min_deg: T::from_f64(-180.0),
            gamma_max_deg: T::from_f64(180.0),
            alpha_min_deg: T::from_f64(-90.0),
            alpha_max_deg: T::from_f64(90.0),
        }
    }

    /// True when `p` lies inside the limits.
    pub fn contains(&self, p: &Pose<T>) -> bool {
        p.gamma_deg >= self.gamma_min_deg
            && p.gamma_deg <= self.gamma_max_deg
            && p.alpha_deg >= self.alpha_min_deg
            && p.alpha_deg <= self.alpha_max_deg
    }

    /// `p` with each axis clamped into its range.
    pub fn clamp(&self, p: &Pose<T>) -> Pose<T> {
        Pose {
            gamma_deg: p.gamma_deg.clamp(self.gamma_min_deg, self.gamma_max_deg),
            alpha_deg: p.alpha_deg.clamp(self.alpha_min_deg, self.alpha_max_deg),
        }
    }
}

/// The result of choosing a pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Choice<T> {
    /// A solution inside the limits, the one with the least motion.
    Reachable(Pose<T>),
    /// No solution is inside the limits: the nearest pose clamped into them.
    Clamped(Pose<T>),
}

impl<T: Copy> Choice<T> {
    /// The pose, whether exact or clamped.
    pub fn pose(&self) -> Pose<T> {
        match self {
            Choice::Reachable(p) | Choice::Clamped(p) => *p,
        }
    }
}

/// Matrix product `a·b`.
pub fn mat_mul<T: Float>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    let mut m = [[T::ZERO; 3]; 3];
    for (mi, ai) in m.iter_mut().zip(a.iter()) {
        for (j, mij) in mi.iter_mut().enumerate() {
            *mij = ai[0] * b[0][j] + ai[1] * b[1][j] + ai[2] * b[2][j];
        }
    }
    m
}

/// `m·v`.
pub fn mat_vec<T: Float>(m: &Mat3<T>, v: &Vec3<T>) -> Vec3<T> {
    [dot(&m[0], v), dot(&m[1], v), dot(&m[2], v)]
}

/// `mᵀ·v` (the inverse of a rotation, its transpose: Choi et al. eq. 14).
pub fn mat_t_vec<T: Float>(m: &Mat3<T>, v: &Vec3<T>) -> Vec3<T> {
    [
        m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
        m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
        m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
    ]
}

/// Dot product.
pub fn dot<T: Float>(a: &Vec3<T>, b: &Vec3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Angle between two vectors in degrees (shared with `sun_algos`).
pub use sun_algos::position::angle_between_deg;

/// Folds an angle into `(−180, 180]`.
pub fn wrap180<T: Float>(a_deg: T) -> T {
    let r = (a_deg + T::from_f64(180.0)).rem_euclid(T::from_f64(360.0)) - T::from_f64(180.0);
    if r <= T::from_f64(-180.0) {
        r + T::from_f64(360.0)
    } else {
        r
    }
}

/// Unit vector toward the sun in the horizontal frame XYZ (west, south, up)
/// from its elevation θ and azimuth (degrees east of north) — Choi et al.
/// eq. 13.
pub fn sun_vector_xyz<T: Float>(elevation_deg: T, azimuth_deg: T) -> Vec3<T> {
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    // East-of-north azimuth: east = sin A, north = cos A; west = −east, south = −north.
    [-ce * sa, -ce * ca, se]
}

/// Panel normal of a pose in tracker coordinates: `Rz(γ)·Rx(α)·ẑ` (Choi et
/// al. eq. 15–17).
pub fn panel_normal<T: Float>(pose: &Pose<T>) -> Vec3<T> {
    let (sg, cg) = pose.gamma_deg.to_radians().sin_cos();
    let (sa, ca) = pose.alpha_deg.to_radians().sin_cos();
    [sg * sa, -cg * sa, ca]
}

/// `cand` clamped into `limits`, and the angle between where the two
/// point, degrees. Out of line on AVR: [`MountAttitude::choose`] calls it
/// in a loop over six candidates, which the compiler unrolls (436 B of the
/// Mega image; the Cortex-M images are 24 B smaller with it inlined).
#[cfg_attr(target_arch = "avr", inline(never))]
fn clamped_miss<T: Float>(limits: &PoseLimits<T>, cand: &Pose<T>) -> (T, Pose<T>) {
    let c = limits.clamp(cand);
    (angle_between_deg(&panel_normal(&c), &panel_normal(cand)), c)
}

impl<T: Float> MountAttitude<T> {
    /// A level mount with its y axis toward south: the identity.
    pub fn level() -> Self {
        MountAttitude {
            alpha0_deg: T::ZERO,
            beta0_deg: T::ZERO,
            gamma0_deg: T::ZERO,
        }
    }

    /// From the inclinometer's two angles and the tilt-compensated true heading.
    ///
    /// `theta_x_deg`, `theta_y_deg` are Choi et al.'s tilt outputs θx, θy:
    /// the angles between the vertical Z and the tracker's x and y axes,
    /// 0…180° (90° each when level; their eq. 4). With `T` above, `cos θx =
    /// −cos α0 sin β0` and `cos θy = sin α0` (eq. 5–6), so (eq. 7)
    /// `α0 = asin(cos θy)`, `β0 = asin(−cos θx / cos α0)`, both in ±90°.
    ///
    /// `heading_deg` is the true azimuth (east of north; magnetic heading
    /// plus declination, Choi et al. eq. 11) of the horizontal projection of
    /// the tracker's +y axis. That projection is `Rz(γ0)·(0, cos α0, ·)`, so
    /// its azimuth is exactly `180° − γ0` whatever the tilt (eq. 10–11).
    pub fn from_sensors(
        theta_x_deg: T,
        theta_y_deg: T,
        heading_deg: T,
    ) -> Result<Self, AttitudeError> {
        if !theta_x_deg.is_finite() || !theta_y_deg.is_finite() || !heading_deg.is_finite() {
            return Err(AttitudeError::NotFinite);
        }
        let range = T::ZERO..=T::from_f64(180.0);
        if !range.contains(&theta_x_deg) || !range.contains(&theta_y_deg) {
            return Err(AttitudeError::InconsistentTilt);
        }
        let sin_a0 = theta_y_deg.to_radians().cos();
        let alpha0 = sin_a0.clamp(-T::ONE, T::ONE).asin();
        let cos_a0 = alpha0.cos();
        let cos_tx = theta_x_deg.to_radians().cos();
        // Both axes cannot tilt so far that cos²θx + cos²θy > 1.
        let eps = T::from_f64(1e-9);
        if cos_tx * cos_tx + sin_a0 * sin_a0 > T::ONE + eps {
            return Err(AttitudeError::InconsistentTilt);
        }
        let beta0 = if cos_a0 <= eps {
            T::ZERO
        } else {
            (-cos_tx / cos_a0).clamp(-T::ONE, T::ONE).asin()
        };
        Ok(MountAttitude {
            alpha0_deg: alpha0.to_degrees(),
            beta0_deg: beta0.to_degrees(),
            gamma0_deg: wrap180(T::from_f64(180.0) - heading_deg),
        })
    }

    /// The tilt readings (θx, θy) and heading this attitude would produce
    /// (the inverse of [`MountAttitude::from_sensors`]; sensor models use it).
    pub fn to_sensors(&self) -> (T, T, T) {
        let m = self.matrix();
        // Third row of T is the Z (up) component of each tracker axis.
        let tx = m[2][0].clamp(-T::ONE, T::ONE).acos().to_degrees();
        let ty = m[2][1].clamp(-T::ONE, T::ONE).acos().to_degrees();
        let heading = (T::from_f64(180.0) - self.gamma0_deg).rem_euclid(T::from_f64(360.0));
        (tx, ty, heading)
    }

    /// `T = Rz(γ0)·Rx(α0)·Ry(β0)`: tracker coordinates → horizontal (Choi et
    /// al. eq. 12), multiplied out: with `sγ = sin γ0`, `cγ = cos γ0` and
    /// so on,
    ///
    /// ```text
    /// ⎡ cγ·cβ − (sγ·sα)·sβ   −sγ·cα   cγ·sβ + (sγ·sα)·cβ ⎤
    /// ⎢ sγ·cβ + (cγ·sα)·sβ    cγ·cα   sγ·sβ − (cγ·sα)·cβ ⎥
    /// ⎣ −cα·sβ                 sα      cα·cβ              ⎦
    /// ```
    ///
    /// (the product of the three rotations term for term, without its
    /// products with 0 and 1). Out of line on the AVR, where three callers
    /// would each hold a copy.
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn matrix(&self) -> Mat3<T> {
        let (sg, cg) = self.gamma0_deg.to_radians().sin_cos();
        let (sa, ca) = self.alpha0_deg.to_radians().sin_cos();
        let (sb, cb) = self.beta0_deg.to_radians().sin_cos();
        let (sg_sa, cg_sa) = (sg * sa, cg * sa);
        [
            [cg * cb - sg_sa * sb, -sg * ca, cg * sb + sg_sa * cb],
            [sg * cb + cg_sa * sb, cg * ca, sg * sb - cg_sa * cb],
            [-(ca * sb), sa, ca * cb],
        ]
    }

    /// The sun vector seen from the tracker frame, `Tᵀ·S` (Choi et al.
    /// eq. 14).
    pub fn sun_in_tracker(&self, sun_xyz: &Vec3<T>) -> Vec3<T> {
        mat_t_vec(&self.matrix(), sun_xyz)
    }

    /// Panel normal of `pose` in the horizontal frame.
    pub fn normal_xyz(&self, pose: &Pose<T>) -> Vec3<T> {
        mat_vec(&self.matrix(), &panel_normal(pose))
    }

    /// Both poses `(γ1, α1)`, `(γ2, α2)` that point the panel normal along
    /// `sun_xyz` (Choi et al. eq. 18–21): `cos α = S_z`, `tan γ = S_x / (−S_y)` for
    /// α ≥ 0, and the same normal with `γ + 180°`, `−α`. When the sun lies on
    /// the tracker's z axis γ is free: `current_gamma_deg` is kept.
    pub fn solutions(
        &self,
        sun_xyz: &Vec3<T>,
        current_gamma_deg: T,
    ) -> Result<[Pose<T>; 2], AttitudeError> {
        let s = self.sun_in_tracker(sun_xyz);
        let norm = dot(&s, &s).sqrt();
        if !norm.is_finite() {
            return Err(AttitudeError::NotFinite);
        }
        if norm <= T::from_f64(1e-12) {
            return Err(AttitudeError::ZeroVector);
        }
        let s = [s[0] / norm, s[1] / norm, s[2] / norm];
        let horiz = (s[0] * s[0] + s[1] * s[1]).sqrt();
        // α from atan2 keeps full precision near 0° and 180°.
        let alpha1 = horiz.atan2(s[2]).to_degrees();
        let gamma1 = if horiz <= T::from_f64(1e-15) {
            current_gamma_deg
        } else {
            s[0].atan2(-s[1]).to_degrees()
        };
        let p1 = Pose {
            gamma_deg: gamma1,
            alpha_deg: alpha1,
        };
        let p2 = Pose {
            gamma_deg: wrap180(gamma1 + T::from_f64(180.0)),
            alpha_deg: -alpha1,
        };
        Ok([p1, p2])
    }

    /// The pose to drive to: of both solutions (and their ±360° turns on the C
    /// axis) the one inside `limits` that moves least from `current`, as in
    /// the last paragraph of Choi et al. §IV; they do not say how they
    /// measure the movement, here it is the sum of both axes' travel.
    pub fn choose(
        &self,
        sun_xyz: &Vec3<T>,
        current: &Pose<T>,
        limits: &PoseLimits<T>,
    ) -> Result<Choice<T>, AttitudeError> {
        let sols = self.solutions(sun_xyz, current.gamma_deg)?;
        // The six candidates in turn: each solution at −360°, 0 and +360°
        // on the C axis. The out-of-reach ones are clamped again in the
        // second pass rather than kept: an array of six clamped candidates
        // put this function's locals beyond the 63 bytes AVR `ldd`/`std`
        // reach from the frame pointer (328 B less on the ATmega2560).
        // `k` in 8 bits: its division and remainder by 3 are byte-wide on
        // the AVR (28 B less on the ATmega2560 than with `usize`).
        let candidate = |k: u8| {
            let sol = sols.get(usize::from(k / 3))?;
            // ±360° as constants, not a local the closure captures by
            // reference: that local sat in a far stack slot of `choose`
            // (80 B less on the ATmega2560).
            let g = match k % 3 {
                0 => T::from_f64(-360.0),
                1 => T::ZERO,
                _ => T::from_f64(360.0),
            };
            Some(Pose {
                gamma_deg: sol.gamma_deg + g,
                alpha_deg: sol.alpha_deg,
            })
        };
        let mut best: Option<(T, Pose<T>)> = None;
        let mut min_miss: Option<T> = None;
        for cand in (0..6).filter_map(candidate) {
            if limits.contains(&cand) {
                let cost = cand.travel_deg(current);
                if best.is_none_or(|(c, _)| cost < c) {
                    best = Some((cost, cand));
                }
            } else {
                let (miss, _) = clamped_miss(limits, &cand);
                min_miss = Some(min_miss.map_or(miss, |m| m.min(miss)));
            }
        }
        if let Some((_, p)) = best {
            return Ok(Choice::Reachable(p));
        }
        // Out of reach: the smallest miss; among misses within 0.5° of it
        // (e.g. α = ±90° with γ half a turn apart point the same way) the
        // least travel, so that noise does not swing the axes to and fro.
        let Some(min_miss) = min_miss else {
            return Err(AttitudeError::ZeroVector);
        };
        let tol = T::from_f64(0.5);
        let mut least: Option<(T, Pose<T>)> = None;
        // None of the six is inside the limits here (else `best`).
        for cand in (0..6).filter_map(candidate) {
            let (miss, c) = clamped_miss(limits, &cand);
            if miss <= min_miss + tol {
                let travel = c.travel_deg(current);
                match least {
                    Some((t, _)) if t <= travel => {}
                    _ => least = Some((travel, c)),
                }
            }
        }
        least
            .map(|(_, p)| Choice::Clamped(p))
            .ok_or(AttitudeError::ZeroVector)
    }

    /// Angle in degrees between the panel normal at `pose` and `sun_xyz`.
    pub fn pointing_error_deg(&self, pose: &Pose<T>, sun_xyz: &Vec3<T>) -> T {
        angle_between_deg(&self.normal_xyz(pose), sun_xyz)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rot_x(a_deg: f64) -> Mat3<f64> {
        let (s, c) = a_deg.to_radians().sin_cos();
        [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
    }

    fn rot_y(a_deg: f64) -> Mat3<f64> {
        let (s, c) = a_deg.to_radians().sin_cos();
        [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
    }

    fn rot_z(a_deg: f64) -> Mat3<f64> {
        let (s, c) = a_deg.to_radians().sin_cos();
        [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    }

    #[test]
    fn matrix_is_the_product_of_the_three_rotations() {
        // Choi et al. eq. 12, T = Rz(γ0)·Rx(α0)·Ry(β0), by matrix products.
        for &(alpha0_deg, beta0_deg, gamma0_deg) in &[
            (0.0, 0.0, 0.0),
            (12.0, -7.5, 40.0),
            (-30.0, 25.0, 200.0),
            (89.0, -60.0, -135.0),
        ] {
            let m = MountAttitude {
                alpha0_deg,
                beta0_deg,
                gamma0_deg,
            };
            let want = mat_mul(
                &mat_mul(&rot_z(gamma0_deg), &rot_x(alpha0_deg)),
                &rot_y(beta0_deg),
            );
            let got = m.matrix();
            for (gr, wr) in got.iter().zip(want.iter()) {
                for (g, w) in gr.iter().zip(wr.iter()) {
                    assert!((g - w).abs() < 1e-15, "{got:?} != {want:?}");
                }
            }
        }
    }

    #[test]
    fn tilt_readings_round_trip() {
        let m = MountAttitude {
            alpha0_deg: 12.0f64,
            beta0_deg: -7.5,
            gamma0_deg: 40.0,
        };
        let (tx, ty, h) = m.to_sensors();
        let back = MountAttitude::from_sensors(tx, ty, h).unwrap();
        assert!((back.alpha0_deg - 12.0).abs() < 1e-9);
        assert!((back.beta0_deg + 7.5).abs() < 1e-9);
        assert!((back.gamma0_deg - 40.0).abs() < 1e-9);
    }

    #[test]
    fn tilt_of_single_rotation_by_hand() {
        // Rotating 10° about X only: the y axis rises by 10°, so it makes
        // 80° with the vertical; the x axis stays horizontal (90°).
        let m = MountAttitude::from_sensors(90.0f64, 80.0, 180.0).unwrap();
        assert!((m.alpha0_deg - 10.0).abs() < 1e-12);
        assert!(m.beta0_deg.abs() < 1e-12);
        assert!(m.gamma0_deg.abs() < 1e-12);
    }

    #[test]
    fn bad_sensor_values_are_errors() {
        assert_eq!(
            MountAttitude::from_sensors(f64::NAN, 90.0, 0.0),
            Err(AttitudeError::NotFinite)
        );
        assert_eq!(
            MountAttitude::from_sensors(200.0f64, 90.0, 0.0),
            Err(AttitudeError::InconsistentTilt)
        );
        // Both axes 10° from vertical cannot happen together.
        assert_eq!(
            MountAttitude::from_sensors(10.0f64, 10.0, 0.0),
            Err(AttitudeError::InconsistentTilt)
        );
        let m = MountAttitude::<f64>::level();
        assert_eq!(
            m.solutions(&[0.0, 0.0, 0.0], 0.0),
            Err(AttitudeError::ZeroVector)
        );
    }

    #[test]
    fn sun_at_zenith_keeps_gamma() {
        let m = MountAttitude::<f64>::level();
        let s = sun_vector_xyz(90.0, 123.0);
        let [p1, _] = m.solutions(&s, 17.0).unwrap();
        assert_eq!(p1.gamma_deg, 17.0);
        assert!(p1.alpha_deg.abs() < 1e-9);
    }

    #[test]
    fn travel_sums_both_axes() {
        let a = Pose {
            gamma_deg: -170.0f64,
            alpha_deg: 20.0,
        };
        let b = Pose {
            gamma_deg: 170.0,
            alpha_deg: -5.0,
        };
        // 340° on the C axis (no wrap: the axis turns the long way) + 25°.
        assert_eq!(a.travel_deg(&b), 365.0);
        assert_eq!(b.travel_deg(&a), 365.0);
        assert_eq!(a.travel_deg(&a), 0.0);
    }

    #[test]
    fn limits_pick_the_other_solution() {
        let m = MountAttitude::<f64>::level();
        let s = sun_vector_xyz(30.91, 141.61);
        let lim = PoseLimits {
            gamma_min_deg: -180.0,
            gamma_max_deg: 180.0,
            alpha_min_deg: 0.0,
            alpha_max_deg: 90.0,
        };
        let c = m.choose(&s, &Pose::default(), &lim).unwrap();
        let Choice::Reachable(p) = c else {
            panic!("{c:?}")
        };
        assert!(p.alpha_deg > 0.0);
        assert!(m.pointing_error_deg(&p, &s) < 1e-9);
        // Nothing reachable → clamped.
        let lim = PoseLimits {
            gamma_min_deg: 0.0,
            gamma_max_deg: 10.0,
            alpha_min_deg: 0.0,
            alpha_max_deg: 10.0,
        };
        assert!(matches!(
            m.choose(&s, &Pose::default(), &lim),
            Ok(Choice::Clamped(_))
        ));
    }

    #[test]
    fn out_of_reach_takes_the_least_miss_then_the_least_travel() {
        let m = MountAttitude::<f64>::level();
        // Sun 30° high: a level mount tilts the panel by the zenith angle,
        // 60°; at ±10° at most it misses by 50° either way, whichever of the
        // two solutions (half a turn apart) it follows: a tie, so the
        // one nearer the current C angle wins.
        let s = sun_vector_xyz(30.0, 200.0);
        let lim = PoseLimits {
            gamma_min_deg: -180.0,
            gamma_max_deg: 180.0,
            alpha_min_deg: -10.0,
            alpha_max_deg: 10.0,
        };
        for sol in m.solutions(&s, 0.0).unwrap() {
            let gamma = wrap180(sol.gamma_deg);
            let from = Pose {
                gamma_deg: gamma,
                alpha_deg: 0.0,
            };
            let c = m.choose(&s, &from, &lim).unwrap();
            let Choice::Clamped(p) = c else {
                panic!("{c:?}")
            };
            assert!((p.gamma_deg - gamma).abs() < 1e-9, "{p:?} from {from:?}");
            assert!((p.alpha_deg.abs() - 10.0).abs() < 1e-9, "{p:?}");
            assert!((m.pointing_error_deg(&p, &s) - 50.0).abs() < 1e-6);
        }
        // Only α ≥ 0: the solution tilting the other way misses by 60°.
        let lim = PoseLimits {
            alpha_min_deg: 0.0,
            ..lim
        };
        for sol in m.solutions(&s, 0.0).unwrap() {
            let from = Pose {
                gamma_deg: wrap180(sol.gamma_deg),
                alpha_deg: 0.0,
            };
            let c = m.choose(&s, &from, &lim).unwrap();
            let Choice::Clamped(p) = c else {
                panic!("{c:?}")
            };
            assert!((p.alpha_deg - 10.0).abs() < 1e-9, "{p:?}");
            assert!((m.pointing_error_deg(&p, &s) - 50.0).abs() < 1e-6);
        }
    }
}
