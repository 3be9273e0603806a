/* Why the adaptive linear ROM's free run loses to PCA (issue 33, docs/methods.md's free-run
 * section): the scene's full-order run, the adaptive entry's free run (its decoder and moving
 * cubature as romkit compare builds them) and PCA's fixed basis in the same simulator (the fitted
 * quadratic's POD modes, its quadratic term dropped, lambda 1: ROMKIT_GROWTH_LINEAR's PCA), step by
 * step side by side. Per step: each ROM's error against full order |x - x_ref| / |x_ref - X|, its
 * amplitude |u|_M / |u_ref|_M and shape cos(u, u_ref)_M (the error's amplitude and phase), the
 * kinetic and elastic energies of all three, and the share of the adaptive step's incoming kinetic
 * energy its new basis cannot represent, |v - P v|_M^2 / |v|_M^2 (P the M-orthogonal projection on
 * the step's basis; the inertia term drops it), its Newton iterations and the decoder's misfit at
 * its state |g(e(u)) - u|_M / |u|_M (the code leaving the training manifold).
 * Also the floors: full order's state's misfit through PCA's projection and the decoder's manifold.
 * BENCH_REALIGN=1: each step from full order's state (romkit compare's realigned run; the summary's
 * free-run line is then that run's relative error).
 * BENCH_START=k: both ROMs follow full order's states for the first k steps, then run free.
 * BENCH_LAMBDA, BENCH_RIDGE, BENCH_BUDGET override the entry's lambda, ridge and budget.
 * BENCH_EXACT=1: every element's forces (no cubature); BENCH_NEWTON_TOL: the Newton tolerance.
 * Usage: bench_alrom_freerun SCENE.json ENTRY   (ENTRY: an adaptive_linear entry, quadratic_pod) */
#include "pipeline/pipeline.h"
#include "pipeline/method_adaptive_linear.h"
#include "grassmann/grassmann.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* |v - P v|_M^2 / |v|_M^2 over the free dofs, P the M-orthogonal projection on span(U) */
static double dropped(int n, int r, const double *U, const rk_sparse *M, const char *prescribed, const double *v)
{
    double *w = malloc(sizeof(double) * (size_t)n * (3 + (size_t)r)), *Mw = w + n, *Pw = Mw + n, *MU = Pw + n;
    double A[64 * 64], b[64];
    for (int i = 0; i < n; i++) w[i] = prescribed[i] ? 0 : v[i];
    rk_sparse_mul(M, w, Mw);
    for (int j = 0; j < r; j++) rk_sparse_mul(M, U + (size_t)j * n, MU + (size_t)j * n);
    for (int j = 0; j < r; j++) {
        double acc = 0;
        for (int i = 0; i < n; i++) acc += U[(size_t)j * n + i] * Mw[i];
        b[j] = acc;
        for (int k = 0; k < r; k++) {
            double a = 0;
            for (int i = 0; i < n; i++) a += U[(size_t)j * n + i] * MU[(size_t)k * n + i];
            A[j * r + k] = a;
        }
    }
    /* Gaussian elimination (A SPD, r small) */
    for (int c = 0; c < r; c++)
        for (int i = c + 1; i < r; i++) {
            double f = A[i * r + c] / A[c * r + c];
            for (int k = c; k < r; k++) A[i * r + k] -= f * A[c * r + k];
            b[i] -= f * b[c];
        }
    for (int i = r - 1; i >= 0; i--) {
        for (int k = i + 1; k < r; k++) b[i] -= A[i * r + k] * b[k];
        b[i] /= A[i * r + i];
    }
    for (int i = 0; i < n; i++) {
        double acc = 0;
        for (int j = 0; j < r; j++) acc += U[(size_t)j * n + i] * b[j];
        Pw[i] = w[i] - acc;
    }
    double ww = rk_sparse_dot(M, w, w), dd = rk_sparse_dot(M, Pw, Pw);
    free(w);
    return ww > 0 ? dd / ww : 0;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s SCENE.json ENTRY\n", argv[0]);
        return 2;
    }
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    int k = atoi(argv[2]);
    if (rk_scene_load(argv[1], &scene, &err) || rk_scene_build(&scene, &sim, &err)) goto fail;
    if (k < 0 || k >= scene.nentries || !rk_adaptive_linear_of(&scene.entries[k])) {
        fprintf(stderr, "entry %d is not an adaptive_linear entry of %s\n", k, argv[1]);
        return 2;
    }
    const rk_rom_entry *e = &scene.entries[k];
    rk_alrom_options o = rk_adaptive_linear_of(e)->opt, ol;
    double *D = NULL;
    int T = 0, n = 3 * sim.mesh.nv, r = e->basis.size;
    if (r > 64) {
        fprintf(stderr, "entry %d: r = %d, this diagnostic handles r up to 64\n", k, r);
        return 2;
    }
    if ((e->ntraining ? rk_scene_training_set(&scene, &sim, e, &D, &T, &err) : rk_scene_training_frames(&sim, &D, &T, &err)))
        goto fail;
    rk_sparse M;
    if (rk_sparse_alloc_pattern(&sim.fem, &M, &err)) goto fail;
    rk_fem_add_mass(&sim.fem, sim.options.lumped_mass, 1.0, &M);
    rk_decoder dec, lin;
    double *Phi, *Psi;
    if (rk_scene_alrom_decoder(&scene, &sim, e, D, T, &dec, &err) || rk_scene_quadratic_parts(&sim, e, D, T, &Phi, &Psi, &err))
        goto fail;
    memset(Psi, 0, sizeof(double) * (size_t)n * ((size_t)r * (r + 1) / 2));
    if (rk_quadratic_decoder(n, r, Phi, Psi, &M, &lin, &err)) goto fail;
    int *cel = NULL, ncub = 0;
    double *cw = NULL;
    rk_moving_fit fit;
    if (getenv("BENCH_NEWTON_TOL")) sim.options.newton_tol = atof(getenv("BENCH_NEWTON_TOL"));
    int exact = getenv("BENCH_EXACT") && atoi(getenv("BENCH_EXACT"));
    if (e->cubature && !exact && rk_scene_alrom_cubature(&sim, e, &dec, D, T, &cel, &cw, &ncub, &fit, &err)) goto fail;
    o.ncub = ncub, o.cub_element = cel, o.cub_weight = cw;
    if (getenv("BENCH_LAMBDA")) o.lambda = atof(getenv("BENCH_LAMBDA"));
    if (getenv("BENCH_RIDGE")) o.ridge = atof(getenv("BENCH_RIDGE"));
    if (getenv("BENCH_BUDGET")) o.budget = atof(getenv("BENCH_BUDGET"));
    ol = o;
    ol.lambda = 1;
    rk_fom F;
    rk_alrom A, P;
    if (rk_fom_init(&F, &sim.fem, &sim.options, &err) || rk_alrom_init(&A, &sim.fem, &sim.options, &dec, &o, &err) ||
        rk_alrom_init(&P, &sim.fem, &sim.options, &lin, &ol, &err))
        goto fail;
    rk_fom_view view;
    rk_fom_view_get(&A.fom, &view);
    const double *X = sim.mesh.X;
    double *v0 = malloc(sizeof(double) * (size_t)n * 2), *gp = v0 + n, pc[64];
    double *uf = malloc(sizeof(double) * (size_t)n * 3), *ua = uf + n, *up = ua + n;
    if (!v0 || !uf) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    rk_run_error ea, ep;
    rk_run_error_init(&ea, X, n / 3);
    rk_run_error_init(&ep, X, n / 3);
    double lost = 0, sff = 0, sfp = 0, sfa = 0; /* the floors over the run: sum |u_ref|_M^2 and the misfits' */
    printf("step,err_ad,err_pca,amp_ad,amp_pca,cos_ad,cos_pca,ke_fom,ke_ad,ke_pca,el_fom,el_ad,el_pca,dropped_ad,"
           "newton_ad,newton_pca,misfit_ad,floor_pca,floor_ad\n");
    int start = getenv("BENCH_START") ? atoi(getenv("BENCH_START")) : 0;
    int realign = getenv("BENCH_REALIGN") && atoi(getenv("BENCH_REALIGN"));
    for (int t = 0; t < sim.steps; t++) {
        memcpy(v0, A.fom.v, sizeof(double) * (size_t)n);
        double ke_in = rk_fom_kinetic_energy(&A.fom);
        long ia = A.stats.newton_iterations, ip = P.stats.newton_iterations;
        if (t < start) { /* the ROMs put on full order's run until step `start`, then free */
            if (rk_fom_step(&F, &err)) goto fail;
            rk_alrom_set_state(&A, F.x, F.v, NULL, NULL, F.t);
            rk_alrom_set_state(&P, F.x, F.v, NULL, NULL, F.t);
            continue;
        }
        if (realign && t > 0) { /* romkit compare's realigned run, for both ROMs */
            rk_alrom_set_state(&A, F.x, F.v, NULL, NULL, F.t);
            rk_alrom_set_state(&P, F.x, F.v, NULL, NULL, F.t);
            memcpy(v0, A.fom.v, sizeof(double) * (size_t)n);
            ke_in = rk_fom_kinetic_energy(&A.fom);
        }
        if (rk_fom_step(&F, &err) || rk_alrom_step(&A, &err) || rk_alrom_step(&P, &err)) goto fail;
        const double *U = rk_alrom_step_basis(&A);
        double drop = t > start ? dropped(n, r, U, view.M, view.prescribed, v0) : 0;
        lost += drop * ke_in;
        for (int i = 0; i < n; i++) uf[i] = F.x[i] - X[i], ua[i] = A.fom.x[i] - X[i], up[i] = P.fom.x[i] - X[i];
        double ff = rk_sparse_dot(&M, uf, uf), aa = rk_sparse_dot(&M, ua, ua), pp = rk_sparse_dot(&M, up, up);
        double da = 0, dp = 0, rf = 0;
        for (int i = 0; i < n; i++)
            da += (ua[i] - uf[i]) * (ua[i] - uf[i]), dp += (up[i] - uf[i]) * (up[i] - uf[i]), rf += uf[i] * uf[i];
        /* the code's drift: the decoder's misfit at the state, |g(e(u)) - u|_M / |u|_M */
        if (dec.encode(dec.ctx, ua, pc, &err) || dec.decode(dec.ctx, pc, gp, &err)) goto fail;
        for (int i = 0; i < n; i++) gp[i] -= ua[i];
        double misfit = sqrt(rk_sparse_dot(&M, gp, gp) / aa);
        /* the floors: full order's state through PCA's M-orthogonal projection (the linear decoder's
         * encoder) and through the adaptive decoder's manifold */
        double floor_p, floor_a;
        if (lin.encode(lin.ctx, uf, pc, &err) || lin.decode(lin.ctx, pc, gp, &err)) goto fail;
        for (int i = 0; i < n; i++) gp[i] -= uf[i];
        floor_p = sqrt(rk_sparse_dot(&M, gp, gp) / ff);
        if (dec.encode(dec.ctx, uf, pc, &err) || dec.decode(dec.ctx, pc, gp, &err)) goto fail;
        for (int i = 0; i < n; i++) gp[i] -= uf[i];
        floor_a = sqrt(rk_sparse_dot(&M, gp, gp) / ff);
        sff += ff, sfp += floor_p * floor_p * ff, sfa += floor_a * floor_a * ff;
        rk_run_error_add(&ea, A.fom.x, F.x);
        rk_run_error_add(&ep, P.fom.x, F.x);
        printf("%d,%.4g,%.4g,%.4f,%.4f,%.5f,%.5f,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%.3g,%ld,%ld,%.3g,%.3g,%.3g\n", t + 1, sqrt(da / rf),
               sqrt(dp / rf), sqrt(aa / ff), sqrt(pp / ff), rk_sparse_dot(&M, ua, uf) / sqrt(aa * ff),
               rk_sparse_dot(&M, up, uf) / sqrt(pp * ff), rk_fom_kinetic_energy(&F), rk_fom_kinetic_energy(&A.fom),
               rk_fom_kinetic_energy(&P.fom), rk_fom_elastic_energy(&F), rk_fom_elastic_energy(&A.fom),
               rk_fom_elastic_energy(&P.fom), drop, A.stats.newton_iterations - ia, P.stats.newton_iterations - ip, misfit, floor_p, floor_a);
        fflush(stdout);
    }
    if (realign)
        printf("# realigned (relative online) error: adaptive %.5g, pca (same simulator) %.5g\n",
               rk_relative_online_error(&ea), rk_relative_online_error(&ep));
    printf("# free-run relative error: adaptive %.5g, pca (same simulator) %.5g; kinetic energy the adaptive "
           "bases dropped %.4g J in all; cubature %d elements; floors (M) pca %.4g, decoder %.4g\n",
           rk_relative_error(&ea), rk_relative_error(&ep), lost, ncub, sff > 0 ? sqrt(sfp / sff) : 0, sff > 0 ? sqrt(sfa / sff) : 0);
    return 0;
fail:
    fprintf(stderr, "%s\n", err.msg);
    return 1;
}
