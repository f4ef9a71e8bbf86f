/*
 * Out of memory is a status, not a crash: with the address space limited (setrlimit), building a
 * mesh too large for it, and a query whose result cannot grow, both fail with
 * DVH_STATUS_OUT_OF_MEMORY and change nothing; with the limit lifted they succeed. Run without
 * sanitizers or valgrind, which reserve address space of their own.
 */
#include <sys/resource.h>

#include "common.h"

static size_t address_space_in_use(void) {
    unsigned long pages = 0;
    FILE *f = fopen("/proc/self/statm", "r");
    if (f == NULL || fscanf(f, "%lu", &pages) != 1) {
        fprintf(stderr, "cannot read /proc/self/statm\n");
        exit(2);
    }
    fclose(f);
    return (size_t)pages * 4096u;
}

static void limit_address_space(size_t bytes) {
    struct rlimit r;
    CHECK(getrlimit(RLIMIT_AS, &r) == 0);
    r.rlim_cur = bytes == 0 ? r.rlim_max : (rlim_t)bytes;
    CHECK(setrlimit(RLIMIT_AS, &r) == 0);
}

static int flat(int i, int j) { (void)i; (void)j; return 0; }

int main(void) {
    /* 2 million triangles: the build needs far more than the 48 MiB it will be allowed. */
    Mesh big = mesh_terrain(1000, 0, 0, flat);
    DvhMesh *mesh = (DvhMesh *)&big, *sentinel = mesh;
    DvhPairs *pairs = dvh_pairs_new();
    DvhQueryOptions q = dvh_query_options_default();
    DvhQueryStats stats;
    Mesh point;
    DvhMesh *pa = NULL, *pb = NULL;
    size_t i, before;

    limit_address_space(address_space_in_use() + ((size_t)48 << 20));
    CHECK_STATUS(dvh_mesh_create(big.pos, big.vertex_count, big.tris, big.triangle_count, NULL, &mesh), DVH_STATUS_OUT_OF_MEMORY,
                 "out of memory");
    CHECK(mesh == sentinel);
    limit_address_space(0);
    CHECK_STATUS(dvh_mesh_create(big.pos, big.vertex_count, big.tris, big.triangle_count, NULL, &mesh), DVH_STATUS_OK, NULL);
    dvh_mesh_free(mesh);
    mesh_free(&big);

    /* 2,500 triangles all at one point: 6.25 million intersecting pairs, 50 MB of results. */
    point = mesh_alloc(3, 2500);
    for (i = 0; i < 2500; i++) {
        point.tris[3 * i] = 0;
        point.tris[3 * i + 1] = 1;
        point.tris[3 * i + 2] = 2;
    }
    mesh_sync(&point);
    CHECK_STATUS(dvh_mesh_create(point.pos, 3, point.tris, 2500, NULL, &pa), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_mesh_create(point.pos, 3, point.tris, 100, NULL, &pb), DVH_STATUS_OK, NULL);
    CHECK_STATUS(dvh_collide(pa, NULL, pb, NULL, NULL, pairs, &stats), DVH_STATUS_OK, NULL);
    before = dvh_pairs_len(pairs);
    CHECK(before == 250000);
    limit_address_space(address_space_in_use() + ((size_t)16 << 20));
    CHECK_STATUS(dvh_collide(pa, NULL, pa, NULL, NULL, pairs, &stats), DVH_STATUS_OUT_OF_MEMORY, "out of memory");
    CHECK(dvh_pairs_len(pairs) == before);
    /* A bounded query still runs under the limit. */
    q.max_pairs = 1000;
    CHECK_STATUS(dvh_collide(pa, NULL, pa, NULL, &q, pairs, &stats), DVH_STATUS_OK, NULL);
    CHECK(dvh_pairs_len(pairs) == 1000 && stats.truncated);
    limit_address_space(0);

    dvh_pairs_free(pairs);
    dvh_mesh_free(pa);
    dvh_mesh_free(pb);
    mesh_free(&point);
    return finish("test_oom");
}
