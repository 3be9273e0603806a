/* make bench, basis part: seconds to build 32 linear modes (bottom 10% fixed), 16 RKPM skinning
 * eigenmodes on 1000 kernels (40k grid integration points, weights evaluated at every vertex),
 * and 32 POD modes from 100 frames, on the bench meshes from 1k to 100k+ tets. Each is built 3
 * times: X_s is the median of the 3 runs' seconds, X_s_min and X_s_max the fastest and slowest
 * (the spread convention of bench_cases.h; here over repeated runs). The RKPM column is also given as a ratio to the freeform paper's training
 * time, 3.19 s on a GPU (Table 2). POD frames here are synthetic (the 32 modes with smooth
 * random time histories plus noise): POD cost depends on the sizes only, and full-order
 * training time is in fom_scaling (seconds per step times frames). Writes
 * bench/results/basis_scaling.{csv,json}. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "basis/basis.h"
#include "bench_cases.h"
#include "util/util.h"

#define REPEATS 3
#define PAPER_RKPM_SECONDS 3.19

static unsigned char *bottom_fixed(const rk_mesh *m)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int v = 0; v < m->nv; v++) {
        lo = fmin(lo, m->X[3 * v + 1]);
        hi = fmax(hi, m->X[3 * v + 1]);
    }
    unsigned char *f = calloc((size_t)m->nv, 1);
    for (int v = 0; v < m->nv; v++) f[v] = m->X[3 * v + 1] <= lo + 0.1 * (hi - lo);
    return f;
}

static int time_modes(const rk_scene_sim *sim, const unsigned char *fixed, bench_stat *sec, rk_basis *keep, rk_error *err)
{
    double t[REPEATS];
    for (int k = 0; k < REPEATS; k++) {
        rk_basis b;
        double t0 = rk_now();
        if (rk_basis_modes(&sim->fem, fixed, 0, 32, &b, err)) return -1;
        t[k] = rk_now() - t0;
        if (k == REPEATS - 1) *keep = b;
        else rk_basis_free(&b);
    }
    *sec = bench_stat_of(t, REPEATS);
    return 0;
}

static int time_rkpm(const rk_scene_sim *sim, bench_stat *sec, int *npoints, rk_error *err)
{
    double t[REPEATS];
    for (int k = 0; k < REPEATS; k++) {
        double t0 = rk_now();
        rk_rkpm_points pts;
        if (rk_rkpm_sample_mesh(&sim->mesh, 40000, &pts, err)) return -1;
        double *coef = malloc(sizeof(double) * pts.n);
        for (int i = 0; i < pts.n; i++) coef[i] = sim->fem.lambda[pts.tet[i]] + 4 * sim->fem.mu[pts.tet[i]];
        rk_basis b;
        int rc = rk_basis_rkpm_skinning(&pts, coef, 1000, 16, sim->mesh.X, sim->mesh.nv, NULL, NULL, 0, &b, NULL, err);
        t[k] = rk_now() - t0;
        *npoints = pts.n;
        free(coef);
        rk_rkpm_points_free(&pts);
        if (rc) return -1;
        rk_basis_free(&b);
    }
    *sec = bench_stat_of(t, REPEATS);
    return 0;
}

static int time_pod(const rk_scene_sim *sim, const rk_basis *modes, bench_stat *sec, rk_error *err)
{
    int n3 = 3 * sim->mesh.nv, T = 100;
    double *D = malloc(sizeof(double) * n3 * T);
    uint64_t rng = 7; /* util/util.h: the same frames on every platform */
    for (int f = 0; f < T; f++)
        for (int i = 0; i < n3; i++) D[(size_t)f * n3 + i] = 1e-4 * (rk_uniform(&rng) - 0.5);
    for (int j = 0; j < modes->r; j++) {
        double w = 1 + j, ph = rk_uniform(&rng) * 6.28, a = 1.0 / (1 + j);
        for (int f = 0; f < T; f++) {
            double c = a * sin(0.1 * w * f + ph);
            for (int i = 0; i < n3; i++) D[(size_t)f * n3 + i] += c * modes->U[(size_t)j * n3 + i];
        }
    }
    rk_sparse M = {0};
    rk_sparse_alloc_pattern(&sim->fem, &M, err);
    rk_fem_add_mass(&sim->fem, 0, 1.0, &M);
    double t[REPEATS];
    int rc = 0;
    for (int k = 0; k < REPEATS && !rc; k++) {
        rk_basis b;
        double t0 = rk_now();
        rc = rk_basis_pod(D, sim->mesh.nv, T, &M, 32, 0, &b, err);
        t[k] = rk_now() - t0;
        if (!rc) rk_basis_free(&b);
    }
    rk_sparse_free(&M);
    free(D);
    *sec = bench_stat_of(t, rc ? 0 : REPEATS);
    return rc;
}

int main(int argc, char **argv)
{
    const char *data = argc > 1 ? argv[1] : "tests/data/meshes";
    const char *out_dir = argc > 2 ? argv[2] : "bench/results";
    bench_case cases[9];
    int ncases = bench_cases(data, cases) - 1; /* up to box_100k */
    if (getenv("ROMKIT_BENCH_QUICK")) ncases = 4;
    FILE *csv, *json;
    if (bench_open_results(out_dir, "basis_scaling",
                           "case,vertices,tets,modes32_s,modes32_s_min,modes32_s_max,rkpm16_s,rkpm16_s_min,"
                           "rkpm16_s_max,rkpm_vs_paper_gpu,integration_points,pod32_s,pod32_s_min,pod32_s_max",
                           &csv, &json))
        return 1;
    printf("%-14s %8s %8s %12s %12s %12s %12s\n", "case", "verts", "tets", "32 modes s", "16 RKPM s",
           "RKPM/3.19s", "32 POD s");
    for (int c = 0; c < ncases; c++) {
        rk_error err;
        rk_scene scene;
        rk_scene_sim sim;
        rk_basis modes;
        bench_stat s_modes, s_rkpm, s_pod;
        int npoints;
        unsigned char *fixed = NULL;
        if (bench_scene(&cases[c], &scene, &sim, &err)) goto fail;
        fixed = bottom_fixed(&sim.mesh);
        if (time_modes(&sim, fixed, &s_modes, &modes, &err) || time_rkpm(&sim, &s_rkpm, &npoints, &err) ||
            time_pod(&sim, &modes, &s_pod, &err))
            goto fail;
        printf("%-14s %8d %8d %12.4g %12.4g %12.3f %12.4g\n", cases[c].name, sim.mesh.nv, sim.mesh.nt,
               s_modes.median, s_rkpm.median, s_rkpm.median / PAPER_RKPM_SECONDS, s_pod.median);
        fflush(stdout);
        fprintf(csv, "%s,%d,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.4f,%d,%.6g,%.6g,%.6g\n", cases[c].name, sim.mesh.nv,
                sim.mesh.nt, BENCH_STAT3(s_modes), BENCH_STAT3(s_rkpm), s_rkpm.median / PAPER_RKPM_SECONDS, npoints,
                BENCH_STAT3(s_pod));
        fprintf(json,
                "%s  {\"case\": \"%s\", \"vertices\": %d, \"tets\": %d, \"modes32_seconds\": %.6g,"
                " \"modes32_seconds_min\": %.6g, \"modes32_seconds_max\": %.6g, \"rkpm16_seconds\": %.6g,"
                " \"rkpm16_seconds_min\": %.6g, \"rkpm16_seconds_max\": %.6g, \"rkpm_vs_paper_gpu\": %.4f,"
                " \"integration_points\": %d, \"pod32_seconds\": %.6g, \"pod32_seconds_min\": %.6g,"
                " \"pod32_seconds_max\": %.6g}\n",
                c ? "," : "", cases[c].name, sim.mesh.nv, sim.mesh.nt, BENCH_STAT3(s_modes), BENCH_STAT3(s_rkpm),
                s_rkpm.median / PAPER_RKPM_SECONDS, npoints, BENCH_STAT3(s_pod));
        rk_basis_free(&modes);
        free(fixed);
        rk_scene_sim_free(&sim);
        rk_scene_free(&scene);
        continue;
    fail:
        fprintf(stderr, "bench_basis: %s: %s\n", cases[c].name, err.msg);
        return 1;
    }
    fprintf(json, "]\n");
    fclose(csv);
    fclose(json);
    return 0;
}
