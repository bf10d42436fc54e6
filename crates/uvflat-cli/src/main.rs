//! `uvflat`: the command-line tool. Unwraps an OBJ into an OBJ with UVs (and optionally an SVG
//! picture of the layout), measures the distortion of an OBJ's UVs, lists the methods, and
//! reports a mesh's topology. Every failure prints the library's message and exits with
//! status 1 (2 for a command-line usage error); nothing panics on bad input.

mod atlas_output;
mod errors;
mod files;
mod info;
mod methods;
mod metrics;
mod named_method;
mod pgp;
mod quadcover;
mod sphere;
mod unwrap;
mod unwrap_args;

use std::path::PathBuf;
use std::process::ExitCode;

use crate::info::info;
use crate::methods::list_methods;
use crate::metrics::print_metrics;
use crate::pgp::{periodic, PgpArgs};
use crate::quadcover::{quad_cover, QuadCoverArgs};
use crate::sphere::{sphere, SphereArgs};
use crate::unwrap::unwrap;
use crate::unwrap_args::UnwrapArgs;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "uvflat", version, about = "Mesh parameterization (UV unwrapping)")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Computes UVs for IN.obj and writes OUT.obj (input vertices and faces, plus `vt` lines).
    Unwrap(UnwrapArgs),
    /// Distortion of the UVs stored in an OBJ file (`vt` lines).
    Metrics {
        input: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Lists the parameterization methods, one per line.
    Methods,
    /// Prints vertices, faces, components, boundary loops and genus of a mesh.
    Info {
        input: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Maps a closed genus-0 mesh onto the unit sphere and writes OUT.obj with the sphere
    /// positions as vertices (same faces).
    Sphere(SphereArgs),
    /// Periodic Global Parameterization (Ray et al. 2006) of a mesh of any genus, without
    /// cutting: writes OUT.obj with per-corner `vt` = (θ, φ)/2π, so a tiling texture repeats
    /// once per period along the principal curvature directions.
    Pgp(PgpArgs),
    /// QuadCover (Kälberer, Nieser & Polthier 2007) of a mesh of any genus: writes OUT.obj with
    /// per-corner `vt` = (u, v) in grid units, whose integer iso-lines close up over the whole
    /// surface (a texture that repeats once per unit shows a seamless grid).
    Quadcover(QuadCoverArgs),
}

/// `uvflat ... | head` closes stdout early; `println!` then panics with "failed printing to
/// stdout: Broken pipe". Like a C tool killed by SIGPIPE, exit quietly with status 141
/// (128 + SIGPIPE) instead of printing a panic.
fn exit_quietly_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info.payload().downcast_ref::<String>().map_or("", String::as_str);
        if message.contains("Broken pipe") {
            std::process::exit(141);
        }
        // println! panics when stdout cannot be written (a full disk, /dev/full): an error,
        // not a crash.
        if message.starts_with("failed printing to stdout") {
            eprintln!("uvflat: {message}");
            std::process::exit(1);
        }
        default(info);
    }));
}

fn main() -> ExitCode {
    exit_quietly_on_broken_pipe();
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Unwrap(args) => unwrap(&args),
        Command::Metrics { input, json } => print_metrics(&input, json),
        Command::Methods => {
            list_methods();
            Ok(())
        }
        Command::Info { input, json } => info(&input, json),
        Command::Sphere(args) => sphere(&args),
        Command::Pgp(args) => periodic(&args),
        Command::Quadcover(args) => quad_cover(&args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("uvflat: {}", f.message);
            ExitCode::from(if f.usage { 2 } else { 1 })
        }
    }
}
