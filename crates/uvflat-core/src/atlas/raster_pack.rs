//! Raster packing of charts: each chart's shape, not its bounding rectangle, decides where it
//! fits, so small charts fill the concave bays and holes of large ones.
//!
//! This is the "Tetris" packing of Lévy et al. 2002 (LSCM, §6: charts inserted one by one,
//! largest first, each as low as possible over what is already placed), done on bitmaps as
//! xatlas does: every chart is rasterized conservatively, every pixel its triangles touch after
//! growing them by half the margin; two charts whose pixel sets are disjoint are at least the
//! margin apart. Charts are placed largest first at the lowest, then leftmost, free position of
//! a canvas of fixed width and growing height, in the orientation (the minimum-area rectangle of
//! [`super::pack`], or one, two or three quarter turns of it when rotation is allowed) whose
//! top ends lowest. Canvas
//! widths around the square root of the charts' pixel area are tried and the layout with the
//! smallest enclosing square is kept; then everything is scaled uniformly into the unit square.
//!
//! Cost: O(pixels touched) to rasterize; each placement scans candidate rows (skipping those
//! whose longest free run is shorter than a chart row's longest run) and positions with 64-pixel
//! word operations, stopping at the first chart row that collides and jumping to the next free
//! pixel. With many small charts this is still slow, so a layout is abandoned past
//! `MAX_TESTS` tested positions and not tried above `MAX_CHARTS` charts (the skyline
//! packing is then used). The resolution is fixed per call (about
//! `FOOTPRINT_PIXELS` pixels for the charts' total area, fewer on small meshes), so the result does not depend on
//! the number of threads or on the machine.

use super::pack::{orient, Packing};
use rayon::prelude::*;

/// Pixels covered by the charts' total area (before growing by the margin), at most: small
/// meshes get [`PIXELS_PER_TRIANGLE`] per triangle (at least [`MIN_FOOTPRINT_PIXELS`]), so that
/// packing a few hundred triangles does not cost more than flattening them.
const FOOTPRINT_PIXELS: f64 = 100_000.0;
/// See [`FOOTPRINT_PIXELS`].
const PIXELS_PER_TRIANGLE: f64 = 16.0;
/// See [`FOOTPRINT_PIXELS`].
const MIN_FOOTPRINT_PIXELS: f64 = 16_000.0;

/// One chart as a bitmap: `rows` of `words` 64-bit words each, bit `x % 64` of word `x / 64` of
/// row `y` set when pixel (x, y) is covered.
struct Bitmap {
    width: usize,
    height: usize,
    words: usize,
    bits: Vec<u64>,
    /// Longest run of set pixels of every row (filled by [`Bitmap::finish`]).
    runs: Vec<usize>,
    /// First set pixel of every row (`width` for an empty row).
    first: Vec<usize>,
}

impl Bitmap {
    fn new(width: usize, height: usize) -> Self {
        let words = width.div_ceil(64);
        Bitmap { width, height, words, bits: vec![0; words * height], runs: Vec::new(), first: Vec::new() }
    }

    /// Computes the rows' longest runs once every pixel is set.
    fn finish(mut self) -> Self {
        self.runs = (0..self.height).map(|y| longest_run(self.row(y), self.width, true)).collect();
        self.first = (0..self.height)
            .map(|y| (0..self.width).find(|&x| (self.row(y)[x / 64] >> (x % 64)) & 1 == 1).unwrap_or(self.width))
            .collect();
        self
    }

    fn set(&mut self, x: usize, y: usize) {
        self.bits[y * self.words + x / 64] |= 1 << (x % 64);
    }

    fn row(&self, y: usize) -> &[u64] {
        &self.bits[y * self.words..(y + 1) * self.words]
    }
}

/// Longest run of pixels equal to `set` among the first `width` pixels of a bitmap row.
fn longest_run(row: &[u64], width: usize, set: bool) -> usize {
    let (mut best, mut run) = (0, 0);
    for x in 0..width {
        if ((row[x / 64] >> (x % 64)) & 1 == 1) == set {
            run += 1;
            best = best.max(run);
        } else {
            run = 0;
        }
    }
    best
}

/// The canvas: fixed width, rows added as charts are placed.
struct Canvas {
    width: usize,
    words: usize,
    rows: Vec<Vec<u64>>,
    /// Longest run of free pixels of every row: a chart row needs at least its own longest
    /// run free, which rules out most candidate rows without testing positions.
    free: Vec<usize>,
    /// Positions tested so far (the work budget, [`MAX_TESTS`]).
    tests: std::cell::Cell<u64>,
}

/// Most candidate positions one layout may test. Many small charts (hundreds, as on the
/// 133-handle cheese) make the position search slow for a small gain over the rectangles; past
/// this budget the layout is abandoned and the skyline packing is used. Counting tests, not
/// time, keeps the result deterministic.
const MAX_TESTS: u64 = 4_000_000;

/// Above this many charts the raster packing is not tried: on the collection the meshes with
/// more charts (man 197, chinese_dragon 160, cheese 422) all ran out of [`MAX_TESTS`], which
/// cost them 0.3–0.5 s for nothing.
const MAX_CHARTS: usize = 150;

/// Largest total of the charts' bounding boxes in pixels (before padding) that is rasterized:
/// the footprint is at most `FOOTPRINT_PIXELS` of area, so only charts far thinner than their
/// extent (slivers of existing layouts given to `atlas::repack`, never validated flattenings
/// in practice) exceed it; the skyline of rectangles packs those instead of a bitmap that could
/// take gigabytes.
const MAX_BOX_PIXELS: f64 = 64.0 * FOOTPRINT_PIXELS;

impl Canvas {
    fn new(width: usize) -> Self {
        Canvas { width, words: width.div_ceil(64) + 1, rows: Vec::new(), free: Vec::new(), tests: Default::default() }
    }

    fn free_run(&self, y: usize) -> usize {
        self.free.get(y).copied().unwrap_or(self.width)
    }

    /// The 64 canvas bits of row `y` starting at pixel `x`.
    fn bits_at(&self, y: usize, x: usize) -> u64 {
        let Some(row) = self.rows.get(y) else { return 0 };
        let (w, o) = (x / 64, x % 64);
        let low = row.get(w).copied().unwrap_or(0) >> o;
        let high = if o == 0 { 0 } else { row.get(w + 1).copied().unwrap_or(0) << (64 - o) };
        low | high
    }

    /// The first row of `chart` placed at (x, y) that collides, if any.
    fn collision(&self, chart: &Bitmap, x: usize, y: usize) -> Option<usize> {
        self.tests.set(self.tests.get() + 1);
        (0..chart.height)
            .find(|&r| chart.row(r).iter().enumerate().any(|(k, &b)| b & self.bits_at(y + r, x + 64 * k) != 0))
    }

    /// First free pixel of row `y` at or after `x` (`width` when there is none).
    fn next_free(&self, y: usize, mut x: usize) -> usize {
        while x < self.width {
            let taken = self.bits_at(y, x);
            if taken != u64::MAX {
                return (x + (!taken).trailing_zeros() as usize).min(self.width);
            }
            x += 64;
        }
        self.width
    }

    /// Lowest, then leftmost, position where `chart` (not wider than the canvas) fits, among
    /// those whose top is below `top_limit`; `None` when there is none.
    fn lowest_fit(&self, chart: &Bitmap, top_limit: usize) -> Option<(usize, usize)> {
        for y in 0..=self.rows.len() {
            if y + chart.height >= top_limit {
                return None;
            }
            if (0..chart.height).any(|r| self.free_run(y + r) < chart.runs[r]) {
                continue;
            }
            // Scan x; after a collision in chart row r, the next x that can fit puts that row's
            // first pixel on a free canvas pixel.
            let mut x = 0;
            while x + chart.width <= self.width && self.tests.get() <= MAX_TESTS {
                let Some(r) = self.collision(chart, x, y) else { return Some((x, y)) };
                let first = chart.first[r];
                x = (x + 1).max(self.next_free(y + r, x + first).saturating_sub(first));
            }
        }
        None
    }

    fn place(&mut self, chart: &Bitmap, x: usize, y: usize) {
        while self.rows.len() < y + chart.height {
            self.rows.push(vec![0; self.words]);
        }
        while self.free.len() < self.rows.len() {
            self.free.push(self.width);
        }
        for r in 0..chart.height {
            let row = &mut self.rows[y + r];
            for (k, &b) in chart.row(r).iter().enumerate() {
                let (w, o) = ((x + 64 * k) / 64, (x + 64 * k) % 64);
                row[w] |= b << o;
                if o > 0 {
                    row[w + 1] |= b >> (64 - o);
                }
            }
            self.free[y + r] = longest_run(row, self.width, false);
        }
    }
}

/// A chart turned to its packing orientation, with its corner at the origin.
struct Shape<'a> {
    points: Vec<[f64; 2]>,
    size: [f64; 2],
    triangles: &'a [[u32; 3]],
}

impl Shape<'_> {
    /// The same chart turned `k` quarters.
    fn turned_times(&self, k: usize) -> Self {
        let mut shape = Shape { points: self.points.clone(), ..*self };
        for _ in 0..k {
            shape = shape.turned();
        }
        shape
    }

    /// The same chart turned a quarter: (x, y) → (h − y, x).
    fn turned(&self) -> Self {
        let h = self.size[1];
        Shape {
            points: self.points.iter().map(|p| [h - p[1], p[0]]).collect(),
            size: [self.size[1], self.size[0]],
            triangles: self.triangles,
        }
    }

    /// Conservative bitmap at pixel size `pixel`: pixel (i, j) is set when the chart grown by
    /// `pad` meets the square [i·pixel, (i+1)·pixel] × [j·pixel, (j+1)·pixel], the chart being
    /// shifted by `pad` so that its grown shape starts at 0.
    fn rasterize(&self, pixel: f64, pad: f64) -> Bitmap {
        let cells = |extent: f64| ((extent + 2.0 * pad) / pixel).ceil().max(1.0) as usize;
        let mut bitmap = Bitmap::new(cells(self.size[0]), cells(self.size[1]));
        for t in self.triangles {
            let p = t.map(|v| {
                let q = self.points[v as usize];
                [q[0] + pad, q[1] + pad]
            });
            let lo = |d: usize| p.iter().map(|q| q[d]).fold(f64::INFINITY, f64::min) - pad;
            let hi = |d: usize| p.iter().map(|q| q[d]).fold(f64::NEG_INFINITY, f64::max) + pad;
            let range = |d: usize, n: usize| {
                let a = (lo(d) / pixel).floor().max(0.0) as usize;
                let b = ((hi(d) / pixel).floor().max(0.0) as usize).min(n - 1);
                a..=b
            };
            for j in range(1, bitmap.height) {
                for i in range(0, bitmap.width) {
                    let square = [
                        i as f64 * pixel - pad,
                        j as f64 * pixel - pad,
                        (i + 1) as f64 * pixel + pad,
                        (j + 1) as f64 * pixel + pad,
                    ];
                    if triangle_meets_box(&p, square) {
                        bitmap.set(i, j);
                    }
                }
            }
        }
        bitmap.finish()
    }
}

/// Whether the triangle `p` and the axis-aligned box `[x0, y0, x1, y1]` intersect (closed
/// sets), by the separating axis theorem: the box's axes (the caller iterates over boxes that
/// meet the triangle's bounding box, checked again here) and the triangle's three edge normals.
fn triangle_meets_box(p: &[[f64; 2]; 3], b: [f64; 4]) -> bool {
    let (lo_x, hi_x) = (p[0][0].min(p[1][0]).min(p[2][0]), p[0][0].max(p[1][0]).max(p[2][0]));
    let (lo_y, hi_y) = (p[0][1].min(p[1][1]).min(p[2][1]), p[0][1].max(p[1][1]).max(p[2][1]));
    if hi_x < b[0] || lo_x > b[2] || hi_y < b[1] || lo_y > b[3] {
        return false;
    }
    let area = cross(p[0], p[1], p[2]);
    if area == 0.0 {
        // A degenerate triangle (valid charts have none): the bounding box decides, which
        // can only mark more pixels.
        return true;
    }
    let corners = [[b[0], b[1]], [b[2], b[1]], [b[2], b[3]], [b[0], b[3]]];
    let orientation = area.signum();
    (0..3).all(|k| {
        let (a, c) = (p[k], p[(k + 1) % 3]);
        corners.iter().any(|&q| cross(a, c, q) * orientation >= 0.0)
    })
}

fn cross(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// One layout: per chart its quarter turns and pixel position; the used extent.
struct Layout {
    turns: Vec<usize>,
    positions: Vec<(usize, usize)>,
    side_pixels: usize,
}

/// Places the charts (bitmaps per orientation, largest area first) on a canvas `width` wide;
/// `None` past the work budget.
fn layout(bitmaps: &[Vec<Bitmap>], order: &[usize], width: usize) -> Option<Layout> {
    let mut canvas = Canvas::new(width);
    let mut turns = vec![0; bitmaps.len()];
    let mut positions = vec![(0, 0); bitmaps.len()];
    let mut used_width = 0;
    for &c in order {
        // The orientation whose top ends lowest; each search stops at the best top so far.
        let mut best: Option<(usize, usize, usize)> = None;
        for (o, bitmap) in bitmaps[c].iter().enumerate().filter(|(_, b)| b.width <= width) {
            let limit = best.map_or(usize::MAX, |(_, y, b)| y + bitmaps[c][b].height);
            if let Some((x, y)) = canvas.lowest_fit(bitmap, limit) {
                best = Some((x, y, o));
            }
        }
        if canvas.tests.get() > MAX_TESTS {
            return None;
        }
        let (x, y, o) = best.unwrap_or_else(|| {
            let o = (0..bitmaps[c].len()).min_by_key(|&o| bitmaps[c][o].width).unwrap_or(0);
            (0, canvas.rows.len(), o)
        });
        canvas.place(&bitmaps[c][o], x, y);
        used_width = used_width.max(x + bitmaps[c][o].width);
        turns[c] = o;
        positions[c] = (x, y);
    }
    Some(Layout { turns, positions, side_pixels: used_width.max(canvas.rows.len()) })
}

/// Packs the charts (UV points, modified in place, their triangles and UV areas) into the unit
/// square with `margin` between charts and half of it to the sides. Returns `None` (charts
/// untouched) for fewer than two or more than `MAX_CHARTS` (150) charts, or past the work budget.
pub fn pack_raster(
    charts: &mut [Vec<[f64; 2]>],
    triangles: &[&[[u32; 3]]],
    areas: &[f64],
    margin: f64,
    rotate: bool,
) -> Option<Packing> {
    let total: f64 = areas.iter().sum();
    // One chart: its minimum-area rectangle is as good as its shape; nothing to interlock.
    if charts.len() < 2 || charts.len() > MAX_CHARTS || !(total > 0.0) {
        return None;
    }
    let shapes: Vec<Shape> = charts
        .iter()
        .zip(triangles)
        .map(|(uv, &tris)| {
            let (t, size) = orient(uv, rotate);
            Shape { points: uv.iter().map(|&p| t.apply(p)).collect(), size, triangles: tris }
        })
        .collect();
    let triangle_count = triangles.iter().map(|t| t.len()).sum::<usize>() as f64;
    let footprint = (PIXELS_PER_TRIANGLE * triangle_count).clamp(MIN_FOOTPRINT_PIXELS, FOOTPRINT_PIXELS);
    let pixel = (total / footprint).sqrt();
    let box_pixels: f64 = shapes.iter().map(|s| (s.size[0] / pixel + 2.0) * (s.size[1] / pixel + 2.0)).sum();
    if !(box_pixels <= MAX_BOX_PIXELS) {
        return None;
    }
    let mut order: Vec<usize> = (0..charts.len()).collect();
    order.sort_by(|&a, &b| areas[b].total_cmp(&areas[a]).then(a.cmp(&b)));
    // The margin is in final units and the final scale depends on the layout: re-derive the
    // padding from the enclosing square until it holds (as `pack` does).
    let mut side = total.sqrt() / 0.6;
    let mut result = None;
    for _ in 0..6 {
        let pad = 0.5 * margin * side;
        let bitmaps: Vec<Vec<Bitmap>> = shapes
            .iter()
            .map(|s| {
                let turns = if rotate { 4 } else { 1 };
                (0..turns).map(|k| s.turned_times(k).rasterize(pixel, pad)).collect()
            })
            .collect();
        let covered: usize =
            bitmaps.iter().map(|b| b[0].bits.iter().map(|w| w.count_ones() as usize).sum::<usize>()).sum();
        let widest = bitmaps.iter().map(|b| b.iter().map(|m| m.width).min().unwrap_or(1)).max().unwrap_or(1);
        let best = [1.0, 1.1, 1.25]
            .par_iter()
            .map(|f| ((f * (covered as f64).sqrt()).ceil() as usize).max(widest))
            .map(|w| layout(&bitmaps, &order, w))
            .collect::<Option<Vec<Layout>>>()?
            .into_iter()
            .min_by_key(|l| l.side_pixels)?;
        let used = best.side_pixels as f64 * pixel;
        let achieved = pad / used;
        result = Some((best, pad, used));
        if margin == 0.0 || achieved >= 0.5 * margin * (1.0 - 1e-12) {
            break;
        }
        side = used * 1.05;
    }
    let (best, pad, used) = result?;
    if !(0.5 * margin * used <= pad * (1.0 + 1e-9)) {
        return None;
    }
    let scale = 1.0 / used;
    for (c, uv) in charts.iter_mut().enumerate() {
        let shape = shapes[c].turned_times(best.turns[c]);
        let (x, y) = best.positions[c];
        let origin = [x as f64 * pixel + pad, y as f64 * pixel + pad];
        for (p, q) in uv.iter_mut().zip(&shape.points) {
            *p = [(q[0] + origin[0]) * scale, (q[1] + origin[1]) * scale];
        }
    }
    Some(Packing { utilization: total * scale * scale })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_box_test_separates_and_touches() {
        let t = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(triangle_meets_box(&t, [0.2, 0.2, 0.3, 0.3]));
        assert!(!triangle_meets_box(&t, [0.6, 0.6, 0.7, 0.7]), "beyond the hypotenuse");
        assert!(triangle_meets_box(&t, [0.5, 0.5, 0.7, 0.7]), "touching the hypotenuse");
        assert!(!triangle_meets_box(&t, [1.1, 0.0, 1.2, 0.1]));
        let clockwise = [t[0], t[2], t[1]];
        assert!(!triangle_meets_box(&clockwise, [0.6, 0.6, 0.7, 0.7]), "either orientation");
        assert!(triangle_meets_box(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]], [0.4, 0.4, 0.6, 0.6]), "degenerate");
    }

    #[test]
    fn l_shapes_interlock_better_than_their_rectangles() {
        // Two L-shaped charts (three unit squares each): their bounding squares (2×2) cannot
        // share a 2-wide strip better than stacking, their shapes can.
        let l = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
        let tris: Vec<[u32; 3]> = vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]];
        let mut charts = vec![l.clone(), l.clone()];
        let packing = pack_raster(&mut charts, &[&tris, &tris], &[3.0, 3.0], 0.01, true).expect("packed");
        assert!(packing.utilization > 0.5, "{}", packing.utilization);
        for uv in &charts {
            assert!(uv.iter().flatten().all(|&x| (0.0..=1.0).contains(&x)));
        }
    }
}
