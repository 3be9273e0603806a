/* A Koopman entry as a method of the comparison (method_koopman.c's compare): fitted on the scene's full-order
 * run, stepped in real eigen-coordinates y (one step y <- B (y + c), c the gravity and loads'
 * impulse of Eq. 19), errors against the reference as for the reduced models. */
#include "pipeline/method_koopman.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

typedef struct {
    int n, r;
    double *out, *in, *y, *c, *z, *x, *u_prev, *secs;
} koopman_run;

static void run_free(koopman_run *K)
{
    free(K->out), free(K->in), free(K->y), free(K->c), free(K->z), free(K->x), free(K->u_prev), free(K->secs);
}

static int run_init(const rk_koopman *k, const rk_scene_sim *sim, const rk_fom_frames *F, koopman_run *K, rk_error *err)
{
    int n = F->ndof, r = k->r;
    memset(K, 0, sizeof *K);
    K->n = n, K->r = r;
    K->out = rk_calloc((size_t)n * r, sizeof(double), err);
    K->in = rk_calloc((size_t)n * r, sizeof(double), err);
    K->y = rk_calloc((size_t)r, sizeof(double), err);
    K->c = rk_calloc((size_t)r, sizeof(double), err);
    K->z = rk_calloc((size_t)r, sizeof(double), err);
    K->x = rk_calloc((size_t)n, sizeof(double), err);
    K->u_prev = rk_calloc((size_t)n, sizeof(double), err);
    K->secs = rk_calloc((size_t)F->T + 1, sizeof(double), err);
    if (!K->out || !K->in || !K->y || !K->c || !K->z || !K->x || !K->u_prev || !K->secs) return -1;
    /* the start, X_0 = [u_0; h v_0] (u_0 = 0: the full-order run starts at rest positions) */
    rk_koopman_frame_before(sim, F->v, K->u_prev);
    if (rk_koopman_real_form(k, K->out, K->in, K->x, K->u_prev, K->y, err)) return -1;
    /* the forcing's impulse per step, in y: in (gravity + loads / mass) h^2 */
    rk_koopman_scene_accel(sim, sim->options.gravity, sim->options.force, K->x);
    cblas_dgemv(CblasColMajor, CblasNoTrans, r, n, k->h * k->h, K->in, r, K->x, 1, 0.0, K->c, 1);
    return 0;
}

static void step(const rk_koopman *k, const koopman_run *K)
{
    for (int j = 0; j < K->r; j++) K->y[j] += K->c[j];
    rk_koopman_real_step(k, K->y);
}

/* positions x = X + out y */
static void positions(const rk_scene_sim *sim, const koopman_run *K)
{
    memcpy(K->x, sim->mesh.X, sizeof(double) * K->n);
    cblas_dgemv(CblasColMajor, CblasNoTrans, K->n, K->r, 1.0, K->out, K->n, K->y, 1, 1.0, K->x, 1);
}

static int run_free_and_realigned(const rk_koopman *k, const rk_scene_sim *sim, const rk_fom_frames *F,
                                  rk_compare_method *m, rk_error *err)
{
    koopman_run K;
    int rc = -1, n = F->ndof;
    if (run_init(k, sim, F, &K, err)) goto out;
    rk_run_error e;
    rk_run_error_init(&e, sim->mesh.X, n / 3);
    for (int s = 0; s < F->T; s++) {
        double t0 = rk_now();
        step(k, &K);
        K.secs[s] = rk_now() - t0;
        positions(sim, &K);
        if (!isfinite(K.x[0]) || !isfinite(K.x[n - 1])) {
            rk_fail(err, "the Koopman state overflowed at step %d (an eigenvalue above 1: set clamp)", s);
            goto out;
        }
        rk_run_error_add(&e, K.x, F->x + (size_t)n * (s + 1));
    }
    rk_compare_record_errors(m, &e);
    m->seconds_per_step = rk_median(K.secs, F->T);
    /* realigned: each step from the full-order state before it, lifted */
    rk_run_error online;
    rk_run_error_init(&online, sim->mesh.X, n / 3);
    for (int s = 0; s < F->T; s++) {
        const double *xs = F->x + (size_t)n * s, *ref = F->x + (size_t)n * (s + 1);
        for (int i = 0; i < n; i++) {
            K.x[i] = xs[i] - sim->mesh.X[i];
            K.u_prev[i] = s ? F->x[(size_t)n * (s - 1) + i] - sim->mesh.X[i] : K.x[i] - sim->options.h * F->v[i];
        }
        rk_koopman_lift(k, K.x, K.u_prev, K.z);
        cblas_dgemv(CblasColMajor, CblasNoTrans, k->r, k->r, 1.0, k->Winv, k->r, K.z, 1, 0.0, K.y, 1);
        step(k, &K);
        positions(sim, &K);
        rk_run_error_add(&online, K.x, ref);
    }
    m->relative_online_error = rk_relative_online_error(&online);
    rc = 0;
out:
    run_free(&K);
    return rc;
}

int rk_koopman_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);

/* Fitted on the scene's own run (its trajectories; no training list) and measured against c->ref. */
int rk_koopman_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err)
{
    rk_scene_koopman K;
    const rk_scene_sim *sim = c->sim;
    const rk_fom_frames *F = c->fom, *ref = c->ref;
    if (rk_scene_koopman_build(c->scene, sim, e, c->D, F->T, &K, err)) return -1;
    const rk_koopman_scene_info *ki = &K.info;
    if (ki->projected)
        snprintf(m->basis_reason, sizeof m->basis_reason, "Koopman fitted on the %s basis's %d coordinates",
                 rk_basis_type_name(ki->basis_type), ki->basis_columns);
    else
        snprintf(m->basis_reason, sizeof m->basis_reason, "Koopman fitted on full displacements");
    m->seconds_basis = ki->seconds_basis;
    m->seconds_training_run = ki->seconds_fom;
    m->seconds_fit = ki->seconds_fit;
    /* the scene as written is one of its training runs, unless every trajectory changes something */
    snprintf(m->cubature_reason, sizeof m->cubature_reason, "none (Koopman: rank %d of %d observables, %d "
             "trajectories, %d clamped; fitted on runs that %s this one, so the error %s)", K.k.r, K.k.d,
             ki->trajectories, K.k.clamped, ki->reused ? "include" : "differ from",
             !ki->reused ? "measures prediction"
             : ref == F ? "measures reconstruction, not prediction"
                        : "against the refined reference is reconstruction plus the scene mesh's own error");
    m->r = K.k.r;
    m->size = K.k.d;
    rk_koopman_measures *km = rk_method_measures(m, &rk_method_koopman);
    km->max_abs_eigenvalue = rk_max_abs_eigenvalue(K.k.lambda_re, K.k.lambda_im, K.k.r);
    int rc = run_free_and_realigned(&K.k, sim, ref, m, err);
    rk_scene_koopman_free(&K);
    return rc;
}
