// FCL with its own broad phase, as an FCL user would query a scene of deforming objects: the
// models of an FclSide (world coordinates, identity transforms) in one
// DynamicAABBTreeCollisionManagerd, each object's index as its user data. Each frame every model
// is replaced and refit as FclSide::update does, its box recomputed, the manager updated, and
// every object pair the manager reports queried as FclSide::collide does (every contact).
// Kept apart from fcl_side.hpp, which the benchmark runner compiles too.
#pragma once

#include <fcl/fcl.h>

#include <algorithm>
#include <cstdint>
#include <tuple>
#include <utility>
#include <vector>

#include "fcl_side.hpp"

namespace xc {

// One contact of a scene: triangle `a` of object `object_a` meets triangle `b` of object
// `object_b`, object_a < object_b (indices into Scene::objects).
struct SceneContact {
    uint32_t object_a, object_b, a, b;
    friend bool operator<(const SceneContact& x, const SceneContact& y) {
        return std::tie(x.object_a, x.object_b, x.a, x.b) < std::tie(y.object_a, y.object_b, y.a, y.b);
    }
    friend bool operator==(const SceneContact& x, const SceneContact& y) {
        return std::tie(x.object_a, x.object_b, x.a, x.b) == std::tie(y.object_a, y.object_b, y.a, y.b);
    }
};

// Sorted, distinct contacts.
using ContactSet = std::vector<SceneContact>;

template <typename BV>
class FclBroadPhase {
public:
    // Adds the next object (index = number of objects added before).
    void build(const uint32_t* tris, size_t triangle_count, const std::vector<fcl::Vector3d>& world) {
        side_.build(tris, triangle_count, world);
        auto index = static_cast<uintptr_t>(side_.objects.size() - 1);
        side_.objects.back()->setUserData(reinterpret_cast<void*>(index));
    }

    // After the last build: which object pairs may be reported (`tested[i * n + j]`, i < j; the
    // scene's pairs), and the manager takes every object.
    void finish(std::vector<char> tested) {
        tested_ = std::move(tested);
        std::vector<fcl::CollisionObjectd*> all;
        for (auto& o : side_.objects) all.push_back(o.get());
        manager_.registerObjects(all);
        manager_.setup();
    }

    // New world positions for object `i`: replace + bottom-up refit, then its world box.
    void update(size_t i, const std::vector<fcl::Vector3d>& world) {
        side_.update(i, world);
        // endReplaceModel refits the tree but leaves the model's own box (aabb_local, which
        // CollisionObject::computeAABB reads) at the first frame's: without this the manager
        // would sort stale boxes and miss object pairs.
        side_.models[i]->computeLocalAABB();
        side_.objects[i]->computeAABB();
    }

    // The manager's tree refit to the boxes of `update`.
    void update_manager() { manager_.update(); }

    // Every contact of the frame; `pairs_reported` gets the number of object pairs the broad
    // phase reported (and the scene tests).
    ContactSet collide(size_t& pairs_reported) const {
        Collected c{this, {}, 0};
        manager_.collide(&c, &FclBroadPhase::on_pair);
        std::sort(c.contacts.begin(), c.contacts.end());
        c.contacts.erase(std::unique(c.contacts.begin(), c.contacts.end()), c.contacts.end());
        pairs_reported = c.pairs;
        return std::move(c.contacts);
    }

private:
    struct Collected {
        const FclBroadPhase* self;
        ContactSet contacts;
        size_t pairs;
    };

    static size_t index(const fcl::CollisionObjectd* o) { return reinterpret_cast<uintptr_t>(o->getUserData()); }

    // The manager's callback for each object pair whose boxes overlap; false: keep going.
    static bool on_pair(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
        auto& c = *static_cast<Collected*>(data);
        size_t i = index(o1), j = index(o2);
        if (i > j) std::swap(i, j);  // FclSide::collide(i, j) gives (triangle of i, triangle of j)
        if (i == j || !c.self->tested_[i * c.self->side_.objects.size() + j]) return false;
        c.pairs++;
        for (uint64_t key : c.self->side_.collide(i, j))
            c.contacts.push_back({(uint32_t)i, (uint32_t)j, (uint32_t)(key >> 32), (uint32_t)key});
        return false;
    }

    FclSide<BV> side_;
    std::vector<char> tested_;
    fcl::DynamicAABBTreeCollisionManagerd manager_;
};

}  // namespace xc
