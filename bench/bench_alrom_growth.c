/* How the adaptive linear ROM carries a perturbation, against full order (issue 33): two copies of
 * the entry's simulator (precompute/grassmann) and two of the full-order one step the scene side
 * by side; after step K0 one copy of each is moved by EPS times a fixed random direction on the
 * free dofs (rk_alrom_set_state / rk_fom_set_state: the history ring is kept), and every later
 * step prints |x_B - x_A| and its ratio to the perturbation's size. A stable method carries it
 * like full order does (which damps it); a ratio far above 1 is a free run that amplifies its
 * own errors.
 * Usage: bench_alrom_growth SCENE.json ENTRY K0 EPS   (the entry: method adaptive_linear, with its
 * training list if it has one) */
#include "pipeline/pipeline.h"
#include "pipeline/method_adaptive_linear.h"
#include "grassmann/grassmann.h"
#include "fom/fom.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static double distance(const double *a, const double *b, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += (a[i] - b[i]) * (a[i] - b[i]);
    return sqrt(s);
}

/* x + eps dir on the free dofs, as the simulator's new state at time t */
static void nudge(const double *x, const double *dir, const char *prescribed, double eps, int n, double *out)
{
    for (int i = 0; i < n; i++) out[i] = x[i] + (prescribed[i] ? 0 : eps * dir[i]);
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: %s SCENE.json ENTRY K0 EPS\n", argv[0]);
        return 2;
    }
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    int k = atoi(argv[2]), k0 = atoi(argv[3]);
    double eps = atof(argv[4]);
    if (rk_scene_load(argv[1], &scene, &err) || rk_scene_build(&scene, &sim, &err)) goto fail;
    if (k < 0 || k >= scene.nentries || !rk_adaptive_linear_of(&scene.entries[k])) {
        fprintf(stderr, "entry %d is not an adaptive_linear entry of %s\n", k, argv[1]);
        return 2;
    }
    const rk_rom_entry *e = &scene.entries[k];
    double *D = NULL;
    int T = 0;
    if ((e->ntraining ? rk_scene_training_set(&scene, &sim, e, &D, &T, &err) : rk_scene_training_frames(&sim, &D, &T, &err)))
        goto fail;
    int n = 3 * sim.mesh.nv;
    rk_alrom A, B;
    rk_decoder dA, dB;
    rk_fom FA, FB;
    if (rk_scene_alrom_init(&scene, &sim, e, D, T, &A, &dA, NULL, &err) ||
        rk_scene_alrom_init(&scene, &sim, e, D, T, &B, &dB, NULL, &err) || rk_fom_init(&FA, &sim.fem, &sim.options, &err) ||
        rk_fom_init(&FB, &sim.fem, &sim.options, &err))
        goto fail;
    double *x = malloc(sizeof(double) * n), *dir = malloc(sizeof(double) * n), d0 = 0, f0 = 0;
    if (!x || !dir) return 1;
    uint64_t seed = 7;
    for (int i = 0; i < n; i++) dir[i] = rk_uniform(&seed) - 0.5;
    rk_fom_view view;
    rk_fom_view_get(&FA, &view);
    printf("step,alrom_difference,alrom_growth,fom_difference,fom_growth\n");
    for (int t = 0; t < sim.steps; t++) {
        if (rk_alrom_step(&A, &err) || rk_alrom_step(&B, &err) || rk_fom_step(&FA, &err) || rk_fom_step(&FB, &err))
            goto fail;
        if (t == k0) {
            double time = (t + 1) * sim.options.h;
            nudge(B.fom.x, dir, view.prescribed, eps, n, x);
            rk_alrom_set_state(&B, x, B.fom.v, NULL, NULL, time);
            nudge(FB.x, dir, view.prescribed, eps, n, x);
            rk_fom_set_state(&FB, x, FB.v, NULL, NULL, time);
            d0 = distance(B.fom.x, A.fom.x, n);
            f0 = distance(FB.x, FA.x, n);
        } else if (t > k0) {
            double d = distance(B.fom.x, A.fom.x, n), f = distance(FB.x, FA.x, n);
            printf("%d,%.4e,%.4g,%.4e,%.4g\n", t + 1, d, d / d0, f, f / f0);
        }
    }
    return 0;
fail:
    fprintf(stderr, "%s\n", err.msg);
    return 1;
}
