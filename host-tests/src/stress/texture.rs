//! Texture edges: the sampler, pyramid sizes and storage limits.

use raymip::baseline_f32::SamplerF32;
use raymip::texture::storage::mip::{
    self, Geometry, MAX_SIZE, MipError, Pyramid, Texel, generate, pyramid_len,
};
use raymip::texture::{AddressMode, FilterError, Mode, Sampler};
use raymip::units::{Lod, TexCoord};

use super::{FLOAT_CLASSES, Runner, bad, clamp, err, value};

/// Level-0 texels with channels in `[10, 200]` and their channel range.
pub(super) fn texels_for(g: &Geometry) -> Vec<Texel> {
    let mut buf = vec![0; g.len()];
    let (w, h) = g.level_size(0);
    for y in 0..h {
        for x in 0..w {
            let c = |k: u32| 10 + ((x * 7 + y * 13 + k * 29) % 191) as u8;
            buf[g.texel_index(0, x, y)] = u32::from_le_bytes([c(0), c(1), c(2), c(3)]);
        }
    }
    buf
}

/// True when every channel of `t` lies in the range of the level-0 texels
/// (a filter of convex weights cannot leave it).
pub(super) fn in_range(t: Texel) -> bool {
    t.to_le_bytes().iter().all(|&c| (10..=200).contains(&c))
}

pub(super) const MODES: [Mode; 4] = [
    Mode::Trilinear,
    Mode::BilinearNearestLevel,
    Mode::Nearest,
    Mode::NearestTexelLinearLevel,
];

pub(super) fn sampler(r: &mut Runner) {
    let g = Geometry::new(8, 8, 4).expect("8×8, 4 levels");
    let mut buf = texels_for(&g);
    generate(&g, &mut buf).expect("exact buffer");
    for (name, x, xf) in FLOAT_CLASSES {
        for (which, edge) in [
            (0, "sampler: Sampler::sample_f64 u"),
            (1, "sampler: Sampler::sample_f64 v"),
            (2, "sampler: Sampler::sample_f64 lod"),
        ] {
            let buf = &buf;
            r.case(name, edge, move || {
                let mut seen = Vec::new();
                for a in [AddressMode::Wrap, AddressMode::ClampToEdge] {
                    let mut s =
                        Sampler::with_address(Pyramid::new(g, buf).map_err(|e| e.to_string())?, a);
                    for m in MODES {
                        let mut args = [0.3, 0.6, 1.2];
                        args[which] = x;
                        match s.sample_f64(args[0], args[1], args[2], m) {
                            Err(FilterError::NonFinite) if !x.is_finite() => {}
                            Ok(t) if x.is_finite() && in_range(t) => seen.push(t),
                            o => return bad(format!("{a:?} {m:?}: {o:?}")),
                        }
                    }
                }
                if x.is_finite() {
                    value(format!("{} texels in range", seen.len()))
                } else {
                    err("NonFinite")
                }
            });
            r.case(
                name,
                match which {
                    0 => "sampler: SamplerF32::sample u (float baseline)",
                    1 => "sampler: SamplerF32::sample v (float baseline)",
                    _ => "sampler: SamplerF32::sample lod (float baseline)",
                },
                move || {
                    for a in [AddressMode::Wrap, AddressMode::ClampToEdge] {
                        let s = SamplerF32::new(g, buf, a).ok_or("SamplerF32::new")?;
                        for m in MODES {
                            let mut args = [0.3f32, 0.6, 1.2];
                            args[which] = xf;
                            let t = s.sample(args[0], args[1], args[2], m);
                            // Documented: non-finite input, unspecified
                            // texel; finite input, a filtered one.
                            if xf.is_finite() && !in_range(t) {
                                return bad(format!("{a:?} {m:?}: {t:08x} out of range"));
                            }
                        }
                    }
                    if xf.is_finite() {
                        clamp("a texel in range")
                    } else {
                        value("a texel (documented: unspecified for non-finite input), no panic")
                    }
                },
            );
        }
    }
    let coords = [
        ("u,v MIN", TexCoord::MIN),
        ("u,v MAX", TexCoord::MAX),
        ("u,v -2^-32", -TexCoord::DELTA),
    ];
    for (cn, c) in coords {
        for (ln, l) in [("lod MIN", Lod::MIN), ("lod MAX", Lod::MAX)] {
            let buf = &buf;
            r.case(
                format!("{cn}, {ln}"),
                "sampler: Sampler::sample",
                move || {
                    for a in [AddressMode::Wrap, AddressMode::ClampToEdge] {
                        let mut s = Sampler::with_address(
                            Pyramid::new(g, buf).map_err(|e| e.to_string())?,
                            a,
                        );
                        for m in MODES {
                            let t = s.sample(c, c, l, m);
                            if !in_range(t) {
                                return bad(format!("{a:?} {m:?}: {t:08x}"));
                            }
                        }
                    }
                    clamp("clamped level and address, texels in range")
                },
            );
        }
    }
}

pub(super) fn textures(r: &mut Runner) {
    let sizes = [
        (1u32, 1u32),
        (1, 4096),
        (4096, 1),
        (MAX_SIZE, 1),
        (1, MAX_SIZE),
        (4096, 4096),
    ];
    for (w, h) in sizes {
        r.case(
            format!("{w}×{h} texture, full chain"),
            "texture: generate + sample",
            move || {
                let levels = mip::full_levels(w, h);
                let g = Geometry::new(w, h, levels).map_err(|e| e.to_string())?;
                let want_len: u64 = (0..levels)
                    .map(|k| u64::from((w >> k).max(1)) * u64::from((h >> k).max(1)))
                    .sum();
                if g.len() as u64 != want_len || pyramid_len(w, h, levels) as u64 != want_len {
                    return bad(format!("len {} vs {want_len}", g.len()));
                }
                let mut buf = texels_for(&g);
                let level0 = g.level_size(0);
                let n0 = (level0.0 * level0.1) as usize;
                let before: Vec<Texel> = buf[..n0].to_vec();
                generate(&g, &mut buf).map_err(|e| e.to_string())?;
                if buf[..n0] != before[..] {
                    return bad("level 0 changed");
                }
                if !buf.iter().all(|&t| in_range(t)) {
                    return bad("a generated texel out of range");
                }
                let mut s = Sampler::wrap(Pyramid::new(g, &buf).map_err(|e| e.to_string())?);
                for l in [Lod::MIN, Lod::ZERO, Lod::from_num(levels), Lod::MAX] {
                    for m in MODES {
                        for c in [TexCoord::ZERO, TexCoord::from_num(0.999), TexCoord::MAX] {
                            if !in_range(s.sample(c, c, l, m)) {
                                return bad(format!("sample at lod {l} {m:?} out of range"));
                            }
                        }
                    }
                }
                value(format!("{levels} levels, {want_len} texels; level 0 kept"))
            },
        );
        r.case(
            format!("{w}×{h} pyramid, storage one texel short"),
            "texture: generate / Pyramid::new",
            move || {
                let g = Geometry::new(w, h, mip::full_levels(w, h)).map_err(|e| e.to_string())?;
                let mut buf = texels_for(&g);
                buf.pop();
                let before = buf.clone();
                let (n, got) = (g.len(), buf.len());
                let a = generate(&g, &mut buf);
                let b = Pyramid::new(g, &buf).map(|_| ());
                let want = Err(MipError::BufferTooShort { needed: n, got });
                if a == want && b == want && buf == before {
                    err(format!(
                        "BufferTooShort {{ needed: {n}, got: {got} }}, buffer untouched"
                    ))
                } else {
                    bad(format!("{a:?} / {b:?}"))
                }
            },
        );
    }
}

pub(super) fn texture_limits(r: &mut Runner) {
    r.case(
        format!("{MAX_SIZE}×{MAX_SIZE} texture (geometry only)"),
        "texture: Geometry::new",
        || {
            let g = Geometry::new(MAX_SIZE, MAX_SIZE, 16).map_err(|e| e.to_string())?;
            let want: u64 = (0..16).map(|k| (u64::from(MAX_SIZE) >> k).pow(2)).sum();
            if g.len() as u64 == want {
                value(format!("{want} texels, 16 levels"))
            } else {
                bad(format!("{} vs {want}", g.len()))
            }
        },
    );
    for (name, w, h, l, want) in [
        ("side MAX_SIZE + 1", MAX_SIZE + 1, 1, 1, MipError::TooLarge),
        ("width 0", 0, 16, 1, MipError::ZeroSize),
        ("0 levels", 16, 16, 0, MipError::BadLevels),
        ("full_levels + 1", 16, 16, 6, MipError::BadLevels),
    ] {
        r.case(
            name,
            "texture: Geometry::new",
            move || match Geometry::new(w, h, l) {
                Err(e) if e == want => err(format!("{e:?}")),
                o => bad(format!("{o:?}")),
            },
        );
    }
    r.case("sides u32::MAX, 255 levels", "texture: pyramid_len", || {
        if pyramid_len(u32::MAX, u32::MAX, 255) == usize::MAX {
            clamp("usize::MAX (saturated)")
        } else {
            bad(format!("{}", pyramid_len(u32::MAX, u32::MAX, 255)))
        }
    });
}
