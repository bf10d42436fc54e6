//! Packing existing UV islands into the unit square (`atlas::repack`), as Blender's *Pack
//! Islands* does: convert, call, convert back.

use super::status::UvfStatus;
use super::{borrow_slice, borrow_slice_mut, checked_count, guard, read_options, SizedOut};
use uvflat_core::atlas::repack::{pack_islands, RepackOptions};

/// Options of `uvf_pack_islands`. Initialise with `uvf_pack_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfPackOptions {
    /// `sizeof(UvfPackOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// Gap between islands in the unit square, half of it to the square's sides, in [0, 0.5)
    /// (default 0.005).
    pub margin: f64,
    /// Non-zero: islands may be rotated (to their minimum-area rectangle, and by quarter turns;
    /// default 1). Turn it off for UVs of a non-square texture whose islands were squeezed to
    /// its aspect ratio: a rotation there would shear them in the image.
    pub rotate: u32,
}

impl Default for UvfPackOptions {
    fn default() -> Self {
        let d = RepackOptions::default();
        UvfPackOptions { struct_size: std::mem::size_of::<Self>(), margin: d.margin, rotate: d.rotate as u32 }
    }
}

const PACK_OPTIONS_V1: usize = std::mem::size_of::<UvfPackOptions>();

/// What `uvf_pack_islands` did. The caller sets `struct_size`; the library writes only the
/// fields that fit in that many bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfPackReport {
    /// `sizeof(UvfPackReport)`, set by the caller.
    pub struct_size: usize,
    /// Islands packed.
    pub islands: usize,
    /// Fraction of the unit square covered by islands.
    pub utilization: f64,
}

/// Fills `options` with defaults (margin 0.005, rotation on).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_pack_options_default(options: *mut UvfPackOptions) {
    if !options.is_null() {
        // SAFETY: the caller passes a writable struct or NULL (checked).
        unsafe { options.write(UvfPackOptions::default()) };
    }
}

/// Packs the islands of an existing UV layout into the unit square (Blender's *Pack Islands*):
/// islands are the connected components of the UV triangles (triangles sharing a UV vertex);
/// each is moved rigidly (and rotated when `options->rotate` is set) and scaled uniformly, and
/// no two packed islands overlap (they are at least `options->margin` apart). The packer is the
/// atlas's: the skyline of the islands' minimum-area rectangles and a packing of their
/// rasterized shapes, the one covering more of the square kept.
///
/// `uv`: 2 doubles per UV (`uv_count`); `uv_triangles`: 3 indices into `uv` per triangle.
/// `surface_areas` (NULL: none): the surface (3D) area of every triangle; each island is then
/// scaled so that its UV area equals its surface area before packing (one texel density), and
/// without, islands keep their relative sizes. Islands that overlap in the input are moved as
/// they are, not repaired.
///
/// `uv_out` receives `2 × uv_count` doubles (may be `uv`): the packed UVs, UVs no triangle uses
/// copied unchanged. `island_out` (NULL: not wanted) receives the island of each triangle,
/// numbered in order of their first triangle. `report_out` (NULL: not wanted) the island
/// count and the fraction of the square covered; its `struct_size` must be set.
///
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (NULL or mis-sized array, a UV index ≥ `uv_count`,
/// a non-finite UV, an island of zero UV area, a negative or non-finite surface area, margin
/// outside [0, 0.5), no triangles) or `UVF_INTERNAL_ERROR`; the outputs are untouched on
/// failure.
///
/// # Safety
/// The arrays must hold the stated number of elements; `report_out`, when not NULL, must point
/// to a `UvfPackReport` with its `struct_size` set.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_pack_islands(
    uv: *const f64,
    uv_count: usize,
    uv_triangles: *const u32,
    triangle_count: usize,
    surface_areas: *const f64,
    options: *const UvfPackOptions,
    uv_out: *mut f64,
    island_out: *mut u32,
    report_out: *mut UvfPackReport,
) -> UvfStatus {
    guard(|| {
        let report = unsafe { SizedOut::optional(report_out, "report_out", "UvfPackReport") }?;
        let o = read_options(options, UvfPackOptions::default(), PACK_OPTIONS_V1, "UvfPackOptions")?;
        let points: Vec<[f64; 2]> = borrow_slice(uv, checked_count(uv_count, 2, "uv_count")?, "uv")?
            .chunks_exact(2)
            .map(|p| [p[0], p[1]])
            .collect();
        let triangles: Vec<[u32; 3]> =
            borrow_slice(uv_triangles, checked_count(triangle_count, 3, "triangle_count")?, "uv_triangles")?
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect();
        let areas = if surface_areas.is_null() {
            None
        } else {
            Some(borrow_slice(surface_areas, triangle_count, "surface_areas")?)
        };
        let packed =
            pack_islands(&points, &triangles, areas, &RepackOptions { margin: o.margin, rotate: o.rotate != 0 })?;
        let out = borrow_slice_mut(uv_out, 2 * uv_count, "uv_out")?;
        if !island_out.is_null() {
            borrow_slice_mut(island_out, triangle_count, "island_out")?.copy_from_slice(&packed.island_of_triangle);
        }
        for (d, p) in out.chunks_exact_mut(2).zip(&packed.uv) {
            d.copy_from_slice(p);
        }
        if let Some(report) = report {
            report.write(UvfPackReport { struct_size: 0, islands: packed.islands, utilization: packed.utilization });
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_null_output_is_refused_and_nothing_is_written() {
        let uv = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
        let tri = [0u32, 1, 2];
        let mut island = [7u32];
        let status = unsafe {
            uvf_pack_islands(
                uv.as_ptr(),
                3,
                tri.as_ptr(),
                1,
                std::ptr::null(),
                std::ptr::null(),
                std::ptr::null_mut(),
                island.as_mut_ptr(),
                std::ptr::null_mut(),
            )
        };
        assert_eq!(status, UvfStatus::UVF_INVALID_ARGUMENT);
        assert_eq!(island, [7]);
    }
}
