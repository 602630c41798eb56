//! Code-size probe of one raymip feature set (`scripts/features` builds it
//! with `--no-default-features --features <set>`). Always: Pb table
//! lookup, ray stack push/pop with `advance`/`bounce`, `table_lod_clamped`
//! and `Sampler::sample` from a pyramid in memory with a run-time mode
//! (every mode the set has). Per feature: `cone` adds `cone_lod` (with
//! `n·d`), `cache` samples through a `TexelCache`, `mipgen` runs
//! `mip::generate`, `trilinear` adds the two linear-level modes. Inputs come
//! through `black_box`; never meant to be run for its output.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use core::hint::black_box as bb;
use raymip_size_probe::{TEX, TEX_LEN, TEX_LEVELS, TEX_SIZE};

use raymip::lod::table_lod_clamped;
use raymip::path::raystack::{PathState, RayStack};
use raymip::setup::camera::PixelSpread;
use raymip::setup::table::PbTable;
use raymip::texture::storage::mip::{Geometry, Pyramid};
use raymip::texture::{Mode, Sampler};
use raymip::units::{Accurate, Lod, Log2Pb, PathLength, Spread, TexCoord};

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
    let mut stack: RayStack = RayStack::new();
    let st = PathState::primary(&spread, bb(0xFF))
        .advance(bb(PathLength::from_bits(1 << 33)))
        .bounce(bb(Spread::ZERO));
    let _ = bb(stack.push(st));
    let st = stack.pop().unwrap_or(st);
    let pb = table.get(bb(0)).unwrap_or(Log2Pb::UNTEXTURED);
    let lod = table_lod_clamped::<Accurate>(st.pl, pb, g.levels()).unwrap_or(Lod::ZERO);
    #[cfg(feature = "cone")]
    let lod = bb(lod).saturating_add(raymip::lod::cone_lod::<Accurate>(
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
    raymip_size_probe::keep_type_sizes();
    exit(0)
}
