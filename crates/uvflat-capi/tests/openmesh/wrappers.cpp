// The C++ wrapper's handle classes and newer functions (run by crates/uvflat-capi/tests/it/openmesh.rs): meshes are
// read with OpenMesh and handed to uvflat through bindings/cpp/uvflat.hpp. PGP (singularities
// against Hopf–Poincaré, the quad-dominant remesh, the chart layout, the per-chart
// parameterization), QuadCover's quad mesh, principal curvatures (against the torus' closed
// form), the atlas, the intrinsic tools, triangle components, moved-from handles, invalid
// arguments, and the C++ option defaults against the library's.
//
// usage: wrappers MESH_DIR   (reads closed_g1_torus.obj, closed_g2_eight.obj and
//                             disk_nefertiti_small.obj from it)
// Prints what it measured; exits 1 if any check failed.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "flat_arrays.hpp"
#include "uvflat.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <numeric>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace {

int failures = 0;
std::string context; // the check running, for the messages

void expect(bool ok, const std::string &what) {
    if (!ok) {
        std::printf("FAIL %s: %s\n", context.c_str(), what.c_str());
        ++failures;
    }
}

/// Runs `f`, which must throw uvflat::Error with `status` and a message.
template <class F> void expect_error(UvfStatus status, const std::string &what, F f) {
    try {
        f();
        expect(false, what + ": no uvflat::Error was thrown");
    } catch (const uvflat::Error &e) {
        expect(e.status() == status, what + ": status " + std::to_string(int(e.status())) + " (" + e.what() +
                                         "), expected " + std::to_string(int(status)));
        expect(std::string(e.what()).size() > 0, what + ": an error without a message");
    }
}

Arrays read(const std::string &path) {
    Mesh mesh;
    Arrays a;
    if (!OpenMesh::IO::read_mesh(mesh, path)) {
        context = path;
        expect(false, "OpenMesh cannot read it");
        return a;
    }
    return flat_arrays(mesh);
}

bool all_finite(const std::vector<double> &x) {
    return std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
}

double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Checks a polygon mesh copied from a QuadMesh against its info: the face sizes sum to the
/// index count, the indices are in range, and at least `min_quads` of the faces are quads.
void check_polygons(const uvflat::QuadMesh &quads, double min_quads, const std::string &what) {
    const UvfQuadMeshInfo info = quads.info();
    const uvflat::PolygonMesh m = quads.polygons();
    const std::size_t sum = std::accumulate(m.face_sizes.begin(), m.face_sizes.end(), std::size_t(0));
    const std::size_t quad_count = std::count(m.face_sizes.begin(), m.face_sizes.end(), 4u);
    std::printf("%s %s: %zu vertices, %zu faces, %zu quads (%.1f%%)\n", context.c_str(), what.c_str(),
                info.vertex_count, info.face_count, info.quad_count, 100.0 * double(info.quad_count) / double(info.face_count));
    expect(info.face_count > 0, what + ": no face");
    expect(m.positions.size() == 3 * info.vertex_count && all_finite(m.positions), what + ": positions");
    expect(m.face_sizes.size() == info.face_count, what + ": face count");
    expect(sum == info.index_count && m.indices.size() == info.index_count, what + ": face sizes do not sum to the index count");
    expect(quad_count == info.quad_count, what + ": quad count differs from info");
    expect(std::all_of(m.face_sizes.begin(), m.face_sizes.end(), [](std::uint32_t s) { return s >= 3; }),
           what + ": a face with fewer than 3 corners");
    expect(std::all_of(m.indices.begin(), m.indices.end(), [&](std::uint32_t i) { return i < info.vertex_count; }),
           what + ": an index out of range");
    expect(double(quad_count) >= min_quads * double(info.face_count), what + ": too few quads");
}

/// PGP on a closed mesh of genus g: the singular points' indices (quarters) sum to 2 − 2g
/// (Hopf–Poincaré) as info() says; the singular lists match info()'s counts and are sorted;
/// the remesh at 8 lines per period has ≥ 90% quads; the chart layout and the per-chart
/// parameterization match their infos; moved-from handles and bad densities throw.
void check_pgp(const std::string &name, const Arrays &a, long long genus) {
    context = name + " PGP";
    const double chi = 2.0 - 2.0 * double(genus);
    uvflat::Pgp pgp(a.positions, a.triangles);
    const UvfPgpInfo info = pgp.info();

    const std::vector<uvflat::SingularPoint> points = pgp.singular_points();
    double sum = 0;
    for (const uvflat::SingularPoint &p : points) {
        sum += p.index;
        expect(p.vertex < a.vertex_count(), "a singular point is not a vertex");
        expect(p.index != 0 && std::abs(4 * p.index - std::round(4 * p.index)) < 1e-9, "an index is not a non-zero quarter");
    }
    std::printf("%s: %zu singular points summing to %g (chi %g), %zu singular triangles, %u Newton iterations%s\n",
                context.c_str(), points.size(), sum, chi, info.singular_triangle_count, info.newton_iterations,
                info.converged ? "" : (" (not converged: gradient " + std::to_string(info.final_gradient) + ")").c_str());
    expect(points.size() == info.singular_point_count, "singular point count differs from info");
    expect(std::abs(sum - chi) < 1e-9, "singular point indices do not sum to 2 - 2g");
    expect(std::abs(info.index_sum - chi) < 1e-9, "info.index_sum is not 2 - 2g");
    expect(info.omega > 0 && std::isfinite(info.stretch), "omega or stretch");

    const std::vector<std::uint32_t> vertices = pgp.singular_vertices(), triangles = pgp.singular_triangles(),
                                     edges = pgp.singular_edges();
    expect(vertices.size() == info.singular_vertex_count && std::is_sorted(vertices.begin(), vertices.end()),
           "singular vertices");
    expect(triangles.size() == info.singular_triangle_count && std::is_sorted(triangles.begin(), triangles.end()) &&
               (triangles.empty() || triangles.back() < a.triangle_count()),
           "singular triangles");
    expect(edges.size() == 2 * info.singular_edge_count, "singular edge count");
    for (std::size_t k = 0; k < edges.size(); k += 2) {
        if (!(edges[k] < edges[k + 1] && edges[k + 1] < a.vertex_count())) {
            expect(false, "a singular edge is not a pair a < b of vertices");
            break;
        }
    }
    expect(pgp.corner_theta_phi().size() == 6 * a.triangle_count() && all_finite(pgp.corner_theta_phi()),
           "corner (theta, phi)");
    const std::vector<double> field = pgp.field();
    expect(field.size() == a.positions.size() && all_finite(field), "field");

    check_polygons(pgp.quad_mesh(8), 0.9, "quad mesh, density 8");

    const uvflat::ChartLayout layout = pgp.chart_layout();
    const UvfChartLayoutInfo layout_info = layout.info();
    const std::vector<std::vector<double>> lines = layout.polylines();
    const std::vector<std::uint32_t> corners = layout.chart_corners();
    std::size_t point_count = 0;
    for (const std::vector<double> &line : lines) {
        point_count += line.size() / 3;
        expect(line.size() % 3 == 0 && line.size() >= 6 && all_finite(line), "a polyline is not 2+ finite points");
    }
    std::printf("%s: chart layout of %zu charts (%zu with four corners), %zu polylines\n", context.c_str(),
                layout_info.chart_count, layout_info.four_corner_chart_count, layout_info.polyline_count);
    expect(layout_info.chart_count > 0, "no chart");
    expect(lines.size() == layout_info.polyline_count && point_count == layout_info.point_count, "polyline counts");
    expect(corners.size() == layout_info.chart_count &&
               std::size_t(std::count(corners.begin(), corners.end(), 4u)) == layout_info.four_corner_chart_count,
           "chart corner counts");

    const uvflat::PgpCharts charts = pgp.charts(1);
    const UvfPgpChartsInfo charts_info = charts.info();
    const std::vector<double> cut_positions = charts.positions(), corner_uv = charts.corner_uv();
    const std::vector<std::uint32_t> cut_triangles = charts.triangles(), chart = charts.chart_of_triangle(),
                                     origin = charts.origin_triangles();
    const std::vector<uvflat::PgpChart> descriptors = charts.charts();
    std::printf("%s: %zu charts over %zu triangles\n", context.c_str(), charts_info.chart_count,
                charts_info.triangle_count);
    expect(charts_info.chart_count > 0 && descriptors.size() == charts_info.chart_count, "chart count");
    expect(cut_positions.size() == 3 * charts_info.vertex_count &&
               std::equal(a.positions.begin(), a.positions.end(), cut_positions.begin()),
           "the cut triangulation does not start with the input's vertices");
    expect(cut_triangles.size() == 3 * charts_info.triangle_count &&
               std::all_of(cut_triangles.begin(), cut_triangles.end(),
                           [&](std::uint32_t v) { return v < charts_info.vertex_count; }),
           "cut triangles");
    expect(corner_uv.size() == 6 * charts_info.triangle_count && all_finite(corner_uv), "chart (u, v)");
    expect(chart.size() == charts_info.triangle_count &&
               std::all_of(chart.begin(), chart.end(), [&](std::uint32_t c) { return c < charts_info.chart_count; }),
           "a triangle outside every chart");
    const std::set<std::uint32_t> covered(origin.begin(), origin.end());
    expect(origin.size() == charts_info.triangle_count && covered.size() == a.triangle_count() &&
               *covered.rbegin() < a.triangle_count(),
           "the charts do not cover every input triangle");
    std::size_t kinds[5] = {0, 0, 0, 0, 0};
    for (const uvflat::PgpChart &c : descriptors) {
        if (std::uint32_t(c.kind) < 5) ++kinds[std::uint32_t(c.kind)];
    }
    for (int k = 0; k < 5; ++k) expect(kinds[k] == charts_info.kind_counts[k], "chart kinds differ from info");

    expect_error(UVF_INVALID_ARGUMENT, "quad mesh of density 0.5", [&] { pgp.quad_mesh(0.5); });
    expect_error(UVF_INVALID_ARGUMENT, "quad mesh of density 0", [&] { pgp.quad_mesh(0); });
    expect_error(UVF_INVALID_ARGUMENT, "charts of density 1.5", [&] { pgp.charts(1.5); });

    // Moving: the new owner works, the old one throws, assignment releases the old handle.
    uvflat::Pgp moved = std::move(pgp);
    expect(moved.info().singular_point_count == info.singular_point_count, "the moved-to PGP lost its result");
    expect(pgp.corner_theta_phi().empty(), "the moved-from PGP kept its corners");
    expect_error(UVF_INVALID_ARGUMENT, "info of a moved-from PGP", [&] { pgp.info(); });
    expect_error(UVF_INVALID_ARGUMENT, "quad mesh of a moved-from PGP", [&] { pgp.quad_mesh(1); });
    expect_error(UVF_INVALID_ARGUMENT, "singular points of a moved-from PGP", [&] { pgp.singular_points(); });
    uvflat::QuadMesh quads = moved.quad_mesh(1);
    const std::size_t coarse = quads.info().face_count;
    quads = moved.quad_mesh(2);
    expect(quads.info().face_count > coarse, "a move-assigned quad mesh is not the new one");
    uvflat::QuadMesh other = std::move(quads);
    expect_error(UVF_INVALID_ARGUMENT, "info of a moved-from quad mesh", [&] { quads.info(); });
    uvflat::ChartLayout layout2 = moved.chart_layout();
    uvflat::ChartLayout layout3 = std::move(layout2);
    expect_error(UVF_INVALID_ARGUMENT, "a moved-from chart layout", [&] { layout2.chart_corners(); });
    expect(layout3.info().chart_count == layout_info.chart_count, "the moved-to chart layout");
    uvflat::PgpCharts charts2 = moved.charts(1);
    uvflat::PgpCharts charts3 = std::move(charts2);
    expect_error(UVF_INVALID_ARGUMENT, "a moved-from chart parameterization", [&] { charts2.charts(); });
    expect(charts3.info().chart_count == charts_info.chart_count, "the moved-to chart parameterization");
}

/// PGP's invalid arguments, cancellation, and the wrapper's options against the library's.
void check_pgp_arguments(const Arrays &a) {
    context = "PGP arguments";
    expect_error(UVF_INVALID_ARGUMENT, "positions not a multiple of 3", [&] {
        std::vector<double> bad = a.positions;
        bad.pop_back();
        uvflat::Pgp(bad, a.triangles);
    });
    uvflat::PgpOptions options;
    options.field.assign(7, 1.0);
    expect_error(UVF_INVALID_ARGUMENT, "a field of the wrong size", [&] { uvflat::Pgp(a.positions, a.triangles, options); });
    options.field.clear();
    options.smoothing = static_cast<uvflat::Smoothing>(3);
    expect_error(UVF_INVALID_ARGUMENT, "an unknown smoothing", [&] { uvflat::Pgp(a.positions, a.triangles, options); });
    options.smoothing = uvflat::Smoothing::half_pi;
    options.curvature.rings = 0;
    expect_error(UVF_INVALID_ARGUMENT, "zero curvature rings", [&] { uvflat::Pgp(a.positions, a.triangles, options); });
    options.curvature.rings = 2;
    expect_error(UVF_INVALID_MESH, "an empty mesh", [] { uvflat::Pgp({}, {}); });
    options.progress = [](double) { return false; };
    expect_error(UVF_CANCELLED, "a cancelling callback", [&] { uvflat::Pgp(a.positions, a.triangles, options); });

    UvfPgpOptions c;
    uvf_pgp_options_default(&c);
    const UvfPgpOptions w = uvflat::detail::pgp_options(uvflat::PgpOptions{}, a.vertex_count());
    expect(w.struct_size == c.struct_size && w.omega == c.omega && w.field == c.field && w.smoothing == c.smoothing &&
               w.curl_correction == c.curl_correction && w.rho == c.rho && w.smoothing_epsilon == c.smoothing_epsilon &&
               w.epsilon == c.epsilon && w.gradient_tolerance == c.gradient_tolerance &&
               w.max_newton_iterations == c.max_newton_iterations &&
               w.curvature_neighbourhood == c.curvature_neighbourhood && w.curvature_rings == c.curvature_rings &&
               w.curvature_radius == c.curvature_radius && w.untangle == c.untangle &&
               w.feature_periods == c.feature_periods && w.pair_periods == c.pair_periods &&
               w.dislocation_periods == c.dislocation_periods && w.relax == c.relax && w.progress == c.progress,
           "uvflat::PgpOptions{} differs from uvf_pgp_options_default");
}

/// The wrapper's other option defaults equal the library's.
void check_option_defaults() {
    context = "option defaults";
    UvfCurvatureOptions cc;
    uvf_curvature_options_default(&cc);
    const UvfCurvatureOptions cw = uvflat::detail::curvature_options({});
    expect(cw.neighbourhood == cc.neighbourhood && cw.rings == cc.rings && cw.radius == cc.radius, "CurvatureOptions");
    UvfAtlasOptions ac;
    uvf_atlas_options_default(&ac);
    const UvfAtlasOptions aw = uvflat::detail::atlas_options({});
    expect(aw.max_stretch == ac.max_stretch && aw.margin == ac.margin && aw.method == ac.method &&
               aw.iterations == ac.iterations && aw.rotate == ac.rotate && aw.merge == ac.merge &&
               aw.polish_iterations == ac.polish_iterations,
           "AtlasOptions");
    UvfQuadCoverOptions qc;
    uvf_quadcover_options_default(&qc);
    const UvfQuadCoverOptions qw = uvflat::detail::quadcover_options({}, 0);
    expect(qw.grid_spacing == qc.grid_spacing && qw.alignment == qc.alignment && qw.round == qc.round &&
               qw.cones_on_grid == qc.cones_on_grid && qw.pair_cells == qc.pair_cells && qw.untangle == qc.untangle,
           "QuadCoverOptions");
    UvfIntrinsicOptimalOptions ic;
    uvf_intrinsic_optimal_options_default(&ic);
    const UvfIntrinsicOptimalOptions iw = uvflat::detail::intrinsic_optimal_options({});
    expect(iw.energy == ic.energy && iw.boundary == ic.boundary && iw.distribution == ic.distribution &&
               iw.lambda_min == ic.lambda_min && iw.lambda_max == ic.lambda_max && iw.given_count == ic.given_count,
           "IntrinsicOptimalOptions");
    UvfBoundaryOptimizationOptions bc;
    uvf_boundary_optimization_options_default(&bc);
    const UvfBoundaryOptimizationOptions bw = uvflat::detail::boundary_optimization_options({});
    expect(bw.energy == bc.energy && bw.iterations == bc.iterations && bw.lambda == bc.lambda && bw.mu == bc.mu &&
               bw.tolerance == bc.tolerance && bw.boundary == bc.boundary && bw.distribution == bc.distribution &&
               bw.given_count == bc.given_count,
           "BoundaryOptimizationOptions");
    UvfFixedBoundaryOptions fc;
    uvf_fixed_boundary_options_default(&fc);
    const UvfFixedBoundaryOptions fw = uvflat::detail::fixed_boundary_options({});
    expect(fw.weights == fc.weights && fw.boundary == fc.boundary && fw.distribution == fc.distribution &&
               fw.lambda == fc.lambda && fw.mu == fc.mu && fw.given_count == fc.given_count,
           "FixedBoundaryOptions");
}

/// QuadCover's quad mesh of a closed mesh: ≥ 90% quads, sizes consistent; bad densities throw.
void check_quadcover_quad_mesh(const std::string &name, const Arrays &a) {
    context = name + " QuadCover quad mesh";
    UvfQuadCoverReport report{};
    const uvflat::QuadMesh quads = uvflat::quadcover_quad_mesh(a.positions, a.triangles, 1, {}, &report);
    expect(report.grid_spacing > 0, "the report was not filled");
    check_polygons(quads, 0.9, "density 1");
    expect_error(UVF_INVALID_ARGUMENT, "density 0.5", [&] { uvflat::quadcover_quad_mesh(a.positions, a.triangles, 0.5); });
    uvflat::QuadCoverOptions options;
    options.field.assign(5, 0.0);
    expect_error(UVF_INVALID_ARGUMENT, "a field of the wrong size",
                 [&] { uvflat::quadcover_quad_mesh(a.positions, a.triangles, 1, options); });
}

/// Principal curvatures of the torus of radii R = 1 (axis y) and r = 0.25: kmin ≤ kmax,
/// unit directions orthogonal to each other and to the exact normal, kmax close to 1/r and
/// kmin's direction along the parallels; the discrete Gauss–Bonnet integral is near 0.
void check_curvature_torus(const Arrays &a) {
    context = "torus curvature";
    const uvflat::Curvatures c = uvflat::curvature(a.positions, a.triangles);
    const std::size_t nv = a.vertex_count();
    expect(c.kmin.size() == nv && c.kmax.size() == nv && c.kmin_direction.size() == 3 * nv &&
               c.kmax_direction.size() == 3 * nv,
           "output sizes");
    double worst_order = 0, worst_unit = 0, worst_tangent = 0, worst_orthogonal = 0, kmax_error = 0, along = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        const double *p = &a.positions[3 * v], *d1 = &c.kmin_direction[3 * v], *d2 = &c.kmax_direction[3 * v];
        const double rho = std::hypot(p[0], p[2]);
        const double normal[3] = {(p[0] - p[0] / rho) / 0.25, p[1] / 0.25, (p[2] - p[2] / rho) / 0.25};
        const double parallel[3] = {-p[2] / rho, 0, p[0] / rho};
        worst_order = std::max(worst_order, c.kmin[v] - c.kmax[v]);
        worst_unit = std::max({worst_unit, std::abs(dot3(d1, d1) - 1), std::abs(dot3(d2, d2) - 1)});
        worst_tangent = std::max({worst_tangent, std::abs(dot3(d1, normal)), std::abs(dot3(d2, normal))});
        worst_orthogonal = std::max(worst_orthogonal, std::abs(dot3(d1, d2)));
        kmax_error += std::abs(c.kmax[v] - 4.0) / 4.0 / double(nv);
        along += std::abs(dot3(d1, parallel)) / double(nv);
    }
    // ∫ K dA with a third of each triangle's area at each corner.
    double gauss = 0, gauss_abs = 0;
    for (std::size_t t = 0; t < a.triangle_count(); ++t) {
        const std::uint32_t *tri = &a.triangles[3 * t];
        double e1[3], e2[3];
        for (int d = 0; d < 3; ++d) {
            e1[d] = a.positions[3 * tri[1] + d] - a.positions[3 * tri[0] + d];
            e2[d] = a.positions[3 * tri[2] + d] - a.positions[3 * tri[0] + d];
        }
        const double cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                 e1[0] * e2[1] - e1[1] * e2[0]};
        const double third = std::sqrt(dot3(cross, cross)) / 6;
        for (int k = 0; k < 3; ++k) {
            gauss += c.kmin[tri[k]] * c.kmax[tri[k]] * third;
            gauss_abs += std::abs(c.kmin[tri[k]] * c.kmax[tri[k]]) * third;
        }
    }
    std::printf("%s: kmin - kmax <= %.1e, unit within %.1e, normal component <= %.3f, kmax off 1/r by %.2f%%, "
                "kmin along the parallels %.3f, integral of K %.3f (of |K| %.3f)\n",
                context.c_str(), worst_order, worst_unit, worst_tangent, 100 * kmax_error, along, gauss, gauss_abs);
    expect(worst_order <= 0, "kmin > kmax");
    expect(worst_unit < 1e-9, "directions are not unit vectors");
    expect(worst_orthogonal < 1e-9, "the two directions are not orthogonal");
    expect(worst_tangent < 0.05, "directions are not tangent");
    expect(kmax_error < 0.05, "kmax is not 1/r");
    expect(along > 0.95, "kmin's direction does not follow the parallels");
    expect(std::abs(gauss) < 0.05 * gauss_abs, "the integral of the Gauss curvature of a torus is not 0");

    uvflat::CurvatureOptions bad;
    bad.rings = 0;
    expect_error(UVF_INVALID_ARGUMENT, "zero rings", [&] { uvflat::curvature(a.positions, a.triangles, bad); });
    bad.neighbourhood = uvflat::CurvatureNeighbourhood::radius;
    bad.radius = -1;
    expect_error(UVF_INVALID_ARGUMENT, "a negative radius", [&] { uvflat::curvature(a.positions, a.triangles, bad); });
    uvflat::CurvatureOptions radius;
    radius.neighbourhood = uvflat::CurvatureNeighbourhood::radius;
    radius.radius = 0.1;
    const uvflat::Curvatures r = uvflat::curvature(a.positions, a.triangles, radius);
    double error = 0;
    for (double k : r.kmax) error += std::abs(k - 4.0) / 4.0 / double(nv);
    expect(error < 0.05, "kmax is not 1/r with a radius neighbourhood");
}

/// The atlas of a mesh: every triangle in one of the charts and every chart used, UVs finite
/// in [0, 1], corners mapping back to the input's vertices, per-corner UVs agreeing with the
/// indexed ones, no flipped triangle, chart stretch within the bound; bad options throw.
void check_atlas(const std::string &name, const Arrays &a) {
    context = name + " atlas";
    const uvflat::AtlasOptions options;
    uvflat::Atlas atlas(a.positions, a.triangles, options);
    const UvfAtlasInfo info = atlas.info();
    const std::vector<double> uv = atlas.uv(), corner_uv = atlas.corner_uv();
    const std::vector<std::uint32_t> uv_triangles = atlas.uv_triangles(), chart = atlas.chart_of_triangle(),
                                     original = atlas.original_vertices();
    std::printf("%s: %zu charts, %zu uv vertices, utilization %.3f, stretch %.4f (chart max %.4f)\n", context.c_str(),
                info.chart_count, info.vertex_count, info.utilization, info.stretch_l2, info.max_chart_stretch);
    expect(info.chart_count > 0 && info.triangle_count == a.triangle_count(), "counts");
    expect(chart.size() == a.triangle_count(), "chart ids");
    std::vector<bool> used(info.chart_count, false);
    for (std::uint32_t c : chart) {
        if (c < info.chart_count) {
            used[c] = true;
        } else {
            expect(false, "a triangle is in no chart");
            break;
        }
    }
    expect(std::all_of(used.begin(), used.end(), [](bool u) { return u; }), "an empty chart");
    expect(uv.size() == 2 * info.vertex_count && all_finite(uv), "UVs not finite");
    expect(std::all_of(uv.begin(), uv.end(), [](double x) { return x >= -1e-12 && x <= 1 + 1e-12; }),
           "UVs outside the unit square");
    expect(original.size() == info.vertex_count && uv_triangles.size() == a.triangles.size(), "sizes");
    bool corners_ok = corner_uv.size() == 6 * a.triangle_count();
    for (std::size_t k = 0; corners_ok && k < uv_triangles.size(); ++k) {
        const std::uint32_t w = uv_triangles[k];
        corners_ok = w < info.vertex_count && original[w] == a.triangles[k] && corner_uv[2 * k] == uv[2 * w] &&
                     corner_uv[2 * k + 1] == uv[2 * w + 1];
    }
    expect(corners_ok, "corners do not map back to the input's vertices and their UVs");
    const UvfMetrics m = uvflat::metrics(a.positions, a.triangles, uv, uv_triangles);
    expect(m.flipped == 0, "flipped triangles");
    expect(info.max_chart_stretch <= options.max_stretch + 1e-9, "a chart exceeds the stretch bound");

    uvflat::AtlasOptions bad;
    bad.margin = 0.6;
    expect_error(UVF_INVALID_ARGUMENT, "margin 0.6", [&] { uvflat::Atlas(a.positions, a.triangles, bad); });
    bad.margin = 0.005;
    bad.method = static_cast<uvflat::AtlasChartMethod>(9);
    expect_error(UVF_INVALID_ARGUMENT, "an unknown chart method", [&] { uvflat::Atlas(a.positions, a.triangles, bad); });
    uvflat::Atlas moved = std::move(atlas);
    expect(moved.info().chart_count == info.chart_count, "the moved-to atlas");
    expect_error(UVF_INVALID_ARGUMENT, "a moved-from atlas", [&] { atlas.uv(); });
}

/// The default unwrap through the C++ owner: the report's verified counts, corners mapping back,
/// flips measured again by metrics, seams as sorted vertex pairs; one island without a bound.
void check_unwrap(const std::string &name, const Arrays &a) {
    context = name + " unwrap";
    uvflat::Unwrap result(a.positions, a.triangles);
    const UvfUnwrapReport r = result.report();
    std::printf("%s: %zu islands (%zu repaired), %zu seam edges, max island L2 %.4f\n", context.c_str(), r.islands,
                r.repaired_islands, r.seam_edges, r.max_island_stretch);
    expect(r.flipped == 0 && r.overlaps == 0 && r.max_island_stretch <= 1.5, "verified counts");
    const std::vector<double> uv = result.uv();
    const std::vector<std::uint32_t> uv_triangles = result.uv_triangles(), original = result.original_vertices(),
                                     seams = result.seams(), islands = result.island_of_triangle();
    bool corners_ok = uv_triangles.size() == a.triangles.size();
    for (std::size_t k = 0; corners_ok && k < uv_triangles.size(); ++k) corners_ok = original[uv_triangles[k]] == a.triangles[k];
    expect(corners_ok, "corners do not map back to the input's vertices");
    expect(std::all_of(islands.begin(), islands.end(), [&](std::uint32_t i) { return i < r.islands; }), "island ids");
    expect(uvflat::metrics(a.positions, a.triangles, uv, uv_triangles).flipped == 0, "metrics finds flips");
    bool seams_ok = seams.size() == 2 * r.seam_edges;
    for (std::size_t k = 0; seams_ok && k < r.seam_edges; ++k) seams_ok = seams[2 * k] < seams[2 * k + 1];
    expect(seams_ok, "seams are not sorted vertex pairs");
    uvflat::UnwrapOptions whole;
    whole.max_stretch = std::numeric_limits<double>::infinity();
    expect(uvflat::Unwrap(a.positions, a.triangles, whole).report().islands == 1, "one island without a bound");
    uvflat::UnwrapOptions bad;
    bad.max_stretch = 0.5;
    expect_error(UVF_INVALID_ARGUMENT, "max_stretch 0.5", [&] { uvflat::Unwrap(a.positions, a.triangles, bad); });
}

/// A mesh handle: the methods on it give the flat calls' results, bit for bit; a mesh of
/// OpenMesh's float positions read in place at their stride gives the same handle.
void check_mesh_handle(const Arrays &a) {
    context = "mesh handle";
    const uvflat::Mesh mesh(a.positions, a.triangles);
    expect(mesh.vertex_count() == a.vertex_count() && mesh.triangles() == a.triangles, "the handle keeps the triangles");
    expect(uvflat::natural_conformal_map(mesh) == uvflat::natural_conformal_map(a.positions, a.triangles),
           "natural conformal map: handle = flat");
    expect(uvflat::fixed_boundary_map(mesh) == uvflat::fixed_boundary_map(a.positions, a.triangles),
           "fixed boundary map: handle = flat");
    const uvflat::Unwrap unwrap(mesh);
    expect(unwrap.report().flipped == 0 && unwrap.report().overlaps == 0, "unwrap of the handle is valid");
    std::vector<float> floats(a.positions.begin(), a.positions.end());
    UvfMeshDesc desc;
    uvf_mesh_desc_default(&desc);
    desc.positions = floats.data();
    desc.position_type = UVF_SCALAR_FLOAT;
    desc.vertex_count = a.vertex_count();
    desc.indices = a.triangles.data();
    desc.face_count = a.triangles.size() / 3;
    const uvflat::Mesh float_mesh(desc);
    expect(float_mesh.info().triangles == a.triangles.size() / 3, "a float mesh has the triangles");
    // Views: the same call on raw pointers and counts.
    expect(uvflat::natural_conformal_map({a.positions.data(), a.positions.size()},
                                         {a.triangles.data(), a.triangles.size()}) ==
               uvflat::natural_conformal_map(a.positions, a.triangles),
           "pointer + count views give the vector call's result");
    UvfAbfReport flat_report{}, handle_report{};
    uvflat::AbfOptions abf_options;
    abf_options.max_iterations = 3;
    abf_options.tolerance = 1e-30;
    expect(uvflat::abf(mesh, abf_options, &handle_report) == uvflat::abf(a.positions, a.triangles, abf_options, &flat_report),
           "ABF++: handle = flat");
    expect(flat_report.iterations == 3 && flat_report.converged == 0, "ABF++ max_iterations and tolerance are passed");
    uvflat::NonlinearOptions slim;
    slim.iterations = 5;
    slim.theta = 4.0;
    expect(uvflat::nonlinear_map(mesh, slim) == uvflat::nonlinear_map(a.positions, a.triangles, slim), "SLIM: handle = flat");
    const std::vector<double> uv = uvflat::natural_conformal_map(mesh);
    expect(uvflat::metrics(mesh, uv).stretch_l2 == uvflat::metrics(a.positions, a.triangles, uv).stretch_l2,
           "metrics: handle = flat");
    const uvflat::Atlas atlas(mesh);
    expect(atlas.info().chart_count >= 1, "atlas of the handle");
    const std::vector<double> corner_uv = unwrap.corner_uv(), unwrap_uv = unwrap.uv();
    const std::vector<std::uint32_t> unwrap_triangles = unwrap.uv_triangles();
    bool corners_agree = corner_uv.size() == 2 * unwrap_triangles.size();
    for (std::size_t k = 0; corners_agree && k < unwrap_triangles.size(); ++k) {
        corners_agree = corner_uv[2 * k] == unwrap_uv[2 * unwrap_triangles[k]] &&
                        corner_uv[2 * k + 1] == unwrap_uv[2 * unwrap_triangles[k] + 1];
    }
    expect(corners_agree, "the unwrap's corner UVs are its UVs at its corners");
    const UvfLayoutCheck layout = uvflat::check_layout(unwrap_uv, unwrap_triangles);
    expect(layout.flipped == 0 && layout.overlaps == 0 && layout.islands == unwrap.report().islands,
           "the exact check of the unwrap's layout");
    expect(uvflat::spectral_conformal_map(mesh) == uvflat::spectral_conformal_map(a.positions, a.triangles),
           "spectral: handle = flat");
    expect(uvflat::circle_pattern_map(mesh) == uvflat::circle_pattern_map(a.positions, a.triangles),
           "circle patterns: handle = flat");
    uvflat::SpectralOptions spectral;
    spectral.iterations = 1;
    UvfSpectralReport spectral_report{};
    uvflat::spectral_conformal_map(a.positions, a.triangles, spectral, &spectral_report);
    expect(spectral_report.iterations == 1, "spectral iterations are passed");
    expect_error(UVF_INVALID_ARGUMENT, "a description without arrays", [] {
        UvfMeshDesc empty;
        uvf_mesh_desc_default(&empty);
        empty.vertex_count = 3;
        empty.face_count = 1;
        uvflat::Mesh bad(empty);
    });
}

/// Triangle components of two disjoint copies of a mesh, the ABI version, bad input.
void check_components(const Arrays &a) {
    context = "triangle components";
    expect(uvflat::abi_version() == UVF_ABI_VERSION, "the library's ABI version differs from the header's");
    expect(uvflat::version_number() == UVF_VERSION_NUMBER, "the library's version differs from the header's");
    expect(uvflat::status_string(UVF_INVALID_MESH) == "invalid mesh", "status string");
    expect(uvflat::thread_count() >= 1, "at least one worker thread");
    expect_error(UVF_INVALID_ARGUMENT, "set_thread_count after the workers exist", [] { uvflat::set_thread_count(1); });
    Arrays two = a;
    for (std::size_t k = 0; k < a.positions.size(); ++k) two.positions.push_back(a.positions[k] + (k % 3 == 0 ? 10 : 0));
    for (std::uint32_t v : a.triangles) two.triangles.push_back(v + std::uint32_t(a.vertex_count()));
    const std::vector<std::uint32_t> c = uvflat::triangle_components(two.positions, two.triangles);
    const std::size_t nt = a.triangle_count();
    expect(c.size() == 2 * nt, "one component per triangle");
    expect(std::all_of(c.begin(), c.begin() + nt, [&](std::uint32_t x) { return x == c[0]; }) &&
               std::all_of(c.begin() + nt, c.end(), [&](std::uint32_t x) { return x == c[nt]; }) && c[0] != c[nt] &&
               std::max(c[0], c[nt]) == 1,
           "the two copies are not components 0 and 1");
    std::vector<std::uint32_t> out_of_range = a.triangles;
    out_of_range[4] = std::uint32_t(a.vertex_count());
    expect_error(UVF_INVALID_MESH, "an index out of range",
                 [&] { uvflat::triangle_components(a.positions, out_of_range); });
    // Empty vectors reach the library as NULL with count 0: an empty mesh, not a crash.
    expect_error(UVF_INVALID_MESH, "triangle components of an empty mesh", [] { uvflat::triangle_components({}, {}); });
    expect_error(UVF_INVALID_MESH, "curvature of an empty mesh", [] { uvflat::curvature({}, {}); });
    expect_error(UVF_INVALID_MESH, "atlas of an empty mesh", [] { uvflat::Atlas({}, {}); });
    expect_error(UVF_INVALID_MESH, "QuadCover quad mesh of an empty mesh", [] { uvflat::quadcover_quad_mesh({}, {}); });
    std::vector<std::uint32_t> short_triangles = a.triangles;
    short_triangles.pop_back();
    expect_error(UVF_INVALID_ARGUMENT, "triangles not a multiple of 3",
                 [&] { uvflat::triangle_components(a.positions, short_triangles); });
}

/// Polygon islands of two copies of a mesh (OpenMesh's triangles as polygons of 3): two islands,
/// one island vertex per mesh vertex; one seam-free copy packed with pack_islands (the
/// mean value map of the disk, twice, on top of each other) moves the copies apart: the two
/// islands' boxes stay inside the unit square and each copy keeps its shape.
void check_islands_and_packing(const Arrays &a) {
    context = "polygon islands and packing";
    std::vector<std::uint32_t> corners = a.triangles;
    for (std::uint32_t v : a.triangles) corners.push_back(v + std::uint32_t(a.vertex_count()));
    const uvflat::PolygonIslands islands = uvflat::polygon_islands(corners, 2 * a.vertex_count());
    expect(islands.info.islands == 2 && islands.info.island_vertices == 2 * a.vertex_count(), "two copies, two islands");
    expect(islands.face_island.front() == 0 && islands.face_island.back() == 1, "islands in order of their first face");
    std::vector<std::uint8_t> none(a.triangle_count() * 2, 0);
    none[0] = 1;
    const uvflat::PolygonIslands selected = uvflat::polygon_islands(corners, 2 * a.vertex_count(), {}, none);
    expect(selected.info.islands == 1 && selected.face_island[1] == UVF_NOT_IN_AN_ISLAND, "one selected face");
    const std::vector<double> uv = uvflat::fixed_boundary_map(a.positions, a.triangles);
    std::vector<double> both = uv;
    both.insert(both.end(), uv.begin(), uv.end());
    const uvflat::PackedIslands packed = uvflat::pack_islands(both, corners, {}, 0.02);
    expect(packed.report.islands == 2 && packed.report.utilization > 0.2, "two islands packed");
    const std::size_t n = a.vertex_count();
    double lo[2][2] = {{1e300, 1e300}, {1e300, 1e300}}, hi[2][2] = {{-1e300, -1e300}, {-1e300, -1e300}};
    for (std::size_t v = 0; v < 2 * n; ++v)
        for (int d = 0; d < 2; ++d) {
            lo[v / n][d] = std::min(lo[v / n][d], packed.uv[2 * v + d]);
            hi[v / n][d] = std::max(hi[v / n][d], packed.uv[2 * v + d]);
        }
    for (int k = 0; k < 2; ++k)
        expect(lo[k][0] >= 0 && lo[k][1] >= 0 && hi[k][0] <= 1 && hi[k][1] <= 1, "packed inside the unit square");
    // Same shape: the distance between vertices 0 and 1 over that between 0 and 2, in both copies.
    auto ratio = [&](std::size_t off) {
        auto d = [&](std::size_t x, std::size_t y) {
            return std::hypot(packed.uv[2 * (off + x)] - packed.uv[2 * (off + y)], packed.uv[2 * (off + x) + 1] - packed.uv[2 * (off + y) + 1]);
        };
        return d(0, 1) / d(0, 2);
    };
    expect(std::abs(ratio(0) - ratio(n)) < 1e-9, "both copies keep their shape");
    expect_error(UVF_INVALID_ARGUMENT, "a vertex past vertex_count", [&] { uvflat::polygon_islands(corners, a.vertex_count()); });
    expect_error(UVF_INVALID_ARGUMENT, "margin 0.5", [&] { uvflat::pack_islands(both, corners, {}, 0.5); });
    const std::vector<double> one_area{1.0};
    expect_error(UVF_INVALID_ARGUMENT, "one surface area for many triangles", [&] { uvflat::pack_islands(both, corners, one_area); });
    const std::vector<std::uint8_t> one_flag{1};
    expect_error(UVF_INVALID_ARGUMENT, "one seam flag for many corners",
                 [&] { uvflat::polygon_islands(corners, 2 * a.vertex_count(), {}, {}, one_flag); });
}

double max_difference(const std::vector<double> &x, const std::vector<double> &y) {
    if (x.size() != y.size()) return INFINITY;
    double worst = 0;
    for (std::size_t k = 0; k < x.size(); ++k) worst = std::max(worst, std::abs(x[k] - y[k]));
    return worst;
}

/// The intrinsic tools on a disk: pins and point constraints reproduce the 2-pin natural
/// conformal map and meet their targets; the near-optimal λ is no worse than DCP or DAP; the
/// boundary optimization never raises the energy and reports its history; the Green basis
/// reproduces the boundary editor's solve; the polygon boundary curvature turns by 2π/4 at
/// four corners.
void check_intrinsic_tools(const Arrays &a) {
    context = "intrinsic tools";
    const std::vector<std::vector<std::uint32_t>> loops = uvflat::boundary_loops(a.positions, a.triangles);
    const std::vector<std::uint32_t> &loop = loops.at(0);
    const std::uint32_t b0 = loop[0], b1 = loop[loop.size() / 2];
    const std::vector<uvflat::Pin> pins = {{b0, 0, 0}, {b1, 1, 0}};
    uvflat::NaturalConformalOptions natural;
    natural.pins = pins;
    const std::vector<double> reference = uvflat::natural_conformal_map(a.positions, a.triangles, natural);
    const std::vector<double> pinned = uvflat::pinned_natural_conformal_map(a.positions, a.triangles, pins);
    expect(max_difference(pinned, reference) < 1e-8, "two pins differ from the natural conformal map");
    const std::vector<uvflat::Pin> three = {{b0, 0, 0}, {b1, 1, 0}, {loop[loop.size() / 4], 0.5, 0.5}};
    const std::vector<double> pinned3 = uvflat::pinned_natural_conformal_map(a.positions, a.triangles, three);
    for (const uvflat::Pin &p : three) {
        expect(std::hypot(pinned3[2 * p.vertex] - p.u, pinned3[2 * p.vertex + 1] - p.v) < 1e-9, "a pin moved");
    }
    expect_error(UVF_INVALID_ARGUMENT, "one pin",
                 [&] { uvflat::pinned_natural_conformal_map(a.positions, a.triangles, {pins[0]}); });

    // The corners of triangles holding b0 and b1 as vertex constraints.
    auto vertex_constraint = [&](std::uint32_t v, double u, double w) {
        for (std::size_t k = 0; k < a.triangles.size(); ++k) {
            if (a.triangles[k] == v) {
                uvflat::PointConstraint c{std::uint32_t(k / 3), {0, 0, 0}, {u, w}};
                c.barycentric[k % 3] = 1;
                return c;
            }
        }
        return uvflat::PointConstraint{0, {1, 0, 0}, {u, w}};
    };
    const std::vector<uvflat::PointConstraint> two = {vertex_constraint(b0, 0, 0), vertex_constraint(b1, 1, 0)};
    const std::vector<double> constrained = uvflat::constrained_natural_conformal_map(a.positions, a.triangles, two);
    expect(max_difference(constrained, reference) < 1e-8, "two vertex constraints differ from the natural conformal map");

    // An interior point of the fixed-boundary map moved to a target.
    const std::vector<double> fixed = uvflat::fixed_boundary_map(a.positions, a.triangles);
    const std::uint32_t *t = &a.triangles[3 * (a.triangle_count() / 2)];
    double centre[2] = {0, 0};
    for (int k = 0; k < 3; ++k) {
        centre[0] += fixed[2 * t[k]] / 3;
        centre[1] += fixed[2 * t[k] + 1] / 3;
    }
    const uvflat::PointConstraint moved{std::uint32_t(a.triangle_count() / 2), {1, 1, 1}, {centre[0] + 0.01, centre[1]}};
    const std::vector<double> dragged = uvflat::constrained_fixed_boundary_map(a.positions, a.triangles, {moved});
    double at[2] = {0, 0};
    for (int k = 0; k < 3; ++k) {
        at[0] += dragged[2 * t[k]] / 3;
        at[1] += dragged[2 * t[k] + 1] / 3;
    }
    expect(std::hypot(at[0] - moved.uv[0], at[1] - moved.uv[1]) < 1e-9, "the constrained point missed its target");
    expect(max_difference(uvflat::constrained_fixed_boundary_map(a.positions, a.triangles, {}), fixed) < 1e-12,
           "no constraint differs from the fixed-boundary map");

    UvfIntrinsicOptimalReport optimal{};
    const std::vector<double> near = uvflat::intrinsic_optimal_map(a.positions, a.triangles, {}, &optimal);
    std::printf("%s: near-optimal lambda %.3f, energy %.4g (DCP %.4g, DAP %.4g)\n", context.c_str(), optimal.lambda,
                optimal.energy, optimal.energy_conformal, optimal.energy_authalic);
    expect(all_finite(near) && optimal.energy <= std::min(optimal.energy_conformal, optimal.energy_authalic) + 1e-12,
           "the near-optimal map is worse than DCP or DAP");
    uvflat::IntrinsicOptimalOptions empty_range;
    empty_range.lambda_min = 1;
    empty_range.lambda_max = 0;
    expect_error(UVF_INVALID_ARGUMENT, "an empty lambda range",
                 [&] { uvflat::intrinsic_optimal_map(a.positions, a.triangles, empty_range); });

    uvflat::BoundaryOptimizationOptions descent;
    descent.iterations = 5;
    UvfBoundaryOptimizationReport report{};
    std::vector<double> history;
    const std::vector<double> optimized =
        uvflat::boundary_optimized_map(a.positions, a.triangles, descent, &report, &history);
    std::printf("%s: boundary optimization %u iterations, energy %.4g -> %.4g\n", context.c_str(), report.iterations,
                report.initial_energy, report.final_energy);
    expect(all_finite(optimized) && report.final_energy <= report.initial_energy, "the energy went up");
    expect(history.size() == report.history_length && !history.empty() && history.front() == report.initial_energy &&
               history.back() == report.final_energy,
           "the history does not match the report");
    expect(std::is_sorted(history.rbegin(), history.rend()), "the energy history is not non-increasing");

    const uvflat::BoundaryEditor editor(a.positions, a.triangles);
    const std::vector<std::uint32_t> boundary = editor.boundary();
    std::vector<double> boundary_uv;
    for (std::size_t i = 0; i < boundary.size(); ++i) {
        const double angle = 2 * M_PI * double(i) / double(boundary.size());
        boundary_uv.insert(boundary_uv.end(), {std::cos(angle), std::sin(angle)});
    }
    const std::vector<double> solved = editor.solve(boundary_uv);
    const std::vector<double> basis = editor.basis();
    const std::size_t n = a.vertex_count();
    expect(basis.size() == boundary.size() * n, "basis size");
    double worst = 0;
    for (std::uint32_t v : a.triangles) {
        double u = 0, w = 0;
        for (std::size_t i = 0; i < boundary.size(); ++i) {
            u += basis[i * n + v] * boundary_uv[2 * i];
            w += basis[i * n + v] * boundary_uv[2 * i + 1];
        }
        worst = std::max(worst, std::hypot(u - solved[2 * v], w - solved[2 * v + 1]));
    }
    expect(worst < 1e-9, "the Green basis does not reproduce the solve");
    expect_error(UVF_INVALID_ARGUMENT, "a basis over its memory budget", [&] { editor.basis(64); });

    const std::vector<std::uint32_t> corners = {loop[0], loop[loop.size() / 4], loop[loop.size() / 2],
                                                loop[3 * loop.size() / 4]};
    const std::vector<double> curvature = uvflat::circle_pattern_polygon_curvature(a.positions, a.triangles, corners);
    const std::set<std::uint32_t> on_loop(loop.begin(), loop.end()), corner_set(corners.begin(), corners.end());
    bool curvature_ok = curvature.size() == n;
    for (std::uint32_t v = 0; curvature_ok && v < n; ++v) {
        const double expected = corner_set.count(v) ? M_PI / 2 : on_loop.count(v) ? 0.0 : NAN;
        curvature_ok = std::isnan(expected) ? std::isnan(curvature[v]) : std::abs(curvature[v] - expected) < 1e-12;
    }
    expect(curvature_ok, "the polygon boundary curvature is not pi/2 at the corners, 0 along the loop, NaN inside");
    expect_error(UVF_INVALID_ARGUMENT, "a polygon of two corners", [&] {
        uvflat::circle_pattern_polygon_curvature(a.positions, a.triangles, {corners[0], corners[1]});
    });
}

} // namespace

int main(int argc, char **argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s MESH_DIR\n", argv[0]);
        return 2;
    }
    OpenMesh::IO::IOManager(); // make sure the OBJ reader is registered
    const std::string dir = argv[1];
    const Arrays torus = read(dir + "/closed_g1_torus.obj");
    const Arrays eight = read(dir + "/closed_g2_eight.obj");
    const Arrays disk = read(dir + "/disk_nefertiti_small.obj");
    if (failures != 0) return 1;
    auto run = [](const char *what, auto check) {
        try {
            check();
        } catch (const uvflat::Error &e) {
            expect(false, std::string(what) + " threw (status " + std::to_string(int(e.status())) + "): " + e.what());
        }
    };
    run("option defaults", [&] { check_option_defaults(); });
    run("components", [&] { check_components(torus); });
    run("curvature", [&] { check_curvature_torus(torus); });
    run("PGP on eight", [&] { check_pgp("closed_g2_eight.obj", eight, 2); });
    run("PGP on the torus", [&] { check_pgp("closed_g1_torus.obj", torus, 1); });
    run("PGP arguments", [&] { check_pgp_arguments(eight); });
    run("QuadCover quad mesh", [&] { check_quadcover_quad_mesh("closed_g1_torus.obj", torus); });
    run("atlas of eight", [&] { check_atlas("closed_g2_eight.obj", eight); });
    run("atlas of the disk", [&] { check_atlas("disk_nefertiti_small.obj", disk); });
    run("intrinsic tools", [&] { check_intrinsic_tools(disk); });
    run("mesh handle", [&] { check_mesh_handle(disk); });
    run("islands and packing", [&] { check_islands_and_packing(disk); });
    run("unwrap of the torus", [&] { check_unwrap("closed_g1_torus.obj", torus); });
    run("unwrap of the disk", [&] { check_unwrap("disk_nefertiti_small.obj", disk); });
    std::printf("%d failure(s)\n", failures);
    return failures == 0 ? 0 : 1;
}
