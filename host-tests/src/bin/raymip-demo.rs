//! Host side of the bare-metal demos.
//!
//! * `raymip-demo gen-data [--check]`: writes `demo/scene/src/data.rs` (the
//!   camera's pixel spread, the Pb table and the textures as `static` data,
//!   computed on the host with floats at set-up) and the texture pyramids it
//!   embeds (`tex0.bin`, `tex1.bin`); `--check` only compares and fails when
//!   a file is stale.
//! * `raymip-demo render [--ppm FILE]`: renders the demo tile with the same
//!   fixed-point code the firmware runs and prints the checksum and counter
//!   lines the QEMU demos print (`scripts/test-all` compares them).
//! * `raymip-demo parity`: prints the GPU-style sampler's parity line (the
//!   firmware `parity` binary prints the same on both targets).
//! * `raymip-demo pow2-check`: prints the power-of-two pyramid check's
//!   line (`raymip_demo_scene::pow2_check`; the firmware `check-pow2`
//!   binary prints the same on the soft cores).
//! * `raymip-demo pcpi-vectors FILE`: writes the texture co-processor's
//!   reference vectors (`raymip_host::cli::pcpi_vectors`) for the
//!   Verilator testbench of `demo/softcore/pcpi_tex.v`.

use std::path::PathBuf;
use std::process::ExitCode;

use raymip_host::cli::demo_data::{DATA_DIR, generate_data, stale_files};

fn usage() -> ExitCode {
    eprintln!(
        "usage: raymip-demo gen-data [--check] | render [--ppm FILE] | parity | pow2-check | pcpi-vectors FILE"
    );
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    match args.first().map(String::as_str) {
        Some("gen-data") => {
            let check = args.get(1).map(String::as_str) == Some("--check");
            let files = match generate_data() {
                Ok(f) => f,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::FAILURE;
                }
            };
            if check {
                let stale = stale_files(&root, &files);
                for path in &stale {
                    eprintln!(
                        "error: {} is stale: run `cargo run -p raymip-host --bin raymip-demo -- gen-data`",
                        path.display()
                    );
                }
                if !stale.is_empty() {
                    return ExitCode::FAILURE;
                }
                println!("{} is up to date", root.join(DATA_DIR).display());
                return ExitCode::SUCCESS;
            }
            for f in &files {
                let path = root.join(DATA_DIR).join(&f.name);
                if let Err(e) = std::fs::write(&path, &f.bytes) {
                    eprintln!("error: {}: {e}", path.display());
                    return ExitCode::FAILURE;
                }
                println!("wrote {}", path.display());
            }
            ExitCode::SUCCESS
        }
        Some("pcpi-vectors") => {
            let Some(path) = args.get(1) else {
                return usage();
            };
            let v = raymip_host::cli::pcpi_vectors::vectors();
            if let Err(e) = std::fs::write(path, &v) {
                eprintln!("error: {path}: {e}");
                return ExitCode::FAILURE;
            }
            println!(
                "pcpi-vectors: {} vectors written to {path}",
                v.lines().count()
            );
            ExitCode::SUCCESS
        }
        Some("render") => {
            let ppm = match (args.get(1).map(String::as_str), args.get(2)) {
                (Some("--ppm"), Some(p)) => Some(PathBuf::from(p)),
                (None, _) => None,
                _ => return usage(),
            };
            let Some(mut r) = raymip_demo_scene::Renderer::new() else {
                eprintln!("error: demo data invalid (pixel spread)");
                return ExitCode::FAILURE;
            };
            let mut h = raymip_demo_scene::Fnv1a::default();
            let mut img = raymip_host::scene::ppm::RgbImage {
                width: raymip_demo_scene::WIDTH,
                height: raymip_demo_scene::HEIGHT,
                pixels: Vec::new(),
            };
            r.render(|_, _, rgb| {
                h.write(&rgb);
                img.pixels.push(rgb);
            });
            println!("{}", raymip_host::cli::demo_data::checksum_line(h.finish()));
            println!("counters: {}", r.counters);
            if let Some(p) = ppm
                && let Err(e) = raymip_host::scene::ppm::write_ppm(&p, &img)
            {
                eprintln!("error: {}: {e}", p.display());
                return ExitCode::FAILURE;
            }
            ExitCode::SUCCESS
        }
        Some("parity") => match raymip_demo_scene::parity::checksum() {
            Some(line) => {
                println!("{line}");
                ExitCode::SUCCESS
            }
            None => {
                eprintln!("error: parity set-up failed");
                ExitCode::FAILURE
            }
        },
        Some("pow2-check") => match raymip_demo_scene::pow2_check::run() {
            Some(c) => {
                println!("{c}");
                ExitCode::SUCCESS
            }
            None => {
                eprintln!("error: the demo texture is invalid");
                ExitCode::FAILURE
            }
        },
        _ => usage(),
    }
}
