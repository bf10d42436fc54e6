//! Wavefront OBJ input and output of triangle meshes with texture coordinates.
//!
//! Reading keeps the file's numbering: vertex i is the i-th `v` line and uv i the i-th `vt` line
//! (0-based), whether or not a face uses them, across all `o`/`g` groups (OBJ indices are
//! global). Faces are fan-triangulated: (c0, c1, c2), (c0, c2, c3), …, except a polygon whose
//! fan would hold a flat triangle or one turned against the polygon (concave, or collinear
//! corners), which is cut by ear clipping in its plane instead; indices may be negative
//! (relative) and may refer to `v` lines further down. Only `v x y z`, `vt u [v]` and `f` are
//! interpreted; `vn`, `l`, `p`, groups, materials and comments are skipped. Coordinates are read
//! as f64 exactly as written (`nan`/`inf` included; validating them is the mesh's job). A
//! gzip-compressed file (`.obj.gz`, recognised by its magic bytes, not its name) is read through
//! `flate2`'s decoder.
//!
//! This is a small parser of its own rather than `tobj`: tobj (4.0) renumbers vertices in order of
//! first use per model, drops unreferenced ones, duplicates vertices shared by two models and
//! stores f32, none of which suits a library that returns one uv per input vertex. The tests
//! check this reader against tobj on a real mesh.
//!
//! Writing emits `v`, `vt` and `f a/ta b/tb c/tc` (1-based), numbers in shortest round-trip
//! form (exponent form below 1e-5 and from 1e16 in magnitude), through a buffered writer.
//!
//! Cost: linear in the file size.

use std::fmt::Display;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::Error;

/// A triangle mesh as read from an OBJ file, in flat arrays.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ObjMesh {
    /// 3 per vertex, vertex i from the i-th `v` line.
    pub positions: Vec<f64>,
    /// 3 per triangle, 0-based indices into the vertices.
    pub triangles: Vec<u32>,
    /// 2 per `vt` line (the third coordinate, if any, is dropped); may be empty.
    pub uv: Vec<f64>,
    /// 3 per triangle, 0-based indices into `uv`; empty when no face gives `vt` indices.
    pub uv_triangles: Vec<u32>,
}

impl ObjMesh {
    pub fn vertex_count(&self) -> usize {
        self.positions.len() / 3
    }

    pub fn triangle_count(&self) -> usize {
        self.triangles.len() / 3
    }
}

/// Reads an OBJ file. Errors (`Error::Io`, with the line number for malformed content): the file
/// cannot be read, a number does not parse, a face has fewer than 3 corners, an index is 0 or out
/// of range, or some faces have `vt` indices and others do not.
pub fn read_obj(path: &Path) -> Result<ObjMesh, Error> {
    read(path, false)
}

/// [`read_obj`] without the texture coordinates: `vt` lines and the `vt` indices of faces are
/// skipped, so a file whose old UVs are incomplete or broken still gives its mesh (for callers
/// that compute new UVs).
pub fn read_obj_geometry(path: &Path) -> Result<ObjMesh, Error> {
    read(path, true)
}

fn read(path: &Path, geometry_only: bool) -> Result<ObjMesh, Error> {
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    let bytes = gunzipped(bytes).map_err(|e| io_error(path, e))?;
    let text = String::from_utf8_lossy(&bytes);
    parse_obj_with(&text, geometry_only).map_err(|message| Error::Io { path: path.display().to_string(), message })
}

/// The file's bytes, decompressed when they start with the gzip magic number (RFC 1952 §2.3.1;
/// every member of a multi-member file).
fn gunzipped(bytes: Vec<u8>) -> std::io::Result<Vec<u8>> {
    if !bytes.starts_with(&[0x1f, 0x8b]) {
        return Ok(bytes);
    }
    let mut text = Vec::new();
    std::io::Read::read_to_end(&mut flate2::read::MultiGzDecoder::new(bytes.as_slice()), &mut text)?;
    Ok(text)
}

/// Writes a mesh with one uv per vertex: `v` lines, one `vt` per vertex, `f a/a b/b c/c`. A uv
/// with a NaN (or infinite) coordinate is written as `vt 0 0` after a comment saying so.
pub fn write_obj_with_uv(path: &Path, positions: &[f64], triangles: &[u32], uv: &[[f64; 2]]) -> Result<(), Error> {
    let vertices = validate_positions(positions, triangles)?;
    if uv.len() != vertices {
        return Err(Error::InvalidArgument(format!(
            "{} uv coordinates for {vertices} vertices; per-vertex uv needs one per vertex",
            uv.len()
        )));
    }
    validate_triangles(triangles, vertices, "vertex")?;
    write_file(path, |out| write_obj_to(out, positions, triangles, uv, triangles))
}

/// Writes a mesh with per-corner uv: `uv_triangles[3t + k]` indexes the uv of corner k of
/// triangle t, written as `f a/ta b/tb c/tc`. Non-finite uvs are written as `vt 0 0`.
pub fn write_obj_with_corner_uv(
    path: &Path,
    positions: &[f64],
    triangles: &[u32],
    uv: &[[f64; 2]],
    uv_triangles: &[u32],
) -> Result<(), Error> {
    let vertices = validate_positions(positions, triangles)?;
    validate_triangles(triangles, vertices, "vertex")?;
    if uv_triangles.len() != triangles.len() {
        return Err(Error::InvalidArgument(format!(
            "{} uv triangle indices for {} triangle indices; they must match corner for corner",
            uv_triangles.len(),
            triangles.len()
        )));
    }
    validate_triangles(uv_triangles, uv.len(), "uv")?;
    write_file(path, |out| write_obj_to(out, positions, triangles, uv, uv_triangles))
}

// ---------------------------------------------------------------------------------------------
// Reading

/// One face corner as written: 1-based or negative indices, `vt` optional.
struct Corner {
    vertex: i64,
    uv: Option<i64>,
}

/// Indices that point past what has been read so far; checked once the file is read.
struct ForwardReference {
    line: usize,
    index: usize,
    kind: &'static str,
}

#[derive(Default)]
struct ObjParser {
    mesh: ObjMesh,
    forward: Vec<ForwardReference>,
    first_face_with_uv: Option<usize>,
    first_face_without_uv: Option<usize>,
    /// Faces of more than three corners: their first triangle and their corners (positions may
    /// come later in the file, so their fans are checked at the end).
    polygons: Vec<(usize, Vec<u32>)>,
    /// Skip texture coordinates (`vt` lines and indices).
    geometry_only: bool,
}

#[cfg(test)]
fn parse_obj(text: &str) -> Result<ObjMesh, String> {
    parse_obj_with(text, false)
}

fn parse_obj_with(text: &str, geometry_only: bool) -> Result<ObjMesh, String> {
    // A UTF-8 byte-order mark (Windows editors write one) is not part of the first line.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut parser = ObjParser { geometry_only, ..ObjParser::default() };
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut words = content.split_ascii_whitespace();
        let result = match words.next() {
            Some("v") => parse_numbers(&mut words, 3, 3, "a vertex").map(|xyz| {
                parser.mesh.positions.extend_from_slice(&xyz);
            }),
            Some("vt") if geometry_only => Ok(()),
            Some("vt") => parse_numbers(&mut words, 1, 2, "a texture coordinate").map(|mut uv| {
                uv.resize(2, 0.0);
                parser.mesh.uv.extend_from_slice(&uv);
            }),
            Some("f") => parser.add_face(line, words),
            _ => Ok(()),
        };
        result.map_err(|message| format!("line {line}: {message}"))?;
    }
    parser.finish()
}

/// Reads `min..=max` numbers from the front of `words` (further words are ignored).
fn parse_numbers<'a>(
    words: &mut impl Iterator<Item = &'a str>,
    min: usize,
    max: usize,
    what: &str,
) -> Result<Vec<f64>, String> {
    let numbers = words
        .take(max)
        .map(|w| w.parse::<f64>().map_err(|_| format!("`{w}` is not a number")))
        .collect::<Result<Vec<f64>, String>>()?;
    if numbers.len() < min {
        return Err(format!("{what} needs {min} coordinates, found {}", numbers.len()));
    }
    Ok(numbers)
}

fn parse_corner(word: &str) -> Result<Corner, String> {
    let mut parts = word.split('/');
    let vertex = parse_index(parts.next().unwrap_or(""), word)?;
    let uv = match parts.next() {
        None | Some("") => None,
        Some(t) => Some(parse_index(t, word)?),
    };
    Ok(Corner { vertex, uv })
}

fn parse_index(text: &str, corner: &str) -> Result<i64, String> {
    match text.parse::<i64>() {
        Ok(0) => Err(format!("face corner `{corner}` has index 0 (OBJ indices start at 1)")),
        Ok(i) => Ok(i),
        Err(_) => Err(format!("face corner `{corner}` is not an index")),
    }
}

impl ObjParser {
    fn add_face<'a>(&mut self, line: usize, words: impl Iterator<Item = &'a str>) -> Result<(), String> {
        let corners = words.map(parse_corner).collect::<Result<Vec<Corner>, String>>()?;
        if corners.len() < 3 {
            return Err(format!("a face needs at least 3 corners, found {}", corners.len()));
        }
        let vertex_count = self.mesh.positions.len() / 3;
        let uv_count = self.mesh.uv.len() / 2;
        let mut vertices = Vec::with_capacity(corners.len());
        let mut uvs = Vec::with_capacity(corners.len());
        for c in &corners {
            vertices.push(self.resolve(line, c.vertex, vertex_count, "vertex")?);
            if self.geometry_only {
                continue;
            }
            match c.uv {
                Some(t) => uvs.push(self.resolve(line, t, uv_count, "texture coordinate")?),
                None => self.first_face_without_uv = self.first_face_without_uv.or(Some(line)),
            }
        }
        if !uvs.is_empty() {
            self.first_face_with_uv = self.first_face_with_uv.or(Some(line));
        }
        if corners.len() > 3 {
            self.polygons.push((self.mesh.triangles.len() / 3, vertices.clone()));
        }
        for k in 1..corners.len() - 1 {
            self.mesh.triangles.extend([vertices[0], vertices[k], vertices[k + 1]]);
            if uvs.len() == corners.len() {
                self.mesh.uv_triangles.extend([uvs[0], uvs[k], uvs[k + 1]]);
            }
        }
        Ok(())
    }

    /// 0-based index of a 1-based (or negative, relative to the `count` read so far) OBJ index.
    fn resolve(&mut self, line: usize, index: i64, count: usize, kind: &'static str) -> Result<u32, String> {
        let resolved = if index > 0 {
            usize::try_from(index - 1).ok()
        } else {
            usize::try_from(index.unsigned_abs()).ok().and_then(|back| count.checked_sub(back))
        };
        let Some(resolved) = resolved else {
            return Err(format!("{kind} index {index} is before the first {kind} ({count} so far)"));
        };
        let Ok(narrow) = u32::try_from(resolved) else {
            return Err(format!("{kind} index {index} does not fit in 32 bits"));
        };
        if resolved >= count {
            self.forward.push(ForwardReference { line, index: resolved, kind });
        }
        Ok(narrow)
    }

    fn finish(mut self) -> Result<ObjMesh, String> {
        let vertex_count = self.mesh.positions.len() / 3;
        let uv_count = self.mesh.uv.len() / 2;
        for f in &self.forward {
            let count = if f.kind == "vertex" { vertex_count } else { uv_count };
            if f.index >= count {
                return Err(format!(
                    "line {}: face uses {} {} but the file has only {count}",
                    f.line,
                    f.kind,
                    f.index + 1
                ));
            }
        }
        if let (Some(with), Some(without)) = (self.first_face_with_uv, self.first_face_without_uv) {
            return Err(format!(
                "line {without}: face corner without a texture coordinate, but the face on \
                 line {with} has them; faces must all have `vt` indices or none"
            ));
        }
        if u32::try_from(vertex_count).is_err() || u32::try_from(uv_count).is_err() {
            return Err("more than 2^32 vertices or texture coordinates".into());
        }
        for (first, vertices) in std::mem::take(&mut self.polygons) {
            self.retriangulate_if_fan_folds(first, &vertices);
        }
        Ok(self.mesh)
    }

    /// Replaces the fan of a polygon (triangles `first`.. of the mesh) by an ear-clipping
    /// triangulation when a fan triangle is flat or turns against the polygon (a concave
    /// polygon seen from a corner that does not see all others; collinear corners): the fan
    /// would then overlap itself or hold a degenerate triangle. Convex polygons keep their fan.
    fn retriangulate_if_fan_folds(&mut self, first: usize, vertices: &[u32]) {
        let point = |v: u32| {
            let i = 3 * v as usize;
            [self.mesh.positions[i], self.mesh.positions[i + 1], self.mesh.positions[i + 2]]
        };
        let ring: Vec<[f64; 3]> = vertices.iter().map(|&v| point(v)).collect();
        let Some(order) = crate::mesh::polygon::ears_where_the_fan_folds(&ring) else { return };
        let corner_uvs = (!self.mesh.uv_triangles.is_empty()).then(|| {
            let t = &self.mesh.uv_triangles[3 * first..3 * (first + ring.len() - 2)];
            // The fan's corners: c0 in every triangle, then c1, c2, … in order.
            let mut uvs = vec![t[0], t[1]];
            uvs.extend(t.chunks(3).map(|c| c[2]));
            uvs
        });
        for (k, tri) in order.iter().enumerate() {
            let at = 3 * (first + k);
            self.mesh.triangles[at..at + 3].copy_from_slice(&tri.map(|c| vertices[c]));
            if let Some(uvs) = &corner_uvs {
                self.mesh.uv_triangles[at..at + 3].copy_from_slice(&tri.map(|c| uvs[c]));
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Writing

/// The vertex count of `positions`, refusing a non-finite coordinate on a vertex `triangles`
/// use. A vertex no triangle uses is written as it was read (the reader keeps every `v` line,
/// `nan` included, and the meshes allow unreferenced vertices).
fn validate_positions(positions: &[f64], triangles: &[u32]) -> Result<usize, Error> {
    if positions.len() % 3 != 0 {
        return Err(Error::InvalidArgument(format!("positions has {} numbers, not a multiple of 3", positions.len())));
    }
    let count = positions.len() / 3;
    if positions.iter().any(|x| !x.is_finite()) {
        let mut used = vec![false; count];
        triangles.iter().filter(|&&v| (v as usize) < count).for_each(|&v| used[v as usize] = true);
        if let Some(i) = (0..positions.len()).find(|&i| !positions[i].is_finite() && used[i / 3]) {
            return Err(Error::InvalidArgument(format!(
                "vertex {} has a non-finite coordinate ({})",
                i / 3,
                positions[i]
            )));
        }
    }
    Ok(count)
}

fn validate_triangles(indices: &[u32], count: usize, kind: &str) -> Result<(), Error> {
    if indices.len() % 3 != 0 {
        return Err(Error::InvalidArgument(format!(
            "{kind} triangle indices have {} entries, not a multiple of 3",
            indices.len()
        )));
    }
    match indices.iter().position(|&i| i as usize >= count) {
        Some(k) => Err(Error::InvalidArgument(format!(
            "triangle {} references {kind} {} but there are {count}",
            k / 3,
            indices[k]
        ))),
        None => Ok(()),
    }
}

fn write_file(path: &Path, write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>) -> Result<(), Error> {
    let file = File::create(path).map_err(|e| io_error(path, e))?;
    let mut out = BufWriter::with_capacity(1 << 16, file);
    write(&mut out).map_err(|e| io_error(path, e))?;
    out.flush().map_err(|e| io_error(path, e))
}

/// Writes validated arrays; `uv_triangles` has one uv index per corner of `triangles`.
fn write_obj_to(
    out: &mut impl Write,
    positions: &[f64],
    triangles: &[u32],
    uv: &[[f64; 2]],
    uv_triangles: &[u32],
) -> std::io::Result<()> {
    writeln!(
        out,
        "# uvflat: {} vertices, {} triangles, {} texture coordinates",
        positions.len() / 3,
        triangles.len() / 3,
        uv.len()
    )?;
    for p in positions.chunks_exact(3) {
        writeln!(out, "v {} {} {}", Number(p[0]), Number(p[1]), Number(p[2]))?;
    }
    for (i, t) in uv.iter().enumerate() {
        if t.iter().all(|x| x.is_finite()) {
            writeln!(out, "vt {} {}", Number(t[0]), Number(t[1]))?;
        } else {
            writeln!(out, "# texture coordinate {} is undefined ({}, {}), written as 0 0", i + 1, t[0], t[1])?;
            writeln!(out, "vt 0 0")?;
        }
    }
    for (f, t) in triangles.chunks_exact(3).zip(uv_triangles.chunks_exact(3)) {
        writeln!(out, "f {}/{} {}/{} {}/{}", f[0] + 1, t[0] + 1, f[1] + 1, t[1] + 1, f[2] + 1, t[2] + 1)?;
    }
    Ok(())
}

/// An f64 printed in shortest round-trip form, in exponent form when plain digits would be long.
struct Number(f64);

impl Display for Number {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let magnitude = self.0.abs();
        if magnitude == 0.0 || (1e-5..1e16).contains(&magnitude) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

fn io_error(path: &Path, e: std::io::Error) -> Error {
    Error::Io { path: path.display().to_string(), message: e.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn scratch_file(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("uvflat-obj-test-{}-{name}", std::process::id()))
    }

    /// A test mesh of the repository (`tests/data/meshes`, gzip-compressed).
    fn test_mesh(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/meshes").join(format!("{name}.gz"))
    }

    #[test]
    fn per_vertex_uv_survives_a_round_trip() {
        let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.5, 0.0, 1.0, -0.25];
        let triangles = [0, 1, 2, 0, 2, 3];
        let uv = [[0.0, 0.0], [1.0, 0.0], [f64::NAN, 1.0], [0.1, 0.7]];
        let path = scratch_file("per-vertex.obj");
        write_obj_with_uv(&path, &positions, &triangles, &uv).unwrap();
        let mesh = read_obj(&path).unwrap();
        // Another reader (tobj) understands the file too.
        let options = tobj::LoadOptions { single_index: true, ..Default::default() };
        let (models, _) = tobj::load_obj(&path, &options).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(models[0].mesh.indices.len(), 6);
        assert_eq!(models[0].mesh.texcoords.len(), 8);
        assert_eq!(mesh.positions, positions);
        assert_eq!(mesh.triangles, triangles);
        assert_eq!(mesh.uv, [0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.1, 0.7]);
        assert_eq!(mesh.uv_triangles, triangles);
    }

    /// Twice the signed area of every triangle of `mesh` in the xy-plane.
    fn xy_areas(mesh: &ObjMesh) -> Vec<f64> {
        let p = |v: u32| [mesh.positions[3 * v as usize], mesh.positions[3 * v as usize + 1]];
        (mesh.triangles.chunks(3))
            .map(|t| {
                let [a, b, c] = [p(t[0]), p(t[1]), p(t[2])];
                (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
            })
            .collect()
    }

    #[test]
    fn a_concave_polygon_is_cut_into_triangles_inside_it() {
        // A notched rectangle (area 6): the fan from corner 1 would cover the notch at corner 5
        // twice and leave out the rest.
        let text =
            "v 0 0 0\nv 4 0 0\nv 4 2 0\nv 0 2 0\nv 2 1 0\nf 1 2 3 4 5\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n";
        let mesh = parse_obj(text).unwrap();
        assert_ne!(mesh.triangles, [0, 1, 2, 0, 2, 3, 0, 3, 4], "the fan was kept");
        let areas = xy_areas(&mesh);
        assert_eq!(areas.len(), 3);
        assert!(areas.iter().all(|&a| a > 0.0), "{areas:?}");
        assert!((areas.iter().sum::<f64>() - 2.0 * 6.0).abs() < 1e-12, "{areas:?}");
        let with_uv = parse_obj(&text.replace("f 1 2 3 4 5", "f 1/1 2/2 3/3 4/4 5/5")).unwrap();
        assert_eq!(with_uv.triangles, mesh.triangles);
        assert_eq!(with_uv.uv_triangles, mesh.triangles, "each corner keeps its own vt");
    }

    #[test]
    fn collinear_corners_of_a_convex_polygon_make_no_flat_triangle() {
        // A pentagon with corners 1, 2, 3 on one line: the fan from corner 1 has (1, 2, 3) flat.
        let text = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nf 1 2 3 4 5\n";
        let areas = xy_areas(&parse_obj(text).unwrap());
        assert!(areas.iter().all(|&a| a > 0.0), "{areas:?}");
        assert!((areas.iter().sum::<f64>() - 8.0).abs() < 1e-12, "{areas:?}");
    }

    #[test]
    fn geometry_only_skips_incomplete_texture_coordinates() {
        // One face with `vt` indices, one without, one out of range: refused with the UVs,
        // read without them.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 2 4 3\nf 1/9 2/9 3/9\n";
        assert!(parse_obj(text).is_err());
        let mesh = parse_obj_with(text, true).unwrap();
        assert_eq!(mesh.triangles, [0, 1, 2, 1, 3, 2, 0, 1, 2]);
        assert!(mesh.uv.is_empty() && mesh.uv_triangles.is_empty());
    }

    #[test]
    fn a_byte_order_mark_does_not_hide_the_first_vertex() {
        let text = "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let mesh = parse_obj(text).unwrap();
        assert_eq!(mesh.positions, [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        assert_eq!(mesh.triangles, [0, 1, 2]);
    }

    #[test]
    fn per_corner_uv_survives_a_round_trip() {
        let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0];
        let triangles = [0, 1, 2, 0, 2, 3];
        let uv = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [5.0, 5.0], [6.0, 6.0], [5.0, 6.0]];
        let uv_triangles = [0, 1, 2, 3, 4, 5];
        let path = scratch_file("per-corner.obj");
        write_obj_with_corner_uv(&path, &positions, &triangles, &uv, &uv_triangles).unwrap();
        let mesh = read_obj(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(mesh.positions, positions);
        assert_eq!(mesh.triangles, triangles);
        assert_eq!(mesh.uv, uv.concat());
        assert_eq!(mesh.uv_triangles, uv_triangles);
    }

    #[test]
    fn numbers_are_written_in_shortest_round_trip_form() {
        let values = [1e-300, -2.5e-7, 0.1, 1.0 / 3.0, 123456.789, 9.87654321e20, -0.0, 7.0];
        let mut positions = values.to_vec();
        positions.push(0.0);
        let mut out = Vec::new();
        write_obj_to(&mut out, &positions, &[], &[], &[]).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.contains("v 1e-300 -2.5e-7 0.1\n"), "{text}");
        let mesh = parse_obj(&text).unwrap();
        assert_eq!(mesh.positions, positions);
        assert!(text.len() < 200);
    }

    #[test]
    fn vertex_i_is_the_ith_v_line_even_when_unused() {
        let text = "# comment\r\n\
            v 9 9 9\r\n\
            o first\n\
            v 0 0 0\n\
            vn 0 0 1\n\
            v 1 0 0   # trailing comment\n\
            v 1 1 0\n\
            v 7 7 7\n\
            g second\n\
            f 4 3 2\n\
            v 0 1 0\n\
            f -5 -3 -2 -1\n\
            f 2//1 3//1 7\n\
            v 0 2 0\n";
        let mesh = parse_obj(text).unwrap();
        assert_eq!(mesh.vertex_count(), 7);
        assert_eq!(&mesh.positions[..3], &[9.0, 9.0, 9.0]);
        assert_eq!(&mesh.positions[15..18], &[0.0, 1.0, 0.0]);
        // The quad (-5 -3 -2 -1 = 2 4 5 6) becomes the fan (2 4 5), (2 5 6).
        assert_eq!(mesh.triangles, [3, 2, 1, 1, 3, 4, 1, 4, 5, 1, 2, 6]);
        assert!(mesh.uv.is_empty() && mesh.uv_triangles.is_empty());
    }

    #[test]
    fn shared_unreferenced_vertices_file_keeps_every_vertex() {
        let mesh = read_obj(&test_mesh("bad_unreferenced_vertices.obj")).unwrap();
        assert_eq!(mesh.vertex_count(), 86);
        assert_eq!(mesh.triangle_count(), 128);
        assert_eq!(&mesh.positions[..6], &[5.0, 5.0, 5.0, -3.0, 0.0, 1.0]);
    }

    #[test]
    fn cat_head_has_131_vertices_and_248_triangles() {
        let path = test_mesh("disk_cat_head.obj");
        let mesh = read_obj(&path).unwrap();
        assert_eq!(mesh.vertex_count(), 131);
        assert_eq!(mesh.triangle_count(), 248);
        assert!(mesh.uv.is_empty() && mesh.uv_triangles.is_empty());
        assert_eq!(&mesh.positions[..3], &[-0.008298, 0.583053, 0.070454]);
        // Same triangles, corner for corner, as tobj reads them (tobj renumbers and uses f32)
        // from the text that flate2 decompresses.
        let text = gunzipped(std::fs::read(&path).unwrap()).unwrap();
        assert!(text.starts_with(b"#"), "the file is decompressed");
        let options = tobj::LoadOptions { triangulate: true, ..Default::default() };
        let (models, _) =
            tobj::load_obj_buf(&mut text.as_slice(), &options, |_| Err(tobj::LoadError::OpenFileFailed)).unwrap();
        let theirs: Vec<[f32; 3]> = models
            .iter()
            .flat_map(|m| {
                let p = &m.mesh.positions;
                m.mesh.indices.iter().map(move |&i| {
                    let i = i as usize * 3;
                    [p[i], p[i + 1], p[i + 2]]
                })
            })
            .collect();
        assert_eq!(theirs.len(), mesh.triangles.len());
        for (corner, &v) in theirs.iter().zip(&mesh.triangles) {
            for (k, theirs) in corner.iter().enumerate() {
                let ours = mesh.positions[3 * v as usize + k];
                assert!((ours - f64::from(*theirs)).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn texture_coordinates_are_indexed_per_corner() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.25 0\nvt 1 0\nvt 0\nf 1/3 2/2/1 3/1\n";
        let mesh = parse_obj(text).unwrap();
        assert_eq!(mesh.uv, [0.5, 0.25, 1.0, 0.0, 0.0, 0.0]);
        assert_eq!(mesh.uv_triangles, [2, 1, 0]);
    }

    #[test]
    fn malformed_files_are_errors_with_a_line_number() {
        let cases = [
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "index 0"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "line 4"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "3 corners"),
            ("v 0 0\n", "line 1"),
            ("v 0 zero 0\n", "`zero`"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1 2 3\n", "line 6"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n", "texture coordinate 2"),
        ];
        for (text, expected) in cases {
            match parse_obj(text) {
                Err(message) => {
                    assert!(message.contains(expected), "{message} (wanted {expected})")
                }
                Ok(mesh) => panic!("accepted {text:?} as {mesh:?}"),
            }
        }
        match read_obj(&test_mesh("bad_out_of_range_index.obj")) {
            Err(Error::Io { message, .. }) => assert!(message.starts_with("line "), "{message}"),
            other => panic!("{other:?}"),
        }
        assert!(matches!(read_obj(&scratch_file("missing.obj")), Err(Error::Io { .. })));
    }

    #[test]
    fn non_finite_coordinates_are_read_as_written() {
        let mesh = read_obj(&test_mesh("bad_nan_coordinate.obj")).unwrap();
        assert!(mesh.positions.iter().any(|x| x.is_nan()));
        assert!(mesh.positions.iter().any(|x| x.is_infinite()));
    }

    #[test]
    fn an_unused_vertex_with_a_nan_coordinate_round_trips() {
        let path = scratch_file("unused-nan.obj");
        let positions = [0.0, 0.0, 0.0, f64::NAN, 5.0, 5.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        write_obj_with_uv(&path, &positions, &[0, 2, 3], &[[0.0, 0.0]; 4]).unwrap();
        let mesh = read_obj(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert!(mesh.positions[3].is_nan() && mesh.positions[4] == 5.0);
        assert_eq!(mesh.triangles, [0, 2, 3]);
    }

    #[test]
    fn writers_reject_inconsistent_arrays() {
        let path = scratch_file("never-written.obj");
        let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let uv = [[0.0, 0.0]; 3];
        let bad_index = write_obj_with_uv(&path, &positions, &[0, 1, 3], &uv);
        assert!(matches!(bad_index, Err(Error::InvalidArgument(m)) if m.contains("triangle 0")));
        assert!(write_obj_with_uv(&path, &positions, &[0, 1, 2], &uv[..2]).is_err());
        assert!(write_obj_with_uv(&path, &positions[..8], &[0, 1, 2], &uv).is_err());
        let nan = [0.0, 0.0, 0.0, 1.0, f64::NAN, 0.0, 0.0, 1.0, 0.0];
        assert!(write_obj_with_uv(&path, &nan, &[0, 1, 2], &uv).is_err());
        // (A NaN on a vertex no triangle uses is written as read: see the next test.)
        assert!(write_obj_with_corner_uv(&path, &positions, &[0, 1, 2], &uv, &[0, 1]).is_err());
        assert!(write_obj_with_corner_uv(&path, &positions, &[0, 1, 2], &uv, &[0, 1, 3]).is_err());
        assert!(!path.exists());
    }
}
