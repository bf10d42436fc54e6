// An OpenMesh triangle mesh as uvflat's flat arrays (3 doubles per vertex, 3 indices per
// triangle), shared by the OpenMesh test programs of this directory.
#ifndef UVFLAT_TESTS_FLAT_ARRAYS_HPP
#define UVFLAT_TESTS_FLAT_ARRAYS_HPP

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cstddef>
#include <cstdint>
#include <vector>

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

struct Arrays {
    std::vector<double> positions;
    std::vector<std::uint32_t> triangles;
    std::size_t vertex_count() const { return positions.size() / 3; }
    std::size_t triangle_count() const { return triangles.size() / 3; }
};

inline Arrays flat_arrays(const Mesh &mesh) {
    Arrays a;
    for (auto v : mesh.vertices()) {
        const auto p = mesh.point(v);
        a.positions.insert(a.positions.end(), {double(p[0]), double(p[1]), double(p[2])});
    }
    for (auto f : mesh.faces()) {
        for (auto v : mesh.fv_range(f)) a.triangles.push_back(std::uint32_t(v.idx()));
    }
    return a;
}

#endif
