// The C++ layer (dvh.hpp): every owner's lifetime and moves, every wrapper against the same call
// made through the raw C API, the errors (status and message, and a failed call changing
// nothing), the spans and the options. Built as C++17 and C++20 by ctests/run.sh, under
// AddressSanitizer (which also catches a handle released twice or never) and
// UndefinedBehaviorSanitizer.
#include <dvh.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <tuple>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

// A check that holds in every build: prints what failed and aborts.
#define REQUIRE(cond)                                                                      \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            std::fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
            std::abort();                                                                  \
        }                                                                                  \
    } while (0)

// `statement` must throw dvh::Error with `expected` and a message containing `needle`.
#define REQUIRE_ERROR(statement, expected, needle)                                                      \
    do {                                                                                                \
        bool thrown_ = false;                                                                           \
        try {                                                                                           \
            statement;                                                                                  \
        } catch (const dvh::Error& e_) {                                                                \
            thrown_ = true;                                                                             \
            require_error(e_, (expected), (needle), __FILE__, __LINE__, #statement);                    \
        }                                                                                               \
        if (!thrown_) {                                                                                 \
            std::fprintf(stderr, "%s:%d: %s did not throw dvh::Error\n", __FILE__, __LINE__, #statement); \
            std::abort();                                                                               \
        }                                                                                               \
    } while (0)

namespace {

void require_error(const dvh::Error& e, DvhStatus expected, const char* needle, const char* file, int line, const char* what) {
    if (e.status() != expected || std::strstr(e.what(), needle) == nullptr) {
        std::fprintf(stderr, "%s:%d: %s threw %s \"%s\", expected %s with \"%s\"\n", file, line, what,
                     dvh::status_name(e.status()), e.what(), dvh::status_name(expected), needle);
        std::abort();
    }
}

// Every owner is move-only, its moves never throw.
template <typename T>
constexpr bool move_only() {
    return !std::is_copy_constructible_v<T> && !std::is_copy_assignable_v<T> && std::is_nothrow_move_constructible_v<T> &&
           std::is_nothrow_move_assignable_v<T>;
}
static_assert(move_only<dvh::Mesh>() && move_only<dvh::Pairs>() && move_only<dvh::Scene>() && move_only<dvh::Contacts>() &&
                  move_only<dvh::Impacts>() && move_only<dvh::NearPairs>(),
              "owners are move-only");
static_assert(std::is_base_of_v<std::runtime_error, dvh::Error>, "dvh::Error is a std::runtime_error");
static_assert(!std::is_convertible_v<DvhMesh*, dvh::Mesh> && !std::is_convertible_v<DvhImpacts*, dvh::Impacts>,
              "adopting a handle is explicit");

// ---- meshes with small integer coordinates (exact in float too) ----

struct Geometry {
    std::vector<double> positions;       // x, y, z per vertex
    std::vector<std::uint32_t> triangles;  // three indices per triangle
    std::size_t vertices() const { return positions.size() / 3; }
    std::size_t count() const { return triangles.size() / 3; }
};

int flat(int, int) { return 0; }
int wave(int i, int j) { return ((i * 3 + j * 5) % 4) - 1; }
int ridge(int i, int j) { return (i % 3 == 0) ? 2 : (j % 2); }

// A height field over an n x n grid, two triangles per cell.
Geometry terrain(int n, int x0, int y0, int (*height)(int, int)) {
    Geometry g;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            g.positions.push_back(x0 + i);
            g.positions.push_back(y0 + j);
            g.positions.push_back(height(i, j));
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            std::uint32_t a = (std::uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (std::uint32_t)n + 2, d = a + (std::uint32_t)n + 1;
            g.triangles.insert(g.triangles.end(), {a, b, c, a, c, d});
        }
    return g;
}

std::uint64_t lcg_state = 12345;
int lcg_below(int n) {
    lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (int)((lcg_state >> 33) % (std::uint64_t)n);
}

// Independent random triangles with coordinates in [lo, lo + span].
Geometry soup(std::size_t count, int lo, int span) {
    Geometry g;
    for (std::size_t t = 0; t < count; t++) {
        for (int k = 0; k < 9; k++) g.positions.push_back(lo + lcg_below(span + 1));
        for (std::uint32_t c = 0; c < 3; c++) g.triangles.push_back((std::uint32_t)(3 * t) + c);
    }
    return g;
}

std::vector<float> to_float(const std::vector<double>& v) { return std::vector<float>(v.begin(), v.end()); }

// `g` moved by (dx, dy, dz).
std::vector<double> moved(const Geometry& g, double dx, double dy, double dz) {
    std::vector<double> p = g.positions;
    for (std::size_t i = 0; i < p.size(); i += 3) {
        p[i] += dx;
        p[i + 1] += dy;
        p[i + 2] += dz;
    }
    return p;
}

DvhPose translation(double x, double y, double z) { return DvhPose{{1, 0, 0, 0, 1, 0, 0, 0, 1}, {x, y, z}}; }

// A quarter turn about z, then a translation.
DvhPose turned(double x, double y, double z) { return DvhPose{{0, -1, 0, 1, 0, 0, 0, 0, 1}, {x, y, z}}; }

// ---- the raw C API, for the references ----

DvhMesh* c_mesh(const Geometry& g, const DvhBuildOptions* options = nullptr) {
    DvhMesh* m = nullptr;
    REQUIRE(dvh_mesh_create(g.positions.data(), g.vertices(), g.triangles.data(), g.count(), options, &m) == DVH_STATUS_OK);
    return m;
}

bool same_pair(const DvhPair& x, const DvhPair& y) { return x.a == y.a && x.b == y.b; }

// The wrapper's result equals the C buffer's: the same pairs, in the same order, of the same kind.
bool same(const dvh::Pairs& pairs, const DvhPairs* c) {
    dvh::Span<DvhPair> v = pairs.view();
    if (v.size() != dvh_pairs_len(c) || pairs.size() != v.size() || pairs.kind() != dvh_pairs_kind(c)) return false;
    for (std::size_t i = 0; i < v.size(); i++)
        if (!same_pair(v[i], dvh_pairs_data(c)[i])) return false;
    return true;
}

std::vector<DvhPair> copy(const dvh::Pairs& pairs) { return std::vector<DvhPair>(pairs.begin(), pairs.end()); }

bool same(const dvh::Pairs& pairs, const std::vector<DvhPair>& expected) {
    if (pairs.size() != expected.size()) return false;
    for (std::size_t i = 0; i < expected.size(); i++)
        if (!same_pair(pairs.view()[i], expected[i])) return false;
    return true;
}

bool same(const dvh::Contacts& contacts, const DvhContacts* c) {
    dvh::Span<DvhContact> v = contacts.view();
    if (v.size() != dvh_contacts_len(c) || contacts.size() != v.size() || contacts.kind() != dvh_contacts_kind(c)) return false;
    for (std::size_t i = 0; i < v.size(); i++) {
        const DvhContact& x = v[i];
        const DvhContact& y = dvh_contacts_data(c)[i];
        if (x.object_a != y.object_a || x.object_b != y.object_b || x.a != y.a || x.b != y.b) return false;
    }
    return true;
}

bool same(const DvhQueryStats& x, const DvhQueryStats& y) {
    return x.bv_tests == y.bv_tests && x.triangle_tests == y.triangle_tests && x.triangle_candidates == y.triangle_candidates &&
           x.leaf_pairs == y.leaf_pairs && x.pairs == y.pairs && x.nodes_refit == y.nodes_refit && x.truncated == y.truncated &&
           x.frontier_pairs == y.frontier_pairs;
}

bool same(const DvhSceneStats& x, const DvhSceneStats& y) {
    return x.objects == y.objects && x.object_pairs_tested == y.object_pairs_tested &&
           x.object_pairs_colliding == y.object_pairs_colliding && x.bv_tests == y.bv_tests && x.triangle_tests == y.triangle_tests &&
           x.nodes_refit == y.nodes_refit && x.contacts == y.contacts && x.truncated == y.truncated;
}

// ---- the tests ----

void test_version_status_and_messages() {
    REQUIRE(std::strcmp(dvh::version(), dvh_version()) == 0);
    REQUIRE(std::strcmp(dvh::status_name(DVH_STATUS_INDEX_OUT_OF_RANGE), "DVH_STATUS_INDEX_OUT_OF_RANGE") == 0);
    REQUIRE(std::strcmp(dvh::status_name(4242), "DVH_STATUS_UNKNOWN") == 0);

    // The message is the C function's, whole (the wrapper asks for its length first); a success
    // clears it.
    REQUIRE(dvh_mesh_validate(nullptr) == DVH_STATUS_NULL_ARGUMENT);
    char c_message[512];
    std::size_t length = dvh_last_error_message(c_message, sizeof c_message);
    REQUIRE(length > 0 && length < sizeof c_message);
    std::string message = dvh::last_error_message();
    REQUIRE(message == c_message && message.size() == length);
    dvh::check(DVH_STATUS_OK);
    REQUIRE_ERROR(dvh::check(dvh_mesh_validate(nullptr)), DVH_STATUS_NULL_ARGUMENT, c_message);
    const double t[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bool hit = false;
    REQUIRE(dvh_triangles_intersect(t, t, &hit) == DVH_STATUS_OK && hit);
    REQUIRE(dvh::last_error_message().empty());
    // A status without a message (none of the library's) still says what it is.
    REQUIRE_ERROR(dvh::check(DVH_STATUS_BUSY), DVH_STATUS_BUSY, "DVH_STATUS_BUSY");
    const dvh::Error made(DVH_STATUS_INVALID_ARGUMENT, "made here");
    REQUIRE(made.status() == DVH_STATUS_INVALID_ARGUMENT && std::strcmp(made.what(), "made here") == 0);
}

void test_span() {
    dvh::Span<int> empty;
    REQUIRE(empty.empty() && empty.size() == 0 && empty.data() == nullptr && empty.begin() == empty.end());
    const int values[] = {3, 1, 4, 1, 5};
    dvh::Span<int> s(values, 5);
    REQUIRE(!s.empty() && s.size() == 5 && s.data() == values && s[2] == 4 && s.end() - s.begin() == 5);
    int sum = 0;
    for (int v : s) sum += v;
    REQUIRE(sum == 14);
    constexpr dvh::Span<int> compile_time;
    static_assert(compile_time.empty(), "spans are constexpr");
#if __cplusplus >= 202002L
    std::span<const int> standard = s;
    REQUIRE(standard.data() == values && standard.size() == 5);
    std::span<const int> none = empty;
    REQUIRE(none.empty());
#endif
}

void test_options() {
    // The defaults are the C defaults.
    const DvhBuildOptions c_default = dvh_build_options_default(), c_rigid = dvh_build_options_rigid();
    const dvh::BuildOptions b;
    REQUIRE(std::memcmp(&b.c(), &c_default, sizeof c_default) == 0);
    REQUIRE(std::memcmp(&dvh::BuildOptions::rigid().c(), &c_rigid, sizeof c_rigid) == 0);
    const DvhQueryOptions c_query = dvh_query_options_default();
    const dvh::QueryOptions q;
    REQUIRE(std::memcmp(&q.c(), &c_query, sizeof c_query) == 0);

    // Setters on a variable return it; on a temporary they chain into a value.
    dvh::BuildOptions o;
    REQUIRE(&o.tree(DVH_TREE_KIND_BINARY) == &o);
    o.radius(DVH_RADIUS_KIND_WRAPPED).leftovers(DVH_LEFTOVER_POLICY_EXTRA_RINGS).volume(DVH_VOLUME_KIND_DVH).refit_threads(3);
    REQUIRE(o.tree() == DVH_TREE_KIND_BINARY && o.radius() == DVH_RADIUS_KIND_WRAPPED &&
            o.leftovers() == DVH_LEFTOVER_POLICY_EXTRA_RINGS && o.volume() == DVH_VOLUME_KIND_DVH && o.refit_threads() == 3);
    REQUIRE(o.c().tree == DVH_TREE_KIND_BINARY && o.c().radius == DVH_RADIUS_KIND_WRAPPED &&
            o.c().leftovers == DVH_LEFTOVER_POLICY_EXTRA_RINGS && o.c().volume == DVH_VOLUME_KIND_DVH && o.c().refit_threads == 3);
    const dvh::BuildOptions chained = dvh::BuildOptions{}
                                          .tree(DVH_TREE_KIND_BINARY)
                                          .radius(DVH_RADIUS_KIND_WRAPPED)
                                          .leftovers(DVH_LEFTOVER_POLICY_EXTRA_RINGS)
                                          .volume(DVH_VOLUME_KIND_DVH)
                                          .refit_threads(3);
    REQUIRE(std::memcmp(&chained.c(), &o.c(), sizeof o.c()) == 0);
    const dvh::BuildOptions from_c = c_rigid;
    REQUIRE(from_c.volume() == DVH_VOLUME_KIND_SBV && from_c.radius() == DVH_RADIUS_KIND_WRAPPED);

    dvh::QueryOptions p;
    REQUIRE(&p.mode(DVH_QUERY_MODE_DEPTH) == &p);
    p.max_depth(4).max_pairs(9).budget(77).threads(2);
    REQUIRE(p.mode() == DVH_QUERY_MODE_DEPTH && p.max_depth() == 4 && p.max_pairs() == 9 && p.budget() == 77 && p.threads() == 2);
    REQUIRE(p.c().mode == DVH_QUERY_MODE_DEPTH && p.c().max_depth == 4 && p.c().max_pairs == 9 && p.c().budget == 77 &&
            p.c().threads == 2);
    const dvh::QueryOptions chained_q = dvh::QueryOptions{}.mode(DVH_QUERY_MODE_DEPTH).max_depth(4).max_pairs(9).budget(77).threads(2);
    REQUIRE(std::memcmp(&chained_q.c(), &p.c(), sizeof p.c()) == 0);
    DvhQueryOptions raw = c_query;
    raw.max_pairs = 5;
    const dvh::QueryOptions from_raw = raw;
    REQUIRE(from_raw.max_pairs() == 5);

    // Values out of range are the library's to refuse.
    const Geometry g = terrain(3, 0, 0, flat);
    REQUIRE_ERROR(dvh::Mesh(g.positions, g.triangles, dvh::BuildOptions{}.tree(7)), DVH_STATUS_INVALID_ARGUMENT, "options->tree = 7");
    const dvh::Mesh m(g.positions, g.triangles);
    dvh::Pairs pairs;
    REQUIRE_ERROR(dvh::collide(m, nullptr, m, nullptr, dvh::QueryOptions{}.mode(9), pairs), DVH_STATUS_INVALID_ARGUMENT,
                  "options->mode = 9");
}

void test_owners() {
    const Geometry g = terrain(4, 0, 0, wave), h = terrain(4, 1, 1, ridge);

    // Mesh: moves, release, adoption, an owner of none.
    dvh::Mesh a(g.positions, g.triangles);
    DvhMesh* raw = a.get();
    REQUIRE(raw != nullptr && static_cast<bool>(a));
    dvh::Mesh b(std::move(a));
    REQUIRE(b.get() == raw && a.get() == nullptr && !a);
    REQUIRE(a.vertex_count() == 0 && a.triangle_count() == 0 && a.node_count() == 0);
    REQUIRE_ERROR((void)a.tree_stats(), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
    REQUIRE_ERROR(a.refit(g.positions), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
    a = std::move(b);  // into an owner of none
    REQUIRE(a.get() == raw && !b);
    dvh::Mesh other(h.positions, h.triangles);
    a = std::move(other);  // releases the first mesh (a leak or a double release would be reported)
    REQUIRE(a.get() != raw && a.vertex_count() == h.vertices() && !other);
    dvh::Mesh& alias = a;
    DvhMesh* kept = a.get();
    a = std::move(alias);  // to itself: keeps its mesh
    REQUIRE(a.get() == kept);
    DvhMesh* released = a.release();
    REQUIRE(released == kept && !a);
    REQUIRE(dvh_mesh_triangle_count(released) == h.count());
    dvh_mesh_free(released);
    dvh::Mesh adopted(c_mesh(g));
    REQUIRE(adopted.triangle_count() == g.count());
    dvh::Mesh none(nullptr);
    REQUIRE(!none);
    // In a container that moves them as it grows.
    std::vector<dvh::Mesh> meshes;
    for (int i = 0; i < 9; i++) meshes.emplace_back(moved(g, i, 0, 0), g.triangles);
    for (const auto& m : meshes) REQUIRE(m.triangle_count() == g.count());

    // Pairs: a result moves with its buffer.
    const dvh::Mesh ma(g.positions, g.triangles), mb(h.positions, h.triangles);
    dvh::Pairs p;
    REQUIRE(p && p.empty() && p.size() == 0 && p.view().empty() && p.kind() == DVH_PAIR_KIND_TRIANGLES);
    dvh::collide(ma, nullptr, mb, nullptr, dvh::QueryOptions{}, p);
    REQUIRE(!p.empty());
    const DvhPair* data = p.view().data();
    const std::size_t n = p.size();
    dvh::Pairs q(std::move(p));
    REQUIRE(q.view().data() == data && q.size() == n && !p && p.size() == 0 && p.view().data() == nullptr);
    REQUIRE(p.kind() == DVH_PAIR_KIND_TRIANGLES && p.begin() == p.end());
    REQUIRE_ERROR(dvh::collide(ma, nullptr, mb, nullptr, dvh::QueryOptions{}, p), DVH_STATUS_NULL_ARGUMENT, "`pairs_out`");
    p = std::move(q);
    REQUIRE(p.view().data() == data && !q);
    p = dvh::Pairs();  // releases the filled buffer
    REQUIRE(p && p.empty());
    DvhPairs* raw_pairs = p.release();
    REQUIRE(dvh_collide(ma.get(), nullptr, mb.get(), nullptr, nullptr, raw_pairs, nullptr) == DVH_STATUS_OK);
    dvh::Pairs adopted_pairs(raw_pairs);
    REQUIRE(adopted_pairs.size() == n);

    // Contacts and Scene.
    dvh::Scene scene;
    DvhScene* raw_scene = scene.get();
    REQUIRE(raw_scene != nullptr);
    REQUIRE(scene.add_deformable(ma) == 0 && scene.add_deformable(mb) == 1);
    dvh::Contacts contacts;
    REQUIRE(contacts && contacts.empty() && contacts.kind() == DVH_PAIR_KIND_TRIANGLES);
    scene.collide(dvh::QueryOptions{}, contacts);
    REQUIRE(contacts.size() == n);
    const DvhContact* first = contacts.view().data();
    dvh::Contacts contacts2(std::move(contacts));
    REQUIRE(contacts2.view().data() == first && !contacts && contacts.size() == 0 && contacts.view().empty());
    REQUIRE(contacts.begin() == contacts.end() && contacts.kind() == DVH_PAIR_KIND_TRIANGLES);
    REQUIRE_ERROR(scene.collide(dvh::QueryOptions{}, contacts), DVH_STATUS_NULL_ARGUMENT, "`contacts_out`");
    contacts = std::move(contacts2);
    REQUIRE(contacts.view().data() == first);
    dvh::Scene scene2(std::move(scene));
    REQUIRE(scene2.get() == raw_scene && !scene);
    REQUIRE_ERROR(scene.add_deformable(ma), DVH_STATUS_NULL_ARGUMENT, "`scene`");
    REQUIRE_ERROR(scene.set_lazy_refit(false), DVH_STATUS_NULL_ARGUMENT, "`scene`");
    scene = std::move(scene2);
    REQUIRE(scene.get() == raw_scene);
    scene = dvh::Scene();  // releases the first scene
    REQUIRE(scene && scene.get() != nullptr);
    DvhScene* raw_scene2 = scene.release();
    DvhContacts* raw_contacts = contacts.release();
    REQUIRE(!scene && !contacts);
    std::uint32_t id = 99;
    REQUIRE(dvh_scene_add_deformable(raw_scene2, ma.get(), 1, 1, &id) == DVH_STATUS_OK && id == 0);
    dvh::Scene adopted_scene(raw_scene2);
    dvh::Contacts adopted_contacts(raw_contacts);
    REQUIRE(adopted_contacts.size() == n);  // the result it held
    adopted_scene.collide(dvh::QueryOptions{}, adopted_contacts);
    REQUIRE(adopted_contacts.empty());
    // A scene keeps what it needs of its meshes: they may go first.
    {
        dvh::Mesh gone(g.positions, g.triangles);
        adopted_scene.add_rigid(gone, nullptr);
    }
    adopted_scene.collide(dvh::QueryOptions{}, adopted_contacts);
    REQUIRE(adopted_contacts.size() > 0);
}

void test_mesh() {
    const Geometry g = terrain(5, 0, 0, ridge), h = terrain(5, 2, 1, wave);
    DvhMesh* c_a = c_mesh(g);
    DvhMesh* c_b = c_mesh(h);
    DvhPairs* c_pairs = dvh_pairs_new();
    REQUIRE(dvh_collide(c_a, nullptr, c_b, nullptr, nullptr, c_pairs, nullptr) == DVH_STATUS_OK && dvh_pairs_len(c_pairs) > 0);
    const dvh::Mesh b(h.positions, h.triangles);
    dvh::Pairs pairs;

    // Every way to build the same mesh gives the same mesh.
    std::vector<std::uint16_t> tris16(g.triangles.begin(), g.triangles.end());
    const std::vector<float> f32 = to_float(g.positions);
    // Interleaved float vertices (position, normal, uv: 32 bytes), misaligned on purpose.
    const std::size_t stride = 32;
    std::vector<unsigned char> storage(g.vertices() * stride + 3);
    unsigned char* base = storage.data() + 2;
    for (std::size_t i = 0; i < g.vertices(); i++) {
        const float v[8] = {f32[3 * i], f32[3 * i + 1], f32[3 * i + 2], 0.0f, 0.0f, 1.0f, 0.5f, 0.25f};
        std::memcpy(base + i * stride, v, sizeof v);
    }
    const float* strided = reinterpret_cast<const float*>(static_cast<const void*>(base));
    std::vector<dvh::Mesh> ways;
    ways.emplace_back(g.positions.data(), g.vertices(), g.triangles.data(), g.count());
    ways.emplace_back(g.positions.data(), g.vertices(), tris16.data(), g.count());
    ways.emplace_back(f32.data(), g.vertices(), g.triangles.data(), g.count());
    ways.push_back(dvh::Mesh::from_strided(strided, stride, g.vertices(), g.triangles.data(), g.count()));
    ways.emplace_back(g.positions, g.triangles);
    ways.emplace_back(g.positions, tris16);
    ways.emplace_back(f32, g.triangles);
    ways.emplace_back(g.positions, g.triangles, dvh::BuildOptions::rigid());
    ways.emplace_back(f32.data(), g.vertices(), g.triangles.data(), g.count(), dvh::BuildOptions{}.tree(DVH_TREE_KIND_BINARY));
    for (const auto& m : ways) {
        REQUIRE(m.vertex_count() == g.vertices() && m.triangle_count() == g.count() && m.node_count() >= 1);
        m.validate();
        dvh::collide(m, nullptr, b, nullptr, dvh::QueryOptions{}, pairs);
        REQUIRE(same(pairs, c_pairs));
    }

    // The accessors give what the C functions give.
    const dvh::Mesh& a = ways.front();
    DvhTreeStats c_tree;
    REQUIRE(dvh_mesh_tree_stats(c_a, &c_tree) == DVH_STATUS_OK);
    const DvhTreeStats tree = a.tree_stats();
    REQUIRE(tree.triangles == c_tree.triangles && tree.rings == c_tree.rings && tree.inner_nodes == c_tree.inner_nodes &&
            tree.levels == c_tree.levels && tree.max_ring_triangles == c_tree.max_ring_triangles);
    DvhRefitStats c_refit;
    REQUIRE(dvh_mesh_last_refit_stats(c_a, &c_refit) == DVH_STATUS_OK);
    DvhRefitStats refit = a.last_refit_stats();
    REQUIRE(refit.nodes_refit == c_refit.nodes_refit && refit.distance_evaluations == c_refit.distance_evaluations);
    REQUIRE(a.node_count() == dvh_mesh_node_count(c_a));
    for (std::uint32_t node = 0; node < a.node_count(); node++) {
        const std::uint32_t* c_tris = nullptr;
        std::size_t c_count = 0;
        REQUIRE(dvh_mesh_node_triangles(a.get(), node, &c_tris, &c_count) == DVH_STATUS_OK);
        const dvh::Span<std::uint32_t> tris = a.node_triangles(node);
        REQUIRE(tris.data() == c_tris && tris.size() == c_count);  // the mesh's own array, not a copy
    }
    REQUIRE(a.node_triangles(0).size() == g.count());
#if __cplusplus >= 202002L
    const std::span<const std::uint32_t> root = a.node_triangles(0);
    REQUIRE(root.size() == g.count());
#endif
    REQUIRE_ERROR((void)a.node_triangles((std::uint32_t)a.node_count()), DVH_STATUS_INVALID_ARGUMENT, "out of range");

    // Build errors: the status and the library's message.
    std::vector<std::uint32_t> bad = {0, 1, 2, 2, 1, 999};
    REQUIRE_ERROR(dvh::Mesh(g.positions.data(), g.vertices(), bad.data(), 2), DVH_STATUS_INDEX_OUT_OF_RANGE,
                  "triangle 1, corner 2: vertex index 999");
    REQUIRE_ERROR(dvh::Mesh(g.positions, bad), DVH_STATUS_INDEX_OUT_OF_RANGE, "triangle 1, corner 2: vertex index 999");
    std::vector<std::uint16_t> bad16 = tris16;
    bad16[4] = 60000;
    REQUIRE_ERROR(dvh::Mesh(g.positions, bad16), DVH_STATUS_INDEX_OUT_OF_RANGE, "triangle 1, corner 1: vertex index 60000");
    std::vector<double> nan_positions = g.positions;
    nan_positions[3 * 5 + 2] = std::nan("");
    REQUIRE_ERROR(dvh::Mesh(nan_positions, g.triangles), DVH_STATUS_NON_FINITE_COORDINATE, "vertex 5: coordinate z is NaN");
    std::vector<float> inf_positions = f32;
    inf_positions[4] = std::numeric_limits<float>::infinity();
    REQUIRE_ERROR(dvh::Mesh(inf_positions, g.triangles), DVH_STATUS_NON_FINITE_COORDINATE, "vertex 1: coordinate y is inf");
    REQUIRE_ERROR((void)dvh::Mesh::from_strided(strided, 8, g.vertices(), g.triangles.data(), g.count()), DVH_STATUS_INVALID_ARGUMENT,
                  "stride_bytes = 8");
    REQUIRE_ERROR(dvh::Mesh(static_cast<const double*>(nullptr), 3, g.triangles.data(), 1), DVH_STATUS_NULL_ARGUMENT,
                  "`positions`");
    // Vectors: a partial triple is refused here; empty vectors are no vertices or no triangles.
    std::vector<double> partial = g.positions;
    partial.push_back(1.0);
    REQUIRE_ERROR(dvh::Mesh(partial, g.triangles), DVH_STATUS_INVALID_ARGUMENT,
                  ("positions holds " + std::to_string(partial.size()) + " values, not a multiple of 3").c_str());
    std::vector<std::uint32_t> partial_tris = {0, 1};
    REQUIRE_ERROR(dvh::Mesh(g.positions, partial_tris), DVH_STATUS_INVALID_ARGUMENT, "triangles holds 2 values");
    REQUIRE_ERROR(dvh::Mesh(g.positions, std::vector<std::uint32_t>()), DVH_STATUS_INVALID_ARGUMENT, "no triangles");
    REQUIRE_ERROR(dvh::Mesh(std::vector<double>(), g.triangles), DVH_STATUS_INDEX_OUT_OF_RANGE, "vertex index");

    // Refits through every overload give what a C refit of the same positions gives.
    dvh::Mesh r(g.positions, g.triangles);
    int step = 0;
    auto refit_and_compare = [&](auto&& refit_with) {
        step++;
        const std::vector<double> p = moved(g, step % 2, step % 3 == 0 ? 1 : 0, 0.5 * (step % 4));
        REQUIRE(dvh_mesh_refit(c_a, p.data(), g.vertices()) == DVH_STATUS_OK);
        refit_with(p);
        r.validate();
        REQUIRE(dvh_collide(c_a, nullptr, c_b, nullptr, nullptr, c_pairs, nullptr) == DVH_STATUS_OK);
        dvh::collide(r, nullptr, b, nullptr, dvh::QueryOptions{}, pairs);
        REQUIRE(same(pairs, c_pairs));
        REQUIRE(r.last_refit_stats().nodes_refit == r.node_count());
    };
    refit_and_compare([&](const std::vector<double>& p) { r.refit(p.data(), g.vertices()); });
    refit_and_compare([&](const std::vector<double>& p) { r.refit(p); });
    refit_and_compare([&](const std::vector<double>& p) { r.refit(to_float(p).data(), g.vertices()); });
    refit_and_compare([&](const std::vector<double>& p) { r.refit(to_float(p)); });
    refit_and_compare([&](const std::vector<double>& p) {
        const std::vector<float> packed = to_float(p);
        for (std::size_t i = 0; i < g.vertices(); i++) std::memcpy(base + i * stride, &packed[3 * i], 3 * sizeof(float));
        r.refit_strided(strided, stride, g.vertices());
    });
    REQUIRE(!pairs.empty());

    // A failed refit leaves the mesh as it was: the same answer, the same counters.
    const std::vector<DvhPair> before = copy(pairs);
    const DvhRefitStats refit_before = r.last_refit_stats();
    std::vector<double> nan_refit = g.positions;
    nan_refit[3 * 4 + 1] = std::nan("");
    REQUIRE_ERROR(r.refit(nan_refit), DVH_STATUS_NON_FINITE_COORDINATE, "vertex 4: coordinate y is NaN");
    REQUIRE_ERROR(r.refit(nan_refit.data(), g.vertices() - 1), DVH_STATUS_INVALID_ARGUMENT, "vertex_count");
    REQUIRE_ERROR(r.refit(std::vector<double>(nan_refit.begin(), nan_refit.end() - 1)), DVH_STATUS_INVALID_ARGUMENT,
                  "not a multiple of 3");
    REQUIRE_ERROR(r.refit(to_float(nan_refit)), DVH_STATUS_NON_FINITE_COORDINATE, "vertex 4: coordinate y is NaN");
    REQUIRE_ERROR(r.refit_strided(strided, 4, g.vertices()), DVH_STATUS_INVALID_ARGUMENT, "stride_bytes = 4");
    REQUIRE(r.last_refit_stats().nodes_refit == refit_before.nodes_refit &&
            r.last_refit_stats().distance_evaluations == refit_before.distance_evaluations);
    r.validate();
    dvh::collide(r, nullptr, b, nullptr, dvh::QueryOptions{}, pairs);
    REQUIRE(same(pairs, before));

    dvh_pairs_free(c_pairs);
    dvh_mesh_free(c_a);
    dvh_mesh_free(c_b);
}

void test_queries() {
    lcg_state = 7;
    const Geometry g = terrain(6, 0, 0, wave), h = terrain(5, 1, 2, ridge), s = soup(200, 0, 10);
    const dvh::Mesh a(g.positions, g.triangles), b(h.positions, h.triangles), sm(s.positions, s.triangles);
    DvhMesh* c_a = c_mesh(g);
    DvhMesh* c_b = c_mesh(h);
    DvhMesh* c_s = c_mesh(s);
    DvhPairs* c_pairs = dvh_pairs_new();
    dvh::Pairs pairs;
    const DvhPose pose_a = translation(0, 0, 0.5), pose_b = turned(5, 0, 0);
    DvhQueryStats c_stats;

    // collide, every mode, with and without poses, against dvh_collide.
    for (DvhQueryMode mode = DVH_QUERY_MODE_TRIANGLES; mode <= DVH_QUERY_MODE_BUDGET; mode++)
        for (int posed = 0; posed < 2; posed++) {
            const DvhPose* pa = posed ? &pose_a : nullptr;
            const DvhPose* pb = posed ? &pose_b : nullptr;
            const dvh::QueryOptions o = dvh::QueryOptions{}.mode(mode).max_depth(2).budget(30).threads(1);
            REQUIRE(dvh_collide(c_a, pa, c_b, pb, &o.c(), c_pairs, &c_stats) == DVH_STATUS_OK);
            const DvhQueryStats stats = dvh::collide(a, pa, b, pb, o, pairs);
            REQUIRE(same(pairs, c_pairs) && same(stats, c_stats));
            REQUIRE(same(dvh::collide(a, pa, b, pb, o), c_pairs));
            REQUIRE(pairs.kind() == (mode >= DVH_QUERY_MODE_LEAVES ? DVH_PAIR_KIND_NODES : DVH_PAIR_KIND_TRIANGLES));
        }
    REQUIRE(dvh_collide(c_a, nullptr, c_b, nullptr, nullptr, c_pairs, nullptr) == DVH_STATUS_OK && dvh_pairs_len(c_pairs) > 2);
    REQUIRE(same(dvh::collide(a, nullptr, b, nullptr), c_pairs));
    const DvhQueryStats cut = dvh::collide(a, nullptr, b, nullptr, dvh::QueryOptions{}.max_pairs(2), pairs);
    REQUIRE(pairs.size() == 2 && cut.truncated);

    // A failed query leaves the buffer as it was.
    dvh::collide(a, nullptr, b, nullptr, dvh::QueryOptions{}, pairs);
    const std::vector<DvhPair> before = copy(pairs);
    REQUIRE(!before.empty());
    REQUIRE_ERROR(dvh::collide(a, nullptr, b, nullptr, dvh::QueryOptions{}.mode(DVH_QUERY_MODE_BUDGET).budget(0), pairs),
                  DVH_STATUS_INVALID_ARGUMENT, "options->budget = 0");
    DvhPose nan_pose = pose_b;
    nan_pose.translation[2] = std::nan("");
    REQUIRE_ERROR(dvh::collide(a, nullptr, b, &nan_pose, dvh::QueryOptions{}, pairs), DVH_STATUS_NON_FINITE_COORDINATE,
                  "pose_b: pose translation[2] is NaN");
    DvhPose skewed = pose_a;
    skewed.rotation[0] = 1.1;
    REQUIRE_ERROR(dvh::collide(a, &skewed, b, nullptr, dvh::QueryOptions{}, pairs), DVH_STATUS_NON_RIGID_POSE, "pose_a");
    REQUIRE_ERROR((void)dvh::collide(a, &skewed, b, nullptr), DVH_STATUS_NON_RIGID_POSE, "pose_a");
    REQUIRE_ERROR(dvh::collide(dvh::Mesh(nullptr), nullptr, b, nullptr, dvh::QueryOptions{}, pairs), DVH_STATUS_NULL_ARGUMENT, "`a`");
    REQUIRE(same(pairs, before));

    // self_collide against dvh_self_collide.
    for (DvhQueryMode mode = DVH_QUERY_MODE_TRIANGLES; mode <= DVH_QUERY_MODE_BUDGET; mode++) {
        const dvh::QueryOptions o = dvh::QueryOptions{}.mode(mode).max_depth(2).budget(50).threads(1);
        REQUIRE(dvh_self_collide(c_s, &o.c(), c_pairs, &c_stats) == DVH_STATUS_OK);
        REQUIRE(same(dvh::self_collide(sm, o), c_pairs));
        const DvhQueryStats stats = dvh::self_collide(sm, o, pairs);
        REQUIRE(same(pairs, c_pairs) && same(stats, c_stats));
    }
    REQUIRE(dvh_self_collide(c_s, nullptr, c_pairs, nullptr) == DVH_STATUS_OK && dvh_pairs_len(c_pairs) > 0);
    REQUIRE(same(dvh::self_collide(sm), c_pairs));
    REQUIRE(dvh::self_collide(a).empty());  // an intact surface
    const std::vector<DvhPair> self_before = copy(dvh::self_collide(sm));
    dvh::self_collide(sm, dvh::QueryOptions{}, pairs);
    REQUIRE_ERROR(dvh::self_collide(sm, dvh::QueryOptions{}.mode(9), pairs), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 9");
    REQUIRE(same(pairs, self_before));

    // proximity and self_proximity against dvh_proximity and dvh_self_proximity.
    for (double distance : {0.0, 0.5, 1.0, 3.0}) {
        const dvh::QueryOptions o = dvh::QueryOptions{}.threads(1);
        REQUIRE(dvh_proximity(c_a, &pose_a, c_b, &pose_b, distance, &o.c(), c_pairs, &c_stats) == DVH_STATUS_OK);
        DvhQueryStats stats = dvh::proximity(a, &pose_a, b, &pose_b, distance, o, pairs);
        REQUIRE(same(pairs, c_pairs) && same(stats, c_stats));
        REQUIRE(same(dvh::proximity(a, &pose_a, b, &pose_b, distance), c_pairs));
        REQUIRE(dvh_self_proximity(c_a, distance, &o.c(), c_pairs, &c_stats) == DVH_STATUS_OK);
        stats = dvh::self_proximity(a, distance, o, pairs);
        REQUIRE(same(pairs, c_pairs) && same(stats, c_stats));
        REQUIRE(same(dvh::self_proximity(a, distance), c_pairs));
    }
    REQUIRE(!pairs.empty());
    const std::vector<DvhPair> near_before = copy(pairs);
    REQUIRE_ERROR(dvh::proximity(a, nullptr, b, nullptr, -1.0, dvh::QueryOptions{}, pairs), DVH_STATUS_INVALID_ARGUMENT, "distance");
    REQUIRE_ERROR(dvh::self_proximity(a, std::nan(""), dvh::QueryOptions{}, pairs), DVH_STATUS_INVALID_ARGUMENT, "distance");
    REQUIRE_ERROR((void)dvh::self_proximity(a, -1.0), DVH_STATUS_INVALID_ARGUMENT, "distance");
    REQUIRE(same(pairs, near_before));

    // triangles_intersect against dvh_triangles_intersect.
    lcg_state = 99;
    int hits = 0;
    for (int k = 0; k < 500; k++) {
        std::array<double, 9> t1{}, t2{};
        for (int c = 0; c < 9; c++) {
            t1[c] = lcg_below(5) - 2;
            t2[c] = lcg_below(5) - 2;
        }
        bool c_hit = false;
        REQUIRE(dvh_triangles_intersect(t1.data(), t2.data(), &c_hit) == DVH_STATUS_OK);
        REQUIRE(dvh::triangles_intersect(t1, t2) == c_hit && dvh::triangles_intersect(t1.data(), t2.data()) == c_hit);
        hits += c_hit;
    }
    REQUIRE(hits > 0 && hits < 500);
    double t1[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, t2[9] = {0};
    t2[7] = std::nan("");
    REQUIRE_ERROR((void)dvh::triangles_intersect(t1, t2), DVH_STATUS_NON_FINITE_COORDINATE, "t2[7] is NaN");
    REQUIRE_ERROR((void)dvh::triangles_intersect(nullptr, t1), DVH_STATUS_NULL_ARGUMENT, "`t1`");

    dvh_pairs_free(c_pairs);
    dvh_mesh_free(c_a);
    dvh_mesh_free(c_b);
    dvh_mesh_free(c_s);
}

// Every verb of dvh::Scene, each mirrored on a scene driven through the C API: the contacts and
// counters must be the same after each.
void test_scene() {
    const Geometry g = terrain(6, 0, 0, wave), h = terrain(5, 1, 1, ridge);
    const dvh::Mesh a(g.positions, g.triangles), b(h.positions, h.triangles);
    dvh::Scene scene;
    DvhScene* c_scene = nullptr;
    REQUIRE(dvh_scene_create(&c_scene) == DVH_STATUS_OK);
    dvh::Contacts contacts;
    DvhContacts* c_contacts = dvh_contacts_new();
    std::uint32_t id = 0;
    const dvh::QueryOptions one = dvh::QueryOptions{}.threads(1);
    auto compare = [&](const dvh::QueryOptions& o) {
        DvhSceneStats c_stats;
        REQUIRE(dvh_scene_collide(c_scene, &o.c(), c_contacts, &c_stats) == DVH_STATUS_OK);
        const DvhSceneStats stats = scene.collide(o, contacts);
        REQUIRE(same(contacts, c_contacts) && same(stats, c_stats));
    };

    const DvhPose near = turned(6, 0, 0.5), far = translation(30, 0, 0);
    REQUIRE(scene.add_deformable(a) == 0);
    REQUIRE(dvh_scene_add_deformable(c_scene, a.get(), 1, 0xffffffffu, &id) == DVH_STATUS_OK && id == 0);
    REQUIRE(scene.add_rigid(b, &near) == 1);
    REQUIRE(dvh_scene_add_rigid(c_scene, b.get(), &near, 1, 0xffffffffu, &id) == DVH_STATUS_OK && id == 1);
    REQUIRE(scene.add_rigid(b, &far, 1, 0xffffffffu) == 2);
    REQUIRE(dvh_scene_add_rigid(c_scene, b.get(), &far, 1, 0xffffffffu, &id) == DVH_STATUS_OK && id == 2);
    REQUIRE(scene.add_deformable(a, 2, 2) == 3);
    REQUIRE(dvh_scene_add_deformable(c_scene, a.get(), 2, 2, &id) == DVH_STATUS_OK && id == 3);
    compare(one);
    REQUIRE(!contacts.empty());

    // New positions through every overload.
    std::uint32_t object = 0;
    int step = 0;
    auto move_and_compare = [&](auto&& set) {
        step++;
        const std::vector<double> p = moved(g, 0.5 * step, step % 2, 1.0 + 0.25 * step);
        REQUIRE(dvh_scene_set_positions(c_scene, object, p.data(), g.vertices()) == DVH_STATUS_OK);
        set(p);
        compare(one);
    };
    move_and_compare([&](const std::vector<double>& p) { scene.set_positions(object, p.data(), g.vertices()); });
    move_and_compare([&](const std::vector<double>& p) { scene.set_positions(object, p); });
    move_and_compare([&](const std::vector<double>& p) { scene.set_positions(object, to_float(p).data(), g.vertices()); });
    move_and_compare([&](const std::vector<double>& p) { scene.set_positions(object, to_float(p)); });
    move_and_compare([&](const std::vector<double>& p) {
        std::vector<float> padded;  // x, y, z, w
        for (std::size_t i = 0; i < g.vertices(); i++)
            padded.insert(padded.end(), {(float)p[3 * i], (float)p[3 * i + 1], (float)p[3 * i + 2], 0.0f});
        scene.set_positions_strided(object, padded.data(), 4 * sizeof(float), g.vertices());
    });
    REQUIRE(!contacts.empty());

    // Poses, every mode, the lazy refit off, exclusions, removal and id reuse.
    const DvhPose nearer = turned(5, 1, 0.5);
    scene.set_pose(1, &nearer);
    REQUIRE(dvh_scene_set_pose(c_scene, 1, &nearer) == DVH_STATUS_OK);
    compare(one);
    scene.set_pose(2, nullptr);  // the identity: right on object 0's rest place
    REQUIRE(dvh_scene_set_pose(c_scene, 2, nullptr) == DVH_STATUS_OK);
    for (DvhQueryMode mode = DVH_QUERY_MODE_TRIANGLES; mode <= DVH_QUERY_MODE_BUDGET; mode++) {
        compare(dvh::QueryOptions{}.mode(mode).max_depth(2).budget(30).threads(1));
        REQUIRE(contacts.kind() == (mode >= DVH_QUERY_MODE_LEAVES ? DVH_PAIR_KIND_NODES : DVH_PAIR_KIND_TRIANGLES));
    }
    compare(dvh::QueryOptions{}.max_pairs(3).threads(1));
    REQUIRE(contacts.size() == 3);
    scene.set_lazy_refit(false);
    REQUIRE(dvh_scene_set_lazy_refit(c_scene, false) == DVH_STATUS_OK);
    object = 3;
    move_and_compare([&](const std::vector<double>& p) { scene.set_positions(object, p); });
    scene.exclude_pair(0, 1);
    REQUIRE(dvh_scene_exclude_pair(c_scene, 0, 1) == DVH_STATUS_OK);
    compare(one);
    for (const DvhContact& c : contacts) REQUIRE(!(c.object_a == 0 && c.object_b == 1));
    scene.remove(2);
    REQUIRE(dvh_scene_remove(c_scene, 2) == DVH_STATUS_OK);
    compare(one);
    REQUIRE(scene.add_rigid(b, &nearer, 1, 1) == 2);
    REQUIRE(dvh_scene_add_rigid(c_scene, b.get(), &nearer, 1, 1, &id) == DVH_STATUS_OK && id == 2);
    compare(one);
    REQUIRE(dvh_scene_collide(c_scene, nullptr, c_contacts, nullptr) == DVH_STATUS_OK);
    REQUIRE(same(scene.collide(), c_contacts));

    // Errors: the status, the message, and the scene and its last result as they were.
    REQUIRE(!contacts.empty());
    const std::vector<DvhContact> kept(contacts.begin(), contacts.end());
    REQUIRE_ERROR(scene.set_pose(0, nullptr), DVH_STATUS_INVALID_ARGUMENT, "object 0 is deformable");
    REQUIRE_ERROR(scene.set_pose(9, &near), DVH_STATUS_INVALID_ARGUMENT, "object 9 is not in the scene");
    DvhPose skewed = near;
    skewed.rotation[0] = 2.0;
    REQUIRE_ERROR(scene.set_pose(1, &skewed), DVH_STATUS_NON_RIGID_POSE, "pose");
    REQUIRE_ERROR(scene.add_rigid(b, &skewed), DVH_STATUS_NON_RIGID_POSE, "pose");
    std::vector<double> nan_positions = g.positions;
    nan_positions[3 * 2 + 1] = std::nan("");
    REQUIRE_ERROR(scene.set_positions(0, nan_positions), DVH_STATUS_NON_FINITE_COORDINATE, "object 0: vertex 2: coordinate y is NaN");
    REQUIRE_ERROR(scene.set_positions(0, to_float(nan_positions)), DVH_STATUS_NON_FINITE_COORDINATE, "coordinate y is NaN");
    REQUIRE_ERROR(scene.set_positions(1, h.positions), DVH_STATUS_INVALID_ARGUMENT, "object 1 is rigid");
    REQUIRE_ERROR(scene.set_positions(0, g.positions.data(), 3), DVH_STATUS_INVALID_ARGUMENT, "vertex_count = 3, but object 0 has");
    REQUIRE_ERROR(scene.set_positions_strided(0, to_float(g.positions).data(), 8, g.vertices()), DVH_STATUS_INVALID_ARGUMENT,
                  "stride_bytes = 8");
    REQUIRE_ERROR(scene.remove(7), DVH_STATUS_INVALID_ARGUMENT, "object 7");
    REQUIRE_ERROR(scene.exclude_pair(1, 1), DVH_STATUS_INVALID_ARGUMENT, "object 1 was paired with itself");
    REQUIRE_ERROR(scene.add_deformable(dvh::Mesh(nullptr)), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
    REQUIRE_ERROR(scene.collide(dvh::QueryOptions{}.mode(9), contacts), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 9");
    REQUIRE_ERROR((void)scene.collide(dvh::QueryOptions{}.mode(DVH_QUERY_MODE_BUDGET)), DVH_STATUS_INVALID_ARGUMENT,
                  "options->budget = 0");
    REQUIRE(contacts.size() == kept.size());
    for (std::size_t i = 0; i < kept.size(); i++)
        REQUIRE(std::memcmp(&contacts.view()[i], &kept[i], sizeof(DvhContact)) == 0);
    compare(one);

    dvh_contacts_free(c_contacts);
    dvh_scene_free(c_scene);
}

// ---- continuous collision ----

bool same(const DvhImpact& x, const DvhImpact& y) {
    return x.kind == y.kind && x.a0 == y.a0 && x.a1 == y.a1 && x.b0 == y.b0 && x.b1 == y.b1 && x.toi == y.toi;
}

// The wrapper's impacts equal the C buffer's, in the same order.
bool same(const dvh::Impacts& impacts, const DvhImpacts* c) {
    const dvh::Span<DvhImpact> v = impacts.view();
    if (v.size() != dvh_impacts_len(c) || impacts.size() != v.size()) return false;
    if (v.empty()) return v.data() == nullptr && dvh_impacts_data(c) == nullptr;
    for (std::size_t i = 0; i < v.size(); i++)
        if (!same(v[i], dvh_impacts_data(c)[i])) return false;
    return true;
}

bool same(const dvh::Impacts& impacts, const std::vector<DvhImpact>& expected) {
    if (impacts.size() != expected.size()) return false;
    for (std::size_t i = 0; i < expected.size(); i++)
        if (!same(impacts.view()[i], expected[i])) return false;
    return true;
}

std::vector<DvhImpact> copy(const dvh::Impacts& impacts) { return std::vector<DvhImpact>(impacts.begin(), impacts.end()); }

bool same(const DvhCcdStats& x, const DvhCcdStats& y) {
    return x.bv_tests == y.bv_tests && x.primitive_tests == y.primitive_tests && x.impacts == y.impacts &&
           x.earliest_toi == y.earliest_toi && x.truncated == y.truncated;
}

DvhImpact impact(DvhImpactKind kind, std::uint32_t a0, std::uint32_t a1, std::uint32_t b0, std::uint32_t b1, double toi) {
    DvhImpact i{};
    i.kind = kind;
    i.a0 = a0;
    i.a1 = a1;
    i.b0 = b0;
    i.b1 = b1;
    i.toi = toi;
    return i;
}

// A still floor triangle in z = 0 and a tilted triangle falling by 4 through it, apart at the
// start and at the end (as in test_api.c): B's height over (x, y) at the start is
// 2 + x/2 + y/4, and each pair meets when that height has fallen to 0.
const std::vector<double> floor_positions = {0, 0, 0, 4, 0, 0, 0, 4, 0};
const std::vector<double> falling_start = {1, 1, 2.75, -3, -1, 0.25, 1, -3, 1.75};
const std::vector<double> falling_end = {1, 1, -1.25, -3, -1, -3.75, 1, -3, -2.25};
const std::vector<std::uint32_t> one_triangle = {0, 1, 2};
// continuous_collide(falling, floor).
const std::vector<DvhImpact> falling_impacts = {
    impact(DVH_IMPACT_KIND_VERTEX_FACE, 0, 0, 0, 0, 0.6875),
    impact(DVH_IMPACT_KIND_FACE_VERTEX, 0, 0, 0, 0, 0.5),
    impact(DVH_IMPACT_KIND_EDGE_EDGE, 0, 1, 0, 2, 0.53125),
    impact(DVH_IMPACT_KIND_EDGE_EDGE, 0, 2, 0, 1, 0.625),
};

void test_ccd_options() {
    const DvhCcdOptions c_default = dvh_ccd_options_default();
    const dvh::CcdOptions o;
    REQUIRE(o.c().mode == c_default.mode && o.c().threads == c_default.threads && o.c().max_impacts == c_default.max_impacts &&
            o.c().earliest_only == c_default.earliest_only);
    REQUIRE(o.mode() == dvh::CcdMode::exact && o.threads() == 0 && o.max_impacts() == 0 && !o.earliest_only());
    static_assert(static_cast<DvhCcdMode>(dvh::CcdMode::exact) == DVH_CCD_MODE_EXACT &&
                      static_cast<DvhCcdMode>(dvh::CcdMode::conservative) == DVH_CCD_MODE_CONSERVATIVE,
                  "the modes are the C constants");

    dvh::CcdOptions p;
    REQUIRE(&p.mode(dvh::CcdMode::conservative) == &p);
    p.threads(2).max_impacts(9).earliest_only(true);
    REQUIRE(p.mode() == dvh::CcdMode::conservative && p.threads() == 2 && p.max_impacts() == 9 && p.earliest_only());
    REQUIRE(p.c().mode == DVH_CCD_MODE_CONSERVATIVE && p.c().threads == 2 && p.c().max_impacts == 9 && p.c().earliest_only);
    const dvh::CcdOptions chained = dvh::CcdOptions{}.mode(dvh::CcdMode::conservative).threads(2).max_impacts(9).earliest_only(true);
    REQUIRE(chained.c().mode == p.c().mode && chained.c().threads == p.c().threads && chained.c().max_impacts == p.c().max_impacts &&
            chained.c().earliest_only == p.c().earliest_only);
    // The C constants work too, and a raw value out of range is the library's to refuse.
    REQUIRE(dvh::CcdOptions{}.mode(DVH_CCD_MODE_CONSERVATIVE).mode() == dvh::CcdMode::conservative);
    REQUIRE(dvh::CcdOptions{}.mode(dvh::CcdMode::conservative).mode(DVH_CCD_MODE_EXACT).c().mode == DVH_CCD_MODE_EXACT);
    REQUIRE(dvh::CcdOptions{}.mode(7).c().mode == 7);
    DvhCcdOptions raw = c_default;
    raw.max_impacts = 5;
    raw.earliest_only = true;
    const dvh::CcdOptions from_raw = raw;
    REQUIRE(from_raw.max_impacts() == 5 && from_raw.earliest_only() && !dvh::CcdOptions(raw).earliest_only(false).earliest_only());
}

void test_ccd_primitives() {
    // A point falling through the floor triangle: z = 1 - 4t meets z = 0 at t = 1/4 exactly.
    std::array<double, 12> s = {0.25, 0.25, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::array<double, 12> e = {0.25, 0.25, -3, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    auto c_test = [](auto test, const double* start, const double* end, DvhCcdMode mode) {
        DvhCcdOptions o = dvh_ccd_options_default();
        o.mode = mode;
        bool hit = false;
        double toi = -1.0;
        REQUIRE(test(start, end, &o, &hit, &toi) == DVH_STATUS_OK);
        return hit ? std::optional<double>(toi) : std::nullopt;
    };
    const std::optional<double> fall = dvh::ccd_vertex_face(s, e);
    REQUIRE(fall && *fall == 0.25);
    REQUIRE(dvh::ccd_vertex_face(s.data(), e.data()) == fall);
    REQUIRE(dvh::ccd_vertex_face(e, s) == 0.75);  // rising
    for (const dvh::CcdMode mode : {dvh::CcdMode::exact, dvh::CcdMode::conservative}) {
        const std::optional<double> t = dvh::ccd_vertex_face(s, e, dvh::CcdOptions{}.mode(mode));
        REQUIRE(t == c_test(dvh_ccd_vertex_face, s.data(), e.data(), static_cast<DvhCcdMode>(mode)));
        REQUIRE(t && *t <= 0.25);
    }
    // The other fields are ignored.
    REQUIRE(dvh::ccd_vertex_face(s, e, dvh::CcdOptions{}.threads(3).max_impacts(1).earliest_only(true)) == 0.25);
    // A miss.
    std::array<double, 12> s_miss = s, e_miss = e;
    s_miss[0] = e_miss[0] = 2.0;
    REQUIRE(!dvh::ccd_vertex_face(s_miss, e_miss));
    REQUIRE(!dvh::ccd_vertex_face(s_miss, e_miss, dvh::CcdOptions{}.mode(dvh::CcdMode::conservative)));

    // Edge a along x at y = 1/2 falls from z = 3/4 (z = 3/4 - 2t) across the still edge b along y
    // at x = 1/2: they cross at t = 3/8.
    const std::array<double, 12> es = {0, 0.5, 0.75, 1, 0.5, 0.75, 0.5, 0, 0, 0.5, 1, 0};
    const std::array<double, 12> ee = {0, 0.5, -1.25, 1, 0.5, -1.25, 0.5, 0, 0, 0.5, 1, 0};
    REQUIRE(dvh::ccd_edge_edge(es, ee) == 0.375);
    REQUIRE(dvh::ccd_edge_edge(es.data(), ee.data(), dvh::CcdOptions{}.mode(dvh::CcdMode::exact)) == 0.375);
    REQUIRE(dvh::ccd_edge_edge(es, ee, dvh::CcdOptions{}.mode(dvh::CcdMode::conservative)) ==
            c_test(dvh_ccd_edge_edge, es.data(), ee.data(), DVH_CCD_MODE_CONSERVATIVE));
    std::array<double, 12> es_miss = es, ee_miss = ee;
    es_miss[6] = es_miss[9] = ee_miss[6] = ee_miss[9] = 1.5;  // edge b beyond edge a's end
    REQUIRE(!dvh::ccd_edge_edge(es_miss, ee_miss));
    // Random small integer motions: the wrappers say what the C functions say.
    lcg_state = 31;
    int hits = 0;
    for (int k = 0; k < 400; k++) {
        std::array<double, 12> a{}, b{};
        for (int c = 0; c < 12; c++) {
            a[c] = lcg_below(5) - 2;
            b[c] = lcg_below(5) - 2;
        }
        const std::optional<double> vf = dvh::ccd_vertex_face(a, b), ef = dvh::ccd_edge_edge(a, b);
        REQUIRE(vf == c_test(dvh_ccd_vertex_face, a.data(), b.data(), DVH_CCD_MODE_EXACT));
        REQUIRE(ef == c_test(dvh_ccd_edge_edge, a.data(), b.data(), DVH_CCD_MODE_EXACT));
        hits += vf.has_value() + ef.has_value();
    }
    REQUIRE(hits > 0 && hits < 800);

    // Errors: the status and the library's message.
    std::array<double, 12> nan_start = s;
    nan_start[4] = std::nan("");
    REQUIRE_ERROR((void)dvh::ccd_vertex_face(nan_start, e), DVH_STATUS_NON_FINITE_COORDINATE, "start[4] is NaN, not a finite number");
    std::array<double, 12> inf_end = ee;
    inf_end[11] = std::numeric_limits<double>::infinity();
    REQUIRE_ERROR((void)dvh::ccd_edge_edge(es, inf_end), DVH_STATUS_NON_FINITE_COORDINATE, "end[11] is inf");
    REQUIRE_ERROR((void)dvh::ccd_vertex_face(s, e, dvh::CcdOptions{}.mode(7)), DVH_STATUS_INVALID_ARGUMENT,
                  "options->mode = 7 is not a DVH_CCD_MODE_* value (0 or 1)");
    REQUIRE_ERROR((void)dvh::ccd_edge_edge(es, ee, dvh::CcdOptions{}.mode(2)), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 2");
    REQUIRE_ERROR((void)dvh::ccd_vertex_face(nullptr, e.data()), DVH_STATUS_NULL_ARGUMENT, "argument `start` is NULL");
    REQUIRE_ERROR((void)dvh::ccd_edge_edge(es.data(), nullptr), DVH_STATUS_NULL_ARGUMENT, "argument `end` is NULL");
    // A success clears the message.
    REQUIRE(dvh::ccd_edge_edge(es, ee) == 0.375 && dvh::last_error_message().empty());
}

void test_impacts_owner() {
    const dvh::Mesh floor(floor_positions, one_triangle);
    dvh::Mesh falling(falling_start, one_triangle);
    falling.refit_motion(falling_start, falling_end);

    dvh::Impacts p;
    REQUIRE(p && p.empty() && p.size() == 0 && p.view().empty() && p.view().data() == nullptr && p.begin() == p.end());
    dvh::continuous_collide(falling, floor, dvh::CcdOptions{}, p);
    REQUIRE(same(p, falling_impacts));
    const DvhImpact* data = p.view().data();
    dvh::Impacts q(std::move(p));
    REQUIRE(q.view().data() == data && q.size() == 4 && !p && p.get() == nullptr && p.size() == 0 && p.view().data() == nullptr);
    REQUIRE(p.empty() && p.begin() == p.end());
    REQUIRE_ERROR(dvh::continuous_collide(falling, floor, dvh::CcdOptions{}, p), DVH_STATUS_NULL_ARGUMENT, "`impacts_out`");
    REQUIRE_ERROR(dvh::self_continuous_collide(falling, dvh::CcdOptions{}, p), DVH_STATUS_NULL_ARGUMENT, "`impacts_out`");
    p = std::move(q);  // into an owner of none
    REQUIRE(p.view().data() == data && !q);
    dvh::Impacts& alias = p;
    p = std::move(alias);  // to itself: keeps its buffer
    REQUIRE(p.view().data() == data && p.size() == 4);
    p = dvh::Impacts();  // releases the filled buffer
    REQUIRE(p && p.empty());
    DvhImpacts* raw = p.release();
    REQUIRE(!p && raw != nullptr);
    REQUIRE(dvh_continuous_collide(falling.get(), floor.get(), nullptr, raw, nullptr) == DVH_STATUS_OK);
    dvh::Impacts adopted(raw);
    REQUIRE(same(adopted, falling_impacts));
    dvh::Impacts none(nullptr);
    REQUIRE(!none && none.size() == 0);
    // In a container that moves them as it grows: each keeps its own result.
    std::vector<dvh::Impacts> buffers;
    for (int i = 0; i < 9; i++) {
        buffers.emplace_back();
        if (i % 2 == 0) dvh::continuous_collide(falling, floor, dvh::CcdOptions{}, buffers.back());
    }
    for (std::size_t i = 0; i < buffers.size(); i++) REQUIRE(buffers[i].size() == (i % 2 == 0 ? 4u : 0u));
}

void test_continuous() {
    // The same meshes through the wrappers and through the C API.
    const dvh::Mesh floor(floor_positions, one_triangle);
    dvh::Mesh falling(falling_start, one_triangle);
    DvhMesh* c_floor = nullptr;
    DvhMesh* c_falling = nullptr;
    REQUIRE(dvh_mesh_create(floor_positions.data(), 3, one_triangle.data(), 1, nullptr, &c_floor) == DVH_STATUS_OK);
    REQUIRE(dvh_mesh_create(falling_start.data(), 3, one_triangle.data(), 1, nullptr, &c_falling) == DVH_STATUS_OK);
    DvhImpacts* c_impacts = dvh_impacts_new();
    dvh::Impacts impacts;
    DvhCcdStats c_stats{};
    auto compare = [&](const dvh::Mesh& a, DvhMesh* c_a, const dvh::Mesh& b, DvhMesh* c_b, const dvh::CcdOptions& o) {
        REQUIRE(dvh_continuous_collide(c_a, c_b, &o.c(), c_impacts, &c_stats) == DVH_STATUS_OK);
        const DvhCcdStats stats = dvh::continuous_collide(a, b, o, impacts);
        REQUIRE(same(impacts, c_impacts) && same(stats, c_stats));
        REQUIRE(same(dvh::continuous_collide(a, b, o), c_impacts));
    };

    // Still: nothing.
    compare(falling, c_falling, floor, c_floor, dvh::CcdOptions{});
    REQUIRE(impacts.empty() && c_stats.impacts == 0 && std::isinf(c_stats.earliest_toi));
    REQUIRE(dvh::continuous_collide(falling, floor).empty());

    // Falling: apart at the end, but it passed through.
    falling.refit_motion(falling_start, falling_end);
    REQUIRE(dvh_mesh_refit_motion(c_falling, falling_start.data(), falling_end.data(), 3) == DVH_STATUS_OK);
    falling.validate();
    REQUIRE(dvh::collide(falling, nullptr, floor, nullptr).empty());
    for (const dvh::CcdMode mode : {dvh::CcdMode::exact, dvh::CcdMode::conservative})
        for (std::uint32_t threads = 0; threads < 3; threads++) {
            const dvh::CcdOptions o = dvh::CcdOptions{}.mode(mode).threads(threads);
            compare(falling, c_falling, floor, c_floor, o);
            compare(floor, c_floor, falling, c_falling, o);
            compare(falling, c_falling, floor, c_floor, dvh::CcdOptions(o).earliest_only(true));
            compare(falling, c_falling, floor, c_floor, dvh::CcdOptions(o).max_impacts(1));
        }
    const DvhCcdStats stats = dvh::continuous_collide(falling, floor, dvh::CcdOptions{}, impacts);
    REQUIRE(same(impacts, falling_impacts) && stats.impacts == 4 && stats.earliest_toi == 0.5 && !stats.truncated);
    REQUIRE(same(dvh::continuous_collide(falling, floor), falling_impacts));
    dvh::Impacts earliest = dvh::continuous_collide(falling, floor, dvh::CcdOptions{}.earliest_only(true));
    REQUIRE(earliest.size() == 1 && same(earliest.view()[0], falling_impacts[1]));
    const DvhCcdStats cut = dvh::continuous_collide(falling, floor, dvh::CcdOptions{}.max_impacts(1), earliest);
    REQUIRE(earliest.size() == 1 && cut.truncated);

    // Every refit_motion overload gives what the C call gives.
    const std::vector<double> lower_start = moved(Geometry{falling_start, one_triangle}, 0.25, 0, -0.5);
    const std::vector<double> lower_end = moved(Geometry{falling_end, one_triangle}, 0.25, 0, -0.5);
    REQUIRE(dvh_mesh_refit_motion(c_falling, lower_start.data(), lower_end.data(), 3) == DVH_STATUS_OK);
    falling.refit_motion(lower_start.data(), lower_end.data(), 3);
    compare(falling, c_falling, floor, c_floor, dvh::CcdOptions{});
    REQUIRE(!impacts.empty() && !same(impacts, falling_impacts));
    falling.refit_motion(falling_start, falling_end);
    REQUIRE(dvh_mesh_refit_motion(c_falling, falling_start.data(), falling_end.data(), 3) == DVH_STATUS_OK);
    compare(falling, c_falling, floor, c_floor, dvh::CcdOptions{});
    REQUIRE(same(impacts, falling_impacts));

    // A failed motion leaves the mesh as it was: the same impacts, the same counters.
    const DvhRefitStats refit_before = falling.last_refit_stats();
    std::vector<double> nan_end = falling_end;
    nan_end[3 * 1 + 1] = std::nan("");
    REQUIRE_ERROR(falling.refit_motion(lower_start, nan_end), DVH_STATUS_NON_FINITE_COORDINATE,
                  "end positions: vertex 1: coordinate y is NaN, not a finite number");
    REQUIRE_ERROR(falling.refit_motion(nan_end, lower_end), DVH_STATUS_NON_FINITE_COORDINATE,
                  "start positions: vertex 1: coordinate y is NaN");
    REQUIRE_ERROR(falling.refit_motion(lower_start.data(), lower_end.data(), 2), DVH_STATUS_INVALID_ARGUMENT,
                  "vertex_count = 2, but the mesh has 3 vertices");
    REQUIRE_ERROR(falling.refit_motion(lower_start.data(), nullptr, 3), DVH_STATUS_NULL_ARGUMENT, "argument `end` is NULL");
    REQUIRE_ERROR(falling.refit_motion(std::vector<double>(lower_start.begin(), lower_start.end() - 1), lower_end),
                  DVH_STATUS_INVALID_ARGUMENT, "start holds 8 values, not a multiple of 3");
    REQUIRE_ERROR(falling.refit_motion(lower_start, std::vector<double>(lower_end.begin(), lower_end.end() - 1)),
                  DVH_STATUS_INVALID_ARGUMENT, "end holds 8 values, not a multiple of 3");
    REQUIRE_ERROR(falling.refit_motion(lower_start, std::vector<double>(lower_end.begin(), lower_end.end() - 3)),
                  DVH_STATUS_INVALID_ARGUMENT, "start holds 9 values but end holds 6");
    REQUIRE_ERROR(falling.refit_motion(std::vector<double>(), std::vector<double>()), DVH_STATUS_INVALID_ARGUMENT,
                  "vertex_count = 0, but the mesh has 3 vertices");
    REQUIRE(falling.last_refit_stats().nodes_refit == refit_before.nodes_refit &&
            falling.last_refit_stats().distance_evaluations == refit_before.distance_evaluations);
    falling.validate();
    compare(falling, c_falling, floor, c_floor, dvh::CcdOptions{});
    REQUIRE(same(impacts, falling_impacts));
    dvh::Mesh gone(nullptr);
    REQUIRE_ERROR(gone.refit_motion(falling_start, falling_end), DVH_STATUS_NULL_ARGUMENT, "argument `mesh` is NULL");

    // A failed query leaves the buffer as it was.
    const std::vector<DvhImpact> before = copy(impacts);
    REQUIRE_ERROR(dvh::continuous_collide(falling, floor, dvh::CcdOptions{}.mode(7), impacts), DVH_STATUS_INVALID_ARGUMENT,
                  "options->mode = 7 is not a DVH_CCD_MODE_* value (0 or 1)");
    REQUIRE_ERROR((void)dvh::continuous_collide(falling, floor, dvh::CcdOptions{}.mode(7)), DVH_STATUS_INVALID_ARGUMENT,
                  "options->mode = 7");
    REQUIRE_ERROR(dvh::continuous_collide(dvh::Mesh(nullptr), floor, dvh::CcdOptions{}, impacts), DVH_STATUS_NULL_ARGUMENT,
                  "argument `a` is NULL");
    REQUIRE_ERROR(dvh::continuous_collide(falling, gone, dvh::CcdOptions{}, impacts), DVH_STATUS_NULL_ARGUMENT,
                  "argument `b` is NULL");
    REQUIRE_ERROR(dvh::self_continuous_collide(falling, dvh::CcdOptions{}.mode(9), impacts), DVH_STATUS_INVALID_ARGUMENT,
                  "options->mode = 9");
    REQUIRE_ERROR((void)dvh::self_continuous_collide(gone), DVH_STATUS_NULL_ARGUMENT, "argument `mesh` is NULL");
    REQUIRE(same(impacts, before));

    // A plain refit makes the mesh stationary again.
    falling.refit(falling_end);
    REQUIRE(dvh_mesh_refit(c_falling, falling_end.data(), 3) == DVH_STATUS_OK);
    compare(falling, c_falling, floor, c_floor, dvh::CcdOptions{});
    REQUIRE(impacts.empty());

    // Self: a hinge, triangle 1 swinging about the shared edge through triangle 0; its vertex 3
    // crosses z = 0 at t = 1/2 inside triangle 0.
    const std::vector<double> hinge_start = {0, 0, 0, 0, 4, 0, 4, 2, 0, -2, 2, 2};
    const std::vector<double> hinge_end = {0, 0, 0, 0, 4, 0, 4, 2, 0, 3, 2, -2};
    const std::vector<std::uint32_t> hinge_tris = {0, 1, 2, 0, 1, 3};
    dvh::Mesh hinge(hinge_start, hinge_tris);
    REQUIRE(dvh::self_continuous_collide(hinge).empty());
    hinge.refit_motion(hinge_start, hinge_end);
    REQUIRE(dvh::self_collide(hinge).empty());
    const dvh::Impacts folded = dvh::self_continuous_collide(hinge);
    REQUIRE(same(folded, std::vector<DvhImpact>{impact(DVH_IMPACT_KIND_VERTEX_FACE, 3, 0, 0, 0, 0.5)}));
    // A folding grid against the C query: every thread count, every option.
    const Geometry g = terrain(6, 0, 0, flat);
    std::vector<double> ramp = g.positions, under = g.positions;
    for (int j = 0; j <= 6; j++)
        for (int i = 4; i <= 6; i++) {
            const std::size_t v = (std::size_t)(j * 7 + i);
            ramp[3 * v + 2] = i - 3;
            under[3 * v] = 6 - i + 0.0625 * j;
            under[3 * v + 2] = -0.125 * (i - 3);
        }
    dvh::Mesh sheet(g.positions, g.triangles);
    DvhMesh* c_sheet = c_mesh(g);
    sheet.refit_motion(ramp, under);
    REQUIRE(dvh_mesh_refit_motion(c_sheet, ramp.data(), under.data(), g.vertices()) == DVH_STATUS_OK);
    for (std::uint32_t threads = 0; threads < 3; threads++)
        for (const dvh::CcdOptions& o : {dvh::CcdOptions{}, dvh::CcdOptions{}.earliest_only(true), dvh::CcdOptions{}.max_impacts(3),
                                         dvh::CcdOptions{}.mode(dvh::CcdMode::conservative)}) {
            const dvh::CcdOptions with = dvh::CcdOptions(o).threads(threads);
            REQUIRE(dvh_self_continuous_collide(c_sheet, &with.c(), c_impacts, &c_stats) == DVH_STATUS_OK);
            const DvhCcdStats self_stats = dvh::self_continuous_collide(sheet, with, impacts);
            REQUIRE(same(impacts, c_impacts) && same(self_stats, c_stats));
            REQUIRE(same(dvh::self_continuous_collide(sheet, with), c_impacts));
        }
    REQUIRE(dvh::self_continuous_collide(sheet).size() > 3);
    for (const DvhImpact& i : dvh::self_continuous_collide(sheet)) REQUIRE(i.kind != DVH_IMPACT_KIND_FACE_VERTEX);
    const std::vector<DvhImpact> self_before = copy(impacts);
    REQUIRE_ERROR(dvh::self_continuous_collide(sheet, dvh::CcdOptions{}.mode(7), impacts), DVH_STATUS_INVALID_ARGUMENT,
                  "options->mode = 7");
    REQUIRE(same(impacts, self_before));

    dvh_impacts_free(c_impacts);
    dvh_mesh_free(c_floor);
    dvh_mesh_free(c_falling);
    dvh_mesh_free(c_sheet);
}

}  // namespace

bool same(const DvhNearPair& x, const DvhNearPair& y) { return std::memcmp(&x, &y, sizeof x) == 0; }

// The wrapper's stencils equal the C buffer's, byte for byte, in the same order.
bool same(const dvh::NearPairs& pairs, const DvhNearPairs* c) {
    const dvh::Span<DvhNearPair> v = pairs.view();
    if (v.size() != dvh_near_pairs_len(c) || pairs.size() != v.size()) return false;
    if (v.empty()) return v.data() == nullptr && dvh_near_pairs_data(c) == nullptr;
    for (std::size_t i = 0; i < v.size(); i++)
        if (!same(v[i], dvh_near_pairs_data(c)[i])) return false;
    return true;
}

void test_nearest() {
    // Two terrains and one through the wrappers and through the C API, every form, several
    // distances and options; the owner's moves.
    const Geometry ga = terrain(5, 0, 0, wave), gb = terrain(5, 1, 2, ridge);
    const dvh::Mesh a(ga.positions, ga.triangles), b(gb.positions, gb.triangles);
    DvhMesh* c_a = c_mesh(ga);
    DvhMesh* c_b = c_mesh(gb);
    DvhNearPairs* c_pairs = dvh_near_pairs_new();
    dvh::NearPairs pairs;
    REQUIRE(pairs && pairs.empty() && pairs.view().data() == nullptr && pairs.begin() == pairs.end());
    const DvhPose up = translation(0, 0, 2), turn = turned(6, 1, 1);
    std::size_t found = 0;
    for (const double d : {0.0, 0.5, 1.0, 2.0})
        for (const dvh::QueryOptions& o : {dvh::QueryOptions{}, dvh::QueryOptions{}.threads(1).max_pairs(4),
                                           dvh::QueryOptions{}.mode(DVH_QUERY_MODE_FIRST_HIT)}) {
            DvhQueryStats c_stats{};
            REQUIRE(dvh_nearest_features(c_a, nullptr, c_b, &up, d, &o.c(), c_pairs, &c_stats) == DVH_STATUS_OK);
            DvhQueryStats stats = dvh::nearest_features(a, nullptr, b, &up, d, o, pairs);
            REQUIRE(same(pairs, c_pairs) && same(stats, c_stats));
            REQUIRE(same(dvh::nearest_features(a, nullptr, b, &up, d, o), c_pairs));
            found += pairs.size();
            REQUIRE(dvh_nearest_features(c_b, &turn, c_a, nullptr, d, &o.c(), c_pairs, &c_stats) == DVH_STATUS_OK);
            stats = dvh::nearest_features(b, &turn, a, nullptr, d, o, pairs);
            REQUIRE(same(pairs, c_pairs) && same(stats, c_stats));
            REQUIRE(dvh_self_nearest_features(c_a, d, &o.c(), c_pairs, &c_stats) == DVH_STATUS_OK);
            stats = dvh::self_nearest_features(a, d, o, pairs);
            REQUIRE(same(pairs, c_pairs) && same(stats, c_stats));
            REQUIRE(same(dvh::self_nearest_features(a, d, o), c_pairs));
            found += pairs.size();
            for (const DvhNearPair& p : pairs) REQUIRE(p.distance <= d && p.kind != DVH_IMPACT_KIND_FACE_VERTEX);
        }
    REQUIRE(found > 100);

    // A failed query throws and leaves the buffer as it was.
    dvh::self_nearest_features(a, 1.0, dvh::QueryOptions{}, pairs);
    const std::vector<DvhNearPair> before(pairs.begin(), pairs.end());
    REQUIRE(!before.empty());
    REQUIRE_ERROR(dvh::self_nearest_features(a, -1.0, dvh::QueryOptions{}, pairs), DVH_STATUS_INVALID_ARGUMENT, "distance");
    REQUIRE_ERROR(dvh::nearest_features(a, nullptr, b, nullptr, std::nan(""), dvh::QueryOptions{}, pairs),
                  DVH_STATUS_INVALID_ARGUMENT, "distance");
    const DvhPose far{{1, 0, 0, 0, 1, 0, 0, 0, 1}, {1e301, 0, 0}};
    REQUIRE_ERROR(dvh::nearest_features(a, &far, b, nullptr, 1.0, dvh::QueryOptions{}, pairs), DVH_STATUS_POSE_OUT_OF_RANGE,
                  "");
    REQUIRE(pairs.size() == before.size() && std::equal(before.begin(), before.end(), pairs.begin(),
                                                         [](const DvhNearPair& x, const DvhNearPair& y) { return same(x, y); }));

    // Moves: the buffer goes with the owner; a moved-from owner refuses queries.
    const DvhNearPair* data = pairs.view().data();
    dvh::NearPairs moved_to(std::move(pairs));
    REQUIRE(moved_to.view().data() == data && !pairs && pairs.size() == 0 && pairs.empty());
    REQUIRE_ERROR(dvh::self_nearest_features(a, 1.0, dvh::QueryOptions{}, pairs), DVH_STATUS_NULL_ARGUMENT, "`pairs_out`");
    pairs = std::move(moved_to);
    REQUIRE(pairs.view().data() == data && !moved_to);
    DvhNearPairs* raw = pairs.release();
    REQUIRE(!pairs && raw != nullptr);
    dvh::NearPairs adopted(raw);
    REQUIRE(adopted.size() == before.size());

    dvh_near_pairs_free(c_pairs);
    dvh_mesh_free(c_a);
    dvh_mesh_free(c_b);
}

// ---- scenes over a step ----

bool same(const DvhSceneImpact& x, const DvhSceneImpact& y) {
    return x.object_a == y.object_a && x.object_b == y.object_b && same(x.impact, y.impact);
}

// The wrapper's impacts equal the C buffer's, in the same order.
bool same(const dvh::SceneImpacts& impacts, const DvhSceneImpacts* c) {
    const dvh::Span<DvhSceneImpact> v = impacts.view();
    if (v.size() != dvh_scene_impacts_len(c) || impacts.size() != v.size()) return false;
    if (v.empty()) return v.data() == nullptr && dvh_scene_impacts_data(c) == nullptr;
    for (std::size_t i = 0; i < v.size(); i++)
        if (!same(v[i], dvh_scene_impacts_data(c)[i])) return false;
    return true;
}

bool same(const dvh::SceneImpacts& impacts, const std::vector<DvhSceneImpact>& expected) {
    if (impacts.size() != expected.size()) return false;
    for (std::size_t i = 0; i < expected.size(); i++)
        if (!same(impacts.view()[i], expected[i])) return false;
    return true;
}

// Field by field: DvhNearPair has padding before `distance`.
bool same_fields(const DvhNearPair& x, const DvhNearPair& y) {
    return x.kind == y.kind && x.a0 == y.a0 && x.a1 == y.a1 && x.b0 == y.b0 && x.b1 == y.b1 && x.feature_a == y.feature_a &&
           x.feature_b == y.feature_b && x.distance == y.distance &&
           std::memcmp(x.closest_a, y.closest_a, sizeof x.closest_a) == 0 && std::memcmp(x.closest_b, y.closest_b, sizeof x.closest_b) == 0 &&
           std::memcmp(x.weights_a, y.weights_a, sizeof x.weights_a) == 0 && std::memcmp(x.weights_b, y.weights_b, sizeof x.weights_b) == 0;
}

bool same(const DvhSceneNearPair& x, const DvhSceneNearPair& y) {
    return x.object_a == y.object_a && x.object_b == y.object_b && same_fields(x.pair, y.pair);
}

bool same(const dvh::SceneNearPairs& pairs, const DvhSceneNearPairs* c) {
    const dvh::Span<DvhSceneNearPair> v = pairs.view();
    if (v.size() != dvh_scene_near_pairs_len(c) || pairs.size() != v.size()) return false;
    if (v.empty()) return v.data() == nullptr && dvh_scene_near_pairs_data(c) == nullptr;
    for (std::size_t i = 0; i < v.size(); i++)
        if (!same(v[i], dvh_scene_near_pairs_data(c)[i])) return false;
    return true;
}

DvhSceneImpact scene_impact(std::uint32_t object_a, std::uint32_t object_b, const DvhImpact& impact) {
    DvhSceneImpact s{};
    s.object_a = object_a;
    s.object_b = object_b;
    s.impact = impact;
    return s;
}

void test_scene_owners() {
    static_assert(move_only<dvh::SceneImpacts>() && move_only<dvh::SceneNearPairs>(), "owners are move-only");
    static_assert(!std::is_convertible_v<DvhSceneImpacts*, dvh::SceneImpacts> &&
                      !std::is_convertible_v<DvhSceneNearPairs*, dvh::SceneNearPairs>,
                  "adopting a handle is explicit");
    const dvh::Mesh floor(floor_positions, one_triangle), falling(falling_start, one_triangle);
    dvh::Scene scene;
    REQUIRE(scene.add_deformable(falling) == 0 && scene.add_rigid(floor) == 1);
    scene.set_motion(0, falling_start, falling_end);

    dvh::SceneImpacts p;
    REQUIRE(p && p.empty() && p.size() == 0 && p.view().data() == nullptr && p.begin() == p.end());
    scene.continuous_collide(dvh::CcdOptions{}, p);
    REQUIRE(p.size() == 4);
    const DvhSceneImpact* data = p.view().data();
    dvh::SceneImpacts q(std::move(p));
    REQUIRE(q.view().data() == data && q.size() == 4 && !p && p.get() == nullptr && p.size() == 0 && p.begin() == p.end());
    REQUIRE_ERROR(scene.continuous_collide(dvh::CcdOptions{}, p), DVH_STATUS_NULL_ARGUMENT, "`impacts_out`");
    p = std::move(q);
    REQUIRE(p.view().data() == data && !q);
    dvh::SceneImpacts& alias = p;
    p = std::move(alias);  // to itself: keeps its buffer
    REQUIRE(p.view().data() == data);
    DvhSceneImpacts* raw = p.release();
    REQUIRE(!p && raw != nullptr);
    dvh::SceneImpacts adopted(raw);
    REQUIRE(adopted.size() == 4 && adopted.view().data() == data);
    adopted = dvh::SceneImpacts();  // releases the filled buffer
    REQUIRE(adopted && adopted.empty());

    dvh::SceneNearPairs n;
    REQUIRE(n && n.empty() && n.view().data() == nullptr && n.begin() == n.end());
    scene.nearest_features(10.0, dvh::QueryOptions{}, n);
    REQUIRE(!n.empty());
    const DvhSceneNearPair* first = n.view().data();
    const std::size_t count = n.size();
    dvh::SceneNearPairs m(std::move(n));
    REQUIRE(m.view().data() == first && !n && n.size() == 0 && n.empty());
    REQUIRE_ERROR(scene.nearest_features(1.0, dvh::QueryOptions{}, n), DVH_STATUS_NULL_ARGUMENT, "`pairs_out`");
    n = std::move(m);
    DvhSceneNearPairs* raw_pairs = n.release();
    dvh::SceneNearPairs adopted_pairs(raw_pairs);
    REQUIRE(adopted_pairs.size() == count && !n);
    dvh::SceneNearPairs none(nullptr);
    REQUIRE(!none && none.size() == 0);
    // A moved-from scene refuses the new calls too.
    dvh::Scene moved_to(std::move(scene));
    REQUIRE_ERROR(scene.set_motion(0, falling_start, falling_end), DVH_STATUS_NULL_ARGUMENT, "`scene`");
    REQUIRE_ERROR(scene.set_self_contact(0, true), DVH_STATUS_NULL_ARGUMENT, "`scene`");
    REQUIRE_ERROR(scene.set_pose_motion(1, nullptr, nullptr), DVH_STATUS_NULL_ARGUMENT, "`scene`");
    REQUIRE_ERROR((void)scene.continuous_collide(), DVH_STATUS_NULL_ARGUMENT, "`scene`");
    REQUIRE_ERROR((void)scene.nearest_features(1.0), DVH_STATUS_NULL_ARGUMENT, "`scene`");
    REQUIRE(moved_to.continuous_collide().size() == 4);
}

void test_scene_step() {
    // The same scene through the wrappers and through the C API: the falling triangle (0,
    // deformable), the floor (1, rigid), a hinge folding through itself far away (2, deformable,
    // self-contact on).
    const std::vector<double> hinge_start = {100, 0, 0, 100, 4, 0, 104, 2, 0, 98, 2, 2};
    const std::vector<double> hinge_end = {100, 0, 0, 100, 4, 0, 104, 2, 0, 103, 2, -2};
    const std::vector<std::uint32_t> hinge_tris = {0, 1, 2, 0, 1, 3};
    const dvh::Mesh floor(floor_positions, one_triangle), falling(falling_start, one_triangle), hinge(hinge_start, hinge_tris);
    dvh::Scene scene;
    DvhScene* c_scene = nullptr;
    REQUIRE(dvh_scene_create(&c_scene) == DVH_STATUS_OK);
    std::uint32_t id = 99;
    REQUIRE(scene.add_deformable(falling) == 0 && dvh_scene_add_deformable(c_scene, falling.get(), 1, 0xffffffffu, &id) == DVH_STATUS_OK);
    REQUIRE(scene.add_rigid(floor) == 1 && dvh_scene_add_rigid(c_scene, floor.get(), nullptr, 1, 0xffffffffu, &id) == DVH_STATUS_OK);
    REQUIRE(scene.add_deformable(hinge) == 2 && dvh_scene_add_deformable(c_scene, hinge.get(), 1, 0xffffffffu, &id) == DVH_STATUS_OK);
    REQUIRE(id == 2);
    dvh::SceneImpacts impacts;
    DvhSceneImpacts* c_impacts = dvh_scene_impacts_new();
    dvh::SceneNearPairs pairs;
    DvhSceneNearPairs* c_pairs = dvh_scene_near_pairs_new();
    auto compare = [&](const dvh::CcdOptions& o) {
        DvhCcdStats c_stats{};
        REQUIRE(dvh_scene_continuous_collide(c_scene, &o.c(), c_impacts, &c_stats) == DVH_STATUS_OK);
        const DvhCcdStats stats = scene.continuous_collide(o, impacts);
        // The answer's counters always; the work counters on one thread (on several, an
        // earliest-only or limited query's work depends on which thread finds what first).
        REQUIRE(same(impacts, c_impacts) && stats.impacts == c_stats.impacts &&
                stats.earliest_toi == c_stats.earliest_toi && stats.truncated == c_stats.truncated);
        if (o.c().threads == 1) REQUIRE(same(stats, c_stats));
        REQUIRE(same(scene.continuous_collide(o), c_impacts));
    };
    auto compare_near = [&](double distance, const dvh::QueryOptions& o) {
        DvhQueryStats c_stats{};
        REQUIRE(dvh_scene_nearest_features(c_scene, distance, &o.c(), c_pairs, &c_stats) == DVH_STATUS_OK);
        const DvhQueryStats stats = scene.nearest_features(distance, o, pairs);
        REQUIRE(same(pairs, c_pairs) && same(stats, c_stats) && stats.pairs == pairs.size());
        REQUIRE(same(scene.nearest_features(distance, o), c_pairs));
    };

    // Still: nothing.
    compare(dvh::CcdOptions{});
    REQUIRE(impacts.empty());

    // The triangle falls through the floor, which stands still through its pose motion; the
    // hinge swings through itself.
    std::vector<DvhSceneImpact> expected;
    for (const DvhImpact& i : falling_impacts) expected.push_back(scene_impact(0, 1, i));
    scene.set_motion(0, falling_start, falling_end);
    REQUIRE(dvh_scene_set_motion(c_scene, 0, falling_start.data(), falling_end.data(), 3) == DVH_STATUS_OK);
    scene.set_pose_motion(1, nullptr, nullptr);
    REQUIRE(dvh_scene_set_pose_motion(c_scene, 1, nullptr, nullptr) == DVH_STATUS_OK);
    scene.set_motion(2, hinge_start.data(), hinge_end.data(), 4);
    REQUIRE(dvh_scene_set_motion(c_scene, 2, hinge_start.data(), hinge_end.data(), 4) == DVH_STATUS_OK);
    compare(dvh::CcdOptions{});
    REQUIRE(same(impacts, expected));
    scene.set_self_contact(2, true);
    REQUIRE(dvh_scene_set_self_contact(c_scene, 2, true) == DVH_STATUS_OK);
    expected.push_back(scene_impact(2, 2, impact(DVH_IMPACT_KIND_VERTEX_FACE, 3, 0, 0, 0, 0.5)));
    for (const dvh::CcdMode mode : {dvh::CcdMode::exact, dvh::CcdMode::conservative})
        for (std::uint32_t threads = 0; threads < 3; threads++) {
            const dvh::CcdOptions o = dvh::CcdOptions{}.mode(mode).threads(threads);
            compare(o);
            compare(dvh::CcdOptions(o).earliest_only(true));
            compare(dvh::CcdOptions(o).max_impacts(2));
        }
    compare(dvh::CcdOptions{});
    REQUIRE(same(impacts, expected));
    REQUIRE(same(scene.continuous_collide(dvh::CcdOptions{}.earliest_only(true)), std::vector<DvhSceneImpact>{expected[1]}));
    const DvhCcdStats cut = scene.continuous_collide(dvh::CcdOptions{}.max_impacts(2), impacts);
    REQUIRE(impacts.size() == 2 && cut.truncated && cut.impacts == 2);

    // Every set_motion overload gives what the C call gives.
    const std::vector<double> lower_start = moved(Geometry{falling_start, one_triangle}, 0.25, 0, -0.5);
    const std::vector<double> lower_end = moved(Geometry{falling_end, one_triangle}, 0.25, 0, -0.5);
    REQUIRE(dvh_scene_set_motion(c_scene, 0, lower_start.data(), lower_end.data(), 3) == DVH_STATUS_OK);
    auto check_motion = [&](auto&& set) {
        scene.set_motion(0, falling_start, falling_end);  // away from the C scene's, first
        set();
        compare(dvh::CcdOptions{});
        REQUIRE(!impacts.empty() && !same(impacts, expected));
    };
    check_motion([&] { scene.set_motion(0, lower_start, lower_end); });
    check_motion([&] { scene.set_motion(0, lower_start.data(), lower_end.data(), 3); });
    check_motion([&] { scene.set_motion(0, to_float(lower_start), to_float(lower_end)); });
    check_motion([&] { scene.set_motion(0, to_float(lower_start).data(), to_float(lower_end).data(), 3); });
    check_motion([&] {
        std::vector<float> s, e;  // x, y, z, w
        for (std::size_t i = 0; i < 3; i++) {
            s.insert(s.end(), {(float)lower_start[3 * i], (float)lower_start[3 * i + 1], (float)lower_start[3 * i + 2], 0.0f});
            e.insert(e.end(), {(float)lower_end[3 * i], (float)lower_end[3 * i + 1], (float)lower_end[3 * i + 2], 0.0f});
        }
        scene.set_motion_strided(0, s.data(), e.data(), 4 * sizeof(float), 3);
    });
    // A pose motion: the floor rising by 4 over the step.
    const DvhPose below = translation(0, 0, -2), above = translation(0, 0, 2);
    scene.set_pose_motion(1, &below, &above);
    REQUIRE(dvh_scene_set_pose_motion(c_scene, 1, &below, &above) == DVH_STATUS_OK);
    compare(dvh::CcdOptions{});
    compare(dvh::CcdOptions{}.earliest_only(true));

    // Stencils: the triangle at the end of its step over the floor, the hinge with itself.
    for (const double d : {0.0, 0.5, 2.0, 5.0})
        for (const dvh::QueryOptions& o :
             {dvh::QueryOptions{}, dvh::QueryOptions{}.threads(1).max_pairs(3), dvh::QueryOptions{}.mode(DVH_QUERY_MODE_FIRST_HIT)})
            compare_near(d, o);
    REQUIRE(!scene.nearest_features(5.0).empty());
    bool self_seen = false;
    for (const DvhSceneNearPair& p : scene.nearest_features(5.0)) {
        REQUIRE(p.object_a <= p.object_b && p.pair.distance <= 5.0);
        self_seen |= p.object_a == 2 && p.object_b == 2;
    }
    REQUIRE(self_seen);

    // Errors: the status, the message, and the scene and its last results as they were.
    compare(dvh::CcdOptions{});
    compare_near(2.0, dvh::QueryOptions{});
    const std::vector<DvhSceneImpact> kept(impacts.begin(), impacts.end());
    const std::size_t kept_pairs = pairs.size();
    REQUIRE_ERROR(scene.set_motion(1, falling_start, falling_end), DVH_STATUS_INVALID_ARGUMENT, "object 1 is rigid");
    REQUIRE_ERROR(scene.set_motion(9, falling_start, falling_end), DVH_STATUS_INVALID_ARGUMENT, "object 9 is not in the scene");
    REQUIRE_ERROR(scene.set_motion(0, falling_start, std::vector<double>(falling_end.begin(), falling_end.end() - 3)),
                  DVH_STATUS_INVALID_ARGUMENT, "start holds 9 values but end holds 6");
    REQUIRE_ERROR(scene.set_motion(0, to_float(falling_start), std::vector<float>(8)), DVH_STATUS_INVALID_ARGUMENT,
                  "end holds 8 values, not a multiple of 3");
    REQUIRE_ERROR(scene.set_motion(0, falling_start.data(), nullptr, 3), DVH_STATUS_NULL_ARGUMENT, "argument `end` is NULL");
    REQUIRE_ERROR(scene.set_motion(0, falling_start.data(), falling_end.data(), 2), DVH_STATUS_INVALID_ARGUMENT,
                  "vertex_count = 2, but object 0 has 3 vertices");
    std::vector<double> nan_end = falling_end;
    nan_end[3 * 1 + 1] = std::nan("");
    REQUIRE_ERROR(scene.set_motion(0, falling_start, nan_end), DVH_STATUS_NON_FINITE_COORDINATE,
                  "object 0: end positions: vertex 1: coordinate y is NaN");
    REQUIRE_ERROR(scene.set_motion_strided(0, to_float(falling_start).data(), to_float(falling_end).data(), 8, 3),
                  DVH_STATUS_INVALID_ARGUMENT, "stride_bytes = 8");
    REQUIRE_ERROR(scene.set_pose_motion(0, &below, &above), DVH_STATUS_INVALID_ARGUMENT, "object 0 is deformable");
    DvhPose skewed = above;
    skewed.rotation[0] = 2.0;
    REQUIRE_ERROR(scene.set_pose_motion(1, &below, &skewed), DVH_STATUS_NON_RIGID_POSE, "end: ");
    REQUIRE_ERROR(scene.set_self_contact(1, true), DVH_STATUS_INVALID_ARGUMENT, "object 1 is rigid: self-contact");
    scene.set_self_contact(1, false);
    REQUIRE_ERROR(scene.continuous_collide(dvh::CcdOptions{}.mode(7), impacts), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 7");
    REQUIRE_ERROR((void)scene.continuous_collide(dvh::CcdOptions{}.mode(7)), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 7");
    REQUIRE_ERROR(scene.nearest_features(-1.0, dvh::QueryOptions{}, pairs), DVH_STATUS_INVALID_ARGUMENT, "distance");
    REQUIRE_ERROR(scene.nearest_features(1.0, dvh::QueryOptions{}.mode(DVH_QUERY_MODE_BUDGET), pairs), DVH_STATUS_INVALID_ARGUMENT,
                  "options->budget = 0");
    REQUIRE(impacts.size() == kept.size() && std::equal(kept.begin(), kept.end(), impacts.begin(),
                                                        [](const DvhSceneImpact& x, const DvhSceneImpact& y) { return same(x, y); }));
    REQUIRE(pairs.size() == kept_pairs);
    compare(dvh::CcdOptions{});
    compare_near(2.0, dvh::QueryOptions{});

    // Self-contact off: the hinge's own impacts vanish; the frame's contacts see the ends.
    scene.set_self_contact(2, false);
    REQUIRE(dvh_scene_set_self_contact(c_scene, 2, false) == DVH_STATUS_OK);
    compare(dvh::CcdOptions{});
    for (const DvhSceneImpact& i : impacts) REQUIRE(i.object_a != 2 && i.object_b != 2);
    REQUIRE(scene.collide().empty());

    dvh_scene_impacts_free(c_impacts);
    dvh_scene_near_pairs_free(c_pairs);
    dvh_scene_free(c_scene);
}

// ---- intersection curves ----

// The wrapper's curves equal the C buffer's, byte for byte, curve by curve.
bool same(const dvh::Curves& curves, const DvhCurves* c) {
    const dvh::Span<DvhCurveSegment> v = curves.view();
    if (v.size() != dvh_curves_len(c) || curves.curve_count() != dvh_curves_curve_count(c)) return false;
    if (curves.degenerate().size() != dvh_curves_degenerate_len(c)) return false;
    if (!v.empty() && std::memcmp(v.data(), dvh_curves_data(c), v.size() * sizeof(DvhCurveSegment)) != 0) return false;
    for (std::size_t i = 0; i < curves.curve_count(); i++) {
        std::size_t first = 0, count = 0;
        bool closed = false;
        if (dvh_curves_curve(c, i, &first, &count, &closed) != DVH_STATUS_OK) return false;
        const dvh::Curve curve = curves.curve(i);
        if (curve.segments.data() != v.data() + first || curve.segments.size() != count || curve.closed != closed) return false;
    }
    return true;
}

void test_curves() {
    // Two terrains through each other and a posed copy, through the wrappers and the C API.
    const Geometry ga = terrain(6, 0, 0, wave), gb = terrain(6, 1, 2, ridge);
    const dvh::Mesh a(ga.positions, ga.triangles), b(gb.positions, gb.triangles);
    DvhMesh* c_a = c_mesh(ga);
    DvhMesh* c_b = c_mesh(gb);
    DvhCurves* c_curves = dvh_curves_new();
    dvh::Curves curves;
    REQUIRE(curves && curves.empty() && curves.curve_count() == 0 && curves.degenerate().empty());
    const DvhPose turn = turned(6, 1, 1);
    std::size_t found = 0;
    for (const dvh::QueryOptions& o : {dvh::QueryOptions{}, dvh::QueryOptions{}.threads(1).max_pairs(4)}) {
        DvhQueryStats c_stats{};
        REQUIRE(dvh_intersection_curves(c_a, nullptr, c_b, &turn, &o.c(), c_curves, &c_stats) == DVH_STATUS_OK);
        DvhQueryStats stats = dvh::intersection_curves(a, nullptr, b, &turn, o, curves);
        REQUIRE(same(curves, c_curves) && same(stats, c_stats));
        REQUIRE(same(dvh::intersection_curves(a, nullptr, b, &turn, o), c_curves));
        found += curves.size();
        REQUIRE(dvh_self_intersection_curves(c_a, &o.c(), c_curves, &c_stats) == DVH_STATUS_OK);
        stats = dvh::self_intersection_curves(a, o, curves);
        REQUIRE(same(curves, c_curves) && same(stats, c_stats));
        REQUIRE(same(dvh::self_intersection_curves(a, o), c_curves));
    }
    REQUIRE(found > 4);
    // Chains: each segment starts where the one before ends.
    dvh::intersection_curves(a, nullptr, b, &turn, dvh::QueryOptions{}, curves);
    for (std::size_t i = 0; i < curves.curve_count(); i++) {
        const dvh::Curve c = curves.curve(i);
        for (std::size_t k = 1; k < c.segments.size(); k++)
            REQUIRE(std::memcmp(c.segments[k - 1].end, c.segments[k].start, sizeof c.segments[k].start) == 0);
    }

    // The length gradient, as the C call gives it.
    {
        std::vector<double> ga, gb;
        std::vector<double> c_ga(3 * a.vertex_count()), c_gb(3 * b.vertex_count());
        REQUIRE(dvh_intersection_curves(c_a, nullptr, c_b, &turn, nullptr, c_curves, nullptr) == DVH_STATUS_OK);
        REQUIRE(dvh_curves_length_gradient(c_curves, c_a, nullptr, c_b, &turn, c_ga.data(), a.vertex_count(), c_gb.data(),
                                           b.vertex_count()) == DVH_STATUS_OK);
        std::tie(ga, gb) = curves.length_gradient(a, nullptr, b, &turn);
        REQUIRE(ga == c_ga && gb == c_gb);
        REQUIRE(std::any_of(ga.begin(), ga.end(), [](double x) { return x != 0.0; }));
        REQUIRE_ERROR((void)curves.self_length_gradient(a), DVH_STATUS_INVALID_ARGUMENT, "curves of two meshes");
        dvh::Curves own = dvh::self_intersection_curves(a);
        REQUIRE(own.self_length_gradient(a).size() == 3 * a.vertex_count());
    }

    // Errors throw and leave the buffer as it was.
    const std::vector<DvhCurveSegment> before(curves.begin(), curves.end());
    REQUIRE(!before.empty());
    REQUIRE_ERROR((void)curves.curve(curves.curve_count()), DVH_STATUS_INVALID_ARGUMENT, "out of range");
    REQUIRE_ERROR(dvh::intersection_curves(a, nullptr, b, &turn, dvh::QueryOptions{}.mode(DVH_QUERY_MODE_LEAVES), curves),
                  DVH_STATUS_INVALID_ARGUMENT, "DVH_QUERY_MODE_TRIANGLES");
    const DvhPose far{{1, 0, 0, 0, 1, 0, 0, 0, 1}, {1e301, 0, 0}};
    REQUIRE_ERROR(dvh::intersection_curves(a, &far, b, nullptr, dvh::QueryOptions{}, curves), DVH_STATUS_POSE_OUT_OF_RANGE, "");
    REQUIRE(curves.size() == before.size() &&
            std::memcmp(curves.view().data(), before.data(), before.size() * sizeof(DvhCurveSegment)) == 0);

    // Moves: the buffer goes with the owner; a moved-from owner refuses queries.
    const DvhCurveSegment* data = curves.view().data();
    dvh::Curves moved_to(std::move(curves));
    REQUIRE(moved_to.view().data() == data && !curves && curves.size() == 0 && curves.curve_count() == 0);
    REQUIRE_ERROR(dvh::self_intersection_curves(a, dvh::QueryOptions{}, curves), DVH_STATUS_NULL_ARGUMENT, "`curves_out`");
    REQUIRE_ERROR((void)curves.curve(0), DVH_STATUS_NULL_ARGUMENT, "curves");
    DvhCurves* raw = moved_to.release();
    REQUIRE(!moved_to && raw != nullptr);
    dvh::Curves adopted(raw);
    REQUIRE(adopted.size() == before.size());

    dvh_curves_free(c_curves);
    dvh_mesh_free(c_a);
    dvh_mesh_free(c_b);
}

// An axis-aligned box [x0, x0 + w] x [0, w] x [0, w] of twelve outward triangles.
Geometry box(int x0, int w) {
    Geometry g;
    for (int i = 0; i < 8; i++) {
        g.positions.push_back(x0 + (i & 1) * w);
        g.positions.push_back(((i >> 1) & 1) * w);
        g.positions.push_back(((i >> 2) & 1) * w);
    }
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) g.triangles.insert(g.triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    return g;
}

void test_distances() {
    const Geometry g0 = box(0, 2), g1 = box(5, 2), open = terrain(2, 0, 0, flat);
    const dvh::Mesh a(g0.positions, g0.triangles), b(g1.positions, g1.triangles), o(open.positions, open.triangles);
    REQUIRE(a.is_closed() && !o.is_closed());
    const DvhDistance d = dvh::distance(a, nullptr, b, nullptr);
    DvhDistance raw{};
    const DvhDistanceOptions defaults = dvh_distance_options_default();
    REQUIRE(dvh_distance(a.get(), nullptr, b.get(), nullptr, &defaults, &raw, nullptr) == DVH_STATUS_OK);
    REQUIRE(std::memcmp(&d, &raw, sizeof d) == 0 && d.found == 1 && d.distance == 3.0);
    REQUIRE(dvh::distance(a, nullptr, b, nullptr, dvh::DistanceOptions().max_distance(1.0)).found == 0);
    REQUIRE_ERROR((void)dvh::distance(a, nullptr, b, nullptr, dvh::DistanceOptions().rel_err(-1.0)),
                  DVH_STATUS_INVALID_ARGUMENT, "rel_err");

    const std::vector<double> points = {1, 1, 1, 1.5, 0.5, 5, 2, 1, 1};
    const auto closest = dvh::closest_points(a, nullptr, points);
    REQUIRE(closest.size() == 3 && closest[0].distance == 1.0 && closest[1].distance == 3.0 && closest[2].distance == 0.0);
    const auto winding = dvh::winding_numbers(a, nullptr, points);
    REQUIRE(winding == (std::vector<std::int32_t>{1, 0, DVH_WINDING_ON_SURFACE}));
    const auto signed_ = dvh::signed_distances(a, nullptr, points, dvh::DistanceOptions().threads(1));
    REQUIRE(signed_ == (std::vector<double>{-1.0, 3.0, 0.0}));
    REQUIRE_ERROR((void)dvh::winding_numbers(o, nullptr, points), DVH_STATUS_NOT_CLOSED, "not closed");
    REQUIRE_ERROR((void)dvh::closest_points(a, nullptr, std::vector<double>{1, 2}), DVH_STATUS_INVALID_ARGUMENT, "three per point");
    const std::vector<double> nan_point = {0, 0, std::nan("")};
    REQUIRE_ERROR((void)dvh::signed_distances(a, nullptr, nan_point), DVH_STATUS_NON_FINITE_COORDINATE, "point 0");

    dvh::Scene scene;
    const std::uint32_t i0 = scene.add_rigid(a, nullptr), i1 = scene.add_rigid(b, nullptr);
    const auto least = scene.distance();
    REQUIRE(least && least->object_a == i0 && least->object_b == i1 && least->distance.distance == 3.0);
    const auto mine = scene.object_distance(i1);
    REQUIRE(mine && mine->object_a == i1 && mine->object_b == i0 && mine->distance.closest_a[0] == 5.0);
    REQUIRE(!scene.distance(dvh::DistanceOptions().max_distance(2.0)));
    REQUIRE_ERROR((void)scene.object_distance(7), DVH_STATUS_INVALID_ARGUMENT, "object 7");
}

int main() {
    test_version_status_and_messages();
    test_span();
    test_options();
    test_owners();
    test_mesh();
    test_queries();
    test_scene();
    test_ccd_options();
    test_ccd_primitives();
    test_impacts_owner();
    test_continuous();
    test_nearest();
    test_scene_owners();
    test_scene_step();
    test_curves();
    test_distances();
    std::printf("test_cpp (C++%ld): all checks passed\n", (long)(__cplusplus / 100 % 100));
    return 0;
}
