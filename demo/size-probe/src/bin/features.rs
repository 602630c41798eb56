//! Code-size probe of one raymip feature set (`scripts/features` builds it
//! with `--no-default-features --features <set>`). Always: Pb table
//! lookup, ray stack push/pop with `advance`/`bounce`, `table_lod_clamped`
//! and `Sampler::sample` from a pyramid in memory with a run-time mode
//! (every mode the set has). Per feature: `cone` adds `cone_lod` (with
//! `n·d`), `cache` samples through a `TexelCache`, `mipgen` runs
//! `mip::generate`, `trilinear` adds the two linear-level modes; the opt-in
//! stages: `raydiff` the ray-differential chain (primary and G-buffer
//! set-up, transfer, reflection, refraction, footprint and its lod; the
//! differentials ride in every ray-stack entry), `envmap` the
//! environment-map cone lod and `(u, v)` mapping (and the differential lod
//! with `raydiff`), `f32` the f32 baseline's table and cone lod and one
//! f32 sample, `pcpi` the table lod and filter through the PicoRV32
//! co-processor (RV32 only; on other targets the feature changes nothing).
//! Inputs come through `black_box`; never meant to be run for its output.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use core::hint::black_box as bb;
use raymip_size_probe::{TEX, TEX_LEN, TEX_LEVELS, TEX_SIZE};

use raymip::setup::camera::PixelSpread;
use raymip::setup::table::PbTable;
use raymip::texture::storage::mip::{Geometry, Pyramid};
use raymip::texture::{Mode, Sampler};
use raymip::units::{Log2Pb, Spread, TexCoord};

fn exit(code: i32) -> ! {
    semihosting::process::exit(code)
}

/// Every filter mode the feature set has.
const MODES: &[Mode] = &[
    Mode::BilinearNearestLevel,
    Mode::Nearest,
    #[cfg(feature = "trilinear")]
    Mode::Trilinear,
    #[cfg(feature = "trilinear")]
    Mode::NearestTexelLinearLevel,
];

raymip_demo_entry::main! {
    let Ok(spread) = PixelSpread::from_angle(bb(Spread::from_bits(1 << 20))) else {
        exit(1)
    };
    let mut entries = bb([Log2Pb::UNTEXTURED; 4]);
    let table = PbTable::new(&mut entries);
    let Ok(g) = Geometry::new(bb(TEX_SIZE), bb(TEX_SIZE), bb(TEX_LEVELS)) else {
        exit(1)
    };
    #[cfg(feature = "mipgen")]
    let texels = {
        let mut buf = [0u32; TEX_LEN];
        buf.copy_from_slice(bb(&TEX));
        let _ = bb(raymip::texture::storage::mip::generate(&g, &mut buf));
        buf
    };
    #[cfg(not(feature = "mipgen"))]
    let texels: &[u32; TEX_LEN] = bb(&TEX);
    let Ok(p) = Pyramid::new(g, &texels[..]) else {
        exit(1)
    };
    let mut direct = Sampler::wrap(p);
    #[cfg(feature = "cache")]
    let mut cached = Sampler::clamp(raymip::texture::storage::cache::TexelCache::<_, 8, 2>::new(p));
    // The state and the entry feed the optional stages below.
    #[cfg_attr(not(feature = "cone"), allow(unused_variables))]
    let (st, pb, lod) = raymip_size_probe::one_bounce!(&spread, table, g.levels());
    #[cfg(feature = "cone")]
    let lod = bb(lod).saturating_add(raymip::lod::cone_lod::<raymip::units::Accurate>(
        st.cone.width,
        pb.delta(&spread).unwrap_or(raymip::units::Delta::ZERO),
        bb(Some(fixed::types::U1F31::from_bits(1 << 30))),
    ));
    let (u, v) = (
        bb(TexCoord::from_bits(1 << 30)),
        bb(TexCoord::from_bits(3 << 29)),
    );
    let mode = bb(MODES).get(bb(0)).copied().unwrap_or(Mode::Nearest);
    let acc = direct.sample(u, v, lod, mode);
    #[cfg(feature = "cache")]
    let acc = acc ^ cached.sample(u, v, lod, mode);
    bb(acc);
    #[cfg(feature = "raydiff")]
    raydiff(g, st);
    #[cfg(feature = "envmap")]
    envmap(st);
    #[cfg(feature = "f32")]
    {
        let Some(s) = raymip::baseline_f32::SamplerF32::new(
            g,
            &texels[..],
            bb(raymip::texture::AddressMode::Wrap),
        ) else {
            exit(1)
        };
        let l = raymip::baseline_f32::table_lod_f32(bb(10.0), bb(-3.5))
            + raymip::baseline_f32::cone_lod_f32(bb(0.01), bb(2.0), bb(Some(0.5)));
        bb(s.sample(bb(0.25), bb(0.75), l, mode));
    }
    raymip_size_probe::keep_type_sizes();
    exit(0)
}

/// The ray-differential chain of one path: set-up (primary, G-buffer),
/// transfer, reflection, refraction, the footprint on one triangle and its
/// lod.
#[cfg(feature = "raydiff")]
#[inline(never)]
fn raydiff(g: Geometry, st: raymip::path::raystack::PathState) {
    use fixed::types::{I2F30, I4F28};
    use raymip::lod::raydiff::RayDiffTriangle;
    use raymip::path::raydiff::gbuffer::{GSample, first_hit};
    use raymip::path::raydiff::{DirDiff, Eta, RayDiff};
    use raymip::setup::table::TexTriangle;
    use raymip::units::{Coord, UnitVec};
    let c = |x: i32| Coord::from_bits(i64::from(x) << 32);
    let t = |x: i32| TexCoord::from_bits(i64::from(x) << 32);
    let Ok(tri) = TexTriangle::new(
        bb([[c(0), c(0), c(0)], [c(4), c(0), c(1)], [c(0), c(3), c(0)]]),
        bb([[t(0), t(0)], [t(2), t(0)], [t(0), t(1)]]),
        g.width(),
        g.height(),
    ) else {
        exit(1)
    };
    let tri = RayDiffTriangle::new(&tri);
    let z = I2F30::ZERO;
    let d = bb(UnitVec::new([z, z, I2F30::from_bits(-(1 << 30))]));
    let n = bb(UnitVec::new([z, z, I2F30::from_bits(1 << 30)]));
    let dd = bb(DirDiff::from_i2f30([I2F30::from_bits(1 << 20), z, z]));
    let mut s = RayDiff::primary(d, n, dd, dd);
    let g = GSample {
        p: bb([0; 3]),
        n,
        t: bb(1 << 20),
    };
    let nb = [Some(&g); 4];
    let [dnx, dny] = first_hit(&mut s, bb(&g), bb(nb), bb(-24)).normal_diffs();
    s.transfer(d, st.pl, n);
    s.reflect(d, n, [dnx, dny]);
    s.refract(
        d,
        n,
        [dnx, dny],
        bb(Eta::from_fixed(I4F28::from_bits(0x0AAA_AAAB))),
        bb(I2F30::from_bits(0x3999_999A)),
    );
    let mut entry = st;
    entry.diff = s;
    bb(tri.footprint(&bb(entry).diff).lod());
}

/// The environment-map lod of a ray leaving the scene: the cone lod with
/// the pole term, the `(u, v)` of its direction and, with `raydiff`, the
/// differential lod.
#[cfg(feature = "envmap")]
#[inline(never)]
fn envmap(st: raymip::path::raystack::PathState) {
    use fixed::types::I2F30;
    use raymip::lod::envmap::{EnvMap, direction_uv};
    use raymip::units::UnitVec;
    let Ok(map) = EnvMap::new(bb(2048), bb(1024)) else {
        exit(1)
    };
    let z = I2F30::ZERO;
    let d = bb(UnitVec::new([
        z,
        I2F30::from_bits(1 << 29),
        I2F30::from_bits(-(7 << 27)),
    ]));
    #[cfg(feature = "cone")]
    let spread = st.cone.spread;
    #[cfg(not(feature = "cone"))]
    let spread = bb(Spread::from_bits(1 << 20));
    bb(map.cone_lod(spread, Some(d)));
    bb(direction_uv(d));
    #[cfg(feature = "raydiff")]
    bb(map.raydiff_lod(st.diff.ddx(), st.diff.ddy(), Some(d)));
    let _ = st;
}
