/* The meshes every make-bench program runs on (1k to 200k tets), and the shared helpers: the
 * scene around a mesh, and a timing's median with its spread.
 *
 * Spread convention, every bench: a timing column X is the median of its repeated samples and is
 * followed by X_min and X_max, the smallest and largest sample (CSV columns and JSON keys alike).
 * Each bench's header comment says what its samples are (repeated runs, or the steps of one run). */
#ifndef RK_BENCH_CASES_H
#define RK_BENCH_CASES_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "pipeline/pipeline.h"
#include "util/util.h"

typedef struct {
    const char *name;
    char mesh_json[512]; /* the scene's "mesh" value */
    int steps;           /* full-order steps to time */
} bench_case;

/* Fills cases (room for 9) with the mesh set; returns the count. */
static inline int bench_cases(const char *data, bench_case *c)
{
    static const struct { const char *name, *box, *file; int steps; } t[] = {
        {"box_1k", "[10, 5, 4]", NULL, 10},
        {"octopus-low", NULL, "octopus-low.mesh", 10},
        {"armadillo_4k", NULL, "armadillo_4k.node", 10},
        {"box_10k", "[20, 10, 8]", NULL, 8},
        {"bunny_19k", NULL, "bunny_19k.msh", 6},
        {"dinosaur_50k", NULL, "dinosaur_bin.msh", 5},
        {"box_50k", "[40, 15, 14]", NULL, 5},
        {"box_100k", "[50, 20, 17]", NULL, 4},
        {"box_200k", "[64, 24, 22]", NULL, 3},
    };
    for (int k = 0; k < 9; k++) {
        c[k].name = t[k].name;
        c[k].steps = t[k].steps;
        if (t[k].box) snprintf(c[k].mesh_json, sizeof c[k].mesh_json, "{\"box\": {\"size\": [2, 1, 1], \"cells\": %s}}", t[k].box);
        else snprintf(c[k].mesh_json, sizeof c[k].mesh_json, "{\"file\": \"%s/%s\"}", data, t[k].file);
    }
    return 9;
}

/* One thread per library unless the caller chose (the variables all set): romkit's own count
 * (ROMKIT_THREADS, util.h, which sets OpenBLAS's over its variable), OpenBLAS's and OpenMP's, then
 * the program starts again so the libraries read them. For benches whose rows must not depend on
 * how loaded the 2-core machine is. */
static inline void bench_pin_one_thread(char **argv, const char *name)
{
    setenv("ROMKIT_THREADS", "1", 0);
    if (getenv("OPENBLAS_NUM_THREADS") && getenv("OMP_NUM_THREADS") && getenv("OMP_THREAD_LIMIT")) return;
    setenv("OPENBLAS_NUM_THREADS", "1", 0);
    setenv("OMP_NUM_THREADS", "1", 0);
    setenv("OMP_THREAD_LIMIT", "1", 0);
    execv("/proc/self/exe", argv);
    fprintf(stderr, "%s: re-executing with the thread counts set failed\n", name);
    exit(1);
}

/* A timing: the median of its samples and their spread (smallest, largest). */
typedef struct {
    double median, min, max;
} bench_stat;

/* The median, min and max of t[0..n); sorts t (rk_median sorts in place). NAN when n < 1. */
static inline bench_stat bench_stat_of(double *t, int n)
{
    bench_stat s = {NAN, NAN, NAN};
    if (n < 1) return s;
    s.median = rk_median(t, n);
    s.min = t[0];
    s.max = t[n - 1];
    return s;
}

/* s scaled by k (seconds to microseconds, say). */
static inline bench_stat bench_stat_scale(bench_stat s, double k)
{
    bench_stat o = {s.median * k, s.min * k, s.max * k};
    return o;
}

/* The three values of s for a "%.6g,%.6g,%.6g" (or JSON) format: median, min, max. */
#define BENCH_STAT3(s) (s).median, (s).min, (s).max

/* A soft neo-Hookean object of the case's mesh under gravity, h = 0.01 s. */
static inline int bench_scene(const bench_case *c, rk_scene *scene, rk_scene_sim *sim, rk_error *err)
{
    char text[2048];
    snprintf(text, sizeof text,
             "{\"objects\": [{\"mesh\": %s,"
             " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}}],"
             " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 1}}",
             c->mesh_json);
    if (rk_scene_parse(text, "bench.json", scene, err)) return -1;
    if (rk_scene_build(scene, sim, err)) {
        rk_scene_free(scene);
        return -1;
    }
    return 0;
}

/* Opens OUT_DIR/NAME.csv (with its header line) and OUT_DIR/NAME.json (with its opening "["). */
static inline int bench_open_results(const char *out_dir, const char *name, const char *csv_header,
                                     FILE **csv, FILE **json)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.csv", out_dir, name);
    *csv = fopen(path, "w");
    snprintf(path, sizeof path, "%s/%s.json", out_dir, name);
    *json = fopen(path, "w");
    if (!*csv || !*json) {
        fprintf(stderr, "bench: cannot write %s results into %s\n", name, out_dir);
        return -1;
    }
    fprintf(*csv, "%s\n", csv_header);
    fprintf(*json, "[\n");
    return 0;
}


#endif
