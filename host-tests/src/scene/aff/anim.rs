//! Transforms and keyframe animation (FORMAT.md sections 4 and 6).
//!
//! * Static `xs`: `M = T · R · S` (column vectors, `p' = M p`).
//! * Tracks: Kochanek–Bartels cubic for translation and scale (6.2),
//!   quaternion KB spline / squad for rotation (6.3), first-match segment
//!   selection that tolerates repeated and backwards key times (6.1),
//!   hemisphere walk that flips keys once, in file order (6.3 step 2),
//!   and `w` clamped before `acos` so non-unit axes cannot give NaN.
//! * Track matrix `T(t) · R(t) · S(t)` (6.4); camera from a track (6.5).
//!
//! All f64; nothing here runs per ray.

pub use crate::scene::V3;

/// Affine transform: rows of a 3×4 matrix, `p' = A p + b` with the last
/// column as `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine(pub [[f64; 4]; 3]);

impl Affine {
    /// The identity.
    pub const IDENTITY: Self = Self([[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., 1., 0.]]);

    /// Translation by `t`.
    pub fn translation(t: V3) -> Self {
        let mut m = Self::IDENTITY;
        for (row, ti) in m.0.iter_mut().zip(t.to_array()) {
            row[3] = ti;
        }
        m
    }

    /// Axis-aligned scale.
    pub fn scale(s: V3) -> Self {
        let mut m = Self::IDENTITY;
        for (i, si) in s.to_array().into_iter().enumerate() {
            m.0[i][i] = si;
        }
        m
    }

    /// Right-handed rotation by `deg` degrees about `axis` (normalised here;
    /// a zero or non-finite axis gives the identity).
    pub fn rotation_deg(axis: V3, deg: f64) -> Self {
        let len = axis.length();
        if len == 0.0 || !len.is_finite() {
            return Self::IDENTITY;
        }
        let half = deg.to_radians() * 0.5;
        let a = axis * (half.sin() / len);
        Self::from_unit_quat([half.cos(), a[0], a[1], a[2]])
    }

    /// Rotation of a unit quaternion `(w, x, y, z)`.
    pub fn from_unit_quat(q: Quat) -> Self {
        let [w, x, y, z] = q;
        Self([
            [
                1. - 2. * (y * y + z * z),
                2. * (x * y - w * z),
                2. * (x * z + w * y),
                0.,
            ],
            [
                2. * (x * y + w * z),
                1. - 2. * (x * x + z * z),
                2. * (y * z - w * x),
                0.,
            ],
            [
                2. * (x * z - w * y),
                2. * (y * z + w * x),
                1. - 2. * (x * x + y * y),
                0.,
            ],
        ])
    }

    /// `T · R · S` of the `xs` record.
    pub fn trs(t: V3, r_axis: V3, r_deg: f64, s: V3) -> Self {
        Self::translation(t)
            .mul(&Self::rotation_deg(r_axis, r_deg))
            .mul(&Self::scale(s))
    }

    /// Matrix product `self · other`.
    #[must_use]
    pub fn mul(&self, o: &Self) -> Self {
        let a = &self.0;
        let b = &o.0;
        let mut r = [[0.0; 4]; 3];
        for i in 0..3 {
            for j in 0..4 {
                r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
            }
            r[i][3] += a[i][3];
        }
        Self(r)
    }

    /// Transforms a point.
    pub fn point(&self, p: V3) -> V3 {
        let m = &self.0;
        V3::from([0, 1, 2].map(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3]))
    }

    /// Transforms a direction (no translation).
    #[cfg(test)]
    pub fn vector(&self, v: V3) -> V3 {
        let m = &self.0;
        V3::from([0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2]))
    }

    /// Column `j` of the 3×3 part.
    pub fn column(&self, j: usize) -> V3 {
        V3::new(self.0[0][j], self.0[1][j], self.0[2][j])
    }

    /// The inverse transpose of the 3×3 part (the normal matrix), as rows;
    /// `None` when the part is singular or not finite.
    pub fn normal_matrix(&self) -> Option<[[f64; 3]; 3]> {
        let m = &self.0;
        // Cofactor matrix = det · inverse-transpose; the normal direction
        // does not care about the positive factor, only its sign.
        let c = |r0: usize, r1: usize, c0: usize, c1: usize| {
            m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]
        };
        let cof = [
            [c(1, 2, 1, 2), -c(1, 2, 0, 2), c(1, 2, 0, 1)],
            [-c(0, 2, 1, 2), c(0, 2, 0, 2), -c(0, 2, 0, 1)],
            [c(0, 1, 1, 2), -c(0, 1, 0, 2), c(0, 1, 0, 1)],
        ];
        let det = m[0][0] * cof[0][0] + m[0][1] * cof[0][1] + m[0][2] * cof[0][2];
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        Some(cof.map(|row| row.map(|v| v / det)))
    }
}

/// Quaternion `(w, x, y, z)`; not necessarily unit (see 6.3).
pub type Quat = [f64; 4];

fn qmul(a: Quat, b: Quat) -> Quat {
    let [aw, ax, ay, az] = a;
    let [bw, bx, by, bz] = b;
    [
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ]
}
fn qconj(q: Quat) -> Quat {
    [q[0], -q[1], -q[2], -q[3]]
}
fn qdot(a: Quat, b: Quat) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}
fn qscale(q: Quat, s: f64) -> Quat {
    q.map(|v| v * s)
}
fn qadd(a: Quat, b: Quat) -> Quat {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
}
fn vpart(q: Quat) -> V3 {
    V3::new(q[1], q[2], q[3])
}

/// `log(w, v) = (0, φ · v / sin φ)`, φ = acos w; `(0, v)` unchanged when
/// `|w| ≥ 1` or `sin φ < 1e-3`.
///
/// For a unit quaternion `sin φ = |v|`, which is how FORMAT.md §6.3 writes
/// it (`φ v/|v|`). The key quaternions with non-unit axes are not unit,
/// and there the two differ: dividing by `sin φ` reproduces the reference's
/// NaN window on robots `grip_rot2` exactly (w > 1 for t in V3::new(5.888, 6.0)
/// and (42.0, 42.182), as FORMAT.md reports), dividing by `|v|` does not
/// (V3::new(5.911, 6.0) and (42.0, 42.143)); so the reference divides by `sin φ`
/// (test `grip_rot2_window_where_w_exceeds_one_matches_reference`).
fn qlog(q: Quat) -> Quat {
    let v = vpart(q);
    if q[0].abs() >= 1.0 {
        return [0.0, v[0], v[1], v[2]];
    }
    let phi = q[0].acos();
    let sin_phi = phi.sin();
    if sin_phi < 1e-3 {
        return [0.0, v[0], v[1], v[2]];
    }
    let s = phi / sin_phi;
    [0.0, v[0] * s, v[1] * s, v[2] * s]
}

/// `exp(0, v) = (cos|v|, sin|v| · v/|v|)`; the vector part stays `v` when
/// `sin|v| < 1e-3`.
fn qexp(q: Quat) -> Quat {
    let v = vpart(q);
    let th = v.length();
    let s = th.sin();
    if s < 1e-3 {
        return [th.cos(), v[0], v[1], v[2]];
    }
    let k = s / th;
    [th.cos(), v[0] * k, v[1] * k, v[2] * k]
}

/// Spherical interpolation; dot clamped to [−1, 1], returns `p` when
/// sin(angle) < 1e-3; no sign flip.
fn slerp(p: Quat, q: Quat, s: f64) -> Quat {
    let c = qdot(p, q).clamp(-1.0, 1.0);
    let a = c.acos();
    let sa = a.sin();
    if sa < 1e-3 {
        return p;
    }
    qadd(
        qscale(p, ((1.0 - s) * a).sin() / sa),
        qscale(q, (s * a).sin() / sa),
    )
}

/// Tension, continuity, bias of one key.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tcb {
    /// Tension.
    pub t: f64,
    /// Continuity.
    pub c: f64,
    /// Bias.
    pub b: f64,
}

impl Tcb {
    /// Weights of (incoming difference, outgoing difference) for the
    /// outgoing tangent at this key.
    fn out_weights(&self) -> (f64, f64) {
        (
            0.5 * (1. - self.t) * (1. + self.c) * (1. + self.b),
            0.5 * (1. - self.t) * (1. - self.c) * (1. - self.b),
        )
    }
    /// Weights of (incoming, outgoing) difference for the incoming tangent.
    fn in_weights(&self) -> (f64, f64) {
        (
            0.5 * (1. - self.t) * (1. - self.c) * (1. + self.b),
            0.5 * (1. - self.t) * (1. + self.c) * (1. - self.b),
        )
    }
}

/// One key of a vector channel (translation or scale).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VecKey {
    /// Key time.
    pub time: f64,
    /// Value.
    pub value: V3,
    /// Spline shape.
    pub tcb: Tcb,
}

/// One key of a rotation channel, as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotKey {
    /// Key time.
    pub time: f64,
    /// Axis as written (not normalised, 6.3).
    pub axis: V3,
    /// Angle in degrees (any size).
    pub deg: f64,
    /// Spline shape.
    pub tcb: Tcb,
}

/// Minimum number of keys per spline channel (the reference needs 4).
pub const MIN_KEYS: usize = 4;

/// Segment and parameter for time `t` (6.1). `times.len() >= 4`.
/// Returns `(j, u)`: the segment from key j+1 to key j+2, `u ∈ [0, 1]`.
pub fn segment(times: &[f64], t: f64) -> (usize, f64) {
    let n = times.len();
    debug_assert!(n >= MIN_KEYS);
    if t <= times[1] {
        return (0, 0.0);
    }
    if t >= times[n - 2] {
        return (n - 4, 1.0);
    }
    for j in 0..n - 3 {
        if t < times[j + 2] {
            let (tb, tc) = (times[j + 1], times[j + 2]);
            let u = if tc > tb { (t - tb) / (tc - tb) } else { 0.0 };
            return (j, u.clamp(0.0, 1.0));
        }
    }
    (n - 4, 1.0)
}

/// Time-adjustment factor `2 (t_c − t_b) / den`; 1 when `den` is zero or
/// the result not finite (never the case in the BART data).
fn gain(tc_minus_tb: f64, den: f64) -> f64 {
    let g = 2.0 * tc_minus_tb / den;
    if g.is_finite() { g } else { 1.0 }
}

/// Kochanek–Bartels cubic (6.2) at time `t`.
pub fn eval_vec(keys: &[VecKey], t: f64) -> V3 {
    let times: Vec<f64> = keys.iter().map(|k| k.time).collect();
    let (j, u) = segment(&times, t);
    let (a, b, c, d) = (&keys[j], &keys[j + 1], &keys[j + 2], &keys[j + 3]);
    let dd = c.value - b.value;
    let gb = gain(c.time - b.time, c.time - a.time);
    let gc = gain(c.time - b.time, d.time - b.time);
    let (wi, wo) = b.tcb.out_weights();
    let tout = (((b.value - a.value) * wi) + (dd * wo)) * gb;
    let (wi, wo) = c.tcb.in_weights();
    let tin = ((dd * wi) + ((d.value - c.value) * wo)) * gc;
    let (u2, u3) = (u * u, u * u * u);
    V3::from([0, 1, 2].map(|i| {
        b.value[i]
            + tout[i] * u
            + (3. * dd[i] - 2. * tout[i] - tin[i]) * u2
            + (-2. * dd[i] + tout[i] + tin[i]) * u3
    }))
}

fn key_quat(axis: V3, deg: f64) -> Quat {
    let h = deg.to_radians() * 0.5;
    let s = h.sin();
    [h.cos(), axis[0] * s, axis[1] * s, axis[2] * s]
}

/// Rotation channel prepared for evaluation: quaternions after the
/// hemisphere walk of 6.3 step 2.
#[derive(Clone, Debug, PartialEq)]
pub struct RotChannel {
    times: Vec<f64>,
    tcb: Vec<Tcb>,
    q: Vec<Quat>,
}

impl RotChannel {
    /// Builds the channel (`keys.len() >= 4`): key quaternions
    /// `(cos θ/2, sin θ/2 · axis)` with the axis as written, then, segment by
    /// segment in file order, `q_{j+2}` negated when `q_{j+1} · q_{j+2} < 0`;
    /// a negated key is stored back with a normalised axis (as the
    /// reference's axis/angle round trip does).
    pub fn new(keys: &[RotKey]) -> Self {
        let mut q: Vec<Quat> = keys.iter().map(|k| key_quat(k.axis, k.deg)).collect();
        for j in 0..keys.len().saturating_sub(3) {
            if qdot(q[j + 1], q[j + 2]) < 0.0 {
                let n = qscale(q[j + 2], -1.0);
                // Axis/angle round trip: same w, vector part rescaled to
                // length sqrt(1 − w²).
                let w = n[0].clamp(-1.0, 1.0);
                let v = vpart(n);
                q[j + 2] = match v.try_normalize() {
                    Some(ax) => {
                        let s = (1.0 - w * w).sqrt();
                        [w, ax[0] * s, ax[1] * s, ax[2] * s]
                    }
                    None => [w, 0.0, 0.0, 0.0],
                };
            }
        }
        Self {
            times: keys.iter().map(|k| k.time).collect(),
            tcb: keys.iter().map(|k| k.tcb).collect(),
            q,
        }
    }

    /// The interpolated (not yet normalised) quaternion at `t` (6.3 step 3).
    pub fn eval_quat(&self, t: f64) -> Quat {
        let (j, s) = segment(&self.times, t);
        let (qa, qb, qc, qd) = (self.q[j], self.q[j + 1], self.q[j + 2], self.q[j + 3]);
        let (ta, tb, tc, td) = (
            self.times[j],
            self.times[j + 1],
            self.times[j + 2],
            self.times[j + 3],
        );
        let gb = gain(tc - tb, tc - ta);
        let gc = gain(tc - tb, td - tb);
        let l = qlog(qmul(qconj(qb), qc));
        let (wi, wo) = self.tcb[j + 1].out_weights();
        let tout = qscale(
            qadd(qscale(qlog(qmul(qconj(qa), qb)), wi), qscale(l, wo)),
            gb,
        );
        let (wi, wo) = self.tcb[j + 2].in_weights();
        let tin = qscale(
            qadd(qscale(l, wi), qscale(qlog(qmul(qconj(qc), qd)), wo)),
            gc,
        );
        let a = qmul(qb, qexp(qscale(qadd(tout, qscale(l, -1.0)), 0.5)));
        let b = qmul(qc, qexp(qscale(qadd(l, qscale(tin, -1.0)), 0.5)));
        slerp(slerp(qb, qc, s), slerp(a, b, s), 2.0 * s * (1.0 - s))
    }

    /// The rotation at `t` (6.3 step 4): `w` clamped to [−1, 1], axis =
    /// normalised vector part (identity when it is zero).
    pub fn eval(&self, t: f64) -> Affine {
        Affine::from_unit_quat(unit_from(self.eval_quat(t)))
    }
}

/// `(w, √(1−w²) · axis)` with w clamped to [−1, 1]; identity for a zero or
/// non-finite vector part.
fn unit_from(q: Quat) -> Quat {
    if !q.iter().all(|v| v.is_finite()) {
        return [1.0, 0.0, 0.0, 0.0];
    }
    let w = q[0].clamp(-1.0, 1.0);
    match vpart(q).try_normalize() {
        Some(ax) => {
            let s = (1.0 - w * w).sqrt();
            [w, ax[0] * s, ax[1] * s, ax[2] * s]
        }
        None => [1.0, 0.0, 0.0, 0.0],
    }
}

/// Visibility channel key (6.7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VisKey {
    /// Key time.
    pub time: f64,
    /// Visible from this time on.
    pub visible: bool,
}

/// A keyframe track `k NAME { … }`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Track {
    /// Translation keys (≥ 4) or none.
    pub transl: Option<Vec<VecKey>>,
    /// Rotation channel or none.
    pub rot: Option<RotChannel>,
    /// Scale keys (≥ 4) or none.
    pub scale: Option<Vec<VecKey>>,
    /// Visibility keys or none.
    pub visibility: Option<Vec<VisKey>>,
}

impl Track {
    /// Translation at `t` (zero when the channel is missing).
    pub fn translation(&self, t: f64) -> Option<V3> {
        self.transl.as_ref().map(|k| eval_vec(k, t))
    }

    /// `M(t) = T(t) · R(t) · S(t)` (6.4).
    pub fn matrix(&self, t: f64) -> Affine {
        let tr = self
            .translation(t)
            .map_or(Affine::IDENTITY, Affine::translation);
        let r = self.rot.as_ref().map_or(Affine::IDENTITY, |r| r.eval(t));
        let s = self
            .scale
            .as_ref()
            .map_or(Affine::IDENTITY, |k| Affine::scale(eval_vec(k, t)));
        tr.mul(&r).mul(&s)
    }

    /// Visible at `t` (6.7): visible before the first key; from each key time
    /// on, that key's flag (keys in file order, the last key not after `t`
    /// wins).
    pub fn visible(&self, t: f64) -> bool {
        let Some(keys) = &self.visibility else {
            return true;
        };
        let mut vis = true;
        for k in keys {
            if k.time <= t {
                vis = k.visible;
            }
        }
        vis
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vk(time: f64, x: f64) -> VecKey {
        VecKey {
            time,
            value: V3::new(x, 2.0 * x, -x),
            tcb: Tcb::default(),
        }
    }
    fn rk(time: f64, axis: V3, deg: f64) -> RotKey {
        RotKey {
            time,
            axis,
            deg,
            tcb: Tcb::default(),
        }
    }
    /// Keys about `axis` at times 0, 1, 2, … with the angles `degs`.
    fn keys_about(axis: V3, degs: &[f64]) -> Vec<RotKey> {
        degs.iter()
            .enumerate()
            .map(|(i, &d)| rk(i as f64, axis, d))
            .collect()
    }
    fn close(a: V3, b: V3, eps: f64) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() <= eps)
    }

    #[test]
    fn segment_selection_first_match_with_backwards_and_repeated_times() {
        // Shape of robots gun_rot: … 47.5, 48, 42, 42.5 … 50, 50.
        let times = [0.0, 0.0, 47.5, 48.0, 42.0, 42.5, 50.0, 50.0];
        assert_eq!(segment(&times, -3.0), (0, 0.0));
        assert_eq!(segment(&times, 0.0), (0, 0.0));
        // 40 < 47.5 → first segment (keys 1..2), u = 40/47.5.
        assert_eq!(segment(&times, 40.0), (0, 40.0 / 47.5));
        // 47.75: not < 47.5; < 48 → segment 1 (keys 2..3), u = 0.5.
        assert_eq!(segment(&times, 47.75), (1, 0.5));
        // 49: not < 47.5, 48, 42, 42.5; < 50 → segment 4 (keys 5..6).
        assert_eq!(segment(&times, 49.0), (4, (49.0 - 42.5) / 7.5));
        assert_eq!(segment(&times, 50.0), (4, 1.0));
        assert_eq!(segment(&times, 99.0), (4, 1.0));
        // Repeated time in the middle: zero-length segment never chosen.
        let times = [0.0, 1.0, 2.0, 2.0, 3.0, 4.0];
        assert_eq!(segment(&times, 2.0), (2, 0.0));
        assert_eq!(segment(&times, 1.5), (0, 0.5));
    }

    #[test]
    fn linear_keys_give_linear_motion() {
        // Equal spacing: Catmull–Rom of collinear equally spaced data is
        // the line: P(u) = 1 + u (by hand: Tout = Tin = D = 1).
        let keys = [vk(0., 0.), vk(1., 1.), vk(2., 2.), vk(3., 3.)];
        assert!(close(
            eval_vec(&keys, 1.25),
            V3::new(1.25, 2.5, -1.25),
            1e-12
        ));
        assert!(close(eval_vec(&keys, -5.0), V3::new(1.0, 2.0, -1.0), 1e-12));
        assert!(close(eval_vec(&keys, 9.0), V3::new(2.0, 4.0, -2.0), 1e-12));
        // Unequal spacing, value = time: g_b = g_c = 4/3, Tout = Tin = 2,
        // D = 2 → P(u) = 1 + 2u, i.e. P(2) = 2.
        let keys = [vk(0., 0.), vk(1., 1.), vk(3., 3.), vk(4., 4.)];
        assert!(close(eval_vec(&keys, 2.0), V3::new(2.0, 4.0, -2.0), 1e-12));
        assert!(close(eval_vec(&keys, 1.5), V3::new(1.5, 3.0, -1.5), 1e-12));
    }

    #[test]
    fn full_tension_gives_zero_tangents() {
        // Tension 1: Tout = Tin = 0, P(u) = P_b + D (3u² − 2u³).
        let mut keys = [vk(0., 5.), vk(1., 1.), vk(2., 3.), vk(3., -7.)];
        for k in &mut keys {
            k.tcb.t = 1.0;
        }
        // u = 0.25: 3/16 − 2/64 = 0.15625 → 1 + 2·0.15625 = 1.3125.
        let p = eval_vec(&keys, 1.25);
        assert!(close(p, V3::new(1.3125, 2.625, -1.3125), 1e-12), "{p:?}");
    }

    #[test]
    fn bias_one_uses_only_incoming_difference() {
        // Key b bias 1 (T = C = 0): Tout = g_b · (P_b − P_a) (weight 1, 0).
        // Keys 0,1,2,3 at values 0,1,1,1: P_b − P_a = 1, D = 0, Tin = 0
        // (key c: incoming D = 0, outgoing 0). P(u) = 1 + u − 2u² + u³.
        let mut keys = [vk(0., 0.), vk(1., 1.), vk(2., 1.), vk(3., 1.)];
        keys[1].tcb.b = 1.0;
        let u: f64 = 0.5;
        let want = 1.0 + u - 2.0 * u * u + u * u * u;
        assert!((eval_vec(&keys, 1.5)[0] - want).abs() < 1e-12);
    }

    #[test]
    fn ninety_degrees_about_non_unit_axis() {
        // Axis (0, 0, 2) as written: q = (cos 45°, 0, 0, 2 sin 45°), not
        // unit; every key equal so the spline returns q, and step 4
        // normalises the axis: 90° about +z maps x to y and y to −x.
        let keys = keys_about(V3::new(0., 0., 2.), &[90.; 4]);
        let r = RotChannel::new(&keys).eval(1.5);
        assert!(close(
            r.vector(V3::new(1., 0., 0.)),
            V3::new(0., 1., 0.),
            1e-12
        ));
        assert!(close(
            r.vector(V3::new(0., 1., 0.)),
            V3::new(-1., 0., 0.),
            1e-12
        ));
        assert!(close(
            r.vector(V3::new(0., 0., 1.)),
            V3::new(0., 0., 1.),
            1e-12
        ));
    }

    fn angle_about_z(r: &Affine) -> f64 {
        let x = r.vector(V3::new(1., 0., 0.));
        assert!(x[2].abs() < 1e-12);
        x[1].atan2(x[0]).to_degrees()
    }

    #[test]
    fn squad_about_one_axis_matches_hand_values() {
        // Keys 0°, 0°, 90°, 90° about z at t = 0..3, TCB 0. Segment 1→2:
        // L = (0,0,0,π/4), Tout = Tin = L/2, A = exp(−L/4) (−22.5°),
        // B = q_c·exp(L/4) (112.5°). Same-axis slerps interpolate the angle
        // linearly: at s = 0.25, slerp(q_b,q_c) = 22.5°, slerp(A,B) =
        // −22.5 + 0.25·135 = 11.25°, blend h = 2·0.25·0.75 = 0.375 →
        // 22.5 + 0.375·(11.25 − 22.5) = 18.28125°. At s = 0.5 → 45°.
        let keys = keys_about(V3::new(0., 0., 1.), &[0., 0., 90., 90.]);
        let ch = RotChannel::new(&keys);
        assert!((angle_about_z(&ch.eval(1.25)) - 18.28125).abs() < 1e-9);
        assert!((angle_about_z(&ch.eval(1.5)) - 45.0).abs() < 1e-9);
        assert!((angle_about_z(&ch.eval(2.0)) - 90.0).abs() < 1e-9);
        assert!(angle_about_z(&ch.eval(0.5)).abs() < 1e-9);
    }

    #[test]
    fn hemisphere_walk_takes_the_short_way() {
        // 350° and 10° are 20° apart as rotations but their quaternions
        // (cos 175°, …) and (cos 5°, …) have a negative dot product; the
        // walk negates key 2 so the midpoint is 0° (= 360°), not 180°.
        let keys = keys_about(V3::new(0., 0., 1.), &[350., 350., 10., 10.]);
        let a = angle_about_z(&RotChannel::new(&keys).eval(1.5));
        assert!(a.abs() < 1e-9, "{a}");
    }

    #[test]
    fn non_unit_axes_never_give_nan() {
        // Axis length 1.077 (robots grip_rot2): interpolated w can exceed 1;
        // the clamp keeps the result a finite rotation.
        let keys = keys_about(V3::new(0.0, 1.077, 0.0), &[0., 0., 720., 720., 10., 10.]);
        let ch = RotChannel::new(&keys);
        for i in 0..=500 {
            let m = ch.eval(i as f64 * 0.01);
            assert!(m.0.iter().flatten().all(|v| v.is_finite()), "t={i}");
            // Still a rotation: columns unit length.
            for j in 0..3 {
                assert!((m.column(j).length() - 1.0).abs() < 1e-9);
            }
        }
    }

    /// Robots `grip_rot2` (Robot2.aff): axis length 1.077, 90° steps. FORMAT.md
    /// §6.3 reports that the reference's interpolated `w` exceeds 1 (acos →
    /// NaN) exactly for t in V3::new(5.888, 6.0) and (42.0, 42.182): the spline
    /// here must put the same window there (to the 3 printed digits), and
    /// the clamp must turn it into the identity.
    #[test]
    fn grip_rot2_window_where_w_exceeds_one_matches_reference() {
        let times = [
            0., 0., 0.75, 1.5, 2.25, 3., 3.75, 4.5, 5.25, 6., 42., 43.25, 44.5, 45.75, 47., 48.25,
            49.5, 50.75, 52., 52.,
        ];
        let degs = [
            0., 0., 90., 180., 270., 360., 450., 540., 630., 720., 0., 90., 180., 270., 360., 450.,
            540., 630., 720., 720.,
        ];
        let keys: Vec<RotKey> = times
            .iter()
            .zip(degs)
            .map(|(&t, d)| rk(t, V3::new(0.76, -0.62, -0.445), d))
            .collect();
        let ch = RotChannel::new(&keys);
        let over = |t: f64| ch.eval_quat(t)[0] > 1.0;
        // Scan in steps of 1e-4 and find the window edges; the reference's
        // are given to 1e-3 (first 5.888, last 42.182).
        let first = (58_000..60_000)
            .map(|i| i as f64 * 1e-4)
            .find(|&t| over(t))
            .unwrap();
        assert!((5.887..=5.888).contains(&first), "{first}");
        assert!(over(5.9999) && !over(6.0));
        let last = (420_001..423_000)
            .rev()
            .map(|i| i as f64 * 1e-4)
            .find(|&t| over(t))
            .unwrap();
        assert!((42.182..42.183).contains(&last), "{last}");
        assert!(over(42.0001));
        for t in [5.9, 5.95, 42.1] {
            assert_eq!(ch.eval(t), Affine::IDENTITY, "t = {t}");
        }
    }

    #[test]
    fn static_transform_order_is_t_r_s() {
        // Scale x by 2, rotate 90° about y (x → −z), translate by (1,2,3):
        // (1,0,0) → (2,0,0) → (0,0,−2) → (1,2,1).
        let m = Affine::trs(
            V3::new(1., 2., 3.),
            V3::new(0., 1., 0.),
            90.,
            V3::new(2., 1., 1.),
        );
        assert!(close(
            m.point(V3::new(1., 0., 0.)),
            V3::new(1., 2., 1.),
            1e-12
        ));
        // Normals under non-uniform scale use the inverse transpose: the
        // plane x + y = 0 scaled by (2,1,1) has normal ∝ (1/2, 1, 0).
        let s = Affine::scale(V3::new(2., 1., 1.));
        let nm = s.normal_matrix().unwrap();
        let n = V3::from([0, 1, 2].map(|i| V3::from(nm[i]).dot(V3::new(1., 1., 0.))));
        assert!(close(n, V3::new(0.5, 1., 0.), 1e-12));
        assert!(Affine::scale(V3::new(0., 1., 1.)).normal_matrix().is_none());
    }

    #[test]
    fn track_matrix_and_visibility() {
        let t = Track {
            transl: Some(vec![vk(0., 1.); 4]),
            scale: Some(vec![
                VecKey {
                    time: 0.,
                    value: V3::new(3., 3., 3.),
                    tcb: Tcb::default()
                };
                4
            ]),
            visibility: Some(vec![
                VisKey {
                    time: 1.0,
                    visible: false,
                },
                VisKey {
                    time: 2.0,
                    visible: true,
                },
            ]),
            ..Track::default()
        };
        // T · S: (1,0,0) → (3,0,0) → (4,2,−1).
        assert!(close(
            t.matrix(0.).point(V3::new(1., 0., 0.)),
            V3::new(4., 2., -1.),
            1e-12
        ));
        assert!(t.visible(0.5) && !t.visible(1.0) && !t.visible(1.5) && t.visible(2.0));
    }
}
