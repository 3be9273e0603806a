/* bench/beam_reference.sh's tool: one level of a mesh-convergence study of a scene's full-order
 * run, and the normalized MSE between two levels at the coarse level's vertices.
 *
 *   bench_reference run SCENE.json LEVEL FRAMES.npy [--cells X,Y,Z] [--steps N] [--order 2]
 *       The scene (its box mesh given X x Y x Z cells when --cells is there) with every object's
 *       mesh refined LEVEL more times, built as romkit compare builds a refined reference
 *       (rk_scene_build_reference), run at full order as the scene says. FRAMES.npy: every frame
 *       (the start, then after each step: T + 1 x n x 3 positions) of the n vertices of the
 *       unrefined scene, which refinement numbers first (checked bit for bit). Prints one line,
 *           vertices,tets,steps,seconds_total,seconds_per_step,newton_per_step,unconverged_steps,peak_rss_mib
 *       seconds_total: the whole run (rk_fom_stats.seconds_total); seconds_per_step: the median step;
 *       peak_rss_mib: this process's peak resident memory (ru_maxrss), the level's alone.
 *       --steps N: only the first N steps (a probe, to estimate what the whole run costs).
 *       --order 2: on quadratic tets (rk_p2_fom_run, the scene key "reference": {"order": 2});
 *       vertices then counts the P1 mesh's vertices, not the P2 nodes.
 *   bench_reference nmse A.npy B.npy [--steps N]
 *       Two such files of the same vertices and frames (the same rest positions, checked): prints
 *           normalized_mse,normalized_max_error
 *       over every frame after the start, or over the first N (--steps N).
 *       util/util.h's metrics (the FreeForm paper's normalized MSE: mean over the vertices and the
 *       frames after the start of |a - b|^2 over the squared rest bounding-box diagonal), as romkit
 *       compare reports them.
 *
 * Threads: ROMKIT_THREADS (util.h) as the caller sets it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "pipeline/pipeline.h"
#include "util/util.h"

typedef struct {
    const int *map;  /* the refined run's vertex kept as vertex i */
    int n;           /* vertices kept */
    int T;
    double *x;       /* (T + 1) x n x 3 */
    double *secs;    /* each step's seconds */
} frames;

static int keep_x(frames *f, int step, const double *xs, double seconds)
{
    double *x = f->x + (size_t)3 * f->n * step;
    for (int i = 0; i < f->n; i++) memcpy(x + 3 * (size_t)i, xs + 3 * (size_t)f->map[i], 3 * sizeof(double));
    if (step > 0) f->secs[step - 1] = seconds;
    return 0;
}

static int keep(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    return keep_x(ctx, step, fom->x, seconds);
}

static int keep_p2(void *ctx, int step, const double *x, const double *v, double seconds, rk_error *err)
{
    return keep_x(ctx, step, x, seconds);
}

static int parse_cells(const char *s, int cells[3])
{
    char tail;
    return sscanf(s, "%d,%d,%d%c", &cells[0], &cells[1], &cells[2], &tail) == 3 && cells[0] > 0 && cells[1] > 0 &&
           cells[2] > 0;
}

static int run_level(const char *scene_path, int level, const char *out, const int *cells, int steps, int order,
                     rk_error *err)
{
    rk_scene scene;
    if (rk_scene_load(scene_path, &scene, err)) return -1;
    int rc = -1, *map = NULL;
    rk_scene_sim coarse = {0}, fine = {0};
    frames f = {0};
    if (cells)
        for (int k = 0; k < scene.nobjects; k++) {
            if (scene.objects[k].shape != RK_SHAPE_BOX) {
                rk_fail(err, "%s: --cells: objects[%d] is not a box mesh", scene_path, k);
                goto done;
            }
            memcpy(scene.objects[k].box_cells, cells, sizeof scene.objects[k].box_cells);
        }
    if (rk_scene_build(&scene, &coarse, err)) goto done;
    rk_scene_sim *sim = &coarse;
    if (level > 0) {
        if (rk_scene_build_reference(&scene, &coarse, level, &fine, &map, err)) goto done;
        sim = &fine;
    } else {
        map = rk_calloc((size_t)coarse.mesh.nv, sizeof *map, err);
        if (!map) goto done;
        for (int i = 0; i < coarse.mesh.nv; i++) map[i] = i;
    }
    if (steps > 0 && steps < sim->steps) sim->steps = sim->options.steps = steps;
    f.map = map;
    f.n = coarse.mesh.nv;
    f.T = sim->options.is_static ? 1 : sim->steps;
    f.x = rk_calloc((size_t)3 * f.n * (f.T + 1), sizeof(double), err);
    f.secs = rk_calloc((size_t)f.T + 1, sizeof(double), err);
    if (!f.x || !f.secs) goto done;
    int nv = sim->mesh.nv, nt = sim->mesh.nt;
    char label[64];
    snprintf(label, sizeof label, "level %d (%d tets)", level, nt);
    rk_fom_stats stats;
    if (order == 2 ? rk_p2_fom_run(&sim->fem, &sim->options, keep_p2, &f, &stats, err)
                   : rk_scene_fom_run(sim, NULL, label, keep, &f, &stats, err))
        goto done;
    long shape[3] = {f.T + 1, f.n, 3};
    if (rk_npy_write(out, f.x, 3, shape, err)) goto done;
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("%d,%d,%d,%.6g,%.6g,%.4g,%ld,%.1f\n", nv, nt, f.T, stats.seconds_total, rk_median(f.secs, f.T),
           (double)stats.newton_iterations / (f.T > 0 ? f.T : 1), stats.unconverged_steps, ru.ru_maxrss / 1024.0);
    rc = 0;
done:
    free(f.x);
    free(f.secs);
    free(map);
    rk_scene_sim_free(&fine);
    rk_scene_sim_free(&coarse);
    rk_scene_free(&scene);
    return rc;
}

static int nmse(const char *a_path, const char *b_path, int steps, rk_error *err)
{
    double *a = NULL, *b = NULL;
    int nda, ndb, rc = -1;
    long sa[4], sb[4];
    if (rk_npy_read(a_path, &a, &nda, sa, err) || rk_npy_read(b_path, &b, &ndb, sb, err)) goto done;
    if (nda != 3 || ndb != 3 || sa[2] != 3 || sa[0] != sb[0] || sa[1] != sb[1] || sb[2] != 3 || sa[0] < 2) {
        rk_fail(err, "%s and %s: need T x n x 3 frames of the same T >= 2 and n", a_path, b_path);
        goto done;
    }
    int n = (int)sa[1], T = (int)sa[0] - 1;
    if (steps > 0 && steps < T) T = steps;
    if (memcmp(a, b, sizeof(double) * 3 * (size_t)n)) {
        rk_fail(err, "%s and %s: the first frames (rest positions) differ: not the same vertices", a_path, b_path);
        goto done;
    }
    rk_run_error e;
    rk_run_error_init(&e, a, n);
    for (int s = 1; s <= T; s++) rk_run_error_add(&e, a + (size_t)3 * n * s, b + (size_t)3 * n * s);
    printf("%.6e,%.6e\n", rk_normalized_mse(&e), rk_normalized_max_error(&e));
    rc = 0;
done:
    free(a);
    free(b);
    return rc;
}

static void usage(void)
{
    fprintf(stderr, "usage: bench_reference run SCENE.json LEVEL FRAMES.npy [--cells X,Y,Z] [--steps N] [--order 2]\n"
                    "       bench_reference nmse A.npy B.npy [--steps N]\n");
}

int main(int argc, char **argv)
{
    rk_error err = {{0}};
    if (rk_threads_init(&err)) {
        fprintf(stderr, "bench_reference: %s\n", err.msg);
        return 1;
    }
    if (argc >= 5 && strcmp(argv[1], "run") == 0) {
        int cells[3], *c = NULL;
        char *end;
        long level = strtol(argv[3], &end, 10);
        if (*end || level < 0 || level > RK_MESH_REFINE_MAX_LEVELS) {
            usage();
            return 2;
        }
        long steps = 0;
        int order = 1;
        for (int i = 5; i < argc; i += 2) {
            if (i + 1 < argc && strcmp(argv[i], "--cells") == 0 && parse_cells(argv[i + 1], cells)) c = cells;
            else if (i + 1 < argc && strcmp(argv[i], "--order") == 0 && strcmp(argv[i + 1], "2") == 0) order = 2;
            else if (i + 1 < argc && strcmp(argv[i], "--steps") == 0 && (steps = strtol(argv[i + 1], &end, 10)) > 0 &&
                     !*end)
                continue;
            else {
                usage();
                return 2;
            }
        }
        if (run_level(argv[2], (int)level, argv[4], c, (int)steps, order, &err) == 0) return 0;
    } else if ((argc == 4 || (argc == 6 && strcmp(argv[4], "--steps") == 0)) && strcmp(argv[1], "nmse") == 0) {
        char *end = NULL;
        long steps = argc == 6 ? strtol(argv[5], &end, 10) : 0;
        if (argc == 6 && (*end || steps < 1)) {
            usage();
            return 2;
        }
        if (nmse(argv[2], argv[3], (int)steps, &err) == 0) return 0;
    } else {
        usage();
        return 2;
    }
    fprintf(stderr, "bench_reference: %s\n", err.msg);
    return 1;
}
