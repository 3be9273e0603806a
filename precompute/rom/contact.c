/* Contact in the subspace (rom.h): the contact stage on the boundary vertices x_v = X_v + U_v q.
 * The barrier's gradient and Hessian blocks come back per vertex and are pulled into the subspace
 * through the rows of the vertices each pair touches; a step dq moves them by U_v dq, so CCD
 * filters it exactly as at full order. */
#include "rom/rom_impl.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The boundary vertices, ascending (as the contact stage lists them). */
static int boundary_vertices(const rk_mesh *view, rk_rom_model *m, rk_error *err)
{
    int *tris = NULL, nf = 0;
    if (rk_mesh_boundary(view, &tris, &nf, err)) return -1;
    char *on = rk_calloc((size_t)view->nv + 1, 1, err);
    m->cv = rk_calloc((size_t)view->nv + 1, sizeof(int), err);
    if (!on || !m->cv) {
        free(tris), free(on);
        return -1;
    }
    for (int i = 0; i < 3 * nf; i++) on[tris[i]] = 1;
    for (int v = 0; v < view->nv; v++)
        if (on[v]) m->cv[m->ncv++] = v;
    free(tris), free(on);
    return 0;
}

int rk_rom_contact_init(rk_rom_model *m, const rk_fem *fem, const rk_fom_options *opt, const double *U, rk_error *err)
{
    /* the boundary vertices and their rows always: the scene's contact and an app's colliders act on them */
    rk_mesh view = {.nv = fem->nv, .nt = fem->nt, .X = (double *)fem->X, .tets = (int *)fem->tets,
                    .nghost = fem->nghost, .ghost = (int *)fem->ghost};
    if (boundary_vertices(&view, m, err)) return -1;
    int nc = m->ncv, r = m->r, ndof = 3 * fem->nv;
    m->cv_rows = rk_calloc(3 * (size_t)nc * r + 1, sizeof(double), err);
    m->cv_X = rk_calloc(3 * (size_t)nc + 1, sizeof(double), err);
    m->cv_of = rk_calloc((size_t)fem->nv + 1, sizeof(int), err);
    if (!m->cv_rows || !m->cv_X || !m->cv_of) return -1;
    for (int v = 0; v < fem->nv; v++) m->cv_of[v] = -1;
    for (int i = 0; i < nc; i++) {
        int v = m->cv[i];
        m->cv_of[v] = i;
        memcpy(m->cv_X + 3 * i, fem->X + 3 * (size_t)v, 3 * sizeof(double));
        for (int a = 0; a < 3; a++)
            for (int j = 0; j < r; j++) m->cv_rows[(size_t)(3 * i + a) * r + j] = U[(size_t)ndof * j + 3 * v + a];
    }
    rk_contact_options co = opt->contact;
    if (co.dhat == 0) co.dhat = 1e-3 * rk_points_diagonal(fem->X, fem->nv);
    if (co.kappa == 0) {
        double g = sqrt(opt->gravity[0] * opt->gravity[0] + opt->gravity[1] * opt->gravity[1] +
                        opt->gravity[2] * opt->gravity[2]);
        /* the average vertex's weight, over the vertices that carry the bodies: a mesh's (those of
         * its tets), and a point cloud's contact surface, on which its mass sits (not its many
         * points: beside a mesh they made the slab's weight look 20 times lighter than it is, and
         * the float runtime stalled with it pressed to 3e-3 dhat of its plane) */
        int carriers = 0;
        char *in_tet = rk_calloc((size_t)fem->nv + 1, 1, err);
        if (!in_tet) return -1;
        for (size_t k = 0; k < 4 * (size_t)fem->nt; k++) in_tet[fem->tets[k]] = 1;
        for (int v = 0; v < fem->nv; v++) carriers += in_tet[v] || m->cv_of[v] >= 0;
        free(in_tet);
        if (carriers == 0) carriers = fem->nv;
        co.kappa = rk_contact_holding_kappa(co.dhat, m->mass / carriers * fmax(g, 1.0));
    }
    m->contact_options = co;
    m->has_contact = opt->nobstacles > 0 || opt->nobjects > 1 || opt->contact.self;
    if (!m->has_contact) return 0;
    if (rk_contact_init(&m->contact, &view, opt->object_first_vertex, opt->nobjects, opt->obstacles, opt->nobstacles,
                        &co, m->mass / fem->nv, err))
        return -1;
    if (m->contact.nv != nc || memcmp(m->contact.vertex, m->cv, sizeof(int) * (size_t)nc) != 0)
        return rk_fail(err, "the contact stage's boundary (%d vertices) is not the reduced model's (%d)",
                       m->contact.nv, nc);
    /* every obstacle but a plane has vertices: bake_obstacles.c's condition for OBHD */
    m->surface = m->contact.onv > 0 || m->contact.mesh_pairs;
    return 0;
}

int rk_rom_colliders_surface(const rk_rom_model *m, const rk_fem *fem, rk_contact *out, rk_error *err)
{
    rk_mesh view = {.nv = fem->nv, .nt = fem->nt, .X = (double *)fem->X, .tets = (int *)fem->tets,
                    .nghost = fem->nghost, .ghost = (int *)fem->ghost};
    if (rk_contact_init(out, &view, NULL, 1, NULL, 0, &m->contact_options, m->mass / fem->nv, err)) return -1;
    if (out->nv != m->ncv) {
        int nv = out->nv;
        rk_contact_free(out);
        return rk_fail(err, "the collision surface's %d vertices are not the reduced model's %d", nv, m->ncv);
    }
    return 0;
}

int rk_rom_contact_for_colliders(rk_rom_model *m, const rk_fem *fem, rk_error *err)
{
    if (m->surface || m->ncv == 0) return 0;
    if (!m->has_contact) {
        if (rk_rom_colliders_surface(m, fem, &m->contact, err)) return -1;
        m->colliders_contact = 1;
    }
    m->surface = 1;
    return 0;
}

/* x_v = X_v + U_v q at every collision vertex, into s->x. */
void rk_rom_contact_positions(rk_rom *s, const double *q)
{
    const rk_rom_model *m = s->model;
    int r = m->r;
    for (int i = 0; i < m->ncv; i++) {
        int v = m->cv[i];
        for (int a = 0; a < 3; a++)
            s->x[3 * v + a] = m->cv_X[3 * i + a] + cblas_ddot(r, m->cv_rows + (size_t)(3 * i + a) * r, 1, q, 1);
    }
}

void rk_rom_reduce_block(void *ctx, const int *id, int npoints, const double *B)
{
    rk_rom_reduce_ctx *c = ctx;
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
    if (!c->way) return;
    /* the obstacles moving by s_k D_o (obstacle_solve.c): d2/ds_k ds_l += D_k . B D_l and
     * d2/dq ds_k += sum over the mesh points of J^T B D_k */
    double BD[48];
    int units[4], nu = rk_obstacle_way_block(c->way, id, npoints, B, units, BD, c->hss, c->way->n);
    for (int j = 0; j < nu; j++)
        for (int i = 0; i < dim; i++)
            if (rows[i] && BD[12 * j + i] != 0) cblas_daxpy(r, BD[12 * j + i], rows[i], 1, c->hqs + (size_t)r * units[j], 1);
}

double rk_rom_contact_energy(rk_rom *s, const double *q, int friction, double *g, double *H, rk_error *err)
{
    rk_rom_model *m = s->model;
    rk_rom_contact_positions(s, q);
    if (rk_contact_gather(&m->contact, s->x, &s->pairs, err)) return NAN;
    if (g) rk_rom_clear_vertex_gradient(s);
    rk_rom_reduce_ctx ctx = {m, H, s->jb, s->obs_way, s->obs_hqs, s->obs_hss};
    int onv = m->contact.onv;
    double *og = s->obs_way && g ? s->ogx : NULL; /* the obstacles' gradient, for d/ds */
    if (og) memset(og, 0, sizeof(double) * 3 * (size_t)onv);
    double E = rk_contact_energy(&m->contact, &s->pairs, s->x, g ? s->gx : NULL, og, H ? rk_rom_reduce_block : NULL,
                                 &ctx, NULL);
    if (friction && isfinite(E))
        E += rk_contact_friction_energy(&m->contact, s->x, m->h, g ? s->gx : NULL, og,
                                        H ? rk_rom_reduce_block : NULL, &ctx);
    if (g && isfinite(E)) rk_rom_pull_vertex_gradient(s, g);
    if (og && isfinite(E)) rk_obstacle_way_gradient(s->obs_way, og, s->obs_gs);
    return E;
}

void rk_rom_clear_vertex_gradient(rk_rom *s)
{
    const rk_rom_model *m = s->model;
    for (int i = 0; i < m->ncv; i++)
        for (int a = 0; a < 3; a++) s->gx[3 * m->cv[i] + a] = 0;
}

void rk_rom_pull_vertex_gradient(rk_rom *s, double *g)
{
    const rk_rom_model *m = s->model;
    for (int i = 0; i < m->ncv; i++)
        for (int a = 0; a < 3; a++) {
            double gv = s->gx[3 * m->cv[i] + a];
            if (gv != 0) cblas_daxpy(m->r, gv, m->cv_rows + (size_t)(3 * i + a) * m->r, 1, g, 1);
        }
}

void rk_rom_contact_move(rk_rom *s, const double *q, const double *dq)
{
    const rk_rom_model *m = s->model;
    int r = m->r;
    rk_rom_contact_positions(s, q);
    for (int i = 0; i < m->ncv; i++)
        for (int a = 0; a < 3; a++)
            s->dx[3 * m->cv[i] + a] = dq ? cblas_ddot(r, m->cv_rows + (size_t)(3 * i + a) * r, 1, dq, 1) : 0;
}

double rk_rom_contact_max_step(rk_rom *s, const double *q, const double *dq, double t, rk_error *err)
{
    rk_rom_model *m = s->model;
    rk_rom_contact_move(s, q, dq);
    double alpha = 1;
    if (rk_rom_contact_on(m)) {
        if (!isnan(t)) { /* the obstacles' way to where they are at t */
            rk_contact_obstacles_at(&m->contact, t, s->odx);
            for (int i = 0; i < 3 * m->contact.onv; i++) s->odx[i] -= m->contact.ox[i];
        }
        alpha = rk_contact_max_step(&m->contact, s->x, s->dx, isnan(t) ? NULL : s->odx, err);
    }
    if (dq && alpha > 0) alpha = fmin(alpha, rk_rom_colliders_max_step(s));
    return alpha;
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
    if (!rk_rom_contact_on(s->model)) return 0;
    rk_rom_contact_positions(s, s->q);
    return rk_contact_measure(&s->model->contact, s->x, intersections, min_distance, err);
}

int rk_rom_friction_start(rk_rom *s, const double *q, rk_error *err)
{
    rk_rom_contact_positions(s, q);
    rk_rom_colliders_friction_start(s);
    return rk_rom_contact_on(s->model) ? rk_contact_friction_start(&s->model->contact, s->x, err) : 0;
}

int rk_rom_friction_lag(rk_rom *s, const double *q, rk_error *err)
{
    rk_rom_contact_positions(s, q);
    rk_rom_colliders_friction_lag(s);
    return rk_rom_contact_on(s->model) ? rk_contact_friction_lag(&s->model->contact, s->x, err) : 0;
}
