//! Packing UV islands that already exist (Blender's *Pack Islands*): a layout given as UV
//! coordinates and the UV triangles that use them, its islands being the connected components
//! of those triangles (triangles sharing a UV vertex), is laid out again into the unit square
//! by the atlas's packer (`pack_best`: the skyline of minimum-area rectangles and the
//! rasterized shapes, the better kept), each island moved rigidly (translation, rotation when
//! allowed) and scaled uniformly.
//!
//! Scale: with the surface area of every triangle given, each island is scaled so that its UV
//! area equals its surface area before packing (one texel density over all islands, as Blender
//! does with *Scale* on; an island of zero surface area keeps its size); without, the islands
//! keep their relative sizes. Islands much thinner than their extent (slivers) are packed by
//! their rectangles only (the raster packer's bitmap budget, `raster_pack::MAX_BOX_PIXELS`).
//!
//! Packing never makes islands overlap (the packer keeps them a margin apart), but islands that
//! overlap each other or themselves in the input are not repaired: each is moved as it is.
//!
//! Cost: near-linear in the triangles for the components, then the packer's (`atlas::pack`,
//! `atlas::raster_pack`).

use super::pack_layouts;
use crate::error::{Error, Result};
use uvflat_sparse::union_find::{set_labels, union};

/// Options of [`pack_islands`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RepackOptions {
    /// Gap between islands in the unit square (half of it to the square's sides), in [0, 0.5).
    pub margin: f64,
    /// Let the packer rotate islands (to their minimum-area rectangle, and by quarter turns).
    pub rotate: bool,
}

impl Default for RepackOptions {
    fn default() -> Self {
        RepackOptions { margin: 0.005, rotate: true }
    }
}

/// The packed layout of [`pack_islands`].
#[derive(Debug, Clone)]
pub struct Repacked {
    /// The UVs, packed (UV vertices no triangle uses are left as they were).
    pub uv: Vec<[f64; 2]>,
    /// Island of every triangle, in order of the islands' first triangles.
    pub island_of_triangle: Vec<u32>,
    /// Number of islands.
    pub islands: usize,
    /// Fraction of the unit square covered by islands.
    pub utilization: f64,
}

/// Packs the islands of `uv` / `uv_triangles` into the unit square (see the module docs).
/// `surface_areas`: the 3D area of every triangle, or None to keep the islands' relative sizes.
pub fn pack_islands(
    uv: &[[f64; 2]],
    uv_triangles: &[[u32; 3]],
    surface_areas: Option<&[f64]>,
    options: &RepackOptions,
) -> Result<Repacked> {
    check_input(uv, uv_triangles, surface_areas, options)?;
    let (island_of_triangle, islands) = uv_components(uv.len(), uv_triangles);
    let mut members: Vec<Island> = (0..islands).map(|_| Island::default()).collect();
    let mut local = vec![u32::MAX; uv.len()];
    for (t, tri) in uv_triangles.iter().enumerate() {
        let island = &mut members[island_of_triangle[t] as usize];
        let corners = tri.map(|v| {
            if local[v as usize] == u32::MAX {
                local[v as usize] = island.vertices.len() as u32;
                island.vertices.push(v);
            }
            local[v as usize]
        });
        island.triangles.push(corners);
        island.surface_area += surface_areas.map_or(0.0, |a| a[t]);
    }
    let mut layouts = Vec::with_capacity(islands);
    let mut areas = Vec::with_capacity(islands);
    for (i, island) in members.iter().enumerate() {
        let mut points: Vec<[f64; 2]> = island.vertices.iter().map(|&v| uv[v as usize]).collect();
        let area: f64 = island.triangles.iter().map(|t| triangle_area(&points, *t)).sum();
        if !(area > 0.0) {
            return Err(Error::InvalidArgument(format!(
                "island {i} (from UV triangle {}) has no UV area: every corner of it is on one line",
                island_of_triangle.iter().position(|&x| x as usize == i).unwrap_or(0)
            )));
        }
        let scale = match surface_areas {
            Some(_) if island.surface_area > 0.0 => (island.surface_area / area).sqrt(),
            _ => 1.0,
        };
        if !scale.is_finite() {
            return Err(Error::InvalidArgument(format!(
                "island {i}: its UV area {area:e} is too small for its surface area {:e}",
                island.surface_area
            )));
        }
        for p in &mut points {
            *p = [p[0] * scale, p[1] * scale];
        }
        layouts.push(points);
        areas.push(area * scale * scale);
    }
    let triangles: Vec<&[[u32; 3]]> = members.iter().map(|m| m.triangles.as_slice()).collect();
    let utilization = pack_layouts(&mut layouts, &triangles, &areas, options.margin, options.rotate).utilization;
    let mut packed = uv.to_vec();
    for (island, layout) in members.iter().zip(&layouts) {
        for (&v, &p) in island.vertices.iter().zip(layout) {
            packed[v as usize] = p;
        }
    }
    Ok(Repacked { uv: packed, island_of_triangle, islands, utilization })
}

/// One island's UV vertices (input indices), its triangles over them, its surface area.
#[derive(Default)]
struct Island {
    vertices: Vec<u32>,
    triangles: Vec<[u32; 3]>,
    surface_area: f64,
}

fn check_input(
    uv: &[[f64; 2]],
    uv_triangles: &[[u32; 3]],
    surface_areas: Option<&[f64]>,
    options: &RepackOptions,
) -> Result<()> {
    if uv_triangles.is_empty() {
        return Err(Error::InvalidArgument("no UV triangles to pack".into()));
    }
    if !(0.0..0.5).contains(&options.margin) {
        return Err(Error::InvalidArgument(format!("margin must be in [0, 0.5), not {}", options.margin)));
    }
    if let Some((t, v)) = uv_triangles
        .iter()
        .enumerate()
        .find_map(|(t, tri)| tri.iter().find(|&&v| v as usize >= uv.len()).map(|&v| (t, v)))
    {
        return Err(Error::InvalidArgument(format!("UV triangle {t} names UV {v}, but there are {} UVs", uv.len())));
    }
    if let Some(t) =
        uv_triangles.iter().position(|tri| tri.iter().any(|&v| !uv[v as usize].iter().all(|x| x.is_finite())))
    {
        return Err(Error::InvalidArgument(format!("UV triangle {t} has a corner that is not finite")));
    }
    if let Some(a) = surface_areas {
        if a.len() != uv_triangles.len() {
            return Err(Error::InvalidArgument(format!(
                "{} surface areas for {} triangles",
                a.len(),
                uv_triangles.len()
            )));
        }
        if let Some(t) = a.iter().position(|x| !(x.is_finite() && *x >= 0.0)) {
            return Err(Error::InvalidArgument(format!(
                "the surface area of triangle {t} is {}, not ≥ 0 and finite",
                a[t]
            )));
        }
    }
    Ok(())
}

/// Island of every triangle (components of triangles sharing a UV vertex), numbered in order of
/// their first triangle, and the island count.
fn uv_components(uv_count: usize, uv_triangles: &[[u32; 3]]) -> (Vec<u32>, usize) {
    let mut parent: Vec<u32> = (0..uv_count as u32).collect();
    for t in uv_triangles {
        union(&mut parent, t[0], t[1]);
        union(&mut parent, t[0], t[2]);
    }
    let (vertex_label, _) = set_labels(&mut parent);
    // Renumber by first triangle (unused UV vertices have labels of their own).
    let mut number = std::collections::HashMap::new();
    let island_of_triangle = uv_triangles
        .iter()
        .map(|t| {
            let n = number.len() as u32;
            *number.entry(vertex_label[t[0] as usize]).or_insert(n)
        })
        .collect();
    (island_of_triangle, number.len())
}

fn triangle_area(points: &[[f64; 2]], t: [u32; 3]) -> f64 {
    let [a, b, c] = t.map(|v| points[v as usize]);
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit squares (two triangles each) stacked on each other at the origin, the second
    /// twice as large in UV.
    fn two_squares() -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
        let uv = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        (uv, vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    }

    fn bounds(uv: &[[f64; 2]], range: std::ops::Range<usize>) -> [f64; 4] {
        let p = &uv[range];
        let f = |k: usize, max: bool| {
            p.iter().map(|q| q[k]).fold(if max { f64::MIN } else { f64::MAX }, if max { f64::max } else { f64::min })
        };
        [f(0, false), f(1, false), f(0, true), f(1, true)]
    }

    #[test]
    fn two_stacked_islands_are_moved_apart_into_the_unit_square() {
        let (uv, t) = two_squares();
        let r = pack_islands(&uv, &t, None, &RepackOptions { margin: 0.02, rotate: false }).unwrap();
        assert_eq!((r.islands, r.island_of_triangle.clone()), (2, vec![0, 0, 1, 1]));
        let (a, b) = (bounds(&r.uv, 0..4), bounds(&r.uv, 4..8));
        for x in a.iter().chain(&b) {
            assert!((0.0..=1.0).contains(x), "{a:?} {b:?}");
        }
        assert!(
            a[2] + 0.02 - 1e-12 <= b[0]
                || b[2] + 0.02 - 1e-12 <= a[0]
                || a[3] + 0.02 - 1e-12 <= b[1]
                || b[3] + 0.02 - 1e-12 <= a[1],
            "{a:?} {b:?}"
        );
        // Relative sizes kept without surface areas: side ratio 2.
        assert!(((b[2] - b[0]) / (a[2] - a[0]) - 2.0).abs() < 1e-9);
    }

    #[test]
    fn surface_areas_give_one_texel_density() {
        let (uv, t) = two_squares();
        let r =
            pack_islands(&uv, &t, Some(&[0.5, 0.5, 0.5, 0.5]), &RepackOptions { margin: 0.0, rotate: false }).unwrap();
        let (a, b) = (bounds(&r.uv, 0..4), bounds(&r.uv, 4..8));
        assert!(((b[2] - b[0]) / (a[2] - a[0]) - 1.0).abs() < 1e-9, "{a:?} {b:?}");
    }

    #[test]
    fn a_sliver_island_at_one_texel_density_is_packed_by_its_rectangle_without_a_huge_bitmap() {
        // A square and a diagonal sliver of UV area 1e-8 whose surface area is 1: scaled up by
        // 10⁴ it is a needle ~10⁴ long, far beyond the raster packer's bitmap budget.
        let uv = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0], [1.0, 1.0], [0.5, 0.5 + 1e-8]];
        let t = vec![[0, 1, 2], [0, 2, 3], [4, 5, 6]];
        let r = pack_islands(&uv, &t, Some(&[0.5, 0.5, 1.0]), &RepackOptions { margin: 0.01, rotate: false }).unwrap();
        assert_eq!(r.islands, 2);
        assert!(r.uv.iter().flatten().all(|x| x.is_finite() && (-1e-12..=1.0 + 1e-12).contains(x)), "{:?}", r.uv);
    }

    #[test]
    fn bad_layouts_are_refused() {
        let (mut uv, t) = two_squares();
        let o = RepackOptions::default();
        assert!(pack_islands(&uv, &[[0, 1, 9]], None, &o).is_err());
        assert!(pack_islands(&uv, &t, Some(&[1.0]), &o).is_err());
        assert!(pack_islands(&uv, &t, None, &RepackOptions { margin: 0.5, rotate: true }).is_err());
        uv[2] = [2.0, 0.0];
        uv[3] = [3.0, 0.0];
        assert!(matches!(pack_islands(&uv, &t, None, &o), Err(Error::InvalidArgument(m)) if m.contains("no UV area")));
        uv[2] = [f64::NAN, 0.0];
        assert!(pack_islands(&uv, &t, None, &o).is_err());
    }
}
