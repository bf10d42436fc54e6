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
/// connected).
pub fn triangle_components(triangle_count: usize, conn: &Connectivity) -> (Vec<u32>, usize) {
    let mut comp = vec![NONE; triangle_count];
    let mut count = 0u32;
    let mut stack = Vec::new();
    for seed in 0..triangle_count {
        if comp[seed] != NONE {
            continue;
        }
        comp[seed] = count;
        stack.push(seed);
        while let Some(t) = stack.pop() {
            for k in 0..3 {
                let tw = conn.twin[3 * t + k];
                if tw != NONE && comp[(tw / 3) as usize] == NONE {
                    comp[(tw / 3) as usize] = count;
                    stack.push((tw / 3) as usize);
                }
            }
        }
        count += 1;
    }
    (comp, count as usize)
}
