//! `include/raymip.h` is exactly what cbindgen (as a library, so the test
//! command needs no `cargo install cbindgen`) generates from `src/ffi.rs`
//! with `cbindgen.toml`. `RAYMIP_WRITE_HEADER=1` rewrites the header instead
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
        .with_src(root.join("src/ffi.rs"))
        .generate()
        .expect("cbindgen parses src/ffi.rs");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let path = root.join("include/raymip.h");
    if std::env::var_os("RAYMIP_WRITE_HEADER").is_some_and(|v| v == "1") {
        std::fs::write(&path, &generated).expect("include/raymip.h is writable");
        return;
    }
    let current = std::fs::read(&path).expect("include/raymip.h exists");
    assert!(
        current == generated,
        "include/raymip.h is stale: run scripts/c-abi --write (or RAYMIP_WRITE_HEADER=1 cargo test -p raymip-ffi --test header)\n--- generated ---\n{}",
        String::from_utf8_lossy(&generated)
    );
}
