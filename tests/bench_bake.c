/* bench_bake.c - `make bench` figures of the bake on the demo city: BENCH <name> <value> <unit>. */
#include "../tools/cli.h"
#include "test.h"
#include <stdlib.h>
#include <string.h>

int main(void) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    tool_error te;
    pvs_word *bits;
    uint32_t c, n = 100, objects;
    uint64_t rays = 0;
    double t, t_scene;
    gp = test_gen_params(GEN_CITY, 1, 1.0f, 0);
    t = cli_seconds();
    if (test_generate(&gp, &m, &cells, NULL)) return 1;
    printf("BENCH city_generate_ms %.1f ms\n", 1000.0 * (cli_seconds() - t));
    t = cli_seconds();
    if (cli_make_scene("city", &m, 1, &scene, &te)) { fprintf(stderr, "%s\n", te.message); return 1; }
    t_scene = cli_seconds() - t;
    printf("BENCH city_scene_create_ms %.1f ms\n", 1000.0 * t_scene);
    objects = pvs_scene_object_count(scene);
    bits = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
    if (n > cells.count) n = cells.count;
    t = cli_seconds();
    for (c = 0; c < n; ++c) {
        uint32_t cell = (uint32_t)((uint64_t)c * cells.count / n);
        memset(bits, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
        rays += pvs_sample_visibility(scene, (const pvs_box *)(cells.boxes + 6 * (size_t)cell), 32, 2048, c, bits);
    }
    t = cli_seconds() - t;
    printf("BENCH sample_ms_per_cell %.2f ms\n", 1000.0 * t / n); /* 32 points x 2048 rays, one core */
    printf("BENCH city_rays_per_s %.0f rays/s\n", (double)rays / t);
    free(bits);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return 0;
}
