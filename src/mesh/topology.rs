//! Global topology from half-edge connectivity: ordered boundary loops, connected components,
//! Euler characteristic and genus.

use super::connectivity::{next, Connectivity, NONE};

/// Ordered boundary loops. Each loop lists vertices in the direction of its boundary
/// half-edges, i.e. counter-clockwise with the surface on the left.
pub fn boundary_loops(triangles: &[[u32; 3]], conn: &Connectivity) -> Vec<Vec<u32>> {
    let vertex = |h: u32| triangles[(h / 3) as usize][(h % 3) as usize];
    let mut seen = vec![false; conn.twin.len()];
    let mut loops = Vec::new();
    for h in 0..conn.twin.len() as u32 {
        if conn.twin[h as usize] != NONE || seen[h as usize] {
            continue;
        }
        let mut lp = Vec::new();
        let mut g = h;
        while !seen[g as usize] {
            seen[g as usize] = true;
            lp.push(vertex(g));
            // The head of g is a boundary vertex; its boundary outgoing half-edge continues the loop.
            g = conn.vertex_halfedge[vertex(next(g)) as usize];
        }
        loops.push(lp);
    }
    loops
}

/// Component id of every triangle and the number of components (triangles sharing an edge are
/// connected). Ids are numbered in order of each component's lowest triangle. Union–find over
/// the twin pairs in half-edge order (linking the higher root under the lower, with path
/// halving), which reads the twins sequentially instead of chasing them.
pub fn triangle_components(triangle_count: usize, conn: &Connectivity) -> (Vec<u32>, usize) {
    let mut parent: Vec<u32> = (0..triangle_count as u32).collect();
    for (h, &t) in conn.twin.iter().enumerate() {
        if t != NONE && (t as usize) > h {
            let (a, b) = (find(&mut parent, (h / 3) as u32), find(&mut parent, t / 3));
            if a != b {
                parent[a.max(b) as usize] = a.min(b);
            }
        }
    }
    set_labels(&mut parent)
}

/// Numbers the sets of a union–find forest 0, 1, … in order of their lowest element (when, as
/// here, every root is the lowest element of its set, roots are labelled first); returns the
/// label of every element and the number of sets.
pub(crate) fn set_labels(parent: &mut [u32]) -> (Vec<u32>, usize) {
    let mut label = vec![NONE; parent.len()];
    let mut count = 0u32;
    for x in 0..parent.len() {
        let root = find(parent, x as u32) as usize;
        if label[root] == NONE {
            label[root] = count;
            count += 1;
        }
        label[x] = label[root];
    }
    (label, count as usize)
}

/// Root of `x` in a union–find forest, halving the path on the way.
pub(crate) fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let grandparent = parent[parent[x as usize] as usize];
        parent[x as usize] = grandparent;
        x = grandparent;
    }
    x
}

/// Joins the trees of `x` and `y` (the smaller root becomes the parent).
pub(crate) fn union(parent: &mut [u32], x: u32, y: u32) {
    let (a, b) = (find(parent, x), find(parent, y));
    if a != b {
        parent[a.max(b) as usize] = a.min(b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_are_numbered_by_lowest_triangle() {
        // Three strips of two triangles, interleaved: triangles 0 and 3, 1 and 4, 2 and 5 pair up.
        let tris: Vec<[u32; 3]> = vec![[0, 1, 2], [4, 5, 6], [8, 9, 10], [0, 2, 3], [4, 6, 7], [8, 10, 11]];
        let conn = Connectivity::new(12, &tris).expect("valid mesh");
        let (comp, count) = triangle_components(tris.len(), &conn);
        assert_eq!(count, 3);
        assert_eq!(comp, vec![0, 1, 2, 0, 1, 2]);
    }
}
