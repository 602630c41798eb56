//! The crate's documentation against the code it describes: the module
//! table of `src/lib.rs` lists every public module, and every error bound
//! the docs and rustdoc quote by its constant's name has that constant's
//! value.

use std::fs;
use std::path::{Path, PathBuf};

/// The checkout's root (this crate's manifest directory).
fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The names `X` of the `pub mod X;` declarations in `text`, at any indent
/// (a `#[cfg]` line above one does not matter: the table lists
/// feature-gated modules too).
fn pub_mods(text: &str) -> Vec<String> {
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod ")?.strip_suffix(';'))
        .map(str::to_owned)
        .collect()
}

/// The module paths the "module" column of `src/lib.rs`'s stage table
/// names (code spans, linked or not), e.g. `setup::camera`.
fn table_modules(lib: &str) -> Vec<String> {
    let mut rows = lib
        .lines()
        .skip_while(|l| !l.starts_with("//! | part | stage | module |"))
        .skip(2)
        .take_while(|l| l.starts_with("//! |"));
    let mut out = Vec::new();
    for row in rows.by_ref() {
        let cells: Vec<&str> = row.split('|').collect();
        // "//! ", part, stage, module, per hit, "".
        let module = cells.get(3).expect("a row of four cells");
        out.extend(module.split('`').skip(1).step_by(2).map(str::to_owned));
    }
    out
}

/// A module is listed whole (its own path, or a prefix of its submodules'
/// paths), and when the table lists any of its submodules it lists all of
/// them: a module added to `src/` without a row fails here.
#[test]
fn lib_module_table_lists_every_public_module() {
    let lib = read(&root().join("src/lib.rs"));
    let table = table_modules(&lib);
    assert!(table.len() > 10, "stage table not found in src/lib.rs");
    let mut missing = Vec::new();
    for m in pub_mods(&lib) {
        let prefix = format!("{m}::");
        if !table.iter().any(|t| *t == m || t.starts_with(&prefix)) {
            missing.push(m.clone());
        }
        let dir = root().join("src").join(&m).join("mod.rs");
        if dir.exists() && table.iter().any(|t| t.starts_with(&prefix)) {
            for sub in pub_mods(&read(&dir)) {
                let path = format!("{m}::{sub}");
                if !table.contains(&path) {
                    missing.push(path);
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "modules missing from src/lib.rs's stage table: {missing:?}"
    );
}

/// Every error bound a page may quote by name, with its value.
fn bounds() -> Vec<(&'static str, f64)> {
    use raymip::texture::kernel::{accurate, fast, srgb};
    #[allow(unused_mut)]
    let mut b = vec![
        ("LOD_MAX_ERROR", raymip::lod::LOD_MAX_ERROR),
        ("TABLE_MAX_ERROR", raymip::setup::table::TABLE_MAX_ERROR),
        ("LOD_PARAM_MAX_ERROR", raymip::geomlod::LOD_PARAM_MAX_ERROR),
        ("BILERP_MAX_ERROR_LSB", accurate::BILERP_MAX_ERROR_LSB),
        ("FAST_MAX_ERROR_LSB", fast::FAST_MAX_ERROR_LSB),
        ("FAST_LEVEL_MAX_ERROR_LSB", fast::FAST_LEVEL_MAX_ERROR_LSB),
        ("SRGB_MAX_ERROR_LSB", srgb::SRGB_MAX_ERROR_LSB),
        ("SRGB_LINEAR_MAX_ERROR_LSB", srgb::SRGB_LINEAR_MAX_ERROR_LSB),
        (
            "SRGB_ENCODE_MAX_ERROR_LSB",
            raymip::texture::storage::srgb::SRGB_ENCODE_MAX_ERROR_LSB,
        ),
        (
            "MEAN_ERROR_TEXEL_LSB",
            raymip::texture::sampler::stochastic::MEAN_ERROR_TEXEL_LSB,
        ),
    ];
    #[cfg(feature = "raydiff")]
    b.extend([
        ("PRIMARY_ERROR", raymip::path::raydiff::PRIMARY_ERROR),
        ("TRANSFER_ERROR", raymip::path::raydiff::TRANSFER_ERROR),
        ("REFLECT_ERROR", raymip::path::raydiff::REFLECT_ERROR),
        ("REFRACT_ERROR", raymip::path::raydiff::REFRACT_ERROR),
        ("FOOTPRINT_ERROR", raymip::lod::raydiff::FOOTPRINT_ERROR),
        (
            "LOD_ROUNDING_ERROR",
            raymip::lod::raydiff::LOD_ROUNDING_ERROR,
        ),
        (
            "RAYDIFF_LOD_MAX_ERROR",
            raymip::lod::raydiff::RAYDIFF_LOD_MAX_ERROR,
        ),
    ]);
    #[cfg(feature = "envmap")]
    b.extend([
        (
            "ENVMAP_LOD_MAX_ERROR",
            raymip::lod::envmap::ENVMAP_LOD_MAX_ERROR,
        ),
        (
            "ENVMAP_UV_MAX_ERROR",
            raymip::lod::envmap::ENVMAP_UV_MAX_ERROR,
        ),
    ]);
    b
}

/// Bounds of features this build leaves out: quoted, but not checked here.
const FEATURE_GATED: &[&str] = &[
    "PRIMARY_ERROR",
    "TRANSFER_ERROR",
    "REFLECT_ERROR",
    "REFRACT_ERROR",
    "FOOTPRINT_ERROR",
    "LOD_ROUNDING_ERROR",
    "RAYDIFF_LOD_MAX_ERROR",
    "ENVMAP_LOD_MAX_ERROR",
    "ENVMAP_UV_MAX_ERROR",
];

/// The value of a quoted bound at the start of `s`: terms joined by
/// ` + `, each a decimal (`0.5625`) or a power of two (`2⁻⁸`); `None`
/// when `s` does not start with one.
fn quoted_value(s: &str) -> Option<f64> {
    let mut total = 0.0;
    let mut rest = s;
    loop {
        let (term, tail) = quoted_term(rest)?;
        total += term;
        match tail.strip_prefix(" + ") {
            Some(t) if quoted_term(t).is_some() => rest = t,
            _ => return Some(total),
        }
    }
}

fn quoted_term(s: &str) -> Option<(f64, &str)> {
    if let Some(exp) = s.strip_prefix("2⁻") {
        let digits: String = exp
            .chars()
            .take_while(|c| "⁰¹²³⁴⁵⁶⁷⁸⁹".contains(*c))
            .collect();
        let n = digits.chars().fold(0i32, |n, c| {
            n * 10 + "⁰¹²³⁴⁵⁶⁷⁸⁹".chars().position(|d| d == c).unwrap_or(0) as i32
        });
        return (!digits.is_empty()).then(|| (2f64.powi(-n), &exp[digits.len()..]));
    }
    let end = s
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(s.len());
    let number = s[..end].trim_end_matches('.');
    number.parse().ok().map(|v| (v, &s[number.len()..]))
}

/// The pages that quote bounds: rustdoc and comments in `src/`, the
/// README and `docs/`.
fn pages() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let p = e.expect("directory entry").path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs" || x == "md") {
                out.push(p);
            }
        }
    }
    let mut out = vec![root().join("README.md")];
    walk(&root().join("src"), &mut out);
    walk(&root().join("docs"), &mut out);
    out
}

/// Every `NAME = value` (also `` `NAME` = ``, `` [`path::NAME`] = ``) whose
/// NAME ends in `ERROR` or `ERROR_LSB`: NAME is a bound of [`bounds`] and the
/// value is its constant's. A bound changed in the code, or a new one
/// quoted without an entry above, fails here.
#[test]
fn bounds_quoted_by_name_equal_their_constants() {
    let bounds = bounds();
    let mut quotes = 0;
    let mut wrong = Vec::new();
    for page in pages() {
        let text = read(&page);
        for (i, _) in text.match_indices(" = ") {
            let before = text[..i].trim_end_matches(['`', ']']);
            let name_start = before
                .char_indices()
                .rev()
                .find(|&(_, c)| !(c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_'))
                .map_or(0, |(k, c)| k + c.len_utf8());
            let name = &before[name_start..];
            if !(name.ends_with("ERROR") || name.ends_with("ERROR_LSB")) {
                continue;
            }
            let Some(value) = quoted_value(&text[i + 3..]) else {
                // A definition (`pub const X: f64 = 1.0 / 256.0`) or code.
                continue;
            };
            let page = page.strip_prefix(root()).unwrap_or(&page).display();
            match bounds.iter().find(|(n, _)| *n == name) {
                Some(&(_, want)) => {
                    quotes += 1;
                    if value != want {
                        wrong.push(format!("{page}: {name} = {value}, the constant is {want}"));
                    }
                }
                None if FEATURE_GATED.contains(&name) => {}
                None => wrong.push(format!(
                    "{page}: {name} quoted, not in this test's bounds()"
                )),
            }
        }
    }
    assert!(quotes >= 5, "only {quotes} bounds quoted by name found");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The C ABI's tier docs (src/ffi/status.rs, hence include/raymip.h) quote
/// the tiers' bounds in words: ACCURATE's linear and sRGB bounds, FAST's
/// linear bound.
#[test]
fn c_abi_tier_docs_quote_the_tier_bounds() {
    use raymip::texture::kernel::{accurate, fast, srgb};
    let text = read(&root().join("src/ffi/status.rs"));
    let doc = |from: &str, to: &str| -> String {
        let a = text
            .find(from)
            .unwrap_or_else(|| panic!("{from} not found"));
        let b = a + text[a..]
            .find(to)
            .unwrap_or_else(|| panic!("{to} not found"));
        text[a..b]
            .split_whitespace()
            .filter(|w| *w != "///")
            .collect::<Vec<_>>()
            .join(" ")
    };
    let accurate_doc = doc("/// ACCURATE", "Accurate = 0");
    let fast_doc = doc("/// FAST", "Fast = 1");
    for (doc, quote) in [
        (
            &accurate_doc,
            format!("linear filtering ≤ {} LSB", accurate::BILERP_MAX_ERROR_LSB),
        ),
        (
            &accurate_doc,
            format!("sRGB re-encoded ≤ {} LSB", srgb::SRGB_MAX_ERROR_LSB),
        ),
        (
            &fast_doc,
            format!("linear filtering ≤ {} LSB", fast::FAST_MAX_ERROR_LSB),
        ),
    ] {
        assert!(doc.contains(&quote), "{quote:?} not in {doc:?}");
    }
}
