//! Shared by the CGAL cross-check tests and the `vs_cgal` benchmark: compiles
//! `cgal/cgal_reference.cpp` (beside this crate's sources) against the system CGAL and Eigen headers,
//! runs it, and reads what it writes; lists the disk test meshes.
//!
//! The executable is cached under `<target>/cgal_reference/`, keyed by a hash of the
//! source and the compile command, because CGAL's templates take ~20 s to compile.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::compiler::{compiler, target_dir};
use crate::meshes;

/// The reference program's source, compiled into the test so the cache key follows it.
pub const SOURCE: &str = include_str!("../cgal/cgal_reference.cpp");
pub const SOURCE_PATH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/cgal/cgal_reference.cpp");

pub const EIGEN_INCLUDE: &str = "/usr/include/eigen3";
/// Headers whose absence means CGAL or Eigen is not installed.
const REQUIRED_HEADERS: [&str; 2] =
    ["/usr/include/CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h", "/usr/include/eigen3/Eigen/Sparse"];
pub const INSTALL_HINT: &str = "CGAL reference unavailable: apt-get install libcgal-dev libeigen3-dev";

/// The CGAL methods the reference program runs, with uvflat's counterpart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Discrete_conformal_map_parameterizer_3 ↔ `Weights::Conformal`.
    Dcp,
    /// Discrete_authalic_parameterizer_3 ↔ `Weights::Authalic`.
    Dap,
    /// Mean_value_coordinates_parameterizer_3 ↔ `Weights::MeanValue`.
    Mvc,
    /// Barycentric_mapping_parameterizer_3 ↔ `Weights::Uniform`.
    Tutte,
    /// LSCM_parameterizer_3 with two pinned vertices ↔ `natural_conformal_map`.
    Lscm,
}

impl Method {
    pub const ALL: [Method; 5] = [Method::Dcp, Method::Dap, Method::Mvc, Method::Tutte, Method::Lscm];

    /// The name on the reference program's command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::Dcp => "dcp",
            Method::Dap => "dap",
            Method::Mvc => "mvc",
            Method::Tutte => "tutte",
            Method::Lscm => "lscm",
        }
    }
}

/// What one reference run wrote.
#[derive(Debug, Clone)]
pub struct Reference {
    /// Wall time of CGAL's `parameterize()` call alone.
    pub seconds: f64,
    /// The two pinned vertices (LSCM only).
    pub pins: Option<(u32, u32)>,
    /// UV per vertex, in OBJ order.
    pub uv: Vec<[f64; 2]>,
}

/// Whether the CGAL and Eigen headers are installed.
pub fn headers_present() -> bool {
    REQUIRED_HEADERS.iter().all(|h| Path::new(h).exists())
}

/// If the headers are missing: under CI (`CI=true`) panics with the install hint,
/// otherwise prints it and returns false so the caller can skip.
pub fn require_headers_or_skip() -> bool {
    if headers_present() {
        return true;
    }
    if std::env::var("CI").map(|v| v == "true").unwrap_or(false) {
        panic!("{INSTALL_HINT}");
    }
    eprintln!("skipped: {INSTALL_HINT}");
    false
}

/// 64-bit FNV-1a: a stable hash for the cache key (std's hasher may change between releases).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

/// The compile command without the output and input paths.
fn compiler_command() -> Command {
    let mut command = compiler(true, "c++17");
    command.arg("-DNDEBUG").arg("-I").arg(EIGEN_INCLUDE);
    command
}

/// Path of the compiled reference program, compiling it first unless a build of the
/// same source with the same command is cached. CGAL is header-only here and the
/// program uses no exact kernel, so nothing beyond the C++ runtime is linked (no GMP/MPFR).
/// Returns the compiler's output on failure.
pub fn reference_executable() -> Result<PathBuf, String> {
    let command = compiler_command();
    let description = format!("{command:?}");
    let key = fnv1a(format!("{SOURCE}\n{description}").as_bytes());
    let dir = target_dir().join("cgal_reference");
    let exe = dir.join(format!("cgal_reference-{key:016x}"));
    if exe.exists() {
        return Ok(exe);
    }
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    // Compile to a private name, then rename: concurrent test and bench runs never see a
    // half-written executable.
    let partial = dir.join(format!("cgal_reference-{key:016x}.{}.partial", std::process::id()));
    let mut command = command;
    command.arg("-o").arg(&partial).arg(SOURCE_PATH);
    let output = command.output().map_err(|e| format!("cannot run the C++ compiler ({description}): {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "compiling {SOURCE_PATH} failed ({:?}):\n{}",
            command,
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    std::fs::rename(&partial, &exe).map_err(|e| format!("cannot move {} into place: {e}", partial.display()))?;
    Ok(exe)
}

/// Runs the reference program. `Err` holds CGAL's message (for example a solver that did not
/// converge: "error code 7 ERROR_CANNOT_SOLVE_LINEAR_SYSTEM").
pub fn run_reference(exe: &Path, method: Method, obj: &Path, pins: Option<(u32, u32)>) -> Result<Reference, String> {
    let out = std::env::temp_dir().join(format!(
        "uvflat-cgal-{}-{}-{}-{:?}.txt",
        std::process::id(),
        method.name(),
        obj.file_stem().and_then(|s| s.to_str()).unwrap_or("mesh"),
        std::thread::current().id()
    ));
    let mut command = Command::new(exe);
    command.arg(method.name()).arg(obj).arg(&out);
    if let Some((a, b)) = pins {
        command.arg(a.to_string()).arg(b.to_string());
    }
    let output = command.output().map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
    if !output.status.success() {
        let _ = std::fs::remove_file(&out);
        let stderr = String::from_utf8_lossy(&output.stderr);
        return Err(format!("{} ({})", stderr.trim(), output.status));
    }
    let text = std::fs::read_to_string(&out).map_err(|e| format!("cannot read {}: {e}", out.display()));
    let _ = std::fs::remove_file(&out);
    parse_reference(&text?)
}

fn parse_reference(text: &str) -> Result<Reference, String> {
    let mut lines = text.lines();
    let seconds = lines
        .next()
        .and_then(|l| l.strip_prefix("seconds "))
        .and_then(|s| s.trim().parse::<f64>().ok())
        .ok_or("reference output: first line is not `seconds S`")?;
    let pins: Vec<i64> = lines
        .next()
        .and_then(|l| l.strip_prefix("pins "))
        .map(|s| s.split_whitespace().filter_map(|t| t.parse().ok()).collect())
        .ok_or("reference output: second line is not `pins A B`")?;
    let pins = match pins[..] {
        [-1, -1] => None,
        [a, b] if a >= 0 && b >= 0 => Some((a as u32, b as u32)),
        _ => return Err(format!("reference output: bad pins {pins:?}")),
    };
    let mut uv = Vec::new();
    for (i, line) in lines.enumerate() {
        let values: Vec<f64> = line.split_whitespace().filter_map(|t| t.parse().ok()).collect();
        match values[..] {
            [u, v] => uv.push([u, v]),
            _ => return Err(format!("reference output: bad uv line {} `{line}`", i + 3)),
        }
    }
    Ok(Reference { seconds, pins, uv })
}

/// A disk test mesh, decompressed for the reference program.
#[derive(Debug, Clone)]
pub struct DiskMesh {
    pub name: String,
    pub path: PathBuf,
    pub faces: usize,
}

impl DiskMesh {
    /// Test mesh `name` (without `.obj`), decompressed.
    pub fn named(name: &str) -> DiskMesh {
        let file = format!("{name}.obj");
        DiskMesh { name: name.into(), path: meshes::unpacked(&file), faces: meshes::faces(&file) }
    }
}

/// The `disk_*.obj` test meshes with at most `max_faces` faces, smallest first, decompressed.
pub fn disk_meshes(max_faces: usize) -> Vec<DiskMesh> {
    meshes::up_to("disk_", max_faces)
        .into_iter()
        .map(|(_, file)| DiskMesh::named(file.trim_end_matches(".obj")))
        .collect()
}

/// Vertices on the boundary (edges used by exactly one triangle), from the raw triangle list.
pub fn boundary_vertices(triangles: &[u32]) -> Vec<u32> {
    let mut edge_count = std::collections::HashMap::new();
    for t in triangles.chunks_exact(3) {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *edge_count.entry((a.min(b), a.max(b))).or_insert(0u32) += 1;
        }
    }
    let mut vertices: Vec<u32> = edge_count.iter().filter(|(_, &c)| c == 1).flat_map(|(&(a, b), _)| [a, b]).collect();
    vertices.sort_unstable();
    vertices.dedup();
    vertices
}

/// Length of the diagonal of the bounding box of `uv`.
pub fn bbox_diagonal(uv: &[[f64; 2]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in uv {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt()
}

/// Median of a non-empty sample.
pub fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(|a, b| a.total_cmp(b));
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// Positions (3 per vertex) and triangles (3 per face, 0-based) of a plain OBJ with only `v`
/// and `f` lines, in file order, exactly as `cgal_reference.cpp` reads it.
pub fn read_plain_obj(path: &Path) -> Result<(Vec<f64>, Vec<u32>), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let (mut positions, mut triangles) = (Vec::new(), Vec::new());
    for (number, line) in text.lines().enumerate() {
        let mut tokens = line.split_whitespace();
        let bad = || format!("{}:{}: cannot parse `{line}`", path.display(), number + 1);
        match tokens.next() {
            Some("v") => {
                for _ in 0..3 {
                    positions.push(tokens.next().and_then(|t| t.parse::<f64>().ok()).ok_or_else(bad)?);
                }
            }
            Some("f") => {
                let corners: Vec<u32> = tokens
                    .map(|t| t.split('/').next().and_then(|i| i.parse::<u32>().ok()).filter(|&i| i >= 1).map(|i| i - 1))
                    .collect::<Option<_>>()
                    .ok_or_else(bad)?;
                if corners.len() != 3 {
                    return Err(bad());
                }
                triangles.extend(corners);
            }
            _ => {}
        }
    }
    Ok((positions, triangles))
}
