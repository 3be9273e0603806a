/* One time step: backward Euler or BDF2 on q, projected Newton with Armijo backtracking, the
 * iteration of the precompute's solver (precompute/solver) on the reduced model (precompute/rom)
 * in r x r, C99 and fixed buffers; its constants are the solver's (physics/physics.h). */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

#define ARMIJO_C RT_K(RK_ARMIJO_C)
#define MAX_HALVINGS RK_MAX_HALVINGS
/* In float, small-strain stresses lose digits (P ~ mu (F - F^-T) cancels), so Newton steps
 * bottom out at a noise level well above the asset's tolerance. A step below 1e-6 of the
 * state's RMS displacement counts as converged, and so does one below 1e-4 of it that shrank
 * by less than half since the last, or one whose decrease the line search could not tell from
 * round-off (stagnation: iterating on would only stir noise). 1e-4, not 1e-3: projected Newton
 * converges linearly where barrier Hessians are projected (a cloud landing on a slab: steps
 * shrinking by 0.66-0.75 an iteration), and at 1e-3 the float solve stopped in that tail, the
 * splat capture of test_runtime_cloud_mesh 1.03e-3 from the reduced simulator, 2.5e-5 at 1e-4
 * (docs/cloud_march.md); the float pour's Newton count is the same at both. In double
 * the asset's tolerance binds, and the runtime takes the precompute's iterates exactly. */
#ifdef ROMRT_DOUBLE
#define TOL_FLOOR 0.0
#define STAGNATION 0.0
#else
#define TOL_FLOOR 1e-6f
#define STAGNATION 1e-4f
#endif

static int all_finite(const romrt_real *a, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

/* sqrt(x^T M x / mass) over q's part: an RMS displacement (m). */
static romrt_real rms(romrt_model *m, const romrt_real *x)
{
    romrt_real Mx[ROMRT_MAX_R], s;
    rt_symv(m->r, m->M, x, Mx);
    s = rt_dot(m->r, x, Mx) / m->mass;
    return s > 0 ? RT_SQRT(s) : 0;
}

/* The unknowns: q, the moved colliders' progress, the moving obstacles' (contact_progress.c). */
static int unknowns(const romrt_model *m)
{
    return m->r + m->nmoving + m->obs_joint;
}

/* The step's size: the body's RMS step, or a moved collider's or obstacle's along its path,
 * whichever is larger. */
static romrt_real step_size(romrt_model *m, const romrt_real *d)
{
    romrt_real size = rms(m, d);
    int k, p = m->r + m->nmoving;
    for (k = 0; k < m->nmoving; k++)
        if (RT_FABS(d[m->r + k]) * m->move_L[k] > size) size = RT_FABS(d[m->r + k]) * m->move_L[k];
    for (k = 0; k < m->obs_joint; k++)
        if (RT_FABS(d[p + k]) * m->obs_L[k] > size) size = RT_FABS(d[p + k]) * m->obs_L[k];
    return size;
}

/* The potential over y = (q, the moved colliders' progress s_k): the colliders placed at s_k,
 * plus w_k/2 (1 - s_k)^2 and the terms' derivatives in s_k (precompute/rom/collider_solve.c);
 * likewise the moving obstacles' progress s in a joint solve (precompute/rom/obstacle_solve.c),
 * whose derivatives the contact terms add as they go (contact_progress.c). */
static romrt_real potential(romrt_model *m, const rt_terms *T, const romrt_real *y, romrt_real *g, romrt_real *H,
                            romrt_real *magnitude)
{
    int r = m->r, n = unknowns(m), p = r + m->nmoving, k, i;
    romrt_real E;
    if (m->nmoving) rt_colliders_place(m, y);
    if (m->obs_joint) {
        rt_obstacles_place(m, y + p, 0);
        for (k = 0; k < m->obs_joint; k++) {
            if (g) g[p + k] = 0;
            for (i = 0; H && i <= p + k; i++) H[i + (size_t)n * (p + k)] = 0;
        }
    }
    E = rt_potential(m, T, y, g, H, n, magnitude);
    if (!isfinite(E)) return E;
    for (k = 0; k < m->obs_joint; k++) { /* w_k/2 (1 - s_k)^2 - lambda_k (1 - s_k), lambda_k the multiplier's (obstacles_solve) */
        romrt_real c = 1 - y[p + k], e = RT_K(0.5) * m->obs_w[k] * c * c - m->obs_lambda[k] * c;
        E += e;
        if (magnitude) *magnitude += RT_FABS(e);
        if (g) g[p + k] += m->obs_lambda[k] - m->obs_w[k] * c;
        if (H) H[p + k + (size_t)n * (p + k)] += m->obs_w[k];
    }
    for (k = 0; k < m->nmoving; k++) {
        romrt_real sk = y[r + k], gs = 0, hss = 0, pull = m->move_w[k] * (1 - sk), *hqs = H ? H + (size_t)n * (r + k) : 0;
        if (hqs)
            for (i = 0; i < n; i++) hqs[i] = 0;
        if (g || H) rt_colliders_path_terms(m, y, k, sk, &gs, H ? &hss : 0, hqs);
        E += RT_K(0.5) * pull * (1 - sk);
        if (magnitude) *magnitude += RT_K(0.5) * pull * (1 - sk);
        if (g) g[r + k] = gs - pull;
        if (H) hqs[r + k] = hss + m->move_w[k];
    }
    return E;
}

/* Whether a step along a direction must be filtered: planes, colliders or other objects to keep. */
static int filtered(const romrt_model *m)
{
    return m->ncontacts || m->ncolliders || rt_surface_on(m);
}

static romrt_real max_step(romrt_model *m, const romrt_real *y, const romrt_real *d)
{
    romrt_real alpha = m->ncontacts ? rt_contact_max_step(m, y, d) : 1, c;
    int p = m->r + m->nmoving, k;
    for (k = p; k < p + m->obs_joint; k++) { /* each s_k stays in [0, 1] */
        if (d[k] > 0 && (1 - y[k]) / d[k] < alpha) alpha = (1 - y[k]) / d[k];
        if (d[k] < 0 && y[k] / -d[k] < alpha) alpha = y[k] / -d[k];
    }
    if (m->ncolliders && alpha > 0 && (c = rt_colliders_max_step(m, y, d)) < alpha) alpha = c;
    if (rt_surface_on(m) && alpha > 0 && (c = rt_obstacles_max_step(m, y, d)) < alpha) alpha = c;
    return alpha;
}

/* The projected Newton matrix is a sum of PSD blocks, but in float the rounding of a stiff
 * barrier's blocks (kappa b'' ~ 1e8 against inertia ~ 1e4) can leave it a hair indefinite: it is
 * assembled again with a diagonal shift, 1e-6 of its largest diagonal entry, then 100 and 10^4
 * times that, until it factors (0), or not (-1). A shift only shortens the step along the stiff
 * directions; the line search and the step filter still judge it. In double it never serves. */
static int shifted_factor(romrt_model *m, const rt_terms *T, const romrt_real *y, int n)
{
#ifdef ROMRT_DOUBLE
    (void)m, (void)T, (void)y, (void)n;
    return -1;
#else
    romrt_real big = 0, shift;
    int tries, i;
    for (tries = 0; tries < 3; tries++) {
        if (!isfinite(potential(m, T, y, 0, m->H, 0))) return -1;
        for (i = 0; i < n && tries == 0; i++)
            if (RT_FABS(m->H[i + (size_t)n * i]) > big) big = RT_FABS(m->H[i + (size_t)n * i]);
        shift = big * RT_K(1e-6) * (tries == 0 ? 1 : tries == 1 ? 100 : 10000);
        for (i = 0; i < n; i++) m->H[i + (size_t)n * i] += shift;
        if (rt_cholesky(n, m->H) == 0) return 0;
    }
    return -1;
#endif
}

/* The default (romrt.h, romrt_set_hessian_reuse; bench/results/newton_modes.csv): in the converged
 * mode a matrix kept for up to DEFAULT_REUSE steps, since there a kept matrix that stops paying is
 * replaced (newton) and the answer meets the same tolerance at a fraction of the cost. On an asset
 * with a collision surface (obstacles other than planes, several objects, self-contact) only a
 * matrix built while no surface term acts (no barrier pair within dhat, no lagged friction pair)
 * is kept, and only while none acts (contact_terms): the barrier's terms change the matrix from
 * one iteration to the next, and a matrix kept with them took 40-46% more iterations and 7-9%
 * more time (a slab on spikes); its elastic part kept alone took 2.5 times the iterations of the
 * fresh matrix on a splat capture landing on a mesh (docs/runtime.md). Objects falling apart, the
 * frames before a landing, take a lone object's kept matrix. Fresh in the fixed-cost mode, whose
 * steps nothing checks, so a kept matrix would only move its answer. */
#define DEFAULT_REUSE 10

/* Whether the model's basis comes from a CROM decoder: a basis with no K-space to carry a Newton
 * matrix from one step's basis into the next (alrom_keep.c), so its matrix is never kept. */
static int crom_basis(const romrt_model *m) { return m->alrom && m->al.decoder; }

/* How many steps a Newton matrix may be kept: the app's romrt_set_hessian_reuse, else the default. */
int rt_reuse_steps(const romrt_model *m)
{
    if (m->kind != ROMRT_KIND_REDUCED || crom_basis(m)) return 0;
    if (m->hessian_reuse_set) return m->hessian_reuse;
    return m->fixed_iterations ? 0 : DEFAULT_REUSE;
}

/* Whether contact terms bar keeping the matrix of the last potential: on an asset with a collision
 * surface, any barrier or friction term (its planes' too: an octopus resting on a plane under a
 * splat capture took 20 Newton iterations a step on a kept matrix, 2.3 on fresh ones); the
 * default's rule above. A planes-only asset keeps its matrix through its contacts as before (a
 * slab resting on a plane: 2.8 iterations and 0.28 factorizations a step, 0.82 times the time of
 * this rule's 2.5 and 2.3); an app's romrt_set_hessian_reuse keeps whatever it asked for. */
static int contact_terms(const romrt_model *m)
{
    return !m->hessian_reuse_set && rt_surface_on(m) && m->contact_terms > 0;
}

/* Whether the Newton matrix factored in m->H may serve this iteration (romrt_set_hessian_reuse):
 * built for the body alone (a solve that moves colliders builds its own, of another size), for
 * this step's inertia weight (BDF2's first step changes it), fewer than reuse_steps steps ago. */
static int kept_matrix(const romrt_model *m, const rt_terms *T)
{
    int reuse = rt_reuse_steps(m);
    return reuse > 1 && m->nmoving == 0 && !m->obs_joint && m->hessian_age >= 0 && m->hessian_age < reuse && m->hessian_w == T->w_inertia;
}

/* The potential at y, its gradient in m->g, and the Newton matrix factored in m->H: the exact
 * Hessian first (the elements' dP/dF unprojected, as Vega's tangent stiffness), which the inertia
 * M_r / h^2 almost always keeps positive definite over the elements' small negative twist
 * eigenvalues, at no SVD per element; where its Cholesky factorization fails, the projected
 * Hessian at the same y. The reduced simulator does the same (precompute/rom/newton.c); a solve
 * that moves colliders always projects, as its model there does. With fresh == 0 and a kept
 * matrix (kept_matrix), only the potential and gradient are evaluated: the factor stays, and the
 * direction it gives is a modified Newton step, still a descent direction (the matrix is SPD). */
static romrt_status newton_system(romrt_model *m, const rt_terms *T, const romrt_real *y, romrt_real *E,
                                  romrt_real *magnitude, int it, int fresh, int *kept, romrt_error *err)
{
    int n = unknowns(m), indefinite = 0;
    *kept = !fresh && kept_matrix(m, T);
    if (*kept) {
        *E = potential(m, T, y, m->g, 0, magnitude);
        *kept = !contact_terms(m); /* a contact term acts at y: the matrix it lacks, fresh */
    }
    if (!*kept) {
        m->exact_hessian = m->nmoving == 0 && !m->obs_joint;
        *E = potential(m, T, y, m->g, m->H, magnitude);
        indefinite = isfinite(*E) && (!m->exact_hessian || rt_cholesky(n, m->H));
        if (indefinite && m->exact_hessian) {
            m->exact_hessian = 0;
            *E = potential(m, T, y, m->g, m->H, magnitude);
        }
        m->exact_hessian = 0;
        m->hessian_age = -1; /* H is being rewritten */
        m->last.factorizations++;
        if (indefinite) m->last.projected_hessians++;
    }
    if (!isfinite(*E) || !all_finite(m->g, n))
        return rt_fail_n(err, ROMRT_E_DIVERGED, 0, "the incremental potential is not finite at Newton iteration ",
                         (uint64_t)it, "");
    if (*kept) return ROMRT_OK;
    if (indefinite && rt_cholesky(n, m->H) && shifted_factor(m, T, y, n))
        return rt_fail_n(err, ROMRT_E_DIVERGED, 0, "the Newton matrix is not positive definite at iteration ",
                         (uint64_t)it, "");
    if (m->nmoving == 0 && !m->obs_joint && !crom_basis(m) && !contact_terms(m)) {
        m->hessian_age = 0;
        m->hessian_w = T->w_inertia;
    }
    return ROMRT_OK;
}

/* d = -H^-1 g from the factor in m->H. */
static romrt_status direction(romrt_model *m, int n, int it, romrt_error *err)
{
    int i;
    for (i = 0; i < n; i++) m->d[i] = -m->g[i];
    rt_cholesky_solve(n, m->H, m->d);
    m->last.newton_iterations++;
    if (!all_finite(m->d, n))
        return rt_fail_n(err, ROMRT_E_DIVERGED, 0, "the Newton direction is not finite at iteration ", (uint64_t)it, "");
    return ROMRT_OK;
}

/* The fixed-cost mode (romrt_set_newton_iterations): exactly m->fixed_iterations full Newton
 * steps, no line search and no convergence test (as Vega's reduced StVK runs by default), each
 * shortened only as far as the contacts' step filter demands. The cost of a step is then known in
 * advance; its distance from the converged answer is what the bench reports. */
static romrt_status newton_fixed(romrt_model *m, const rt_terms *T, romrt_error *err)
{
    int n = unknowns(m), it, i, kept;
    romrt_real *y = m->y, *d = m->d, *trial = m->trial, alpha, E, magnitude;
    romrt_status st;
    for (it = 0; it < m->fixed_iterations; it++) {
        if ((st = newton_system(m, T, y, &E, &magnitude, it, 0, &kept, err))) return st;
        if ((st = direction(m, n, it, err))) return st;
        alpha = filtered(m) ? max_step(m, y, d) : 1;
        if (kept) {
            /* A kept matrix's modified step is the one step here that can run away: a matrix from
             * up to hessian_reuse steps back, too soft for a stiffer state (the projected volume's
             * C^T C at nu = 0.45), overshoots, and with nothing checking, the next step starts from
             * an inverted point. Where it does not lower the potential, a fresh matrix at y gives the
             * step (unchecked, as every fixed-mode step is): one energy per iteration more. */
            romrt_real Et;
            for (i = 0; i < n; i++) trial[i] = y[i] + alpha * d[i];
            Et = potential(m, T, trial, 0, 0, 0);
            if (!(Et <= E)) {
                if ((st = newton_system(m, T, y, &E, &magnitude, it, 1, &kept, err)) || (st = direction(m, n, it, err)))
                    return st;
                alpha = filtered(m) ? max_step(m, y, d) : 1;
            }
        }
        for (i = 0; i < n; i++) y[i] += alpha * d[i];
    }
    m->last.converged = 0; /* not tested */
    return ROMRT_OK;
}

/* The step size that ends the solve: the asset's tolerance; in float also its floor, 1e-6 of the
 * state's RMS, and a step below STAGNATION of it that did not halve (see TOL_FLOOR). */
/* The asset's tolerance, in float no finer than TOL_FLOOR of the state's RMS (*size; 0 in double). */
static romrt_real floor_tol(romrt_model *m, const romrt_real *y, romrt_real *size)
{
    *size = TOL_FLOOR > 0 ? rms(m, y) : 0;
    return TOL_FLOOR * *size > m->tol ? TOL_FLOOR * *size : m->tol;
}

static romrt_real stop_tol(romrt_model *m, const romrt_real *y, romrt_real step, romrt_real last)
{
    romrt_real size, tol = floor_tol(m, y, &size);
    if (TOL_FLOOR > 0 && step < STAGNATION * size && step > RT_K(0.5) * last) tol = step;
    return tol;
}

/* The solve's last step y + alpha d into y (m->y, direction m->d) where the potential there is
 * finite (no inverted point), and 1; else 0, y kept, m->trial = y + back d and the colliders or
 * moving obstacles placed there. */
static int whole_step(romrt_model *m, const rt_terms *T, romrt_real alpha, romrt_real back)
{
    int n = unknowns(m), i;
    for (i = 0; i < n; i++) m->trial[i] = m->y[i] + alpha * m->d[i];
    if (isfinite(potential(m, T, m->trial, 0, 0, 0))) {
        memcpy(m->y, m->trial, sizeof(romrt_real) * (size_t)n);
        return 1;
    }
    for (i = 0; i < n; i++) m->trial[i] = m->y[i] + back * m->d[i];
    if (m->nmoving) rt_colliders_place(m, m->trial);
    else if (m->obs_joint) rt_obstacles_place(m, m->trial + m->r, 0);
    return 0;
}

/* Projected Newton on y = (q, moved colliders' progress) from m->y, the precompute solver's loop. */
static romrt_status newton(romrt_model *m, const rt_terms *T, romrt_error *err)
{
    int n = unknowns(m), it, k, i, fresh = 0;
    romrt_real *y = m->y, *g = m->g, *d = m->d, *trial = m->trial, last = (romrt_real)INFINITY;
    if (m->fixed_iterations) return newton_fixed(m, T, err);
    for (it = 0; it < m->max_iter; it++) {
        romrt_real magnitude, E, gd, alpha, tol, step, full;
        int accepted = 0, armijo = 0, kept;
        romrt_status st = newton_system(m, T, y, &E, &magnitude, it, fresh, &kept, err);
        if (st || (st = direction(m, n, it, err))) return st;
        step = step_size(m, d);
        /* A kept matrix converges linearly; once its step is not half the last, a fresh one at y. */
        if (kept && step > RT_K(0.5) * last) {
            if ((st = newton_system(m, T, y, &E, &magnitude, it, 1, &kept, err)) || (st = direction(m, n, it, err)))
                return st;
            step = step_size(m, d);
        }
        tol = stop_tol(m, y, step, last);
        /* Float's floor, not the asset's tolerance, is about to end the solve, with this step taken
         * as the last correction: on a kept matrix that is a modified Newton step, which left an
         * ill-conditioned RKPM beam 7x further from the reduced simulator than the fresh mode's
         * full one (test_runtime_parity). A fresh matrix at y gives the full step. */
        if (kept && step <= tol && step > m->tol) {
            if ((st = newton_system(m, T, y, &E, &magnitude, it, 1, &kept, err)) || (st = direction(m, n, it, err)))
                return st;
            step = step_size(m, d);
            tol = stop_tol(m, y, step, last);
        }
        if (step <= tol) {
            /* Float's floor or stagnation ends the solve above the asset's tolerance: the line
             * search can no longer tell progress from round-off, but this last Newton step is still
             * the best correction there is, and dropping it every time step let the demo's RKPM beam
             * drift a fifth from the double runtime over 100 steps (steps of 0.1-0.5 mm left out) */
            if (step > m->tol) whole_step(m, T, filtered(m) ? max_step(m, y, d) : 1, 0);
            m->last.converged = 1;
            return ROMRT_OK;
        }
        last = step;
        gd = rt_dot(n, g, d);
        alpha = filtered(m) ? max_step(m, y, d) : 1;
        full = alpha;
        for (k = 0; k <= MAX_HALVINGS && !accepted; k++) {
            romrt_real Et;
            if (k > 0) {
                alpha *= RT_K(0.5);
                m->last.line_search_halvings++;
            }
            for (i = 0; i < n; i++) trial[i] = y[i] + alpha * d[i];
            Et = potential(m, T, trial, 0, 0, 0);
            /* (in float, E + c alpha g.d rounds to E for small alpha: demand a real decrease) */
            armijo = Et <= E + ARMIJO_C * alpha * gd && (STAGNATION == 0 || Et < E);
            accepted = armijo || (isfinite(Et) && Et - E <= RT_ENERGY_NOISE * magnitude);
        }
        if (!accepted && kept) { /* the kept matrix's direction failed here: a fresh one */
            fresh = 1;
            continue;
        }
        if (!accepted) return ROMRT_OK; /* no decrease left to find: keep y */
        fresh = kept && k > 1; /* a kept matrix whose step had to be shortened is replaced */
        /* Round-off ends the solve here (below), on a step the line search shortened because it
         * could not tell the whole step's change from noise: the whole step is taken, as at the
         * floor above (the float stiff cantilever of test_runtime_parity came 6.8e-5 from the
         * reduced simulator so, 1.3e-4 on the shortened step). Not where friction acts and the
         * step is longer than its smoothing eps_v h: there the energy is far from quadratic
         * along the step (the stick edge, docs/runtime.md) and the shortened step is the better. */
        if (STAGNATION > 0 && !armijo && !kept && alpha < full && alpha * step <= STAGNATION * rms(m, trial) &&
            (!T->friction || full * step <= m->eps_v * m->h) && whole_step(m, T, full, alpha)) {
            m->last.converged = 1;
            return ROMRT_OK;
        }
        memcpy(y, trial, sizeof(romrt_real) * (size_t)n);
        /* The energy change was round-off. That ends the solve only when the step was small too:
         * a large model's energy (gravity's work on a sagging beam) can hide in its float rounding
         * the decrease of a Newton step that still moves it, and Newton then goes on. */
        if (STAGNATION > 0 && !armijo && alpha * step <= STAGNATION * rms(m, y)) {
            if (kept) { /* a kept matrix's step: a fresh one decides (as above) */
                fresh = 1;
                continue;
            }
            m->last.converged = 1;
            return ROMRT_OK;
        }

    }
    return ROMRT_OK;
}

static romrt_status solve(romrt_model *m, const rt_terms *T, int move_colliders, romrt_error *err);

/* Newton from m->q (with the moved colliders, when there are, from where they are), into m->q. */
static romrt_status solve(romrt_model *m, const rt_terms *T, int move_colliders, romrt_error *err)
{
    romrt_status st;
    int k;
    if (move_colliders) rt_colliders_begin_move(m, m->q);
    memcpy(m->y, m->q, sizeof(romrt_real) * (size_t)m->r);
    for (k = 0; k < m->nmoving; k++) m->y[m->r + k] = 0;
    for (k = 0; k < m->obs_joint; k++) m->y[m->r + m->nmoving + k] = m->obs_s[k];
    st = newton(m, T, err);
    if (m->nmoving) {
        if (st) m->nmoving = 0; /* the caller puts the colliders back */
        else rt_colliders_end_move(m, m->y);
    }
    if (!st) memcpy(m->q, m->y, sizeof(romrt_real) * (size_t)m->r);
    return st;
}

/* How near the end of their way the obstacles count as arrived: the solve's own tolerance (in
 * float its floor, as stop_tol's: s rounds to 6e-8 of the way, and the multiplier's rounds stirred
 * noise below that) */
static romrt_real arrival_tol(romrt_model *m)
{
    romrt_real size;
    return floor_tol(m, m->q, &size);
}

/* The scene's moving obstacles to where they are at the step's end and the app's moved meshes to
 * their poses, solved for with the body (contact_progress.c); where the body cannot give way they
 * stop short (colliders_behind) and go on at the next step. */
static romrt_status obstacles_solve(romrt_model *m, const rt_terms *T, romrt_error *err)
{
    double t = rt_clock(m, 1);
    romrt_status st = ROMRT_OK;
    int round, k, again;
    if (!rt_obstacles_begin_joint(m, t)) {
        m->obs_behind = 0;
        return solve(m, T, 0, err);
    }
    if (rt_obstacles_fraction(m, m->q, 0) >= 1) { /* the whole way is clear of the body as it is: */
        m->obs_joint = 0, m->obs_behind = 0;           /* there at once, the body solved after them */
        rt_obstacles_arrive(m, t);
        return solve(m, T, 0, err);
    }
    for (round = 0; round < RK_OBSTACLE_ROUNDS && !st; round++) {
        st = solve(m, T, 0, err);
        /* each arrived; or pinned: a round that did not halve its shortfall (the body cannot give
         * way); another round while one's multiplier rises */
        for (k = 0, again = 0; k < m->obs_joint && !st; k++) {
            romrt_real short_by = 1 - (m->obs_s[k] = m->y[m->r + k]);
            if (short_by * m->obs_L[k] <= arrival_tol(m) || short_by > RT_K(0.5) * m->obs_short[k]) continue;
            m->obs_short[k] = short_by;
            m->obs_lambda[k] -= m->obs_w[k] * short_by; /* the method of multipliers */
            again = 1;
        }
        if (!again) break;
    }
    if (st) {
        m->obs_joint = 0;
        return st;
    }
    m->obs_behind = rt_obstacles_end_joint(m, m->obs_s, t, arrival_tol(m));
    return ROMRT_OK;
}

romrt_status romrt_set_newton_iterations(romrt_model *m, size_t iterations, romrt_error *err)
{
    if (!m) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_newton_iterations: no model (NULL)");
    if (m->kind != ROMRT_KIND_REDUCED)
        return rt_fail(err, ROMRT_E_UNSUPPORTED, 0, "romrt_set_newton_iterations: a Koopman model has no Newton solve");
    if (iterations > ROMRT_MAX_NEWTON)
        return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_newton_iterations: iterations must be 0 (converged) to 1000");
    m->fixed_iterations = (int)iterations;
    return ROMRT_OK;
}

romrt_status romrt_set_hessian_reuse(romrt_model *m, size_t steps, romrt_error *err)
{
    if (!m) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_hessian_reuse: no model (NULL)");
    if (m->kind != ROMRT_KIND_REDUCED)
        return rt_fail(err, ROMRT_E_UNSUPPORTED, 0, "romrt_set_hessian_reuse: a Koopman model has no Newton solve");
    if (crom_basis(m))
        return rt_fail(err, ROMRT_E_UNSUPPORTED, 0,
                       "romrt_set_hessian_reuse: a CROM decoder's basis has no K-space to carry a Newton matrix in");
    if (steps > ROMRT_MAX_NEWTON)
        return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_hessian_reuse: steps must be 0 to 1000");
    m->hessian_reuse = (int)steps;
    m->hessian_reuse_set = 1;
    m->hessian_age = -1;
    return ROMRT_OK;
}

romrt_status romrt_step(romrt_model *m, romrt_error *err)
{
    int r, i, bdf2, behind = 0;
    romrt_real h, vnew[ROMRT_MAX_R];
    rt_terms T;
    romrt_status st;
    if (!m) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_step: no model (NULL)");
    if (m->kind == ROMRT_KIND_KOOPMAN) return rt_koopman_step(m, err);
    r = m->r;
    h = m->h;
    bdf2 = m->integrator == 1 && m->have_prev;
    memset(&m->last, 0, sizeof m->last);
    if (m->alrom) { /* this step's basis, and the prediction in it (alrom.c) */
        RT_PROF_BEGIN(RT_PROF_ALROM_TERMS);
        st = rt_alrom_begin(m, &T.w_inertia, err);
        RT_PROF_END(RT_PROF_ALROM_TERMS);
        if (st) {
            rt_alrom_abort(m);
            return st;
        }
    } else if (bdf2) {
        for (i = 0; i < r; i++)
            m->qtilde[i] = (4 * m->q[i] - m->q_prev[i]) / 3 + 2 * h / 9 * (4 * m->v[i] - m->v_prev[i]);
        T.w_inertia = RT_K(9.0) / (RT_K(4.0) * h * h);
    } else {
        for (i = 0; i < r; i++) m->qtilde[i] = m->q[i] + h * m->v[i];
        T.w_inertia = 1 / (h * h);
    }
    T.w_damping = 1 / h;
    T.friction = m->mu > 0 && (m->ncontacts || m->ncolliders || rt_surface_on(m));
    memcpy(m->qt, m->q, sizeof(romrt_real) * (size_t)r);
    if (rt_surface_on(m)) { /* the obstacles where the clock puts them (a reset may have moved it), unless
                       * the last step left them behind; kept to go back to if this one fails */
        m->obs_overflow = 0;
        behind = m->obs_behind;
        if (m->obs_moving && !behind && m->obs_time != rt_clock(m, 0)) rt_obstacles_at(m, rt_clock(m, 0));
        if (m->obs_moving) memcpy(m->ox_from, m->ox, sizeof(romrt_real) * 3 * (size_t)m->onv);
        if (m->nmeshes) rt_meshes_begin(m);
    }
    /* friction lagged at q_t for the first solve; the colliders' poses now, to go back to on failure */
    rt_colliders_lag(m, m->qt, 1);
    if (rt_surface_on(m) && T.friction) rt_obstacles_lag(m, m->qt, 1);
    rt_pin_target(m, rt_clock(m, 1));
    /* Start from the inertial prediction when no contact is crossed on the way there. */
    for (i = 0; i < r; i++) m->d[i] = m->qtilde[i] - m->qt[i];
    m->nmoving = 0;
    if (!filtered(m) || max_step(m, m->qt, m->d) >= 1)
        memcpy(m->q, m->qtilde, sizeof(romrt_real) * (size_t)r);
    rt_lift(m, rt_clock(m, 1), m->q); /* the lifted group where it is due, before Newton moves the rest */
    /* the colliders the app moved, with the body in one solve; then the step's solve; then
     * friction lagged again at the solution until a solve has nothing left to do */
    st = rt_colliders_pending(m) ? solve(m, &T, 1, err) : ROMRT_OK;
    if (!st) st = m->obs_moving || (m->nmeshes && rt_meshes_pending(m)) ? obstacles_solve(m, &T, err) : solve(m, &T, 0, err);
    for (i = 1; !st && T.friction && !m->fixed_iterations && i < m->friction_iterations; i++) {
        size_t before = m->last.newton_iterations;
        rt_colliders_lag(m, m->q, 0);
        if (rt_surface_on(m)) rt_obstacles_lag(m, m->q, 0);
        st = solve(m, &T, 0, err);
        if (m->last.newton_iterations - before <= 1) break;
    }
    m->last.colliders_behind = rt_colliders_pending(m) || (m->nmeshes && rt_meshes_pending(m)) || m->obs_behind;
    m->last.contact_pairs = rt_surface_on(m) ? (size_t)m->ncand : 0;
    m->last.friction_pairs = rt_surface_on(m) ? (size_t)m->nfric : 0;
    for (i = 0; i < r && !st; i++) {
        vnew[i] = bdf2 ? (3 * m->q[i] - 4 * m->qt[i] + m->q_prev[i]) / (2 * h) : (m->q[i] - m->qt[i]) / h;
        if (!isfinite(m->q[i]) || !isfinite(vnew[i]))
            st = rt_fail_n(err, ROMRT_E_DIVERGED, 0, "reduced coordinate ", (uint64_t)i, " is not finite after the step");
    }
    if (!st && !rt_showable(m, m->q))
        st = rt_fail(err, ROMRT_E_DIVERGED, 0, "the state grew past what the shown positions can hold");
    /* an adaptive model's stored vertices move on; its q is back at 0 in the next step's basis */
    if (!st && m->alrom) {
        RT_PROF_BEGIN(RT_PROF_ALROM_TERMS);
        st = rt_alrom_commit(m, err);
        RT_PROF_END(RT_PROF_ALROM_TERMS);
    }
    if (st && rt_surface_on(m) && m->obs_overflow) /* the cause, rather than the non-finite potential it left */
        st = rt_fail_n(err, ROMRT_E_LIMIT, ROMBIN_OBHD, "more contact pairs than the asset's capacity of ",
                       (uint64_t)m->pair_cap, " (bake with a larger rom.asset.contact_pairs)");
    if (st) { /* leave the state as it was, the colliders too */
        int k;
        memcpy(m->q, m->qt, sizeof(romrt_real) * (size_t)r);
        for (k = 0; k < ROMRT_MAX_COLLIDERS; k++) memcpy(m->colliders[k].now, m->colliders[k].start, sizeof m->colliders[k].now);
        if (m->nmeshes) rt_meshes_abort(m);
        if (m->obs_moving) { /* the obstacles back where the step began */
            memcpy(m->ox, m->ox_from, sizeof(romrt_real) * 3 * (size_t)m->onv);
            rt_obstacles_refit(m, 0);
            m->obs_behind = behind;
            m->obs_time = behind ? (double)NAN : rt_clock(m, 0);
        }
        if (m->alrom) rt_alrom_abort(m);
        return st;
    }
    for (i = 0; i < r && !m->alrom; i++) {
        m->q_prev[i] = m->qt[i];
        m->v_prev[i] = m->v[i];
        m->v[i] = vnew[i];
    }
    m->have_prev = 1;
    if (m->hessian_age >= 0) m->hessian_age++;
    rt_clock_advance(m, 1);
    return ROMRT_OK;
}
