//! Parser state and records (FORMAT.md sections 2–5).
//!
//! One pass over the top-level file with includes expanded in place. The
//! state is the global current material (never restored at `}` or at the
//! end of an include), a stack of transform nodes (`xs` static, `x NAME`
//! bound by name after the whole scene is read), the tracks collected by
//! name (the most recently parsed wins) and the object-space triangles,
//! each tagged with its transform node. [`Parser::finish`] evaluates every
//! node at the load time and moves the triangles to world space.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use super::anim::{Affine, MIN_KEYS, RotChannel, RotKey, Tcb, Track, V3, VecKey, VisKey};
use super::error::{AffError, AffErrorKind};
use super::lexer::{Lexer, Token, parse_f64, parse_i64, parse_usize};
use super::mesh::{RawTri, cone, sphere, zero_area, zero_uv_area};
use super::{Camera, LoadStats, Material, Scene, Texture, Triangle};

/// Deepest include nesting accepted (the top file counts as 1). The
/// reference allows 5; more is accepted here, the limit only stops
/// recursive includes.
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// Material used by primitives that come before any `fm`/`f`: white matte
/// (ambient 0, diffuse 1, no specular, opaque). BART never relies on it.
pub const DEFAULT_MATERIAL: Material = Material {
    ambient: V3::ZERO,
    diffuse: V3::ONE,
    specular: V3::ZERO,
    shine: 0.0,
    transmission: V3::ZERO,
    ior: 1.0,
};

enum NodeKind {
    Static(Affine),
    Anim(Rc<[u8]>),
}

struct Node {
    parent: u32,
    kind: NodeKind,
}

struct OpenBrace {
    file: PathBuf,
    line: usize,
}

struct RawLight {
    position: V3,
    color: V3,
    track: Option<Rc<[u8]>>,
}

/// The parser: everything read so far.
pub(crate) struct Parser {
    time: f64,
    dir: PathBuf,
    files: HashMap<PathBuf, Rc<[u8]>>,
    /// Files given in memory ([`Parser::from_memory`]): includes and
    /// textures resolve among them only, never the file system.
    memory: Option<HashMap<PathBuf, Rc<[u8]>>>,
    nodes: Vec<Node>,
    node: u32,
    open: Vec<(u32, OpenBrace)>,
    chain: Vec<(PathBuf, usize)>,
    detail: i64,
    material: Option<u32>,
    materials: Vec<Material>,
    material_ids: HashMap<[u64; 14], u32>,
    textures: Vec<Texture>,
    texture_ids: HashMap<Vec<u8>, u32>,
    tris: Vec<RawTri>,
    tracks: HashMap<Rc<[u8]>, Track>,
    view: Option<Camera>,
    background: V3,
    ambient: V3,
    lights: Vec<RawLight>,
    stats: LoadStats,
}

/// One file being read: its path and lexer.
struct Src<'a> {
    path: &'a Path,
    lx: Lexer<'a>,
}

impl<'a> Src<'a> {
    fn err(&self, line: usize, kind: AffErrorKind) -> AffError {
        AffError::new(self.path, line, kind)
    }
    fn syntax(&self, line: usize, msg: String) -> AffError {
        self.err(line, AffErrorKind::Syntax(msg))
    }
    fn tok(&mut self, expected: &str) -> Result<Token<'a>, AffError> {
        self.lx.next_token().ok_or_else(|| {
            self.err(
                self.lx.line(),
                AffErrorKind::UnexpectedEof {
                    expected: expected.to_string(),
                },
            )
        })
    }
    fn f64(&mut self, what: &str) -> Result<f64, AffError> {
        let t = self.tok(what)?;
        parse_f64(t.text).ok_or_else(|| bad_number(self.path, &t, what))
    }
    fn v3(&mut self, what: &str) -> Result<V3, AffError> {
        Ok(V3::new(self.f64(what)?, self.f64(what)?, self.f64(what)?))
    }
    fn count(&mut self, what: &str) -> Result<usize, AffError> {
        let t = self.tok(what)?;
        parse_usize(t.text).ok_or_else(|| bad_number(self.path, &t, what))
    }
    fn int(&mut self, what: &str) -> Result<i64, AffError> {
        let t = self.tok(what)?;
        parse_i64(t.text).ok_or_else(|| bad_number(self.path, &t, what))
    }
    fn keyword(&mut self, kw: &str) -> Result<Token<'a>, AffError> {
        let t = self.tok(&format!("keyword {kw:?}"))?;
        if t.text != kw.as_bytes() {
            return Err(self.syntax(
                t.line,
                format!("expected keyword {kw:?}, found {:?}", t.show()),
            ));
        }
        Ok(t)
    }
    /// A name token (not a brace).
    fn name(&mut self, what: &str) -> Result<Token<'a>, AffError> {
        let t = self.tok(what)?;
        if t.text == b"{" || t.text == b"}" {
            return Err(self.syntax(t.line, format!("expected {what}, found {:?}", t.show())));
        }
        Ok(t)
    }
    fn open_brace(&mut self, after: &str) -> Result<Token<'a>, AffError> {
        let t = self.tok(&format!("'{{' after {after}"))?;
        if t.text != b"{" {
            return Err(self.syntax(
                t.line,
                format!("expected '{{' after {after}, found {:?}", t.show()),
            ));
        }
        Ok(t)
    }
    /// True when the next token reads as a number (optional fields).
    fn next_is_number(&mut self) -> bool {
        self.lx.peek().is_some_and(|t| parse_f64(t.text).is_some())
    }
}

/// Capacity to reserve for `n` items announced by a count in the file: a
/// malformed huge count must give an "unexpected end of file" error, not an
/// allocation failure, so at most 2^16 items are reserved up front.
fn reserve(n: usize) -> usize {
    n.min(1 << 16)
}

fn bad_number(path: &Path, t: &Token<'_>, what: &str) -> AffError {
    AffError::new(
        path,
        t.line,
        AffErrorKind::BadNumber {
            token: t.show(),
            expected: what.to_string(),
        },
    )
}

/// The `n` items of a mesh section, each read by `read`; a number/EOF error
/// names the item (`mesh {item} {i} of {n}`).
fn mesh_items<T>(
    src: &mut Src<'_>,
    n: usize,
    item: &str,
    mut read: impl FnMut(&mut Src<'_>) -> Result<T, AffError>,
) -> Result<Vec<T>, AffError> {
    let mut v = Vec::with_capacity(reserve(n));
    for i in 0..n {
        v.push(read(src).map_err(|e| context(e, || format!("mesh {item} {} of {n}", i + 1)))?);
    }
    Ok(v)
}

/// Adds context (e.g. "vertex 3 of 4") to a number/EOF error.
fn context(mut e: AffError, ctx: impl FnOnce() -> String) -> AffError {
    match &mut *e.kind {
        AffErrorKind::BadNumber { expected, .. } | AffErrorKind::UnexpectedEof { expected } => {
            expected.push_str(&format!(" ({})", ctx()));
        }
        _ => {}
    }
    e
}

fn utf8_name(src: &Src<'_>, t: &Token<'_>) -> Result<String, AffError> {
    String::from_utf8(t.text.to_vec())
        .map_err(|_| src.syntax(t.line, format!("name {:?} is not valid UTF-8", t.show())))
}

impl Parser {
    /// A parser for a scene whose names resolve against `dir`.
    pub fn new(dir: PathBuf, time: f64) -> Self {
        Self {
            time,
            dir,
            files: HashMap::new(),
            memory: None,
            nodes: vec![Node {
                parent: 0,
                kind: NodeKind::Static(Affine::IDENTITY),
            }],
            node: 0,
            open: Vec::new(),
            chain: Vec::new(),
            detail: 0,
            material: None,
            materials: Vec::new(),
            material_ids: HashMap::new(),
            textures: Vec::new(),
            texture_ids: HashMap::new(),
            tris: Vec::new(),
            tracks: HashMap::new(),
            view: None,
            background: V3::ZERO,
            ambient: V3::ONE,
            lights: Vec::new(),
            stats: LoadStats {
                time,
                ..LoadStats::default()
            },
        }
    }

    /// A parser whose files (scene files and PPM textures, named relative
    /// to `dir`) are the given bytes; any other name is "not found".
    pub fn from_memory(dir: PathBuf, time: f64, files: &[(&str, &[u8])]) -> Self {
        let memory = files
            .iter()
            .map(|&(name, bytes)| (dir.join(name), Rc::from(bytes)))
            .collect();
        Self {
            memory: Some(memory),
            ..Self::new(dir, time)
        }
    }

    /// The bytes of `path`: from memory, or from the file system.
    fn source_bytes(&self, path: &Path) -> std::io::Result<Rc<[u8]>> {
        match &self.memory {
            Some(m) => m.get(path).cloned().ok_or_else(|| {
                std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "not among the in-memory files",
                )
            }),
            None => Ok(std::fs::read(path)?.into()),
        }
    }

    fn read_file(&mut self, path: &Path) -> std::io::Result<Rc<[u8]>> {
        if let Some(b) = self.files.get(path) {
            return Ok(b.clone());
        }
        let b = self.source_bytes(path)?;
        self.files.insert(path.to_path_buf(), b.clone());
        self.stats.distinct_files += 1;
        Ok(b)
    }

    /// Parses the top-level file.
    pub fn parse_top(&mut self, path: &Path) -> Result<(), AffError> {
        let bytes = self
            .read_file(path)
            .map_err(|e| AffError::new(path, 0, AffErrorKind::Io(e)))?;
        self.parse_bytes(path, &bytes)?;
        if let Some((_, b)) = self.open.last() {
            return Err(AffError::new(
                &b.file,
                b.line,
                AffErrorKind::Syntax("'{' is never closed".into()),
            ));
        }
        Ok(())
    }

    fn parse_bytes(&mut self, path: &Path, bytes: &[u8]) -> Result<(), AffError> {
        self.stats.files += 1;
        let mut src = Src {
            path,
            lx: Lexer::new(bytes),
        };
        while let Some(t) = src.lx.next_token() {
            self.command(&mut src, t)?;
        }
        // After the last token the lexer stands at the end of the file.
        self.stats.lines += src.lx.line_count_at_end();
        Ok(())
    }

    fn command(&mut self, src: &mut Src<'_>, t: Token<'_>) -> Result<(), AffError> {
        match t.text {
            [b'#' | b'%', ..] => src.lx.skip_line(),
            b"v" => self.view(src, t)?,
            b"b" => self.background = src.v3("background colour")?,
            b"am" => self.ambient = src.v3("ambient intensity")?,
            b"l" | b"la" => self.light(src, t.text == b"la")?,
            b"a" => {
                let t0 = src.f64("clock start time")?;
                let t1 = src.f64("clock end time")?;
                let n = src.count("clock frame count")?;
                self.stats.clock = Some((t0, t1, n));
            }
            b"d" => self.detail = src.int("detail level")?,
            b"i" => self.include(src)?,
            b"fm" => self.material_fm(src)?,
            b"f" => self.material_f(src)?,
            b"p" | b"pp" => self.polygon(src, t.text == b"pp")?,
            b"tt" | b"ttp" => self.textured_triangle(src, t.text == b"ttp")?,
            b"tpa" => self.animated_triangles(src)?,
            b"s" => self.sphere(src)?,
            b"c" => self.cone(src)?,
            b"m" => self.mesh(src)?,
            b"xs" => {
                let s = src.v3("scale")?;
                let axis = src.v3("rotation axis")?;
                let deg = src.f64("rotation angle (degrees)")?;
                let tr = src.v3("translation")?;
                let brace = src.open_brace("`xs`")?;
                self.push_node(
                    NodeKind::Static(Affine::trs(tr, axis, deg, s)),
                    src.path,
                    brace.line,
                );
            }
            b"x" => {
                let name = src.name("animation name")?;
                let brace = src.open_brace("`x NAME`")?;
                self.push_node(NodeKind::Anim(name.text.into()), src.path, brace.line);
            }
            b"}" => {
                let Some((node, _)) = self.open.pop() else {
                    return Err(src.syntax(t.line, "'}' without a matching '{'".into()));
                };
                self.node = self.nodes[node as usize].parent;
            }
            b"k" => self.track(src)?,
            _ => {
                return Err(src.err(t.line, AffErrorKind::UnknownCommand(t.show())));
            }
        }
        Ok(())
    }

    /// `l` / `la NAME`: a point light, static or animated.
    fn light(&mut self, src: &mut Src<'_>, animated: bool) -> Result<(), AffError> {
        let track = if animated {
            Some(src.name("animation name")?.text.into())
        } else {
            None
        };
        let position = src.v3("light position")?;
        let color = self.opt_color(src)?;
        self.lights.push(RawLight {
            position,
            color,
            track,
        });
        Ok(())
    }

    /// `N` material values, each error naming the field of `cmd`.
    fn material_values<const N: usize>(src: &mut Src<'_>, cmd: &str) -> Result<[f64; N], AffError> {
        let mut v = [0.0; N];
        for (i, x) in v.iter_mut().enumerate() {
            *x = src
                .f64("material value")
                .map_err(|e| context(e, || format!("`{cmd}` field {} of {N}", i + 1)))?;
        }
        Ok(v)
    }

    /// `fm`: ambient, diffuse, specular RGB, shine, transmission, ior.
    fn material_fm(&mut self, src: &mut Src<'_>) -> Result<(), AffError> {
        let v: [f64; 12] = Self::material_values(src, "fm")?;
        self.set_material(Material {
            ambient: V3::new(v[0], v[1], v[2]),
            diffuse: V3::new(v[3], v[4], v[5]),
            specular: V3::new(v[6], v[7], v[8]),
            shine: v[9],
            transmission: V3::splat(v[10]),
            ior: guard_ior(v[11]),
        });
        Ok(())
    }

    /// `f`: RGB, kd, ks, shine, transmission, ior (NFF).
    fn material_f(&mut self, src: &mut Src<'_>) -> Result<(), AffError> {
        let v: [f64; 8] = Self::material_values(src, "f")?;
        let rgb = V3::new(v[0], v[1], v[2]);
        let diffuse = rgb * v[3];
        self.set_material(Material {
            ambient: diffuse,
            diffuse,
            specular: V3::splat(v[4]),
            shine: v[5],
            transmission: V3::splat(v[6]),
            ior: guard_ior(v[7]),
        });
        Ok(())
    }

    /// `s`: a tessellated sphere.
    fn sphere(&mut self, src: &mut Src<'_>) -> Result<(), AffError> {
        let c = src.v3("sphere centre")?;
        let r = src.f64("sphere radius")?;
        self.stats.spheres += 1;
        for (p, n) in sphere(c, r) {
            self.push_tri(p, Some(n), None, None);
        }
        Ok(())
    }

    /// `c`: a tessellated cone (or cylinder).
    fn cone(&mut self, src: &mut Src<'_>) -> Result<(), AffError> {
        let b = src.v3("cone base point")?;
        let rb = src.f64("cone base radius")?;
        let a = src.v3("cone apex point")?;
        let ra = src.f64("cone apex radius")?;
        self.stats.cones += 1;
        for (p, n) in cone(b, rb, a, ra) {
            self.push_tri(p, Some(n), None, None);
        }
        Ok(())
    }

    fn opt_color(&mut self, src: &mut Src<'_>) -> Result<V3, AffError> {
        if src.next_is_number() {
            src.v3("light colour")
        } else {
            Ok(V3::ONE)
        }
    }

    fn push_node(&mut self, kind: NodeKind, file: &Path, line: usize) {
        let id = self.nodes.len() as u32;
        self.nodes.push(Node {
            parent: self.node,
            kind,
        });
        self.open.push((
            id,
            OpenBrace {
                file: file.to_path_buf(),
                line,
            },
        ));
        self.node = id;
    }

    fn view(&mut self, src: &mut Src<'_>, t: Token<'_>) -> Result<(), AffError> {
        src.keyword("from")?;
        let from = src.v3("`from` point")?;
        src.keyword("at")?;
        let at = src.v3("`at` point")?;
        src.keyword("up")?;
        let up = src.v3("`up` vector")?;
        src.keyword("angle")?;
        let angle_tok = src.lx.peek();
        let fov = src.f64("field of view (degrees)")?;
        if !(fov > 0.0 && fov < 180.0) {
            let line = angle_tok.map_or(t.line, |a| a.line);
            return Err(src.syntax(line, format!("field of view {fov} not in (0, 180) degrees")));
        }
        src.keyword("hither")?;
        let mut hither = src.f64("hither distance")?;
        // As the reference parser: tiny hither values mean 1.0.
        if hither < 1e-4 {
            hither = 1.0;
        }
        let kw = src.keyword("resolution")?;
        let w = src.count("image width")?;
        let h = src.count("image height")?;
        let (Ok(width), Ok(height)) = (u32::try_from(w), u32::try_from(h)) else {
            return Err(src.syntax(kw.line, format!("resolution {w}x{h} too large")));
        };
        if width == 0 || height == 0 {
            return Err(src.syntax(kw.line, format!("resolution {w}x{h} is empty")));
        }
        if from == at || up == V3::ZERO {
            return Err(src.syntax(
                t.line,
                "degenerate view: `from` equals `at` or `up` is zero".into(),
            ));
        }
        self.view = Some(Camera {
            from,
            at,
            up,
            fov_y_deg: fov,
            hither,
            width,
            height,
        });
        Ok(())
    }

    fn include(&mut self, src: &mut Src<'_>) -> Result<(), AffError> {
        let level = src.int("detail level")?;
        let name = src.name("file name")?;
        if level > self.detail {
            return Ok(());
        }
        let name_s = utf8_name(src, &name)?;
        if self.chain.len() + 1 >= MAX_INCLUDE_DEPTH {
            return Err(src.syntax(
                name.line,
                format!("includes nested deeper than {MAX_INCLUDE_DEPTH} (recursive include?)"),
            ));
        }
        // Every name resolves against the top-level file's folder.
        let path = self.dir.join(&name_s);
        let bytes = self.read_file(&path).map_err(|e| {
            src.err(
                name.line,
                AffErrorKind::MissingInclude {
                    name: name_s.clone(),
                    path: path.clone(),
                    source: e,
                },
            )
        })?;
        self.chain.push((src.path.to_path_buf(), name.line));
        let r = self.parse_bytes(&path, &bytes);
        self.chain.pop();
        r.map_err(|mut e| {
            e.included_from.push((src.path.to_path_buf(), name.line));
            e
        })
    }

    fn set_material(&mut self, m: Material) {
        let key = material_key(&m);
        let next = self.materials.len() as u32;
        let id = *self.material_ids.entry(key).or_insert(next);
        if id == next {
            self.materials.push(m);
        }
        self.material = Some(id);
    }

    fn current_material(&mut self) -> u32 {
        match self.material {
            Some(m) => m,
            None => {
                self.set_material(DEFAULT_MATERIAL);
                self.stats.used_default_material = true;
                self.material.unwrap_or(0)
            }
        }
    }

    fn texture(&mut self, src: &Src<'_>, name: &Token<'_>) -> Result<u32, AffError> {
        if let Some(&id) = self.texture_ids.get(name.text) {
            return Ok(id);
        }
        let name_s = utf8_name(src, name)?;
        let path = self.dir.join(&name_s);
        let image = match &self.memory {
            None => crate::scene::ppm::read_ppm(&path),
            Some(_) => self
                .source_bytes(&path)
                .map_err(|e| crate::scene::ppm::PpmError {
                    path: path.clone(),
                    line: None,
                    message: format!("cannot read: {e}"),
                })
                .and_then(|b| crate::scene::ppm::parse_ppm(&b, &path)),
        }
        .map_err(|e| {
            src.err(
                name.line,
                AffErrorKind::Texture {
                    name: name_s.clone(),
                    source: e,
                },
            )
        })?;
        let id = self.textures.len() as u32;
        self.textures.push(Texture {
            name: name_s,
            path,
            image,
        });
        self.texture_ids.insert(name.text.to_vec(), id);
        Ok(id)
    }

    fn push_tri(
        &mut self,
        p: [V3; 3],
        n: Option<[V3; 3]>,
        uv: Option<[[f64; 2]; 3]>,
        texture: Option<u32>,
    ) {
        let material = self.current_material();
        self.stats.triangles_read += 1;
        if texture.is_some() {
            self.stats.textured_read += 1;
        }
        if let Some(uv) = &uv
            && zero_uv_area(uv)
        {
            self.stats.zero_uv_area += 1;
        }
        if zero_area(&p) {
            self.stats.skipped_degenerate += 1;
            if texture.is_some() {
                self.stats.skipped_degenerate_textured += 1;
            }
            return;
        }
        self.tris.push(RawTri {
            p,
            n,
            uv,
            material,
            texture,
            node: self.node,
        });
    }

    fn polygon(&mut self, src: &mut Src<'_>, normals: bool) -> Result<(), AffError> {
        let nt = src.lx.peek();
        let n = src.count("polygon vertex count")?;
        if n < 3 {
            let line = nt.map_or(src.lx.line(), |t| t.line);
            return Err(src.syntax(line, format!("polygon with {n} vertices (need ≥ 3)")));
        }
        let mut p = Vec::with_capacity(reserve(n));
        let mut nn = Vec::with_capacity(reserve(n));
        for i in 0..n {
            let ctx = || format!("polygon vertex {} of {n}", i + 1);
            p.push(src.v3("vertex coordinate").map_err(|e| context(e, ctx))?);
            if normals {
                nn.push(src.v3("normal component").map_err(|e| context(e, ctx))?);
            }
        }
        self.stats.polygons += 1;
        for i in 1..n - 1 {
            let tri = [p[0], p[i], p[i + 1]];
            let nor = normals.then(|| [nn[0], nn[i], nn[i + 1]]);
            self.push_tri(tri, nor, None, None);
        }
        Ok(())
    }

    fn textured_triangle(&mut self, src: &mut Src<'_>, normals: bool) -> Result<(), AffError> {
        let name = src.name("texture name")?;
        let tex = self.texture(src, &name)?;
        let mut p = [V3::ZERO; 3];
        let mut n = [V3::ZERO; 3];
        let mut uv = [[0.0; 2]; 3];
        for i in 0..3 {
            let ctx = || format!("textured-triangle vertex {} of 3", i + 1);
            p[i] = src.v3("vertex coordinate").map_err(|e| context(e, ctx))?;
            if normals {
                n[i] = src.v3("normal component").map_err(|e| context(e, ctx))?;
            }
            uv[i] = [
                src.f64("texture coordinate").map_err(|e| context(e, ctx))?,
                src.f64("texture coordinate").map_err(|e| context(e, ctx))?,
            ];
        }
        self.push_tri(p, normals.then_some(n), Some(uv), Some(tex));
        Ok(())
    }

    /// `tpa N`: N key poses; linear interpolation at the load time between
    /// the bracketing keys, first/last pose outside (6.6).
    fn animated_triangles(&mut self, src: &mut Src<'_>) -> Result<(), AffError> {
        let n = src.count("key pose count")?;
        if n == 0 {
            return Err(src.syntax(src.lx.line(), "`tpa` with 0 key poses".into()));
        }
        let mut keys: Vec<(f64, [V3; 3], [V3; 3])> = Vec::with_capacity(reserve(n));
        for k in 0..n {
            let ctx = || format!("`tpa` key {} of {n}", k + 1);
            let time = src.f64("key time").map_err(|e| context(e, ctx))?;
            let mut p = [V3::ZERO; 3];
            let mut nn = [V3::ZERO; 3];
            for i in 0..3 {
                p[i] = src.v3("vertex coordinate").map_err(|e| context(e, ctx))?;
                nn[i] = src.v3("normal component").map_err(|e| context(e, ctx))?;
            }
            keys.push((time, p, nn));
        }
        let t = self.time;
        let (p, nn) = if t <= keys[0].0 {
            (keys[0].1, keys[0].2)
        } else if t >= keys[n - 1].0 {
            (keys[n - 1].1, keys[n - 1].2)
        } else {
            let i = keys.iter().position(|k| k.0 > t).unwrap_or(n - 1).max(1);
            let (a, b) = (&keys[i - 1], &keys[i]);
            let s = if b.0 > a.0 {
                (t - a.0) / (b.0 - a.0)
            } else {
                0.0
            };
            let lerp = |x: V3, y: V3| x + ((y - x) * s);
            (
                [0, 1, 2].map(|j| lerp(a.1[j], b.1[j])),
                [0, 1, 2].map(|j| lerp(a.2[j], b.2[j])),
            )
        };
        self.stats.animated_triangles += 1;
        self.push_tri(p, Some(nn), None, None);
        Ok(())
    }

    fn mesh(&mut self, src: &mut Src<'_>) -> Result<(), AffError> {
        src.keyword("vertices")?;
        let nv = src.count("vertex count")?;
        let verts = mesh_items(src, nv, "vertex", |s| s.v3("vertex coordinate"))?;
        let mut kw = src.tok("`normals`, `texturecoords` or `triangles`")?;
        let mut normals = None;
        if kw.text == b"normals" {
            let nn = src.count("normal count")?;
            normals = Some(mesh_items(src, nn, "normal", |s| s.v3("normal component"))?);
            kw = src.tok("`texturecoords` or `triangles`")?;
        }
        let mut uvs = None;
        if kw.text == b"texturecoords" {
            let nt = src.count("texture coordinate count")?;
            let name = src.name("texture name")?;
            let tex = self.texture(src, &name)?;
            let v = mesh_items(src, nt, "texture coordinate", |s| {
                Ok([s.f64("texture coordinate")?, s.f64("texture coordinate")?])
            })?;
            uvs = Some((v, tex));
            kw = src.tok("`triangles`")?;
        }
        if kw.text != b"triangles" {
            let want = match (normals.is_some(), uvs.is_some()) {
                (false, false) => "`normals`, `texturecoords` or `triangles`",
                (true, false) => "`texturecoords` or `triangles`",
                _ => "`triangles`",
            };
            return Err(src.syntax(
                kw.line,
                format!(
                    "mesh: expected {want}, found {:?} (is a vertex, normal or texture-coordinate count too small?)",
                    kw.show()
                ),
            ));
        }
        let nt = src.count("triangle count")?;
        self.stats.meshes += 1;
        self.mesh_triangles(src, nt, &verts, normals.as_deref(), uvs.as_ref())
    }

    /// The `triangles` block of a mesh: `nt` index triples (vertex, then
    /// normal and texture-coordinate ones when the mesh has them).
    fn mesh_triangles(
        &mut self,
        src: &mut Src<'_>,
        nt: usize,
        verts: &[V3],
        normals: Option<&[V3]>,
        uvs: Option<&(Vec<[f64; 2]>, u32)>,
    ) -> Result<(), AffError> {
        let per = 3 + 3 * usize::from(normals.is_some()) + 3 * usize::from(uvs.is_some());
        let mut idx = [0usize; 9];
        for i in 0..nt {
            let mut line = 0;
            for (k, slot) in idx[..per].iter_mut().enumerate() {
                let t = src
                    .tok("triangle index")
                    .map_err(|e| context(e, || format!("mesh triangle {} of {nt}", i + 1)))?;
                if k == 0 {
                    line = t.line;
                }
                *slot = parse_usize(t.text).ok_or_else(|| {
                    context(bad_number(src.path, &t, "triangle index"), || {
                        format!("mesh triangle {} of {nt}", i + 1)
                    })
                })?;
            }
            let check = |ids: &[usize],
                         len: usize,
                         what: &str,
                         plural: &str|
             -> Result<(), AffError> {
                match ids.iter().find(|&&v| v >= len) {
                    Some(bad) => Err(src.syntax(
                        line,
                        format!(
                            "mesh triangle {} of {nt}: {what} index {bad} out of range (mesh has {len} {plural})",
                            i + 1
                        ),
                    )),
                    None => Ok(()),
                }
            };
            check(&idx[0..3], verts.len(), "vertex", "vertices")?;
            let p = [verts[idx[0]], verts[idx[1]], verts[idx[2]]];
            let mut next = 3;
            let n = match normals {
                Some(nv) => {
                    check(&idx[next..next + 3], nv.len(), "normal", "normals")?;
                    let n = [nv[idx[next]], nv[idx[next + 1]], nv[idx[next + 2]]];
                    next += 3;
                    Some(n)
                }
                None => None,
            };
            let (uv, tex) = match uvs {
                Some((tv, tex)) => {
                    check(
                        &idx[next..next + 3],
                        tv.len(),
                        "texture coordinate",
                        "texture coordinates",
                    )?;
                    (
                        Some([tv[idx[next]], tv[idx[next + 1]], tv[idx[next + 2]]]),
                        Some(*tex),
                    )
                }
                None => (None, None),
            };
            self.push_tri(p, n, uv, tex);
        }
        Ok(())
    }

    fn track(&mut self, src: &mut Src<'_>) -> Result<(), AffError> {
        let name = src.name("track name")?;
        src.open_brace("`k NAME`")?;
        let mut track = Track::default();
        loop {
            let t = src.tok("a channel (`transl`, `rot`, `scale`, `visibility`) or '}'")?;
            let chan = t.text;
            if chan == b"}" {
                break;
            }
            if matches!(chan, [b'#' | b'%', ..]) {
                src.lx.skip_line();
                continue;
            }
            let n = src.count("key count")?;
            let cname_owned = t.show();
            let cname: &str = &cname_owned;
            let ctx = |k: usize| move || format!("`{cname}` key {} of {n}", k + 1);
            let path = src.path;
            let line = t.line;
            let syntax = |m: String| AffError::new(path, line, AffErrorKind::Syntax(m));
            let dup = || syntax(format!("channel `{cname}` given twice in track"));
            let few = || {
                syntax(format!(
                    "channel `{cname}` has {n} keys; splines need at least {MIN_KEYS}"
                ))
            };
            match chan {
                b"transl" | b"scale" => {
                    let keys = read_keys(src, n, ctx, |src| {
                        let time = src.f64("key time")?;
                        let value = src.v3("key value")?;
                        let tcb = read_tcb(src)?;
                        Ok(VecKey { time, value, tcb })
                    })?;
                    if n < MIN_KEYS {
                        return Err(few());
                    }
                    let slot = if chan == b"transl" {
                        &mut track.transl
                    } else {
                        &mut track.scale
                    };
                    if slot.replace(keys).is_some() {
                        return Err(dup());
                    }
                }
                b"rot" => {
                    let keys = read_keys(src, n, ctx, |src| {
                        let time = src.f64("key time")?;
                        let axis = src.v3("rotation axis")?;
                        let deg = src.f64("rotation angle (degrees)")?;
                        let tcb = read_tcb(src)?;
                        Ok(RotKey {
                            time,
                            axis,
                            deg,
                            tcb,
                        })
                    })?;
                    if n < MIN_KEYS {
                        return Err(few());
                    }
                    if track.rot.replace(RotChannel::new(&keys)).is_some() {
                        return Err(dup());
                    }
                }
                b"visibility" => {
                    let keys = read_keys(src, n, ctx, |src| {
                        let time = src.f64("key time")?;
                        let flag = src.f64("visibility flag")?;
                        Ok(VisKey {
                            time,
                            visible: flag != 0.0,
                        })
                    })?;
                    if track.visibility.replace(keys).is_some() {
                        return Err(dup());
                    }
                }
                _ => {
                    return Err(src.syntax(
                        t.line,
                        format!(
                            "unknown track channel {cname:?} (expected transl, rot, scale or visibility)"
                        ),
                    ));
                }
            }
        }
        self.stats.tracks += 1;
        // The most recently parsed track of a name wins (as the reference).
        self.tracks.insert(name.text.into(), track);
        Ok(())
    }

    /// Evaluates transforms and camera at the load time; world-space scene.
    pub fn finish(mut self, top: &Path) -> Result<Scene, AffError> {
        let world = self.world_nodes();
        let triangles = self.world_triangles(&world);
        let camera = self.camera_at_time(top)?;
        let lights = self.lights_at_time();
        Ok(Scene {
            camera,
            background: self.background,
            ambient: self.ambient,
            lights,
            materials: self.materials,
            textures: self.textures,
            triangles,
            stats: self.stats,
        })
    }

    /// World matrix and visibility per node at the load time (parents
    /// precede children); names of unbound tracks go to the stats.
    fn world_nodes(&mut self) -> Vec<(Affine, bool)> {
        let t = self.time;
        // World matrix and visibility per node; parents precede children.
        let mut world: Vec<(Affine, bool)> = Vec::with_capacity(self.nodes.len());
        let mut unbound: Vec<String> = Vec::new();
        for (i, node) in self.nodes.iter().enumerate() {
            let (local, vis) = match &node.kind {
                NodeKind::Static(m) => (*m, true),
                NodeKind::Anim(name) => match self.tracks.get(name) {
                    Some(tr) => (tr.matrix(t), tr.visible(t)),
                    None => {
                        let s = String::from_utf8_lossy(name).into_owned();
                        if !unbound.contains(&s) {
                            unbound.push(s);
                        }
                        (Affine::IDENTITY, true)
                    }
                },
            };
            if i == 0 {
                world.push((local, vis));
            } else {
                let (pm, pv) = world[node.parent as usize];
                world.push((pm.mul(&local), pv && vis));
            }
        }
        self.stats.unbound_tracks = unbound;
        world
    }

    /// Visible triangles in world space (normals by the inverse transpose,
    /// dropped where it is singular).
    fn world_triangles(&mut self, world: &[(Affine, bool)]) -> Vec<Triangle> {
        let normal_mats: Vec<Option<[[f64; 3]; 3]>> =
            world.iter().map(|(m, _)| m.normal_matrix()).collect();
        let mut triangles = Vec::with_capacity(self.tris.len());
        for r in &self.tris {
            let (m, vis) = &world[r.node as usize];
            if !vis {
                self.stats.hidden += 1;
                continue;
            }
            let p = r.p.map(|v| m.point(v));
            if !p.iter().all(|v| v.is_finite()) {
                // Only reachable with absurd scales (e.g. 1e300 · 1e300).
                self.stats.skipped_non_finite += 1;
                continue;
            }
            let n = match (r.n, &normal_mats[r.node as usize]) {
                (Some(n), Some(nm)) => {
                    let w = n.map(|v| {
                        V3::from([0, 1, 2].map(|i| V3::from(nm[i]).dot(v))).try_normalize()
                    });
                    match w {
                        [Some(a), Some(b), Some(c)] => Some([a, b, c]),
                        _ => {
                            self.stats.dropped_normals += 1;
                            None
                        }
                    }
                }
                (Some(_), None) => {
                    self.stats.dropped_normals += 1;
                    None
                }
                (None, _) => None,
            };
            triangles.push(Triangle {
                p,
                n,
                uv: r.uv,
                material: r.material,
                texture: r.texture,
            });
        }
        triangles
    }

    /// The view at the load time (the `camera` track when present).
    fn camera_at_time(&mut self, top: &Path) -> Result<Camera, AffError> {
        let t = self.time;
        let Some(mut camera) = self.view else {
            return Err(AffError::new(
                top,
                0,
                AffErrorKind::Syntax("no view (`v`) record in the scene".into()),
            ));
        };
        if let Some(cam) = self.tracks.get(&b"camera"[..]) {
            self.stats.camera_from_track = true;
            apply_camera_track(&mut camera, cam, t);
        }
        let finite = |v: V3| v.is_finite();
        if !(finite(camera.from) && finite(camera.at) && finite(camera.up)) {
            return Err(AffError::new(
                top,
                0,
                AffErrorKind::Syntax(format!(
                    "camera at time {t} is not finite (from {:?}, at {:?}, up {:?})",
                    camera.from, camera.at, camera.up
                )),
            ));
        }
        Ok(camera)
    }

    /// Lights at the load time.
    fn lights_at_time(&self) -> Vec<super::Light> {
        let t = self.time;
        let mut lights = Vec::with_capacity(self.lights.len());
        for l in &self.lights {
            // `la`: the track's translation at t replaces the written
            // position (unused in BART; the written one stays when the track
            // or its translation channel is missing).
            let position = l
                .track
                .as_ref()
                .and_then(|n| self.tracks.get(n))
                .and_then(|tr| tr.translation(t))
                .unwrap_or(l.position);
            lights.push(super::Light {
                position,
                color: l.color,
            });
        }
        lights
    }
}

/// 6.5: eye = translation at t; view direction = −(third column of R),
/// up = second column of R; `v` keeps angle, hither and resolution.
pub(crate) fn apply_camera_track(camera: &mut Camera, track: &Track, t: f64) {
    let eye = track.translation(t).unwrap_or(camera.from);
    match &track.rot {
        Some(r) => {
            let m = r.eval(t);
            let dir = m.column(2) * -1.0;
            camera.at = eye + dir;
            camera.up = m.column(1);
        }
        None => camera.at = eye + (camera.at - camera.from),
    }
    camera.from = eye;
}

fn read_tcb(src: &mut Src<'_>) -> Result<Tcb, AffError> {
    Ok(Tcb {
        t: src.f64("tension")?,
        c: src.f64("continuity")?,
        b: src.f64("bias")?,
    })
}

/// `ior <= 0` (robots has transmissive materials with ior 0) → 1, i.e. no
/// bending; NaN cannot occur (numbers are checked finite).
fn guard_ior(ior: f64) -> f64 {
    if ior > 0.0 { ior } else { 1.0 }
}

fn material_key(m: &Material) -> [u64; 14] {
    let mut k = [0u64; 14];
    let [a, d, s, t] = [m.ambient, m.diffuse, m.specular, m.transmission].map(|c| c.to_array());
    let vals = a
        .iter()
        .chain(&d)
        .chain(&s)
        .chain([&m.shine])
        .chain(&t[..1])
        .chain([&m.ior]);
    for (slot, v) in k.iter_mut().zip(vals) {
        *slot = v.to_bits();
    }
    k
}

/// `n` keys read by `key`, each error naming the key (`ctx(k)`).
fn read_keys<T, C: FnOnce() -> String>(
    src: &mut Src<'_>,
    n: usize,
    ctx: impl Fn(usize) -> C,
    mut key: impl FnMut(&mut Src<'_>) -> Result<T, AffError>,
) -> Result<Vec<T>, AffError> {
    let mut keys = Vec::with_capacity(reserve(n));
    for k in 0..n {
        keys.push(key(src).map_err(|e| context(e, ctx(k)))?);
    }
    Ok(keys)
}
