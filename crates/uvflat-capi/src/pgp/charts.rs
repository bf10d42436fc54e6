//! Charts of a PGP result (Ray et al. 2006, §3.3–3.4): the chart layout along the iso-2kπ lines and
//! the per-chart parameterization of the cut surface.

use crate::pgp::solve::{handle, UvfPgp};
use crate::pgp::{check_optional, copy_optional};
use crate::status::UvfStatus;
use crate::SizedOut;
use crate::{borrow_slice_mut, guard};
use uvflat_core::error::{Error, Result};
use uvflat_core::methods::pgp::charts::{chart_parameterization, ChartKind, ChartParameterization};
use uvflat_core::methods::pgp::ChartLayout;

/// The chart layout of a PGP result (Ray et al. 2006, §3.3): created by
/// `uvf_pgp_chart_layout`, read with `uvf_chart_layout_info` and `uvf_chart_layout_copy`,
/// released with `uvf_chart_layout_free`.
pub struct UvfChartLayout {
    layout: ChartLayout,
}

/// Counts of a chart layout.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfChartLayoutInfo {
    /// `sizeof(UvfChartLayoutInfo)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Chart-boundary polylines.
    pub polyline_count: usize,
    /// Points of all polylines (3 doubles each in `uvf_chart_layout_copy`).
    pub point_count: usize,
    /// Charts (faces bounded by the polylines).
    pub chart_count: usize,
    /// Charts with four corners (the regular ones).
    pub four_corner_chart_count: usize,
}

/// Chart layout (§3.3, Algorithm 2): the chart boundaries along the iso-2kπ lines of θ and φ
/// as polylines on the surface between chart corners, and the number of corners of every
/// chart (the per-chart parameterization of §3.4: `uvf_pgp_charts`). Returns `UVF_OK` (a
/// handle in `*layout_out`, free it with `uvf_chart_layout_free`) or `UVF_INVALID_ARGUMENT`
/// (NULL handle or output; `*layout_out` untouched).
///
/// # Safety
/// `pgp` must be a live handle or NULL; `layout_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_chart_layout(pgp: *const UvfPgp, layout_out: *mut *mut UvfChartLayout) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        let slot = borrow_slice_mut(layout_out, 1, "layout_out")?;
        let layout = uvflat_core::methods::pgp::chart_layout(&p.mesh, &p.result)?;
        slot[0] = Box::into_raw(Box::new(UvfChartLayout { layout }));
        Ok(())
    })
}

/// Counts of a chart layout. Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL).
///
/// # Safety
/// `layout` must be a live handle or NULL; `info_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_chart_layout_info(
    layout: *const UvfChartLayout,
    info_out: *mut UvfChartLayoutInfo,
) -> UvfStatus {
    guard(|| {
        // SAFETY: the caller passes a handle from `uvf_pgp_chart_layout` not yet freed, or NULL.
        let l = &unsafe { layout.as_ref() }
            .ok_or_else(|| Error::InvalidArgument("chart layout handle is NULL".into()))?
            .layout;
        unsafe { SizedOut::required(info_out, "info_out", "UvfChartLayoutInfo") }?.write(UvfChartLayoutInfo {
            struct_size: 0,
            polyline_count: l.polylines.len(),
            point_count: l.polylines.iter().map(Vec::len).sum(),
            chart_count: l.chart_corners.len(),
            four_corner_chart_count: l.chart_corners.iter().filter(|&&c| c == 4).count(),
        });
        Ok(())
    })
}

/// Copies a chart layout: `polyline_count` polyline sizes (points per polyline),
/// `3 × point_count` coordinates (the polylines concatenated) and `chart_count` corner counts.
/// Any output may be NULL (with capacity 0) to skip it. Statuses as `uvf_quad_mesh_copy`.
///
/// # Safety
/// `layout` must be a live handle or NULL; each non-NULL output must hold its capacity.
#[no_mangle]
pub unsafe extern "C" fn uvf_chart_layout_copy(
    layout: *const UvfChartLayout,
    polyline_sizes_out: *mut u32,
    polyline_sizes_capacity: usize,
    points_out: *mut f64,
    points_capacity: usize,
    chart_corners_out: *mut u32,
    chart_corners_capacity: usize,
) -> UvfStatus {
    guard(|| {
        // SAFETY: as in `uvf_chart_layout_info`.
        let l = &unsafe { layout.as_ref() }
            .ok_or_else(|| Error::InvalidArgument("chart layout handle is NULL".into()))?
            .layout;
        let sizes: Vec<u32> = l.polylines.iter().map(|p| p.len() as u32).collect();
        let points: Vec<f64> = l.polylines.iter().flatten().flatten().copied().collect();
        check_optional(polyline_sizes_out, polyline_sizes_capacity, sizes.len(), "polyline_sizes_out")?;
        check_optional(points_out, points_capacity, points.len(), "points_out")?;
        check_optional(chart_corners_out, chart_corners_capacity, l.chart_corners.len(), "chart_corners_out")?;
        copy_optional(&sizes, polyline_sizes_out, polyline_sizes_capacity, "polyline_sizes_out")?;
        copy_optional(&points, points_out, points_capacity, "points_out")?;
        copy_optional(&l.chart_corners, chart_corners_out, chart_corners_capacity, "chart_corners_out")
    })
}

/// Releases a chart layout (NULL is ignored).
///
/// # Safety
/// `layout` must come from `uvf_pgp_chart_layout` and not have been freed.
#[no_mangle]
pub unsafe extern "C" fn uvf_chart_layout_free(layout: *mut UvfChartLayout) {
    if !layout.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in `uvf_pgp_chart_layout`.
            drop(unsafe { Box::from_raw(layout) });
        }));
    }
}

/// Chart kind: a chart without singularity, its triangles' (θ, φ) assembled (§3.4).
pub const UVF_PGP_CHART_ASSEMBLED: u32 = 0;

/// Chart kind: four corners, equal opposite sides, re-parameterized by mean-value coordinates.
pub const UVF_PGP_CHART_MEAN_VALUE: u32 = 1;

/// Chart kind: one of the quads an N-sided chart was split into, mean-value re-parameterized.
pub const UVF_PGP_CHART_SPLIT_QUAD: u32 = 2;

/// Chart kind: part of a chart that is not a disk with three or more corners, flattened by the
/// atlas segmentation (no quad structure, not continuous with its neighbours, not folded).
pub const UVF_PGP_CHART_ATLAS: u32 = 3;

/// Chart kind: per-triangle (θ, φ) kept (the atlas failed on it).
pub const UVF_PGP_CHART_UNRESOLVED: u32 = 4;

/// The per-chart parameterization of a PGP result (Ray et al. 2006, §3.3–3.4): the surface
/// cut along the chart boundaries, every chart with its own (u, v). Created by
/// `uvf_pgp_charts`, read with `uvf_pgp_charts_info`, `uvf_pgp_charts_copy` and
/// `uvf_pgp_charts_copy_charts`, released with `uvf_pgp_charts_free`.
pub struct UvfPgpCharts {
    charts: ChartParameterization,
}

/// Counts of a per-chart parameterization.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfPgpChartsInfo {
    /// `sizeof(UvfPgpChartsInfo)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Vertices of the cut triangulation (the input's first, in the same order).
    pub vertex_count: usize,
    /// Triangles of the cut triangulation.
    pub triangle_count: usize,
    /// Charts.
    pub chart_count: usize,
    /// Charts of each kind, indexed by `UVF_PGP_CHART_*`.
    pub kind_counts: [usize; 5],
}

/// Per-chart parameterization (§3.3–3.4): cuts the surface along the iso-lines at `density`
/// lines per period (1: the paper's iso-2kπ chart boundaries; a whole number) and
/// parameterizes every chart in cells (a regular chart is the unit square): charts without
/// singularity are assembled from the per-triangle (θ, φ), four-sided charts with
/// singularities are re-parameterized by mean-value coordinates, N-sided ones split into N
/// quads; the (u, v) of two charts agree along their common side. Returns `UVF_OK` (a handle
/// in `*charts_out`, free it with `uvf_pgp_charts_free`) or `UVF_INVALID_ARGUMENT` (NULL handle
/// or output, bad density, or one whose line graph would not fit in the memory available;
/// `*charts_out` untouched).
///
/// # Safety
/// `pgp` must be a live handle or NULL; `charts_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_charts(
    pgp: *const UvfPgp,
    density: f64,
    charts_out: *mut *mut UvfPgpCharts,
) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        let slot = borrow_slice_mut(charts_out, 1, "charts_out")?;
        let charts = chart_parameterization(&p.mesh, &p.result, density)?;
        slot[0] = Box::into_raw(Box::new(UvfPgpCharts { charts }));
        Ok(())
    })
}

/// The parameterization behind a charts handle.
///
/// # Safety
/// `charts` must be a live handle or NULL.
unsafe fn charts_ref<'a>(charts: *const UvfPgpCharts) -> Result<&'a ChartParameterization> {
    // SAFETY: the caller passes a handle from `uvf_pgp_charts` not yet freed, or NULL.
    Ok(&unsafe { charts.as_ref() }.ok_or_else(|| Error::InvalidArgument("charts handle is NULL".into()))?.charts)
}

fn kind_code(kind: ChartKind) -> u32 {
    match kind {
        ChartKind::Assembled => UVF_PGP_CHART_ASSEMBLED,
        ChartKind::MeanValue => UVF_PGP_CHART_MEAN_VALUE,
        ChartKind::SplitQuad => UVF_PGP_CHART_SPLIT_QUAD,
        ChartKind::Atlas => UVF_PGP_CHART_ATLAS,
        ChartKind::Unresolved => UVF_PGP_CHART_UNRESOLVED,
    }
}

/// Counts of a per-chart parameterization. Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL).
///
/// # Safety
/// `charts` must be a live handle or NULL; `info_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_charts_info(
    charts: *const UvfPgpCharts,
    info_out: *mut UvfPgpChartsInfo,
) -> UvfStatus {
    guard(|| {
        let c = unsafe { charts_ref(charts) }?;
        let mut kind_counts = [0usize; 5];
        for ch in &c.charts {
            kind_counts[kind_code(ch.kind) as usize] += 1;
        }
        unsafe { SizedOut::required(info_out, "info_out", "UvfPgpChartsInfo") }?.write(UvfPgpChartsInfo {
            struct_size: 0,
            vertex_count: c.positions.len(),
            triangle_count: c.triangles.len(),
            chart_count: c.charts.len(),
            kind_counts,
        });
        Ok(())
    })
}

/// Copies the cut triangulation and its parameterization: `3 × vertex_count` coordinates,
/// `3 × triangle_count` vertex indices (counter-clockwise like the input), `6 × triangle_count`
/// (u, v) values (per corner, in cells), the chart of every triangle and the input triangle it
/// lies in (`triangle_count` each). Any output may be NULL (with capacity 0) to skip it.
/// Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL handle, a capacity too small; outputs
/// untouched).
///
/// # Safety
/// `charts` must be a live handle or NULL; each non-NULL output must hold its capacity.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_pgp_charts_copy(
    charts: *const UvfPgpCharts,
    positions_out: *mut f64,
    positions_capacity: usize,
    triangles_out: *mut u32,
    triangles_capacity: usize,
    uv_out: *mut f64,
    uv_capacity: usize,
    chart_out: *mut u32,
    chart_capacity: usize,
    origin_out: *mut u32,
    origin_capacity: usize,
) -> UvfStatus {
    guard(|| {
        let c = unsafe { charts_ref(charts) }?;
        let uv: Vec<f64> = c.uv.iter().flatten().flatten().copied().collect();
        check_optional(positions_out, positions_capacity, 3 * c.positions.len(), "positions_out")?;
        check_optional(triangles_out, triangles_capacity, 3 * c.triangles.len(), "triangles_out")?;
        check_optional(uv_out, uv_capacity, uv.len(), "uv_out")?;
        check_optional(chart_out, chart_capacity, c.chart.len(), "chart_out")?;
        check_optional(origin_out, origin_capacity, c.origin.len(), "origin_out")?;
        copy_optional(c.positions.as_flattened(), positions_out, positions_capacity, "positions_out")?;
        copy_optional(c.triangles.as_flattened(), triangles_out, triangles_capacity, "triangles_out")?;
        copy_optional(&uv, uv_out, uv_capacity, "uv_out")?;
        copy_optional(&c.chart, chart_out, chart_capacity, "chart_out")?;
        copy_optional(&c.origin, origin_out, origin_capacity, "origin_out")
    })
}

/// Copies, per chart (`chart_count` entries each): its kind (`UVF_PGP_CHART_*`), its number of
/// corners (0 when it is not a disk), the layout chart it comes from (the same for the quads
/// of one split chart) and its (u, v) extent in cells (2 doubles). Outputs may be NULL (with
/// capacity 0). Statuses as `uvf_pgp_charts_copy`.
///
/// # Safety
/// `charts` must be a live handle or NULL; each non-NULL output must hold its capacity.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_pgp_charts_copy_charts(
    charts: *const UvfPgpCharts,
    kinds_out: *mut u32,
    kinds_capacity: usize,
    corners_out: *mut u32,
    corners_capacity: usize,
    layout_out: *mut u32,
    layout_capacity: usize,
    sizes_out: *mut f64,
    sizes_capacity: usize,
) -> UvfStatus {
    guard(|| {
        let c = unsafe { charts_ref(charts) }?;
        let kinds: Vec<u32> = c.charts.iter().map(|ch| kind_code(ch.kind)).collect();
        let corners: Vec<u32> = c.charts.iter().map(|ch| ch.corners).collect();
        let layout: Vec<u32> = c.charts.iter().map(|ch| ch.layout).collect();
        let sizes: Vec<f64> = c.charts.iter().flat_map(|ch| ch.size).collect();
        check_optional(kinds_out, kinds_capacity, kinds.len(), "kinds_out")?;
        check_optional(corners_out, corners_capacity, corners.len(), "corners_out")?;
        check_optional(layout_out, layout_capacity, layout.len(), "layout_out")?;
        check_optional(sizes_out, sizes_capacity, sizes.len(), "sizes_out")?;
        copy_optional(&kinds, kinds_out, kinds_capacity, "kinds_out")?;
        copy_optional(&corners, corners_out, corners_capacity, "corners_out")?;
        copy_optional(&layout, layout_out, layout_capacity, "layout_out")?;
        copy_optional(&sizes, sizes_out, sizes_capacity, "sizes_out")
    })
}

/// Releases a per-chart parameterization (NULL is ignored).
///
/// # Safety
/// `charts` must come from `uvf_pgp_charts` and not have been freed.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_charts_free(charts: *mut UvfPgpCharts) {
    if !charts.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in `uvf_pgp_charts`.
            drop(unsafe { Box::from_raw(charts) });
        }));
    }
}
