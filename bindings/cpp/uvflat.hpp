// uvflat.hpp: header-only C++17 wrapper over the uvflat C API (include/uvflat.h).
//
// - Inputs: any contiguous range of doubles (3 per vertex) and uint32_t (3 per triangle),
//   passed as std::vector or as `{pointer, count}` (`uvflat::Positions`, `uvflat::Triangles`:
//   views, nothing is copied), or a `uvflat::Mesh` validated once (float or double positions
//   at any stride, uint16/uint32 indices, polygons); outputs come back as std::vector.
// - Failures throw uvflat::Error, which carries the UvfStatus and the library's message.
// - Options are plain structs initialised from the library's defaults; progress callbacks are
//   std::function<bool(double)> returning false to cancel (uvflat::Error with UVF_CANCELLED).
//   An exception thrown by the callback cancels the computation and is rethrown.
//
//   #include <uvflat.hpp>
//   std::vector<double> uv = uvflat::natural_conformal_map(positions, triangles);
//   UvfMetrics m = uvflat::metrics(positions, triangles, uv);
//   uvflat::Pgp pgp(positions, triangles);                     // any genus, no cut
//   uvflat::PolygonMesh quads = pgp.quad_mesh(8).polygons();  // 8 lines per period
//
// Wrapped: fixed-boundary (barycentric) maps, with point constraints; the natural conformal
// map (LSCM), with point constraints or any number of pins; the near-optimal and the
// boundary-optimized intrinsic maps; ABF / ABF++; the non-linear maps (SLIM, ARAP, MIPS,
// stretch, Green–Lagrange, Degener); the spectral conformal map; circle patterns (free,
// prescribed, polygon or convex boundary; cone maps and automatic cone placement); spherical
// maps; principal curvatures; Periodic Global Parameterization (`Pgp`: singularities, the
// quad-dominant remesh `QuadMesh`, the `ChartLayout` and the per-chart `PgpCharts`);
// QuadCover and its quad mesh; the chart `Atlas`; metrics, mesh info, boundary loops, triangle
// components, the cut to a disk and the boundary editor (with its Green-function basis); the
// version and ABI version, the thread count, the layout check. The flat-array C functions are
// all wrapped; of the `uvf_mesh_*` handle twins, those of the most used methods. Library
// handles are owned by move-only classes whose destructor frees them; a moved-from object's
// accessors throw uvflat::Error (UVF_INVALID_ARGUMENT).
#ifndef UVFLAT_HPP
#define UVFLAT_HPP

#include "uvflat.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace uvflat {

/// A read-only view of contiguous elements (std::span-style; C++17 has no std::span): made
/// implicitly from a std::vector, or from a pointer and an element count, e.g.
/// `uvflat::natural_conformal_map({positions, 3 * vertex_count}, {triangles, 3 * triangle_count})`.
template <class T> class View {
  public:
    View() noexcept : data_(nullptr), size_(0) {}
    View(const std::vector<T> &v) noexcept : data_(v.data()), size_(v.size()) {}
    View(const T *data, std::size_t size) noexcept : data_(data), size_(size) {}
    const T *data() const noexcept { return data_; }
    std::size_t size() const noexcept { return size_; }
    bool empty() const noexcept { return size_ == 0; }
    const T &operator[](std::size_t k) const noexcept { return data_[k]; }
    const T *begin() const noexcept { return data_; }
    const T *end() const noexcept { return data_ + size_; }

  private:
    const T *data_;
    std::size_t size_;
};

/// 3 doubles per vertex.
using Positions = View<double>;
/// 3 vertex indices per triangle.
using Triangles = View<std::uint32_t>;

/// A failed uvflat call: the status code and the library's message.
class Error : public std::runtime_error {
public:
    Error(UvfStatus status, const std::string &message) : std::runtime_error(message), status_(status) {}
    UvfStatus status() const noexcept { return status_; }

private:
    UvfStatus status_;
};

namespace detail {

/// A report or info struct for the library to write into: zeroed, with its `struct_size` set
/// (the library writes only that many bytes of it).
template <class T> T sized() {
    T value{};
    value.struct_size = sizeof(T);
    return value;
}

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

inline std::size_t count_of(View<double> flat, std::size_t per, const char *what) {
    if (flat.size() % per != 0) {
        throw Error(UVF_INVALID_ARGUMENT, std::string(what) + " must hold " + std::to_string(per) +
                                              " values per element, but its size is " + std::to_string(flat.size()));
    }
    return flat.size() / per;
}

inline std::size_t count_of(View<std::uint32_t> flat, const char *what) {
    if (flat.size() % 3 != 0) {
        throw Error(UVF_INVALID_ARGUMENT,
                    std::string(what) + " must hold 3 indices per triangle, but its size is " + std::to_string(flat.size()));
    }
    return flat.size() / 3;
}

/// Owns one library handle: move-only, released by `Free` (which ignores NULL) when destroyed
/// or assigned over. The classes below hold one; their implicit moves move it.
template <class T, void (*Free)(T *)> class Handle {
  public:
    Handle() = default;
    explicit Handle(T *handle) noexcept : handle_(handle) {}
    Handle(const Handle &) = delete;
    Handle &operator=(const Handle &) = delete;
    Handle(Handle &&other) noexcept : handle_(std::exchange(other.handle_, nullptr)) {}
    Handle &operator=(Handle &&other) noexcept {
        if (this != &other) {
            Free(handle_);
            handle_ = std::exchange(other.handle_, nullptr);
        }
        return *this;
    }
    ~Handle() { Free(handle_); }

    T *get() const noexcept { return handle_; }
    /// The slot a C call writes a new handle to; whatever it held is released first.
    T **out() noexcept {
        Free(std::exchange(handle_, nullptr));
        return &handle_;
    }

  private:
    T *handle_ = nullptr;
};

/// Checks that an optional per-element array is empty or holds `per` values for each of
/// `count` elements.
template <class T>
void check_optional_size(const std::vector<T> &values, std::size_t count, std::size_t per, const char *what) {
    if (!values.empty() && values.size() != per * count) {
        throw Error(UVF_INVALID_ARGUMENT, std::string(what) + " must be empty or hold " + std::to_string(per * count) +
                                              " values, but its size is " + std::to_string(values.size()));
    }
}

} // namespace detail

/// A mesh validated once for many calls (`uvf_mesh_new`): float or double positions at any
/// byte stride, uint16 or uint32 indices, triangles or polygons (triangulated inside). Pass it to
/// `natural_conformal_map`, `fixed_boundary_map` and `Unwrap` instead of the arrays.
class Mesh {
  public:
    /// A triangle mesh from packed arrays (3 doubles per vertex, 3 indices per triangle).
    Mesh(Positions positions, Triangles triangles) {
        UvfMeshDesc d;
        uvf_mesh_desc_default(&d);
        d.positions = positions.data();
        d.vertex_count = detail::count_of(positions, 3, "positions");
        d.indices = triangles.data();
        d.face_count = detail::count_of(triangles, "triangles");
        build(d);
    }
    /// Any mesh a description says (initialise it with `uvf_mesh_desc_default`).
    explicit Mesh(const UvfMeshDesc &desc) { build(desc); }

    /// Counts and topology of the triangulation.
    UvfMeshInfo info() const {
        UvfMeshInfo i = detail::sized<UvfMeshInfo>();
        detail::check(uvf_mesh_handle_info(handle_.get(), &i));
        return i;
    }
    std::size_t vertex_count() const { return vertex_count_; }
    /// The triangulation: 3 vertex indices per triangle.
    std::vector<std::uint32_t> triangles() const {
        std::vector<std::uint32_t> out(3 * info().triangles);
        detail::check(uvf_mesh_copy_triangles(handle_.get(), out.data(), out.size()));
        return out;
    }
    /// The input face of every triangle.
    std::vector<std::uint32_t> triangle_faces() const {
        std::vector<std::uint32_t> out(info().triangles);
        detail::check(uvf_mesh_copy_triangle_faces(handle_.get(), out.data(), out.size()));
        return out;
    }
    /// Per-triangle-corner UVs (6 doubles per triangle) as 2 doubles per input face corner.
    std::vector<double> face_corner_uv(const std::vector<double> &corner_uv, std::size_t corner_count) const {
        std::vector<double> out(2 * corner_count);
        detail::check(
            uvf_mesh_face_corner_uv(handle_.get(), corner_uv.data(), corner_uv.size(), out.data(), out.size()));
        return out;
    }
    const UvfMesh *get() const noexcept { return handle_.get(); }

  private:
    void build(const UvfMeshDesc &desc) {
        detail::check(uvf_mesh_new(&desc, handle_.out()));
        vertex_count_ = info().vertices;
    }
    detail::Handle<UvfMesh, uvf_mesh_free> handle_;
    std::size_t vertex_count_ = 0;
};

/// Library version string, e.g. "1.0.0".
inline std::string version() { return uvf_version(); }

/// ABI version of the loaded library; equal to the header's UVF_ABI_VERSION when they match.
inline std::uint32_t abi_version() { return uvf_abi_version(); }

/// Library version as major * 10000 + minor * 100 + patch (the header's UVF_VERSION_NUMBER).
inline std::uint32_t version_number() { return uvf_version_number(); }

/// A short description of a status code ("invalid mesh").
inline std::string status_string(UvfStatus status) { return uvf_status_string(status); }

/// Number of worker threads the library computes on (0: one per core or RAYON_NUM_THREADS).
/// Call it before any other uvflat call; afterwards it throws (the workers exist).
inline void set_thread_count(std::uint32_t count) { detail::check(uvf_set_thread_count(count)); }

/// Number of worker threads the library computes on.
inline std::uint32_t thread_count() { return uvf_thread_count(); }

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
                                 Positions positions, Triangles triangles,
                                 Report *report) {
    Progress progress;
    progress.callback = &callback;
    progress.install(o);
    const std::size_t nv = count_of(positions, 3, "positions");
    std::vector<double> uv(2 * nv);
    Report r = detail::sized<Report>();
    progress.finish(method(positions.data(), nv, triangles.data(), count_of(triangles, "triangles"), &o, uv.data(), &r));
    if (report) *report = r;
    return uv;
}

/// `run_reported` for a mesh-handle twin, `method(mesh, &options, uv_out, report_out)`.
template <class COptions, class Report, class Method, class MeshT>
std::vector<double> run_on_mesh(Method method, COptions &o, const std::function<bool(double)> &callback,
                                const MeshT &mesh, Report *report) {
    Progress progress;
    progress.callback = &callback;
    progress.install(o);
    std::vector<double> uv(2 * mesh.vertex_count());
    Report r = detail::sized<Report>();
    progress.finish(method(mesh.get(), &o, uv.data(), &r));
    if (report) *report = r;
    return uv;
}

} // namespace detail

/// Topology of a mesh (validates it; throws on invalid meshes).
inline UvfMeshInfo mesh_info(const double *positions, std::size_t vertex_count, const std::uint32_t *triangles,
                             std::size_t triangle_count) {
    UvfMeshInfo info = detail::sized<UvfMeshInfo>();
    detail::check(uvf_mesh_info(positions, vertex_count, triangles, triangle_count, &info));
    return info;
}

inline UvfMeshInfo mesh_info(Positions positions, Triangles triangles) {
    return mesh_info(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                     detail::count_of(triangles, "triangles"));
}

/// Ordered boundary loops (counter-clockwise).
inline std::vector<std::vector<std::uint32_t>> boundary_loops(Positions positions,
                                                              Triangles triangles) {
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

/// Connected component (0-based) of every triangle: 1 entry per triangle.
inline std::vector<std::uint32_t> triangle_components(Positions positions,
                                                      Triangles triangles) {
    const std::size_t nt = detail::count_of(triangles, "triangles");
    std::vector<std::uint32_t> component(nt);
    detail::check(uvf_triangle_components(positions.data(), detail::count_of(positions, 3, "positions"),
                                          triangles.data(), nt, component.data()));
    return component;
}

/// The UV islands of a polygon mesh (`polygon_islands`).
struct PolygonIslands {
    /// Island of every face, `UVF_NOT_IN_AN_ISLAND` where not selected.
    std::vector<std::uint32_t> face_island;
    /// Island vertex (one UV) of every corner, `UVF_NOT_IN_AN_ISLAND` for unselected faces' corners.
    std::vector<std::uint32_t> corner_vertex;
    /// Counts: islands, island vertices, non-manifold and misoriented edges cut.
    UvfPolygonIslandsInfo info;
};

/// UV islands of the selected faces of a polygon mesh, cut at seams (`uvf_polygon_islands`):
/// `corner_vertices` face after face, `face_sizes` empty for triangles, `selected` (one flag per
/// face) and `seams` (one flag per corner: the edge to the next corner) empty for all / none.
inline PolygonIslands polygon_islands(View<std::uint32_t> corner_vertices, std::size_t vertex_count,
                                      View<std::uint32_t> face_sizes = {}, View<std::uint8_t> selected = {},
                                      View<std::uint8_t> seams = {}) {
    const std::size_t faces = face_sizes.empty() ? corner_vertices.size() / 3 : face_sizes.size();
    if (!selected.empty() && selected.size() != faces)
        throw Error(UVF_INVALID_ARGUMENT, "selected must be empty or hold one flag per face (" + std::to_string(faces) + ")");
    if (!seams.empty() && seams.size() != corner_vertices.size())
        throw Error(UVF_INVALID_ARGUMENT,
                    "seams must be empty or hold one flag per corner (" + std::to_string(corner_vertices.size()) + ")");
    PolygonIslands out{std::vector<std::uint32_t>(faces), std::vector<std::uint32_t>(corner_vertices.size()), {}};
    out.info.struct_size = sizeof out.info;
    detail::check(uvf_polygon_islands(corner_vertices.data(), corner_vertices.size(), vertex_count,
                                      face_sizes.empty() ? nullptr : face_sizes.data(), faces,
                                      selected.empty() ? nullptr : selected.data(), seams.empty() ? nullptr : seams.data(),
                                      out.face_island.data(), out.corner_vertex.data(), &out.info));
    return out;
}

/// Packed islands (`pack_islands`).
struct PackedIslands {
    /// 2 values per UV: the packed layout.
    std::vector<double> uv;
    /// Island of every UV triangle.
    std::vector<std::uint32_t> island;
    /// Island count and the fraction of the unit square covered.
    UvfPackReport report;
};

/// Packs the islands of an existing layout into the unit square (`uvf_pack_islands`): `uv` 2
/// values per UV, `uv_triangles` 3 indices per triangle, `surface_areas` (empty: keep relative
/// sizes) one 3D area per triangle for one texel density.
inline PackedIslands pack_islands(View<double> uv, View<std::uint32_t> uv_triangles, View<double> surface_areas = {},
                                  double margin = 0.005, bool rotate = true) {
    const std::size_t nt = detail::count_of(uv_triangles, "uv_triangles");
    if (!surface_areas.empty() && surface_areas.size() != nt)
        throw Error(UVF_INVALID_ARGUMENT, "surface_areas must be empty or hold one area per triangle (" + std::to_string(nt) + ")");
    UvfPackOptions o;
    uvf_pack_options_default(&o);
    o.margin = margin;
    o.rotate = rotate ? 1u : 0u;
    PackedIslands out{std::vector<double>(uv.size()), std::vector<std::uint32_t>(nt), {}};
    out.report.struct_size = sizeof out.report;
    detail::check(uvf_pack_islands(uv.data(), detail::count_of(uv, 2, "uv"), uv_triangles.data(), nt,
                                   surface_areas.empty() ? nullptr : surface_areas.data(), &o, out.uv.data(),
                                   out.island.data(), &out.report));
    return out;
}

namespace detail {

/// Checks a given boundary: 2 UV values per given vertex.
inline void check_given(const std::vector<std::uint32_t> &vertices, const std::vector<double> &uv) {
    if (uv.size() != 2 * vertices.size()) throw Error(UVF_INVALID_ARGUMENT, "given_uv must hold 2 values per given vertex");
}

/// The boundary shape, distribution and given boundary vertices of options `options` in the C
/// options `o` (which then point into `options.given_vertices` and `options.given_uv`).
template <class C, class O> void set_boundary(C &o, const O &options) {
    o.boundary = static_cast<std::uint32_t>(options.boundary);
    o.distribution = static_cast<std::uint32_t>(options.distribution);
    check_given(options.given_vertices, options.given_uv);
    o.given_count = options.given_vertices.size();
    o.given_vertices = options.given_vertices.data();
    o.given_uv = options.given_uv.data();
}

/// The C options of `fixed_boundary_map` (no progress callback installed); they point into
/// `options.given_vertices` and `options.given_uv`.
inline UvfFixedBoundaryOptions fixed_boundary_options(const FixedBoundaryOptions &options) {
    UvfFixedBoundaryOptions o;
    uvf_fixed_boundary_options_default(&o);
    o.weights = static_cast<std::uint32_t>(options.weights);
    o.lambda = options.lambda;
    o.mu = options.mu;
    set_boundary(o, options);
    return o;
}

} // namespace detail

/// Fixed-boundary barycentric map; returns 2 doubles per vertex (NaN for unreferenced ones).
inline std::vector<double> fixed_boundary_map(const double *positions, std::size_t vertex_count,
                                              const std::uint32_t *triangles, std::size_t triangle_count,
                                              const FixedBoundaryOptions &options = {}) {
    UvfFixedBoundaryOptions o = detail::fixed_boundary_options(options);
    return detail::run_uv_method(uvf_fixed_boundary_map, o, options.progress, positions, vertex_count, triangles,
                                 triangle_count);
}

inline std::vector<double> fixed_boundary_map(Positions positions,
                                              Triangles triangles,
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

inline std::vector<double> natural_conformal_map(Positions positions,
                                                 Triangles triangles,
                                                 const NaturalConformalOptions &options = {}) {
    return natural_conformal_map(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                                 detail::count_of(triangles, "triangles"), options);
}

/// `fixed_boundary_map` on a mesh handle.
inline std::vector<double> fixed_boundary_map(const Mesh &mesh, const FixedBoundaryOptions &options = {}) {
    UvfFixedBoundaryOptions o = detail::fixed_boundary_options(options);
    detail::Progress progress;
    progress.callback = &options.progress;
    progress.install(o);
    std::vector<double> uv(2 * mesh.vertex_count());
    progress.finish(uvf_mesh_fixed_boundary_map(mesh.get(), &o, uv.data()));
    return uv;
}

/// `natural_conformal_map` on a mesh handle.
inline std::vector<double> natural_conformal_map(const Mesh &mesh, const NaturalConformalOptions &options = {}) {
    UvfNaturalConformalOptions o;
    uvf_natural_conformal_options_default(&o);
    detail::set_pins(o, options.pins);
    detail::Progress progress;
    progress.callback = &options.progress;
    progress.install(o);
    std::vector<double> uv(2 * mesh.vertex_count());
    progress.finish(uvf_mesh_natural_conformal_map(mesh.get(), &o, uv.data()));
    return uv;
}

/// A point of the surface and the UV it must map to: `{triangle, {b0, b1, b2}, {u, v}}`, the
/// barycentric coordinates with respect to the triangle's corners (normalized by their sum).
using PointConstraint = UvfPointConstraint;

namespace detail {

/// Runs an intrinsic tool `method(positions, nv, triangles, nt, ..., &options, uv_out)` whose
/// arguments after the mesh are bound by `call(options, uv_out)`.
template <class Call>
std::vector<double> run_tool(Positions positions, const std::function<bool(double)> &callback,
                             Call call) {
    UvfIntrinsicToolOptions o;
    uvf_intrinsic_tool_options_default(&o);
    Progress progress;
    progress.callback = &callback;
    progress.install(o);
    std::vector<double> uv(2 * count_of(positions, 3, "positions"));
    progress.finish(call(&o, uv.data()));
    return uv;
}

} // namespace detail

/// Fixed-boundary map with point constraints (Desbrun et al. 2002 §4.1, Lagrange
/// multipliers): `fixed_boundary_map` with every constraint met exactly; 2 doubles per vertex.
inline std::vector<double> constrained_fixed_boundary_map(Positions positions,
                                                          Triangles triangles,
                                                          const std::vector<PointConstraint> &constraints,
                                                          const FixedBoundaryOptions &options = {}) {
    UvfFixedBoundaryOptions o = detail::fixed_boundary_options(options);
    detail::Progress progress;
    progress.callback = &options.progress;
    progress.install(o);
    const std::size_t nv = detail::count_of(positions, 3, "positions");
    std::vector<double> uv(2 * nv);
    progress.finish(uvf_constrained_fixed_boundary_map(positions.data(), nv, triangles.data(),
                                                       detail::count_of(triangles, "triangles"), &o,
                                                       constraints.data(), constraints.size(), uv.data()));
    return uv;
}

/// Natural conformal map with point constraints instead of two pins (Desbrun et al. 2002
/// §4.1): at least 2 constraints, not all with the same target; 2 doubles per vertex.
inline std::vector<double> constrained_natural_conformal_map(Positions positions,
                                                             Triangles triangles,
                                                             const std::vector<PointConstraint> &constraints,
                                                             const std::function<bool(double)> &progress = {}) {
    return detail::run_tool(positions, progress, [&](const UvfIntrinsicToolOptions *o, double *uv) {
        return uvf_constrained_natural_conformal_map(positions.data(), detail::count_of(positions, 3, "positions"),
                                                     triangles.data(),
                                                     detail::count_of(triangles, "triangles"), constraints.data(),
                                                     constraints.size(), o, uv);
    });
}

/// Natural conformal map with any number (≥ 2) of pinned vertices; 2 doubles per vertex.
inline std::vector<double> pinned_natural_conformal_map(Positions positions,
                                                        Triangles triangles,
                                                        const std::vector<Pin> &pins,
                                                        const std::function<bool(double)> &progress = {}) {
    std::vector<std::uint32_t> vertices;
    std::vector<double> uv;
    for (const Pin &p : pins) {
        vertices.push_back(p.vertex);
        uv.insert(uv.end(), {p.u, p.v});
    }
    return detail::run_tool(positions, progress, [&](const UvfIntrinsicToolOptions *o, double *out) {
        return uvf_pinned_natural_conformal_map(positions.data(), detail::count_of(positions, 3, "positions"),
                                                triangles.data(),
                                                detail::count_of(triangles, "triangles"), vertices.data(), uv.data(),
                                                pins.size(), o, out);
    });
}

/// Distortion energy of the intrinsic-map optimizations (UVF_ENERGY_*, Desbrun et al. 2002 §5.1).
enum class Energy : std::uint32_t { edge_length = UVF_ENERGY_EDGE_LENGTH, area = UVF_ENERGY_AREA };

/// Options of `intrinsic_optimal_map`; defaults as `uvf_intrinsic_optimal_options_default`.
struct IntrinsicOptimalOptions {
    Energy energy = Energy::edge_length;
    Boundary boundary = Boundary::circle;
    Distribution distribution = Distribution::chord;
    /// The range of λ searched.
    double lambda_min = -std::numeric_limits<double>::infinity();
    double lambda_max = std::numeric_limits<double>::infinity();
    /// For Boundary::given: vertices of whole boundary loops and their UVs (2 per vertex).
    std::vector<std::uint32_t> given_vertices;
    std::vector<double> given_uv;
    std::function<bool(double)> progress;
};

namespace detail {

/// The C options of `intrinsic_optimal_map` (no progress callback installed).
inline UvfIntrinsicOptimalOptions intrinsic_optimal_options(const IntrinsicOptimalOptions &options) {
    UvfIntrinsicOptimalOptions o;
    uvf_intrinsic_optimal_options_default(&o);
    o.energy = static_cast<std::uint32_t>(options.energy);
    o.lambda_min = options.lambda_min;
    o.lambda_max = options.lambda_max;
    set_boundary(o, options);
    return o;
}

} // namespace detail

/// Near-optimal intrinsic map (Desbrun et al. 2002 §5.1): λ·DCP + (1 − λ)·DAP with the λ
/// minimizing the energy (never worse than pure DCP or DAP when they are in the range); 2
/// doubles per vertex, λ and the energies in `*report` if given.
inline std::vector<double> intrinsic_optimal_map(Positions positions,
                                                 Triangles triangles,
                                                 const IntrinsicOptimalOptions &options = {},
                                                 UvfIntrinsicOptimalReport *report = nullptr) {
    UvfIntrinsicOptimalOptions o = detail::intrinsic_optimal_options(options);
    return detail::run_reported(uvf_intrinsic_optimal_map, o, options.progress, positions, triangles, report);
}

/// Options of `boundary_optimized_map`; defaults as `uvf_boundary_optimization_options_default`.
struct BoundaryOptimizationOptions {
    Energy energy = Energy::edge_length;
    std::uint32_t iterations = 100;
    /// The intrinsic map λ·DCP + μ·DAP.
    double lambda = 1.0;
    double mu = 0.0;
    /// Stop when an iteration lowers the energy by less than tolerance × energy.
    double tolerance = 1e-6;
    /// The starting boundary; given positions must cover exactly the outer (longest) loop.
    Boundary boundary = Boundary::circle;
    Distribution distribution = Distribution::chord;
    std::vector<std::uint32_t> given_vertices;
    std::vector<double> given_uv;
    std::function<bool(double)> progress;
};

namespace detail {

/// The C options of `boundary_optimized_map` (no progress callback installed).
inline UvfBoundaryOptimizationOptions boundary_optimization_options(const BoundaryOptimizationOptions &options) {
    UvfBoundaryOptimizationOptions o;
    uvf_boundary_optimization_options_default(&o);
    o.energy = static_cast<std::uint32_t>(options.energy);
    o.iterations = options.iterations;
    o.lambda = options.lambda;
    o.mu = options.mu;
    o.tolerance = options.tolerance;
    set_boundary(o, options);
    return o;
}

} // namespace detail

/// Boundary-optimized intrinsic map (Desbrun et al. 2002 §5.2): the outer boundary moved to
/// minimize the energy, never flipping a triangle; 2 doubles per vertex. The energies (start
/// first, one per accepted iteration) go to `*history`, the figures to `*report`, if given.
inline std::vector<double> boundary_optimized_map(Positions positions,
                                                  Triangles triangles,
                                                  const BoundaryOptimizationOptions &options = {},
                                                  UvfBoundaryOptimizationReport *report = nullptr,
                                                  std::vector<double> *history = nullptr) {
    UvfBoundaryOptimizationOptions o = detail::boundary_optimization_options(options);
    detail::Progress progress;
    progress.callback = &options.progress;
    progress.install(o);
    const std::size_t nv = detail::count_of(positions, 3, "positions");
    std::vector<double> uv(2 * nv);
    // The history has at most one entry per iteration and the start.
    std::vector<double> energies(history ? std::size_t(options.iterations) + 1 : 0);
    UvfBoundaryOptimizationReport r = detail::sized<UvfBoundaryOptimizationReport>();
    progress.finish(uvf_boundary_optimized_map(positions.data(), nv, triangles.data(),
                                               detail::count_of(triangles, "triangles"), &o, uv.data(),
                                               energies.empty() ? nullptr : energies.data(), energies.size(), &r));
    if (history) {
        energies.resize(std::min(energies.size(), r.history_length));
        *history = std::move(energies);
    }
    if (report) *report = r;
    return uv;
}

/// ABF variant (UVF_ABF_VARIANT_*).
enum class AbfVariant : std::uint32_t { abf = UVF_ABF_VARIANT_ABF, abf_plus_plus = UVF_ABF_VARIANT_ABF_PLUS_PLUS };

/// Options of `abf`: no pins means the library's automatic pair for the reconstruction.
struct AbfOptions {
    AbfVariant variant = AbfVariant::abf_plus_plus;
    std::vector<Pin> pins; // empty or exactly two
    std::function<bool(double)> progress;
    /// Unset: the library's defaults (`uvf_abf_options_default`).
    std::optional<std::uint32_t> max_iterations;
    std::optional<double> tolerance;
    /// UVF_ABF_WEIGHTS_*.
    std::optional<std::uint32_t> weights;
    /// The weight of the angle barrier; 0 turns it off.
    std::optional<double> barrier;
};

namespace detail {

/// The C options of `abf` (no progress callback installed).
inline UvfAbfOptions abf_options(const AbfOptions &options) {
    UvfAbfOptions o;
    uvf_abf_options_default(&o);
    o.variant = static_cast<std::uint32_t>(options.variant);
    set_pins(o, options.pins);
    if (options.max_iterations) o.max_iterations = *options.max_iterations;
    if (options.tolerance) o.tolerance = *options.tolerance;
    if (options.weights) o.weights = *options.weights;
    if (options.barrier) o.barrier = *options.barrier;
    return o;
}

} // namespace detail

/// Angle Based Flattening (Sheffer & de Sturler 2001) or ABF++ (Sheffer et al. 2005), free
/// boundary; returns 2 doubles per vertex, and the solver's figures in `*report` if given.
inline std::vector<double> abf(Positions positions, Triangles triangles,
                               const AbfOptions &options = {}, UvfAbfReport *report = nullptr) {
    UvfAbfOptions o = detail::abf_options(options);
    return detail::run_reported(uvf_abf, o, options.progress, positions, triangles, report);
}

/// `abf` on a mesh handle.
inline std::vector<double> abf(const Mesh &mesh, const AbfOptions &options = {}, UvfAbfReport *report = nullptr) {
    UvfAbfOptions o = detail::abf_options(options);
    return detail::run_on_mesh(uvf_mesh_abf, o, options.progress, mesh, report);
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
    /// Keep the whole map bijective (a scaffold keeps the free boundary apart).
    bool bijective = false;
    std::function<bool(double)> progress;
    /// Unset: the library's defaults (`uvf_nonlinear_options_default`).
    std::optional<double> tolerance;
    /// SLIM's reweighting exponent θ.
    std::optional<double> theta;
};

namespace detail {

/// The C options of `nonlinear_map` (no progress callback installed).
inline UvfNonlinearOptions nonlinear_options(const NonlinearOptions &options) {
    UvfNonlinearOptions o;
    uvf_nonlinear_options_default(&o);
    o.method = static_cast<std::uint32_t>(options.method);
    if (options.iterations != 0) o.iterations = options.iterations;
    o.bijective = options.bijective ? 1 : 0;
    if (options.tolerance) o.tolerance = *options.tolerance;
    if (options.theta) o.theta = *options.theta;
    return o;
}

} // namespace detail

/// Free-boundary, flip-free map minimizing a non-linear distortion energy from the mean value
/// map; returns 2 doubles per vertex.
inline std::vector<double> nonlinear_map(Positions positions,
                                         Triangles triangles,
                                         const NonlinearOptions &options = {}, UvfNonlinearReport *report = nullptr) {
    UvfNonlinearOptions o = detail::nonlinear_options(options);
    return detail::run_reported(uvf_nonlinear_map, o, options.progress, positions, triangles, report);
}

/// `nonlinear_map` on a mesh handle.
inline std::vector<double> nonlinear_map(const Mesh &mesh, const NonlinearOptions &options = {},
                                         UvfNonlinearReport *report = nullptr) {
    UvfNonlinearOptions o = detail::nonlinear_options(options);
    return detail::run_on_mesh(uvf_mesh_nonlinear_map, o, options.progress, mesh, report);
}

/// Spectral conformal map (Mullen et al. 2008): free boundary, no pins; 2 doubles per vertex.
inline std::vector<double> spectral_conformal_map(Positions positions,
                                                  Triangles triangles,
                                                  const std::function<bool(double)> &progress = {},
                                                  UvfSpectralReport *report = nullptr) {
    UvfSpectralOptions o;
    uvf_spectral_options_default(&o);
    return detail::run_reported(uvf_spectral_conformal_map, o, progress, positions, triangles, report);
}

/// Options of `spectral_conformal_map`; unset fields keep the library's defaults.
struct SpectralOptions {
    std::optional<std::uint32_t> iterations;
    std::optional<double> tolerance;
    std::function<bool(double)> progress;
};

namespace detail {

/// The C options of `spectral_conformal_map` (no progress callback installed).
inline UvfSpectralOptions spectral_options(const SpectralOptions &options) {
    UvfSpectralOptions o;
    uvf_spectral_options_default(&o);
    if (options.iterations) o.iterations = *options.iterations;
    if (options.tolerance) o.tolerance = *options.tolerance;
    return o;
}

} // namespace detail

/// `spectral_conformal_map` with every option.
inline std::vector<double> spectral_conformal_map(Positions positions,
                                                  Triangles triangles,
                                                  const SpectralOptions &options,
                                                  UvfSpectralReport *report = nullptr) {
    UvfSpectralOptions o = detail::spectral_options(options);
    return detail::run_reported(uvf_spectral_conformal_map, o, options.progress, positions, triangles, report);
}

/// `spectral_conformal_map` on a mesh handle.
inline std::vector<double> spectral_conformal_map(const Mesh &mesh, const SpectralOptions &options = {},
                                                  UvfSpectralReport *report = nullptr) {
    UvfSpectralOptions o = detail::spectral_options(options);
    return detail::run_on_mesh(uvf_mesh_spectral_conformal_map, o, options.progress, mesh, report);
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
    /// Unset: the library's defaults (`uvf_circle_pattern_options_default`).
    std::optional<std::uint32_t> max_iterations;
    std::optional<double> tolerance;
};

namespace detail {

inline UvfCirclePatternOptions circle_pattern_options(const CirclePatternOptions &options, std::size_t vertex_count) {
    UvfCirclePatternOptions o;
    uvf_circle_pattern_options_default(&o);
    o.intrinsic_delaunay = options.intrinsic_delaunay ? 1 : 0;
    o.convex_boundary = options.convex_boundary ? 1 : 0;
    if (options.max_iterations) o.max_iterations = *options.max_iterations;
    if (options.tolerance) o.tolerance = *options.tolerance;
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
inline std::vector<double> circle_pattern_map(Positions positions,
                                              Triangles triangles,
                                              const CirclePatternOptions &options = {},
                                              UvfCirclePatternReport *report = nullptr) {
    UvfCirclePatternOptions o = detail::circle_pattern_options(options, detail::count_of(positions, 3, "positions"));
    return detail::run_reported(uvf_circle_pattern_map, o, options.progress, positions, triangles, report);
}

/// `circle_pattern_map` on a mesh handle.
inline std::vector<double> circle_pattern_map(const Mesh &mesh, const CirclePatternOptions &options = {},
                                              UvfCirclePatternReport *report = nullptr) {
    UvfCirclePatternOptions o = detail::circle_pattern_options(options, mesh.vertex_count());
    return detail::run_on_mesh(uvf_mesh_circle_pattern_map, o, options.progress, mesh, report);
}

/// Boundary curvature making the longest boundary loop a convex polygon with the given ≥ 3
/// corner vertices (turning 2π / corners at each, straight between, NaN off the loop), for
/// `CirclePatternOptions::boundary_curvature`: 1 double per vertex.
inline std::vector<double> circle_pattern_polygon_curvature(Positions positions,
                                                            Triangles triangles,
                                                            const std::vector<std::uint32_t> &corners) {
    const std::size_t nv = detail::count_of(positions, 3, "positions");
    std::vector<double> curvature(nv);
    detail::check(uvf_circle_pattern_polygon_curvature(positions.data(), nv, triangles.data(),
                                                       detail::count_of(triangles, "triangles"), corners.data(),
                                                       corners.size(), curvature.data()));
    return curvature;
}

/// A cone singularity: an interior vertex and its curvature (2π minus the cone angle).
struct Cone {
    std::uint32_t vertex;
    double curvature;
};

/// Cones placed greedily where the conformal flattening's log scale is largest (Ben-Chen et
/// al. 2008), until it is at most `max_log_scale` or `max_cones` are placed; the largest log
/// scale left goes to `*max_log_scale_out` if given.
inline std::vector<Cone> place_cones(Positions positions, Triangles triangles,
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

/// Options of `place_cones`.
struct ConePlacementOptions {
    std::uint32_t max_cones = 64;
    double max_log_scale = 0.7;
    std::function<bool(double)> progress;
};

/// `place_cones` with a progress callback (returning false cancels: `uvflat::Error` with
/// `UVF_CANCELLED`).
inline std::vector<Cone> place_cones(Positions positions, Triangles triangles,
                                     const ConePlacementOptions &options, double *max_log_scale_out = nullptr) {
    UvfConePlacementOptions o;
    uvf_cone_placement_options_default(&o);
    o.max_cones = options.max_cones;
    o.max_log_scale = options.max_log_scale;
    detail::Progress progress;
    progress.callback = &options.progress;
    progress.install(o);
    const std::size_t nv = detail::count_of(positions, 3, "positions");
    std::vector<std::uint32_t> vertices(std::max<std::size_t>(std::min<std::size_t>(options.max_cones, nv), 1));
    std::vector<double> curvatures(vertices.size());
    std::size_t count = 0;
    double largest = 0;
    progress.finish(uvf_place_cones(positions.data(), nv, triangles.data(), detail::count_of(triangles, "triangles"),
                                    &o, vertices.data(), curvatures.data(), &count, &largest));
    if (max_log_scale_out) *max_log_scale_out = largest;
    std::vector<Cone> cones(count);
    for (std::size_t k = 0; k < count; ++k) cones[k] = Cone{vertices[k], curvatures[k]};
    return cones;
}

/// Conformal map with cone singularities by circle patterns, on a mesh of any genus cut through
/// the cones: 6 doubles per triangle (u, v of its three corners).
inline std::vector<double> circle_pattern_cone_map(Positions positions,
                                                   Triangles triangles,
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
    UvfCirclePatternReport r = detail::sized<UvfCirclePatternReport>();
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
inline std::vector<double> spherical_map(Positions positions,
                                         Triangles triangles,
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

/// Options of `spherical_map`; unset `sweeps` keeps the library's default.
struct SphereOptions {
    SphereMethod method = SphereMethod::tutte_gnomonic;
    std::optional<std::uint32_t> sweeps;
    std::function<bool(double)> progress;
};

namespace detail {

/// The C options of `spherical_map` (no progress callback installed).
inline UvfSphereOptions sphere_options(const SphereOptions &options) {
    UvfSphereOptions o;
    uvf_sphere_options_default(&o);
    o.method = static_cast<std::uint32_t>(options.method);
    if (options.sweeps) o.sweeps = *options.sweeps;
    return o;
}

} // namespace detail

/// `spherical_map` with every option (returning false from `progress` cancels).
inline std::vector<double> spherical_map(Positions positions,
                                         Triangles triangles, const SphereOptions &options,
                                         std::size_t *flipped = nullptr) {
    UvfSphereOptions o = detail::sphere_options(options);
    detail::Progress progress;
    progress.callback = &options.progress;
    progress.install(o);
    const std::size_t nv = detail::count_of(positions, 3, "positions");
    std::vector<double> sphere(3 * nv);
    std::size_t count = 0;
    progress.finish(uvf_spherical_map(positions.data(), nv, triangles.data(), detail::count_of(triangles, "triangles"),
                                      &o, sphere.data(), &count));
    if (flipped) *flipped = count;
    return sphere;
}

/// `spherical_map` on a mesh handle.
inline std::vector<double> spherical_map(const Mesh &mesh, const SphereOptions &options = {},
                                         std::size_t *flipped = nullptr) {
    UvfSphereOptions o = detail::sphere_options(options);
    detail::Progress progress;
    progress.callback = &options.progress;
    progress.install(o);
    std::vector<double> sphere(3 * mesh.vertex_count());
    std::size_t count = 0;
    progress.finish(uvf_mesh_spherical_map(mesh.get(), &o, sphere.data(), &count));
    if (flipped) *flipped = count;
    return sphere;
}

/// Curvature neighbourhood (UVF_CURVATURE_*): rings of triangles, or a graph-distance radius.
enum class CurvatureNeighbourhood : std::uint32_t { rings = UVF_CURVATURE_RINGS, radius = UVF_CURVATURE_RADIUS };

/// Options of `curvature` (and of PGP's field); defaults as `uvf_curvature_options_default`.
struct CurvatureOptions {
    CurvatureNeighbourhood neighbourhood = CurvatureNeighbourhood::rings;
    /// Rings for `rings` (≥ 1): the triangles around the vertices at most rings − 1 edges away.
    std::uint32_t rings = 2;
    /// Radius for `radius` (finite, > 0).
    double radius = 0;
};

/// Principal curvatures per vertex: unit tangent directions (3 doubles per vertex, kmax =
/// normal × kmin) and signed curvatures (1 per vertex, kmin ≤ kmax; 1/r on a sphere of radius
/// r with outward normals). Unreferenced vertices get zeros.
struct Curvatures {
    std::vector<double> kmin_direction, kmax_direction;
    std::vector<double> kmin, kmax;
};

namespace detail {

inline UvfCurvatureOptions curvature_options(const CurvatureOptions &options) {
    UvfCurvatureOptions o;
    uvf_curvature_options_default(&o);
    o.neighbourhood = static_cast<std::uint32_t>(options.neighbourhood);
    o.rings = options.rings;
    o.radius = options.radius;
    return o;
}

} // namespace detail

/// Principal curvatures by the normal-cycle tensor (Cohen-Steiner & Morvan 2003) averaged
/// over a neighbourhood of each vertex (`uvf_curvature`).
inline Curvatures curvature(Positions positions, Triangles triangles,
                            const CurvatureOptions &options = {}) {
    const UvfCurvatureOptions o = detail::curvature_options(options);
    const std::size_t nv = detail::count_of(positions, 3, "positions");
    Curvatures c;
    c.kmin_direction.resize(3 * nv);
    c.kmax_direction.resize(3 * nv);
    c.kmin.resize(nv);
    c.kmax.resize(nv);
    detail::check(uvf_curvature(positions.data(), nv, triangles.data(), detail::count_of(triangles, "triangles"), &o,
                                c.kmin_direction.data(), c.kmax_direction.data(), c.kmin.data(), c.kmax.data()));
    return c;
}

/// A polygon mesh: 3 doubles per vertex, the number of corners of every face, and the faces'
/// vertex indices one face after the other (counter-clockwise seen from outside).
struct PolygonMesh {
    std::vector<double> positions;
    std::vector<std::uint32_t> face_sizes;
    std::vector<std::uint32_t> indices;
};

/// A quad-dominant remesh (`Pgp::quad_mesh`, `quadcover_quad_mesh`): move-only owner of a
/// `UvfQuadMesh` handle, freed by the destructor.
class QuadMesh {
  public:
    /// Takes ownership of a handle from `uvf_pgp_quad_mesh` or `uvf_quadcover_quad_mesh`.
    explicit QuadMesh(UvfQuadMesh *handle) noexcept : handle_(handle) {}

    /// Vertex, face, index and quad counts.
    UvfQuadMeshInfo info() const {
        UvfQuadMeshInfo i = detail::sized<UvfQuadMeshInfo>();
        detail::check(uvf_quad_mesh_info(handle_.get(), &i));
        return i;
    }
    /// The faces, copied out (`uvf_quad_mesh_copy`).
    PolygonMesh polygons() const {
        const UvfQuadMeshInfo i = info();
        PolygonMesh m;
        m.positions.resize(3 * i.vertex_count);
        m.face_sizes.resize(i.face_count);
        m.indices.resize(i.index_count);
        detail::check(uvf_quad_mesh_copy(handle_.get(), m.positions.data(), m.positions.size(), m.face_sizes.data(),
                                         m.face_sizes.size(), m.indices.data(), m.indices.size()));
        return m;
    }

  private:
    detail::Handle<UvfQuadMesh, uvf_quad_mesh_free> handle_;
};

/// The chart layout of a PGP result (Ray et al. 2006 §3.3, `Pgp::chart_layout`): chart
/// boundaries along the iso-2kπ lines as polylines on the surface, and the corners of every
/// chart. Move-only owner of a `UvfChartLayout` handle, freed by the destructor.
class ChartLayout {
  public:
    /// Takes ownership of a handle from `uvf_pgp_chart_layout`.
    explicit ChartLayout(UvfChartLayout *handle) noexcept : handle_(handle) {}

    UvfChartLayoutInfo info() const {
        UvfChartLayoutInfo i = detail::sized<UvfChartLayoutInfo>();
        detail::check(uvf_chart_layout_info(handle_.get(), &i));
        return i;
    }
    /// Every chart-boundary polyline: 3 doubles per point.
    std::vector<std::vector<double>> polylines() const {
        const UvfChartLayoutInfo i = info();
        std::vector<std::uint32_t> sizes(i.polyline_count);
        std::vector<double> points(3 * i.point_count);
        detail::check(uvf_chart_layout_copy(handle_.get(), sizes.data(), sizes.size(), points.data(), points.size(),
                                            nullptr, 0));
        std::vector<std::vector<double>> lines;
        std::size_t at = 0;
        for (std::uint32_t size : sizes) {
            lines.emplace_back(points.begin() + 3 * at, points.begin() + 3 * (at + size));
            at += size;
        }
        return lines;
    }
    /// The number of corners of every chart (4 for a regular one).
    std::vector<std::uint32_t> chart_corners() const {
        std::vector<std::uint32_t> corners(info().chart_count);
        detail::check(uvf_chart_layout_copy(handle_.get(), nullptr, 0, nullptr, 0, corners.data(), corners.size()));
        return corners;
    }

  private:
    detail::Handle<UvfChartLayout, uvf_chart_layout_free> handle_;
};

/// How a chart of `PgpCharts` is parameterized (UVF_PGP_CHART_*).
enum class PgpChartKind : std::uint32_t {
    assembled = UVF_PGP_CHART_ASSEMBLED,
    mean_value = UVF_PGP_CHART_MEAN_VALUE,
    split_quad = UVF_PGP_CHART_SPLIT_QUAD,
    atlas = UVF_PGP_CHART_ATLAS,
    unresolved = UVF_PGP_CHART_UNRESOLVED,
};

/// One chart of `PgpCharts`: its kind, corners (0 when it is not a disk), the layout chart it
/// comes from (shared by the quads of one split chart) and its (u, v) extent in cells.
struct PgpChart {
    PgpChartKind kind;
    std::uint32_t corners;
    std::uint32_t layout_chart;
    double u_size, v_size;
};

/// The per-chart parameterization of a PGP result (Ray et al. 2006 §3.3–3.4, `Pgp::charts`):
/// the surface cut along the chart boundaries, every chart with its own (u, v) in cells.
/// Move-only owner of a `UvfPgpCharts` handle, freed by the destructor.
class PgpCharts {
  public:
    /// Takes ownership of a handle from `uvf_pgp_charts`.
    explicit PgpCharts(UvfPgpCharts *handle) noexcept : handle_(handle) {}

    UvfPgpChartsInfo info() const {
        UvfPgpChartsInfo i = detail::sized<UvfPgpChartsInfo>();
        detail::check(uvf_pgp_charts_info(handle_.get(), &i));
        return i;
    }
    /// Vertices of the cut triangulation (3 doubles each; the input's first, in its order).
    std::vector<double> positions() const {
        std::vector<double> out(3 * info().vertex_count);
        detail::check(uvf_pgp_charts_copy(handle_.get(), out.data(), out.size(), nullptr, 0, nullptr, 0, nullptr, 0,
                                          nullptr, 0));
        return out;
    }
    /// Triangles of the cut triangulation (3 indices each, counter-clockwise like the input).
    std::vector<std::uint32_t> triangles() const {
        std::vector<std::uint32_t> out(3 * info().triangle_count);
        detail::check(uvf_pgp_charts_copy(handle_.get(), nullptr, 0, out.data(), out.size(), nullptr, 0, nullptr, 0,
                                          nullptr, 0));
        return out;
    }
    /// (u, v) in cells per corner: 6 doubles per triangle of the cut triangulation.
    std::vector<double> corner_uv() const {
        std::vector<double> out(6 * info().triangle_count);
        detail::check(uvf_pgp_charts_copy(handle_.get(), nullptr, 0, nullptr, 0, out.data(), out.size(), nullptr, 0,
                                          nullptr, 0));
        return out;
    }
    /// The chart of every triangle of the cut triangulation.
    std::vector<std::uint32_t> chart_of_triangle() const {
        std::vector<std::uint32_t> out(info().triangle_count);
        detail::check(uvf_pgp_charts_copy(handle_.get(), nullptr, 0, nullptr, 0, nullptr, 0, out.data(), out.size(),
                                          nullptr, 0));
        return out;
    }
    /// The input triangle every triangle of the cut triangulation lies in.
    std::vector<std::uint32_t> origin_triangles() const {
        std::vector<std::uint32_t> out(info().triangle_count);
        detail::check(uvf_pgp_charts_copy(handle_.get(), nullptr, 0, nullptr, 0, nullptr, 0, nullptr, 0, out.data(),
                                          out.size()));
        return out;
    }
    /// Every chart's kind, corners, layout chart and size (`uvf_pgp_charts_copy_charts`).
    std::vector<PgpChart> charts() const {
        const std::size_t n = info().chart_count;
        std::vector<std::uint32_t> kinds(n), corners(n), layout(n);
        std::vector<double> sizes(2 * n);
        detail::check(uvf_pgp_charts_copy_charts(handle_.get(), kinds.data(), n, corners.data(), n, layout.data(), n,
                                                 sizes.data(), sizes.size()));
        std::vector<PgpChart> charts(n);
        for (std::size_t k = 0; k < n; ++k) {
            charts[k] = PgpChart{static_cast<PgpChartKind>(kinds[k]), corners[k], layout[k], sizes[2 * k],
                                 sizes[2 * k + 1]};
        }
        return charts;
    }

  private:
    detail::Handle<UvfPgpCharts, uvf_pgp_charts_free> handle_;
};

/// Field smoothing of PGP (UVF_SMOOTH_*): none, or directions equal modulo 2π, π or π/2.
enum class Smoothing : std::uint32_t {
    none = UVF_SMOOTH_NONE,
    two_pi = UVF_SMOOTH_2PI,
    pi = UVF_SMOOTH_PI,
    half_pi = UVF_SMOOTH_HALF_PI,
};

/// Options of `Pgp`; defaults as `uvf_pgp_options_default` (see `UvfPgpOptions` for each).
struct PgpOptions {
    /// θ grows by ω per unit length; 0: 2π / (10 × mean edge length).
    double omega = 0;
    /// Empty (the maximum principal curvature direction) or 3 doubles per vertex.
    std::vector<double> field;
    Smoothing smoothing = Smoothing::half_pi;
    /// Curl correction (§4.1): fewer singularities, conformal rather than isometric.
    bool curl_correction = false;
    double rho = 0.8;
    double smoothing_epsilon = 0.1;
    double epsilon = 0.1;
    double gradient_tolerance = 1e-6;
    std::uint32_t max_newton_iterations = 100;
    /// The curvature neighbourhood of the field.
    CurvatureOptions curvature;
    bool untangle = true;
    double feature_periods = 3;
    double pair_periods = 0.5;
    double dislocation_periods = 1.5;
    bool relax = true;
    std::function<bool(double)> progress;
};

namespace detail {

/// The C options of `Pgp` (no progress callback installed); `field` points into
/// `options.field`.
inline UvfPgpOptions pgp_options(const PgpOptions &options, std::size_t vertex_count) {
    check_optional_size(options.field, vertex_count, 3, "the field");
    UvfPgpOptions o;
    uvf_pgp_options_default(&o);
    o.omega = options.omega;
    o.field = options.field.empty() ? nullptr : options.field.data();
    o.smoothing = static_cast<std::uint32_t>(options.smoothing);
    o.curl_correction = options.curl_correction ? 1 : 0;
    o.rho = options.rho;
    o.smoothing_epsilon = options.smoothing_epsilon;
    o.epsilon = options.epsilon;
    o.gradient_tolerance = options.gradient_tolerance;
    o.max_newton_iterations = options.max_newton_iterations;
    o.curvature_neighbourhood = static_cast<std::uint32_t>(options.curvature.neighbourhood);
    o.curvature_rings = options.curvature.rings;
    o.curvature_radius = options.curvature.radius;
    o.untangle = options.untangle ? 1 : 0;
    o.feature_periods = options.feature_periods;
    o.pair_periods = options.pair_periods;
    o.dislocation_periods = options.dislocation_periods;
    o.relax = options.relax ? 1 : 0;
    return o;
}

} // namespace detail

/// A singular point of PGP: a vertex and its index (a multiple of 1/4).
struct SingularPoint {
    std::uint32_t vertex;
    double index;
};

/// Periodic Global Parameterization (Ray, Li, Lévy, Sheffer & Alliez 2006, `uvf_pgp`) of a
/// manifold mesh of any genus, with or without boundary: per-corner (θ, φ) and the
/// singularities, from which the quad-dominant remesh, the chart layout and the per-chart
/// parameterization are made. Move-only owner of the `UvfPgp` handle, freed by the destructor.
class Pgp {
  public:
    Pgp(Positions positions, Triangles triangles,
        const PgpOptions &options = {})
        : vertex_count_(detail::count_of(positions, 3, "positions")) {
        UvfPgpOptions o = detail::pgp_options(options, vertex_count_);
        detail::Progress progress;
        progress.callback = &options.progress;
        progress.install(o);
        const std::size_t nt = detail::count_of(triangles, "triangles");
        corner_theta_phi_.resize(6 * nt);
        progress.finish(uvf_pgp(positions.data(), vertex_count_, triangles.data(), nt, &o, corner_theta_phi_.data(),
                                handle_.out()));
    }

    /// Counts, ω, the index sum and the quality figures.
    UvfPgpInfo info() const {
        UvfPgpInfo i = detail::sized<UvfPgpInfo>();
        detail::check(uvf_pgp_info(handle_.get(), &i));
        return i;
    }
    /// (θ, φ) in radians for every corner: 6 doubles per triangle, corner k of triangle t at
    /// 6t + 2k; θ/2π, φ/2π are texture coordinates of a periodic texture.
    const std::vector<double> &corner_theta_phi() const noexcept { return corner_theta_phi_; }
    /// The field the periodic solve followed: 3 doubles per vertex.
    std::vector<double> field() const {
        std::vector<double> out(3 * vertex_count_);
        detail::check(uvf_pgp_copy_field(handle_.get(), out.data(), out.size()));
        return out;
    }
    /// Singular vertices (§3.2), ascending.
    std::vector<std::uint32_t> singular_vertices() const {
        std::vector<std::uint32_t> out(info().singular_vertex_count);
        detail::check(uvf_pgp_copy_singular_vertices(handle_.get(), out.data(), out.size()));
        return out;
    }
    /// Singular edges as vertex pairs a < b (2 per edge), sorted.
    std::vector<std::uint32_t> singular_edges() const {
        std::vector<std::uint32_t> out(2 * info().singular_edge_count);
        detail::check(uvf_pgp_copy_singular_edges(handle_.get(), out.data(), out.size()));
        return out;
    }
    /// Singular triangles, ascending.
    std::vector<std::uint32_t> singular_triangles() const {
        std::vector<std::uint32_t> out(info().singular_triangle_count);
        detail::check(uvf_pgp_copy_singular_triangles(handle_.get(), out.data(), out.size()));
        return out;
    }
    /// Vertices of non-zero index; the indices sum to 2 − 2g on a closed surface of genus g.
    std::vector<SingularPoint> singular_points() const {
        const std::size_t n = info().singular_point_count;
        std::vector<std::uint32_t> vertices(n);
        std::vector<double> indices(n);
        detail::check(uvf_pgp_copy_singular_points(handle_.get(), vertices.data(), indices.data(), n));
        std::vector<SingularPoint> points(n);
        for (std::size_t k = 0; k < n; ++k) points[k] = SingularPoint{vertices[k], indices[k]};
        return points;
    }
    /// Quad-dominant remesh (§5): the iso-lines at `density` lines per period (a whole
    /// number ≥ 1).
    QuadMesh quad_mesh(double density = 1) const {
        UvfQuadMesh *mesh = nullptr;
        detail::check(uvf_pgp_quad_mesh(handle_.get(), density, &mesh));
        return QuadMesh(mesh);
    }
    /// Chart layout (§3.3, Algorithm 2).
    ChartLayout chart_layout() const {
        UvfChartLayout *layout = nullptr;
        detail::check(uvf_pgp_chart_layout(handle_.get(), &layout));
        return ChartLayout(layout);
    }
    /// Per-chart parameterization (§3.3–3.4), cut along the iso-lines at `density` lines per
    /// period (1: the paper's iso-2kπ chart boundaries; a whole number).
    PgpCharts charts(double density = 1) const {
        UvfPgpCharts *charts = nullptr;
        detail::check(uvf_pgp_charts(handle_.get(), density, &charts));
        return PgpCharts(charts);
    }

  private:
    detail::Handle<UvfPgp, uvf_pgp_free> handle_;
    std::size_t vertex_count_ = 0;
    std::vector<double> corner_theta_phi_;
};

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
    UvfQuadCoverReport report = detail::sized<UvfQuadCoverReport>();
};

namespace detail {

/// The C options of `quadcover` (no progress callback installed).
inline UvfQuadCoverOptions quadcover_options(const QuadCoverOptions &options, std::size_t triangle_count) {
    check_optional_size(options.field, triangle_count, 3, "the field");
    UvfQuadCoverOptions o;
    uvf_quadcover_options_default(&o);
    o.grid_spacing = options.grid_spacing;
    o.alignment = options.alignment;
    o.round = options.round ? 1 : 0;
    o.cones_on_grid = options.cones_on_grid ? 1 : 0;
    o.pair_cells = options.pair_cells;
    o.untangle = options.untangle ? 1 : 0;
    return o;
}

} // namespace detail

/// QuadCover (Kälberer, Nieser & Polthier 2007): a seamless global parameterization whose
/// integer iso-lines close up over the surface (quarter turns and integer translations across
/// every seam).
inline QuadCoverMap quadcover(Positions positions, Triangles triangles,
                              const QuadCoverOptions &options = {}) {
    const std::size_t nv = detail::count_of(positions, 3, "positions");
    const std::size_t nt = detail::count_of(triangles, "triangles");
    UvfQuadCoverOptions o = detail::quadcover_options(options, nt);
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

/// The integer grid lines of a QuadCover map (computed as `quadcover` does) as a quad-dominant
/// mesh on the surface: the lines u, v ∈ ℤ / `density` (a whole number ≥ 1); the report goes
/// to `*report` if given.
inline QuadMesh quadcover_quad_mesh(Positions positions, Triangles triangles,
                                    double density = 1, const QuadCoverOptions &options = {},
                                    UvfQuadCoverReport *report = nullptr) {
    const std::size_t nt = detail::count_of(triangles, "triangles");
    UvfQuadCoverOptions o = detail::quadcover_options(options, nt);
    detail::Progress progress;
    progress.callback = &options.progress;
    progress.install(o);
    UvfQuadMesh *handle = nullptr;
    UvfQuadCoverReport r = detail::sized<UvfQuadCoverReport>();
    const UvfStatus status = uvf_quadcover_quad_mesh(positions.data(), detail::count_of(positions, 3, "positions"),
                                                     triangles.data(), nt, &o,
                                                     options.field.empty() ? nullptr : options.field.data(), density,
                                                     &handle, &r);
    QuadMesh mesh(handle);
    progress.finish(status);
    if (report) *report = r;
    return mesh;
}

/// How `Atlas` flattens its charts (UVF_ATLAS_CHART_*).
enum class AtlasChartMethod : std::uint32_t {
    natural_conformal = UVF_ATLAS_CHART_NATURAL_CONFORMAL,
    mean_value = UVF_ATLAS_CHART_MEAN_VALUE,
    slim = UVF_ATLAS_CHART_SLIM,
    stretch = UVF_ATLAS_CHART_STRETCH,
};

/// Options of `Atlas`; defaults as `uvf_atlas_options_default`.
struct AtlasOptions {
    /// Largest L2 stretch of a chart (≥ 1); infinity splits only charts that flip or overlap.
    double max_stretch = 1.004;
    /// Gap between charts in the unit square, in [0, 0.5).
    double margin = 0.005;
    AtlasChartMethod method = AtlasChartMethod::natural_conformal;
    /// Iterations of the non-linear chart methods.
    std::uint32_t iterations = 20;
    bool rotate = true;
    bool merge = true;
    /// L2-stretch polishing iterations per chart (0: none).
    std::uint32_t polish_iterations = 10;
    std::function<bool(double)> progress;
};

namespace detail {

/// The C options of `Atlas` (no progress callback installed).
inline UvfAtlasOptions atlas_options(const AtlasOptions &options) {
    UvfAtlasOptions o;
    uvf_atlas_options_default(&o);
    o.max_stretch = options.max_stretch;
    o.margin = options.margin;
    o.method = static_cast<std::uint32_t>(options.method);
    o.iterations = options.iterations;
    o.rotate = options.rotate ? 1 : 0;
    o.merge = options.merge ? 1 : 0;
    o.polish_iterations = options.polish_iterations;
    return o;
}

} // namespace detail

/// A packed chart atlas of any manifold mesh (`uvf_atlas`): charts without flips, overlaps or
/// stretch above the bound, packed without overlap into [0, 1]². Move-only owner of the
/// `UvfAtlas` handle, freed by the destructor. `metrics(positions, triangles, uv(),
/// uv_triangles())` measures it.
class Atlas {
  public:
    Atlas(Positions positions, Triangles triangles,
          const AtlasOptions &options = {}) {
        UvfAtlasOptions o = detail::atlas_options(options);
        detail::Progress progress;
        progress.callback = &options.progress;
        progress.install(o);
        progress.finish(uvf_atlas(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                                  detail::count_of(triangles, "triangles"), &o, handle_.out()));
    }
    /// The atlas of a mesh handle.
    explicit Atlas(const Mesh &mesh, const AtlasOptions &options = {}) {
        UvfAtlasOptions o = detail::atlas_options(options);
        detail::Progress progress;
        progress.callback = &options.progress;
        progress.install(o);
        progress.finish(uvf_mesh_atlas(mesh.get(), &o, handle_.out()));
    }

    /// Sizes, utilization and stretch.
    UvfAtlasInfo info() const {
        UvfAtlasInfo i = detail::sized<UvfAtlasInfo>();
        detail::check(uvf_atlas_info(handle_.get(), &i));
        return i;
    }
    /// UV of every atlas vertex (2 doubles each, in [0, 1]).
    std::vector<double> uv() const {
        std::vector<double> out(2 * info().vertex_count);
        detail::check(uvf_atlas_copy_uv(handle_.get(), out.data(), out.size()));
        return out;
    }
    /// The atlas vertex of every corner: 3 indices into `uv()` per input triangle.
    std::vector<std::uint32_t> uv_triangles() const {
        std::vector<std::uint32_t> out(3 * info().triangle_count);
        detail::check(uvf_atlas_copy_triangles(handle_.get(), out.data(), out.size()));
        return out;
    }
    /// UV of every corner: 6 doubles per input triangle.
    std::vector<double> corner_uv() const {
        std::vector<double> out(6 * info().triangle_count);
        detail::check(uvf_atlas_copy_corner_uv(handle_.get(), out.data(), out.size()));
        return out;
    }
    /// The chart of every input triangle, in [0, chart_count).
    std::vector<std::uint32_t> chart_of_triangle() const {
        std::vector<std::uint32_t> out(info().triangle_count);
        detail::check(uvf_atlas_copy_charts(handle_.get(), out.data(), out.size()));
        return out;
    }
    /// The input vertex of every atlas vertex.
    std::vector<std::uint32_t> original_vertices() const {
        std::vector<std::uint32_t> out(info().vertex_count);
        detail::check(uvf_atlas_copy_original_vertices(handle_.get(), out.data(), out.size()));
        return out;
    }

  private:
    detail::Handle<UvfAtlas, uvf_atlas_free> handle_;
};

/// Options of `Unwrap`; defaults as `uvf_unwrap_options_default`.
struct UnwrapOptions {
    /// Largest L2 stretch of an island (≥ 1); infinity keeps every component one island.
    double max_stretch = 1.5;
    /// Gap between islands in the unit square, in [0, 0.5).
    double margin = 0.005;
    AtlasChartMethod method = AtlasChartMethod::natural_conformal;
    /// Iteration limit of the non-linear solves (the bijective repair included).
    std::uint32_t iterations = 100;
    bool rotate = true;
    std::function<bool(double)> progress;
};

/// The default unwrap of any manifold mesh (`uvf_unwrap`): islands without flips, overlaps or
/// stretch above the bound, packed into [0, 1]² and verified by the library's exact checker.
/// Move-only owner of the `UvfUnwrap` handle, freed by the destructor.
class Unwrap {
  public:
    Unwrap(Positions positions, Triangles triangles,
           const UnwrapOptions &options = {}) {
        UvfUnwrapOptions o = c_options(options);
        detail::Progress progress;
        progress.callback = &options.progress;
        progress.install(o);
        progress.finish(uvf_unwrap(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                                   detail::count_of(triangles, "triangles"), &o, handle_.out()));
    }
    /// The unwrap of a mesh handle.
    explicit Unwrap(const Mesh &mesh, const UnwrapOptions &options = {}) {
        UvfUnwrapOptions o = c_options(options);
        detail::Progress progress;
        progress.callback = &options.progress;
        progress.install(o);
        progress.finish(uvf_mesh_unwrap(mesh.get(), &o, handle_.out()));
    }

    /// What the unwrap did: islands, repairs, seams, verified flips and overlaps (0), stretch.
    UvfUnwrapReport report() const {
        UvfUnwrapReport r = detail::sized<UvfUnwrapReport>();
        detail::check(uvf_unwrap_report(handle_.get(), &r));
        return r;
    }
    /// UV of every corner: 6 doubles per input triangle.
    std::vector<double> corner_uv() const {
        UvfAtlasInfo i = detail::sized<UvfAtlasInfo>();
        detail::check(uvf_atlas_info(layout(), &i));
        std::vector<double> out(6 * i.triangle_count);
        detail::check(uvf_atlas_copy_corner_uv(layout(), out.data(), out.size()));
        return out;
    }
    /// UV of every UV vertex (2 doubles each, in [0, 1]).
    std::vector<double> uv() const {
        std::vector<double> out(2 * report().uv_vertex_count);
        detail::check(uvf_atlas_copy_uv(layout(), out.data(), out.size()));
        return out;
    }
    /// The UV vertex of every corner: 3 indices into `uv()` per input triangle.
    std::vector<std::uint32_t> uv_triangles() const {
        UvfAtlasInfo i = detail::sized<UvfAtlasInfo>();
        detail::check(uvf_atlas_info(layout(), &i));
        std::vector<std::uint32_t> out(3 * i.triangle_count);
        detail::check(uvf_atlas_copy_triangles(layout(), out.data(), out.size()));
        return out;
    }
    /// The island of every input triangle, in [0, islands).
    std::vector<std::uint32_t> island_of_triangle() const {
        UvfAtlasInfo i = detail::sized<UvfAtlasInfo>();
        detail::check(uvf_atlas_info(layout(), &i));
        std::vector<std::uint32_t> out(i.triangle_count);
        detail::check(uvf_atlas_copy_charts(layout(), out.data(), out.size()));
        return out;
    }
    /// The input vertex of every UV vertex.
    std::vector<std::uint32_t> original_vertices() const {
        std::vector<std::uint32_t> out(report().uv_vertex_count);
        detail::check(uvf_atlas_copy_original_vertices(layout(), out.data(), out.size()));
        return out;
    }
    /// The cut input edges: pairs of vertex indices a < b, sorted.
    std::vector<std::uint32_t> seams() const {
        std::vector<std::uint32_t> out(2 * report().seam_edges);
        detail::check(uvf_unwrap_copy_seams(handle_.get(), out.data(), out.size()));
        return out;
    }

  private:
    static UvfUnwrapOptions c_options(const UnwrapOptions &options) {
        UvfUnwrapOptions o;
        uvf_unwrap_options_default(&o);
        o.max_stretch = options.max_stretch;
        o.margin = options.margin;
        o.method = static_cast<std::uint32_t>(options.method);
        o.iterations = options.iterations;
        o.rotate = options.rotate ? 1 : 0;
        return o;
    }
    const UvfAtlas *layout() const {
        const UvfAtlas *a = nullptr;
        detail::check(uvf_unwrap_atlas(handle_.get(), &a));
        return a;
    }
    detail::Handle<UvfUnwrap, uvf_unwrap_free> handle_;
};

/// Distortion of per-vertex UVs (2 doubles per vertex).
inline UvfMetrics metrics(Positions positions, Triangles triangles,
                          const std::vector<double> &uv) {
    UvfMetrics m = detail::sized<UvfMetrics>();
    detail::check(uvf_metrics(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                              detail::count_of(triangles, "triangles"), uv.data(), detail::count_of(uv, 2, "uv"),
                              nullptr, &m));
    return m;
}

/// Distortion of per-corner UVs: `uv_triangles` holds 3 indices into `uv` per triangle.
inline UvfMetrics metrics(Positions positions, Triangles triangles,
                          const std::vector<double> &uv, const std::vector<std::uint32_t> &uv_triangles) {
    if (uv_triangles.size() != triangles.size()) {
        throw Error(UVF_INVALID_ARGUMENT, "uv_triangles must have as many entries as triangles");
    }
    UvfMetrics m = detail::sized<UvfMetrics>();
    detail::check(uvf_metrics(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                              detail::count_of(triangles, "triangles"), uv.data(), detail::count_of(uv, 2, "uv"),
                              uv_triangles.data(), &m));
    return m;
}

/// Distortion of per-vertex UVs on a mesh handle (its triangulation).
inline UvfMetrics metrics(const Mesh &mesh, const std::vector<double> &uv) {
    UvfMetrics m = detail::sized<UvfMetrics>();
    detail::check(uvf_mesh_metrics(mesh.get(), uv.data(), detail::count_of(uv, 2, "uv"), nullptr, &m));
    return m;
}

/// The exact layout check (`uvf_check_layout`): flipped triangles, crossing or touching UV
/// boundary edges, islands of per-corner UVs (`uv_triangles`: 3 indices into `uv` per triangle).
inline UvfLayoutCheck check_layout(const std::vector<double> &uv, const std::vector<std::uint32_t> &uv_triangles) {
    UvfLayoutCheck c = detail::sized<UvfLayoutCheck>();
    detail::check(uvf_check_layout(uv.data(), detail::count_of(uv, 2, "uv"), uv_triangles.data(),
                                   detail::count_of(uv_triangles, "uv_triangles"), &c));
    return c;
}

/// A mesh cut into a topological disk (`uvf_cut_to_disk`: tree-cotree cut graph); owns the
/// library's handle (move-only, freed by the destructor). Any disk method runs on
/// `positions()` / `triangles()`; `original_vertices()` maps the cut mesh back.
class Cut {
  public:
    Cut(Positions positions, Triangles triangles,
        std::uint32_t cost = UVF_CUT_COST_CURVATURE) {
        UvfCutOptions options;
        uvf_cut_options_default(&options);
        options.cost = cost;
        detail::check(uvf_cut_to_disk(positions.data(), detail::count_of(positions, 3, "positions"), triangles.data(),
                                      detail::count_of(triangles, "triangles"), &options, &handle_));
    }
    /// The cut of a mesh handle.
    explicit Cut(const Mesh &mesh, std::uint32_t cost = UVF_CUT_COST_CURVATURE) {
        UvfCutOptions options;
        uvf_cut_options_default(&options);
        options.cost = cost;
        detail::check(uvf_mesh_cut_to_disk(mesh.get(), &options, &handle_));
    }
    /// A cut along the cheapest edges by the caller's costs (`UVF_CUT_COST_GIVEN`): 3 doubles
    /// per triangle, the cost of the edge from corner k to corner k + 1 at `3t + k`.
    Cut(Positions positions, Triangles triangles,
        const std::vector<double> &edge_cost) {
        if (edge_cost.size() != triangles.size()) {
            throw Error(UVF_INVALID_ARGUMENT, "edge_cost must hold 3 values per triangle");
        }
        UvfCutOptions options;
        uvf_cut_options_default(&options);
        options.cost = UVF_CUT_COST_GIVEN;
        options.edge_cost = edge_cost.data();
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
        UvfCutInfo i = detail::sized<UvfCutInfo>();
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
/// The optional progress callback follows (and can cancel) the factorization.
class BoundaryEditor {
  public:
    BoundaryEditor(Positions positions, Triangles triangles,
                   double lambda = 1.0, double mu = 0.0, const std::function<bool(double)> &callback = {})
        : vertex_count_(detail::count_of(positions, 3, "positions")) {
        UvfIntrinsicToolOptions o;
        uvf_intrinsic_tool_options_default(&o);
        detail::Progress progress;
        progress.callback = &callback;
        progress.install(o);
        const UvfStatus status = uvf_boundary_editor_new(positions.data(), vertex_count_, triangles.data(),
                                                         detail::count_of(triangles, "triangles"), lambda, mu, &o,
                                                         &handle_);
        try {
            progress.finish(status);
        } catch (...) { // no destructor runs for a constructor that throws
            uvf_boundary_editor_free(std::exchange(handle_, nullptr));
            throw;
        }
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
    /// The Green-function basis (Desbrun et al. 2002 §4.2): b × n doubles (b boundary vertices,
    /// n mesh vertices), `basis[i * n + v]` the weight of boundary vertex i in the UV of vertex
    /// v. Refused with UVF_INVALID_ARGUMENT when it would take more than `max_bytes`.
    std::vector<double> basis(std::size_t max_bytes = std::size_t(1) << 30) const {
        const std::size_t count = boundary().size() * vertex_count_;
        std::vector<double> out;
        // Over the budget the library refuses before writing; nothing is allocated here.
        if (count <= max_bytes / sizeof(double)) out.resize(count);
        detail::check(uvf_boundary_editor_basis(handle_, max_bytes, out.empty() ? nullptr : out.data()));
        return out;
    }

  private:
    UvfBoundaryEditor *handle_ = nullptr;
    std::size_t vertex_count_ = 0;
};

} // namespace uvflat

#endif // UVFLAT_HPP
