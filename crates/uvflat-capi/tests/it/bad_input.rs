//! Bad input through the C ABI, one test per class, called from Rust with raw pointers exactly
//! as a C caller would (DESIGN.md, "C ABI conventions").
//!
//! Every test checks:
//! - the exact `UvfStatus`;
//! - that `uvf_last_error_message()` names the offending element (triangle, vertex, edge, count,
//!   field) and the problem;
//! - that the output array or struct is untouched on failure (it is filled with a sentinel first);
//! - for mesh defects, that `uvf_mesh_info`, `uvf_natural_conformal_map` and
//!   `uvf_fixed_boundary_map` agree (same validation, same message).
//!
//! `distinct_classes_give_distinct_messages` then checks that no two classes share a message
//! template (the message with its numbers blanked out).
//!
//! Meshes: a 4×4-vertex wavy grid (`grid()`, 16 vertices, 18 triangles, cell (i, j) split into
//! triangles 2c = [a, b, c] and 2c+1 = [a, c, d] with c = 3j + i) with one defect each, plus
//! `closed_g0_cow.obj`, `holes_punctured_torus.obj` and the `bad_*`/`realbad_*` files of the
//! shared collection.

use std::ffi::CStr;
use std::os::raw::{c_int, c_void};
use uvflat_test_support::meshes;

use uvflat::barycentric::{uvf_fixed_boundary_map, UvfFixedBoundaryOptions, UVF_BOUNDARY_GIVEN, UVF_WEIGHTS_INTRINSIC};
use uvflat::conformal::{uvf_natural_conformal_map, UvfNaturalConformalOptions};
use uvflat::errors::uvf_last_error_message;
use uvflat::mesh::{uvf_mesh_info, UvfMeshInfo};
use uvflat::metrics::{uvf_metrics, UvfMetrics};
use uvflat::UvfStatus::{self, *};

/// A NaN with a payload no computation produces: a double that still has these bits after a
/// call was not written.
const SENTINEL: u64 = 0x7ff4_dead_beef_0bad;

// ---------------------------------------------------------------------------------------------
// Meshes

#[derive(Clone)]
struct Raw {
    positions: Vec<f64>,
    triangles: Vec<u32>,
}

impl Raw {
    fn nv(&self) -> usize {
        self.positions.len() / 3
    }
    fn nt(&self) -> usize {
        self.triangles.len() / 3
    }
    fn push_vertex(&mut self, p: [f64; 3]) -> u32 {
        self.positions.extend(p);
        (self.nv() - 1) as u32
    }
    fn push_triangle(&mut self, t: [u32; 3]) -> usize {
        self.triangles.extend(t);
        self.nt() - 1
    }
    fn triangle(&self, t: usize) -> [u32; 3] {
        [self.triangles[3 * t], self.triangles[3 * t + 1], self.triangles[3 * t + 2]]
    }
    fn set_triangle(&mut self, t: usize, tri: [u32; 3]) {
        self.triangles[3 * t..3 * t + 3].copy_from_slice(&tri);
    }
}

/// 4×4 vertices on a gently curved grid, vertex (i, j) = 4j + i, counter-clockwise triangles.
fn grid() -> Raw {
    let mut positions = Vec::new();
    for j in 0..4 {
        for i in 0..4 {
            let (x, y) = (i as f64, j as f64);
            positions.extend([x, y, 0.1 * (x * 0.9).sin() * (y * 0.7).cos()]);
        }
    }
    let mut triangles = Vec::new();
    for j in 0..3u32 {
        for i in 0..3u32 {
            let (a, b, c, d) = (4 * j + i, 4 * j + i + 1, 4 * (j + 1) + i + 1, 4 * (j + 1) + i);
            triangles.extend([a, b, c, a, c, d]);
        }
    }
    Raw { positions, triangles }
}

fn load(file: &str) -> Raw {
    let obj = meshes::read(file);
    Raw { positions: obj.positions, triangles: obj.triangles }
}

// ---------------------------------------------------------------------------------------------
// Calls

fn last_message() -> String {
    // SAFETY: uvflat returns a valid NUL-terminated string, valid until its next call.
    unsafe { CStr::from_ptr(uvf_last_error_message()) }.to_string_lossy().into_owned()
}

#[derive(Debug, Clone, PartialEq)]
struct Outcome {
    status: UvfStatus,
    message: String,
}

fn sentinel_buffer(len: usize) -> Vec<f64> {
    vec![f64::from_bits(SENTINEL); len]
}

fn untouched(buffer: &[f64]) -> bool {
    buffer.iter().all(|x| x.to_bits() == SENTINEL)
}

fn bytes_of<T: Copy>(x: &T) -> Vec<u8> {
    // SAFETY: reading the bytes of a plain-old-data struct without padding.
    unsafe { std::slice::from_raw_parts(x as *const T as *const u8, std::mem::size_of::<T>()) }.to_vec()
}

/// Raw pointers and counts of one call (counts may lie about the arrays, which is the point).
#[derive(Clone, Copy)]
struct Args {
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
}

impl Args {
    fn of(raw: &Raw) -> Args {
        Args {
            positions: raw.positions.as_ptr(),
            vertex_count: raw.nv(),
            triangles: raw.triangles.as_ptr(),
            triangle_count: raw.nt(),
        }
    }
    /// Room for the UV output: 2 per vertex, but never more than a small buffer for the lying
    /// counts (those calls must fail before writing anything).
    fn uv_len(&self) -> usize {
        2 * self.vertex_count.min(100_000)
    }
}

/// `uvf_mesh_info`, checking that `info_out` is untouched on failure.
fn info(a: Args) -> (Outcome, UvfMeshInfo) {
    let sentinel = UvfMeshInfo {
        struct_size: std::mem::size_of::<UvfMeshInfo>(),
        vertices: 0xdead,
        referenced_vertices: 0xdead,
        triangles: 0xdead,
        edges: 0xdead,
        components: 0xdead,
        boundary_loops: 0xdead,
        boundary_vertices: 0xdead,
        euler_characteristic: -0xdead,
        genus: -0xdead,
    };
    let mut out = sentinel;
    // SAFETY: the arrays hold what the counts say, except in the tests of lying counts, which
    // uvflat must reject before reading.
    let status = unsafe { uvf_mesh_info(a.positions, a.vertex_count, a.triangles, a.triangle_count, &mut out) };
    let outcome = Outcome { status, message: last_message() };
    if status != UVF_OK {
        assert_eq!(
            bytes_of(&out),
            bytes_of(&sentinel),
            "uvf_mesh_info wrote info_out although it failed ({outcome:?})"
        );
    }
    (outcome, out)
}

/// `uvf_natural_conformal_map` into a sentinel-filled buffer; checks it is untouched on failure.
fn conformal(a: Args, options: Option<&UvfNaturalConformalOptions>) -> (Outcome, Vec<f64>) {
    let mut uv = sentinel_buffer(a.uv_len());
    let o = options.map_or(std::ptr::null(), |o| o as *const _);
    // SAFETY: as in `info`; `uv` holds 2 doubles per vertex whenever the call can succeed.
    let status = unsafe {
        uvf_natural_conformal_map(a.positions, a.vertex_count, a.triangles, a.triangle_count, o, uv.as_mut_ptr())
    };
    let outcome = Outcome { status, message: last_message() };
    if status != UVF_OK {
        assert!(untouched(&uv), "uvf_natural_conformal_map wrote uv_out although it failed ({outcome:?})");
    }
    (outcome, uv)
}

/// `uvf_fixed_boundary_map` into a sentinel-filled buffer; checks it is untouched on failure.
fn fixed(a: Args, options: Option<&UvfFixedBoundaryOptions>) -> (Outcome, Vec<f64>) {
    let mut uv = sentinel_buffer(a.uv_len());
    let o = options.map_or(std::ptr::null(), |o| o as *const _);
    // SAFETY: as in `conformal`.
    let status = unsafe {
        uvf_fixed_boundary_map(a.positions, a.vertex_count, a.triangles, a.triangle_count, o, uv.as_mut_ptr())
    };
    let outcome = Outcome { status, message: last_message() };
    if status != UVF_OK {
        assert!(untouched(&uv), "uvf_fixed_boundary_map wrote uv_out although it failed ({outcome:?})");
    }
    (outcome, uv)
}

/// `uvf_metrics` with per-vertex UVs (`uv_triangles` NULL) unless given; checks `out` is
/// untouched on failure.
fn metrics(a: Args, uv: *const f64, uv_count: usize, uv_triangles: *const u32) -> (Outcome, UvfMetrics) {
    let bits = f64::from_bits(SENTINEL);
    let sentinel = UvfMetrics {
        struct_size: std::mem::size_of::<UvfMetrics>(),
        triangles: 0xdead,
        flipped: 0xdead,
        degenerate_uv: 0xdead,
        boundary_intersections: 0xdead,
        stretch_l2: bits,
        stretch_linf: bits,
        conformal_mean: bits,
        conformal_max: bits,
        angle_mean: bits,
        angle_max: bits,
        area_mean: bits,
        area_max: bits,
    };
    let mut out = sentinel;
    // SAFETY: as in `info`.
    let status = unsafe {
        uvf_metrics(a.positions, a.vertex_count, a.triangles, a.triangle_count, uv, uv_count, uv_triangles, &mut out)
    };
    let outcome = Outcome { status, message: last_message() };
    if status != UVF_OK {
        assert_eq!(bytes_of(&out), bytes_of(&sentinel), "uvf_metrics wrote out although it failed ({outcome:?})");
    }
    (outcome, out)
}

fn assert_outcome(what: &str, o: &Outcome, status: UvfStatus, needles: &[&str]) {
    assert_eq!(o.status, status, "{what}: expected {status:?}, got {:?} with message {:?}", o.status, o.message);
    for needle in needles {
        assert!(o.message.contains(needle), "{what}: message {:?} does not contain {needle:?}", o.message);
    }
}

/// A mesh defect: all three mesh-consuming functions must fail with `status`, the same message,
/// containing every needle, and leave their outputs untouched. Returns the message.
fn expect_mesh_error(what: &str, a: Args, status: UvfStatus, needles: &[&str]) -> String {
    let (i, _) = info(a);
    let (c, _) = conformal(a, None);
    let (f, _) = fixed(a, None);
    assert_outcome(&format!("{what} (uvf_mesh_info)"), &i, status, needles);
    assert_outcome(&format!("{what} (uvf_natural_conformal_map)"), &c, status, needles);
    assert_outcome(&format!("{what} (uvf_fixed_boundary_map)"), &f, status, needles);
    assert_eq!(i.message, c.message, "{what}: uvf_mesh_info and uvf_natural_conformal_map disagree");
    assert_eq!(i.message, f.message, "{what}: uvf_mesh_info and uvf_fixed_boundary_map disagree");
    i.message
}

/// A valid mesh whose topology the methods do not support: `uvf_mesh_info` succeeds, both
/// methods fail with `UVF_UNSUPPORTED_TOPOLOGY`. Returns the methods' message and the info.
fn expect_unsupported(what: &str, raw: &Raw, needles: &[&str]) -> (String, UvfMeshInfo) {
    let a = Args::of(raw);
    let (i, info) = info(a);
    assert_outcome(&format!("{what} (uvf_mesh_info)"), &i, UVF_OK, &[]);
    assert_eq!(i.message, "", "{what}: the message must be empty after a success");
    let (c, _) = conformal(a, None);
    let (f, _) = fixed(a, None);
    assert_outcome(&format!("{what} (uvf_natural_conformal_map)"), &c, UVF_UNSUPPORTED_TOPOLOGY, needles);
    assert_outcome(&format!("{what} (uvf_fixed_boundary_map)"), &f, UVF_UNSUPPORTED_TOPOLOGY, needles);
    assert_eq!(c.message, f.message, "{what}: the two methods report the topology differently");
    (c.message, info)
}

// ---------------------------------------------------------------------------------------------
// One function per class; each returns (class, message) pairs for the distinctness test.

type Messages = Vec<(&'static str, String)>;

fn class_index_out_of_range() -> Messages {
    let mut out = Vec::new();
    for bad in [16u32, 99, u32::MAX] {
        let mut m = grid();
        let mut t = m.triangle(7);
        t[1] = bad;
        m.set_triangle(7, t);
        let needle = format!("triangle 7 references vertex {bad} but the mesh has 16 vertices");
        out.push((
            "index out of range",
            expect_mesh_error("index out of range", Args::of(&m), UVF_INVALID_MESH, &[&needle]),
        ));
        // uvf_metrics does not need a manifold mesh but does check indices.
        let uv = vec![0.5; 32];
        let (o, _) = metrics(Args::of(&m), uv.as_ptr(), 16, std::ptr::null());
        assert_outcome(
            "index out of range (uvf_metrics)",
            &o,
            UVF_INVALID_ARGUMENT,
            &[&format!("triangle 7 references vertex {bad}")],
        );
        out.push(("index out of range", o.message));
    }
    out
}

fn class_non_finite_coordinate() -> Messages {
    let mut out = Vec::new();
    for (vertex, axis, value, text) in
        [(5usize, 1usize, f64::NAN, "NaN"), (9, 2, f64::INFINITY, "inf"), (12, 0, f64::NEG_INFINITY, "-inf")]
    {
        let mut m = grid();
        m.positions[3 * vertex + axis] = value;
        let needle = format!("vertex {vertex} has a non-finite coordinate ({text})");
        out.push((
            "non-finite coordinate",
            expect_mesh_error("non-finite coordinate", Args::of(&m), UVF_INVALID_MESH, &[&needle]),
        ));
        let uv = vec![0.5; 32];
        let (o, _) = metrics(Args::of(&m), uv.as_ptr(), 16, std::ptr::null());
        assert_outcome(
            "non-finite position (uvf_metrics)",
            &o,
            UVF_INVALID_ARGUMENT,
            &[&format!("position of vertex {vertex} is not finite")],
        );
        out.push(("non-finite coordinate", o.message));
        // A non-finite UV is the metrics' counterpart.
        let g = grid();
        let mut uv: Vec<f64> = g.positions.chunks(3).flat_map(|p| [p[0], p[1]]).collect();
        uv[2 * vertex + axis.min(1)] = value;
        let (o, _) = metrics(Args::of(&g), uv.as_ptr(), 16, std::ptr::null());
        assert_outcome(
            "non-finite uv (uvf_metrics)",
            &o,
            UVF_INVALID_ARGUMENT,
            &[&format!("uv {vertex} is not finite")],
        );
        out.push(("non-finite uv", o.message));
    }
    out
}

fn class_degenerate_triangle() -> Messages {
    let mut out = Vec::new();
    for (label, third) in [
        ("collinear", [2.0, 0.0, 5.0]),
        ("near-zero area (relative area 5e-14)", [0.5, 1e-13, 5.0]),
        ("two coincident vertices", [0.0, 0.0, 5.0]),
    ] {
        let mut m = grid();
        let a = m.push_vertex([0.0, 0.0, 5.0]);
        let b = m.push_vertex([1.0, 0.0, 5.0]);
        let c = m.push_vertex(third);
        let t = m.push_triangle([a, b, c]);
        assert_eq!(t, 18);
        let what = format!("degenerate triangle, {label}");
        out.push((
            "degenerate triangle",
            expect_mesh_error(&what, Args::of(&m), UVF_INVALID_MESH, &["triangle 18 is degenerate"]),
        ));
    }
    // A thin but valid needle (relative area 5e-9) is accepted.
    let mut m = grid();
    let a = m.push_vertex([0.0, 0.0, 5.0]);
    let b = m.push_vertex([1.0, 0.0, 5.0]);
    let c = m.push_vertex([0.5, 1e-8, 5.0]);
    m.push_triangle([a, b, c]);
    let (o, info) = info(Args::of(&m));
    assert_outcome("thin needle", &o, UVF_OK, &[]);
    assert_eq!(info.components, 2);
    out
}

fn class_repeated_vertex() -> Messages {
    let mut out = Vec::new();
    for tri in [[5, 9, 5], [5, 5, 9], [9, 5, 5]] {
        let mut m = grid();
        m.set_triangle(4, tri);
        out.push((
            "repeated vertex",
            expect_mesh_error(
                "repeated vertex",
                Args::of(&m),
                UVF_INVALID_MESH,
                &["triangle 4 uses vertex 5 more than once"],
            ),
        ));
    }
    out
}

fn class_duplicate_triangle() -> Messages {
    let mut out = Vec::new();
    for (label, rotate, reverse) in
        [("same orientation", 0, false), ("same orientation, rotated", 1, false), ("opposite orientation", 0, true)]
    {
        let mut m = grid();
        let mut t = m.triangle(6);
        t.rotate_left(rotate);
        if reverse {
            t.swap(1, 2);
        }
        m.push_triangle(t);
        let what = format!("duplicate triangle, {label}");
        out.push((
            "duplicate triangle",
            expect_mesh_error(
                &what,
                Args::of(&m),
                UVF_INVALID_MESH,
                &["triangle 18 uses the same three vertices as triangle 6"],
            ),
        ));
    }
    out
}

fn class_non_manifold_edge() -> Messages {
    // Edge (5, 10) is the diagonal of cell (1, 1), shared by triangles 8 = [5, 6, 10] and
    // 9 = [5, 10, 9]; a fin [5, 10, 16] makes it a three-triangle edge.
    let mut m = grid();
    let apex = m.push_vertex([1.5, 1.5, 1.0]);
    m.push_triangle([5, 10, apex]);
    let message = expect_mesh_error(
        "non-manifold edge",
        Args::of(&m),
        UVF_INVALID_MESH,
        &["edge (5, 10) is non-manifold", "shared by 3 triangles [8, 9, 18]"],
    );
    vec![("non-manifold edge", message)]
}

fn class_non_manifold_vertex() -> Messages {
    // A triangle touching the grid only at its corner vertex 15: a bow-tie.
    let mut m = grid();
    let a = m.push_vertex([4.0, 3.5, 0.0]);
    let b = m.push_vertex([3.5, 4.0, 0.0]);
    m.push_triangle([15, a, b]);
    let message = expect_mesh_error(
        "bow-tie vertex",
        Args::of(&m),
        UVF_INVALID_MESH,
        &["vertex 15 is non-manifold", "2 separate fans"],
    );
    vec![("non-manifold vertex", message)]
}

fn class_inconsistent_orientation() -> Messages {
    // Triangle 9 = [5, 10, 9] reversed; triangle 6 = [4, 5, 9] also runs 5 → 9.
    let mut m = grid();
    m.set_triangle(9, [5, 9, 10]);
    let message = expect_mesh_error(
        "inconsistent orientation",
        Args::of(&m),
        UVF_INVALID_MESH,
        &["triangles 6 and 9 are inconsistently oriented", "edge (5, 9)"],
    );
    vec![("inconsistent orientation", message)]
}

fn class_empty_mesh() -> Messages {
    let mut out = Vec::new();
    let g = grid();
    for (label, a) in [
        ("no triangles, valid pointers", Args { triangle_count: 0, ..Args::of(&g) }),
        ("no triangles, NULL triangles", Args { triangles: std::ptr::null(), triangle_count: 0, ..Args::of(&g) }),
        (
            "nothing at all, NULL pointers",
            Args { positions: std::ptr::null(), vertex_count: 0, triangles: std::ptr::null(), triangle_count: 0 },
        ),
    ] {
        out.push((
            "empty mesh",
            expect_mesh_error(&format!("empty mesh, {label}"), a, UVF_INVALID_MESH, &["no triangles"]),
        ));
        let uv = vec![0.5; 2 * a.vertex_count];
        let (o, _) = metrics(a, uv.as_ptr(), a.vertex_count, std::ptr::null());
        assert_outcome(&format!("empty mesh, {label} (uvf_metrics)"), &o, UVF_INVALID_ARGUMENT, &["no triangles"]);
        out.push(("empty mesh", o.message));
    }
    out
}

fn class_size_overflow() -> Messages {
    let mut out = Vec::new();
    let g = grid();
    let ok = Args::of(&g);
    let huge_vertices = usize::MAX / 2;
    let bytes_overflow = usize::MAX / 24 + 1; // ×3 fits in usize, ×3×8 bytes does not fit in isize
    for (label, a, needle) in [
        (
            "vertex_count = usize::MAX / 2",
            Args { vertex_count: huge_vertices, ..ok },
            format!("vertex count {huge_vertices} is too large"),
        ),
        (
            "vertex_count whose byte size overflows",
            Args { vertex_count: bytes_overflow, ..ok },
            format!("positions count {} is too large", 3 * bytes_overflow),
        ),
        (
            "triangle_count = usize::MAX / 2",
            Args { triangle_count: usize::MAX / 2, ..ok },
            format!("triangle count {} is too large", usize::MAX / 2),
        ),
        (
            "triangle_count = usize::MAX",
            Args { triangle_count: usize::MAX, ..ok },
            format!("triangle count {} is too large", usize::MAX),
        ),
    ] {
        out.push((
            "size overflow",
            expect_mesh_error(&format!("size overflow, {label}"), a, UVF_INVALID_ARGUMENT, &[&needle]),
        ));
    }
    let uv = vec![0.5; 32];
    let (o, _) = metrics(ok, uv.as_ptr(), usize::MAX, ok.triangles);
    assert_outcome(
        "size overflow, uv_count (uvf_metrics)",
        &o,
        UVF_INVALID_ARGUMENT,
        &[&format!("uv count {} is too large", usize::MAX)],
    );
    out.push(("size overflow", o.message));
    // A boundary given with an overflowing count.
    let vertices = [0u32, 1, 2];
    let given_uv = [0.0; 6];
    let mut options = UvfFixedBoundaryOptions { boundary: UVF_BOUNDARY_GIVEN, ..Default::default() };
    options.given_count = usize::MAX / 2;
    options.given_vertices = vertices.as_ptr();
    options.given_uv = given_uv.as_ptr();
    let (o, _) = fixed(ok, Some(&options));
    assert_outcome(
        "size overflow, given_count",
        &o,
        UVF_INVALID_ARGUMENT,
        &[&format!("given_vertices count {} is too large", usize::MAX / 2)],
    );
    out.push(("size overflow", o.message));
    out
}

fn class_null_pointer() -> Messages {
    let mut out = Vec::new();
    let g = grid();
    let ok = Args::of(&g);
    for (label, a, needle) in [
        ("positions", Args { positions: std::ptr::null(), ..ok }, "positions is NULL but its count is 48"),
        ("triangles", Args { triangles: std::ptr::null(), ..ok }, "triangles is NULL but its count is 54"),
    ] {
        out.push(("NULL pointer", expect_mesh_error(&format!("NULL {label}"), a, UVF_INVALID_ARGUMENT, &[needle])));
    }
    // NULL outputs.
    // SAFETY: valid mesh arrays, NULL output.
    let status =
        unsafe { uvf_mesh_info(ok.positions, ok.vertex_count, ok.triangles, ok.triangle_count, std::ptr::null_mut()) };
    let o = Outcome { status, message: last_message() };
    assert_outcome("NULL info_out", &o, UVF_INVALID_ARGUMENT, &["info_out is NULL"]);
    out.push(("NULL pointer", o.message));
    // SAFETY: valid mesh arrays, NULL output.
    let status = unsafe {
        uvf_natural_conformal_map(
            ok.positions,
            ok.vertex_count,
            ok.triangles,
            ok.triangle_count,
            std::ptr::null(),
            std::ptr::null_mut(),
        )
    };
    let o = Outcome { status, message: last_message() };
    assert_outcome(
        "NULL uv_out (natural conformal)",
        &o,
        UVF_INVALID_ARGUMENT,
        &["uv_out is NULL but 32 elements must be written"],
    );
    out.push(("NULL pointer", o.message));
    // SAFETY: valid mesh arrays, NULL output.
    let status = unsafe {
        uvf_fixed_boundary_map(
            ok.positions,
            ok.vertex_count,
            ok.triangles,
            ok.triangle_count,
            std::ptr::null(),
            std::ptr::null_mut(),
        )
    };
    let o = Outcome { status, message: last_message() };
    assert_outcome(
        "NULL uv_out (fixed boundary)",
        &o,
        UVF_INVALID_ARGUMENT,
        &["uv_out is NULL but 32 elements must be written"],
    );
    out.push(("NULL pointer", o.message));
    // uvf_metrics: NULL uv, NULL out.
    let (o, _) = metrics(ok, std::ptr::null(), 16, std::ptr::null());
    assert_outcome("NULL uv (uvf_metrics)", &o, UVF_INVALID_ARGUMENT, &["uv is NULL but its count is 32"]);
    out.push(("NULL pointer", o.message));
    let uv = vec![0.5; 32];
    // SAFETY: valid arrays, NULL output.
    let status = unsafe {
        uvf_metrics(
            ok.positions,
            ok.vertex_count,
            ok.triangles,
            ok.triangle_count,
            uv.as_ptr(),
            16,
            std::ptr::null(),
            std::ptr::null_mut(),
        )
    };
    let o = Outcome { status, message: last_message() };
    assert_outcome("NULL out (uvf_metrics)", &o, UVF_INVALID_ARGUMENT, &["out is NULL"]);
    out.push(("NULL pointer", o.message));
    // A given boundary with NULL arrays.
    let options = UvfFixedBoundaryOptions { boundary: UVF_BOUNDARY_GIVEN, given_count: 12, ..Default::default() };
    let (o, _) = fixed(ok, Some(&options));
    assert_outcome("NULL given_vertices", &o, UVF_INVALID_ARGUMENT, &["given_vertices is NULL but its count is 12"]);
    out.push(("NULL pointer", o.message));
    out
}

fn class_unaligned_pointer() -> Messages {
    let mut out = Vec::new();
    let g = grid();
    // Copies of the arrays starting one byte into a buffer.
    let mut pbytes = vec![0u8; 8 * g.positions.len() + 8];
    for (k, x) in g.positions.iter().enumerate() {
        pbytes[1 + 8 * k..9 + 8 * k].copy_from_slice(&x.to_ne_bytes());
    }
    let mut tbytes = vec![0u8; 4 * g.triangles.len() + 4];
    for (k, x) in g.triangles.iter().enumerate() {
        tbytes[2 + 4 * k..6 + 4 * k].copy_from_slice(&x.to_ne_bytes());
    }
    let ok = Args::of(&g);
    let unaligned_positions = pbytes[1..].as_ptr() as *const f64;
    let unaligned_triangles = tbytes[2..].as_ptr() as *const u32;
    assert!(unaligned_positions as usize % 8 != 0 && unaligned_triangles as usize % 4 != 0);
    for (label, a, needle) in [
        ("positions", Args { positions: unaligned_positions, ..ok }, "positions is not aligned"),
        ("triangles", Args { triangles: unaligned_triangles, ..ok }, "triangles is not aligned"),
    ] {
        out.push((
            "unaligned pointer",
            expect_mesh_error(&format!("unaligned {label}"), a, UVF_INVALID_ARGUMENT, &[needle]),
        ));
    }
    // An unaligned output: nothing may be written through it.
    let mut obytes = vec![0xabu8; 8 * 32 + 8];
    let unaligned_out = obytes[3..].as_mut_ptr() as *mut f64;
    // SAFETY: valid mesh arrays; the output is rejected before any write.
    let status = unsafe {
        uvf_natural_conformal_map(
            ok.positions,
            ok.vertex_count,
            ok.triangles,
            ok.triangle_count,
            std::ptr::null(),
            unaligned_out,
        )
    };
    let o = Outcome { status, message: last_message() };
    assert_outcome("unaligned uv_out", &o, UVF_INVALID_ARGUMENT, &["uv_out is not aligned"]);
    assert!(obytes.iter().all(|&b| b == 0xab), "an unaligned uv_out was written to");
    out.push(("unaligned pointer", o.message));
    out
}

fn class_options_too_small() -> Messages {
    let mut out = Vec::new();
    let g = grid();
    let a = Args::of(&g);
    let fixed_size = std::mem::size_of::<UvfFixedBoundaryOptions>();
    let conformal_size = std::mem::size_of::<UvfNaturalConformalOptions>();
    for size in [0usize, 8, fixed_size - 1] {
        let options = UvfFixedBoundaryOptions { struct_size: size, ..Default::default() };
        let (o, _) = fixed(a, Some(&options));
        let needle = format!("UvfFixedBoundaryOptions.struct_size is {size} but must be at least {fixed_size}");
        assert_outcome("fixed-boundary options too small", &o, UVF_INVALID_ARGUMENT, &[&needle]);
        out.push(("options struct_size too small", o.message));
    }
    // A caller compiled against a later header passes a larger struct: accepted, the unknown
    // tail ignored.
    #[repr(C)]
    struct Later<T> {
        known: T,
        added_fields: [u64; 3],
    }
    let later = Later {
        known: UvfFixedBoundaryOptions {
            struct_size: std::mem::size_of::<Later<UvfFixedBoundaryOptions>>(),
            ..Default::default()
        },
        added_fields: [u64::MAX; 3],
    };
    let (o, _) = fixed(a, Some(&later.known));
    assert_outcome("larger fixed-boundary options", &o, UVF_OK, &[]);
    let later = Later {
        known: UvfNaturalConformalOptions {
            struct_size: std::mem::size_of::<Later<UvfNaturalConformalOptions>>(),
            ..Default::default()
        },
        added_fields: [u64::MAX; 3],
    };
    let (o, _) = conformal(a, Some(&later.known));
    assert_outcome("larger natural conformal options", &o, UVF_OK, &[]);
    assert_eq!(later.added_fields, [u64::MAX; 3]);

    for size in [0usize, 8, conformal_size - 1] {
        let options = UvfNaturalConformalOptions { struct_size: size, ..Default::default() };
        let (o, _) = conformal(a, Some(&options));
        let needle = format!("UvfNaturalConformalOptions.struct_size is {size} but must be at least {conformal_size}");
        assert_outcome("natural conformal options too small", &o, UVF_INVALID_ARGUMENT, &[&needle]);
        out.push(("options struct_size too small", o.message));
    }
    out
}

/// A caller-given boundary (`UVF_BOUNDARY_GIVEN`) that does not cover whole boundary loops
/// with finite positions. The grid's boundary loop is its 12 outer vertices.
fn class_bad_given_boundary() -> Messages {
    let mut out = Vec::new();
    let g = grid();
    let a = Args::of(&g);
    let outer: Vec<u32> = vec![0, 1, 2, 3, 7, 11, 15, 14, 13, 12, 8, 4];
    let on_circle = |k: usize| {
        let t = 2.0 * std::f64::consts::PI * k as f64 / 12.0;
        [0.5 + 0.5 * t.cos(), 0.5 + 0.5 * t.sin()]
    };
    let whole: Vec<f64> = (0..12).flat_map(on_circle).collect();
    let cases: [(&'static str, Vec<u32>, Vec<f64>, &str); 6] = [
        (
            "given vertex not on the boundary",
            [outer.clone(), vec![5]].concat(),
            [whole.clone(), vec![0.5, 0.5]].concat(),
            "vertex 5 was given a boundary position but is not on a boundary loop",
        ),
        (
            "given boundary covers part of a loop",
            outer[..3].to_vec(),
            whole[..6].to_vec(),
            "boundary positions must cover whole loops: vertex 3 is on a loop of 12 vertices of which only 3 were given",
        ),
        (
            "given vertex out of range",
            [outer.clone(), vec![99]].concat(),
            [whole.clone(), vec![0.5, 0.5]].concat(),
            "boundary vertex 99 does not exist (the mesh has 16 vertices)",
        ),
        (
            "given position not finite",
            outer.clone(),
            [vec![f64::NAN, 0.0], whole[2..].to_vec()].concat(),
            "boundary vertex 0 was given a non-finite position",
        ),
        ("no given positions", Vec::new(), Vec::new(), "no boundary positions were given"),
        (
            "given vertex twice",
            [outer.clone(), vec![0]].concat(),
            [whole.clone(), vec![5.0, 5.0]].concat(),
            "boundary vertex 0 is given twice",
        ),
    ];
    for (class, vertices, uv, needle) in cases {
        let options = UvfFixedBoundaryOptions {
            boundary: UVF_BOUNDARY_GIVEN,
            given_count: vertices.len(),
            given_vertices: vertices.as_ptr(),
            given_uv: uv.as_ptr(),
            ..Default::default()
        };
        let (o, _) = fixed(a, Some(&options));
        assert_outcome(class, &o, UVF_INVALID_ARGUMENT, &[needle]);
        out.push((class, o.message));
    }
    // The whole loop, given: accepted, and the boundary is where it was put.
    let options = UvfFixedBoundaryOptions {
        boundary: UVF_BOUNDARY_GIVEN,
        given_count: 12,
        given_vertices: outer.as_ptr(),
        given_uv: whole.as_ptr(),
        ..Default::default()
    };
    let (o, uv) = fixed(a, Some(&options));
    assert_outcome("whole loop given", &o, UVF_OK, &[]);
    for (k, &v) in outer.iter().enumerate() {
        assert_eq!([uv[2 * v as usize], uv[2 * v as usize + 1]], on_circle(k), "given boundary vertex {v} moved");
    }
    out
}

fn class_invalid_enum() -> Messages {
    let mut out = Vec::new();
    let g = grid();
    let a = Args::of(&g);
    for (label, options, needle) in [
        ("weights", UvfFixedBoundaryOptions { weights: 99, ..Default::default() }, "unknown weights 99"),
        ("weights", UvfFixedBoundaryOptions { weights: u32::MAX, ..Default::default() }, "unknown weights 4294967295"),
        ("boundary", UvfFixedBoundaryOptions { boundary: 7, ..Default::default() }, "unknown boundary 7"),
        ("distribution", UvfFixedBoundaryOptions { distribution: 5, ..Default::default() }, "unknown distribution 5"),
    ] {
        let (o, _) = fixed(a, Some(&options));
        assert_outcome(&format!("invalid {label}"), &o, UVF_INVALID_ARGUMENT, &[needle]);
        out.push(("invalid enum value", o.message));
    }
    // The intrinsic weights' parameters.
    for (lambda, mu) in [(0.0, 0.0), (f64::NAN, 1.0), (1.0, f64::INFINITY)] {
        let options = UvfFixedBoundaryOptions { weights: UVF_WEIGHTS_INTRINSIC, lambda, mu, ..Default::default() };
        let (o, _) = fixed(a, Some(&options));
        assert_outcome(
            &format!("intrinsic λ = {lambda}, μ = {mu}"),
            &o,
            UVF_INVALID_ARGUMENT,
            &["intrinsic weights need finite λ, μ not both zero"],
        );
        out.push(("invalid intrinsic parameters", o.message));
    }
    out
}

fn pins(vertices: [u32; 2], uv: [f64; 4]) -> UvfNaturalConformalOptions {
    UvfNaturalConformalOptions { pin_count: 2, pin_vertices: vertices, pin_uv: uv, ..Default::default() }
}

fn class_bad_pins() -> Messages {
    let mut out = Vec::new();
    let mut m = grid();
    let unreferenced = m.push_vertex([9.0, 9.0, 9.0]);
    let a = Args::of(&m);
    let cases: [(&'static str, UvfNaturalConformalOptions, String); 6] = [
        (
            "pin count",
            UvfNaturalConformalOptions { pin_count: 1, ..Default::default() },
            "pin_count must be 0 or 2, not 1".into(),
        ),
        (
            "same pin twice",
            pins([3, 3], [0.0, 0.0, 1.0, 0.0]),
            "the two pins must be different vertices (both are 3)".into(),
        ),
        (
            "pin out of range",
            pins([0, 1000], [0.0, 0.0, 1.0, 0.0]),
            format!("pinned vertex 1000 is out of range: the mesh has {} vertices", m.nv()),
        ),
        (
            "pin on unreferenced vertex",
            pins([unreferenced, 0], [0.0, 0.0, 1.0, 0.0]),
            format!("pinned vertex {unreferenced} is not used by any triangle"),
        ),
        (
            "pins at the same position",
            pins([0, 15], [0.5, 0.5, 0.5, 0.5]),
            "the two pins must have different positions".into(),
        ),
        (
            "non-finite pin position",
            pins([0, 15], [0.0, 0.0, f64::NAN, 0.0]),
            "pinned vertex 15 has a non-finite position".into(),
        ),
    ];
    for (class, options, needle) in cases {
        let (o, _) = conformal(a, Some(&options));
        assert_outcome(class, &o, UVF_INVALID_ARGUMENT, &[&needle]);
        out.push((class, o.message));
    }
    out
}

fn class_not_a_disk() -> Messages {
    let mut out = Vec::new();
    let cow = load("closed_g0_cow.obj");
    let (message, info) = expect_unsupported(
        "closed mesh closed_g0_cow.obj",
        &cow,
        &["not a topological disk", "0 boundary loop(s)", "genus 0"],
    );
    assert_eq!((info.boundary_loops, info.genus, info.components), (0, 0, 1), "closed_g0_cow.obj: {info:?}");
    out.push(("not a disk (closed, or genus > 0)", message));

    let mut two = grid();
    let n = two.nv() as u32;
    let copy: Vec<f64> = grid().positions.chunks(3).flat_map(|p| [p[0] + 10.0, p[1], p[2]]).collect();
    two.positions.extend(copy);
    let shifted: Vec<u32> = grid().triangles.iter().map(|&v| v + n).collect();
    two.triangles.extend(shifted);
    let (message, info) = expect_unsupported("two components", &two, &["2 connected components"]);
    assert_eq!(info.components, 2, "two grids: {info:?}");
    out.push(("several components", message));

    let torus = load("holes_punctured_torus.obj");
    let (message, info) = expect_unsupported(
        "genus 1 with a boundary, holes_punctured_torus.obj",
        &torus,
        &["not a topological disk", "1 boundary loop(s)", "genus 1"],
    );
    assert_eq!((info.boundary_loops, info.genus), (1, 1), "holes_punctured_torus.obj: {info:?}");
    out.push(("not a disk (closed, or genus > 0)", message));
    out
}

// ---------------------------------------------------------------------------------------------
// Tests

#[test]
fn index_out_of_range_is_invalid_mesh() {
    class_index_out_of_range();
}

#[test]
fn non_finite_coordinate_is_invalid_mesh() {
    class_non_finite_coordinate();
}

#[test]
fn zero_and_near_zero_area_triangles_are_invalid_mesh() {
    class_degenerate_triangle();
}

#[test]
fn repeated_vertex_in_a_triangle_is_invalid_mesh() {
    class_repeated_vertex();
}

#[test]
fn duplicate_triangle_in_either_orientation_is_invalid_mesh() {
    class_duplicate_triangle();
}

#[test]
fn edge_with_three_triangles_is_invalid_mesh() {
    class_non_manifold_edge();
}

#[test]
fn bow_tie_vertex_is_invalid_mesh() {
    class_non_manifold_vertex();
}

#[test]
fn inconsistently_oriented_neighbours_are_invalid_mesh() {
    class_inconsistent_orientation();
}

#[test]
fn empty_mesh_is_invalid_mesh() {
    class_empty_mesh();
}

#[test]
fn counts_whose_byte_size_overflows_are_invalid_arguments() {
    class_size_overflow();
}

#[test]
fn null_pointers_with_nonzero_counts_are_invalid_arguments() {
    class_null_pointer();
}

#[test]
fn unaligned_pointers_are_invalid_arguments() {
    class_unaligned_pointer();
}

#[test]
fn options_struct_size_too_small_is_invalid_argument() {
    class_options_too_small();
}

#[test]
fn given_boundary_must_cover_whole_loops_with_finite_positions() {
    class_bad_given_boundary();
}

#[test]
fn invalid_enum_values_are_invalid_arguments() {
    class_invalid_enum();
}

#[test]
fn bad_pins_are_invalid_arguments() {
    class_bad_pins();
}

#[test]
fn not_a_disk_is_unsupported_topology() {
    class_not_a_disk();
}

/// Messages with their numbers blanked, so that two variants of one class (another index,
/// NaN or inf) compare equal and two classes only when their wording is the same.
fn template(message: &str) -> String {
    let mut out = String::new();
    let mut in_number = false;
    for ch in message.chars() {
        if ch.is_ascii_digit() {
            if !in_number {
                out.push('#');
            }
            in_number = true;
        } else {
            in_number = false;
            out.push(ch);
        }
    }
    out.replace("-inf", "#").replace("inf", "#").replace("NaN", "#")
}

/// Every class has wording of its own, so a caller (or a support ticket) can tell them apart.
/// Pins out of range and pins on unreferenced vertices are compared separately in
/// `pin_out_of_range_and_pin_on_unreferenced_vertex_have_distinct_messages`.
#[test]
fn distinct_classes_give_distinct_messages() {
    let all: Messages = [
        class_index_out_of_range(),
        class_non_finite_coordinate(),
        class_degenerate_triangle(),
        class_repeated_vertex(),
        class_duplicate_triangle(),
        class_non_manifold_edge(),
        class_non_manifold_vertex(),
        class_inconsistent_orientation(),
        class_empty_mesh(),
        class_size_overflow(),
        class_null_pointer(),
        class_unaligned_pointer(),
        class_options_too_small(),
        class_invalid_enum(),
        class_bad_given_boundary(),
        class_bad_pins(),
        class_not_a_disk(),
    ]
    .concat();
    let mut owner: std::collections::HashMap<String, (&str, &str)> = std::collections::HashMap::new();
    for (class, message) in &all {
        assert!(!message.is_empty(), "{class}: empty message");
        if let Some((other, other_message)) = owner.insert(template(message), (class, message)) {
            assert_eq!(
                other, *class,
                "classes {other:?} and {class:?} share the message template:\n  {other_message}\n  {message}"
            );
        }
    }
}

#[test]
fn pin_out_of_range_and_pin_on_unreferenced_vertex_have_distinct_messages() {
    let messages = class_bad_pins();
    let find =
        |class: &str| messages.iter().find(|(c, _)| *c == class).map(|(_, m)| template(m)).expect("class present");
    assert_ne!(find("pin out of range"), find("pin on unreferenced vertex"));
}

/// Unreferenced vertices are allowed (even with non-finite coordinates): both methods give them
/// NaN and every other vertex a finite UV; `uvf_metrics` only reads referenced UVs.
#[test]
fn unreferenced_vertices_get_nan_uv() {
    let mut m = grid();
    let far = m.push_vertex([50.0, -3.0, 2.0]);
    let nan = m.push_vertex([f64::NAN, f64::INFINITY, 0.0]);
    let first = m.nv() as u32;
    // Also an unreferenced vertex before the referenced ones: shift every index by one.
    let mut shifted =
        Raw { positions: vec![1e300, -1e300, 0.0], triangles: m.triangles.iter().map(|&v| v + 1).collect() };
    shifted.positions.extend(&m.positions);
    let unreferenced = [0u32, far + 1, nan + 1];
    assert_eq!(shifted.nv() as u32, first + 1);

    let a = Args::of(&shifted);
    let (o, info) = info(a);
    assert_outcome("unreferenced vertices (uvf_mesh_info)", &o, UVF_OK, &[]);
    assert_eq!((info.vertices, info.referenced_vertices, info.triangles), (19, 16, 18), "{info:?}");
    for (label, (o, uv)) in [("natural conformal", conformal(a, None)), ("fixed boundary", fixed(a, None))] {
        assert_outcome(&format!("unreferenced vertices ({label})"), &o, UVF_OK, &[]);
        assert_eq!(o.message, "", "{label}: message after success");
        for v in 0..shifted.nv() {
            let (u, w) = (uv[2 * v], uv[2 * v + 1]);
            if unreferenced.contains(&(v as u32)) {
                assert!(u.is_nan() && w.is_nan(), "{label}: unreferenced vertex {v} has uv ({u}, {w}), expected NaN");
                assert_ne!(u.to_bits(), SENTINEL, "{label}: unreferenced vertex {v} was not written");
            } else {
                assert!(u.is_finite() && w.is_finite(), "{label}: vertex {v} has uv ({u}, {w})");
            }
        }
        let (mo, mm) = metrics(a, uv.as_ptr(), shifted.nv(), std::ptr::null());
        assert_outcome(&format!("metrics of {label} with NaN for unreferenced vertices"), &mo, UVF_OK, &[]);
        assert_eq!((mm.triangles, mm.flipped), (18, 0), "{label}: {mm:?}");
    }
}

/// What a progress callback sees: every fraction, and from which fraction on it cancels.
struct Recorder {
    fractions: Vec<f64>,
    cancel_from: f64,
}

unsafe extern "C" fn record(user: *mut c_void, fraction: f64) -> c_int {
    // SAFETY: `user` is the &mut Recorder passed with this callback.
    let r = unsafe { &mut *(user as *mut Recorder) };
    r.fractions.push(fraction);
    c_int::from(fraction >= r.cancel_from)
}

/// A non-zero return from the progress callback cancels (`UVF_CANCELLED`, output untouched);
/// a callback that always continues sees nondecreasing fractions in [0, 1] ending at 1.
#[test]
fn progress_callback_can_cancel_and_reaches_one() {
    let g = grid();
    let a = Args::of(&g);
    for cancel_from in [0.0, 0.5, f64::INFINITY] {
        let mut fixed_recorder = Recorder { fractions: Vec::new(), cancel_from };
        let options = UvfFixedBoundaryOptions {
            progress: Some(record),
            progress_user: &mut fixed_recorder as *mut Recorder as *mut c_void,
            ..Default::default()
        };
        let (fo, _) = fixed(a, Some(&options));
        let mut conformal_recorder = Recorder { fractions: Vec::new(), cancel_from };
        let options = UvfNaturalConformalOptions {
            progress: Some(record),
            progress_user: &mut conformal_recorder as *mut Recorder as *mut c_void,
            ..Default::default()
        };
        let (co, _) = conformal(a, Some(&options));
        for (label, o, r) in [("fixed boundary", fo, fixed_recorder), ("natural conformal", co, conformal_recorder)] {
            let f = &r.fractions;
            assert!(!f.is_empty(), "{label}: the callback was never called");
            assert!(f.windows(2).all(|w| w[0] <= w[1]), "{label}: fractions decrease: {f:?}");
            assert!(f.iter().all(|x| (0.0..=1.0).contains(x)), "{label}: fractions outside [0, 1]: {f:?}");
            if cancel_from.is_finite() {
                assert_outcome(
                    &format!("{label}, cancel from {cancel_from}"),
                    &o,
                    UVF_CANCELLED,
                    &["cancelled by the progress callback"],
                );
                let last = *f.last().unwrap();
                assert!(last >= cancel_from, "{label}: stopped at {last} before the callback said so");
                assert_eq!(
                    f.iter().filter(|&&x| x >= cancel_from).count(),
                    1,
                    "{label}: called again after cancelling: {f:?}"
                );
            } else {
                assert_outcome(&format!("{label}, never cancelled"), &o, UVF_OK, &[]);
                assert_eq!(*f.last().unwrap(), 1.0, "{label}: the last fraction is not 1: {f:?}");
                assert!(f.len() >= 3, "{label}: too few progress reports: {f:?}");
            }
        }
    }
}

/// The defective test meshes (`bad_*`, `realbad_*`) give `UVF_INVALID_MESH`
/// with the expected defect named, and `bad_unreferenced_vertices.obj` is accepted.
#[test]
fn defective_mesh_files_are_rejected_with_the_defect_named() {
    for (file, needle) in [
        ("bad_nonmanifold_edge.obj", "is non-manifold: it is shared by 3 triangles"),
        ("bad_nonmanifold_vertex.obj", "separate fans"),
        ("bad_duplicate_faces.obj", "uses the same three vertices as triangle"),
        ("bad_degenerate_faces.obj", "more than once"),
        ("bad_nan_coordinate.obj", "has a non-finite coordinate"),
        ("bad_inconsistent_orientation.obj", "inconsistently oriented"),
        ("bad_empty_no_faces.obj", "no triangles"),
        ("realbad_cow_nonmanifold_vertex.obj", "separate fans"),
        ("realbad_moebius.obj", "inconsistently oriented"),
        ("realbad_inverted_triangles.obj", "inconsistently oriented"),
    ] {
        let m = load(file);
        expect_mesh_error(file, Args::of(&m), UVF_INVALID_MESH, &[needle]);
    }
    for file in ["realbad_suzanne.obj", "realbad_triple_vierbein.obj"] {
        let m = load(file);
        let (o, _) = info(Args::of(&m));
        assert_eq!(o.status, UVF_INVALID_MESH, "{file}: {o:?}");
    }
    let m = load("bad_unreferenced_vertices.obj");
    let (o, uv) = fixed(Args::of(&m), None);
    assert_outcome("bad_unreferenced_vertices.obj", &o, UVF_OK, &[]);
    assert_eq!(
        uv.chunks(2).filter(|p| p[0].is_nan()).count(),
        5,
        "bad_unreferenced_vertices.obj has 5 unreferenced vertices"
    );
}
