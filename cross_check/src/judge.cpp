#include "judge.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <variant>

namespace xc {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Segment = K::Segment_3;
using Triangle = K::Triangle_3;
using Shape = std::variant<Point, Segment, Triangle>;

Shape shape(const double c[9]) {
    Point p[3] = {Point(c[0], c[1], c[2]), Point(c[3], c[4], c[5]), Point(c[6], c[7], c[8])};
    if (!CGAL::collinear(p[0], p[1], p[2])) return Triangle(p[0], p[1], p[2]);
    // Collinear: the extremes in lexicographic order are the segment's ends (exact comparisons).
    auto [lo, hi] = std::minmax_element(p, p + 3, [](const Point& a, const Point& b) {
        return CGAL::compare_xyz(a, b) == CGAL::SMALLER;
    });
    if (*lo == *hi) return *lo;
    return Segment(*lo, *hi);
}

struct Meet {
    bool operator()(const Point& a, const Point& b) const { return a == b; }
    bool operator()(const Point& a, const Segment& b) const { return b.has_on(a); }
    bool operator()(const Point& a, const Triangle& b) const { return b.has_on(a); }
    bool operator()(const Segment& a, const Point& b) const { return a.has_on(b); }
    bool operator()(const Segment& a, const Segment& b) const { return CGAL::do_intersect(a, b); }
    bool operator()(const Segment& a, const Triangle& b) const { return CGAL::do_intersect(a, b); }
    bool operator()(const Triangle& a, const Point& b) const { return a.has_on(b); }
    bool operator()(const Triangle& a, const Segment& b) const { return CGAL::do_intersect(a, b); }
    bool operator()(const Triangle& a, const Triangle& b) const { return CGAL::do_intersect(a, b); }
};

}  // namespace

bool cgal_intersect(const double a[9], const double b[9]) {
    return std::visit(Meet{}, shape(a), shape(b));
}

}  // namespace xc
