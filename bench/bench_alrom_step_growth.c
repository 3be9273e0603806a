/* The adaptive linear ROM's per-step growth factor (issue 33): the scene's entry stepped from rest,
 * and at every step the finite-difference derivative of the step map (u, v) -> (u', v') with its
 * basis update, its largest ratio over a short power iteration in the energy norm (growth.c,
 * rk_alrom_step_growth). A step that does not amplify errors has it at most 1.
 * Usage: bench_alrom_step_growth SCENE.json ENTRY [NDIR [EPS]]   (ENTRY: an index into the rom list)
 * ROMKIT_GROWTH_LAMBDA, _RIDGE and _BUDGET override the entry's lambda, ridge and budget; ROMKIT_GROWTH_LINEAR=1 drops a quadratic
 * decoder's quadratic term and takes lambda 1: PCA's fixed basis in the same simulator.
 * Prints step, growth, blended (1: the step's basis blended the history). */
#include "pipeline/pipeline.h"
#include "pipeline/method_adaptive_linear.h"
#include "grassmann/grassmann.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s SCENE.json ENTRY [NDIR [EPS]]\n", argv[0]);
        return 2;
    }
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    int k = atoi(argv[2]), ndir = argc > 3 ? atoi(argv[3]) : 4;
    double eps = argc > 4 ? atof(argv[4]) : 1e-6;
    if (rk_scene_load(argv[1], &scene, &err) || rk_scene_build(&scene, &sim, &err)) goto fail;
    if (k < 0 || k >= scene.nentries || !rk_adaptive_linear_of(&scene.entries[k])) {
        fprintf(stderr, "entry %d is not an adaptive_linear entry of %s\n", k, argv[1]);
        return 2;
    }
    const rk_rom_entry *e = &scene.entries[k];
    rk_alrom_options o = rk_adaptive_linear_of(e)->opt;
    const char *lam = getenv("ROMKIT_GROWTH_LAMBDA"), *lin = getenv("ROMKIT_GROWTH_LINEAR");
    if (lam) o.lambda = atof(lam);
    if (getenv("ROMKIT_GROWTH_RIDGE")) o.ridge = atof(getenv("ROMKIT_GROWTH_RIDGE"));
    if (getenv("ROMKIT_GROWTH_BUDGET")) o.budget = atof(getenv("ROMKIT_GROWTH_BUDGET"));
    double *D = NULL;
    int T = 0, n = 3 * sim.mesh.nv;
    if ((e->ntraining ? rk_scene_training_set(&scene, &sim, e, &D, &T, &err) : rk_scene_training_frames(&sim, &D, &T, &err)))
        goto fail;
    rk_sparse M, K;
    if (rk_sparse_alloc_pattern(&sim.fem, &M, &err) || rk_sparse_alloc_pattern(&sim.fem, &K, &err)) goto fail;
    rk_fem_add_mass(&sim.fem, sim.options.lumped_mass, 1.0, &M);
    rk_fem_add_rest_stiffness(&sim.fem, 1.0, &K);
    rk_decoder dec;
    if (lin && atoi(lin)) {
        double *Phi, *Psi;
        if (rk_scene_quadratic_parts(&sim, e, D, T, &Phi, &Psi, &err)) goto fail;
        memset(Psi, 0, sizeof(double) * (size_t)n * ((size_t)e->basis.size * (e->basis.size + 1) / 2));
        if (rk_quadratic_decoder(n, e->basis.size, Phi, Psi, &M, &dec, &err)) goto fail;
        free(Phi);
        free(Psi);
        o.lambda = 1;
    } else if (rk_scene_alrom_decoder(&scene, &sim, e, D, T, &dec, &err))
        goto fail;
    sim.options.newton_tol = 1e-9; /* m/s: the differences are of 1e-6 of the state */
    rk_alrom A, pre, probe;
    if (rk_alrom_init(&A, &sim.fem, &sim.options, &dec, &o, &err) || rk_alrom_init(&pre, &sim.fem, &sim.options, &dec, &o, &err) ||
        rk_alrom_init(&probe, &sim.fem, &sim.options, &dec, &o, &err))
        goto fail;
    uint64_t seed = 7;
    double worst = 0, worst_blended = 0, log_sum = 0;
    int blended_steps = 0;
    printf("step,growth,blended\n");
    for (int t = 0; t < sim.steps; t++) {
        double g;
        long used = A.stats.history_used;
        if (rk_alrom_step_growth(&A, &pre, &probe, &M, &K, ndir, eps, &seed, &g, &err)) goto fail;
        int blended = A.stats.history_used > used;
        printf("%d,%.4f,%d\n", t + 1, g, blended);
        fflush(stdout);
        worst = fmax(worst, g);
        if (blended) worst_blended = fmax(worst_blended, g), log_sum += log(g), blended_steps++;
    }
    printf("# largest growth %.4f, over blended steps %.4f (geometric mean %.4f, %d steps)\n", worst, worst_blended,
           blended_steps ? exp(log_sum / blended_steps) : 0, blended_steps);
    return 0;
fail:
    fprintf(stderr, "%s\n", err.msg);
    return 1;
}
