// Cross-check of dvh against FCL 0.7, frame by frame, with CGAL as the judge.
//
// For every scene and frame, the same world-coordinate vertex arrays go to FCL (BVHModel<OBBRSSd>
// and BVHModel<AABBd>, replace + bottom-up refit, identity transforms, every contact requested)
// and to dvh through dvh.h (refit + exact query), and dvh runs a second time with its own poses
// (local coordinates refit, the rigid motion passed as DvhPose). The sets of intersecting
// triangle pairs are compared; CGAL's exact do_intersect judges every pair in a symmetric
// difference, and a sample of the agreed pairs. dvh must agree with CGAL on every judged pair and
// its posed answers must equal its world-coordinate answers; FCL's errors are counted.
//
// dvh runs on one thread (refit and query: the single-thread figures FCL is compared with) and,
// on separate meshes, with `--threads N` (DvhQueryOptions.threads and
// DvhBuildOptions.refit_threads; default 0, every core); both must give the same pairs.
//
// Usage: dvh_cross_check [--full] [--frames N] [--scene NAME] [--threads N] [--checksums] --data DIR
//                        [--out DIR]
// (--checksums prints a hash of every scene's world coordinates at its first and last frame and
// exits: the benchmark runner's port of the scenes must print the same.)

#include <dvh.h>
#include <fcl/fcl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "fcl_side.hpp"
#include "geometry.hpp"
#include "judge.hpp"
#include "scenes.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using xc::PairSet;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

[[noreturn]] void dvh_fail(DvhStatus status, const char* what) {
    char message[512];
    dvh_last_error_message(message, sizeof message);
    throw std::runtime_error(std::string(what) + ": " + dvh_status_name(status) + ": " + message);
}

void dvh_check(DvhStatus status, const char* what) {
    if (status != DVH_STATUS_OK) dvh_fail(status, what);
}

PairSet to_set(const DvhPairs* pairs) {
    PairSet s(dvh_pairs_len(pairs));
    const DvhPair* data = dvh_pairs_data(pairs);
    for (size_t i = 0; i < s.size(); i++) s[i] = ((uint64_t)data[i].a << 32) | data[i].b;
    return s;  // dvh's output is already sorted by (a, b)
}

DvhPose to_dvh(const xc::Pose& p) {
    DvhPose d;
    std::copy(p.r, p.r + 9, d.rotation);
    std::copy(p.t, p.t + 3, d.translation);
    return d;
}

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
};

struct Offence {
    std::string scene;
    int frame;
    std::string objects;
    uint32_t a, b;
    bool dvh, cgal;
    double ta[9], tb[9];
};

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void triangle(const xc::MeshData& m, const std::vector<double>& world, uint32_t t, double out[9]) {
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++) out[3 * c + k] = world[3 * (size_t)m.tris[3 * (size_t)t + c] + k];
}

bool contains(const PairSet& s, uint64_t x) { return std::binary_search(s.begin(), s.end(), x); }

PairSet symmetric_difference(const PairSet& a, const PairSet& b) {
    PairSet d;
    std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
    return d;
}

PairSet difference(const PairSet& a, const PairSet& b) {
    PairSet d;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
    return d;
}

std::vector<FrameRow> run_scene(xc::Scene& scene, uint32_t threads, std::vector<Offence>& offences) {
    const size_t n = scene.objects.size();
    std::vector<std::vector<double>> local(n), world(n);
    std::vector<std::vector<fcl::Vector3d>> fcl_world(n);
    std::vector<xc::Pose> poses(n);
    auto place = [&](double t) {
        for (size_t i = 0; i < n; i++) {
            auto& o = scene.objects[i];
            if (o.deforms)
                o.morph.apply(o.rest.pos, t, local[i]);
            else
                local[i] = o.rest.pos;
            poses[i] = o.motion(t);
            xc::apply_pose(poses[i], local[i], world[i]);
            fcl_world[i].resize(o.rest.vertices());
            for (size_t v = 0; v < fcl_world[i].size(); v++)
                fcl_world[i][v] = fcl::Vector3d(world[i][3 * v], world[i][3 * v + 1], world[i][3 * v + 2]);
        }
    };

    place(0.0);
    std::vector<DvhMesh*> dvh_one(n, nullptr), dvh_world(n, nullptr), dvh_local(n, nullptr);
    xc::FclSide<fcl::OBBRSSd> obb;
    xc::FclSide<fcl::AABBd> aabb;
    DvhBuildOptions one_thread = dvh_build_options_default(), many = dvh_build_options_default();
    one_thread.refit_threads = 1;
    many.refit_threads = threads;
    DvhQueryOptions query_one = dvh_query_options_default(), query_many = dvh_query_options_default();
    query_one.threads = 1;
    query_many.threads = threads;
    for (size_t i = 0; i < n; i++) {
        const auto& m = scene.objects[i].rest;
        dvh_check(dvh_mesh_create(world[i].data(), m.vertices(), m.tris.data(), m.triangles(), &one_thread, &dvh_one[i]), "create");
        dvh_check(dvh_mesh_create(world[i].data(), m.vertices(), m.tris.data(), m.triangles(), &many, &dvh_world[i]), "create");
        dvh_check(dvh_mesh_create(local[i].data(), m.vertices(), m.tris.data(), m.triangles(), &many, &dvh_local[i]), "create");
        obb.build(m.tris.data(), m.triangles(), fcl_world[i]);
        aabb.build(m.tris.data(), m.triangles(), fcl_world[i]);
    }
    DvhPairs* pairs = dvh_pairs_new();
    if (pairs == nullptr) throw std::runtime_error("dvh_pairs_new failed");

    std::vector<FrameRow> rows;
    const size_t kSample = 20;  // agreed pairs spot-checked per object pair and frame
    for (int f = 0; f < scene.frames; f++) {
        FrameRow row;
        row.scene = scene.name;
        row.frame = f;
        place((double)f / scene.frames);
        std::vector<DvhPose> dposes(n);
        for (size_t i = 0; i < n; i++) dposes[i] = to_dvh(poses[i]);

        std::vector<PairSet> s1(scene.pairs.size()), sw(scene.pairs.size()), sp(scene.pairs.size()), so(scene.pairs.size()),
            sa(scene.pairs.size());
        // One dvh configuration: refit every mesh, then query every pair (with poses or not), each
        // timed.
        auto run_dvh = [&](std::vector<DvhMesh*>& meshes, const std::vector<std::vector<double>>& coords, bool posed,
                           const DvhQueryOptions& query, std::vector<PairSet>& out, double& refit_ms, double& query_ms) {
            auto t0 = Clock::now();
            for (size_t i = 0; i < n; i++)
                dvh_check(dvh_mesh_refit(meshes[i], coords[i].data(), scene.objects[i].rest.vertices()), "refit");
            refit_ms = ms_since(t0);
            t0 = Clock::now();
            for (size_t p = 0; p < scene.pairs.size(); p++) {
                auto [i, j] = scene.pairs[p];
                dvh_check(dvh_collide(meshes[i], posed ? &dposes[i] : nullptr, meshes[j], posed ? &dposes[j] : nullptr, &query,
                                      pairs, nullptr),
                          "collide");
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
        std::fflush(stdout);
        rows.push_back(row);
    }
    dvh_pairs_free(pairs);
    for (size_t i = 0; i < n; i++) {
        dvh_mesh_free(dvh_one[i]);
        dvh_mesh_free(dvh_world[i]);
        dvh_mesh_free(dvh_local[i]);
    }
    return rows;
}

struct Summary {
    std::string scene, description;
    int frames = 0;
    size_t pairs_compared = 0, disagreements = 0, judged = 0, sampled = 0;
    size_t dvh_wrong = 0, obb_wrong = 0, aabb_wrong = 0, posed_mismatch = 0, threads_mismatch = 0;
    double one = 0, dvh = 0, posed = 0, obb = 0, aabb = 0;
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
    }
    s.one = median(one);
    s.dvh = median(dvh);
    s.posed = median(posed);
    s.obb = median(obb);
    s.aabb = median(aabb);
    return s;
}

void write_outputs(const std::string& dir, const std::vector<FrameRow>& rows, const std::vector<Summary>& sums) {
    std::ofstream csv(dir + "/frames.csv");
    csv << "scene,frame,dvh_pairs,obb_pairs,aabb_pairs,dvh_only_vs_obb,obb_only,dvh_only_vs_aabb,aabb_only,judged,sampled,"
           "cgal_with_dvh,cgal_with_fcl,dvh_wrong,obb_wrong,aabb_wrong,posed_mismatch,threads_mismatch,one_thread_refit_ms,"
           "one_thread_query_ms,dvh_refit_ms,dvh_query_ms,posed_refit_ms,posed_query_ms,obb_update_ms,obb_query_ms,"
           "aabb_update_ms,aabb_query_ms\n";
    for (const auto& r : rows)
        csv << r.scene << ',' << r.frame << ',' << r.dvh_pairs << ',' << r.obb_pairs << ',' << r.aabb_pairs << ','
            << r.dvh_only_obb << ',' << r.obb_only << ',' << r.dvh_only_aabb << ',' << r.aabb_only << ',' << r.judged << ','
            << r.sampled << ',' << r.cgal_with_dvh << ',' << r.cgal_with_fcl << ',' << r.dvh_wrong << ',' << r.obb_wrong << ','
            << r.aabb_wrong << ',' << r.posed_mismatch << ',' << r.threads_mismatch << ',' << r.one_refit << ',' << r.one_query
            << ',' << r.dvh_refit << ',' << r.dvh_query << ',' << r.posed_refit << ','
            << r.posed_query << ',' << r.obb_update << ',' << r.obb_query << ',' << r.aabb_update << ',' << r.aabb_query << '\n';
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
             << ", \"dvh_posed\": " << s.posed << ", \"fcl_obbrss\": " << s.obb << ", \"fcl_aabb\": " << s.aabb << "}}"
             << (k + 1 < sums.size() ? "," : "") << "\n";
    }
    json << "]\n";
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
    bool checksums = false;
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
        else {
            std::fprintf(stderr, "usage: %s [--full] [--frames N] [--scene NAME] [--threads N] [--checksums] --data DIR [--out DIR]\n",
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
    std::printf("dvh %s against FCL %s, judged by CGAL; %s run; dvh threaded: --threads %u%s\n", dvh_version(), FCL_VERSION,
                options.full ? "full" : "short", threads, threads == 0 ? " (every core)" : "");
    std::vector<FrameRow> all_rows;
    std::vector<Summary> sums;
    std::vector<Offence> offences;
    try {
        auto scenes = xc::make_scenes(options);
        for (auto& scene : scenes) {
            if (!only.empty() && scene.name != only) continue;
            std::printf("== %s: %s, %d frames\n", scene.name.c_str(), scene.description.c_str(), scene.frames);
            auto rows = run_scene(scene, threads, offences);
            sums.push_back(summarize(scene, rows));
            all_rows.insert(all_rows.end(), rows.begin(), rows.end());
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }

    std::printf("\nSummary (medians per frame, ms; dvh 1t on one thread, dvh Nt threaded, posed threaded; ratio = faster FCL\n"
                "configuration / dvh on one thread; speed-up = dvh 1t / dvh Nt)\n");
    std::printf("%-10s %6s %10s %9s %8s %9s %9s %9s %9s %9s %9s %9s %9s %7s %8s\n", "scene", "frames", "pairs", "disagree",
                "judged", "dvh wrong", "obb wrong", "aabb wrng", "dvh 1t", "dvh Nt", "dvh posed", "fcl obb", "fcl aabb", "ratio",
                "speed-up");
    bool ok = true;
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
    if (!out_dir.empty()) write_outputs(out_dir, all_rows, sums);
    for (const auto& o : offences) {
        std::printf("\nDVH DISAGREES WITH CGAL: scene %s frame %d (%s), triangles %u and %u: dvh says %s, CGAL says %s\n",
                    o.scene.c_str(), o.frame, o.objects.c_str(), o.a, o.b, o.dvh ? "intersect" : "apart",
                    o.cgal ? "intersect" : "apart");
        for (int c = 0; c < 3; c++) std::printf("  a[%d] = (%.17g, %.17g, %.17g)\n", c, o.ta[3 * c], o.ta[3 * c + 1], o.ta[3 * c + 2]);
        for (int c = 0; c < 3; c++) std::printf("  b[%d] = (%.17g, %.17g, %.17g)\n", c, o.tb[3 * c], o.tb[3 * c + 1], o.tb[3 * c + 2]);
    }
    std::printf("\n%s\n", ok ? "VERDICT: dvh agrees with CGAL on every judged pair, threaded or not" : "VERDICT: FAILED");
    return ok ? 0 : 1;
}
