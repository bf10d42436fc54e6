//! Union–find (disjoint sets) over `u32` elements stored as a parent array: path halving, the
//! smaller root becomes the parent, so every root is the lowest element of its set. Used by the
//! connected components of the orderings' graphs and, in the parameterization crate, for mesh components,
//! cut graphs and chart merging.

/// Marks an element without a label.
const NONE: u32 = u32::MAX;

/// Numbers the sets of a union–find forest 0, 1, … in order of their lowest element (when, as
/// here, every root is the lowest element of its set, roots are labelled first); returns the
/// label of every element and the number of sets.
pub fn set_labels(parent: &mut [u32]) -> (Vec<u32>, usize) {
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
pub fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let grandparent = parent[parent[x as usize] as usize];
        parent[x as usize] = grandparent;
        x = grandparent;
    }
    x
}

/// Joins the trees of `x` and `y` (the smaller root becomes the parent).
pub fn union(parent: &mut [u32], x: u32, y: u32) {
    let (a, b) = (find(parent, x), find(parent, y));
    if a != b {
        parent[a.max(b) as usize] = a.min(b);
    }
}
