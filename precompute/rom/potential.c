/* The reduced incremental potential of rom.h: value, gradient and dense Hessian (both triangles). */
#include "rom/rom_impl.h"

#include <cblas.h>
#include <math.h>
#include <string.h>

/* w/2 (q - ref)^T S (q - ref) and, with g, w S (q - ref) added into g (ref NULL: 0). tmp: 2r. */
static double quadratic(const double *S, int r, double w, const double *q, const double *ref, double *g,
                        double *tmp)
{
    double *d = tmp, *Sd = tmp + r;
    for (int i = 0; i < r; i++) d[i] = q[i] - (ref ? ref[i] : 0);
    cblas_dsymv(CblasColMajor, CblasUpper, r, 1.0, S, r, d, 1, 0.0, Sd, 1);
    if (g) cblas_daxpy(r, w, Sd, 1, g, 1);
    return 0.5 * w * cblas_ddot(r, d, 1, Sd, 1);
}

/* The penalty's linear term b(t) = sum_g T_g e_g(t) (rom.h). */
void rk_rom_pin_target(const rk_rom_model *m, double t, double *b)
{
    memset(b, 0, sizeof(double) * m->r);
    for (int g = 0; g < m->npins; g++) {
        double R[9], shift[3], e[12];
        rk_prescribed_transform(&m->pins[g].motion, t, R, shift);
        for (int k = 0; k < 9; k++) e[k] = R[k] - (k % 4 == 0);
        for (int k = 0; k < 3; k++) e[9 + k] = shift[k];
        cblas_dgemv(CblasColMajor, CblasNoTrans, m->r, 12, 1.0, m->pins[g].T, m->r, e, 1, 1.0, b, 1);
    }
}

double rk_rom_potential(rk_rom *s, const rk_rom_terms *T, const double *q, double *g, double *H,
                        double *magnitude, rk_error *err)
{
    rk_rom_model *m = s->model;
    int r = m->r;
    double *tmp = s->work + RK_ROM_WORK_TMP * (size_t)r;
    if (g) memset(g, 0, sizeof(double) * r);
    if (H) memset(H, 0, sizeof(double) * r * r);
    double stored = rk_quadrature_eval(&m->quad, q, g, H, !s->exact_hessian);
    if (rk_rom_contact_on(m) && isfinite(stored)) stored += rk_rom_contact_energy(s, q, T->friction, g, H, err);
    if (s->ncolliders && isfinite(stored)) stored += rk_rom_colliders_energy(s, q, T->friction, g, H);
    if (!isfinite(stored)) return INFINITY;
    /* Loads and the penalty's linear part: -(load f + b(t)) . q. */
    double work = T->load * cblas_ddot(r, m->f, 1, q, 1) + cblas_ddot(r, T->pin_b, 1, q, 1);
    double quad = quadratic(m->A, r, 1.0, q, NULL, g, tmp);
    if (T->w_inertia > 0) quad += quadratic(m->M, r, T->w_inertia, q, T->qtilde, g, tmp);
    if (T->w_damping > 0 && m->C) quad += quadratic(m->C, r, T->w_damping, q, T->qt, g, tmp);
    if (g) {
        cblas_daxpy(r, -T->load, m->f, 1, g, 1);
        cblas_daxpy(r, -1.0, T->pin_b, 1, g, 1);
    }
    if (H) {
        for (size_t k = 0; k < (size_t)r * r; k++) {
            double a = m->A[k] + T->w_inertia * m->M[k] + T->reg * m->M[k];
            if (T->w_damping > 0 && m->C) a += T->w_damping * m->C[k];
            H[k] += a;
        }
    }
    if (m->lift_handle) /* the lifting handle's coordinates are set, not solved for: Newton leaves them */
        for (int i = 12 * (m->lift_handle - 1); i < 12 * m->lift_handle; i++) {
            if (g) g[i] = 0;
            for (int j = 0; H && j < r; j++) H[i + (size_t)r * j] = H[j + (size_t)r * i] = i == j;
        }
    double E = stored - work + quad;
    if (magnitude) *magnitude = fabs(stored) + fabs(work) + quad;
    return isfinite(E) ? E : INFINITY;
}
