//! Fixed boundary maps for barycentric methods (course notes §2.3 "boundary mapping"):
//! the outer boundary loop goes to a convex shape — a circle (centre (0.5, 0.5), radius 0.5) or
//! the unit square — with its vertices spaced by one of three distributions along the loop;
//! or the caller gives the UV of every vertex of one or more boundary loops.
//!
//! Loops are walked counter-clockwise (surface on the left) and placed counter-clockwise, so
//! the resulting maps preserve orientation.

use crate::error::{Error, Result};
use crate::geometry::distance;
use crate::mesh::TriMesh;

/// Where the boundary goes.
#[derive(Debug, Clone, PartialEq)]
pub enum BoundaryShape {
    /// Circle of centre (0.5, 0.5) and radius 0.5.
    Circle,
    /// The unit square [0, 1]².
    Square,
    /// Caller-given UV for every vertex of one or more whole boundary loops; loops not given
    /// are treated as holes.
    Given(Vec<(u32, [f64; 2])>),
}

/// How vertices are spaced along the shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Distribution {
    /// Equal parameter steps per boundary edge.
    Uniform,
    /// Steps proportional to 3D edge length.
    ChordLength,
    /// Steps proportional to the square root of 3D edge length.
    Centripetal,
}

/// The fixed vertices and which boundary loops they cover.
#[derive(Debug, Clone)]
pub struct FixedBoundary {
    /// (vertex, uv) of every fixed vertex.
    pub fixed: Vec<(u32, [f64; 2])>,
    /// For each boundary loop of the mesh, whether it is fixed (the others are holes).
    pub loop_fixed: Vec<bool>,
}

/// Normalized parameters in [0, 1) of the vertices of a closed loop.
pub fn loop_parameters(points: &[[f64; 3]], lp: &[u32], distribution: Distribution) -> Vec<f64> {
    let step = |i: usize| -> f64 {
        let d = distance(points[lp[i] as usize], points[lp[(i + 1) % lp.len()] as usize]);
        match distribution {
            Distribution::Uniform => 1.0,
            Distribution::ChordLength => d,
            Distribution::Centripetal => d.sqrt(),
        }
    };
    let steps: Vec<f64> = (0..lp.len()).map(step).collect();
    let total: f64 = steps.iter().sum();
    let mut t = Vec::with_capacity(lp.len());
    let mut acc = 0.0;
    for s in &steps {
        t.push(if total > 0.0 { acc / total } else { t.len() as f64 / lp.len() as f64 });
        acc += s;
    }
    t
}

/// Point of the circle at parameter `t`.
pub fn circle_point(t: f64) -> [f64; 2] {
    let a = 2.0 * std::f64::consts::PI * t;
    [0.5 + 0.5 * a.cos(), 0.5 + 0.5 * a.sin()]
}

/// Point of the unit square's perimeter at parameter `t`, counter-clockwise from (0, 0).
pub fn square_point(t: f64) -> [f64; 2] {
    let s = 4.0 * t;
    match s {
        s if s < 1.0 => [s, 0.0],
        s if s < 2.0 => [1.0, s - 1.0],
        s if s < 3.0 => [3.0 - s, 1.0],
        s => [0.0, 4.0 - s],
    }
}

/// Places the boundary: the longest loop on a convex shape, or the caller's positions.
pub fn fixed_boundary(mesh: &TriMesh, shape: &BoundaryShape, distribution: Distribution) -> Result<FixedBoundary> {
    let loops = mesh.boundary_loops();
    let outer = mesh.longest_boundary_loop().ok_or(Error::NotADisk {
        components: 1,
        boundary_loops: 0,
        genus: mesh.topology().genus,
    })?;
    let on_shape = |f: fn(f64) -> [f64; 2]| -> FixedBoundary {
        let t = loop_parameters(mesh.points(), &loops[outer], distribution);
        let fixed = loops[outer].iter().zip(t).map(|(&v, t)| (v, f(t))).collect();
        let loop_fixed = (0..loops.len()).map(|i| i == outer).collect();
        FixedBoundary { fixed, loop_fixed }
    };
    match shape {
        BoundaryShape::Circle => Ok(on_shape(circle_point)),
        BoundaryShape::Square => Ok(on_shape(square_point)),
        BoundaryShape::Given(given) => given_boundary(mesh, given),
    }
}

/// Checks that caller-given positions cover whole boundary loops and nothing else.
fn given_boundary(mesh: &TriMesh, given: &[(u32, [f64; 2])]) -> Result<FixedBoundary> {
    let n = mesh.vertex_count();
    let mut uv: Vec<Option<[f64; 2]>> = vec![None; n];
    for &(v, p) in given {
        if v as usize >= n {
            return Err(Error::InvalidArgument(format!(
                "boundary vertex {v} does not exist (the mesh has {n} vertices)"
            )));
        }
        if !mesh.is_boundary_vertex(v) {
            return Err(Error::InvalidArgument(format!(
                "vertex {v} was given a boundary position but is not on a boundary loop"
            )));
        }
        if !(p[0].is_finite() && p[1].is_finite()) {
            return Err(Error::InvalidArgument(format!("boundary vertex {v} was given a non-finite position")));
        }
        if uv[v as usize].replace(p).is_some() {
            // (The last position would silently win, as a conflicting one did before.)
            return Err(Error::InvalidArgument(format!("boundary vertex {v} is given twice")));
        }
    }
    let mut loop_fixed = Vec::new();
    for lp in mesh.boundary_loops() {
        let count = lp.iter().filter(|&&v| uv[v as usize].is_some()).count();
        if count != 0 && count != lp.len() {
            let missing = lp.iter().find(|&&v| uv[v as usize].is_none()).copied().unwrap_or(0);
            return Err(Error::InvalidArgument(format!(
                "boundary positions must cover whole loops: vertex {missing} is on a loop of {} vertices of which only {count} were given",
                lp.len()
            )));
        }
        loop_fixed.push(count > 0);
    }
    if !loop_fixed.iter().any(|&f| f) {
        return Err(Error::InvalidArgument("no boundary positions were given".into()));
    }
    let fixed = (0..n as u32).filter_map(|v| uv[v as usize].map(|p| (v, p))).collect();
    Ok(FixedBoundary { fixed, loop_fixed })
}
