//! QuadCover, step 1: a frame field per triangle, its matchings across edges, and the combing
//! that makes the matchings trivial away from a cut (Kälberer, Nieser & Polthier 2007,
//! "QuadCover — surface parameterization using branched coverings"; course notes ch. 8:
//! §8.2.1 matchings r_ij ∈ {0..3} with Df_i = J^{r_ij} Df_j, eq. 8.1; §8.2.2 discrete frame
//! fields, X_{j,k} = X_{i,(k − r_ij) mod 4}; §8.2.3 the layer shift around a vertex, eq. 8.5).
//!
//! A frame is stored as its first vector X₀ per triangle (unit, tangent to the triangle);
//! X₁ = n × X₀, X₂ = −X₀, X₃ = −X₁. The matching of half-edge h (triangle f) with its twin
//! (triangle g) is the r with θ_g ≈ θ_f + r·π/2, both angles measured from the shared edge in
//! their own triangle's plane (unfolding the two triangles about the edge is the discrete
//! parallel transport, the one of [`crate::fields::indices::face_field_indices`]).
//!
//! Combing: a breadth-first traversal of the triangles across uncut edges turns each frame by
//! a multiple of π/2 so that the matching across every traversed edge becomes 0. Across every
//! other uncut edge it is then 0 as well when all vertices of non-zero layer shift lie on the
//! cut: such an edge closes a loop of the disk that encloses regular vertices only, and the
//! layer shifts of the enclosed vertices add up to the matchings along the loop.

use crate::error::{Error, Result};
use crate::fields::frames::{rotate_quarter, triangle_normal};
use crate::geometry::{cross, dot, sub};
use crate::mesh::NONE;
use crate::TriMesh;
use std::collections::VecDeque;
use std::f64::consts::FRAC_PI_2;

/// Angle of the tangent vector `x` from the edge vector `e` about the unit normal `n`.
fn angle_from_edge(x: [f64; 3], e: [f64; 3], n: [f64; 3]) -> f64 {
    dot(cross(e, x), n).atan2(dot(e, x))
}

/// Matching of every half-edge with its twin (θ_twin ≈ θ_h + r·π/2, r ∈ {0..3}); 0 on the
/// boundary.
pub fn matchings(mesh: &TriMesh, directions: &[[f64; 3]]) -> Vec<u8> {
    let twin = &mesh.connectivity().twin;
    let normals: Vec<[f64; 3]> = (0..mesh.triangle_count()).map(|t| triangle_normal(mesh, t)).collect();
    (0..twin.len())
        .map(|h| {
            let g = twin[h];
            if g == NONE {
                return 0;
            }
            let e = sub(mesh.points()[mesh.head(h as u32) as usize], mesh.points()[mesh.tail(h as u32) as usize]);
            let (f, t) = (h / 3, g as usize / 3);
            let delta = angle_from_edge(directions[t], e, normals[t]) - angle_from_edge(directions[f], e, normals[f]);
            (delta / FRAC_PI_2).round().rem_euclid(4.0) as u8
        })
        .collect()
}

/// Layer shift (eq. 8.5) at every interior vertex: the matchings of the edges crossed going
/// once around it counter-clockwise, summed modulo 4. 0 on the boundary. (The tests check that
/// the matchings of a smooth field shift no layer.)
#[cfg(test)]
pub fn layer_shifts(mesh: &TriMesh, matching: &[u8]) -> Vec<u8> {
    let twin = &mesh.connectivity().twin;
    (0..mesh.vertex_count() as u32)
        .map(|v| {
            if !mesh.is_referenced(v) || mesh.is_boundary_vertex(v) {
                return 0;
            }
            // Counter-clockwise around v, edge h (outgoing) is crossed from twin(h)'s triangle
            // into h's.
            mesh.outgoing_halfedges(v).map(|h| matching[twin[h as usize] as usize] as u32).sum::<u32>() as u8 % 4
        })
        .collect()
}

/// Combed frames and matchings (module comment): `is_cut[h]` marks the half-edges of cut
/// edges. Errors (internal) when an uncut interior edge keeps a non-zero matching, i.e. a
/// vertex of non-zero layer shift is off the cut.
pub fn comb(
    mesh: &TriMesh,
    directions: &[[f64; 3]],
    matching: &[u8],
    is_cut: &[bool],
) -> Result<(Vec<[f64; 3]>, Vec<u8>)> {
    let twin = &mesh.connectivity().twin;
    let nt = mesh.triangle_count();
    let mut turn = vec![u8::MAX; nt];
    let mut queue = VecDeque::new();
    for root in 0..nt {
        if turn[root] != u8::MAX {
            continue;
        }
        turn[root] = 0;
        queue.push_back(root);
        while let Some(f) = queue.pop_front() {
            for h in 3 * f..3 * f + 3 {
                let g = twin[h];
                if g == NONE || is_cut[h] || turn[g as usize / 3] != u8::MAX {
                    continue;
                }
                // r' = r + k_g − k_f = 0.
                turn[g as usize / 3] = (turn[f] + 4 - matching[h]) % 4;
                queue.push_back(g as usize / 3);
            }
        }
    }
    let combed: Vec<u8> = (0..twin.len())
        .map(|h| {
            let g = twin[h];
            if g == NONE {
                return 0;
            }
            (matching[h] + turn[g as usize / 3] + 4 - turn[h / 3]) % 4
        })
        .collect();
    if let Some(h) = (0..twin.len()).find(|&h| twin[h] != NONE && !is_cut[h] && combed[h] != 0) {
        return Err(Error::Internal(format!(
            "QuadCover: the frame field still turns across the uncut edge {}–{} after combing",
            mesh.tail(h as u32),
            mesh.head(h as u32)
        )));
    }
    let frames = (0..nt).map(|t| rotate_quarter(triangle_normal(mesh, t), directions[t], turn[t])).collect();
    Ok((frames, combed))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat 2 × 2 square split into 8 triangles around the centre vertex 4.
    fn flat_square() -> TriMesh {
        let mut p = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                p.extend([i as f64, j as f64, 0.0]);
            }
        }
        let t = [0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7];
        TriMesh::new(&p, &t).expect("square")
    }

    #[test]
    fn frames_turned_by_quarter_turns_match_by_those_turns_and_comb_back() {
        let mesh = flat_square();
        let nt = mesh.triangle_count();
        let turns: Vec<u8> = (0..nt).map(|t| (t * 7 % 4) as u8).collect();
        let dirs: Vec<[f64; 3]> =
            (0..nt).map(|t| rotate_quarter([0.0, 0.0, 1.0], [0.96, 0.28, 0.0], turns[t])).collect();
        let m = matchings(&mesh, &dirs);
        let twin = &mesh.connectivity().twin;
        for h in 0..twin.len() {
            if twin[h] != NONE {
                assert_eq!(m[h], (turns[twin[h] as usize / 3] + 4 - turns[h / 3]) % 4, "half-edge {h}");
            }
        }
        assert!(layer_shifts(&mesh, &m).iter().all(|&s| s == 0));
        let (frames, combed) = comb(&mesh, &dirs, &m, &vec![false; twin.len()]).expect("comb");
        assert!(combed.iter().all(|&r| r == 0));
        for f in &frames {
            assert!((dot(*f, frames[0]) - 1.0).abs() < 1e-12, "all frames agree after combing");
        }
    }

    #[test]
    fn a_field_turning_a_quarter_around_the_centre_has_layer_shift_one_there() {
        let mesh = flat_square();
        // The direction of each triangle: its centroid direction from the centre, turned by a
        // quarter of the polar angle (a +1/4-like winding around vertex 4).
        let dirs: Vec<[f64; 3]> = (0..mesh.triangle_count())
            .map(|t| {
                let c = mesh.triangles()[t].iter().fold([0.0; 3], |a, &v| {
                    let p = mesh.points()[v as usize];
                    [a[0] + p[0] / 3.0 - 1.0 / 3.0, a[1] + p[1] / 3.0 - 1.0 / 3.0, 0.0]
                });
                let a = c[1].atan2(c[0]) / 4.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let shifts = layer_shifts(&mesh, &matchings(&mesh, &dirs));
        assert_eq!(shifts[4] % 2, 1, "a quarter (or three-quarter) turn around the centre: {shifts:?}");
        assert!(shifts.iter().enumerate().all(|(v, &s)| v == 4 || s == 0));
    }
}
