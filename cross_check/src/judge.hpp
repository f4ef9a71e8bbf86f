// CGAL as the judge: exact do_intersect on closed triangles, degenerate ones as the segments or
// points they cover. Kept in its own translation unit because CGAL's headers are heavy.
#pragma once

namespace xc {

// Do the closed triangles (9 doubles each: three corners) share a point? Decided by CGAL's
// Exact_predicates_inexact_constructions_kernel; a triangle with collinear corners is tested as
// the segment between its extreme corners, one with three equal corners as a point.
bool cgal_intersect(const double a[9], const double b[9]);

}  // namespace xc
