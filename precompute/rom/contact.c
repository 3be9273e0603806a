/* Contact in the subspace (rom.h): the contact stage on the boundary vertices x_v = X_v + U_v q.
 * The barrier's gradient and Hessian blocks come back per vertex and are pulled into the subspace
 * through the rows of the vertices each pair touches; a step dq moves them by U_v dq, so CCD
 * filters it exactly as at full order. */
#include "rom/rom_impl.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int rk_rom_contact_init(rk_rom_model *m, const rk_fem *fem, const rk_fom_options *opt, const double *U, rk_error *err)
{
    m->has_contact = opt->nobstacles > 0 || opt->nobjects > 1 || opt->contact.self;
    if (!m->has_contact) return 0;
    rk_contact_options co = opt->contact;
    if (co.dhat == 0) co.dhat = 1e-3 * rk_points_diagonal(fem->X, fem->nv);
    if (co.kappa == 0) {
        double g = sqrt(opt->gravity[0] * opt->gravity[0] + opt->gravity[1] * opt->gravity[1] +
                        opt->gravity[2] * opt->gravity[2]);
        co.kappa = rk_contact_holding_kappa(co.dhat, m->mass / fem->nv * fmax(g, 1.0));
    }
    rk_mesh view = {.nv = fem->nv, .nt = fem->nt, .X = (double *)fem->X, .tets = (int *)fem->tets,
                    .nghost = fem->nghost, .ghost = (int *)fem->ghost};
    if (rk_contact_init(&m->contact, &view, opt->object_first_vertex, opt->nobjects, opt->obstacles, opt->nobstacles,
                        &co, m->mass / fem->nv, err))
        return -1;
    int nc = m->contact.nv, r = m->r, ndof = 3 * fem->nv;
    m->cv_rows = rk_calloc(3 * (size_t)nc * r + 1, sizeof(double), err);
    m->cv_of = rk_calloc((size_t)fem->nv + 1, sizeof(int), err);
    if (!m->cv_rows || !m->cv_of) return -1;
    for (int v = 0; v < fem->nv; v++) m->cv_of[v] = -1;
    for (int i = 0; i < nc; i++) {
        int v = m->contact.vertex[i];
        m->cv_of[v] = i;
        for (int a = 0; a < 3; a++)
            for (int j = 0; j < r; j++) m->cv_rows[(size_t)(3 * i + a) * r + j] = U[(size_t)ndof * j + 3 * v + a];
    }
    return 0;
}

/* x_v = X_v + U_v q at every collision vertex, into s->x. */
void rk_rom_contact_positions(rk_rom *s, const double *q)
{
    const rk_rom_model *m = s->model;
    int r = m->r;
    for (int i = 0; i < m->contact.nv; i++) {
        int v = m->contact.vertex[i];
        for (int a = 0; a < 3; a++)
            s->x[3 * v + a] = m->contact.X[3 * v + a] + cblas_ddot(r, m->cv_rows + (size_t)(3 * i + a) * r, 1, q, 1);
    }
}

typedef struct {
    const rk_rom_model *m;
    double *H;      /* r x r, column-major (both triangles) */
    double *JB;     /* 12 x r scratch */
} reduce_ctx;

/* H += J^T B J for a pair's block B over its points' rows J (obstacle points have none). */
static void reduce_block(void *ctx, const int *id, int npoints, const double *B)
{
    reduce_ctx *c = ctx;
    const rk_rom_model *m = c->m;
    int r = m->r, dim = 3 * npoints;
    const double *rows[12] = {0};
    for (int k = 0; k < npoints; k++)
        for (int a = 0; a < 3; a++)
            rows[3 * k + a] = id[k] >= 0 ? m->cv_rows + (size_t)(3 * m->cv_of[id[k]] + a) * r : NULL;
    /* JB = B J (dim x r), then H += J^T JB */
    for (int i = 0; i < dim; i++) {
        double *out = c->JB + (size_t)i * r;
        memset(out, 0, sizeof(double) * (size_t)r);
        for (int k = 0; k < dim; k++)
            if (rows[k] && B[dim * i + k] != 0) cblas_daxpy(r, B[dim * i + k], rows[k], 1, out, 1);
    }
    for (int i = 0; i < dim; i++)
        if (rows[i]) cblas_dger(CblasColMajor, r, r, 1.0, rows[i], 1, c->JB + (size_t)i * r, 1, c->H, r);
}

double rk_rom_contact_energy(rk_rom *s, const double *q, int friction, double *g, double *H, rk_error *err)
{
    rk_rom_model *m = s->model;
    int r = m->r;
    rk_rom_contact_positions(s, q);
    if (rk_contact_gather(&m->contact, s->x, &s->pairs, err)) return NAN;
    for (int i = 0; g && i < m->contact.nv; i++)
        for (int a = 0; a < 3; a++) s->gx[3 * m->contact.vertex[i] + a] = 0;
    reduce_ctx ctx = {m, H, s->jb};
    double E = rk_contact_energy(&m->contact, &s->pairs, s->x, g ? s->gx : NULL, NULL, H ? reduce_block : NULL, &ctx,
                                 NULL);
    if (friction && isfinite(E))
        E += rk_contact_friction_energy(&m->contact, s->x, m->h, g ? s->gx : NULL, NULL, H ? reduce_block : NULL, &ctx);
    if (g && isfinite(E))
        for (int i = 0; i < m->contact.nv; i++)
            for (int a = 0; a < 3; a++) {
                double gv = s->gx[3 * m->contact.vertex[i] + a];
                if (gv != 0) cblas_daxpy(r, gv, m->cv_rows + (size_t)(3 * i + a) * r, 1, g, 1);
            }
    return E;
}

double rk_rom_contact_max_step(rk_rom *s, const double *q, const double *dq, double t, rk_error *err)
{
    rk_rom_model *m = s->model;
    int r = m->r;
    rk_rom_contact_positions(s, q);
    for (int i = 0; i < m->contact.nv; i++) {
        int v = m->contact.vertex[i];
        for (int a = 0; a < 3; a++)
            s->dx[3 * v + a] = dq ? cblas_ddot(r, m->cv_rows + (size_t)(3 * i + a) * r, 1, dq, 1) : 0;
    }
    if (!isnan(t)) { /* the obstacles' way to where they are at t */
        rk_contact_obstacles_at(&m->contact, t, s->odx);
        for (int i = 0; i < 3 * m->contact.onv; i++) s->odx[i] -= m->contact.ox[i];
    }
    return rk_contact_max_step(&m->contact, s->x, s->dx, isnan(t) ? NULL : s->odx, err);
}

int rk_rom_contact_intersections(rk_rom *s, const double *q, rk_error *err)
{
    rk_rom_contact_positions(s, q);
    return rk_contact_intersections(&s->model->contact, s->x, err);
}

int rk_rom_contact_measure(rk_rom *s, int *intersections, double *min_distance, rk_error *err)
{
    *intersections = 0;
    *min_distance = INFINITY;
    if (!s->model->has_contact) return 0;
    *intersections = rk_rom_contact_intersections(s, s->q, err);
    if (*intersections < 0) return -1;
    *min_distance = rk_contact_min_distance(&s->model->contact, s->x, err); /* s->x: set just above */
    return isnan(*min_distance) ? -1 : 0;
}

int rk_rom_friction_start(rk_rom *s, const double *q, rk_error *err)
{
    rk_rom_contact_positions(s, q);
    return rk_contact_friction_start(&s->model->contact, s->x, err);
}

int rk_rom_friction_lag(rk_rom *s, const double *q, rk_error *err)
{
    rk_rom_contact_positions(s, q);
    return rk_contact_friction_lag(&s->model->contact, s->x, err);
}
