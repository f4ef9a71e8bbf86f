// CGAL's self-intersection test on a mesh file, timed: the peer that the Python benchmark
// (peers.py) runs beside dvh.self_collide. CGAL::Polygon_mesh_processing::self_intersections
// with exact predicates (Epick), sequential, on a Surface_mesh read from OFF.
//
//   g++ -O2 -std=c++17 cgal_self.cpp -o cgal_self -lgmp -lmpfr
//   cgal_self MESH.off REPEATS   prints: faces pairs median_ms
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <utility>
#include <vector>

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Face = boost::graph_traits<Mesh>::face_descriptor;

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: cgal_self MESH.off REPEATS\n");
        return 2;
    }
    Mesh mesh;
    if (!CGAL::Polygon_mesh_processing::IO::read_polygon_mesh(argv[1], mesh) || !CGAL::is_triangle_mesh(mesh)) {
        std::fprintf(stderr, "cgal_self: %s: not a triangle mesh CGAL can read\n", argv[1]);
        return 2;
    }
    const int repeats = std::max(1, std::atoi(argv[2]));
    std::vector<double> ms;
    std::size_t pairs = 0;
    for (int r = 0; r < repeats; r++) {
        std::vector<std::pair<Face, Face>> out;
        const auto t0 = std::chrono::steady_clock::now();
        CGAL::Polygon_mesh_processing::self_intersections<CGAL::Sequential_tag>(mesh, std::back_inserter(out));
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        pairs = out.size();
    }
    std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
    std::printf("%zu %zu %.3f\n", static_cast<std::size_t>(num_faces(mesh)), pairs, ms[ms.size() / 2]);
}
