//! Code-size probe of the full float-free firmware API: Pb table build and
//! update (fixed-point set-up), table and cone LOD, ray stack, MIP
//! generation, all four filter modes from memory and through the block
//! cache. (The float set-up helpers `PixelSpread::from_fov_y`,
//! `TexTriangle::from_f32` and `Sampler::sample_f64` are excluded: they are
//! for hosts.)
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use core::hint::black_box as bb;
use raymip_size_probe as _;

use fixed::types::U1F31;
use raymip::lod::cone_lod;
use raymip::setup::camera::PixelSpread;
use raymip::setup::table::{PbTable, TexTriangle};
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::mip::{Geometry, Pyramid, generate};
use raymip::texture::{Mode, Sampler};
use raymip::units::{Accurate, Coord, Delta, Log2Pb, Spread, TexCoord, Width};

fn exit(code: i32) -> ! {
    semihosting::process::exit(code)
}

raymip_demo_entry::main! {
    let Ok(spread) = PixelSpread::from_angle(bb(Spread::from_bits(1 << 20))) else {
        exit(1)
    };
    let c = |x: i64| Coord::from_bits(bb(x));
    let t = |x: i64| TexCoord::from_bits(bb(x));
    let Ok(tri) = TexTriangle::new(
        [[c(0), c(1), c(2)], [c(3), c(4), c(5)], [c(6), c(7), c(8)]],
        [[t(9), t(10)], [t(11), t(12)], [t(13), t(14)]],
        bb(32),
        bb(32),
    ) else {
        exit(1)
    };
    let mut entries = [Log2Pb::UNTEXTURED; 4];
    let mut table = PbTable::new(&mut entries);
    let _ = bb(table.build([Some(tri), None], &spread));
    let _ = bb(table.update(bb(1), [Some(tri)], &spread));
    let Ok(g) = Geometry::new(bb(32), bb(32), bb(6)) else {
        exit(1)
    };
    let mut buf = [0u32; raymip_demo_scene::TEX_LEN];
    buf.copy_from_slice(bb(&raymip_demo_scene::TEX0));
    let _ = bb(generate(&g, &mut buf));
    let Ok(p) = Pyramid::new(g, &buf) else {
        exit(1)
    };
    let mut direct = Sampler::wrap(p);
    let mut cached = Sampler::clamp(TexelCache::<_, 8, 2>::new(p));
    let (st, pb, l1) = raymip_size_probe::one_bounce!(&spread, table, g.levels());
    let l2 = cone_lod::<Accurate>(
        st.cone.width,
        pb.delta(&spread).unwrap_or(Delta::ZERO),
        bb(Some(U1F31::from_bits(1 << 30))),
    );
    let (u, v) = (
        bb(TexCoord::from_bits(1 << 30)),
        bb(TexCoord::from_bits(3 << 29)),
    );
    let mut acc = 0u32;
    for m in [
        Mode::Trilinear,
        Mode::BilinearNearestLevel,
        Mode::Nearest,
        Mode::NearestTexelLinearLevel,
    ] {
        acc ^= direct.sample(u, v, l1, bb(m));
        acc ^= cached.sample(u, v, l2, bb(m));
    }
    bb(Width::ZERO);
    bb(acc);
    exit(0)
}
