//! `uvflat info`: counts and topology of a mesh.

use std::path::Path;

use crate::errors::Failure;
use crate::files::load_mesh;

pub(crate) fn info(path: &Path, json: bool) -> Result<(), Failure> {
    let (_, mesh) = load_mesh(path)?;
    let t = mesh.topology();
    if json {
        println!(
            "{}",
            serde_json::json!({
                "vertices": t.vertices,
                "referenced_vertices": t.referenced_vertices,
                "faces": t.triangles,
                "edges": t.edges,
                "components": t.components,
                "boundary_loops": t.boundary_loops,
                "euler_characteristic": t.euler_characteristic,
                "genus": t.genus,
            })
        );
    } else {
        println!("vertices        {} ({} referenced)", t.vertices, t.referenced_vertices);
        println!("faces           {}", t.triangles);
        println!("edges           {}", t.edges);
        println!("components      {}", t.components);
        println!("boundary loops  {}", t.boundary_loops);
        println!("euler           {}", t.euler_characteristic);
        println!("genus           {}", t.genus);
    }
    Ok(())
}
