//! SVG picture of a uv layout, to look at a parameterization.
//!
//! The layout's bounding box is fitted, aspect kept, into a 1024 × 1024 px square with a 16 px
//! margin, v pointing up (SVG's y axis points down, so y = top − v·scale). Drawn in order:
//! flipped triangles filled red (orientation judged against the majority by area, exactly as
//! `metrics::uv_orientations` does for `Metrics::flipped`), every interior edge once as a thin
//! grey line, and boundary edges (used by one triangle, as in `metrics::uv_edges`) as thicker
//! black lines. Each class of edges is one `<path>`; above 200 000 triangles the path data is
//! compacted (relative line-tos, 0.1 px precision, edges shorter than that dropped) to keep the
//! file size sane. Triangles with an out-of-range index or a non-finite uv are not drawn.
//!
//! Cost: O(m log m) for m triangles (the edge sort); output about 25 bytes per edge.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::Error;
use crate::metrics::{uv_edges, uv_orientations, UvOrientation};

/// Side of the square picture, in px.
const PICTURE_SIZE: f64 = 1024.0;
/// Empty border around the layout, in px.
const MARGIN: f64 = 16.0;
/// Above this many triangles the path data is written in its compact form.
const HUGE_MESH_TRIANGLES: usize = 200_000;

/// Writes `uv_svg_string(uv, uv_triangles)` to `path`. Errors: an index out of range
/// (`InvalidArgument`, naming the triangle), or the file cannot be written (`Io`).
pub fn write_uv_svg(path: &Path, uv: &[[f64; 2]], uv_triangles: &[[u32; 3]]) -> Result<(), Error> {
    if let Some((t, tri)) = uv_triangles.iter().enumerate().find(|(_, tri)| tri.iter().any(|&i| i as usize >= uv.len()))
    {
        return Err(Error::InvalidArgument(format!(
            "triangle {t} references uv {tri:?} but there are {} uv coordinates",
            uv.len()
        )));
    }
    std::fs::write(path, uv_svg_string(uv, uv_triangles))
        .map_err(|e| Error::Io { path: path.display().to_string(), message: e.to_string() })
}

/// The SVG document of the layout (see the module comment). Never panics; invalid triangles are
/// left out.
pub fn uv_svg_string(uv: &[[f64; 2]], uv_triangles: &[[u32; 3]]) -> String {
    uv_svg_document(uv, uv_triangles, uv_triangles.len() > HUGE_MESH_TRIANGLES)
}

/// The SVG document; `huge` selects the compact path data.
fn uv_svg_document(uv: &[[f64; 2]], uv_triangles: &[[u32; 3]], huge: bool) -> String {
    let orientations = uv_orientations(uv, uv_triangles);
    let drawable: Vec<[u32; 3]> = uv_triangles
        .iter()
        .zip(&orientations)
        .filter(|(_, o)| **o != UvOrientation::Invalid)
        .map(|(t, _)| *t)
        .collect();
    let flipped: Vec<[u32; 3]> = uv_triangles
        .iter()
        .zip(&orientations)
        .filter(|(_, o)| **o == UvOrientation::Flipped)
        .map(|(t, _)| *t)
        .collect();
    let frame = PictureFrame::fitting(uv, &drawable);
    let edges = uv_edges(&drawable);

    let mut svg = String::with_capacity(64 * drawable.len() + 1024);
    svg.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{0}\" viewBox=\"0 0 {0} {0}\">",
        PICTURE_SIZE
    );
    let _ = writeln!(
        svg,
        "<title>uv layout: {} triangles, {} flipped (red), {} boundary edges (black)</title>",
        uv_triangles.len(),
        flipped.len(),
        edges.boundary.len()
    );
    svg.push_str("<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n");
    push_flipped_triangles(&mut svg, &frame, uv, &flipped, huge);
    let (grey_width, decimals) = if huge { (0.25, 1) } else { (0.5, 2) };
    push_edge_path(&mut svg, &frame, uv, &edges.interior, "#999999", grey_width, decimals, huge);
    push_edge_path(&mut svg, &frame, uv, &edges.boundary, "black", 1.5, decimals, huge);
    svg.push_str("</svg>\n");
    svg
}

/// Maps uv to px: uniform scale, centred, v up.
struct PictureFrame {
    lower: [f64; 2],
    scale: f64,
    offset: [f64; 2],
}

impl PictureFrame {
    fn fitting(uv: &[[f64; 2]], triangles: &[[u32; 3]]) -> PictureFrame {
        let mut lower = [f64::INFINITY; 2];
        let mut upper = [f64::NEG_INFINITY; 2];
        for q in triangles.iter().flatten().filter_map(|&i| uv.get(i as usize)) {
            for k in 0..2 {
                lower[k] = lower[k].min(q[k]);
                upper[k] = upper[k].max(q[k]);
            }
        }
        if !(lower[0] <= upper[0] && lower[1] <= upper[1]) {
            return PictureFrame { lower: [0.0; 2], scale: 1.0, offset: [MARGIN; 2] };
        }
        let inner = PICTURE_SIZE - 2.0 * MARGIN;
        let extent = [upper[0] - lower[0], upper[1] - lower[1]];
        let largest = extent[0].max(extent[1]);
        let scale = if largest > 0.0 && (inner / largest).is_finite() { inner / largest } else { 1.0 };
        let offset = [0, 1].map(|k| MARGIN + 0.5 * (inner - extent[k] * scale));
        PictureFrame { lower, scale, offset }
    }

    fn px(&self, q: [f64; 2]) -> [f64; 2] {
        let x = self.offset[0] + (q[0] - self.lower[0]) * self.scale;
        let y = PICTURE_SIZE - self.offset[1] - (q[1] - self.lower[1]) * self.scale;
        [x, y]
    }
}

fn push_flipped_triangles(svg: &mut String, frame: &PictureFrame, uv: &[[f64; 2]], flipped: &[[u32; 3]], huge: bool) {
    if flipped.is_empty() {
        return;
    }
    let corners = |t: &[u32; 3]| t.map(|i| frame.px(uv[i as usize]));
    if huge {
        svg.push_str("<path fill=\"red\" stroke=\"none\" d=\"");
        for t in flipped {
            let [a, b, c] = corners(t);
            svg.push('M');
            push_point(svg, a, 1);
            svg.push('L');
            push_point(svg, b, 1);
            svg.push('L');
            push_point(svg, c, 1);
            svg.push('Z');
        }
        svg.push_str("\"/>\n");
    } else {
        for t in flipped {
            svg.push_str("<polygon fill=\"red\" stroke=\"none\" points=\"");
            for (k, p) in corners(t).iter().enumerate() {
                if k > 0 {
                    svg.push(' ');
                }
                push_number(svg, p[0], 2);
                svg.push(',');
                push_number(svg, p[1], 2);
            }
            svg.push_str("\"/>\n");
        }
    }
}

/// One `<path>` with a move-to and line-to per edge; `relative` writes the line-to as an offset
/// and drops edges shorter than the precision.
#[allow(clippy::too_many_arguments)]
fn push_edge_path(
    svg: &mut String,
    frame: &PictureFrame,
    uv: &[[f64; 2]],
    edges: &[[u32; 2]],
    colour: &str,
    width: f64,
    decimals: usize,
    relative: bool,
) {
    if edges.is_empty() {
        return;
    }
    let _ =
        write!(svg, "<path fill=\"none\" stroke=\"{colour}\" stroke-width=\"{width}\" stroke-linecap=\"round\" d=\"");
    let precision = 0.1f64.powi(decimals as i32);
    for e in edges {
        let a = frame.px(uv[e[0] as usize]);
        let b = frame.px(uv[e[1] as usize]);
        let d = [b[0] - a[0], b[1] - a[1]];
        if relative && d[0].abs() < precision && d[1].abs() < precision {
            continue;
        }
        svg.push('M');
        push_point(svg, a, decimals);
        if relative {
            svg.push('l');
            push_point(svg, d, decimals);
        } else {
            svg.push('L');
            push_point(svg, b, decimals);
        }
    }
    svg.push_str("\"/>\n");
}

/// "x y", or "x-y" when y is written with a minus sign (valid path syntax, one byte shorter).
fn push_point(svg: &mut String, p: [f64; 2], decimals: usize) {
    push_number(svg, p[0], decimals);
    let separator = svg.len();
    svg.push(' ');
    push_number(svg, p[1], decimals);
    if svg[separator + 1..].starts_with('-') {
        svg.remove(separator);
    }
}

/// A number with at most `decimals` decimals, trailing zeros dropped ("12.5", "3", "-0.25").
fn push_number(svg: &mut String, x: f64, decimals: usize) {
    let start = svg.len();
    let _ = write!(svg, "{x:.decimals$}");
    if svg[start..].contains('.') {
        let trimmed = svg.trim_end_matches('0').trim_end_matches('.').len();
        svg.truncate(trimmed);
    }
    if &svg[start..] == "-0" {
        svg.truncate(start);
        svg.push('0');
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_square_grid(n: u32) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
        let mut uv = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                uv.push([i as f64 / n as f64, j as f64 / n as f64]);
            }
        }
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (uv, triangles)
    }

    fn count(haystack: &str, needle: &str) -> usize {
        haystack.matches(needle).count()
    }

    #[test]
    fn one_flipped_triangle_is_one_red_polygon() {
        let (uv, mut triangles) = unit_square_grid(4);
        triangles[7].swap(1, 2);
        let svg = uv_svg_string(&uv, &triangles);
        assert!(svg.starts_with("<?xml") && svg.trim_end().ends_with("</svg>"));
        assert_eq!(count(&svg, "<svg "), 1);
        assert_eq!(count(&svg, "<polygon"), 1);
        assert_eq!(count(&svg, "fill=\"red\""), 1);
        // Every element is closed: self-closing tags plus <svg>, <title> and their end tags.
        assert_eq!(count(&svg, "<") - count(&svg, "</") - count(&svg, "<?"), count(&svg, "/>") + 2);
        assert_eq!(count(&svg, "</"), 2);
    }

    #[test]
    fn layout_fills_the_square_with_v_up() {
        let (uv, triangles) = unit_square_grid(1);
        let svg = uv_svg_string(&uv, &triangles);
        assert_eq!(count(&svg, "<polygon"), 0);
        // uv (0,0) is bottom-left: (16, 1008); uv (1,1) is top-right: (1008, 16).
        let boundary = svg.lines().find(|l| l.contains("stroke=\"black\"")).unwrap_or("");
        assert!(boundary.contains("M16 1008L1008 1008"), "{boundary}");
        assert!(boundary.contains("1008 16"), "{boundary}");
        // One diagonal interior edge, four boundary edges.
        let interior = svg.lines().find(|l| l.contains("#999999")).unwrap_or("");
        assert_eq!(count(interior, "M"), 1);
        assert_eq!(count(boundary, "M"), 4);
    }

    #[test]
    fn mirrored_layout_has_no_red() {
        let (uv, triangles) = unit_square_grid(3);
        let mirrored: Vec<[f64; 2]> = uv.iter().map(|q| [-q[0], q[1]]).collect();
        assert!(!uv_svg_string(&mirrored, &triangles).contains("fill=\"red\""));
    }

    #[test]
    fn invalid_triangles_are_skipped_or_refused() {
        let (mut uv, mut triangles) = unit_square_grid(2);
        uv[4] = [f64::NAN, 0.0];
        triangles.push([0, 1, 99]);
        let svg = uv_svg_string(&uv, &triangles);
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
        let path = std::env::temp_dir().join(format!("uvflat-svg-{}.svg", std::process::id()));
        let refused = write_uv_svg(&path, &uv, &triangles);
        assert!(matches!(refused, Err(Error::InvalidArgument(m)) if m.contains("triangle 8")));
        triangles.pop();
        write_uv_svg(&path, &uv, &triangles).unwrap();
        assert!(std::fs::read_to_string(&path).unwrap_or_default().contains("</svg>"));
        std::fs::remove_file(&path).ok();
        assert!(uv_svg_string(&[], &[]).contains("</svg>"));
    }

    /// Checks that a path's data is a sequence of M/L/l/Z commands, each with the right number of
    /// well-formed numbers, and returns how many commands it has.
    fn path_commands(d: &str) -> usize {
        let mut commands = 0;
        let mut rest = d;
        while let Some(c) = rest.chars().next() {
            assert!("MLlZ".contains(c), "unexpected {c:?} in {rest:.40}");
            rest = &rest[1..];
            commands += 1;
            let wanted = if c == 'Z' { 0 } else { 2 };
            for k in 0..wanted {
                rest = rest.strip_prefix(' ').filter(|_| k == 1).unwrap_or(rest);
                let end = rest
                    .char_indices()
                    .find(|&(i, ch)| !(ch.is_ascii_digit() || ch == '.' || (ch == '-' && i == 0)))
                    .map_or(rest.len(), |(i, _)| i);
                let number = &rest[..end];
                assert!(number.parse::<f64>().is_ok(), "bad number {number:?}");
                assert!(number.matches('.').count() <= 1 && !number.ends_with('.'), "{number}");
                rest = &rest[end..];
            }
        }
        commands
    }

    fn path_data<'a>(svg: &'a str, stroke: &str) -> &'a str {
        let line = svg.lines().find(|l| l.contains(stroke)).unwrap_or("");
        line.split(" d=\"").nth(1).and_then(|d| d.split('"').next()).unwrap_or("")
    }

    #[test]
    fn compact_paths_of_huge_meshes_are_well_formed() {
        // Tiny negative offsets round to "-0": the writer must not glue them to the x value.
        let mut point = String::new();
        push_point(&mut point, [1.2, -0.04], 1);
        push_point(&mut point, [-3.0, -2.5], 1);
        assert_eq!(point, "1.2 0-3-2.5");

        let (uv, mut triangles) = unit_square_grid(60);
        triangles[100].swap(0, 1);
        let wobbly: Vec<[f64; 2]> = uv
            .iter()
            .enumerate()
            .map(|(i, q)| [q[0] + 1e-3 * (i as f64).sin(), q[1] - 1e-3 * (i as f64).cos()])
            .collect();
        for huge in [false, true] {
            let svg = uv_svg_document(&wobbly, &triangles, huge);
            let interior = path_commands(path_data(&svg, "#999999"));
            assert_eq!(path_commands(path_data(&svg, "stroke=\"black\"")), 2 * 240);
            assert_eq!(path_commands(path_data(&svg, "fill=\"red\"")), if huge { 4 } else { 0 });
            let expected = 2 * (3 * 7200 / 2 - 120);
            assert!(interior <= expected && interior > expected * 9 / 10, "{interior}");
        }
    }

    #[test]
    fn numbers_are_short() {
        let mut s = String::new();
        for (x, d) in [(12.5, 2), (3.0, 2), (-0.001, 2), (7.25, 1), (-4.126, 2), (100.0, 1)] {
            push_number(&mut s, x, d);
            s.push(' ');
        }
        assert_eq!(s, "12.5 3 0 7.2 -4.13 100 ");
    }
}
