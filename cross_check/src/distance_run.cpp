// The distance run: the least distance between two meshes, dvh_distance against FCL's distance()
// on the same deforming meshes, frame by frame, CGAL's exact squared distances judging.
//
// Pairs of objects: every object pair of the pairwise run's scenes (at their short sizes whatever
// the mode), twice per frame: as they move (mostly intersecting: distance 0) and with the second
// object moved apart along x, so that a gap of at least 2% of the scene's diagonal opens between
// their boxes and the least distance is a real one between deforming surfaces. dvh on world
// coordinates on one thread (refit + query: the figure FCL is compared with), threaded, with its
// own poses (local coordinates and DvhPose), all three equal; and with rel_err = 0.01, within it.
// FCL: BVHModel<OBBRSSd> (its distance bounding volume), replace + bottom-up refit each frame,
// distance() with nearest points.
//
// The judge: for intersecting meshes dvh's triangle pair must intersect (CGAL's exact
// do_intersect) and FCL's distance is then counted wrong unless 0; for meshes apart, the exact
// squared distances of dvh's triangle pair and of FCL's: FCL's pair may not be closer than
// dvh's (dvh wrong), dvh's distance must round its pair's exact one (within two units in the last
// place), and FCL's reported distance is compared with the exact least (its error counted).

#include <dvh.hpp>
#include <fcl/fcl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "common.hpp"
#include "exact.hpp"
#include "judge.hpp"
#include "runs.hpp"

namespace xc {

namespace {

// Within `units` units in the last place of `y`?
bool near_ulps(double x, double y, double units) {
    return std::fabs(x - y) <= units * (std::nextafter(std::fabs(y), HUGE_VAL) - std::fabs(y));
}

struct Models {
    std::vector<std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>>> models;
    std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
};

void print_row(const DistanceRow& r) {
    std::printf("%-10s %4d %-5s %-28s: dvh %-12.6g %s fcl %-12.6g | exact-dvh %s fcl-err %.2g | dvh wrong %zu fcl wrong %zu "
                "posed %zu threads %zu tol %s | fcl rebuilt %.6g wrong %zu | ms dvh 1t %.3f Nt %.3f tol %.3f fcl %.3f rebuilt %.3f\n",
                r.scene.c_str(), r.frame, r.apart ? "apart" : "moved", r.objects.c_str(), r.dvh, r.intersecting ? "(meet)" : "      ",
                r.fcl, r.exact_ok ? "ok" : "NO", r.fcl_error, r.dvh_wrong, r.fcl_wrong, r.posed_mismatch, r.threads_mismatch,
                r.tolerance_ok ? "ok" : "NO", r.fcl_rebuilt, r.fcl_rebuilt_wrong, r.dvh_one, r.dvh_many, r.dvh_tolerant, r.fcl_ms,
                r.fcl_rebuilt_ms);
    std::fflush(stdout);
}

void run_pairs(Scene& scene, int frames, uint32_t threads, DistanceResults& out) {
    const size_t n = scene.objects.size();
    std::vector<std::vector<double>> local(n), world(n);
    std::vector<DvhPose> poses(n);
    auto place = [&](double t) {
        for (size_t i = 0; i < n; i++) poses[i] = to_dvh(place_object(scene.objects[i], t, local[i], world[i]));
    };
    auto box = [](const std::vector<double>& w, int k, bool hi) {
        double x = hi ? -HUGE_VAL : HUGE_VAL;
        for (size_t v = k; v < w.size(); v += 3) x = hi ? std::max(x, w[v]) : std::min(x, w[v]);
        return x;
    };
    dvh::BuildOptions one_build, many_build;
    one_build.refit_threads(1);
    many_build.refit_threads(threads);
    const dvh::DistanceOptions exact_one = dvh::DistanceOptions().threads(1);
    const dvh::DistanceOptions exact_many = dvh::DistanceOptions().threads(threads);
    const dvh::DistanceOptions tolerant = dvh::DistanceOptions().threads(1).rel_err(0.01);
    place(0.0);
    for (auto [i, j] : scene.pairs) {
        const auto& mi = scene.objects[i].rest;
        const auto& mj = scene.objects[j].rest;
        const std::string objects = scene.objects[i].name + " x " + scene.objects[j].name;
        for (bool moved_apart : {false, true}) {
            // The second object's world coordinates and pose this run uses (apart: its pose
            // moved along x, so that dvh's posed coordinates are still the harness's world ones).
            std::vector<double> wj;
            DvhPose pj;
            auto second = [&](double t) {
                Pose pose = scene.objects[j].motion(t);
                if (moved_apart) {
                    double diag = 0;
                    for (int k = 0; k < 3; k++) {
                        double lo = std::min(box(world[i], k, false), box(world[j], k, false));
                        double hi = std::max(box(world[i], k, true), box(world[j], k, true));
                        diag += (hi - lo) * (hi - lo);
                    }
                    pose.t[0] += box(world[i], 0, true) - box(world[j], 0, false) + 0.02 * std::sqrt(diag);
                }
                apply_pose(pose, local[j], wj);
                pj = to_dvh(pose);
            };
            second(0.0);
            dvh::Mesh a1(world[i].data(), mi.vertices(), mi.tris.data(), mi.triangles(), one_build);
            dvh::Mesh b1(wj.data(), mj.vertices(), mj.tris.data(), mj.triangles(), one_build);
            dvh::Mesh an(world[i].data(), mi.vertices(), mi.tris.data(), mi.triangles(), many_build);
            dvh::Mesh bn(wj.data(), mj.vertices(), mj.tris.data(), mj.triangles(), many_build);
            dvh::Mesh ap(local[i].data(), mi.vertices(), mi.tris.data(), mi.triangles(), many_build);
            dvh::Mesh bp(local[j].data(), mj.vertices(), mj.tris.data(), mj.triangles(), many_build);
            auto fcl_model = [](const MeshData& m, const std::vector<double>& w) {
                std::vector<fcl::Vector3d> v;
                to_fcl(w, v);
                std::vector<fcl::Triangle> t(m.triangles());
                for (size_t k = 0; k < t.size(); k++) t[k] = fcl::Triangle(m.tris[3 * k], m.tris[3 * k + 1], m.tris[3 * k + 2]);
                auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
                model->beginModel((int)t.size(), (int)v.size());
                model->addSubModel(v, t);
                model->endModel();
                return model;
            };
            auto fa = fcl_model(mi, world[i]), fb = fcl_model(mj, wj);
            fcl::CollisionObjectd oa(fa, fcl::Transform3d::Identity()), ob(fb, fcl::Transform3d::Identity());
            for (int f = 0; f < frames; f++) {
                const double t = (double)f / frames;
                place(t);
                second(t);
                DistanceRow row;
                row.scene = scene.name;
                row.objects = objects;
                row.frame = f;
                row.apart = moved_apart;
                // dvh: refit and query on one thread.
                auto t0 = Clock::now();
                a1.refit(world[i].data(), mi.vertices());
                b1.refit(wj.data(), mj.vertices());
                const DvhDistance d = dvh::distance(a1, nullptr, b1, nullptr, exact_one);
                row.dvh_one = ms_since(t0);
                t0 = Clock::now();
                an.refit(world[i].data(), mi.vertices());
                bn.refit(wj.data(), mj.vertices());
                const DvhDistance dn = dvh::distance(an, nullptr, bn, nullptr, exact_many);
                row.dvh_many = ms_since(t0);
                t0 = Clock::now();
                const DvhDistance dt = dvh::distance(a1, nullptr, b1, nullptr, tolerant);
                row.dvh_tolerant = ms_since(t0);
                // With poses: local coordinates; the answer must be the same to the bit.
                ap.refit(local[i].data(), mi.vertices());
                bp.refit(local[j].data(), mj.vertices());
                const DvhDistance dp = dvh::distance(ap, &poses[i], bp, &pj, exact_many);
                auto same = [](const DvhDistance& x, const DvhDistance& y) { return std::memcmp(&x, &y, sizeof x) == 0; };
                row.threads_mismatch = same(d, dn) ? 0 : 1;
                row.posed_mismatch = same(d, dp) ? 0 : 1;
                // FCL: replace + refit + distance.
                std::vector<fcl::Vector3d> vi, vj;
                to_fcl(world[i], vi);
                to_fcl(wj, vj);
                t0 = Clock::now();
                fa->beginReplaceModel();
                fa->replaceSubModel(vi);
                fa->endReplaceModel(true, true);
                fb->beginReplaceModel();
                fb->replaceSubModel(vj);
                fb->endReplaceModel(true, true);
                oa.computeAABB();
                ob.computeAABB();
                fcl::DistanceRequestd request(true);
                fcl::DistanceResultd result;
                fcl::distance(&oa, &ob, request, result);
                row.fcl_ms = ms_since(t0);
                // FCL rebuilt: new models from this frame's coordinates.
                t0 = Clock::now();
                auto ra = fcl_model(mi, world[i]), rb = fcl_model(mj, wj);
                fcl::CollisionObjectd xa(ra, fcl::Transform3d::Identity()), xb(rb, fcl::Transform3d::Identity());
                fcl::DistanceResultd rebuilt;
                fcl::distance(&xa, &xb, request, rebuilt);
                row.fcl_rebuilt_ms = ms_since(t0);
                row.fcl_rebuilt = rebuilt.min_distance;
                row.dvh = d.distance;
                row.intersecting = d.intersecting != 0;
                row.fcl = result.min_distance;
                double ta[9], tb[9];
                triangle(mi, world[i], d.triangle_a, ta);
                triangle(mj, wj, d.triangle_b, tb);
                if (d.intersecting) {
                    row.exact_ok = cgal_intersect(ta, tb);
                    row.dvh_wrong = row.exact_ok ? 0 : 1;
                    row.fcl_wrong = result.min_distance > 0 ? 1 : 0;
                    row.fcl_error = std::max(0.0, result.min_distance);
                    row.fcl_rebuilt_wrong = rebuilt.min_distance > 0 ? 1 : 0;
                    row.fcl_rebuilt_error = std::max(0.0, rebuilt.min_distance);
                    row.tolerance_ok = dt.intersecting != 0;
                } else {
                    const double exact = cgal_distance(ta, tb);
                    row.exact_ok = near_ulps(d.distance, exact, 2);
                    double fa9[9], fb9[9];
                    triangle(mi, world[i], (uint32_t)result.b1, fa9);
                    triangle(mj, wj, (uint32_t)result.b2, fb9);
                    const int c = cgal_compare_distances(fa9, fb9, ta, tb);
                    row.dvh_wrong = (c < 0 || !row.exact_ok) ? 1 : 0;
                    row.fcl_wrong = c > 0 ? 1 : 0;  // FCL's pair is not the closest
                    row.fcl_error = std::fabs(result.min_distance - exact) / std::max(exact, 1e-300);
                    triangle(mi, world[i], (uint32_t)rebuilt.b1, fa9);
                    triangle(mj, wj, (uint32_t)rebuilt.b2, fb9);
                    const int r = cgal_compare_distances(fa9, fb9, ta, tb);
                    row.dvh_wrong += r < 0 ? 1 : 0;
                    row.fcl_rebuilt_wrong = r > 0 ? 1 : 0;
                    row.fcl_rebuilt_error = std::fabs(rebuilt.min_distance - exact) / std::max(exact, 1e-300);
                    row.tolerance_ok = !dt.intersecting && dt.distance >= d.distance * (1 - 4e-16) &&
                                       dt.distance <= 1.01 * d.distance * (1 + 4e-16);
                }
                row.dvh_wrong += row.threads_mismatch + row.posed_mismatch + (row.tolerance_ok ? 0 : 1);
                print_row(row);
                out.rows.push_back(row);
            }
        }
    }
}

}  // namespace

DistanceResults run_distance(const RunOptions& options) {
    DistanceResults out;
    SceneOptions small = options.scenes;
    small.full = false;
    const int frames = options.scenes.frames > 0 ? options.scenes.frames : (options.scenes.full ? 10 : 2);
    for (auto& scene : make_scenes(small)) {
        if (!options.only.empty() && scene.name != options.only) continue;
        std::printf("== %s (distance): %s, %d frames\n", scene.name.c_str(), scene.description.c_str(), frames);
        run_pairs(scene, frames, options.threads, out);
    }
    return out;
}

bool report_distance(const DistanceResults& results) {
    if (results.rows.empty()) return true;
    std::printf("\nSummary of the distance runs (dvh_distance against FCL distance() on OBBRSS, per scene, as the objects move and\n"
                "moved apart; dvh wrong = dvh's answer beaten or unproved by CGAL's exact distances, or its threaded, posed or\n"
                "tolerant runs off; FCL refit (replace + bottom-up refit) and rebuilt (new models each frame): wrg = its pair\n"
                "not the closest, or a distance above 0 for meshes that meet; err = the largest relative error of its distance;\n"
                "medians per frame, ms, refit (or rebuild) + query of every object pair; ratio = FCL / dvh on one thread;\n"
                "tol = dvh exact / dvh with rel_err 0.01, queries only)\n");
    std::printf("%-10s %-5s %6s %6s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s %7s %7s %7s\n", "scene", "kind", "pairs", "meet",
                "dvh wrong", "refit wrg", "refit err", "rbld wrg", "rbld err", "dvh 1t", "dvh Nt", "dvh tol", "fcl refit", "fcl rbld",
                "ratio", "ratio rb", "tol");
    bool ok = true;
    std::vector<std::string> scenes;
    for (const auto& r : results.rows)
        if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
    for (const auto& scene : scenes)
        for (bool apart : {false, true}) {
            size_t pairs = 0, meet = 0, dvh_wrong = 0, fcl_wrong = 0, rebuilt_wrong = 0;
            double err = 0, rebuilt_err = 0;
            std::vector<int> frames;
            for (const auto& r : results.rows)
                if (r.scene == scene && r.apart == apart && std::find(frames.begin(), frames.end(), r.frame) == frames.end())
                    frames.push_back(r.frame);
            std::vector<double> one, many, tol, fcl, rebuilt;
            for (int f : frames) {
                double o = 0, m = 0, t = 0, c = 0, b = 0;
                for (const auto& r : results.rows) {
                    if (r.scene != scene || r.apart != apart || r.frame != f) continue;
                    pairs++;
                    meet += r.intersecting;
                    dvh_wrong += r.dvh_wrong;
                    fcl_wrong += r.fcl_wrong;
                    err = std::max(err, r.fcl_error);
                    rebuilt_wrong += r.fcl_rebuilt_wrong;
                    rebuilt_err = std::max(rebuilt_err, r.fcl_rebuilt_error);
                    b += r.fcl_rebuilt_ms;
                    o += r.dvh_one;
                    m += r.dvh_many;
                    t += r.dvh_tolerant;
                    c += r.fcl_ms;
                }
                one.push_back(o);
                many.push_back(m);
                tol.push_back(t);
                fcl.push_back(c);
                rebuilt.push_back(b);
            }
            const double mo = median(one), mf = median(fcl), mt = median(tol), mb = median(rebuilt);
            std::printf("%-10s %-5s %6zu %6zu %9zu %9zu %9.3g %9zu %9.3g %9.3f %9.3f %9.3f %9.3f %9.3f %6.1fx %6.1fx %6.1fx\n",
                        scene.c_str(), apart ? "apart" : "moved", pairs, meet, dvh_wrong, fcl_wrong, err, rebuilt_wrong, rebuilt_err,
                        mo, median(many), mt, mf, mb, mo > 0 ? mf / mo : 0.0, mo > 0 ? mb / mo : 0.0, mt > 0 ? mo / mt : 0.0);
            ok = ok && dvh_wrong == 0;
        }
    return ok;
}

void write_distance_outputs(const std::string& dir, const DistanceResults& results) {
    std::ofstream csv(dir + "/distance_frames.csv");
    csv << "scene,objects,frame,apart,dvh_distance,intersecting,fcl_distance,exact_ok,fcl_relative_error,dvh_wrong,fcl_wrong,"
           "posed_mismatch,threads_mismatch,tolerance_ok,fcl_rebuilt_distance,fcl_rebuilt_wrong,fcl_rebuilt_relative_error,"
           "dvh_one_thread_ms,dvh_threaded_ms,dvh_tolerant_query_ms,fcl_refit_ms,fcl_rebuilt_ms\n";
    for (const auto& r : results.rows) {
        char d[64], f[64];
        std::snprintf(d, sizeof d, "%.17g", r.dvh);
        std::snprintf(f, sizeof f, "%.17g", r.fcl);
        csv << r.scene << ',' << r.objects << ',' << r.frame << ',' << r.apart << ',' << d << ',' << r.intersecting << ',' << f << ','
            << r.exact_ok << ',' << r.fcl_error << ',' << r.dvh_wrong << ',' << r.fcl_wrong << ',' << r.posed_mismatch << ','
            << r.threads_mismatch << ',' << r.tolerance_ok << ',' << r.fcl_rebuilt << ',' << r.fcl_rebuilt_wrong << ','
            << r.fcl_rebuilt_error << ',' << r.dvh_one << ',' << r.dvh_many << ',' << r.dvh_tolerant << ',' << r.fcl_ms << ','
            << r.fcl_rebuilt_ms << '\n';
    }
}

}  // namespace xc
