//! UV islands of a polygon mesh as a DCC tool holds it: faces given by their corners (each corner
//! a vertex index, a face's corners counter-clockwise and contiguous), some faces selected, some
//! edges marked as seams. This is the first step of every interactive unwrap (Blender's, Maya's):
//! which faces are laid out together, and which corners share one UV.
//!
//! An **inner edge** is an edge (an unordered vertex pair) that is used by exactly two corners of
//! the whole mesh, both in selected faces, of two different faces that traverse it in opposite
//! directions, and is not a seam. Every other edge of a selected face is a **cut**: the selection
//! border, seams, non-manifold edges (more than two uses) and edges whose two faces disagree in
//! orientation (both traverse it the same way; a flipped neighbour starts a new island).
//!
//! - An **island** is a connected component of selected faces joined across inner edges.
//! - An **island vertex** is a class of corners joined across inner edges: across the inner edge
//!   a→b of corner c (and b→a of corner d), c is joined with the corner after d and d with the
//!   corner after c. So a seam that ends inside an island slits it open, and two fans of faces
//!   touching at one vertex get a vertex each: exactly the corners that take one UV.
//!
//! Numbering is deterministic: islands in increasing order of their lowest face, island vertices
//! island by island (all of island 0's first), within an island in increasing order of their
//! lowest corner.
//!
//! Cost: O(c log c) for c corners (one sort of the corners by edge), then near-linear union–find.

use crate::error::{Error, Result};
use uvflat_sparse::union_find::{find, union};

/// Marks a face that is not selected, or a corner of such a face.
pub const NOT_IN_AN_ISLAND: u32 = u32::MAX;

/// A polygon mesh's faces and the flags that decide its islands (see the module docs).
#[derive(Debug, Clone, Copy)]
pub struct PolygonFaces<'a> {
    /// Vertex of every corner, face after face.
    pub corner_vertices: &'a [u32],
    /// Corners of every face (each ≥ 3); they sum to `corner_vertices.len()`.
    pub face_sizes: &'a [u32],
    /// Number of vertices (every corner's vertex is below it).
    pub vertex_count: usize,
    /// Per face, whether it is laid out; None: every face.
    pub selected: Option<&'a [bool]>,
    /// Per corner, whether the edge from it to the next corner of its face is a seam; None: no
    /// seams. An edge is a seam when either of its corners says so.
    pub seams: Option<&'a [bool]>,
}

/// The islands of [`polygon_islands`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PolygonIslands {
    /// Island of every face, [`NOT_IN_AN_ISLAND`] for faces not selected.
    pub face_island: Vec<u32>,
    /// Island vertex of every corner (numbered island by island), [`NOT_IN_AN_ISLAND`] for the
    /// corners of faces not selected.
    pub corner_vertex: Vec<u32>,
    /// Number of islands.
    pub island_count: usize,
    /// First island vertex of every island, and the total count last (`island_count + 1`
    /// entries): island i holds vertices `vertex_start[i] .. vertex_start[i + 1]`.
    pub vertex_start: Vec<u32>,
    /// Edges of selected faces used by more than two corners (cut as non-manifold).
    pub non_manifold_edges: usize,
    /// Edges between two selected faces that traverse them in the same direction (cut: the
    /// faces' orientations disagree).
    pub misoriented_edges: usize,
}

/// Splits the selected faces into islands (see the module docs).
pub fn polygon_islands(faces: &PolygonFaces) -> Result<PolygonIslands> {
    let layout = CornerLayout::new(faces)?;
    let n = faces.corner_vertices.len();
    let selected_face = |f: usize| faces.selected.is_none_or(|s| s[f]);
    let seam = |c: usize| faces.seams.is_some_and(|s| s[c]);

    // Corners sorted by their edge (unordered vertex pair), so the uses of an edge are adjacent.
    let edge_key = |c: usize| {
        let (a, b) = (faces.corner_vertices[c], faces.corner_vertices[layout.next[c] as usize]);
        (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
    };
    let mut by_edge: Vec<u32> = (0..n as u32).collect();
    by_edge.sort_unstable_by_key(|&c| (edge_key(c as usize), c));

    let mut face_parent: Vec<u32> = (0..faces.face_sizes.len() as u32).collect();
    let mut corner_parent: Vec<u32> = (0..n as u32).collect();
    let (mut non_manifold, mut misoriented) = (0, 0);
    for uses in by_edge.chunk_by(|&x, &y| edge_key(x as usize) == edge_key(y as usize)) {
        let selected_uses = uses.iter().filter(|&&c| selected_face(layout.face[c as usize] as usize)).count();
        if uses.len() > 2 && selected_uses > 0 {
            non_manifold += 1;
        }
        let &[c, d] = uses else { continue };
        let (c, d) = (c as usize, d as usize);
        let (fc, fd) = (layout.face[c], layout.face[d]);
        if selected_uses != 2 || fc == fd || seam(c) || seam(d) {
            continue;
        }
        if faces.corner_vertices[c] == faces.corner_vertices[d] {
            misoriented += 1;
            continue;
        }
        union(&mut face_parent, fc, fd);
        union(&mut corner_parent, c as u32, layout.next[d]);
        union(&mut corner_parent, layout.next[c], d as u32);
    }
    Ok(numbered(faces, &layout, &mut face_parent, &mut corner_parent, non_manifold, misoriented))
}

/// Face of every corner and the corner after it in its face.
struct CornerLayout {
    face: Vec<u32>,
    next: Vec<u32>,
}

impl CornerLayout {
    fn new(faces: &PolygonFaces) -> Result<Self> {
        let n = faces.corner_vertices.len();
        if n >= u32::MAX as usize || faces.face_sizes.len() >= u32::MAX as usize {
            return Err(Error::InvalidArgument(format!(
                "{n} corners and {} faces: at most 2^32 − 2 of each are supported",
                faces.face_sizes.len()
            )));
        }
        let total: u64 = faces.face_sizes.iter().map(|&s| u64::from(s)).sum();
        if total != n as u64 {
            return Err(Error::InvalidArgument(format!("the face sizes add up to {total} corners, but {n} are given")));
        }
        if let Some(f) = faces.face_sizes.iter().position(|&s| s < 3) {
            return Err(Error::InvalidArgument(format!(
                "face {f} has {} corners; a face needs at least 3",
                faces.face_sizes[f]
            )));
        }
        if let Some(c) = faces.corner_vertices.iter().position(|&v| v as usize >= faces.vertex_count) {
            return Err(Error::InvalidArgument(format!(
                "corner {c} names vertex {}, but the mesh has {} vertices",
                faces.corner_vertices[c], faces.vertex_count
            )));
        }
        if faces.selected.is_some_and(|s| s.len() != faces.face_sizes.len()) {
            return Err(Error::InvalidArgument("the selection needs one flag per face".into()));
        }
        if faces.seams.is_some_and(|s| s.len() != n) {
            return Err(Error::InvalidArgument("the seams need one flag per corner".into()));
        }
        let mut face = Vec::with_capacity(n);
        let mut next = Vec::with_capacity(n);
        let mut start = 0u32;
        for (f, &size) in faces.face_sizes.iter().enumerate() {
            face.extend(std::iter::repeat_n(f as u32, size as usize));
            next.extend((start + 1..start + size).chain([start]));
            start += size;
        }
        Ok(CornerLayout { face, next })
    }
}

/// Numbers islands by their lowest face and island vertices island by island, each island's in
/// order of their lowest corner (union–find roots are the lowest members).
fn numbered(
    faces: &PolygonFaces,
    layout: &CornerLayout,
    face_parent: &mut [u32],
    corner_parent: &mut [u32],
    non_manifold_edges: usize,
    misoriented_edges: usize,
) -> PolygonIslands {
    let selected_face = |f: usize| faces.selected.is_none_or(|s| s[f]);
    let mut face_island = vec![NOT_IN_AN_ISLAND; face_parent.len()];
    let mut island_count = 0u32;
    for f in 0..face_parent.len() {
        if !selected_face(f) {
            continue;
        }
        let root = find(face_parent, f as u32) as usize;
        if face_island[root] == NOT_IN_AN_ISLAND {
            face_island[root] = island_count;
            island_count += 1;
        }
        face_island[f] = face_island[root];
    }
    // Island vertices are the corner classes whose root is their own lowest corner; count them
    // per island, then hand out numbers in corner order.
    let n = corner_parent.len();
    let mut per_island = vec![0u32; island_count as usize + 1];
    let mut root_of = vec![NOT_IN_AN_ISLAND; n];
    for c in 0..n {
        let island = face_island[layout.face[c] as usize];
        if island == NOT_IN_AN_ISLAND {
            continue;
        }
        let root = find(corner_parent, c as u32);
        root_of[c] = root;
        if root == c as u32 {
            per_island[island as usize + 1] += 1;
        }
    }
    for i in 0..island_count as usize {
        per_island[i + 1] += per_island[i];
    }
    let vertex_start = per_island.clone();
    let mut next_id = per_island;
    let mut corner_vertex = vec![NOT_IN_AN_ISLAND; n];
    for c in 0..n {
        if root_of[c] == c as u32 {
            let island = face_island[layout.face[c] as usize] as usize;
            corner_vertex[c] = next_id[island];
            next_id[island] += 1;
        }
    }
    for c in 0..n {
        if root_of[c] != NOT_IN_AN_ISLAND {
            corner_vertex[c] = corner_vertex[root_of[c] as usize];
        }
    }
    PolygonIslands {
        face_island,
        corner_vertex,
        island_count: island_count as usize,
        vertex_start,
        non_manifold_edges,
        misoriented_edges,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of `n` quads: vertices (i, 0) = 2i and (i, 1) = 2i + 1.
    fn strip(n: u32) -> (Vec<u32>, Vec<u32>) {
        let corners = (0..n).flat_map(|i| [2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1]).collect();
        (corners, vec![4; n as usize])
    }

    fn islands_of(corners: &[u32], sizes: &[u32], selected: Option<&[bool]>, seams: Option<&[bool]>) -> PolygonIslands {
        let vertex_count = *corners.iter().max().unwrap() as usize + 1;
        polygon_islands(&PolygonFaces { corner_vertices: corners, face_sizes: sizes, vertex_count, selected, seams })
            .unwrap()
    }

    #[test]
    fn a_strip_is_one_island_with_one_vertex_per_mesh_vertex() {
        let (c, s) = strip(3);
        let r = islands_of(&c, &s, None, None);
        assert_eq!(r.island_count, 1);
        assert_eq!(r.vertex_start, vec![0, 8]);
        // Corners of one mesh vertex share an island vertex, different mesh vertices never do.
        for x in 0..c.len() {
            for y in 0..c.len() {
                assert_eq!(c[x] == c[y], r.corner_vertex[x] == r.corner_vertex[y], "corners {x}, {y}");
            }
        }
    }

    #[test]
    fn a_seam_across_the_strip_makes_two_islands_and_the_selection_border_cuts() {
        let (c, s) = strip(3);
        let mut seams = vec![false; c.len()];
        seams[5] = true; // quad 1 = (2, 4, 5, 3): its corner 5 starts the edge 4 → 5 it shares with quad 2
        let r = islands_of(&c, &s, None, Some(&seams));
        assert_eq!(r.island_count, 2);
        assert_eq!(r.face_island, vec![0, 0, 1]);
        assert_eq!(r.vertex_start, vec![0, 6, 10]);
        let selected = [true, false, true];
        let r = islands_of(&c, &s, Some(&selected), None);
        assert_eq!(r.face_island, vec![0, NOT_IN_AN_ISLAND, 1]);
        assert!(r.corner_vertex[4..8].iter().all(|&v| v == NOT_IN_AN_ISLAND));
    }

    #[test]
    fn a_seam_ending_inside_an_island_slits_it_open() {
        // A 2 × 2 grid of quads (vertices 3j + i); the seam runs from the border (1, 0) to the
        // centre (1, 1): one island, the seam's border vertex and its edge doubled.
        let id = |i: u32, j: u32| 3 * j + i;
        let quads = [[id(0, 0), id(1, 0), id(1, 1), id(0, 1)], [id(1, 0), id(2, 0), id(2, 1), id(1, 1)]];
        let top = [[id(0, 1), id(1, 1), id(1, 2), id(0, 2)], [id(1, 1), id(2, 1), id(2, 2), id(1, 2)]];
        let c: Vec<u32> = quads.iter().chain(&top).flatten().copied().collect();
        let mut seams = vec![false; 16];
        seams[1] = true; // quad 0, corner 1: edge (1,0) → (1,1)
        let r = islands_of(&c, &[4; 4], None, Some(&seams));
        assert_eq!(r.island_count, 1);
        assert_eq!(r.vertex_start, vec![0, 10]);
        assert_ne!(r.corner_vertex[1], r.corner_vertex[4]); // (1, 0) in quads 0 and 1
        assert_eq!(r.corner_vertex[2], r.corner_vertex[7]); // the centre stays one vertex
    }

    #[test]
    fn a_flipped_face_and_a_non_manifold_edge_are_cut_and_counted() {
        let (mut c, s) = strip(2);
        c[4..8].reverse(); // quad 1 turned the other way
        let r = islands_of(&c, &s, None, None);
        assert_eq!((r.island_count, r.misoriented_edges), (2, 1));
        // Three quads on one edge (0, 1).
        let c = [0, 2, 3, 1, 1, 4, 5, 0, 0, 6, 7, 1];
        let r = islands_of(&c, &[4, 4, 4], None, None);
        assert_eq!((r.island_count, r.non_manifold_edges), (3, 1));
    }

    #[test]
    fn bad_input_is_refused_with_a_message() {
        let (c, s) = strip(2);
        let bad = |corners: &[u32], sizes: &[u32], vertex_count: usize| {
            polygon_islands(&PolygonFaces {
                corner_vertices: corners,
                face_sizes: sizes,
                vertex_count,
                selected: None,
                seams: None,
            })
        };
        assert!(matches!(bad(&c, &s, 3), Err(Error::InvalidArgument(m)) if m.contains("names vertex 3")));
        assert!(matches!(bad(&c, &[4, 3], 6), Err(Error::InvalidArgument(m)) if m.contains("add up")));
        assert!(matches!(bad(&c[..6], &[2, 4], 6), Err(Error::InvalidArgument(m)) if m.contains("at least 3")));
        let none = bad(&[], &[], 0).unwrap();
        assert_eq!((none.island_count, none.vertex_start.clone()), (0, vec![0]), "no faces: no islands");
    }
}
