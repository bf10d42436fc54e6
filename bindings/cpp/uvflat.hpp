// uvflat.hpp: header-only C++17 wrapper over the uvflat C API (include/uvflat.h).
//
// - Inputs: any contiguous range of doubles (3 per vertex) and uint32_t (3 per triangle),
//   passed as pointer + count or as std::vector; outputs come back as std::vector.
// - Failures throw uvflat::Error, which carries the UvfStatus and the library's message.
// - Options are plain structs initialised from the library's defaults; progress callbacks are
//   std::function<bool(double)> returning false to cancel (uvflat::Error with UVF_CANCELLED).
//   An exception thrown by the callback cancels the computation and is rethrown.
//
//   #include <uvflat.hpp>
//   std::vector<double> uv = uvflat::natural_conformal_map(positions, triangles);
//   UvfMetrics m = uvflat::metrics(positions, triangles, uv);
//
// Wrapped: fixed-boundary (barycentric) maps, the natural conformal map (LSCM), ABF / ABF++,
// the non-linear maps (SLIM, ARAP, MIPS, stretch, Green–Lagrange, Degener), the spectral
// conformal map, circle patterns (free, prescribed or convex boundary; cone maps and automatic
// cone placement), metrics, the cut to a disk and the boundary editor. Everything else is in
// the C API (include/uvflat.h), which this header includes.
#ifndef UVFLAT_HPP
#define UVFLAT_HPP

#include "uvflat.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace uvflat {

/// A failed uvflat call: the status code and the library's message.
class Error : public std::runtime_error {
public:
    Error(UvfStatus status, const std::string &message) : std::runtime_error(message), status_(status) {}
    UvfStatus status() const noexcept { return status_; }

private:
    UvfStatus status_;
};

namespace detail {

inline void check(UvfStatus status) {
    if (status != UVF_OK) throw Error(status, uvf_last_error_message());
}

/// Holds a std::function progress callback for the duration of one call and remembers an
/// exception it threw, so it can be rethrown once the C call has returned.
struct Progress {
    const std::function<bool(double)> *callback = nullptr;
    std::exception_ptr error;

    static int trampoline(void *user, double fraction) {
        auto *self = static_cast<Progress *>(user);
        try {
            return (*self->callback)(fraction) ? 0 : 1;
        } catch (...) {
            self->error = std::current_exception();
            return 1;
        }
    }

    template <class Options> void install(Options &o) {
        if (callback && *callback) {
            o.progress = &Progress::trampoline;
            o.progress_user = this;
        }
    }

    void finish(UvfStatus status) const {
        if (error) std::rethrow_exception(error);
        check(status);
    }
};

/// Runs a per-vertex UV method `method(positions, nv, triangles, nt, &options, uv_out)` with
/// the C options `o` and the C++ progress callback; returns the UVs (2 per vertex).
template <class COptions, class Method>
std::vector<double> run_uv_method(Method method, COptions &o, const std::function<bool(double)> &callback,
                                  const double *positions, std::size_t vertex_count, const std::uint32_t *triangles,
                                  std::size_t triangle_count) {
    Progress progress;
    progress.callback = &callback;
    progress.install(o);
    std::vector<double> uv(2 * vertex_count);
    progress.finish(method(positions, vertex_count, triangles, triangle_count, &o, uv.data()));
    return uv;
}

inline std::size_t count_of(const std::vector<double> &flat, std::size_t per, const char *what) {
    if (flat.size() % per != 0) {
        throw Error(UVF_INVALID_ARGUMENT, std::string(what) + " must hold " + std::to_string(per) +
                                              " values per element, but its size is " + std::to_string(flat.size()));
    }
    return flat.size() / per;
}

inline std::size_t count_of(const std::vector<std::uint32_t> &flat, const char *what) {
    if (flat.size() % 3 != 0) {
        throw Error(UVF_INVALID_ARGUMENT,
                    std::string(what) + " must hold 3 indices per triangle, but its size is " + std::to_string(flat.size()));
    }
    return flat.size() / 3;
}

} // namespace detail

/// Library version string, e.g. "0.1.0".
inline std::string version() { return uvf_version(); }

/// Barycentric weights of `fixed_boundary_map` (UVF_WEIGHTS_*).
enum class Weights : std::uint32_t {
    uniform = UVF_WEIGHTS_UNIFORM,
    floater = UVF_WEIGHTS_FLOATER,
    authalic = UVF_WEIGHTS_AUTHALIC,
    conformal = UVF_WEIGHTS_CONFORMAL,
    mean_value = UVF_WEIGHTS_MEAN_VALUE,
    intrinsic = UVF_WEIGHTS_INTRINSIC,
};

/// Boundary shape of `fixed_boundary_map` (UVF_BOUNDARY_*); `given` uses `given_vertices`.
enum class Boundary : std::uint32_t { circle = UVF_BOUNDARY_CIRCLE, square = UVF_BOUNDARY_SQUARE, given = UVF_BOUNDARY_GIVEN };

/// Spacing of boundary vertices (UVF_DISTRIBUTION_*).
enum class Distribution : std::uint32_t {
    uniform = UVF_DISTRIBUTION_UNIFORM,
    chord = UVF_DISTRIBUTION_CHORD,
    centripetal = UVF_DISTRIBUTION_CENTRIPETAL,
};

/// Options of `fixed_boundary_map`; defaults as `uvf_fixed_boundary_options_default`.
struct FixedBoundaryOptions {
    Weights weights = Weights::mean_value;
    Boundary boundary = Boundary::circle;
    Distribution distribution = Distribution::chord;
    double lambda = 1.0;
    double mu = 0.0;
    /// For Boundary::given: vertices of whole boundary loops and their UVs (2 per vertex).
    std::vector<std::uint32_t> given_vertices;
    std::vector<double> given_uv;
    std::function<bool(double)> progress;
};

/// A vertex held at a UV position.
struct Pin {
    std::uint32_t vertex;
    double u, v;
};

/// Options of `natural_conformal_map`: no pins means the two boundary vertices farthest apart.
struct NaturalConformalOptions {
    using Pin = uvflat::Pin;
    std::vector<Pin> pins; // empty or exactly two
    std::function<bool(double)> progress;
};

namespace detail {

/// Copies no pins or exactly two into the C options' `pin_count`, `pin_vertices`, `pin_uv`.
template <class COptions> void set_pins(COptions &o, const std::vector<Pin> &pins) {
    if (pins.empty()) return;
    if (pins.size() != 2) throw Error(UVF_INVALID_ARGUMENT, "give no pins or exactly two");
    o.pin_count = 2;
    for (int k = 0; k < 2; ++k) {
        o.pin_vertices[k] = pins[k].vertex;
        o.pin_uv[2 * k] = pins[k].u;
        o.pin_uv[2 * k + 1] = pins[k].v;
    }
}

/// Runs a per-vertex UV method with a report, `method(positions, nv, triangles, nt, &options,
/// uv_out, report_out)`; fills `*report` when it is not null.
template <class COptions, class Report, class Method>
std::vector<double> run_reported(Method method, COptions &o, const std::function<bool(double)> &callback,
                                 const std::vector<double> &positions, const std::vector<std::uint32_t> &triangles,
                                 Report *report) {
    Progress progress;
    progress.callback = &callback;
    progress.install(o);
    const std::size_t nv = count_of(positions, 3, "positions");
    std::vector<double> uv(2 * nv);
    Report r{};
    progress.finish(method(positions.data(), nv, triangles.data(), count_of(triangles, "triangles"), &o, uv.data(), &r));
    if (report) *report = r;
    return uv;
}

} // namespace detail

/// Topology of a mesh (validates it; throws on invalid meshes).
inline UvfMeshInfo mesh_info(const double *positions, std::size_t vertex_count, const std::uint32_t *triangles,
                             std::size_t triangle_count) {
    UvfMeshInfo info{};
    detail::check(uvf_mesh_info(positions, vertex_count, triangles, triangle_count, &info));
    return info;
}

inline UvfMeshInfo mesh_info(const std::vector<double> &positions, const std::vector<std::uint32_t> &triangles) {
    return mesh_info(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                     detail::count_of(triangles, "triangles"));
}

/// Ordered boundary loops (counter-clockwise).
inline std::vector<std::vector<std::uint32_t>> boundary_loops(const std::vector<double> &positions,
                                                              const std::vector<std::uint32_t> &triangles) {
    const std::size_t nv = detail::count_of(positions, 3, "positions"), nt = detail::count_of(triangles, "triangles");
    const UvfMeshInfo info = mesh_info(positions.data(), nv, triangles.data(), nt);
    std::vector<std::uint32_t> vertices(info.boundary_vertices), offsets(info.boundary_loops + 1);
    detail::check(uvf_boundary_loops(positions.data(), nv, triangles.data(), nt, vertices.data(), vertices.size(),
                                     offsets.data(), offsets.size()));
    std::vector<std::vector<std::uint32_t>> loops;
    for (std::size_t k = 0; k + 1 < offsets.size(); ++k) {
        loops.emplace_back(vertices.begin() + offsets[k], vertices.begin() + offsets[k + 1]);
    }
    return loops;
}

/// Fixed-boundary barycentric map; returns 2 doubles per vertex (NaN for unreferenced ones).
inline std::vector<double> fixed_boundary_map(const double *positions, std::size_t vertex_count,
                                              const std::uint32_t *triangles, std::size_t triangle_count,
                                              const FixedBoundaryOptions &options = {}) {
    UvfFixedBoundaryOptions o;
    uvf_fixed_boundary_options_default(&o);
    o.weights = static_cast<std::uint32_t>(options.weights);
    o.boundary = static_cast<std::uint32_t>(options.boundary);
    o.distribution = static_cast<std::uint32_t>(options.distribution);
    o.lambda = options.lambda;
    o.mu = options.mu;
    if (options.given_uv.size() != 2 * options.given_vertices.size()) {
        throw Error(UVF_INVALID_ARGUMENT, "given_uv must hold 2 values per given vertex");
    }
    o.given_count = options.given_vertices.size();
    o.given_vertices = options.given_vertices.data();
    o.given_uv = options.given_uv.data();
    return detail::run_uv_method(uvf_fixed_boundary_map, o, options.progress, positions, vertex_count, triangles,
                                 triangle_count);
}

inline std::vector<double> fixed_boundary_map(const std::vector<double> &positions,
                                              const std::vector<std::uint32_t> &triangles,
                                              const FixedBoundaryOptions &options = {}) {
    return fixed_boundary_map(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                              detail::count_of(triangles, "triangles"), options);
}

/// Natural conformal map (= LSCM); returns 2 doubles per vertex (NaN for unreferenced ones).
inline std::vector<double> natural_conformal_map(const double *positions, std::size_t vertex_count,
                                                 const std::uint32_t *triangles, std::size_t triangle_count,
                                                 const NaturalConformalOptions &options = {}) {
    UvfNaturalConformalOptions o;
    uvf_natural_conformal_options_default(&o);
    detail::set_pins(o, options.pins);
    return detail::run_uv_method(uvf_natural_conformal_map, o, options.progress, positions, vertex_count, triangles,
                                 triangle_count);
}

inline std::vector<double> natural_conformal_map(const std::vector<double> &positions,
                                                 const std::vector<std::uint32_t> &triangles,
                                                 const NaturalConformalOptions &options = {}) {
    return natural_conformal_map(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                                 detail::count_of(triangles, "triangles"), options);
}

/// ABF variant (UVF_ABF_VARIANT_*).
enum class AbfVariant : std::uint32_t { abf = UVF_ABF_VARIANT_ABF, abf_plus_plus = UVF_ABF_VARIANT_ABF_PLUS_PLUS };

/// Options of `abf`: no pins means the library's automatic pair for the reconstruction.
struct AbfOptions {
    AbfVariant variant = AbfVariant::abf_plus_plus;
    std::vector<Pin> pins; // empty or exactly two
    std::function<bool(double)> progress;
};

/// Angle Based Flattening (Sheffer & de Sturler 2001) or ABF++ (Sheffer et al. 2005), free
/// boundary; returns 2 doubles per vertex, and the solver's figures in `*report` if given.
inline std::vector<double> abf(const std::vector<double> &positions, const std::vector<std::uint32_t> &triangles,
                               const AbfOptions &options = {}, UvfAbfReport *report = nullptr) {
    UvfAbfOptions o;
    uvf_abf_options_default(&o);
    o.variant = static_cast<std::uint32_t>(options.variant);
    detail::set_pins(o, options.pins);
    return detail::run_reported(uvf_abf, o, options.progress, positions, triangles, report);
}

/// Distortion energy of `nonlinear_map` (UVF_NONLINEAR_*).
enum class Nonlinear : std::uint32_t {
    slim = UVF_NONLINEAR_SLIM,
    arap = UVF_NONLINEAR_ARAP,
    mips = UVF_NONLINEAR_MIPS,
    stretch = UVF_NONLINEAR_STRETCH,
    green_lagrange = UVF_NONLINEAR_GREEN_LAGRANGE,
    degener = UVF_NONLINEAR_DEGENER,
};

/// Options of `nonlinear_map`; `iterations` 0 keeps the library's default.
struct NonlinearOptions {
    Nonlinear method = Nonlinear::slim;
    std::uint32_t iterations = 0;
    std::function<bool(double)> progress;
};

/// Free-boundary, flip-free map minimizing a non-linear distortion energy from the mean value
/// map; returns 2 doubles per vertex.
inline std::vector<double> nonlinear_map(const std::vector<double> &positions,
                                         const std::vector<std::uint32_t> &triangles,
                                         const NonlinearOptions &options = {}, UvfNonlinearReport *report = nullptr) {
    UvfNonlinearOptions o;
    uvf_nonlinear_options_default(&o);
    o.method = static_cast<std::uint32_t>(options.method);
    if (options.iterations != 0) o.iterations = options.iterations;
    return detail::run_reported(uvf_nonlinear_map, o, options.progress, positions, triangles, report);
}

/// Spectral conformal map (Mullen et al. 2008): free boundary, no pins; 2 doubles per vertex.
inline std::vector<double> spectral_conformal_map(const std::vector<double> &positions,
                                                  const std::vector<std::uint32_t> &triangles,
                                                  const std::function<bool(double)> &progress = {},
                                                  UvfSpectralReport *report = nullptr) {
    UvfSpectralOptions o;
    uvf_spectral_options_default(&o);
    return detail::run_reported(uvf_spectral_conformal_map, o, progress, positions, triangles, report);
}

/// Options of the circle-pattern maps (Kharevych, Springborn & Schröder 2006).
struct CirclePatternOptions {
    /// Flip to the intrinsic Delaunay triangulation first (the paper's method).
    bool intrinsic_delaunay = true;
    /// Keep the uv boundary convex: the map then cannot overlap itself.
    bool convex_boundary = false;
    /// Empty (free boundary) or one turning angle per vertex, NaN where free.
    std::vector<double> boundary_curvature;
    std::vector<Pin> pins; // empty or exactly two (not for cone maps)
    std::function<bool(double)> progress;
};

namespace detail {

inline UvfCirclePatternOptions circle_pattern_options(const CirclePatternOptions &options, std::size_t vertex_count) {
    UvfCirclePatternOptions o;
    uvf_circle_pattern_options_default(&o);
    o.intrinsic_delaunay = options.intrinsic_delaunay ? 1 : 0;
    o.convex_boundary = options.convex_boundary ? 1 : 0;
    if (!options.boundary_curvature.empty()) {
        if (options.boundary_curvature.size() != vertex_count) {
            throw Error(UVF_INVALID_ARGUMENT, "boundary_curvature must hold one value per vertex");
        }
        o.boundary_curvature = options.boundary_curvature.data();
    }
    set_pins(o, options.pins);
    return o;
}

} // namespace detail

/// Conformal map of a disk (holes allowed) by circle patterns; 2 doubles per vertex.
inline std::vector<double> circle_pattern_map(const std::vector<double> &positions,
                                              const std::vector<std::uint32_t> &triangles,
                                              const CirclePatternOptions &options = {},
                                              UvfCirclePatternReport *report = nullptr) {
    UvfCirclePatternOptions o = detail::circle_pattern_options(options, detail::count_of(positions, 3, "positions"));
    return detail::run_reported(uvf_circle_pattern_map, o, options.progress, positions, triangles, report);
}

/// A cone singularity: an interior vertex and its curvature (2π minus the cone angle).
struct Cone {
    std::uint32_t vertex;
    double curvature;
};

/// Cones placed greedily where the conformal flattening's log scale is largest (Ben-Chen et
/// al. 2008), until it is at most `max_log_scale` or `max_cones` are placed; the largest log
/// scale left goes to `*max_log_scale_out` if given.
inline std::vector<Cone> place_cones(const std::vector<double> &positions, const std::vector<std::uint32_t> &triangles,
                                     std::uint32_t max_cones = 64, double max_log_scale = 0.7,
                                     double *max_log_scale_out = nullptr) {
    UvfConePlacementOptions o;
    uvf_cone_placement_options_default(&o);
    o.max_cones = max_cones;
    o.max_log_scale = max_log_scale;
    const std::size_t nv = detail::count_of(positions, 3, "positions");
    std::vector<std::uint32_t> vertices(std::max<std::size_t>(std::min<std::size_t>(max_cones, nv), 1));
    std::vector<double> curvatures(vertices.size());
    std::size_t count = 0;
    double largest = 0;
    detail::check(uvf_place_cones(positions.data(), nv, triangles.data(),
                                  detail::count_of(triangles, "triangles"), &o, vertices.data(), curvatures.data(),
                                  &count, &largest));
    if (max_log_scale_out) *max_log_scale_out = largest;
    std::vector<Cone> cones(count);
    for (std::size_t k = 0; k < count; ++k) cones[k] = Cone{vertices[k], curvatures[k]};
    return cones;
}

/// Conformal map with cone singularities by circle patterns, on a mesh of any genus cut through
/// the cones: 6 doubles per triangle (u, v of its three corners).
inline std::vector<double> circle_pattern_cone_map(const std::vector<double> &positions,
                                                   const std::vector<std::uint32_t> &triangles,
                                                   const std::vector<Cone> &cones,
                                                   const CirclePatternOptions &options = {},
                                                   UvfCirclePatternReport *report = nullptr) {
    UvfCirclePatternOptions o = detail::circle_pattern_options(options, detail::count_of(positions, 3, "positions"));
    std::vector<std::uint32_t> vertices;
    std::vector<double> curvatures;
    for (const Cone &c : cones) {
        vertices.push_back(c.vertex);
        curvatures.push_back(c.curvature);
    }
    detail::Progress progress;
    progress.callback = &options.progress;
    progress.install(o);
    const std::size_t nt = detail::count_of(triangles, "triangles");
    std::vector<double> corner_uv(6 * nt);
    UvfCirclePatternReport r{};
    progress.finish(uvf_circle_pattern_cone_map(positions.data(), detail::count_of(positions, 3, "positions"),
                                                triangles.data(), nt, vertices.data(), curvatures.data(),
                                                cones.size(), &o, corner_uv.data(), &r));
    if (report) *report = r;
    return corner_uv;
}

enum class SphereMethod : std::uint32_t {
    tutte_gnomonic = UVF_SPHERE_TUTTE_GNOMONIC,
    gauss_seidel = UVF_SPHERE_GAUSS_SEIDEL,
    stereographic = UVF_SPHERE_STEREOGRAPHIC,
    circle_patterns = UVF_SPHERE_CIRCLE_PATTERNS,
};

/// Spherical parameterization of a closed genus-0 mesh: 3 doubles per vertex on the unit sphere;
/// the flipped spherical triangles go to `*flipped` if given (0 with `tutte_gnomonic`).
inline std::vector<double> spherical_map(const std::vector<double> &positions,
                                         const std::vector<std::uint32_t> &triangles,
                                         SphereMethod method = SphereMethod::tutte_gnomonic,
                                         std::size_t *flipped = nullptr) {
    UvfSphereOptions o;
    uvf_sphere_options_default(&o);
    o.method = static_cast<std::uint32_t>(method);
    const std::size_t nv = detail::count_of(positions, 3, "positions");
    std::vector<double> sphere(3 * nv);
    std::size_t count = 0;
    detail::check(uvf_spherical_map(positions.data(), nv, triangles.data(), detail::count_of(triangles, "triangles"),
                                    &o, sphere.data(), &count));
    if (flipped) *flipped = count;
    return sphere;
}

/// Options of `quadcover`; 0 for `grid_spacing` is 3 mean edge lengths.
struct QuadCoverOptions {
    double grid_spacing = 0;
    double alignment = 1;
    bool round = true;
    bool cones_on_grid = false;
    /// ± cone pairs of the field closer than this many grid cells are cancelled, cones that
    /// close to the boundary moved onto it; 0 keeps the field's cones.
    double pair_cells = 2;
    /// Untangle the folds left after rounding (regular vertices move; gaps, seams and cones
    /// stay).
    bool untangle = true;
    /// One tangent vector per triangle (3 doubles each); empty: the curvature-aligned field.
    std::vector<double> field;
    std::function<bool(double)> progress;
};

/// A QuadCover map: (u, v) per corner in grid units (6 doubles per triangle), 4 × the field's
/// index per vertex (0 off the cones) and the report.
struct QuadCoverMap {
    std::vector<double> corner_uv;
    std::vector<std::int32_t> cone_index;
    UvfQuadCoverReport report{};
};

/// QuadCover (Kälberer, Nieser & Polthier 2007): a seamless global parameterization whose
/// integer iso-lines close up over the surface (quarter turns and integer translations across
/// every seam).
inline QuadCoverMap quadcover(const std::vector<double> &positions, const std::vector<std::uint32_t> &triangles,
                              const QuadCoverOptions &options = {}) {
    UvfQuadCoverOptions o;
    uvf_quadcover_options_default(&o);
    o.grid_spacing = options.grid_spacing;
    o.alignment = options.alignment;
    o.round = options.round ? 1 : 0;
    o.cones_on_grid = options.cones_on_grid ? 1 : 0;
    o.pair_cells = options.pair_cells;
    o.untangle = options.untangle ? 1 : 0;
    const std::size_t nv = detail::count_of(positions, 3, "positions");
    const std::size_t nt = detail::count_of(triangles, "triangles");
    if (!options.field.empty() && options.field.size() != 3 * nt) {
        throw Error(UVF_INVALID_ARGUMENT, "the field must hold 3 doubles per triangle (" + std::to_string(3 * nt) +
                                              "), but its size is " + std::to_string(options.field.size()));
    }
    detail::Progress progress;
    progress.callback = &options.progress;
    progress.install(o);
    QuadCoverMap map;
    map.corner_uv.resize(6 * nt);
    map.cone_index.resize(nv);
    progress.finish(uvf_quadcover(positions.data(), nv, triangles.data(), nt, &o,
                                  options.field.empty() ? nullptr : options.field.data(), map.corner_uv.data(),
                                  map.cone_index.data(), &map.report));
    return map;
}

/// Distortion of per-vertex UVs (2 doubles per vertex).
inline UvfMetrics metrics(const std::vector<double> &positions, const std::vector<std::uint32_t> &triangles,
                          const std::vector<double> &uv) {
    UvfMetrics m{};
    detail::check(uvf_metrics(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                              detail::count_of(triangles, "triangles"), uv.data(), detail::count_of(uv, 2, "uv"),
                              nullptr, &m));
    return m;
}

/// Distortion of per-corner UVs: `uv_triangles` holds 3 indices into `uv` per triangle.
inline UvfMetrics metrics(const std::vector<double> &positions, const std::vector<std::uint32_t> &triangles,
                          const std::vector<double> &uv, const std::vector<std::uint32_t> &uv_triangles) {
    if (uv_triangles.size() != triangles.size()) {
        throw Error(UVF_INVALID_ARGUMENT, "uv_triangles must have as many entries as triangles");
    }
    UvfMetrics m{};
    detail::check(uvf_metrics(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                              detail::count_of(triangles, "triangles"), uv.data(), detail::count_of(uv, 2, "uv"),
                              uv_triangles.data(), &m));
    return m;
}

/// A mesh cut into a topological disk (`uvf_cut_to_disk`: tree-cotree cut graph); owns the
/// library's handle (move-only, freed by the destructor). Any disk method runs on
/// `positions()` / `triangles()`; `original_vertices()` maps the cut mesh back.
class Cut {
  public:
    Cut(const std::vector<double> &positions, const std::vector<std::uint32_t> &triangles,
        std::uint32_t cost = UVF_CUT_COST_CURVATURE) {
        UvfCutOptions options;
        uvf_cut_options_default(&options);
        options.cost = cost;
        detail::check(uvf_cut_to_disk(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                                      detail::count_of(triangles, "triangles"), &options, &handle_));
    }
    Cut(const Cut &) = delete;
    Cut &operator=(const Cut &) = delete;
    Cut(Cut &&other) noexcept : handle_(std::exchange(other.handle_, nullptr)) {}
    Cut &operator=(Cut &&other) noexcept {
        if (this != &other) {
            uvf_cut_free(handle_);
            handle_ = std::exchange(other.handle_, nullptr);
        }
        return *this;
    }
    ~Cut() { uvf_cut_free(handle_); }

    UvfCutInfo info() const {
        UvfCutInfo i{};
        detail::check(uvf_cut_info(handle_, &i));
        return i;
    }
    std::vector<double> positions() const {
        std::vector<double> out(3 * info().vertex_count);
        detail::check(uvf_cut_copy_positions(handle_, out.data(), out.size()));
        return out;
    }
    std::vector<std::uint32_t> triangles() const {
        std::vector<std::uint32_t> out(3 * info().triangle_count);
        detail::check(uvf_cut_copy_triangles(handle_, out.data(), out.size()));
        return out;
    }
    std::vector<std::uint32_t> original_vertices() const {
        std::vector<std::uint32_t> out(info().vertex_count);
        detail::check(uvf_cut_copy_original_vertices(handle_, out.data(), out.size()));
        return out;
    }
    /// Input vertex pairs along the cut (2 per edge).
    std::vector<std::uint32_t> edges() const {
        std::vector<std::uint32_t> out(2 * info().edge_count);
        detail::check(uvf_cut_copy_edges(handle_, out.data(), out.size()));
        return out;
    }

  private:
    UvfCut *handle_ = nullptr;
};

/// Real-time boundary editing (Desbrun et al. 2002 §4.2, `uvf_boundary_editor_*`): factors
/// λ·DCP + μ·DAP once; `solve` maps new positions of the outer boundary to the whole map.
/// Move-only owner of the library's handle; `solve` may run concurrently from several threads.
class BoundaryEditor {
  public:
    BoundaryEditor(const std::vector<double> &positions, const std::vector<std::uint32_t> &triangles,
                   double lambda = 1.0, double mu = 0.0)
        : vertex_count_(detail::count_of(positions, 3, "positions")) {
        detail::check(uvf_boundary_editor_new(positions.data(), vertex_count_, triangles.data(),
                                              detail::count_of(triangles, "triangles"), lambda, mu, nullptr, &handle_));
    }
    BoundaryEditor(const BoundaryEditor &) = delete;
    BoundaryEditor &operator=(const BoundaryEditor &) = delete;
    BoundaryEditor(BoundaryEditor &&other) noexcept
        : handle_(std::exchange(other.handle_, nullptr)), vertex_count_(other.vertex_count_) {}
    BoundaryEditor &operator=(BoundaryEditor &&other) noexcept {
        if (this != &other) {
            uvf_boundary_editor_free(handle_);
            handle_ = std::exchange(other.handle_, nullptr);
            vertex_count_ = other.vertex_count_;
        }
        return *this;
    }
    ~BoundaryEditor() { uvf_boundary_editor_free(handle_); }

    /// The outer loop's vertices, in the order `solve` expects their UVs.
    std::vector<std::uint32_t> boundary() const {
        std::size_t count = 0;
        detail::check(uvf_boundary_editor_boundary(handle_, &count, nullptr));
        std::vector<std::uint32_t> out(count);
        detail::check(uvf_boundary_editor_boundary(handle_, &count, out.data()));
        return out;
    }
    /// UVs of every vertex (2 per vertex) for `boundary_uv` (2 per boundary vertex).
    std::vector<double> solve(const std::vector<double> &boundary_uv) const {
        std::vector<double> uv(2 * vertex_count_);
        detail::check(uvf_boundary_editor_solve(handle_, boundary_uv.data(),
                                                detail::count_of(boundary_uv, 2, "boundary_uv"), uv.data()));
        return uv;
    }

  private:
    UvfBoundaryEditor *handle_ = nullptr;
    std::size_t vertex_count_ = 0;
};

} // namespace uvflat

#endif // UVFLAT_HPP
