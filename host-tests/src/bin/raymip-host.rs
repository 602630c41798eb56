//! `raymip-host`: command-line front end of the host harness (a thin
//! dispatcher; each subcommand's logic lives in the library): sample the
//! firmware texture unit, render scenes through the firmware texture path,
//! compare against float references and ground truth, reproduce Table I.

use std::io::{self, BufWriter};
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use raymip_host::cli::instances::{cmd_bench, cmd_render as cmd_render_instances};
use raymip_host::cli::memory::{MemoryArgs, cmd_memory};
use raymip_host::cli::sample::{self, SampleArgs};
use raymip_host::cli::stress::cmd_stress;
use raymip_host::cli::tradeoff::{Args as TradeoffArgs, cmd_tradeoff};
use raymip_host::cli::{cmd_compare, cmd_render, cmd_table1, parse_size};
use raymip_host::render::instances::{Config, GeomLodMode, MaskPolicy};
use raymip_host::render::{Arithmetic, Method, Options};
use raymip_host::scene::default_bart_dir;
use raymip_host::scene::instances::{DEFAULT_SIZE, View};

#[derive(Parser, Debug)]
#[command(
    name = "raymip-host",
    version,
    about = "Host harness for the raymip texture unit"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Texture filter of `render`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum FilterArg {
    /// Trilinear at the LOD method's level of detail.
    Trilinear,
    /// Anisotropic (trilinear probes along the footprint's major axis).
    Aniso,
}

#[derive(clap::Args, Debug)]
struct RenderArgs {
    /// `builtin:hall|mirrors|glass|instances` or a path to an `.aff` file.
    #[arg(long)]
    scene: String,
    /// Image size WxH (default: 800x480 for built-in scenes, the camera's for AFF).
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Animation time (AFF scenes).
    #[arg(long, default_value_t = 0.0)]
    time: f64,
    /// Maximum reflection/refraction bounces.
    #[arg(long, default_value_t = 10)]
    bounces: u8,
    /// Samples per pixel of the ground truth.
    #[arg(long, default_value_t = 256)]
    spp: u32,
    /// Output directory.
    #[arg(long)]
    out: PathBuf,
}

/// Options of `--scene builtin:instances` (stochastic geometric LOD).
#[derive(clap::Args, Debug)]
struct GeomArgs {
    /// Geometric LOD (builtin:instances): none, discrete or stochastic.
    #[arg(long, value_enum, default_value_t = GeomLodMode::Stochastic)]
    geom_lod: GeomLodMode,
    /// Transition interval t in [0, 1] of the stochastic mode.
    #[arg(long, default_value_t = 0.5)]
    transition: f64,
    /// LOD bias in levels.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    lod_bias: f64,
    /// Frames to accumulate (builtin:instances).
    #[arg(long, default_value_t = 16)]
    frames: u32,
    /// Camera view of builtin:instances.
    #[arg(long, value_enum, default_value_t = View::High)]
    view: View,
    /// Also render the exact blend (mean of the 8 single-bit ray masks) and
    /// report the RMS of the accumulation against it.
    #[arg(long)]
    reference: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Read `u,v,lod,mode` (or anisotropic `u,v,mode,dudx,dvdx,dudy,dvdy`)
    /// lines from stdin and print filtered `r,g,b,a` lines (firmware
    /// fixed-point path; sampler state, formats, sRGB and anisotropy by
    /// option). Modes: 0 trilinear, 1 bilinear + nearest level, 2 nearest
    /// texel + nearest level, 3 nearest texel + linear between levels.
    Sample(SampleArgs),
    /// Render one image: image.png, levels.png (mip level per pixel), report.json/md.
    Render {
        #[command(flatten)]
        args: RenderArgs,
        /// Texture LOD method.
        #[arg(long, value_enum, default_value_t = Method::Table)]
        method: Method,
        /// Arithmetic of the lod and the texture unit: fixed point
        /// (firmware) or the f64 reference (`--precision` is an alias).
        #[arg(long, value_enum, alias = "precision", default_value_t = Arithmetic::Fixed)]
        arithmetic: Arithmetic,
        /// Texture filter: trilinear at the method's lod, or anisotropic
        /// over the pixel footprint from ray differentials (pbrt-style
        /// axes; the method then only sets the level histogram).
        #[arg(long, value_enum, default_value_t = FilterArg::Trilinear)]
        filter: FilterArg,
        /// Maximum anisotropy (probes) for `--filter aniso`, 1..=16.
        #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u8).range(1..=16))]
        max_aniso: u8,
        #[command(flatten)]
        geom: GeomArgs,
    },
    /// Geometric-LOD benchmark of `builtin:instances`: every view with no
    /// LOD, discrete and stochastic LOD (t = 0, 0.25, 0.5, 1); writes
    /// bench.md and bench.json.
    GeomlodBench {
        /// Image size WxH.
        #[arg(long, value_parser = parse_size, default_value = "400x240")]
        size: (u32, u32),
        /// Frames per configuration (the best time is kept).
        #[arg(long, default_value_t = 3)]
        repeats: u32,
        /// Maximum reflection bounces.
        #[arg(long, default_value_t = 2)]
        bounces: u8,
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// Also write the table between `<!-- geomlod-bench:begin/end -->`
        /// markers in these files (docs/geometric-lod.md, BENCHMARKS.md).
        #[arg(long)]
        write: Vec<PathBuf>,
    },
    /// PSNR / max difference: fixed vs float per method and every method vs ground truth.
    Compare {
        #[command(flatten)]
        args: RenderArgs,
        /// Methods to compare (truth is always rendered).
        #[arg(
            long,
            value_enum,
            value_delimiter = ',',
            default_value = "table,cone,raydiff,gbuffer,mip0"
        )]
        methods: Vec<Method>,
    },
    /// Run time against error: every LOD method and precision, every
    /// filter (incl. stochastic) and whole frames, timed on the host and
    /// compared with f64 references and ground truth; writes
    /// tradeoff.json/.md and Pareto charts (PNG, SVG).
    Tradeoff {
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// Small sizes for CI (a few seconds; frames of builtin:hall only).
        #[arg(long)]
        quick: bool,
        /// Frame-stage scenes (`builtin:NAME`, an .aff file or a BART
        /// folder), comma-separated; default builtin:hall, builtin:mirrors
        /// and the BART kitchen and robots when found.
        #[arg(long, value_delimiter = ',')]
        scene: Vec<String>,
        /// BART folder (default ../shared/scenes/bart).
        #[arg(long)]
        bart: Option<PathBuf>,
        /// Frame size WxH (default 320x192, 40x24 with --quick).
        #[arg(long, value_parser = parse_size)]
        size: Option<(u32, u32)>,
        /// Also write the charts into ROOT/docs/tradeoff/ and the
        /// `tradeoff` blocks of ROOT/BENCHMARKS.md and ROOT/docs/tradeoff.md.
        #[arg(long, value_name = "ROOT")]
        publish: Option<PathBuf>,
    },
    /// Every class of bad input (NaN, ±inf, subnormals, ±0, 1e±30,
    /// degenerate triangles, saturating path lengths, stack overflow,
    /// extreme texture sizes, short buffers, bad C ABI arguments) at every
    /// API edge: a table of what came back; exits non-zero when a case
    /// panicked or did not return its documented result.
    Stress {
        /// Also write the totals between `<!-- stress:begin/end -->`
        /// markers of this file (docs/reliability.md).
        #[arg(long)]
        write_readme: Option<PathBuf>,
    },
    /// The memory a firmware needs for a scene (a scene file, or numbers:
    /// --triangles, --texture, --path-range) on a target with a feature set:
    /// Pb table, pyramids full and trimmed, ray stack, texel caches,
    /// samplers, code.
    Memory(MemoryArgs),
    /// Table I: mip-level shares and texel-cache hit rates (mip mapping off/on) per BART scene.
    Table1 {
        /// Folder with one sub-folder per scene (default ../shared/scenes/bart).
        #[arg(long)]
        scenes: Option<PathBuf>,
        /// Image size WxH.
        #[arg(long, value_parser = parse_size, default_value = "800x480")]
        size: (u32, u32),
        /// Maximum reflection/refraction bounces.
        #[arg(long, default_value_t = 10)]
        bounces: u8,
        /// Animation time.
        #[arg(long, default_value_t = 0.0)]
        time: f64,
        /// Also measure the built-in scenes.
        #[arg(long)]
        builtin: bool,
        /// Write table1.md and table1.json here.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Measure the other scenes when one fails to load (it is named on
        /// stderr); without it a scene that cannot be loaded is an error.
        #[arg(long)]
        skip_unloadable: bool,
    },
}

fn options(a: &RenderArgs, method: Method, arithmetic: Arithmetic) -> Options {
    Options {
        method,
        arithmetic,
        size: a.size,
        bounces: a.bounces,
        spp: a.spp,
        record_blocks: false,
        progress: true,
        aniso: None,
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let r: Result<(), Box<dyn std::error::Error>> = match &cli.command {
        Command::Sample(args) => {
            let out = BufWriter::new(io::stdout().lock());
            sample::run(args, io::stdin().lock(), out)
                .map(|_| ())
                .map_err(Into::into)
        }
        Command::Render { args, geom, .. } if args.scene == "builtin:instances" => {
            let cfg = Config {
                mode: geom.geom_lod,
                transition: geom.transition,
                bias: geom.lod_bias,
                view: geom.view,
                size: args.size.unwrap_or(DEFAULT_SIZE),
                frames: geom.frames.max(1),
                bounces: args.bounces,
                policy: MaskPolicy::PerPath,
                serial: false,
            };
            cmd_render_instances(&cfg, geom.reference, &args.out).map_err(Into::into)
        }
        Command::Memory(args) => cmd_memory(args).map_err(Into::into),
        Command::Stress { write_readme } => cmd_stress(write_readme.as_deref()).map_err(Into::into),
        Command::GeomlodBench {
            size,
            repeats,
            bounces,
            out,
            write,
        } => cmd_bench(*size, *repeats, *bounces, out, write).map_err(Into::into),
        Command::Render {
            args,
            method,
            arithmetic,
            filter,
            max_aniso,
            ..
        } => cmd_render(
            &args.scene,
            args.time,
            &Options {
                aniso: (*filter == FilterArg::Aniso).then_some(*max_aniso),
                ..options(args, *method, *arithmetic)
            },
            &args.out,
        )
        .map_err(Into::into),
        Command::Compare { args, methods } => cmd_compare(
            &args.scene,
            args.time,
            &options(args, Method::Table, Arithmetic::Fixed),
            methods,
            &args.out,
        )
        .map_err(Into::into),
        Command::Tradeoff {
            out,
            quick,
            scene,
            bart,
            size,
            publish,
        } => cmd_tradeoff(&TradeoffArgs {
            out: out.clone(),
            quick: *quick,
            scenes: scene.clone(),
            bart: bart.clone().unwrap_or_else(default_bart_dir),
            size: *size,
            publish: publish.clone(),
        })
        .map(|_| ())
        .map_err(Into::into),
        Command::Table1 {
            scenes,
            size,
            bounces,
            time,
            builtin,
            out,
            skip_unloadable,
        } => cmd_table1(
            scenes.as_deref(),
            *size,
            *bounces,
            *time,
            *builtin,
            out.as_deref(),
            *skip_unloadable,
        )
        .map_err(Into::into),
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
