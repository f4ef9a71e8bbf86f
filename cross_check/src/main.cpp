// Cross-check of dvh against FCL 0.7, frame by frame, with CGAL as the judge.
//
// The pairwise run: for every scene and frame, the same world-coordinate vertex arrays go to FCL
// (BVHModel<OBBRSSd> and BVHModel<AABBd>, replace + bottom-up refit, identity transforms, every
// contact requested) and to dvh through dvh.hpp (refit + exact query), and dvh runs a second time
// with its own poses (local coordinates refit, the rigid motion passed as DvhPose). Every object
// pair of the scene is queried. The sets of intersecting triangle pairs are compared; CGAL's
// exact do_intersect judges every pair in a symmetric difference, and a sample of the agreed
// pairs. dvh must agree with CGAL on every judged pair and its posed answers must equal its
// world-coordinate answers; FCL's errors are counted.
//
// A pair that dvh and both FCL configurations miss is in no disagreement, so on three scenes
// (whole_set_frames: coplanar, near-1e-15 and medium) dvh's whole set is also compared with
// CGAL's exact set of intersecting triangle pairs, computed independently (exact.hpp:
// CGAL::box_intersection_d over the triangles' boxes, then the judge on each candidate), every
// frame of the short run and every 10th of the full one. dvh must equal it pair for pair; the
// pairs judged one by one must agree with it (else the reference is broken).
//
// dvh runs on one thread (refit and query: the single-thread figures FCL is compared with) and,
// on separate meshes, with `--threads N` (DvhQueryOptions.threads and
// DvhBuildOptions.refit_threads; default 0, every core); both must give the same pairs.
//
// The scene run, on the scenes of three or more objects (where a broad phase has pairs to
// discard), in the same frames and world coordinates: every object in one DvhScene as a
// deformable object (dvh_scene_set_positions, then dvh_scene_collide, on one thread; a second
// scene with `--threads N` must agree), against FCL's own broad phase (each configuration's
// models in a DynamicAABBTreeCollisionManagerd: replace + refit, boxes, manager update, and every
// object pair it reports queried for every contact). The sets of (object a, object b, triangle
// a, triangle b) are judged as in the pairwise run, and dvh's must equal its pairwise run's.
//
// Then two runs against complete exact sets (self_run.cpp, proximity_run.cpp; the sets from
// exact.cpp). The self-collision run: meshes bent frame by frame until they pass through
// themselves (make_self_scenes: a rolled and a crumpled sheet, a folded elephant, a twisted
// armadillo); dvh_self_collide against CGAL's set (pairs sharing a vertex: meeting beyond it;
// the others: intersecting) and against FCL's naive route (the model collided with itself, pairs
// sharing a vertex dropped), whose disagreements with dvh are judged as above. The proximity run:
// every triangle pair within 0, 0.1%, 1% and 5% of a scene's size, by dvh_proximity (world
// coordinates and poses) on scenes of the pairwise run and by dvh_self_proximity on the small
// bending meshes, against CGAL's set (box filter, exact distances); at distance 0 they must
// equal dvh_collide and dvh_self_collide.
//
// The curves run (curves_run.cpp), on the pairwise run's scenes and object pairs (4 frames; 20
// in the full run): dvh_intersection_curves against CGAL's PMP::surface_intersection on the same
// world coordinates; where dvh finds no degenerate pair, the same points (each within 4 units in
// the last place of the scene's largest coordinate of the other's nearest, or, where CGAL's are
// up to 64 units off, dvh's within 4 of their pairs' exact intersections), curves and segments.
//
// The distance run (distance_run.cpp), on the same scenes and object pairs (2 frames; 10 in the
// full run), as they move and with the second object moved apart: dvh_distance (one thread,
// threaded, posed, rel_err = 0.01) against FCL's distance() on OBBRSS models, each answer judged
// by CGAL's exact squared distances of the triangle pairs dvh and FCL report.
//
// Usage: dvh_cross_check [--full] [--frames N] [--scene NAME] [--threads N] [--scene-run-only]
//                        [--self-run-only] [--distance-run-only] [--checksums] --data DIR [--out DIR]
// (--scene-run-only skips the pairwise run and makes the scene run on every selected scene, two
// objects or more; --self-run-only makes only the self-collision and proximity runs (with
// --scene-run-only too: those and the scene run); --distance-run-only makes only the distance
// run; --scene NAME selects a scene of any run;
// --checksums prints a hash of every scene's world coordinates at its first and last frame and
// exits: the benchmark runner's port of the scenes must print the same.)
//
// Output: a line per frame and run, a summary of each run, the verdict (exit status 1 when dvh
// is wrong or its runs differ, 2 on errors or when an exact reference contradicts itself). With
// --out DIR: frames.csv and summary.json (the pairwise run, per frame and per scene, with the
// whole-set comparison's counts where it ran),
// scene_frames.csv and scene_summary.json (the scene run: per frame, each FCL configuration's
// columns prefixed obb_ or aabb_; per scene, medians per frame and totals), self_frames.csv and
// self_summary.json (the self-collision run), proximity_frames.csv and proximity_summary.json
// (the proximity run: per scene, frame and distance; per scene and distance), curves_frames.csv
// (the curves run: per scene, frame and object pair), distance_frames.csv (the distance run: per
// scene, object pair, frame and placement), mismatches.txt
// (every pair kept on which dvh differs from an exact set, with coordinates).

#include <dvh.hpp>
#include <fcl/fcl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "common.hpp"
#include "exact.hpp"
#include "fcl_scene.hpp"
#include "fcl_side.hpp"
#include "geometry.hpp"
#include "judge.hpp"
#include "runs.hpp"
#include "scenes.hpp"

namespace {

using xc::Clock;
using xc::ContactSet;
using xc::contains;
using xc::difference;
using xc::median;
using xc::ms_since;
using xc::PairSet;
using xc::SceneContact;
using xc::symmetric_difference;
using xc::to_dvh;
using xc::to_set;
using xc::triangle;

struct FrameRow {
    std::string scene;
    int frame = 0;
    size_t dvh_pairs = 0, obb_pairs = 0, aabb_pairs = 0;
    size_t dvh_only_obb = 0, obb_only = 0, dvh_only_aabb = 0, aabb_only = 0;
    size_t judged = 0, sampled = 0;
    size_t cgal_with_dvh = 0, cgal_with_fcl = 0;
    size_t dvh_wrong = 0, obb_wrong = 0, aabb_wrong = 0, posed_mismatch = 0, threads_mismatch = 0;
    double one_refit = 0, one_query = 0, dvh_refit = 0, dvh_query = 0, posed_refit = 0, posed_query = 0;
    double obb_update = 0, obb_query = 0, aabb_update = 0, aabb_query = 0;
    // Against CGAL's exact set (when whole_set): its pairs and box candidates, the pairs only dvh
    // or only the exact set has, each FCL configuration's differences from it, the judged pairs
    // on which the judge and the exact set disagree, and the reference's time (every core).
    bool whole_set = false;
    size_t exact_pairs = 0, exact_candidates = 0, exact_dvh_only = 0, exact_only = 0;
    size_t exact_obb_diff = 0, exact_aabb_diff = 0, reference_broken = 0;
    double exact_ms = 0;
};

struct Offence {
    std::string scene;
    int frame;
    std::string objects;
    uint32_t a, b;
    bool dvh, cgal;
    double ta[9], tb[9];
};

const size_t kSample = 20;  // agreed pairs spot-checked per object pair and frame, in both runs

// One FCL configuration in one frame of a scene run.
struct FclFrame {
    size_t tested = 0, colliding = 0;  // object pairs: reported by the broad phase, with contacts
    size_t contacts = 0, dvh_only = 0, only = 0, wrong = 0;
    double refit = 0, manager = 0, collide = 0;  // ms: replace + refit + boxes, manager update, collide
    double ms() const { return refit + manager + collide; }
};

// One frame of a scene run.
struct SceneRow {
    std::string scene;
    int frame = 0;
    size_t dvh_tested = 0, dvh_colliding = 0;  // object pairs, as in FclFrame
    size_t dvh_contacts = 0;
    FclFrame obb, aabb;
    size_t judged = 0, sampled = 0, cgal_with_dvh = 0, cgal_with_fcl = 0, dvh_wrong = 0;
    bool pairwise_checked = false;
    size_t pairwise_mismatch = 0, threads_mismatch = 0;
    double dvh_set = 0, dvh_collide = 0;  // ms: set_positions of every object, dvh_scene_collide
};

// Object pairs with at least one contact in a sorted set.
size_t object_pairs(const ContactSet& s) {
    size_t n = 0;
    for (size_t k = 0; k < s.size(); k++)
        if (k == 0 || s[k].object_a != s[k - 1].object_a || s[k].object_b != s[k - 1].object_b) n++;
    return n;
}

bool contains(const ContactSet& s, const SceneContact& c) { return std::binary_search(s.begin(), s.end(), c); }

// The scene run: every object of a scene in one DvhScene (deformable, world coordinates, refit
// and query on one thread) against FCL's own broad phase over the same two configurations as
// the pairwise run, with the world coordinates the pairwise run uses. With `threads` != 1 a
// second scene, threaded, must agree with the first.
class SceneRun {
public:
    SceneRun(const xc::Scene& scene, const std::vector<std::vector<double>>& world,
             const std::vector<std::vector<fcl::Vector3d>>& fcl_world, uint32_t threads)
        : scene_(scene), query_one_(dvh::QueryOptions{}.threads(1)), query_many_(dvh::QueryOptions{}.threads(threads)) {
        const size_t n = scene.objects.size();
        std::vector<char> tested(n * n, 0);
        for (auto [i, j] : scene.pairs) tested[std::min(i, j) * n + std::max(i, j)] = 1;
        add_objects(dvh::BuildOptions{}.refit_threads(1), world, tested, one_);
        if (threads != 1) add_objects(dvh::BuildOptions{}.refit_threads(threads), world, tested, many_);
        for (size_t i = 0; i < n; i++) {
            const auto& m = scene.objects[i].rest;
            obb_.build(m.tris.data(), m.triangles(), fcl_world[i]);
            aabb_.build(m.tris.data(), m.triangles(), fcl_world[i]);
        }
        obb_.finish(tested);
        aabb_.finish(tested);
    }

    // `pairwise`: the pairwise run's one-thread sets of this frame, one per Scene::pairs entry,
    // or null when it did not run.
    SceneRow frame(int f, const std::vector<std::vector<double>>& world, const std::vector<std::vector<fcl::Vector3d>>& fcl_world,
                   const std::vector<PairSet>* pairwise, std::vector<Offence>& offences) {
        SceneRow row;
        row.scene = scene_.name;
        row.frame = f;

        auto t0 = Clock::now();
        set_positions(one_, world);
        row.dvh_set = ms_since(t0);
        t0 = Clock::now();
        DvhSceneStats stats;
        ContactSet dvh = collide(one_, query_one_, &stats);
        row.dvh_collide = ms_since(t0);
        row.dvh_tested = stats.object_pairs_tested;
        row.dvh_colliding = stats.object_pairs_colliding;
        row.dvh_contacts = dvh.size();

        ContactSet obb = run_fcl(obb_, fcl_world, dvh, row.obb);
        ContactSet aabb = run_fcl(aabb_, fcl_world, dvh, row.aabb);

        if (many_.scene) {
            set_positions(many_, world);
            ContactSet threaded = collide(many_, query_many_, nullptr);
            row.threads_mismatch = symmetric_difference(dvh, threaded).size();
        }
        if (pairwise != nullptr) {
            ContactSet apart;
            for (size_t p = 0; p < scene_.pairs.size(); p++) {
                auto [i, j] = scene_.pairs[p];
                for (uint64_t key : (*pairwise)[p])
                    apart.push_back(ordered((uint32_t)i, (uint32_t)j, (uint32_t)(key >> 32), (uint32_t)key));
            }
            std::sort(apart.begin(), apart.end());
            row.pairwise_checked = true;
            row.pairwise_mismatch = symmetric_difference(dvh, apart).size();
        }

        // Judged as in the pairwise run: every contact on which dvh and either FCL configuration
        // disagree, and a sample of those all three report, per object pair.
        ContactSet disputed = symmetric_difference(dvh, obb), more = symmetric_difference(dvh, aabb), agreed;
        disputed.insert(disputed.end(), more.begin(), more.end());
        std::sort(disputed.begin(), disputed.end());
        disputed.erase(std::unique(disputed.begin(), disputed.end()), disputed.end());
        std::set_intersection(dvh.begin(), dvh.end(), obb.begin(), obb.end(), std::back_inserter(agreed));
        agreed = difference(agreed, disputed);
        auto judge = [&](const SceneContact& c, bool disputed_pair) {
            const auto& oa = scene_.objects[c.object_a];
            const auto& ob = scene_.objects[c.object_b];
            Offence off;
            off.a = c.a;
            off.b = c.b;
            triangle(oa.rest, world[c.object_a], c.a, off.ta);
            triangle(ob.rest, world[c.object_b], c.b, off.tb);
            bool truth = xc::cgal_intersect(off.ta, off.tb);
            bool by_dvh = contains(dvh, c);
            if (disputed_pair) {
                row.judged++;
                (truth == by_dvh ? row.cgal_with_dvh : row.cgal_with_fcl)++;
            } else {
                row.sampled++;
            }
            if (contains(obb, c) != truth) row.obb.wrong++;
            if (contains(aabb, c) != truth) row.aabb.wrong++;
            if (by_dvh != truth) {
                row.dvh_wrong++;
                off.scene = scene_.name + " (scene run)";
                off.frame = f;
                off.objects = oa.name + " x " + ob.name;
                off.dvh = by_dvh;
                off.cgal = truth;
                if (offences.size() < 20) offences.push_back(off);
            }
        };
        for (const auto& c : disputed) judge(c, true);
        for (size_t begin = 0, end; begin < agreed.size(); begin = end) {
            end = begin;
            while (end < agreed.size() && agreed[end].object_a == agreed[begin].object_a &&
                   agreed[end].object_b == agreed[begin].object_b)
                end++;
            size_t step = std::max<size_t>(1, (end - begin) / kSample);
            for (size_t k = begin; k < end; k += step) judge(agreed[k], false);
        }

        std::printf("%-10s %4d  scene run: object pairs colliding/tested dvh %4zu/%4zu obb %4zu/%4zu aabb %4zu/%4zu | contacts dvh "
                    "%7zu obb %7zu aabb %7zu | dvh-only %5zu/%5zu fcl-only %5zu/%5zu | judged %5zu cgal: dvh %5zu fcl %5zu | "
                    "dvh wrong %zu pairwise diff %s threads diff %zu | ms dvh %.2f+%.2f obb %.2f+%.2f+%.2f aabb %.2f+%.2f+%.2f\n",
                    scene_.name.c_str(), f, row.dvh_colliding, row.dvh_tested, row.obb.colliding, row.obb.tested,
                    row.aabb.colliding, row.aabb.tested, row.dvh_contacts, row.obb.contacts, row.aabb.contacts, row.obb.dvh_only,
                    row.aabb.dvh_only, row.obb.only, row.aabb.only, row.judged, row.cgal_with_dvh, row.cgal_with_fcl,
                    row.dvh_wrong, row.pairwise_checked ? std::to_string(row.pairwise_mismatch).c_str() : "-",
                    row.threads_mismatch, row.dvh_set, row.dvh_collide, row.obb.refit, row.obb.manager, row.obb.collide,
                    row.aabb.refit, row.aabb.manager, row.aabb.collide);
        std::fflush(stdout);
        return row;
    }

private:
    struct Dvh {
        dvh::Scene scene{nullptr};    // none until add_objects
        std::vector<uint32_t> ids;    // dvh's id of every object
        std::vector<uint32_t> index;  // the object of every dvh id
        bool in_order = true;         // ids increase with the object index: dvh's order is ours
    };

    // Every object as a deformable object made from a mesh of its first-frame world
    // coordinates (the scene keeps what it needs of the mesh), pairs outside Scene::pairs
    // excluded.
    void add_objects(const dvh::BuildOptions& build, const std::vector<std::vector<double>>& world, const std::vector<char>& tested,
                     Dvh& d) {
        const size_t n = scene_.objects.size();
        d.scene = dvh::Scene();
        for (size_t i = 0; i < n; i++) {
            const auto& m = scene_.objects[i].rest;
            const dvh::Mesh mesh(world[i].data(), m.vertices(), m.tris.data(), m.triangles(), build);
            const uint32_t id = d.scene.add_deformable(mesh, 1, 0xffffffffu);
            d.ids.push_back(id);
            if (d.index.size() <= id) d.index.resize(id + 1, UINT32_MAX);
            d.index[id] = (uint32_t)i;
            d.in_order = d.in_order && (i == 0 || id > d.ids[i - 1]);
        }
        for (size_t i = 0; i < n; i++)
            for (size_t j = i + 1; j < n; j++)
                if (!tested[i * n + j]) d.scene.exclude_pair(d.ids[i], d.ids[j]);
    }

    void set_positions(Dvh& d, const std::vector<std::vector<double>>& world) {
        for (size_t i = 0; i < world.size(); i++) d.scene.set_positions(d.ids[i], world[i].data(), scene_.objects[i].rest.vertices());
    }

    // One FCL configuration's frame, each step timed: new positions for every model, the
    // manager's update, the query of every pair it reports.
    template <typename BV>
    ContactSet run_fcl(xc::FclBroadPhase<BV>& fcl, const std::vector<std::vector<fcl::Vector3d>>& fcl_world, const ContactSet& dvh,
                       FclFrame& out) {
        auto t0 = Clock::now();
        for (size_t i = 0; i < fcl_world.size(); i++) fcl.update(i, fcl_world[i]);
        out.refit = ms_since(t0);
        t0 = Clock::now();
        fcl.update_manager();
        out.manager = ms_since(t0);
        t0 = Clock::now();
        ContactSet s = fcl.collide(out.tested);
        out.collide = ms_since(t0);
        out.colliding = object_pairs(s);
        out.contacts = s.size();
        out.dvh_only = difference(dvh, s).size();
        out.only = difference(s, dvh).size();
        return s;
    }

    static SceneContact ordered(uint32_t i, uint32_t j, uint32_t a, uint32_t b) {
        return i < j ? SceneContact{i, j, a, b} : SceneContact{j, i, b, a};
    }

    // Every contact of the frame, in object indices.
    ContactSet collide(Dvh& d, const dvh::QueryOptions& query, DvhSceneStats* stats) {
        const DvhSceneStats got = d.scene.collide(query, contacts_);
        if (stats != nullptr) *stats = got;
        if (got.truncated) throw std::runtime_error("dvh_scene_collide truncated its result");
        const dvh::Span<DvhContact> data = contacts_.view();
        ContactSet s(data.size());
        for (size_t k = 0; k < s.size(); k++)
            s[k] = ordered(d.index[data[k].object_a], d.index[data[k].object_b], data[k].a, data[k].b);
        if (!d.in_order) std::sort(s.begin(), s.end());  // else already sorted by dvh
        return s;
    }

    const xc::Scene& scene_;
    dvh::QueryOptions query_one_, query_many_;
    Dvh one_, many_;
    dvh::Contacts contacts_;
    xc::FclBroadPhase<fcl::OBBRSSd> obb_;
    xc::FclBroadPhase<fcl::AABBd> aabb_;
};

// What runs on a scene, frame by frame: the pairwise run (its rows are returned) and the scene run
// (its rows go to `scene_rows`). `whole_set`: the pairwise run also compares dvh's whole set with
// CGAL's exact set on the frames it names.
struct Runs {
    bool pairwise = true, scene = true;
    std::function<bool(int)> whole_set;
};

const size_t kKeep = 200;  // whole-set mismatches kept for the report

// dvh's pairs of objects `i` and `j` against CGAL's exact set: counts in `row`, the differences
// kept in `mismatches`.
void compare_whole(const PairSet& dvh, const PairSet& exact, const xc::Scene& scene, size_t i, size_t j,
                   const std::vector<std::vector<double>>& world, FrameRow& row, std::vector<xc::Mismatch>& mismatches) {
    const auto& mi = scene.objects[i].rest;
    const auto& mj = scene.objects[j].rest;
    for (uint64_t k : symmetric_difference(dvh, exact)) {
        xc::Mismatch x;
        x.run = "pairwise (whole set)";
        x.scene = scene.name;
        x.objects = scene.objects[i].name + " x " + scene.objects[j].name;
        x.frame = row.frame;
        x.a = (uint32_t)(k >> 32);
        x.b = (uint32_t)k;
        std::copy(&mi.tris[3 * (size_t)x.a], &mi.tris[3 * (size_t)x.a] + 3, x.ia);
        std::copy(&mj.tris[3 * (size_t)x.b], &mj.tris[3 * (size_t)x.b] + 3, x.ib);
        triangle(mi, world[i], x.a, x.ta);
        triangle(mj, world[j], x.b, x.tb);
        x.dvh = contains(dvh, k);
        x.exact = !x.dvh;
        (x.dvh ? row.exact_dvh_only : row.exact_only)++;
        if (mismatches.size() < kKeep) mismatches.push_back(x);
    }
}

std::vector<FrameRow> run_scene(xc::Scene& scene, uint32_t threads, const Runs& runs, std::vector<Offence>& offences,
                                std::vector<xc::Mismatch>& mismatches, std::vector<SceneRow>& scene_rows) {
    const size_t n = scene.objects.size();
    std::vector<std::vector<double>> local(n), world(n);
    std::vector<std::vector<fcl::Vector3d>> fcl_world(n);
    std::vector<xc::Pose> poses(n);
    auto place = [&](double t) {
        for (size_t i = 0; i < n; i++) {
            poses[i] = xc::place_object(scene.objects[i], t, local[i], world[i]);
            xc::to_fcl(world[i], fcl_world[i]);
        }
    };

    place(0.0);
    std::vector<dvh::Mesh> dvh_one, dvh_world, dvh_local;
    xc::FclSide<fcl::OBBRSSd> obb;
    xc::FclSide<fcl::AABBd> aabb;
    const dvh::BuildOptions one_thread = dvh::BuildOptions{}.refit_threads(1), many = dvh::BuildOptions{}.refit_threads(threads);
    const dvh::QueryOptions query_one = dvh::QueryOptions{}.threads(1), query_many = dvh::QueryOptions{}.threads(threads);
    for (size_t i = 0; runs.pairwise && i < n; i++) {
        const auto& m = scene.objects[i].rest;
        dvh_one.emplace_back(world[i].data(), m.vertices(), m.tris.data(), m.triangles(), one_thread);
        dvh_world.emplace_back(world[i].data(), m.vertices(), m.tris.data(), m.triangles(), many);
        dvh_local.emplace_back(local[i].data(), m.vertices(), m.tris.data(), m.triangles(), many);
        obb.build(m.tris.data(), m.triangles(), fcl_world[i]);
        aabb.build(m.tris.data(), m.triangles(), fcl_world[i]);
    }
    dvh::Pairs pairs;
    std::unique_ptr<SceneRun> whole;
    if (runs.scene) whole = std::make_unique<SceneRun>(scene, world, fcl_world, threads);

    std::vector<FrameRow> rows;
    for (int f = 0; f < scene.frames; f++) {
        FrameRow row;
        row.scene = scene.name;
        row.frame = f;
        place((double)f / scene.frames);
        std::vector<DvhPose> dposes(n);
        for (size_t i = 0; i < n; i++) dposes[i] = to_dvh(poses[i]);

        std::vector<PairSet> s1(scene.pairs.size()), sw(scene.pairs.size()), sp(scene.pairs.size()), so(scene.pairs.size()),
            sa(scene.pairs.size());
        if (!runs.pairwise) {
            if (whole) scene_rows.push_back(whole->frame(f, world, fcl_world, nullptr, offences));
            continue;
        }
        // One dvh configuration: refit every mesh, then query every pair (with poses or not), each
        // timed.
        auto run_dvh = [&](std::vector<dvh::Mesh>& meshes, const std::vector<std::vector<double>>& coords, bool posed,
                           const dvh::QueryOptions& query, std::vector<PairSet>& out, double& refit_ms, double& query_ms) {
            auto t0 = Clock::now();
            for (size_t i = 0; i < n; i++) meshes[i].refit(coords[i].data(), scene.objects[i].rest.vertices());
            refit_ms = ms_since(t0);
            t0 = Clock::now();
            for (size_t p = 0; p < scene.pairs.size(); p++) {
                auto [i, j] = scene.pairs[p];
                dvh::collide(meshes[i], posed ? &dposes[i] : nullptr, meshes[j], posed ? &dposes[j] : nullptr, query, pairs);
                out[p] = to_set(pairs);
            }
            query_ms = ms_since(t0);
        };
        run_dvh(dvh_one, world, false, query_one, s1, row.one_refit, row.one_query);
        run_dvh(dvh_world, world, false, query_many, sw, row.dvh_refit, row.dvh_query);
        run_dvh(dvh_local, local, true, query_many, sp, row.posed_refit, row.posed_query);

        // One FCL configuration: update every model, then query every pair, each timed.
        auto run_fcl = [&](auto& fcl, std::vector<PairSet>& out, double& update_ms, double& query_ms) {
            auto t0 = Clock::now();
            for (size_t i = 0; i < n; i++) fcl.update(i, fcl_world[i]);
            update_ms = ms_since(t0);
            t0 = Clock::now();
            for (size_t p = 0; p < scene.pairs.size(); p++) out[p] = fcl.collide(scene.pairs[p].first, scene.pairs[p].second);
            query_ms = ms_since(t0);
        };
        run_fcl(obb, so, row.obb_update, row.obb_query);
        run_fcl(aabb, sa, row.aabb_update, row.aabb_query);
        row.whole_set = runs.whole_set && runs.whole_set(f);

        for (size_t p = 0; p < scene.pairs.size(); p++) {
            auto [i, j] = scene.pairs[p];
            const auto& mi = scene.objects[i].rest;
            const auto& mj = scene.objects[j].rest;
            row.dvh_pairs += sw[p].size();
            row.obb_pairs += so[p].size();
            row.aabb_pairs += sa[p].size();
            row.posed_mismatch += symmetric_difference(sw[p], sp[p]).size();
            row.threads_mismatch += symmetric_difference(sw[p], s1[p]).size();
            row.dvh_only_obb += difference(sw[p], so[p]).size();
            row.obb_only += difference(so[p], sw[p]).size();
            row.dvh_only_aabb += difference(sw[p], sa[p]).size();
            row.aabb_only += difference(sa[p], sw[p]).size();
            PairSet disputed = symmetric_difference(sw[p], so[p]);
            PairSet more = symmetric_difference(sw[p], sa[p]);
            disputed.insert(disputed.end(), more.begin(), more.end());
            std::sort(disputed.begin(), disputed.end());
            disputed.erase(std::unique(disputed.begin(), disputed.end()), disputed.end());
            // A sample of the pairs all three agree on, spread over the set, is judged too.
            PairSet agreed, sample;
            std::set_intersection(sw[p].begin(), sw[p].end(), so[p].begin(), so[p].end(), std::back_inserter(agreed));
            agreed = difference(agreed, disputed);
            size_t step = std::max<size_t>(1, agreed.size() / kSample);
            for (size_t k = 0; k < agreed.size(); k += step) sample.push_back(agreed[k]);
            // The exact set at distance 0: every pair of intersecting closed triangles, found
            // without dvh's or FCL's help.
            PairSet exact;
            if (row.whole_set) {
                auto t0 = Clock::now();
                xc::WithinCounts counts;
                exact = xc::exact_pairs_within(mi, world[i], mj, world[j], 0.0, counts);
                row.exact_ms += ms_since(t0);
                row.exact_candidates += counts.candidates;
                row.exact_pairs += exact.size();
                row.exact_obb_diff += symmetric_difference(so[p], exact).size();
                row.exact_aabb_diff += symmetric_difference(sa[p], exact).size();
                compare_whole(sw[p], exact, scene, i, j, world, row, mismatches);
            }
            auto judge = [&](uint64_t key, bool disputed_pair) {
                Offence off;
                off.a = (uint32_t)(key >> 32);
                off.b = (uint32_t)key;
                triangle(mi, world[i], off.a, off.ta);
                triangle(mj, world[j], off.b, off.tb);
                bool truth = xc::cgal_intersect(off.ta, off.tb);
                bool by_dvh = contains(sw[p], key);
                if (disputed_pair) {
                    row.judged++;
                    (truth == by_dvh ? row.cgal_with_dvh : row.cgal_with_fcl)++;
                } else {
                    row.sampled++;
                }
                if (contains(so[p], key) != truth) row.obb_wrong++;
                if (contains(sa[p], key) != truth) row.aabb_wrong++;
                if (row.whole_set && contains(exact, key) != truth) row.reference_broken++;
                if (by_dvh != truth) {
                    row.dvh_wrong++;
                    off.scene = scene.name;
                    off.frame = f;
                    off.objects = scene.objects[i].name + " x " + scene.objects[j].name;
                    off.dvh = by_dvh;
                    off.cgal = truth;
                    if (offences.size() < 20) offences.push_back(off);
                }
            };
            for (uint64_t key : disputed) judge(key, true);
            for (uint64_t key : sample) judge(key, false);
        }
        std::printf("%-10s %4d  pairs dvh %7zu obb %7zu aabb %7zu | dvh-only %5zu/%5zu fcl-only %5zu/%5zu | judged %5zu cgal: dvh %5zu fcl %5zu | "
                    "dvh wrong %zu posed diff %zu threads diff %zu | ms dvh 1 thread %.2f+%.2f threaded %.2f+%.2f posed %.2f+%.2f "
                    "obb %.2f+%.2f aabb %.2f+%.2f\n",
                    scene.name.c_str(), f, row.dvh_pairs, row.obb_pairs, row.aabb_pairs, row.dvh_only_obb, row.dvh_only_aabb,
                    row.obb_only, row.aabb_only, row.judged, row.cgal_with_dvh, row.cgal_with_fcl, row.dvh_wrong,
                    row.posed_mismatch, row.threads_mismatch, row.one_refit, row.one_query, row.dvh_refit, row.dvh_query,
                    row.posed_refit, row.posed_query, row.obb_update, row.obb_query, row.aabb_update, row.aabb_query);
        if (row.whole_set)
            std::printf("%-10s %4d  whole set: exact %7zu (candidates %zu) | dvh-only %zu exact-only %zu | obb differs on %zu aabb %zu "
                        "| ms exact %.1f\n",
                        scene.name.c_str(), f, row.exact_pairs, row.exact_candidates, row.exact_dvh_only, row.exact_only,
                        row.exact_obb_diff, row.exact_aabb_diff, row.exact_ms);
        if (row.reference_broken != 0)
            std::printf("  REFERENCE BROKEN: %zu judged pairs on which the judge and the exact set disagree\n", row.reference_broken);
        std::fflush(stdout);
        rows.push_back(row);
        if (whole) scene_rows.push_back(whole->frame(f, world, fcl_world, &s1, offences));
    }
    return rows;
}

struct Summary {
    std::string scene, description;
    int frames = 0;
    size_t pairs_compared = 0, disagreements = 0, judged = 0, sampled = 0;
    size_t dvh_wrong = 0, obb_wrong = 0, aabb_wrong = 0, posed_mismatch = 0, threads_mismatch = 0;
    double one = 0, dvh = 0, posed = 0, obb = 0, aabb = 0;
    // Over the frames whose whole set was compared with CGAL's exact set (FrameRow).
    int whole_frames = 0;
    size_t exact_pairs = 0, exact_candidates = 0, exact_dvh_only = 0, exact_only = 0;
    size_t exact_obb_diff = 0, exact_aabb_diff = 0, reference_broken = 0;
    double exact_ms = 0;  // total
    size_t whole_differences() const { return exact_dvh_only + exact_only; }
};

Summary summarize(const xc::Scene& scene, const std::vector<FrameRow>& rows) {
    Summary s;
    s.scene = scene.name;
    s.description = scene.description;
    s.frames = (int)rows.size();
    std::vector<double> one, dvh, posed, obb, aabb;
    for (const auto& r : rows) {
        s.pairs_compared += r.dvh_pairs;
        s.disagreements += r.dvh_only_obb + r.obb_only + r.dvh_only_aabb + r.aabb_only;
        s.judged += r.judged;
        s.sampled += r.sampled;
        s.dvh_wrong += r.dvh_wrong;
        s.obb_wrong += r.obb_wrong;
        s.aabb_wrong += r.aabb_wrong;
        s.posed_mismatch += r.posed_mismatch;
        s.threads_mismatch += r.threads_mismatch;
        one.push_back(r.one_refit + r.one_query);
        dvh.push_back(r.dvh_refit + r.dvh_query);
        posed.push_back(r.posed_refit + r.posed_query);
        obb.push_back(r.obb_update + r.obb_query);
        aabb.push_back(r.aabb_update + r.aabb_query);
        s.reference_broken += r.reference_broken;
        if (!r.whole_set) continue;
        s.whole_frames++;
        s.exact_pairs += r.exact_pairs;
        s.exact_candidates += r.exact_candidates;
        s.exact_dvh_only += r.exact_dvh_only;
        s.exact_only += r.exact_only;
        s.exact_obb_diff += r.exact_obb_diff;
        s.exact_aabb_diff += r.exact_aabb_diff;
        s.exact_ms += r.exact_ms;
    }
    s.one = median(one);
    s.dvh = median(dvh);
    s.posed = median(posed);
    s.obb = median(obb);
    s.aabb = median(aabb);
    return s;
}

struct SceneSummary {
    std::string scene;
    int frames = 0;
    double colliding = 0, dvh_tested = 0, fcl_tested = 0, contacts = 0;  // medians per frame (dvh's; FCL's broad phase)
    size_t contacts_total = 0, disagreements = 0, judged = 0, sampled = 0, cgal_with_dvh = 0, cgal_with_fcl = 0;
    size_t dvh_wrong = 0, obb_wrong = 0, aabb_wrong = 0, threads_mismatch = 0;
    bool pairwise_checked = true;
    size_t pairwise_mismatch = 0;
    double dvh = 0, obb = 0, aabb = 0;  // medians per frame, ms
};

SceneSummary summarize_scene_run(const std::string& scene, const std::vector<SceneRow>& all) {
    SceneSummary s;
    s.scene = scene;
    std::vector<double> colliding, dvh_tested, fcl_tested, contacts, dvh, obb, aabb;
    for (const auto& r : all) {
        if (r.scene != scene) continue;
        s.frames++;
        colliding.push_back((double)r.dvh_colliding);
        dvh_tested.push_back((double)r.dvh_tested);
        fcl_tested.push_back((double)r.obb.tested);
        contacts.push_back((double)r.dvh_contacts);
        s.contacts_total += r.dvh_contacts;
        s.disagreements += r.obb.dvh_only + r.obb.only + r.aabb.dvh_only + r.aabb.only;
        s.judged += r.judged;
        s.sampled += r.sampled;
        s.cgal_with_dvh += r.cgal_with_dvh;
        s.cgal_with_fcl += r.cgal_with_fcl;
        s.dvh_wrong += r.dvh_wrong;
        s.obb_wrong += r.obb.wrong;
        s.aabb_wrong += r.aabb.wrong;
        s.threads_mismatch += r.threads_mismatch;
        s.pairwise_checked = s.pairwise_checked && r.pairwise_checked;
        s.pairwise_mismatch += r.pairwise_mismatch;
        dvh.push_back(r.dvh_set + r.dvh_collide);
        obb.push_back(r.obb.ms());
        aabb.push_back(r.aabb.ms());
    }
    s.colliding = median(colliding);
    s.dvh_tested = median(dvh_tested);
    s.fcl_tested = median(fcl_tested);
    s.contacts = median(contacts);
    s.dvh = median(dvh);
    s.obb = median(obb);
    s.aabb = median(aabb);
    return s;
}

void write_outputs(const std::string& dir, const std::vector<FrameRow>& rows, const std::vector<Summary>& sums,
                   const std::vector<SceneRow>& scene_rows, const std::vector<SceneSummary>& scene_sums) {
    std::ofstream csv(dir + "/frames.csv");
    csv << "scene,frame,dvh_pairs,obb_pairs,aabb_pairs,dvh_only_vs_obb,obb_only,dvh_only_vs_aabb,aabb_only,judged,sampled,"
           "cgal_with_dvh,cgal_with_fcl,dvh_wrong,obb_wrong,aabb_wrong,posed_mismatch,threads_mismatch,one_thread_refit_ms,"
           "one_thread_query_ms,dvh_refit_ms,dvh_query_ms,posed_refit_ms,posed_query_ms,obb_update_ms,obb_query_ms,"
           "aabb_update_ms,aabb_query_ms,exact_pairs,exact_candidates,exact_dvh_only,exact_only,exact_obb_differences,"
           "exact_aabb_differences,reference_broken,exact_ms\n";
    for (const auto& r : rows) {
        csv << r.scene << ',' << r.frame << ',' << r.dvh_pairs << ',' << r.obb_pairs << ',' << r.aabb_pairs << ','
            << r.dvh_only_obb << ',' << r.obb_only << ',' << r.dvh_only_aabb << ',' << r.aabb_only << ',' << r.judged << ','
            << r.sampled << ',' << r.cgal_with_dvh << ',' << r.cgal_with_fcl << ',' << r.dvh_wrong << ',' << r.obb_wrong << ','
            << r.aabb_wrong << ',' << r.posed_mismatch << ',' << r.threads_mismatch << ',' << r.one_refit << ',' << r.one_query
            << ',' << r.dvh_refit << ',' << r.dvh_query << ',' << r.posed_refit << ','
            << r.posed_query << ',' << r.obb_update << ',' << r.obb_query << ',' << r.aabb_update << ',' << r.aabb_query;
        if (r.whole_set)
            csv << ',' << r.exact_pairs << ',' << r.exact_candidates << ',' << r.exact_dvh_only << ',' << r.exact_only << ','
                << r.exact_obb_diff << ',' << r.exact_aabb_diff << ',' << r.reference_broken << ',' << r.exact_ms << '\n';
        else  // empty: the whole set was not compared in this frame
            csv << ",,,,,,,,\n";
    }
    std::ofstream json(dir + "/summary.json");
    json << "[\n";
    for (size_t k = 0; k < sums.size(); k++) {
        const auto& s = sums[k];
        json << "  {\"scene\": \"" << s.scene << "\", \"description\": \"" << s.description << "\", \"frames\": " << s.frames
             << ", \"pairs_compared\": " << s.pairs_compared << ", \"disagreements\": " << s.disagreements
             << ", \"judged\": " << s.judged << ", \"sampled\": " << s.sampled << ", \"dvh_wrong\": " << s.dvh_wrong
             << ", \"obb_wrong\": " << s.obb_wrong << ", \"aabb_wrong\": " << s.aabb_wrong
             << ", \"posed_mismatch\": " << s.posed_mismatch << ", \"threads_mismatch\": " << s.threads_mismatch
             << ", \"median_ms\": {\"dvh_one_thread\": " << s.one << ", \"dvh\": " << s.dvh
             << ", \"dvh_posed\": " << s.posed << ", \"fcl_obbrss\": " << s.obb << ", \"fcl_aabb\": " << s.aabb << "}"
             << ", \"reference_broken\": " << s.reference_broken << ", \"whole_set\": ";
        if (s.whole_frames > 0)
            json << "{\"frames\": " << s.whole_frames << ", \"exact_pairs\": " << s.exact_pairs << ", \"candidates\": "
                 << s.exact_candidates << ", \"differences\": " << s.whole_differences() << ", \"dvh_only\": " << s.exact_dvh_only
                 << ", \"exact_only\": " << s.exact_only << ", \"fcl_obbrss_differences\": " << s.exact_obb_diff
                 << ", \"fcl_aabb_differences\": " << s.exact_aabb_diff << ", \"exact_ms\": " << s.exact_ms << "}";
        else
            json << "null";
        json << "}" << (k + 1 < sums.size() ? "," : "") << "\n";
    }
    json << "]\n";

    std::ofstream scsv(dir + "/scene_frames.csv");
    scsv << "scene,frame,dvh_object_pairs_tested,dvh_object_pairs_colliding,dvh_contacts,obb_object_pairs_tested,"
            "obb_object_pairs_colliding,obb_contacts,dvh_only_vs_obb,obb_only,aabb_object_pairs_tested,aabb_object_pairs_colliding,"
            "aabb_contacts,dvh_only_vs_aabb,aabb_only,judged,sampled,cgal_with_dvh,cgal_with_fcl,dvh_wrong,obb_wrong,aabb_wrong,"
            "pairwise_mismatch,threads_mismatch,dvh_set_positions_ms,dvh_collide_ms,obb_refit_ms,obb_manager_update_ms,"
            "obb_collide_ms,aabb_refit_ms,aabb_manager_update_ms,aabb_collide_ms\n";
    for (const auto& r : scene_rows) {
        scsv << r.scene << ',' << r.frame << ',' << r.dvh_tested << ',' << r.dvh_colliding << ',' << r.dvh_contacts;
        for (const FclFrame* c : {&r.obb, &r.aabb})
            scsv << ',' << c->tested << ',' << c->colliding << ',' << c->contacts << ',' << c->dvh_only << ',' << c->only;
        scsv << ',' << r.judged << ',' << r.sampled << ',' << r.cgal_with_dvh << ',' << r.cgal_with_fcl << ',' << r.dvh_wrong << ','
             << r.obb.wrong << ',' << r.aabb.wrong << ',';
        if (r.pairwise_checked) scsv << r.pairwise_mismatch;  // empty: the pairwise run did not run
        scsv << ',' << r.threads_mismatch << ',' << r.dvh_set << ',' << r.dvh_collide;
        for (const FclFrame* c : {&r.obb, &r.aabb}) scsv << ',' << c->refit << ',' << c->manager << ',' << c->collide;
        scsv << '\n';
    }
    std::ofstream sjson(dir + "/scene_summary.json");
    sjson << "[\n";
    for (size_t k = 0; k < scene_sums.size(); k++) {
        const auto& s = scene_sums[k];
        sjson << "  {\"scene\": \"" << s.scene << "\", \"frames\": " << s.frames
              << ", \"median_per_frame\": {\"object_pairs_colliding\": " << s.colliding << ", \"dvh_object_pairs_tested\": "
              << s.dvh_tested << ", \"fcl_object_pairs_tested\": " << s.fcl_tested << ", \"contacts\": " << s.contacts
              << "}, \"contacts\": " << s.contacts_total << ", \"disagreements\": " << s.disagreements
              << ", \"judged\": " << s.judged << ", \"sampled\": " << s.sampled << ", \"cgal_with_dvh\": " << s.cgal_with_dvh
              << ", \"cgal_with_fcl\": " << s.cgal_with_fcl << ", \"dvh_wrong\": " << s.dvh_wrong
              << ", \"obb_wrong\": " << s.obb_wrong << ", \"aabb_wrong\": " << s.aabb_wrong << ", \"pairwise_mismatch\": ";
        if (s.pairwise_checked)
            sjson << s.pairwise_mismatch;
        else
            sjson << "null";
        sjson << ", \"threads_mismatch\": " << s.threads_mismatch << ", \"median_ms\": {\"dvh\": " << s.dvh
              << ", \"fcl_obbrss\": " << s.obb << ", \"fcl_aabb\": " << s.aabb << "}}" << (k + 1 < scene_sums.size() ? "," : "")
              << "\n";
    }
    sjson << "]\n";
}

// The frames of `scene` on which the pairwise run compares dvh's whole set with CGAL's exact set,
// or none. Two stress scenes where FCL is weak (coplanar sheets: every contact a coplanar pair;
// the copy shifted by 1e-15, where both FCL configurations miss and invent pairs) and an ordinary
// one (medium meshes deforming into each other). The short run's reference takes about 0.5 s for
// every frame of the three; the full run's, about 2.5 s a frame, so there every 10th frame.
std::function<bool(int)> whole_set_frames(const xc::Scene& scene, bool full) {
    if (scene.name != "coplanar" && scene.name != "near-1e-15" && scene.name != "medium") return nullptr;
    if (!full) return [](int) { return true; };
    return [](int f) { return f % 10 == 0; };
}

// FNV-1a over the bytes of every world coordinate of every object at time t: the benchmark
// runner (dvh-runner checksums) computes the same over its port of the scenes.
uint64_t world_checksum(xc::Scene& scene, double t) {
    uint64_t h = 0xcbf29ce484222325ULL;
    std::vector<double> local, world;
    for (auto& o : scene.objects) {
        if (o.deforms)
            o.morph.apply(o.rest.pos, t, local);
        else
            local = o.rest.pos;
        xc::apply_pose(o.motion(t), local, world);
        for (double x : world) {
            uint64_t bits;
            std::memcpy(&bits, &x, sizeof bits);
            for (int k = 0; k < 8; k++) h = (h ^ ((bits >> (8 * k)) & 0xff)) * 0x100000001b3ULL;
        }
    }
    return h;
}

}  // namespace

int main(int argc, char** argv) {
    xc::SceneOptions options;
    std::string out_dir, only;
    bool checksums = false, scene_run_only = false, self_run_only = false, distance_run_only = false;
    uint32_t threads = 0;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
            return argv[++i];
        };
        if (a == "--full") options.full = true;
        else if (a == "--frames") options.frames = std::stoi(value());
        else if (a == "--data") options.data_dir = value();
        else if (a == "--out") out_dir = value();
        else if (a == "--scene") only = value();
        else if (a == "--checksums") checksums = true;
        else if (a == "--threads") threads = (uint32_t)std::stoul(value());
        else if (a == "--scene-run-only") scene_run_only = true;
        else if (a == "--self-run-only") self_run_only = true;
        else if (a == "--distance-run-only") distance_run_only = true;
        else {
            std::fprintf(stderr,
                         "usage: %s [--full] [--frames N] [--scene NAME] [--threads N] [--scene-run-only] [--self-run-only]\n"
                         "       [--distance-run-only] [--checksums] --data DIR [--out DIR]\n",
                         argv[0]);
            return 2;
        }
    }
    if (options.data_dir.empty()) {
        std::fprintf(stderr, "--data DIR (the unpacked CGAL demo meshes) is required\n");
        return 2;
    }
    if (checksums) {
        try {
            for (auto& scene : xc::make_scenes(options)) {
                if (!only.empty() && scene.name != only) continue;
                for (int f : {0, scene.frames - 1})
                    std::printf("%s frame %d: %016llx\n", scene.name.c_str(), f,
                                (unsigned long long)world_checksum(scene, (double)f / scene.frames));
            }
        } catch (const std::exception& e) {
            std::fprintf(stderr, "error: %s\n", e.what());
            return 2;
        }
        return 0;
    }
    std::printf("dvh %s against FCL %s, judged by CGAL; %s run; dvh threaded: --threads %u%s\n", dvh::version(), FCL_VERSION,
                options.full ? "full" : "short", threads, threads == 0 ? " (every core)" : "");
    std::vector<FrameRow> all_rows;
    std::vector<Summary> sums;
    std::vector<SceneRow> scene_rows;
    std::vector<SceneSummary> scene_sums;
    std::vector<Offence> offences;
    std::vector<xc::Mismatch> whole_mismatches;  // the pairwise run's, against CGAL's exact sets
    // The --*-only flags add up: each keeps its runs.
    const bool old_runs = !distance_run_only && (!self_run_only || scene_run_only);
    const bool new_runs = !distance_run_only && (!scene_run_only || self_run_only);
    xc::SelfResults self;
    xc::ProximityResults proximity;
    xc::CurvesResults curves;
    xc::DistanceResults distance;
    try {
        auto scenes = xc::make_scenes(options);
        for (auto& scene : scenes) {
            if (!old_runs || (!only.empty() && scene.name != only)) continue;
            std::printf("== %s: %s, %d frames\n", scene.name.c_str(), scene.description.c_str(), scene.frames);
            Runs runs;
            runs.pairwise = !scene_run_only;
            // By default only where a broad phase has a choice to make: with two objects the
            // scene run would repeat the pairwise run's single pair.
            runs.scene = scene.objects.size() >= (scene_run_only ? 2 : 3);
            if (runs.pairwise) runs.whole_set = whole_set_frames(scene, options.full);
            auto rows = run_scene(scene, threads, runs, offences, whole_mismatches, scene_rows);
            if (runs.pairwise) sums.push_back(summarize(scene, rows));
            if (runs.scene) scene_sums.push_back(summarize_scene_run(scene.name, scene_rows));
            all_rows.insert(all_rows.end(), rows.begin(), rows.end());
        }
        if (new_runs) {
            xc::RunOptions run_options{options, only, threads};
            self = xc::run_self(run_options);
            proximity = xc::run_proximity(run_options);
        }
        if (!scene_run_only && !self_run_only && !distance_run_only) curves = xc::run_curves(xc::RunOptions{options, only, threads});
        if ((!scene_run_only && !self_run_only) || distance_run_only)
            distance = xc::run_distance(xc::RunOptions{options, only, threads});
    } catch (const dvh::Error& e) {
        std::fprintf(stderr, "error: dvh: %s: %s\n", dvh::status_name(e.status()), e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }

    bool ok = true;
    if (!sums.empty()) {
        std::printf("\nSummary (medians per frame, ms; dvh 1t on one thread, dvh Nt threaded, posed threaded; ratio = faster FCL\n"
                    "configuration / dvh on one thread; speed-up = dvh 1t / dvh Nt)\n");
        std::printf("%-10s %6s %10s %9s %8s %9s %9s %9s %9s %9s %9s %9s %9s %7s %8s\n", "scene", "frames", "pairs", "disagree",
                    "judged", "dvh wrong", "obb wrong", "aabb wrng", "dvh 1t", "dvh Nt", "dvh posed", "fcl obb", "fcl aabb", "ratio",
                    "speed-up");
    }
    for (const auto& s : sums) {
        double best = std::min(s.obb, s.aabb);
        std::printf("%-10s %6d %10zu %9zu %8zu %9zu %9zu %9zu %9.3f %9.3f %9.3f %9.3f %9.3f %6.1fx %7.2fx\n", s.scene.c_str(),
                    s.frames, s.pairs_compared, s.disagreements, s.judged, s.dvh_wrong, s.obb_wrong, s.aabb_wrong, s.one, s.dvh,
                    s.posed, s.obb, s.aabb, s.one > 0 ? best / s.one : 0.0, s.dvh > 0 ? s.one / s.dvh : 0.0);
        ok = ok && s.dvh_wrong == 0 && s.posed_mismatch == 0 && s.threads_mismatch == 0;
        if (s.threads_mismatch != 0)
            std::printf("  %s: dvh threaded differs from dvh on one thread on %zu pairs\n", s.scene.c_str(), s.threads_mismatch);
        if (s.posed_mismatch != 0)
            std::printf("  %s: dvh with poses differs from dvh with world coordinates on %zu pairs\n", s.scene.c_str(), s.posed_mismatch);
    }
    bool reference_ok = true;
    for (const auto& s : sums) {
        if (s.whole_frames > 0)
            std::printf("whole-set judge: scene %s, %d frames, %zu pairs (CGAL's exact set), %zu differences (dvh-only %zu, exact-only %zu; FCL obb "
                        "differs on %zu, aabb on %zu; %zu candidates, %.1f ms)\n",
                        s.scene.c_str(), s.whole_frames, s.exact_pairs, s.whole_differences(), s.exact_dvh_only, s.exact_only,
                        s.exact_obb_diff, s.exact_aabb_diff, s.exact_candidates, s.exact_ms);
        ok = ok && s.whole_differences() == 0;
        if (s.whole_differences() != 0)
            std::printf("  %s: dvh's whole set differs from CGAL's exact set on %zu pairs (%zu dvh's alone, %zu the exact set's alone; "
                        "the first are listed below)\n",
                        s.scene.c_str(), s.whole_differences(), s.exact_dvh_only, s.exact_only);
        if (s.reference_broken != 0) {
            std::printf("  %s: the exact set contradicts the judge on %zu pairs\n", s.scene.c_str(), s.reference_broken);
            reference_ok = false;
        }
    }
    if (!scene_sums.empty()) {
        std::printf("\nSummary of the scene runs (every object in one DvhScene: set_positions + dvh_scene_collide on one thread;\n"
                    "FCL: each configuration's models in a DynamicAABBTreeCollisionManager, replace + refit + boxes + manager update\n"
                    "+ collide. Medians per frame: object pairs colliding and tested by each broad phase, contacts, ms; the other\n"
                    "counts over every frame; pairwise = contacts differing from dvh pair by pair; ratio = faster FCL / dvh)\n");
        std::printf("%-10s %6s %9s %8s %8s %9s %8s %7s %8s %9s %9s %9s %8s %9s %9s %9s %7s\n", "scene", "frames", "colliding",
                    "test dvh", "test fcl", "contacts", "disagree", "judged", "cgal dvh", "dvh wrong", "obb wrong", "aabb wrng",
                    "pairwise", "dvh", "fcl obb", "fcl aabb", "ratio");
    }
    for (const auto& s : scene_sums) {
        double best = std::min(s.obb, s.aabb);
        std::printf("%-10s %6d %9.0f %8.0f %8.0f %9.0f %8zu %7zu %8zu %9zu %9zu %9zu %8s %9.3f %9.3f %9.3f %6.1fx\n", s.scene.c_str(),
                    s.frames, s.colliding, s.dvh_tested, s.fcl_tested, s.contacts, s.disagreements, s.judged, s.cgal_with_dvh,
                    s.dvh_wrong, s.obb_wrong, s.aabb_wrong, s.pairwise_checked ? std::to_string(s.pairwise_mismatch).c_str() : "-",
                    s.dvh, s.obb, s.aabb, s.dvh > 0 ? best / s.dvh : 0.0);
        ok = ok && s.dvh_wrong == 0 && s.pairwise_mismatch == 0 && s.threads_mismatch == 0;
        if (s.threads_mismatch != 0)
            std::printf("  %s: the threaded scene differs from the scene on one thread on %zu contacts\n", s.scene.c_str(),
                        s.threads_mismatch);
        if (s.pairwise_mismatch != 0)
            std::printf("  %s: the scene differs from dvh pair by pair on %zu contacts\n", s.scene.c_str(), s.pairwise_mismatch);
    }
    ok = xc::report_self(self, reference_ok) && ok;
    ok = xc::report_proximity(proximity, reference_ok) && ok;
    ok = xc::report_curves(curves) && ok;
    ok = xc::report_distance(distance) && ok;
    if (!out_dir.empty()) {
        if (old_runs) write_outputs(out_dir, all_rows, sums, scene_rows, scene_sums);
        if (new_runs) {
            xc::write_self_outputs(out_dir, self);
            xc::write_proximity_outputs(out_dir, proximity);
        }
        if (!curves.rows.empty()) xc::write_curves_outputs(out_dir, curves);
        if (!distance.rows.empty()) xc::write_distance_outputs(out_dir, distance);
    }
    for (const auto& o : offences) {
        std::printf("\nDVH DISAGREES WITH CGAL: scene %s frame %d (%s), triangles %u and %u: dvh says %s, CGAL says %s\n",
                    o.scene.c_str(), o.frame, o.objects.c_str(), o.a, o.b, o.dvh ? "intersect" : "apart",
                    o.cgal ? "intersect" : "apart");
        for (int c = 0; c < 3; c++) std::printf("  a[%d] = (%.17g, %.17g, %.17g)\n", c, o.ta[3 * c], o.ta[3 * c + 1], o.ta[3 * c + 2]);
        for (int c = 0; c < 3; c++) std::printf("  b[%d] = (%.17g, %.17g, %.17g)\n", c, o.tb[3 * c], o.tb[3 * c + 1], o.tb[3 * c + 2]);
    }
    std::vector<xc::Mismatch> mismatches = whole_mismatches;
    mismatches.insert(mismatches.end(), self.mismatches.begin(), self.mismatches.end());
    mismatches.insert(mismatches.end(), proximity.mismatches.begin(), proximity.mismatches.end());
    const bool exact_sets = new_runs || !sums.empty();  // some run compared dvh with exact sets
    xc::report_mismatches(mismatches, out_dir.empty() || !exact_sets ? "" : out_dir + "/mismatches.txt");
    if (!reference_ok) {
        std::printf("\nVERDICT: UNDECIDED, the exact reference contradicts itself (a bug of the harness)\n");
        return 2;
    }
    if (!ok) {
        std::printf("\nVERDICT: FAILED\n");
        return 1;
    }
    std::vector<std::string> exact;  // what equals CGAL's exact sets
    if (std::any_of(sums.begin(), sums.end(), [](const Summary& s) { return s.whole_frames > 0; }))
        exact.push_back("whole sets where compared");
    if (new_runs) exact.push_back("self-collisions and pairs within a distance");
    std::string also;
    for (size_t k = 0; k < exact.size(); k++) also += (k == 0 ? "; its " : ", ") + exact[k];
    if (!also.empty()) also += " are CGAL's exact sets";
    std::printf("\nVERDICT: dvh agrees with CGAL on every judged pair, threaded or not, pair by pair or as a scene%s\n",
                also.c_str());
    return 0;
}

namespace xc {

void report_mismatches(const std::vector<Mismatch>& mismatches, const std::string& path) {
    auto write = [](std::FILE* out, const Mismatch& m) {
        std::fprintf(out, "\nDVH DIFFERS FROM THE EXACT SET: %s run, scene %s frame %d (%s)%s, triangles %u (%u %u %u) and %u (%u %u %u)%s: "
                     "dvh says %s, CGAL says %s\n",
                     m.run.c_str(), m.scene.c_str(), m.frame, m.objects.c_str(),
                     m.distance > 0 ? (", distance " + std::to_string(m.distance)).c_str() : "", m.a, m.ia[0], m.ia[1], m.ia[2],
                     m.b, m.ib[0], m.ib[1], m.ib[2], m.adjacent ? ", sharing a vertex" : "", m.dvh ? "in" : "out",
                     m.exact ? "in" : "out");
        if (m.distance > 0) std::fprintf(out, "  distance = %.17g\n", m.distance);
        for (int c = 0; c < 3; c++) std::fprintf(out, "  a[%d] = (%.17g, %.17g, %.17g)\n", c, m.ta[3 * c], m.ta[3 * c + 1], m.ta[3 * c + 2]);
        for (int c = 0; c < 3; c++) std::fprintf(out, "  b[%d] = (%.17g, %.17g, %.17g)\n", c, m.tb[3 * c], m.tb[3 * c + 1], m.tb[3 * c + 2]);
    };
    for (size_t k = 0; k < mismatches.size() && k < 20; k++) write(stdout, mismatches[k]);
    if (path.empty()) return;
    std::FILE* out = std::fopen(path.c_str(), "w");
    if (out == nullptr) return;
    for (const auto& m : mismatches) write(out, m);
    std::fclose(out);
    if (!mismatches.empty()) std::printf("\n(%zu mismatches kept in %s)\n", mismatches.size(), path.c_str());
}

}  // namespace xc
