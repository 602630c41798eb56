//! The firmware's ray-differential lod against the f64 reference on random
//! camera chains ([`raymip_host::raydiff_chains`]), per case class: the
//! largest and the 99.9th-percentile error, how many chains exceed
//! `RAYDIFF_LOD_MAX_ERROR`, how many exceed their first-order bound, and
//! the largest amplification among the chains within the constant.
//!
//! ```sh
//! cargo run --release -p raymip-host --example raydiff_accuracy -- [CHAINS_PER_CLASS] [SEED]
//! ```

use raymip::lod::raydiff::RAYDIFF_LOD_MAX_ERROR;
use raymip_host::raydiff_chains::{CLASSES, Outcome, Raymip, run};
use raymip_host::reference::Rng;
use rayon::prelude::*;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: u64 = args.first().and_then(|a| a.parse().ok()).unwrap_or(100_000);
    let seed: u64 = args
        .get(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(0x9E37_79B9);
    println!(
        "| class | chains | max error | 99.9 % | over 2⁻⁷ | over bound | max amplification | smallest cos |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for class in CLASSES {
        let mut out: Vec<Outcome> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut rng = Rng(seed ^ (i.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1));
                run(&Raymip, class, &mut rng)
            })
            .collect();
        out.sort_by(|a, b| a.err.total_cmp(&b.err));
        let p999 = out[((out.len() as f64) * 0.999) as usize].err;
        let max = out.last().map_or(0.0, |o| o.err);
        let over = out.iter().filter(|o| o.err > RAYDIFF_LOD_MAX_ERROR).count();
        let over_bound = out.iter().filter(|o| o.err > o.bound).count();
        let amp = out.iter().map(|o| o.amp).fold(0.0f64, f64::max);
        let cos = out.iter().map(|o| o.cos_min).fold(1.0f64, f64::min);
        println!(
            "| {} | {n} | {max:.4} | {p999:.4} | {over} | {over_bound} | {amp:.3e} | {cos:.3e} |",
            class.name()
        );
        if let Some(w) = out.last() {
            eprintln!("{}: worst {w:?}", class.name());
        }
    }
}
