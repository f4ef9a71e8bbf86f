// The curves run: on every object pair of the pairwise run's scenes, frame by frame, dvh's
// intersection curves (dvh_intersection_curves on meshes refit to the frame's world coordinates)
// against CGAL's Polygon_mesh_processing::surface_intersection on Surface_mesh copies of the same
// coordinates (Exact_predicates_inexact_constructions_kernel: exact predicates, intersection
// points constructed exactly and rounded). Where dvh reports no degenerate pair (the meshes
// cross in general position), the two must give the same points (each of dvh's distinct segment
// ends within 4 units in the last place of the scene's largest coordinate of one of CGAL's
// polyline points, and each of those of one of dvh's; CGAL's are not always correctly rounded, so
// beyond 4 units, up to 64, every dvh segment must instead be its pair's exact intersection within
// 4 units), the same number of curves and of segments; elsewhere (coplanar contact, a copy) the counts are reported only, CGAL's polylines
// then meaning something else.
// Timed: dvh's refit + curves, dvh's refit + collide (each the fastest of three turns taken
// alternately: timed once each, the first call would meet the caches CGAL's work left cold and
// the second the warm ones), CGAL's surface_intersection (its meshes built from the frame's
// arrays beforehand, not timed: it keeps no tree between calls, so a user builds them every
// frame).
//
// Then the self-collision run's bending meshes: dvh_self_intersection_curves against a CGAL
// route to the same segments, PMP::self_intersections for the pairs (the same rule for triangles
// sharing vertices) and CGAL::intersection of each pair's triangles in
// Exact_predicates_exact_constructions_kernel. Every dvh segment must be its pair's exact
// intersection (its two ends within 4 units in the last place of the largest coordinate), and
// the segments plus degenerate pairs must be CGAL's pairs.

#include <dvh.hpp>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <list>

#include "common.hpp"
#include "runs.hpp"

namespace xc {

namespace {

// dvh's two timed steps of a frame, refit + curves and refit + collide, each the fastest of
// `turns` turns taken alternately, so that neither is measured alone with cold caches.
template <class Curves, class Collide>
void time_both(int turns, Curves&& curves, Collide&& collide, double& curves_ms, double& collide_ms) {
    curves_ms = collide_ms = 1e300;
    for (int k = 0; k < turns; k++) {
        auto t0 = Clock::now();
        curves();
        curves_ms = std::min(curves_ms, ms_since(t0));
        t0 = Clock::now();
        collide();
        collide_ms = std::min(collide_ms, ms_since(t0));
    }
}

constexpr int TIMED_TURNS = 3;

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Epeck = CGAL::Exact_predicates_exact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

void world_of(Object& o, double t, std::vector<double>& local, std::vector<double>& world) {
    if (o.deforms)
        o.morph.apply(o.rest.pos, t, local);
    else
        local = o.rest.pos;
    apply_pose(o.motion(t), local, world);
}

SurfaceMesh surface(const MeshData& m, const std::vector<double>& pos) {
    SurfaceMesh s;
    std::vector<SurfaceMesh::Vertex_index> v(m.vertices());
    for (size_t i = 0; i < v.size(); i++) v[i] = s.add_vertex(K::Point_3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]));
    for (size_t t = 0; t < m.triangles(); t++) s.add_face(v[m.tris[3 * t]], v[m.tris[3 * t + 1]], v[m.tris[3 * t + 2]]);
    return s;
}

using Point = std::array<double, 3>;

std::vector<Point> distinct(std::vector<Point> p) {
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
    return p;
}

// The largest distance (per coordinate) from a point of `a` to its nearest point of `b`, both
// sorted: a one-sided Hausdorff distance, found by scanning the points of `b` whose x lies within
// the best distance so far. Near-coincident points (a mesh a hair's breadth from another) make a
// matching of sorted lists misleading; this matches each point to its nearest.
double farthest_from(const std::vector<Point>& a, const std::vector<Point>& b) {
    if (b.empty()) return a.empty() ? 0.0 : INFINITY;
    double worst = 0;
    for (const Point& p : a) {
        auto it = std::lower_bound(b.begin(), b.end(), p);
        double best = INFINITY;
        auto gap = [&](const Point& q) {
            return std::max({std::fabs(p[0] - q[0]), std::fabs(p[1] - q[1]), std::fabs(p[2] - q[2])});
        };
        for (auto up = it; up != b.end() && (*up)[0] - p[0] <= best; ++up) best = std::min(best, gap(*up));
        for (auto down = it; down != b.begin() && p[0] - (*(down - 1))[0] <= best; --down) best = std::min(best, gap(*(down - 1)));
        worst = std::max(worst, best);
    }
    return worst;
}

// The largest distance from a point of either set to the nearest point of the other.
double largest_difference(const std::vector<Point>& a, const std::vector<Point>& b) {
    return std::max(farthest_from(a, b), farthest_from(b, a));
}

// The largest distance (per coordinate) from an end of `seg` to the matching end of the segment
// `p`-`q` (either way round, whichever is nearer).
double segment_difference(const DvhCurveSegment& seg, const Point& p, const Point& q) {
    const Point a{seg.start[0], seg.start[1], seg.start[2]}, b{seg.end[0], seg.end[1], seg.end[2]};
    auto diff = [](const Point& x, const Point& y) {
        return std::max({std::fabs(x[0] - y[0]), std::fabs(x[1] - y[1]), std::fabs(x[2] - y[2])});
    };
    return std::min(std::max(diff(a, p), diff(b, q)), std::max(diff(a, q), diff(b, p)));
}

// The ends of the segment where two triangles meet, by CGAL in exact constructions,
// rounded to doubles; false when they meet in something else.
bool cgal_segment(const double a[9], const double b[9], Point& p, Point& q) {
    auto tri = [](const double* c) {
        return Epeck::Triangle_3(Epeck::Point_3(c[0], c[1], c[2]), Epeck::Point_3(c[3], c[4], c[5]),
                                 Epeck::Point_3(c[6], c[7], c[8]));
    };
    auto meet = CGAL::intersection(tri(a), tri(b));
    if (!meet) return false;
    const Epeck::Segment_3* s = boost::get<Epeck::Segment_3>(&*meet);
    if (s == nullptr) return false;
    // From the exact coordinates (the lazy numbers' own approximations can be off by more).
    auto rounded = [](const Epeck::Point_3& x) {
        return Point{CGAL::to_double(CGAL::exact(x.x())), CGAL::to_double(CGAL::exact(x.y())),
                     CGAL::to_double(CGAL::exact(x.z()))};
    };
    p = rounded(s->source());
    q = rounded(s->target());
    return true;
}


// The largest distance (per coordinate) from an end of a dvh segment to the nearer end of its
// pair's exact intersection (CGAL::intersection in exact constructions); infinite where a pair
// does not meet in a segment. `one_mesh`: both triangles are of `ma`.
double exact_difference(const dvh::Curves& curves, const MeshData& ma, const std::vector<double>& pa, const MeshData& mb,
                        const std::vector<double>& pb, bool one_mesh) {
    double worst = 0;
    for (const DvhCurveSegment& seg : curves) {
        double ta[9], tb[9];
        triangle(ma, pa, seg.triangle_a, ta);
        if (one_mesh)
            triangle(ma, pa, seg.triangle_b, tb);
        else
            triangle(mb, pb, seg.triangle_b, tb);
        Point p, q;
        if (!cgal_segment(ta, tb, p, q)) return INFINITY;
        worst = std::max(worst, segment_difference(seg, p, q));
    }
    return worst;
}

}  // namespace

CurvesResults run_curves(const RunOptions& options) {
    CurvesResults out;
    auto scenes = make_scenes(options.scenes);
    for (auto& scene : scenes) {
        if (!options.only.empty() && scene.name != options.only) continue;
        std::vector<std::vector<double>> local(scene.objects.size()), world(scene.objects.size());
        for (size_t i = 0; i < scene.objects.size(); i++) world_of(scene.objects[i], 0.0, local[i], world[i]);
        std::vector<dvh::Mesh> meshes;
        for (size_t i = 0; i < scene.objects.size(); i++) {
            const MeshData& m = scene.objects[i].rest;
            meshes.emplace_back(world[i].data(), m.vertices(), m.tris.data(), m.triangles(), dvh::BuildOptions{}.refit_threads(1));
        }
        dvh::Curves curves;
        dvh::Pairs pairs;
        const dvh::QueryOptions one = dvh::QueryOptions{}.threads(1);
        const int frames = std::min(scene.frames, options.scenes.full ? 20 : 4);
        for (int f = 0; f < frames; f++) {
            const double t = (double)f / scene.frames;
            for (size_t i = 0; i < scene.objects.size(); i++) world_of(scene.objects[i], t, local[i], world[i]);
            for (auto [i, j] : scene.pairs) {
                const MeshData &mi = scene.objects[i].rest, &mj = scene.objects[j].rest;
                CurvesRow row;
                row.scene = scene.name;
                row.objects = scene.objects[i].name + " x " + scene.objects[j].name;
                row.frame = f;
                row.triangles = mi.triangles() + mj.triangles();

                time_both(
                    TIMED_TURNS,
                    [&] {
                        meshes[i].refit(world[i].data(), mi.vertices());
                        meshes[j].refit(world[j].data(), mj.vertices());
                        dvh::intersection_curves(meshes[i], nullptr, meshes[j], nullptr, one, curves);
                    },
                    [&] {
                        meshes[i].refit(world[i].data(), mi.vertices());
                        meshes[j].refit(world[j].data(), mj.vertices());
                        dvh::collide(meshes[i], nullptr, meshes[j], nullptr, one, pairs);
                    },
                    row.dvh_curves, row.dvh_collide);
                row.segments = curves.size();
                row.curves = curves.curve_count();
                row.degenerate = curves.degenerate().size();

                const SurfaceMesh si = surface(mi, world[i]), sj = surface(mj, world[j]);
                std::list<std::vector<K::Point_3>> polylines;
                auto t0 = Clock::now();
                PMP::surface_intersection(si, sj, std::back_inserter(polylines));
                row.cgal = ms_since(t0);
                row.cgal_polylines = polylines.size();

                std::vector<Point> ours, theirs;
                for (const DvhCurveSegment& s : curves) {
                    ours.push_back({s.start[0], s.start[1], s.start[2]});
                    ours.push_back({s.end[0], s.end[1], s.end[2]});
                }
                for (const auto& line : polylines) {
                    row.cgal_segments += line.size() > 0 ? line.size() - 1 : 0;
                    for (const auto& p : line) theirs.push_back({p.x(), p.y(), p.z()});
                }
                ours = distinct(ours);
                theirs = distinct(theirs);
                row.dvh_points = ours.size();
                row.cgal_points = theirs.size();
                double scale = 0;
                for (const auto& w : {world[i], world[j]})
                    for (double x : w) scale = std::max(scale, std::fabs(x));
                row.difference_ulps = largest_difference(ours, theirs) / (scale * 0x1p-52);
                row.general = row.degenerate == 0;
                // Distinct points a hair's breadth apart may round to one double on one side and
                // two on the other: the points are compared each with its nearest, the counts of
                // curves and segments exactly.
                // CGAL's constructions are not always correctly rounded (up to 9 units off on the
                // terrains 1e-12 apart, where edges nearly lie in the other surface). Beyond 4
                // units, dvh's points are judged exactly instead: each segment must be its pair's
                // exact intersection, and CGAL's points still near dvh's.
                bool judged = false;
                if (row.difference_ulps > 4.0 && row.difference_ulps <= 64.0) {
                    judged = true;
                    row.exact_ulps = exact_difference(curves, mi, world[i], mj, world[j], false) / (scale * 0x1p-52);
                }
                row.same = (row.difference_ulps <= 4.0 || (judged && row.exact_ulps <= 4.0)) &&
                           row.curves == row.cgal_polylines && row.segments == row.cgal_segments;
                char exact_note[64] = "";
                if (judged) std::snprintf(exact_note, sizeof exact_note, "; dvh's %.1f ulps from exact", row.exact_ulps);
                std::printf("curves %-10s %-28s frame %3d: %6zu segments, %4zu curves, %5zu degenerate; CGAL %6zu segments, %4zu "
                            "polylines; points %s (%.1f ulps%s); dvh %.3f ms (collide %.3f), CGAL %.3f ms\n",
                            row.scene.c_str(), row.objects.c_str(), f, row.segments, row.curves, row.degenerate,
                            row.cgal_segments, row.cgal_polylines, row.same ? "the same" : "differ", row.difference_ulps,
                            exact_note, row.dvh_curves, row.dvh_collide, row.cgal);
                out.rows.push_back(row);
            }
        }
    }
    run_self_curves(options, out);
    return out;
}

void run_self_curves(const RunOptions& options, CurvesResults& out) {
    using Face = boost::graph_traits<SurfaceMesh>::face_descriptor;
    for (auto& s : make_self_scenes(options.scenes)) {
        if (!options.only.empty() && s.name != options.only) continue;
        const MeshData& m = s.rest;
        std::vector<double> pos;
        s.at(0.0, pos);
        dvh::Mesh mesh(pos.data(), m.vertices(), m.tris.data(), m.triangles(), dvh::BuildOptions{}.refit_threads(1));
        dvh::Curves curves;
        dvh::Pairs pairs;
        const dvh::QueryOptions one = dvh::QueryOptions{}.threads(1);
        const int frames = std::min(s.frames, options.scenes.full ? 10 : 3);
        for (int f = 0; f < frames; f++) {
            // The later frames, where the meshes pass through themselves.
            const double t = frames > 1 ? 0.5 + 0.5 * f / (frames - 1) : 1.0;
            s.at(t, pos);
            CurvesRow row;
            row.scene = s.name;
            row.objects = "self";
            row.frame = f;
            row.triangles = m.triangles();
            time_both(
                TIMED_TURNS,
                [&] {
                    mesh.refit(pos.data(), m.vertices());
                    dvh::self_intersection_curves(mesh, one, curves);
                },
                [&] {
                    mesh.refit(pos.data(), m.vertices());
                    dvh::self_collide(mesh, one, pairs);
                },
                row.dvh_curves, row.dvh_collide);
            row.segments = curves.size();
            row.curves = curves.curve_count();
            row.degenerate = curves.degenerate().size();

            const SurfaceMesh sm = surface(m, pos);
            std::vector<std::pair<Face, Face>> found;
            auto t0 = Clock::now();
            PMP::self_intersections(sm, std::back_inserter(found));
            std::vector<std::pair<uint64_t, std::array<Point, 2>>> exact;
            for (const auto& [x, y] : found) {
                uint32_t a = (uint32_t)x.idx(), b = (uint32_t)y.idx();
                if (a > b) std::swap(a, b);
                double ta[9], tb[9];
                triangle(m, pos, a, ta);
                triangle(m, pos, b, tb);
                Point p, q;
                if (cgal_segment(ta, tb, p, q)) exact.push_back({pair_key(a, b), {p, q}});
            }
            row.cgal = ms_since(t0);
            std::sort(exact.begin(), exact.end());
            row.cgal_polylines = found.size();  // pairs, for this run
            row.cgal_segments = exact.size();
            double scale = 0;
            for (double x : pos) scale = std::max(scale, std::fabs(x));
            size_t matched = 0;
            double worst = 0;
            for (const DvhCurveSegment& seg : curves) {
                auto it = std::lower_bound(exact.begin(), exact.end(), pair_key(seg.triangle_a, seg.triangle_b),
                                           [](const auto& e, uint64_t k) { return e.first < k; });
                if (it == exact.end() || it->first != pair_key(seg.triangle_a, seg.triangle_b)) continue;
                worst = std::max(worst, segment_difference(seg, it->second[0], it->second[1]));
                matched++;
            }
            row.dvh_points = matched;
            row.difference_ulps = worst / (scale * 0x1p-52);
            row.general = true;
            row.same = matched == row.segments && row.difference_ulps <= 4.0 && row.segments == row.cgal_segments &&
                       row.segments + row.degenerate == found.size();
            std::printf("curves %-10s self frame %3d: %6zu segments, %4zu curves, %5zu degenerate; CGAL %6zu pairs, %6zu segments; "
                        "%s (%.1f ulps); dvh %.3f ms (self_collide %.3f), CGAL %.3f ms\n",
                        row.scene.c_str(), f, row.segments, row.curves, row.degenerate, found.size(), exact.size(),
                        row.same ? "the same" : "differ", row.difference_ulps, row.dvh_curves, row.dvh_collide, row.cgal);
            out.rows.push_back(row);
        }
    }
}

bool report_curves(const CurvesResults& results) {
    if (results.rows.empty()) return true;
    std::printf("\nCurves (medians per frame and object pair, ms, one thread; dvh: refit + curves; CGAL: surface_intersection)\n");
    std::printf("%-10s %7s %9s %8s %9s %9s %11s %9s %9s %8s %8s\n", "scene", "frames", "segments", "general", "differ",
                "dvh", "dvh collide", "curves/col", "CGAL", "CGAL/dvh", "");
    bool ok = true;
    std::vector<std::string> names;
    for (const auto& r : results.rows)
        if (std::find(names.begin(), names.end(), r.scene) == names.end()) names.push_back(r.scene);
    for (const auto& name : names) {
        std::vector<double> dvh, collide, cgal;
        size_t frames = 0, segments = 0, general = 0, differ = 0;
        for (const auto& r : results.rows) {
            if (r.scene != name) continue;
            frames++;
            segments += r.segments;
            dvh.push_back(r.dvh_curves);
            collide.push_back(r.dvh_collide);
            cgal.push_back(r.cgal);
            if (r.general) {
                general++;
                differ += !r.same;
            }
        }
        ok = ok && differ == 0;
        const double d = median(dvh), c = median(collide), g = median(cgal);
        std::printf("%-10s %7zu %9zu %8zu %9zu %9.3f %11.3f %9.2fx %9.3f %7.1fx\n", name.c_str(), frames, segments, general, differ, d,
                    c, c > 0 ? d / c : 0.0, g, d > 0 ? g / d : 0.0);
    }
    if (!ok) std::printf("curves: dvh's curves differ from CGAL's on frames in general position\n");
    return ok;
}

void write_curves_outputs(const std::string& dir, const CurvesResults& results) {
    std::ofstream f(dir + "/curves_frames.csv");
    f << "scene,objects,frame,triangles,segments,curves,degenerate,cgal_segments,cgal_polylines,dvh_points,cgal_points,"
         "difference_ulps,exact_ulps,general,same,dvh_curves_ms,dvh_collide_ms,cgal_ms\n";
    for (const auto& r : results.rows)
        f << r.scene << ',' << r.objects << ',' << r.frame << ',' << r.triangles << ',' << r.segments << ',' << r.curves << ','
          << r.degenerate << ',' << r.cgal_segments << ',' << r.cgal_polylines << ',' << r.dvh_points << ',' << r.cgal_points << ','
          << r.difference_ulps << ',' << r.exact_ulps << ',' << r.general << ',' << r.same << ',' << r.dvh_curves << ',' << r.dvh_collide << ','
          << r.cgal << '\n';
}

}  // namespace xc
