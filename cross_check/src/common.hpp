// What every run of the harness uses: timing, sorted pair sets, poses for dvh. dvh itself comes
// through dvh.hpp, whose owners release its handles and whose dvh::Error reports its failures.
#pragma once

#include <dvh.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iterator>
#include <vector>

#include "fcl_side.hpp"
#include "geometry.hpp"

namespace xc {

using Clock = std::chrono::steady_clock;

inline double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

inline uint64_t pair_key(uint32_t a, uint32_t b) { return ((uint64_t)a << 32) | b; }

inline PairSet to_set(const dvh::Pairs& pairs) {
    const dvh::Span<DvhPair> view = pairs.view();
    PairSet s(view.size());
    for (size_t i = 0; i < s.size(); i++) s[i] = pair_key(view[i].a, view[i].b);
    return s;  // dvh's output is already sorted by (a, b)
}

inline DvhPose to_dvh(const Pose& p) {
    DvhPose d;
    std::copy(p.r, p.r + 9, d.rotation);
    std::copy(p.t, p.t + 3, d.translation);
    return d;
}

inline double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The corners of triangle `t` of `m` at positions `pos`, as 9 doubles.
inline void triangle(const MeshData& m, const std::vector<double>& pos, uint32_t t, double out[9]) {
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++) out[3 * c + k] = pos[3 * (size_t)m.tris[3 * (size_t)t + c] + k];
}

// Do triangles `a` and `b` of `m` have a vertex index in common?
inline bool share_vertex(const MeshData& m, uint32_t a, uint32_t b) {
    const uint32_t* ta = &m.tris[3 * (size_t)a];
    const uint32_t* tb = &m.tris[3 * (size_t)b];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (ta[i] == tb[j]) return true;
    return false;
}

inline bool contains(const PairSet& s, uint64_t x) { return std::binary_search(s.begin(), s.end(), x); }

template <typename Set>
Set symmetric_difference(const Set& a, const Set& b) {
    Set d;
    std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
    return d;
}

template <typename Set>
Set difference(const Set& a, const Set& b) {
    Set d;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
    return d;
}

// A mesh's self-intersections as FCL's user gets them: its only model (in `side`) collided with
// itself for every contact, which brings both orders and each triangle with itself; kept are the
// pairs a < b of triangles sharing no vertex index (for the others FCL's answer means nothing:
// they touch at least where they share).
template <typename BV>
PairSet fcl_self(const FclSide<BV>& side, const MeshData& m) {
    PairSet out;
    for (uint64_t k : side.collide(0, 0)) {
        uint32_t a = (uint32_t)(k >> 32), b = (uint32_t)k;
        if (a == b || share_vertex(m, a, b)) continue;
        out.push_back(pair_key(std::min(a, b), std::max(a, b)));
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

// Every `step`-th element of `s`, `step` chosen so that about `count` are taken.
inline PairSet spread_sample(const PairSet& s, size_t count) {
    PairSet out;
    size_t step = std::max<size_t>(1, s.size() / std::max<size_t>(1, count));
    for (size_t k = 0; k < s.size(); k += step) out.push_back(s[k]);
    return out;
}

}  // namespace xc
