#include "exact.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>

#include "judge.hpp"

namespace xc {

namespace {

using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;
using Epeck = CGAL::Exact_predicates_exact_constructions_kernel;
// Interval arithmetic (rounding set once per test by Protect_FPU_rounding) and rationals over the
// same code: the first settles almost every distance comparison, the second the rest.
using Ki = CGAL::Simple_cartesian<CGAL::Interval_nt_advanced>;
using Kq = CGAL::Simple_cartesian<CGAL::Exact_rational>;

uint64_t key(uint32_t a, uint32_t b) { return ((uint64_t)a << 32) | b; }

// The corners a closed triangle's point set is spanned by: all three (not collinear), the two
// extremes of a segment, or one point. Decided by exact predicates on the doubles.
struct Corners {
    int n;
    int index[3];
};

Corners corners(const double c[9]) {
    Epick::Point_3 p[3] = {{c[0], c[1], c[2]}, {c[3], c[4], c[5]}, {c[6], c[7], c[8]}};
    if (!CGAL::collinear(p[0], p[1], p[2])) return {3, {0, 1, 2}};
    int lo = 0, hi = 0;
    for (int k = 1; k < 3; k++) {
        if (CGAL::compare_xyz(p[k], p[lo]) == CGAL::SMALLER) lo = k;
        if (CGAL::compare_xyz(p[k], p[hi]) == CGAL::LARGER) hi = k;
    }
    if (p[lo] == p[hi]) return {1, {lo, lo, lo}};
    return {2, {lo, hi, hi}};
}

template <class K>
struct Shape {
    int n;  // 1: point, 2: segment, 3: triangle
    typename K::Point_3 p[3];

    Shape(const double c[9], const Corners& k) : n(k.n) {
        for (int i = 0; i < n; i++) {
            const double* q = c + 3 * k.index[i];
            p[i] = typename K::Point_3(q[0], q[1], q[2]);
        }
    }
    int edges() const { return n == 3 ? 3 : n - 1; }
    typename K::Segment_3 edge(int e) const { return typename K::Segment_3(p[e], p[(e + 1) % n]); }
};

// ---------------------------------------------------------------- adjacent pairs

// The corners of the (convex) intersection of two shapes: its extreme points, so that the whole
// intersection lies in a convex set exactly when they all do.
struct Collect {
    std::vector<Epeck::Point_3>& out;
    void operator()(const Epeck::Point_3& p) const { out.push_back(p); }
    void operator()(const Epeck::Segment_3& s) const {
        out.push_back(s.source());
        out.push_back(s.target());
    }
    void operator()(const Epeck::Triangle_3& t) const {
        for (int i = 0; i < 3; i++) out.push_back(t.vertex(i));
    }
    void operator()(const std::vector<Epeck::Point_3>& v) const { out.insert(out.end(), v.begin(), v.end()); }
};

template <class A, class B>
void collect(const A& a, const B& b, std::vector<Epeck::Point_3>& out) {
    auto meet = CGAL::intersection(a, b);
    if (meet) boost::apply_visitor(Collect{out}, *meet);
}

std::vector<Epeck::Point_3> meeting_corners(const Shape<Epeck>& a, const Shape<Epeck>& b) {
    std::vector<Epeck::Point_3> out;
    if (a.n == 1 || b.n == 1) {
        const Shape<Epeck>& point = a.n == 1 ? a : b;
        const Shape<Epeck>& other = a.n == 1 ? b : a;
        const Epeck::Point_3& p = point.p[0];
        bool on = other.n == 1   ? other.p[0] == p
                  : other.n == 2 ? other.edge(0).has_on(p)
                                 : Epeck::Triangle_3(other.p[0], other.p[1], other.p[2]).has_on(p);
        if (on) out.push_back(p);
    } else if (a.n == 3 && b.n == 3) {
        collect(Epeck::Triangle_3(a.p[0], a.p[1], a.p[2]), Epeck::Triangle_3(b.p[0], b.p[1], b.p[2]), out);
    } else if (a.n == 3) {
        collect(Epeck::Triangle_3(a.p[0], a.p[1], a.p[2]), b.edge(0), out);
    } else if (b.n == 3) {
        collect(Epeck::Triangle_3(b.p[0], b.p[1], b.p[2]), a.edge(0), out);
    } else {
        collect(a.edge(0), b.edge(0), out);
    }
    return out;
}

// Are `u` and `v` strictly on one side of the plane of `t` (not collinear)?
bool one_side(const Epick::Point_3 t[3], const Epick::Point_3& u, const Epick::Point_3& v) {
    CGAL::Orientation s = CGAL::orientation(t[0], t[1], t[2], u);
    return s != CGAL::COPLANAR && s == CGAL::orientation(t[0], t[1], t[2], v);
}

int position(const uint32_t t[3], uint32_t v) {
    for (int k = 0; k < 3; k++)
        if (t[k] == v) return k;
    return -1;
}

// ---------------------------------------------------------------- distances

template <class K>
typename K::FT squared_distance_to(const typename K::Point_3& p, const Shape<K>& s) {
    if (s.n == 1) return CGAL::squared_distance(p, s.p[0]);
    if (s.n == 2) return CGAL::squared_distance(p, s.edge(0));
    return CGAL::squared_distance(p, typename K::Triangle_3(s.p[0], s.p[1], s.p[2]));
}

// Is the point within sqrt(d2) of the triangle? Either within that of an edge, or its projection
// on the plane falls in the closed triangle and it is that close to the plane. (CGAL's own
// point-triangle distance compares the two edges at a closest corner, a tie intervals cannot
// break.)
template <class K>
CGAL::Uncertain<bool> point_within_triangle(const typename K::Point_3& p, const Shape<K>& t, const typename K::FT& d2,
                                            CGAL::Uncertain<bool>& within_edge) {
    using Vector = typename K::Vector_3;
    within_edge = false;
    for (int e = 0; e < 3; e++) {
        CGAL::Uncertain<bool> r = CGAL::squared_distance(p, t.edge(e)) <= d2;
        if (CGAL::certainly(r)) {
            within_edge = true;
            return true;
        }
        if (CGAL::possibly(r)) within_edge = CGAL::Uncertain<bool>::indeterminate();
    }
    Vector n = CGAL::cross_product(t.p[1] - t.p[0], t.p[2] - t.p[0]);
    CGAL::Uncertain<bool> inside = true;
    for (int e = 0; e < 3; e++) {
        const auto& from = t.p[e];
        const auto& to = t.p[(e + 1) % 3];
        inside = inside & (CGAL::cross_product(to - from, n) * (p - from) <= 0);
    }
    typename K::FT h = n * (p - t.p[0]);
    return inside & (h * h <= d2 * (n * n));
}

// Is any corner-to-shape or edge-to-edge distance at most sqrt(d2)? For disjoint convex shapes the
// least of them is their distance. With intervals the answer may be indeterminate, and CGAL may
// throw Uncertain_conversion_exception from within a distance.
template <class K>
CGAL::Uncertain<bool> some_within(const Shape<K>& a, const Shape<K>& b, const typename K::FT& d2) {
    CGAL::Uncertain<bool> answer = false;
    auto within = [&](CGAL::Uncertain<bool> r) {
        if (CGAL::certainly(r)) return true;
        if (CGAL::possibly(r)) answer = CGAL::Uncertain<bool>::indeterminate();
        return false;
    };
    auto corner = [&](const typename K::Point_3& p, const Shape<K>& s) -> CGAL::Uncertain<bool> {
        if (s.n == 1) return CGAL::squared_distance(p, s.p[0]) <= d2;
        if (s.n == 2) return CGAL::squared_distance(p, s.edge(0)) <= d2;
        CGAL::Uncertain<bool> edge = false;
        CGAL::Uncertain<bool> face = point_within_triangle(p, s, d2, edge);
        return edge | face;
    };
    // Corner pairs first: cheap, and they settle most pairs well within the distance.
    for (int i = 0; i < a.n; i++)
        for (int j = 0; j < b.n; j++)
            if (within(CGAL::squared_distance(a.p[i], b.p[j]) <= d2)) return true;
    for (int i = 0; i < a.n; i++)
        if (b.n > 1 && within(corner(a.p[i], b))) return true;
    for (int i = 0; i < b.n; i++)
        if (a.n > 1 && within(corner(b.p[i], a))) return true;
    for (int i = 0; i < a.edges(); i++)
        for (int j = 0; j < b.edges(); j++)
            if (within(CGAL::squared_distance(a.edge(i), b.edge(j)) <= d2)) return true;
    return answer;
}

template <class K>
typename K::FT least_squared_distance(const Shape<K>& a, const Shape<K>& b) {
    typename K::FT best = CGAL::squared_distance(a.p[0], b.p[0]);
    for (int i = 0; i < a.n; i++) best = std::min(best, squared_distance_to(a.p[i], b));
    for (int i = 0; i < b.n; i++) best = std::min(best, squared_distance_to(b.p[i], a));
    for (int i = 0; i < a.edges(); i++)
        for (int j = 0; j < b.edges(); j++) best = std::min(best, CGAL::squared_distance(a.edge(i), b.edge(j)));
    return best;
}

// ---------------------------------------------------------------- candidates

using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, uint32_t, CGAL::Box_intersection_d::ID_EXPLICIT>;

// Each triangle's box, grown by `grow` on every side and rounded outwards: it contains every
// point within `grow` (per coordinate) of the triangle.
std::vector<Box> boxes(const MeshData& m, const std::vector<double>& pos, double grow) {
    std::vector<Box> out;
    out.reserve(m.triangles());
    const double inf = std::numeric_limits<double>::infinity();
    for (size_t t = 0; t < m.triangles(); t++) {
        double lo[3], hi[3];
        for (int k = 0; k < 3; k++) {
            lo[k] = inf;
            hi[k] = -inf;
            for (int c = 0; c < 3; c++) {
                double x = pos[3 * (size_t)m.tris[3 * t + c] + k];
                lo[k] = std::min(lo[k], x);
                hi[k] = std::max(hi[k], x);
            }
            if (grow > 0) {
                lo[k] = std::nextafter(lo[k] - grow, -inf);
                hi[k] = std::nextafter(hi[k] + grow, inf);
            }
        }
        out.emplace_back(lo, hi, (uint32_t)t);
    }
    return out;
}

bool share_vertex(const MeshData& m, uint32_t a, uint32_t b) {
    const uint32_t* ta = &m.tris[3 * (size_t)a];
    const uint32_t* tb = &m.tris[3 * (size_t)b];
    return position(tb, ta[0]) >= 0 || position(tb, ta[1]) >= 0 || position(tb, ta[2]) >= 0;
}

void corners_of(const MeshData& m, const std::vector<double>& pos, uint32_t t, double out[9]) {
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++) out[3 * c + k] = pos[3 * (size_t)m.tris[3 * (size_t)t + c] + k];
}

AdjacentCounts& operator+=(AdjacentCounts& x, const AdjacentCounts& y) {
    x.pairs += y.pairs;
    x.by_planes += y.by_planes;
    x.by_cones += y.by_cones;
    x.constructed += y.constructed;
    x.degenerate += y.degenerate;
    x.same_vertices += y.same_vertices;
    x.checked += y.checked;
    x.check_failed += y.check_failed;
    return x;
}

// The candidates that pass `test(key, counter)`, sorted; the tests are shared among threads,
// each with its own counter, added to `counter` at the end.
template <class Counter, class Test>
Keys keep(std::vector<uint64_t> candidates, Test test, Counter& counter) {
    std::vector<char> pass(candidates.size(), 0);
    std::atomic<size_t> next{0};
    std::mutex lock;
    std::exception_ptr failure;
    auto work = [&]() {
        Counter local{};
        try {
            for (;;) {
                size_t begin = next.fetch_add(1024);
                if (begin >= candidates.size()) break;
                size_t end = std::min(candidates.size(), begin + 1024);
                for (size_t k = begin; k < end; k++) pass[k] = test(candidates[k], local);
            }
        } catch (...) {
            std::lock_guard<std::mutex> g(lock);
            if (!failure) failure = std::current_exception();
        }
        std::lock_guard<std::mutex> g(lock);
        counter += local;
    };
    unsigned n = std::min<size_t>(reference_threads(), 1 + candidates.size() / 4096);
    std::vector<std::thread> pool;
    for (unsigned i = 1; i < n; i++) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    Keys out;
    for (size_t k = 0; k < candidates.size(); k++)
        if (pass[k]) out.push_back(candidates[k]);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

// About 8 of `candidates`, spread over them.
void take_sample(const std::vector<uint64_t>& candidates, Keys& sample) {
    size_t step = std::max<size_t>(1, candidates.size() / 8);
    for (size_t k = 0; k < candidates.size(); k += step) sample.push_back(candidates[k]);
}

}  // namespace

unsigned reference_threads() { return std::max(1u, std::thread::hardware_concurrency()); }

namespace {

// By construction: the corners of the intersection of the two closed shapes, each on the shared
// vertex, or on the segment between the two shared vertices? (`shared`: a's corners holding the
// shared indices.)
bool meet_by_construction(const double a[9], const Corners& ca, const double b[9], const Corners& cb, const int shared[2],
                          int ns) {
    std::vector<Epeck::Point_3> meet = meeting_corners(Shape<Epeck>(a, ca), Shape<Epeck>(b, cb));
    const double* c = a + 3 * shared[0];
    Epeck::Point_3 p(c[0], c[1], c[2]);
    if (ns == 2) {
        c = a + 3 * shared[1];
        Epeck::Point_3 q(c[0], c[1], c[2]);
        if (p != q) {
            Epeck::Segment_3 edge(p, q);
            return std::any_of(meet.begin(), meet.end(), [&](const Epeck::Point_3& x) { return !edge.has_on(x); });
        }
    }
    return std::any_of(meet.begin(), meet.end(), [&](const Epeck::Point_3& x) { return x != p; });
}

// Is direction g - p in the closed cone at p spanned by u - p and v - p (p, u, v not collinear,
// all four coplanar)?
bool in_cone(const Epick::Point_3& p, const Epick::Point_3& u, const Epick::Point_3& v, const Epick::Point_3& g) {
    CGAL::Orientation s = CGAL::coplanar_orientation(p, u, v, g);  // v's side of line p u, or not
    if (s == CGAL::COLLINEAR) return CGAL::angle(u, p, g) == CGAL::ACUTE;
    CGAL::Orientation t = CGAL::coplanar_orientation(p, v, u, g);
    if (t == CGAL::COLLINEAR) return CGAL::angle(v, p, g) == CGAL::ACUTE;
    return s == CGAL::POSITIVE && t == CGAL::POSITIVE;
}

// Triangles (p, q, r) and (p, u, v) in distinct planes, each reaching the other's plane beyond p
// (q and r not strictly on one side of plane p u v, nor u and v of plane p q r): each meets the
// other's plane in a ray from p along the planes' common line, towards the point where its edge
// opposite p crosses that plane, D / (o_q - o_r) with D = o_q (r - p) - o_r (q - p) and o_x the
// volume of (u - p, v - p, x - p). They meet beyond p when the rays point the same way.
template <class K>
CGAL::Uncertain<bool> same_ray(const double* p3, const double* q3, const double* r3, const double* u3, const double* v3) {
    using Point = typename K::Point_3;
    Point p(p3[0], p3[1], p3[2]), q(q3[0], q3[1], q3[2]), r(r3[0], r3[1], r3[2]), u(u3[0], u3[1], u3[2]),
        v(v3[0], v3[1], v3[2]);
    auto pq = q - p, pr = r - p, pu = u - p, pv = v - p;
    auto oq = CGAL::determinant(pu, pv, pq), orr = CGAL::determinant(pu, pv, pr);
    auto ou = CGAL::determinant(pq, pr, pu), ov = CGAL::determinant(pq, pr, pv);
    auto da = pr * oq - pq * orr, db = pv * ou - pu * ov;
    return (da * db) * (oq - orr) * (ou - ov) > 0;
}

bool same_ray(const double* p, const double* q, const double* r, const double* u, const double* v) {
    try {
        CGAL::Protect_FPU_rounding<true> rounding;
        CGAL::Uncertain<bool> answer = same_ray<Ki>(p, q, r, u, v);
        if (CGAL::is_certain(answer)) return answer.make_certain();
    } catch (const CGAL::Uncertain_conversion_exception&) {
    }
    return same_ray<Kq>(p, q, r, u, v).make_certain();
}

// A deterministic sample of the pairs, 1 in 2^bits (every pair when built with
// -DXC_CHECK_EVERY_PAIR, to test the predicates).
bool sampled(const double a[9], const double b[9], int bits) {
#ifdef XC_CHECK_EVERY_PAIR
    return true;
#endif
    uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (int k = 0; k < 9; k++) {
        uint64_t x, y;
        std::memcpy(&x, &a[k], 8);
        std::memcpy(&y, &b[k], 8);
        h = (h ^ x) * 0x100000001b3ULL;
        h = (h ^ y) * 0x100000001b3ULL;
    }
    h ^= h >> 29;
    return (h & ((1ULL << bits) - 1)) == 0;
}

}  // namespace

bool cgal_meet_beyond_shared(const double a[9], const uint32_t ia[3], const double b[9], const uint32_t ib[3],
                             AdjacentCounts& counts) {
    counts.pairs++;
    int shared[3], ns = 0;  // a's corners holding the distinct shared indices
    for (int k = 0; k < 3; k++)
        if (position(ib, ia[k]) >= 0 && position(ia, ia[k]) == k) shared[ns++] = k;
    if (ns == 0) return cgal_intersect(a, b);
    if (ns == 3) {
        counts.same_vertices++;
        return false;
    }
    Corners ca = corners(a), cb = corners(b);
    if (ca.n < 3 || cb.n < 3) {
        counts.degenerate++;
        counts.constructed++;
        return meet_by_construction(a, ca, b, cb, shared, ns);
    }
    // Proper triangles: exact predicates decide, and a sample is checked by construction.
    Epick::Point_3 pa[3], pb[3];
    for (int k = 0; k < 3; k++) {
        pa[k] = Epick::Point_3(a[3 * k], a[3 * k + 1], a[3 * k + 2]);
        pb[k] = Epick::Point_3(b[3 * k], b[3 * k + 1], b[3 * k + 2]);
    }
    bool meet, plain;  // plain: settled by the planes alone
    if (ns == 2) {
        // Shared edge p q, third corners x and y. Off a's plane, b meets it in the edge only;
        // in it, the triangles overlap beyond the edge exactly when x and y are on one side.
        const int kp = shared[0], kq = shared[1], kx = 3 - kp - kq;
        int ky = 0;
        while (position(ia, ib[ky]) >= 0) ky++;
        plain = CGAL::orientation(pa[0], pa[1], pa[2], pb[ky]) != CGAL::COPLANAR;
        meet = !plain && CGAL::coplanar_orientation(pa[kp], pa[kq], pa[kx], pb[ky]) == CGAL::POSITIVE;
    } else {
        // Shared vertex p; a is (p, q, r), b is (p, u, v). If q and r are strictly on one side of
        // b's plane, a meets that plane at p only (and the same the other way round). Otherwise
        // they meet beyond p exactly when their cones at p do: in one plane, when a side of one
        // lies in the other's cone; in two, when the rays along the planes' common line agree.
        const int ka = shared[0], kb = position(ib, ia[ka]);
        const int kq = (ka + 1) % 3, kr = (ka + 2) % 3, ku = (kb + 1) % 3, kv = (kb + 2) % 3;
        plain = one_side(pb, pa[kq], pa[kr]) || one_side(pa, pb[ku], pb[kv]);
        if (plain) {
            meet = false;
        } else if (CGAL::orientation(pa[0], pa[1], pa[2], pb[ku]) == CGAL::COPLANAR &&
                   CGAL::orientation(pa[0], pa[1], pa[2], pb[kv]) == CGAL::COPLANAR) {
            const auto& p = pa[ka];
            meet = in_cone(p, pb[ku], pb[kv], pa[kq]) || in_cone(p, pb[ku], pb[kv], pa[kr]) ||
                   in_cone(p, pa[kq], pa[kr], pb[ku]) || in_cone(p, pa[kq], pa[kr], pb[kv]);
        } else {
            meet = same_ray(a + 3 * ka, a + 3 * kq, a + 3 * kr, b + 3 * ku, b + 3 * kv);
        }
    }
    (plain ? counts.by_planes : counts.by_cones)++;
    if (meet || sampled(a, b, plain ? 10 : 6)) {
        counts.checked++;
        if (meet_by_construction(a, ca, b, cb, shared, ns) != meet) counts.check_failed++;
    }
    return meet;
}

Keys exact_adjacent_self_pairs(const MeshData& m, const std::vector<double>& pos, AdjacentCounts& counts) {
    // Triangles around each vertex (a triangle repeating an index is listed once).
    std::vector<std::vector<uint32_t>> around(m.vertices());
    for (uint32_t t = 0; t < (uint32_t)m.triangles(); t++)
        for (int c = 0; c < 3; c++) {
            uint32_t v = m.tris[3 * (size_t)t + c];
            if (around[v].empty() || around[v].back() != t) around[v].push_back(t);
        }
    std::vector<uint64_t> candidates;
    for (const auto& ts : around)
        for (size_t i = 0; i < ts.size(); i++)
            for (size_t j = i + 1; j < ts.size(); j++) candidates.push_back(key(ts[i], ts[j]));
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    return keep(
        std::move(candidates),
        [&](uint64_t k, AdjacentCounts& c) {
            uint32_t ta = (uint32_t)(k >> 32), tb = (uint32_t)k;
            double ca[9], cb[9];
            corners_of(m, pos, ta, ca);
            corners_of(m, pos, tb, cb);
            return cgal_meet_beyond_shared(ca, &m.tris[3 * (size_t)ta], cb, &m.tris[3 * (size_t)tb], c);
        },
        counts);
}

Keys exact_separate_self_pairs(const MeshData& m, const std::vector<double>& pos, size_t& candidates) {
    std::vector<Box> b = boxes(m, pos, 0.0);
    std::vector<uint64_t> found;
    CGAL::box_self_intersection_d(b.begin(), b.end(), [&](const Box& x, const Box& y) {
        uint32_t s = std::min(x.info(), y.info()), t = std::max(x.info(), y.info());
        if (!share_vertex(m, s, t)) found.push_back(key(s, t));
    });
    candidates = found.size();
    size_t unused = 0;
    return keep(
        std::move(found),
        [&](uint64_t k, size_t&) {
            double ca[9], cb[9];
            corners_of(m, pos, (uint32_t)(k >> 32), ca);
            corners_of(m, pos, (uint32_t)k, cb);
            return cgal_intersect(ca, cb);
        },
        unused);
}

bool cgal_within(const double a[9], const double b[9], double distance, size_t* exact) {
    // At distance 0, only intersecting shapes qualify (and touching ones defeat intervals).
    if (distance == 0) return cgal_intersect(a, b);
    Corners ca = corners(a), cb = corners(b);
    int verdict = -1;
    try {
        CGAL::Protect_FPU_rounding<true> rounding;  // upwards until the end of this block
        CGAL::Interval_nt_advanced d(distance);
        CGAL::Uncertain<bool> r = some_within(Shape<Ki>(a, ca), Shape<Ki>(b, cb), d * d);
        if (CGAL::is_certain(r)) verdict = r.make_certain();
    } catch (const CGAL::Uncertain_conversion_exception&) {
    }
    if (verdict < 0) {
        if (exact != nullptr) ++*exact;
        CGAL::Exact_rational d(distance);
        verdict = some_within(Shape<Kq>(a, ca), Shape<Kq>(b, cb), d * d).make_certain();
    }
    // Intersecting shapes are at distance 0 whatever their corners and edges say.
    return verdict == 1 || cgal_intersect(a, b);
}

bool cgal_distances_agree(const double a[9], const double b[9]) {
    Corners ca = corners(a), cb = corners(b);
    if (ca.n < 3 || cb.n < 3) return true;
    Shape<Kq> sa(a, ca), sb(b, cb);
    Kq::FT ours = cgal_intersect(a, b) ? Kq::FT(0) : least_squared_distance(sa, sb);
    return ours == CGAL::squared_distance(Kq::Triangle_3(sa.p[0], sa.p[1], sa.p[2]), Kq::Triangle_3(sb.p[0], sb.p[1], sb.p[2]));
}

namespace {

Kq::FT exact_squared_distance(const double a[9], const double b[9]) {
    if (cgal_intersect(a, b)) return Kq::FT(0);
    return least_squared_distance(Shape<Kq>(a, corners(a)), Shape<Kq>(b, corners(b)));
}

}  // namespace

double cgal_distance(const double a[9], const double b[9]) {
    // The square to the nearest double and then its root: within a unit of the exact root for
    // the distances of the scenes (no underflow), which the run's tolerance of two allows for.
    return std::sqrt(CGAL::to_double(exact_squared_distance(a, b)));
}

int cgal_compare_distances(const double a1[9], const double b1[9], const double a2[9], const double b2[9]) {
    const Kq::FT x = exact_squared_distance(a1, b1), y = exact_squared_distance(a2, b2);
    return x < y ? -1 : (y < x ? 1 : 0);
}

Keys exact_pairs_within(const MeshData& ma, const std::vector<double>& pa, const MeshData& mb, const std::vector<double>& pb,
                        double distance, WithinCounts& counts) {
    std::vector<Box> ba = boxes(ma, pa, distance), bb = boxes(mb, pb, 0.0);
    std::vector<uint64_t> found;
    CGAL::box_intersection_d(ba.begin(), ba.end(), bb.begin(), bb.end(),
                             [&](const Box& x, const Box& y) { found.push_back(key(x.info(), y.info())); });
    counts.candidates = found.size();
    take_sample(found, counts.sample);
    return keep(
        std::move(found),
        [&](uint64_t k, size_t& exact) {
            double ca[9], cb[9];
            corners_of(ma, pa, (uint32_t)(k >> 32), ca);
            corners_of(mb, pb, (uint32_t)k, cb);
            return cgal_within(ca, cb, distance, &exact);
        },
        counts.exact);
}

Keys exact_self_pairs_within(const MeshData& m, const std::vector<double>& pos, double distance, WithinCounts& counts) {
    // Both boxes grown by half the distance when halving is exact, else both by all of it.
    double half = 0.5 * distance;
    std::vector<Box> b = boxes(m, pos, half + half == distance ? half : distance);
    std::vector<uint64_t> found;
    CGAL::box_self_intersection_d(b.begin(), b.end(), [&](const Box& x, const Box& y) {
        uint32_t s = std::min(x.info(), y.info()), t = std::max(x.info(), y.info());
        if (!share_vertex(m, s, t)) found.push_back(key(s, t));
    });
    counts.candidates = found.size();
    take_sample(found, counts.sample);
    return keep(
        std::move(found),
        [&](uint64_t k, size_t& exact) {
            double ca[9], cb[9];
            corners_of(m, pos, (uint32_t)(k >> 32), ca);
            corners_of(m, pos, (uint32_t)k, cb);
            return cgal_within(ca, cb, distance, &exact);
        },
        counts.exact);
}

}  // namespace xc
