//! Reading the input mesh, and writing polygon meshes (OBJ and SVG).

use std::path::Path;

use crate::errors::Failure;
use uvflat_core::io::obj::{read_obj_geometry, ObjMesh};
use uvflat_core::io::surface_svg::write_polygon_mesh_svg;
use uvflat_core::methods::pgp::PolygonMesh;
use uvflat_core::TriMesh;

/// Reads the geometry of an OBJ (plain or gzip-compressed) and validates it as a mesh; the
/// message of a validation error names the file.
pub(crate) fn load_mesh(path: &Path) -> Result<(ObjMesh, TriMesh), Failure> {
    let obj = read_obj_geometry(path)?;
    let mesh = TriMesh::new(&obj.positions, &obj.triangles)
        .map_err(|e| Failure { message: format!("{}: {e}", path.display()), usage: false })?;
    Ok((obj, mesh))
}

/// Writes a polygon mesh to an OBJ (and its picture to an SVG); returns its face, quad and
/// vertex counts.
pub(crate) fn write_quad_mesh(
    remesh: &PolygonMesh,
    path: &Path,
    svg: Option<&Path>,
) -> Result<(usize, usize, usize), Failure> {
    write_polygon_obj(path, remesh)?;
    if let Some(svg) = svg {
        let faces: Vec<Vec<u32>> = remesh.faces().map(|f| f.to_vec()).collect();
        write_polygon_mesh_svg(svg, &remesh.positions, &faces)?;
    }
    Ok((remesh.face_sizes.len(), remesh.quad_count(), remesh.positions.len()))
}

/// Writes a polygon mesh as `v` and `f` lines.
pub(crate) fn write_polygon_obj(path: &Path, mesh: &PolygonMesh) -> Result<(), Failure> {
    use std::io::Write;
    let fail = |e: std::io::Error| Failure { message: format!("cannot write {}: {e}", path.display()), usage: false };
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(fail)?);
    for p in &mesh.positions {
        writeln!(out, "v {} {} {}", p[0], p[1], p[2]).map_err(fail)?;
    }
    for face in mesh.faces() {
        let line: Vec<String> = face.iter().map(|&v| (v + 1).to_string()).collect();
        writeln!(out, "f {}", line.join(" ")).map_err(fail)?;
    }
    out.flush().map_err(fail)
}
