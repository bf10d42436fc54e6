//! The test meshes of the repository (`tests/data/meshes/NAME.obj.gz`, listed with source and
//! license in its `MANIFEST.tsv`), shared by the integration tests and benches. Meshes are named as `NAME.obj` everywhere; the `.gz` is this module's
//! business. uvflat's own reader takes the compressed files as they are; programs of others
//! (CGAL, OpenMesh) get a decompressed copy from [`unpacked`].

use std::path::{Path, PathBuf};
use uvflat_core::TriMesh;

/// Where the compressed meshes are.
pub const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/meshes");

/// The compressed file of mesh `file` (`NAME.obj`).
pub fn path(file: &str) -> PathBuf {
    Path::new(DIR).join(format!("{file}.gz"))
}

/// Reads mesh `file` (`NAME.obj`) as flat arrays.
pub fn read(file: &str) -> uvflat_core::io::obj::ObjMesh {
    uvflat_core::io::obj::read_obj(&path(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// Loads and validates mesh `file` (`NAME.obj`).
pub fn load(file: &str) -> TriMesh {
    let obj = read(file);
    TriMesh::new(&obj.positions, &obj.triangles).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// Every mesh (`NAME.obj`) whose name passes `keep`, sorted by name.
pub fn names(keep: impl Fn(&str) -> bool) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(DIR)
        .unwrap_or_else(|e| panic!("cannot list {DIR}: {e}"))
        .filter_map(|e| e.ok()?.file_name().into_string().ok()?.strip_suffix(".gz").map(str::to_string))
        .filter(|n| n.ends_with(".obj") && keep(n))
        .collect();
    names.sort();
    names
}

/// Every mesh whose name starts with one of `prefixes`, sorted by name.
pub fn with_prefix(prefixes: &[&str]) -> Vec<String> {
    names(|n| prefixes.iter().any(|p| n.starts_with(p)))
}

/// File names of the closed meshes, sorted.
pub fn closed_meshes() -> Vec<String> {
    let names = with_prefix(&["closed_"]);
    assert!(names.len() >= 10, "closed meshes missing from {DIR}");
    names
}

/// Triangle count of mesh `file` as `MANIFEST.tsv` states it (its `faces` column; the manifest
/// is read once per process).
pub fn faces(file: &str) -> usize {
    static FACES: std::sync::OnceLock<std::collections::HashMap<String, usize>> = std::sync::OnceLock::new();
    let faces = FACES.get_or_init(|| {
        let manifest = std::fs::read_to_string(Path::new(DIR).join("MANIFEST.tsv")).expect("MANIFEST.tsv");
        let rows = manifest.lines().skip(1).map(|l| l.split('\t').collect::<Vec<_>>());
        rows.filter_map(|r| Some((r[0].strip_suffix(".gz")?.to_string(), r.get(4)?.parse().ok()?))).collect()
    });
    *faces.get(file).unwrap_or_else(|| panic!("{file}: no face count in MANIFEST.tsv"))
}

/// Meshes whose names start with `prefix` and that have at most `max_faces` triangles, smallest
/// first (ties by name).
pub fn up_to(prefix: &str, max_faces: usize) -> Vec<(usize, String)> {
    let mut files: Vec<(usize, String)> =
        with_prefix(&[prefix]).into_iter().map(|n| (faces(&n), n)).filter(|(f, _)| *f <= max_faces).collect();
    files.sort();
    files
}

/// A plain (decompressed) copy of mesh `file`, for programs that read only plain OBJ.
pub fn unpacked(file: &str) -> PathBuf {
    unpack(&path(file))
}

/// The optional large mesh `file` (`NAME.obj.gz`, not in the repository: see
/// `tests/data/meshes/README.md`) from the folder `UVFLAT_LARGE_MESHES` names, if it is there.
pub fn large(file: &str) -> Option<PathBuf> {
    let path = Path::new(&std::env::var_os("UVFLAT_LARGE_MESHES")?).join(file);
    path.is_file().then_some(path)
}

/// A plain copy of the gzip-compressed OBJ `source`: written once under `<target>/tmp/meshes`
/// through a temporary name and a rename, so tests running side by side never see
/// half a file; rewritten when `source` is newer.
pub fn unpack(source: &Path) -> PathBuf {
    let dir = crate::compiler::target_dir().join("tmp").join("meshes");
    let name = source.file_name().and_then(|n| n.to_str()).expect("a file name");
    let out = dir.join(name.strip_suffix(".gz").unwrap_or(name));
    let fresh = |o: &Path| {
        let (Ok(o), Ok(s)) = (o.metadata(), source.metadata()) else { return false };
        matches!((o.modified(), s.modified()), (Ok(o), Ok(s)) if o >= s)
    };
    if fresh(&out) {
        return out;
    }
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let compressed = std::fs::File::open(source).unwrap_or_else(|e| panic!("{}: {e}", source.display()));
    let partial = dir.join(format!(".{name}.{}.{:?}", std::process::id(), std::thread::current().id()));
    let mut writer = std::fs::File::create(&partial).unwrap_or_else(|e| panic!("{}: {e}", partial.display()));
    std::io::copy(&mut flate2::read::MultiGzDecoder::new(compressed), &mut writer)
        .unwrap_or_else(|e| panic!("decompressing {}: {e}", source.display()));
    std::fs::rename(&partial, &out).unwrap_or_else(|e| panic!("{}: {e}", out.display()));
    out
}
