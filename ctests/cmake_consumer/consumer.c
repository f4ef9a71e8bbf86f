/* Two triangles that cross, through dvh.h and the static library: exits 0 only when the one
 * pair is found. */
#include <dvh.h>
#include <stdio.h>

int main(void) {
    const double a_pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const double b_pos[] = {0.2, 0.2, -1, 0.2, 0.2, 1, 1, 1, 0};
    const uint32_t tri[] = {0, 1, 2};
    DvhMesh *a = NULL, *b = NULL;
    DvhPairs *pairs = dvh_pairs_new();
    int ok = pairs != NULL && dvh_mesh_create(a_pos, 3, tri, 1, NULL, &a) == DVH_STATUS_OK &&
             dvh_mesh_create(b_pos, 3, tri, 1, NULL, &b) == DVH_STATUS_OK &&
             dvh_collide(a, NULL, b, NULL, NULL, pairs, NULL) == DVH_STATUS_OK &&
             dvh_pairs_len(pairs) == 1 && dvh_pairs_data(pairs)[0].a == 0 &&
             dvh_pairs_data(pairs)[0].b == 0;
    if (ok) printf("dvh %s through CMake (static, C): 1 pair\n", dvh_version());
    else fprintf(stderr, "expected the pair (0, 0)\n");
    dvh_mesh_free(a);
    dvh_mesh_free(b);
    dvh_pairs_free(pairs);
    return ok ? 0 : 1;
}
