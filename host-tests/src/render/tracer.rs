//! The Whitted tracer of one pixel: camera paths, ray segments, shadows.

use fixed::types::{I2F30, U32F32};
use raymip::path::raydiff::RayDiff;
use raymip::path::raystack::{PathState, RayStack, stack_bound};
use raymip::units::{PathLength, Spread, UnitVec};

use super::bvh::Hit;
use super::envmap::{FloatMiss, MissRay};
use super::gbuffer::{FirstHit, Frame, GBuffer, GHit};
use super::lod::{LodQuery, hit_lod};
use super::texunit::{FetchLog, Filter, Unit};
use super::{Arithmetic, Counters, HIST_LEVELS, Method, Options, Prepared};
use crate::scene::{Material, Triangle, V3};

/// f64 ray-differential state (Igehy 1999): position and unit-direction
/// derivatives per pixel in x and y.
#[derive(Clone, Copy, Debug, Default)]
struct Diff {
    dpx: V3,
    dpy: V3,
    ddx: V3,
    ddy: V3,
}

/// Ray-stack entries of the renderer: each hit pushes at most a
/// refraction and a reflection, so `stack_bound(bounces, 2) = bounces + 1`
/// entries hold every branch; sized for the largest `bounces` (`u8::MAX`)
/// so that no setting drops one (256 entries of 232 bytes, ≈ 58 KiB of the
/// tracing thread's stack).
pub const STACK_CAPACITY: usize = stack_bound(u8::MAX, 2);

/// A continuation ray with the firmware ray differentials of its path
/// state (zero in float precision).
type Continuation = (Ray, RayDiff);

/// Host side of one ray: the payload of its ray-stack entry. Its LOD state
/// is the firmware [`PathState`] beside it (fixed-point Pl, cone and ray
/// differentials) in fixed precision, and [`FloatPath`] in float precision:
/// one copy per precision, never both.
#[derive(Clone, Copy, Debug)]
struct Ray {
    o: V3,
    d: V3,
    weight: V3,
    tmin: f64,
    /// The f64 LOD state (float precision only).
    float: Option<FloatPath>,
}

/// The f64 LOD state of a path in float precision: path length, cone
/// width and spread, ray differentials.
#[derive(Clone, Copy, Debug)]
struct FloatPath {
    pl: f64,
    width: f64,
    spread: f64,
    diff: Diff,
}

impl Ray {
    /// A continuation of this ray from `o` in direction `d` with `weight`;
    /// its f64 LOD state (if any) continues with path length and cone
    /// width `(pl, width)` at the hit, this ray's cone spread, and
    /// `dd(ddir, dn)` mapping a direction differential and the matching
    /// shading-normal differential to the new ray's.
    fn continued(
        &self,
        o: V3,
        d: V3,
        weight: V3,
        (pl, width): (f64, f64),
        f: &HitFrame,
        dd: impl Fn(V3, V3) -> V3,
    ) -> Self {
        Self {
            o,
            d,
            weight,
            tmin: 0.0,
            float: self.float.map(|p| FloatPath {
                pl,
                width,
                spread: p.spread,
                diff: Diff {
                    dpx: f.dpx,
                    dpy: f.dpy,
                    ddx: dd(p.diff.ddx, f.dnx),
                    ddy: dd(p.diff.ddy, f.dny),
                },
            }),
        }
    }
}

pub(crate) struct Ctx<'a> {
    pub(crate) prep: &'a Prepared,
    pub(crate) opts: &'a Options,
    pub(crate) unit: Unit<'a>,
    pub(crate) counters: Counters,
    pub(crate) log: FetchLog,
    /// Filter override (`None`: the method's, [`Filter::of`]).
    pub(crate) filter: Option<Filter>,
    /// The pixel's generator of stochastic-filter bits (reseeded per pixel).
    pub(crate) rng: raymip::rng::Rng,
    /// The G-buffer ([`Method::Gbuffer`] only): first-hit differentials.
    pub(crate) gbuffer: Option<&'a Frame>,
    /// The pixel being traced.
    pub(crate) px: (u32, u32),
}

/// Deterministic per-sample random numbers in [0, 1).
fn hash01(x: u32, y: u32, s: u32, k: u32) -> f64 {
    let mut z = u64::from(x)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(u64::from(y).wrapping_mul(0xC2B2_AE3D_27D4_EB4F))
        .wrapping_add(u64::from(s).wrapping_mul(0x1656_67B1_9E37_79F9))
        .wrapping_add(u64::from(k));
    z ^= z >> 30;
    z = z.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z ^= z >> 27;
    z = z.wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

impl Ctx<'_> {
    pub(crate) fn pixel(&mut self, x: u32, y: u32) -> (V3, f64) {
        self.px = (x, y);
        if self.opts.method == Method::Truth {
            let n = self.opts.spp.max(1);
            let k = (f64::from(n).sqrt() as u32).max(1);
            let mut acc = V3::ZERO;
            let mut first = f64::NAN;
            for s in 0..n {
                // Stratified k×k jitter for the first k² samples, uniform after.
                let (jx, jy) = if s < k * k {
                    (
                        (f64::from(s % k) + hash01(x, y, s, 0)) / f64::from(k),
                        (f64::from(s / k) + hash01(x, y, s, 1)) / f64::from(k),
                    )
                } else {
                    (hash01(x, y, s, 0), hash01(x, y, s, 1))
                };
                let (c, l) = self.path(f64::from(x) + jx, f64::from(y) + jy);
                acc += c;
                if s == 0 {
                    first = l;
                }
            }
            (acc * (1.0 / f64::from(n)), first)
        } else {
            self.path(f64::from(x) + 0.5, f64::from(y) + 0.5)
        }
    }

    /// Traces one camera path; returns colour and the first textured lod.
    fn path(&mut self, fx: f64, fy: f64) -> (V3, f64) {
        let prep = self.prep;
        let (dv, dxv, dyv) = prep.cam.primary_dir(fx, fy);
        let dd = dv.dot(dv);
        let ddir = |r: V3| ((r * dd) - (dv * dv.dot(r))) * dd.powf(-1.5);
        let fixed = self.fixed();
        let ray = Ray {
            o: prep.cam.eye,
            d: dv.normalize_or_zero(),
            weight: V3::ONE,
            tmin: 0.0,
            float: (!fixed).then(|| FloatPath {
                pl: 0.0,
                width: 0.0,
                spread: prep.cam.gamma,
                diff: Diff {
                    ddx: ddir(dxv),
                    ddy: ddir(dyv),
                    ..Diff::default()
                },
            }),
        };
        self.counters.paths += 1;
        let mut stack: RayStack<Ray, STACK_CAPACITY> = RayStack::new();
        let mut color = V3::ZERO;
        let mut first_lod = f64::NAN;
        let mut state = PathState::primary(&prep.spread, 0xFF);
        if fixed {
            // Firmware set-up: unit direction, forward axis and the change of
            // the unnormalised direction per pixel (its forward part is 1).
            let (d, sat) =
                RayDiff::primary(unit_q(ray.d), unit_q(prep.cam.fwd), dir_q(dxv), dir_q(dyv));
            state.diff = d;
            self.counters.saturations += u64::from(sat);
        }
        // The primary state always fits an empty stack.
        let _ = stack.push_with(state, ray);
        while let Some((state, ray)) = stack.pop_with() {
            self.segment(state, ray, &mut stack, &mut color, &mut first_lod);
        }
        (color, first_lod)
    }

    /// One ray segment: hit frame, texture (LOD choice + sample), local
    /// shading, continuation rays with the surface spread.
    fn segment(
        &mut self,
        state: PathState,
        ray: Ray,
        stack: &mut RayStack<Ray, STACK_CAPACITY>,
        color: &mut V3,
        first_lod: &mut f64,
    ) {
        let prep = self.prep;
        let scene = &prep.scene;
        self.counters.rays += 1;
        let Some(hit) = prep.bvh.closest(ray.o, ray.d, ray.tmin, f64::INFINITY) else {
            *color += ray.weight * self.miss(&state, &ray);
            return;
        };
        self.counters.hits += 1;
        let depth = usize::from(state.depth);
        if let Some(c) = self.counters.depth_hist.get_mut(depth) {
            *c += 1;
        }
        let t_fixed = U32F32::saturating_from_num(hit.t);
        let mut state = state.advance(PathLength::from_fixed(t_fixed));
        let tri = &scene.triangles[hit.tri as usize];
        let mat = &scene.materials[tri.material as usize];
        // A path's first hit takes its differentials from the G-buffer
        // (method gbuffer), every other hit transfers them.
        let first = match (self.gbuffer, state.depth) {
            (Some(g), 0) => g.first_hit(self.px.0, self.px.1, &state.diff),
            _ => None,
        };
        // The ray differentials at the hit plane (geometric normal): the
        // firmware's in fixed precision, f64 in float.
        let mut f = HitFrame::new(tri, &ray, &hit, |ng| match (first, ray.float) {
            (Some(FirstHit::Fixed(d, _, sat)), _) => {
                state.diff = d;
                state.saturated |= sat;
                (v3_of(d.dodx), v3_of(d.dody))
            }
            (Some(FirstHit::Float(dp, _)), _) => (dp[0], dp[1]),
            (None, None) => {
                let (d, sat) =
                    state
                        .diff
                        .transfer(unit_q(ray.d), PathLength::from_fixed(t_fixed), unit_q(ng));
                state.diff = d;
                state.saturated |= sat;
                (v3_of(d.dodx), v3_of(d.dody))
            }
            (None, Some(p)) => {
                let transfer = |dp: V3, dd: V3| {
                    let q = dp + dd * hit.t;
                    let dt = -q.dot(ng) / ray.d.dot(ng);
                    q + ray.d * dt
                };
                (
                    transfer(p.diff.dpx, p.diff.ddx),
                    transfer(p.diff.dpy, p.diff.ddy),
                )
            }
        });
        // ... and its shading-normal differentials, for the reflection and
        // refraction differentials.
        match first {
            Some(FirstHit::Fixed(_, [dnx, dny], _)) => {
                (f.dnx, f.dny) = (v3_dir(dnx), v3_dir(dny));
                f.dn_fixed = Some([dnx, dny]);
            }
            Some(FirstHit::Float(_, [dnx, dny])) => (f.dnx, f.dny) = (dnx, dny),
            None => {}
        }
        if state.saturated {
            self.counters.saturations += 1;
        }
        // Path length and cone width at the hit, in the precision's state.
        let (pl, width) = match ray.float {
            None => (state.pl.to_num::<f64>(), state.cone.width.to_num::<f64>()),
            Some(p) => (p.pl + f.t, p.width + p.spread * f.t),
        };
        let kd = self.texture(hit.tri as usize, &f, &ray, &state, pl, width, first_lod);
        let local = self.local_shading(mat, &f, &ray, kd, tri.is_textured());
        *color += ray.weight * local;
        if usize::from(state.depth) >= usize::from(self.opts.bounces) {
            return;
        }
        let (refr, refl) = self.continuations(mat, &f, &ray, pl, width, &state);
        let beta = surface_spread(&f, width);
        let beta_fixed = Spread::saturating_from_num(beta);
        let refl = refl.map(|(mut r, d)| {
            if let Some(p) = r.float.as_mut() {
                p.spread += beta;
            }
            (r, d, beta_fixed)
        });
        let refr = refr.map(|(r, d)| (r, d, Spread::ZERO));
        self.counters.refractions += u64::from(refr.is_some());
        self.counters.reflections += u64::from(refl.is_some());
        for (r, d, b) in [refr, refl].into_iter().flatten() {
            let mut next = state.bounce(b);
            next.diff = d;
            if stack.push_with(next, r).is_ok() {
                self.counters.bounces += 1;
            } else {
                self.counters.stack_full += 1;
            }
        }
        self.counters.stack_peak = self.counters.stack_peak.max(stack.len() as u64);
    }

    /// Texture step: the LOD choice and one sample; returns the diffuse
    /// colour modulated by the texture (the material's diffuse when
    /// untextured or when the lod is undefined).
    #[allow(clippy::too_many_arguments)]
    fn texture(
        &mut self,
        tri_index: usize,
        f: &HitFrame,
        ray: &Ray,
        state: &PathState,
        pl: f64,
        width: f64,
        first_lod: &mut f64,
    ) -> V3 {
        let prep = self.prep;
        let tri = &prep.scene.triangles[tri_index];
        let kd = prep.scene.materials[tri.material as usize].diffuse;
        let (Some(x), Some(uv)) = (tri.texture, tri.uv) else {
            self.counters.untextured_skipped += 1;
            return kd;
        };
        let tex = &prep.textures[x as usize];
        let [b0, b1, b2] = f.b;
        let u = b0 * uv[0][0] + b1 * uv[1][0] + b2 * uv[2][0];
        let vv = b0 * uv[0][1] + b1 * uv[1][1] + b2 * uv[2][1];
        let query = LodQuery {
            tri: tri_index,
            tex,
            uv: &uv,
            state,
            pl,
            width,
            n_dot_d: f.ng.dot(ray.d).abs(),
            dbx: f.dbx,
            dby: f.dby,
        };
        let Some(hit) = hit_lod(&mut self.unit, prep, self.opts.method, &query) else {
            self.counters.untextured_skipped += 1;
            return kd;
        };
        let lod = hit.lod();
        self.counters.textured_hits += 1;
        self.counters.level_hist[lod.level(tex.levels).min(HIST_LEVELS - 1)] += 1;
        self.counters.lod_sum_256 += lod.q256();
        if first_lod.is_nan() {
            *first_lod = lod.to_f64();
        }
        // Anisotropic filtering over the method's own footprint: only ray
        // differentials give one (other methods: `Options::validate`
        // refuses aniso; set anyway, isotropic at the method's lod).
        let filter = self.filter.unwrap_or(Filter::of(self.opts.method));
        let c = hit.sample(
            x as usize,
            u,
            vv,
            filter,
            self.opts.aniso.is_some(),
            &mut self.rng,
            &mut self.log,
        );
        kd * V3::from(c)
    }

    /// The colour of a ray that leaves the scene: the environment map at
    /// the method's lod ([`super::envmap`]), else the background colour.
    fn miss(&self, state: &PathState, ray: &Ray) -> V3 {
        let prep = self.prep;
        let Some(env) = &prep.env else {
            return prep.scene.background;
        };
        let m = MissRay {
            d: ray.d,
            dq: unit_q(ray.d),
            float: ray.float.map(|f| FloatMiss {
                spread: f.spread,
                ddx: f.diff.ddx,
                ddy: f.diff.ddy,
            }),
        };
        env.color(self.opts, state, (prep.spread.angle(), prep.cam.gamma), &m)
    }

    /// Local shading: ambient plus Phong from every light not in shadow.
    fn local_shading(
        &mut self,
        mat: &Material,
        f: &HitFrame,
        ray: &Ray,
        kd: V3,
        textured: bool,
    ) -> V3 {
        let scene = &self.prep.scene;
        let mut local = (scene.ambient * mat.ambient)
            * (if textured {
                kd_ratio(kd, mat.diffuse)
            } else {
                V3::ONE
            });
        let po = f.p + f.face_ng * self.eps();
        for light in &scene.lights {
            let to = light.position - po;
            let dist = to.length();
            let l = to * (1.0 / dist);
            let nl = f.ns.dot(l);
            if nl <= 0.0 || f.face_ng.dot(l) <= 0.0 {
                continue;
            }
            let att = self.shadow(po, l, dist);
            if att.max_element() <= 0.0 {
                continue;
            }
            let hv = (l - ray.d).normalize_or_zero();
            let spec = f.ns.dot(hv).max(0.0).powf(mat.shine.max(1.0));
            let c = (kd * nl) + (mat.specular * spec);
            local += (c * light.color) * att;
        }
        local
    }

    /// Fixed precision: the firmware path state (Pl, cone, ray
    /// differentials) is the only LOD state of a path.
    fn fixed(&self) -> bool {
        self.opts.arithmetic == Arithmetic::Fixed
    }

    /// Ray offset along the normal (scene-relative).
    fn eps(&self) -> f64 {
        self.prep.eps()
    }

    /// Continuation rays: refraction (total internal reflection folds into
    /// the reflection weight) and reflection, with their ray differentials;
    /// `(refracted, reflected)`. Cone spreads are the incoming ray's (the
    /// caller adds the surface spread of the reflection).
    fn continuations(
        &self,
        mat: &Material,
        f: &HitFrame,
        ray: &Ray,
        pl: f64,
        width: f64,
        state: &PathState,
    ) -> (Option<Continuation>, Option<Continuation>) {
        let fw = self.fixed();
        let (dq, nq) = (unit_q(ray.d), unit_q(f.ns));
        let [dnxq, dnyq] = f.dn_fixed.unwrap_or([dir_q(f.dnx), dir_q(f.dny)]);
        let eps = self.eps();
        let ns = f.ns;
        let face_ng = f.face_ng;
        let mut refl_w = ray.weight * mat.specular;
        let trans_w = ray.weight * mat.transmission;
        let cosi = -ray.d.dot(ns);
        let mut refr: Option<Continuation> = None;
        if trans_w.max_element() > 1e-3 {
            let eta = if f.entering {
                1.0 / mat.ior.max(1e-3)
            } else {
                mat.ior
            };
            let k = 1.0 - eta * eta * (1.0 - cosi * cosi);
            if k < 0.0 {
                refl_w += trans_w;
            } else {
                let sk = k.sqrt();
                let mu = eta * cosi - sk;
                let mut dir = ((ray.d * eta) + (ns * mu)).normalize_or_zero();
                if dir.dot(face_ng) >= 0.0 {
                    // The interpolated normal bent the ray back out: refract
                    // about the geometric normal instead.
                    let c = -ray.d.dot(face_ng);
                    let kg = (1.0 - eta * eta * (1.0 - c * c)).max(0.0);
                    dir = ((ray.d * eta) + (face_ng * (eta * c - kg.sqrt()))).normalize_or_zero();
                }
                let dtr = |dd: V3, dn: V3| {
                    let dcos = -(dd.dot(ns) + ray.d.dot(dn));
                    let dmu = (eta - eta * eta * cosi / sk) * dcos;
                    ((dd * eta) + (ns * dmu)) + (dn * mu)
                };
                let fd = if fw {
                    let eta_q = raymip::path::raydiff::Eta::saturating_from_num(eta);
                    let ct = fixed::types::I2F30::saturating_from_num(sk);
                    state.diff.refract(dq, nq, dnxq, dnyq, eta_q, ct).0
                } else {
                    RayDiff::ZERO
                };
                refr = Some((
                    ray.continued(f.p + face_ng * -eps, dir, trans_w, (pl, width), f, dtr),
                    fd,
                ));
            }
        }
        let refl = (refl_w.max_element() > 1e-3).then(|| {
            let dn_ = ray.d.dot(ns);
            let mut dir = (ray.d + ns * (-2.0 * dn_)).normalize_or_zero();
            if dir.dot(face_ng) <= 0.0 {
                // Interpolated normal sends the ray below the surface:
                // reflect about the geometric normal instead.
                dir = (ray.d + face_ng * (-2.0 * ray.d.dot(face_ng))).normalize_or_zero();
            }
            let drf = |dd: V3, dn: V3| {
                let ddn = dd.dot(ns) + ray.d.dot(dn);
                dd - (((dn * dn_) + (ns * ddn)) * 2.0)
            };
            let fd = if fw {
                state.diff.reflect(dq, nq, dnxq, dnyq).0
            } else {
                RayDiff::ZERO
            };
            (
                ray.continued(f.p + face_ng * eps, dir, refl_w, (pl, width), f, drf),
                fd,
            )
        });
        (refr, refl)
    }

    /// Transmission towards a light at `dist` (0 = blocked by an opaque surface).
    fn shadow(&mut self, o: V3, l: V3, dist: f64) -> V3 {
        let prep = self.prep;
        let mut att = V3::ONE;
        let mut tmin = 0.0;
        for _ in 0..8 {
            self.counters.shadow_rays += 1;
            let Some(h) = prep.bvh.closest(o, l, tmin, dist) else {
                return att;
            };
            let m = &prep.scene.materials[prep.scene.triangles[h.tri as usize].material as usize];
            att *= m.transmission;
            if att.max_element() < 1e-3 {
                return V3::ZERO;
            }
            tmin = h.t + 1e-7 * prep.scale;
        }
        att
    }
}

/// Texture modulation factor `kd / diffuse` (1 where the diffuse is 0).
fn kd_ratio(kd: V3, diffuse: V3) -> V3 {
    V3::from(std::array::from_fn::<f64, 3, _>(|k| {
        if diffuse[k] > 0.0 {
            kd[k] / diffuse[k]
        } else {
            1.0
        }
    }))
}

/// The surface at a hit: position, barycentrics, normals and the ray
/// differentials transferred to the hit plane.
struct HitFrame {
    /// Distance along the ray.
    t: f64,
    /// Hit point.
    p: V3,
    /// Barycentric weights of vertices 0, 1, 2.
    b: [f64; 3],
    /// Unit geometric normal (winding side).
    ng: V3,
    /// Geometric normal facing the incoming ray.
    face_ng: V3,
    /// The ray enters the surface (hits the winding side).
    entering: bool,
    /// Unit shading normal facing the incoming ray.
    ns: V3,
    /// Shading-normal derivatives per pixel in x and y.
    dnx: V3,
    dny: V3,
    /// The firmware's shading-normal differentials when they come from
    /// the firmware (the G-buffer's, fixed precision): passed on as they
    /// are instead of `dnx`, `dny`.
    dn_fixed: Option<[[I2F30; 3]; 2]>,
    /// Position differentials on the hit plane per pixel in x and y.
    dpx: V3,
    dpy: V3,
    /// Barycentric (b1, b2) differentials per pixel in x and y.
    dbx: (f64, f64),
    dby: (f64, f64),
}

impl HitFrame {
    fn new(tri: &Triangle, ray: &Ray, hit: &Hit, dp: impl FnOnce(V3) -> (V3, V3)) -> Self {
        let t = hit.t;
        let p = ray.o + ray.d * t;
        let (b0, b1, b2) = (1.0 - hit.b1 - hit.b2, hit.b1, hit.b2);
        let e1 = tri.p[1] - tri.p[0];
        let e2 = tri.p[2] - tri.p[0];
        let gn_raw = e1.cross(e2);
        let gn2 = gn_raw.dot(gn_raw);
        let ng = gn_raw.normalize_or_zero();
        let entering = ng.dot(ray.d) < 0.0;
        let (dpx, dpy) = dp(ng);
        let bary_d = |dp: V3| {
            (
                dp.cross(e2).dot(gn_raw) / gn2,
                e1.cross(dp).dot(gn_raw) / gn2,
            )
        };
        let dbx = bary_d(dpx);
        let dby = bary_d(dpy);
        let (mut ns, mut dnx, mut dny) = shading_normal(tri, ng, [b0, b1, b2], dbx, dby);
        if ns.dot(ray.d) > 0.0 {
            ns *= -1.0;
            dnx *= -1.0;
            dny *= -1.0;
        }
        let face_ng = if entering { ng } else { ng * -1.0 };
        Self {
            t,
            p,
            b: [b0, b1, b2],
            ng,
            face_ng,
            entering,
            ns,
            dnx,
            dny,
            dn_fixed: None,
            dpx,
            dpy,
            dbx,
            dby,
        }
    }
}

/// Interpolated unit shading normal and its derivatives per pixel (from the
/// barycentric differentials); the geometric normal `ng` and zero
/// derivatives for flat triangles.
fn shading_normal(
    tri: &Triangle,
    ng: V3,
    b: [f64; 3],
    (db1x, db2x): (f64, f64),
    (db1y, db2y): (f64, f64),
) -> (V3, V3, V3) {
    let Some(n) = tri.n else {
        return (ng, V3::ZERO, V3::ZERO);
    };
    let nn = ((n[0] * b[0]) + (n[1] * b[1])) + (n[2] * b[2]);
    let l2 = nn.dot(nn);
    if l2.is_nan() || l2 <= 0.0 {
        return (ng, V3::ZERO, V3::ZERO);
    }
    let dn = |a: f64, b: f64| {
        let d = ((n[1] - n[0]) * a) + ((n[2] - n[0]) * b);
        ((d * l2) - (nn * nn.dot(d))) * l2.powf(-1.5)
    };
    (nn.normalize_or_zero(), dn(db1x, db2x), dn(db1y, db2y))
}

/// Surface spread angle β of the reflected cone (curved surfaces): across
/// the cone's footprint (width |w|) the shading normal turns by κ·|w|,
/// κ = |dn|/|dp| from the ray differentials, and the reflected direction by
/// twice that; positive (spreading) on convex surfaces (dp·dn > 0),
/// negative on concave ones. Flat: 0. Refracted cones keep β = 0 (the
/// published refraction of a cone is patented: docs/environment-map.md).
fn surface_spread(f: &HitFrame, width: f64) -> f64 {
    let kappa = |dp: V3, dn: V3| {
        let l = dp.length();
        if l > 0.0 { dn.length() / l } else { 0.0 }
    };
    let k = kappa(f.dpx, f.dnx).max(kappa(f.dpy, f.dny));
    let convex = f.dpx.dot(f.dnx) + f.dpy.dot(f.dny) >= 0.0;
    if k.is_finite() {
        let b = (2.0 * k * width.abs()).min(1.0);
        if convex { b } else { -b }
    } else {
        0.0
    }
}

/// An f64 vector as the firmware's I2F30 components (saturating; a
/// non-finite component reads as 0).
fn unit_q(v: V3) -> UnitVec {
    UnitVec::new(dir_q(v))
}

/// An f64 direction differential as the firmware's I2F30 components
/// (saturating; a non-finite component reads as 0).
fn dir_q(v: V3) -> [I2F30; 3] {
    v.to_array().map(|x| {
        if x.is_finite() {
            I2F30::saturating_from_num(x)
        } else {
            I2F30::ZERO
        }
    })
}

/// Firmware position differentials as f64.
fn v3_of(d: [raymip::path::raydiff::PosDiff; 3]) -> V3 {
    V3::from(d.map(|x| x.to_num::<f64>()))
}

/// Firmware direction (normal) differentials as f64 (exact).
fn v3_dir(d: [raymip::path::raydiff::DirDiff; 3]) -> V3 {
    V3::from(d.map(|x| x.to_num::<f64>()))
}

/// The first hit of pixel `(x, y)`'s primary ray through its centre, as
/// the G-buffer stores it: position, unit shading normal facing the ray
/// (flat triangles: the geometric normal) and distance; `None` on a miss.
fn gbuffer_entry(prep: &Prepared, x: u32, y: u32) -> Option<GHit> {
    let (dv, _, _) = prep.cam.primary_dir(f64::from(x) + 0.5, f64::from(y) + 0.5);
    let d = dv.normalize_or_zero();
    let hit = prep.bvh.closest(prep.cam.eye, d, 0.0, f64::INFINITY)?;
    let tri = &prep.scene.triangles[hit.tri as usize];
    let ng = (tri.p[1] - tri.p[0])
        .cross(tri.p[2] - tri.p[0])
        .normalize_or_zero();
    let b = [1.0 - hit.b1 - hit.b2, hit.b1, hit.b2];
    let (n, _, _) = shading_normal(tri, ng, b, (0.0, 0.0), (0.0, 0.0));
    Some(GHit {
        p: prep.cam.eye + d * hit.t,
        n: if n.dot(d) > 0.0 { n * -1.0 } else { n },
        t: hit.t,
    })
}

/// The G-buffer pass of a render: every pixel's [`gbuffer_entry`], rows in
/// parallel, stored in the render's precision (`fixed`: the firmware's
/// entries).
pub(crate) fn gbuffer_pass(prep: &Prepared, fixed: bool) -> Frame {
    use rayon::prelude::*;
    let (w, h) = (prep.width, prep.height);
    let hits: Vec<Option<GHit>> = (0..h)
        .into_par_iter()
        .flat_map_iter(|y| (0..w).map(move |x| gbuffer_entry(prep, x, y)))
        .collect();
    if fixed {
        Frame::Fixed(GBuffer {
            width: w,
            height: h,
            entries: hits.iter().map(|e| e.map(|g| g.to_fixed())).collect(),
        })
    } else {
        Frame::Float(GBuffer {
            width: w,
            height: h,
            entries: hits,
        })
    }
}
