// The self-collision run (self_run.cpp), the proximity run (proximity_run.cpp) and the curves run
// (curves_run.cpp): each runs its
// frames (printing a line per frame), then main prints their summaries with the others and writes
// their files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scenes.hpp"

namespace xc {

// What the runs take from the command line.
struct RunOptions {
    SceneOptions scenes;
    std::string only;      // --scene NAME: only that scene (of any run)
    uint32_t threads = 0;  // --threads N: dvh's threaded queries (0: every core)
};

// A triangle pair on which dvh and the exact reference differ, with everything needed to replay it.
struct Mismatch {
    std::string run, scene, objects;  // objects: "a x b", or the one mesh's name
    int frame = 0;
    double distance = 0;  // the query's distance (0 for a collision query)
    uint32_t a = 0, b = 0, ia[3] = {0, 0, 0}, ib[3] = {0, 0, 0};  // triangles and their vertex indices
    double ta[9], tb[9];  // world coordinates
    bool dvh = false, exact = false, adjacent = false;
};

// Per scene and frame of the self-collision run.
struct SelfRow {
    std::string scene;
    int frame = 0;
    double t = 0;
    size_t triangles = 0;
    size_t dvh_pairs = 0, dvh_adjacent = 0, exact_pairs = 0, exact_adjacent = 0;
    size_t adjacent_tested = 0, adjacent_checked = 0, adjacent_degenerate = 0, separate_candidates = 0;
    size_t obb_pairs = 0, aabb_pairs = 0;  // FCL's, triangles sharing a vertex dropped
    size_t dvh_only_obb = 0, obb_only = 0, dvh_only_aabb = 0, aabb_only = 0;
    size_t judged = 0, sampled = 0, cgal_with_dvh = 0, cgal_with_fcl = 0;
    size_t dvh_wrong = 0, adjacent_wrong = 0, obb_wrong = 0, aabb_wrong = 0, threads_mismatch = 0;
    size_t reference_broken = 0;  // the exact reference contradicting itself or CGAL's judge
    uint64_t triangle_tests = 0;  // dvh's, on one thread
    double one_refit = 0, one_query = 0, dvh_refit = 0, dvh_query = 0;
    double obb_update = 0, obb_query = 0, aabb_update = 0, aabb_query = 0;  // query: collide + filtering
    double exact_adjacent_ms = 0, exact_separate_ms = 0;
};

struct SelfSummary {
    std::string scene, description;
    int frames = 0;
    size_t triangles = 0, pairs = 0, adjacent = 0, disagreements = 0, judged = 0, cgal_with_dvh = 0, cgal_with_fcl = 0;
    size_t dvh_wrong = 0, adjacent_wrong = 0, obb_wrong = 0, aabb_wrong = 0, threads_mismatch = 0, reference_broken = 0;
    double one = 0, dvh = 0, obb = 0, aabb = 0, exact = 0;  // medians per frame, ms
};

struct SelfResults {
    std::vector<SelfRow> rows;
    std::vector<SelfSummary> sums;
    std::vector<Mismatch> mismatches;  // the first few hundred
};

// Per scene, frame and distance of the proximity run (summed over the scene's object pairs), or
// per mesh, frame and distance of its self-proximity part.
struct ProximityRow {
    std::string kind;  // "pair" (dvh_proximity) or "self" (dvh_self_proximity)
    std::string scene;
    int frame = 0;
    double t = 0, fraction = 0, distance = 0;
    size_t dvh_pairs = 0, exact_pairs = 0, candidates = 0, rational = 0;
    size_t dvh_only = 0, exact_only = 0;
    long posed_mismatch = -1;  // dvh with poses against dvh in world coordinates (-1: self, no poses)
    size_t threads_mismatch = 0;
    long zero_mismatch = -1;  // at distance 0 only: against dvh_collide (or dvh_self_collide's pairs sharing no vertex)
    size_t distance_checked = 0, reference_broken = 0;  // exact distances computed both ways (sample), and differing
    uint64_t triangle_tests = 0;
    double dvh_query = 0, dvh_threaded = 0, posed_query = 0, exact_ms = 0;
    double refit = 0, fcl = 0;  // the frame's, repeated on each distance: dvh's refit on one thread; FCL OBBRSS update + collide
};

struct ProximitySummary {
    std::string kind, scene;
    double fraction = 0, distance = 0;
    int frames = 0;
    size_t pairs = 0, dvh_wrong = 0, posed_mismatch = 0, threads_mismatch = 0, zero_mismatch = 0, reference_broken = 0;
    double dvh = 0, threaded = 0, posed = 0, exact = 0, fcl = 0;  // medians per frame, ms
};

struct ProximityResults {
    std::vector<ProximityRow> rows;
    std::vector<ProximitySummary> sums;
    std::vector<Mismatch> mismatches;
};

// Per scene, frame and object pair of the curves run (curves_run.cpp).
struct CurvesRow {
    std::string scene, objects;
    int frame = 0;
    size_t triangles = 0, segments = 0, curves = 0, degenerate = 0;
    size_t cgal_segments = 0, cgal_polylines = 0, dvh_points = 0, cgal_points = 0;
    double difference_ulps = 0;  // of the largest coordinate, between the sorted point sets
    double exact_ulps = 0;       // dvh's points from their pairs' exact intersections, where judged (beyond 4 units from CGAL's)
    bool general = false, same = false;  // no degenerate pair; the same points, curves and segments as CGAL's
    double dvh_curves = 0, dvh_collide = 0, cgal = 0;  // ms: refit + curves, refit + collide, surface_intersection
};

struct CurvesResults {
    std::vector<CurvesRow> rows;
};

// Per scene, object pair, frame and placement of the distance run (distance_run.cpp).
struct DistanceRow {
    std::string scene, objects;
    int frame = 0;
    bool apart = false;         // the second object moved apart along x
    double dvh = 0, fcl = 0;    // the distances
    bool intersecting = false;  // dvh's answer
    bool exact_ok = false;      // dvh's pair intersects (meeting), or dvh's distance rounds its pair's exact one
    double fcl_error = 0;       // FCL's relative error against the exact distance (meeting: its distance)
    double fcl_rebuilt = 0, fcl_rebuilt_error = 0;  // the same with FCL's models rebuilt each frame
    size_t fcl_rebuilt_wrong = 0;
    size_t dvh_wrong = 0, fcl_wrong = 0, posed_mismatch = 0, threads_mismatch = 0;
    bool tolerance_ok = false;  // rel_err = 0.01: within it
    double dvh_one = 0, dvh_many = 0, dvh_tolerant = 0, fcl_ms = 0, fcl_rebuilt_ms = 0;  // ms: refit (or build) + query (tolerant: query only)
};

struct DistanceResults {
    std::vector<DistanceRow> rows;
};

SelfResults run_self(const RunOptions& options);
// Prints the summary; true when dvh was right everywhere. `reference_ok` is cleared when the
// reference contradicted itself.
bool report_self(const SelfResults& results, bool& reference_ok);
void write_self_outputs(const std::string& dir, const SelfResults& results);

ProximityResults run_proximity(const RunOptions& options);
bool report_proximity(const ProximityResults& results, bool& reference_ok);
void write_proximity_outputs(const std::string& dir, const ProximityResults& results);

CurvesResults run_curves(const RunOptions& options);
// Its second part, on the self-collision run's meshes (called by run_curves).
void run_self_curves(const RunOptions& options, CurvesResults& out);
// Prints the summary; true when dvh's curves are CGAL's on every frame in general position.
bool report_curves(const CurvesResults& results);
void write_curves_outputs(const std::string& dir, const CurvesResults& results);

DistanceResults run_distance(const RunOptions& options);
// Prints the summary; true when dvh was right on every pair and frame.
bool report_distance(const DistanceResults& results);
void write_distance_outputs(const std::string& dir, const DistanceResults& results);

// Prints the first mismatches and writes every one kept to `path` (when not empty), coordinates
// with 17 digits.
void report_mismatches(const std::vector<Mismatch>& mismatches, const std::string& path);

}  // namespace xc
