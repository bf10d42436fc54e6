//! Global topology from half-edge connectivity: ordered boundary loops, connected components,
//! Euler characteristic and genus.

use super::connectivity::{next, Connectivity, NONE};
use uvflat_sparse::union_find::{set_labels, union};

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
            union(&mut parent, (h / 3) as u32, t / 3);
        }
    }
    set_labels(&mut parent)
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
