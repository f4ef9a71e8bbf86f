/*
 * Every function of dvh.h and every error path: NULL pointers, bad sizes and strides, misaligned
 * arrays, NaN and infinity, out-of-range indices and options, non-rigid and out-of-range poses,
 * f32 positions with a stride, reuse of a DvhPairs; every query mode checked against an
 * independent brute-force oracle on meshes with integer coordinates; and continuous collision:
 * the primitive tests on motions with exact times of impact, the mesh queries on small cases
 * worked out by hand and on deforming terrains against an oracle built from the primitive tests.
 */
#include <math.h>

#include "common.h"

static int flat(int i, int j) { (void)i; (void)j; return 0; }
static int wave(int i, int j) { return ((i * 3 + j * 5) % 4) - 1; }
static int ridge(int i, int j) { return (i % 3 == 0) ? 2 : (j % 2); }

static DvhMesh *create(const Mesh *m, const DvhBuildOptions *o) {
    DvhMesh *out = NULL;
    CHECK_STATUS(dvh_mesh_create(m->pos, m->vertex_count, m->tris, m->triangle_count, o, &out), DVH_STATUS_OK, NULL);
    CHECK(out != NULL);
    if (out != NULL) CHECK_STATUS(dvh_mesh_validate(out), DVH_STATUS_OK, NULL);
    return out;
}

static int same_pairs(const DvhPairs *p, const DvhPair *expected, size_t n) {
    size_t len = dvh_pairs_len(p), i;
    const DvhPair *data = dvh_pairs_data(p);
    if (len != n) return 0;
    if (n == 0) return data == NULL;
    for (i = 0; i < n; i++)
        if (data[i].a != expected[i].a || data[i].b != expected[i].b) return 0;
    return 1;
}

static int contains(const DvhPair *v, size_t n, DvhPair x) {
    size_t i;
    for (i = 0; i < n; i++)
        if (v[i].a == x.a && v[i].b == x.b) return 1;
    return 0;
}

/* Every expected triangle pair (a, b) lies below one of the node pairs reported in `p`; with
 * `either`, (a, b) or (b, a) does (one mesh against itself). Each node pair's triangles are stamped
 * once, then every expected pair is looked up: two calls per node pair, so that the check stays
 * quick under valgrind. */
static int covers_in(const DvhMesh *a, const DvhMesh *b, const DvhPairs *p, const DvhPair *expected, size_t n,
                     int either) {
    size_t na_all = dvh_mesh_triangle_count(a), nb_all = dvh_mesh_triangle_count(b), e, k, len = dvh_pairs_len(p);
    const DvhPair *nodes = dvh_pairs_data(p);
    size_t *stamp_a = calloc(na_all + 1, sizeof *stamp_a), *stamp_b = calloc(nb_all + 1, sizeof *stamp_b);
    char *found = calloc(n + 1, 1);
    int ok = stamp_a != NULL && stamp_b != NULL && found != NULL;
    for (k = 0; k < len && ok; k++) {
        const uint32_t *ta, *tb;
        size_t na, nb, i;
        if (dvh_mesh_node_triangles(a, nodes[k].a, &ta, &na) != DVH_STATUS_OK ||
            dvh_mesh_node_triangles(b, nodes[k].b, &tb, &nb) != DVH_STATUS_OK) {
            ok = 0;
            break;
        }
        /* Stamp k + 1 marks the triangles below this node pair's two nodes. */
        for (i = 0; i < na; i++)
            if (ta[i] < na_all) stamp_a[ta[i]] = k + 1;
        for (i = 0; i < nb; i++)
            if (tb[i] < nb_all) stamp_b[tb[i]] = k + 1;
        for (e = 0; e < n; e++) {
            uint32_t x = expected[e].a, y = expected[e].b;
            if (x < na_all && y < nb_all && stamp_a[x] == k + 1 && stamp_b[y] == k + 1) found[e] = 1;
            if (either && y < na_all && x < nb_all && stamp_a[y] == k + 1 && stamp_b[x] == k + 1) found[e] = 1;
        }
    }
    for (e = 0; e < n && ok; e++)
        if (!found[e]) ok = 0;
    free(stamp_a);
    free(stamp_b);
    free(found);
    return ok;
}

static int covers(const DvhMesh *a, const DvhMesh *b, const DvhPairs *p, const DvhPair *expected, size_t n) {
    return covers_in(a, b, p, expected, n, 0);
}

/* All query modes on one scene, against the oracle. */
static void check_scene(const Mesh *ma, const IPose *ipa, const Mesh *mb, const IPose *ipb, const DvhBuildOptions *o,
                        DvhPairs *pairs) {
    DvhMesh *a = create(ma, o), *b = create(mb, o);
    DvhPose pa, pb;
    DvhPair *expected;
    size_t n = brute_force(ma, ipa, mb, ipb, &expected);
    DvhQueryOptions q = dvh_query_options_default();
    DvhQueryStats stats;
    uint32_t depth;
    if (ipa != NULL) pa = ipose_to_dvh(ipa);
    if (ipb != NULL) pb = ipose_to_dvh(ipb);

    CHECK_STATUS(dvh_collide(a, ipa ? &pa : NULL, b, ipb ? &pb : NULL, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_kind(pairs) == DVH_PAIR_KIND_TRIANGLES);
    CHECK(same_pairs(pairs, expected, n));
    CHECK(stats.pairs == n && !stats.truncated && stats.triangle_tests >= n && stats.bv_tests >= 1);

    q.mode = DVH_QUERY_MODE_FIRST_HIT;
    CHECK_STATUS(dvh_collide(a, ipa ? &pa : NULL, b, ipb ? &pb : NULL, &q, pairs, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == (n > 0 ? 1u : 0u));
    if (n > 0) CHECK(contains(expected, n, dvh_pairs_data(pairs)[0]));

    q.mode = DVH_QUERY_MODE_TRIANGLES;
    q.max_pairs = (n + 1) / 2;
    if (q.max_pairs > 0) {
        size_t i;
        CHECK_STATUS(dvh_collide(a, ipa ? &pa : NULL, b, ipb ? &pb : NULL, &q, pairs, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(pairs) == q.max_pairs && stats.truncated);
        for (i = 0; i < dvh_pairs_len(pairs); i++) CHECK(contains(expected, n, dvh_pairs_data(pairs)[i]));
    }
    q.max_pairs = 0;

    q.mode = DVH_QUERY_MODE_LEAVES;
    CHECK_STATUS(dvh_collide(a, ipa ? &pa : NULL, b, ipb ? &pb : NULL, &q, pairs, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_kind(pairs) == DVH_PAIR_KIND_NODES);
    CHECK(covers(a, b, pairs, expected, n));
    for (depth = 0; depth < 4; depth++) {
        q.mode = DVH_QUERY_MODE_DEPTH;
        q.max_depth = depth;
        CHECK_STATUS(dvh_collide(a, ipa ? &pa : NULL, b, ipb ? &pb : NULL, &q, pairs, NULL), DVH_STATUS_OK, NULL);
        CHECK(covers(a, b, pairs, expected, n));
    }
    /* Budgets: the frontier covers every pair; the tests stay within the budget plus one
     * opening (64 child tests at most); a budget that suffices gives the leaves' answer. */
    {
        uint64_t budgets[] = {1, 3, 17, 120, UINT64_MAX};
        size_t k, leaves_len;
        DvhPair *leaves;
        uint64_t leaves_tests;
        q.mode = DVH_QUERY_MODE_LEAVES;
        CHECK_STATUS(dvh_collide(a, ipa ? &pa : NULL, b, ipb ? &pb : NULL, &q, pairs, &stats), DVH_STATUS_OK, NULL);
        leaves_len = dvh_pairs_len(pairs);
        leaves_tests = stats.bv_tests;
        leaves = malloc((leaves_len + 1) * sizeof *leaves);
        if (leaves_len > 0) memcpy(leaves, dvh_pairs_data(pairs), leaves_len * sizeof *leaves);
        q.mode = DVH_QUERY_MODE_BUDGET;
        for (k = 0; k < sizeof budgets / sizeof budgets[0]; k++) {
            q.budget = budgets[k];
            CHECK_STATUS(dvh_collide(a, ipa ? &pa : NULL, b, ipb ? &pb : NULL, &q, pairs, &stats), DVH_STATUS_OK, NULL);
            CHECK(dvh_pairs_kind(pairs) == DVH_PAIR_KIND_NODES);
            CHECK(covers(a, b, pairs, expected, n));
            CHECK(stats.bv_tests <= (q.budget > UINT64_MAX - 64 ? UINT64_MAX : q.budget + 64));
            if (q.budget >= leaves_tests) {
                CHECK(stats.frontier_pairs == 0 && stats.bv_tests == leaves_tests);
                CHECK(same_pairs(pairs, leaves, leaves_len));
            }
        }
        q.budget = 0;
        free(leaves);
    }
    free(expected);
    dvh_mesh_free(a);
    dvh_mesh_free(b);
}

static void test_versions_and_names(void) {
    const char *v = dvh_version();
    unsigned s;
    CHECK(v != NULL && v[0] >= '0' && v[0] <= '9' && strchr(v, '.') != NULL);
    CHECK(strcmp(dvh_status_name(DVH_STATUS_OK), "DVH_STATUS_OK") == 0);
    CHECK(strcmp(dvh_status_name(DVH_STATUS_NULL_ARGUMENT), "DVH_STATUS_NULL_ARGUMENT") == 0);
    CHECK(strcmp(dvh_status_name(DVH_STATUS_INVARIANT_BROKEN), "DVH_STATUS_INVARIANT_BROKEN") == 0);
    CHECK(strcmp(dvh_status_name(DVH_STATUS_BUSY), "DVH_STATUS_BUSY") == 0);
    CHECK(strcmp(dvh_status_name(4242), "DVH_STATUS_UNKNOWN") == 0);
    for (s = 0; s <= DVH_STATUS_BUSY; s++) CHECK(strcmp(dvh_status_name(s), "DVH_STATUS_UNKNOWN") != 0);
}

static void test_defaults(void) {
    DvhBuildOptions b = dvh_build_options_default();
    DvhQueryOptions q = dvh_query_options_default();
    DvhBuildOptions r = dvh_build_options_rigid();
    DvhQueryOptions zero_q;
    CHECK(b.tree == DVH_TREE_KIND_OCTREE && b.radius == DVH_RADIUS_KIND_LAYERED &&
          b.leftovers == DVH_LEFTOVER_POLICY_JOIN_ADJACENT && b.volume == DVH_VOLUME_KIND_AABB &&
          b.refit_threads == 0);
    CHECK(r.tree == DVH_TREE_KIND_OCTREE && r.radius == DVH_RADIUS_KIND_WRAPPED &&
          r.leftovers == DVH_LEFTOVER_POLICY_JOIN_ADJACENT && r.volume == DVH_VOLUME_KIND_SBV);
    CHECK(q.mode == DVH_QUERY_MODE_TRIANGLES && q.max_pairs == 0 && q.budget == 0 && q.threads == 0);
    /* Zeroed query options are the defaults. */
    memset(&zero_q, 0, sizeof zero_q);
    CHECK(memcmp(&zero_q, &q, sizeof q) == 0);
}

static void test_last_error_message(void) {
    char small[8];
    char big[256];
    size_t len;
    DvhMesh *m = (DvhMesh *)&len; /* a sentinel: must not be overwritten */
    CHECK(dvh_mesh_create(NULL, 3, NULL, 1, NULL, &m) == DVH_STATUS_NULL_ARGUMENT);
    CHECK(m == (DvhMesh *)&len);
    len = dvh_last_error_message(NULL, 0);
    CHECK(len == strlen("argument `positions` is NULL"));
    CHECK(dvh_last_error_message(small, sizeof small) == len);
    CHECK(strcmp(small, "argumen") == 0);
    CHECK(dvh_last_error_message(big, sizeof big) == len && strcmp(big, "argument `positions` is NULL") == 0);
    CHECK(dvh_last_error_message(big, 1) == len && big[0] == '\0');
    /* A successful call clears it. */
    {
        double t[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        bool hit = false;
        CHECK(dvh_triangles_intersect(t, t, &hit) == DVH_STATUS_OK && hit);
        CHECK(dvh_last_error_message(NULL, 0) == 0);
    }
}

static void test_create_errors(void) {
    Mesh m = mesh_terrain(3, 0, 0, flat);
    DvhMesh *sentinel = (DvhMesh *)&m, *out = sentinel;
    DvhBuildOptions o = dvh_build_options_default();
    uint32_t bad[6] = {0, 1, 2, 2, 1, 999};
    double *nan_pos = malloc(m.vertex_count * 3 * sizeof(double));
    char *raw = malloc(m.vertex_count * 3 * sizeof(double) + 8);
    float f32[16] = {0};

    CHECK_STATUS(dvh_mesh_create(NULL, m.vertex_count, m.tris, m.triangle_count, NULL, &out), DVH_STATUS_NULL_ARGUMENT, "`positions`");
    CHECK_STATUS(dvh_mesh_create(m.pos, m.vertex_count, NULL, m.triangle_count, NULL, &out), DVH_STATUS_NULL_ARGUMENT, "`triangles`");
    CHECK_STATUS(dvh_mesh_create(m.pos, m.vertex_count, m.tris, m.triangle_count, NULL, NULL), DVH_STATUS_NULL_ARGUMENT, "`mesh_out`");
    CHECK_STATUS(dvh_mesh_create(m.pos, m.vertex_count, m.tris, 0, NULL, &out), DVH_STATUS_INVALID_ARGUMENT, "no triangles");
    CHECK_STATUS(dvh_mesh_create(m.pos, m.vertex_count, bad, 2, NULL, &out), DVH_STATUS_INDEX_OUT_OF_RANGE,
                 "triangle 1, corner 2: vertex index 999");
    /* Counts beyond what u32 indices address are refused before anything is read. */
    CHECK_STATUS(dvh_mesh_create(m.pos, (size_t)1 << 40, m.tris, m.triangle_count, NULL, &out), DVH_STATUS_INVALID_ARGUMENT,
                 "vertex_count = 1099511627776");
    CHECK_STATUS(dvh_mesh_create(m.pos, m.vertex_count, m.tris, (size_t)1 << 33, NULL, &out), DVH_STATUS_INVALID_ARGUMENT,
                 "triangle_count = 8589934592");
    CHECK_STATUS(dvh_mesh_create_f32(f32, 12, (size_t)1 << 40, m.tris, 1, NULL, &out), DVH_STATUS_INVALID_ARGUMENT,
                 "vertex_count = 1099511627776");
    memcpy(nan_pos, m.pos, m.vertex_count * 3 * sizeof(double));
    nan_pos[3 * 5 + 2] = NAN;
    CHECK_STATUS(dvh_mesh_create(nan_pos, m.vertex_count, m.tris, m.triangle_count, NULL, &out), DVH_STATUS_NON_FINITE_COORDINATE,
                 "vertex 5: coordinate z is NaN");
    nan_pos[3 * 5 + 2] = -INFINITY;
    CHECK_STATUS(dvh_mesh_create(nan_pos, m.vertex_count, m.tris, m.triangle_count, NULL, &out), DVH_STATUS_NON_FINITE_COORDINATE,
                 "-inf");
    /* A misaligned double array. */
    memcpy(raw + 1, m.pos, m.vertex_count * 3 * sizeof(double));
    CHECK_STATUS(dvh_mesh_create((const double *)(const void *)(raw + 1), m.vertex_count, m.tris, m.triangle_count, NULL, &out),
                 DVH_STATUS_INVALID_ARGUMENT, "aligned");
    o.tree = 7;
    CHECK_STATUS(dvh_mesh_create(m.pos, m.vertex_count, m.tris, m.triangle_count, &o, &out), DVH_STATUS_INVALID_ARGUMENT,
                 "options->tree = 7");
    o = dvh_build_options_default();
    o.radius = 2;
    CHECK_STATUS(dvh_mesh_create(m.pos, m.vertex_count, m.tris, m.triangle_count, &o, &out), DVH_STATUS_INVALID_ARGUMENT,
                 "options->radius = 2");
    o = dvh_build_options_default();
    o.leftovers = 99;
    CHECK_STATUS(dvh_mesh_create(m.pos, m.vertex_count, m.tris, m.triangle_count, &o, &out), DVH_STATUS_INVALID_ARGUMENT,
                 "options->leftovers = 99");
    o = dvh_build_options_default();
    o.volume = 3;
    CHECK_STATUS(dvh_mesh_create(m.pos, m.vertex_count, m.tris, m.triangle_count, &o, &out), DVH_STATUS_INVALID_ARGUMENT,
                 "options->volume = 3");
    /* f32 creation errors. */
    CHECK_STATUS(dvh_mesh_create_f32(NULL, 12, 3, m.tris, 1, NULL, &out), DVH_STATUS_NULL_ARGUMENT, "`positions`");
    CHECK_STATUS(dvh_mesh_create_f32(f32, 8, 3, m.tris, 1, NULL, &out), DVH_STATUS_INVALID_ARGUMENT, "stride_bytes = 8");
    CHECK_STATUS(dvh_mesh_create_f32(f32, 12, 3, m.tris, 1, NULL, NULL), DVH_STATUS_NULL_ARGUMENT, "`mesh_out`");
    CHECK_STATUS(dvh_mesh_create_f32(f32, (size_t)1 << 62, 1000, m.tris, 1, NULL, &out), DVH_STATUS_INVALID_ARGUMENT,
                 "do not fit");
    f32[4] = INFINITY;
    CHECK_STATUS(dvh_mesh_create_f32(f32, 12, 3, m.tris, 1, NULL, &out), DVH_STATUS_NON_FINITE_COORDINATE,
                 "vertex 1: coordinate y is inf");
    CHECK(out == sentinel);
    free(nan_pos);
    free(raw);
    mesh_free(&m);
}

static void test_accessors(void) {
    Mesh m = mesh_terrain(6, 0, 0, wave);
    DvhMesh *mesh = create(&m, NULL);
    DvhTreeStats ts;
    DvhRefitStats rs;
    const uint32_t *tris;
    size_t count, node_count;
    CHECK(dvh_mesh_vertex_count(mesh) == m.vertex_count);
    CHECK(dvh_mesh_triangle_count(mesh) == m.triangle_count);
    node_count = dvh_mesh_node_count(mesh);
    CHECK(node_count >= 1);
    CHECK(dvh_mesh_vertex_count(NULL) == 0 && dvh_mesh_triangle_count(NULL) == 0 && dvh_mesh_node_count(NULL) == 0);
    CHECK_STATUS(dvh_mesh_tree_stats(mesh, &ts), DVH_STATUS_OK, NULL);
    CHECK(ts.triangles == m.triangle_count && ts.rings + ts.inner_nodes == node_count && ts.levels >= 1);
    CHECK_STATUS(dvh_mesh_tree_stats(NULL, &ts), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
    CHECK_STATUS(dvh_mesh_tree_stats(mesh, NULL), DVH_STATUS_NULL_ARGUMENT, "`stats_out`");
    CHECK_STATUS(dvh_mesh_last_refit_stats(mesh, &rs), DVH_STATUS_OK, NULL);
    CHECK(rs.nodes_refit == node_count && rs.distance_evaluations > 0);
    CHECK_STATUS(dvh_mesh_last_refit_stats(NULL, &rs), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
    CHECK_STATUS(dvh_mesh_last_refit_stats(mesh, NULL), DVH_STATUS_NULL_ARGUMENT, "`stats_out`");
    /* The root holds every triangle once. */
    CHECK_STATUS(dvh_mesh_node_triangles(mesh, 0, &tris, &count), DVH_STATUS_OK, NULL);
    CHECK(count == m.triangle_count);
    {
        size_t i;
        unsigned char *seen = calloc(m.triangle_count, 1);
        for (i = 0; i < count; i++) {
            CHECK(tris[i] < m.triangle_count && !seen[tris[i]]);
            seen[tris[i]] = 1;
        }
        free(seen);
    }
    CHECK_STATUS(dvh_mesh_node_triangles(mesh, (uint32_t)node_count, &tris, &count), DVH_STATUS_INVALID_ARGUMENT, "out of range");
    CHECK_STATUS(dvh_mesh_node_triangles(NULL, 0, &tris, &count), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
    CHECK_STATUS(dvh_mesh_node_triangles(mesh, 0, NULL, &count), DVH_STATUS_NULL_ARGUMENT, "`triangles_out`");
    CHECK_STATUS(dvh_mesh_node_triangles(mesh, 0, &tris, NULL), DVH_STATUS_NULL_ARGUMENT, "`count_out`");
    CHECK_STATUS(dvh_mesh_validate(NULL), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
    dvh_mesh_free(mesh);
    dvh_mesh_free(NULL);
    mesh_free(&m);
}

/* Interleaved f32 vertices (position, normal, uv: 32 bytes), deliberately misaligned. */
static void test_f32_stride_and_refit(void) {
    Mesh ma = mesh_terrain(5, 0, 0, ridge), mb = mesh_terrain(5, 2, 1, wave);
    size_t stride = 32, i;
    unsigned char *storage = malloc(ma.vertex_count * stride + 3);
    unsigned char *base = storage + 2;
    DvhMesh *a64 = create(&ma, NULL), *b = create(&mb, NULL), *a32 = NULL;
    DvhPairs *p64 = dvh_pairs_new(), *p32 = dvh_pairs_new();
    double *moved = malloc(ma.vertex_count * 3 * sizeof(double));
    DvhRefitStats rs;

    for (i = 0; i < ma.vertex_count; i++) {
        float v[8];
        v[0] = (float)ma.pos[3 * i];
        v[1] = (float)ma.pos[3 * i + 1];
        v[2] = (float)ma.pos[3 * i + 2];
        v[3] = 0.0f; v[4] = 0.0f; v[5] = 1.0f; v[6] = 0.5f; v[7] = 0.25f;
        memcpy(base + i * stride, v, sizeof v);
    }
    CHECK_STATUS(dvh_mesh_create_f32((const float *)(const void *)base, stride, ma.vertex_count, ma.tris, ma.triangle_count, NULL, &a32),
                 DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_collide(a64, NULL, b, NULL, NULL, p64, NULL), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_collide(a32, NULL, b, NULL, NULL, p32, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(p64) > 0 && same_pairs(p32, dvh_pairs_data(p64), dvh_pairs_len(p64)));

    /* Move every vertex up by 1 in both layouts: the same answer again. */
    for (i = 0; i < ma.vertex_count; i++) {
        float z = (float)(ma.pos[3 * i + 2] + 1.0);
        memcpy(base + i * stride + 8, &z, sizeof z);
        moved[3 * i] = ma.pos[3 * i];
        moved[3 * i + 1] = ma.pos[3 * i + 1];
        moved[3 * i + 2] = ma.pos[3 * i + 2] + 1.0;
    }
    CHECK_STATUS(dvh_mesh_refit(a64, moved, ma.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_refit_f32(a32, (const float *)(const void *)base, stride, ma.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_validate(a32), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_last_refit_stats(a32, &rs), DVH_STATUS_OK, NULL);
    CHECK(rs.nodes_refit == dvh_mesh_node_count(a32));
    CHECK_STATUS(dvh_collide(a64, NULL, b, NULL, NULL, p64, NULL), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_collide(a32, NULL, b, NULL, NULL, p32, NULL), DVH_STATUS_OK, NULL);
    CHECK(same_pairs(p32, dvh_pairs_data(p64), dvh_pairs_len(p64)));

    /* Refit errors leave the mesh exactly as it was: same answer afterwards. */
    {
        size_t before = dvh_pairs_len(p32);
        float bad = NAN;
        moved[3 * 4 + 1] = INFINITY;
        CHECK_STATUS(dvh_mesh_refit(a64, moved, ma.vertex_count), DVH_STATUS_NON_FINITE_COORDINATE, "vertex 4: coordinate y is inf");
        CHECK_STATUS(dvh_mesh_refit(a64, moved, ma.vertex_count - 1), DVH_STATUS_INVALID_ARGUMENT, "vertex_count");
        CHECK_STATUS(dvh_mesh_refit(NULL, moved, ma.vertex_count), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
        CHECK_STATUS(dvh_mesh_refit(a64, NULL, ma.vertex_count), DVH_STATUS_NULL_ARGUMENT, "`positions`");
        memcpy(base + 7 * stride, &bad, sizeof bad);
        CHECK_STATUS(dvh_mesh_refit_f32(a32, (const float *)(const void *)base, stride, ma.vertex_count),
                     DVH_STATUS_NON_FINITE_COORDINATE, "vertex 7: coordinate x is NaN");
        CHECK_STATUS(dvh_mesh_refit_f32(a32, (const float *)(const void *)base, 4, ma.vertex_count), DVH_STATUS_INVALID_ARGUMENT,
                     "stride_bytes = 4");
        CHECK_STATUS(dvh_mesh_refit_f32(a32, NULL, stride, ma.vertex_count), DVH_STATUS_NULL_ARGUMENT, "`positions`");
        CHECK_STATUS(dvh_mesh_refit_f32(a32, (const float *)(const void *)base, stride, 3), DVH_STATUS_INVALID_ARGUMENT,
                     "vertex_count = 3");
        CHECK_STATUS(dvh_mesh_validate(a64), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_mesh_validate(a32), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_collide(a64, NULL, b, NULL, NULL, p64, NULL), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_collide(a32, NULL, b, NULL, NULL, p32, NULL), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(p32) == before && same_pairs(p32, dvh_pairs_data(p64), dvh_pairs_len(p64)));
    }
    dvh_pairs_free(p64);
    dvh_pairs_free(p32);
    dvh_mesh_free(a64);
    dvh_mesh_free(a32);
    dvh_mesh_free(b);
    free(storage);
    free(moved);
    mesh_free(&ma);
    mesh_free(&mb);
}

static void test_collide_errors(void) {
    Mesh ma = mesh_terrain(4, 0, 0, wave), mb = mesh_terrain(4, 1, 1, ridge);
    DvhMesh *a = create(&ma, NULL), *b = create(&mb, NULL);
    DvhPairs *pairs = dvh_pairs_new();
    DvhQueryOptions q = dvh_query_options_default();
    DvhQueryStats stats, sentinel;
    IPose ip = ipose_make(0, 0, 0, 0);
    DvhPose pose = ipose_to_dvh(&ip), bad;
    DvhPair *before;
    size_t n, i;

    CHECK(pairs != NULL);
    CHECK(dvh_pairs_len(pairs) == 0 && dvh_pairs_data(pairs) == NULL && dvh_pairs_kind(pairs) == DVH_PAIR_KIND_TRIANGLES);
    CHECK(dvh_pairs_len(NULL) == 0 && dvh_pairs_data(NULL) == NULL && dvh_pairs_kind(NULL) == DVH_PAIR_KIND_TRIANGLES);
    CHECK_STATUS(dvh_collide(a, NULL, b, &pose, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
    n = dvh_pairs_len(pairs);
    CHECK(n > 0);
    before = malloc(n * sizeof *before);
    memcpy(before, dvh_pairs_data(pairs), n * sizeof *before);
    memset(&sentinel, 0xab, sizeof sentinel);
    stats = sentinel;

    CHECK_STATUS(dvh_collide(NULL, NULL, b, NULL, NULL, pairs, &stats), DVH_STATUS_NULL_ARGUMENT, "`a`");
    CHECK_STATUS(dvh_collide(a, NULL, NULL, NULL, NULL, pairs, &stats), DVH_STATUS_NULL_ARGUMENT, "`b`");
    CHECK_STATUS(dvh_collide(a, NULL, b, NULL, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT, "`pairs_out`");
    q.mode = 5;
    CHECK_STATUS(dvh_collide(a, NULL, b, NULL, &q, pairs, &stats), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 5");
    q.mode = DVH_QUERY_MODE_BUDGET;
    q.budget = 0;
    CHECK_STATUS(dvh_collide(a, NULL, b, NULL, &q, pairs, &stats), DVH_STATUS_INVALID_ARGUMENT, "options->budget = 0");
    bad = pose;
    bad.rotation[0] = 1.1;
    CHECK_STATUS(dvh_collide(a, &bad, b, NULL, NULL, pairs, &stats), DVH_STATUS_NON_RIGID_POSE, "pose_a: pose rotation is not a rotation");
    bad = pose;
    bad.rotation[4] = -bad.rotation[4];
    bad.rotation[3] = -bad.rotation[3];
    bad.rotation[5] = -bad.rotation[5]; /* a reflection */
    CHECK_STATUS(dvh_collide(a, NULL, b, &bad, NULL, pairs, &stats), DVH_STATUS_NON_RIGID_POSE, "pose_b");
    bad = pose;
    bad.translation[2] = NAN;
    CHECK_STATUS(dvh_collide(a, NULL, b, &bad, NULL, pairs, &stats), DVH_STATUS_NON_FINITE_COORDINATE, "pose_b: pose translation[2] is NaN");
    bad = pose;
    bad.translation[0] = 1e305;
    CHECK_STATUS(dvh_collide(a, &bad, b, NULL, NULL, pairs, &stats), DVH_STATUS_POSE_OUT_OF_RANGE, "pose of mesh A");
    /* Nothing changed. */
    CHECK(memcmp(&stats, &sentinel, sizeof stats) == 0);
    CHECK(same_pairs(pairs, before, n));

    /* Reuse: a query that finds nothing empties the buffer; another fills it again. */
    {
        IPose far = ipose_make(0, 100, 0, 0);
        DvhPose pfar = ipose_to_dvh(&far);
        CHECK_STATUS(dvh_collide(a, NULL, b, &pfar, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(pairs) == 0 && dvh_pairs_data(pairs) == NULL && stats.pairs == 0);
        for (i = 0; i < 3; i++) {
            CHECK_STATUS(dvh_collide(a, NULL, b, &pose, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
            CHECK(same_pairs(pairs, before, n));
        }
    }
    /* A limit of 1 in the default mode. */
    q = dvh_query_options_default();
    q.max_pairs = 1;
    CHECK_STATUS(dvh_collide(a, NULL, b, &pose, &q, pairs, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == 1 && stats.truncated);

    free(before);
    dvh_pairs_free(pairs);
    dvh_pairs_free(NULL);
    dvh_mesh_free(a);
    dvh_mesh_free(b);
    mesh_free(&ma);
    mesh_free(&mb);
}

static void test_triangle_test(void) {
    double t1[9] = {0}, t2[9] = {0};
    bool hit = false, sentinel = true;
    int k, c, agree = 1;
    CHECK_STATUS(dvh_triangles_intersect(NULL, t2, &hit), DVH_STATUS_NULL_ARGUMENT, "`t1`");
    CHECK_STATUS(dvh_triangles_intersect(t1, NULL, &hit), DVH_STATUS_NULL_ARGUMENT, "`t2`");
    CHECK_STATUS(dvh_triangles_intersect(t1, t2, NULL), DVH_STATUS_NULL_ARGUMENT, "`result_out`");
    t2[7] = NAN;
    CHECK_STATUS(dvh_triangles_intersect(t1, t2, &sentinel), DVH_STATUS_NON_FINITE_COORDINATE, "t2[7] is NaN");
    CHECK(sentinel == true);
    lcg_state = 99;
    for (k = 0; k < 3000; k++) {
        int64_t a[3][3], b[3][3];
        for (c = 0; c < 9; c++) {
            a[c / 3][c % 3] = lcg_below(5) - 2;
            b[c / 3][c % 3] = lcg_below(5) - 2;
            t1[c] = (double)a[c / 3][c % 3];
            t2[c] = (double)b[c / 3][c % 3];
        }
        if (dvh_triangles_intersect(t1, t2, &hit) != DVH_STATUS_OK || hit != (oracle_intersect(a, b) != 0)) agree = 0;
    }
    CHECK(agree);
}

static void test_against_oracle(void) {
    DvhPairs *pairs = dvh_pairs_new();
    Mesh t1 = mesh_terrain(6, 0, 0, wave), t2 = mesh_terrain(5, 1, 2, ridge), t3 = mesh_terrain(4, 2, 2, flat);
    Mesh s1, s2;
    DvhBuildOptions o = dvh_build_options_default();
    unsigned tree, radius, left, volume;
    int k;
    lcg_state = 7;
    s1 = mesh_soup(80, -4, 8);
    s2 = mesh_soup(60, -3, 7);
    for (volume = 0; volume < 3; volume++)
        for (tree = 0; tree < 2; tree++)
            for (radius = 0; radius < 2; radius++)
                for (left = 0; left < 2; left++) {
                    /* Every DVH combination; for SBV and boxes, which share the trees and the
                     * rings, one per tree kind (boxes ignore the radius kind). */
                    if (volume != DVH_VOLUME_KIND_DVH && (radius != tree || left != tree)) continue;
                    o.radius = radius;
                    o.volume = volume;
                    o.tree = tree;
                    o.leftovers = left;
                    check_scene(&t1, NULL, &t2, NULL, &o, pairs);
                    check_scene(&t1, NULL, &t3, NULL, &o, pairs); /* coplanar contact */
                    check_scene(&s1, NULL, &s2, NULL, &o, pairs);
                    for (k = 0; k < 24; k += 5) {
                        IPose pa = ipose_make(k, 1, -1, 0), pb = ipose_make(23 - k, 2, 1, 1);
                        check_scene(&t1, &pa, &s2, &pb, &o, pairs);
                        check_scene(&s1, NULL, &t2, &pb, &o, pairs);
                    }
                    check_scene(&t2, NULL, &t2, NULL, &o, pairs); /* a mesh against an exact copy */
                }
    dvh_pairs_free(pairs);
    mesh_free(&t1);
    mesh_free(&t2);
    mesh_free(&t3);
    mesh_free(&s1);
    mesh_free(&s2);
}

/* ---- scenes ---- */

typedef struct SceneModel {
    const DvhMesh *mesh; /* the geometry to query pair by pair */
    int posed;
    DvhPose pose;
    int alive;
} SceneModel;

/* The contacts of every live object pair, queried pair by pair with dvh_collide, in the scene's
 * order; returns the count (at most `cap` written). */
static size_t scene_expected(const SceneModel *m, size_t n, const DvhQueryOptions *o, DvhContact *out, size_t cap) {
    DvhPairs *p = dvh_pairs_new();
    size_t count = 0, i, j, k;
    for (i = 0; i < n; i++)
        for (j = i + 1; j < n; j++) {
            if (!m[i].alive || !m[j].alive) continue;
            CHECK_STATUS(dvh_collide(m[i].mesh, m[i].posed ? &m[i].pose : NULL, m[j].mesh, m[j].posed ? &m[j].pose : NULL, o, p, NULL),
                         DVH_STATUS_OK, NULL);
            for (k = 0; k < dvh_pairs_len(p); k++, count++)
                if (count < cap) {
                    out[count].object_a = (uint32_t)i;
                    out[count].object_b = (uint32_t)j;
                    out[count].a = dvh_pairs_data(p)[k].a;
                    out[count].b = dvh_pairs_data(p)[k].b;
                }
        }
    dvh_pairs_free(p);
    return count;
}

static int same_contacts(const DvhContacts *c, const DvhContact *expected, size_t n) {
    size_t i;
    const DvhContact *d = dvh_contacts_data(c);
    if (dvh_contacts_len(c) != n) return 0;
    if (n == 0) return d == NULL;
    for (i = 0; i < n; i++)
        if (memcmp(&d[i], &expected[i], sizeof *d) != 0) return 0;
    return 1;
}

static void test_scene(void) {
    enum { CAP = 20000 };
    Mesh ma = mesh_terrain(6, 0, 0, wave), mb = mesh_terrain(5, 1, 1, ridge);
    DvhMesh *a = create(&ma, NULL), *b = create(&mb, NULL), *a_moved = create(&ma, NULL), *a16 = NULL;
    DvhScene *scene = NULL;
    DvhContacts *contacts = dvh_contacts_new();
    DvhContact *expected = malloc(CAP * sizeof *expected);
    DvhSceneStats st;
    DvhQueryOptions o = dvh_query_options_default();
    IPose ip1 = ipose_make(5, 5, 0, 4), ip2 = ipose_make(0, 30, 0, 0);
    SceneModel model[4];
    uint32_t id = 99, ids[4];
    double *moved = malloc(ma.vertex_count * 3 * sizeof(double));
    float *moved32 = malloc(ma.vertex_count * 4 * sizeof(float));
    uint16_t *tris16 = malloc(ma.triangle_count * 3 * sizeof(uint16_t));
    size_t n, i;
    int mode;

    /* 16-bit indices build the same mesh. */
    for (i = 0; i < ma.triangle_count * 3; i++) tris16[i] = (uint16_t)ma.tris[i];
    CHECK_STATUS(dvh_mesh_create_u16(ma.pos, ma.vertex_count, tris16, ma.triangle_count, NULL, &a16), DVH_STATUS_OK, NULL);
    CHECK(a16 != NULL && dvh_mesh_triangle_count(a16) == ma.triangle_count);
    tris16[4] = 60000;
    CHECK_STATUS(dvh_mesh_create_u16(ma.pos, ma.vertex_count, tris16, ma.triangle_count, NULL, &a16), DVH_STATUS_INDEX_OUT_OF_RANGE,
                 "triangle 1, corner 1: vertex index 60000");
    CHECK_STATUS(dvh_mesh_create_u16(ma.pos, ma.vertex_count, NULL, ma.triangle_count, NULL, &a16), DVH_STATUS_NULL_ARGUMENT, "`triangles`");

    CHECK_STATUS(dvh_scene_create(NULL), DVH_STATUS_NULL_ARGUMENT, "`scene_out`");
    CHECK_STATUS(dvh_scene_create(&scene), DVH_STATUS_OK, NULL);
    /* 0: terrain a, deformable; 1, 2: terrain b, rigid, sharing its mesh; 3: a16, deformable. */
    CHECK_STATUS(dvh_scene_add_deformable(scene, a, 1, 0xffffffffu, &ids[0]), DVH_STATUS_OK, NULL);
    model[0].mesh = a_moved; model[0].posed = 0; model[0].alive = 1;
    model[1].mesh = b; model[1].posed = 1; model[1].pose = ipose_to_dvh(&ip1); model[1].alive = 1;
    model[2].mesh = b; model[2].posed = 1; model[2].pose = ipose_to_dvh(&ip2); model[2].alive = 1;
    model[3].mesh = a16; model[3].posed = 0; model[3].alive = 1;
    CHECK_STATUS(dvh_scene_add_rigid(scene, b, &model[1].pose, 1, 0xffffffffu, &ids[1]), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_add_rigid(scene, b, &model[2].pose, 1, 0xffffffffu, &ids[2]), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_add_deformable(scene, a16, 1, 0xffffffffu, &ids[3]), DVH_STATUS_OK, NULL);
    for (i = 0; i < 4; i++) CHECK(ids[i] == i);

    /* Object 0 moves by (1, 0, 1) in double, the copy a_moved with it; object 3 stays (f32 input
     * of the same values). */
    for (i = 0; i < ma.vertex_count; i++) {
        moved[3 * i] = ma.pos[3 * i] + 1.0;
        moved[3 * i + 1] = ma.pos[3 * i + 1];
        moved[3 * i + 2] = ma.pos[3 * i + 2] + 1.0;
        moved32[4 * i] = (float)ma.pos[3 * i];
        moved32[4 * i + 1] = (float)ma.pos[3 * i + 1];
        moved32[4 * i + 2] = (float)ma.pos[3 * i + 2];
        moved32[4 * i + 3] = 0.0f;
    }
    CHECK_STATUS(dvh_scene_set_positions(scene, 0, moved, ma.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_refit(a_moved, moved, ma.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_set_positions_f32(scene, 3, moved32, 16, ma.vertex_count), DVH_STATUS_OK, NULL);

    for (mode = 0; mode < 5; mode++) {
        unsigned threads;
        o = dvh_query_options_default();
        o.mode = (DvhQueryMode)mode;
        o.max_depth = 2;
        o.budget = 30;
        n = scene_expected(model, 4, &o, expected, CAP);
        CHECK(n > 0 && n <= CAP);
        for (threads = 0; threads < 3; threads++) {
            o.threads = threads;
            CHECK_STATUS(dvh_scene_collide(scene, &o, contacts, &st), DVH_STATUS_OK, NULL);
            CHECK(same_contacts(contacts, expected, n));
            CHECK(st.contacts == n && st.objects == 4 && !st.truncated);
            CHECK(dvh_contacts_kind(contacts) == (mode >= DVH_QUERY_MODE_LEAVES ? DVH_PAIR_KIND_NODES : DVH_PAIR_KIND_TRIANGLES));
        }
    }
    /* The far object 2 is culled by the broad phase: at most the 3 pairs without it are
     * queried, and the colliding ones are those with contacts. */
    CHECK_STATUS(dvh_scene_collide(scene, NULL, contacts, &st), DVH_STATUS_OK, NULL);
    {
        uint64_t colliding = 0;
        const DvhContact *d = dvh_contacts_data(contacts);
        for (i = 0; i < dvh_contacts_len(contacts); i++) {
            CHECK(d[i].object_a != 2 && d[i].object_b != 2);
            colliding += i == 0 || d[i].object_a != d[i - 1].object_a || d[i].object_b != d[i - 1].object_b;
        }
        CHECK(colliding >= 2 && st.object_pairs_colliding == colliding);
        CHECK(st.object_pairs_tested >= colliding && st.object_pairs_tested <= 3);
    }

    /* max_pairs bounds the whole result. */
    o = dvh_query_options_default();
    o.max_pairs = 5;
    CHECK_STATUS(dvh_scene_collide(scene, &o, contacts, &st), DVH_STATUS_OK, NULL);
    CHECK(dvh_contacts_len(contacts) == 5 && st.truncated);

    /* Errors name what was wrong and change nothing. */
    CHECK_STATUS(dvh_scene_set_pose(scene, 9, NULL), DVH_STATUS_INVALID_ARGUMENT, "object 9 is not in the scene");
    CHECK_STATUS(dvh_scene_set_pose(scene, 0, NULL), DVH_STATUS_INVALID_ARGUMENT, "object 0 is deformable");
    CHECK_STATUS(dvh_scene_set_positions(scene, 1, moved, mb.vertex_count), DVH_STATUS_INVALID_ARGUMENT, "object 1 is rigid");
    CHECK_STATUS(dvh_scene_set_positions(scene, 0, moved, 3), DVH_STATUS_INVALID_ARGUMENT, "vertex_count = 3, but object 0 has");
    CHECK_STATUS(dvh_scene_set_positions(scene, 0, NULL, ma.vertex_count), DVH_STATUS_NULL_ARGUMENT, "`positions`");
    CHECK_STATUS(dvh_scene_set_positions_f32(scene, 0, moved32, 8, ma.vertex_count), DVH_STATUS_INVALID_ARGUMENT, "stride_bytes = 8");
    moved[3 * 2 + 1] = NAN;
    CHECK_STATUS(dvh_scene_set_positions(scene, 0, moved, ma.vertex_count), DVH_STATUS_NON_FINITE_COORDINATE,
                 "object 0: vertex 2: coordinate y is NaN");
    {
        DvhPose bad = model[1].pose;
        bad.rotation[0] = 2.0;
        CHECK_STATUS(dvh_scene_set_pose(scene, 1, &bad), DVH_STATUS_NON_RIGID_POSE, "pose");
        bad = model[1].pose;
        bad.translation[1] = 1e301;
        CHECK_STATUS(dvh_scene_set_pose(scene, 1, &bad), DVH_STATUS_POSE_OUT_OF_RANGE, "object 1: pose moves");
        CHECK_STATUS(dvh_scene_add_rigid(scene, b, &bad, 1, 1, &id), DVH_STATUS_POSE_OUT_OF_RANGE, "pose moves");
    }
    CHECK_STATUS(dvh_scene_add_rigid(NULL, b, NULL, 1, 1, &id), DVH_STATUS_NULL_ARGUMENT, "`scene`");
    CHECK_STATUS(dvh_scene_add_rigid(scene, NULL, NULL, 1, 1, &id), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
    CHECK_STATUS(dvh_scene_add_deformable(scene, a, 1, 1, NULL), DVH_STATUS_NULL_ARGUMENT, "`object_out`");
    CHECK_STATUS(dvh_scene_exclude_pair(scene, 1, 1), DVH_STATUS_INVALID_ARGUMENT, "object 1 was paired with itself");
    CHECK_STATUS(dvh_scene_exclude_pair(scene, 1, 7), DVH_STATUS_INVALID_ARGUMENT, "object 7");
    CHECK_STATUS(dvh_scene_remove(scene, 7), DVH_STATUS_INVALID_ARGUMENT, "object 7");
    CHECK_STATUS(dvh_scene_remove(NULL, 0), DVH_STATUS_NULL_ARGUMENT, "`scene`");
    CHECK_STATUS(dvh_scene_collide(scene, NULL, NULL, &st), DVH_STATUS_NULL_ARGUMENT, "`contacts_out`");
    o = dvh_query_options_default();
    o.mode = 9;
    CHECK_STATUS(dvh_scene_collide(scene, &o, contacts, &st), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 9");
    CHECK(id == 99);
    o = dvh_query_options_default();
    n = scene_expected(model, 4, &o, expected, CAP);
    CHECK_STATUS(dvh_scene_collide(scene, NULL, contacts, &st), DVH_STATUS_OK, NULL);
    CHECK(same_contacts(contacts, expected, n));

    /* Exclusions and filters; a removed id is reused. */
    CHECK_STATUS(dvh_scene_exclude_pair(scene, 3, 0), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_collide(scene, NULL, contacts, &st), DVH_STATUS_OK, NULL);
    for (i = 0; i < dvh_contacts_len(contacts); i++) CHECK(!(dvh_contacts_data(contacts)[i].object_a == 0 && dvh_contacts_data(contacts)[i].object_b == 3));
    CHECK(st.object_pairs_tested <= 2 && dvh_contacts_len(contacts) > 0);
    CHECK_STATUS(dvh_scene_remove(scene, 1), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_add_rigid(scene, b, &model[1].pose, 2, 2, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 1);
    CHECK_STATUS(dvh_scene_collide(scene, NULL, contacts, &st), DVH_STATUS_OK, NULL);
    CHECK(st.objects == 4 && st.object_pairs_tested == 0 && dvh_contacts_len(contacts) == 0 && dvh_contacts_data(contacts) == NULL);

    /* A rigid-only scene: three placed copies of one mesh, the second shifted by one cell (the
     * ridges cross), the third far away. */
    {
        DvhScene *rigid_scene = NULL;
        SceneModel rm[3];
        IPose here = ipose_make(0, 0, 0, 0), beside = ipose_make(0, 1, 0, 0), far = ipose_make(3, 40, 0, 0);
        rm[0].mesh = b; rm[0].posed = 1; rm[0].pose = ipose_to_dvh(&here); rm[0].alive = 1;
        rm[1].mesh = b; rm[1].posed = 1; rm[1].pose = ipose_to_dvh(&beside); rm[1].alive = 1;
        rm[2].mesh = b; rm[2].posed = 1; rm[2].pose = ipose_to_dvh(&far); rm[2].alive = 1;
        CHECK_STATUS(dvh_scene_create(&rigid_scene), DVH_STATUS_OK, NULL);
        for (i = 0; i < 3; i++) {
            CHECK_STATUS(dvh_scene_add_rigid(rigid_scene, b, &rm[i].pose, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
            CHECK(id == i);
        }
        o = dvh_query_options_default();
        n = scene_expected(rm, 3, &o, expected, CAP);
        CHECK(n > 0 && n <= CAP);
        CHECK_STATUS(dvh_scene_collide(rigid_scene, &o, contacts, &st), DVH_STATUS_OK, NULL);
        CHECK(same_contacts(contacts, expected, n) && st.nodes_refit == 0 && st.object_pairs_tested == 1);
        dvh_scene_free(rigid_scene);
    }

    CHECK(dvh_contacts_len(NULL) == 0 && dvh_contacts_data(NULL) == NULL);
    CHECK(dvh_contacts_kind(NULL) == DVH_PAIR_KIND_TRIANGLES);
    dvh_contacts_free(NULL);
    dvh_scene_free(NULL);
    dvh_contacts_free(contacts);
    dvh_scene_free(scene);
    dvh_mesh_free(a);
    dvh_mesh_free(b);
    dvh_mesh_free(a_moved);
    dvh_mesh_free(a16);
    free(expected);
    free(moved);
    free(moved32);
    free(tris16);
    mesh_free(&ma);
    mesh_free(&mb);
}

/* Lazy refit against eager: a large deforming sheet crossed at one corner by small deforming
 * and rigid sheets, over random frames. The scene refits only the blocks of the large sheet a
 * traversal reaches; its contacts must equal dvh_collide's on meshes refit whole with
 * dvh_mesh_refit. */
static void test_scene_lazy(void) {
    enum { CAP = 50000, N = 48, OBJECTS = 3, FRAMES = 8 };
    Mesh big = mesh_terrain(N, 0, 0, wave), small = mesh_terrain(4, 0, 0, ridge);
    DvhMesh *model_big = create(&big, NULL), *model_small = create(&small, NULL), *rigid = create(&small, NULL);
    DvhScene *scene = NULL;
    DvhContacts *contacts = dvh_contacts_new();
    DvhContact *expected = malloc(CAP * sizeof *expected);
    double *pb = malloc(big.vertex_count * 3 * sizeof(double)), *ps = malloc(small.vertex_count * 3 * sizeof(double));
    SceneModel model[OBJECTS];
    DvhSceneStats st;
    uint32_t id;
    size_t i, n;
    int frame;

    CHECK_STATUS(dvh_scene_create(&scene), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_add_deformable(scene, model_big, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 0);
    CHECK_STATUS(dvh_scene_add_deformable(scene, model_small, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 1);
    model[0].mesh = model_big; model[0].posed = 0; model[0].alive = 1;
    model[1].mesh = model_small; model[1].posed = 0; model[1].alive = 1;
    model[2].mesh = rigid; model[2].posed = 1; model[2].alive = 1;
    {
        IPose ip = ipose_make(N - 3, N - 3, 0, 0);
        model[2].pose = ipose_to_dvh(&ip);
    }
    CHECK_STATUS(dvh_scene_add_rigid(scene, rigid, &model[2].pose, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 2);
    lcg_state = 2024;
    for (frame = 0; frame < FRAMES; frame++) {
        DvhQueryOptions o = dvh_query_options_default();
        /* The large sheet: heights jitter by quarters; the small one crosses a corner. */
        for (i = 0; i < big.vertex_count; i++) {
            pb[3 * i] = big.pos[3 * i];
            pb[3 * i + 1] = big.pos[3 * i + 1];
            pb[3 * i + 2] = big.pos[3 * i + 2] + 0.25 * (lcg_below(5) - 2);
        }
        for (i = 0; i < small.vertex_count; i++) {
            ps[3 * i] = small.pos[3 * i] + 0.5 * lcg_below(3);
            ps[3 * i + 1] = small.pos[3 * i + 1] + 0.5 * lcg_below(3);
            ps[3 * i + 2] = small.pos[3 * i + 2] - 0.5;
        }
        if (frame % 3 != 2) {
            CHECK_STATUS(dvh_scene_set_positions(scene, 0, pb, big.vertex_count), DVH_STATUS_OK, NULL);
            CHECK_STATUS(dvh_mesh_refit(model_big, pb, big.vertex_count), DVH_STATUS_OK, NULL);
        }
        CHECK_STATUS(dvh_scene_set_positions(scene, 1, ps, small.vertex_count), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_mesh_refit(model_small, ps, small.vertex_count), DVH_STATUS_OK, NULL);
        o.mode = frame % 4 == 3 ? DVH_QUERY_MODE_FIRST_HIT : DVH_QUERY_MODE_TRIANGLES;
        o.threads = (uint32_t)(frame % 2);
        n = scene_expected(model, OBJECTS, &o, expected, CAP);
        CHECK(n <= CAP);
        CHECK_STATUS(dvh_scene_collide(scene, &o, contacts, &st), DVH_STATUS_OK, NULL);
        CHECK(same_contacts(contacts, expected, n));
        /* The sheets touch at two corners: most of the large one is never refit. */
        CHECK(st.nodes_refit < dvh_mesh_node_count(model_big) / 2 + dvh_mesh_node_count(model_small));
    }
    /* Eager refit: the moved objects whole, the same contacts. */
    CHECK_STATUS(dvh_scene_set_lazy_refit(NULL, false), DVH_STATUS_NULL_ARGUMENT, "`scene`");
    CHECK_STATUS(dvh_scene_set_lazy_refit(scene, false), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_set_positions(scene, 0, pb, big.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_set_positions(scene, 1, ps, small.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_collide(scene, NULL, contacts, &st), DVH_STATUS_OK, NULL);
    {
        DvhQueryOptions o = dvh_query_options_default();
        n = scene_expected(model, OBJECTS, &o, expected, CAP);
    }
    CHECK(same_contacts(contacts, expected, n));
    CHECK(st.nodes_refit == dvh_mesh_node_count(model_big) + dvh_mesh_node_count(model_small));
    CHECK(n > 0);
    dvh_contacts_free(contacts);
    dvh_scene_free(scene);
    dvh_mesh_free(model_big);
    dvh_mesh_free(model_small);
    dvh_mesh_free(rigid);
    free(expected);
    free(pb);
    free(ps);
    mesh_free(&big);
    mesh_free(&small);
}

/* Pairs a < b of `all` (every ordered intersecting pair of a mesh with itself), in place. */
static size_t upper_pairs(DvhPair *all, size_t n) {
    size_t i, k = 0;
    for (i = 0; i < n; i++)
        if (all[i].a < all[i].b) all[k++] = all[i];
    return k;
}

static int shares_vertex(const Mesh *m, uint32_t s, uint32_t t) {
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            if (m->tris[3 * s + (size_t)i] == m->tris[3 * t + (size_t)j]) return 1;
    return 0;
}

static void test_self_collide(void) {
    DvhPairs *pairs = dvh_pairs_new();
    DvhQueryStats stats;
    DvhQueryOptions q = dvh_query_options_default();
    uint32_t threads;

    /* A soup shares no vertex: its self-collision is every intersecting pair a < b. */
    {
        Mesh m = mesh_soup(300, 0, 12);
        DvhMesh *d = create(&m, NULL);
        DvhPair *all, *before;
        size_t n, modes;
        n = brute_force(&m, NULL, &m, NULL, &all);
        n = upper_pairs(all, n);
        CHECK(n > 10);
        for (threads = 1; threads <= 2; threads++) {
            q = dvh_query_options_default();
            q.threads = threads;
            CHECK_STATUS(dvh_self_collide(d, &q, pairs, &stats), DVH_STATUS_OK, NULL);
            CHECK(same_pairs(pairs, all, n) && stats.pairs == n);
            CHECK(dvh_pairs_kind(pairs) == DVH_PAIR_KIND_TRIANGLES);
        }
        CHECK_STATUS(dvh_self_collide(d, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
        CHECK(same_pairs(pairs, all, n));
        q = dvh_query_options_default();
        q.mode = DVH_QUERY_MODE_FIRST_HIT;
        CHECK_STATUS(dvh_self_collide(d, &q, pairs, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(pairs) == 1 && contains(all, n, dvh_pairs_data(pairs)[0]));
        q = dvh_query_options_default();
        q.max_pairs = 3;
        CHECK_STATUS(dvh_self_collide(d, &q, pairs, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(pairs) == 3 && stats.truncated);
        /* The coarse modes: node pairs (lower, higher) whose triangles hold every pair, in
         * either order. */
        for (modes = 0; modes < 3; modes++) {
            size_t k;
            q = dvh_query_options_default();
            q.mode = modes == 0 ? DVH_QUERY_MODE_LEAVES : modes == 1 ? DVH_QUERY_MODE_DEPTH : DVH_QUERY_MODE_BUDGET;
            q.max_depth = 2;
            q.budget = 50;
            CHECK_STATUS(dvh_self_collide(d, &q, pairs, &stats), DVH_STATUS_OK, NULL);
            CHECK(dvh_pairs_kind(pairs) == DVH_PAIR_KIND_NODES);
            for (k = 0; k < dvh_pairs_len(pairs); k++) CHECK(dvh_pairs_data(pairs)[k].a <= dvh_pairs_data(pairs)[k].b);
            CHECK(covers_in(d, d, pairs, all, n, 1));
        }
        /* Errors leave the result as it was. */
        CHECK_STATUS(dvh_self_collide(d, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
        before = malloc(n * sizeof *before);
        memcpy(before, dvh_pairs_data(pairs), n * sizeof *before);
        CHECK_STATUS(dvh_self_collide(NULL, NULL, pairs, &stats), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
        CHECK_STATUS(dvh_self_collide(d, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT, "`pairs_out`");
        q = dvh_query_options_default();
        q.mode = DVH_QUERY_MODE_BUDGET;
        q.budget = 0;
        CHECK_STATUS(dvh_self_collide(d, &q, pairs, &stats), DVH_STATUS_INVALID_ARGUMENT, "options->budget = 0");
        q.mode = 9;
        CHECK_STATUS(dvh_self_collide(d, &q, pairs, &stats), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 9");
        CHECK(same_pairs(pairs, before, n));
        free(before);
        free(all);
        dvh_mesh_free(d);
        mesh_free(&m);
    }
    /* An intact surface reports nothing, however it bends. */
    {
        Mesh m = mesh_terrain(12, 0, 0, ridge);
        DvhMesh *d = create(&m, NULL);
        CHECK_STATUS(dvh_self_collide(d, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(pairs) == 0 && stats.pairs == 0);
        dvh_mesh_free(d);
        mesh_free(&m);
    }
    /* Triangles sharing vertices count where they meet beyond them: a triangle folded flat onto
     * its neighbour across their shared edge, and one through the other's corner. */
    {
        static const double pos[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 1, 1, 0, 1, 1, -1, 1, 1, 1, 5, 5, 5, 6, 5, 5, 5, 6, 5};
        static const uint32_t tris[] = {0, 1, 2, 0, 1, 3, 0, 4, 5, 6, 7, 8};
        static const DvhPair expected[] = {{0, 1}, {0, 2}, {1, 2}};
        DvhMesh *d = NULL;
        CHECK_STATUS(dvh_mesh_create(pos, 9, tris, 4, NULL, &d), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_self_collide(d, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
        CHECK(same_pairs(pairs, expected, 3));
        dvh_mesh_free(d);
    }
    dvh_pairs_free(pairs);
}

static void test_proximity(void) {
    Mesh ma = mesh_terrain(6, 0, 0, flat), mb = mesh_terrain(6, 2, 1, wave);
    DvhMesh *a = create(&ma, NULL), *b = create(&mb, NULL);
    DvhPairs *pairs = dvh_pairs_new(), *hits = dvh_pairs_new();
    DvhQueryStats stats, sentinel;
    DvhQueryOptions q = dvh_query_options_default();
    IPose up = ipose_make(0, 0, 0, 1), turned = ipose_make(1, 10, 0, 0); /* x and z reversed */
    DvhPose pup = ipose_to_dvh(&up), pturned = ipose_to_dvh(&turned);
    DvhPair *before;
    size_t n, k, all_apart = 0, i, j;
    uint32_t threads;
    static const double bad[] = {-1.0, NAN, INFINITY, -INFINITY};

    /* Distance 0 is dvh_collide, with and without poses. */
    for (threads = 1; threads <= 2; threads++) {
        DvhPair *expected;
        q.threads = threads;
        n = brute_force(&ma, NULL, &mb, &turned, &expected);
        CHECK(n > 0);
        CHECK_STATUS(dvh_proximity(a, NULL, b, &pturned, 0.0, &q, pairs, &stats), DVH_STATUS_OK, NULL);
        CHECK(same_pairs(pairs, expected, n) && stats.pairs == n);
        CHECK_STATUS(dvh_collide(a, NULL, b, &pturned, &q, hits, NULL), DVH_STATUS_OK, NULL);
        CHECK(same_pairs(hits, expected, n));
        free(expected);
    }
    /* A flat sheet and its copy lifted by exactly 1: every facing pair is 1 apart, none closer. */
    CHECK_STATUS(dvh_proximity(a, NULL, a, &pup, 1.0, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
    n = dvh_pairs_len(pairs);
    CHECK(n >= ma.triangle_count);
    for (k = 0; k < ma.triangle_count; k++) {
        DvhPair same;
        same.a = same.b = (uint32_t)k;
        CHECK(contains(dvh_pairs_data(pairs), n, same));
    }
    CHECK_STATUS(dvh_proximity(a, &pup, a, NULL, nextafter(1.0, 0.0), NULL, pairs, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == 0);
    /* Far enough, every pair; the limit and the coarse modes. */
    CHECK_STATUS(dvh_proximity(a, NULL, a, &pup, 100.0, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == ma.triangle_count * ma.triangle_count);
    q = dvh_query_options_default();
    q.max_pairs = 5;
    CHECK_STATUS(dvh_proximity(a, NULL, a, &pup, 100.0, &q, pairs, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == 5 && stats.truncated);
    q = dvh_query_options_default();
    q.mode = DVH_QUERY_MODE_LEAVES;
    CHECK_STATUS(dvh_proximity(a, NULL, a, &pup, 1.0, &q, pairs, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_kind(pairs) == DVH_PAIR_KIND_NODES && dvh_pairs_len(pairs) > 0);

    /* Self-proximity: pairs a < b sharing no vertex; none at distance 0 on an intact sheet, all
     * of them far enough, and growing with the distance. */
    for (i = 0; i < ma.triangle_count; i++)
        for (j = i + 1; j < ma.triangle_count; j++)
            all_apart += !shares_vertex(&ma, (uint32_t)i, (uint32_t)j);
    CHECK_STATUS(dvh_self_proximity(a, 0.0, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == 0);
    CHECK_STATUS(dvh_self_proximity(a, 100.0, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == all_apart && stats.pairs == all_apart);
    {
        size_t last = 0;
        double d;
        for (d = 0.5; d <= 4.0; d *= 2) {
            const DvhPair *p;
            CHECK_STATUS(dvh_self_proximity(a, d, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
            p = dvh_pairs_data(pairs);
            CHECK(dvh_pairs_len(pairs) >= last);
            last = dvh_pairs_len(pairs);
            for (k = 0; k < last; k++) CHECK(p[k].a < p[k].b && !shares_vertex(&ma, p[k].a, p[k].b));
        }
        /* Unit cells: triangles one cell apart are exactly 1 from each other. */
        CHECK_STATUS(dvh_self_proximity(a, 1.0, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
        last = dvh_pairs_len(pairs);
        CHECK_STATUS(dvh_self_proximity(a, nextafter(1.0, 0.0), NULL, pairs, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(pairs) < last);
    }

    /* Errors leave everything as it was. */
    CHECK_STATUS(dvh_self_proximity(a, 1.0, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
    n = dvh_pairs_len(pairs);
    before = malloc(n * sizeof *before);
    memcpy(before, dvh_pairs_data(pairs), n * sizeof *before);
    memset(&sentinel, 0xab, sizeof sentinel);
    stats = sentinel;
    for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        CHECK_STATUS(dvh_proximity(a, NULL, b, NULL, bad[k], NULL, pairs, &stats), DVH_STATUS_INVALID_ARGUMENT, "distance");
        CHECK_STATUS(dvh_self_proximity(a, bad[k], NULL, pairs, &stats), DVH_STATUS_INVALID_ARGUMENT, "distance");
    }
    CHECK_STATUS(dvh_proximity(NULL, NULL, b, NULL, 1.0, NULL, pairs, &stats), DVH_STATUS_NULL_ARGUMENT, "`a`");
    CHECK_STATUS(dvh_proximity(a, NULL, NULL, NULL, 1.0, NULL, pairs, &stats), DVH_STATUS_NULL_ARGUMENT, "`b`");
    CHECK_STATUS(dvh_proximity(a, NULL, b, NULL, 1.0, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT, "`pairs_out`");
    CHECK_STATUS(dvh_self_proximity(NULL, 1.0, NULL, pairs, &stats), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
    CHECK_STATUS(dvh_self_proximity(a, 1.0, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT, "`pairs_out`");
    {
        DvhPose nan_pose = pup;
        nan_pose.translation[1] = NAN;
        CHECK_STATUS(dvh_proximity(a, &nan_pose, b, NULL, 1.0, NULL, pairs, &stats), DVH_STATUS_NON_FINITE_COORDINATE, "pose_a");
    }
    q = dvh_query_options_default();
    q.mode = DVH_QUERY_MODE_BUDGET;
    CHECK_STATUS(dvh_self_proximity(a, 1.0, &q, pairs, &stats), DVH_STATUS_INVALID_ARGUMENT, "options->budget = 0");
    CHECK(memcmp(&stats, &sentinel, sizeof stats) == 0);
    CHECK(same_pairs(pairs, before, n));

    free(before);
    dvh_pairs_free(pairs);
    dvh_pairs_free(hits);
    dvh_mesh_free(a);
    dvh_mesh_free(b);
    mesh_free(&ma);
    mesh_free(&mb);
}

/* ---- continuous collision ---- */

static DvhImpact impact(DvhImpactKind kind, uint32_t a0, uint32_t a1, uint32_t b0, uint32_t b1, double toi) {
    DvhImpact i;
    memset(&i, 0, sizeof i);
    i.kind = kind;
    i.a0 = a0;
    i.a1 = a1;
    i.b0 = b0;
    i.b1 = b1;
    i.toi = toi;
    return i;
}

/* Field by field: DvhImpact has padding before `toi`. */
static int same_impact(const DvhImpact *x, const DvhImpact *y) {
    return x->kind == y->kind && x->a0 == y->a0 && x->a1 == y->a1 && x->b0 == y->b0 && x->b1 == y->b1 && x->toi == y->toi;
}

/* The results' order: (kind, a0, a1, b0, b1). */
static int impact_key_cmp(const DvhImpact *x, const DvhImpact *y) {
    const uint32_t kx[5] = {x->kind, x->a0, x->a1, x->b0, x->b1}, ky[5] = {y->kind, y->a0, y->a1, y->b0, y->b1};
    int k;
    for (k = 0; k < 5; k++)
        if (kx[k] != ky[k]) return kx[k] < ky[k] ? -1 : 1;
    return 0;
}

static int same_impacts(const DvhImpacts *r, const DvhImpact *expected, size_t n) {
    size_t len = dvh_impacts_len(r), i;
    const DvhImpact *data = dvh_impacts_data(r);
    if (len != n) return 0;
    if (n == 0) return data == NULL;
    for (i = 0; i < n; i++)
        if (!same_impact(&data[i], &expected[i])) return 0;
    return 1;
}

static int contains_impact(const DvhImpact *v, size_t n, const DvhImpact *x) {
    size_t i;
    for (i = 0; i < n; i++)
        if (same_impact(&v[i], x)) return 1;
    return 0;
}

/* The impact a query with `earliest_only` reports: the earliest, the first in the results'
 * order of several at that time. */
static size_t earliest_index(const DvhImpact *v, size_t n) {
    size_t i, best = 0;
    for (i = 1; i < n; i++)
        if (v[i].toi < v[best].toi) best = i;
    return best;
}

static void check_ccd_stats(const DvhCcdStats *s, const DvhImpact *v, size_t n) {
    double earliest = INFINITY;
    size_t i;
    for (i = 0; i < n; i++)
        if (v[i].toi < earliest) earliest = v[i].toi;
    CHECK(s->impacts == n && !s->truncated && s->earliest_toi == earliest);
    CHECK(s->primitive_tests >= n);
}

/* A mesh over one step: every vertex from `start` to `end` in a straight line. */
typedef struct Motion {
    size_t vertex_count, triangle_count;
    const uint32_t *tris;
    const double *start, *end; /* 3 per vertex each */
} Motion;

static int edge_cmp(const void *x, const void *y) {
    const uint32_t *a = x, *b = y;
    if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
    if (a[1] != b[1]) return a[1] < b[1] ? -1 : 1;
    return 0;
}

/* The edges of a mesh, as the continuous queries define them: distinct pairs (lower, higher) of
 * distinct vertices joined by a triangle side, sorted; two per edge in *out (malloc'd). */
static size_t motion_edges(const Motion *m, uint32_t **out) {
    uint32_t *e = malloc((m->triangle_count * 6 + 2) * sizeof *e);
    size_t n = 0, u = 0, t, k;
    if (e == NULL) exit(2);
    for (t = 0; t < m->triangle_count; t++)
        for (k = 0; k < 3; k++) {
            uint32_t p = m->tris[3 * t + k], q = m->tris[3 * t + (k + 1) % 3];
            if (p == q) continue;
            e[2 * n] = p < q ? p : q;
            e[2 * n + 1] = p < q ? q : p;
            n++;
        }
    qsort(e, n, 2 * sizeof *e, edge_cmp);
    for (k = 0; k < n; k++)
        if (u == 0 || edge_cmp(&e[2 * k], &e[2 * (u - 1)]) != 0) {
            e[2 * u] = e[2 * k];
            e[2 * u + 1] = e[2 * k + 1];
            u++;
        }
    *out = e;
    return u;
}

typedef struct ImpactList {
    DvhImpact *v;
    size_t n, cap;
} ImpactList;

typedef DvhStatus (*CcdTest)(const double *, const double *, const DvhCcdOptions *, bool *, double *);

/* Tests the four moving points `v[k]` of `m[k]` with `test`; appends `key` with the time when they
 * meet. */
static void test_four(CcdTest test, const Motion **m, const uint32_t *v, const DvhCcdOptions *o, ImpactList *l, DvhImpact key) {
    double s[12], e[12], toi = -1.0;
    bool hit = false;
    int k;
    for (k = 0; k < 4; k++) {
        memcpy(&s[3 * k], &m[k]->start[3 * (size_t)v[k]], 3 * sizeof(double));
        memcpy(&e[3 * k], &m[k]->end[3 * (size_t)v[k]], 3 * sizeof(double));
    }
    CHECK(test(s, e, o, &hit, &toi) == DVH_STATUS_OK);
    if (!hit) return;
    CHECK(toi >= 0.0 && toi <= 1.0);
    if (l->n == l->cap) {
        DvhImpact *w;
        l->cap = l->cap == 0 ? 64 : 2 * l->cap;
        w = realloc(l->v, l->cap * sizeof *w);
        if (w == NULL) exit(2);
        l->v = w;
    }
    key.toi = toi;
    l->v[l->n++] = key;
}

static unsigned char *vertices_used(const Motion *m) {
    unsigned char *used = calloc(m->vertex_count + 1, 1);
    size_t i;
    if (used == NULL) exit(2);
    for (i = 0; i < m->triangle_count * 3; i++) used[m->tris[i]] = 1;
    return used;
}

/* The oracle of the continuous queries, from the primitive tests alone: every impact of `a`
 * against `b` (of `a` with itself when `b` is NULL), in the results' order; the count is
 * returned, the impacts go to *out (malloc'd). */
static size_t ccd_brute_force(const Motion *a, const Motion *b, DvhCcdMode mode, DvhImpact **out) {
    const int self = b == NULL;
    const Motion *mb = self ? a : b;
    DvhCcdOptions o = dvh_ccd_options_default();
    ImpactList l = {NULL, 0, 0};
    unsigned char *used_a = vertices_used(a), *used_b = vertices_used(mb);
    uint32_t *ea, *eb;
    size_t na = motion_edges(a, &ea), nb = motion_edges(mb, &eb), i, j;
    o.mode = mode;
    /* A vertex of a against a triangle of b (in a self query, one without the vertex). */
    for (i = 0; i < a->vertex_count; i++) {
        if (!used_a[i]) continue;
        for (j = 0; j < mb->triangle_count; j++) {
            const uint32_t *t = &mb->tris[3 * j];
            const Motion *m[4];
            uint32_t v[4];
            if (self && (t[0] == i || t[1] == i || t[2] == i)) continue;
            m[0] = a; m[1] = m[2] = m[3] = mb;
            v[0] = (uint32_t)i; v[1] = t[0]; v[2] = t[1]; v[3] = t[2];
            test_four(dvh_ccd_vertex_face, m, v, &o, &l, impact(DVH_IMPACT_KIND_VERTEX_FACE, (uint32_t)i, 0, (uint32_t)j, 0, 0.0));
        }
    }
    /* A triangle of a against a vertex of b. */
    if (!self)
        for (i = 0; i < a->triangle_count; i++) {
            const uint32_t *t = &a->tris[3 * i];
            for (j = 0; j < mb->vertex_count; j++) {
                const Motion *m[4];
                uint32_t v[4];
                if (!used_b[j]) continue;
                m[0] = mb; m[1] = m[2] = m[3] = a;
                v[0] = (uint32_t)j; v[1] = t[0]; v[2] = t[1]; v[3] = t[2];
                test_four(dvh_ccd_vertex_face, m, v, &o, &l, impact(DVH_IMPACT_KIND_FACE_VERTEX, (uint32_t)i, 0, (uint32_t)j, 0, 0.0));
            }
        }
    /* An edge of a against an edge of b (in a self query, a later one sharing no vertex). */
    for (i = 0; i < na; i++)
        for (j = self ? i + 1 : 0; j < nb; j++) {
            const uint32_t *p = &ea[2 * i], *q = &eb[2 * j];
            const Motion *m[4];
            uint32_t v[4];
            if (self && (p[0] == q[0] || p[0] == q[1] || p[1] == q[0] || p[1] == q[1])) continue;
            m[0] = m[1] = a; m[2] = m[3] = mb;
            v[0] = p[0]; v[1] = p[1]; v[2] = q[0]; v[3] = q[1];
            test_four(dvh_ccd_edge_edge, m, v, &o, &l, impact(DVH_IMPACT_KIND_EDGE_EDGE, p[0], p[1], q[0], q[1], 0.0));
        }
    free(used_a);
    free(used_b);
    free(ea);
    free(eb);
    if (l.v == NULL) {
        l.v = malloc(sizeof *l.v);
        if (l.v == NULL) exit(2);
    }
    *out = l.v;
    return l.n;
}

/* Writes point k of a primitive (12 doubles: four points). */
static void set_point(double *v, int k, double x, double y, double z) {
    v[3 * k] = x;
    v[3 * k + 1] = y;
    v[3 * k + 2] = z;
}

static void test_ccd_primitives(void) {
    DvhCcdOptions o = dvh_ccd_options_default(), odd;
    double s[12], e[12], toi;
    bool hit;
    char *raw = malloc(12 * sizeof(double) + 8);

    /* The defaults: exact, every core, no limit, every impact (all fields zero). */
    CHECK(o.mode == DVH_CCD_MODE_EXACT && o.threads == 0 && o.max_impacts == 0 && !o.earliest_only);

    /* A point falling through a floor triangle: z = 1 - 4t meets z = 0 at t = 1/4 exactly. */
    set_point(s, 0, 0.25, 0.25, 1.0);
    set_point(e, 0, 0.25, 0.25, -3.0);
    set_point(s, 1, 0, 0, 0); set_point(s, 2, 1, 0, 0); set_point(s, 3, 0, 1, 0);
    set_point(e, 1, 0, 0, 0); set_point(e, 2, 1, 0, 0); set_point(e, 3, 0, 1, 0);
    hit = false;
    toi = -1.0;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.25);
    hit = false;
    toi = -1.0;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, &o, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.25);
    /* No time wanted. */
    hit = false;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, NULL, &hit, NULL), DVH_STATUS_OK, NULL);
    CHECK(hit);
    /* Conservative: a hit, never later. */
    o.mode = DVH_CCD_MODE_CONSERVATIVE;
    hit = false;
    toi = -1.0;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, &o, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi >= 0.0 && toi <= 0.25);
    /* The other fields are ignored. */
    odd = dvh_ccd_options_default();
    odd.threads = 3;
    odd.max_impacts = 1;
    odd.earliest_only = true;
    hit = false;
    toi = -1.0;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, &odd, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.25);
    /* Rising instead: z = -3 + 4t meets the floor at t = 3/4. */
    hit = false;
    CHECK_STATUS(dvh_ccd_vertex_face(e, s, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.75);
    /* Closed in time: touching at the end is t = 1, at the start t = 0. */
    e[2] = 0.0;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 1.0);
    CHECK_STATUS(dvh_ccd_vertex_face(e, s, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.0);
    /* And in space: through the corner (1, 0, 0). */
    set_point(s, 0, 1, 0, 1);
    set_point(e, 0, 1, 0, -1);
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.5);
    /* A miss: *hit_out is false, *toi_out untouched. */
    set_point(s, 0, 2, 2, 1);
    set_point(e, 0, 2, 2, -3);
    hit = true;
    toi = 42.0;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(!hit && toi == 42.0);
    o.mode = DVH_CCD_MODE_CONSERVATIVE;
    hit = true;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, &o, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(!hit && toi == 42.0);
    /* A triangle rising through a still point: z = -1 + 4t reaches 1/2 at t = 3/8. */
    set_point(s, 0, 0.25, 0.25, 0.5);
    set_point(e, 0, 0.25, 0.25, 0.5);
    set_point(s, 1, 0, 0, -1); set_point(s, 2, 1, 0, -1); set_point(s, 3, 0, 1, -1);
    set_point(e, 1, 0, 0, 3); set_point(e, 2, 1, 0, 3); set_point(e, 3, 0, 1, 3);
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.375);

    /* Edge-edge: edge a along x at y = 1/2 falls from z = 3/4 to z = -5/4 (z = 3/4 - 2t) across
     * the still edge b along y at x = 1/2, z = 0: they cross at t = 3/8. */
    set_point(s, 0, 0, 0.5, 0.75); set_point(s, 1, 1, 0.5, 0.75);
    set_point(e, 0, 0, 0.5, -1.25); set_point(e, 1, 1, 0.5, -1.25);
    set_point(s, 2, 0.5, 0, 0); set_point(s, 3, 0.5, 1, 0);
    set_point(e, 2, 0.5, 0, 0); set_point(e, 3, 0.5, 1, 0);
    hit = false;
    toi = -1.0;
    CHECK_STATUS(dvh_ccd_edge_edge(s, e, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.375);
    o.mode = DVH_CCD_MODE_EXACT;
    CHECK_STATUS(dvh_ccd_edge_edge(s, e, &o, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.375);
    o.mode = DVH_CCD_MODE_CONSERVATIVE;
    toi = -1.0;
    CHECK_STATUS(dvh_ccd_edge_edge(s, e, &o, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi >= 0.0 && toi <= 0.375);
    /* Edge b shifted beyond edge a's end: a miss. */
    s[6] = e[6] = s[9] = e[9] = 1.5;
    hit = true;
    toi = 42.0;
    CHECK_STATUS(dvh_ccd_edge_edge(s, e, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(!hit && toi == 42.0);
    /* Parallel segments that come to overlap: decided like any others (t = 3/8). */
    set_point(s, 2, 0.5, 0.5, 0); set_point(s, 3, 2, 0.5, 0);
    set_point(e, 2, 0.5, 0.5, 0); set_point(e, 3, 2, 0.5, 0);
    CHECK_STATUS(dvh_ccd_edge_edge(s, e, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.375);

    /* Errors change nothing and name the culprit. */
    set_point(s, 2, 0.5, 0, 0); set_point(s, 3, 0.5, 1, 0);
    set_point(e, 2, 0.5, 0, 0); set_point(e, 3, 0.5, 1, 0);
    hit = false;
    toi = 42.0;
    CHECK_STATUS(dvh_ccd_vertex_face(NULL, e, NULL, &hit, &toi), DVH_STATUS_NULL_ARGUMENT, "argument `start` is NULL");
    CHECK_STATUS(dvh_ccd_vertex_face(s, NULL, NULL, &hit, &toi), DVH_STATUS_NULL_ARGUMENT, "argument `end` is NULL");
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, NULL, NULL, &toi), DVH_STATUS_NULL_ARGUMENT, "argument `hit_out` is NULL");
    CHECK_STATUS(dvh_ccd_edge_edge(NULL, e, NULL, &hit, &toi), DVH_STATUS_NULL_ARGUMENT, "argument `start` is NULL");
    CHECK_STATUS(dvh_ccd_edge_edge(s, NULL, NULL, &hit, &toi), DVH_STATUS_NULL_ARGUMENT, "argument `end` is NULL");
    CHECK_STATUS(dvh_ccd_edge_edge(s, e, NULL, NULL, &toi), DVH_STATUS_NULL_ARGUMENT, "argument `hit_out` is NULL");
    s[4] = NAN;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, NULL, &hit, &toi), DVH_STATUS_NON_FINITE_COORDINATE,
                 "start[4] is NaN, not a finite number");
    CHECK_STATUS(dvh_ccd_edge_edge(s, e, NULL, &hit, &toi), DVH_STATUS_NON_FINITE_COORDINATE, "start[4] is NaN");
    s[4] = 0.5;
    e[11] = INFINITY;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, NULL, &hit, &toi), DVH_STATUS_NON_FINITE_COORDINATE, "end[11] is inf");
    e[11] = -INFINITY;
    CHECK_STATUS(dvh_ccd_edge_edge(s, e, NULL, &hit, &toi), DVH_STATUS_NON_FINITE_COORDINATE, "end[11] is -inf");
    e[11] = 0.0;
    o = dvh_ccd_options_default();
    o.mode = 7;
    CHECK_STATUS(dvh_ccd_vertex_face(s, e, &o, &hit, &toi), DVH_STATUS_INVALID_ARGUMENT,
                 "options->mode = 7 is not a DVH_CCD_MODE_* value (0 or 1)");
    CHECK_STATUS(dvh_ccd_edge_edge(s, e, &o, &hit, &toi), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 7");
    memcpy(raw + 1, s, sizeof s);
    CHECK_STATUS(dvh_ccd_vertex_face((const double *)(const void *)(raw + 1), e, NULL, &hit, &toi), DVH_STATUS_INVALID_ARGUMENT,
                 "argument `start` is not aligned");
    CHECK_STATUS(dvh_ccd_edge_edge(s, (const double *)(const void *)(raw + 1), NULL, &hit, &toi), DVH_STATUS_INVALID_ARGUMENT,
                 "argument `end` is not aligned");
    CHECK(!hit && toi == 42.0);
    /* The inputs are fine again: a hit. */
    CHECK_STATUS(dvh_ccd_edge_edge(s, e, NULL, &hit, &toi), DVH_STATUS_OK, NULL);
    CHECK(hit && toi == 0.375);
    free(raw);
}

/* Two triangles: a still floor A in z = 0 and a tilted triangle B falling by 4 through it. B's
 * height over (x, y) at the start is 2 + x/2 + y/4, between 1/4 and 11/4 at its corners, so
 * neither touches the other at the start or at the end, and each primitive pair meets when B's
 * height over their meeting point has fallen to 0: at a quarter of that height.
 *   B's vertex 0 over (1, 1) through A's triangle: t = 2.75 / 4 = 0.6875;
 *   B's triangle over A's vertex 0 at (0, 0): t = 2 / 4 = 0.5;
 *   B's edge (0, 1) across A's edge (0, 2) at (0, 1/2): t = 2.125 / 4 = 0.53125;
 *   B's edge (0, 2) across A's edge (0, 1) at (1, 0): t = 2.5 / 4 = 0.625. */
static const double floor_pos[] = {0, 0, 0, 4, 0, 0, 0, 4, 0};
static const double falling_start[] = {1, 1, 2.75, -3, -1, 0.25, 1, -3, 1.75};
static const double falling_end[] = {1, 1, -1.25, -3, -1, -3.75, 1, -3, -2.25};
static const uint32_t one_triangle[] = {0, 1, 2};

static void test_continuous_collide(void) {
    const DvhImpact expected[4] = {
        {DVH_IMPACT_KIND_VERTEX_FACE, 0, 0, 0, 0, 0.6875},
        {DVH_IMPACT_KIND_FACE_VERTEX, 0, 0, 0, 0, 0.5},
        {DVH_IMPACT_KIND_EDGE_EDGE, 0, 1, 0, 2, 0.53125},
        {DVH_IMPACT_KIND_EDGE_EDGE, 0, 2, 0, 1, 0.625},
    };
    const DvhImpact swapped[4] = {
        {DVH_IMPACT_KIND_VERTEX_FACE, 0, 0, 0, 0, 0.5},
        {DVH_IMPACT_KIND_FACE_VERTEX, 0, 0, 0, 0, 0.6875},
        {DVH_IMPACT_KIND_EDGE_EDGE, 0, 1, 0, 2, 0.625},
        {DVH_IMPACT_KIND_EDGE_EDGE, 0, 2, 0, 1, 0.53125},
    };
    DvhMesh *a = NULL, *b = NULL;
    DvhImpacts *impacts = dvh_impacts_new(), *other = dvh_impacts_new();
    DvhPairs *pairs = dvh_pairs_new();
    DvhCcdOptions o = dvh_ccd_options_default();
    DvhCcdStats stats, sentinel;
    Motion ma, mb;
    DvhImpact *oracle;
    size_t n, k;
    uint32_t threads;
    double bad[9], shifted[9];
    char *raw = malloc(sizeof bad + 8);

    CHECK(impacts != NULL && other != NULL);
    CHECK(dvh_impacts_len(impacts) == 0 && dvh_impacts_data(impacts) == NULL);
    CHECK(dvh_impacts_len(NULL) == 0 && dvh_impacts_data(NULL) == NULL);
    CHECK_STATUS(dvh_mesh_create(floor_pos, 3, one_triangle, 1, NULL, &a), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_create(falling_start, 3, one_triangle, 1, NULL, &b), DVH_STATUS_OK, NULL);

    /* Apart at the start; still meshes meet nowhere in time either. */
    CHECK_STATUS(dvh_collide(b, NULL, a, NULL, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == 0);
    memset(&stats, 0xab, sizeof stats);
    CHECK_STATUS(dvh_continuous_collide(b, a, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_impacts_len(impacts) == 0 && dvh_impacts_data(impacts) == NULL);
    CHECK(stats.impacts == 0 && !stats.truncated && isinf(stats.earliest_toi) && stats.earliest_toi > 0);

    /* B falls: apart at the end too, but it passed through A. */
    CHECK_STATUS(dvh_mesh_refit_motion(b, falling_start, falling_end, 3), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_validate(b), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_collide(b, NULL, a, NULL, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == 0);
    CHECK_STATUS(dvh_continuous_collide(b, a, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_impacts(impacts, expected, 4));
    check_ccd_stats(&stats, expected, 4);
    CHECK(stats.earliest_toi == 0.5 && stats.bv_tests >= 1);
    CHECK_STATUS(dvh_continuous_collide(a, b, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_impacts(impacts, swapped, 4));
    check_ccd_stats(&stats, swapped, 4);
    /* The oracle agrees, both ways. */
    ma.vertex_count = 3; ma.triangle_count = 1; ma.tris = one_triangle; ma.start = floor_pos; ma.end = floor_pos;
    mb.vertex_count = 3; mb.triangle_count = 1; mb.tris = one_triangle; mb.start = falling_start; mb.end = falling_end;
    n = ccd_brute_force(&mb, &ma, DVH_CCD_MODE_EXACT, &oracle);
    CHECK(n == 4);
    for (k = 0; k < n && k < 4; k++) CHECK(same_impact(&oracle[k], &expected[k]));
    free(oracle);
    n = ccd_brute_force(&ma, &mb, DVH_CCD_MODE_EXACT, &oracle);
    CHECK(n == 4);
    for (k = 0; k < n && k < 4; k++) CHECK(same_impact(&oracle[k], &swapped[k]));
    free(oracle);
    /* Every thread count, one answer; the options explicit. */
    for (threads = 0; threads < 3; threads++) {
        o = dvh_ccd_options_default();
        o.threads = threads;
        CHECK_STATUS(dvh_continuous_collide(b, a, &o, impacts, &stats), DVH_STATUS_OK, NULL);
        CHECK(same_impacts(impacts, expected, 4));
        check_ccd_stats(&stats, expected, 4);
    }
    /* The earliest alone; a limit. */
    o = dvh_ccd_options_default();
    o.earliest_only = true;
    CHECK_STATUS(dvh_continuous_collide(b, a, &o, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_impacts(impacts, &expected[1], 1));
    CHECK(stats.impacts == 1 && stats.earliest_toi == 0.5 && !stats.truncated);
    CHECK_STATUS(dvh_continuous_collide(a, b, &o, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_impacts(impacts, &swapped[0], 1));
    o = dvh_ccd_options_default();
    o.max_impacts = 1;
    CHECK_STATUS(dvh_continuous_collide(b, a, &o, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_impacts_len(impacts) == 1 && stats.truncated && stats.impacts == 1);
    CHECK(dvh_impacts_len(impacts) == 1 && contains_impact(expected, 4, &dvh_impacts_data(impacts)[0]));
    CHECK(stats.earliest_toi == dvh_impacts_data(impacts)[0].toi);
    o.max_impacts = 5;
    CHECK_STATUS(dvh_continuous_collide(b, a, &o, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_impacts(impacts, expected, 4) && !stats.truncated);
    /* Conservative: every impact, none later. */
    o = dvh_ccd_options_default();
    o.mode = DVH_CCD_MODE_CONSERVATIVE;
    CHECK_STATUS(dvh_continuous_collide(b, a, &o, impacts, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_impacts_len(impacts) >= 4);
    for (k = 0; k < 4; k++) {
        size_t i, found = 0;
        for (i = 0; i < dvh_impacts_len(impacts); i++) {
            const DvhImpact *c = &dvh_impacts_data(impacts)[i];
            if (impact_key_cmp(c, &expected[k]) == 0) found = 1 + (c->toi <= expected[k].toi);
        }
        CHECK(found == 2);
    }

    /* Failed motions leave the mesh as it was: the same impacts afterwards, and a stationary
     * refit still stops it. */
    CHECK_STATUS(dvh_continuous_collide(b, a, NULL, impacts, NULL), DVH_STATUS_OK, NULL);
    memcpy(bad, falling_end, sizeof bad);
    bad[3 * 1 + 1] = NAN;
    for (k = 0; k < 9; k++) shifted[k] = falling_start[k] + 0.5; /* a valid start, paired with bad ends */
    CHECK_STATUS(dvh_mesh_refit_motion(b, falling_start, falling_end, 2), DVH_STATUS_INVALID_ARGUMENT,
                 "vertex_count = 2, but the mesh has 3 vertices");
    CHECK_STATUS(dvh_mesh_refit_motion(b, shifted, bad, 3), DVH_STATUS_NON_FINITE_COORDINATE,
                 "end positions: vertex 1: coordinate y is NaN, not a finite number");
    bad[3 * 1 + 1] = falling_end[3 * 1 + 1];
    bad[3 * 2 + 2] = INFINITY;
    CHECK_STATUS(dvh_mesh_refit_motion(b, bad, shifted, 3), DVH_STATUS_NON_FINITE_COORDINATE,
                 "start positions: vertex 2: coordinate z is inf");
    CHECK_STATUS(dvh_mesh_refit_motion(b, shifted, bad, 3), DVH_STATUS_NON_FINITE_COORDINATE, "end positions: vertex 2");
    CHECK_STATUS(dvh_mesh_refit_motion(NULL, falling_start, falling_end, 3), DVH_STATUS_NULL_ARGUMENT, "argument `mesh` is NULL");
    CHECK_STATUS(dvh_mesh_refit_motion(b, NULL, falling_end, 3), DVH_STATUS_NULL_ARGUMENT, "argument `start` is NULL");
    CHECK_STATUS(dvh_mesh_refit_motion(b, shifted, NULL, 3), DVH_STATUS_NULL_ARGUMENT, "argument `end` is NULL");
    memcpy(raw + 1, falling_end, sizeof bad);
    CHECK_STATUS(dvh_mesh_refit_motion(b, shifted, (const double *)(const void *)(raw + 1), 3), DVH_STATUS_INVALID_ARGUMENT,
                 "argument `end` is not aligned");
    CHECK_STATUS(dvh_mesh_validate(b), DVH_STATUS_OK, NULL);
    CHECK(dvh_mesh_vertex_count(b) == 3);
    CHECK_STATUS(dvh_continuous_collide(b, a, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_impacts(impacts, expected, 4));
    check_ccd_stats(&stats, expected, 4);
    CHECK_STATUS(dvh_collide(b, NULL, a, NULL, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == 0);

    /* Failed queries leave the result and the counters as they were. */
    memset(&sentinel, 0xab, sizeof sentinel);
    stats = sentinel;
    o = dvh_ccd_options_default();
    o.mode = 7;
    CHECK_STATUS(dvh_continuous_collide(b, a, &o, impacts, &stats), DVH_STATUS_INVALID_ARGUMENT,
                 "options->mode = 7 is not a DVH_CCD_MODE_* value (0 or 1)");
    CHECK_STATUS(dvh_self_continuous_collide(b, &o, impacts, &stats), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 7");
    CHECK_STATUS(dvh_continuous_collide(NULL, a, NULL, impacts, &stats), DVH_STATUS_NULL_ARGUMENT, "argument `a` is NULL");
    CHECK_STATUS(dvh_continuous_collide(b, NULL, NULL, impacts, &stats), DVH_STATUS_NULL_ARGUMENT, "argument `b` is NULL");
    CHECK_STATUS(dvh_continuous_collide(b, a, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT, "argument `impacts_out` is NULL");
    CHECK_STATUS(dvh_self_continuous_collide(NULL, NULL, impacts, &stats), DVH_STATUS_NULL_ARGUMENT, "argument `mesh` is NULL");
    CHECK_STATUS(dvh_self_continuous_collide(b, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT, "argument `impacts_out` is NULL");
    /* Pointers that are not live handles of the right kind: memory from elsewhere, a mesh
     * where a buffer belongs. */
    {
        static uint64_t elsewhere[1024];
        CHECK_STATUS(dvh_continuous_collide((const DvhMesh *)(const void *)elsewhere, a, NULL, impacts, &stats),
                     DVH_STATUS_INVALID_ARGUMENT, "DvhMesh `a` is not a live handle");
        CHECK_STATUS(dvh_self_continuous_collide((const DvhMesh *)(const void *)elsewhere, NULL, impacts, &stats),
                     DVH_STATUS_INVALID_ARGUMENT, "DvhMesh `mesh` is not a live handle");
        CHECK_STATUS(dvh_continuous_collide(b, a, NULL, (DvhImpacts *)(void *)elsewhere, &stats), DVH_STATUS_INVALID_ARGUMENT,
                     "DvhImpacts `impacts_out` is not a live handle");
        CHECK_STATUS(dvh_continuous_collide(b, a, NULL, (DvhImpacts *)(void *)a, &stats), DVH_STATUS_INVALID_ARGUMENT,
                     "DvhImpacts `impacts_out` is not a live handle");
        CHECK(dvh_impacts_len((const DvhImpacts *)(const void *)a) == 0);
        CHECK(dvh_impacts_data((const DvhImpacts *)(const void *)a) == NULL);
    }
    CHECK(memcmp(&stats, &sentinel, sizeof stats) == 0);
    CHECK(same_impacts(impacts, expected, 4));
    /* A failed query into one buffer leaves another alone; a query that finds nothing empties
     * its buffer. */
    CHECK_STATUS(dvh_continuous_collide(a, b, NULL, other, NULL), DVH_STATUS_OK, NULL);
    CHECK(same_impacts(other, swapped, 4) && same_impacts(impacts, expected, 4));
    /* A still mesh against itself touches everywhere from t = 0. */
    CHECK_STATUS(dvh_continuous_collide(a, a, NULL, other, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_impacts_len(other) > 0 && stats.earliest_toi == 0.0);

    /* A plain refit makes B stationary again: at its end positions, apart from A. */
    CHECK_STATUS(dvh_mesh_refit(b, falling_end, 3), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_continuous_collide(b, a, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_impacts_len(impacts) == 0 && dvh_impacts_data(impacts) == NULL && stats.impacts == 0);
    CHECK(isinf(stats.earliest_toi));

    /* Reuse: a buffer that held other impacts takes the next query's. */
    CHECK_STATUS(dvh_mesh_refit_motion(b, falling_start, falling_end, 3), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_continuous_collide(b, a, NULL, other, NULL), DVH_STATUS_OK, NULL);
    CHECK(same_impacts(other, expected, 4));

    dvh_impacts_free(other);
    dvh_impacts_free(impacts);
    dvh_impacts_free(NULL);
    dvh_pairs_free(pairs);
    dvh_mesh_free(a);
    dvh_mesh_free(b);
    free(raw);
}

/* Every option on one query against the oracle: the impacts, whatever the thread count; the
 * earliest alone; a limit; the conservative mode's never-missed, never-later impacts. */
static void check_continuous(const DvhMesh *a, const Motion *ma, const DvhMesh *b, const Motion *mb, DvhImpacts *impacts) {
    DvhImpact *expected, *loose;
    size_t n, n_loose, k, i;
    uint32_t threads;
    DvhCcdOptions o;
    DvhCcdStats stats;
#define CCD_QUERY(options) (b != NULL ? dvh_continuous_collide(a, b, (options), impacts, &stats) \
                                      : dvh_self_continuous_collide(a, (options), impacts, &stats))
    n = ccd_brute_force(ma, mb, DVH_CCD_MODE_EXACT, &expected);
    CHECK(n > 3);
    for (threads = 0; threads < 3; threads++) {
        o = dvh_ccd_options_default();
        o.threads = threads;
        CHECK_STATUS(CCD_QUERY(&o), DVH_STATUS_OK, NULL);
        CHECK(same_impacts(impacts, expected, n));
        check_ccd_stats(&stats, expected, n);
        for (k = 1; k < dvh_impacts_len(impacts); k++)
            CHECK(impact_key_cmp(&dvh_impacts_data(impacts)[k - 1], &dvh_impacts_data(impacts)[k]) < 0);
        o.earliest_only = true;
        CHECK_STATUS(CCD_QUERY(&o), DVH_STATUS_OK, NULL);
        CHECK(same_impacts(impacts, &expected[earliest_index(expected, n)], 1));
        CHECK(stats.impacts == 1 && stats.earliest_toi == expected[earliest_index(expected, n)].toi);
        o.earliest_only = false;
        o.max_impacts = 3;
        CHECK_STATUS(CCD_QUERY(&o), DVH_STATUS_OK, NULL);
        CHECK(dvh_impacts_len(impacts) == 3 && stats.truncated && stats.impacts == 3);
        for (k = 0; k < dvh_impacts_len(impacts); k++) CHECK(contains_impact(expected, n, &dvh_impacts_data(impacts)[k]));
    }
    CHECK_STATUS(CCD_QUERY(NULL), DVH_STATUS_OK, NULL);
    CHECK(same_impacts(impacts, expected, n));
    o = dvh_ccd_options_default();
    o.mode = DVH_CCD_MODE_CONSERVATIVE;
    n_loose = ccd_brute_force(ma, mb, DVH_CCD_MODE_CONSERVATIVE, &loose);
    CHECK_STATUS(CCD_QUERY(&o), DVH_STATUS_OK, NULL);
    CHECK(same_impacts(impacts, loose, n_loose));
    for (k = 0; k < n; k++) {
        int found = 0;
        for (i = 0; i < n_loose; i++)
            if (impact_key_cmp(&loose[i], &expected[k]) == 0) found = loose[i].toi <= expected[k].toi;
        CHECK(found);
    }
    for (k = 0; k < dvh_impacts_len(impacts); k++) {
        const DvhImpact *x = &dvh_impacts_data(impacts)[k];
        if (b == NULL) CHECK(x->kind != DVH_IMPACT_KIND_FACE_VERTEX);
        if (x->kind == DVH_IMPACT_KIND_EDGE_EDGE) {
            CHECK(x->a0 < x->a1 && x->b0 < x->b1);
            if (b == NULL) CHECK(x->a0 < x->b0 || (x->a0 == x->b0 && x->a1 < x->b1));
        } else {
            CHECK(x->a1 == 0 && x->b1 == 0);
        }
    }
#undef CCD_QUERY
    free(expected);
    free(loose);
}

/* Deforming terrains: one rising a little, the other falling through it, apart at the start and
 * at the end; against the oracle. */
static void test_continuous_terrains(void) {
    Mesh ta = mesh_terrain(8, 0, 0, wave), tb = mesh_terrain(5, 1, 2, ridge);
    double *a_end = malloc(ta.vertex_count * 3 * sizeof(double));
    double *b_start = malloc(tb.vertex_count * 3 * sizeof(double)), *b_end = malloc(tb.vertex_count * 3 * sizeof(double));
    DvhMesh *a, *b, *b_at_start;
    DvhImpacts *impacts = dvh_impacts_new();
    DvhPairs *pairs = dvh_pairs_new();
    Motion ma, mb;
    size_t i;
    for (i = 0; i < ta.vertex_count * 3; i++) a_end[i] = ta.pos[i] + (i % 3 == 2 ? 0.5 : 0.0);
    for (i = 0; i < tb.vertex_count * 3; i++) {
        double shift = i % 3 == 0 ? 0.5 : i % 3 == 1 ? 0.25 : 0.0;
        b_start[i] = tb.pos[i] + shift + (i % 3 == 2 ? 4.0 : 0.0);
        b_end[i] = tb.pos[i] + shift - (i % 3 == 2 ? 4.0 : 0.0);
    }
    a = create(&ta, NULL);
    b = create(&tb, NULL);
    b_at_start = NULL;
    CHECK_STATUS(dvh_mesh_create(b_start, tb.vertex_count, tb.tris, tb.triangle_count, NULL, &b_at_start), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_collide(a, NULL, b_at_start, NULL, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == 0);
    CHECK_STATUS(dvh_mesh_refit_motion(a, ta.pos, a_end, ta.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_refit_motion(b, b_start, b_end, tb.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_validate(a), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_validate(b), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_collide(a, NULL, b, NULL, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == 0);
    ma.vertex_count = ta.vertex_count; ma.triangle_count = ta.triangle_count; ma.tris = ta.tris; ma.start = ta.pos; ma.end = a_end;
    mb.vertex_count = tb.vertex_count; mb.triangle_count = tb.triangle_count; mb.tris = tb.tris; mb.start = b_start; mb.end = b_end;
    check_continuous(a, &ma, b, &mb, impacts);
    check_continuous(b, &mb, a, &ma, impacts);
    /* A still mesh against a moving one. */
    CHECK_STATUS(dvh_mesh_refit(a, ta.pos, ta.vertex_count), DVH_STATUS_OK, NULL);
    ma.end = ta.pos;
    check_continuous(b, &mb, a, &ma, impacts);
    dvh_impacts_free(impacts);
    dvh_pairs_free(pairs);
    dvh_mesh_free(a);
    dvh_mesh_free(b);
    dvh_mesh_free(b_at_start);
    free(a_end);
    free(b_start);
    free(b_end);
    mesh_free(&ta);
    mesh_free(&tb);
}

static void test_self_continuous_collide(void) {
    DvhImpacts *impacts = dvh_impacts_new();
    DvhPairs *pairs = dvh_pairs_new();
    DvhCcdStats stats;
    /* A hinge: triangle 1 swings about the shared edge (0, 1) through triangle 0, its vertex 3
     * crossing z = 0 at t = 1/2 at (1/2, 2, 0), inside triangle 0. Apart (but for the shared edge)
     * at the start and at the end. */
    {
        static const double start[] = {0, 0, 0, 0, 4, 0, 4, 2, 0, -2, 2, 2};
        static const double end[] = {0, 0, 0, 0, 4, 0, 4, 2, 0, 3, 2, -2};
        static const uint32_t tris[] = {0, 1, 2, 0, 1, 3};
        const DvhImpact expected[1] = {{DVH_IMPACT_KIND_VERTEX_FACE, 3, 0, 0, 0, 0.5}};
        DvhMesh *m = NULL;
        Motion mm;
        DvhImpact *oracle;
        size_t n;
        CHECK_STATUS(dvh_mesh_create(start, 4, tris, 2, NULL, &m), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_self_collide(m, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(pairs) == 0);
        CHECK_STATUS(dvh_self_continuous_collide(m, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_impacts_len(impacts) == 0 && stats.impacts == 0 && isinf(stats.earliest_toi));
        CHECK_STATUS(dvh_mesh_refit_motion(m, start, end, 4), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_self_collide(m, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(pairs) == 0);
        CHECK_STATUS(dvh_self_continuous_collide(m, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
        CHECK(same_impacts(impacts, expected, 1));
        check_ccd_stats(&stats, expected, 1);
        mm.vertex_count = 4; mm.triangle_count = 2; mm.tris = tris; mm.start = start; mm.end = end;
        n = ccd_brute_force(&mm, NULL, DVH_CCD_MODE_EXACT, &oracle);
        CHECK(n == 1 && same_impact(&oracle[0], &expected[0]));
        free(oracle);
        /* A failed motion (the end's vertex count, a NaN end) keeps the motion. */
        {
            double bad[12];
            memcpy(bad, end, sizeof bad);
            bad[3 * 3] = NAN;
            CHECK_STATUS(dvh_mesh_refit_motion(m, start, end, 3), DVH_STATUS_INVALID_ARGUMENT, "vertex_count = 3");
            CHECK_STATUS(dvh_mesh_refit_motion(m, start, bad, 4), DVH_STATUS_NON_FINITE_COORDINATE,
                         "end positions: vertex 3: coordinate x is NaN");
            CHECK_STATUS(dvh_self_continuous_collide(m, NULL, impacts, NULL), DVH_STATUS_OK, NULL);
            CHECK(same_impacts(impacts, expected, 1));
        }
        dvh_mesh_free(m);
    }
    /* A grid folding over: the columns beyond x = 3, a ramp at the start, swing through the
     * still part to end below it, sheared a little. */
    {
        const int n = 6;
        Mesh g = mesh_terrain(n, 0, 0, flat);
        double *start = malloc(g.vertex_count * 3 * sizeof(double)), *end = malloc(g.vertex_count * 3 * sizeof(double));
        DvhMesh *m = NULL, *at_start = NULL;
        Motion mm;
        int i, j;
        memcpy(start, g.pos, g.vertex_count * 3 * sizeof(double));
        memcpy(end, g.pos, g.vertex_count * 3 * sizeof(double));
        for (j = 0; j <= n; j++)
            for (i = 4; i <= n; i++) {
                size_t v = (size_t)(j * (n + 1) + i);
                start[3 * v + 2] = i - 3;
                end[3 * v] = n - i + 0.0625 * j;
                end[3 * v + 2] = -0.125 * (i - 3);
            }
        CHECK_STATUS(dvh_mesh_create(start, g.vertex_count, g.tris, g.triangle_count, NULL, &at_start), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_self_collide(at_start, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(pairs) == 0);
        m = create(&g, NULL);
        CHECK_STATUS(dvh_mesh_refit_motion(m, start, end, g.vertex_count), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_mesh_validate(m), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_self_collide(m, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
        CHECK(dvh_pairs_len(pairs) == 0);
        mm.vertex_count = g.vertex_count; mm.triangle_count = g.triangle_count; mm.tris = g.tris; mm.start = start; mm.end = end;
        check_continuous(m, &mm, NULL, NULL, impacts);
        /* Stationary again: an intact sheet meets nothing. */
        CHECK_STATUS(dvh_mesh_refit(m, g.pos, g.vertex_count), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_self_continuous_collide(m, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_impacts_len(impacts) == 0 && stats.impacts == 0);
        dvh_mesh_free(m);
        dvh_mesh_free(at_start);
        free(start);
        free(end);
        mesh_free(&g);
    }
    dvh_impacts_free(impacts);
    dvh_pairs_free(pairs);
}

/* ---- closest-point stencils ---- */

/* A mesh in world coordinates, integers (a terrain placed by an exact pose). */
typedef struct World {
    size_t vertex_count, triangle_count;
    const uint32_t *tris;
    int64_t *p; /* 3 per vertex */
} World;

static World world_of(const Mesh *m, const IPose *pose) {
    World w;
    size_t v;
    w.vertex_count = m->vertex_count;
    w.triangle_count = m->triangle_count;
    w.tris = m->tris;
    w.p = malloc(m->vertex_count * 3 * sizeof *w.p);
    if (w.p == NULL) exit(2);
    for (v = 0; v < m->vertex_count; v++) {
        if (pose != NULL)
            ipose_apply(pose, &m->ipos[3 * v], &w.p[3 * v]);
        else
            memcpy(&w.p[3 * v], &m->ipos[3 * v], 3 * sizeof(int64_t));
    }
    return w;
}

static void sub3(const int64_t *a, const int64_t *b, int64_t out[3]) {
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

static void cross3(const int64_t a[3], const int64_t b[3], int64_t out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* The best candidate so far: squared distance num / den, exactly, and whether it is <= d^2 =
 * quarter_d2 / 4. Every candidate is the distance of two points of the primitives, and the
 * least of them is the primitives' distance, so "some candidate within" decides exactly. */
typedef struct Gap {
    int within;
    double least; /* the least squared distance, rounded */
} Gap;

static void candidate(Gap *g, int64_t num, int64_t den, int64_t quarter_d2) {
    /* 4 num <= quarter_d2 den; small integer coordinates keep these products in 64 bits. */
    if (4 * num <= quarter_d2 * den) g->within = 1;
    if ((double)num / (double)den < g->least) g->least = (double)num / (double)den;
}

/* Point x against the closed segment [a, b]. */
static void point_segment(Gap *g, const int64_t *x, const int64_t *a, const int64_t *b, int64_t q) {
    int64_t u[3], w[3], c[3], uu, along;
    sub3(b, a, u);
    sub3(x, a, w);
    uu = dot3(u, u);
    along = dot3(w, u);
    if (uu == 0 || along <= 0) {
        candidate(g, dot3(w, w), 1, q);
    } else if (along >= uu) {
        int64_t y[3];
        sub3(x, b, y);
        candidate(g, dot3(y, y), 1, q);
    } else {
        cross3(w, u, c);
        candidate(g, dot3(c, c), uu, q);
    }
}

/* Vertex x against the closed triangle t0 t1 t2. */
static Gap vertex_face_gap(const int64_t *x, const int64_t *t0, const int64_t *t1, const int64_t *t2, int64_t q) {
    Gap g = {0, INFINITY};
    const int64_t *t[3];
    int64_t e1[3], e2[3], n[3], nn;
    int k, inside = 1;
    t[0] = t0; t[1] = t1; t[2] = t2;
    for (k = 0; k < 3; k++) point_segment(&g, x, t[k], t[(k + 1) % 3], q);
    sub3(t1, t0, e1);
    sub3(t2, t0, e2);
    cross3(e1, e2, n);
    nn = dot3(n, n);
    if (nn == 0) return g;
    for (k = 0; k < 3; k++) {
        int64_t ab[3], ax[3], c[3];
        sub3(t[(k + 1) % 3], t[k], ab);
        sub3(x, t[k], ax);
        cross3(ab, ax, c);
        if (dot3(n, c) <= 0) inside = 0;
    }
    if (inside) {
        int64_t w[3], h;
        sub3(x, t0, w);
        h = dot3(n, w);
        candidate(&g, h * h, nn, q);
    }
    return g;
}

/* The closed segments [a0, a1] and [b0, b1]. */
static Gap edge_edge_gap(const int64_t *a0, const int64_t *a1, const int64_t *b0, const int64_t *b1, int64_t q) {
    Gap g = {0, INFINITY};
    int64_t u[3], v[3], w[3], n[3], nn;
    point_segment(&g, a0, b0, b1, q);
    point_segment(&g, a1, b0, b1, q);
    point_segment(&g, b0, a0, a1, q);
    point_segment(&g, b1, a0, a1, q);
    sub3(a1, a0, u);
    sub3(b1, b0, v);
    sub3(a0, b0, w);
    cross3(u, v, n);
    nn = dot3(n, n);
    if (nn != 0) {
        int64_t uu = dot3(u, u), uv = dot3(u, v), vv = dot3(v, v), uw = dot3(u, w), vw = dot3(v, w);
        int64_t s = uv * vw - vv * uw, t = uu * vw - uv * uw, h = dot3(w, n);
        if (s > 0 && s < nn && t > 0 && t < nn) candidate(&g, h * h, nn, q);
    }
    return g;
}

typedef struct NearList {
    DvhNearPair *v;
    size_t n, cap;
} NearList;

static void near_push(NearList *l, DvhImpactKind kind, uint32_t a0, uint32_t a1, uint32_t b0, uint32_t b1, Gap g) {
    DvhNearPair p;
    if (!g.within) return;
    if (l->n == l->cap) {
        l->cap = l->cap * 2 + 16;
        l->v = realloc(l->v, l->cap * sizeof *l->v);
        if (l->v == NULL) exit(2);
    }
    memset(&p, 0, sizeof p);
    p.kind = kind; p.a0 = a0; p.a1 = a1; p.b0 = b0; p.b1 = b1;
    p.distance = sqrt(g.least);
    l->v[l->n++] = p;
}

static int near_key_cmp(const void *x, const void *y) {
    const DvhNearPair *a = x, *b = y;
    uint32_t ka[5], kb[5];
    int i;
    ka[0] = a->kind; ka[1] = a->a0; ka[2] = a->a1; ka[3] = a->b0; ka[4] = a->b1;
    kb[0] = b->kind; kb[1] = b->a0; kb[2] = b->a1; kb[3] = b->b0; kb[4] = b->b1;
    for (i = 0; i < 5; i++)
        if (ka[i] != kb[i]) return ka[i] < kb[i] ? -1 : 1;
    return 0;
}

/* Every stencil of `a` against `b` (of `a` with itself when `b` is NULL) within d, d^2 =
 * quarter_d2 / 4, decided exactly, keys and distances only; sorted as the query sorts. */
static size_t near_brute_force(const World *a, const World *b, int64_t quarter_d2, DvhNearPair **out) {
    const int self = b == NULL;
    const World *mb = self ? a : b;
    NearList l = {NULL, 0, 0};
    uint32_t *ea, *eb;
    size_t na, nb, i, j, t;
    Motion ma, mbm;
    unsigned char *used_a, *used_b;
    ma.vertex_count = a->vertex_count; ma.triangle_count = a->triangle_count; ma.tris = a->tris;
    mbm.vertex_count = mb->vertex_count; mbm.triangle_count = mb->triangle_count; mbm.tris = mb->tris;
    used_a = vertices_used(&ma);
    used_b = vertices_used(&mbm);
    for (i = 0; i < a->vertex_count; i++) {
        if (!used_a[i]) continue;
        for (t = 0; t < mb->triangle_count; t++) {
            const uint32_t *c = &mb->tris[3 * t];
            if (self && (c[0] == i || c[1] == i || c[2] == i)) continue;
            near_push(&l, DVH_IMPACT_KIND_VERTEX_FACE, (uint32_t)i, 0, (uint32_t)t, 0,
                      vertex_face_gap(&a->p[3 * i], &mb->p[3 * c[0]], &mb->p[3 * c[1]], &mb->p[3 * c[2]], quarter_d2));
        }
    }
    if (!self)
        for (t = 0; t < a->triangle_count; t++) {
            const uint32_t *c = &a->tris[3 * t];
            for (i = 0; i < mb->vertex_count; i++) {
                if (!used_b[i]) continue;
                near_push(&l, DVH_IMPACT_KIND_FACE_VERTEX, (uint32_t)t, 0, (uint32_t)i, 0,
                          vertex_face_gap(&mb->p[3 * i], &a->p[3 * c[0]], &a->p[3 * c[1]], &a->p[3 * c[2]], quarter_d2));
            }
        }
    na = motion_edges(&ma, &ea);
    nb = motion_edges(&mbm, &eb);
    for (i = 0; i < na; i++)
        for (j = self ? i + 1 : 0; j < nb; j++) {
            const uint32_t *x = &ea[2 * i], *y = &eb[2 * j];
            if (self && (y[0] == x[0] || y[0] == x[1] || y[1] == x[0] || y[1] == x[1])) continue;
            near_push(&l, DVH_IMPACT_KIND_EDGE_EDGE, x[0], x[1], y[0], y[1],
                      edge_edge_gap(&a->p[3 * x[0]], &a->p[3 * x[1]], &mb->p[3 * y[0]], &mb->p[3 * y[1]], quarter_d2));
        }
    if (l.n > 0) qsort(l.v, l.n, sizeof *l.v, near_key_cmp);
    free(ea);
    free(eb);
    free(used_a);
    free(used_b);
    *out = l.v;
    return l.n;
}

/* A stencil's values against its own primitives: weights in [0, 1] summing to one, zero past the
 * primitive's corners, one at a corner feature, the closest points the weighted corners, their
 * distance the reported one. */
static int stencil_consistent(const DvhNearPair *p, const World *a, const World *b) {
    const int64_t *ca[3], *cb[3];
    size_t na = 0, nb = 0, k;
    int side, ok = 1;
    switch (p->kind) {
    case DVH_IMPACT_KIND_VERTEX_FACE:
        ca[na++] = &a->p[3 * p->a0];
        for (k = 0; k < 3; k++) cb[nb++] = &b->p[3 * b->tris[3 * p->b0 + k]];
        break;
    case DVH_IMPACT_KIND_FACE_VERTEX:
        for (k = 0; k < 3; k++) ca[na++] = &a->p[3 * a->tris[3 * p->a0 + k]];
        cb[nb++] = &b->p[3 * p->b0];
        break;
    default:
        ca[na++] = &a->p[3 * p->a0];
        ca[na++] = &a->p[3 * p->a1];
        cb[nb++] = &b->p[3 * p->b0];
        cb[nb++] = &b->p[3 * p->b1];
    }
    for (side = 0; side < 2; side++) {
        const double *w = side == 0 ? p->weights_a : p->weights_b, *x = side == 0 ? p->closest_a : p->closest_b;
        const int64_t **c = side == 0 ? ca : cb;
        size_t n = side == 0 ? na : nb;
        uint32_t f = side == 0 ? p->feature_a : p->feature_b;
        double sum = 0.0;
        int axis;
        for (k = 0; k < 3; k++) {
            ok &= w[k] >= 0.0 && w[k] <= 1.0;
            if (k >= n) ok &= w[k] == 0.0;
            sum += w[k];
        }
        ok &= fabs(sum - 1.0) < 1e-12;
        ok &= f <= DVH_FEATURE_INTERIOR;
        if (f <= DVH_FEATURE_VERTEX_2) ok &= f < n && w[f] == 1.0;
        if (n == 1) ok &= f == DVH_FEATURE_VERTEX_0;
        if (n == 2) ok &= f <= DVH_FEATURE_VERTEX_1 || f == DVH_FEATURE_EDGE_01;
        if (f == DVH_FEATURE_INTERIOR) ok &= w[0] > 0.0 && w[1] > 0.0 && w[2] > 0.0;
        for (axis = 0; axis < 3; axis++) {
            double y = 0.0;
            for (k = 0; k < n; k++) y += w[k] * (double)c[k][axis];
            ok &= fabs(y - x[axis]) < 1e-12 * 64;
        }
    }
    {
        double dx = p->closest_a[0] - p->closest_b[0], dy = p->closest_a[1] - p->closest_b[1],
               dz = p->closest_a[2] - p->closest_b[2];
        ok &= fabs(sqrt(dx * dx + dy * dy + dz * dz) - p->distance) < 1e-12 * 64;
    }
    if (!ok)
        fprintf(stderr, "inconsistent stencil kind %u (%u %u %u %u) features %u %u distance %.17g\n", p->kind, p->a0,
                p->a1, p->b0, p->b1, p->feature_a, p->feature_b, p->distance);
    return ok;
}

/* The query on `a` (placed by `pa`) and `b` (by `pb`; NULL `mb`: `a` with itself) at distance
 * sqrt(quarter_d2) / 2 against the exact brute force: the same keys in the same order, distances
 * within a few units of the last place, values consistent; every mode and thread count the same
 * answer, FIRST_HIT one of it, max_pairs a sorted part of it. Returns the number of stencils. */
static size_t check_nearest(const DvhMesh *a, const Mesh *ma, const IPose *pa, const DvhMesh *b, const Mesh *mb,
                            const IPose *pb, int64_t quarter_d2, DvhNearPairs *out) {
    World wa = world_of(ma, pa), wb = world_of(mb != NULL ? mb : ma, pb);
    DvhPose da, db;
    DvhNearPair *expected, *first = NULL;
    DvhQueryStats stats;
    DvhQueryOptions q;
    const double d = sqrt((double)quarter_d2) / 2.0;
    size_t n, k, first_n = 0;
    int mode, threads;
    static const DvhQueryMode modes[] = {DVH_QUERY_MODE_TRIANGLES, DVH_QUERY_MODE_LEAVES, DVH_QUERY_MODE_DEPTH,
                                         DVH_QUERY_MODE_BUDGET, DVH_QUERY_MODE_FIRST_HIT};
    if (pa != NULL) da = ipose_to_dvh(pa);
    if (pb != NULL) db = ipose_to_dvh(pb);
    n = near_brute_force(&wa, mb != NULL ? &wb : NULL, quarter_d2, &expected);
    for (threads = 1; threads <= 2; threads++)
        for (mode = 0; mode < 5; mode++) {
            const DvhNearPair *got;
            size_t len;
            q = dvh_query_options_default();
            q.threads = (uint32_t)threads;
            q.mode = modes[mode];
            q.max_depth = 2;
            q.budget = 5;
            if (mb != NULL)
                CHECK_STATUS(dvh_nearest_features(a, pa != NULL ? &da : NULL, b, pb != NULL ? &db : NULL, d, &q, out, &stats),
                             DVH_STATUS_OK, NULL);
            else
                CHECK_STATUS(dvh_self_nearest_features(a, d, &q, out, &stats), DVH_STATUS_OK, NULL);
            got = dvh_near_pairs_data(out);
            len = dvh_near_pairs_len(out);
            CHECK(stats.pairs == len && !stats.truncated);
            if (modes[mode] == DVH_QUERY_MODE_FIRST_HIT) {
                CHECK(len == (n > 0 ? 1u : 0u));
                if (len == 1) {
                    CHECK(bsearch(got, expected, n, sizeof *expected, near_key_cmp) != NULL);
                    if (first == NULL) {
                        first = malloc(sizeof *first);
                        *first = got[0];
                        first_n = 1;
                    } else {
                        CHECK(memcmp(first, got, sizeof *first) == 0);
                    }
                }
                continue;
            }
            CHECK(len == n);
            if (len != n) continue;
            for (k = 0; k < n; k++) {
                CHECK(near_key_cmp(&got[k], &expected[k]) == 0);
                CHECK(fabs(got[k].distance - expected[k].distance) <= 4e-16 * (expected[k].distance + 1e-300));
                CHECK(got[k].distance <= d);
                if (threads == 1 && mode == 0) CHECK(stencil_consistent(&got[k], &wa, &wb));
            }
        }
    if (n > 3) {
        const DvhNearPair *got;
        q = dvh_query_options_default();
        q.max_pairs = 3;
        if (mb != NULL)
            CHECK_STATUS(dvh_nearest_features(a, pa != NULL ? &da : NULL, b, pb != NULL ? &db : NULL, d, &q, out, &stats),
                         DVH_STATUS_OK, NULL);
        else
            CHECK_STATUS(dvh_self_nearest_features(a, d, &q, out, &stats), DVH_STATUS_OK, NULL);
        got = dvh_near_pairs_data(out);
        CHECK(dvh_near_pairs_len(out) == 3 && stats.truncated);
        for (k = 0; k < 3; k++) {
            CHECK(bsearch(&got[k], expected, n, sizeof *expected, near_key_cmp) != NULL);
            if (k > 0) CHECK(near_key_cmp(&got[k - 1], &got[k]) < 0);
        }
    }
    (void)first_n;
    free(first);
    free(expected);
    free(wa.p);
    free(wb.p);
    return n;
}

static int same_near_pairs(const DvhNearPairs *r, const DvhNearPair *expected, size_t n) {
    return dvh_near_pairs_len(r) == n && (n == 0 || memcmp(dvh_near_pairs_data(r), expected, n * sizeof *expected) == 0);
}

static void test_nearest_features(void) {
    DvhNearPairs *out = dvh_near_pairs_new();
    DvhQueryStats stats, sentinel;
    size_t found = 0;

    /* Hand-worked: a vertex 1/2 above a right triangle's interior, an edge 1/4 above two of its
     * edges, parallel to the third. */
    {
        static const double pa[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        static const double pb[] = {0.25, 0.25, 0.5, 0.25, -1, 0.25, 0.25, 2, 0.25};
        static const uint32_t tri[] = {0, 1, 2};
        DvhMesh *a = NULL, *b = NULL;
        const DvhNearPair *p;
        CHECK_STATUS(dvh_mesh_create(pa, 3, tri, 1, NULL, &a), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_mesh_create(pb, 3, tri, 1, NULL, &b), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_nearest_features(a, NULL, b, NULL, 0.25, NULL, out, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_near_pairs_len(out) == 2 && stats.pairs == 2);
        p = dvh_near_pairs_data(out);
        if (dvh_near_pairs_len(out) == 2) {
            CHECK(p[0].kind == DVH_IMPACT_KIND_EDGE_EDGE && p[0].a0 == 0 && p[0].a1 == 1 && p[0].b0 == 1 && p[0].b1 == 2);
            CHECK(p[1].kind == DVH_IMPACT_KIND_EDGE_EDGE && p[1].a0 == 1 && p[1].a1 == 2 && p[1].b0 == 1 && p[1].b1 == 2);
            CHECK(p[0].distance == 0.25 && p[0].feature_a == DVH_FEATURE_EDGE_01 && p[0].feature_b == DVH_FEATURE_EDGE_01);
            CHECK(p[0].closest_a[0] == 0.25 && p[0].closest_a[1] == 0 && p[0].closest_a[2] == 0);
            CHECK(p[0].closest_b[0] == 0.25 && p[0].closest_b[1] == 0 && p[0].closest_b[2] == 0.25);
            CHECK(p[0].weights_a[0] == 0.75 && p[0].weights_a[1] == 0.25 && p[0].weights_a[2] == 0);
            CHECK(p[0].weights_b[0] == 2.0 / 3.0 && p[0].weights_b[1] == 1.0 / 3.0 && p[0].weights_b[2] == 0);
        }
        CHECK_STATUS(dvh_nearest_features(a, NULL, b, NULL, 0.5, NULL, out, NULL), DVH_STATUS_OK, NULL);
        {
            size_t k, seen = 0;
            p = dvh_near_pairs_data(out);
            for (k = 0; k < dvh_near_pairs_len(out); k++)
                if (p[k].kind == DVH_IMPACT_KIND_FACE_VERTEX && p[k].b0 == 0) {
                    seen++;
                    CHECK(p[k].a0 == 0 && p[k].distance == 0.5);
                    CHECK(p[k].feature_a == DVH_FEATURE_INTERIOR && p[k].feature_b == DVH_FEATURE_VERTEX_0);
                    CHECK(p[k].closest_a[0] == 0.25 && p[k].closest_a[1] == 0.25 && p[k].closest_a[2] == 0);
                    CHECK(p[k].weights_a[0] == 0.5 && p[k].weights_a[1] == 0.25 && p[k].weights_a[2] == 0.25);
                    CHECK(p[k].weights_b[0] == 1 && p[k].weights_b[1] == 0 && p[k].weights_b[2] == 0);
                }
            CHECK(seen == 1);
        }
        dvh_mesh_free(a);
        dvh_mesh_free(b);
    }

    /* Terrains, placed and not, against the exact brute force at several distances. */
    {
        Mesh ma = mesh_terrain(5, 0, 0, wave), mb = mesh_terrain(5, 1, 2, ridge);
        DvhMesh *a = create(&ma, NULL), *b = create(&mb, NULL);
        IPose up = ipose_make(0, 0, 0, 2), turned = ipose_make(5, 6, 1, 1);
        static const int64_t quarter_d2[] = {0, 1, 4, 9, 17};
        size_t k;
        for (k = 0; k < sizeof quarter_d2 / sizeof quarter_d2[0]; k++) {
            found += check_nearest(a, &ma, NULL, b, &mb, &up, quarter_d2[k], out);
            found += check_nearest(b, &mb, &turned, a, &ma, NULL, quarter_d2[k], out);
            found += check_nearest(a, &ma, NULL, NULL, NULL, NULL, quarter_d2[k], out);
            found += check_nearest(b, &mb, NULL, NULL, NULL, NULL, quarter_d2[k], out);
        }
        CHECK(found > 1000);

        /* Errors leave the buffer and the counters as they were. */
        {
            static const double bad[] = {-1.0, NAN, INFINITY, -INFINITY};
            DvhNearPair *before;
            DvhPose nan_pose = ipose_to_dvh(&up), squashed = ipose_to_dvh(&up);
            DvhQueryOptions q = dvh_query_options_default();
            DvhPairs *wrong = dvh_pairs_new();
            size_t n;
            CHECK_STATUS(dvh_self_nearest_features(a, 2.0, NULL, out, NULL), DVH_STATUS_OK, NULL);
            n = dvh_near_pairs_len(out);
            CHECK(n > 0);
            before = malloc(n * sizeof *before);
            memcpy(before, dvh_near_pairs_data(out), n * sizeof *before);
            memset(&sentinel, 0xab, sizeof sentinel);
            stats = sentinel;
            for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
                CHECK_STATUS(dvh_nearest_features(a, NULL, b, NULL, bad[k], NULL, out, &stats), DVH_STATUS_INVALID_ARGUMENT,
                             "distance");
                CHECK_STATUS(dvh_self_nearest_features(a, bad[k], NULL, out, &stats), DVH_STATUS_INVALID_ARGUMENT, "distance");
            }
            CHECK_STATUS(dvh_nearest_features(NULL, NULL, b, NULL, 1.0, NULL, out, &stats), DVH_STATUS_NULL_ARGUMENT, "`a`");
            CHECK_STATUS(dvh_nearest_features(a, NULL, NULL, NULL, 1.0, NULL, out, &stats), DVH_STATUS_NULL_ARGUMENT, "`b`");
            CHECK_STATUS(dvh_nearest_features(a, NULL, b, NULL, 1.0, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT,
                         "`pairs_out`");
            CHECK_STATUS(dvh_self_nearest_features(NULL, 1.0, NULL, out, &stats), DVH_STATUS_NULL_ARGUMENT, "`mesh`");
            CHECK_STATUS(dvh_self_nearest_features(a, 1.0, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT, "`pairs_out`");
            CHECK_STATUS(dvh_self_nearest_features(a, 1.0, NULL, (DvhNearPairs *)(void *)wrong, &stats),
                         DVH_STATUS_INVALID_ARGUMENT, "DvhNearPairs");
            CHECK_STATUS(dvh_nearest_features((const DvhMesh *)(const void *)wrong, NULL, b, NULL, 1.0, NULL, out, &stats),
                         DVH_STATUS_INVALID_ARGUMENT, "DvhMesh");
            nan_pose.translation[2] = NAN;
            CHECK_STATUS(dvh_nearest_features(a, NULL, b, &nan_pose, 1.0, NULL, out, &stats), DVH_STATUS_NON_FINITE_COORDINATE,
                         "pose_b");
            squashed.rotation[0] = 2.0;
            CHECK_STATUS(dvh_nearest_features(a, &squashed, b, NULL, 1.0, NULL, out, &stats), DVH_STATUS_NON_RIGID_POSE,
                         "pose_a");
            q.mode = DVH_QUERY_MODE_BUDGET;
            CHECK_STATUS(dvh_self_nearest_features(a, 1.0, &q, out, &stats), DVH_STATUS_INVALID_ARGUMENT, "options->budget = 0");
            q.mode = 42;
            CHECK_STATUS(dvh_nearest_features(a, NULL, b, NULL, 1.0, &q, out, &stats), DVH_STATUS_INVALID_ARGUMENT,
                         "options->mode = 42");
            CHECK(memcmp(&stats, &sentinel, sizeof stats) == 0);
            CHECK(same_near_pairs(out, before, n));
            free(before);
            dvh_pairs_free(wrong);
        }
        dvh_mesh_free(a);
        dvh_mesh_free(b);
        mesh_free(&ma);
        mesh_free(&mb);
    }

    /* The accessors on NULL and on a new buffer. */
    CHECK(dvh_near_pairs_len(NULL) == 0 && dvh_near_pairs_data(NULL) == NULL);
    {
        DvhNearPairs *fresh = dvh_near_pairs_new();
        CHECK(fresh != NULL && dvh_near_pairs_len(fresh) == 0 && dvh_near_pairs_data(fresh) == NULL);
        dvh_near_pairs_free(fresh);
    }
    dvh_near_pairs_free(NULL);
    dvh_near_pairs_free(out);
}

/* ---- scenes over a step: self-contact, motions, continuous collision and stencils ---- */

static DvhSceneImpact scene_impact(uint32_t object_a, uint32_t object_b, DvhImpact i) {
    DvhSceneImpact s;
    memset(&s, 0, sizeof s);
    s.object_a = object_a;
    s.object_b = object_b;
    s.impact = i;
    return s;
}

static int same_scene_impact(const DvhSceneImpact *x, const DvhSceneImpact *y) {
    return x->object_a == y->object_a && x->object_b == y->object_b && same_impact(&x->impact, &y->impact);
}

static int same_scene_impacts(const DvhSceneImpacts *r, const DvhSceneImpact *expected, size_t n) {
    size_t len = dvh_scene_impacts_len(r), i;
    const DvhSceneImpact *data = dvh_scene_impacts_data(r);
    if (len != n) return 0;
    if (n == 0) return data == NULL;
    for (i = 0; i < n; i++)
        if (!same_scene_impact(&data[i], &expected[i])) return 0;
    return 1;
}

/* Field by field: DvhNearPair has padding before `distance`. */
static int same_near_pair(const DvhNearPair *x, const DvhNearPair *y) {
    return x->kind == y->kind && x->a0 == y->a0 && x->a1 == y->a1 && x->b0 == y->b0 && x->b1 == y->b1 &&
           x->feature_a == y->feature_a && x->feature_b == y->feature_b && x->distance == y->distance &&
           memcmp(x->closest_a, y->closest_a, sizeof x->closest_a) == 0 && memcmp(x->closest_b, y->closest_b, sizeof x->closest_b) == 0 &&
           memcmp(x->weights_a, y->weights_a, sizeof x->weights_a) == 0 && memcmp(x->weights_b, y->weights_b, sizeof x->weights_b) == 0;
}

static int same_scene_near_pairs(const DvhSceneNearPairs *r, const DvhSceneNearPair *expected, size_t n) {
    size_t len = dvh_scene_near_pairs_len(r), i;
    const DvhSceneNearPair *data = dvh_scene_near_pairs_data(r);
    if (len != n) return 0;
    if (n == 0) return data == NULL;
    for (i = 0; i < n; i++)
        if (data[i].object_a != expected[i].object_a || data[i].object_b != expected[i].object_b ||
            !same_near_pair(&data[i].pair, &expected[i].pair))
            return 0;
    return 1;
}

/* Appends the impacts of `r` as those of objects (a, b); returns the new count (at most `cap`). */
static size_t append_impacts(DvhSceneImpact *out, size_t n, size_t cap, uint32_t a, uint32_t b, const DvhImpacts *r) {
    size_t k;
    for (k = 0; k < dvh_impacts_len(r) && n < cap; k++) out[n++] = scene_impact(a, b, dvh_impacts_data(r)[k]);
    return n;
}

/* Appends the stencils of `r` as those of objects (a, b); returns the new count (at most `cap`). */
static size_t append_near_pairs(DvhSceneNearPair *out, size_t n, size_t cap, uint32_t a, uint32_t b, const DvhNearPairs *r) {
    size_t k;
    for (k = 0; k < dvh_near_pairs_len(r) && n < cap; k++, n++) {
        memset(&out[n], 0, sizeof out[n]);
        out[n].object_a = a;
        out[n].object_b = b;
        out[n].pair = dvh_near_pairs_data(r)[k];
    }
    return n;
}

static DvhPose translated(double x, double y, double z) {
    IPose p = ipose_make(0, 0, 0, 0);
    DvhPose d = ipose_to_dvh(&p);
    d.translation[0] = x;
    d.translation[1] = y;
    d.translation[2] = z;
    return d;
}

/* The falling triangle of test_continuous_collide as a deformable object (0) with a motion, the
 * floor triangle as a rigid object (1) with a pose motion, a copy of the floor far away (2):
 * the impacts worked out by hand, their object ids and kinds, every option; every error path of
 * the new calls, leaving the scene and the results as they were; the buffers' accessors on NULL,
 * new and wrong-kind handles. */
static void test_scene_continuous(void) {
    /* The floor still: object 0's impacts with it are those of test_continuous_collide. */
    const DvhSceneImpact still[4] = {
        scene_impact(0, 1, impact(DVH_IMPACT_KIND_VERTEX_FACE, 0, 0, 0, 0, 0.6875)),
        scene_impact(0, 1, impact(DVH_IMPACT_KIND_FACE_VERTEX, 0, 0, 0, 0, 0.5)),
        scene_impact(0, 1, impact(DVH_IMPACT_KIND_EDGE_EDGE, 0, 1, 0, 2, 0.53125)),
        scene_impact(0, 1, impact(DVH_IMPACT_KIND_EDGE_EDGE, 0, 2, 0, 1, 0.625)),
    };
    /* The floor rising from z = -2 to z = 2 while the triangle falls by 4: each pair meets when
     * the triangle's height over the floor, 2 more at the start, has fallen by 8 times t. */
    const DvhSceneImpact rising[4] = {
        scene_impact(0, 1, impact(DVH_IMPACT_KIND_VERTEX_FACE, 0, 0, 0, 0, 0.59375)),
        scene_impact(0, 1, impact(DVH_IMPACT_KIND_FACE_VERTEX, 0, 0, 0, 0, 0.5)),
        scene_impact(0, 1, impact(DVH_IMPACT_KIND_EDGE_EDGE, 0, 1, 0, 2, 0.515625)),
        scene_impact(0, 1, impact(DVH_IMPACT_KIND_EDGE_EDGE, 0, 2, 0, 1, 0.5625)),
    };
    const DvhPose below = translated(0, 0, -2), above = translated(0, 0, 2), far = translated(40, 0, 0);
    DvhMesh *falling = NULL, *floor_mesh = NULL, *floor_moving = NULL, *falling_moving = NULL;
    DvhScene *scene = NULL;
    DvhSceneImpacts *impacts = dvh_scene_impacts_new(), *fresh = dvh_scene_impacts_new();
    DvhImpacts *pairwise = dvh_impacts_new();
    DvhContacts *contacts = dvh_contacts_new();
    DvhSceneNearPairs *near = dvh_scene_near_pairs_new();
    DvhCcdOptions o = dvh_ccd_options_default();
    DvhCcdStats stats, sentinel;
    DvhSceneImpact oracle[8];
    double floor_start[9], floor_end[9], bad[9];
    float start32[12], end32[12];
    char *raw = malloc(sizeof bad + 8);
    uint32_t id = 99, threads;
    size_t k, n;

    CHECK(impacts != NULL && fresh != NULL && near != NULL);
    CHECK(dvh_scene_impacts_len(fresh) == 0 && dvh_scene_impacts_data(fresh) == NULL);
    CHECK(dvh_scene_impacts_len(NULL) == 0 && dvh_scene_impacts_data(NULL) == NULL);
    dvh_scene_impacts_free(NULL);
    CHECK_STATUS(dvh_mesh_create(falling_start, 3, one_triangle, 1, NULL, &falling), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_create(floor_pos, 3, one_triangle, 1, NULL, &floor_mesh), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_create(&scene), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_add_deformable(scene, falling, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 0);
    CHECK_STATUS(dvh_scene_add_rigid(scene, floor_mesh, NULL, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 1);
    CHECK_STATUS(dvh_scene_add_rigid(scene, floor_mesh, &far, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 2);

    /* No steps: everything stands still, apart. */
    memset(&stats, 0xab, sizeof stats);
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_scene_impacts_len(impacts) == 0 && dvh_scene_impacts_data(impacts) == NULL);
    CHECK(stats.impacts == 0 && !stats.truncated && isinf(stats.earliest_toi));

    /* The triangle falls through the still floor (a pose motion between two identities, NULL). */
    CHECK_STATUS(dvh_scene_set_motion(scene, 0, falling_start, falling_end, 3), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_set_pose_motion(scene, 1, NULL, NULL), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_scene_impacts(impacts, still, 4));
    CHECK(stats.impacts == 4 && stats.earliest_toi == 0.5 && !stats.truncated && stats.primitive_tests >= 4);
    /* The discrete queries see the end of the step: apart. */
    CHECK_STATUS(dvh_scene_collide(scene, NULL, contacts, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_contacts_len(contacts) == 0);

    /* The floor rises while the triangle falls. */
    CHECK_STATUS(dvh_scene_set_pose_motion(scene, 1, &below, &above), DVH_STATUS_OK, NULL);
    for (threads = 0; threads < 3; threads++) {
        o = dvh_ccd_options_default();
        o.threads = threads;
        CHECK_STATUS(dvh_scene_continuous_collide(scene, &o, impacts, &stats), DVH_STATUS_OK, NULL);
        CHECK(same_scene_impacts(impacts, rising, 4));
        CHECK(stats.impacts == 4 && stats.earliest_toi == 0.5 && !stats.truncated && stats.primitive_tests >= 4);
    }
    /* The same as the query of two stand-alone meshes moving as the objects do. */
    for (k = 0; k < 9; k++) {
        floor_start[k] = floor_pos[k] + (k % 3 == 2 ? -2.0 : 0.0);
        floor_end[k] = floor_pos[k] + (k % 3 == 2 ? 2.0 : 0.0);
    }
    CHECK_STATUS(dvh_mesh_create(floor_pos, 3, one_triangle, 1, NULL, &floor_moving), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_refit_motion(floor_moving, floor_start, floor_end, 3), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_create(falling_start, 3, one_triangle, 1, NULL, &falling_moving), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_refit_motion(falling_moving, falling_start, falling_end, 3), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_continuous_collide(falling_moving, floor_moving, NULL, pairwise, NULL), DVH_STATUS_OK, NULL);
    n = append_impacts(oracle, 0, 8, 0, 1, pairwise);
    CHECK(n == 4 && same_scene_impacts(impacts, oracle, n));
    /* The earliest alone; a limit. */
    o = dvh_ccd_options_default();
    o.earliest_only = true;
    CHECK_STATUS(dvh_scene_continuous_collide(scene, &o, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_scene_impacts(impacts, &rising[1], 1));
    CHECK(stats.impacts == 1 && stats.earliest_toi == 0.5 && !stats.truncated);
    o = dvh_ccd_options_default();
    o.max_impacts = 1;
    CHECK_STATUS(dvh_scene_continuous_collide(scene, &o, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_scene_impacts_len(impacts) == 1 && stats.truncated && stats.impacts == 1);
    if (dvh_scene_impacts_len(impacts) == 1) {
        size_t found = 0;
        for (k = 0; k < n; k++) found += same_scene_impact(dvh_scene_impacts_data(impacts), &oracle[k]);
        CHECK(found == 1);
    }
    /* float motions at a stride: the same step. */
    for (k = 0; k < 3; k++) {
        start32[4 * k] = (float)falling_start[3 * k];
        start32[4 * k + 1] = (float)falling_start[3 * k + 1];
        start32[4 * k + 2] = (float)falling_start[3 * k + 2];
        end32[4 * k] = (float)falling_end[3 * k];
        end32[4 * k + 1] = (float)falling_end[3 * k + 1];
        end32[4 * k + 2] = (float)falling_end[3 * k + 2];
        start32[4 * k + 3] = end32[4 * k + 3] = 0.0f;
    }
    CHECK_STATUS(dvh_scene_set_motion_f32(scene, 0, start32, end32, 16, 3), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_scene_impacts(impacts, rising, 4));

    /* Failed calls name what was wrong and change nothing: the same impacts afterwards. */
    memcpy(bad, falling_end, sizeof bad);
    bad[3 * 1 + 1] = NAN;
    CHECK_STATUS(dvh_scene_set_motion(NULL, 0, falling_start, falling_end, 3), DVH_STATUS_NULL_ARGUMENT, "argument `scene` is NULL");
    CHECK_STATUS(dvh_scene_set_motion(scene, 0, NULL, falling_end, 3), DVH_STATUS_NULL_ARGUMENT, "argument `start` is NULL");
    CHECK_STATUS(dvh_scene_set_motion(scene, 0, falling_start, NULL, 3), DVH_STATUS_NULL_ARGUMENT, "argument `end` is NULL");
    CHECK_STATUS(dvh_scene_set_motion(scene, 1, falling_start, falling_end, 3), DVH_STATUS_INVALID_ARGUMENT,
                 "object 1 is rigid: it is moved by a pose");
    CHECK_STATUS(dvh_scene_set_motion(scene, 9, falling_start, falling_end, 3), DVH_STATUS_INVALID_ARGUMENT,
                 "object 9 is not in the scene");
    CHECK_STATUS(dvh_scene_set_motion(scene, 0, falling_start, falling_end, 2), DVH_STATUS_INVALID_ARGUMENT,
                 "vertex_count = 2, but object 0 has 3 vertices");
    CHECK_STATUS(dvh_scene_set_motion(scene, 0, falling_start, bad, 3), DVH_STATUS_NON_FINITE_COORDINATE,
                 "object 0: end positions: vertex 1: coordinate y is NaN");
    CHECK_STATUS(dvh_scene_set_motion(scene, 0, bad, falling_end, 3), DVH_STATUS_NON_FINITE_COORDINATE,
                 "object 0: start positions: vertex 1: coordinate y is NaN");
    memcpy(raw + 1, falling_end, sizeof bad);
    CHECK_STATUS(dvh_scene_set_motion(scene, 0, falling_start, (const double *)(const void *)(raw + 1), 3),
                 DVH_STATUS_INVALID_ARGUMENT, "argument `end` is not aligned");
    CHECK_STATUS(dvh_scene_set_motion_f32(NULL, 0, start32, end32, 16, 3), DVH_STATUS_NULL_ARGUMENT, "argument `scene` is NULL");
    CHECK_STATUS(dvh_scene_set_motion_f32(scene, 0, NULL, end32, 16, 3), DVH_STATUS_NULL_ARGUMENT, "argument `start` is NULL");
    CHECK_STATUS(dvh_scene_set_motion_f32(scene, 0, start32, NULL, 16, 3), DVH_STATUS_NULL_ARGUMENT, "argument `end` is NULL");
    CHECK_STATUS(dvh_scene_set_motion_f32(scene, 0, start32, end32, 8, 3), DVH_STATUS_INVALID_ARGUMENT, "stride_bytes = 8");
    CHECK_STATUS(dvh_scene_set_motion_f32(scene, 1, start32, end32, 16, 3), DVH_STATUS_INVALID_ARGUMENT, "object 1 is rigid");
    CHECK_STATUS(dvh_scene_set_motion_f32(scene, 0, start32, end32, 16, 4), DVH_STATUS_INVALID_ARGUMENT,
                 "vertex_count = 4, but object 0 has 3 vertices");
    end32[4 * 2] = (float)INFINITY;
    CHECK_STATUS(dvh_scene_set_motion_f32(scene, 0, start32, end32, 16, 3), DVH_STATUS_NON_FINITE_COORDINATE,
                 "object 0: end positions: vertex 2: coordinate x is inf");
    {
        DvhPose skewed = above, nan_pose = above, out_of_range = above;
        skewed.rotation[0] = 2.0;
        nan_pose.translation[2] = NAN;
        out_of_range.translation[1] = 1e301;
        CHECK_STATUS(dvh_scene_set_pose_motion(NULL, 1, &below, &above), DVH_STATUS_NULL_ARGUMENT, "argument `scene` is NULL");
        CHECK_STATUS(dvh_scene_set_pose_motion(scene, 0, &below, &above), DVH_STATUS_INVALID_ARGUMENT,
                     "object 0 is deformable: it is moved by its positions");
        CHECK_STATUS(dvh_scene_set_pose_motion(scene, 0, NULL, NULL), DVH_STATUS_INVALID_ARGUMENT, "object 0 is deformable");
        CHECK_STATUS(dvh_scene_set_pose_motion(scene, 9, &below, &above), DVH_STATUS_INVALID_ARGUMENT, "object 9 is not in the scene");
        CHECK_STATUS(dvh_scene_set_pose_motion(scene, 1, &skewed, &above), DVH_STATUS_NON_RIGID_POSE, "start: ");
        CHECK_STATUS(dvh_scene_set_pose_motion(scene, 1, &below, &skewed), DVH_STATUS_NON_RIGID_POSE, "end: ");
        CHECK_STATUS(dvh_scene_set_pose_motion(scene, 1, &below, &nan_pose), DVH_STATUS_NON_FINITE_COORDINATE, "end: ");
        CHECK_STATUS(dvh_scene_set_pose_motion(scene, 1, &out_of_range, &above), DVH_STATUS_POSE_OUT_OF_RANGE, "object 1: pose moves");
        CHECK_STATUS(dvh_scene_set_pose_motion(scene, 1, &below, &out_of_range), DVH_STATUS_POSE_OUT_OF_RANGE, "object 1: pose moves");
    }
    CHECK_STATUS(dvh_scene_set_self_contact(NULL, 0, true), DVH_STATUS_NULL_ARGUMENT, "argument `scene` is NULL");
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 1, true), DVH_STATUS_INVALID_ARGUMENT,
                 "object 1 is rigid: self-contact is for deformable objects");
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 9, false), DVH_STATUS_INVALID_ARGUMENT, "object 9 is not in the scene");
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 1, false), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_scene_impacts(impacts, rising, 4));

    /* Failed queries leave the result and the counters as they were. */
    memset(&sentinel, 0xab, sizeof sentinel);
    stats = sentinel;
    o = dvh_ccd_options_default();
    o.mode = 7;
    CHECK_STATUS(dvh_scene_continuous_collide(scene, &o, impacts, &stats), DVH_STATUS_INVALID_ARGUMENT,
                 "options->mode = 7 is not a DVH_CCD_MODE_* value (0 or 1)");
    CHECK_STATUS(dvh_scene_continuous_collide(NULL, NULL, impacts, &stats), DVH_STATUS_NULL_ARGUMENT, "argument `scene` is NULL");
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT,
                 "argument `impacts_out` is NULL");
    /* Handles of another kind, both ways. */
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, (DvhSceneImpacts *)(void *)pairwise, &stats), DVH_STATUS_INVALID_ARGUMENT,
                 "DvhSceneImpacts `impacts_out` is not a live handle");
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, (DvhSceneImpacts *)(void *)near, &stats), DVH_STATUS_INVALID_ARGUMENT,
                 "DvhSceneImpacts `impacts_out` is not a live handle");
    CHECK_STATUS(dvh_scene_continuous_collide((DvhScene *)(void *)impacts, NULL, fresh, &stats), DVH_STATUS_INVALID_ARGUMENT,
                 "DvhScene `scene` is not a live handle");
    CHECK_STATUS(dvh_continuous_collide(falling_moving, floor_moving, NULL, (DvhImpacts *)(void *)impacts, &stats),
                 DVH_STATUS_INVALID_ARGUMENT, "DvhImpacts `impacts_out` is not a live handle");
    CHECK_STATUS(dvh_scene_collide(scene, NULL, (DvhContacts *)(void *)impacts, NULL), DVH_STATUS_INVALID_ARGUMENT,
                 "DvhContacts `contacts_out` is not a live handle");
    CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, NULL, (DvhSceneNearPairs *)(void *)impacts, NULL),
                 DVH_STATUS_INVALID_ARGUMENT, "DvhSceneNearPairs `pairs_out` is not a live handle");
    CHECK_STATUS(dvh_scene_set_motion((DvhScene *)(void *)impacts, 0, falling_start, falling_end, 3), DVH_STATUS_INVALID_ARGUMENT,
                 "DvhScene `scene` is not a live handle");
    CHECK(dvh_scene_impacts_len((const DvhSceneImpacts *)(const void *)pairwise) == 0);
    CHECK(dvh_scene_impacts_data((const DvhSceneImpacts *)(const void *)pairwise) == NULL);
    CHECK(dvh_scene_impacts_len((const DvhSceneImpacts *)(const void *)scene) == 0);
    CHECK(dvh_impacts_len((const DvhImpacts *)(const void *)impacts) == 0);
    /* Releasing a handle of another kind is refused and says so; the handle lives on. */
    dvh_scene_impacts_free((DvhSceneImpacts *)(void *)pairwise);
    {
        char message[256];
        dvh_last_error_message(message, sizeof message);
        CHECK(strstr(message, "DvhSceneImpacts `impacts` is not a live handle") != NULL && strstr(message, "not released") != NULL);
    }
    CHECK(dvh_impacts_len(pairwise) == 4);
    CHECK(memcmp(&stats, &sentinel, sizeof stats) == 0);
    CHECK(same_scene_impacts(impacts, rising, 4));
    CHECK(dvh_scene_impacts_len(fresh) == 0 && dvh_scene_impacts_data(fresh) == NULL);

    /* A new position ends the triangle's step, a pose the floor's: still again, apart. */
    CHECK_STATUS(dvh_scene_set_positions(scene, 0, falling_end, 3), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_scene_impacts_len(impacts) > 0); /* the floor still rises through it */
    CHECK_STATUS(dvh_scene_set_pose(scene, 1, NULL), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_scene_impacts_len(impacts) == 0 && dvh_scene_impacts_data(impacts) == NULL && stats.impacts == 0);
    /* And a new step: into a buffer that held other impacts. */
    CHECK_STATUS(dvh_scene_set_motion(scene, 0, falling_start, falling_end, 3), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, fresh, NULL), DVH_STATUS_OK, NULL);
    CHECK(same_scene_impacts(fresh, still, 4));

    dvh_scene_impacts_free(impacts);
    dvh_scene_impacts_free(fresh);
    dvh_scene_near_pairs_free(near);
    dvh_impacts_free(pairwise);
    dvh_contacts_free(contacts);
    dvh_scene_free(scene);
    dvh_mesh_free(falling);
    dvh_mesh_free(floor_mesh);
    dvh_mesh_free(floor_moving);
    dvh_mesh_free(falling_moving);
    free(raw);
}

/* A deforming terrain (0) rising, a rigid terrain (1) turned a half turn about z falling through
 * it by a pose motion, a sheet (2) folding through itself far away with self-contact on: the
 * scene's impacts are the pairwise query's on stand-alone meshes moving as the objects do, then
 * the sheet's own, whatever the thread count; off, the sheet's vanish. */
static void test_scene_continuous_oracle(void) {
    enum { CAP = 20000 };
    Mesh ta = mesh_terrain(8, 0, 0, wave), tb = mesh_terrain(5, 1, 2, ridge), g = mesh_terrain(6, 100, 0, flat);
    IPose high = ipose_make(3, 8, 9, 4), low = ipose_make(3, 8, 9, -4);
    DvhPose dhigh = ipose_to_dvh(&high), dlow = ipose_to_dvh(&low);
    double *a_end = malloc(ta.vertex_count * 3 * sizeof(double));
    double *b_start = malloc(tb.vertex_count * 3 * sizeof(double)), *b_end = malloc(tb.vertex_count * 3 * sizeof(double));
    double *g_start = malloc(g.vertex_count * 3 * sizeof(double)), *g_end = malloc(g.vertex_count * 3 * sizeof(double));
    DvhSceneImpact *expected = malloc(CAP * sizeof *expected);
    DvhMesh *a = create(&ta, NULL), *b = create(&tb, NULL), *sheet = create(&g, NULL);
    DvhMesh *a_alone = create(&ta, NULL), *b_alone = create(&tb, NULL), *sheet_alone = create(&g, NULL);
    DvhScene *scene = NULL;
    DvhSceneImpacts *impacts = dvh_scene_impacts_new();
    DvhImpacts *pairwise = dvh_impacts_new();
    DvhCcdOptions o;
    DvhCcdStats stats;
    size_t i, n, n_pair, best;
    uint32_t id, threads;
    int j, col;

    for (i = 0; i < ta.vertex_count * 3; i++) a_end[i] = ta.pos[i] + (i % 3 == 2 ? 0.5 : 0.0);
    for (i = 0; i < tb.vertex_count; i++) {
        int64_t w[3];
        int c;
        ipose_apply(&high, &tb.ipos[3 * i], w);
        for (c = 0; c < 3; c++) b_start[3 * i + (size_t)c] = (double)w[c];
        ipose_apply(&low, &tb.ipos[3 * i], w);
        for (c = 0; c < 3; c++) b_end[3 * i + (size_t)c] = (double)w[c];
    }
    /* The sheet's columns beyond x = 103, a ramp at the start, swing under the rest (as in
     * test_self_continuous_collide, moved by 100 along x). */
    memcpy(g_start, g.pos, g.vertex_count * 3 * sizeof(double));
    memcpy(g_end, g.pos, g.vertex_count * 3 * sizeof(double));
    for (j = 0; j <= 6; j++)
        for (col = 4; col <= 6; col++) {
            size_t v = (size_t)(j * 7 + col);
            g_start[3 * v + 2] = col - 3;
            g_end[3 * v] = 100 + 6 - col + 0.0625 * j;
            g_end[3 * v + 2] = -0.125 * (col - 3);
        }

    CHECK_STATUS(dvh_scene_create(&scene), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_add_deformable(scene, a, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 0);
    CHECK_STATUS(dvh_scene_add_rigid(scene, b, &dhigh, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 1);
    CHECK_STATUS(dvh_scene_add_deformable(scene, sheet, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 2);
    CHECK_STATUS(dvh_scene_set_motion(scene, 0, ta.pos, a_end, ta.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_set_pose_motion(scene, 1, &dhigh, &dlow), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_set_motion(scene, 2, g_start, g_end, g.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 2, true), DVH_STATUS_OK, NULL);

    /* The stand-alone meshes, in world coordinates over the same step. */
    CHECK_STATUS(dvh_mesh_refit_motion(a_alone, ta.pos, a_end, ta.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_refit_motion(b_alone, b_start, b_end, tb.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_refit_motion(sheet_alone, g_start, g_end, g.vertex_count), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_continuous_collide(a_alone, b_alone, NULL, pairwise, NULL), DVH_STATUS_OK, NULL);
    n_pair = append_impacts(expected, 0, CAP, 0, 1, pairwise);
    CHECK_STATUS(dvh_self_continuous_collide(sheet_alone, NULL, pairwise, NULL), DVH_STATUS_OK, NULL);
    n = append_impacts(expected, n_pair, CAP, 2, 2, pairwise);
    CHECK(n_pair > 3 && n > n_pair + 3 && n < CAP);
    best = 0;
    for (i = 1; i < n; i++)
        if (expected[i].impact.toi < expected[best].impact.toi) best = i;

    for (threads = 0; threads < 3; threads++) {
        o = dvh_ccd_options_default();
        o.threads = threads;
        CHECK_STATUS(dvh_scene_continuous_collide(scene, &o, impacts, &stats), DVH_STATUS_OK, NULL);
        CHECK(same_scene_impacts(impacts, expected, n));
        CHECK(stats.impacts == n && !stats.truncated && stats.earliest_toi == expected[best].impact.toi);
        o.earliest_only = true;
        CHECK_STATUS(dvh_scene_continuous_collide(scene, &o, impacts, &stats), DVH_STATUS_OK, NULL);
        CHECK(same_scene_impacts(impacts, &expected[best], 1));
        o.earliest_only = false;
        o.max_impacts = 3;
        CHECK_STATUS(dvh_scene_continuous_collide(scene, &o, impacts, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_scene_impacts_len(impacts) == 3 && stats.truncated && stats.impacts == 3);
        for (i = 0; i < dvh_scene_impacts_len(impacts); i++) {
            const DvhSceneImpact *x = &dvh_scene_impacts_data(impacts)[i];
            size_t k, found = 0;
            for (k = 0; k < n; k++) found += same_scene_impact(x, &expected[k]);
            CHECK(found == 1);
        }
    }
    /* Self-contact off: the sheet's own impacts vanish. */
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 2, false), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, impacts, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_scene_impacts(impacts, expected, n_pair));

    dvh_scene_impacts_free(impacts);
    dvh_impacts_free(pairwise);
    dvh_scene_free(scene);
    dvh_mesh_free(a);
    dvh_mesh_free(b);
    dvh_mesh_free(sheet);
    dvh_mesh_free(a_alone);
    dvh_mesh_free(b_alone);
    dvh_mesh_free(sheet_alone);
    free(a_end);
    free(b_start);
    free(b_end);
    free(g_start);
    free(g_end);
    free(expected);
    mesh_free(&ta);
    mesh_free(&tb);
    mesh_free(&g);
}

/* Self-contact in the frame's query: a mesh whose triangles fold through each other reports its
 * self-intersections as contacts with object_a == object_b while its self-contact is on, and an
 * intact sheet none; off, they vanish. */
static void test_scene_self_contact(void) {
    /* test_self_collide's fold: triangle 1 folded flat onto triangle 0, triangle 2 through their
     * corner, triangle 3 apart. */
    static const double pos[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 1, 1, 0, 1, 1, -1, 1, 1, 1, 5, 5, 5, 6, 5, 5, 5, 6, 5};
    static const uint32_t tris[] = {0, 1, 2, 0, 1, 3, 0, 4, 5, 6, 7, 8};
    Mesh sheet = mesh_terrain(4, 20, 0, ridge);
    DvhMesh *fold = NULL, *intact = create(&sheet, NULL);
    DvhScene *scene = NULL;
    DvhContacts *contacts = dvh_contacts_new();
    DvhSceneStats st;
    const DvhContact *c;
    uint32_t id;

    CHECK_STATUS(dvh_mesh_create(pos, 9, tris, 4, NULL, &fold), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_create(&scene), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_add_rigid(scene, fold, NULL, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 0);
    CHECK_STATUS(dvh_scene_add_deformable(scene, intact, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 1);
    CHECK_STATUS(dvh_scene_add_deformable(scene, fold, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 2);
    CHECK_STATUS(dvh_scene_exclude_pair(scene, 0, 2), DVH_STATUS_OK, NULL);
    /* Off by default: nothing (the rigid copy overlaps the deformable one, but they are
     * excluded; exclusions do not gate self-contact). */
    CHECK_STATUS(dvh_scene_collide(scene, NULL, contacts, &st), DVH_STATUS_OK, NULL);
    CHECK(dvh_contacts_len(contacts) == 0 && st.contacts == 0);
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 0, true), DVH_STATUS_INVALID_ARGUMENT, "object 0 is rigid");
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 1, true), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 2, true), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_collide(scene, NULL, contacts, &st), DVH_STATUS_OK, NULL);
    CHECK(dvh_contacts_len(contacts) == 3 && st.contacts == 3);
    c = dvh_contacts_data(contacts);
    if (dvh_contacts_len(contacts) == 3) {
        CHECK(c[0].object_a == 2 && c[0].object_b == 2 && c[0].a == 0 && c[0].b == 1);
        CHECK(c[1].object_a == 2 && c[1].object_b == 2 && c[1].a == 0 && c[1].b == 2);
        CHECK(c[2].object_a == 2 && c[2].object_b == 2 && c[2].a == 1 && c[2].b == 2);
    }
    /* Moved, the fold still folds; the first-hit mode keeps one contact of it. */
    {
        double moved[27];
        size_t k;
        DvhQueryOptions q = dvh_query_options_default();
        for (k = 0; k < 27; k++) moved[k] = pos[k] + (k % 3 == 0 ? 40.0 : 0.0);
        CHECK_STATUS(dvh_scene_set_positions(scene, 2, moved, 9), DVH_STATUS_OK, NULL);
        q.mode = DVH_QUERY_MODE_FIRST_HIT;
        CHECK_STATUS(dvh_scene_collide(scene, &q, contacts, &st), DVH_STATUS_OK, NULL);
        CHECK(dvh_contacts_len(contacts) == 1 && dvh_contacts_data(contacts)[0].object_a == 2 &&
              dvh_contacts_data(contacts)[0].object_b == 2);
    }
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 2, false), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_collide(scene, NULL, contacts, &st), DVH_STATUS_OK, NULL);
    CHECK(dvh_contacts_len(contacts) == 0 && dvh_contacts_data(contacts) == NULL);
    dvh_contacts_free(contacts);
    dvh_scene_free(scene);
    dvh_mesh_free(fold);
    dvh_mesh_free(intact);
    mesh_free(&sheet);
}

/* Stencils of a scene: a triangle hovering over a rigid one across a gap (hand-worked, as in
 * test_nearest_features, moved by 10 along x), a terrain with itself while its self-contact is
 * on; each equal to the pairwise or self query; every error path. */
static void test_scene_nearest(void) {
    enum { CAP = 4000 };
    static const double pa[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static const double pb[] = {10.25, 0.25, 0.5, 10.25, -1, 0.25, 10.25, 2, 0.25};
    static const double pb_far[] = {30.25, 0.25, 0.5, 30.25, -1, 0.25, 30.25, 2, 0.25};
    static const uint32_t tri[] = {0, 1, 2};
    static const double bad[] = {-1.0, NAN, INFINITY, -INFINITY};
    const DvhPose at10 = translated(10, 0, 0);
    Mesh tm = mesh_terrain(5, 40, 0, wave);
    DvhMesh *a = NULL, *b = NULL, *terrain = create(&tm, NULL);
    DvhScene *scene = NULL;
    DvhSceneNearPairs *out = dvh_scene_near_pairs_new();
    DvhNearPairs *pairwise = dvh_near_pairs_new();
    DvhSceneNearPair *expected = malloc(CAP * sizeof *expected);
    DvhQueryOptions q;
    DvhQueryStats stats, sentinel;
    const DvhSceneNearPair *p;
    uint32_t id, threads;
    size_t n, n_pair, k;

    CHECK(out != NULL && dvh_scene_near_pairs_len(out) == 0 && dvh_scene_near_pairs_data(out) == NULL);
    CHECK(dvh_scene_near_pairs_len(NULL) == 0 && dvh_scene_near_pairs_data(NULL) == NULL);
    dvh_scene_near_pairs_free(NULL);
    CHECK_STATUS(dvh_mesh_create(pa, 3, tri, 1, NULL, &a), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_create(pb, 3, tri, 1, NULL, &b), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_create(&scene), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_add_rigid(scene, a, &at10, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 0);
    CHECK_STATUS(dvh_scene_add_deformable(scene, b, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 1);
    CHECK_STATUS(dvh_scene_add_deformable(scene, terrain, 1, 0xffffffffu, &id), DVH_STATUS_OK, NULL);
    CHECK(id == 2);

    /* The two edge-edge stencils a quarter apart, by hand. */
    CHECK_STATUS(dvh_scene_nearest_features(scene, 0.25, NULL, out, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_scene_near_pairs_len(out) == 2 && stats.pairs == 2 && !stats.truncated);
    p = dvh_scene_near_pairs_data(out);
    if (dvh_scene_near_pairs_len(out) == 2) {
        CHECK(p[0].object_a == 0 && p[0].object_b == 1 && p[1].object_a == 0 && p[1].object_b == 1);
        CHECK(p[0].pair.kind == DVH_IMPACT_KIND_EDGE_EDGE && p[0].pair.a0 == 0 && p[0].pair.a1 == 1 && p[0].pair.b0 == 1 &&
              p[0].pair.b1 == 2);
        CHECK(p[1].pair.kind == DVH_IMPACT_KIND_EDGE_EDGE && p[1].pair.a0 == 1 && p[1].pair.a1 == 2 && p[1].pair.b0 == 1 &&
              p[1].pair.b1 == 2);
        CHECK(p[0].pair.distance == 0.25 && p[0].pair.feature_a == DVH_FEATURE_EDGE_01 && p[0].pair.feature_b == DVH_FEATURE_EDGE_01);
        CHECK(p[0].pair.closest_a[0] == 10.25 && p[0].pair.closest_a[1] == 0 && p[0].pair.closest_a[2] == 0);
        CHECK(p[0].pair.closest_b[0] == 10.25 && p[0].pair.closest_b[1] == 0 && p[0].pair.closest_b[2] == 0.25);
    }
    /* Across a wider gap than the distance: nothing. */
    CHECK_STATUS(dvh_scene_nearest_features(scene, 0.125, NULL, out, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_scene_near_pairs_len(out) == 0 && dvh_scene_near_pairs_data(out) == NULL && stats.pairs == 0);

    /* At distance 1, with the terrain's self-contact on: the pairwise query, then the self query. */
    CHECK_STATUS(dvh_nearest_features(a, &at10, b, NULL, 1.0, NULL, pairwise, NULL), DVH_STATUS_OK, NULL);
    n_pair = append_near_pairs(expected, 0, CAP, 0, 1, pairwise);
    CHECK_STATUS(dvh_self_nearest_features(terrain, 1.0, NULL, pairwise, NULL), DVH_STATUS_OK, NULL);
    n = append_near_pairs(expected, n_pair, CAP, 2, 2, pairwise);
    CHECK(n_pair > 2 && n > n_pair + 3 && n < CAP);
    CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, NULL, out, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_scene_near_pairs(out, expected, n_pair));
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 2, true), DVH_STATUS_OK, NULL);
    for (threads = 0; threads < 3; threads++) {
        q = dvh_query_options_default();
        q.threads = threads;
        CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, &q, out, &stats), DVH_STATUS_OK, NULL);
        CHECK(same_scene_near_pairs(out, expected, n));
        CHECK(stats.pairs == n && !stats.truncated);
        /* One stencil per object pair in the first-hit mode. */
        q.mode = DVH_QUERY_MODE_FIRST_HIT;
        CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, &q, out, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_scene_near_pairs_len(out) == 2 && stats.pairs == 2);
        p = dvh_scene_near_pairs_data(out);
        if (dvh_scene_near_pairs_len(out) == 2) CHECK(p[0].object_a == 0 && p[0].object_b == 1 && p[1].object_a == 2 && p[1].object_b == 2);
        q.mode = DVH_QUERY_MODE_TRIANGLES;
        q.max_pairs = 1;
        CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, &q, out, &stats), DVH_STATUS_OK, NULL);
        CHECK(dvh_scene_near_pairs_len(out) == 1 && stats.truncated && stats.pairs == 1);
    }
    /* A step is seen at its end: from far away to where it was, the same stencils. */
    CHECK_STATUS(dvh_scene_set_motion(scene, 1, pb_far, pb, 3), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, NULL, out, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_scene_near_pairs(out, expected, n));

    /* Errors leave the buffer and the counters as they were. */
    memset(&sentinel, 0xab, sizeof sentinel);
    stats = sentinel;
    for (k = 0; k < sizeof bad / sizeof bad[0]; k++)
        CHECK_STATUS(dvh_scene_nearest_features(scene, bad[k], NULL, out, &stats), DVH_STATUS_INVALID_ARGUMENT, "distance");
    CHECK_STATUS(dvh_scene_nearest_features(NULL, 1.0, NULL, out, &stats), DVH_STATUS_NULL_ARGUMENT, "argument `scene` is NULL");
    CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT, "argument `pairs_out` is NULL");
    q = dvh_query_options_default();
    q.mode = DVH_QUERY_MODE_BUDGET;
    CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, &q, out, &stats), DVH_STATUS_INVALID_ARGUMENT, "options->budget = 0");
    q.mode = 42;
    CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, &q, out, &stats), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 42");
    CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, NULL, (DvhSceneNearPairs *)(void *)pairwise, &stats),
                 DVH_STATUS_INVALID_ARGUMENT, "DvhSceneNearPairs `pairs_out` is not a live handle");
    CHECK_STATUS(dvh_self_nearest_features(terrain, 1.0, NULL, (DvhNearPairs *)(void *)out, &stats), DVH_STATUS_INVALID_ARGUMENT,
                 "DvhNearPairs `pairs_out` is not a live handle");
    CHECK_STATUS(dvh_scene_continuous_collide(scene, NULL, (DvhSceneImpacts *)(void *)out, NULL), DVH_STATUS_INVALID_ARGUMENT,
                 "DvhSceneImpacts `impacts_out` is not a live handle");
    CHECK_STATUS(dvh_scene_nearest_features((DvhScene *)(void *)out, 1.0, NULL, out, &stats), DVH_STATUS_INVALID_ARGUMENT,
                 "DvhScene `scene` is not a live handle");
    CHECK(dvh_scene_near_pairs_len((const DvhSceneNearPairs *)(const void *)pairwise) == 0);
    CHECK(dvh_scene_near_pairs_data((const DvhSceneNearPairs *)(const void *)pairwise) == NULL);
    CHECK(dvh_near_pairs_len((const DvhNearPairs *)(const void *)out) == 0);
    dvh_scene_near_pairs_free((DvhSceneNearPairs *)(void *)pairwise);
    CHECK(dvh_near_pairs_len(pairwise) == n - n_pair);
    CHECK(memcmp(&stats, &sentinel, sizeof stats) == 0);
    CHECK(same_scene_near_pairs(out, expected, n));

    /* Off again: the terrain's own stencils vanish. */
    CHECK_STATUS(dvh_scene_set_self_contact(scene, 2, false), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_nearest_features(scene, 1.0, NULL, out, &stats), DVH_STATUS_OK, NULL);
    CHECK(same_scene_near_pairs(out, expected, n_pair));

    dvh_scene_near_pairs_free(out);
    dvh_near_pairs_free(pairwise);
    dvh_scene_free(scene);
    dvh_mesh_free(a);
    dvh_mesh_free(b);
    dvh_mesh_free(terrain);
    free(expected);
    mesh_free(&tm);
}

/* An octahedron with corners at distance r from (cx, cy, cz), outward normals; appended to `m`
   at vertex `v0` and triangle `t0`. */
static void octahedron(double *pos, uint32_t *tris, uint32_t v0, double r, double cx, double cy, double cz) {
    static const int corners[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const uint32_t faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                         {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    int i, k;
    for (i = 0; i < 6; i++) {
        pos[3 * i + 0] = cx + r * corners[i][0];
        pos[3 * i + 1] = cy + r * corners[i][1];
        pos[3 * i + 2] = cz + r * corners[i][2];
    }
    for (i = 0; i < 8; i++)
        for (k = 0; k < 3; k++) tris[3 * i + k] = v0 + faces[i][k];
}

/* Every curve of `c` a chain (each segment starting, bit for bit, where the one before ends),
   closed when `closed`, the curves covering the segments in order; and the segments' and
   degenerate pairs' triangle pairs exactly `expected` (sorted, n of them). */
static void check_curves(const DvhCurves *c, const DvhPair *expected, size_t n, int closed) {
    size_t curves = dvh_curves_curve_count(c), len = dvh_curves_len(c), dlen = dvh_curves_degenerate_len(c);
    const DvhCurveSegment *s = dvh_curves_data(c);
    const DvhDegeneratePair *d = dvh_curves_degenerate_data(c);
    size_t i, k, next = 0, first, count, found = 0;
    bool is_closed;
    CHECK(len + dlen == n);
    CHECK((len == 0) == (s == NULL) && (dlen == 0) == (d == NULL));
    for (i = 0; i < curves; i++) {
        CHECK_STATUS(dvh_curves_curve(c, i, &first, &count, &is_closed), DVH_STATUS_OK, NULL);
        CHECK(first == next && count > 0 && first + count <= len);
        if (first != next || count == 0 || first + count > len) return;
        if (closed) CHECK(is_closed);
        for (k = first; k < first + count; k++) {
            CHECK(s[k].curve == i && s[k].reserved == 0);
            if (k > first) CHECK(memcmp(s[k - 1].end, s[k].start, sizeof s[k].start) == 0);
        }
        if (is_closed) CHECK(memcmp(s[first + count - 1].end, s[first].start, sizeof s[first].start) == 0);
        next = first + count;
    }
    CHECK(next == len);
    for (i = 0; i < len; i++) {
        DvhPair p;
        p.a = s[i].triangle_a;
        p.b = s[i].triangle_b;
        found += contains(expected, n, p);
    }
    for (i = 0; i < dlen; i++) {
        DvhPair p;
        p.a = d[i].triangle_a;
        p.b = d[i].triangle_b;
        found += contains(expected, n, p);
        CHECK(d[i].reserved == 0 && (d[i].kind == DVH_DEGENERATE_KIND_POINT || d[i].kind == DVH_DEGENERATE_KIND_COPLANAR));
        if (i > 0) CHECK(d[i - 1].triangle_a < d[i].triangle_a || (d[i - 1].triangle_a == d[i].triangle_a && d[i - 1].triangle_b < d[i].triangle_b));
    }
    CHECK(found == n);
}

static void test_intersection_curves(void) {
    double pa[18], pb[18], both[36];
    uint32_t ta[24], tb[24], tboth[48];
    DvhMesh *a = NULL, *b = NULL, *one = NULL;
    DvhCurves *c = dvh_curves_new(), *c2 = dvh_curves_new();
    DvhPairs *pairs = dvh_pairs_new();
    DvhQueryStats stats, sentinel;
    DvhQueryOptions q;
    DvhPose shift;
    const DvhCurveSegment *s;
    size_t n, len, i, first = 7, count = 7;
    bool closed = false;
    int threads;
    DvhPair expected[64];

    octahedron(pa, ta, 0, 1.0, 0.0, 0.0, 0.0);
    octahedron(pb, tb, 0, 0.9, 0.61, 0.27, 0.13);
    CHECK_STATUS(dvh_mesh_create(pa, 6, ta, 8, NULL, &a), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_create(pb, 6, tb, 8, NULL, &b), DVH_STATUS_OK, NULL);
    CHECK(c != NULL && c2 != NULL && pairs != NULL);
    if (a == NULL || b == NULL || c == NULL || c2 == NULL || pairs == NULL) return;

    /* A new buffer is empty; NULL reads as empty. */
    CHECK(dvh_curves_len(c) == 0 && dvh_curves_data(c) == NULL && dvh_curves_curve_count(c) == 0);
    CHECK(dvh_curves_degenerate_len(NULL) == 0 && dvh_curves_degenerate_data(NULL) == NULL);

    /* Two closed surfaces in general position cross in closed curves, one segment or degenerate
       pair per pair dvh_collide reports, on every thread count. */
    CHECK_STATUS(dvh_collide(a, NULL, b, NULL, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
    n = dvh_pairs_len(pairs);
    CHECK(n > 3 && n <= 64);
    if (n > 64) return;
    memcpy(expected, dvh_pairs_data(pairs), n * sizeof *expected);
    for (threads = 0; threads < 3; threads++) {
        q = dvh_query_options_default();
        q.threads = (uint32_t)threads;
        CHECK_STATUS(dvh_intersection_curves(a, NULL, b, NULL, &q, c, &stats), DVH_STATUS_OK, NULL);
        CHECK(stats.pairs == n && !stats.truncated);
        CHECK(dvh_curves_degenerate_len(c) == 0 && dvh_curves_curve_count(c) >= 1);
        check_curves(c, expected, n, 1);
    }
    len = dvh_curves_len(c);

    /* Posed: the same as the mesh moved there (a translation by a power of two is exact). */
    memset(&shift, 0, sizeof shift);
    shift.rotation[0] = shift.rotation[4] = shift.rotation[8] = 1.0;
    shift.translation[0] = 0.5;
    {
        double moved[18];
        DvhMesh *m = NULL;
        for (i = 0; i < 18; i++) moved[i] = pb[i] + (i % 3 == 0 ? 0.5 : 0.0);
        CHECK_STATUS(dvh_mesh_create(moved, 6, tb, 8, NULL, &m), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_intersection_curves(a, NULL, b, &shift, NULL, c2, NULL), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_intersection_curves(a, NULL, m, NULL, NULL, c, NULL), DVH_STATUS_OK, NULL);
        CHECK(dvh_curves_len(c) == dvh_curves_len(c2) && dvh_curves_len(c) > 0);
        CHECK(memcmp(dvh_curves_data(c), dvh_curves_data(c2), dvh_curves_len(c) * sizeof(DvhCurveSegment)) == 0);
        dvh_mesh_free(m);
    }

    /* The two as one mesh: its self curves are the same segments, the second's triangles shifted. */
    memcpy(both, pa, sizeof pa);
    memcpy(both + 18, pb, sizeof pb);
    memcpy(tboth, ta, sizeof ta);
    for (i = 0; i < 24; i++) tboth[24 + i] = tb[i] + 6;
    CHECK_STATUS(dvh_mesh_create(both, 12, tboth, 16, NULL, &one), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_intersection_curves(a, NULL, b, NULL, NULL, c, NULL), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_self_intersection_curves(one, NULL, c2, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_curves_len(c2) == len && stats.pairs == n && dvh_curves_curve_count(c2) == dvh_curves_curve_count(c));
    s = dvh_curves_data(c2);
    for (i = 0; i < len && dvh_curves_len(c2) == len; i++) {
        const DvhCurveSegment *t = dvh_curves_data(c) + i;
        CHECK(s[i].triangle_a == t->triangle_a && s[i].triangle_b == t->triangle_b + 8 && s[i].curve == t->curve);
        CHECK(memcmp(s[i].start, t->start, sizeof t->start) == 0 && memcmp(s[i].end, t->end, sizeof t->end) == 0);
    }

    /* A copy: identical triangles are coplanar pairs, neighbours touch along shared edges. */
    CHECK_STATUS(dvh_intersection_curves(a, NULL, a, NULL, NULL, c2, &stats), DVH_STATUS_OK, NULL);
    {
        const DvhDegeneratePair *d = dvh_curves_degenerate_data(c2);
        size_t coplanar = 0;
        for (i = 0; i < dvh_curves_degenerate_len(c2); i++)
            coplanar += d[i].kind == DVH_DEGENERATE_KIND_COPLANAR && d[i].triangle_a == d[i].triangle_b;
        CHECK(coplanar == 8 && dvh_curves_len(c2) == 24);
    }

    /* max_pairs bounds segments plus degenerate pairs. */
    q = dvh_query_options_default();
    q.max_pairs = 2;
    CHECK_STATUS(dvh_intersection_curves(a, NULL, b, NULL, &q, c2, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_curves_len(c2) + dvh_curves_degenerate_len(c2) == 2 && stats.truncated && stats.pairs == 2);

    /* Errors name the culprit and change nothing. */
    CHECK_STATUS(dvh_intersection_curves(a, NULL, b, NULL, NULL, c, NULL), DVH_STATUS_OK, NULL);
    memset(&sentinel, 0xab, sizeof sentinel);
    stats = sentinel;
    q = dvh_query_options_default();
    q.mode = DVH_QUERY_MODE_LEAVES;
    CHECK_STATUS(dvh_intersection_curves(a, NULL, b, NULL, &q, c, &stats), DVH_STATUS_INVALID_ARGUMENT, "DVH_QUERY_MODE_TRIANGLES");
    q.mode = DVH_QUERY_MODE_FIRST_HIT;
    CHECK_STATUS(dvh_self_intersection_curves(one, &q, c, &stats), DVH_STATUS_INVALID_ARGUMENT, "triangles mode");
    q.mode = 42;
    CHECK_STATUS(dvh_intersection_curves(a, NULL, b, NULL, &q, c, &stats), DVH_STATUS_INVALID_ARGUMENT, "options->mode = 42");
    CHECK_STATUS(dvh_intersection_curves(NULL, NULL, b, NULL, NULL, c, &stats), DVH_STATUS_NULL_ARGUMENT, "argument `a` is NULL");
    CHECK_STATUS(dvh_intersection_curves(a, NULL, b, NULL, NULL, NULL, &stats), DVH_STATUS_NULL_ARGUMENT,
                 "argument `curves_out` is NULL");
    CHECK_STATUS(dvh_self_intersection_curves(NULL, NULL, c, &stats), DVH_STATUS_NULL_ARGUMENT, "argument `mesh` is NULL");
    shift.rotation[1] = 0.5;
    CHECK_STATUS(dvh_intersection_curves(a, NULL, b, &shift, NULL, c, &stats), DVH_STATUS_NON_RIGID_POSE, "pose_b");
    CHECK_STATUS(dvh_intersection_curves(a, NULL, b, NULL, NULL, (DvhCurves *)(void *)pairs, &stats), DVH_STATUS_INVALID_ARGUMENT,
                 "DvhCurves `curves_out` is not a live handle");
    CHECK_STATUS(dvh_collide(a, NULL, b, NULL, NULL, (DvhPairs *)(void *)c, &stats), DVH_STATUS_INVALID_ARGUMENT,
                 "DvhPairs `pairs_out` is not a live handle");
    CHECK(memcmp(&stats, &sentinel, sizeof stats) == 0);
    CHECK(dvh_curves_len(c) == len);
    check_curves(c, expected, n, 1);

    /* The length gradient: nonzero at the curves' triangles only, and its checks. */
    {
        double ga[18], gb[18], g_one[36], sentinel_g[18];
        size_t nonzero = 0;
        memset(ga, 0xab, sizeof ga);
        memcpy(sentinel_g, ga, sizeof ga);
        CHECK_STATUS(dvh_curves_length_gradient(c, a, NULL, b, NULL, ga, 6, gb, 6), DVH_STATUS_OK, NULL);
        for (i = 0; i < 18; i++) nonzero += ga[i] != 0.0 && gb[i] != 0.0;
        CHECK(nonzero > 0);
        memcpy(ga, sentinel_g, sizeof ga);
        CHECK_STATUS(dvh_curves_length_gradient(c, a, NULL, b, NULL, ga, 5, gb, 6), DVH_STATUS_INVALID_ARGUMENT, "has 6");
        CHECK_STATUS(dvh_curves_length_gradient(c, a, NULL, b, NULL, NULL, 6, gb, 6), DVH_STATUS_NULL_ARGUMENT, "gradient_a");
        CHECK_STATUS(dvh_curves_length_gradient(c, a, NULL, b, NULL, ga, 6, gb, SIZE_MAX), DVH_STATUS_INVALID_ARGUMENT, "gradient_b");
        CHECK_STATUS(dvh_curves_length_gradient(NULL, a, NULL, b, NULL, ga, 6, gb, 6), DVH_STATUS_NULL_ARGUMENT, "curves");
        CHECK_STATUS(dvh_curves_self_length_gradient(c, one, g_one, 12), DVH_STATUS_INVALID_ARGUMENT, "curves of two meshes");
        CHECK(memcmp(ga, sentinel_g, sizeof ga) == 0);
        CHECK_STATUS(dvh_self_intersection_curves(one, NULL, c2, NULL), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_curves_self_length_gradient(c2, one, g_one, 12), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_curves_length_gradient(c2, a, NULL, b, NULL, ga, 6, gb, 6), DVH_STATUS_INVALID_ARGUMENT, "self-intersection");
        CHECK_STATUS(dvh_curves_self_length_gradient(c2, a, ga, 6), DVH_STATUS_INVALID_ARGUMENT, "not this mesh's curves");
        /* The same gradient, the second mesh's part shifted. */
        CHECK_STATUS(dvh_curves_length_gradient(c, a, NULL, b, NULL, ga, 6, gb, 6), DVH_STATUS_OK, NULL);
        for (i = 0; i < 18; i++) CHECK(fabs(g_one[i] - ga[i]) <= 1e-12 && fabs(g_one[18 + i] - gb[i]) <= 1e-12);
    }

    /* The curve accessor: out of range, NULL out-pointers, not a buffer. */
    n = dvh_curves_curve_count(c);
    CHECK_STATUS(dvh_curves_curve(c, n, &first, &count, &closed), DVH_STATUS_INVALID_ARGUMENT, "out of range");
    CHECK_STATUS(dvh_curves_curve(c, (size_t)-1, &first, &count, &closed), DVH_STATUS_INVALID_ARGUMENT, "out of range");
    CHECK_STATUS(dvh_curves_curve(c, 0, NULL, &count, &closed), DVH_STATUS_NULL_ARGUMENT, "first_out");
    CHECK_STATUS(dvh_curves_curve(c, 0, &first, NULL, &closed), DVH_STATUS_NULL_ARGUMENT, "count_out");
    CHECK_STATUS(dvh_curves_curve(c, 0, &first, &count, NULL), DVH_STATUS_NULL_ARGUMENT, "closed_out");
    CHECK_STATUS(dvh_curves_curve(NULL, 0, &first, &count, &closed), DVH_STATUS_NULL_ARGUMENT, "curves");
    CHECK_STATUS(dvh_curves_curve((const DvhCurves *)(const void *)pairs, 0, &first, &count, &closed), DVH_STATUS_INVALID_ARGUMENT,
                 "not a live handle");
    CHECK(first == 7 && count == 7 && !closed);
    CHECK(dvh_curves_len((const DvhCurves *)(const void *)pairs) == 0);

    dvh_curves_free(NULL);
    dvh_curves_free(c);
    dvh_curves_free(c2);
    dvh_pairs_free(pairs);
    dvh_mesh_free(a);
    dvh_mesh_free(b);
    dvh_mesh_free(one);
}

/* An axis-aligned box [x0, x0 + w] x [0, w] x [0, w] of twelve outward triangles. */
static Mesh mesh_box(int x0, int w) {
    static const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    Mesh m = mesh_alloc(8, 12);
    int i;
    for (i = 0; i < 8; i++) {
        m.ipos[3 * i] = x0 + (i & 1) * w;
        m.ipos[3 * i + 1] = ((i >> 1) & 1) * w;
        m.ipos[3 * i + 2] = ((i >> 2) & 1) * w;
    }
    for (i = 0; i < 6; i++) {
        uint32_t *t = &m.tris[6 * i];
        t[0] = quads[i][0]; t[1] = quads[i][1]; t[2] = quads[i][2];
        t[3] = quads[i][0]; t[4] = quads[i][2]; t[5] = quads[i][3];
    }
    mesh_sync(&m);
    return m;
}

static void test_distances(void) {
    Mesh mb0 = mesh_box(0, 2), mb1 = mesh_box(5, 2), mb2 = mesh_box(1, 2), mt = mesh_terrain(3, 0, 0, flat);
    DvhMesh *b0 = create(&mb0, NULL), *b1 = create(&mb1, NULL), *b2 = create(&mb2, NULL), *open = create(&mt, NULL);
    DvhDistanceOptions o = dvh_distance_options_default();
    DvhDistance d, untouched;
    DvhQueryStats stats;
    bool closed = false;
    CHECK(isinf(o.max_distance) && o.rel_err == 0.0 && o.abs_err == 0.0 && o.threads == 0 && o.reserved == 0);

    CHECK_STATUS(dvh_mesh_is_closed(b0, &closed), DVH_STATUS_OK, NULL);
    CHECK(closed);
    CHECK_STATUS(dvh_mesh_is_closed(open, &closed), DVH_STATUS_OK, NULL);
    CHECK(!closed);
    CHECK_STATUS(dvh_mesh_is_closed(NULL, &closed), DVH_STATUS_NULL_ARGUMENT, "mesh");
    CHECK_STATUS(dvh_mesh_is_closed(b0, NULL), DVH_STATUS_NULL_ARGUMENT, "closed_out");

    /* Boxes [0, 2] and [5, 7] along x: 3 apart, face to face. */
    CHECK_STATUS(dvh_distance(b0, NULL, b1, NULL, NULL, &d, &stats), DVH_STATUS_OK, NULL);
    CHECK(d.found == 1 && d.intersecting == 0 && d.distance == 3.0);
    CHECK(d.closest_a[0] == 2.0 && d.closest_b[0] == 5.0 && d.stencil.distance == 3.0);
    CHECK(d.triangle_a < 12 && d.triangle_b < 12 && stats.bv_tests > 0);
    /* Posed: the second box moved back by 4 along x overlaps the first. */
    {
        DvhPose back = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {-4, 0, 0}};
        CHECK_STATUS(dvh_distance(b0, NULL, b1, &back, NULL, &d, NULL), DVH_STATUS_OK, NULL);
        CHECK(d.found == 1 && d.intersecting == 1 && d.distance == 0.0);
    }
    CHECK_STATUS(dvh_distance(b0, NULL, b2, NULL, NULL, &d, NULL), DVH_STATUS_OK, NULL);
    CHECK(d.found == 1 && d.intersecting == 1 && d.distance == 0.0 && d.stencil.kind == 0 && d.stencil.a0 == 0);
    /* Bounded below the distance: not found, every field zero. */
    o.max_distance = 2.5;
    CHECK_STATUS(dvh_distance(b0, NULL, b1, NULL, &o, &d, NULL), DVH_STATUS_OK, NULL);
    CHECK(d.found == 0 && d.distance == 0.0 && d.triangle_a == 0);
    o.max_distance = 3.0;
    CHECK_STATUS(dvh_distance(b0, NULL, b1, NULL, &o, &d, NULL), DVH_STATUS_OK, NULL);
    CHECK(d.found == 1 && d.distance == 3.0);
    /* Errors change nothing. */
    untouched = d;
    o.max_distance = -1.0;
    CHECK_STATUS(dvh_distance(b0, NULL, b1, NULL, &o, &d, NULL), DVH_STATUS_INVALID_ARGUMENT, "max_distance");
    o = dvh_distance_options_default();
    o.rel_err = NAN;
    CHECK_STATUS(dvh_distance(b0, NULL, b1, NULL, &o, &d, NULL), DVH_STATUS_INVALID_ARGUMENT, "rel_err");
    o = dvh_distance_options_default();
    o.reserved = 1;
    CHECK_STATUS(dvh_distance(b0, NULL, b1, NULL, &o, &d, NULL), DVH_STATUS_INVALID_ARGUMENT, "reserved");
    o = dvh_distance_options_default();
    CHECK_STATUS(dvh_distance(NULL, NULL, b1, NULL, &o, &d, NULL), DVH_STATUS_NULL_ARGUMENT, "`a`");
    CHECK_STATUS(dvh_distance(b0, NULL, b1, NULL, &o, NULL, NULL), DVH_STATUS_NULL_ARGUMENT, "distance_out");
    CHECK(memcmp(&d, &untouched, sizeof d) == 0);

    /* Points: inside, outside, on a face, on an edge, on a corner; rays from them run along
     * the box's faces and edges. */
    {
        const double points[] = {1, 1, 1, 1.5, 0.5, 5, 2, 1, 1, 2, 2, 1, 0, 0, 0, -1, 0, 0, 1, 0, 2.5, 3, 3, 3};
        const double expected_distance[] = {1, 3, 0, 0, 0, 1, 0.5, sqrt(3.0)};
        const int32_t expected_winding[] = {1, 0, DVH_WINDING_ON_SURFACE, DVH_WINDING_ON_SURFACE,
                                            DVH_WINDING_ON_SURFACE, 0, 0, 0};
        DvhClosestPoint c[8];
        int32_t w[8];
        double sd[8];
        size_t i, n = 8;
        CHECK_STATUS(dvh_closest_points(b0, NULL, points, n, NULL, c, &stats), DVH_STATUS_OK, NULL);
        CHECK(stats.pairs == n);
        for (i = 0; i < n; i++) {
            CHECK(c[i].found == 1 && c[i].triangle < 12 && c[i].feature <= DVH_FEATURE_INTERIOR);
            CHECK(c[i].distance == expected_distance[i]);
        }
        CHECK(c[1].point[0] == 1.5 && c[1].point[1] == 0.5 && c[1].point[2] == 2.0 && c[1].feature == DVH_FEATURE_INTERIOR);
        CHECK(c[7].feature <= DVH_FEATURE_VERTEX_2 && c[7].point[0] == 2.0);
        CHECK_STATUS(dvh_winding_numbers(b0, NULL, points, n, 0, w), DVH_STATUS_OK, NULL);
        for (i = 0; i < n; i++) CHECK(w[i] == expected_winding[i]);
        CHECK_STATUS(dvh_signed_distances(b0, NULL, points, n, NULL, sd, &stats), DVH_STATUS_OK, NULL);
        for (i = 0; i < n; i++)
            CHECK(sd[i] == (expected_winding[i] == 1 ? -expected_distance[i] : expected_distance[i]));
        /* Posed: the box moved by 10 along y. */
        {
            DvhPose up = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 10, 0}};
            const double p[] = {1, 11, 1, 1, 1, 1};
            CHECK_STATUS(dvh_winding_numbers(b0, &up, p, 2, 1, w), DVH_STATUS_OK, NULL);
            CHECK(w[0] == 1 && w[1] == 0);
            CHECK_STATUS(dvh_closest_points(b0, &up, p, 2, NULL, c, NULL), DVH_STATUS_OK, NULL);
            CHECK(c[0].distance == 1.0 && c[1].distance == 9.0);
        }
        /* Bounded: beyond it, not found and an infinity of the point's sign. */
        o.max_distance = 0.75;
        CHECK_STATUS(dvh_closest_points(b0, NULL, points, n, &o, c, &stats), DVH_STATUS_OK, NULL);
        CHECK(c[0].found == 0 && c[1].found == 0 && c[2].found == 1 && c[6].found == 1 && stats.pairs == 4);
        CHECK_STATUS(dvh_signed_distances(b0, NULL, points, n, &o, sd, NULL), DVH_STATUS_OK, NULL);
        CHECK(isinf(sd[0]) && sd[0] < 0 && isinf(sd[1]) && sd[1] > 0 && sd[6] == 0.5);
        o = dvh_distance_options_default();
        /* Errors: a NaN point named with its axis, an open mesh, NULL arrays; nothing written. */
        {
            double bad[] = {0, 0, 0, 1, NAN, 1};
            int32_t before = w[0];
            CHECK_STATUS(dvh_winding_numbers(b0, NULL, bad, 2, 0, w), DVH_STATUS_NON_FINITE_COORDINATE, "point 1");
            CHECK_STATUS(dvh_closest_points(b0, NULL, bad, 2, NULL, c, NULL), DVH_STATUS_NON_FINITE_COORDINATE, "y = NaN");
            CHECK_STATUS(dvh_signed_distances(b0, NULL, bad, 2, NULL, sd, NULL), DVH_STATUS_NON_FINITE_COORDINATE, "point 1");
            CHECK_STATUS(dvh_winding_numbers(open, NULL, points, 2, 0, w), DVH_STATUS_NOT_CLOSED, "not closed");
            CHECK_STATUS(dvh_signed_distances(open, NULL, points, 2, NULL, sd, NULL), DVH_STATUS_NOT_CLOSED, "edge from vertex");
            CHECK(w[0] == before);
            CHECK_STATUS(dvh_winding_numbers(b0, NULL, NULL, 2, 0, w), DVH_STATUS_NULL_ARGUMENT, "points");
            CHECK_STATUS(dvh_closest_points(b0, NULL, points, 2, NULL, NULL, NULL), DVH_STATUS_NULL_ARGUMENT, "results_out");
            CHECK_STATUS(dvh_signed_distances(NULL, NULL, points, 2, NULL, sd, NULL), DVH_STATUS_NULL_ARGUMENT, "mesh");
            CHECK(strcmp(dvh_status_name(DVH_STATUS_NOT_CLOSED), "DVH_STATUS_NOT_CLOSED") == 0);
        }
    }

    /* A scene of the three boxes: b0 and b2 intersect; excluded, the closest pair is b2, b1. */
    {
        DvhScene *scene = NULL;
        uint32_t ia, ib, i0, i1, i2, other;
        CHECK_STATUS(dvh_scene_create(&scene), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_scene_add_rigid(scene, b0, NULL, 1, 0xffffffffu, &i0), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_scene_add_rigid(scene, b1, NULL, 1, 0xffffffffu, &i1), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_scene_add_rigid(scene, b2, NULL, 1, 0xffffffffu, &i2), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_scene_distance(scene, NULL, &ia, &ib, &d), DVH_STATUS_OK, NULL);
        CHECK(ia == i0 && ib == i2 && d.intersecting == 1);
        CHECK_STATUS(dvh_scene_exclude_pair(scene, i0, i2), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_scene_distance(scene, NULL, &ia, &ib, &d), DVH_STATUS_OK, NULL);
        CHECK(ia == i1 && ib == i2 && d.found == 1 && d.distance == 2.0);
        CHECK_STATUS(dvh_scene_object_distance(scene, i1, NULL, &other, &d), DVH_STATUS_OK, NULL);
        CHECK(other == i2 && d.distance == 2.0 && d.closest_a[0] == 5.0);
        o.max_distance = 1.0;
        CHECK_STATUS(dvh_scene_object_distance(scene, i1, &o, &other, &d), DVH_STATUS_OK, NULL);
        CHECK(other == 0xffffffffu && d.found == 0);
        CHECK_STATUS(dvh_scene_distance(scene, &o, &ia, &ib, &d), DVH_STATUS_OK, NULL);
        CHECK(ia == 0xffffffffu && ib == 0xffffffffu && d.found == 0);
        o = dvh_distance_options_default();
        CHECK_STATUS(dvh_scene_object_distance(scene, 99, NULL, &other, &d), DVH_STATUS_INVALID_ARGUMENT, "object 99");
        CHECK_STATUS(dvh_scene_distance(scene, NULL, NULL, &ib, &d), DVH_STATUS_NULL_ARGUMENT, "object_a_out");
        CHECK_STATUS(dvh_scene_object_distance(NULL, 0, NULL, &other, &d), DVH_STATUS_NULL_ARGUMENT, "scene");
        dvh_scene_free(scene);
    }
    dvh_mesh_free(b0);
    dvh_mesh_free(b1);
    dvh_mesh_free(b2);
    dvh_mesh_free(open);
    mesh_free(&mb0);
    mesh_free(&mb1);
    mesh_free(&mb2);
    mesh_free(&mt);
}

int main(void) {
    test_versions_and_names();
    test_defaults();
    test_last_error_message();
    test_create_errors();
    test_accessors();
    test_f32_stride_and_refit();
    test_collide_errors();
    test_triangle_test();
    test_against_oracle();
    test_scene();
    test_scene_lazy();
    test_self_collide();
    test_proximity();
    test_ccd_primitives();
    test_continuous_collide();
    test_continuous_terrains();
    test_self_continuous_collide();
    test_nearest_features();
    test_scene_continuous();
    test_scene_continuous_oracle();
    test_scene_self_contact();
    test_scene_nearest();
    test_intersection_curves();
    test_distances();
    return finish("test_api");
}
