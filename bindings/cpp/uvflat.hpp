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
#ifndef UVFLAT_HPP
#define UVFLAT_HPP

#include "uvflat.h"

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

/// Options of `natural_conformal_map`: no pins means the two boundary vertices farthest apart.
struct NaturalConformalOptions {
    struct Pin {
        std::uint32_t vertex;
        double u, v;
    };
    std::vector<Pin> pins; // empty or exactly two
    std::function<bool(double)> progress;
};

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
    if (!options.pins.empty()) {
        if (options.pins.size() != 2) throw Error(UVF_INVALID_ARGUMENT, "give no pins or exactly two");
        o.pin_count = 2;
        for (int k = 0; k < 2; ++k) {
            o.pin_vertices[k] = options.pins[k].vertex;
            o.pin_uv[2 * k] = options.pins[k].u;
            o.pin_uv[2 * k + 1] = options.pins[k].v;
        }
    }
    return detail::run_uv_method(uvf_natural_conformal_map, o, options.progress, positions, vertex_count, triangles,
                                 triangle_count);
}

inline std::vector<double> natural_conformal_map(const std::vector<double> &positions,
                                                 const std::vector<std::uint32_t> &triangles,
                                                 const NaturalConformalOptions &options = {}) {
    return natural_conformal_map(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                                 detail::count_of(triangles, "triangles"), options);
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
