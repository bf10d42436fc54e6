//! `uvflat sphere`: a closed genus-0 mesh mapped onto the unit sphere.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::errors::{check_outputs, usage, Failure};
use crate::files::load_mesh;
use clap::ValueEnum;
use uvflat_core::methods::sphere::{spherical_map, SphereMethod, SphereOptions};

#[derive(clap::Args)]
pub(crate) struct SphereArgs {
    /// Input mesh (OBJ), closed genus 0.
    pub(crate) input: PathBuf,
    /// Output OBJ with unit-sphere vertex positions.
    #[arg(short = 'o', long = "output")]
    pub(crate) output: PathBuf,
    /// Spherical parameterization method.
    #[arg(long, value_enum, default_value_t = SphereMethodName::TutteGnomonic)]
    pub(crate) method: SphereMethodName,
    /// Relaxation sweeps (Gauss–Seidel iterations, guarded relaxation of tutte-gnomonic; the
    /// other methods have none); default 100.
    #[arg(long)]
    pub(crate) sweeps: Option<usize>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum SphereMethodName {
    /// Tutte embedding minus a vertex star, gnomonic lift, flip-guarded relaxation (never flips).
    TutteGnomonic,
    /// Projected Gauss–Seidel barycentric iteration (course notes §6.1; may flip).
    GaussSeidel,
    /// Haker et al. 2000: harmonic map minus one triangle, inverse stereographic (may flip).
    Stereographic,
    /// Kharevych et al. 2006: conformal circle pattern minus one vertex star, balanced,
    /// inverse stereographic (may flip).
    CirclePatterns,
}

pub(crate) fn sphere(args: &SphereArgs) -> Result<(), Failure> {
    check_outputs(&[("-o", Some(&args.output))])?;
    let relaxed = matches!(args.method, SphereMethodName::TutteGnomonic | SphereMethodName::GaussSeidel);
    if args.sweeps.is_some() && !relaxed {
        return Err(usage("--sweeps applies to --method tutte-gnomonic and gauss-seidel only"));
    }
    let (obj, mesh) = load_mesh(&args.input)?;
    let method = match args.method {
        SphereMethodName::TutteGnomonic => SphereMethod::TutteGnomonic,
        SphereMethodName::GaussSeidel => SphereMethod::GaussSeidel,
        SphereMethodName::Stereographic => SphereMethod::Stereographic,
        SphereMethodName::CirclePatterns => SphereMethod::CirclePatterns,
    };
    let start = Instant::now();
    let map = spherical_map(&mesh, &SphereOptions { method, sweeps: args.sweeps.unwrap_or(100) })?;
    let seconds = start.elapsed().as_secs_f64();
    write_sphere_obj(&args.output, &map.positions, &obj.triangles)?;
    let name = SphereMethodName::value_variants()
        .iter()
        .find(|m| **m == args.method)
        .and_then(|m| m.to_possible_value())
        .map_or("?".to_string(), |v| v.get_name().to_string());
    if args.json {
        println!(
            "{}",
            serde_json::json!({"method": name, "seconds": seconds, "vertices": mesh.vertex_count(), "triangles": mesh.triangle_count(), "flipped": map.flipped, "output": args.output.display().to_string()})
        );
    } else {
        println!(
            "{name}: {} vertices, {} triangles, {:.3} s, {} flipped -> {}",
            mesh.vertex_count(),
            mesh.triangle_count(),
            seconds,
            map.flipped,
            args.output.display()
        );
    }
    Ok(())
}

/// Writes `v` lines (NaN positions of unreferenced vertices as `v 0 0 0`) and `f` lines.
pub(crate) fn write_sphere_obj(path: &Path, positions: &[[f64; 3]], triangles: &[u32]) -> Result<(), Failure> {
    use std::io::Write;
    let fail = |e: std::io::Error| Failure { message: format!("cannot write {}: {e}", path.display()), usage: false };
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(fail)?);
    for p in positions {
        let p = if p.iter().all(|x| x.is_finite()) { *p } else { [0.0; 3] };
        writeln!(out, "v {} {} {}", p[0], p[1], p[2]).map_err(fail)?;
    }
    for t in triangles.chunks_exact(3) {
        writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).map_err(fail)?;
    }
    out.flush().map_err(fail)
}
