//! `raymip-host`: command-line front end of the host harness. A thin
//! dispatcher: each subcommand's logic lives in the library.

use std::io::{self, BufWriter};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use raymip_host::sample::{self, SampleArgs};

/// Host harness for the raymip texture unit.
#[derive(Debug, Parser)]
#[command(name = "raymip-host", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Read `u,v,lod,mode` lines from stdin and print filtered `r,g,b,a`
    /// lines (firmware fixed-point path). Modes: 0 trilinear, 1 bilinear +
    /// nearest level, 2 nearest texel + nearest level, 3 nearest texel +
    /// linear between levels.
    Sample(SampleArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Sample(args) => {
            let out = BufWriter::new(io::stdout().lock());
            sample::run(args, io::stdin().lock(), out).map(|_| ())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
