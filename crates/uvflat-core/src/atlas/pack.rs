//! Packing flattened charts into the unit square.
//!
//! 1. Each chart is turned to its minimum-area bounding rectangle (when rotation is allowed):
//!    the optimal rectangle has a side along an edge of the convex hull (Freeman & Shapira 1975),
//!    so every hull edge direction is tried; the hull is Andrew's monotone chain. The chart is
//!    then turned a quarter if needed so that the rectangle is at least as wide as high.
//! 2. The rectangles, padded by half the margin on each side, are packed by the skyline
//!    bottom-left heuristic (Jylänki 2010, "A thousand ways to pack the bin", §4): sorted by
//!    decreasing height, each goes where its top is lowest along the skyline (ties: leftmost),
//!    trying both orientations when rotation is allowed. Strip widths from √(area) to 1.6·√(area)
//!    are tried and the packing with the smallest enclosing square is kept.
//! 3. Everything is scaled uniformly into the unit square (texel density stays uniform).
//!
//! The margin is given in unit-square units; since the final scale depends on the packing, the
//! padding is re-derived from the enclosing square until the margin holds. Rectangles never
//! overlap, so neither do the charts inside them.
//!
//! Cost: O(h log h) per chart for the hull (h vertices), O(h²) for the rectangle search over the
//! hull, O(n²) per strip width for the skyline with n charts.

/// Placement of one chart: UV' = scale · (R(θ) · uv + offset), θ such that the chart's minimum
/// rectangle is axis-aligned.
#[derive(Debug, Clone, Copy)]
pub(super) struct Transform {
    cos: f64,
    sin: f64,
    /// Translation after rotation (chart units).
    offset: [f64; 2],
}

impl Transform {
    pub(super) fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        [self.cos * p[0] - self.sin * p[1] + self.offset[0], self.sin * p[0] + self.cos * p[1] + self.offset[1]]
    }
}

/// Result of [`pack`]: the fraction of the unit square covered by charts.
pub struct Packing {
    pub utilization: f64,
}

/// Packs the charts (each a set of UV points, modified in place, and its UV area) into the unit
/// square with `margin` between charts (and half of it to the square's sides).
pub fn pack(charts: &mut [Vec<[f64; 2]>], areas: &[f64], margin: f64, rotate: bool) -> Packing {
    if charts.is_empty() {
        return Packing { utilization: 0.0 };
    }
    let placements: Vec<(Transform, [f64; 2])> = charts.iter().map(|uv| orient(uv, rotate)).collect();
    let sizes: Vec<[f64; 2]> = placements.iter().map(|p| p.1).collect();
    let total: f64 = sizes.iter().map(|s| s[0] * s[1]).sum::<f64>().max(f64::MIN_POSITIVE);
    // Padding in chart units: half the margin on each side, margin given in final units.
    let mut side = total.sqrt();
    let mut best = None;
    for _ in 0..30 {
        let pad = 0.5 * margin * side;
        let (positions, turned, used) = best_skyline(&sizes, pad, rotate);
        let achieved = if used > 0.0 { pad / used } else { f64::INFINITY };
        best = Some((positions, turned, used, pad));
        if achieved >= 0.5 * margin * (1.0 - 1e-12) || margin == 0.0 {
            break;
        }
        side = used * 1.05;
    }
    let Some((positions, turned, used, pad)) = best else { return Packing { utilization: 0.0 } };
    let scale = 1.0 / used;
    let mut covered = 0.0;
    for (i, uv) in charts.iter_mut().enumerate() {
        let (mut t, size) = placements[i];
        if turned[i] {
            // A quarter turn: (x, y) → (h − y, x) maps [0, w]×[0, h] onto [0, h]×[0, w].
            let (c, s) = (t.cos, t.sin);
            t.cos = -s;
            t.sin = c;
            let o = t.offset;
            t.offset = [size[1] - o[1], o[0]];
        }
        let origin = [positions[i][0] + pad, positions[i][1] + pad];
        for p in uv.iter_mut() {
            let q = t.apply(*p);
            *p = [(q[0] + origin[0]) * scale, (q[1] + origin[1]) * scale];
        }
        covered += areas[i] * scale * scale;
    }
    Packing { utilization: covered }
}

/// Rotation putting the chart's minimum-area rectangle (or its bounding box when `rotate` is
/// false) axis-aligned at the origin, at least as wide as high; returns it and the rectangle.
pub(super) fn orient(uv: &[[f64; 2]], rotate: bool) -> (Transform, [f64; 2]) {
    let angle = if rotate { minimum_area_rectangle_angle(&convex_hull(uv)) } else { 0.0 };
    let (mut c, mut s) = (angle.cos(), angle.sin());
    let (w, h) = extent(uv, c, s);
    if rotate && h > w {
        (c, s) = (-s, c);
    }
    let (lo, hi) = bounds(uv, c, s);
    (Transform { cos: c, sin: s, offset: [-lo[0], -lo[1]] }, [hi[0] - lo[0], hi[1] - lo[1]])
}

/// Rotation angle that makes the minimum-area enclosing rectangle of a convex polygon
/// (counter-clockwise) axis-aligned. The rectangle has a side on a hull edge (Freeman & Shapira
/// 1975); rotating calipers (Toussaint 1983) visit every edge with the extreme points along and
/// across it, each advancing monotonically, in O(h) instead of O(h²).
fn minimum_area_rectangle_angle(hull: &[[f64; 2]]) -> f64 {
    let n = hull.len();
    if n < 3 {
        return 0.0;
    }
    let at = |i: usize| hull[i % n];
    // Projections of point p on the direction d of the edge starting at a, and across it.
    let along = |a: [f64; 2], d: [f64; 2], p: [f64; 2]| (p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1];
    let across = |a: [f64; 2], d: [f64; 2], p: [f64; 2]| d[0] * (p[1] - a[1]) - d[1] * (p[0] - a[0]);
    let (mut right, mut top, mut left) = (1usize, 1usize, 1usize);
    let (mut best, mut angle) = (f64::INFINITY, 0.0);
    for i in 0..n {
        let (a, b) = (at(i), at(i + 1));
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        if length == 0.0 {
            continue;
        }
        let d = [(b[0] - a[0]) / length, (b[1] - a[1]) / length];
        // Each pointer moves forward while that improves its extreme (at most a full turn).
        let advance = |mut k: usize, better: &dyn Fn(usize, usize) -> bool| {
            let stop = k + n;
            while k + 1 < stop && better(k + 1, k) {
                k += 1;
            }
            k
        };
        right = advance(right.max(i + 1), &|x, y| along(a, d, at(x)) >= along(a, d, at(y)));
        top = advance(top.max(right), &|x, y| across(a, d, at(x)) >= across(a, d, at(y)));
        left = advance(left.max(top), &|x, y| along(a, d, at(x)) <= along(a, d, at(y)));
        let width = along(a, d, at(right)) - along(a, d, at(left));
        let area = width * across(a, d, at(top));
        if area < best {
            best = area;
            angle = -d[1].atan2(d[0]);
        }
    }
    angle
}

fn bounds(points: &[[f64; 2]], c: f64, s: f64) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in points {
        let q = [c * p[0] - s * p[1], s * p[0] + c * p[1]];
        for d in 0..2 {
            lo[d] = lo[d].min(q[d]);
            hi[d] = hi[d].max(q[d]);
        }
    }
    (lo, hi)
}

fn extent(points: &[[f64; 2]], c: f64, s: f64) -> (f64, f64) {
    let (lo, hi) = bounds(points, c, s);
    (hi[0] - lo[0], hi[1] - lo[1])
}

/// Convex hull, counter-clockwise (Andrew's monotone chain), of the points not strictly inside
/// the octagon of the extreme points in x, y, x + y and x − y (Akl & Toussaint 1978's
/// throw-away: a chart's interior vertices need not be sorted).
fn convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut p: Vec<[f64; 2]> = outside_extreme_octagon(points);
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> =
            if pass == 0 { Box::new(p.iter()) } else { Box::new(p.iter().rev()) };
        for &q in iter {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0 {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

/// The points that are not strictly inside the convex octagon whose corners are the points
/// extreme in x, y, x + y and x − y (those inside cannot be on the hull). All of them when
/// that polygon is degenerate.
fn outside_extreme_octagon(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let keys: [fn([f64; 2]) -> f64; 4] = [|p| p[0], |p| p[0] + p[1], |p| p[1], |p| p[1] - p[0]];
    let Some(&first) = points.first() else { return Vec::new() };
    // Counter-clockwise: max x, max x + y, max y, max y − x, min x, min x + y, min y, min y − x.
    let mut corners = [first; 8];
    for &q in points {
        for (k, key) in keys.iter().enumerate() {
            if key(q) > key(corners[k]) {
                corners[k] = q;
            }
            if key(q) < key(corners[k + 4]) {
                corners[k + 4] = q;
            }
        }
    }
    let mut polygon: Vec<[f64; 2]> = Vec::with_capacity(8);
    for c in corners {
        if polygon.last() != Some(&c) && polygon.first() != Some(&c) {
            polygon.push(c);
        }
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let n = polygon.len();
    let convex = n >= 3 && (0..n).all(|i| cross(polygon[i], polygon[(i + 1) % n], polygon[(i + 2) % n]) > 0.0);
    if !convex {
        return points.to_vec();
    }
    let inside = |q: [f64; 2]| (0..n).all(|i| cross(polygon[i], polygon[(i + 1) % n], q) > 0.0);
    points.iter().copied().filter(|&q| !inside(q)).collect()
}

/// Tries several strip widths; returns the lower-left corners of the padded rectangles, whether
/// each was turned, and the side of the enclosing square of the best packing.
fn best_skyline(sizes: &[[f64; 2]], pad: f64, rotate: bool) -> (Vec<[f64; 2]>, Vec<bool>, f64) {
    let padded: Vec<[f64; 2]> = sizes.iter().map(|s| [s[0] + 2.0 * pad, s[1] + 2.0 * pad]).collect();
    let area: f64 = padded.iter().map(|s| s[0] * s[1]).sum();
    let widest = padded.iter().map(|s| if rotate { s[0].min(s[1]) } else { s[0] }).fold(0.0, f64::max);
    let mut best: Option<(Vec<[f64; 2]>, Vec<bool>, f64)> = None;
    for step in 0..=12 {
        let width = (area.sqrt() * (1.0 + 0.05 * step as f64)).max(widest);
        let (positions, turned, used_w, used_h) = skyline(&padded, width, rotate);
        let side = used_w.max(used_h);
        if best.as_ref().is_none_or(|b| side < b.2) {
            best = Some((positions, turned, side));
        }
    }
    best.unwrap_or_default()
}

/// Skyline bottom-left packing of `sizes` into a strip of width `width`: lower-left corner of
/// each rectangle, whether it was turned, and the used width and height.
fn skyline(sizes: &[[f64; 2]], width: f64, rotate: bool) -> (Vec<[f64; 2]>, Vec<bool>, f64, f64) {
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    let tall = |s: [f64; 2]| if rotate { s[0].min(s[1]) } else { s[1] };
    order.sort_by(|&a, &b| tall(sizes[b]).total_cmp(&tall(sizes[a])).then(a.cmp(&b)));
    // Skyline segments (x, y, w), left to right, covering [0, width].
    let mut line: Vec<[f64; 3]> = vec![[0.0, 0.0, width]];
    let mut positions = vec![[0.0; 2]; sizes.len()];
    let mut turned = vec![false; sizes.len()];
    let (mut used_w, mut used_h) = (0.0f64, 0.0f64);
    for &i in &order {
        let options: &[bool] = if rotate { &[false, true] } else { &[false] };
        let mut choice: Option<(f64, f64, usize, bool)> = None; // (top, x, segment, turned)
        for &turn in options {
            let [w, h] = if turn { [sizes[i][1], sizes[i][0]] } else { sizes[i] };
            for j in 0..line.len() {
                let Some(y) = fit(&line, j, w, width) else { continue };
                let top = y + h;
                let better = choice.is_none_or(|(t, x, _, _)| top < t || (top == t && line[j][0] < x));
                if better {
                    choice = Some((top, line[j][0], j, turn));
                }
            }
        }
        // A rectangle wider than the strip (not expected: the strip is at least the widest
        // rectangle) goes on top of everything at x = 0.
        let (top, x, j, turn) = choice.unwrap_or_else(|| {
            let h = sizes[i][1];
            (line.iter().map(|s| s[1]).fold(0.0, f64::max) + h, 0.0, 0, false)
        });
        let [w, h] = if turn { [sizes[i][1], sizes[i][0]] } else { sizes[i] };
        positions[i] = [x, top - h];
        turned[i] = turn;
        used_w = used_w.max(x + w);
        used_h = used_h.max(top);
        add_to_skyline(&mut line, j, x, w, top);
    }
    (positions, turned, used_w, used_h)
}

/// The height at which a rectangle of width `w` rests when its left side is at segment `j`, or
/// `None` when it would stick out of the strip.
fn fit(line: &[[f64; 3]], j: usize, w: f64, width: f64) -> Option<f64> {
    let x = line[j][0];
    if x + w > width * (1.0 + 1e-12) {
        return None;
    }
    let mut y = 0.0f64;
    let mut k = j;
    let end = x + w;
    while k < line.len() && line[k][0] < end {
        y = y.max(line[k][1]);
        k += 1;
    }
    Some(y)
}

/// Raises the skyline to `top` over [x, x + w].
fn add_to_skyline(line: &mut Vec<[f64; 3]>, _j: usize, x: f64, w: f64, top: f64) {
    let end = x + w;
    let mut next: Vec<[f64; 3]> = Vec::with_capacity(line.len() + 2);
    for &[sx, sy, sw] in line.iter() {
        let se = sx + sw;
        if se <= x || sx >= end {
            next.push([sx, sy, sw]);
            continue;
        }
        if sx < x {
            next.push([sx, sy, x - sx]);
        }
        if se > end {
            next.push([end, sy, se - end]);
        }
    }
    next.push([x, top, w]);
    next.sort_by(|a, b| a[0].total_cmp(&b[0]));
    // Merge neighbours at the same height.
    let mut merged: Vec<[f64; 3]> = Vec::with_capacity(next.len());
    for s in next {
        if let Some(last) = merged.last_mut() {
            if last[1] == s[1] && (last[0] + last[2] - s[0]).abs() <= 1e-12 * (1.0 + s[0].abs()) {
                last[2] = s[0] + s[2] - last[0];
                continue;
            }
        }
        merged.push(s);
    }
    *line = merged;
}

#[cfg(test)]
mod tests {

    #[test]
    fn the_throw_away_keeps_every_hull_point() {
        let mut seed = 99u64;
        let mut random = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [1, 2, 3, 8, 100, 2000] {
            let disk: Vec<[f64; 2]> = (0..n)
                .map(|_| {
                    let (r, t) = (random().sqrt(), std::f64::consts::TAU * random());
                    [r * t.cos(), r * t.sin()]
                })
                .collect();
            let kept = outside_extreme_octagon(&disk);
            assert!(n < 100 || kept.len() < n / 2, "{} of {n} kept", kept.len());
            // The hull of every point: made of input points, strictly convex, and no point
            // outside it.
            let hull = convex_hull(&disk);
            let h = hull.len();
            let cross =
                |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
            assert!(hull.iter().all(|p| disk.contains(p)));
            if n >= 3 {
                assert!((0..h).all(|i| cross(hull[i], hull[(i + 1) % h], hull[(i + 2) % h]) > 0.0), "{n} points");
                assert!(
                    disk.iter().all(|&q| (0..h).all(|i| cross(hull[i], hull[(i + 1) % h], q) >= 0.0)),
                    "{n} points"
                );
            }
        }
    }

    #[test]
    fn rotating_calipers_find_the_rectangle_of_the_exhaustive_search() {
        // Every hull edge tried with every hull point: the O(h²) definition.
        let exhaustive = |hull: &[[f64; 2]]| {
            (0..hull.len())
                .map(|i| {
                    let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
                    let theta = -(b[1] - a[1]).atan2(b[0] - a[0]);
                    let (w, h) = extent(hull, theta.cos(), theta.sin());
                    w * h
                })
                .fold(f64::INFINITY, f64::min)
        };
        let mut seed = 12345u64;
        let mut random = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [3, 4, 5, 10, 50, 400] {
            for _ in 0..20 {
                let points: Vec<[f64; 2]> = (0..n).map(|_| [3.0 * random() - 1.0, random()]).collect();
                let hull = convex_hull(&points);
                let angle = minimum_area_rectangle_angle(&hull);
                let (w, h) = extent(&hull, angle.cos(), angle.sin());
                let best = exhaustive(&hull);
                assert!((w * h - best).abs() <= 1e-12 * best.max(1.0), "{n} points: {} vs {best}", w * h);
            }
        }
    }
    use super::*;

    #[test]
    fn minimum_rectangle_of_a_turned_square_is_the_square() {
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let sq: Vec<[f64; 2]> = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
            .iter()
            .map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]])
            .collect();
        let (_, size) = orient(&sq, true);
        assert!((size[0] - 2.0).abs() < 1e-12 && (size[1] - 2.0).abs() < 1e-12, "{size:?}");
    }

    #[test]
    fn packed_rectangles_do_not_overlap_and_keep_the_margin() {
        // 40 rectangles of assorted sizes as two-point "charts".
        let mut charts: Vec<Vec<[f64; 2]>> = (0..40)
            .map(|i| {
                let (w, h) = (1.0 + (i * 7 % 5) as f64, 0.5 + (i * 3 % 4) as f64);
                vec![[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]]
            })
            .collect();
        let areas: Vec<f64> = charts.iter().map(|c| c[1][0] * c[2][1]).collect();
        let margin = 0.01;
        let packing = pack(&mut charts, &areas, margin, true);
        let boxes: Vec<([f64; 2], [f64; 2])> = charts.iter().map(|c| bounds(c, 1.0, 0.0)).collect();
        for (lo, hi) in &boxes {
            assert!(lo[0] >= 0.5 * margin - 1e-12 && lo[1] >= 0.5 * margin - 1e-12);
            assert!(hi[0] <= 1.0 - 0.5 * margin + 1e-12 && hi[1] <= 1.0 - 0.5 * margin + 1e-12);
        }
        for i in 0..boxes.len() {
            for j in 0..i {
                let (a, b) = (boxes[i], boxes[j]);
                let gap_x = (b.0[0] - a.1[0]).max(a.0[0] - b.1[0]);
                let gap_y = (b.0[1] - a.1[1]).max(a.0[1] - b.1[1]);
                assert!(gap_x.max(gap_y) >= margin * (1.0 - 1e-9), "charts {i} and {j} closer than the margin");
            }
        }
        let covered: f64 = boxes.iter().map(|(lo, hi)| (hi[0] - lo[0]) * (hi[1] - lo[1])).sum();
        assert!((covered - packing.utilization).abs() < 1e-9);
        assert!(packing.utilization > 0.5, "utilization {}", packing.utilization);
    }
}
