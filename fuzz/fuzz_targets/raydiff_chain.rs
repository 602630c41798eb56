//! Ray differentials from arbitrary bytes, two ways. The first bytes pick a
//! case class and a seed of `raymip_host::raydiff_chains`: a random camera
//! chain (planes, convex and concave mirrors, refractions up to total
//! internal reflection) to a triangle of the class (slivers, lopsided and
//! slowly varying UVs, collinear vertices, zero UV area, grazing hits),
//! checked against the f64 reference: within the first-order bound of the
//! firmware's documented constants, exact for the degenerate classes. The
//! rest drives the firmware API directly with arbitrary mantissas,
//! exponents, unit vectors (any I2F30 bits), distances, indices of
//! refraction, cosines, triangles and G-buffer samples: never a panic or an
//! overflow (the fuzz build checks both), exponents inside their range,
//! lods inside the `Lod` range.
#![no_main]

use fixed::types::{I2F30, I4F28};
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use raymip::lod::raydiff::RayDiffTriangle;
use raymip::path::raydiff::gbuffer::{GSample, first_hit};
use raymip::path::raydiff::{DirDiff, Eta, PosDiff, RayDiff};
use raymip::rng::XorShift64;
use raymip::setup::table::TexTriangle;
use raymip::units::{Coord, PathLength, TexCoord, UnitVec};
use raymip_host::raydiff_chains::{CLASSES, Class, Raymip, run};

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let _ = chain(&mut u);
    let _ = api(&mut u);
});

fn chain(u: &mut Unstructured) -> Result<()> {
    let class = CLASSES[u.int_in_range(0..=CLASSES.len() - 1)?];
    let seed = u.arbitrary::<u64>()? | 1;
    let o = run(&Raymip, class, &mut XorShift64(seed));
    if matches!(class, Class::Collinear | Class::FlatUv) {
        assert_eq!(o.err, 0.0, "{o:?}");
    }
    assert!(o.err <= o.bound, "{o:?}");
    Ok(())
}

fn unit(u: &mut Unstructured) -> Result<UnitVec> {
    Ok(UnitVec(
        [(); 3].map(|()| I2F30::from_bits(u.arbitrary().unwrap_or(0))),
    ))
}

fn diff(u: &mut Unstructured) -> Result<(([i32; 3], i32), ([i32; 3], i32))> {
    Ok((
        (u.arbitrary()?, u.arbitrary()?),
        (u.arbitrary()?, u.arbitrary()?),
    ))
}

fn api(u: &mut Unstructured) -> Result<()> {
    let ((a, ea), (b, eb)) = diff(u)?;
    let ((c, ec), (d, ed)) = diff(u)?;
    let mut s = RayDiff::new(
        PosDiff::new(a, ea),
        PosDiff::new(b, eb),
        DirDiff::new(c, ec),
        DirDiff::new(d, ed),
    );
    let dn = [
        DirDiff::new(u.arbitrary()?, u.arbitrary()?),
        DirDiff::new(u.arbitrary()?, u.arbitrary()?),
    ];
    for _ in 0..u.int_in_range(0..=12)? {
        let (dir, n) = (unit(u)?, unit(u)?);
        match u.int_in_range(0..=3)? {
            0 => s.transfer(dir, PathLength::from_bits(u.arbitrary()?), n),
            1 => s.reflect(dir, n, dn),
            2 => s.refract(
                dir,
                n,
                dn,
                Eta::from_fixed(I4F28::from_bits(u.arbitrary()?)),
                I2F30::from_bits(u.arbitrary()?),
            ),
            _ => s = RayDiff::primary(dir, n, dn[0], dn[1]),
        }
        for v in [
            s.dox().parts(),
            s.doy().parts(),
            s.ddx().parts(),
            s.ddy().parts(),
        ] {
            assert!((-(1 << 14)..1 << 14).contains(&v.1), "{s:?}");
        }
    }
    let mut coord = || -> Result<Coord> { Ok(Coord::from_bits(u.arbitrary()?)) };
    let p = [
        [coord()?, coord()?, coord()?],
        [coord()?, coord()?, coord()?],
        [coord()?, coord()?, coord()?],
    ];
    let mut tc = || -> Result<TexCoord> { Ok(TexCoord::from_bits(u.arbitrary()?)) };
    let uv = [[tc()?, tc()?], [tc()?, tc()?], [tc()?, tc()?]];
    if let Ok(t) = TexTriangle::new(p, uv, u.arbitrary::<u32>()? | 1, u.arbitrary::<u32>()? | 1) {
        let tri = RayDiffTriangle::new(&t);
        let fp = tri.footprint(&s);
        let _ = fp.lod();
        let _ = fp.axes(&tri);
    }
    let g = |u: &mut Unstructured| -> Result<GSample> {
        Ok(GSample {
            p: u.arbitrary()?,
            n: unit(u)?,
            t: u.arbitrary()?,
        })
    };
    let (cen, l, r) = (g(u)?, g(u)?, g(u)?);
    let _ = first_hit(
        &mut s,
        &cen,
        [Some(&l), Some(&r), None, Some(&cen)],
        u.arbitrary()?,
    )
    .normal_diffs();
    if let Ok(map) =
        raymip::lod::envmap::EnvMap::new(u.int_in_range(1..=1 << 15)?, u.int_in_range(1..=1 << 15)?)
    {
        let _ = map.raydiff_lod(s.ddx(), s.ddy(), Some(unit(u)?));
    }
    Ok(())
}
