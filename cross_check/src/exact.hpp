// Exact references for the self-collision and proximity runs, by CGAL: complete sets of triangle
// pairs, not judgements of someone else's disagreements. Kept in its own translation unit (with
// judge.cpp) because CGAL's headers are heavy.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry.hpp"

namespace xc {

// Sorted, distinct triangle pairs (a << 32 | b).
using Keys = std::vector<uint64_t>;

// How the adjacent pairs of one mesh were decided.
struct AdjacentCounts {
    size_t pairs = 0;          // triangle pairs sharing at least one vertex index
    size_t by_planes = 0;      // proper triangles kept apart by each other's planes
    size_t by_cones = 0;       // proper triangles decided by their cones at the shared vertex
    size_t constructed = 0;    // decided by CGAL::intersection (a triangle with collinear corners)
    size_t degenerate = 0;     // with a triangle of collinear corners (as the segment or point it is)
    size_t same_vertices = 0;  // sharing all three vertices: nothing lies beyond what they share
    size_t checked = 0;        // predicate decisions checked by construction: every meeting pair, a sample of the rest
    size_t check_failed = 0;   // of which the construction disagreed: the reference is broken
};

// Do triangles `a` and `b` of one mesh (corners as 9 doubles, vertex indices `ia` and `ib`), which
// share at least one vertex index, have a common point other than their shared vertex, or off the
// segment between their two shared vertices? Exact. Proper triangles are decided by exact
// predicates (a shared edge: apart unless coplanar, then meeting when folded onto each other; a
// shared vertex: apart when one lies on one side of the other's plane, else meeting when their
// cones at the vertex share a ray), and every meeting pair and a sample of the others checked
// against CGAL::intersection in Exact_predicates_exact_constructions_kernel, which decides the
// pairs with a triangle of collinear corners (the segment or point it covers).
bool cgal_meet_beyond_shared(const double a[9], const uint32_t ia[3], const double b[9], const uint32_t ib[3],
                             AdjacentCounts& counts);

// Every pair a < b of triangles of `m` at positions `pos` that share a vertex index and meet
// beyond what they share (cgal_meet_beyond_shared), enumerated from the vertex-to-triangle
// adjacency.
Keys exact_adjacent_self_pairs(const MeshData& m, const std::vector<double>& pos, AdjacentCounts& counts);

// Every pair a < b of triangles of `m` that share no vertex index and intersect (closed
// triangles): CGAL::box_self_intersection_d over the triangles' exact boxes, then cgal_intersect.
// `candidates` gets the number of box pairs tested.
Keys exact_separate_self_pairs(const MeshData& m, const std::vector<double>& pos, size_t& candidates);

// How a set of pairs within a distance was decided.
struct WithinCounts {
    size_t candidates = 0;  // box pairs (boxes grown by the distance, rounded outwards)
    size_t exact = 0;       // pairs that interval arithmetic left open, decided in rationals
    Keys sample;            // a few candidates, spread over them, in the set or not: to check the reference
};

// Is the Euclidean distance between the closed triangles (degenerate ones as their segments or
// points) at most `distance`? Exact for the given doubles: the least squared distance between a
// corner of one and the other, or between an edge of each, compared with distance^2 in interval
// arithmetic, and in CGAL::Exact_rational when the intervals cannot tell; true when they
// intersect. `exact` is incremented when rationals were needed.
bool cgal_within(const double a[9], const double b[9], double distance, size_t* exact);

// Do the two ways of computing the exact squared distance agree: the corner and edge distances
// cgal_within uses (0 when the shapes intersect), and CGAL's own squared_distance(Triangle_3,
// Triangle_3) (for triangles with non-collinear corners; others agree trivially)? Both in
// rationals: a check of the reference on a sample.
bool cgal_distances_agree(const double a[9], const double b[9]);

// The exact distance between the closed triangles (0 when they intersect; degenerate ones as
// their segments or points), its square computed in rationals and its root rounded.
double cgal_distance(const double a[9], const double b[9]);

// -1, 0 or 1 as the exact distance between triangles a1 and b1 is less than, equal to or greater
// than that between a2 and b2.
int cgal_compare_distances(const double a1[9], const double b1[9], const double a2[9], const double b2[9]);

// Every pair (triangle of `ma`, triangle of `mb`) at distance at most `distance`:
// CGAL::box_intersection_d over boxes grown by `distance` (rounded outwards), then cgal_within.
Keys exact_pairs_within(const MeshData& ma, const std::vector<double>& pa, const MeshData& mb, const std::vector<double>& pb,
                        double distance, WithinCounts& counts);

// Every pair a < b of triangles of `m` sharing no vertex index, at distance at most `distance`.
Keys exact_self_pairs_within(const MeshData& m, const std::vector<double>& pos, double distance, WithinCounts& counts);

// Threads the exact references share their triangle tests among (every core).
unsigned reference_threads();

}  // namespace xc
