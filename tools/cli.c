/* cli.c - see cli.h */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include <time.h>
#include <errno.h>
#include <unistd.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cli__make_scene(const char *name, const mesh *m, uint32_t up_axis, cli_memory *memory, pvs_scene **scene, tool_error *err) {
    pvs_scene_desc d;
    pvs_object_desc *obs;
    pvs_error pe;
    uint32_t i;
    *scene = NULL;
    if (m->object_count == 0 || m->triangle_count == 0) {
        tool_error_set(err, name, 0, "no faces");
        return -1;
    }
    obs = (pvs_object_desc *)malloc(m->object_count * sizeof(pvs_object_desc));
    if (!obs) {
        tool_error_set(err, name, 0, "out of memory");
        return -1;
    }
    for (i = 0; i < m->object_count; ++i) {
        obs[i].first_triangle = m->objects[i].first_triangle;
        obs[i].triangle_count = m->objects[i].triangle_count;
        obs[i].flags = ((m->objects[i].flags & MESH_OBJECT_OCCLUDER) ? PVS_OBJECT_OCCLUDER_ONLY : 0u) |
                       ((m->objects[i].flags & MESH_OBJECT_SEE_THROUGH) ? PVS_OBJECT_SEE_THROUGH : 0u) |
                       ((m->objects[i].flags & MESH_OBJECT_ONE_SIDED) ? PVS_OBJECT_ONE_SIDED : 0u);
    }
    memset(&d, 0, sizeof(d));
    d.positions = m->positions;
    d.vertex_count = m->vertex_count;
    d.indices = m->indices;
    d.triangle_count = m->triangle_count;
    d.objects = obs;
    d.object_count = m->object_count;
    d.up_axis = up_axis;
    d.flags = PVS_SCENE_ALLOW_EMPTY_OBJECTS;
    if (memory) d.allocator = cli_memory_allocator(memory);
    if (pvs_scene_create(&d, scene, &pe) != PVS_OK) {
        /* name the source line of the offending object where the message is about an object */
        if (pe.index >= 0 && (uint64_t)pe.index < m->object_count &&
            (pe.result == PVS_ERROR_EMPTY_OBJECT || pe.result == PVS_ERROR_DEGENERATE_OBJECT || pe.result == PVS_ERROR_OVERLAPPING_OBJECTS))
            tool_error_set(err, name, (int)m->objects[pe.index].line, "object '%s': %s", m->objects[pe.index].name, pe.message);
        else
            tool_error_set(err, name, 0, "%s", pe.message);
        free(obs);
        return -1;
    }
    free(obs);
    {
        uint32_t flat = 0, first = 0;
        for (i = 0; i < m->object_count; ++i) {
            pvs_box b = pvs_scene_object_box(*scene, i);
            if (m->objects[i].triangle_count && b.min[0] > b.max[0] && !flat++) first = i;
        }
        if (flat)
            fprintf(stderr, "warning: %s:%u: object %u '%s' has only zero-area triangles (%u such object%s, never visible)\n", name,
                    m->objects[first].line, first, m->objects[first].name, flat, flat == 1 ? "" : "s");
    }
    return 0;
}

int cli_make_scene(const char *name, const mesh *m, uint32_t up_axis, pvs_scene **scene, tool_error *err) {
    return cli__make_scene(name, m, up_axis, NULL, scene, err);
}

int cli_load_scene_limited(const char *path, uint32_t up_axis, mesh *m, cli_memory *memory, pvs_scene **scene, tool_error *err) {
    tool_error warn;
    uint32_t empty;
    mesh_init(m);
    if (obj_load(path, m, err)) return -1;
    empty = obj_check_empty_objects(path, m, &warn);
    if (empty) fprintf(stderr, "warning: %s (%u object%s without faces, never visible)\n", warn.message, empty, empty == 1 ? "" : "s");
    if (memory) /* the mesh counts against the limit too */
        cli_memory_add(memory, (size_t)m->vertex_cap * 12 + (size_t)m->triangle_cap * 12 + (size_t)m->object_cap * sizeof(mesh_object));
    if (cli__make_scene(path, m, up_axis, memory, scene, err)) {
        mesh_free(m);
        return -1;
    }
    return 0;
}

int cli_load_scene(const char *path, uint32_t up_axis, mesh *m, pvs_scene **scene, tool_error *err) {
    return cli_load_scene_limited(path, up_axis, m, NULL, scene, err);
}

int cli_load_pvs_scene(const char *pvs_path, const char *scene_path, uint32_t up_axis, void **data, pvs_file *file, mesh *m, pvs_scene **scene,
                       tool_error *err) {
    size_t size = 0;
    pvs_error pe;
    if (read_file(pvs_path, data, &size, err)) return -1;
    if (pvs_file_open(*data, size, file, &pe) != PVS_OK) {
        tool_error_set(err, pvs_path, 0, "%s", pe.message);
        return -1;
    }
    if (file->flags & PVS_FILE_NO_LOOKUP) {
        tool_error_set(err, pvs_path, 0, "stores no cell boxes (baked --no-lookup): give the file baked with them");
        return -1;
    }
    if (cli_load_scene(scene_path, up_axis ? up_axis : file->up_axis, m, scene, err)) return -1;
    uint64_t fp = pvs_scene_fingerprint(*scene);
    if (file->scene_fingerprint && file->object_count == pvs_scene_object_count(*scene) && /* else: not the same */
        file->scene_fingerprint != fp) {
        tool_error_set(err, pvs_path, 0, "stale: baked from another version of %s (scene fingerprint %016llx, "
                       "the file's %016llx): bake it again", scene_path, (unsigned long long)fp,
                       (unsigned long long)file->scene_fingerprint);
        return -1;
    }
    if (pvs_file_object_name(file, 0) && file->object_count == m->object_count) { /* names stored: same order? */
        uint32_t o;
        for (o = 0; o < m->object_count; ++o)
            if (strcmp(pvs_file_object_name(file, o), m->objects[o].name)) {
                tool_error_set(err, pvs_path, 0, "stale: object %u is '%s' in the file but '%s' in %s (renamed or "
                               "reordered): bake it again", o, pvs_file_object_name(file, o), m->objects[o].name, scene_path);
                return -1;
            }
    }
    return 0;
}

int cli_grid_cells(const pvs_scene *scene, float size, uint32_t max_cells, mesh_cells *cells, tool_error *err) {
    pvs_box b = pvs_scene_bounds(scene);
    double n[3], total = 1.0;
    uint32_t c[3], x, y, z;
    int k;
    if (!(size > 0.0f) || !isfinite(size)) {
        tool_error_set(err, "--grid", 0, "cell size must be a positive number");
        return -1;
    }
    for (k = 0; k < 3; ++k) {
        n[k] = ceil(((double)b.max[k] - b.min[k]) / size);
        if (n[k] < 1.0) n[k] = 1.0;
        total *= n[k];
    }
    if (total > max_cells) {
        tool_error_set(err, "--grid", 0, "%.0f cells of size %g exceed the limit of %u", total, size, max_cells);
        return -1;
    }
    for (k = 0; k < 3; ++k) c[k] = (uint32_t)n[k];
    for (z = 0; z < c[2]; ++z)
        for (y = 0; y < c[1]; ++y)
            for (x = 0; x < c[0]; ++x) {
                float box[6];
                uint32_t ix[3];
                ix[0] = x; ix[1] = y; ix[2] = z;
                for (k = 0; k < 3; ++k) {
                    box[k] = b.min[k] + size * (float)ix[k];
                    box[3 + k] = ix[k] + 1 == c[k] ? (b.max[k] > box[k] ? b.max[k] : box[k]) : b.min[k] + size * (float)(ix[k] + 1);
                }
                if (mesh_cells_add(cells, box)) {
                    tool_error_set(err, "--grid", 0, "out of memory");
                    return -1;
                }
            }
    return 0;
}

typedef struct cli__bake_job {
    pvs_bake *bake;
    progress *bar;
    pthread_mutex_t mutex;
    int failed;
    uint32_t failed_task;
    pvs_error error;
} cli__bake_job;

static void cli__bake_one(void *user, uint32_t task, uint32_t thread) {
    cli__bake_job *job = (cli__bake_job *)user;
    pvs_error e;
    (void)thread;
    if (pvs_bake_run_task(job->bake, task, &e) != PVS_OK) {
        pthread_mutex_lock(&job->mutex);
        if (!job->failed || task < job->failed_task) { /* report the lowest failing task: deterministic */
            job->failed = 1;
            job->failed_task = task;
            job->error = e;
        }
        pthread_mutex_unlock(&job->mutex);
    }
    if (job->bar) progress_add(job->bar, 1);
}

int cli_run_bake(pvs_bake *bake, uint32_t threads, int quiet, const char *label, tool_error *err) {
    cli__bake_job job;
    progress bar;
    memset(&job, 0, sizeof(job));
    job.bake = bake;
    pthread_mutex_init(&job.mutex, NULL);
    if (!quiet) {
        progress_begin(&bar, label, pvs_bake_task_count(bake));
        job.bar = &bar;
    }
    parallel_for(threads, pvs_bake_task_count(bake), cli__bake_one, &job);
    if (job.bar) progress_end(&bar);
    pthread_mutex_destroy(&job.mutex);
    if (job.failed) {
        tool_error_set(err, NULL, 0, "cell %u: %s", pvs_bake_task_cell(bake, job.failed_task), job.error.message);
        return -1;
    }
    return 0;
}

typedef struct cli__check_job {
    const pvs_scene *scene;
    const pvs_file *file;
    uint32_t points, rays, aim;
    uint64_t seed;
    uint32_t words;
    float max_distance;   /* > 0: objects farther from the cell do not count as misses */
    pvs_word *seen, *pvs; /* per thread scratch: threads x words each */
    uint32_t *miss_count, *first_miss, *pvs_size, *seen_size;
    uint64_t *rays_cast;
    progress *bar;
    /* files with virtual occluders: the PVS checked is the one pvs_vocc_cull rebuilds */
    pvs_box *boxes;       /* object boxes, empty for occluder-only objects (as the bake saw them) */
    pvs_kdtree *tree;
    uint8_t *scratch;     /* per thread */
    size_t scratch_size;
    pvs_word *stored;     /* per thread: the stored records, compared with the rebuilt PVS */
    uint8_t *differs;     /* per cell */
} cli__check_job;

static void cli__check_one(void *user, uint32_t cell, uint32_t thread) {
    cli__check_job *job = (cli__check_job *)user;
    pvs_word *seen = job->seen + (size_t)thread * job->words, *pvs = job->pvs + (size_t)thread * job->words;
    pvs_box box = pvs_file_cell_box(job->file, cell);
    uint64_t state = job->seed ^ ((uint64_t)cell * 0xd1b54a32d192ed03ull);
    uint32_t i, n = job->file->object_count, misses = 0, first = 0xffffffffu;
    uint64_t z;
    /* a per-cell seed (splitmix64 finaliser) independent of the thread */
    z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    memset(seen, 0, job->words * sizeof(pvs_word));
    job->rays_cast[cell] = pvs_sample_visibility(job->scene, &box, job->points, job->rays, z ^ (z >> 31), seen);
    /* then rays aimed at every object not seen yet: small and far objects that uniform directions pass by */
    if (job->aim) job->rays_cast[cell] += pvs_sample_visibility_toward(job->scene, &box, NULL, job->aim, z ^ (z >> 17), seen);
    if (job->boxes) {
        /* the runtime's rebuild: the top-down walk of the object tree (it may cull an object whose
           parts lie behind different occluders, so it is checked: it is what an engine draws) */
        pvs_word *stored = job->stored + 2 * (size_t)thread * job->words, *flat = stored + job->words;
        uint8_t *scratch = job->scratch + (size_t)thread * job->scratch_size;
        size_t w;
        pvs_vocc_cull(job->file, cell, 0, job->boxes, n, job->tree, scratch, job->scratch_size, pvs, NULL);
        if (!(job->file->vocc_flags & PVS_VOCC_ONLY)) {
            /* the stored PVS is the one every box against each occluder gives (minus objects beyond a
               draw distance): never an object that rebuild leaves out */
            pvs_vocc_cull(job->file, cell, 0, job->boxes, n, NULL, scratch, job->scratch_size, flat, NULL);
            pvs_file_decode(job->file, cell, stored, job->words, NULL);
            for (w = 0; w < job->words; ++w)
                if (stored[w] & ~flat[w]) job->differs[cell] = 1;
        }
    } else {
        pvs_file_decode(job->file, cell, pvs, job->words, NULL);
    }
    if (job->max_distance > 0.0f) /* a bake with a draw distance: what rays see beyond it is not a miss */
        for (i = pvs_bitset_next(seen, n, 0); i < n; i = pvs_bitset_next(seen, n, i + 1)) {
            pvs_box ob = pvs_scene_object_box(job->scene, i);
            double g2 = 0.0;
            int k;
            for (k = 0; k < 3; ++k) {
                double g = ob.min[k] > box.max[k] ? (double)ob.min[k] - box.max[k] : box.min[k] > ob.max[k] ? (double)box.min[k] - ob.max[k] : 0.0;
                g2 += g * g;
            }
            if (g2 > (double)job->max_distance * job->max_distance) pvs_bitset_clear(seen, i);
        }
    for (i = pvs_bitset_next(seen, n, 0); i < n; i = pvs_bitset_next(seen, n, i + 1))
        if (!pvs_bitset_test(pvs, i)) {
            if (first == 0xffffffffu) first = i;
            ++misses;
        }
    job->miss_count[cell] = misses;
    job->first_miss[cell] = first;
    job->pvs_size[cell] = pvs_bitset_count(pvs, n);
    job->seen_size[cell] = pvs_bitset_count(seen, n);
    if (job->bar) progress_add(job->bar, 1);
}

uint64_t cli_reference_visibility(const pvs_scene *scene, const pvs_box *cell, uint64_t seed, pvs_word *visible) {
    uint64_t rays = pvs_sample_visibility(scene, cell, 32, 2048, seed, visible);
    return rays + pvs_sample_visibility_toward(scene, cell, NULL, 32, seed ^ 0x5bd1e995u, visible);
}

int cli_check_file(const pvs_scene *scene, const pvs_file *file, uint32_t points, uint32_t rays, uint32_t aim, uint64_t seed,
                   uint32_t threads, int quiet, cli_check *out, tool_error *err) {
    return cli_check_file_ex(scene, file, points, rays, aim, seed, threads, quiet, 0.0f, out, err);
}

int cli_check_file_ex(const pvs_scene *scene, const pvs_file *file, uint32_t points, uint32_t rays, uint32_t aim, uint64_t seed,
                      uint32_t threads, int quiet, float max_distance, cli_check *out, tool_error *err) {
    cli__check_job job;
    progress bar;
    uint32_t c, nt = threads ? threads : cpu_count();
    memset(out, 0, sizeof(*out));
    if (file->object_count != pvs_scene_object_count(scene)) {
        tool_error_set(err, NULL, 0, "the file has %u objects but the scene has %u: not the same scene", file->object_count,
                       pvs_scene_object_count(scene));
        return -1;
    }
    memset(&job, 0, sizeof(job));
    job.scene = scene;
    job.file = file;
    job.points = points;
    job.rays = rays;
    job.aim = aim;
    job.seed = seed;
    job.words = (uint32_t)PVS_BITSET_WORDS(file->object_count);
    job.max_distance = max_distance;
    job.seen = (pvs_word *)malloc((size_t)nt * job.words * sizeof(pvs_word));
    job.pvs = (pvs_word *)malloc((size_t)nt * job.words * sizeof(pvs_word));
    job.miss_count = (uint32_t *)malloc(file->cell_count * sizeof(uint32_t));
    job.first_miss = (uint32_t *)malloc(file->cell_count * sizeof(uint32_t));
    job.pvs_size = (uint32_t *)malloc(file->cell_count * sizeof(uint32_t));
    job.seen_size = (uint32_t *)malloc(file->cell_count * sizeof(uint32_t));
    job.rays_cast = (uint64_t *)malloc(file->cell_count * sizeof(uint64_t));
    if (file->vocc_flags & PVS_VOCC_STORED) { /* rebuild every cell's PVS from its virtual occluders */
        pvs_kdtree_desc kd;
        memset(&kd, 0, sizeof(kd));
        job.boxes = (pvs_box *)malloc((size_t)file->object_count * sizeof(pvs_box) + 1);
        job.differs = (uint8_t *)calloc(file->cell_count, 1);
        job.stored = (pvs_word *)malloc(2 * (size_t)nt * job.words * sizeof(pvs_word));
        if (job.boxes)
            for (c = 0; c < file->object_count; ++c) {
                job.boxes[c] = pvs_scene_object_box(scene, c);
                if (pvs_scene_object_flags(scene, c) & PVS_OBJECT_OCCLUDER_ONLY) job.boxes[c].min[0] = 1.0f, job.boxes[c].max[0] = 0.0f;
            }
        kd.boxes = job.boxes;
        kd.count = file->object_count;
        if (job.boxes && pvs_kdtree_create(&kd, &job.tree, NULL) == PVS_OK) {
            job.scratch_size = (pvs_vocc_cull_scratch_size(job.tree, 255) + 63) / 64 * 64;
            job.scratch = (uint8_t *)malloc((size_t)nt * job.scratch_size);
        }
        out->rebuilt = 1;
    }
    if (!job.seen || !job.pvs || !job.miss_count || !job.first_miss || !job.pvs_size || !job.seen_size || !job.rays_cast ||
        (out->rebuilt && (!job.tree || !job.scratch || !job.differs || !job.stored))) {
        tool_error_set(err, NULL, 0, "out of memory");
    } else {
        if (!quiet) {
            progress_begin(&bar, "check", file->cell_count);
            job.bar = &bar;
        }
        parallel_for(nt, file->cell_count, cli__check_one, &job);
        if (!quiet) progress_end(&bar);
        out->cells = file->cell_count;
        out->first_miss_cell = out->first_miss_object = 0xffffffffu;
        for (c = 0; c < file->cell_count; ++c) {
            out->misses += job.miss_count[c];
            if (job.miss_count[c]) {
                if (!out->cells_with_misses) {
                    out->first_miss_cell = c;
                    out->first_miss_object = job.first_miss[c];
                }
                out->cells_with_misses++;
            }
            out->pvs_sum += job.pvs_size[c];
            if (job.differs) out->stored_differs += job.differs[c];
            out->seen_sum += job.seen_size[c];
            out->rays += job.rays_cast[c];
        }
    }
    free(job.seen); free(job.pvs); free(job.miss_count); free(job.first_miss); free(job.pvs_size); free(job.seen_size);
    free(job.boxes); free(job.differs); free(job.stored); free(job.scratch);
    pvs_kdtree_destroy(job.tree);
    free(job.rays_cast);
    return out->cells ? 0 : -1;
}

int cli_parse_up(const char *s, uint32_t *up) {
    if (!strcmp(s, "y") || !strcmp(s, "Y")) { *up = 1; return 0; }
    if (!strcmp(s, "z") || !strcmp(s, "Z")) { *up = 2; return 0; }
    return -1;
}

static int cli__attached_jobs(const char *a) { return a[0] == '-' && a[1] == 'j' && a[2] >= '0' && a[2] <= '9'; }

int cli_is_option(const char *option, const char *const *list) {
    for (; list && *list; ++list)
        if (!strcmp(option, *list)) return 1;
    return 0;
}

char **cli_split_jobs(int *argc, char **argv, const char *const *value_options) {
    int i, n = 0, k = 0;
    char **out;
    for (i = 0; i < *argc; ++i) n += cli__attached_jobs(argv[i]);
    if (!n || !(out = (char **)malloc(sizeof(char *) * ((size_t)*argc + (size_t)n + 1)))) return argv;
    for (i = 0; i < *argc; ++i) {
        if (cli_is_option(argv[i], value_options) && i + 1 < *argc) {
            out[k++] = argv[i++]; /* the option and its value, whatever it looks like */
            out[k++] = argv[i];
        } else if (cli__attached_jobs(argv[i])) {
            out[k++] = (char *)"-j";
            out[k++] = argv[i] + 2;
        } else {
            out[k++] = argv[i];
        }
    }
    out[k] = NULL;
    *argc = k;
    return out;
}

int cli_parse_u32(const char *s, uint32_t lo, uint32_t hi, uint32_t *out) {
    char *end;
    unsigned long long v;
    if (!s || *s < '0' || *s > '9') return -1;
    errno = 0;
    v = strtoull(s, &end, 10);
    if (errno || *end || v < lo || v > hi) return -1;
    *out = (uint32_t)v;
    return 0;
}

double cli_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int cli_write_bake(const pvs_bake *bake, const char *path, size_t *size, tool_error *err) {
    pvs_error pe;
    size_t need = pvs_bake_file_size(bake);
    void *bytes;
    int rc;
    *size = 0;
    if (!need) {
        tool_error_set(err, path, 0, "cannot encode the bake (unfinished, or out of memory)");
        return -1;
    }
    bytes = malloc(need);
    if (!bytes) {
        tool_error_set(err, path, 0, "out of memory (%zu bytes)", need);
        return -1;
    }
    if (pvs_bake_write_file(bake, bytes, need, size, &pe) != PVS_OK) {
        tool_error_set(err, path, 0, "%s", pe.message);
        free(bytes);
        return -1;
    }
    rc = write_file_atomic(path, bytes, *size, err);
    free(bytes);
    return rc;
}

/* 1 when two files store the same object names, or neither stores any. */
static int cli__same_names(const pvs_file *a, const pvs_file *b) {
    uint32_t o;
    if (!pvs_file_object_name(a, 0) != !pvs_file_object_name(b, 0)) return 0;
    for (o = 0; pvs_file_object_name(a, 0) && o < a->object_count && o < b->object_count; ++o)
        if (strcmp(pvs_file_object_name(a, o), pvs_file_object_name(b, o))) return 0;
    return 1;
}

/* Reads and opens the part files of a merge; they must be parts (unless a single whole file) of one
   bake: the same shard count, cells, objects, method and parameters. 0, or -1 with err set. */
static int cli__open_parts(const char *const *paths, int count, void **data, pvs_file *files, tool_error *err) {
    pvs_error pe;
    int i;
    for (i = 0; i < count; ++i) {
        size_t size;
        const pvs_file *f = files + i, *f0 = files;
        if (read_file(paths[i], &data[i], &size, err)) return -1;
        if (pvs_file_open(data[i], size, files + i, &pe) != PVS_OK) {
            tool_error_set(err, paths[i], 0, "%s (byte %llu)", pe.message, (unsigned long long)pe.offset);
            return -1;
        }
        if (f->shard_count < 2 && count > 1) {
            tool_error_set(err, paths[i], 0, "not a part file (bake it with --shard K/N)");
            return -1;
        }
        if (i && (f->shard_count != f0->shard_count || f->total_cell_count != f0->total_cell_count ||
                  f->object_count != f0->object_count || f->method != f0->method || f->eps != f0->eps ||
                  f->up_axis != f0->up_axis || f->flags != f0->flags || f->max_chain != f0->max_chain || f->vocc_flags != f0->vocc_flags ||
                  f->vocc_base != f0->vocc_base || f->vocc_height_step != f0->vocc_height_step ||
                  f->scene_fingerprint != f0->scene_fingerprint || !cli__same_names(f, f0))) {
            tool_error_set(err, paths[i], 0, "does not belong to the bake of %s (shard count, cells, objects, method, eps, "
                                             "up axis, flags, chain bound, virtual occluders, scene or names differ)", paths[0]);
            return -1;
        }
    }
    return 0;
}

/* by_shard[k] = the part holding shard k of n: each once. 0, or -1 with err set. */
static int cli__order_parts(const char *const *paths, int count, const pvs_file *files, uint32_t n, int *by_shard, tool_error *err) {
    uint32_t c;
    int i;
    for (c = 0; c < n; ++c) by_shard[c] = -1;
    for (i = 0; i < count; ++i) {
        uint32_t k = files[i].shard_index;
        if (by_shard[k] >= 0) {
            tool_error_set(err, paths[i], 0, "shard %u/%u is also in %s", k + 1, n, paths[by_shard[k]]);
            return -1;
        }
        by_shard[k] = i;
    }
    for (c = 0; c < n; ++c)
        if (by_shard[c] < 0) {
            tool_error_set(err, paths[0], 0, "shard %u/%u is missing", c + 1, n);
            return -1;
        }
    return 0;
}

/* The merged table's rows, decoded from the parts on demand (memory: the parts, not cells x objects). */
typedef struct cli__merge_rows {
    const pvs_file *files;
    const int *by_shard;
    uint32_t n, words;
} cli__merge_rows;

static const pvs_word *cli__merge_row(const void *user, uint32_t c, pvs_word *buffer) {
    const cli__merge_rows *m = (const cli__merge_rows *)user;
    pvs_file_decode(m->files + m->by_shard[c % m->n], c / m->n, buffer, m->words, NULL);
    return buffer;
}

int cli_merge_parts(const char *const *paths, int count, int no_lookup, void **out, size_t *out_size, tool_error *err) {
    void **data = (void **)calloc((size_t)count, sizeof(void *));
    pvs_file *files = (pvs_file *)calloc((size_t)count, sizeof(pvs_file));
    int *by_shard = NULL, i, rc = -1;
    uint32_t n = 0, total = 0, words = 0, c;
    pvs_box *boxes = NULL;
    cli__merge_rows rows;
    uint8_t *vcount = NULL, *vscale = NULL, *vbytes = NULL;
    const char **names = NULL;
    size_t vat = 0;
    pvs_file_desc d;
    pvs_error pe;
    size_t need = 0;
    *out = NULL;
    *out_size = 0;
    if (!data || !files) { tool_error_set(err, NULL, 0, "out of memory"); goto done; }
    if (cli__open_parts(paths, count, data, files, err)) goto done;
    n = files[0].shard_count ? files[0].shard_count : 1; /* one whole file merges into itself */
    total = files[0].shard_count ? files[0].total_cell_count : files[0].cell_count;
    by_shard = (int *)malloc(n * sizeof(int));
    if (!by_shard) { tool_error_set(err, NULL, 0, "out of memory"); goto done; }
    if (cli__order_parts(paths, count, files, n, by_shard, err)) goto done;
    if (files[0].flags & PVS_FILE_NO_LOOKUP) { /* no boxes to encode (bases take them) */
        tool_error_set(err, paths[0], 0, "stores no cell boxes (--no-lookup): merge the files that have them");
        goto done;
    }
    words = (uint32_t)PVS_BITSET_WORDS(files[0].object_count);
    boxes = (pvs_box *)malloc((size_t)total * sizeof(pvs_box));
    if (!boxes) { tool_error_set(err, NULL, 0, "out of memory for %u cells", total); goto done; }
    if (files[0].vocc_flags & PVS_VOCC_STORED) { /* the virtual occluders too, back to back in cell order */
        size_t occluders = 0;
        for (i = 0; i < count; ++i) occluders += files[i].virtual_occluder_count;
        vcount = (uint8_t *)malloc(total);
        vscale = (uint8_t *)malloc(total);
        vbytes = (uint8_t *)malloc(5 * occluders + 1);
        if (!vcount || !vscale || !vbytes) { tool_error_set(err, NULL, 0, "out of memory for %u cells", total); goto done; }
    }
    for (c = 0; c < total; ++c) {
        const pvs_file *f = files + by_shard[c % n];
        uint32_t local = c / n;
        boxes[c] = pvs_file_cell_box(f, local);
        if (vcount) {
            const uint8_t *p = NULL;
            uint32_t sc = 0, k = pvs_file_vocc_record(f, local, &sc, &p);
            vcount[c] = (uint8_t)k;
            vscale[c] = (uint8_t)sc;
            if (k) memcpy(vbytes + vat, p, 5 * (size_t)k);
            vat += 5 * (size_t)k;
        }
    }
    memset(&d, 0, sizeof(d));
    d.cells = boxes;
    d.cell_count = total;
    d.object_count = files[0].object_count;
    rows.files = files;
    rows.by_shard = by_shard;
    rows.n = n;
    rows.words = words;
    d.pvs_row = cli__merge_row;
    d.pvs_user = &rows;
    d.method = files[0].method;
    d.eps = files[0].eps;
    d.up_axis = files[0].up_axis;
    d.flags = (files[0].flags & PVS_FILE_APPROXIMATE) | (no_lookup ? PVS_FILE_NO_LOOKUP : 0u); /* others: unknown */
    d.max_chain = files[0].max_chain;
    d.scene_fingerprint = files[0].scene_fingerprint;
    if (pvs_file_object_name(files, 0)) {
        uint32_t o;
        if (!(names = (const char **)malloc(files[0].object_count * sizeof(char *)))) {
            tool_error_set(err, NULL, 0, "out of memory");
            goto done;
        }
        for (o = 0; o < files[0].object_count; ++o) names[o] = pvs_file_object_name(files, o);
        d.object_names = names;
    }
    if (vcount) {
        d.vocc_counts = vcount;
        d.vocc_scales = vscale;
        d.virtual_occluders = vbytes;
        d.vocc_base = files[0].vocc_base;
        d.vocc_height_step = files[0].vocc_height_step;
        d.vocc_flags = files[0].vocc_flags & PVS_VOCC_ONLY;
    }
    if (pvs_file_encode(&d, NULL, 0, &need, &pe) != PVS_OK || !(*out = malloc(need)) ||
        pvs_file_encode(&d, *out, need, out_size, &pe) != PVS_OK) {
        tool_error_set(err, NULL, 0, "encoding the merged file: %s", *out ? pe.message : "out of memory");
        free(*out);
        *out = NULL;
        goto done;
    }
    rc = 0;
done:
    free(names);
    for (i = 0; data && i < count; ++i) free(data[i]);
    free(data);
    free(files);
    free(by_shard);
    free(boxes);
    free(vcount);
    free(vscale);
    free(vbytes);
    return rc;
}

int cli_demo_city(mesh *m, mesh_cells *cells, pvs_scene **scene, tool_error *err) {
    gen_params gp;
    memset(&gp, 0, sizeof(gp));
    gp.kind = GEN_CITY;
    gp.seed = 1;
    gp.size = 1.0f;
    mesh_init(m);
    mesh_cells_init(cells);
    *scene = NULL;
    if (gen_scene(&gp, m, cells)) {
        tool_error_set(err, "city", 0, "out of memory generating the city");
        return -1;
    }
    return cli_make_scene("city", m, 1, scene, err);
}

/* ---- a bake-wide memory limit ---- */

static void *cli__memory_alloc(size_t size, size_t align, void *user) {
    cli_memory *m = (cli_memory *)user;
    void *p = NULL;
    int ok;
    pthread_mutex_lock(&m->mutex);
    ok = size <= m->limit - m->used && m->used <= m->limit;
    if (ok) {
        m->used += size;
        if (m->used > m->peak) m->peak = m->used;
    } else {
        m->refused = 1;
    }
    pthread_mutex_unlock(&m->mutex);
    if (!ok) return NULL;
    if (align <= 16) p = malloc(size);
    else if (posix_memalign(&p, align, size) != 0) p = NULL;
    if (!p) {
        pthread_mutex_lock(&m->mutex);
        m->used -= size;
        pthread_mutex_unlock(&m->mutex);
    }
    return p;
}

static void cli__memory_free(void *p, size_t size, void *user) {
    cli_memory *m = (cli_memory *)user;
    if (!p) return;
    free(p);
    pthread_mutex_lock(&m->mutex);
    m->used -= size;
    pthread_mutex_unlock(&m->mutex);
}

void cli_memory_init(cli_memory *m, size_t limit, const char *source) {
    memset(m, 0, sizeof(*m));
    pthread_mutex_init(&m->mutex, NULL);
    m->limit = limit;
    m->source = source;
}
void cli_memory_destroy(cli_memory *m) { pthread_mutex_destroy(&m->mutex); }
pvs_allocator cli_memory_allocator(cli_memory *m) {
    pvs_allocator a;
    a.alloc = cli__memory_alloc;
    a.free = cli__memory_free;
    a.user = m;
    return a;
}
void cli_memory_add(cli_memory *m, size_t bytes) {
    pthread_mutex_lock(&m->mutex);
    m->used += bytes;
    if (m->used > m->peak) m->peak = m->used;
    pthread_mutex_unlock(&m->mutex);
}
size_t cli_memory_used(cli_memory *m) {
    size_t u;
    pthread_mutex_lock(&m->mutex);
    u = m->used;
    pthread_mutex_unlock(&m->mutex);
    return u;
}

const char *cli_size_text(double bytes, char *buf) {
    if (bytes >= 1073741824.0) snprintf(buf, 32, "%.1f GiB", bytes / 1073741824.0);
    else if (bytes >= 1048576.0) snprintf(buf, 32, "%.0f MiB", bytes / 1048576.0);
    else snprintf(buf, 32, "%.0f byte%s", bytes, bytes == 1.0 ? "" : "s");
    return buf;
}

int cli_parse_size(const char *s, size_t *out) {
    char *end = NULL;
    double v, scale = 1.0;
    if (!s || !*s || *s == '-' || *s == '+') return -1;
    errno = 0;
    v = strtod(s, &end);
    if (errno || end == s) return -1;
    if (*end == 'K' || *end == 'k') scale = 1024.0, ++end;
    else if (*end == 'M' || *end == 'm') scale = 1048576.0, ++end;
    else if (*end == 'G' || *end == 'g') scale = 1073741824.0, ++end;
    else if (*end == 'T' || *end == 't') scale = 1099511627776.0, ++end;
    if (*end == 'B' || *end == 'b') ++end; /* 512MB, 2GiB are fine too */
    else if (*end == 'i' && (end[1] == 'B' || end[1] == 'b') && scale > 1.0) end += 2;
    if (*end || !(v * scale >= 1.0) || !(v * scale < 1.8e19)) return -1;
    *out = (size_t)(v * scale) < (size_t)-1 ? (size_t)(v * scale) : (size_t)-1;
    return 0;
}

/* ---- resumable bakes ---- */

uint64_t cli_fingerprint(uint64_t h, const void *data, size_t size) {
    const unsigned char *p = (const unsigned char *)data;
    size_t i;
    for (i = 0; i < size; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

/* The state file: an append-only journal of finished cells. A 32-byte header ("PVSSTATE", u32
   version 2, u32 task count, u32 object count, u64 fingerprint, u32 CRC-32 of the 28 bytes before),
   then one record per finished task: u32 task, u32 payload size P, P payload bytes, u32 CRC-32 of the
   8 + P bytes before it. The payload is the task's PVS, whichever is smaller: byte 0 = 0 and the raw
   bitset (object count bits, little-endian bytes), or byte 0 = 1 and the lengths of its alternating
   runs of clear and set bits, clear first, as LEB128 varints summing to the object count. So a
   finished cell costs one record, of the order of its PVS, instead of a rewrite of the whole state.
   A record cut short by a kill (or damaged), and everything after it, is ignored when reading. On
   resume and when a bake fails, the journal is compacted: rewritten (temp file + rename) with one
   record per finished task, in task order. All little-endian. */
#define CLI__STATE_HEAD 32u
#define CLI__STATE_VERSION 2u
#define CLI__FLUSH_SECONDS 1.0   /* appended records reach the file at least this often, */
#define CLI__SYNC_SECONDS 5.0    /* and the disk at least this often */

static void cli__put32(unsigned char *p, uint32_t v) { p[0] = (unsigned char)v; p[1] = (unsigned char)(v >> 8); p[2] = (unsigned char)(v >> 16); p[3] = (unsigned char)(v >> 24); }
static void cli__put64(unsigned char *p, uint64_t v) { cli__put32(p, (uint32_t)v); cli__put32(p + 4, (uint32_t)(v >> 32)); }
static uint64_t cli__get64(const unsigned char *p) { return (uint64_t)tool_get32(p) | (uint64_t)tool_get32(p + 4) << 32; }

/* The largest payload of `objects` bits: the raw form. */
static size_t cli__payload_max(uint32_t objects) { return 1 + ((size_t)objects + 7) / 8; }

/* Encodes a PVS of `objects` bits (NULL: none set) into out (cli__payload_max bytes). Returns the size. */
static size_t cli__pvs_encode(const pvs_word *bits, uint32_t objects, unsigned char *out) {
    size_t max = cli__payload_max(objects), n = 1, i;
    uint32_t at = 0;
    int set = 0;
    out[0] = 1;
    while (at < objects && n < max) { /* runs: clear, set, clear, ... */
        uint32_t end = at;
        while (end < objects && (bits && pvs_bitset_test(bits, end)) == set) ++end;
        for (uint32_t run = end - at; n < max;) {
            out[n++] = (unsigned char)((run & 0x7fu) | (run > 0x7fu ? 0x80u : 0u));
            run >>= 7;
            if (!run) break;
        }
        at = end;
        set = !set;
    }
    if (at == objects && n < max) return n;
    out[0] = 0; /* raw: the runs were no smaller */
    memset(out + 1, 0, max - 1);
    for (i = 0; bits && i < objects; ++i)
        if (pvs_bitset_test(bits, (uint32_t)i)) out[1 + i / 8] |= (unsigned char)(1u << (i % 8));
    return max;
}

/* Decodes a payload into bits (PVS_BITSET_WORDS(objects) words). Returns 0, or -1 when malformed. */
static int cli__pvs_decode(const unsigned char *p, size_t size, uint32_t objects, pvs_word *bits) {
    size_t n = 1, i;
    uint32_t at = 0;
    int set = 0;
    memset(bits, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
    if (size < 1) return -1;
    if (p[0] == 0) {
        if (size != cli__payload_max(objects)) return -1;
        for (i = 0; i < objects; ++i)
            if (p[1 + i / 8] >> (i % 8) & 1u) pvs_bitset_set(bits, (uint32_t)i);
        return 0;
    }
    if (p[0] != 1) return -1;
    while (n < size) {
        uint64_t run = 0;
        int shift = 0;
        do {
            if (n >= size || shift > 28) return -1;
            run |= (uint64_t)(p[n] & 0x7fu) << shift;
            shift += 7;
        } while (p[n++] & 0x80u);
        if (run > objects - at) return -1;
        if (set)
            for (i = 0; i < run; ++i) pvs_bitset_set(bits, at + (uint32_t)i);
        at += (uint32_t)run;
        set = !set;
    }
    return at == objects ? 0 : -1;
}

/* The journal being appended to. */
typedef struct cli__journal {
    FILE *f;
    const char *path;
    uint32_t tasks, objects, every, pending;
    unsigned char *rec;      /* 12 + cli__payload_max bytes */
    double flushed, synced;  /* when */
    int failed;
    tool_error error;
} cli__journal;

/* Writes one record of task t (its PVS `bits`) to f. Returns 0 or -1. */
static int cli__record_write(FILE *f, unsigned char *rec, uint32_t objects, uint32_t t, const pvs_word *bits) {
    size_t p = cli__pvs_encode(bits, objects, rec + 8);
    cli__put32(rec, t);
    cli__put32(rec + 4, (uint32_t)p);
    cli__put32(rec + 8 + p, tool_crc32(0, rec, 8 + p));
    return fwrite(rec, 1, 12 + p, f) == 12 + p ? 0 : -1;
}

static int cli__sync(FILE *f) {
    if (fflush(f) != 0) return -1;
    return fsync(fileno(f)) != 0 && errno != EINVAL && errno != EROFS ? -1 : 0;
}

/* Starts the journal at j->path anew (temp file + rename) with the tasks marked in done[] (NULL:
   none), then opens it for appending. Returns 0 or -1 with j->error set. */
static int cli__journal_start(cli__journal *j, const pvs_bake *bake, uint64_t fp, const unsigned char *done) {
    unsigned char head[CLI__STATE_HEAD];
    size_t plen = strlen(j->path);
    char *tmp = (char *)malloc(plen + 32);
    FILE *f;
    uint32_t t;
    int ok;
    if (j->f) fclose(j->f);
    j->f = NULL;
    if (!tmp) {
        tool_error_set(&j->error, j->path, 0, "out of memory");
        return -1;
    }
    snprintf(tmp, plen + 32, "%s.tmp.%ld", j->path, (long)getpid());
    memcpy(head, "PVSSTATE", 8);
    cli__put32(head + 8, CLI__STATE_VERSION);
    cli__put32(head + 12, j->tasks);
    cli__put32(head + 16, j->objects);
    cli__put64(head + 20, fp);
    cli__put32(head + 28, tool_crc32(0, head, 28));
    f = fopen(tmp, "wb");
    ok = f && fwrite(head, 1, sizeof(head), f) == sizeof(head);
    for (t = 0; ok && done && t < j->tasks; ++t)
        if (done[t]) ok = cli__record_write(f, j->rec, j->objects, t, pvs_bake_cell_pvs(bake, pvs_bake_task_cell(bake, t))) == 0;
    ok = ok && cli__sync(f) == 0;
    if (f && fclose(f) != 0) ok = 0;
    if (ok && rename(tmp, j->path) != 0) ok = 0;
    if (!ok) {
        tool_error_set(&j->error, j->path, 0, "cannot write the state file: %s", strerror(errno));
        remove(tmp);
        free(tmp);
        return -1;
    }
    free(tmp);
    j->f = fopen(j->path, "ab");
    if (!j->f) {
        tool_error_set(&j->error, j->path, 0, "cannot append to the state file: %s", strerror(errno));
        return -1;
    }
    j->flushed = j->synced = cli_seconds();
    j->pending = 0;
    return 0;
}

/* Appends task t's record; flushes after `every` records or a second, syncs every few seconds. A
   failure marks the journal failed (the bake goes on: only resuming it would not). */
static void cli__journal_append(cli__journal *j, uint32_t t, const pvs_word *bits) {
    double now;
    if (!j->f || j->failed) return;
    if (cli__record_write(j->f, j->rec, j->objects, t, bits)) goto fail;
    now = cli_seconds();
    if (++j->pending >= j->every || now - j->flushed >= CLI__FLUSH_SECONDS) {
        if (fflush(j->f) != 0) goto fail;
        j->pending = 0;
        j->flushed = now;
        if (now - j->synced >= CLI__SYNC_SECONDS) {
            if (cli__sync(j->f)) goto fail;
            j->synced = now;
        }
    }
    return;
fail:
    tool_error_set(&j->error, j->path, 0, "cannot append to the state file: %s", strerror(errno));
    j->failed = 1;
}

/* Restores the tasks of a state journal (streamed; a torn or damaged record ends it: *torn = 1).
   Returns the count restored, or -1 when the file is not a state of this bake (other version,
   fingerprint or shape): the caller starts over. */
static int cli__journal_read(pvs_bake *bake, uint32_t objects, const char *path, uint64_t fp, unsigned char *done, int *torn) {
    uint32_t tasks = pvs_bake_task_count(bake);
    size_t max = cli__payload_max(objects), words = PVS_BITSET_WORDS(objects);
    unsigned char head[CLI__STATE_HEAD], *rec = (unsigned char *)malloc(12 + max);
    pvs_word *bits = (pvs_word *)malloc(words * sizeof(pvs_word) + 8);
    FILE *f = fopen(path, "rb");
    int restored = -1;
    if (!f || !rec || !bits || fread(head, 1, sizeof(head), f) != sizeof(head) || memcmp(head, "PVSSTATE", 8) ||
        tool_get32(head + 8) != CLI__STATE_VERSION || tool_get32(head + 12) != tasks || tool_get32(head + 16) != objects ||
        cli__get64(head + 20) != fp || tool_get32(head + 28) != tool_crc32(0, head, 28))
        goto done;
    restored = 0;
    for (;;) {
        uint32_t t, p;
        size_t got = fread(rec, 1, 8, f);
        if (got != 8) {
            *torn |= got != 0;
            break;
        }
        t = tool_get32(rec);
        p = tool_get32(rec + 4);
        if (t >= tasks || p < 1 || p > max || fread(rec + 8, 1, (size_t)p + 4, f) != (size_t)p + 4 ||
            tool_get32(rec + 8 + p) != tool_crc32(0, rec, 8 + (size_t)p) || cli__pvs_decode(rec + 8, p, objects, bits)) {
            *torn = 1; /* a torn or damaged tail */
            break;
        }
        if (done[t]) continue;
        if (pvs_bake_restore_task(bake, t, bits, words, NULL) == PVS_OK) {
            done[t] = 1;
            ++restored;
        }
    }
done:
    if (f) fclose(f);
    free(rec);
    free(bits);
    return restored;
}

typedef struct cli__run_job {
    pvs_bake *bake;
    progress *bar;
    pthread_mutex_t mutex;
    const uint32_t *todo;      /* tasks to run, from index `first` */
    uint32_t first;
    unsigned char *done;       /* per task, under the mutex */
    cli_bake_run *run;
    cli__journal journal;      /* under the mutex; journal.f NULL: no state file */
    int failed;
    uint32_t failed_task;
    pvs_error error;
    uint32_t *retry, retry_count; /* tasks refused memory while others ran (NULL: fail them) */
} cli__run_job;

static void cli__run_one(void *user, uint32_t index, uint32_t thread) {
    cli__run_job *job = (cli__run_job *)user;
    uint32_t task = job->todo[job->first + index];
    pvs_error e;
    double t0 = cli_seconds();
    int ok = pvs_bake_run_task(job->bake, task, &e) == PVS_OK;
    double dt = cli_seconds() - t0;
    (void)thread;
    pthread_mutex_lock(&job->mutex);
    if (job->run->task_seconds) job->run->task_seconds[task] = dt;
    if (!ok && e.result == PVS_ERROR_OUT_OF_MEMORY && job->retry) { /* another thread held the memory: again, alone */
        job->retry[job->retry_count++] = task;
        pthread_mutex_unlock(&job->mutex);
        return;
    }
    if (!ok) {
        if (!job->failed || task < job->failed_task) { /* report the lowest failing task: deterministic */
            job->failed = 1;
            job->failed_task = task;
            job->error = e;
        }
    } else {
        job->done[task] = 1;
        cli__journal_append(&job->journal, task, pvs_bake_cell_pvs(job->bake, pvs_bake_task_cell(job->bake, task)));
    }
    pthread_mutex_unlock(&job->mutex);
    if (job->bar) progress_add(job->bar, 1);
}

/* The threads the memory limit fits for the n tasks in job->todo: the known task size first, then
   one task run alone and measured (job->first becomes 1). Lowers *threads (0: every CPU), or returns
   -2 with err set when not even one fits or -j asked for more. */
static int cli__plan_threads(cli__run_job *job, uint32_t *threads, uint32_t n, tool_error *err) {
    cli_bake_run *run = job->run;
    cli_memory *m = run->memory;
    uint32_t want = *threads ? *threads : cpu_count(), fit;
    size_t used = cli_memory_used(m), left = used < m->limit ? m->limit - used : 0, per;
    char a[32], b[32], c[32], d[32];
    const char *what = run->task_what ? run->task_what : "a cell";
    if (want > n) want = n; /* never more threads than tasks */
    if (run->task_bytes > left) {
        tool_error_set(err, NULL, 0, "%s needs about %s per thread, more than the %s that the memory limit of %s (%s) leaves after the scene "
                       "and the methods' preparation (%s)%s%s", what, cli_size_text((double)run->task_bytes, a), cli_size_text((double)left, b),
                       cli_size_text((double)m->limit, c), m->source, cli_size_text((double)used, d), run->task_hint ? ": " : "",
                       run->task_hint ? run->task_hint : "");
        return -2;
    }
    if (run->threads_given && run->task_bytes && (double)want * run->task_bytes > (double)left) {
        fit = (uint32_t)(left / run->task_bytes);
        tool_error_set(err, NULL, 0, "-j %u needs about %s (%s per thread for %s), more than the %s that the memory limit of %s (%s) leaves: "
                       "use -j %u or fewer", want, cli_size_text((double)want * run->task_bytes, a), cli_size_text((double)run->task_bytes, b),
                       what, cli_size_text((double)left, c), cli_size_text((double)m->limit, d), m->source, fit);
        return -2;
    }
    if (want > 1) { /* a cell alone, measured: what one thread holds */
        size_t base;
        pthread_mutex_lock(&m->mutex);
        base = m->used;
        m->peak = m->used;
        pthread_mutex_unlock(&m->mutex);
        cli__run_one(job, 0, 0);
        job->first = 1;
        pthread_mutex_lock(&m->mutex);
        per = m->peak - base;
        used = m->used;
        pthread_mutex_unlock(&m->mutex);
        per += per / 4; /* cells differ: a margin; a refusal is run again alone anyway */
        if (per < run->task_bytes) per = run->task_bytes;
        left = used < m->limit ? m->limit - used : 0;
        fit = per ? (uint32_t)(left / per < 1024 ? left / per : 1024) : want;
        if (fit < 1) fit = 1;
        if (want > fit) {
            if (!run->quiet_plan)
                fprintf(stderr, "pvsbake: %u thread%s, not %u: a cell holds about %s and the memory limit of %s (%s) leaves %s\n", fit,
                        fit == 1 ? "" : "s", want, cli_size_text((double)per, a), cli_size_text((double)m->limit, b), m->source,
                        cli_size_text((double)left, c));
            want = fit;
        }
    }
    *threads = want;
    return 0;
}

int cli_run_bake_ex(pvs_bake *bake, uint32_t threads, int quiet, const char *label, cli_bake_run *run, tool_error *err) {
    cli__run_job job;
    progress bar;
    uint32_t tasks = pvs_bake_task_count(bake), t, n = 0;
    uint32_t *todo = (uint32_t *)malloc((size_t)tasks * sizeof(uint32_t) + 4);
    unsigned char *done = (unsigned char *)calloc((size_t)tasks + 1, 1);
    int rc = 0;
    run->resumed = 0;
    run->state_ignored = 0;
    run->state_torn = 0;
    if (!run->state_every) run->state_every = 32;
    if (!todo || !done) {
        free(todo);
        free(done);
        tool_error_set(err, NULL, 0, "out of memory");
        return -1;
    }
    if (run->task_seconds)
        for (t = 0; t < tasks; ++t) run->task_seconds[t] = -1.0;
    if (run->state_path && !run->object_count) {
        free(todo);
        free(done);
        tool_error_set(err, run->state_path, 0, "a state file needs the object count");
        return -1;
    }
    memset(&job, 0, sizeof(job));
    if (run->state_path) {
        FILE *f = fopen(run->state_path, "rb");
        if (f) {
            int r;
            fclose(f);
            r = cli__journal_read(bake, run->object_count, run->state_path, run->fingerprint, done, &run->state_torn);
            if (r < 0) run->state_ignored = 1;
            else run->resumed = (uint32_t)r;
        }
        /* a new journal, holding what was restored (compacted: no torn tail, no duplicates) */
        job.journal.path = run->state_path;
        job.journal.tasks = tasks;
        job.journal.objects = run->object_count;
        job.journal.every = run->state_every;
        job.journal.rec = (unsigned char *)malloc(12 + cli__payload_max(run->object_count));
        if (!job.journal.rec) tool_error_set(&job.journal.error, run->state_path, 0, "out of memory");
        if (!job.journal.rec || cli__journal_start(&job.journal, bake, run->fingerprint, done)) job.journal.failed = 1;
    }
    for (t = 0; t < tasks; ++t)
        if (!done[t]) todo[n++] = t;
    job.bake = bake;
    job.todo = todo;
    job.done = done;
    job.run = run;
    pthread_mutex_init(&job.mutex, NULL);
    run->threads_used = 0;
    if (run->memory && n) rc = cli__plan_threads(&job, &threads, n, err); /* may run the first task, alone */
    if (!quiet && rc == 0) {
        progress_begin(&bar, label, n - job.first);
        job.bar = &bar;
    }
    if (rc == 0 && n > job.first) {
        uint32_t i, k = threads ? threads : cpu_count();
        run->threads_used = k < n ? k : n;
        if (run->memory && k > 1) job.retry = (uint32_t *)malloc((size_t)n * sizeof(uint32_t));
        parallel_for(threads, n - job.first, cli__run_one, &job);
        if (job.retry) { /* the tasks refused memory while others ran, alone now (in task order) */
            uint32_t *again = job.retry, count = job.retry_count;
            job.retry = NULL;
            for (i = 1; i < count; ++i) /* insertion sort: few */
                for (k = i; k > 0 && again[k] < again[k - 1]; --k) { t = again[k]; again[k] = again[k - 1]; again[k - 1] = t; }
            job.todo = again;
            job.first = 0;
            for (i = 0; i < count; ++i) cli__run_one(&job, i, 0);
            free(again);
        }
    } else if (rc == 0 && n) {
        run->threads_used = 1;
    }
    if (job.bar) progress_end(&bar);
    pthread_mutex_destroy(&job.mutex);
    if (job.failed && run->state_path && job.journal.rec) /* keep what is done, compacted */
        job.journal.failed = cli__journal_start(&job.journal, bake, run->fingerprint, done) != 0;
    if (job.journal.f && fclose(job.journal.f) != 0 && !job.journal.failed) {
        tool_error_set(&job.journal.error, run->state_path, 0, "cannot write the state file: %s", strerror(errno));
        job.journal.failed = 1;
    }
    free(job.journal.rec);
    if (rc) {
        /* err is set */
    } else if (job.failed) {
        char a[32];
        if (job.error.result == PVS_ERROR_OUT_OF_MEMORY && run->memory && run->memory->refused)
            tool_error_set(err, NULL, 0, "cell %u: %s (the memory limit of %s (%s) was reached with the cell alone)",
                           pvs_bake_task_cell(bake, job.failed_task), job.error.message, cli_size_text((double)run->memory->limit, a),
                           run->memory->source);
        else
            tool_error_set(err, NULL, 0, "cell %u: %s", pvs_bake_task_cell(bake, job.failed_task), job.error.message);
        rc = -1;
    } else if (job.journal.failed) { /* the bake itself is fine: only resuming it would not be */
        fprintf(stderr, "warning: cannot save the bake's state: %s\n", job.journal.error.message);
    }
    free(todo);
    free(done);
    return rc;
}
