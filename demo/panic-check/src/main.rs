//! Panic-freedom check of the per-hit path (`scripts/link-checks`).
//!
//! Calls every per-hit function of raymip with inputs the optimiser cannot
//! see (`core::hint::black_box`) and links with `panic-never`, whose panic
//! handler references an undefined symbol: this binary links at the
//! release opt-level only if no panicking branch survives in any of them.
//! The C ABI (`raymip::ffi`, feature `ffi`) is checked the same way: no
//! panic can cross the boundary. Built for `thumbv7em-none-eabihf`; never run.
#![no_std]
#![no_main]
#![deny(unsafe_code)]
// Never run: a failed set-up just parks the core.
#![allow(clippy::empty_loop)]

use core::hint::black_box as bb;

use cortex_m_rt::entry;
use panic_never as _;
use raymip::ffi::{
    RM_RAY_STACK_CAPACITY, RM_SAMPLER_WORDS, RmAddressBits, RmFootprint, RmHit, RmImage,
    RmModeBits, RmPathState, RmRayStack, RmSampler, RmSamplerDesc, RmTexture, RmTriangle,
    rm_clamp_lod, rm_cone_lod, rm_delta, rm_image_len, rm_mip_generate, rm_path_advance,
    rm_path_bounce, rm_path_primary, rm_pyramid_len, rm_ray_stack_init, rm_ray_stack_pop,
    rm_ray_stack_push, rm_sample, rm_sample_aniso, rm_sample_batch, rm_sampler_desc_default,
    rm_sampler_init, rm_sampler_init_desc, rm_sampler_init_image, rm_sampler_init_wrap,
    rm_table_build, rm_table_lod, rm_table_update,
};
use raymip::geomlod::{
    DepthToLod, InstanceLod, LodMode, Selector, choose, ray_mask, transition_step, visible,
};
use raymip::lod::{
    LodWord, clamp_lod, cone_lod, cone_lod_batch, table_lod, table_lod_batch, table_lod_clamped,
    table_lod_norm, table_lod_norm_batch,
};
use raymip::log2::fast::{NormPl, log2_u32f32_fast};
use raymip::log2::{clz32, log2_bits, log2_u16f16, log2_u32, log2_u32f32};
use raymip::path::raystack::{PathState, RayStack};
use raymip::rng::{Rng, mix32};
use raymip::setup::camera::PixelSpread;
use raymip::setup::table::PbTable;
use raymip::texture::address::AddressMode;
use raymip::texture::address::{ClampToBorder, Mirror, Wrap};
use raymip::texture::kernel::{Linear, SrgbToLinear};
use raymip::texture::sampler::aniso::probes;
use raymip::texture::sampler::dynamic::DynSampler;
use raymip::texture::sampler::state::{SamplerDesc, SamplerState, SrgbOutput};
use raymip::texture::sampler::stochastic::StochasticMode;
use raymip::texture::storage::analysis::{PathBounds, TextureUse, analyse, mark_skipped};
use raymip::texture::storage::bc;
use raymip::texture::storage::cache::{BlockCache, BlockLayout, TexelCache};
use raymip::texture::storage::format::{ColorSpace, Format, Rgb565, TexelFormat};
use raymip::texture::storage::image::Image;
use raymip::texture::storage::mip::{Geometry, Pyramid, Texel, TexelSource};
use raymip::texture::storage::srgb;
use raymip::texture::{Cfg, Mode, Sampler};
use raymip::units::{
    Accurate, Delta, Depth, Fast, Lod, LodBias, PathLength, Precision, Spread, TexCoord,
    Transition, UnitVec, Width,
};
use raymip::units::{Footprint, Log2Pb};

static TEXELS: [Texel; 1365] = [0x8040_2010; 1365];
static BYTES: [u8; 4096] = [0x5A; 4096];

/// Every function of the C ABI with opaque arguments.
#[allow(unsafe_code)]
fn c_abi() {
    let mut entries = [0i32; 4];
    let tri = bb(RmTriangle {
        positions: [[0; 3]; 3],
        uvs: [[0; 2]; 3],
        tex_width: 1,
        tex_height: 1,
        textured: 1,
    });
    let mut stack = bb(RmRayStack {
        entries: [RmPathState::default(); RM_RAY_STACK_CAPACITY],
        len: 0,
    });
    let mut st = RmPathState::default();
    let mut lod = 0i16;
    let mut out = 0u32;
    let tex = bb(RmTexture {
        texels: TEXELS.as_ptr(),
        len: TEXELS.len(),
        width: 32,
        height: 32,
        levels: 6,
    });
    // SAFETY: every pointer is valid for the stated lengths.
    unsafe {
        bb(rm_table_build(
            bb(entries.as_mut_ptr()),
            bb(4),
            &tri,
            bb(1),
            bb(1 << 20),
            core::ptr::null_mut(),
        ));
        bb(rm_table_update(
            bb(entries.as_mut_ptr()),
            bb(4),
            bb(2),
            &tri,
            bb(1),
            bb(1 << 20),
            core::ptr::null_mut(),
        ));
        bb(rm_table_lod(bb(99), bb(entries[1]), &mut lod));
        bb(rm_ray_stack_init(&mut stack));
        bb(rm_path_primary(bb(1 << 20), bb(3), &mut st));
        bb(rm_path_advance(&mut st, bb(12345)));
        bb(rm_path_bounce(&mut st, bb(7)));
        bb(rm_ray_stack_push(&mut stack, &st));
        bb(rm_ray_stack_pop(&mut stack, &mut st));

        let mut sampler = RmSampler {
            opaque: [0; RM_SAMPLER_WORDS],
        };
        bb(rm_sampler_init(&mut sampler, &tex, RmAddressBits(bb(1))));
        bb(rm_sampler_init_wrap(bb(&mut sampler), &tex));
        // One sample at texel (5, 6) and the table's lod.
        let sample = |s: &mut RmSampler, out: &mut u32| {
            bb(rm_sample(s, bb(5), bb(6), bb(lod), RmModeBits(bb(0)), out))
        };
        sample(&mut sampler, &mut out);
        let mut desc = RmSamplerDesc::default();
        bb(rm_sampler_desc_default(&mut desc));
        let desc = bb(desc);
        bb(rm_sampler_init_desc(&mut sampler, &tex, &desc));
        let hits = bb([RmHit::default(); 3]);
        let mut texels = [0u32; 3];
        bb(rm_sample_batch(
            &mut sampler,
            hits.as_ptr(),
            bb(3),
            RmModeBits(bb(0)),
            texels.as_mut_ptr(),
        ));
        bb(texels);
        let fp = bb(RmFootprint::default());
        bb(rm_sample_aniso(&mut sampler, bb(5), bb(6), &fp, &mut out));
        let img = bb(RmImage {
            bytes: BYTES.as_ptr(),
            len: BYTES.len(),
            width: 16,
            height: 16,
            levels: 5,
            format: bb(1),
            srgb: bb(0),
        });
        bb(rm_image_len(bb(16), bb(16), bb(5), bb(7)));
        bb(rm_sampler_init_image(&mut sampler, &img, &desc));
        sample(&mut sampler, &mut out);
    }
    let mut pyr = [0u32; 21];
    // SAFETY: `pyr` holds 21 writable texels.
    unsafe {
        bb(rm_mip_generate(
            bb(pyr.as_mut_ptr()),
            bb(21),
            bb(4),
            bb(4),
            bb(3),
        ));
    }
    bb(pyr);
    bb(rm_cone_lod(bb(1), bb(2), bb(3)));
    let mut delta = 0i32;
    // SAFETY: a valid, aligned out pointer.
    bb(unsafe { rm_delta(bb(1), bb(2), &mut delta) });
    bb(delta);
    bb(rm_clamp_lod(bb(1), bb(2)));
    bb(rm_pyramid_len(bb(1), bb(2), bb(3)));
    bb(out);
}

#[entry]
fn main() -> ! {
    let mut stack: RayStack = RayStack::new();
    let mut entries = [Log2Pb::UNTEXTURED; 4];
    let table = PbTable::new(&mut entries);
    let Ok(spread) = PixelSpread::from_angle(bb(Spread::from_bits(1 << 20))) else {
        loop {}
    };
    let Ok(geometry) = Geometry::new(bb(32), bb(32), bb(6)) else {
        loop {}
    };
    let Ok(pyramid) = Pyramid::new(geometry, &TEXELS) else {
        loop {}
    };
    let Ok(range) = DepthToLod::new(
        bb(Depth::from_bits(1 << 32)),
        bb(Depth::from_bits(256 << 32)),
        bb(8),
        bb(LodBias::from_bits(-3)),
    ) else {
        loop {}
    };
    let Ok(selector) = Selector::new(
        range,
        bb(LodMode::Stochastic(Transition::from_bits(0x8000))),
    ) else {
        loop {}
    };
    let mut records = [InstanceLod::default(); 8];
    let mut direct = Sampler::wrap(pyramid);
    // A trimmed pyramid (levels 2..=4 of the same texels).
    let Ok(trimmed) = pyramid.trim(bb(2), bb(4)) else {
        loop {}
    };
    let mut trimmed = Sampler::wrap(trimmed);
    let mut cached = Sampler::clamp(TexelCache::<_, 16, 2>::new(pyramid));
    let mut tags: BlockCache<32, 4> = BlockCache::new();
    // The GPU-style sampler: state, every format (through the cache: BC
    // decode on fill), sRGB, border, anisotropy.
    let Ok(state) = SamplerState::new(SamplerDesc {
        address_u: bb(AddressMode::ClampToBorder),
        address_v: bb(AddressMode::Mirror),
        border: bb(0x1234_5678),
        lod_bias: bb(Lod::from_bits(-100)),
        min_lod: bb(Lod::from_bits(10)),
        max_lod: bb(Lod::from_bits(900)),
        max_anisotropy: bb(16),
        srgb_output: bb(SrgbOutput::Linear),
    }) else {
        loop {}
    };
    let Ok(format) = Format::new(bb(TexelFormat::Bc3), bb(ColorSpace::Srgb)) else {
        loop {}
    };
    let Ok(image) = Image::new(geometry, format, &BYTES) else {
        loop {}
    };
    // Every key of the run-time table (one `match` per call), over the
    // cache of a BC3 sRGB image.
    let mut gpu = DynSampler::new(
        TexelCache::<_, 16, 2>::new(image),
        state,
        format.space(),
        bb(Precision::Fast),
    );
    let Ok(mut gpu_direct) =
        Sampler::<_, Cfg<ClampToBorder, Mirror, SrgbToLinear>>::with_state(image, state)
    else {
        loop {}
    };
    // Typed formats and the FAST tier.
    let Ok(rgb565) = Image::<Rgb565>::typed(geometry, ColorSpace::Linear, &BYTES) else {
        loop {}
    };
    let Ok(mut typed) = Sampler::<_, Cfg<ClampToBorder, Mirror>>::with_state(rgb565, state) else {
        loop {}
    };
    let mut direct_fast: Sampler<_, Cfg<Wrap, Wrap, Linear, Fast>> = Sampler::new(pyramid);
    let mut cached_fast: Sampler<_, Cfg<Mirror, ClampToBorder, Linear, Fast>> =
        Sampler::new(TexelCache::<_, 16, 2>::new(pyramid));
    let modes = [
        Mode::Trilinear,
        Mode::BilinearNearestLevel,
        Mode::Nearest,
        Mode::NearestTexelLinearLevel,
    ];
    loop {
        c_abi();
        // log2
        bb(clz32(bb(0x1234)));
        bb(log2_bits(bb(12345), bb(32)));
        bb(log2_u32f32(bb(fixed::types::U32F32::from_bits(99))));
        bb(log2_u16f16(bb(fixed::types::U16F16::from_bits(99))));
        bb(log2_u32(bb(99)));
        bb(log2_u32f32_fast(bb(fixed::types::U32F32::from_bits(99))));
        // Pb table lookup and lod
        let pb = table.get(bb(3)).unwrap_or(Log2Pb::UNTEXTURED);
        let pl = bb(PathLength::from_bits(0x1_2345_6789));
        bb(table_lod::<Accurate>(pl, pb));
        bb(table_lod_clamped::<Accurate>(pl, pb, bb(7)));
        bb(table_lod::<Fast>(pl, pb));
        bb(clamp_lod(bb(Lod::from_bits(1000)), bb(200)));
        bb(pb.delta(&spread));
        bb(cone_lod::<Accurate>(
            bb(Width::from_bits(77)),
            bb(Delta::from_bits(5)),
            bb(Some(fixed::types::U1F31::from_bits(3))),
        ));
        bb(cone_lod::<Fast>(
            bb(Width::from_bits(-77)),
            bb(Delta::from_bits(5)),
            bb(Some(fixed::types::U1F31::from_bits(3))),
        ));
        // ray stack and path state
        let st = PathState::primary(&spread, bb(0xFF))
            .advance(pl)
            .bounce(bb(Spread::from_bits(9)));
        bb(stack.push(bb(st)).is_ok());
        bb(stack.pop());
        bb(stack.peek());
        // fetch, filter, cache
        let (u, v) = (
            bb(TexCoord::from_bits(0x1234_5678)),
            bb(TexCoord::from_bits(-77)),
        );
        let lod = bb(Lod::from_bits(300));
        for &m in &modes {
            bb(trimmed.sample(u, v, lod, bb(m)));
            bb(direct.sample(u, v, lod, bb(m)));
            bb(cached.sample(u, v, lod, bb(m)));
        }
        // the FAST tier, typed formats
        for &m in &modes {
            bb(direct_fast.sample(u, v, lod, bb(m)));
            bb(cached_fast.sample(u, v, lod, bb(m)));
            bb(typed.sample(u, v, lod, bb(m)));
        }
        // batch entry points (slices of opaque length)
        let hits = bb([(pl, pb); 4]);
        let mut lods = [None; 3];
        bb(table_lod_batch::<Accurate>(
            hits.get(..bb(4)).unwrap_or_default(),
            lods.get_mut(..bb(3)).unwrap_or_default(),
        ));
        let cones = bb([(
            Width::from_bits(77),
            Delta::from_bits(5),
            Some(fixed::types::U1F31::from_bits(3)),
        ); 4]);
        let norm_hits = bb([(NormPl::from_bits(bb(-7)), pb); 4]);
        bb(table_lod_norm(NormPl::new(pl), pb));
        bb(NormPl::from_bits(bb(i32::MAX)).to_bits());
        let mut words = [LodWord::default(); 3];
        bb(table_lod_norm_batch(
            norm_hits.get(..bb(4)).unwrap_or_default(),
            words.get_mut(..bb(3)).unwrap_or_default(),
        ));
        bb(words.map(LodWord::get));
        bb(LodWord(bb(1 << 20)).get());
        bb(LodWord::from(bb(Some(Lod::ONE))) == LodWord::UNTEXTURED);
        bb(Option::<Lod>::from(bb(LodWord::UNTEXTURED)));
        let mut cone_out = [Lod::ZERO; 4];
        bb(cone_lod_batch::<Accurate>(
            cones.get(..bb(2)).unwrap_or_default(),
            cone_out.get_mut(..bb(4)).unwrap_or_default(),
        ));
        bb(cone_lod_batch::<Fast>(
            cones.get(..bb(2)).unwrap_or_default(),
            cone_out.get_mut(..bb(4)).unwrap_or_default(),
        ));
        // Ray differentials (feature `raydiff`): every per-hit operation
        // and the triangle set-up.
        {
            use raymip::lod::raydiff::RayDiffTriangle;
            use raymip::path::raydiff::gbuffer::{GSample, axis, first_hit};
            use raymip::path::raydiff::{DirDiff, Eta, PosDiff, RayDiff};
            let v3 = |x: i32| UnitVec::new(bb([fixed::types::I2F30::from_bits(x); 3]));
            let m3 = |x: i32| bb([x, x.wrapping_mul(3), -x]);
            let mut s = bb(RayDiff::new(
                PosDiff::new(m3(bb(7)), bb(-40)),
                PosDiff::new(m3(bb(-9)), bb(-41)),
                DirDiff::new(m3(bb(3)), bb(-42)),
                DirDiff::new(m3(bb(-5)), bb(-43)),
            ));
            let (d, n) = (v3(1 << 29), v3(-(1 << 29)));
            let dn = DirDiff::new(m3(bb(11)), bb(-50));
            s.transfer(d, pl, n);
            bb(s);
            s.reflect(d, n, [dn, dn]);
            bb(s);
            s.refract(
                d,
                n,
                [dn, bb(dn)],
                Eta::from_fixed(fixed::types::I4F28::from_bits(bb(1 << 28))),
                fixed::types::I2F30::from_bits(bb(0)),
            );
            bb(s);
            bb(RayDiff::primary(d, n, dn, dn));
            let c = |x: i64| raymip::units::Coord::from_bits(bb(x));
            let t = |x: i64| TexCoord::from_bits(bb(x));
            if let Ok(t) = raymip::setup::table::TexTriangle::new(
                [
                    [c(0), c(1), c(2)],
                    [c(3 << 32), c(0), c(5)],
                    [c(0), c(7 << 30), c(0)],
                ],
                [[t(0), t(0)], [t(1 << 32), t(0)], [t(0), t(1 << 32)]],
                bb(64),
                bb(32),
            ) {
                let tri = bb(RayDiffTriangle::new(&t));
                let fp = bb(tri.footprint(&s));
                bb(fp.lod());
                bb(fp.axes(&tri));
            }
            let g = bb(GSample {
                p: m3(bb(13)),
                n,
                t: bb(5),
            });
            bb(axis(&g, Some(&g), None, bb(-20)));
            bb(first_hit(&mut s, &g, [Some(&g), None, Some(&g), None], bb(-20)).normal_diffs());
            bb(s);
        }
        // Environment map (feature `envmap`): the lods of a ray that leaves
        // the scene and the lat-long (u, v) of its direction.
        {
            use raymip::lod::envmap::{EnvMap, direction_uv};
            use raymip::path::raydiff::DirDiff;
            let v3 = |x: i32| bb([fixed::types::I2F30::from_bits(x); 3]);
            if let Ok(map) = EnvMap::new(bb(2048), bb(1024)) {
                let map = bb(map);
                let (d, dd) = (v3(bb(1 << 29)), DirDiff::new(bb([-3, 1, 2]), bb(-40)));
                let g = raymip::units::Spread::from_bits(bb(1 << 20));
                bb(map.cone_lod(g, None));
                bb(map.cone_lod(g, Some(UnitVec::new(d))));
                bb(map.raydiff_lod(dd, bb(dd), bb(Some(UnitVec::new(d)))));
            }
            bb(direction_uv(UnitVec::new(v3(bb(-7)))));
        }
        let samples = bb([(u, v, lod); 4]);
        let mut texels = [0; 4];
        // `sample_batch` of a sampler (any key) with `n` samples into `k`
        // texel slots (unequal lengths: the shorter one bounds the batch).
        macro_rules! batch {
            ($s:expr, $m:expr, $n:expr, $k:expr) => {
                bb($s.sample_batch(
                    samples.get(..bb($n)).unwrap_or_default(),
                    bb($m),
                    texels.get_mut(..bb($k)).unwrap_or_default(),
                ))
            };
        }
        for &m in &modes {
            batch!(direct, m, 4, 3);
            batch!(cached, m, 3, 4);
        }
        for m in [
            StochasticMode::Trilinear,
            StochasticMode::Bilinear,
            StochasticMode::TrilinearBilinear,
        ] {
            bb(direct.sample_stochastic(u, v, lod, bb(m), bb(0x8765_4321)));
            bb(cached.sample_stochastic(u, v, lod, bb(m), bb(0x1234_5678)));
        }
        bb(cached.source_mut().texel(bb(2), bb(5), bb(6)));
        let fp = bb(Footprint {
            x: [
                bb(TexCoord::from_bits(1 << 27)),
                bb(TexCoord::from_bits(-5)),
            ],
            y: [
                bb(TexCoord::from_bits(3 << 20)),
                bb(TexCoord::from_bits(1 << 22)),
            ],
        });
        for &m in &modes {
            bb(gpu.sample(u, v, lod, bb(m)));
            bb(gpu_direct.sample(u, v, lod, bb(m)));
            batch!(gpu, m, 3, 4);
            batch!(direct_fast, m, 4, 3);
        }
        bb(gpu.sample_aniso(u, v, &fp));
        bb(gpu_direct.sample_aniso(u, v, &fp));
        bb(direct.sample_aniso(u, v, &fp));
        bb(direct_fast.sample_aniso(u, v, &fp));
        bb(typed.sample_aniso(u, v, &fp));
        bb(gpu.sample_stochastic(u, v, lod, bb(StochasticMode::Bilinear), bb(7)));
        bb(direct_fast.sample_stochastic(u, v, lod, bb(StochasticMode::Trilinear), bb(9)));
        bb(probes(&fp, bb(512), bb(64), bb(8)));
        bb(state.lod(lod, bb(7)));
        bb(bb(AddressMode::MirrorOnce).index(bb(-77), bb(5)));
        bb(bb(AddressMode::Wrap).linear(u, bb(5)));
        bb(bb(AddressMode::Mirror).nearest(v, bb(5)));
        for f in TexelFormat::ALL {
            bb(bb(f).decode(bb(0x1234_5678)));
            bb(bc::decode_texel(
                bb(f),
                BYTES.get(..bb(16)).unwrap_or(&[]),
                bb(7),
            ));
            let mut out = [0; 16];
            bc::decode_block(bb(f), BYTES.get(..bb(12)).unwrap_or(&[]), &mut out);
            bb(out);
        }
        bb(srgb::encode(bb(123_456)));
        bb(srgb::decode(bb(77)));
        bb(image.get(bb(3), bb(9), bb(1)));
        bb(tags.access(bb(1234)));
        bb(BlockLayout::new(&geometry).index(bb(3), bb(1), bb(2)));
        bb(geometry.level_size(bb(9)));
        bb(geometry.texel_index(bb(9), bb(100), bb(3)));
        // stochastic geometric LOD (per instance) and the path's ray mask
        let z = bb(Depth::from_bits(0x12_3456_789A));
        bb(range.lod_param(z));
        bb(selector.pick(z));
        bb(choose(bb(range.lod_param(z)), bb(9), bb(LodMode::Discrete)));
        bb(transition_step(bb(0x9000), bb(0x2_0000)));
        bb(selector.fill(
            (0..bb(6u32)).map(|i| (i, Depth::from_bits(i64::from(i) << 33))),
            &mut records,
        ))
        .ok();
        let mut rng = Rng::for_pixel(bb(3), bb(4), bb(5));
        let m = ray_mask(&mut rng);
        bb(visible(bb(records[1].mask), m));
        bb(mix32(bb(rng.next_u32())));
        // Set-up scene analysis.
        let mut usage = [TextureUse::default(); 2];
        let ids = bb([0u16, 1, 7, 0]);
        let bounds = bb([
            Some(PathBounds {
                nearest: bb(PathLength::from_bits(1 << 30)),
                farthest: bb(PathLength::from_bits(1 << 40)),
            }),
            None,
        ]);
        let mut pbs = bb([Log2Pb::from_bits(bb(5 << 16)); 4]);
        bb(analyse(&pbs, &ids, &bounds, &mut usage).is_ok());
        if let Some(r) = usage.first().and_then(|u| u.lod) {
            bb(r.levels(bb(Mode::Trilinear), bb(9)));
            bb(r.for_cones());
        }
        bb(mark_skipped(&mut pbs, &ids, &usage));
        bb(Geometry::trimmed(bb(64), bb(32), bb(7), bb(1), bb(5)).is_ok());
    }
}
