//! A mesh validated once and shared by many calls (`UvfMesh`), built from the data DCC tools
//! hold: positions as `float` or `double` with any byte stride (a field of a vertex struct),
//! indices as `uint16_t` or `uint32_t` with any stride, triangles or polygons (face sizes).
//! Polygons are triangulated as the OBJ reader does (`mesh::polygon`: the fan, or ear clipping
//! where the fan would fold), and per-corner results map back to the polygons' corners.
//!
//! Cost: one pass over the input plus the mesh validation and connectivity of
//! `TriMesh::new`, paid once per handle instead of once per call.

use super::status::UvfStatus;
use super::{borrow_slice, borrow_slice_mut, checked_count, guard, read_options};
use std::os::raw::c_void;
use uvflat_core::error::{Error, Result};
use uvflat_core::mesh::polygon;
use uvflat_core::TriMesh;

/// `UvfMeshDesc.position_type`: 64-bit `double` coordinates.
pub const UVF_SCALAR_DOUBLE: u32 = 0;
/// `UvfMeshDesc.position_type`: 32-bit `float` coordinates.
pub const UVF_SCALAR_FLOAT: u32 = 1;
/// `UvfMeshDesc.index_type`: `uint32_t` vertex indices.
pub const UVF_INDEX_UINT32: u32 = 0;
/// `UvfMeshDesc.index_type`: `uint16_t` vertex indices.
pub const UVF_INDEX_UINT16: u32 = 1;

/// Where `uvf_mesh_new` reads a mesh from. Initialise with `uvf_mesh_desc_default`, then set
/// the arrays. Nothing is kept: the handle copies what it needs.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfMeshDesc {
    /// `sizeof(UvfMeshDesc)`, set by the default initialiser.
    pub struct_size: usize,
    /// Vertex coordinates: x, y, z of vertex v start `v × position_stride` bytes after this
    /// pointer (any alignment).
    pub positions: *const c_void,
    /// `UVF_SCALAR_DOUBLE` (default) or `UVF_SCALAR_FLOAT`.
    pub position_type: u32,
    /// Bytes from one vertex's x to the next one's; 0 (default) for packed x, y, z triples.
    pub position_stride: usize,
    /// Number of vertices.
    pub vertex_count: usize,
    /// Vertex indices of every face's corners, face after face (counter-clockwise): index k
    /// starts `k × index_stride` bytes after this pointer (any alignment).
    pub indices: *const c_void,
    /// `UVF_INDEX_UINT32` (default) or `UVF_INDEX_UINT16`.
    pub index_type: u32,
    /// Bytes from one index to the next; 0 (default) for packed indices.
    pub index_stride: usize,
    /// Corners of each face (each ≥ 3), or NULL (default) when every face is a triangle.
    pub face_sizes: *const u32,
    /// Number of faces (triangles when `face_sizes` is NULL).
    pub face_count: usize,
}

impl Default for UvfMeshDesc {
    fn default() -> Self {
        UvfMeshDesc {
            struct_size: std::mem::size_of::<UvfMeshDesc>(),
            positions: std::ptr::null(),
            position_type: UVF_SCALAR_DOUBLE,
            position_stride: 0,
            vertex_count: 0,
            indices: std::ptr::null(),
            index_type: UVF_INDEX_UINT32,
            index_stride: 0,
            face_sizes: std::ptr::null(),
            face_count: 0,
        }
    }
}

/// A validated triangle mesh with its connectivity, and how its triangles come from the input
/// faces. Immutable: may be used by any number of calls on any threads at once.
pub struct UvfMesh {
    pub(crate) mesh: TriMesh,
    /// The input face of each triangle.
    triangle_face: Vec<u32>,
    /// For each triangle corner (3 per triangle), the input corner it is (an index into the
    /// input's index list).
    triangle_corner: Vec<usize>,
    /// Number of input corners (the length of the input's index list).
    corner_count: usize,
}

/// Fills `desc` with the defaults (packed `double` positions, packed `uint32_t` triangles, no
/// arrays yet) and sets its `struct_size`.
///
/// # Safety
/// `desc` must be NULL or point to a writable `UvfMeshDesc`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_desc_default(desc: *mut UvfMeshDesc) {
    if !desc.is_null() {
        desc.write(UvfMeshDesc::default());
    }
}

/// Reads, triangulates and validates a mesh once, for any number of later calls (the
/// `uvf_mesh_*` variants of the methods). `*mesh_out` receives a handle to release with
/// `uvf_mesh_free`. Invalid input is refused as by the flat-array calls (`UVF_INVALID_ARGUMENT`
/// for the description, `UVF_INVALID_MESH` for the data; a problem in a polygon names the
/// face). On failure `*mesh_out` is untouched.
///
/// # Safety
/// `desc` must point to a `UvfMeshDesc` whose arrays hold what it says; `mesh_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_new(desc: *const UvfMeshDesc, mesh_out: *mut *mut UvfMesh) -> UvfStatus {
    guard(|| {
        if desc.is_null() {
            return Err(Error::InvalidArgument("desc is NULL".into()));
        }
        let d = read_options(desc, UvfMeshDesc::default(), std::mem::size_of::<UvfMeshDesc>(), "UvfMeshDesc")?;
        let out = borrow_slice_mut(mesh_out, 1, "mesh_out")?;
        let mesh = unsafe { build(&d) }?;
        out[0] = Box::into_raw(Box::new(mesh));
        Ok(())
    })
}

/// Releases a mesh handle (NULL is ignored). No call may be using it.
///
/// # Safety
/// `mesh` must come from `uvf_mesh_new` and not have been freed.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_free(mesh: *mut UvfMesh) {
    if !mesh.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| drop(unsafe { Box::from_raw(mesh) })));
    }
}

/// Copies the triangles of the handle (3 vertex indices each, `info.triangles` of them) into
/// `triangles_out`, which holds `capacity` elements.
///
/// # Safety
/// `mesh` a live handle or NULL; `triangles_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_copy_triangles(
    mesh: *const UvfMesh,
    triangles_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let m = unsafe { handle(mesh) }?;
        let flat: Vec<u32> = m.mesh.triangles().iter().flatten().copied().collect();
        super::copy_out(&flat, triangles_out, capacity, "triangles_out")
    })
}

/// Copies the input face of each triangle (`info.triangles` elements) into `faces_out`.
///
/// # Safety
/// `mesh` a live handle or NULL; `faces_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_copy_triangle_faces(
    mesh: *const UvfMesh,
    faces_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let m = unsafe { handle(mesh) }?;
        super::copy_out(&m.triangle_face, faces_out, capacity, "faces_out")
    })
}

/// Maps per-triangle-corner UVs (6 doubles per triangle, as `uvf_mesh_unwrap`'s layout gives
/// them) to the input's face corners: 2 doubles per input corner, in the order of the input's
/// index list, into `face_corner_uv_out` (capacity in doubles). A polygon cut by a seam along
/// one of its triangulation's diagonals has two UVs at a corner; the first triangle's is kept.
///
/// # Safety
/// `mesh` a live handle or NULL; `corner_uv` must hold `corner_uv_count` doubles and
/// `face_corner_uv_out` `capacity` doubles.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_face_corner_uv(
    mesh: *const UvfMesh,
    corner_uv: *const f64,
    corner_uv_count: usize,
    face_corner_uv_out: *mut f64,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let m = unsafe { handle(mesh) }?;
        let needed = checked_count(m.mesh.triangle_count(), 6, "corner uv")?;
        if corner_uv_count != needed {
            return Err(Error::InvalidArgument(format!(
                "corner_uv_count is {corner_uv_count} but the mesh has {} triangles: 6 doubles each, {needed}",
                m.mesh.triangle_count()
            )));
        }
        let input = borrow_slice(corner_uv, corner_uv_count, "corner_uv")?;
        let mut out = vec![f64::NAN; checked_count(m.corner_count, 2, "face corner uv")?];
        let mut seen = vec![false; m.corner_count];
        for (k, &corner) in m.triangle_corner.iter().enumerate() {
            if !std::mem::replace(&mut seen[corner], true) {
                out[2 * corner..2 * corner + 2].copy_from_slice(&input[2 * k..2 * k + 2]);
            }
        }
        super::copy_out(&out, face_corner_uv_out, capacity, "face_corner_uv_out")
    })
}

/// The live handle behind `mesh`.
///
/// # Safety
/// `mesh` must be NULL or a live handle.
pub(crate) unsafe fn handle<'a>(mesh: *const UvfMesh) -> Result<&'a UvfMesh> {
    // SAFETY: the caller passes a handle from `uvf_mesh_new` not yet freed, or NULL.
    unsafe { mesh.as_ref() }.ok_or_else(|| Error::InvalidArgument("mesh handle is NULL".into()))
}

/// Reads the description's arrays, triangulates the faces and validates the result.
///
/// # Safety
/// The description's arrays must hold what it says.
unsafe fn build(d: &UvfMeshDesc) -> Result<UvfMesh> {
    let flat = unsafe { read_positions(d) }?;
    let vertex_count = flat.len() / 3;
    let sizes: Vec<u32> = if d.face_sizes.is_null() {
        vec![3; d.face_count]
    } else {
        borrow_slice(d.face_sizes, d.face_count, "face_sizes")?.to_vec()
    };
    let corner_count = sizes.iter().try_fold(0usize, |sum, &n| sum.checked_add(n as usize));
    let corner_count = corner_count.ok_or(Error::SizeOverflow { what: "face corner", count: d.face_count })?;
    let indices = unsafe { read_indices(d, corner_count) }?;
    let mut triangles = Vec::with_capacity(3 * corner_count.saturating_sub(2 * sizes.len()));
    let mut triangle_face = Vec::with_capacity(triangles.capacity() / 3);
    let mut triangle_corner = Vec::with_capacity(triangles.capacity());
    let mut start = 0usize;
    for (face, &n) in sizes.iter().enumerate() {
        let n = n as usize;
        if n < 3 {
            return Err(Error::InvalidFace {
                face,
                problem: Box::new(Error::InvalidArgument(format!("it has {n} corners; a face needs at least 3"))),
            });
        }
        let corners = &indices[start..start + n];
        if let Some(&v) = corners.iter().find(|&&v| v as usize >= vertex_count) {
            let problem = format!("it uses vertex {v} but the mesh has {vertex_count} vertices");
            return Err(Error::InvalidFace { face, problem: Box::new(Error::InvalidArgument(problem)) });
        }
        let order = if n == 3 {
            vec![[0, 1, 2]]
        } else {
            let ring: Vec<[f64; 3]> =
                corners.iter().map(|&v| std::array::from_fn(|k| flat[3 * v as usize + k])).collect();
            polygon::triangulate(&ring)
        };
        for tri in order {
            triangles.extend(tri.map(|c| corners[c]));
            triangle_corner.extend(tri.map(|c| start + c));
            triangle_face.push(u32::try_from(face).map_err(|_| Error::SizeOverflow { what: "face", count: face })?);
        }
        start += n;
    }
    let polygons = !d.face_sizes.is_null();
    let mesh = TriMesh::new(&flat, &triangles).map_err(|e| in_face_terms(e, polygons, &triangle_face))?;
    Ok(UvfMesh { mesh, triangle_face, triangle_corner, corner_count })
}

/// A validation error of the triangulated mesh, named by the input face its first triangle
/// comes from when the input was polygons.
fn in_face_terms(error: Error, polygons: bool, triangle_face: &[u32]) -> Error {
    let triangle = match &error {
        Error::RepeatedVertex { triangle, .. }
        | Error::DegenerateTriangle { triangle, .. }
        | Error::DuplicateTriangle { triangle, .. }
        | Error::IndexOutOfRange { triangle, .. } => Some(*triangle),
        Error::InconsistentOrientation { first, .. } => Some(*first),
        Error::NonManifoldEdge { triangles, .. } => triangles.first().copied(),
        _ => None,
    };
    match triangle.and_then(|t| triangle_face.get(t)) {
        Some(&face) if polygons => Error::InvalidFace { face: face as usize, problem: Box::new(error) },
        _ => error,
    }
}

/// The description's vertex positions, 3 doubles per vertex.
///
/// # Safety
/// `d.positions` must hold `vertex_count` vertices at `position_stride`.
unsafe fn read_positions(d: &UvfMeshDesc) -> Result<Vec<f64>> {
    let scalar = match d.position_type {
        UVF_SCALAR_DOUBLE => 8,
        UVF_SCALAR_FLOAT => 4,
        t => return Err(Error::InvalidArgument(format!("unknown position_type {t}; use UVF_SCALAR_*"))),
    };
    let stride = strided(d.position_stride, 3 * scalar, d.vertex_count, "position")?;
    if d.vertex_count > 0 && d.positions.is_null() {
        return Err(Error::InvalidArgument(format!("positions is NULL but vertex_count is {}", d.vertex_count)));
    }
    let base = d.positions as *const u8;
    let count = checked_count(d.vertex_count, 3, "vertex")?;
    Ok((0..count)
        .map(|i| {
            // SAFETY: the caller promises vertex_count vertices at this stride; unaligned reads.
            unsafe {
                let at = base.add((i / 3) * stride + (i % 3) * scalar);
                if scalar == 8 {
                    (at as *const f64).read_unaligned()
                } else {
                    f64::from((at as *const f32).read_unaligned())
                }
            }
        })
        .collect())
}

/// The description's `count` vertex indices.
///
/// # Safety
/// `d.indices` must hold `count` indices at `index_stride`.
unsafe fn read_indices(d: &UvfMeshDesc, count: usize) -> Result<Vec<u32>> {
    let size = match d.index_type {
        UVF_INDEX_UINT32 => 4,
        UVF_INDEX_UINT16 => 2,
        t => return Err(Error::InvalidArgument(format!("unknown index_type {t}; use UVF_INDEX_*"))),
    };
    let stride = strided(d.index_stride, size, count, "index")?;
    if count > 0 && d.indices.is_null() {
        return Err(Error::InvalidArgument(format!("indices is NULL but the faces have {count} corners")));
    }
    let base = d.indices as *const u8;
    Ok((0..count)
        .map(|k| {
            // SAFETY: the caller promises `count` indices at this stride; unaligned reads.
            unsafe {
                let at = base.add(k * stride);
                if size == 4 {
                    (at as *const u32).read_unaligned()
                } else {
                    u32::from((at as *const u16).read_unaligned())
                }
            }
        })
        .collect())
}

/// The byte stride of `count` elements of `element` bytes (`given`, or packed when 0), checked
/// against the element size and the address space.
fn strided(given: usize, element: usize, count: usize, what: &'static str) -> Result<usize> {
    let stride = if given == 0 { element } else { given };
    if stride < element {
        return Err(Error::InvalidArgument(format!("{what}_stride is {given} bytes but one {what} takes {element}")));
    }
    let span = count.checked_sub(1).map_or(Some(0), |last| last.checked_mul(stride)?.checked_add(element));
    match span {
        Some(bytes) if bytes <= isize::MAX as usize => Ok(stride),
        _ => Err(Error::SizeOverflow { what, count }),
    }
}
