/*
 * Several threads query the same meshes at once, each with its own DvhPairs, and must get the
 * single-threaded answers; each thread's last error message is its own. One query and one refit
 * shared out over the library's threads (DvhQueryOptions.threads, DvhBuildOptions.refit_threads)
 * give the answers of the calling thread alone, pair for pair.
 */
#include <pthread.h>
#include <time.h>

#include "common.h"

#define THREADS 4
#define POSES 24

static int bumpy(int i, int j) { return ((i * 7 + j * 3) % 5) - 2; }
static int hill(int i, int j) { return (i + j) % 3; }

typedef struct Shared {
    const DvhMesh *a, *b;
    DvhPose poses[POSES];
    DvhPair *expected[POSES];
    size_t counts[POSES];
} Shared;

typedef struct Work {
    const Shared *shared;
    int id;
    int mismatches;
    int message_leaks;
} Work;

static void *worker(void *arg) {
    Work *w = arg;
    DvhPairs *pairs = dvh_pairs_new();
    int round, k;
    char message[128];
    if (pairs == NULL) {
        w->mismatches++;
        return NULL;
    }
    for (round = 0; round < 20; round++)
        for (k = (w->id + round) % 3; k < POSES; k++) {
            const DvhPair *data;
            size_t n, i;
            /* Odd workers also fail on purpose: their messages must not reach the others. */
            if (w->id % 2 == 1 && dvh_collide(NULL, NULL, w->shared->b, NULL, NULL, pairs, NULL) != DVH_STATUS_NULL_ARGUMENT)
                w->mismatches++;
            if (dvh_collide(w->shared->a, NULL, w->shared->b, &w->shared->poses[k], NULL, pairs, NULL) != DVH_STATUS_OK) {
                w->mismatches++;
                continue;
            }
            if (dvh_last_error_message(message, sizeof message) != 0) w->message_leaks++;
            n = dvh_pairs_len(pairs);
            data = dvh_pairs_data(pairs);
            if (n != w->shared->counts[k]) {
                w->mismatches++;
                continue;
            }
            for (i = 0; i < n; i++)
                if (data[i].a != w->shared->expected[k][i].a || data[i].b != w->shared->expected[k][i].b) {
                    w->mismatches++;
                    break;
                }
        }
    dvh_pairs_free(pairs);
    return NULL;
}

static int wavy(int i, int j) { return ((i * 5 + j * 11) % 7) - 3; }
static int slope(int i, int j) { return (i + 2 * j) % 5 - 2; }

/* Terrains of 33,800 triangles and 17,161 vertices each, in dense contact: large enough for the
 * library to share a query and a refit out. */
static void test_one_query_on_many_threads(void) {
    const int n = 130;
    Mesh ma = mesh_terrain(n, 0, 0, wavy), mb = mesh_terrain(n, 0, 0, slope);
    const uint32_t modes[] = {DVH_QUERY_MODE_TRIANGLES, DVH_QUERY_MODE_FIRST_HIT, DVH_QUERY_MODE_LEAVES,
                              DVH_QUERY_MODE_DEPTH, DVH_QUERY_MODE_TRIANGLES};
    const uint32_t query_threads[] = {0, 2, 3};
    const uint32_t refit_threads[] = {1, 0};
    DvhPair *expected[5];
    size_t counts[5], m, r, t, i;
    DvhPairs *pairs = dvh_pairs_new();
    double *moved = malloc(mb.vertex_count * 3 * sizeof *moved);
    for (i = 0; i < mb.vertex_count * 3; i++) moved[i] = mb.pos[i] + ((i % 3 == 2) ? 0.25 * (double)(i % 5) : 0.0);
    for (r = 0; r < 2; r++) {
        DvhBuildOptions o = dvh_build_options_default();
        DvhMesh *a = NULL, *b = NULL;
        o.refit_threads = refit_threads[r];
        CHECK_STATUS(dvh_mesh_create(ma.pos, ma.vertex_count, ma.tris, ma.triangle_count, &o, &a), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_mesh_create(mb.pos, mb.vertex_count, mb.tris, mb.triangle_count, &o, &b), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_mesh_refit(b, moved, mb.vertex_count), DVH_STATUS_OK, NULL);
        CHECK_STATUS(dvh_mesh_validate(b), DVH_STATUS_OK, NULL);
        for (m = 0; m < 5; m++) {
            DvhQueryOptions q = dvh_query_options_default();
            DvhQueryStats one, many;
            q.mode = modes[m];
            q.max_depth = 4;
            if (m == 4) q.max_pairs = 1000; /* cut short: the same first 1000 pairs */
            q.threads = 1;
            CHECK_STATUS(dvh_collide(a, NULL, b, NULL, &q, pairs, &one), DVH_STATUS_OK, NULL);
            if (r == 0) {
                /* The reference: one thread for the refit and the query. */
                counts[m] = dvh_pairs_len(pairs);
                expected[m] = malloc((counts[m] + 1) * sizeof(DvhPair));
                if (counts[m] > 0) memcpy(expected[m], dvh_pairs_data(pairs), counts[m] * sizeof(DvhPair));
            } else {
                CHECK(dvh_pairs_len(pairs) == counts[m]);
                CHECK(counts[m] == 0 || memcmp(dvh_pairs_data(pairs), expected[m], counts[m] * sizeof(DvhPair)) == 0);
            }
            CHECK(m == 1 || counts[m] >= 1000); /* dense contact: worth sharing out */
            for (t = 0; t < 3; t++) {
                q.threads = query_threads[t];
                CHECK_STATUS(dvh_collide(a, NULL, b, NULL, &q, pairs, &many), DVH_STATUS_OK, NULL);
                CHECK(dvh_pairs_len(pairs) == counts[m]);
                CHECK(counts[m] == 0 || memcmp(dvh_pairs_data(pairs), expected[m], counts[m] * sizeof(DvhPair)) == 0);
                CHECK(many.pairs == one.pairs && many.truncated == one.truncated);
                if (!one.truncated && modes[m] != DVH_QUERY_MODE_FIRST_HIT)
                    CHECK(many.bv_tests == one.bv_tests && many.triangle_tests == one.triangle_tests &&
                          many.leaf_pairs == one.leaf_pairs);
            }
        }
        dvh_mesh_free(a);
        dvh_mesh_free(b);
    }
    for (m = 0; m < 5; m++) free(expected[m]);
    free(moved);
    dvh_pairs_free(pairs);
    mesh_free(&ma);
    mesh_free(&mb);
}

/* Misuse from C, detected: a refit of a mesh while queries on it run on another thread, two
 * threads sharing one result buffer, two scene queries at once. Each late call is refused with
 * DVH_STATUS_BUSY and a message naming the call and the argument, and touches nothing: every
 * query that succeeds still gives the answer of a quiet run. */
typedef struct Busy {
    const DvhMesh *mesh;
    DvhPairs *pairs; /* shared by both query threads */
    DvhScene *scene;
    size_t expected;
    int stop;
    int wrong, busy, ok;
} Busy;

static void *query_until_stopped(void *arg) {
    Busy *b = arg;
    while (!__atomic_load_n(&b->stop, __ATOMIC_RELAXED)) {
        DvhStatus s = dvh_self_proximity(b->mesh, 1.0, NULL, b->pairs, NULL);
        if (s == DVH_STATUS_OK) {
            __atomic_fetch_add(&b->ok, 1, __ATOMIC_RELAXED);
            /* Both threads ask the same question: whoever wrote last wrote this answer. */
            if (dvh_pairs_len(b->pairs) != b->expected && dvh_pairs_len(b->pairs) != 0)
                __atomic_fetch_add(&b->wrong, 1, __ATOMIC_RELAXED);
        } else if (s == DVH_STATUS_BUSY) {
            char message[256];
            dvh_last_error_message(message, sizeof message);
            if (strstr(message, "dvh_self_proximity: ") != message || strstr(message, "is busy") == NULL)
                __atomic_fetch_add(&b->wrong, 1, __ATOMIC_RELAXED);
            __atomic_fetch_add(&b->busy, 1, __ATOMIC_RELAXED);
        } else {
            __atomic_fetch_add(&b->wrong, 1, __ATOMIC_RELAXED);
        }
    }
    return NULL;
}

static void *scene_until_stopped(void *arg) {
    Busy *b = arg;
    DvhContacts *contacts = dvh_contacts_new();
    while (!__atomic_load_n(&b->stop, __ATOMIC_RELAXED)) {
        DvhStatus s = dvh_scene_collide(b->scene, NULL, contacts, NULL);
        if (s == DVH_STATUS_BUSY)
            __atomic_fetch_add(&b->busy, 1, __ATOMIC_RELAXED);
        else if (s != DVH_STATUS_OK)
            __atomic_fetch_add(&b->wrong, 1, __ATOMIC_RELAXED);
    }
    dvh_contacts_free(contacts);
    return NULL;
}

static void test_misuse_is_refused(void) {
    Mesh m = mesh_terrain(60, 0, 0, wavy);
    DvhMesh *mesh = NULL;
    DvhPairs *pairs = dvh_pairs_new();
    Busy b;
    pthread_t q[2];
    int t, refits_busy = 0, refits_ok = 0;
    int interleaved = getenv("DVH_ONE_THREAD_AT_A_TIME") == NULL;
    time_t start, limit = interleaved ? 20 : 2;
    char message[256];
    uint32_t object;

    CHECK_STATUS(dvh_mesh_create(m.pos, m.vertex_count, m.tris, m.triangle_count, NULL, &mesh), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_self_proximity(mesh, 1.0, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
    memset(&b, 0, sizeof b);
    b.mesh = mesh;
    b.pairs = pairs;
    b.expected = dvh_pairs_len(pairs);
    CHECK(b.expected > 0);
    for (t = 0; t < 2; t++) CHECK(pthread_create(&q[t], NULL, query_until_stopped, &b) == 0);
    /* Refits to the same positions: whichever gets in, the answer does not change. */
    start = time(NULL);
    while (time(NULL) - start < limit &&
           (refits_busy == 0 || refits_ok == 0 || __atomic_load_n(&b.busy, __ATOMIC_RELAXED) == 0)) {
        DvhStatus s = dvh_mesh_refit(mesh, m.pos, m.vertex_count);
        if (s == DVH_STATUS_BUSY) {
            dvh_last_error_message(message, sizeof message);
            CHECK(strstr(message, "dvh_mesh_refit: DvhMesh `mesh` is busy") == message);
            refits_busy++;
        } else {
            CHECK(s == DVH_STATUS_OK);
            refits_ok++;
        }
    }
    __atomic_store_n(&b.stop, 1, __ATOMIC_RELAXED);
    for (t = 0; t < 2; t++) CHECK(pthread_join(q[t], NULL) == 0);
    /* Valgrind runs one thread at a time: calls may then never overlap. */
    CHECK(interleaved == 0 || (refits_busy > 0 && refits_ok > 0 && b.busy > 0 && b.ok > 0));
    CHECK(b.wrong == 0);
    CHECK_STATUS(dvh_self_proximity(mesh, 1.0, NULL, pairs, NULL), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == b.expected);

    /* Two threads querying one scene: the late one is refused. */
    memset(&b, 0, sizeof b);
    CHECK_STATUS(dvh_scene_create(&b.scene), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_add_deformable(b.scene, mesh, 1, 1, &object), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_scene_add_deformable(b.scene, mesh, 1, 1, &object), DVH_STATUS_OK, NULL);
    for (t = 0; t < 2; t++) CHECK(pthread_create(&q[t], NULL, scene_until_stopped, &b) == 0);
    start = time(NULL);
    while (time(NULL) - start < limit && __atomic_load_n(&b.busy, __ATOMIC_RELAXED) == 0) {
        DvhStatus s = dvh_scene_set_positions(b.scene, object, m.pos, m.vertex_count);
        if (s == DVH_STATUS_BUSY) __atomic_fetch_add(&b.busy, 1, __ATOMIC_RELAXED);
        else CHECK(s == DVH_STATUS_OK);
    }
    __atomic_store_n(&b.stop, 1, __ATOMIC_RELAXED);
    for (t = 0; t < 2; t++) CHECK(pthread_join(q[t], NULL) == 0);
    CHECK(interleaved == 0 || b.busy > 0);
    CHECK(b.wrong == 0);
    dvh_scene_free(b.scene);
    dvh_pairs_free(pairs);
    dvh_mesh_free(mesh);
    mesh_free(&m);
}

int main(void) {
    Mesh ma = mesh_terrain(12, 0, 0, bumpy), mb = mesh_terrain(8, 0, 0, hill);
    DvhMesh *a = NULL, *b = NULL;
    Shared shared;
    Work work[THREADS];
    pthread_t threads[THREADS];
    DvhPairs *pairs = dvh_pairs_new();
    int k, t, total = 0;

    CHECK_STATUS(dvh_mesh_create(ma.pos, ma.vertex_count, ma.tris, ma.triangle_count, NULL, &a), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_create(mb.pos, mb.vertex_count, mb.tris, mb.triangle_count, NULL, &b), DVH_STATUS_OK, NULL);
    shared.a = a;
    shared.b = b;
    for (k = 0; k < POSES; k++) {
        IPose ip = ipose_make(k, 2 + k % 4, 1 + k % 3, 0);
        DvhPair *oracle;
        size_t n = brute_force(&ma, NULL, &mb, &ip, &oracle);
        shared.poses[k] = ipose_to_dvh(&ip);
        CHECK_STATUS(dvh_collide(a, NULL, b, &shared.poses[k], NULL, pairs, NULL), DVH_STATUS_OK, NULL);
        shared.counts[k] = dvh_pairs_len(pairs);
        CHECK(shared.counts[k] == n);
        shared.expected[k] = malloc((n > 0 ? n : 1) * sizeof(DvhPair));
        if (n > 0) memcpy(shared.expected[k], dvh_pairs_data(pairs), n * sizeof(DvhPair));
        CHECK(n == 0 || memcmp(shared.expected[k], oracle, n * sizeof(DvhPair)) == 0);
        total += (int)n;
        free(oracle);
    }
    CHECK(total > 0);
    for (t = 0; t < THREADS; t++) {
        work[t].shared = &shared;
        work[t].id = t;
        work[t].mismatches = 0;
        work[t].message_leaks = 0;
        CHECK(pthread_create(&threads[t], NULL, worker, &work[t]) == 0);
    }
    for (t = 0; t < THREADS; t++) {
        CHECK(pthread_join(threads[t], NULL) == 0);
        CHECK(work[t].mismatches == 0);
        CHECK(work[t].message_leaks == 0);
    }
    for (k = 0; k < POSES; k++) free(shared.expected[k]);
    dvh_pairs_free(pairs);
    dvh_mesh_free(a);
    dvh_mesh_free(b);
    mesh_free(&ma);
    mesh_free(&mb);
    test_one_query_on_many_threads();
    test_misuse_is_refused();
    return finish("test_threads");
}
