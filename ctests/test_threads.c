/*
 * Several threads query the same meshes at once, each with its own DvhPairs, and must get the
 * single-threaded answers; each thread's last error message is its own.
 */
#include <pthread.h>

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
    return finish("test_threads");
}
