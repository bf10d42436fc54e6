// cgal_reference: runs one CGAL 5.5 surface-parameterization method on a disk mesh
// and writes the UV coordinates, so that uvflat's results can be checked against
// CGAL's and timed against it (crates/uvflat-core/tests/it/cgal_crosscheck.rs, crates/uvflat-core/benches/vs_cgal.rs).
//
// Usage: cgal_reference METHOD IN.obj OUT.txt [PIN_A PIN_B]
//   METHOD  dcp    Discrete_conformal_map_parameterizer_3      } fixed border:
//           dap    Discrete_authalic_parameterizer_3           } the default
//           mvc    Mean_value_coordinates_parameterizer_3      } Circular_border_arc_length_
//           tutte  Barycentric_mapping_parameterizer_3         } parameterizer_3
//           lscm   LSCM_parameterizer_3 with Two_vertices_parameterizer_3
//   PIN_A PIN_B  (lscm only, 0-based vertex indices) the two pinned vertices; by
//           default the two boundary vertices farthest apart in 3D.
//
// OUT.txt:
//   seconds S          wall time of the parameterize() call only (steady_clock)
//   pins A B           the pinned vertices (lscm), or "pins -1 -1"
//   u v                one line per vertex in OBJ order, %.17g; "nan nan" for a
//                      vertex that CGAL did not parameterize (not in the
//                      connected component of the border)
//
// Pinned positions (read from Two_vertices_parameterizer_3.h in CGAL 5.5.1): when
// the two vertices are given to its constructor, the first one is put at
// (0, 0.5) and the second at (1, 0.5). (Without given vertices CGAL picks the
// extreme vertices along the longest bounding-box axis and keeps their projected
// coordinates instead.) The pins are in the output like every other vertex.
//
// Solvers. Fixed-border methods: CGAL's default solver traits are
// Eigen_solver_traits<Eigen::BiCGSTAB<SparseMatrix, Eigen::IncompleteLUT<double>>>,
// constructed with Eigen 3.4's defaults: relative residual tolerance
// NumTraits<double>::epsilon() = 2.2e-16 and at most 2n iterations; IncompleteLUT
// with drop tolerance 1e-12 and fill factor 10. When BiCGSTAB stops above the
// tolerance, Eigen reports NoConvergence and CGAL returns
// ERROR_CANNOT_SOLVE_LINEAR_SYSTEM. That default tolerance is already tighter than
// any we could ask for (1e-14 would loosen it), so this program changes nothing by
// default: it builds the same solver type explicitly only so that CGAL_REF_TOL and
// CGAL_REF_MAXITER (environment) can override tolerance and iteration limit for
// experiments. A run that returns OK has therefore met a relative residual of
// 2.2e-16 (measured on every disk mesh here: setting 1e-14 changes no UV by more
// than 5e-13). Timings are of CGAL as shipped.
// LSCM: CGAL always uses OpenNL's least-squares assembly (normal equations) with
// Eigen::SimplicialLDLT, a direct solver, so there is no tolerance to set.
//
// The mesh is read by our own small OBJ reader (v and f lines only), so that
// Surface_mesh vertex i is the i-th "v" line; this is checked after loading.

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh_parameterization/Barycentric_mapping_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Circular_border_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_authalic_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_conformal_map_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Error_code.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Mean_value_coordinates_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Two_vertices_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point_2 = Kernel::Point_2;
using Point_3 = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point_3>;
using Vertex = Mesh::Vertex_index;
using Halfedge = Mesh::Halfedge_index;
using UvMap = Mesh::Property_map<Vertex, Point_2>;

namespace SMP = CGAL::Surface_mesh_parameterization;

using Border = SMP::Circular_border_arc_length_parameterizer_3<Mesh>;
// The solver CGAL's fixed-border parameterizers use by default (see the header comment).
using FixedBorderSolver = CGAL::Eigen_solver_traits<
    Eigen::BiCGSTAB<CGAL::Eigen_sparse_matrix<double>::EigenType, Eigen::IncompleteLUT<double>>>;

[[noreturn]] void fail(const std::string& message) {
  std::cerr << "cgal_reference: " << message << std::endl;
  std::exit(1);
}

// CGAL's own get_error_message() table in 5.5.1 lacks an entry for
// ERROR_NO_TOPOLOGICAL_BALL, so messages from code 4 on are shifted; name codes here.
const char* error_code_name(SMP::Error_code code) {
  switch (code) {
    case SMP::OK: return "OK";
    case SMP::ERROR_EMPTY_MESH: return "ERROR_EMPTY_MESH";
    case SMP::ERROR_NON_TRIANGULAR_MESH: return "ERROR_NON_TRIANGULAR_MESH";
    case SMP::ERROR_NO_TOPOLOGICAL_DISC: return "ERROR_NO_TOPOLOGICAL_DISC";
    case SMP::ERROR_NO_TOPOLOGICAL_BALL: return "ERROR_NO_TOPOLOGICAL_BALL";
    case SMP::ERROR_BORDER_TOO_SHORT: return "ERROR_BORDER_TOO_SHORT";
    case SMP::ERROR_NON_CONVEX_BORDER: return "ERROR_NON_CONVEX_BORDER";
    case SMP::ERROR_CANNOT_SOLVE_LINEAR_SYSTEM: return "ERROR_CANNOT_SOLVE_LINEAR_SYSTEM";
    case SMP::ERROR_NO_1_TO_1_MAPPING: return "ERROR_NO_1_TO_1_MAPPING";
    case SMP::ERROR_WRONG_PARAMETER: return "ERROR_WRONG_PARAMETER";
  }
  return "unknown error code";
}

// Reads "v x y z" and "f a b c" lines (1-based; "a/t/n" forms accepted, only the
// vertex index is used). Vertex i of the mesh is the i-th "v" line.
Mesh read_obj(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail("cannot open " + path);
  std::vector<Point_3> points;
  std::vector<std::vector<long>> faces;
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream tokens(line);
    std::string tag;
    if (!(tokens >> tag)) continue;
    if (tag == "v") {
      double x, y, z;
      if (!(tokens >> x >> y >> z)) fail(path + ":" + std::to_string(line_number) + ": bad vertex");
      points.emplace_back(x, y, z);
    } else if (tag == "f") {
      std::vector<long> face;
      std::string corner;
      while (tokens >> corner) face.push_back(std::atol(corner.c_str()));
      if (face.size() != 3) fail(path + ":" + std::to_string(line_number) + ": not a triangle");
      faces.push_back(face);
    }
  }

  Mesh mesh;
  for (const Point_3& p : points) mesh.add_vertex(p);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    std::vector<Vertex> corners;
    for (long index : faces[f]) {
      if (index < 1 || index > static_cast<long>(points.size()))
        fail("face " + std::to_string(f) + " references vertex " + std::to_string(index) +
             " but the file has " + std::to_string(points.size()) + " vertices");
      corners.push_back(Vertex(static_cast<Mesh::size_type>(index - 1)));
    }
    if (mesh.add_face(corners) == Mesh::null_face())
      fail("Surface_mesh::add_face rejected face " + std::to_string(f) + " (non-manifold input?)");
  }

  // Vertex i must be the i-th "v" line: the uvflat side indexes vertices that way.
  if (mesh.number_of_vertices() != points.size()) fail("vertex count changed while loading");
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (mesh.point(Vertex(static_cast<Mesh::size_type>(i))) != points[i])
      fail("vertex " + std::to_string(i) + " was reordered while loading");
  }
  return mesh;
}

// The two border vertices (of the border loop through bhd) farthest apart in 3D,
// by exhaustive O(b^2) search; ties keep the first pair found.
std::pair<Vertex, Vertex> farthest_border_pair(const Mesh& mesh, Halfedge bhd) {
  std::vector<Vertex> border;
  for (Halfedge h : CGAL::halfedges_around_face(bhd, mesh)) border.push_back(mesh.target(h));
  std::pair<Vertex, Vertex> best(border[0], border[border.size() > 1 ? 1 : 0]);
  double best_distance = -1.0;
  for (std::size_t a = 0; a < border.size(); ++a) {
    for (std::size_t b = a + 1; b < border.size(); ++b) {
      double d = CGAL::squared_distance(mesh.point(border[a]), mesh.point(border[b]));
      if (d > best_distance) {
        best_distance = d;
        best = {border[a], border[b]};
      }
    }
  }
  return best;
}

// CGAL's default fixed-border solver; see the header comment for the overrides.
FixedBorderSolver fixed_border_solver() {
  FixedBorderSolver traits;
  if (const char* tolerance = std::getenv("CGAL_REF_TOL"))
    traits.solver().setTolerance(std::atof(tolerance));
  if (const char* max_iterations = std::getenv("CGAL_REF_MAXITER"))
    traits.solver().setMaxIterations(std::atol(max_iterations));
  return traits;
}

template <typename Parameterizer>
SMP::Error_code timed_parameterize(Mesh& mesh, Parameterizer parameterizer, Halfedge bhd, UvMap uv,
                                   double& seconds) {
  auto start = std::chrono::steady_clock::now();
  SMP::Error_code status = SMP::parameterize(mesh, parameterizer, bhd, uv);
  auto stop = std::chrono::steady_clock::now();
  seconds = std::chrono::duration<double>(stop - start).count();
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4 && argc != 6) {
    std::cerr << "usage: cgal_reference dcp|dap|mvc|tutte|lscm IN.obj OUT.txt [PIN_A PIN_B]\n";
    return 2;
  }
  const std::string method = argv[1];
  Mesh mesh = read_obj(argv[2]);
  const std::size_t n = mesh.number_of_vertices();

  Halfedge bhd = CGAL::Polygon_mesh_processing::longest_border(mesh).first;
  if (bhd == Mesh::null_halfedge()) fail("mesh has no border");

  const double nan = std::numeric_limits<double>::quiet_NaN();
  UvMap uv = mesh.add_property_map<Vertex, Point_2>("v:uv", Point_2(nan, nan)).first;

  double seconds = 0.0;
  long pin_a = -1, pin_b = -1;
  SMP::Error_code status;
  if (method == "dcp") {
    SMP::Discrete_conformal_map_parameterizer_3<Mesh, Border, FixedBorderSolver> p(
        Border(), fixed_border_solver());
    status = timed_parameterize(mesh, p, bhd, uv, seconds);
  } else if (method == "dap") {
    SMP::Discrete_authalic_parameterizer_3<Mesh, Border, FixedBorderSolver> p(
        Border(), fixed_border_solver());
    status = timed_parameterize(mesh, p, bhd, uv, seconds);
  } else if (method == "mvc") {
    SMP::Mean_value_coordinates_parameterizer_3<Mesh, Border, FixedBorderSolver> p(
        Border(), fixed_border_solver());
    status = timed_parameterize(mesh, p, bhd, uv, seconds);
  } else if (method == "tutte") {
    SMP::Barycentric_mapping_parameterizer_3<Mesh, Border, FixedBorderSolver> p(
        Border(), fixed_border_solver());
    status = timed_parameterize(mesh, p, bhd, uv, seconds);
  } else if (method == "lscm") {
    std::pair<Vertex, Vertex> pins;
    if (argc == 6) {
      long a = std::atol(argv[4]), b = std::atol(argv[5]);
      if (a < 0 || b < 0 || a >= static_cast<long>(n) || b >= static_cast<long>(n) || a == b)
        fail("pins must be two distinct vertex indices below " + std::to_string(n));
      pins = {Vertex(static_cast<Mesh::size_type>(a)), Vertex(static_cast<Mesh::size_type>(b))};
    } else {
      pins = farthest_border_pair(mesh, bhd);
    }
    pin_a = static_cast<long>(pins.first.idx());
    pin_b = static_cast<long>(pins.second.idx());
    using Pins = SMP::Two_vertices_parameterizer_3<Mesh>;
    SMP::LSCM_parameterizer_3<Mesh, Pins> p{Pins(pins.first, pins.second)};
    status = timed_parameterize(mesh, p, bhd, uv, seconds);
  } else {
    fail("unknown method '" + method + "' (expected dcp, dap, mvc, tutte or lscm)");
  }

  if (status != SMP::OK)
    fail(std::string("CGAL ") + method + " failed on " + argv[2] + ": error code " +
         std::to_string(static_cast<int>(status)) + " " + error_code_name(status));

  FILE* out = std::fopen(argv[3], "w");
  if (out == nullptr) fail(std::string("cannot write ") + argv[3]);
  std::fprintf(out, "seconds %.9g\npins %ld %ld\n", seconds, pin_a, pin_b);
  for (std::size_t i = 0; i < n; ++i) {
    const Point_2& p = uv[Vertex(static_cast<Mesh::size_type>(i))];
    std::fprintf(out, "%.17g %.17g\n", p.x(), p.y());
  }
  if (std::fclose(out) != 0) fail(std::string("cannot write ") + argv[3]);
  return 0;
}
