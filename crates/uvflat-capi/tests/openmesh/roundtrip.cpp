// OpenMesh integration test (run by crates/uvflat-capi/tests/it/openmesh.rs): reads meshes with OpenMesh, hands its
// flat arrays to uvflat through the C++ wrapper, stores the UVs as OpenMesh vertex texcoords,
// writes and re-reads the mesh with OpenMesh, and checks the round trip and the metrics.
//
// usage: roundtrip OUT_DIR MESH.obj...
// Prints one line per mesh and method; exits 1 if any check failed.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "flat_arrays.hpp"
#include "uvflat.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace {

int failures = 0;

void fail(const std::string &mesh, const std::string &what) {
    std::printf("FAIL %s: %s\n", mesh.c_str(), what.c_str());
    ++failures;
}

std::string base_name(const std::string &path) { return path.substr(path.find_last_of('/') + 1); }

double uv_diameter(const std::vector<double> &uv) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (std::size_t i = 0; i < uv.size(); ++i) {
        if (std::isnan(uv[i])) continue;
        lo[i % 2] = std::min(lo[i % 2], uv[i]);
        hi[i % 2] = std::max(hi[i % 2], uv[i]);
    }
    return std::hypot(hi[0] - lo[0], hi[1] - lo[1]);
}

/// Stores `uv` as texcoords, writes an OBJ with OpenMesh, reads it back; returns the largest
/// UV difference relative to the UV diameter (or -1 when OpenMesh could not write or read).
double round_trip(Mesh mesh, const std::vector<double> &uv, const std::string &path) {
    mesh.request_vertex_texcoords2D();
    for (auto v : mesh.vertices()) {
        const double u = uv[2 * v.idx()], w = uv[2 * v.idx() + 1];
        mesh.set_texcoord2D(v, Mesh::TexCoord2D(float(std::isnan(u) ? 0 : u), float(std::isnan(w) ? 0 : w)));
    }
    OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexTexCoord;
    if (!OpenMesh::IO::write_mesh(mesh, path, options, 10)) return -1;
    Mesh back;
    back.request_vertex_texcoords2D();
    OpenMesh::IO::Options read_options = OpenMesh::IO::Options::VertexTexCoord;
    if (!OpenMesh::IO::read_mesh(back, path, read_options) || back.n_vertices() != mesh.n_vertices()) return -1;
    double worst = 0;
    for (auto v : back.vertices()) {
        if (std::isnan(uv[2 * v.idx()])) continue;
        const auto t = back.texcoord2D(v);
        worst = std::max(worst, std::hypot(t[0] - uv[2 * v.idx()], t[1] - uv[2 * v.idx() + 1]));
    }
    return worst / uv_diameter(uv);
}

void check_method(const std::string &name, const Mesh &mesh, const Arrays &a, const char *method,
                  const std::string &out_dir, bool must_not_flip) {
    std::vector<double> uv;
    try {
        if (std::string(method) == "mean-value") {
            uv = uvflat::fixed_boundary_map(a.positions, a.triangles);
        } else {
            uv = uvflat::natural_conformal_map(a.positions, a.triangles);
        }
    } catch (const uvflat::Error &e) {
        fail(name, std::string(method) + " failed on a disk-like mesh: " + e.what());
        return;
    }
    const UvfMetrics m = uvflat::metrics(a.positions, a.triangles, uv);
    // OpenMesh stores texcoords as float: the round trip keeps ~7 significant digits.
    const double trip = round_trip(mesh, uv, out_dir + "/" + name + "." + method + ".obj");
    std::printf("%s %s: flipped %zu, conformal %.4f, stretch %.4f, round trip %.2e\n", name.c_str(), method,
                m.flipped, m.conformal_mean, m.stretch_l2, trip);
    if (trip < 0 || trip > 1e-6) fail(name, std::string(method) + ": OpenMesh round trip lost the UVs");
    if (m.triangles != a.triangles.size() / 3) fail(name, "metrics counted the wrong number of triangles");
    if (must_not_flip && m.flipped != 0) fail(name, std::string(method) + " flipped triangles");
}

/// The RAII cut: the cut mesh is one disk whose corners map back to the input's vertices, and
/// the mean value map of it flips nothing.
void check_cut(const std::string &name, const Arrays &a) {
    try {
        std::vector<double> lengths(a.triangles.size());
        for (std::size_t k = 0; k < lengths.size(); ++k) {
            const std::uint32_t u = a.triangles[k], w = a.triangles[k % 3 == 2 ? k - 2 : k + 1];
            lengths[k] = std::hypot(a.positions[3 * u] - a.positions[3 * w], a.positions[3 * u + 1] - a.positions[3 * w + 1],
                                    a.positions[3 * u + 2] - a.positions[3 * w + 2]);
        }
        const uvflat::Cut given(a.positions, a.triangles, lengths); // the caller's edge costs
        const uvflat::Cut of_handle(uvflat::Mesh(a.positions, a.triangles));
        if (of_handle.triangles() != uvflat::Cut(a.positions, a.triangles).triangles()) fail(name, "Cut of a handle differs");
        if (given.triangles().size() != a.triangles.size()) fail(name, "the cut by given costs changed the triangles");
        uvflat::Cut cut(a.positions, a.triangles);
        uvflat::Cut moved = std::move(cut);
        const std::vector<std::uint32_t> tris = moved.triangles(), original = moved.original_vertices();
        const std::vector<double> pos = moved.positions();
        if (tris.size() != a.triangles.size()) fail(name, "the cut changed the triangle count");
        for (std::size_t k = 0; k < tris.size(); ++k) {
            if (original[tris[k]] != a.triangles[k]) fail(name, "a cut corner does not map back to its vertex");
        }
        const UvfMeshInfo info = uvflat::mesh_info(pos, tris);
        if (info.boundary_loops != 1 || info.euler_characteristic != 1) fail(name, "the cut mesh is not a disk");
        const std::vector<double> uv = uvflat::fixed_boundary_map(pos, tris);
        if (uvflat::metrics(pos, tris, uv).flipped != 0) fail(name, "the cut mesh's mean value map flipped");
    } catch (const uvflat::Error &e) {
        fail(name, std::string("cut failed: ") + e.what());
    }
}

/// The RAII boundary editor reproduces the fixed-boundary map for the boundary it is given.
void check_boundary_editor(const std::string &name, const Arrays &a) {
    if (a.triangles.size() > 3 * 40000) return; // keep the suite fast
    uvflat::FixedBoundaryOptions options;
    options.weights = uvflat::Weights::conformal;
    const std::vector<double> fresh = uvflat::fixed_boundary_map(a.positions, a.triangles, options);
    const uvflat::BoundaryEditor editor(a.positions, a.triangles, 1.0, 0.0);
    std::vector<double> boundary_uv;
    for (std::uint32_t v : editor.boundary()) {
        boundary_uv.push_back(fresh[2 * v]);
        boundary_uv.push_back(fresh[2 * v + 1]);
    }
    const std::vector<double> uv = editor.solve(boundary_uv);
    for (std::size_t k = 0; k < uv.size(); ++k) {
        if (!(std::abs(uv[k] - fresh[k]) <= 1e-8) && !(std::isnan(uv[k]) && std::isnan(fresh[k]))) {
            fail(name, "the boundary editor differs from the fixed-boundary map");
            return;
        }
    }
}

/// The other disk methods of the wrapper on a disk of at most 20k triangles: ABF++ and SLIM
/// flip nothing (as measured on every disk mesh), the spectral map is finite on every referenced vertex, the circle
/// pattern closes its circles and reports the flips the metrics count, and with a convex
/// boundary it does not cross itself (unless its scale spans more than double precision holds,
/// which the report says).
void check_disk_methods(const std::string &name, const Arrays &a) {
    if (a.triangles.size() > 3 * 20000) return; // keep the suite fast
    try {
        UvfAbfReport abf_report{};
        const std::vector<double> abf = uvflat::abf(a.positions, a.triangles, {}, &abf_report);
        if (uvflat::metrics(a.positions, a.triangles, abf).flipped != 0) fail(name, "ABF++ flipped triangles");
        uvflat::NonlinearOptions slim;
        slim.iterations = 5;
        const std::vector<double> uv = uvflat::nonlinear_map(a.positions, a.triangles, slim);
        if (uvflat::metrics(a.positions, a.triangles, uv).flipped != 0) fail(name, "SLIM flipped triangles");
        const std::vector<double> spectral = uvflat::spectral_conformal_map(a.positions, a.triangles);
        for (std::uint32_t v : a.triangles) { // unreferenced vertices get NaN
            if (!std::isfinite(spectral[2 * v]) || !std::isfinite(spectral[2 * v + 1])) {
                fail(name, "the spectral map is not finite");
                break;
            }
        }
        UvfCirclePatternReport report{};
        const std::vector<double> circles = uvflat::circle_pattern_map(a.positions, a.triangles, {}, &report);
        const UvfMetrics m = uvflat::metrics(a.positions, a.triangles, circles);
        if (!(report.closure_error < 1e-9) || m.flipped != report.flipped_triangles) {
            fail(name, "circle pattern: open circles or a wrong flip count");
        }
        uvflat::CirclePatternOptions convex;
        convex.convex_boundary = true;
        const std::vector<double> c = uvflat::circle_pattern_map(a.positions, a.triangles, convex, &report);
        const UvfMetrics cm = uvflat::metrics(a.positions, a.triangles, c);
        std::printf("%s ABF++ %u iterations, circle patterns convex: span %.1f decades, %zu boundary crossings\n",
                    name.c_str(), abf_report.iterations, report.radius_span, cm.boundary_intersections);
        if (report.radius_span < 12 && cm.boundary_intersections != 0) fail(name, "the convex boundary crosses itself");
    } catch (const uvflat::Error &e) {
        fail(name, std::string("a disk method failed: ") + e.what());
    }
}

/// Automatic cones and the circle-pattern cone map on a closed mesh of at most 10k triangles:
/// the curvatures sum to 2π χ, and at most one triangle in 1000 flips.
void check_cone_map(const std::string &name, const Arrays &a, const UvfMeshInfo &info) {
    const std::size_t nt = a.triangles.size() / 3;
    if (nt > 10000 || info.components != 1 || info.boundary_loops != 0) return;
    try {
        const std::uint32_t max_cones = std::max<std::int64_t>(64, -4 * info.euler_characteristic);
        const std::vector<uvflat::Cone> cones = uvflat::place_cones(a.positions, a.triangles, max_cones);
        double total = 0;
        for (const uvflat::Cone &c : cones) total += c.curvature;
        if (std::abs(total - 2 * M_PI * double(info.euler_characteristic)) > 1e-8) fail(name, "cones against Gauss-Bonnet");
        UvfCirclePatternReport report{};
        const std::vector<double> corner_uv = uvflat::circle_pattern_cone_map(a.positions, a.triangles, cones, {}, &report);
        std::vector<std::uint32_t> corners(3 * nt);
        for (std::size_t k = 0; k < corners.size(); ++k) corners[k] = std::uint32_t(k);
        const UvfMetrics m = uvflat::metrics(a.positions, a.triangles, corner_uv, corners);
        std::printf("%s: %zu automatic cones, %zu flipped\n", name.c_str(), cones.size(), m.flipped);
        if (m.flipped * 1000 > nt) fail(name, "the cone map flipped too many triangles");
    } catch (const uvflat::Error &e) {
        fail(name, std::string("cone map failed: ") + e.what());
    }
}

/// The spherical maps of a closed genus-0 mesh of at most 10k triangles: Tutte–gnomonic never
/// flips, and the conformal circle-pattern map keeps the mesh's angles better than it.
void check_sphere(const std::string &name, const Arrays &a, const UvfMeshInfo &info) {
    const std::size_t nt = a.triangles.size() / 3;
    if (nt > 10000 || info.components != 1 || info.boundary_loops != 0 || info.genus != 0) return;
    try {
        std::size_t flipped = 0, conformal_flipped = 0;
        const std::vector<double> tutte = uvflat::spherical_map(a.positions, a.triangles, uvflat::SphereMethod::tutte_gnomonic, &flipped);
        const std::vector<double> circles =
            uvflat::spherical_map(a.positions, a.triangles, uvflat::SphereMethod::circle_patterns, &conformal_flipped);
        if (flipped != 0) fail(name, "the Tutte-gnomonic sphere map flipped");
        if (uvflat::spherical_map(uvflat::Mesh(a.positions, a.triangles)) != tutte) fail(name, "sphere map of a handle differs");
        uvflat::SphereOptions gauss_seidel;
        gauss_seidel.method = uvflat::SphereMethod::gauss_seidel;
        gauss_seidel.sweeps = 1000000;
        gauss_seidel.progress = [](double) { return false; };
        try {
            uvflat::spherical_map(a.positions, a.triangles, gauss_seidel);
            fail(name, "a sphere map whose progress callback says stop was not cancelled");
        } catch (const uvflat::Error &e) {
            if (e.status() != UVF_CANCELLED) fail(name, "cancelling the sphere map gave the wrong status");
        }
        auto angle_error = [&](const std::vector<double> &x) {
            double total = 0;
            std::size_t count = 0;
            for (std::size_t t = 0; t < nt; ++t) {
                for (int k = 0; k < 3; ++k) {
                    auto angle = [&](const std::vector<double> &p) {
                        const std::uint32_t *v = &a.triangles[3 * t];
                        const std::uint32_t i = v[k], j = v[(k + 1) % 3], l = v[(k + 2) % 3];
                        double u[3], w[3], uu = 0, ww = 0, uw = 0;
                        for (int d = 0; d < 3; ++d) {
                            u[d] = p[3 * j + d] - p[3 * i + d];
                            w[d] = p[3 * l + d] - p[3 * i + d];
                            uu += u[d] * u[d];
                            ww += w[d] * w[d];
                            uw += u[d] * w[d];
                        }
                        return std::acos(std::clamp(uw / std::sqrt(uu * ww), -1.0, 1.0));
                    };
                    // Triangles collapsed to a point on the sphere (cow's legs) have no angle.
                    const double e = std::abs(angle(x) - angle(a.positions));
                    if (std::isfinite(e)) {
                        total += e;
                        ++count;
                    }
                }
            }
            return total / double(std::max<std::size_t>(count, 1));
        };
        const double e_tutte = angle_error(tutte), e_circles = angle_error(circles);
        std::printf("%s: sphere angle error %.2f deg (circle patterns, %zu flipped) against %.2f (Tutte-gnomonic)\n",
                    name.c_str(), e_circles * 180 / M_PI, conformal_flipped, e_tutte * 180 / M_PI);
        if (!(e_circles < e_tutte)) fail(name, "the conformal sphere map distorts angles more than Tutte-gnomonic");
    } catch (const uvflat::Error &e) {
        fail(name, std::string("spherical map failed: ") + e.what());
    }
}

/// QuadCover on a closed mesh of at most 10k triangles: the cone indices sum to 4χ quarters
/// (Hopf–Poincaré), the cancellation only removes cones, and across every edge the two
/// triangles' (u, v) differ by a quarter turn and an integer translation.
void check_quadcover(const std::string &name, const Arrays &a, const UvfMeshInfo &info) {
    const std::size_t nt = a.triangles.size() / 3;
    if (nt > 10000 || info.components != 1 || info.boundary_loops != 0) return;
    try {
        const uvflat::QuadCoverMap map = uvflat::quadcover(a.positions, a.triangles);
        long long quarters = 0;
        for (std::int32_t q : map.cone_index) quarters += q;
        if (quarters != 4 * (long long)info.euler_characteristic) fail(name, "QuadCover cones against Hopf-Poincare");
        if (map.report.cone_count > map.report.cones_before_cancellation) fail(name, "the cancellation added cones");
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> corner_of;
        for (std::size_t c = 0; c < 3 * nt; ++c) {
            corner_of[{a.triangles[c], a.triangles[c - c % 3 + (c + 1) % 3]}] = c;
        }
        double worst = 0;
        for (const auto &[edge, c] : corner_of) {
            const std::size_t d = corner_of.at({edge.second, edge.first});
            const std::size_t c1 = c - c % 3 + (c + 1) % 3, d1 = d - d % 3 + (d + 1) % 3;
            // f: a → b in c's triangle, g: b → a in d's; find the r with J^r (f_b − f_a) = g_a − g_b.
            const double fu = map.corner_uv[2 * c1] - map.corner_uv[2 * c], fv = map.corner_uv[2 * c1 + 1] - map.corner_uv[2 * c + 1];
            const double gu = map.corner_uv[2 * d] - map.corner_uv[2 * d1], gv = map.corner_uv[2 * d + 1] - map.corner_uv[2 * d1 + 1];
            double best = 1e300;
            for (int r = 0; r < 4; ++r) {
                double u = fu, v = fv, au = map.corner_uv[2 * c], av = map.corner_uv[2 * c + 1];
                for (int k = 0; k < r; ++k) {
                    u = std::exchange(v, -u);
                    au = std::exchange(av, -au);
                }
                const double misfit = std::hypot(u - gu, v - gv);
                // The translation maps a's corner in c's triangle onto a's corner in d's.
                const double tu = map.corner_uv[2 * d1] - au, tv = map.corner_uv[2 * d1 + 1] - av;
                best = std::min(best, misfit + std::abs(tu - std::round(tu)) + std::abs(tv - std::round(tv)));
            }
            worst = std::max(worst, best);
        }
        std::printf("%s: QuadCover %u cones (%u before the cancellation), %u folded, seams off by %.1e\n", name.c_str(),
                    map.report.cone_count, map.report.cones_before_cancellation, map.report.flipped_count, worst);
        if (!(worst < 1e-6)) fail(name, "QuadCover seams are not quarter turns and integer translations");
    } catch (const uvflat::Error &e) {
        fail(name, std::string("QuadCover failed: ") + e.what());
    }
}

void check_mesh(const std::string &path, const std::string &out_dir) {
    const std::string name = base_name(path);
    Mesh mesh;
    if (!OpenMesh::IO::read_mesh(mesh, path)) {
        std::printf("%s: OpenMesh cannot read it\n", name.c_str());
        return;
    }
    const Arrays a = flat_arrays(mesh);
    UvfMeshInfo info{};
    try {
        info = uvflat::mesh_info(a.positions, a.triangles);
    } catch (const uvflat::Error &e) {
        // OpenMesh drops faces it cannot add; what it keeps may still be invalid for uvflat.
        std::printf("%s: rejected (status %d): %s\n", name.c_str(), int(e.status()), e.what());
        if (std::string(e.what()).empty()) fail(name, "error without a message");
        if (name.rfind("disk_", 0) == 0) fail(name, "a disk mesh was rejected");
        return;
    }
    const bool disk_with_holes = info.components == 1 && info.genus == 0 && info.boundary_loops >= 1;
    if (!disk_with_holes && info.components == 1) check_cut(name, a);
    if (disk_with_holes && info.boundary_loops == 1) check_boundary_editor(name, a);
    if (disk_with_holes && info.boundary_loops == 1) check_disk_methods(name, a);
    check_cone_map(name, a, info);
    check_quadcover(name, a, info);
    check_sphere(name, a, info);
    if (!disk_with_holes) {
        try {
            uvflat::natural_conformal_map(a.positions, a.triangles);
            fail(name, "a mesh that is not a disk with holes was unwrapped");
        } catch (const uvflat::Error &e) {
            std::printf("%s: not a disk (%zu components, %zu loops, genus %lld): %s\n", name.c_str(), info.components,
                        info.boundary_loops, (long long)info.genus, e.what());
            if (e.status() != UVF_UNSUPPORTED_TOPOLOGY) fail(name, "expected UVF_UNSUPPORTED_TOPOLOGY");
        }
        return;
    }
    check_method(name, mesh, a, "mean-value", out_dir, true);
    check_method(name, mesh, a, "natural-conformal", out_dir, false);
}

/// The wrapper's progress plumbing: false cancels with UVF_CANCELLED, an exception thrown by
/// the callback comes back out unchanged, and the callback sees fractions up to 1.
void check_wrapper_progress(const std::string &path) {
    Mesh mesh;
    if (!OpenMesh::IO::read_mesh(mesh, path)) return fail(path, "cannot read");
    const Arrays a = flat_arrays(mesh);
    uvflat::NaturalConformalOptions options;
    double last = 0;
    options.progress = [&](double f) { last = f; return true; };
    uvflat::natural_conformal_map(a.positions, a.triangles, options);
    if (last != 1.0) fail(path, "progress did not reach 1");
    options.progress = [](double f) { return f < 0.5; };
    try {
        uvflat::natural_conformal_map(a.positions, a.triangles, options);
        fail(path, "cancelling did not stop the computation");
    } catch (const uvflat::Error &e) {
        if (e.status() != UVF_CANCELLED) fail(path, "cancelling gave the wrong status");
    }
    struct Stop {};
    uvflat::FixedBoundaryOptions fixed;
    fixed.progress = [](double) -> bool { throw Stop{}; };
    try {
        uvflat::fixed_boundary_map(a.positions, a.triangles, fixed);
        fail(path, "a throwing callback did not stop the computation");
    } catch (const Stop &) {
    }
    std::printf("wrapper progress and cancellation: ok\n");
}

} // namespace

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s OUT_DIR MESH.obj...\n", argv[0]);
        return 2;
    }
    OpenMesh::IO::IOManager(); // make sure the OBJ reader/writer are registered
    for (int i = 2; i < argc; ++i) {
        if (base_name(argv[i]) == "disk_nefertiti_small.obj") check_wrapper_progress(argv[i]);
    }
    for (int i = 2; i < argc; ++i) check_mesh(argv[i], argv[1]);
    std::printf("%d failure(s)\n", failures);
    return failures == 0 ? 0 : 1;
}
