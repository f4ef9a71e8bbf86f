// The self-collision run: each mesh of make_self_scenes bends frame by frame until it passes
// through itself. Per frame, dvh refits and calls dvh_self_collide (on one thread, and with
// `--threads N`; both must agree). FCL, the naive route, collides the mesh's BVHModel (OBBRSS and
// AABB, replace + refit, identity transforms, every contact) with itself and keeps the pairs
// a < b of triangles sharing no vertex index (for the others FCL's answer means nothing: they
// touch at least at the shared vertex). CGAL gives the exact set: for pairs sharing a vertex,
// whether they meet beyond what they share (exact.hpp); for the others, every pair whose boxes
// overlap tested by the judge. dvh must equal it pair for pair; the pairs on which dvh and FCL
// disagree, and a sample of those they agree on, are also judged one by one, as in the pairwise
// run, and must agree with the exact set.

#include <dvh.hpp>
#include <fcl/fcl.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "common.hpp"
#include "exact.hpp"
#include "fcl_side.hpp"
#include "judge.hpp"
#include "runs.hpp"

namespace xc {

namespace {

const size_t kSample = 20;   // agreed pairs judged per frame
const size_t kKeep = 200;    // mismatches kept for the report

PairSet dvh_self(const dvh::Mesh& mesh, const dvh::QueryOptions& query, dvh::Pairs& pairs, DvhQueryStats* stats) {
    const DvhQueryStats got = dvh::self_collide(mesh, query, pairs);
    if (stats != nullptr) *stats = got;
    if (got.truncated) throw std::runtime_error("dvh_self_collide truncated its result");
    return to_set(pairs);
}

void run_scene(SelfScene& s, uint32_t threads, SelfResults& out) {
    const MeshData& m = s.rest;
    std::vector<double> pos;
    std::vector<fcl::Vector3d> fpos(m.vertices());
    auto place = [&](double t) {
        s.at(t, pos);
        for (size_t v = 0; v < fpos.size(); v++) fpos[v] = fcl::Vector3d(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]);
    };
    place(0.0);
    const dvh::QueryOptions query_one = dvh::QueryOptions{}.threads(1), query_many = dvh::QueryOptions{}.threads(threads);
    dvh::Mesh one(pos.data(), m.vertices(), m.tris.data(), m.triangles(), dvh::BuildOptions{}.refit_threads(1));
    dvh::Mesh threaded(pos.data(), m.vertices(), m.tris.data(), m.triangles(), dvh::BuildOptions{}.refit_threads(threads));
    FclSide<fcl::OBBRSSd> obb;
    FclSide<fcl::AABBd> aabb;
    obb.build(m.tris.data(), m.triangles(), fpos);
    aabb.build(m.tris.data(), m.triangles(), fpos);
    dvh::Pairs pairs;

    for (int f = 0; f < s.frames; f++) {
        SelfRow row;
        row.scene = s.name;
        row.frame = f;
        row.t = s.frames > 1 ? (double)f / (s.frames - 1) : 0.0;
        row.triangles = m.triangles();
        place(row.t);

        auto t0 = Clock::now();
        one.refit(pos.data(), m.vertices());
        row.one_refit = ms_since(t0);
        t0 = Clock::now();
        DvhQueryStats stats;
        PairSet dvh = dvh_self(one, query_one, pairs, &stats);
        row.one_query = ms_since(t0);
        row.triangle_tests = stats.triangle_tests;
        t0 = Clock::now();
        threaded.refit(pos.data(), m.vertices());
        row.dvh_refit = ms_since(t0);
        t0 = Clock::now();
        PairSet dvh_many = dvh_self(threaded, query_many, pairs, nullptr);
        row.dvh_query = ms_since(t0);
        row.threads_mismatch = symmetric_difference(dvh, dvh_many).size();

        t0 = Clock::now();
        obb.update(0, fpos);
        row.obb_update = ms_since(t0);
        t0 = Clock::now();
        PairSet so = fcl_self(obb, m);
        row.obb_query = ms_since(t0);
        t0 = Clock::now();
        aabb.update(0, fpos);
        row.aabb_update = ms_since(t0);
        t0 = Clock::now();
        PairSet sa = fcl_self(aabb, m);
        row.aabb_query = ms_since(t0);

        t0 = Clock::now();
        AdjacentCounts counts;
        PairSet exact_adjacent = exact_adjacent_self_pairs(m, pos, counts);
        row.exact_adjacent_ms = ms_since(t0);
        t0 = Clock::now();
        PairSet exact_separate = exact_separate_self_pairs(m, pos, row.separate_candidates);
        row.exact_separate_ms = ms_since(t0);
        PairSet exact;
        std::merge(exact_adjacent.begin(), exact_adjacent.end(), exact_separate.begin(), exact_separate.end(),
                   std::back_inserter(exact));
        row.adjacent_tested = counts.pairs;
        row.adjacent_checked = counts.checked;
        row.adjacent_degenerate = counts.degenerate;
        row.reference_broken = counts.check_failed;

        PairSet dvh_separate;
        for (uint64_t k : dvh)
            if (share_vertex(m, (uint32_t)(k >> 32), (uint32_t)k))
                row.dvh_adjacent++;
            else
                dvh_separate.push_back(k);
        row.dvh_pairs = dvh.size();
        row.exact_pairs = exact.size();
        row.exact_adjacent = exact_adjacent.size();
        row.obb_pairs = so.size();
        row.aabb_pairs = sa.size();
        row.dvh_only_obb = difference(dvh_separate, so).size();
        row.obb_only = difference(so, dvh_separate).size();
        row.dvh_only_aabb = difference(dvh_separate, sa).size();
        row.aabb_only = difference(sa, dvh_separate).size();
        row.obb_wrong = symmetric_difference(so, exact_separate).size();
        row.aabb_wrong = symmetric_difference(sa, exact_separate).size();

        // The pairwise run's judgement, on the pairs sharing no vertex: every disagreement between
        // dvh and FCL and a sample of the agreements, each by CGAL's judge, which must also agree
        // with the exact set (built from the same judge over a box filter).
        PairSet disputed = symmetric_difference(dvh_separate, so), more = symmetric_difference(dvh_separate, sa), agreed;
        disputed.insert(disputed.end(), more.begin(), more.end());
        std::sort(disputed.begin(), disputed.end());
        disputed.erase(std::unique(disputed.begin(), disputed.end()), disputed.end());
        std::set_intersection(dvh_separate.begin(), dvh_separate.end(), so.begin(), so.end(), std::back_inserter(agreed));
        agreed = difference(agreed, disputed);
        auto judge = [&](uint64_t k, bool disputed_pair) {
            double ta[9], tb[9];
            triangle(m, pos, (uint32_t)(k >> 32), ta);
            triangle(m, pos, (uint32_t)k, tb);
            bool truth = cgal_intersect(ta, tb);
            if (disputed_pair) {
                row.judged++;
                (truth == contains(dvh_separate, k) ? row.cgal_with_dvh : row.cgal_with_fcl)++;
            } else {
                row.sampled++;
            }
            // (a pair a >= b can only come from dvh, and is wrong anyway)
            if ((uint32_t)(k >> 32) < (uint32_t)k && truth != contains(exact_separate, k)) row.reference_broken++;
        };
        for (uint64_t k : disputed) judge(k, true);
        for (uint64_t k : spread_sample(agreed, kSample)) judge(k, false);

        for (uint64_t k : symmetric_difference(dvh, exact)) {
            Mismatch x;
            x.run = "self";
            x.scene = s.name;
            x.objects = s.name;
            x.frame = f;
            x.a = (uint32_t)(k >> 32);
            x.b = (uint32_t)k;
            std::copy(&m.tris[3 * (size_t)x.a], &m.tris[3 * (size_t)x.a] + 3, x.ia);
            std::copy(&m.tris[3 * (size_t)x.b], &m.tris[3 * (size_t)x.b] + 3, x.ib);
            triangle(m, pos, x.a, x.ta);
            triangle(m, pos, x.b, x.tb);
            x.dvh = contains(dvh, k);
            x.exact = !x.dvh;
            x.adjacent = share_vertex(m, x.a, x.b);
            row.dvh_wrong++;
            if (x.adjacent) row.adjacent_wrong++;
            if (out.mismatches.size() < kKeep) out.mismatches.push_back(x);
        }

        std::printf("%-8s %4d t %.2f  self: pairs dvh %6zu (%4zu adjacent) exact %6zu (%4zu) obb %6zu aabb %6zu | dvh-only "
                    "%4zu/%4zu fcl-only %4zu/%4zu | judged %4zu cgal: dvh %4zu fcl %4zu | dvh wrong %zu (%zu adjacent) threads "
                    "diff %zu | ms dvh 1 thread %.2f+%.2f threaded %.2f+%.2f obb %.2f+%.2f aabb %.2f+%.2f exact %.1f+%.1f\n",
                    s.name.c_str(), f, row.t, row.dvh_pairs, row.dvh_adjacent, row.exact_pairs, row.exact_adjacent,
                    row.obb_pairs, row.aabb_pairs, row.dvh_only_obb, row.dvh_only_aabb, row.obb_only, row.aabb_only, row.judged,
                    row.cgal_with_dvh, row.cgal_with_fcl, row.dvh_wrong, row.adjacent_wrong, row.threads_mismatch,
                    row.one_refit, row.one_query, row.dvh_refit, row.dvh_query, row.obb_update, row.obb_query, row.aabb_update,
                    row.aabb_query, row.exact_adjacent_ms, row.exact_separate_ms);
        if (row.reference_broken != 0)
            std::printf("  REFERENCE BROKEN: %zu pairs on which the exact reference contradicts itself\n", row.reference_broken);
        std::fflush(stdout);
        out.rows.push_back(row);
    }
}

SelfSummary summarize(const SelfScene& s, const std::vector<SelfRow>& rows) {
    SelfSummary sum;
    sum.scene = s.name;
    sum.description = s.description;
    sum.triangles = s.rest.triangles();
    std::vector<double> one, dvh, obb, aabb, exact;
    for (const auto& r : rows) {
        if (r.scene != s.name) continue;
        sum.frames++;
        sum.pairs += r.dvh_pairs;
        sum.adjacent += r.dvh_adjacent;
        sum.disagreements += r.dvh_only_obb + r.obb_only + r.dvh_only_aabb + r.aabb_only;
        sum.judged += r.judged;
        sum.cgal_with_dvh += r.cgal_with_dvh;
        sum.cgal_with_fcl += r.cgal_with_fcl;
        sum.dvh_wrong += r.dvh_wrong;
        sum.adjacent_wrong += r.adjacent_wrong;
        sum.obb_wrong += r.obb_wrong;
        sum.aabb_wrong += r.aabb_wrong;
        sum.threads_mismatch += r.threads_mismatch;
        sum.reference_broken += r.reference_broken;
        one.push_back(r.one_refit + r.one_query);
        dvh.push_back(r.dvh_refit + r.dvh_query);
        obb.push_back(r.obb_update + r.obb_query);
        aabb.push_back(r.aabb_update + r.aabb_query);
        exact.push_back(r.exact_adjacent_ms + r.exact_separate_ms);
    }
    sum.one = median(one);
    sum.dvh = median(dvh);
    sum.obb = median(obb);
    sum.aabb = median(aabb);
    sum.exact = median(exact);
    return sum;
}

}  // namespace

SelfResults run_self(const RunOptions& options) {
    SelfResults out;
    for (auto& s : make_self_scenes(options.scenes)) {
        if (!options.only.empty() && s.name != options.only) continue;
        std::printf("== %s (self-collision): %s, %d frames\n", s.name.c_str(), s.description.c_str(), s.frames);
        run_scene(s, options.threads, out);
        out.sums.push_back(summarize(s, out.rows));
    }
    return out;
}

bool report_self(const SelfResults& results, bool& reference_ok) {
    if (results.sums.empty()) return true;
    std::printf("\nSummary of the self-collision runs (one mesh against itself. dvh: refit + dvh_self_collide, 1t on one thread,\n"
                "Nt threaded; FCL, the naive route: replace + refit, the model collided with itself for every contact, pairs\n"
                "a < b sharing no vertex kept; exact: CGAL, pairs sharing a vertex meeting beyond it, box filter + judge for the\n"
                "others. Pairs and adjacent (sharing a vertex) are dvh's over every frame; disagree = with FCL, on pairs sharing\n"
                "no vertex, judged by CGAL; wrong = differing from the exact set. Medians per frame, ms; ratio = faster FCL / dvh 1t)\n");
    std::printf("%-8s %6s %9s %8s %8s %8s %7s %9s %9s %9s %9s %9s %9s %9s %9s %7s\n", "scene", "frames", "triangles", "pairs",
                "adjacent", "disagree", "judged", "dvh wrong", "obb wrong", "aabb wrng", "dvh 1t", "dvh Nt", "fcl obb", "fcl aabb",
                "exact", "ratio");
    bool ok = true;
    for (const auto& s : results.sums) {
        double best = std::min(s.obb, s.aabb);
        std::printf("%-8s %6d %9zu %8zu %8zu %8zu %7zu %9zu %9zu %9zu %9.3f %9.3f %9.3f %9.3f %9.1f %6.1fx\n", s.scene.c_str(),
                    s.frames, s.triangles, s.pairs, s.adjacent, s.disagreements, s.judged, s.dvh_wrong, s.obb_wrong, s.aabb_wrong,
                    s.one, s.dvh, s.obb, s.aabb, s.exact, s.one > 0 ? best / s.one : 0.0);
        ok = ok && s.dvh_wrong == 0 && s.threads_mismatch == 0;
        if (s.adjacent_wrong != 0)
            std::printf("  %s: %zu of dvh's wrong pairs share a vertex\n", s.scene.c_str(), s.adjacent_wrong);
        if (s.threads_mismatch != 0)
            std::printf("  %s: dvh threaded differs from dvh on one thread on %zu pairs\n", s.scene.c_str(), s.threads_mismatch);
        if (s.reference_broken != 0) {
            std::printf("  %s: the exact reference contradicts itself on %zu pairs\n", s.scene.c_str(), s.reference_broken);
            reference_ok = false;
        }
    }
    return ok;
}

void write_self_outputs(const std::string& dir, const SelfResults& results) {
    std::ofstream csv(dir + "/self_frames.csv");
    csv << "scene,frame,t,triangles,dvh_pairs,dvh_adjacent,exact_pairs,exact_adjacent,adjacent_pairs_tested,adjacent_checked_by_"
           "construction,adjacent_degenerate,separate_candidates,obb_pairs,aabb_pairs,dvh_only_vs_obb,obb_only,dvh_only_vs_aabb,aabb_only,judged,"
           "sampled,cgal_with_dvh,cgal_with_fcl,dvh_wrong,adjacent_wrong,obb_wrong,aabb_wrong,threads_mismatch,reference_broken,"
           "dvh_triangle_tests,one_thread_refit_ms,one_thread_query_ms,dvh_refit_ms,dvh_query_ms,obb_update_ms,obb_query_ms,"
           "aabb_update_ms,aabb_query_ms,exact_adjacent_ms,exact_separate_ms\n";
    for (const auto& r : results.rows)
        csv << r.scene << ',' << r.frame << ',' << r.t << ',' << r.triangles << ',' << r.dvh_pairs << ',' << r.dvh_adjacent << ','
            << r.exact_pairs << ',' << r.exact_adjacent << ',' << r.adjacent_tested << ',' << r.adjacent_checked << ','
            << r.adjacent_degenerate << ',' << r.separate_candidates << ',' << r.obb_pairs << ',' << r.aabb_pairs << ',' << r.dvh_only_obb << ',' << r.obb_only
            << ',' << r.dvh_only_aabb << ',' << r.aabb_only << ',' << r.judged << ',' << r.sampled << ',' << r.cgal_with_dvh << ','
            << r.cgal_with_fcl << ',' << r.dvh_wrong << ',' << r.adjacent_wrong << ',' << r.obb_wrong << ',' << r.aabb_wrong << ','
            << r.threads_mismatch << ',' << r.reference_broken << ',' << r.triangle_tests << ',' << r.one_refit << ','
            << r.one_query << ',' << r.dvh_refit << ',' << r.dvh_query << ',' << r.obb_update << ',' << r.obb_query << ','
            << r.aabb_update << ',' << r.aabb_query << ',' << r.exact_adjacent_ms << ',' << r.exact_separate_ms << '\n';
    std::ofstream json(dir + "/self_summary.json");
    json << "[\n";
    for (size_t k = 0; k < results.sums.size(); k++) {
        const auto& s = results.sums[k];
        json << "  {\"scene\": \"" << s.scene << "\", \"description\": \"" << s.description << "\", \"frames\": " << s.frames
             << ", \"triangles\": " << s.triangles << ", \"pairs\": " << s.pairs << ", \"adjacent_pairs\": " << s.adjacent
             << ", \"disagreements\": " << s.disagreements << ", \"judged\": " << s.judged
             << ", \"cgal_with_dvh\": " << s.cgal_with_dvh << ", \"cgal_with_fcl\": " << s.cgal_with_fcl
             << ", \"dvh_wrong\": " << s.dvh_wrong << ", \"adjacent_wrong\": " << s.adjacent_wrong
             << ", \"obb_wrong\": " << s.obb_wrong << ", \"aabb_wrong\": " << s.aabb_wrong
             << ", \"threads_mismatch\": " << s.threads_mismatch << ", \"reference_broken\": " << s.reference_broken
             << ", \"median_ms\": {\"dvh_one_thread\": " << s.one << ", \"dvh\": " << s.dvh << ", \"fcl_obbrss\": " << s.obb
             << ", \"fcl_aabb\": " << s.aabb << ", \"exact_reference\": " << s.exact << "}}"
             << (k + 1 < results.sums.size() ? "," : "") << "\n";
    }
    json << "]\n";
}

}  // namespace xc
