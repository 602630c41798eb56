//! The crates' import graphs against their floor order: in `src/` (the
//! order of `src/lib.rs`'s stage table) and in `host-tests/src/` (the
//! order its `lib.rs` gives), a module uses only modules of its own floor
//! or of a floor below, and no two modules use each other, directly or
//! through others.
//!
//! The graph is read from the source text: every `crate::`, `super::` and
//! `self::` path in code (comments and doc comments skipped, `use` brace
//! groups expanded) names the module whose file holds it; `#[cfg(test)]`
//! code is left out (tests may use any floor). A path into the module's own
//! parent (an item the parent declares or re-exports) is not an edge.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

type Module = Vec<String>;
type Graph = BTreeMap<Module, BTreeSet<Module>>;

/// `(module path, source text)` of every `.rs` file under `dir`
/// (`a/mod.rs` and `lib.rs` name their folder).
fn sources(dir: &Path) -> Vec<(Module, String)> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<(Module, String)>) {
        let mut entries: Vec<_> = fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.expect("directory entry").path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(root, &p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p.strip_prefix(root).expect("under the root");
                let mut m: Module = rel
                    .with_extension("")
                    .iter()
                    .map(|s| s.to_string_lossy().into_owned())
                    .collect();
                if matches!(m.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                    m.pop();
                }
                let text =
                    fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                out.push((m, text));
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out
}

/// The code of `text`: comment lines blanked, trailing comments cut (on
/// lines without a string), and the items under a `#[cfg(test)]` (or
/// `#[cfg(all(test, …))]`) attribute left out.
fn code(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < lines.len() {
        let t = lines[i].trim_start();
        if t.starts_with("#[cfg(test") || t.starts_with("#[cfg(all(test") {
            // Skip to the end of the item: its `;`, or its closing brace.
            let mut depth = 0i32;
            let mut opened = false;
            let mut j = i + 1;
            while j < lines.len() {
                let l = lines[j];
                depth += l.matches('{').count() as i32 - l.matches('}').count() as i32;
                opened |= l.contains('{');
                if (opened && depth <= 0) || (!opened && l.trim_end().ends_with(';')) {
                    break;
                }
                j += 1;
            }
            i = j + 1;
            continue;
        }
        if !t.starts_with("//") {
            let l = match lines[i].find("//") {
                Some(k) if !lines[i].contains('"') => &lines[i][..k],
                _ => lines[i],
            };
            out.push_str(l);
        }
        out.push('\n');
        i += 1;
    }
    out
}

/// The paths of a `use` brace group's body, `a, b::{c, d}` → `[a], [b, c],
/// [b, d]`.
fn expand(body: &str) -> Vec<Vec<String>> {
    let mut parts = Vec::new();
    let (mut depth, mut cur) = (0, String::new());
    for ch in body.chars() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            _ => {}
        }
        if ch == ',' && depth == 0 {
            parts.push(std::mem::take(&mut cur));
        } else {
            cur.push(ch);
        }
    }
    parts.push(cur);
    let mut out = Vec::new();
    for p in parts.iter().map(|p| p.trim()).filter(|p| !p.is_empty()) {
        if let Some(k) = p.find("::{") {
            let head = segments(&p[..k]);
            let inner = &p[k + 3..p.rfind('}').expect("closing brace")];
            out.extend(
                expand(inner)
                    .into_iter()
                    .map(|t| [head.clone(), t].concat()),
            );
        } else {
            out.push(segments(p));
        }
    }
    out
}

fn segments(path: &str) -> Vec<String> {
    path.split("::")
        .map(|s| s.split_whitespace().next().unwrap_or("").to_owned())
        .filter(|s| !s.is_empty())
        .collect()
}

/// Every `crate::`/`super::`/`self::` path in `code`, as written.
fn paths(code: &str) -> Vec<Vec<String>> {
    let b = code.as_bytes();
    let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let start = ["crate::", "super::", "self::"]
            .into_iter()
            .find(|k| b[i..].starts_with(k.as_bytes()) && (i == 0 || !ident(b[i - 1])));
        let Some(kw) = start else {
            i += 1;
            continue;
        };
        // The head `kw::seg::seg…`, then an optional `::{ … }` group.
        let mut j = i + kw.len() - 2;
        while b[j..].starts_with(b"::") && j + 2 < b.len() && ident(b[j + 2]) {
            j += 2;
            while j < b.len() && ident(b[j]) {
                j += 1;
            }
        }
        let head = segments(&code[i..j]);
        if b[j..].starts_with(b"::{") {
            let (mut depth, mut k) = (1, j + 3);
            while k < b.len() && depth > 0 {
                depth += i32::from(b[k] == b'{') - i32::from(b[k] == b'}');
                k += 1;
            }
            out.extend(
                expand(&code[j + 3..k - 1])
                    .into_iter()
                    .map(|t| [head.clone(), t].concat()),
            );
            i = k;
        } else {
            out.push(head);
            i = j;
        }
    }
    out
}

/// Module edges of a crate's sources: `a → b` when `a`'s code names an
/// item of `b` (the longest module prefix of the path; not `a` itself nor
/// one of its ancestors).
fn graph(files: &[(Module, String)]) -> Graph {
    let mods: BTreeSet<Module> = files.iter().map(|(m, _)| m.clone()).collect();
    // Modules declared under `#[cfg(test)]` in a file of their own.
    let mut tests = Vec::new();
    for (me, text) in files {
        let lines: Vec<&str> = text.lines().map(str::trim).collect();
        for w in lines.windows(2) {
            let decl = w[1].strip_prefix("pub ").unwrap_or(w[1]);
            if let (true, Some(name)) = (w[0].starts_with("#[cfg(test"), decl.strip_prefix("mod "))
            {
                if let Some(name) = name.strip_suffix(';') {
                    tests.push([me.clone(), vec![name.to_owned()]].concat());
                }
            }
        }
    }
    let mut g = Graph::new();
    for (me, text) in files {
        if tests.iter().any(|t| me.starts_with(t)) {
            continue;
        }
        for p in paths(&code(text)) {
            let mut r: Module = me.clone();
            let mut rest = &p[..];
            match p[0].as_str() {
                "crate" => {
                    r.clear();
                    rest = &p[1..];
                }
                "self" => rest = &p[1..],
                _ => {
                    while rest.first().is_some_and(|s| s == "super") {
                        r.pop();
                        rest = &rest[1..];
                    }
                }
            }
            r.extend(rest.iter().cloned());
            let target = (1..=r.len())
                .rev()
                .map(|k| r[..k].to_vec())
                .find(|t| mods.contains(t));
            if let Some(t) = target.filter(|t| !me.starts_with(t)) {
                g.entry(me.clone()).or_default().insert(t);
            }
        }
    }
    g
}

/// The module sets that use each other (strongly connected components of
/// more than one module), each sorted.
fn circles(g: &Graph) -> Vec<Vec<String>> {
    let nodes: BTreeSet<&Module> = g.keys().chain(g.values().flatten()).collect();
    let reach = |from: &Module| {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from];
        while let Some(n) = todo.pop() {
            for t in g.get(n).into_iter().flatten() {
                if seen.insert(t) {
                    todo.push(t);
                }
            }
        }
        seen
    };
    let reachable: BTreeMap<&Module, BTreeSet<&Module>> =
        nodes.iter().map(|&n| (n, reach(n))).collect();
    let mut done = BTreeSet::new();
    let mut out = Vec::new();
    for &n in &nodes {
        if done.contains(n) || !reachable[n].contains(n) {
            continue;
        }
        let comp: Vec<String> = nodes
            .iter()
            .filter(|&&m| reachable[n].contains(m) && reachable[m].contains(n))
            .map(|m| {
                done.insert(*m);
                m.join("::")
            })
            .collect();
        out.push(comp);
    }
    out
}

/// What breaks the layering of a crate whose sources are `files` and whose
/// floors (top-level modules), ground first, are `order`: module circles,
/// arrows up a floor (`a → b` as `floor a → floor b: module → module`),
/// floors missing from the order.
fn violations(files: &[(Module, String)], order: &[String]) -> Vec<String> {
    let g = graph(files);
    let mut out: Vec<String> = circles(&g)
        .into_iter()
        .map(|c| format!("circle: {}", c.join(", ")))
        .collect();
    let rank = |m: &Module| order.iter().position(|f| m.first() == Some(f));
    for (a, ts) in &g {
        for b in ts {
            match (rank(a), rank(b)) {
                (Some(x), Some(y)) if y > x => {
                    out.push(format!(
                        "arrow up: {} -> {}: {} -> {}",
                        a[0],
                        b[0],
                        a.join("::"),
                        b.join("::")
                    ));
                }
                (Some(_), Some(_)) => {}
                _ => out.push(format!(
                    "floor not in the order: {} -> {}",
                    a.join("::"),
                    b.join("::")
                )),
            }
        }
    }
    out
}

/// The floors of `src/`: the first path segment of each module the stage
/// table of `src/lib.rs` names, in table order (ground floor first).
fn firmware_floors(lib: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let rows = lib
        .lines()
        .skip_while(|l| !l.starts_with("//! | part | stage | module |"))
        .skip(2)
        .take_while(|l| l.starts_with("//! |"));
    for row in rows {
        let module = row.split('|').nth(3).expect("a row of four cells");
        for m in module.split('`').skip(1).step_by(2) {
            let floor = m.split("::").next().expect("a path").to_owned();
            if !out.contains(&floor) {
                out.push(floor);
            }
        }
    }
    out
}

/// The floors of `host-tests/src/`, ground first: the code spans of the
/// paragraph of its `lib.rs` that starts `//! Floors, top first:`, reversed.
fn harness_floors(lib: &str) -> Vec<String> {
    let line = lib
        .lines()
        .skip_while(|l| !l.starts_with("//! Floors, top first:"))
        .take_while(|l| l.starts_with("//! "))
        .collect::<String>();
    let mut out: Vec<String> = line
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_owned)
        .collect();
    out.reverse();
    out
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn firmware_modules_use_only_their_floor_and_below() {
    let lib = fs::read_to_string(root().join("src/lib.rs")).expect("src/lib.rs");
    let order = firmware_floors(&lib);
    assert!(
        order.len() > 8,
        "stage table not found in src/lib.rs: {order:?}"
    );
    let v = violations(&sources(&root().join("src")), &order);
    assert!(
        v.is_empty(),
        "src/ against the floors {order:?}:\n{}",
        v.join("\n")
    );
}

#[test]
fn harness_modules_use_only_their_floor_and_below() {
    let dir = root().join("host-tests/src");
    let lib = fs::read_to_string(dir.join("lib.rs")).expect("host-tests/src/lib.rs");
    let order = harness_floors(&lib);
    assert!(
        order.len() > 5,
        "floor line not found in host-tests/src/lib.rs: {order:?}"
    );
    // The binaries sit above every floor of the library.
    let files: Vec<_> = sources(&dir)
        .into_iter()
        .filter(|(m, _)| m.first().is_none_or(|f| f != "bin"))
        .collect();
    let v = violations(&files, &order);
    assert!(
        v.is_empty(),
        "host-tests/src/ against the floors {order:?}:\n{}",
        v.join("\n")
    );
}

/// The check itself: an arrow up a floor, a circle, a floor missing from
/// the order, each through the path forms the crates use.
#[test]
fn layering_check_finds_what_breaks_it() {
    let m = |s: &str| -> Module { s.split("::").map(str::to_owned).collect() };
    let files = vec![
        (m("units"), "pub struct A;\n// use crate::lod::B;\n".to_owned()),
        (m("lod"), "use crate::{\n    units::A,\n    texture::{mip::T, Other},\n};\n".to_owned()),
        (m("texture"), "pub mod mip;\npub struct Other;\n".to_owned()),
        (m("texture::mip"), "pub struct T;\nfn f() -> super::super::lod::L { todo!() }\n".to_owned()),
        (m("texture::kernel"), "#[cfg(test)]\nmod tests;\n#[cfg(all(test, feature = \"x\"))]\nmod more {\n    use crate::geo::G;\n}\n".to_owned()),
        (m("texture::kernel::tests"), "use crate::geo::G;\n".to_owned()),
        (m("geo"), "use crate::texture::mip::T;\n".to_owned()),
    ];
    let order: Vec<String> = ["units", "lod", "texture"].map(str::to_owned).into();
    let v = violations(&files, &order);
    assert_eq!(
        v,
        [
            "circle: lod, texture::mip",
            "floor not in the order: geo -> texture::mip",
            "arrow up: lod -> texture: lod -> texture",
            "arrow up: lod -> texture: lod -> texture::mip",
        ],
        "{v:#?}"
    );
}
