//! `uvflat metrics`: the distortion of the UVs stored in an OBJ, as text or JSON.

use std::path::Path;

use crate::errors::Failure;
use uvflat_core::io::obj::read_obj;
use uvflat_core::metrics::{distortion, Metrics};

pub(crate) fn print_metrics(path: &Path, json: bool) -> Result<(), Failure> {
    let obj = read_obj(path)?;
    if obj.uv.is_empty() {
        return Err(Failure {
            message: format!("{} has no texture coordinates (`vt` lines)", path.display()),
            usage: false,
        });
    }
    if obj.uv_triangles.len() != obj.triangles.len() {
        return Err(Failure {
            message: format!("{}: some faces have no texture coordinate indices (`f v/vt ...`)", path.display()),
            usage: false,
        });
    }
    let group3 = |flat: &[u32]| flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect::<Vec<_>>();
    let positions: Vec<[f64; 3]> = obj.positions.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let uv: Vec<[f64; 2]> = obj.uv.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
    let metrics = distortion(&positions, &group3(&obj.triangles), &uv, &group3(&obj.uv_triangles))?;
    if json {
        println!("{}", metrics_json(&metrics));
    } else {
        print_metrics_text(&metrics);
    }
    Ok(())
}

/// Area ratio (UV over 3D, both scaled to the same total) beyond which a triangle is reported as
/// collapsed or blown up: a map read from a file may press a triangle nearly flat without
/// flipping it (Green–Lagrange without its area floor did so on disk_cat_head: L2 stretch 3e5).
pub(crate) const EXTREME_AREA_RATIO: f64 = 1e4;

pub(crate) fn print_metrics_text(m: &Metrics) {
    if m.area_max > EXTREME_AREA_RATIO.ln() {
        eprintln!(
            "uvflat: warning: a triangle's UV area is {:.0e} times off its share of the surface's (|log| {:.1}); the \
             map is valid but nearly degenerate there",
            m.area_max.exp(),
            m.area_max
        );
    }
    println!("  triangles               {}", m.triangles);
    println!("  flipped                 {}", m.flipped);
    println!("  degenerate uv           {}", m.degenerate_uv);
    println!("  boundary intersections  {}", m.boundary_intersections);
    println!("  stretch L2 / Linf       {:.4} / {:.4}", m.stretch_l2, m.stretch_linf);
    println!("  conformal mean / max    {:.4} / {:.4}", m.conformal_mean, m.conformal_max);
    println!("  angle error mean / max  {:.3}° / {:.3}°", m.angle_mean.to_degrees(), m.angle_max.to_degrees());
    println!("  area |log| mean / max   {:.4} / {:.4}", m.area_mean, m.area_max);
}

/// All fields of `metrics` as a JSON object (NaN becomes `null`).
pub(crate) fn metrics_json(metrics: &Metrics) -> serde_json::Value {
    serde_json::json!({
        "triangles": metrics.triangles,
        "flipped": metrics.flipped,
        "degenerate_uv": metrics.degenerate_uv,
        "stretch_l2": metrics.stretch_l2,
        "stretch_linf": metrics.stretch_linf,
        "conformal_mean": metrics.conformal_mean,
        "conformal_max": metrics.conformal_max,
        "angle_mean": metrics.angle_mean,
        "angle_max": metrics.angle_max,
        "area_mean": metrics.area_mean,
        "area_max": metrics.area_max,
        "boundary_intersections": metrics.boundary_intersections,
    })
}

/// Adds the fields of `extra` (a JSON object) to `object`.
pub(crate) fn merge(object: &mut serde_json::Value, extra: serde_json::Value) {
    if let (Some(o), serde_json::Value::Object(e)) = (object.as_object_mut(), extra) {
        o.extend(e);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--json` reports every distortion field: an identity map of a 2 × 2 grid (8 triangles)
    /// has L2 stretch 1.
    #[test]
    fn metrics_json_has_every_field() {
        let positions: Vec<[f64; 3]> = (0..9).map(|i| [(i % 3) as f64, (i / 3) as f64, 0.0]).collect();
        let mut triangles = Vec::new();
        for (x, y) in [(0u32, 0u32), (1, 0), (0, 1), (1, 1)] {
            let v = y * 3 + x;
            triangles.push([v, v + 1, v + 4]);
            triangles.push([v, v + 4, v + 3]);
        }
        let uv: Vec<[f64; 2]> = positions.iter().map(|p| [p[0], p[1]]).collect();
        let metrics = uvflat_core::metrics::distortion(&positions, &triangles, &uv, &triangles).expect("metrics");
        let json = metrics_json(&metrics);
        assert_eq!(json["triangles"], 8);
        assert_eq!(json["flipped"], 0);
        assert_eq!(json.as_object().map(|o| o.len()), Some(12));
        assert!((json["stretch_l2"].as_f64().unwrap_or(0.0) - 1.0).abs() < 1e-12);
    }
}
