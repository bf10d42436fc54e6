//! Fuzz input decoding and contract checks for the C ABI, shared by the libFuzzer targets
//! (`crates/uvflat-capi/fuzz/fuzz_targets/*.rs`) and the stable replay test (`crates/uvflat-capi/tests/it/fuzz_regressions.rs`), which
//! both include this file with `#[path]`. It depends on nothing but `uvflat` and `std`.
//!
//! An input is read as a mesh followed by the options of one entry point:
//!
//! - **mesh**: a raw triangle soup (arbitrary counts, coordinates and indices) or a grid
//!   (a disk, or rolled into a cylinder, torus, cup or sphere) followed by up to 31 mutations
//!   (move a coordinate to NaN/huge/tiny, delete, flip, duplicate or rewire triangles, glue
//!   vertices, append unreferenced vertices, rescale, translate). Grids make the decoder reach
//!   the solvers on most inputs; mutations and soups reach every validation branch.
//! - **options**: every field of the options struct, including invalid enum values, non-finite
//!   λ/μ/pins, `struct_size` too small or larger than the struct, NULL options, given boundaries
//!   built from the mesh's real boundary loops (then perturbed), and a progress callback that
//!   may cancel at its k-th call.
//!
//! Counts always match the buffers passed (the C contract); contents are arbitrary. Each call is
//! checked against the contract of `include/uvflat.h`: it returns a status (the fuzzer catches
//! crashes, aborts and hangs), never `UVF_INTERNAL_ERROR` (a caught panic), sets a message on
//! failure and clears it on success, leaves outputs untouched on failure (sentinel-filled
//! buffers), never writes past the stated lengths (guard elements), and on success gives finite
//! UVs for referenced vertices and NaN for unreferenced ones, consistent topology counts, and
//! sane metrics. A violation is returned as `Err(description)`.
#![allow(dead_code)]

use std::ffi::CStr;
use std::os::raw::{c_int, c_void};

use uvflat::barycentric::{uvf_fixed_boundary_map, UvfFixedBoundaryOptions, UVF_BOUNDARY_GIVEN};
use uvflat::conformal::{uvf_natural_conformal_map, UvfNaturalConformalOptions};
use uvflat::errors::uvf_last_error_message;
use uvflat::mesh::{uvf_boundary_loops, uvf_mesh_info, uvf_triangle_components, UvfMeshInfo};
use uvflat::metrics::{uvf_metrics, UvfMetrics};
use uvflat::UvfStatus;

/// The fuzz targets; each name is a binary in `crates/uvflat-capi/fuzz/fuzz_targets/` and a folder in
/// `crates/uvflat-capi/fuzz/regressions/` and `crates/uvflat-capi/fuzz/corpus/`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// `uvf_mesh_info`, `uvf_boundary_loops`, `uvf_triangle_components`.
    Mesh,
    /// `uvf_fixed_boundary_map`.
    FixedBoundary,
    /// `uvf_natural_conformal_map`.
    NaturalConformal,
    /// `uvf_metrics`.
    Metrics,
}

/// Every target with its folder name.
pub const TARGETS: [(&str, Target); 4] = [
    ("mesh", Target::Mesh),
    ("fixed_boundary", Target::FixedBoundary),
    ("natural_conformal", Target::NaturalConformal),
    ("metrics", Target::Metrics),
];

/// Decodes `data` for `target`, makes the calls and checks their contract.
pub fn run(target: Target, data: &[u8]) -> Result<(), String> {
    let mut r = Reader::new(data);
    let mesh = Mesh::decode(&mut r);
    match target {
        Target::Mesh => check_mesh_queries(&mesh, &mut r),
        Target::FixedBoundary => check_fixed_boundary(&mesh, &mut r),
        Target::NaturalConformal => check_natural_conformal(&mesh, &mut r),
        Target::Metrics => check_metrics(&mesh, &mut r),
    }
}

// ---------------------------------------------------------------------------------------------
// Reading bytes

/// Reads little-endian values; past the end every read gives 0, so any input decodes.
pub struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
}

/// Coordinates that break naive arithmetic.
const SPECIAL: [f64; 20] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::MAX,
    f64::MIN,
    f64::MIN_POSITIVE,
    5e-324,
    1e-300,
    1e300,
    1e-150,
    1e150,
    1e-8,
    1e8,
    1.0 + f64::EPSILON,
    1e16,
    -1e-300,
];

impl<'a> Reader<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Reader { data, pos: 0 }
    }
    pub fn u8(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }
    pub fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    pub fn u64(&mut self) -> u64 {
        (self.u32() as u64) | ((self.u32() as u64) << 32)
    }
    pub fn bool(&mut self) -> bool {
        self.u8() & 1 == 1
    }
    /// A coordinate: mostly small values on a 1/8 grid (so coincident and collinear points are
    /// common), sometimes arbitrary bits, special values or extreme magnitudes.
    pub fn coord(&mut self) -> f64 {
        match self.u8() % 16 {
            0..=6 => (self.u8() as i8) as f64 / 8.0,
            7..=8 => (self.u16() as i16) as f64 / 1024.0,
            9 => f64::from_bits(self.u64()),
            10 | 11 => SPECIAL[self.u8() as usize % SPECIAL.len()],
            12 => {
                let mantissa = (self.u8() as i8) as f64 / 16.0;
                let exponent = (self.u16() % 617) as i32 - 308;
                mantissa * 10f64.powi(exponent)
            }
            13 => self.u32() as f32 as f64 * 1e-3,
            _ => 0.0,
        }
    }
    /// A vertex index for a mesh of `n` vertices: mostly in range, sometimes just past the end,
    /// `u32::MAX` or arbitrary.
    pub fn index(&mut self, n: usize) -> u32 {
        match self.u8() % 16 {
            0..=11 if n > 0 => (self.u16() as usize % n) as u32,
            12 => n as u32,
            13 => u32::MAX,
            14 => self.u32(),
            _ => self.u8() as u32,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Meshes

/// Flat caller arrays: 3 doubles per vertex, 3 indices per triangle.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    pub positions: Vec<f64>,
    pub triangles: Vec<u32>,
}

const MAX_SOUP: usize = 48;
const MAX_GRID: usize = 16;
const MAX_TRIANGLES: usize = 1024;

impl Mesh {
    pub fn vertex_count(&self) -> usize {
        self.positions.len() / 3
    }
    pub fn triangle_count(&self) -> usize {
        self.triangles.len() / 3
    }
    fn push_vertex(&mut self, p: [f64; 3]) -> u32 {
        self.positions.extend(p);
        (self.vertex_count() - 1) as u32
    }

    /// Which vertices a triangle uses (indices out of range are ignored).
    pub fn referenced(&self) -> Vec<bool> {
        let mut used = vec![false; self.vertex_count()];
        for &v in &self.triangles {
            if let Some(u) = used.get_mut(v as usize) {
                *u = true;
            }
        }
        used
    }

    pub fn decode(r: &mut Reader) -> Mesh {
        let mut mesh = match r.u8() % 4 {
            0 => Mesh::soup(r),
            _ => Mesh::grid(r),
        };
        let mutations = r.u8() % 32;
        for _ in 0..mutations {
            mesh.mutate(r);
        }
        mesh
    }

    /// Arbitrary counts, coordinates and indices.
    fn soup(r: &mut Reader) -> Mesh {
        let nv = r.u8() as usize % (MAX_SOUP + 1);
        let nt = r.u8() as usize % (MAX_SOUP + 1);
        let mut mesh = Mesh::default();
        for _ in 0..nv {
            let p = [r.coord(), r.coord(), r.coord()];
            mesh.push_vertex(p);
        }
        for _ in 0..3 * nt {
            let v = r.index(nv);
            mesh.triangles.push(v);
        }
        mesh
    }

    /// An `nx × ny` grid of quads split into triangles, optionally rolled (cylinder, torus) and
    /// capped (cup, sphere), embedded in one of a few shapes.
    fn grid(r: &mut Reader) -> Mesh {
        let nx = 1 + r.u8() as usize % MAX_GRID;
        let ny = 1 + r.u8() as usize % MAX_GRID;
        let flags = r.u8();
        let wrap_x = flags & 1 != 0 && nx >= 3;
        let wrap_y = flags & 2 != 0 && wrap_x && ny >= 3;
        let cap_bottom = flags & 4 != 0 && wrap_x && !wrap_y;
        let cap_top = flags & 8 != 0 && wrap_x && !wrap_y;
        let diagonal = (flags >> 4) % 3; // 0: all one way, 1: alternating, 2: the other way
        let shape = (flags >> 6) % 4;
        let columns = if wrap_x { nx } else { nx + 1 };
        let rows = if wrap_y { ny } else { ny + 1 };
        let mut mesh = Mesh::default();
        for j in 0..rows {
            for i in 0..columns {
                let (s, t) = (i as f64 / nx as f64, j as f64 / ny as f64);
                let p = if wrap_y {
                    let (a, b) = (std::f64::consts::TAU * s, std::f64::consts::TAU * t);
                    [(2.0 + b.cos()) * a.cos(), (2.0 + b.cos()) * a.sin(), b.sin()]
                } else if wrap_x {
                    let a = std::f64::consts::TAU * s;
                    [a.cos(), a.sin(), 2.0 * t]
                } else {
                    let (x, y) = (2.0 * s - 1.0, 2.0 * t - 1.0);
                    let z = match shape {
                        0 => 0.0,
                        1 => 0.5 * (x * x + y * y),
                        2 => 0.5 * (x * x - y * y),
                        _ => 0.2 * (3.0 * x).sin() * (2.0 * y).cos(),
                    };
                    [x, y, z]
                };
                mesh.push_vertex(p);
            }
        }
        let id = |i: usize, j: usize| ((j % rows) * columns + (i % columns)) as u32;
        for j in 0..ny {
            for i in 0..nx {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                let flip = match diagonal {
                    0 => false,
                    1 => (i + j) % 2 == 1,
                    _ => true,
                };
                if flip {
                    mesh.triangles.extend([a, b, d, b, c, d]);
                } else {
                    mesh.triangles.extend([a, b, c, a, c, d]);
                }
            }
        }
        if cap_bottom {
            let pole = mesh.push_vertex([0.0, 0.0, -1.0]);
            for i in 0..nx {
                mesh.triangles.extend([id(i + 1, 0), id(i, 0), pole]);
            }
        }
        if cap_top {
            let pole = mesh.push_vertex([0.0, 0.0, 2.0 * ny as f64 / ny as f64 + 1.0]);
            for i in 0..nx {
                mesh.triangles.extend([id(i, ny), id(i + 1, ny), pole]);
            }
        }
        mesh
    }

    fn mutate(&mut self, r: &mut Reader) {
        let (nv, nt) = (self.vertex_count(), self.triangle_count());
        match r.u8() % 14 {
            // One coordinate becomes anything (NaN, huge, tiny, a coincident value).
            0 | 1 if nv > 0 => {
                let v = r.u16() as usize % nv;
                let axis = r.u8() as usize % 3;
                self.positions[3 * v + axis] = r.coord();
            }
            // A small bump (keeps the mesh valid but makes it non-planar or folded).
            2 if nv > 0 => {
                let v = r.u16() as usize % nv;
                let axis = r.u8() as usize % 3;
                self.positions[3 * v + axis] += (r.u8() as i8) as f64 / 64.0;
            }
            // Delete a triangle (makes holes, bow-ties, several components).
            3 | 4 if nt > 0 => {
                let t = r.u16() as usize % nt;
                self.triangles.drain(3 * t..3 * t + 3);
            }
            // Reverse a triangle's orientation.
            5 if nt > 0 => {
                let t = r.u16() as usize % nt;
                self.triangles.swap(3 * t + 1, 3 * t + 2);
            }
            // Rewire one corner to any index (in range or not).
            6 if nt > 0 => {
                let t = r.u16() as usize % nt;
                let k = r.u8() as usize % 3;
                self.triangles[3 * t + k] = r.index(nv);
            }
            // Duplicate a triangle, possibly rotated or reversed.
            7 if nt > 0 && nt < MAX_TRIANGLES => {
                let t = r.u16() as usize % nt;
                let mut tri = [self.triangles[3 * t], self.triangles[3 * t + 1], self.triangles[3 * t + 2]];
                tri.rotate_left(r.u8() as usize % 3);
                if r.bool() {
                    tri.swap(1, 2);
                }
                self.triangles.extend(tri);
            }
            // Append an arbitrary triangle.
            8 if nt < MAX_TRIANGLES => {
                for _ in 0..3 {
                    let v = r.index(nv);
                    self.triangles.push(v);
                }
            }
            // Append an unreferenced vertex (its coordinates may be NaN: that is allowed).
            9 if nv < u16::MAX as usize => {
                let p = [r.coord(), r.coord(), r.coord()];
                self.push_vertex(p);
            }
            // Scale every coordinate.
            10 => {
                let s = r.coord();
                self.positions.iter_mut().for_each(|x| *x *= s);
            }
            // Translate every coordinate (precision loss far from the origin).
            11 => {
                let d = [r.coord(), r.coord(), r.coord()];
                self.positions.chunks_exact_mut(3).for_each(|p| (0..3).for_each(|k| p[k] += d[k]));
            }
            // Move a vertex onto another (degenerate triangles).
            12 if nv > 1 => {
                let (a, b) = (r.u16() as usize % nv, r.u16() as usize % nv);
                for k in 0..3 {
                    self.positions[3 * a + k] = self.positions[3 * b + k];
                }
            }
            // Glue vertex a to vertex b in every triangle (pinches, non-manifold vertices and
            // edges, repeated vertices, handles).
            13 if nv > 1 => {
                let (a, b) = (r.u16() as u32 % nv as u32, r.u16() as u32 % nv as u32);
                self.triangles.iter_mut().filter(|v| **v == a).for_each(|v| *v = b);
            }
            _ => {}
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Output buffers with sentinels and guards

/// A NaN payload no computation produces: a double with these bits was not written.
const SENTINEL: u64 = 0x7ff4_dead_beef_0bad;
const SENTINEL_U32: u32 = 0xdead_0bad;
/// Elements past the stated length, which must never be written.
const GUARD: usize = 4;

/// `len` writable doubles preceded by nothing and followed by `GUARD` sentinels.
struct OutF64 {
    buf: Vec<f64>,
    len: usize,
}

impl OutF64 {
    fn new(len: usize) -> Self {
        OutF64 { buf: vec![f64::from_bits(SENTINEL); len + GUARD], len }
    }
    fn ptr(&mut self) -> *mut f64 {
        self.buf.as_mut_ptr()
    }
    fn values(&self) -> &[f64] {
        &self.buf[..self.len]
    }
    fn untouched(&self) -> bool {
        self.buf.iter().all(|x| x.to_bits() == SENTINEL)
    }
    fn guard_intact(&self) -> bool {
        self.buf[self.len..].iter().all(|x| x.to_bits() == SENTINEL)
    }
}

struct OutU32 {
    buf: Vec<u32>,
    len: usize,
}

impl OutU32 {
    fn new(len: usize) -> Self {
        OutU32 { buf: vec![SENTINEL_U32; len + GUARD], len }
    }
    fn ptr(&mut self) -> *mut u32 {
        self.buf.as_mut_ptr()
    }
    fn values(&self) -> &[u32] {
        &self.buf[..self.len]
    }
    fn untouched(&self) -> bool {
        self.buf.iter().all(|&x| x == SENTINEL_U32)
    }
    fn guard_intact(&self) -> bool {
        self.buf[self.len..].iter().all(|&x| x == SENTINEL_U32)
    }
}

/// Bytes of a plain `repr(C)` struct, to compare a sentinel-filled struct before and after.
fn bytes_of<T>(value: &T) -> Vec<u8> {
    // SAFETY: reading the initialised bytes of a `repr(C)` value for comparison only; every
    // struct compared here was created by `filled_with_sentinel`, so its padding is set too.
    unsafe { std::slice::from_raw_parts(value as *const T as *const u8, std::mem::size_of::<T>()).to_vec() }
}

/// A `repr(C)` plain-data struct (integers and doubles only) whose every byte is 0xA5.
fn filled_with_sentinel<T: Copy>() -> T {
    let mut value = std::mem::MaybeUninit::<T>::uninit();
    // SAFETY: `T` is one of the C ABI's output structs, made of integers and doubles, for
    // which every bit pattern is valid.
    unsafe {
        std::ptr::write_bytes(value.as_mut_ptr() as *mut u8, 0xA5, std::mem::size_of::<T>());
        value.assume_init()
    }
}

// ---------------------------------------------------------------------------------------------
// Status and message checks

fn last_message() -> String {
    let p = uvf_last_error_message();
    if p.is_null() {
        return "<NULL>".into();
    }
    // SAFETY: the library returns a NUL-terminated string valid until the next call.
    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
}

thread_local! {
    static STATUS_COUNTS: std::cell::RefCell<std::collections::BTreeMap<(String, String), usize>> =
        Default::default();
}

/// How often each entry point returned each status on this thread since the last call (the
/// replay test prints it, to show how deep the kept inputs reach).
pub fn take_status_counts() -> Vec<(String, String, usize)> {
    STATUS_COUNTS
        .with(|c| std::mem::take(&mut *c.borrow_mut()))
        .into_iter()
        .map(|((call, status), n)| (call, status, n))
        .collect()
}

/// Checks the status class and the message; returns whether the call succeeded.
fn check_status(call: &str, status: UvfStatus, mesh: &Mesh) -> Result<bool, String> {
    STATUS_COUNTS.with(|c| *c.borrow_mut().entry((call.to_string(), format!("{status:?}"))).or_default() += 1);
    let message = last_message();
    if uvf_last_error_message().is_null() {
        return Err(format!("{call}: uvf_last_error_message() returned NULL"));
    }
    match status {
        UvfStatus::UVF_OK => {
            if !message.is_empty() {
                return Err(format!("{call}: UVF_OK but the error message is {message:?}"));
            }
            Ok(true)
        }
        UvfStatus::UVF_INTERNAL_ERROR | UvfStatus::UVF_NOT_IMPLEMENTED | UvfStatus::UVF_IO_ERROR => Err(format!(
            "{call}: returned {status:?}: {message}\n  mesh: {} vertices, {} triangles",
            mesh.vertex_count(),
            mesh.triangle_count()
        )),
        _ => {
            if message.is_empty() {
                return Err(format!("{call}: failed with {status:?} but the error message is empty"));
            }
            Ok(false)
        }
    }
}

fn mesh_status_ok(status: UvfStatus) -> bool {
    matches!(status, UvfStatus::UVF_OK | UvfStatus::UVF_INVALID_ARGUMENT | UvfStatus::UVF_INVALID_MESH)
}

// ---------------------------------------------------------------------------------------------
// Mesh queries

fn mesh_info(mesh: &Mesh) -> (UvfStatus, UvfMeshInfo) {
    let mut info: UvfMeshInfo = filled_with_sentinel();
    // SAFETY: the arrays hold the stated counts; `info` is writable.
    let status = unsafe {
        uvf_mesh_info(
            mesh.positions.as_ptr(),
            mesh.vertex_count(),
            mesh.triangles.as_ptr(),
            mesh.triangle_count(),
            &mut info,
        )
    };
    (status, info)
}

/// Boundary loops as `(status, vertices, offsets)` with the given capacities.
fn boundary_loops(mesh: &Mesh, vertices: usize, offsets: usize) -> (UvfStatus, OutU32, OutU32) {
    let (mut verts, mut offs) = (OutU32::new(vertices), OutU32::new(offsets));
    // SAFETY: the arrays hold the stated counts (the output ones `len + GUARD`).
    let status = unsafe {
        uvf_boundary_loops(
            mesh.positions.as_ptr(),
            mesh.vertex_count(),
            mesh.triangles.as_ptr(),
            mesh.triangle_count(),
            verts.ptr(),
            vertices,
            offs.ptr(),
            offsets,
        )
    };
    (status, verts, offs)
}

/// The mesh's boundary loops, or none when it is invalid.
fn loops_of(mesh: &Mesh) -> Vec<Vec<u32>> {
    let (status, info) = mesh_info(mesh);
    if status != UvfStatus::UVF_OK {
        return Vec::new();
    }
    let (status, verts, offs) = boundary_loops(mesh, info.boundary_vertices, info.boundary_loops + 1);
    if status != UvfStatus::UVF_OK {
        return Vec::new();
    }
    let (v, o) = (verts.values(), offs.values());
    o.windows(2).filter_map(|w| v.get(w[0] as usize..w[1] as usize).map(<[u32]>::to_vec)).collect()
}

fn check_mesh_queries(mesh: &Mesh, r: &mut Reader) -> Result<(), String> {
    let (nv, nt) = (mesh.vertex_count(), mesh.triangle_count());
    let (status, info) = mesh_info(mesh);
    let ok = check_status("uvf_mesh_info", status, mesh)?;
    if !mesh_status_ok(status) {
        return Err(format!("uvf_mesh_info: unexpected status {status:?}: {}", last_message()));
    }
    if !ok {
        if bytes_of(&info) != bytes_of(&filled_with_sentinel::<UvfMeshInfo>()) {
            return Err(format!("uvf_mesh_info failed ({status:?}) but wrote info_out"));
        }
        // The other queries validate the same way and must fail the same way.
        let (s2, verts, offs) = boundary_loops(mesh, 8, 8);
        if s2 != status || !verts.untouched() || !offs.untouched() {
            return Err(format!(
                "uvf_boundary_loops on an invalid mesh: {s2:?} (mesh_info said {status:?}), outputs touched: {}",
                !(verts.untouched() && offs.untouched())
            ));
        }
        let mut comp = OutU32::new(nt);
        // SAFETY: the arrays hold the stated counts.
        let s3 =
            unsafe { uvf_triangle_components(mesh.positions.as_ptr(), nv, mesh.triangles.as_ptr(), nt, comp.ptr()) };
        if s3 != status || !comp.untouched() {
            return Err(format!("uvf_triangle_components on an invalid mesh: {s3:?} (mesh_info said {status:?})"));
        }
        return Ok(());
    }
    // Invariants of a valid mesh.
    let used = mesh.referenced();
    let referenced = used.iter().filter(|&&u| u).count();
    if info.vertices != nv || info.triangles != nt || info.referenced_vertices != referenced {
        return Err(format!(
            "uvf_mesh_info counts {info:?} for {nv} vertices ({referenced} referenced), {nt} triangles"
        ));
    }
    let chi = info.referenced_vertices as i64 - info.edges as i64 + info.triangles as i64;
    if info.euler_characteristic != chi
        || info.components == 0
        || info.components > nt
        || info.genus < 0
        || 2 * info.components as i64 - info.boundary_loops as i64 - chi != 2 * info.genus
        || 2 * info.edges < 3 * nt
        || info.edges > 3 * nt
        || info.boundary_vertices > info.edges
        || (info.boundary_loops == 0) != (info.boundary_vertices == 0)
    {
        return Err(format!("uvf_mesh_info invariants violated: {info:?}"));
    }

    // Boundary loops with exact, larger or too small capacities.
    let (mut vcap, mut ocap) = (info.boundary_vertices, info.boundary_loops + 1);
    let shrink = match r.u8() % 4 {
        0 => {
            vcap += r.u8() as usize % 4;
            ocap += r.u8() as usize % 4;
            false
        }
        1 if vcap > 0 => {
            vcap -= 1;
            true
        }
        2 => {
            ocap -= 1;
            true
        }
        _ => false,
    };
    let (s, verts, offs) = boundary_loops(mesh, vcap, ocap);
    let ok = check_status("uvf_boundary_loops", s, mesh)?;
    if !verts.guard_intact() || !offs.guard_intact() {
        return Err("uvf_boundary_loops wrote past the stated capacities".into());
    }
    if shrink {
        if s != UvfStatus::UVF_INVALID_ARGUMENT || !verts.untouched() || !offs.untouched() {
            return Err(format!(
                "uvf_boundary_loops with too small capacities ({vcap}, {ocap}): {s:?}, outputs untouched: {}",
                verts.untouched() && offs.untouched()
            ));
        }
    } else if !ok {
        return Err(format!("uvf_boundary_loops failed on a valid mesh: {s:?}: {}", last_message()));
    } else {
        let (v, o) = (verts.values(), offs.values());
        let loops = info.boundary_loops;
        if o[0] != 0 || o[loops] as usize != info.boundary_vertices || o[..=loops].windows(2).any(|w| w[1] <= w[0]) {
            return Err(format!("uvf_boundary_loops offsets {:?} for {info:?}", &o[..=loops]));
        }
        let mut seen = vec![false; nv];
        for &b in &v[..info.boundary_vertices] {
            if b as usize >= nv || !used[b as usize] || std::mem::replace(&mut seen[b as usize], true) {
                return Err(format!("uvf_boundary_loops gave vertex {b} (unknown, unreferenced or repeated)"));
            }
        }
    }

    // Components.
    let mut comp = OutU32::new(nt);
    // SAFETY: the arrays hold the stated counts.
    let s = unsafe { uvf_triangle_components(mesh.positions.as_ptr(), nv, mesh.triangles.as_ptr(), nt, comp.ptr()) };
    if !check_status("uvf_triangle_components", s, mesh)? {
        return Err(format!("uvf_triangle_components failed on a valid mesh: {s:?}: {}", last_message()));
    }
    if !comp.guard_intact() {
        return Err("uvf_triangle_components wrote past triangle_count".into());
    }
    let mut present = vec![false; info.components];
    for &c in comp.values() {
        match present.get_mut(c as usize) {
            Some(p) => *p = true,
            None => return Err(format!("component id {c} but uvf_mesh_info says {} components", info.components)),
        }
    }
    if present.iter().any(|&p| !p) {
        return Err(format!("uvf_triangle_components does not use every id below {}", info.components));
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Progress callbacks

/// State behind the `user` pointer of the progress callback.
#[derive(Debug, Default)]
struct ProgressState {
    calls: u32,
    /// Cancel (return non-zero) at this call (1-based).
    cancel_at: Option<u32>,
    cancelled: bool,
    bad_fraction: Option<f64>,
}

unsafe extern "C" fn progress_callback(user: *mut c_void, fraction: f64) -> c_int {
    // SAFETY: `user` is the `ProgressState` the harness passed with this callback.
    let state = unsafe { &mut *(user as *mut ProgressState) };
    state.calls += 1;
    if !(0.0..=1.0).contains(&fraction) {
        state.bad_fraction = Some(fraction);
    }
    if state.cancel_at == Some(state.calls) {
        state.cancelled = true;
        return 1;
    }
    0
}

/// No callback, a callback that never cancels, or one that cancels at call k.
fn decode_progress(r: &mut Reader) -> Option<ProgressState> {
    match r.u8() % 4 {
        0 | 1 => None,
        2 => Some(ProgressState::default()),
        _ => Some(ProgressState { cancel_at: Some(1 + r.u8() as u32 % 6), ..Default::default() }),
    }
}

fn check_progress(call: &str, state: &Option<ProgressState>, status: UvfStatus) -> Result<(), String> {
    let Some(state) = state else { return Ok(()) };
    if let Some(f) = state.bad_fraction {
        return Err(format!("{call}: progress callback received fraction {f} outside [0, 1]"));
    }
    if state.cancelled && status != UvfStatus::UVF_CANCELLED {
        return Err(format!("{call}: the progress callback cancelled but the call returned {status:?}"));
    }
    if !state.cancelled && status == UvfStatus::UVF_CANCELLED {
        return Err(format!("{call}: UVF_CANCELLED without the callback asking"));
    }
    Ok(())
}

/// How the options pointer is passed: NULL, a valid struct, a struct whose `struct_size` is
/// too small, or one that declares (and has) trailing bytes the library does not know.
#[derive(Debug, Clone, Copy, PartialEq)]
enum OptionsForm {
    Null,
    Exact,
    TooSmall(usize),
    Larger,
}

fn decode_options_form(r: &mut Reader, size: usize) -> OptionsForm {
    match r.u8() % 16 {
        0 => OptionsForm::Null,
        1 => OptionsForm::TooSmall(match r.u8() % 4 {
            0 => 0,
            1 => 8,
            2 => size - 1,
            _ => r.u8() as usize % size,
        }),
        2 => OptionsForm::Larger,
        _ => OptionsForm::Exact,
    }
}

/// An options struct followed by bytes that a larger (future) layout could hold.
#[repr(C)]
struct Padded<T> {
    options: T,
    future: [u64; 4],
}

/// Per-vertex UV checks after a method call.
fn check_uv_output(call: &str, mesh: &Mesh, status: UvfStatus, ok: bool, out: &OutF64) -> Result<(), String> {
    if !out.guard_intact() {
        return Err(format!("{call} wrote past 2 × vertex_count doubles"));
    }
    if !ok {
        if !out.untouched() {
            return Err(format!("{call} failed with {status:?} ({}) but wrote uv_out", last_message()));
        }
        return Ok(());
    }
    let used = mesh.referenced();
    for (v, uv) in out.values().chunks_exact(2).enumerate() {
        if used[v] && !(uv[0].is_finite() && uv[1].is_finite()) {
            return Err(format!("{call} returned UVF_OK with non-finite uv {uv:?} for referenced vertex {v}"));
        }
        if !used[v] && !(uv[0].is_nan() && uv[1].is_nan()) {
            return Err(format!("{call} gave unreferenced vertex {v} uv {uv:?} instead of NaN"));
        }
        if uv.iter().any(|x| x.to_bits() == SENTINEL) {
            return Err(format!("{call} returned UVF_OK but left vertex {v} unwritten"));
        }
    }
    Ok(())
}

fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

// ---------------------------------------------------------------------------------------------
// Fixed-boundary maps

/// Given boundary positions (`given_vertices`, `given_uv`) in one of several forms.
struct Given {
    count: usize,
    vertices: Vec<u32>,
    uv: Vec<f64>,
    null_pointers: bool,
}

fn decode_given(mesh: &Mesh, r: &mut Reader) -> Given {
    let nv = mesh.vertex_count();
    let mut given = Given { count: 0, vertices: Vec::new(), uv: Vec::new(), null_pointers: false };
    match r.u8() % 8 {
        0 => {}
        // Arbitrary pairs.
        1 => {
            for _ in 0..r.u8() % 12 {
                given.vertices.push(r.index(nv));
                given.uv.extend([r.coord(), r.coord()]);
            }
        }
        // A count with NULL arrays.
        2 => {
            given.count = 1 + r.u8() as usize % 8;
            given.null_pointers = true;
        }
        // Whole real loops placed on circles (each loop its own circle), star polygons,
        // clockwise, on a line, or all on one point; then perturbed.
        _ => {
            let loops = loops_of(mesh);
            let mask = r.u8();
            let placement = r.u8() % 6;
            for (k, lp) in loops.iter().enumerate() {
                if mask & (1 << (k % 8)) == 0 && !(k == 0 && mask == 0) {
                    continue;
                }
                let n = lp.len() as f64;
                for (i, &v) in lp.iter().enumerate() {
                    let a = std::f64::consts::TAU * i as f64 / n;
                    let (cx, radius) = (3.0 * k as f64, 1.0);
                    let p = match placement {
                        0 | 1 => [cx + radius * a.cos(), radius * a.sin()],
                        2 => {
                            let rr = if i % 2 == 0 { 1.0 } else { 0.3 };
                            [cx + rr * a.cos(), rr * a.sin()]
                        }
                        3 => [cx + a.cos(), -a.sin()],
                        4 => [cx + i as f64, 0.0],
                        _ => [cx, 0.0],
                    };
                    given.vertices.push(v);
                    given.uv.extend(p);
                }
            }
            for _ in 0..r.u8() % 4 {
                let n = given.vertices.len();
                match r.u8() % 5 {
                    0 if n > 0 => {
                        let i = r.u16() as usize % n;
                        given.uv[2 * i + r.u8() as usize % 2] = r.coord();
                    }
                    1 if n > 1 => {
                        let (i, j) = (r.u16() as usize % n, r.u16() as usize % n);
                        given.uv[2 * i] = given.uv[2 * j];
                        given.uv[2 * i + 1] = given.uv[2 * j + 1];
                    }
                    2 if n > 0 => {
                        let i = r.u16() as usize % n;
                        given.vertices.remove(i);
                        given.uv.drain(2 * i..2 * i + 2);
                    }
                    3 if n > 0 => {
                        let i = r.u16() as usize % n;
                        given.vertices.push(given.vertices[i]);
                        given.uv.extend([r.coord(), r.coord()]);
                    }
                    _ => {
                        given.vertices.push(r.index(nv));
                        given.uv.extend([r.coord(), r.coord()]);
                    }
                }
            }
        }
    }
    if !given.null_pointers {
        given.count = given.vertices.len();
    }
    given
}

/// Weights, boundary and distribution: mostly valid values, sometimes anything.
fn decode_enum(r: &mut Reader, valid: u32) -> u32 {
    match r.u8() % 8 {
        0 => r.u32(),
        1 => valid,
        _ => r.u8() as u32 % valid,
    }
}

fn check_fixed_boundary(mesh: &Mesh, r: &mut Reader) -> Result<(), String> {
    let form = decode_options_form(r, std::mem::size_of::<UvfFixedBoundaryOptions>());
    let mut options = UvfFixedBoundaryOptions::default();
    options.weights = decode_enum(r, 6);
    options.boundary = decode_enum(r, 3);
    options.distribution = decode_enum(r, 3);
    if r.u8() % 4 == 0 {
        options.lambda = r.coord();
        options.mu = r.coord();
    }
    let mut progress = decode_progress(r);
    let given = decode_given(mesh, r);
    options.given_count = given.count;
    if !given.null_pointers {
        options.given_vertices = given.vertices.as_ptr();
        options.given_uv = given.uv.as_ptr();
    }
    if let Some(state) = progress.as_mut() {
        options.progress = Some(progress_callback);
        options.progress_user = state as *mut ProgressState as *mut c_void;
    }
    let deterministic = r.u8() % 4 == 0;

    let call = |options: &UvfFixedBoundaryOptions| -> (UvfStatus, OutF64) {
        let mut padded = Padded { options: *options, future: [u64::MAX; 4] };
        let size = std::mem::size_of::<UvfFixedBoundaryOptions>();
        padded.options.struct_size = match form {
            OptionsForm::TooSmall(s) => s,
            OptionsForm::Larger => std::mem::size_of::<Padded<UvfFixedBoundaryOptions>>(),
            _ => size,
        };
        let ptr = if form == OptionsForm::Null { std::ptr::null() } else { &padded.options as *const _ };
        let mut out = OutF64::new(2 * mesh.vertex_count());
        // SAFETY: the arrays hold the stated counts; the options struct holds `struct_size`
        // bytes; the given arrays hold `given_count` entries (or are NULL); `out` holds 2 per
        // vertex plus guards.
        let status = unsafe {
            uvf_fixed_boundary_map(
                mesh.positions.as_ptr(),
                mesh.vertex_count(),
                mesh.triangles.as_ptr(),
                mesh.triangle_count(),
                ptr,
                out.ptr(),
            )
        };
        (status, out)
    };
    let (status, out) = call(&options);
    let ok = check_status("uvf_fixed_boundary_map", status, mesh)?;
    check_uv_output("uvf_fixed_boundary_map", mesh, status, ok, &out)?;
    if form != OptionsForm::Null {
        check_progress("uvf_fixed_boundary_map", &progress, status)?;
    }
    if matches!(form, OptionsForm::TooSmall(_)) && status != UvfStatus::UVF_INVALID_ARGUMENT {
        return Err(format!("uvf_fixed_boundary_map accepted struct_size {form:?}: {status:?}"));
    }
    if ok && form != OptionsForm::Null && options.boundary == UVF_BOUNDARY_GIVEN {
        // Given vertices are where the caller put them (the last entry wins for repeats).
        let values = out.values();
        for (i, &v) in given.vertices.iter().enumerate().rev() {
            if given.vertices[i + 1..].contains(&v) {
                continue;
            }
            let got = &values[2 * v as usize..2 * v as usize + 2];
            if !same_bits(got, &given.uv[2 * i..2 * i + 2]) {
                return Err(format!(
                    "given boundary vertex {v} got uv {got:?} instead of {:?}",
                    &given.uv[2 * i..2 * i + 2]
                ));
            }
        }
    }
    if deterministic && ok && progress.is_none() {
        let (status2, out2) = call(&options);
        if status2 != status || !same_bits(out.values(), out2.values()) {
            return Err("uvf_fixed_boundary_map is not deterministic: two calls gave different results".into());
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Natural conformal maps

fn check_natural_conformal(mesh: &Mesh, r: &mut Reader) -> Result<(), String> {
    let nv = mesh.vertex_count();
    let form = decode_options_form(r, std::mem::size_of::<UvfNaturalConformalOptions>());
    let mut options = UvfNaturalConformalOptions::default();
    options.pin_count = match r.u8() % 8 {
        0..=2 => 0,
        3..=5 => 2,
        6 => 1,
        _ => r.u32(),
    };
    match r.u8() % 4 {
        // Boundary vertices (the usual, valid choice).
        0 | 1 => {
            let boundary: Vec<u32> = loops_of(mesh).concat();
            if !boundary.is_empty() {
                options.pin_vertices =
                    [boundary[r.u16() as usize % boundary.len()], boundary[r.u16() as usize % boundary.len()]];
            }
        }
        // Any vertex, in range or not, referenced or not, interior or boundary.
        2 => options.pin_vertices = [r.index(nv), r.index(nv)],
        _ => {
            let v = r.index(nv);
            options.pin_vertices = [v, v];
        }
    }
    match r.u8() % 4 {
        0 | 1 => {}
        2 => options.pin_uv = [r.coord(), r.coord(), r.coord(), r.coord()],
        _ => {
            let (u, v) = (r.coord(), r.coord());
            options.pin_uv = [u, v, u, v];
        }
    }
    let mut progress = decode_progress(r);
    if let Some(state) = progress.as_mut() {
        options.progress = Some(progress_callback);
        options.progress_user = state as *mut ProgressState as *mut c_void;
    }
    let deterministic = r.u8() % 4 == 0;

    let call = |options: &UvfNaturalConformalOptions| -> (UvfStatus, OutF64) {
        let mut padded = Padded { options: *options, future: [u64::MAX; 4] };
        let size = std::mem::size_of::<UvfNaturalConformalOptions>();
        padded.options.struct_size = match form {
            OptionsForm::TooSmall(s) => s,
            OptionsForm::Larger => std::mem::size_of::<Padded<UvfNaturalConformalOptions>>(),
            _ => size,
        };
        let ptr = if form == OptionsForm::Null { std::ptr::null() } else { &padded.options as *const _ };
        let mut out = OutF64::new(2 * mesh.vertex_count());
        // SAFETY: as in `check_fixed_boundary`.
        let status = unsafe {
            uvf_natural_conformal_map(
                mesh.positions.as_ptr(),
                mesh.vertex_count(),
                mesh.triangles.as_ptr(),
                mesh.triangle_count(),
                ptr,
                out.ptr(),
            )
        };
        (status, out)
    };
    let (status, out) = call(&options);
    let ok = check_status("uvf_natural_conformal_map", status, mesh)?;
    check_uv_output("uvf_natural_conformal_map", mesh, status, ok, &out)?;
    if form != OptionsForm::Null {
        check_progress("uvf_natural_conformal_map", &progress, status)?;
    }
    if matches!(form, OptionsForm::TooSmall(_)) && status != UvfStatus::UVF_INVALID_ARGUMENT {
        return Err(format!("uvf_natural_conformal_map accepted struct_size {form:?}: {status:?}"));
    }
    if ok && form != OptionsForm::Null && options.pin_count == 2 {
        // The pins are where the caller put them.
        let values = out.values();
        for k in 0..2 {
            let v = options.pin_vertices[k] as usize;
            let (u, w) = (values[2 * v], values[2 * v + 1]);
            if u.to_bits() != options.pin_uv[2 * k].to_bits() || w.to_bits() != options.pin_uv[2 * k + 1].to_bits() {
                return Err(format!(
                    "pinned vertex {v} got uv ({u}, {w}) instead of {:?}",
                    &options.pin_uv[2 * k..2 * k + 2]
                ));
            }
        }
    }
    if deterministic && ok && progress.is_none() {
        let (status2, out2) = call(&options);
        if status2 != status || !same_bits(out.values(), out2.values()) {
            return Err("uvf_natural_conformal_map is not deterministic: two calls gave different results".into());
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Metrics

fn metrics(mesh: &Mesh, uv: &[f64], uv_count: usize, uv_triangles: Option<&[u32]>) -> (UvfStatus, UvfMetrics) {
    let mut out: UvfMetrics = filled_with_sentinel();
    // SAFETY: every array holds its stated count (`uv` 2 per uv, `uv_triangles` 3 per
    // triangle); `out` is writable.
    let status = unsafe {
        uvf_metrics(
            mesh.positions.as_ptr(),
            mesh.vertex_count(),
            mesh.triangles.as_ptr(),
            mesh.triangle_count(),
            uv.as_ptr(),
            uv_count,
            uv_triangles.map_or(std::ptr::null(), <[u32]>::as_ptr),
            &mut out,
        )
    };
    (status, out)
}

/// UVs from a method run on the mesh (NaN for unreferenced vertices), when it succeeds.
fn method_uv(mesh: &Mesh, which: u8) -> Option<Vec<f64>> {
    let mut out = OutF64::new(2 * mesh.vertex_count());
    // SAFETY: the arrays hold the stated counts; NULL options are the defaults.
    let status = unsafe {
        if which == 0 {
            uvf_natural_conformal_map(
                mesh.positions.as_ptr(),
                mesh.vertex_count(),
                mesh.triangles.as_ptr(),
                mesh.triangle_count(),
                std::ptr::null(),
                out.ptr(),
            )
        } else {
            uvf_fixed_boundary_map(
                mesh.positions.as_ptr(),
                mesh.vertex_count(),
                mesh.triangles.as_ptr(),
                mesh.triangle_count(),
                std::ptr::null(),
                out.ptr(),
            )
        }
    };
    (status == UvfStatus::UVF_OK).then(|| out.values().to_vec())
}

fn check_metrics(mesh: &Mesh, r: &mut Reader) -> Result<(), String> {
    let (nv, nt) = (mesh.vertex_count(), mesh.triangle_count());
    let mode = r.u8() % 6;
    // Per-vertex UVs (from a method, the xy projection, or arbitrary), or per-corner UVs with
    // their own triangles.
    let (mut uv, uv_count, uv_triangles): (Vec<f64>, usize, Option<Vec<u32>>) = match mode {
        0 | 1 => {
            let uv = method_uv(mesh, mode)
                .unwrap_or_else(|| mesh.positions.chunks_exact(3).flat_map(|p| [p[0], p[1]]).collect());
            (uv, nv, None)
        }
        2 => (mesh.positions.chunks_exact(3).flat_map(|p| [p[0], p[2]]).collect(), nv, None),
        3 => {
            let count = match r.u8() % 4 {
                0 => nv + 1,
                1 => nv.saturating_sub(1),
                _ => nv,
            };
            ((0..2 * count).map(|_| r.coord()).collect(), count, None)
        }
        _ => {
            let count = r.u8() as usize % 64;
            let uv = (0..2 * count).map(|_| r.coord()).collect();
            let tris = (0..3 * nt).map(|_| r.index(count)).collect();
            (uv, count, Some(tris))
        }
    };
    for _ in 0..r.u8() % 4 {
        if !uv.is_empty() {
            let i = r.u16() as usize % uv.len();
            uv[i] = r.coord();
        }
    }
    let explicit_copy = uv_triangles.is_none() && r.u8() % 2 == 0;

    let (status, out) = metrics(mesh, &uv, uv_count, uv_triangles.as_deref());
    let ok = check_status("uvf_metrics", status, mesh)?;
    if !matches!(status, UvfStatus::UVF_OK | UvfStatus::UVF_INVALID_ARGUMENT) {
        return Err(format!("uvf_metrics returned {status:?}, which it does not document"));
    }
    if !ok {
        if bytes_of(&out) != bytes_of(&filled_with_sentinel::<UvfMetrics>()) {
            return Err(format!("uvf_metrics failed ({status:?}) but wrote out"));
        }
    } else {
        check_metric_values(&out, nt)?;
    }
    // Per-vertex UVs given through uv_triangles = triangles must give the same answer (only
    // meaningful when uv_count == vertex_count, the case NULL accepts).
    if explicit_copy && uv_count == nv {
        let (status2, out2) = metrics(mesh, &uv, uv_count, Some(&mesh.triangles));
        check_status("uvf_metrics (explicit uv_triangles)", status2, mesh)?;
        if status2 != status || (ok && bytes_of(&out2) != bytes_of(&out)) {
            return Err(format!(
                "uvf_metrics differs between uv_triangles = NULL ({status:?}, {out:?}) and uv_triangles = triangles ({status2:?}, {out2:?})"
            ));
        }
    }
    Ok(())
}

fn check_metric_values(m: &UvfMetrics, nt: usize) -> Result<(), String> {
    if m.triangles != nt || m.flipped + m.degenerate_uv > nt {
        return Err(format!("uvf_metrics counts {m:?} for {nt} triangles"));
    }
    let fields = [
        m.stretch_l2,
        m.stretch_linf,
        m.conformal_mean,
        m.conformal_max,
        m.angle_mean,
        m.angle_max,
        m.area_mean,
        m.area_max,
    ];
    if fields.iter().any(|&x| x < 0.0) {
        return Err(format!("uvf_metrics gave a negative distortion: {m:?}"));
    }
    Ok(())
}
