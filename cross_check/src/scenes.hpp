// The scenes: the paper's three experiments and the stress scenes where FCL is known to be weak.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "geometry.hpp"

namespace xc {

struct Object {
    std::string name;
    MeshData rest;       // local coordinates at rest
    Morph morph;         // deformation in local coordinates
    bool deforms = true;
    std::function<Pose(double)> motion;  // pose at time t in [0, 1)
};

struct Scene {
    std::string name;
    std::string description;
    std::vector<Object> objects;
    std::vector<std::pair<int, int>> pairs;  // object pairs tested every frame
    int frames = 0;
};

struct SceneOptions {
    bool full = false;         // paper sizes and 200 frames, or the short version for CI
    int frames = 0;            // 0: the mode's default
    std::string data_dir;      // where the CGAL demo OFF files were unpacked
};

// Object `o` at time `t`: its local coordinates (deformed, or at rest) into `local`, placed by its
// motion into `world`; returns the pose.
Pose place_object(Object& o, double t, std::vector<double>& local, std::vector<double>& world);

// Every scene of the chosen mode, built (meshes loaded, subdivided, placed).
std::vector<Scene> make_scenes(const SceneOptions& options);

// One mesh bending until it passes through itself, for the self-collision run (and, small, for
// the self-proximity part of the proximity run).
struct SelfScene {
    std::string name;
    std::string description;
    MeshData rest;
    std::function<void(double t, std::vector<double>& out)> at;  // positions at time t in [0, 1]; 0: rest
    int frames = 0;
};

// Every self-collision scene of the chosen mode.
std::vector<SelfScene> make_self_scenes(const SceneOptions& options);

}  // namespace xc
