/* The runtime's object-against-object pair term (runtime/objects.c), compiled here in double with
 * the row access (rows.c), dense kernels and physics it uses, on a small model made by hand:
 * - its gradient in q against central differences of its energy, and its Hessian against central
 *   differences of the gradient less the one term it leaves out on purpose (d's own curvature,
 *   kappa b'(d) J^T (I - n n^T) J / |D|, negative semidefinite: the Gauss-Newton Hessian);
 * - the hashed grid's broad phase against brute force over every pair: the same energy, the same
 *   smallest distance, the same step filter, on clouds of collision vertices in several objects;
 * - the step filter: along every returned step each pair keeps 10% of its distance, and the step
 *   is the largest that does (some pair is at exactly 10% at its end unless it is 1). */
#define ROMRT_DOUBLE 1
#include "runtime/dense.c"
#include "runtime/rows.c"
#include "runtime/physics.c"
#include "runtime/objects.c"

#include "testlib.h"

#define R 6
#define MAXV 400

typedef struct {
    romrt_model m;
    double X[3 * MAXV], rows[3 * MAXV * R], rho[4], x[3 * MAXV], dx[3 * MAXV], a[R];
    uint32_t cv[MAXV], obj[MAXV], cell[3 * MAXV], head[1024], next[MAXV];
} hand_model;

static double uniform(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return (double)((*s >> 8) & 0xFFFFFF) / 16777216.0;
}

/* n collision vertices in k objects on a lattice of spacing `side`, each moved by up to 5% of it,
 * neighbours mostly of different objects; random rows of size `scale`. */
static void make_model(hand_model *h, int n, int k, double side, double scale, unsigned seed)
{
    int nx = 1;
    while (nx * nx * nx < n) nx++;
    romrt_model *m = &h->m;
    memset(h, 0, sizeof *h);
    m->r = R, m->nv = n, m->ncv = n, m->nobjects = k;
    m->X = h->X, m->rows = h->rows, m->cv = h->cv, m->cv_obj = h->obj, m->obj_rho = h->rho;
    m->dhat = 0.02, m->kappa = 10;
    for (int j = 0; j < k; j++) {
        h->rho[j] = 0.01 + 0.005 * j;
        if (h->rho[j] > m->rho_max) m->rho_max = h->rho[j];
    }
    for (int i = 0; i < n; i++) {
        int at[3] = {i % nx, i / nx % nx, i / (nx * nx)};
        h->cv[i] = (uint32_t)i, h->obj[i] = (uint32_t)((at[0] + at[1] + at[2] + (int)(3 * uniform(&seed))) % k);
        for (int a = 0; a < 3; a++) h->X[3 * i + a] = side * (at[a] + 0.1 * (uniform(&seed) - 0.5));
        for (int j = 0; j < 3 * R; j++) h->rows[3 * i * R + j] = scale * (2 * uniform(&seed) - 1);
    }
    m->cv_x = h->x, m->cv_dx = h->dx, m->pair_a = h->a;
    m->grid_cell = (int32_t *)(void *)h->cell, m->grid_head = h->head, m->grid_next = h->next;
    m->grid_size = 1;
    while (m->grid_size < 2 * (uint32_t)n) m->grid_size *= 2;
}

/* Brute force: every pair's d at q (and its gradient's pieces), the energy, the curvature term. */
static double brute_energy(hand_model *h, const double *q, double *least, double *curv /* R x R or NULL */)
{
    romrt_model *m = &h->m;
    double E = 0, xi[3], xj[3];
    *least = INFINITY;
    if (curv) memset(curv, 0, sizeof(double) * R * R);
    for (int i = 0; i < m->ncv; i++)
        for (int j = i + 1; j < m->ncv; j++) {
            if (h->obj[i] == h->obj[j]) continue;
            rt_vertex_position(m, (uint32_t)i, q, xi);
            rt_vertex_position(m, (uint32_t)j, q, xj);
            double D[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]}, len = sqrt(D[0] * D[0] + D[1] * D[1] + D[2] * D[2]);
            double d = len - h->rho[h->obj[i]] - h->rho[h->obj[j]], f1, f2;
            *least = fmin(*least, d);
            if (d <= 0) return INFINITY;
            if (d >= m->dhat) continue;
            E += m->kappa * romrt_phys_barrier_distance(d, m->dhat, &f1, &f2);
            if (!curv) continue;
            /* kappa f1 J^T (I - n n^T) J / len, J = B_i - B_j (3 x R) */
            double J[3][R], n[3] = {D[0] / len, D[1] / len, D[2] / len};
            for (int a = 0; a < 3; a++)
                for (int c = 0; c < R; c++) J[a][c] = h->rows[(3 * i + a) * R + c] - h->rows[(3 * j + a) * R + c];
            for (int c1 = 0; c1 < R; c1++)
                for (int c2 = 0; c2 < R; c2++) {
                    double s = 0;
                    for (int a = 0; a < 3; a++)
                        for (int b = 0; b < 3; b++) s += J[a][c1] * ((a == b) - n[a] * n[b]) * J[b][c2];
                    curv[c1 + R * c2] += m->kappa * f1 * s / len;
                }
        }
    return E;
}

TEST(pair_gradient_and_hessian_match_finite_differences)
{
    static hand_model h;
    /* two objects, 12 vertices, rows large enough that q moves pairs through the barrier's range */
    make_model(&h, 12, 2, 0.04, 0.001, 7u);
    double q[R] = {0}, g[R], H[R * R], curv[R * R], least;
    unsigned s = 99u;
    /* a q where several pairs are inside dhat and none touch */
    int found = 0, in_range = 0;
    for (int tries = 0; tries < 20000 && !found; tries++) {
        for (int j = 0; j < R; j++) q[j] = 2 * uniform(&s) - 1;
        double E = brute_energy(&h, q, &least, NULL);
        in_range = 0;
        for (int i = 0; i < 12 && isfinite(E); i++)
            for (int j = i + 1; j < 12; j++) {
                double xi[3], xj[3];
                if (h.obj[i] == h.obj[j]) continue;
                rt_vertex_position(&h.m, (uint32_t)i, q, xi);
                rt_vertex_position(&h.m, (uint32_t)j, q, xj);
                double d = sqrt((xi[0] - xj[0]) * (xi[0] - xj[0]) + (xi[1] - xj[1]) * (xi[1] - xj[1]) +
                                (xi[2] - xj[2]) * (xi[2] - xj[2])) - h.rho[h.obj[i]] - h.rho[h.obj[j]];
                in_range += d > 1e-3 && d < h.m.dhat - 1e-3;
            }
        found = isfinite(E) && least > 1e-3 && in_range >= 2;
    }
    CHECK(found, "no q with two pairs in the barrier's range");
    memset(g, 0, sizeof g), memset(H, 0, sizeof H);
    double E = rt_objects_energy(&h.m, q, g, H, R), Eb = brute_energy(&h, q, &least, curv);
    CHECK(fabs(E - Eb) <= 1e-12 * fabs(Eb), "energy %.17g, brute force %.17g", E, Eb);
    double eps = 1e-6, gerr = 0, gscale = 0, herr = 0, hscale = 0;
    for (int k = 0; k < R; k++) {
        double qp[R], qm[R], gp[R] = {0}, gm[R] = {0};
        memcpy(qp, q, sizeof q), memcpy(qm, q, sizeof q);
        qp[k] += eps, qm[k] -= eps;
        double fd = (rt_objects_energy(&h.m, qp, gp, NULL, R) - rt_objects_energy(&h.m, qm, gm, NULL, R)) / (2 * eps);
        gerr = fmax(gerr, fabs(fd - g[k])), gscale = fmax(gscale, fabs(g[k]));
        for (int i = 0; i < R; i++) { /* column k of the full Hessian, less the left-out curvature */
            double fdh = (gp[i] - gm[i]) / (2 * eps) - curv[i + R * k];
            double hik = i <= k ? H[i + R * k] : H[k + R * i]; /* the upper triangle is written */
            herr = fmax(herr, fabs(fdh - hik)), hscale = fmax(hscale, fabs(hik));
        }
    }
    double cmax = 0;
    for (int i = 0; i < R * R; i++) cmax = fmax(cmax, fabs(curv[i]));
    printf("# %d pairs in range: gradient error %.2e of %.2e, Hessian (Gauss-Newton) error %.2e of %.2e, the curvature "
           "left out %.2e\n", in_range, gerr, gscale, herr, hscale, cmax);
    CHECK(cmax > 1e-3 * hscale, "the left-out curvature %g is too small to tell", cmax);
    CHECK(gscale > 0 && gerr <= 1e-6 * gscale, "gradient error %g of %g", gerr, gscale);
    CHECK(hscale > 0 && herr <= 1e-5 * hscale, "Hessian error %g of %g", herr, hscale);
}

TEST(the_grid_finds_what_brute_force_finds)
{
    static hand_model h;
    double worst_e = 0, worst_d = 0, worst_a = 0;
    int steps_below_one = 0, cases = 0;
    for (int trial = 0; trial < 40; trial++) {
        int n = 100 + 7 * trial, k = 2 + trial % 3;
        make_model(&h, n, k, 0.06 + 0.0005 * trial, 0.002, 1000u + (unsigned)trial);
        double q[R] = {0}, dq[R], least;
        unsigned s = 5u + (unsigned)trial;
        double E = brute_energy(&h, q, &least, NULL);
        if (!isfinite(E)) continue; /* this draw starts touching: no state to step from */
        cases++;
        double Eg = rt_objects_energy(&h.m, q, NULL, NULL, R), dg = rt_objects_min_distance(&h.m, q);
        worst_e = fmax(worst_e, fabs(Eg - E) / fmax(fabs(E), 1e-300));
        /* the grid reports the least d among pairs within its reach (2 rho_max + dhat) */
        if (least < h.m.dhat) worst_d = fmax(worst_d, fabs(dg - least));
        for (int j = 0; j < R; j++) dq[j] = (2 * uniform(&s) - 1) * (1 + trial);
        double alpha = rt_objects_max_step(&h.m, q, dq);
        /* brute force: every pair's first crossing of 10% of its distance along q + t dq */
        double best = 1;
        for (int i = 0; i < n; i++)
            for (int j = i + 1; j < n; j++) {
                if (h.obj[i] == h.obj[j]) continue;
                double xi[3], xj[3], ei[3], ej[3], D[3], e[3];
                rt_vertex_position(&h.m, (uint32_t)i, q, xi);
                rt_vertex_position(&h.m, (uint32_t)j, q, xj);
                for (int a = 0; a < 3; a++) {
                    ei[a] = rt_row_dot(&h.m, (uint32_t)i, a, dq), ej[a] = rt_row_dot(&h.m, (uint32_t)j, a, dq);
                    D[a] = xi[a] - xj[a], e[a] = ei[a] - ej[a];
                }
                double len = sqrt(D[0] * D[0] + D[1] * D[1] + D[2] * D[2]), Rr = h.rho[h.obj[i]] + h.rho[h.obj[j]];
                double target = Rr + 0.1 * (len - Rr), lo = 0, hi = 1;
                /* |D + t e| - target has one sign change on [0, t_min] at most: bisect the first */
                double a2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2], b = D[0] * e[0] + D[1] * e[1] + D[2] * e[2];
                double tmin = a2 > 0 ? fmin(fmax(-b / a2, 0), 1) : 0;
                double at_min = sqrt((D[0] + tmin * e[0]) * (D[0] + tmin * e[0]) + (D[1] + tmin * e[1]) * (D[1] + tmin * e[1]) +
                                     (D[2] + tmin * e[2]) * (D[2] + tmin * e[2]));
                if (at_min >= target) continue;
                hi = tmin;
                for (int it = 0; it < 200; it++) {
                    double mid = 0.5 * (lo + hi), p[3];
                    for (int a = 0; a < 3; a++) p[a] = D[a] + mid * e[a];
                    if (sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) >= target) lo = mid;
                    else hi = mid;
                }
                best = fmin(best, lo);
            }
        worst_a = fmax(worst_a, fabs(alpha - best));
        steps_below_one += alpha < 1;
    }
    printf("# %d clouds of 100-373 vertices in 2-4 objects: energy %.2e relative, least distance %.2e m, step %.2e from "
           "brute force (%d steps shortened)\n",
           cases, worst_e, worst_d, worst_a, steps_below_one);
    CHECK(cases >= 20, "only %d usable draws", cases);
    CHECK(worst_e <= 1e-12, "grid energy off by %g relative", worst_e);
    CHECK(worst_d <= 1e-15, "grid least distance off by %g", worst_d);
    CHECK(worst_a <= 1e-9, "step filter off by %g", worst_a);
    CHECK(steps_below_one >= 10, "only %d steps were shortened: the filter is not exercised", steps_below_one);
}

int main(void)
{
    RUN(pair_gradient_and_hessian_match_finite_differences);
    RUN(the_grid_finds_what_brute_force_finds);
    return test_finish();
}
