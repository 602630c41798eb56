//! `include/raymip.h` is exactly what cbindgen (as a library, so the test
//! command needs no `cargo install cbindgen`) generates from `src/ffi/mod.rs`
//! and the files of the two core enums it exports as they are,
//! `src/texture/mode.rs` (`Mode`, as `RmMode`) and
//! `src/texture/storage/format.rs` (`TexelFormat`, as `RmFormat`), with
//! `cbindgen.toml`, with the rustdoc link brackets taken out of the comments (a link to `rm_sample` reads `rm_sample` in C, not
//! ``[`rm_sample`]``). `RAYMIP_WRITE_HEADER=1` rewrites the header instead
//! (`scripts/c-abi --write`).

use std::path::Path;

#[test]
fn header_is_up_to_date() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("ffi/ lives in the repository root");
    let config =
        cbindgen::Config::from_file(root.join("cbindgen.toml")).expect("cbindgen.toml parses");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(root.join("src/ffi/mod.rs"))
        .with_src(root.join("src/texture/mode.rs"))
        .with_src(root.join("src/texture/storage/format.rs"))
        .generate()
        .expect("cbindgen parses src/ffi/mod.rs and the two core enums' files");
    let mut raw = Vec::new();
    bindings.write(&mut raw);
    let generated = without_link_brackets(&String::from_utf8(raw).expect("cbindgen writes UTF-8"));
    let path = root.join("include/raymip.h");
    if std::env::var_os("RAYMIP_WRITE_HEADER").is_some_and(|v| v == "1") {
        std::fs::write(&path, &generated).expect("include/raymip.h is writable");
        return;
    }
    let current = std::fs::read_to_string(&path).expect("include/raymip.h exists");
    assert!(
        current == generated,
        "include/raymip.h is stale: run scripts/c-abi --write (or RAYMIP_WRITE_HEADER=1 cargo test -p raymip-ffi --test header)\n--- generated ---\n{}",
        generated
    );
}

/// `text` with every rustdoc intra-doc link "[`name`]" written "`name`".
fn without_link_brackets(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find("[`") {
        let tail = &rest[i + 1..];
        match tail[1..].find('`').map(|j| j + 2) {
            Some(end) if tail[end..].starts_with(']') && !tail[1..end - 1].contains('\n') => {
                out.push_str(&rest[..i]);
                out.push_str(&tail[..end]);
                rest = &tail[end + 1..];
            }
            _ => {
                out.push_str(&rest[..i + 2]);
                rest = &rest[i + 2..];
            }
        }
    }
    out.push_str(rest);
    out
}
