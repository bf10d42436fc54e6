//! Splitting a chart in two: a two-proxy Variational Shape Approximation (Cohen-Steiner,
//! Alliez & Desbrun 2004, the segmentation the course notes cite in §6.2) restricted to the
//! chart's triangles.
//!
//! Each of the two regions has a proxy normal N; the `L^{2,1}` error of a triangle t in a
//! region is `area(t) · |n_t − N|²` (Cohen-Steiner et al. eq. 3). Initial proxies: a weighted
//! 2-means of the normals alone, started at the mean normal ± the principal direction of their
//! covariance (robust to a few noisy normals); seeds: the triangles closest to the proxies.
//! Each Lloyd iteration grows both regions at once from their seeds through the
//! chart's edge adjacency, always taking the globally cheapest (triangle, region) pair from a
//! priority queue (the flooding of §3.3, so both regions are connected); then each proxy
//! becomes its region's area-weighted mean normal and each seed its region's triangle of least
//! error. A chart with (nearly) one normal — where normals cannot tell the halves apart — is
//! split into two geodesic halves instead, and so is a chart whose normal split leaves less
//! than 10% of the area on one side (so the number of splitting levels stays logarithmic) (seeds far apart by centroid distance, flooding by
//! distance from the seed).
//!
//! Both halves are non-empty and connected, so repeated splitting ends (at worst at single
//! triangles, which every method flattens validly). Cost: O(k log k) per iteration for a chart
//! of k triangles.

use crate::geometry::{distance, dot, sub};
use crate::mesh::{TriMesh, NONE};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Lloyd iterations of the two-proxy VSA.
const LLOYD_ITERATIONS: usize = 4;

/// Below this squared normal difference between the two seeds the chart is split by distance.
const FLAT_CHART: f64 = 1e-6;

/// Smallest area fraction of the smaller half of a normal split; below it the chart is split
/// into geodesic halves instead.
const MIN_PART: f64 = 0.1;

/// Per-triangle unit normals, areas and centroids of the input mesh.
pub struct FaceData {
    pub normal: Vec<[f64; 3]>,
    pub area: Vec<f64>,
    pub centroid: Vec<[f64; 3]>,
}

impl FaceData {
    pub fn new(mesh: &TriMesh) -> Self {
        let mut normal = Vec::with_capacity(mesh.triangle_count());
        let mut area = Vec::with_capacity(mesh.triangle_count());
        let mut centroid = Vec::with_capacity(mesh.triangle_count());
        for t in mesh.triangles() {
            let [a, b, c] = t.map(|v| mesh.points()[v as usize]);
            let n = crate::geometry::cross(sub(b, a), sub(c, a));
            let l = crate::geometry::norm(n);
            normal.push(if l > 0.0 { n.map(|x| x / l) } else { [0.0; 3] });
            area.push(0.5 * l);
            centroid.push([(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0, (a[2] + b[2] + c[2]) / 3.0]);
        }
        FaceData { normal, area, centroid }
    }
}

/// A queue entry: smallest cost first.
#[derive(PartialEq)]
struct Entry(f64, u32, u8);
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1)).then(other.2.cmp(&self.2))
    }
}

/// Splits the chart `faces` (sorted input triangles, edge-connected, at least 2) into two
/// non-empty connected parts, each sorted.
pub fn split_in_two(mesh: &TriMesh, data: &FaceData, faces: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let neighbours = local_adjacency(mesh, faces);
    let normal = |i: usize| data.normal[faces[i] as usize];
    let err = |i: usize, proxy: [f64; 3]| {
        let d = sub(normal(i), proxy);
        data.area[faces[i] as usize] * dot(d, d)
    };
    let all: Vec<usize> = (0..faces.len()).collect();
    let proxies = two_means_of_normals(data, faces, &all);
    let labels = match proxies {
        None => split_by_distance(data, faces, &neighbours),
        Some(mut proxies) => {
            let seed = |proxy: [f64; 3]| {
                (0..faces.len())
                    .min_by(|&x, &y| {
                        dot2(sub(normal(x), proxy)).total_cmp(&dot2(sub(normal(y), proxy))).then(x.cmp(&y))
                    })
                    .unwrap_or(0)
            };
            let mut seeds = proxies.map(seed);
            let mut labels = Vec::new();
            for _ in 0..LLOYD_ITERATIONS {
                if seeds[0] == seeds[1] {
                    break;
                }
                labels = flood(&neighbours, seeds, |i, r| err(i, proxies[r]));
                let members: [Vec<usize>; 2] =
                    [0, 1].map(|r| (0..faces.len()).filter(|&i| labels[i] == r as u8).collect());
                proxies = [0, 1].map(|r| mean_normal(data, faces, &members[r]));
                let new_seeds = [0, 1].map(|r| {
                    *members[r]
                        .iter()
                        .min_by(|&&x, &&y| err(x, proxies[r]).total_cmp(&err(y, proxies[r])).then(x.cmp(&y)))
                        .unwrap_or(&seeds[r])
                });
                if new_seeds == seeds {
                    break;
                }
                seeds = new_seeds;
            }
            if labels.is_empty() || !balanced(data, faces, &labels) {
                split_by_distance(data, faces, &neighbours)
            } else {
                labels
            }
        }
    };
    let mut parts = (Vec::new(), Vec::new());
    for (i, &f) in faces.iter().enumerate() {
        if labels[i] == 0 {
            parts.0.push(f);
        } else {
            parts.1.push(f);
        }
    }
    parts
}

/// Whether the smaller part has at least `MIN_PART` of the chart's area (otherwise splitting
/// could shave off a few triangles per level and take a number of levels linear in the size).
fn balanced(data: &FaceData, faces: &[u32], labels: &[u8]) -> bool {
    let mut area = [0.0f64; 2];
    for (i, &f) in faces.iter().enumerate() {
        area[labels[i] as usize] += data.area[f as usize];
    }
    area[0].min(area[1]) >= MIN_PART * (area[0] + area[1])
}

/// Two proxy normals by weighted 2-means of the chart's normals (no connectivity), started at
/// the mean normal ± the principal direction of the normals' covariance; `None` when the
/// normals barely vary.
fn two_means_of_normals(data: &FaceData, faces: &[u32], members: &[usize]) -> Option<[[f64; 3]; 2]> {
    let mean = mean_normal(data, faces, members);
    let mut cov = [[0.0f64; 3]; 3];
    let mut total = 0.0;
    for &i in members {
        let f = faces[i] as usize;
        let d = sub(data.normal[f], mean);
        for r in 0..3 {
            for c in 0..3 {
                cov[r][c] += data.area[f] * d[r] * d[c];
            }
        }
        total += data.area[f];
    }
    if !(total > 0.0) {
        return None;
    }
    // Power iteration for the principal direction.
    let mut e = [1.0, 0.7, 0.3];
    let mut lambda = 0.0;
    for _ in 0..50 {
        let m = [0, 1, 2].map(|r| cov[r][0] * e[0] + cov[r][1] * e[1] + cov[r][2] * e[2]);
        lambda = crate::geometry::norm(m);
        if !(lambda > 0.0) {
            return None;
        }
        e = m.map(|x| x / lambda);
    }
    let spread = (lambda / total).sqrt();
    if spread * spread < FLAT_CHART {
        return None;
    }
    let unit = |v: [f64; 3]| {
        let l = crate::geometry::norm(v);
        if l > 0.0 {
            v.map(|x| x / l)
        } else {
            v
        }
    };
    let mut proxies =
        [unit([0, 1, 2].map(|d| mean[d] + spread * e[d])), unit([0, 1, 2].map(|d| mean[d] - spread * e[d]))];
    for _ in 0..8 {
        let mut sums = [[0.0f64; 3]; 2];
        for &i in members {
            let f = faces[i] as usize;
            let n = data.normal[f];
            let r = usize::from(dot2(sub(n, proxies[1])) < dot2(sub(n, proxies[0])));
            for d in 0..3 {
                sums[r][d] += data.area[f] * n[d];
            }
        }
        if sums.iter().any(|s| crate::geometry::norm(*s) == 0.0) {
            break;
        }
        proxies = sums.map(unit);
    }
    Some(proxies)
}

fn dot2(a: [f64; 3]) -> f64 {
    dot(a, a)
}

fn argmax(n: usize, key: impl Fn(usize) -> f64) -> usize {
    (0..n).max_by(|&x, &y| key(x).total_cmp(&key(y)).then(y.cmp(&x))).unwrap_or(0)
}

/// Area-weighted mean normal of `members` (local indices), normalised (zero if it vanishes).
fn mean_normal(data: &FaceData, faces: &[u32], members: &[usize]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for &i in members {
        let f = faces[i] as usize;
        for d in 0..3 {
            s[d] += data.area[f] * data.normal[f][d];
        }
    }
    let l = crate::geometry::norm(s);
    if l > 0.0 {
        s.map(|x| x / l)
    } else {
        s
    }
}

/// Neighbours (local indices) of every chart triangle across edges shared within the chart.
fn local_adjacency(mesh: &TriMesh, faces: &[u32]) -> Vec<[u32; 3]> {
    let twin = &mesh.connectivity().twin;
    faces
        .iter()
        .map(|&f| {
            [0, 1, 2].map(|k| {
                let g = twin[(3 * f + k) as usize];
                if g == NONE {
                    NONE
                } else {
                    faces.binary_search(&(g / 3)).map_or(NONE, |j| j as u32)
                }
            })
        })
        .collect()
}

/// Grows regions 0 and 1 from their seeds, taking the cheapest (triangle, region) pair first.
fn flood(neighbours: &[[u32; 3]], seeds: [usize; 2], cost: impl Fn(usize, usize) -> f64) -> Vec<u8> {
    let mut label = vec![u8::MAX; neighbours.len()];
    let mut heap = BinaryHeap::new();
    for (r, &s) in seeds.iter().enumerate() {
        label[s] = r as u8;
    }
    for (r, &s) in seeds.iter().enumerate() {
        for &j in &neighbours[s] {
            if j != NONE && label[j as usize] == u8::MAX {
                heap.push(Entry(cost(j as usize, r), j, r as u8));
            }
        }
    }
    while let Some(Entry(_, i, r)) = heap.pop() {
        if label[i as usize] != u8::MAX {
            continue;
        }
        label[i as usize] = r;
        for &j in &neighbours[i as usize] {
            if j != NONE && label[j as usize] == u8::MAX {
                heap.push(Entry(cost(j as usize, r as usize), j, r));
            }
        }
    }
    // A connected chart leaves nothing unlabelled; anything left joins region 1 defensively.
    for l in &mut label {
        if *l == u8::MAX {
            *l = 1;
        }
    }
    label
}

/// Two geodesic halves: seeds far apart (two sweeps of Dijkstra over centroid distances), each
/// triangle flooded from the nearer seed.
fn split_by_distance(data: &FaceData, faces: &[u32], neighbours: &[[u32; 3]]) -> Vec<u8> {
    let centroid = |i: usize| data.centroid[faces[i] as usize];
    let dist = |s: usize| dijkstra(neighbours, s, |i, j| distance(centroid(i), centroid(j)));
    let d0 = dist(0);
    let a = argmax(faces.len(), |i| if d0[i].is_finite() { d0[i] } else { -1.0 });
    let da = dist(a);
    let b = argmax(faces.len(), |i| if da[i].is_finite() { da[i] } else { -1.0 });
    let b = if b == a { (a + 1) % faces.len() } else { b };
    let (da, db) = (dist(a), dist(b));
    flood(neighbours, [a, b], |i, r| if r == 0 { da[i] } else { db[i] })
}

fn dijkstra(neighbours: &[[u32; 3]], source: usize, length: impl Fn(usize, usize) -> f64) -> Vec<f64> {
    let mut d = vec![f64::INFINITY; neighbours.len()];
    let mut heap = BinaryHeap::new();
    d[source] = 0.0;
    heap.push(Entry(0.0, source as u32, 0));
    while let Some(Entry(di, i, _)) = heap.pop() {
        if di > d[i as usize] {
            continue;
        }
        for &j in &neighbours[i as usize] {
            if j == NONE {
                continue;
            }
            let nd = di + length(i as usize, j as usize);
            if nd < d[j as usize] {
                d[j as usize] = nd;
                heap.push(Entry(nd, j, 0));
            }
        }
    }
    d
}
