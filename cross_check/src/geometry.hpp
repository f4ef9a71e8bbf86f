// Meshes, deformation and rigid motion for the cross-check: the same vertex arrays go to dvh and
// to FCL. Everything is seeded and deterministic.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace xc {

struct MeshData {
    std::vector<double> pos;     // x, y, z per vertex
    std::vector<uint32_t> tris;  // 3 indices per triangle
    size_t vertices() const { return pos.size() / 3; }
    size_t triangles() const { return tris.size() / 3; }
};

// Reads an OFF file (OFF/COFF/NOFF headers, comments, polygons split into fans). Throws on error.
MeshData load_off(const std::string& path);
// 1-to-4 subdivision with shared edge midpoints: the same surface, four times the triangles.
MeshData subdivide(const MeshData& m);
// Subdivides until the mesh has at least `triangles` triangles.
MeshData subdivided_to(const MeshData& m, size_t triangles);
// Centres the bounding box at the origin and scales its largest side to `size`.
void normalize(MeshData& m, double size);
// A flat square sheet in z = 0, `size` on a side, n x n cells of two triangles.
MeshData grid(int n, double size);
// A height field over [0, size]^2: z = amplitude * smooth bumps; n x n cells.
MeshData terrain(int n, double size, double amplitude, uint64_t seed);
// Lowest and highest coordinate on each axis.
void bounds(const MeshData& m, double lo[3], double hi[3]);

// SplitMix64.
struct Rng {
    uint64_t state;
    explicit Rng(uint64_t seed) : state(seed) {}
    uint64_t next() {
        uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    double unit() { return (double)(next() >> 11) * (1.0 / 9007199254740992.0); }
    double range(double lo, double hi) { return lo + (hi - lo) * unit(); }
};

// Morphing by point specification (the paper's deformation): control points with displacement
// vectors; each vertex moves by sum_k w_k(p) d_k sin(2 pi (t + phase_k)) with Gaussian weights
// w_k, optionally scaled up towards the top of the mesh (y), as in the paper's second scene.
struct Morph {
    struct Control {
        double point[3], displacement[3], width, phase;
    };
    std::vector<Control> controls;
    double upper_bias = 0.0;  // 0: uniform; 1: displacement grows from 0 at the bottom to 2x at the top
    double y_lo = 0.0, y_hi = 1.0;
    // Only move within the plane z = const (for the coplanar stress scene).
    bool planar = false;

    static Morph random(const MeshData& m, int count, double amplitude, uint64_t seed);
    void apply(const std::vector<double>& rest, double t, std::vector<double>& out) const;
};

// A rigid motion, row-major rotation: world = R p + t.
struct Pose {
    double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double t[3] = {0, 0, 0};
    // Rotation by `angle` about the unit `axis`, then translation.
    static Pose from_axis_angle(const double axis[3], double angle, const double translation[3]);
};

// world = R p + t, evaluated as ((R0 x + R1 y) + R2 z) + t without fused operations: exactly the
// coordinates dvh computes for a posed mesh (dvh.h, dvh_collide), so that world-coordinate and
// posed queries see the same doubles.
void apply_pose(const Pose& pose, const std::vector<double>& local, std::vector<double>& world);

}  // namespace xc
