//! Code-size probe of the minimal feature set: table lod (Pb table lookup,
//! `table_lod`, clamp) and one bilinear sample at the nearest level from a
//! pyramid in memory. Inputs come through `black_box`; never meant to be
//! run for its output.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use core::hint::black_box as bb;
use raymip_size_probe as _;

use raymip::lod::table_lod_clamped;
use raymip::setup::table::PbTable;
use raymip::texture::storage::mip::{Geometry, Pyramid};
use raymip::texture::{Mode, Sampler};
use raymip::units::{Accurate, Log2Pb, PathLength, TexCoord};

raymip_demo_entry::main! {
    let mut entries = bb([Log2Pb::UNTEXTURED; 4]);
    let table = PbTable::new(&mut entries);
    let Ok(g) = Geometry::new(bb(32), bb(32), bb(6)) else {
        semihosting::process::exit(1)
    };
    let Ok(p) = Pyramid::new(g, bb(&raymip_demo_scene::TEX0)) else {
        semihosting::process::exit(1)
    };
    let mut s = Sampler::wrap(p);
    let pb = table.get(bb(1)).unwrap_or(Log2Pb::UNTEXTURED);
    let lod = table_lod_clamped::<Accurate>(bb(PathLength::from_bits(1 << 33)), pb, g.levels());
    let t = lod.map_or(0, |l| {
        s.sample(
            bb(TexCoord::from_bits(1 << 30)),
            bb(TexCoord::from_bits(3 << 29)),
            l,
            Mode::BilinearNearestLevel,
        )
    });
    bb(t);
    semihosting::process::exit(0)
}
