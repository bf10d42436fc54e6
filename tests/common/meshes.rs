//! The real meshes of `../shared/meshes`, shared by the PGP tests.

use std::path::Path;
use uvflat::TriMesh;

/// Where the shared meshes are.
const MESH_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes");

/// Loads and validates one mesh of the shared directory.
#[allow(dead_code)]
pub fn load(file: &str) -> TriMesh {
    let obj = uvflat::io::obj::read_obj(&Path::new(MESH_DIR).join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    TriMesh::new(&obj.positions, &obj.triangles).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// File names of the closed meshes, sorted.
#[allow(dead_code)]
pub fn closed_meshes() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(MESH_DIR)
        .expect("mesh dir")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.starts_with("closed_") && n.ends_with(".obj"))
        .collect();
    names.sort();
    assert!(names.len() >= 10, "closed meshes missing from {MESH_DIR}");
    names
}
