//! SVG picture of a periodic parameterization on the surface, in the style of Ray et al. 2006,
//! Figs. 1, 8, 11: the mesh seen from a fixed direction (orthographic, back faces culled,
//! painter's algorithm by depth, flat Lambert shading), the iso-kπ lines of θ (red) and φ
//! (blue) drawn inside each triangle from its corner coordinates, singular triangles filled
//! orange and singular points marked (green: positive index, purple: negative) where a front-facing triangle touches them.
//!
//! The view looks at the mesh from direction `VIEW` (towards −VIEW), with z of the picture up
//! the projection of +z. The picture is fitted into 1024 × 1024 px. Cost: O(F log F) for the
//! depth sort; output grows with the number of visible triangles and iso-lines.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::Error;
use crate::geometry::{cross, dot, norm, sub};

/// Direction the viewer looks from (normalized in use).
const VIEW: [f64; 3] = [0.45, -0.35, 0.82];
const PICTURE_SIZE: f64 = 1024.0;
const MARGIN: f64 = 16.0;

/// What to draw.
pub struct PeriodicPicture<'a> {
    /// Vertex positions.
    pub points: &'a [[f64; 3]],
    /// Triangles.
    pub triangles: &'a [[u32; 3]],
    /// (θ, φ) at the corners of each triangle.
    pub coords: &'a [[[f64; 2]; 3]],
    /// Singular triangles.
    pub singular_triangles: &'a [u32],
    /// Singular points: vertex and index.
    pub singular_points: &'a [(u32, f64)],
}

/// Writes the picture to `path`.
pub fn write_periodic_svg(path: &Path, picture: &PeriodicPicture<'_>) -> Result<(), Error> {
    std::fs::write(path, periodic_svg_string(picture))
        .map_err(|e| Error::Io { path: path.display().to_string(), message: e.to_string() })
}

/// The SVG document (module comment).
pub fn periodic_svg_string(picture: &PeriodicPicture<'_>) -> String {
    let view = normalize(VIEW);
    let right = normalize(cross([0.0, 0.0, 1.0], view));
    let up = cross(view, right);
    let project = |p: [f64; 3]| [dot(p, right), dot(p, up), dot(p, view)];
    let projected: Vec<[f64; 3]> = picture.points.iter().map(|&p| project(p)).collect();
    let (lo, hi) = bounds(&projected);
    let scale = (PICTURE_SIZE - 2.0 * MARGIN) / (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    let to_px = |q: [f64; 3]| [MARGIN + (q[0] - lo[0]) * scale, PICTURE_SIZE - MARGIN - (q[1] - lo[1]) * scale];
    let mut singular = vec![false; picture.triangles.len()];
    for &t in picture.singular_triangles {
        if let Some(s) = singular.get_mut(t as usize) {
            *s = true;
        }
    }
    let mut order: Vec<(f64, usize)> = picture
        .triangles
        .iter()
        .enumerate()
        .filter_map(|(t, tri)| {
            let p = tri.map(|v| picture.points[v as usize]);
            let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
            let facing = dot(n, view) / norm(n).max(f64::MIN_POSITIVE);
            (facing > 0.0).then(|| ((0..3).map(|k| projected[tri[k] as usize][2]).sum::<f64>(), t))
        })
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0)); // far (small depth along view) first
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{s}" height="{s}" viewBox="0 0 {s} {s}"><rect width="100%" height="100%" fill="white"/>"#,
        s = PICTURE_SIZE
    );
    for &(_, t) in &order {
        draw_triangle(&mut out, picture, t, singular[t], view, &projected, &to_px);
    }
    let mut visible = vec![false; picture.points.len()];
    for &(_, t) in &order {
        for v in picture.triangles[t] {
            visible[v as usize] = true;
        }
    }
    draw_points(&mut out, picture, &projected, &to_px, &visible);
    out.push_str("</svg>\n");
    out
}

/// Writes a picture of a polygon mesh (the quad-dominant remesh) to `path`: the same view and
/// shading as [`periodic_svg_string`], quads grey and other faces orange, edges dark.
pub fn write_polygon_mesh_svg(path: &Path, positions: &[[f64; 3]], faces: &[Vec<u32>]) -> Result<(), Error> {
    std::fs::write(path, polygon_mesh_svg_string(positions, faces))
        .map_err(|e| Error::Io { path: path.display().to_string(), message: e.to_string() })
}

/// The SVG document of [`write_polygon_mesh_svg`].
pub fn polygon_mesh_svg_string(positions: &[[f64; 3]], faces: &[Vec<u32>]) -> String {
    let view = normalize(VIEW);
    let right = normalize(cross([0.0, 0.0, 1.0], view));
    let up = cross(view, right);
    let projected: Vec<[f64; 3]> = positions.iter().map(|&p| [dot(p, right), dot(p, up), dot(p, view)]).collect();
    let (lo, hi) = bounds(&projected);
    let scale = (PICTURE_SIZE - 2.0 * MARGIN) / (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    let to_px = |q: [f64; 3]| [MARGIN + (q[0] - lo[0]) * scale, PICTURE_SIZE - MARGIN - (q[1] - lo[1]) * scale];
    let mut order: Vec<(f64, usize, f64)> = faces
        .iter()
        .enumerate()
        .filter_map(|(f, face)| {
            let p: Vec<[f64; 3]> = face.iter().map(|&v| positions[v as usize]).collect();
            let n = (1..p.len() - 1).fold([0.0; 3], |acc, i| {
                let c = cross(sub(p[i], p[0]), sub(p[i + 1], p[0]));
                [acc[0] + c[0], acc[1] + c[1], acc[2] + c[2]]
            });
            let facing = dot(n, view) / norm(n).max(f64::MIN_POSITIVE);
            let depth = face.iter().map(|&v| projected[v as usize][2]).sum::<f64>() / face.len() as f64;
            (facing > 0.0).then_some((depth, f, facing))
        })
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{s}" height="{s}" viewBox="0 0 {s} {s}"><rect width="100%" height="100%" fill="white"/>"#,
        s = PICTURE_SIZE
    );
    for &(_, f, facing) in &order {
        let light = 0.35 + 0.65 * facing.clamp(0.0, 1.0);
        let fill = if faces[f].len() == 4 {
            let g = (230.0 * light) as u8;
            format!("rgb({g},{g},{g})")
        } else {
            format!("rgb({},{},{})", (255.0 * light) as u8, (150.0 * light) as u8, (40.0 * light) as u8)
        };
        let mut d = String::new();
        for (i, &v) in faces[f].iter().enumerate() {
            let q = to_px(projected[v as usize]);
            let _ = write!(d, "{}{:.1} {:.1}", if i == 0 { "M" } else { "L" }, q[0], q[1]);
        }
        let _ = writeln!(out, r#"<path d="{d}Z" fill="{fill}" stroke="rgb(48,48,48)" stroke-width="0.6"/>"#);
    }
    out.push_str("</svg>\n");
    out
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = norm(v);
    [v[0] / l, v[1] / l, v[2] / l]
}

fn bounds(points: &[[f64; 3]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in points.iter().filter(|p| p.iter().all(|c| c.is_finite())) {
        for a in 0..2 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    if lo[0] > hi[0] {
        return ([0.0; 2], [1.0; 2]);
    }
    (lo, hi)
}

fn draw_triangle(
    out: &mut String,
    picture: &PeriodicPicture<'_>,
    t: usize,
    singular: bool,
    view: [f64; 3],
    projected: &[[f64; 3]],
    to_px: &impl Fn([f64; 3]) -> [f64; 2],
) {
    let tri = picture.triangles[t];
    let p = tri.map(|v| picture.points[v as usize]);
    let n = normalize(cross(sub(p[1], p[0]), sub(p[2], p[0])));
    let light = 0.35 + 0.65 * dot(n, view).clamp(0.0, 1.0);
    let fill = if singular {
        format!("rgb({},{},{})", (255.0 * light) as u8, (150.0 * light) as u8, (40.0 * light) as u8)
    } else {
        let g = (230.0 * light) as u8;
        format!("rgb({g},{g},{g})")
    };
    let q = tri.map(|v| to_px(projected[v as usize]));
    let _ = writeln!(
        out,
        r#"<path d="M{:.1} {:.1}L{:.1} {:.1}L{:.1} {:.1}Z" fill="{fill}" stroke="{fill}" stroke-width="0.3"/>"#,
        q[0][0], q[0][1], q[1][0], q[1][1], q[2][0], q[2][1]
    );
    for (component, colour) in [(0usize, "#d62728"), (1usize, "#1f55c8")] {
        let values = [0, 1, 2].map(|k| picture.coords[t][k][component]);
        let mut d = String::new();
        for segment in iso_segments(values) {
            let a = interpolate(q, segment[0]);
            let b = interpolate(q, segment[1]);
            let _ = write!(d, "M{:.1} {:.1}L{:.1} {:.1}", a[0], a[1], b[0], b[1]);
        }
        if !d.is_empty() {
            let _ = writeln!(out, r#"<path d="{d}" stroke="{colour}" stroke-width="0.9" fill="none"/>"#);
        }
    }
}

/// Barycentric point on the 2D triangle `q`.
fn interpolate(q: [[f64; 2]; 3], w: [f64; 3]) -> [f64; 2] {
    [0, 1].map(|a| w[0] * q[0][a] + w[1] * q[1][a] + w[2] * q[2][a])
}

/// Segments (as pairs of barycentric points) where the linear function with corner `values`
/// crosses a multiple of π.
pub fn iso_segments(values: [f64; 3]) -> Vec<[[f64; 3]; 2]> {
    let pi = std::f64::consts::PI;
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) || hi - lo > 1e3 {
        return Vec::new();
    }
    let mut segments = Vec::new();
    let mut k = (lo / pi).ceil();
    while k * pi <= hi {
        let level = k * pi;
        let mut ends = Vec::new();
        for e in 0..3 {
            let (a, b) = (e, (e + 1) % 3);
            let (va, vb) = (values[a], values[b]);
            if (va - level) * (vb - level) < 0.0 || (va == level && vb != level) {
                let s = (level - va) / (vb - va);
                let mut w = [0.0; 3];
                w[a] = 1.0 - s;
                w[b] = s;
                ends.push(w);
            }
        }
        if ends.len() >= 2 {
            segments.push([ends[0], ends[1]]);
        }
        k += 1.0;
    }
    segments
}

fn draw_points(
    out: &mut String,
    picture: &PeriodicPicture<'_>,
    projected: &[[f64; 3]],
    to_px: &impl Fn([f64; 3]) -> [f64; 2],
    visible: &[bool],
) {
    for &(v, index) in picture.singular_points {
        let Some(&p) = projected.get(v as usize) else { continue };
        if !visible[v as usize] {
            continue;
        }
        let c = to_px(p);
        let colour = if index > 0.0 { "#1a9e3a" } else { "#8e2dbf" };
        let _ = writeln!(out, r#"<circle cx="{:.1}" cy="{:.1}" r="3" fill="{colour}"/>"#, c[0], c[1]);
    }
}
