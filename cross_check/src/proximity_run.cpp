// The proximity run: every triangle pair within a distance, at 0, 0.1%, 1% and 5% of the
// diagonal of the box around a scene's objects at its first frame, exactly.
//
// Pairs of objects: scenes of the pairwise run, moving and deforming as there, at their short
// sizes whatever the mode (the pairs within 5% grow with the square of the resolution): coplanar,
// copy and near-1e-09 in the short run, every scene with --full (large: millions of pairs). Per
// frame and distance, dvh_proximity on world coordinates (on one thread, and with `--threads N`),
// and on local coordinates with the poses as DvhPose; all three must be equal. Per frame,
// dvh_proximity at distance 0 must equal dvh_collide.
//
// One mesh: the small self-collision scenes (at most 10,000 triangles), towards and at their most
// bent. dvh_self_proximity on one thread and threaded; at distance 0 it must equal
// dvh_self_collide's pairs of triangles sharing no vertex.
//
// The reference: CGAL::box_intersection_d over the triangles' boxes grown by the distance
// (rounded outwards), then each candidate decided exactly (exact.hpp: interval arithmetic, and
// rationals where it cannot tell). dvh must equal it pair for pair. FCL has no query for every
// pair within a distance; its OBBRSS collide time on the same frame (update + collide, or the
// mesh against itself) is reported for scale, with the reference's time (on every core).

#include <dvh.hpp>
#include <fcl/fcl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "common.hpp"
#include "exact.hpp"
#include "fcl_side.hpp"
#include "runs.hpp"

namespace xc {

namespace {

const double kFractions[] = {0.0, 0.001, 0.01, 0.05};
const size_t kKeep = 200;  // mismatches kept for the report
const size_t kMaxSelfTriangles = 10000;
const size_t kDistanceSample = 8;  // pairs of the exact set, and candidates, whose distance is computed both ways

// The diagonal of the box around every object.
double diagonal(const std::vector<std::vector<double>>& world) {
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const auto& w : world)
        for (size_t i = 0; i < w.size(); i++) {
            lo[i % 3] = std::min(lo[i % 3], w[i]);
            hi[i % 3] = std::max(hi[i % 3], w[i]);
        }
    return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

// The reference checked on a sample: pairs of its set and of the box filter's candidates, each
// exact squared distance computed both ways (exact.hpp).
void check_distances(const PairSet& exact, const PairSet& candidates, const MeshData& ma, const std::vector<double>& pa,
                     const MeshData& mb, const std::vector<double>& pb, ProximityRow& row) {
    for (const PairSet* set : {&exact, &candidates})
        for (uint64_t k : spread_sample(*set, kDistanceSample)) {
            double ta[9], tb[9];
            triangle(ma, pa, (uint32_t)(k >> 32), ta);
            triangle(mb, pb, (uint32_t)k, tb);
            row.distance_checked++;
            if (!cgal_distances_agree(ta, tb)) row.reference_broken++;
        }
}

// dvh's pairs against the reference's: counts in `row`, the differences kept in `out`.
void compare(const PairSet& dvh, const PairSet& exact, const MeshData& ma, const std::vector<double>& pa, const MeshData& mb,
             const std::vector<double>& pb, const std::string& scene, const std::string& objects, bool self, ProximityRow& row,
             ProximityResults& out) {
    for (uint64_t k : symmetric_difference(dvh, exact)) {
        Mismatch x;
        x.run = self ? "self proximity" : "proximity";
        x.scene = scene;
        x.objects = objects;
        x.frame = row.frame;
        x.distance = row.distance;
        x.a = (uint32_t)(k >> 32);
        x.b = (uint32_t)k;
        std::copy(&ma.tris[3 * (size_t)x.a], &ma.tris[3 * (size_t)x.a] + 3, x.ia);
        std::copy(&mb.tris[3 * (size_t)x.b], &mb.tris[3 * (size_t)x.b] + 3, x.ib);
        triangle(ma, pa, x.a, x.ta);
        triangle(mb, pb, x.b, x.tb);
        x.dvh = contains(dvh, k);
        x.exact = !x.dvh;
        x.adjacent = self && share_vertex(ma, x.a, x.b);
        (x.dvh ? row.dvh_only : row.exact_only)++;
        if (out.mismatches.size() < kKeep) out.mismatches.push_back(x);
    }
}

// A count, or "-" when it does not apply (negative).
std::string count(long n) { return n < 0 ? "-" : std::to_string(n); }

void print_row(const ProximityRow& r) {
    char posed[32] = "-";
    if (r.kind != "self") std::snprintf(posed, sizeof posed, "%.2f", r.posed_query);
    std::printf("%-10s %4d %5.1f%% d %-9.3g %s: pairs dvh %7zu exact %7zu | dvh-only %zu exact-only %zu | posed diff %s threads "
                "diff %zu at 0: %s | candidates %7zu rational %zu | ms dvh 1 thread %.2f threaded %.2f posed %s exact %.1f "
                "(refit %.2f, fcl collide %.2f)\n",
                r.scene.c_str(), r.frame, 100 * r.fraction, r.distance, r.kind == "self" ? "self-proximity" : "proximity",
                r.dvh_pairs, r.exact_pairs, r.dvh_only, r.exact_only, count(r.posed_mismatch).c_str(), r.threads_mismatch,
                count(r.zero_mismatch).c_str(), r.candidates, r.rational, r.dvh_query, r.dvh_threaded, posed, r.exact_ms, r.refit,
                r.fcl);
    if (r.reference_broken != 0)
        std::printf("  REFERENCE BROKEN: %zu of %zu sampled pairs with two different exact distances\n", r.reference_broken,
                    r.distance_checked);
    std::fflush(stdout);
}

PairSet proximity(const dvh::Mesh& a, const DvhPose* pa, const dvh::Mesh& b, const DvhPose* pb, double distance,
                  const dvh::QueryOptions& query, dvh::Pairs& pairs, DvhQueryStats* stats) {
    const DvhQueryStats got = dvh::proximity(a, pa, b, pb, distance, query, pairs);
    if (stats != nullptr) *stats = got;
    if (got.truncated) throw std::runtime_error("dvh_proximity truncated its result");
    return to_set(pairs);
}

PairSet self_proximity(const dvh::Mesh& mesh, double distance, const dvh::QueryOptions& query, dvh::Pairs& pairs,
                       DvhQueryStats* stats) {
    const DvhQueryStats got = dvh::self_proximity(mesh, distance, query, pairs);
    if (stats != nullptr) *stats = got;
    if (got.truncated) throw std::runtime_error("dvh_self_proximity truncated its result");
    return to_set(pairs);
}

struct Setup {
    dvh::BuildOptions one, many;
    dvh::QueryOptions query_one, query_many;
    explicit Setup(uint32_t threads) {
        one.refit_threads(1);
        many.refit_threads(threads);
        query_one.threads(1);
        query_many.threads(threads);
    }
};

// A scene of the pairwise run, every object pair it tests.
void run_pairs(Scene& scene, int frames, uint32_t threads, ProximityResults& out) {
    const size_t n = scene.objects.size();
    std::vector<std::vector<double>> local(n), world(n);
    std::vector<std::vector<fcl::Vector3d>> fcl_world(n);
    std::vector<DvhPose> poses(n);
    auto place = [&](double t) {
        for (size_t i = 0; i < n; i++) {
            poses[i] = to_dvh(place_object(scene.objects[i], t, local[i], world[i]));
            to_fcl(world[i], fcl_world[i]);
        }
    };
    place(0.0);
    const double diag = diagonal(world);
    Setup setup(threads);
    std::vector<dvh::Mesh> one, many, posed;
    FclSide<fcl::OBBRSSd> obb;
    for (size_t i = 0; i < n; i++) {
        const auto& m = scene.objects[i].rest;
        one.emplace_back(world[i].data(), m.vertices(), m.tris.data(), m.triangles(), setup.one);
        many.emplace_back(world[i].data(), m.vertices(), m.tris.data(), m.triangles(), setup.many);
        posed.emplace_back(local[i].data(), m.vertices(), m.tris.data(), m.triangles(), setup.many);
        obb.build(m.tris.data(), m.triangles(), fcl_world[i]);
    }
    dvh::Pairs pairs;

    for (int f = 0; f < frames; f++) {
        const double t = (double)f / frames;  // the scenes' own clock, as in the pairwise run
        place(t);
        auto t0 = Clock::now();
        for (size_t i = 0; i < n; i++) one[i].refit(world[i].data(), scene.objects[i].rest.vertices());
        const double refit = ms_since(t0);
        for (size_t i = 0; i < n; i++) {
            many[i].refit(world[i].data(), scene.objects[i].rest.vertices());
            posed[i].refit(local[i].data(), scene.objects[i].rest.vertices());
        }
        t0 = Clock::now();
        for (size_t i = 0; i < n; i++) obb.update(i, fcl_world[i]);
        for (auto [i, j] : scene.pairs) obb.collide(i, j);
        const double fcl = ms_since(t0);
        std::vector<PairSet> collide(scene.pairs.size());
        for (size_t p = 0; p < scene.pairs.size(); p++) {
            auto [i, j] = scene.pairs[p];
            dvh::collide(one[i], nullptr, one[j], nullptr, setup.query_one, pairs);
            collide[p] = to_set(pairs);
        }

        for (double fraction : kFractions) {
            ProximityRow row;
            row.kind = "pair";
            row.scene = scene.name;
            row.frame = f;
            row.t = t;
            row.fraction = fraction;
            row.distance = fraction * diag;
            row.refit = refit;
            row.fcl = fcl;
            row.posed_mismatch = 0;
            if (fraction == 0) row.zero_mismatch = 0;
            for (size_t p = 0; p < scene.pairs.size(); p++) {
                auto [i, j] = scene.pairs[p];
                const auto& mi = scene.objects[i].rest;
                const auto& mj = scene.objects[j].rest;
                t0 = Clock::now();
                DvhQueryStats stats;
                PairSet dvh = proximity(one[i], nullptr, one[j], nullptr, row.distance, setup.query_one, pairs, &stats);
                row.dvh_query += ms_since(t0);
                row.triangle_tests += stats.triangle_tests;
                t0 = Clock::now();
                PairSet threaded = proximity(many[i], nullptr, many[j], nullptr, row.distance, setup.query_many, pairs, nullptr);
                row.dvh_threaded += ms_since(t0);
                t0 = Clock::now();
                PairSet with_poses = proximity(posed[i], &poses[i], posed[j], &poses[j], row.distance, setup.query_many, pairs, nullptr);
                row.posed_query += ms_since(t0);
                t0 = Clock::now();
                WithinCounts counts;
                PairSet exact = exact_pairs_within(mi, world[i], mj, world[j], row.distance, counts);
                row.exact_ms += ms_since(t0);
                row.candidates += counts.candidates;
                row.rational += counts.exact;
                check_distances(exact, counts.sample, mi, world[i], mj, world[j], row);
                row.dvh_pairs += dvh.size();
                row.exact_pairs += exact.size();
                row.threads_mismatch += symmetric_difference(dvh, threaded).size();
                row.posed_mismatch += (long)symmetric_difference(dvh, with_poses).size();
                if (fraction == 0) row.zero_mismatch += (long)symmetric_difference(dvh, collide[p]).size();
                compare(dvh, exact, mi, world[i], mj, world[j], scene.name,
                        scene.objects[i].name + " x " + scene.objects[j].name, false, row, out);
            }
            print_row(row);
            out.rows.push_back(row);
        }
    }
}

// One bending mesh against itself.
void run_self(SelfScene& s, int frames, uint32_t threads, ProximityResults& out) {
    const MeshData& m = s.rest;
    std::vector<double> pos;
    std::vector<fcl::Vector3d> fpos(m.vertices());
    auto place = [&](double t) {
        s.at(t, pos);
        for (size_t v = 0; v < fpos.size(); v++) fpos[v] = fcl::Vector3d(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]);
    };
    place(0.0);
    const double diag = diagonal({pos});
    Setup setup(threads);
    dvh::Mesh one(pos.data(), m.vertices(), m.tris.data(), m.triangles(), setup.one);
    dvh::Mesh many(pos.data(), m.vertices(), m.tris.data(), m.triangles(), setup.many);
    FclSide<fcl::OBBRSSd> obb;
    obb.build(m.tris.data(), m.triangles(), fpos);
    dvh::Pairs pairs;

    for (int f = 0; f < frames; f++) {
        const double t = (double)(f + 1) / frames;  // towards the most bent, which is the last frame
        place(t);
        auto t0 = Clock::now();
        one.refit(pos.data(), m.vertices());
        const double refit = ms_since(t0);
        many.refit(pos.data(), m.vertices());
        t0 = Clock::now();
        obb.update(0, fpos);
        fcl_self(obb, m);
        const double fcl = ms_since(t0);
        dvh::self_collide(one, setup.query_one, pairs);
        PairSet separate;  // dvh_self_collide's pairs of triangles sharing no vertex
        for (uint64_t k : to_set(pairs))
            if (!share_vertex(m, (uint32_t)(k >> 32), (uint32_t)k)) separate.push_back(k);

        for (double fraction : kFractions) {
            ProximityRow row;
            row.kind = "self";
            row.scene = s.name;
            row.frame = f;
            row.t = t;
            row.fraction = fraction;
            row.distance = fraction * diag;
            row.refit = refit;
            row.fcl = fcl;
            t0 = Clock::now();
            DvhQueryStats stats;
            PairSet dvh = self_proximity(one, row.distance, setup.query_one, pairs, &stats);
            row.dvh_query = ms_since(t0);
            row.triangle_tests = stats.triangle_tests;
            t0 = Clock::now();
            PairSet threaded = self_proximity(many, row.distance, setup.query_many, pairs, nullptr);
            row.dvh_threaded = ms_since(t0);
            t0 = Clock::now();
            WithinCounts counts;
            PairSet exact = exact_self_pairs_within(m, pos, row.distance, counts);
            row.exact_ms = ms_since(t0);
            row.candidates = counts.candidates;
            row.rational = counts.exact;
            check_distances(exact, counts.sample, m, pos, m, pos, row);
            row.dvh_pairs = dvh.size();
            row.exact_pairs = exact.size();
            row.threads_mismatch = symmetric_difference(dvh, threaded).size();
            if (fraction == 0) row.zero_mismatch = (long)symmetric_difference(dvh, separate).size();
            compare(dvh, exact, m, pos, m, pos, s.name, s.name, true, row, out);
            print_row(row);
            out.rows.push_back(row);
        }
    }
}

void summarize(const std::string& kind, const std::string& scene, ProximityResults& out) {
    for (double fraction : kFractions) {
        ProximitySummary s;
        s.kind = kind;
        s.scene = scene;
        s.fraction = fraction;
        std::vector<double> dvh, threaded, posed, exact, fcl;
        for (const auto& r : out.rows) {
            if (r.kind != kind || r.scene != scene || r.fraction != fraction) continue;
            s.frames++;
            s.distance = r.distance;
            s.pairs += r.dvh_pairs;
            s.dvh_wrong += r.dvh_only + r.exact_only;
            if (r.posed_mismatch > 0) s.posed_mismatch += (size_t)r.posed_mismatch;
            if (r.zero_mismatch > 0) s.zero_mismatch += (size_t)r.zero_mismatch;
            s.threads_mismatch += r.threads_mismatch;
            s.reference_broken += r.reference_broken;
            dvh.push_back(r.dvh_query);
            threaded.push_back(r.dvh_threaded);
            posed.push_back(r.posed_query);
            exact.push_back(r.exact_ms);
            fcl.push_back(r.fcl);
        }
        s.dvh = median(dvh);
        s.threaded = median(threaded);
        s.posed = median(posed);
        s.exact = median(exact);
        s.fcl = median(fcl);
        out.sums.push_back(s);
    }
}

}  // namespace

ProximityResults run_proximity(const RunOptions& options) {
    ProximityResults out;
    SceneOptions small = options.scenes;
    small.full = false;
    const int frames = options.scenes.frames > 0 ? options.scenes.frames : (options.scenes.full ? 10 : 2);
    for (auto& scene : make_scenes(small)) {
        bool chosen = options.only.empty()
                          ? options.scenes.full || scene.name == "coplanar" || scene.name == "copy" || scene.name == "near-1e-09"
                          : scene.name == options.only;
        if (!chosen) continue;
        std::printf("== %s (proximity): %s, %d frames\n", scene.name.c_str(), scene.description.c_str(), frames);
        run_pairs(scene, frames, options.threads, out);
        summarize("pair", scene.name, out);
    }
    for (auto& s : make_self_scenes(small)) {
        if (s.rest.triangles() > kMaxSelfTriangles || (!options.only.empty() && s.name != options.only)) continue;
        std::printf("== %s (self-proximity): %s, %d frames\n", s.name.c_str(), s.description.c_str(), frames);
        run_self(s, frames, options.threads, out);
        summarize("self", s.name, out);
    }
    return out;
}

bool report_proximity(const ProximityResults& results, bool& reference_ok) {
    if (results.sums.empty()) return true;
    std::printf("\nSummary of the proximity runs (every triangle pair within the distance, a fraction of the diagonal of the\n"
                "box around the objects at the first frame; pair: dvh_proximity over the scene's object pairs, self:\n"
                "dvh_self_proximity, pairs sharing a vertex excluded. Pairs are dvh's over every frame; wrong = differing from\n"
                "the exact set; posed, threads = differing from dvh on one thread in world coordinates; at 0 = dvh_proximity at\n"
                "distance 0 differing from dvh_collide (self: dvh_self_collide's pairs sharing no vertex). Medians per frame,\n"
                "ms, queries only; fcl = FCL OBBRSS update + collide of the same frame, for scale; exact = the reference)\n");
    std::printf("%-5s %-10s %6s %10s %6s %9s %7s %7s %7s %7s %9s %9s %9s %9s %9s\n", "kind", "scene", "dist", "distance",
                "frames", "pairs", "wrong", "posed", "threads", "at 0", "dvh 1t", "dvh Nt", "dvh posed", "exact", "fcl");
    bool ok = true;
    for (const auto& s : results.sums) {
        const bool self = s.kind == "self";
        char posed[32] = "-";
        if (!self) std::snprintf(posed, sizeof posed, "%.3f", s.posed);
        std::printf("%-5s %-10s %5.1f%% %10.3g %6d %9zu %7zu %7s %7zu %7s %9.3f %9.3f %9s %9.1f %9.3f\n", s.kind.c_str(),
                    s.scene.c_str(), 100 * s.fraction, s.distance, s.frames, s.pairs, s.dvh_wrong,
                    count(self ? -1 : (long)s.posed_mismatch).c_str(), s.threads_mismatch,
                    count(s.fraction == 0 ? (long)s.zero_mismatch : -1).c_str(), s.dvh, s.threaded, posed, s.exact, s.fcl);
        ok = ok && s.dvh_wrong == 0 && s.posed_mismatch == 0 && s.threads_mismatch == 0 && s.zero_mismatch == 0;
        if (s.reference_broken != 0) {
            std::printf("  %s at %.1f%%: the exact reference contradicts itself on %zu pairs\n", s.scene.c_str(), 100 * s.fraction,
                        s.reference_broken);
            reference_ok = false;
        }
    }
    return ok;
}

void write_proximity_outputs(const std::string& dir, const ProximityResults& results) {
    // Distances with every digit (they are the queries' arguments), times as usual.
    auto exactly = [](double x) {
        char text[32];
        std::snprintf(text, sizeof text, "%.17g", x);
        return std::string(text);
    };
    std::ofstream csv(dir + "/proximity_frames.csv");
    csv << "kind,scene,frame,t,fraction,distance,dvh_pairs,exact_pairs,candidates,rational_decisions,dvh_only,exact_only,"
           "posed_mismatch,threads_mismatch,zero_distance_mismatch,distances_checked,reference_broken,dvh_triangle_tests,dvh_query_ms,dvh_threaded_ms,dvh_posed_ms,"
           "exact_ms,one_thread_refit_ms,fcl_obbrss_collide_ms\n";
    for (const auto& r : results.rows) {
        csv << r.kind << ',' << r.scene << ',' << r.frame << ',' << r.t << ',' << r.fraction << ',' << exactly(r.distance) << ','
            << r.dvh_pairs << ',' << r.exact_pairs << ',' << r.candidates << ',' << r.rational << ',' << r.dvh_only << ','
            << r.exact_only << ',';
        if (r.posed_mismatch >= 0) csv << r.posed_mismatch;  // empty: no poses (self)
        csv << ',' << r.threads_mismatch << ',';
        if (r.zero_mismatch >= 0) csv << r.zero_mismatch;  // empty: distance above 0
        csv << ',' << r.distance_checked << ',' << r.reference_broken << ',' << r.triangle_tests << ',' << r.dvh_query << ',' << r.dvh_threaded << ',';
        if (r.kind != "self") csv << r.posed_query;
        csv << ',' << r.exact_ms << ',' << r.refit << ',' << r.fcl << '\n';
    }
    std::ofstream json(dir + "/proximity_summary.json");
    json << "[\n";
    for (size_t k = 0; k < results.sums.size(); k++) {
        const auto& s = results.sums[k];
        json << "  {\"kind\": \"" << s.kind << "\", \"scene\": \"" << s.scene << "\", \"fraction\": " << s.fraction
             << ", \"distance\": " << exactly(s.distance) << ", \"frames\": " << s.frames << ", \"pairs\": " << s.pairs
             << ", \"dvh_wrong\": " << s.dvh_wrong << ", \"posed_mismatch\": ";
        if (s.kind == "self")
            json << "null";
        else
            json << s.posed_mismatch;
        json << ", \"threads_mismatch\": " << s.threads_mismatch << ", \"zero_distance_mismatch\": ";
        if (s.fraction == 0)
            json << s.zero_mismatch;
        else
            json << "null";
        json << ", \"reference_broken\": " << s.reference_broken << ", \"median_ms\": {\"dvh_one_thread\": " << s.dvh << ", \"dvh\": " << s.threaded << ", \"dvh_posed\": ";
        if (s.kind == "self")
            json << "null";
        else
            json << s.posed;
        json << ", \"exact_reference\": " << s.exact << ", \"fcl_obbrss_collide\": " << s.fcl << "}}"
             << (k + 1 < results.sums.size() ? "," : "") << "\n";
    }
    json << "]\n";
}

}  // namespace xc
