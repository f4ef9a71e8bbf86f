/*
 * dvh.hpp: the C++17 layer over dvh.h, header-only.
 *
 * Owners that release their handle (dvh::Mesh, dvh::Pairs, dvh::Scene, dvh::Contacts,
 * dvh::Impacts, dvh::NearPairs, dvh::SceneImpacts, dvh::SceneNearPairs, dvh::Curves), one
 * exception,
 * dvh::Error, for every failed call, results viewed in place (dvh::Span), and options with named
 * setters that chain. Each wrapper calls the dvh.h function
 * it names, whose documentation (arguments, errors, thread safety) holds for it too.
 *
 * Conventions
 * - A failed call throws dvh::Error with the DvhStatus and the message of
 *   dvh_last_error_message(), read on the failing thread right after the call; as in C, it
 *   changes nothing (a failed refit leaves the mesh, a failed query its result buffer, a failed
 *   scene call the scene as they were).
 * - Out of memory is a dvh::Error with DVH_STATUS_OUT_OF_MEMORY, whichever call ran out, the
 *   creation of a result buffer (dvh_pairs_new, dvh_contacts_new, dvh_impacts_new,
 *   dvh_near_pairs_new, dvh_scene_impacts_new, dvh_scene_near_pairs_new, dvh_curves_new
 *   returning NULL)
 *   included.
 * - The owners are move-only. A moved-from or released owner holds no handle: get() is null, its
 *   counts are 0, and a call that needs the handle throws dvh::Error (DVH_STATUS_NULL_ARGUMENT).
 *   get() lends the handle to the C API; release() gives it up.
 * - std::vector overloads take three values per vertex (x, y, z) or per triangle; a size that is
 *   not a multiple of 3, or a motion whose start and end differ in size, throws dvh::Error
 *   (DVH_STATUS_INVALID_ARGUMENT) before any call.
 * - Poses are dvh.h's DvhPose (`DvhPose{{1, 0, 0, 0, 1, 0, 0, 0, 1}, {x, y, z}}`), passed by
 *   pointer: nullptr is the identity.
 * - The option and result types are dvh.h's own, as are its DVH_* constants.
 */
#ifndef DVH_HPP
#define DVH_HPP

#include <dvh.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>
#if __cplusplus >= 202002L
#include <span>
#endif

namespace dvh {

/// The library's version, such as `"0.3.0"` (dvh_version).
[[nodiscard]] inline const char* version() noexcept { return dvh_version(); }

/// The name of a status code, such as `"DVH_STATUS_NULL_ARGUMENT"` (dvh_status_name).
[[nodiscard]] inline const char* status_name(DvhStatus status) noexcept { return dvh_status_name(status); }

/// The message of the last failed dvh call on the calling thread, whole whatever its length;
/// empty after a successful call (dvh_last_error_message).
[[nodiscard]] inline std::string last_error_message() {
    const std::size_t length = dvh_last_error_message(nullptr, 0);
    if (length == 0) return std::string();
    std::vector<char> buffer(length + 1);
    const std::size_t full = dvh_last_error_message(buffer.data(), buffer.size());
    return std::string(buffer.data(), full < length ? full : length);
}

/// A failed dvh call: the status it returned and what the library said was wrong.
class Error : public std::runtime_error {
public:
    /// An error with `status` (a DVH_STATUS_* code other than DVH_STATUS_OK) and `message`.
    Error(DvhStatus status, const std::string& message) : std::runtime_error(message), status_(status) {}

    /// The DVH_STATUS_* code. what() is the library's message (dvh_last_error_message), or the
    /// status's name when there is none.
    [[nodiscard]] DvhStatus status() const noexcept { return status_; }

private:
    DvhStatus status_;
};

namespace detail {

[[noreturn]] inline void fail(DvhStatus status) {
    std::string message = last_error_message();
    if (message.empty()) message = status_name(status);
    throw Error(status, message);
}

}  // namespace detail

/// Throws dvh::Error when `status` is not DVH_STATUS_OK, with the calling thread's last error
/// message: call it on the status of a C function right after that function returns.
inline void check(DvhStatus status) {
    if (status != DVH_STATUS_OK) detail::fail(status);
}

/// A read-only view of contiguous elements owned elsewhere (a result buffer, a mesh), valid as
/// long as they are.
template <typename T>
class Span {
public:
    /// The type of the elements.
    using value_type = T;
    /// The type of sizes and indices.
    using size_type = std::size_t;
    /// Iterators are pointers.
    using iterator = const T*;

    /// An empty view.
    constexpr Span() noexcept = default;
    /// The `size` elements at `data` (which may be null when `size` is 0).
    constexpr Span(const T* data, std::size_t size) noexcept : data_(data), size_(size) {}

    /// The first element (null when there are none).
    [[nodiscard]] constexpr const T* data() const noexcept { return data_; }
    /// The number of elements.
    [[nodiscard]] constexpr std::size_t size() const noexcept { return size_; }
    /// Are there no elements?
    [[nodiscard]] constexpr bool empty() const noexcept { return size_ == 0; }
    /// The first element's position.
    [[nodiscard]] constexpr const T* begin() const noexcept { return data_; }
    /// The position past the last element.
    [[nodiscard]] constexpr const T* end() const noexcept { return data_ + size_; }
    /// Element `i`, unchecked: `i` must be below size().
    [[nodiscard]] constexpr const T& operator[](std::size_t i) const noexcept { return data_[i]; }

#if __cplusplus >= 202002L
    /// The same elements as a std::span.
    constexpr operator std::span<const T>() const noexcept { return std::span<const T>(data_, size_); }
#endif

private:
    const T* data_ = nullptr;
    std::size_t size_ = 0;
};

/// Options for building a mesh: a DvhBuildOptions that starts from dvh_build_options_default()
/// and is set by name, `dvh::BuildOptions{}.volume(DVH_VOLUME_KIND_DVH).refit_threads(1)`.
class BuildOptions {
public:
    /// dvh_build_options_default(): the fastest measured for meshes that deform.
    BuildOptions() noexcept : c_(dvh_build_options_default()) {}
    /// The given C options (implicit: a DvhBuildOptions goes wherever options are taken).
    BuildOptions(const DvhBuildOptions& options) noexcept : c_(options) {}
    /// dvh_build_options_rigid(): the fastest measured for meshes moved by poses, never refit.
    [[nodiscard]] static BuildOptions rigid() noexcept { return BuildOptions(dvh_build_options_rigid()); }

    /// Sets how the hierarchy is split: a DVH_TREE_KIND_* value.
    BuildOptions& tree(DvhTreeKind value) & noexcept {
        c_.tree = value;
        return *this;
    }
    /// Sets how the hierarchy is split, on a temporary.
    BuildOptions tree(DvhTreeKind value) && noexcept { return tree(value); }
    /// A DVH_TREE_KIND_* value.
    [[nodiscard]] DvhTreeKind tree() const noexcept { return c_.tree; }

    /// Sets how sphere radii are refit: a DVH_RADIUS_KIND_* value.
    BuildOptions& radius(DvhRadiusKind value) & noexcept {
        c_.radius = value;
        return *this;
    }
    /// Sets how sphere radii are refit, on a temporary.
    BuildOptions radius(DvhRadiusKind value) && noexcept { return radius(value); }
    /// A DVH_RADIUS_KIND_* value.
    [[nodiscard]] DvhRadiusKind radius() const noexcept { return c_.radius; }

    /// Sets where triangles touching no ring centre go: a DVH_LEFTOVER_POLICY_* value.
    BuildOptions& leftovers(DvhLeftoverPolicy value) & noexcept {
        c_.leftovers = value;
        return *this;
    }
    /// Sets where triangles touching no ring centre go, on a temporary.
    BuildOptions leftovers(DvhLeftoverPolicy value) && noexcept { return leftovers(value); }
    /// A DVH_LEFTOVER_POLICY_* value.
    [[nodiscard]] DvhLeftoverPolicy leftovers() const noexcept { return c_.leftovers; }

    /// Sets the bounding volume: a DVH_VOLUME_KIND_* value.
    BuildOptions& volume(DvhVolumeKind value) & noexcept {
        c_.volume = value;
        return *this;
    }
    /// Sets the bounding volume, on a temporary.
    BuildOptions volume(DvhVolumeKind value) && noexcept { return volume(value); }
    /// A DVH_VOLUME_KIND_* value.
    [[nodiscard]] DvhVolumeKind volume() const noexcept { return c_.volume; }

    /// Sets the threads each refit may use: 0 for every core, 1 for the calling thread, n for at
    /// most n.
    BuildOptions& refit_threads(std::uint32_t value) & noexcept {
        c_.refit_threads = value;
        return *this;
    }
    /// Sets the threads each refit may use, on a temporary.
    BuildOptions refit_threads(std::uint32_t value) && noexcept { return refit_threads(value); }
    /// The threads each refit may use.
    [[nodiscard]] std::uint32_t refit_threads() const noexcept { return c_.refit_threads; }

    /// The C struct, for the C API.
    [[nodiscard]] const DvhBuildOptions& c() const noexcept { return c_; }

private:
    DvhBuildOptions c_;
};

/// Options for the queries: a DvhQueryOptions that starts from dvh_query_options_default() (every
/// intersecting triangle pair, no limit, every core) and is set by name,
/// `dvh::QueryOptions{}.mode(DVH_QUERY_MODE_FIRST_HIT).threads(1)`.
class DistanceOptions {
public:
    DistanceOptions() noexcept : c_(dvh_distance_options_default()) {}
    DistanceOptions(const DvhDistanceOptions& options) noexcept : c_(options) {}

    DistanceOptions& max_distance(double value) & noexcept {
        c_.max_distance = value;
        return *this;
    }
    DistanceOptions max_distance(double value) && noexcept { return max_distance(value); }
    [[nodiscard]] double max_distance() const noexcept { return c_.max_distance; }

    DistanceOptions& rel_err(double value) & noexcept {
        c_.rel_err = value;
        return *this;
    }
    DistanceOptions rel_err(double value) && noexcept { return rel_err(value); }
    [[nodiscard]] double rel_err() const noexcept { return c_.rel_err; }

    DistanceOptions& abs_err(double value) & noexcept {
        c_.abs_err = value;
        return *this;
    }
    DistanceOptions abs_err(double value) && noexcept { return abs_err(value); }
    [[nodiscard]] double abs_err() const noexcept { return c_.abs_err; }

    DistanceOptions& threads(std::uint32_t value) & noexcept {
        c_.threads = value;
        return *this;
    }
    DistanceOptions threads(std::uint32_t value) && noexcept { return threads(value); }
    [[nodiscard]] std::uint32_t threads() const noexcept { return c_.threads; }

    [[nodiscard]] const DvhDistanceOptions& c() const noexcept { return c_; }

private:
    DvhDistanceOptions c_;
};

class QueryOptions {
public:
    /// dvh_query_options_default().
    QueryOptions() noexcept : c_(dvh_query_options_default()) {}
    /// The given C options (implicit: a DvhQueryOptions goes wherever options are taken).
    QueryOptions(const DvhQueryOptions& options) noexcept : c_(options) {}

    /// Sets what the query reports: a DVH_QUERY_MODE_* value.
    QueryOptions& mode(DvhQueryMode value) & noexcept {
        c_.mode = value;
        return *this;
    }
    /// Sets what the query reports, on a temporary.
    QueryOptions mode(DvhQueryMode value) && noexcept { return mode(value); }
    /// A DVH_QUERY_MODE_* value.
    [[nodiscard]] DvhQueryMode mode() const noexcept { return c_.mode; }

    /// Sets the deepest level descended in DVH_QUERY_MODE_DEPTH (the root is level 0).
    QueryOptions& max_depth(std::uint32_t value) & noexcept {
        c_.max_depth = value;
        return *this;
    }
    /// Sets the deepest level descended in DVH_QUERY_MODE_DEPTH, on a temporary.
    QueryOptions max_depth(std::uint32_t value) && noexcept { return max_depth(value); }
    /// The deepest level descended in DVH_QUERY_MODE_DEPTH.
    [[nodiscard]] std::uint32_t max_depth() const noexcept { return c_.max_depth; }

    /// Sets the most pairs reported (0: no limit); the statistics' `truncated` says when it cut.
    QueryOptions& max_pairs(std::uint64_t value) & noexcept {
        c_.max_pairs = value;
        return *this;
    }
    /// Sets the most pairs reported, on a temporary.
    QueryOptions max_pairs(std::uint64_t value) && noexcept { return max_pairs(value); }
    /// The most pairs reported (0: no limit).
    [[nodiscard]] std::uint64_t max_pairs() const noexcept { return c_.max_pairs; }

    /// Sets the volume tests allowed in DVH_QUERY_MODE_BUDGET (at least 1 in that mode).
    QueryOptions& budget(std::uint64_t value) & noexcept {
        c_.budget = value;
        return *this;
    }
    /// Sets the volume tests allowed in DVH_QUERY_MODE_BUDGET, on a temporary.
    QueryOptions budget(std::uint64_t value) && noexcept { return budget(value); }
    /// The volume tests allowed in DVH_QUERY_MODE_BUDGET.
    [[nodiscard]] std::uint64_t budget() const noexcept { return c_.budget; }

    /// Sets the threads the query may use: 0 for every core, 1 for the calling thread, n for at
    /// most n. The result is the same whatever the count.
    QueryOptions& threads(std::uint32_t value) & noexcept {
        c_.threads = value;
        return *this;
    }
    /// Sets the threads the query may use, on a temporary.
    QueryOptions threads(std::uint32_t value) && noexcept { return threads(value); }
    /// The threads the query may use.
    [[nodiscard]] std::uint32_t threads() const noexcept { return c_.threads; }

    /// The C struct, for the C API.
    [[nodiscard]] const DvhQueryOptions& c() const noexcept { return c_; }

private:
    DvhQueryOptions c_;
};

/// How a continuous test decides (DvhCcdMode): the DVH_CCD_MODE_* values.
enum class CcdMode : DvhCcdMode {
    /// DVH_CCD_MODE_EXACT: exact for every finite input, the time of impact the earliest contact
    /// rounded down to a double. The default.
    exact = DVH_CCD_MODE_EXACT,
    /// DVH_CCD_MODE_CONSERVATIVE: floating point only; never misses a contact nor reports a later
    /// time than exact, but may report primitives that come within rounding error of contact.
    conservative = DVH_CCD_MODE_CONSERVATIVE,
};

/// Options for the continuous tests and queries: a DvhCcdOptions that starts from
/// dvh_ccd_options_default() (exact, every core, no impact limit, every impact) and is set by
/// name, `dvh::CcdOptions{}.mode(dvh::CcdMode::conservative).earliest_only(true)`. The primitive
/// tests (ccd_vertex_face, ccd_edge_edge) read the mode only.
class CcdOptions {
public:
    /// dvh_ccd_options_default().
    CcdOptions() noexcept : c_(dvh_ccd_options_default()) {}
    /// The given C options (implicit: a DvhCcdOptions goes wherever options are taken).
    CcdOptions(const DvhCcdOptions& options) noexcept : c_(options) {}

    /// Sets how the tests decide.
    CcdOptions& mode(CcdMode value) & noexcept {
        c_.mode = static_cast<DvhCcdMode>(value);
        return *this;
    }
    /// Sets how the tests decide, on a temporary.
    CcdOptions mode(CcdMode value) && noexcept { return mode(value); }
    /// Sets how the tests decide: a DVH_CCD_MODE_* value (one out of range is the library's to
    /// refuse, when the options are used).
    CcdOptions& mode(DvhCcdMode value) & noexcept {
        c_.mode = value;
        return *this;
    }
    /// Sets how the tests decide (a DVH_CCD_MODE_* value), on a temporary.
    CcdOptions mode(DvhCcdMode value) && noexcept { return mode(value); }
    /// How the tests decide.
    [[nodiscard]] CcdMode mode() const noexcept { return static_cast<CcdMode>(c_.mode); }

    /// Sets the threads a query may use: 0 for every core, 1 for the calling thread, n for at
    /// most n. The impacts are the same, in the same order, whatever the count.
    CcdOptions& threads(std::uint32_t value) & noexcept {
        c_.threads = value;
        return *this;
    }
    /// Sets the threads a query may use, on a temporary.
    CcdOptions threads(std::uint32_t value) && noexcept { return threads(value); }
    /// The threads a query may use.
    [[nodiscard]] std::uint32_t threads() const noexcept { return c_.threads; }

    /// Sets the most impacts reported (0: no limit); the statistics' `truncated` says when it
    /// cut.
    CcdOptions& max_impacts(std::uint64_t value) & noexcept {
        c_.max_impacts = value;
        return *this;
    }
    /// Sets the most impacts reported, on a temporary.
    CcdOptions max_impacts(std::uint64_t value) && noexcept { return max_impacts(value); }
    /// The most impacts reported (0: no limit).
    [[nodiscard]] std::uint64_t max_impacts() const noexcept { return c_.max_impacts; }

    /// Sets whether a query reports the earliest impact only (of several at that time, the first
    /// in the result's order): much cheaper than the whole list.
    CcdOptions& earliest_only(bool value) & noexcept {
        c_.earliest_only = value;
        return *this;
    }
    /// Sets whether a query reports the earliest impact only, on a temporary.
    CcdOptions earliest_only(bool value) && noexcept { return earliest_only(value); }
    /// Does a query report the earliest impact only?
    [[nodiscard]] bool earliest_only() const noexcept { return c_.earliest_only; }

    /// The C struct, for the C API.
    [[nodiscard]] const DvhCcdOptions& c() const noexcept { return c_; }

private:
    DvhCcdOptions c_;
};

namespace detail {

inline void free_handle(DvhMesh* handle) noexcept { dvh_mesh_free(handle); }
inline void free_handle(DvhPairs* handle) noexcept { dvh_pairs_free(handle); }
inline void free_handle(DvhScene* handle) noexcept { dvh_scene_free(handle); }
inline void free_handle(DvhContacts* handle) noexcept { dvh_contacts_free(handle); }
inline void free_handle(DvhImpacts* handle) noexcept { dvh_impacts_free(handle); }
inline void free_handle(DvhNearPairs* handle) noexcept { dvh_near_pairs_free(handle); }
inline void free_handle(DvhSceneImpacts* handle) noexcept { dvh_scene_impacts_free(handle); }
inline void free_handle(DvhSceneNearPairs* handle) noexcept { dvh_scene_near_pairs_free(handle); }
inline void free_handle(DvhCurves* handle) noexcept { dvh_curves_free(handle); }

// A handle from a C function that writes it to its last argument.
template <typename Handle, typename Create>
Handle* created(Create create) {
    Handle* handle = nullptr;
    check(create(&handle));
    return handle;
}

// A handle from dvh_*_new, which returns NULL when memory ran out.
template <typename Handle>
Handle* allocated(Handle* handle) {
    if (handle == nullptr) fail(DVH_STATUS_OUT_OF_MEMORY);
    return handle;
}

// The number of triples in `values`, which must hold a whole number of them.
template <typename T>
std::size_t triples(const std::vector<T>& values, const char* what) {
    if (values.size() % 3 != 0)
        throw Error(DVH_STATUS_INVALID_ARGUMENT,
                    std::string(what) + " holds " + std::to_string(values.size()) + " values, not a multiple of 3");
    return values.size() / 3;
}

// The number of vertices of a motion from `start` to `end`, which must hold as many whole
// triples as each other.
template <typename T>
std::size_t motion_vertices(const std::vector<T>& start, const std::vector<T>& end) {
    const std::size_t vertex_count = triples(start, "start");
    if (triples(end, "end") != vertex_count)
        throw Error(DVH_STATUS_INVALID_ARGUMENT, "start holds " + std::to_string(start.size()) + " values but end holds " +
                                                     std::to_string(end.size()) + ": a motion needs as many of each");
    return vertex_count;
}

// The elements of `values`, never null: the C API reads a NULL array as a missing argument,
// where an empty vector means no elements.
template <typename T>
const T* elements(const std::vector<T>& values) noexcept {
    static const T none{};
    return values.empty() ? &none : values.data();
}

// What the owners share: one handle, released by its dvh_*_free when the owner goes.
template <typename Handle>
class Owner {
public:
    Owner(const Owner&) = delete;
    Owner& operator=(const Owner&) = delete;

    /// The handle, still owned here: to pass to the C API. Null when the owner holds none.
    [[nodiscard]] Handle* get() const noexcept { return handle_; }
    /// Gives the handle up without releasing it (the caller releases it with its dvh_*_free);
    /// the owner then holds none.
    [[nodiscard]] Handle* release() noexcept {
        Handle* handle = handle_;
        handle_ = nullptr;
        return handle;
    }
    /// Does the owner hold a handle?
    explicit operator bool() const noexcept { return handle_ != nullptr; }

protected:
    explicit Owner(Handle* handle) noexcept : handle_(handle) {}
    Owner(Owner&& other) noexcept : handle_(other.release()) {}
    Owner& operator=(Owner&& other) noexcept {
        Handle* taken = other.release();  // first: moving an owner to itself keeps its handle
        free_handle(handle_);
        handle_ = taken;
        return *this;
    }
    ~Owner() { free_handle(handle_); }

private:
    Handle* handle_;
};

}  // namespace detail

/// A mesh with its hierarchy (DvhMesh), released by dvh_mesh_free. Any number of threads may
/// query one mesh at once; a refit needs it to themselves.
class Mesh : public detail::Owner<DvhMesh> {
public:
    /// Takes ownership of `mesh`, a mesh from dvh_mesh_create* (or null: an owner of none).
    explicit Mesh(DvhMesh* mesh) noexcept : Owner(mesh) {}

    /// Builds a mesh from `vertex_count` vertices (x, y, z each) and `triangle_count` triangles
    /// (three vertex indices each) (dvh_mesh_create). The arrays are copied.
    Mesh(const double* positions, std::size_t vertex_count, const std::uint32_t* triangles, std::size_t triangle_count,
         const BuildOptions& options = {})
        : Owner(detail::created<DvhMesh>([&](DvhMesh** out) {
              return dvh_mesh_create(positions, vertex_count, triangles, triangle_count, &options.c(), out);
          })) {}

    /// Builds a mesh with 16-bit triangle indices (dvh_mesh_create_u16).
    Mesh(const double* positions, std::size_t vertex_count, const std::uint16_t* triangles, std::size_t triangle_count,
         const BuildOptions& options = {})
        : Owner(detail::created<DvhMesh>([&](DvhMesh** out) {
              return dvh_mesh_create_u16(positions, vertex_count, triangles, triangle_count, &options.c(), out);
          })) {}

    /// Builds a mesh from packed `float` positions, three per vertex (dvh_mesh_create_f32 with a
    /// 12-byte stride); they are widened to double exactly.
    Mesh(const float* positions, std::size_t vertex_count, const std::uint32_t* triangles, std::size_t triangle_count,
         const BuildOptions& options = {})
        : Owner(create_f32(positions, 3 * sizeof(float), vertex_count, triangles, triangle_count, options)) {}

    /// Builds a mesh from `positions` (x, y, z per vertex) and `triangles` (three indices each).
    Mesh(const std::vector<double>& positions, const std::vector<std::uint32_t>& triangles, const BuildOptions& options = {})
        : Mesh(detail::elements(positions), detail::triples(positions, "positions"), detail::elements(triangles),
               detail::triples(triangles, "triangles"), options) {}

    /// Builds a mesh from `positions` and 16-bit `triangles`.
    Mesh(const std::vector<double>& positions, const std::vector<std::uint16_t>& triangles, const BuildOptions& options = {})
        : Mesh(detail::elements(positions), detail::triples(positions, "positions"), detail::elements(triangles),
               detail::triples(triangles, "triangles"), options) {}

    /// Builds a mesh from packed `float` positions and `triangles`.
    Mesh(const std::vector<float>& positions, const std::vector<std::uint32_t>& triangles, const BuildOptions& options = {})
        : Mesh(detail::elements(positions), detail::triples(positions, "positions"), detail::elements(triangles),
               detail::triples(triangles, "triangles"), options) {}

    /// Builds a mesh from `float` positions at a byte stride, as engines keep vertex buffers:
    /// vertex `i` is the three floats at `positions + i * stride_bytes` in bytes, no alignment
    /// required (dvh_mesh_create_f32).
    [[nodiscard]] static Mesh from_strided(const float* positions, std::size_t stride_bytes, std::size_t vertex_count,
                                           const std::uint32_t* triangles, std::size_t triangle_count,
                                           const BuildOptions& options = {}) {
        return Mesh(create_f32(positions, stride_bytes, vertex_count, triangles, triangle_count, options));
    }

    /// Takes `other`'s mesh; `other` holds none afterwards.
    Mesh(Mesh&& other) noexcept = default;
    /// Releases the mesh held here, then takes `other`'s.
    Mesh& operator=(Mesh&& other) noexcept = default;

    /// Refits to new positions, as many vertices as at creation (dvh_mesh_refit). On failure
    /// the mesh is exactly as it was.
    void refit(const double* positions, std::size_t vertex_count) { check(dvh_mesh_refit(get(), positions, vertex_count)); }
    /// Refits to `positions` (x, y, z per vertex).
    void refit(const std::vector<double>& positions) {
        refit(detail::elements(positions), detail::triples(positions, "positions"));
    }
    /// Refits to packed `float` positions (dvh_mesh_refit_f32 with a 12-byte stride).
    void refit(const float* positions, std::size_t vertex_count) { refit_strided(positions, 3 * sizeof(float), vertex_count); }
    /// Refits to packed `float` positions.
    void refit(const std::vector<float>& positions) {
        refit(detail::elements(positions), detail::triples(positions, "positions"));
    }
    /// Refits to `float` positions at a byte stride, as from_strided() reads them
    /// (dvh_mesh_refit_f32).
    void refit_strided(const float* positions, std::size_t stride_bytes, std::size_t vertex_count) {
        check(dvh_mesh_refit_f32(get(), positions, stride_bytes, vertex_count));
    }

    /// Gives the mesh a motion over one step: every vertex moves in a straight line from `start`
    /// (t = 0) to `end` (t = 1), x, y, z per vertex, as many vertices as at creation
    /// (dvh_mesh_refit_motion). The volumes hold the whole motion, for continuous_collide() and
    /// self_continuous_collide(); the positions become `end`. A plain refit() makes the mesh
    /// stationary again. On failure the mesh is exactly as it was (its motion included).
    void refit_motion(const double* start, const double* end, std::size_t vertex_count) {
        check(dvh_mesh_refit_motion(get(), start, end, vertex_count));
    }
    /// Gives the mesh the motion from `start` to `end` (x, y, z per vertex each); two vectors of
    /// different sizes throw dvh::Error (DVH_STATUS_INVALID_ARGUMENT) before any call.
    void refit_motion(const std::vector<double>& start, const std::vector<double>& end) {
        const std::size_t vertex_count = detail::motion_vertices(start, end);
        refit_motion(detail::elements(start), detail::elements(end), vertex_count);
    }

    /// The number of vertices (dvh_mesh_vertex_count).
    [[nodiscard]] std::size_t vertex_count() const noexcept { return dvh_mesh_vertex_count(get()); }
    /// The number of triangles (dvh_mesh_triangle_count).
    [[nodiscard]] std::size_t triangle_count() const noexcept { return dvh_mesh_triangle_count(get()); }
    /// The number of nodes of the hierarchy, leaves included; node 0 is the root
    /// (dvh_mesh_node_count).
    [[nodiscard]] std::size_t node_count() const noexcept { return dvh_mesh_node_count(get()); }

    /// The shape of the hierarchy (dvh_mesh_tree_stats).
    [[nodiscard]] DvhTreeStats tree_stats() const {
        DvhTreeStats stats{};
        check(dvh_mesh_tree_stats(get(), &stats));
        return stats;
    }
    /// The counters of the last refit, or of the build (dvh_mesh_last_refit_stats).
    [[nodiscard]] DvhRefitStats last_refit_stats() const {
        DvhRefitStats stats{};
        check(dvh_mesh_last_refit_stats(get(), &stats));
        return stats;
    }
    /// The triangles below `node`, to expand the node pairs of the coarse query modes; owned by
    /// the mesh, valid while it lives (dvh_mesh_node_triangles).
    [[nodiscard]] Span<std::uint32_t> node_triangles(std::uint32_t node) const {
        const std::uint32_t* triangles = nullptr;
        std::size_t count = 0;
        check(dvh_mesh_node_triangles(get(), node, &triangles, &count));
        return Span<std::uint32_t>(triangles, count);
    }
    /// Checks every invariant of the hierarchy; slow, for tests and bug reports
    /// (dvh_mesh_validate: DVH_STATUS_INVARIANT_BROKEN would be a bug in dvh).
    void validate() const { check(dvh_mesh_validate(get())); }
    /// Is the surface closed (every directed edge matched by its reverse)? Winding numbers and
    /// signed distances need it (dvh_mesh_is_closed).
    [[nodiscard]] bool is_closed() const {
        bool closed = false;
        check(dvh_mesh_is_closed(get(), &closed));
        return closed;
    }

private:
    static DvhMesh* create_f32(const float* positions, std::size_t stride_bytes, std::size_t vertex_count,
                               const std::uint32_t* triangles, std::size_t triangle_count, const BuildOptions& options) {
        return detail::created<DvhMesh>([&](DvhMesh** out) {
            return dvh_mesh_create_f32(positions, stride_bytes, vertex_count, triangles, triangle_count, &options.c(), out);
        });
    }
};

/// A reusable result buffer of the queries (DvhPairs), released by dvh_pairs_free. Use one per
/// thread; once it has grown to a scene's needs, queries into it allocate nothing.
class Pairs : public detail::Owner<DvhPairs> {
public:
    /// A new, empty buffer (dvh_pairs_new).
    Pairs() : Owner(detail::allocated(dvh_pairs_new())) {}
    /// Takes ownership of `pairs`, a buffer from dvh_pairs_new (or null: an owner of none).
    explicit Pairs(DvhPairs* pairs) noexcept : Owner(pairs) {}
    /// Takes `other`'s buffer; `other` holds none afterwards.
    Pairs(Pairs&& other) noexcept = default;
    /// Releases the buffer held here, then takes `other`'s.
    Pairs& operator=(Pairs&& other) noexcept = default;

    /// The pairs of the last successful query into the buffer, sorted by `a` then `b`; valid
    /// until the next query into it (dvh_pairs_data, dvh_pairs_len).
    [[nodiscard]] Span<DvhPair> view() const noexcept { return Span<DvhPair>(dvh_pairs_data(get()), dvh_pairs_len(get())); }
    /// What the indices refer to: DVH_PAIR_KIND_TRIANGLES or DVH_PAIR_KIND_NODES (dvh_pairs_kind).
    [[nodiscard]] DvhPairKind kind() const noexcept { return dvh_pairs_kind(get()); }
    /// The number of pairs (dvh_pairs_len).
    [[nodiscard]] std::size_t size() const noexcept { return dvh_pairs_len(get()); }
    /// Are there no pairs?
    [[nodiscard]] bool empty() const noexcept { return size() == 0; }
    /// The first pair's position, as view().begin().
    [[nodiscard]] const DvhPair* begin() const noexcept { return view().begin(); }
    /// The position past the last pair, as view().end().
    [[nodiscard]] const DvhPair* end() const noexcept { return view().end(); }
};

/// A reusable result buffer of scene queries (DvhContacts), released by dvh_contacts_free. Use
/// one per thread.
class Contacts : public detail::Owner<DvhContacts> {
public:
    /// A new, empty buffer (dvh_contacts_new).
    Contacts() : Owner(detail::allocated(dvh_contacts_new())) {}
    /// Takes ownership of `contacts`, a buffer from dvh_contacts_new (or null: an owner of none).
    explicit Contacts(DvhContacts* contacts) noexcept : Owner(contacts) {}
    /// Takes `other`'s buffer; `other` holds none afterwards.
    Contacts(Contacts&& other) noexcept = default;
    /// Releases the buffer held here, then takes `other`'s.
    Contacts& operator=(Contacts&& other) noexcept = default;

    /// The contacts of the last successful query into the buffer, sorted by
    /// `(object_a, object_b, a, b)`, with `object_a <= object_b` (equal for a contact of an object
    /// with itself, reported while its self-contact is on); valid until the next query into it
    /// (dvh_contacts_data, dvh_contacts_len).
    [[nodiscard]] Span<DvhContact> view() const noexcept {
        return Span<DvhContact>(dvh_contacts_data(get()), dvh_contacts_len(get()));
    }
    /// What `a` and `b` refer to: DVH_PAIR_KIND_TRIANGLES or DVH_PAIR_KIND_NODES
    /// (dvh_contacts_kind).
    [[nodiscard]] DvhPairKind kind() const noexcept { return dvh_contacts_kind(get()); }
    /// The number of contacts (dvh_contacts_len).
    [[nodiscard]] std::size_t size() const noexcept { return dvh_contacts_len(get()); }
    /// Are there no contacts?
    [[nodiscard]] bool empty() const noexcept { return size() == 0; }
    /// The first contact's position, as view().begin().
    [[nodiscard]] const DvhContact* begin() const noexcept { return view().begin(); }
    /// The position past the last contact, as view().end().
    [[nodiscard]] const DvhContact* end() const noexcept { return view().end(); }
};

/// A reusable result buffer of the continuous queries (DvhImpacts), released by
/// dvh_impacts_free. Use one per thread.
class Impacts : public detail::Owner<DvhImpacts> {
public:
    /// A new, empty buffer (dvh_impacts_new).
    Impacts() : Owner(detail::allocated(dvh_impacts_new())) {}
    /// Takes ownership of `impacts`, a buffer from dvh_impacts_new (or null: an owner of none).
    explicit Impacts(DvhImpacts* impacts) noexcept : Owner(impacts) {}
    /// Takes `other`'s buffer; `other` holds none afterwards.
    Impacts(Impacts&& other) noexcept = default;
    /// Releases the buffer held here, then takes `other`'s.
    Impacts& operator=(Impacts&& other) noexcept = default;

    /// The impacts of the last successful query into the buffer, sorted by
    /// `(kind, a0, a1, b0, b1)`; valid until the next query into it (dvh_impacts_data,
    /// dvh_impacts_len).
    [[nodiscard]] Span<DvhImpact> view() const noexcept {
        return Span<DvhImpact>(dvh_impacts_data(get()), dvh_impacts_len(get()));
    }
    /// The number of impacts (dvh_impacts_len).
    [[nodiscard]] std::size_t size() const noexcept { return dvh_impacts_len(get()); }
    /// Are there no impacts?
    [[nodiscard]] bool empty() const noexcept { return size() == 0; }
    /// The first impact's position, as view().begin().
    [[nodiscard]] const DvhImpact* begin() const noexcept { return view().begin(); }
    /// The position past the last impact, as view().end().
    [[nodiscard]] const DvhImpact* end() const noexcept { return view().end(); }
};

/// A reusable result buffer of the closest-point queries (DvhNearPairs), released by
/// dvh_near_pairs_free. Use one per thread.
class NearPairs : public detail::Owner<DvhNearPairs> {
public:
    /// A new, empty buffer (dvh_near_pairs_new).
    NearPairs() : Owner(detail::allocated(dvh_near_pairs_new())) {}
    /// Takes ownership of `pairs`, a buffer from dvh_near_pairs_new (or null: an owner of none).
    explicit NearPairs(DvhNearPairs* pairs) noexcept : Owner(pairs) {}
    /// Takes `other`'s buffer; `other` holds none afterwards.
    NearPairs(NearPairs&& other) noexcept = default;
    /// Releases the buffer held here, then takes `other`'s.
    NearPairs& operator=(NearPairs&& other) noexcept = default;

    /// The stencils of the last successful query into the buffer, sorted by
    /// `(kind, a0, a1, b0, b1)`; valid until the next query into it (dvh_near_pairs_data,
    /// dvh_near_pairs_len).
    [[nodiscard]] Span<DvhNearPair> view() const noexcept {
        return Span<DvhNearPair>(dvh_near_pairs_data(get()), dvh_near_pairs_len(get()));
    }
    /// The number of stencils (dvh_near_pairs_len).
    [[nodiscard]] std::size_t size() const noexcept { return dvh_near_pairs_len(get()); }
    /// Are there no stencils?
    [[nodiscard]] bool empty() const noexcept { return size() == 0; }
    /// The first stencil's position, as view().begin().
    [[nodiscard]] const DvhNearPair* begin() const noexcept { return view().begin(); }
    /// The position past the last stencil, as view().end().
    [[nodiscard]] const DvhNearPair* end() const noexcept { return view().end(); }
};

/// One curve of a dvh::Curves buffer: its segments, in chain order, and whether it is closed
/// (dvh_curves_curve).
struct Curve {
    /// The curve's segments, each starting where the one before ends.
    Span<DvhCurveSegment> segments;
    /// Does the last segment end where the first starts?
    bool closed;
};

/// A reusable result buffer of the intersection-curve queries (DvhCurves), released by
/// dvh_curves_free. Use one per thread.
class Curves : public detail::Owner<DvhCurves> {
public:
    /// A new, empty buffer (dvh_curves_new).
    Curves() : Owner(detail::allocated(dvh_curves_new())) {}
    /// Takes ownership of `curves`, a buffer from dvh_curves_new (or null: an owner of none).
    explicit Curves(DvhCurves* curves) noexcept : Owner(curves) {}
    /// Takes `other`'s buffer; `other` holds none afterwards.
    Curves(Curves&& other) noexcept = default;
    /// Releases the buffer held here, then takes `other`'s.
    Curves& operator=(Curves&& other) noexcept = default;

    /// The segments of the last successful query into the buffer, curve by curve, each curve's
    /// in chain order; valid until the next query into it (dvh_curves_data, dvh_curves_len).
    [[nodiscard]] Span<DvhCurveSegment> view() const noexcept {
        return Span<DvhCurveSegment>(dvh_curves_data(get()), dvh_curves_len(get()));
    }
    /// The number of segments (dvh_curves_len).
    [[nodiscard]] std::size_t size() const noexcept { return dvh_curves_len(get()); }
    /// Are there no segments?
    [[nodiscard]] bool empty() const noexcept { return size() == 0; }
    /// The first segment's position, as view().begin().
    [[nodiscard]] const DvhCurveSegment* begin() const noexcept { return view().begin(); }
    /// The position past the last segment, as view().end().
    [[nodiscard]] const DvhCurveSegment* end() const noexcept { return view().end(); }
    /// The number of curves (dvh_curves_curve_count).
    [[nodiscard]] std::size_t curve_count() const noexcept { return dvh_curves_curve_count(get()); }
    /// Curve `index` (dvh_curves_curve); throws dvh::Error when `index` is not below
    /// curve_count().
    [[nodiscard]] Curve curve(std::size_t index) const {
        std::size_t first = 0;
        std::size_t count = 0;
        bool closed = false;
        check(dvh_curves_curve(get(), index, &first, &count, &closed));
        return Curve{Span<DvhCurveSegment>(dvh_curves_data(get()) + first, count), closed};
    }
    /// The gradient of the curves' total length with respect to the world positions of the
    /// vertices of `a` and `b`, the meshes and poses of the dvh::intersection_curves() call that
    /// gave them (dvh_curves_length_gradient): three values per vertex, in two new vectors.
    [[nodiscard]] std::pair<std::vector<double>, std::vector<double>> length_gradient(const Mesh& a, const DvhPose* pose_a,
                                                                                      const Mesh& b,
                                                                                      const DvhPose* pose_b) const;
    /// The gradient of the total length of the self-intersection curves of `mesh` with respect
    /// to its vertices (dvh_curves_self_length_gradient): three values per vertex.
    [[nodiscard]] std::vector<double> self_length_gradient(const Mesh& mesh) const;
    /// The intersecting pairs that have no segment, sorted by `(triangle_a, triangle_b)`
    /// (dvh_curves_degenerate_data, dvh_curves_degenerate_len).
    [[nodiscard]] Span<DvhDegeneratePair> degenerate() const noexcept {
        return Span<DvhDegeneratePair>(dvh_curves_degenerate_data(get()), dvh_curves_degenerate_len(get()));
    }
};

/// A reusable result buffer of a scene's continuous query (DvhSceneImpacts), released by
/// dvh_scene_impacts_free. Use one per thread.
class SceneImpacts : public detail::Owner<DvhSceneImpacts> {
public:
    /// A new, empty buffer (dvh_scene_impacts_new).
    SceneImpacts() : Owner(detail::allocated(dvh_scene_impacts_new())) {}
    /// Takes ownership of `impacts`, a buffer from dvh_scene_impacts_new (or null: an owner of
    /// none).
    explicit SceneImpacts(DvhSceneImpacts* impacts) noexcept : Owner(impacts) {}
    /// Takes `other`'s buffer; `other` holds none afterwards.
    SceneImpacts(SceneImpacts&& other) noexcept = default;
    /// Releases the buffer held here, then takes `other`'s.
    SceneImpacts& operator=(SceneImpacts&& other) noexcept = default;

    /// The impacts of the last successful query into the buffer, sorted by
    /// `(object_a, object_b)`, then by `(kind, a0, a1, b0, b1)`; valid until the next query into
    /// it (dvh_scene_impacts_data, dvh_scene_impacts_len).
    [[nodiscard]] Span<DvhSceneImpact> view() const noexcept {
        return Span<DvhSceneImpact>(dvh_scene_impacts_data(get()), dvh_scene_impacts_len(get()));
    }
    /// The number of impacts (dvh_scene_impacts_len).
    [[nodiscard]] std::size_t size() const noexcept { return dvh_scene_impacts_len(get()); }
    /// Are there no impacts?
    [[nodiscard]] bool empty() const noexcept { return size() == 0; }
    /// The first impact's position, as view().begin().
    [[nodiscard]] const DvhSceneImpact* begin() const noexcept { return view().begin(); }
    /// The position past the last impact, as view().end().
    [[nodiscard]] const DvhSceneImpact* end() const noexcept { return view().end(); }
};

/// A reusable result buffer of a scene's closest-point query (DvhSceneNearPairs), released by
/// dvh_scene_near_pairs_free. Use one per thread.
class SceneNearPairs : public detail::Owner<DvhSceneNearPairs> {
public:
    /// A new, empty buffer (dvh_scene_near_pairs_new).
    SceneNearPairs() : Owner(detail::allocated(dvh_scene_near_pairs_new())) {}
    /// Takes ownership of `pairs`, a buffer from dvh_scene_near_pairs_new (or null: an owner of
    /// none).
    explicit SceneNearPairs(DvhSceneNearPairs* pairs) noexcept : Owner(pairs) {}
    /// Takes `other`'s buffer; `other` holds none afterwards.
    SceneNearPairs(SceneNearPairs&& other) noexcept = default;
    /// Releases the buffer held here, then takes `other`'s.
    SceneNearPairs& operator=(SceneNearPairs&& other) noexcept = default;

    /// The stencils of the last successful query into the buffer, sorted by
    /// `(object_a, object_b)`, then by `(kind, a0, a1, b0, b1)`; valid until the next query into
    /// it (dvh_scene_near_pairs_data, dvh_scene_near_pairs_len).
    [[nodiscard]] Span<DvhSceneNearPair> view() const noexcept {
        return Span<DvhSceneNearPair>(dvh_scene_near_pairs_data(get()), dvh_scene_near_pairs_len(get()));
    }
    /// The number of stencils (dvh_scene_near_pairs_len).
    [[nodiscard]] std::size_t size() const noexcept { return dvh_scene_near_pairs_len(get()); }
    /// Are there no stencils?
    [[nodiscard]] bool empty() const noexcept { return size() == 0; }
    /// The first stencil's position, as view().begin().
    [[nodiscard]] const DvhSceneNearPair* begin() const noexcept { return view().begin(); }
    /// The position past the last stencil, as view().end().
    [[nodiscard]] const DvhSceneNearPair* end() const noexcept { return view().end(); }
};

/// Objects queried together (DvhScene), released by dvh_scene_free: rigid ones placed by poses,
/// deformable ones with positions of their own. Each object copies what it needs of its mesh,
/// which may then be refit or destroyed. Every call needs the scene to itself.
class Scene : public detail::Owner<DvhScene> {
public:
    /// A new, empty scene (dvh_scene_create).
    Scene() : Owner(detail::created<DvhScene>([](DvhScene** out) { return dvh_scene_create(out); })) {}
    /// Takes ownership of `scene`, a scene from dvh_scene_create (or null: an owner of none).
    explicit Scene(DvhScene* scene) noexcept : Owner(scene) {}
    /// Takes `other`'s scene; `other` holds none afterwards.
    Scene(Scene&& other) noexcept = default;
    /// Releases the scene held here, then takes `other`'s.
    Scene& operator=(Scene&& other) noexcept = default;

    /// Adds a rigid object, `mesh`'s current positions placed by `pose` (nullptr: the identity),
    /// and returns its id (dvh_scene_add_rigid). Objects `i` and `j` are tested when
    /// `group_i & mask_j` and `group_j & mask_i` are both non-zero; by default an object is in
    /// group 1 and tested against every group.
    std::uint32_t add_rigid(const Mesh& mesh, const DvhPose* pose = nullptr, std::uint32_t group = 1,
                            std::uint32_t mask = 0xffffffffu) {
        std::uint32_t object = 0;
        check(dvh_scene_add_rigid(get(), mesh.get(), pose, group, mask, &object));
        return object;
    }
    /// Adds a deformable object, `mesh`'s current positions as world coordinates, and returns
    /// its id (dvh_scene_add_deformable); groups and masks as for add_rigid().
    std::uint32_t add_deformable(const Mesh& mesh, std::uint32_t group = 1, std::uint32_t mask = 0xffffffffu) {
        std::uint32_t object = 0;
        check(dvh_scene_add_deformable(get(), mesh.get(), group, mask, &object));
        return object;
    }
    /// Places rigid object `object` by `pose` (nullptr: the identity) (dvh_scene_set_pose).
    void set_pose(std::uint32_t object, const DvhPose* pose) { check(dvh_scene_set_pose(get(), object, pose)); }
    /// Gives deformable object `object` new world positions, as many vertices as its mesh; they
    /// are checked now and refit by the next query that needs them (dvh_scene_set_positions).
    void set_positions(std::uint32_t object, const double* positions, std::size_t vertex_count) {
        check(dvh_scene_set_positions(get(), object, positions, vertex_count));
    }
    /// Gives deformable object `object` the new world `positions` (x, y, z per vertex).
    void set_positions(std::uint32_t object, const std::vector<double>& positions) {
        set_positions(object, detail::elements(positions), detail::triples(positions, "positions"));
    }
    /// Gives deformable object `object` packed `float` positions (dvh_scene_set_positions_f32
    /// with a 12-byte stride).
    void set_positions(std::uint32_t object, const float* positions, std::size_t vertex_count) {
        set_positions_strided(object, positions, 3 * sizeof(float), vertex_count);
    }
    /// Gives deformable object `object` packed `float` positions.
    void set_positions(std::uint32_t object, const std::vector<float>& positions) {
        set_positions(object, detail::elements(positions), detail::triples(positions, "positions"));
    }
    /// Gives deformable object `object` `float` positions at a byte stride, as
    /// Mesh::from_strided() reads them (dvh_scene_set_positions_f32).
    void set_positions_strided(std::uint32_t object, const float* positions, std::size_t stride_bytes,
                               std::size_t vertex_count) {
        check(dvh_scene_set_positions_f32(get(), object, positions, stride_bytes, vertex_count));
    }
    /// Turns object `object`'s self-contact on or off (off when added): when on, the queries also
    /// report the object with itself (object_a == object_b). Only a deformable object can touch
    /// itself: on for a rigid one throws, off is accepted (dvh_scene_set_self_contact).
    void set_self_contact(std::uint32_t object, bool on) { check(dvh_scene_set_self_contact(get(), object, on)); }
    /// Gives deformable object `object` a step: every vertex moves in a straight line from `start`
    /// (t = 0) to `end` (t = 1), x, y, z per vertex, as many vertices as its mesh. collide() and
    /// nearest_features() see the object at `end`, continuous_collide() the whole step; the step
    /// lasts until the next set_motion() or set_positions() (dvh_scene_set_motion).
    void set_motion(std::uint32_t object, const double* start, const double* end, std::size_t vertex_count) {
        check(dvh_scene_set_motion(get(), object, start, end, vertex_count));
    }
    /// Gives deformable object `object` the step from `start` to `end` (x, y, z per vertex each).
    void set_motion(std::uint32_t object, const std::vector<double>& start, const std::vector<double>& end) {
        const std::size_t vertex_count = detail::motion_vertices(start, end);
        set_motion(object, detail::elements(start), detail::elements(end), vertex_count);
    }
    /// Gives deformable object `object` a step between packed `float` positions
    /// (dvh_scene_set_motion_f32 with a 12-byte stride).
    void set_motion(std::uint32_t object, const float* start, const float* end, std::size_t vertex_count) {
        set_motion_strided(object, start, end, 3 * sizeof(float), vertex_count);
    }
    /// Gives deformable object `object` a step between packed `float` positions.
    void set_motion(std::uint32_t object, const std::vector<float>& start, const std::vector<float>& end) {
        const std::size_t vertex_count = detail::motion_vertices(start, end);
        set_motion(object, detail::elements(start), detail::elements(end), vertex_count);
    }
    /// Gives deformable object `object` a step between `float` positions at a byte stride, the
    /// same for both, as Mesh::from_strided() reads them (dvh_scene_set_motion_f32).
    void set_motion_strided(std::uint32_t object, const float* start, const float* end, std::size_t stride_bytes,
                            std::size_t vertex_count) {
        check(dvh_scene_set_motion_f32(get(), object, start, end, stride_bytes, vertex_count));
    }
    /// Gives rigid object `object` a step from pose `start` to pose `end` (nullptr: the
    /// identity), each vertex moving in a straight line; it lasts until the next set_pose() or
    /// set_pose_motion() (dvh_scene_set_pose_motion).
    void set_pose_motion(std::uint32_t object, const DvhPose* start, const DvhPose* end) {
        check(dvh_scene_set_pose_motion(get(), object, start, end));
    }
    /// Removes object `object` and its pair exclusions; its id may be given to a later object
    /// (dvh_scene_remove).
    void remove(std::uint32_t object) { check(dvh_scene_remove(get(), object)); }
    /// Never tests objects `object_a` and `object_b` against each other (dvh_scene_exclude_pair).
    void exclude_pair(std::uint32_t object_a, std::uint32_t object_b) {
        check(dvh_scene_exclude_pair(get(), object_a, object_b));
    }
    /// Whether queries refit box volumes block by block as traversals reach them (true, the
    /// default) or every deformable object they need whole (dvh_scene_set_lazy_refit). The
    /// contacts are the same either way.
    void set_lazy_refit(bool lazy) { check(dvh_scene_set_lazy_refit(get(), lazy)); }

    /// Every contact of the frame, between two objects and of each object with self-contact on
    /// with itself, into `contacts`, replacing what it held; returns the counters
    /// (dvh_scene_collide). On failure `contacts` is unchanged.
    DvhSceneStats collide(const QueryOptions& options, Contacts& contacts) {
        DvhSceneStats stats{};
        check(dvh_scene_collide(get(), &options.c(), contacts.get(), &stats));
        return stats;
    }
    /// Every contact of the frame, in a new buffer.
    [[nodiscard]] Contacts collide(const QueryOptions& options = {}) {
        Contacts contacts;
        collide(options, contacts);
        return contacts;
    }

    /// Every impact of the step between two objects, and of each object with self-contact on
    /// with itself, into `impacts`, replacing what it held; returns the counters, sums over the
    /// object pairs queried (dvh_scene_continuous_collide). On failure `impacts` is unchanged.
    DvhCcdStats continuous_collide(const CcdOptions& options, SceneImpacts& impacts) {
        DvhCcdStats stats{};
        check(dvh_scene_continuous_collide(get(), &options.c(), impacts.get(), &stats));
        return stats;
    }
    /// Every impact of the step, in a new buffer.
    [[nodiscard]] SceneImpacts continuous_collide(const CcdOptions& options = {}) {
        SceneImpacts impacts;
        continuous_collide(options, impacts);
        return impacts;
    }

    /// Every stencil within `distance` between two objects, and within each object with
    /// self-contact on, into `pairs`, replacing what it held; returns the counters, sums over the
    /// object pairs queried (`pairs`: the stencils reported) (dvh_scene_nearest_features). On
    /// failure `pairs` is unchanged.
    DvhQueryStats nearest_features(double distance, const QueryOptions& options, SceneNearPairs& pairs) {
        DvhQueryStats stats{};
        check(dvh_scene_nearest_features(get(), distance, &options.c(), pairs.get(), &stats));
        return stats;
    }
    /// Every stencil within `distance`, in a new buffer.
    [[nodiscard]] SceneNearPairs nearest_features(double distance, const QueryOptions& options = {}) {
        SceneNearPairs pairs;
        nearest_features(distance, options, pairs);
        return pairs;
    }
    /// Two objects and the least distance between them (the first object's mesh first).
    struct ObjectsDistance {
        std::uint32_t object_a;
        std::uint32_t object_b;
        DvhDistance distance;
    };
    /// The closest pair of distinct objects the filters allow, the lower id first; none within
    /// the options' bound: nullopt (dvh_scene_distance).
    [[nodiscard]] std::optional<ObjectsDistance> distance(const DistanceOptions& options = {}) {
        ObjectsDistance d{};
        check(dvh_scene_distance(get(), &options.c(), &d.object_a, &d.object_b, &d.distance));
        return d.distance.found ? std::optional<ObjectsDistance>(d) : std::nullopt;
    }
    /// The object closest to `object` that the filters allow it to meet, `object` first; none
    /// within the options' bound: nullopt (dvh_scene_object_distance).
    [[nodiscard]] std::optional<ObjectsDistance> object_distance(std::uint32_t object, const DistanceOptions& options = {}) {
        ObjectsDistance d{};
        d.object_a = object;
        check(dvh_scene_object_distance(get(), object, &options.c(), &d.object_b, &d.distance));
        return d.distance.found ? std::optional<ObjectsDistance>(d) : std::nullopt;
    }
};

/// What intersects between mesh `a` placed by `pose_a` and mesh `b` placed by `pose_b` (nullptr:
/// the identity), as `options` asks, into `pairs`, replacing what it held; returns the counters
/// (dvh_collide). On failure `pairs` is unchanged.
inline DvhQueryStats collide(const Mesh& a, const DvhPose* pose_a, const Mesh& b, const DvhPose* pose_b,
                             const QueryOptions& options, Pairs& pairs) {
    DvhQueryStats stats{};
    check(dvh_collide(a.get(), pose_a, b.get(), pose_b, &options.c(), pairs.get(), &stats));
    return stats;
}

/// What intersects between `a` and `b`, placed by their poses, in a new buffer.
[[nodiscard]] inline Pairs collide(const Mesh& a, const DvhPose* pose_a, const Mesh& b, const DvhPose* pose_b,
                                   const QueryOptions& options = {}) {
    Pairs pairs;
    collide(a, pose_a, b, pose_b, options, pairs);
    return pairs;
}

/// The pairs `(a, b)`, `a < b`, of one mesh's triangles that intersect beyond the vertices and
/// edges they share, into `pairs`; returns the counters (dvh_self_collide).
inline DvhQueryStats self_collide(const Mesh& mesh, const QueryOptions& options, Pairs& pairs) {
    DvhQueryStats stats{};
    check(dvh_self_collide(mesh.get(), &options.c(), pairs.get(), &stats));
    return stats;
}

/// One mesh's self-intersections, in a new buffer.
[[nodiscard]] inline Pairs self_collide(const Mesh& mesh, const QueryOptions& options = {}) {
    Pairs pairs;
    self_collide(mesh, options, pairs);
    return pairs;
}

/// Every triangle pair of `a` and `b`, placed by their poses, at distance `<= distance`, decided
/// exactly, into `pairs`; returns the counters (dvh_proximity).
inline DvhQueryStats proximity(const Mesh& a, const DvhPose* pose_a, const Mesh& b, const DvhPose* pose_b, double distance,
                               const QueryOptions& options, Pairs& pairs) {
    DvhQueryStats stats{};
    check(dvh_proximity(a.get(), pose_a, b.get(), pose_b, distance, &options.c(), pairs.get(), &stats));
    return stats;
}

/// Every triangle pair of `a` and `b` within `distance`, in a new buffer.
[[nodiscard]] inline Pairs proximity(const Mesh& a, const DvhPose* pose_a, const Mesh& b, const DvhPose* pose_b,
                                     double distance, const QueryOptions& options = {}) {
    Pairs pairs;
    proximity(a, pose_a, b, pose_b, distance, options, pairs);
    return pairs;
}

/// The pairs `(a, b)`, `a < b`, of one mesh's triangles sharing no vertex at distance
/// `<= distance`, into `pairs`; returns the counters (dvh_self_proximity).
inline DvhQueryStats self_proximity(const Mesh& mesh, double distance, const QueryOptions& options, Pairs& pairs) {
    DvhQueryStats stats{};
    check(dvh_self_proximity(mesh.get(), distance, &options.c(), pairs.get(), &stats));
    return stats;
}

/// One mesh's triangle pairs sharing no vertex within `distance`, in a new buffer.
[[nodiscard]] inline Pairs self_proximity(const Mesh& mesh, double distance, const QueryOptions& options = {}) {
    Pairs pairs;
    self_proximity(mesh, distance, options, pairs);
    return pairs;
}

/// Every vertex-face and edge-edge pair of `a` and `b`, placed by their poses, at distance
/// `<= distance`, decided exactly, with the distance, closest points, weights and features, into
/// `pairs`, replacing what it held; returns the counters (dvh_nearest_features). On failure
/// `pairs` is unchanged.
inline DvhQueryStats nearest_features(const Mesh& a, const DvhPose* pose_a, const Mesh& b, const DvhPose* pose_b,
                                      double distance, const QueryOptions& options, NearPairs& pairs) {
    DvhQueryStats stats{};
    check(dvh_nearest_features(a.get(), pose_a, b.get(), pose_b, distance, &options.c(), pairs.get(), &stats));
    return stats;
}

/// The stencils of `a` and `b` within `distance`, in a new buffer.
[[nodiscard]] inline NearPairs nearest_features(const Mesh& a, const DvhPose* pose_a, const Mesh& b, const DvhPose* pose_b,
                                                double distance, const QueryOptions& options = {}) {
    NearPairs pairs;
    nearest_features(a, pose_a, b, pose_b, distance, options, pairs);
    return pairs;
}

/// One mesh's stencils with itself (a vertex and a triangle without it, two edges sharing no
/// vertex) within `distance`, into `pairs`; returns the counters (dvh_self_nearest_features).
/// On failure `pairs` is unchanged.
inline DvhQueryStats self_nearest_features(const Mesh& mesh, double distance, const QueryOptions& options,
                                           NearPairs& pairs) {
    DvhQueryStats stats{};
    check(dvh_self_nearest_features(mesh.get(), distance, &options.c(), pairs.get(), &stats));
    return stats;
}

/// One mesh's stencils with itself within `distance`, in a new buffer.
[[nodiscard]] inline NearPairs self_nearest_features(const Mesh& mesh, double distance, const QueryOptions& options = {}) {
    NearPairs pairs;
    self_nearest_features(mesh, distance, options, pairs);
    return pairs;
}

inline std::pair<std::vector<double>, std::vector<double>> Curves::length_gradient(const Mesh& a, const DvhPose* pose_a,
                                                                                  const Mesh& b,
                                                                                  const DvhPose* pose_b) const {
    std::vector<double> ga(3 * a.vertex_count()), gb(3 * b.vertex_count());
    check(dvh_curves_length_gradient(get(), a.get(), pose_a, b.get(), pose_b, ga.data(), a.vertex_count(), gb.data(),
                                     b.vertex_count()));
    return {std::move(ga), std::move(gb)};
}

inline std::vector<double> Curves::self_length_gradient(const Mesh& mesh) const {
    std::vector<double> g(3 * mesh.vertex_count());
    check(dvh_curves_self_length_gradient(get(), mesh.get(), g.data(), mesh.vertex_count()));
    return g;
}

/// The curves along which `a` and `b`, placed by their poses, cross, with the pairs that meet
/// but have no segment, into `curves`, replacing what it held; returns the counters
/// (dvh_intersection_curves). On failure `curves` is unchanged.
inline DvhQueryStats intersection_curves(const Mesh& a, const DvhPose* pose_a, const Mesh& b, const DvhPose* pose_b,
                                         const QueryOptions& options, Curves& curves) {
    DvhQueryStats stats{};
    check(dvh_intersection_curves(a.get(), pose_a, b.get(), pose_b, &options.c(), curves.get(), &stats));
    return stats;
}

/// The curves along which `a` and `b` cross, in a new buffer.
[[nodiscard]] inline Curves intersection_curves(const Mesh& a, const DvhPose* pose_a, const Mesh& b, const DvhPose* pose_b,
                                                const QueryOptions& options = {}) {
    Curves curves;
    intersection_curves(a, pose_a, b, pose_b, options, curves);
    return curves;
}

/// The curves along which `mesh` crosses itself, into `curves`; returns the counters
/// (dvh_self_intersection_curves). On failure `curves` is unchanged.
inline DvhQueryStats self_intersection_curves(const Mesh& mesh, const QueryOptions& options, Curves& curves) {
    DvhQueryStats stats{};
    check(dvh_self_intersection_curves(mesh.get(), &options.c(), curves.get(), &stats));
    return stats;
}

/// The curves along which `mesh` crosses itself, in a new buffer.
[[nodiscard]] inline Curves self_intersection_curves(const Mesh& mesh, const QueryOptions& options = {}) {
    Curves curves;
    self_intersection_curves(mesh, options, curves);
    return curves;
}

/// Do the closed triangles `t1` and `t2` (9 doubles each: three corners, x, y, z) share a point?
/// Exact for every finite input (dvh_triangles_intersect).
[[nodiscard]] inline bool triangles_intersect(const double* t1, const double* t2) {
    bool result = false;
    check(dvh_triangles_intersect(t1, t2, &result));
    return result;
}

/// Do the closed triangles `t1` and `t2` share a point?
[[nodiscard]] inline bool triangles_intersect(const std::array<double, 9>& t1, const std::array<double, 9>& t2) {
    return triangles_intersect(t1.data(), t2.data());
}

/// When, if ever, does a point moving in a straight line first meet a moving closed triangle
/// during the step t in [0, 1]? `start` and `end` hold 12 doubles each: the point, then the
/// triangle's three corners (x, y, z each), at t = 0 and t = 1. The time is the earliest contact
/// rounded down to a double; nullopt when they do not meet. Only the options' mode counts
/// (dvh_ccd_vertex_face).
[[nodiscard]] inline std::optional<double> ccd_vertex_face(const double* start, const double* end,
                                                           const CcdOptions& options = {}) {
    bool hit = false;
    double toi = 0.0;
    check(dvh_ccd_vertex_face(start, end, &options.c(), &hit, &toi));
    return hit ? std::optional<double>(toi) : std::nullopt;
}

/// When does the moving point first meet the moving triangle (the point, then the corners)?
[[nodiscard]] inline std::optional<double> ccd_vertex_face(const std::array<double, 12>& start, const std::array<double, 12>& end,
                                                           const CcdOptions& options = {}) {
    return ccd_vertex_face(start.data(), end.data(), options);
}

/// When, if ever, do two closed segments moving with their ends in straight lines first share
/// a point during the step? `start` and `end` hold 12 doubles each: edge a's two ends, then edge
/// b's (dvh_ccd_edge_edge); otherwise as ccd_vertex_face().
[[nodiscard]] inline std::optional<double> ccd_edge_edge(const double* start, const double* end, const CcdOptions& options = {}) {
    bool hit = false;
    double toi = 0.0;
    check(dvh_ccd_edge_edge(start, end, &options.c(), &hit, &toi));
    return hit ? std::optional<double>(toi) : std::nullopt;
}

/// When do the two moving segments first meet (edge a's ends, then edge b's)?
[[nodiscard]] inline std::optional<double> ccd_edge_edge(const std::array<double, 12>& start, const std::array<double, 12>& end,
                                                         const CcdOptions& options = {}) {
    return ccd_edge_edge(start.data(), end.data(), options);
}

/// Every vertex-face, face-vertex and edge-edge pair of `a` and `b` that meets while each moves
/// through its last motion (Mesh::refit_motion; a mesh refit without one stays still), with the
/// earliest time, into `impacts`, replacing what it held; returns the counters
/// (dvh_continuous_collide). On failure `impacts` is unchanged.
inline DvhCcdStats continuous_collide(const Mesh& a, const Mesh& b, const CcdOptions& options, Impacts& impacts) {
    DvhCcdStats stats{};
    check(dvh_continuous_collide(a.get(), b.get(), &options.c(), impacts.get(), &stats));
    return stats;
}

/// Every impact of `a` and `b` over their motions, in a new buffer.
[[nodiscard]] inline Impacts continuous_collide(const Mesh& a, const Mesh& b, const CcdOptions& options = {}) {
    Impacts impacts;
    continuous_collide(a, b, options, impacts);
    return impacts;
}

/// Every pair of one mesh's primitives that meets during its last motion (a vertex and a
/// triangle without it, two edges sharing no vertex), with the earliest time, into `impacts`;
/// returns the counters (dvh_self_continuous_collide). On failure `impacts` is unchanged.
inline DvhCcdStats self_continuous_collide(const Mesh& mesh, const CcdOptions& options, Impacts& impacts) {
    DvhCcdStats stats{};
    check(dvh_self_continuous_collide(mesh.get(), &options.c(), impacts.get(), &stats));
    return stats;
}

/// One mesh's impacts with itself over its motion, in a new buffer.
[[nodiscard]] inline Impacts self_continuous_collide(const Mesh& mesh, const CcdOptions& options = {}) {
    Impacts impacts;
    self_continuous_collide(mesh, options, impacts);
    return impacts;
}

/// The least distance between the surfaces of `a` placed by `pose_a` and `b` placed by `pose_b`
/// (nullptr: the identity), exactly, with the closest points and the pair of primitives that
/// attains it (dvh_distance). `found` is 0 beyond the options' bound; `intersecting` 1 (distance
/// 0) for meshes that intersect.
[[nodiscard]] inline DvhDistance distance(const Mesh& a, const DvhPose* pose_a, const Mesh& b, const DvhPose* pose_b,
                                          const DistanceOptions& options = {}) {
    DvhDistance d{};
    check(dvh_distance(a.get(), pose_a, b.get(), pose_b, &options.c(), &d, nullptr));
    return d;
}

namespace detail {

/// The number of points in a vector of x, y, z values.
inline std::size_t point_count(const std::vector<double>& points) {
    if (points.size() % 3 != 0)
        throw Error(DVH_STATUS_INVALID_ARGUMENT,
                    "points has " + std::to_string(points.size()) + " values, not three per point");
    return points.size() / 3;
}

}  // namespace detail

/// The closest point of `mesh` placed by `pose` to each of `count` points at `points` (x, y, z
/// each), into `results` (`count` entries); returns the counters (dvh_closest_points).
inline DvhQueryStats closest_points(const Mesh& mesh, const DvhPose* pose, const double* points, std::size_t count,
                                    DvhClosestPoint* results, const DistanceOptions& options = {}) {
    DvhQueryStats stats{};
    check(dvh_closest_points(mesh.get(), pose, points, count, &options.c(), results, &stats));
    return stats;
}

/// The closest point of `mesh` to each point (three values each), in a new vector.
[[nodiscard]] inline std::vector<DvhClosestPoint> closest_points(const Mesh& mesh, const DvhPose* pose,
                                                                 const std::vector<double>& points,
                                                                 const DistanceOptions& options = {}) {
    std::vector<DvhClosestPoint> results(detail::point_count(points));
    closest_points(mesh, pose, points.data(), results.size(), results.data(), options);
    return results;
}

/// The winding number of each of `count` points about the closed surface of `mesh` placed by
/// `pose`, into `winding` (DVH_WINDING_ON_SURFACE on the surface) (dvh_winding_numbers).
inline void winding_numbers(const Mesh& mesh, const DvhPose* pose, const double* points, std::size_t count,
                            std::int32_t* winding, std::uint32_t threads = 0) {
    check(dvh_winding_numbers(mesh.get(), pose, points, count, threads, winding));
}

/// The winding number of each point (three values each), in a new vector.
[[nodiscard]] inline std::vector<std::int32_t> winding_numbers(const Mesh& mesh, const DvhPose* pose,
                                                               const std::vector<double>& points,
                                                               std::uint32_t threads = 0) {
    std::vector<std::int32_t> winding(detail::point_count(points));
    winding_numbers(mesh, pose, points.data(), winding.size(), winding.data(), threads);
    return winding;
}

/// The signed distance of each of `count` points to the closed surface of `mesh` placed by
/// `pose` (negative inside), into `distances`; returns the counters (dvh_signed_distances).
inline DvhQueryStats signed_distances(const Mesh& mesh, const DvhPose* pose, const double* points, std::size_t count,
                                      double* distances, const DistanceOptions& options = {}) {
    DvhQueryStats stats{};
    check(dvh_signed_distances(mesh.get(), pose, points, count, &options.c(), distances, &stats));
    return stats;
}

/// The signed distance of each point (three values each), in a new vector.
[[nodiscard]] inline std::vector<double> signed_distances(const Mesh& mesh, const DvhPose* pose,
                                                          const std::vector<double>& points,
                                                          const DistanceOptions& options = {}) {
    std::vector<double> distances(detail::point_count(points));
    signed_distances(mesh, pose, points.data(), distances.size(), distances.data(), options);
    return distances;
}

}  // namespace dvh

#endif  // DVH_HPP
