// A C interface to the cross-check harness's FCL driver, for the Rust runner: one scene's models
// in one FCL configuration, updated and queried exactly as the harness does.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <vector>

#include "fcl_side.hpp"

namespace {

struct Scene {
    // Each object's next positions in FCL's vector type, staged outside the timed update as the
    // harness stages them.
    std::vector<std::vector<fcl::Vector3d>> staged;
    virtual ~Scene() = default;
    virtual void add(const double* pos, size_t vertices, const uint32_t* tris, size_t triangles) = 0;
    virtual void update(size_t object) = 0;
    virtual xc::PairSet collide(size_t a, size_t b) const = 0;
};

std::vector<fcl::Vector3d> points(const double* pos, size_t vertices) {
    std::vector<fcl::Vector3d> out(vertices);
    for (size_t v = 0; v < vertices; v++) out[v] = fcl::Vector3d(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]);
    return out;
}

template <typename BV>
struct SceneOf : Scene {
    xc::FclSide<BV> side;
    void add(const double* pos, size_t vertices, const uint32_t* tris, size_t triangles) override {
        staged.push_back(points(pos, vertices));
        side.build(tris, triangles, staged.back());
    }
    void update(size_t object) override { side.update(object, staged[object]); }
    xc::PairSet collide(size_t a, size_t b) const override { return side.collide(a, b); }
};

}  // namespace

extern "C" {

// kind 0: BVHModel<OBBRSSd>; kind 1: BVHModel<AABBd>. NULL when out of memory.
void* runner_fcl_new(int kind) noexcept {
    try {
        if (kind == 0) return new SceneOf<fcl::OBBRSSd>();
        return new SceneOf<fcl::AABBd>();
    } catch (const std::exception&) {
        return nullptr;
    }
}

void runner_fcl_free(void* scene) noexcept { delete static_cast<Scene*>(scene); }

// Adds an object in world coordinates; returns 0 on success.
int runner_fcl_add(void* scene, const double* pos, size_t vertices, const uint32_t* tris, size_t triangles) noexcept {
    try {
        static_cast<Scene*>(scene)->add(pos, vertices, tris, triangles);
        return 0;
    } catch (const std::exception&) {
        return 1;
    }
}

// Stages the next world positions of object `object` (same vertex count as when added).
void runner_fcl_stage(void* scene, size_t object, const double* pos) noexcept {
    auto& staged = static_cast<Scene*>(scene)->staged[object];
    for (size_t v = 0; v < staged.size(); v++) staged[v] = fcl::Vector3d(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]);
}

// Replaces object `object`'s vertices with the staged ones, then FCL's bottom-up refit; returns
// 0 on success.
int runner_fcl_update(void* scene, size_t object) noexcept {
    try {
        static_cast<Scene*>(scene)->update(object);
        return 0;
    } catch (const std::exception&) {
        return 1;
    }
}

// Every contact of objects a and b, sorted and distinct, as (a << 32 | b) keys appended through
// `push`; returns 0 on success.
int runner_fcl_collide(const void* scene, size_t a, size_t b, void* sink, void (*push)(void*, const uint64_t*, size_t)) noexcept {
    try {
        xc::PairSet s = static_cast<const Scene*>(scene)->collide(a, b);
        push(sink, s.data(), s.size());
        return 0;
    } catch (const std::exception&) {
        return 1;
    }
}

}  // extern "C"
