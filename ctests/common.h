/*
 * Shared helpers of the C tests: checks that report where they failed, small meshes with integer
 * coordinates, exact rigid poses, and an independent brute-force oracle.
 *
 * The oracle decides whether two closed triangles with integer coordinates intersect by looking
 * for a separating direction: they are disjoint iff the origin is outside the convex hull of the
 * nine differences p - q, iff the direction from the origin to the nearest point of that hull
 * separates strictly; that direction is the origin's projection on the affine hull of one, two
 * or three differences, so trying all of them is complete. Coordinates stay within +-16, so every
 * product fits in 64 bits.
 */
#ifndef DVH_CTESTS_COMMON_H
#define DVH_CTESTS_COMMON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dvh.h"

static int failures = 0;

#define CHECK(cond)                                                                \
    do {                                                                           \
        if (!(cond)) {                                                             \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
            failures++;                                                            \
        }                                                                          \
    } while (0)

/* The call returned `expected`, and the last error message contains `needle` (or is empty for
 * DVH_STATUS_OK). */
#define CHECK_STATUS(call, expected, needle) check_status((call), (expected), (needle), __FILE__, __LINE__, #call)

static inline void check_status(DvhStatus got, DvhStatus expected, const char *needle, const char *file, int line,
                         const char *what) {
    char message[512];
    size_t len = dvh_last_error_message(message, sizeof message);
    if (got != expected) {
        fprintf(stderr, "%s:%d: %s returned %s, expected %s (message: %s)\n", file, line, what,
                dvh_status_name(got), dvh_status_name(expected), message);
        failures++;
        return;
    }
    if (expected == DVH_STATUS_OK && len != 0) {
        fprintf(stderr, "%s:%d: %s succeeded but left the message \"%s\"\n", file, line, what, message);
        failures++;
    }
    if (needle != NULL && strstr(message, needle) == NULL) {
        fprintf(stderr, "%s:%d: %s: message \"%s\" lacks \"%s\"\n", file, line, what, message, needle);
        failures++;
    }
}

static inline int finish(const char *name) {
    if (failures != 0) {
        fprintf(stderr, "%s: %d check(s) failed\n", name, failures);
        return 1;
    }
    printf("%s: all checks passed\n", name);
    return 0;
}

/* ---- meshes with small integer coordinates ---- */

typedef struct Mesh {
    size_t vertex_count, triangle_count;
    int64_t *ipos;      /* 3 per vertex */
    double *pos;        /* the same as doubles */
    uint32_t *tris;     /* 3 per triangle */
} Mesh;

static inline Mesh mesh_alloc(size_t vertices, size_t triangles) {
    Mesh m;
    m.vertex_count = vertices;
    m.triangle_count = triangles;
    m.ipos = calloc(vertices * 3, sizeof *m.ipos);
    m.pos = calloc(vertices * 3, sizeof *m.pos);
    m.tris = calloc(triangles * 3, sizeof *m.tris);
    if (m.ipos == NULL || m.pos == NULL || m.tris == NULL) {
        fprintf(stderr, "out of memory in the test\n");
        exit(2);
    }
    return m;
}

static inline void mesh_free(Mesh *m) {
    free(m->ipos);
    free(m->pos);
    free(m->tris);
}

static inline void mesh_sync(Mesh *m) {
    size_t i;
    for (i = 0; i < m->vertex_count * 3; i++) m->pos[i] = (double)m->ipos[i];
}

/* A height field over an n x n grid: z = heights(i, j); two triangles per cell. */
static inline Mesh mesh_terrain(int n, int x0, int y0, int (*height)(int, int)) {
    Mesh m = mesh_alloc((size_t)((n + 1) * (n + 1)), (size_t)(2 * n * n));
    int i, j;
    size_t t = 0;
    for (j = 0; j <= n; j++)
        for (i = 0; i <= n; i++) {
            int64_t *p = &m.ipos[3 * (size_t)(j * (n + 1) + i)];
            p[0] = x0 + i;
            p[1] = y0 + j;
            p[2] = height(i, j);
        }
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)n + 2, d = a + (uint32_t)n + 1;
            uint32_t *q = &m.tris[3 * t];
            q[0] = a; q[1] = b; q[2] = c;
            q[3] = a; q[4] = c; q[5] = d;
            t += 2;
        }
    mesh_sync(&m);
    return m;
}

static uint64_t lcg_state = 12345;
static inline int lcg_below(int n) {
    lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (int)((lcg_state >> 33) % (uint64_t)n);
}

/* Independent random triangles with coordinates in [lo, lo + span]; some repeat a corner. */
static inline Mesh mesh_soup(size_t count, int lo, int span) {
    Mesh m = mesh_alloc(count * 3, count);
    size_t t;
    int k;
    for (t = 0; t < count; t++) {
        for (k = 0; k < 9; k++) m.ipos[9 * t + (size_t)k] = lo + lcg_below(span + 1);
        if (t % 7 == 0) memcpy(&m.ipos[9 * t + 6], &m.ipos[9 * t], 3 * sizeof(int64_t));
        m.tris[3 * t] = (uint32_t)(3 * t);
        m.tris[3 * t + 1] = (uint32_t)(3 * t + 1);
        m.tris[3 * t + 2] = (uint32_t)(3 * t + 2);
    }
    mesh_sync(&m);
    return m;
}

/* ---- exact rigid poses: signed axis permutations with determinant +1, integer translations ---- */

typedef struct IPose {
    int r[9];
    int t[3];
} IPose;

/* The k-th of the 24 rotations of the cube (k in 0..23). */
static inline IPose ipose_make(int k, int tx, int ty, int tz) {
    static const int perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
    IPose p;
    const int *perm = perms[(k / 4) % 6];
    int parity = (k / 4) % 6 >= 3 ? -1 : 1;
    int s0 = (k & 1) ? -1 : 1, s1 = (k & 2) ? -1 : 1, s2 = s0 * s1 * parity; /* determinant +1 */
    int signs[3];
    int i;
    signs[0] = s0;
    signs[1] = s1;
    signs[2] = s2;
    memset(p.r, 0, sizeof p.r);
    for (i = 0; i < 3; i++) p.r[3 * i + perm[i]] = signs[i];
    p.t[0] = tx;
    p.t[1] = ty;
    p.t[2] = tz;
    return p;
}

static inline DvhPose ipose_to_dvh(const IPose *p) {
    DvhPose d;
    int i;
    for (i = 0; i < 9; i++) d.rotation[i] = (double)p->r[i];
    for (i = 0; i < 3; i++) d.translation[i] = (double)p->t[i];
    return d;
}

static inline void ipose_apply(const IPose *p, const int64_t in[3], int64_t out[3]) {
    int i;
    for (i = 0; i < 3; i++)
        out[i] = p->r[3 * i] * in[0] + p->r[3 * i + 1] * in[1] + p->r[3 * i + 2] * in[2] + p->t[i];
}

/* ---- the oracle ---- */

static inline int64_t dot3(const int64_t a[3], const int64_t b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static inline int separates(const int64_t d[3], int64_t s[9][3]) {
    int i;
    for (i = 0; i < 9; i++)
        if (dot3(d, s[i]) <= 0) return 0;
    return 1;
}

static inline int oracle_intersect(int64_t t1[3][3], int64_t t2[3][3]) {
    int64_t s[9][3];
    int i, j, k, c;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            for (c = 0; c < 3; c++) s[3 * i + j][c] = t1[i][c] - t2[j][c];
    for (i = 0; i < 9; i++) {
        if (separates(s[i], s)) return 0;
        for (j = i + 1; j < 9; j++) {
            int64_t e[3], d[3];
            int64_t ee, se;
            for (c = 0; c < 3; c++) e[c] = s[j][c] - s[i][c];
            ee = dot3(e, e);
            se = dot3(s[i], e);
            for (c = 0; c < 3; c++) d[c] = ee * s[i][c] - se * e[c];
            if (separates(d, s)) return 0;
            for (k = j + 1; k < 9; k++) {
                int64_t f[3], n[3], ns;
                for (c = 0; c < 3; c++) f[c] = s[k][c] - s[i][c];
                n[0] = e[1] * f[2] - e[2] * f[1];
                n[1] = e[2] * f[0] - e[0] * f[2];
                n[2] = e[0] * f[1] - e[1] * f[0];
                ns = dot3(n, s[i]);
                for (c = 0; c < 3; c++) d[c] = ns * n[c];
                if (separates(d, s)) return 0;
            }
        }
    }
    return 1;
}

static inline void world_triangle(const Mesh *m, const IPose *pose, size_t t, int64_t out[3][3]) {
    int c;
    for (c = 0; c < 3; c++) {
        const int64_t *p = &m->ipos[3 * (size_t)m->tris[3 * t + (size_t)c]];
        if (pose != NULL)
            ipose_apply(pose, p, out[c]);
        else
            memcpy(out[c], p, 3 * sizeof(int64_t));
    }
}

/* Every intersecting pair, sorted by (a, b); returns the count, the pairs in *out (malloc'd). */
static inline size_t brute_force(const Mesh *a, const IPose *pa, const Mesh *b, const IPose *pb, DvhPair **out) {
    size_t cap = 64, n = 0, i, j;
    DvhPair *v = malloc(cap * sizeof *v);
    if (v == NULL) exit(2);
    for (i = 0; i < a->triangle_count; i++) {
        int64_t ta[3][3];
        world_triangle(a, pa, i, ta);
        for (j = 0; j < b->triangle_count; j++) {
            int64_t tb[3][3];
            world_triangle(b, pb, j, tb);
            if (oracle_intersect(ta, tb)) {
                if (n == cap) {
                    DvhPair *w;
                    cap *= 2;
                    w = realloc(v, cap * sizeof *v);
                    if (w == NULL) exit(2);
                    v = w;
                }
                v[n].a = (uint32_t)i;
                v[n].b = (uint32_t)j;
                n++;
            }
        }
    }
    *out = v;
    return n;
}

#endif
