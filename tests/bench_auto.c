/* bench_auto.c - `make bench` figures of the conservative methods and of AUTO (their intersection)
   side by side on the demo scenes, for the README's method guide: per scene an evenly spread subset
   of cells of the generator at seed 1 (city size 1: 40 cells, indoor size 1: 40, forest size 0.5:
   20), each method baked alone and then AUTO, on one thread, timed in CPU seconds (clock()):
     BENCH methods_<method>_ms_per_cell_<scene>   bake time per cell, preparation included
     BENCH methods_<method>_tightness_<scene>     mean PVS / mean ray-sampled set (cli_reference_visibility)
     BENCH auto_ms_per_cell_<scene>, auto_tightness_<scene>, auto_culled_pct_<scene>
     BENCH auto_vs_best_<scene>                   AUTO's mean PVS / the best single method's (<= 1)
   Every method is baked alone, also where AUTO skips it (it cannot cull there); auto_ms_per_cell
   names the methods AUTO ran. */
#include "../tools/cli.h"
#include "test.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int bench_scene(gen_kind kind, float size, uint32_t n, const char *name) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    tool_error te;
    pvs_box *sub;
    pvs_word *seen;
    uint32_t c, objects, k;
    double seen_sum = 0.0, best = -1.0, auto_sum = 0.0, otree_t = 0.0, otree_sum = 0.0;
    pvs_method methods[PVS_METHOD_COUNT];
    uint32_t method_count = 0;
    gp = test_gen_params(kind, 1, size, 0);
    if (test_generate(&gp, &m, &cells, NULL) || cli_make_scene(name, &m, 1, &scene, &te)) return 1;
    objects = pvs_scene_object_count(scene);
    if (n > cells.count) n = cells.count;
    sub = (pvs_box *)malloc(n * sizeof(pvs_box));
    seen = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
    for (c = 0; c < n; ++c) {
        memcpy(sub + c, cells.boxes + 6 * (size_t)((uint64_t)c * cells.count / n), sizeof(pvs_box));
        memset(seen, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
        cli_reference_visibility(scene, sub + c, 77 + c, seen);
        seen_sum += pvs_bitset_count(seen, objects);
    }
    for (k = 0; k < (uint32_t)PVS_METHOD_COUNT; ++k)
        if (k != PVS_METHOD_DEFAULT && k != PVS_METHOD_SAMPLE && k != PVS_METHOD_AUTO) methods[method_count++] = (pvs_method)k;
    methods[method_count++] = PVS_METHOD_AUTO; /* AUTO last: auto_vs_best compares with every single method */
    for (k = 0; k < method_count; ++k) {
        pvs_bake_desc bd;
        pvs_bake *b;
        pvs_error pe;
        double t, sum = 0.0;
        test_bake_desc(&bd, scene, sub, n, methods[k]);
        t = test_cpu_seconds();
        if (pvs_bake_begin(&bd, &b, &pe) != PVS_OK) {
            printf("BENCH methods_%s_tightness_%s 0 (not available: %s)\n", pvs_method_name(methods[k]), name, pe.message);
            continue;
        }
        for (c = 0; c < n; ++c)
            if (pvs_bake_run_task(b, c, &pe) != PVS_OK) { fprintf(stderr, "%s: %s\n", name, pe.message); return 1; }
        t = test_cpu_seconds() - t;
        for (c = 0; c < n; ++c) sum += pvs_bitset_count(pvs_bake_cell_pvs(b, c), objects);
        if (methods[k] == PVS_METHOD_AUTO) {
            uint32_t i;
            auto_sum = sum;
            printf("BENCH auto_ms_per_cell_%s %.2f ms (ran:", name, 1000.0 * t / n);
            for (i = 0; i < pvs_bake_method_count(b); ++i) {
                pvs_bake_method_info mi;
                pvs_bake_get_method_info(b, i, &mi);
                if (mi.ran) printf(" %s", pvs_method_name(mi.method));
            }
            printf(")\n");
            printf("BENCH auto_tightness_%s %.3f ratio\n", name, seen_sum > 0.0 ? sum / seen_sum : 0.0);
            printf("BENCH auto_culled_pct_%s %.1f %%\n", name, 100.0 * (1.0 - sum / n / objects));
            printf("BENCH auto_vs_best_%s %.3f ratio\n", name, best > 0.0 ? auto_sum / best : 1.0);
            if (otree_t > 0.0) {
                printf("BENCH auto_vs_otree_cost_%s %.2f ratio\n", name, t / otree_t);
                printf("BENCH auto_vs_otree_pvs_%s %.3f ratio\n", name, otree_sum > 0.0 ? auto_sum / otree_sum : 1.0);
            }
        } else {
            printf("BENCH methods_%s_ms_per_cell_%s %.2f ms\n", pvs_method_name(methods[k]), name, 1000.0 * t / n);
            printf("BENCH methods_%s_tightness_%s %.3f ratio\n", pvs_method_name(methods[k]), name, seen_sum > 0.0 ? sum / seen_sum : 0.0);
            if (best < 0.0 || sum < best) best = sum;
            if (methods[k] == PVS_METHOD_OTREE) otree_t = t, otree_sum = sum;
        }
        pvs_bake_destroy(b);
    }
    free(sub);
    free(seen);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return 0;
}

/* The whole demo city (1,211 cells), one thread, CPU time with preparation: what AUTO costs over OTREE alone when
   its sample finds the other methods negligible (issue 28: at most 1.3 times, a PVS no larger). */
static int bench_full_city(void) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    tool_error te;
    double t[2], sum[2] = {0.0, 0.0};
    uint32_t k, c;
    gp = test_gen_params(GEN_CITY, 1, 1.0f, 0);
    if (test_generate(&gp, &m, &cells, NULL) || cli_make_scene("city", &m, 1, &scene, &te)) return 1;
    for (k = 0; k < 2; ++k) {
        pvs_bake_desc bd;
        pvs_bake *b;
        pvs_error pe;
        test_bake_desc(&bd, scene, (const pvs_box *)cells.boxes, cells.count, k ? PVS_METHOD_AUTO : PVS_METHOD_OTREE);
        t[k] = test_cpu_seconds();
        if (pvs_bake_begin(&bd, &b, &pe) != PVS_OK) { fprintf(stderr, "city: %s\n", pe.message); return 1; }
        for (c = 0; c < cells.count; ++c)
            if (pvs_bake_run_task(b, c, &pe) != PVS_OK) { fprintf(stderr, "city: %s\n", pe.message); return 1; }
        t[k] = test_cpu_seconds() - t[k];
        for (c = 0; c < cells.count; ++c) sum[k] += pvs_bitset_count(pvs_bake_cell_pvs(b, c), pvs_scene_object_count(scene));
        pvs_bake_destroy(b);
    }
    printf("BENCH otree_seconds_city_full %.2f s\n", t[0]);
    printf("BENCH auto_seconds_city_full %.2f s\n", t[1]);
    printf("BENCH auto_vs_otree_cost_city_full %.2f ratio\n", t[1] / t[0]);
    printf("BENCH auto_vs_otree_pvs_city_full %.3f ratio\n", sum[0] > 0.0 ? sum[1] / sum[0] : 1.0);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return 0;
}

int main(void) {
    if (bench_full_city()) return 1;
    if (bench_scene(GEN_CITY, 1.0f, 40, "city")) return 1;
    if (bench_scene(GEN_INDOOR, 1.0f, 40, "indoor")) return 1;
    if (bench_scene(GEN_FOREST, 0.5f, 20, "forest")) return 1;
    return 0;
}
