//! Built-in scenes (no files needed) with procedural textures:
//!
//! * `hall`: a textured floor receding to the horizon between two textured
//!   walls (classic minification), one mirror sphere;
//! * `mirrors`: a room with two facing mirrors and mirror spheres (paths of
//!   8–10 bounces);
//! * `glass`: glass spheres and a glass slab over a textured floor (refraction);
//! * `envmap`: a mirror sphere, a glass sphere and a polished floor under a
//!   latitude-longitude environment map of fine detail ([`sky_texture`]):
//!   most rays leave the scene (`render::envmap`).
//!
//! Textures: `tiles` 512×512 (POT), `bricks` 320×192 (NPOT), `grid` 384×384
//! (NPOT). Default image size 800×480. [`fronto_quad`] builds the
//! fronto-parallel quad of the LOD tests.

use super::{Camera, Light, Material, Scene, SceneError, TextureImage, Triangle, V3};

/// Names of the built-in scenes.
pub const NAMES: [&str; 4] = ["hall", "mirrors", "glass", "envmap"];

/// Default image size of the built-in scenes.
pub const DEFAULT_SIZE: (u32, u32) = (800, 480);

/// A built-in scene by name.
pub fn by_name(name: &str) -> Result<Scene, SceneError> {
    match name {
        "hall" => Ok(hall()),
        "mirrors" => Ok(mirrors()),
        "glass" => Ok(glass()),
        "envmap" => Ok(envmap()),
        _ => Err(SceneError::UnknownBuiltin {
            name: name.to_string(),
        }),
    }
}

fn rgba(c: V3) -> u32 {
    let b = c
        .to_array()
        .map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8);
    u32::from_le_bytes([b[0], b[1], b[2], 255])
}

fn image(name: &str, w: u32, h: u32, f: impl Fn(u32, u32) -> V3) -> TextureImage {
    let mut texels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            texels.push(rgba(f(x, y)));
        }
    }
    TextureImage {
        name: name.into(),
        width: w,
        height: h,
        texels,
    }
}

/// 512×512 floor tiles: 8×8 checker cells of 64 texels with 2-texel grout
/// and a fine 4-texel inner pattern (high frequencies that alias without
/// mip mapping).
#[must_use]
pub fn tiles_texture() -> TextureImage {
    image("tiles", 512, 512, |x, y| {
        let (cx, cy) = (x / 64, y / 64);
        let (ix, iy) = (x % 64, y % 64);
        if ix < 2 || iy < 2 {
            return V3::new(0.15, 0.12, 0.1);
        }
        let base = if (cx + cy) % 2 == 0 {
            V3::new(0.85, 0.8, 0.7)
        } else {
            V3::new(0.55, 0.2, 0.15)
        };
        let fine = if ((ix / 4) + (iy / 4)) % 2 == 0 {
            1.0
        } else {
            0.8
        };
        base.map(|c| c * fine)
    })
}

/// 320×192 bricks (NPOT): 64×32 bricks, half-offset rows, 3-texel mortar.
#[must_use]
pub fn bricks_texture() -> TextureImage {
    image("bricks", 320, 192, |x, y| {
        let row = y / 32;
        let xs = x + if row % 2 == 1 { 32 } else { 0 };
        let (bx, ix, iy) = (xs / 64, xs % 64, y % 32);
        if ix < 3 || iy < 3 {
            return V3::new(0.8, 0.8, 0.75);
        }
        let tone = 0.75 + 0.25 * f64::from((bx * 7 + row * 13) % 5) / 4.0;
        V3::new(0.7 * tone, 0.3 * tone, 0.2 * tone)
    })
}

/// 384×384 grid (NPOT): blue and white squares of 24 texels with thin lines.
#[must_use]
pub fn grid_texture() -> TextureImage {
    image("grid", 384, 384, |x, y| {
        if x % 24 == 0 || y % 24 == 0 {
            return V3::new(0.05, 0.05, 0.1);
        }
        if ((x / 24) + (y / 24)) % 2 == 0 {
            V3::new(0.9, 0.9, 0.95)
        } else {
            V3::new(0.2, 0.35, 0.75)
        }
    })
}

fn diffuse(c: V3) -> Material {
    Material {
        ambient: c,
        diffuse: c,
        specular: V3::ZERO,
        shine: 1.0,
        transmission: V3::ZERO,
        ior: 1.0,
    }
}

fn mirror(k: f64, tint: V3) -> Material {
    Material {
        ambient: (tint * 0.05),
        diffuse: (tint * 0.05),
        specular: (tint * k),
        shine: 200.0,
        transmission: V3::ZERO,
        ior: 1.0,
    }
}

/// A white point light at `position` with intensity `grey`.
fn light(position: [f64; 3], grey: f64) -> Light {
    Light {
        position: position.into(),
        color: V3::splat(grey),
    }
}

fn glass_mat() -> Material {
    Material {
        ambient: V3::ZERO,
        diffuse: V3::ZERO,
        specular: V3::splat(0.1),
        shine: 200.0,
        transmission: V3::new(0.88, 0.92, 0.9),
        ior: 1.5,
    }
}

/// Two triangles of the parallelogram `p0, p0+ex, p0+ex+ey, p0+ey`, UVs
/// `(0,0)..(su,sv)` (texture repeats).
#[must_use]
pub fn quad(
    p0: V3,
    ex: V3,
    ey: V3,
    su: f64,
    sv: f64,
    material: u32,
    texture: Option<u32>,
) -> [Triangle; 2] {
    let p1 = p0 + ex;
    let corners = [p0, p1, p1 + ey, p0 + ey];
    let uv = texture.map(|_| [[0.0, 0.0], [su, 0.0], [su, sv], [0.0, sv]]);
    let tri = |k: [usize; 3]| Triangle {
        p: k.map(|i| corners[i]),
        n: None,
        uv: uv.map(|u| k.map(|i| u[i])),
        material,
        texture,
    };
    [tri([0, 1, 2]), tri([0, 2, 3])]
}

/// One [`quad`] as a table row: `(p0, ex, ey, [su, sv], material, texture)`.
pub type QuadRow = ([f64; 3], [f64; 3], [f64; 3], [f64; 2], u32, Option<u32>);

/// The triangles of the quads `rows`, in order (two per row).
#[must_use]
pub fn quads(rows: &[QuadRow]) -> Vec<Triangle> {
    rows.iter()
        .flat_map(|&(p0, ex, ey, [su, sv], material, texture)| {
            quad(p0.into(), ex.into(), ey.into(), su, sv, material, texture)
        })
        .collect()
}

/// A UV sphere with smooth (interpolated) normals: `nu` segments around,
/// `nv` from pole to pole.
#[must_use]
pub fn sphere(c: V3, r: f64, nu: u32, nv: u32, material: u32) -> Vec<Triangle> {
    let pt = |i: u32, j: u32| {
        let th = std::f64::consts::PI * f64::from(j) / f64::from(nv);
        let ph = 2.0 * std::f64::consts::PI * f64::from(i) / f64::from(nu);
        let n = V3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin());
        (c + n * r, n)
    };
    let mut out = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let a = pt(i, j);
            let b = pt(i + 1, j);
            let cc = pt(i + 1, j + 1);
            let d = pt(i, j + 1);
            for (x, y, z) in [(a, cc, b), (a, d, cc)] {
                let area = (y.0 - x.0).cross(z.0 - x.0).length();
                if area > 1e-12 * r * r {
                    out.push(Triangle {
                        p: [x.0, y.0, z.0],
                        n: Some([x.1, y.1, z.1]),
                        uv: None,
                        material,
                        texture: None,
                    });
                }
            }
        }
    }
    out
}

/// An axis-aligned box (12 flat triangles).
#[must_use]
pub fn boxed(lo: V3, hi: V3, material: u32) -> Vec<Triangle> {
    let d = hi - lo;
    let (ex, ey, ez) = (
        V3::new(d[0], 0.0, 0.0),
        V3::new(0.0, d[1], 0.0),
        V3::new(0.0, 0.0, d[2]),
    );
    let mut out = Vec::new();
    for (p, a, b) in [
        (lo, ey, ex),
        (lo, ex, ez),
        (lo, ez, ey),
        (hi, ex * -1.0, ey * -1.0),
        (hi, ez * -1.0, ex * -1.0),
        (hi, ey * -1.0, ez * -1.0),
    ] {
        out.extend(quad(p, a, b, 1.0, 1.0, material, None));
    }
    out
}

fn camera(from: V3, at: V3, fov_y_deg: f64) -> Camera {
    Camera::looking_at(from, at, fov_y_deg, DEFAULT_SIZE)
}

/// The hall: floor 10 wide and 305 deep, walls 4 high, one mirror sphere.
#[must_use]
pub fn hall() -> Scene {
    let (len, z0) = (305.0, 5.0);
    // Floor: 2×2 units per texture repeat; walls: one brick texture repeat
    // per 4 (along) × 2.4 (up) units.
    #[rustfmt::skip]
    let mut triangles = quads(&[
        ([-5.0, 0.0, z0], [10.0, 0.0, 0.0], [0.0, 0.0, -len], [5.0, len / 2.0],       0, Some(0)),
        ([-5.0, 0.0, z0], [0.0, 0.0, -len], [0.0, 4.0, 0.0],  [len / 4.0, 4.0 / 2.4], 1, Some(1)),
        ([5.0, 0.0, z0],  [0.0, 0.0, -len], [0.0, 4.0, 0.0],  [len / 4.0, 4.0 / 2.4], 1, Some(1)),
    ]);
    triangles.extend(sphere(V3::new(1.8, 0.9, -7.0), 0.9, 32, 16, 2));
    Scene {
        camera: camera(V3::new(0.0, 1.7, 4.0), V3::new(0.0, 1.2, -10.0), 50.0),
        background: V3::new(0.55, 0.7, 0.9),
        environment: None,
        ambient: V3::splat(0.25),
        lights: vec![light([0.0, 3.8, 0.0], 0.5), light([-2.0, 3.8, -30.0], 0.4)],
        materials: vec![
            diffuse(V3::splat(0.9)),
            diffuse(V3::splat(0.9)),
            mirror(0.8, V3::new(0.9, 0.95, 1.0)),
        ],
        textures: vec![tiles_texture(), bricks_texture()],
        triangles,
    }
}

/// The mirror room: 8×3.5×8, mirrors on the walls z = ±4, textured floor and
/// side walls, three mirror spheres.
#[must_use]
pub fn mirrors() -> Scene {
    // Floor, ceiling, textured side walls x = ∓4, mirrors z = −4 and +4.
    #[rustfmt::skip]
    let mut t = quads(&[
        ([-4.0, 0.0, 4.0],  [8.0, 0.0, 0.0],  [0.0, 0.0, -8.0], [4.0, 4.0],       0, Some(0)),
        ([-4.0, 3.5, 4.0],  [8.0, 0.0, 0.0],  [0.0, 0.0, -8.0], [1.0, 1.0],       4, None),
        ([-4.0, 0.0, 4.0],  [0.0, 0.0, -8.0], [0.0, 3.5, 0.0],  [3.0, 1.5],       1, Some(1)),
        ([4.0, 0.0, 4.0],   [0.0, 0.0, -8.0], [0.0, 3.5, 0.0],  [3.0, 3.5 / 2.0], 1, Some(2)),
        ([-4.0, 0.0, -4.0], [8.0, 0.0, 0.0],  [0.0, 3.5, 0.0],  [1.0, 1.0],       2, None),
        ([-4.0, 0.0, 4.0],  [8.0, 0.0, 0.0],  [0.0, 3.5, 0.0],  [1.0, 1.0],       2, None),
    ]);
    t.extend(sphere(V3::new(-1.2, 0.8, -1.0), 0.8, 32, 16, 3));
    t.extend(sphere(V3::new(1.4, 0.6, 0.5), 0.6, 32, 16, 2));
    t.extend(sphere(V3::new(0.3, 0.45, -2.6), 0.45, 24, 12, 2));
    Scene {
        camera: camera(V3::new(-2.6, 1.8, 3.0), V3::new(0.8, 1.0, -4.0), 55.0),
        background: V3::ZERO,
        environment: None,
        ambient: V3::splat(0.2),
        lights: vec![light([0.0, 3.2, 0.0], 0.55), light([2.5, 3.0, 2.5], 0.35)],
        materials: vec![
            diffuse(V3::splat(0.9)),
            diffuse(V3::splat(0.85)),
            mirror(0.9, V3::new(1.0, 1.0, 1.0)),
            mirror(0.85, V3::new(1.0, 0.85, 0.6)),
            diffuse(V3::new(0.8, 0.8, 0.75)),
        ],
        textures: vec![tiles_texture(), bricks_texture(), grid_texture()],
        triangles: t,
    }
}

/// Glass: two glass spheres and a glass slab over a textured floor in front
/// of a textured wall.
#[must_use]
pub fn glass() -> Scene {
    // Floor and back wall.
    #[rustfmt::skip]
    let mut t = quads(&[
        ([-30.0, 0.0, 10.0],  [60.0, 0.0, 0.0], [0.0, 0.0, -60.0], [20.0, 20.0],      0, Some(0)),
        ([-30.0, 0.0, -12.0], [60.0, 0.0, 0.0], [0.0, 15.0, 0.0],  [12.0, 15.0 / 2.4], 1, Some(2)),
    ]);
    t.extend(sphere(V3::new(-1.6, 1.0, -2.0), 1.0, 48, 24, 2));
    t.extend(sphere(V3::new(1.2, 0.7, 0.2), 0.7, 40, 20, 2));
    t.extend(boxed(V3::new(2.2, 0.0, -4.5), V3::new(4.2, 2.2, -4.1), 2));
    t.extend(sphere(V3::new(0.5, 0.5, -7.0), 0.5, 24, 12, 3));
    Scene {
        camera: camera(V3::new(0.0, 2.2, 6.0), V3::new(0.0, 0.8, -3.0), 45.0),
        background: V3::new(0.6, 0.7, 0.85),
        environment: None,
        ambient: V3::splat(0.25),
        lights: vec![light([-4.0, 8.0, 6.0], 0.6), light([5.0, 6.0, -1.0], 0.3)],
        materials: vec![
            diffuse(V3::splat(0.9)),
            diffuse(V3::splat(0.9)),
            glass_mat(),
            diffuse(V3::new(0.2, 0.6, 0.3)),
        ],
        textures: vec![tiles_texture(), bricks_texture(), grid_texture()],
        triangles: t,
    }
}

/// 2048×1024 latitude-longitude environment map (`+y` up): a sky-to-ground
/// gradient tinted by longitude, a checker of 2×2-texel cells and dark lines
/// every 32 texels (detail at the finest level, which aliases without mip
/// mapping in every view of it).
#[must_use]
pub fn sky_texture() -> TextureImage {
    image("sky", 2048, 1024, |x, y| {
        let t = f64::from(y) / 1023.0;
        let base = if t < 0.5 {
            V3::new(0.35, 0.55, 0.95).lerp(V3::new(0.85, 0.9, 1.0), t * 2.0)
        } else {
            V3::new(0.6, 0.45, 0.3).lerp(V3::new(0.3, 0.2, 0.12), (t - 0.5) * 2.0)
        };
        let band = f64::from((x / 128) % 4) / 3.0;
        let tint = V3::new(1.0, 0.85 + 0.15 * band, 1.0 - 0.3 * band);
        if x % 32 == 0 || y % 32 == 0 {
            return V3::splat(0.05);
        }
        let fine = if ((x / 2) + (y / 2)) % 2 == 0 {
            1.0
        } else {
            0.45
        };
        (base * tint).map(|c| c * fine)
    })
}

/// The environment-map scene: a mirror sphere, a glass sphere and a
/// polished tiled floor (textured diffuse plus a mirror term) under
/// [`sky_texture`]; the camera sees the map directly above the horizon,
/// reflected in the floor and the sphere, and refracted.
#[must_use]
pub fn envmap() -> Scene {
    #[rustfmt::skip]
    let mut t = quads(&[
        ([-40.0, 0.0, 40.0], [80.0, 0.0, 0.0], [0.0, 0.0, -80.0], [20.0, 20.0], 0, Some(0)),
    ]);
    t.extend(sphere(V3::new(-1.2, 1.0, -1.0), 1.0, 64, 32, 1));
    t.extend(sphere(V3::new(1.3, 0.9, 0.2), 0.9, 64, 32, 2));
    Scene {
        camera: Camera::looking_at(
            V3::new(0.0, 1.6, 5.0),
            V3::new(0.0, 1.2, -1.0),
            60.0,
            (320, 192),
        ),
        background: V3::ZERO,
        environment: Some(sky_texture()),
        ambient: V3::splat(0.1),
        lights: vec![light([3.0, 6.0, 4.0], 0.4)],
        materials: vec![
            // A polished tiled floor: textured diffuse plus a mirror term.
            Material {
                ambient: V3::splat(0.3),
                diffuse: V3::splat(0.3),
                ..mirror(0.6, V3::ONE)
            },
            mirror(0.95, V3::ONE),
            glass_mat(),
        ],
        textures: vec![tiles_texture()],
        triangles: t,
    }
}

/// The distance at which a fronto-parallel square of side `side` mapped
/// once onto a `tex`×`tex` texture shows one texel per pixel for a camera
/// with vertical field of view `fov_y_deg` and `height` rows:
/// `(side/tex)/γ`, `γ = atan(2·tan(fov/2)/height)`.
#[must_use]
pub fn one_texel_per_pixel_distance(side: f64, tex: u32, fov_y_deg: f64, height: u32) -> f64 {
    let g = (2.0 * (fov_y_deg.to_radians() / 2.0).tan() / f64::from(height)).atan();
    side / f64::from(tex) / g
}

/// A fronto-parallel square (side `side`, centred on the view axis at
/// `distance`, whole `tex`×`tex` grid texture once), camera at the origin
/// looking down −z, image `width`×`height`.
#[must_use]
pub fn fronto_quad(
    side: f64,
    tex: u32,
    distance: f64,
    fov_y_deg: f64,
    width: u32,
    height: u32,
) -> Scene {
    let img = image("checker", tex, tex, |x, y| {
        if ((x / 4) + (y / 4)) % 2 == 0 {
            V3::splat(0.9)
        } else {
            V3::splat(0.1)
        }
    });
    let h = side / 2.0;
    Scene {
        camera: Camera::looking_at(
            V3::ZERO,
            V3::new(0.0, 0.0, -1.0),
            fov_y_deg,
            (width, height),
        ),
        background: V3::ZERO,
        environment: None,
        ambient: V3::ONE,
        lights: Vec::new(),
        materials: vec![diffuse(V3::ONE)],
        textures: vec![img],
        triangles: quad(
            V3::new(-h, -h, -distance),
            V3::new(side, 0.0, 0.0),
            V3::new(0.0, side, 0.0),
            1.0,
            1.0,
            0,
            Some(0),
        )
        .to_vec(),
    }
}

/// The fronto-parallel quad of [`fronto_quad`] seen through a 45° flat
/// mirror: the camera at the origin looks down −z at a large mirror whose
/// centre is `a` away; the reflected axis goes up (+y) and meets the
/// textured square (side `side`, whole `tex`×`tex` texture once, facing
/// down) `b` further on. The path length at the square's centre is `a + b`.
#[must_use]
pub fn mirror_quad(
    side: f64,
    tex: u32,
    a: f64,
    b: f64,
    fov_y_deg: f64,
    width: u32,
    height: u32,
) -> Scene {
    let mut s = fronto_quad(side, tex, 1.0, fov_y_deg, width, height);
    s.materials.push(mirror(1.0, V3::ONE));
    let h = side / 2.0;
    let m = 4.0 * (a + b).max(side);
    // Mirror plane through (0, 0, −a) with normal (0, 1, 1)/√2.
    let mut t = quad(
        V3::new(-m, -m, -a + m),
        V3::new(2.0 * m, 0.0, 0.0),
        V3::new(0.0, 2.0 * m, -2.0 * m),
        1.0,
        1.0,
        1,
        None,
    )
    .to_vec();
    t.extend(quad(
        V3::new(-h, b, -a - h),
        V3::new(side, 0.0, 0.0),
        V3::new(0.0, 0.0, side),
        1.0,
        1.0,
        0,
        Some(0),
    ));
    s.triangles = t;
    s
}
