// FCL as the cross-check and the benchmark runner drive it: one BVHModel per object in world
// coordinates with an identity transform, updated each frame by replace + bottom-up refit, and
// queried for every contact (triangle pair), de-duplicated and sorted.
#pragma once

#include <fcl/fcl.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace xc {

// Sorted, distinct triangle pairs (a << 32 | b).
using PairSet = std::vector<uint64_t>;

// x, y, z per vertex as FCL's vectors, into `out`.
inline void to_fcl(const std::vector<double>& xyz, std::vector<fcl::Vector3d>& out) {
    out.resize(xyz.size() / 3);
    for (size_t v = 0; v < out.size(); v++) out[v] = fcl::Vector3d(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
}

// One FCL configuration (OBBRSSd or AABBd) for every object of a scene.
template <typename BV>
struct FclSide {
    std::vector<std::shared_ptr<fcl::BVHModel<BV>>> models;
    std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;

    // Adds an object: `triangle_count` triangles of three indices into `world`.
    void build(const uint32_t* tris, size_t triangle_count, const std::vector<fcl::Vector3d>& world) {
        std::vector<fcl::Triangle> t(triangle_count);
        for (size_t i = 0; i < triangle_count; i++) t[i] = fcl::Triangle(tris[3 * i], tris[3 * i + 1], tris[3 * i + 2]);
        auto model = std::make_shared<fcl::BVHModel<BV>>();
        model->beginModel((int)t.size(), (int)world.size());
        model->addSubModel(world, t);
        model->endModel();
        models.push_back(model);
        objects.push_back(std::make_unique<fcl::CollisionObjectd>(model, fcl::Transform3d::Identity()));
    }

    // New world positions for object `i`, then FCL's bottom-up refit.
    void update(size_t i, const std::vector<fcl::Vector3d>& world) {
        models[i]->beginReplaceModel();
        models[i]->replaceSubModel(world);
        models[i]->endReplaceModel(true, true);
    }

    PairSet collide(size_t i, size_t j) const {
        // The default request stops at one contact: ask for all of them, without contact points.
        fcl::CollisionRequestd request(std::numeric_limits<size_t>::max(), false);
        fcl::CollisionResultd result;
        fcl::collide(objects[i].get(), objects[j].get(), request, result);
        std::vector<fcl::Contactd> contacts;
        result.getContacts(contacts);
        PairSet s;
        s.reserve(contacts.size());
        for (const auto& c : contacts) s.push_back(((uint64_t)(uint32_t)c.b1 << 32) | (uint32_t)c.b2);
        std::sort(s.begin(), s.end());
        s.erase(std::unique(s.begin(), s.end()), s.end());
        return s;
    }
};

}  // namespace xc
