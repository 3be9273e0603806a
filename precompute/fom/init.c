/* rk_fom_init / rk_fom_free: options checked, inputs copied, constant matrices (mass, damping)
 * and loads built once, CHOLMOD's symbolic analysis done once. */
#include "fom/fom_impl.h"
#include "util/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int all_finite(const double *a, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

int rk_fom_check_options(const rk_fom_options *o, int nv, rk_error *err)
{
    if (!(isfinite(o->h) && o->h > 0)) return rk_fail(err, "time step h = %g must be positive", o->h);
    if (o->steps < 0) return rk_fail(err, "steps = %d must not be negative", o->steps);
    if (o->integrator != RK_BACKWARD_EULER && o->integrator != RK_BDF2)
        return rk_fail(err, "unknown integrator %d", (int)o->integrator);
    if (o->newton_max_iter < 0)
        return rk_fail(err, "newton_max_iter = %d must be at least 1 (or 0: the default)", o->newton_max_iter);
    if (!isfinite(o->newton_tol)) return rk_fail(err, "newton_tol = %g is not finite", o->newton_tol);
    if (!all_finite(o->gravity, 3)) return rk_fail(err, "gravity is not finite");
    if (!(isfinite(o->rayleigh_mass) && o->rayleigh_mass >= 0 && isfinite(o->rayleigh_stiffness) &&
          o->rayleigh_stiffness >= 0))
        return rk_fail(err, "Rayleigh damping (%g, %g) must be non-negative", o->rayleigh_mass,
                       o->rayleigh_stiffness);
    for (int i = 0; i < 3 * nv; i++) {
        if (o->force && !isfinite(o->force[i]))
            return rk_fail(err, "force on vertex %d is not finite", i / 3);
        if (o->velocity0 && !isfinite(o->velocity0[i]))
            return rk_fail(err, "initial velocity of vertex %d is not finite", i / 3);
        if (o->position0 && !isfinite(o->position0[i]))
            return rk_fail(err, "initial position of vertex %d is not finite", i / 3);
    }
    if (o->nobstacles < 0 || (o->nobstacles > 0 && !o->obstacles))
        return rk_fail(err, "%d obstacles given without data", o->nobstacles);
    if (!(isfinite(o->contact.dhat) && o->contact.dhat >= 0))
        return rk_fail(err, "contact: dhat = %g must not be negative", o->contact.dhat);
    if (o->nobjects < 0 || (o->nobjects > 1 && !o->object_first_vertex))
        return rk_fail(err, "%d objects given without their first vertices", o->nobjects);
    for (int k = 0; o->object_first_vertex && k < o->nobjects; k++)
        if (o->object_first_vertex[k] > o->object_first_vertex[k + 1] || o->object_first_vertex[0] != 0 ||
            o->object_first_vertex[o->nobjects] != nv)
            return rk_fail(err, "objects: object %d's vertices [%d, %d) do not tile the mesh's %d", k,
                           o->object_first_vertex[k], o->object_first_vertex[k + 1], nv);
    const rk_fom_contact_surface *cs = o->contact_surface;
    if (cs && o->nobjects > 1 && !cs->object_first_vertex)
        return rk_fail(err, "contact surface: %d objects given without their first vertices", o->nobjects);
    for (int k = 0; cs && cs->object_first_vertex && k < o->nobjects; k++)
        if (cs->object_first_vertex[k] > cs->object_first_vertex[k + 1] || cs->object_first_vertex[0] != 0 ||
            cs->object_first_vertex[o->nobjects] != cs->mesh.nv)
            return rk_fail(err, "contact surface: object %d's vertices [%d, %d) do not tile its %d", k,
                           cs->object_first_vertex[k], cs->object_first_vertex[k + 1], cs->mesh.nv);
    if (o->nprescribed < 0 || (o->nprescribed > 0 && !o->prescribed))
        return rk_fail(err, "%d prescribed groups given without data", o->nprescribed);
    if (o->nchambers < 0 || (o->nchambers > 0 && !o->chambers))
        return rk_fail(err, "%d chambers given without data", o->nchambers);
    for (int k = 0; k < o->nchambers; k++)
        if (rk_chamber_check(&o->chambers[k], nv, err)) return rk_error_prefix(err, "chamber %d", k);
    return 0;
}

/* Copies the chambers (their faces and pressures): the caller's arrays need not outlive init. */
static int copy_chambers(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    int n = s->opt.nchambers;
    im->chambers = rk_calloc((size_t)n + 1, sizeof *im->chambers, err);
    if (!im->chambers) return -1;
    for (int k = 0; k < n; k++) {
        const rk_chamber *c = &s->opt.chambers[k];
        im->chambers[k] = (rk_chamber){.nf = c->nf, .pressure = c->pressure, .nkeys = c->nkeys};
        if (!(im->chambers[k].tris = rk_calloc(3 * (size_t)c->nf, sizeof(int), err))) return -1;
        memcpy(im->chambers[k].tris, c->tris, sizeof(int) * 3 * (size_t)c->nf);
        if (!(im->chambers[k].keys = rk_calloc(2 * (size_t)c->nkeys + 1, sizeof(double), err))) return -1;
        if (c->nkeys) memcpy(im->chambers[k].keys, c->keys, sizeof(double) * 2 * (size_t)c->nkeys);
    }
    s->opt.chambers = im->chambers;
    return 0;
}

static int normalize(double v[3])
{
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(isfinite(len) && len > 0)) return -1;
    for (int i = 0; i < 3; i++) v[i] /= len;
    return 0;
}

/* Copies the prescribed groups (axes normalised) and marks their dofs; a vertex in two groups
 * would have two targets. */
static int copy_prescribed(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    int n = s->opt.nprescribed, nv = s->fem->nv;
    im->groups = rk_calloc((size_t)n, sizeof *im->groups, err);
    if (!im->groups) return -1;
    for (int k = 0; k < n; k++) {
        const rk_prescribed *src = &s->opt.prescribed[k];
        rk_prescribed *p = &im->groups[k];
        *p = *src;
        p->verts = rk_calloc((size_t)(src->count > 0 ? src->count : 1), sizeof(int), err);
        if (!p->verts) return -1;
        if (src->count < 0 || (src->count > 0 && !src->verts))
            return rk_fail(err, "prescribed group %d: %d vertices given without data", k, src->count);
        if (src->kind != RK_MOTION_FIXED && src->kind != RK_MOTION_TWIST && src->kind != RK_MOTION_TRANSLATE)
            return rk_fail(err, "prescribed group %d: unknown motion kind %d", k, (int)src->kind);
        if (src->kind == RK_MOTION_TWIST &&
            (normalize(p->axis) || !isfinite(p->rate) || !all_finite(p->center, 3)))
            return rk_fail(err, "prescribed group %d: twist needs a non-zero axis, a finite rate and center", k);
        if (src->kind != RK_MOTION_FIXED && !all_finite(p->velocity, 3))
            return rk_fail(err, "prescribed group %d: translation velocity is not finite", k);
        for (int j = 0; j < src->count; j++) {
            int v = src->verts[j];
            if (v < 0 || v >= nv)
                return rk_fail(err, "prescribed group %d: vertex %d out of range (the mesh has %d)", k, v, nv);
            if (im->prescribed_dof[3 * v])
                return rk_fail(err, "prescribed group %d: vertex %d is already prescribed", k, v);
            im->prescribed_dof[3 * v] = im->prescribed_dof[3 * v + 1] = im->prescribed_dof[3 * v + 2] = 1;
            p->verts[j] = v;
        }
    }
    s->opt.prescribed = im->groups;
    return 0;
}

/* The contact model when there is something to collide with: obstacles, several objects, or
 * self-contact. dhat 0 means 1e-3 of the rest bounding-box diagonal (DESIGN.md). */
static int init_contact(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    const rk_fom_options *o = &s->opt;
    const rk_obstacle *obstacles = o->obstacles;
    const int *first_vertex = o->object_first_vertex;
    const rk_fom_contact_surface *cs = o->contact_surface;
    im->has_contact = o->nobstacles > 0 || o->nobjects > 1 || o->contact.self;
    s->opt.obstacles = NULL; /* copied into the contact model below; the caller's arrays need not outlive init */
    s->opt.object_first_vertex = NULL;
    s->opt.contact_surface = NULL; /* copied into the contact model and im->emb below */
    if (!im->has_contact) return 0;
    const rk_fem *f = s->fem;
    rk_contact_options co = o->contact;
    if (co.dhat == 0) co.dhat = 1e-3 * rk_points_diagonal(f->X, f->nv);
    double mass = 0;
    for (int v = 0; v < f->nv; v++) mass += f->vertex_mass[v];
    rk_mesh view = {.nv = f->nv, .nt = f->nt, .X = (double *)f->X, .tets = (int *)f->tets, .nghost = f->nghost,
                    .ghost = (int *)f->ghost};
    if (cs) { /* an embedded contact surface (contact_view.c): the contact model on its vertices */
        view = cs->mesh;
        first_vertex = cs->object_first_vertex;
    }
    if (rk_fom_embedding_init(&im->emb, cs, f->nv, err) ||
        rk_contact_init(&im->contact, &view, first_vertex, o->nobjects, obstacles, o->nobstacles, &co, mass / f->nv,
                        err))
        return -1;
    s->opt.contact = co;
    /* moving obstacles: every obstacle vertex becomes an unknown (the static ones prescribed) */
    int moving = 0;
    for (int k = 0; k < o->nobstacles; k++) moving |= obstacles[k].motion != RK_MOTION_FIXED;
    im->nobs = moving && !o->obstacle_progress ? im->contact.onv : 0;
    im->ndof = im->n + 3 * im->nobs;
    im->contact.obstacle_dofs = im->nobs > 0;
    im->al_mass = mass / f->nv;
    size_t nd = (size_t)im->ndof;
    char *mask = rk_calloc(nd, 1, err);
    if (!mask) return -1;
    memcpy(mask, im->prescribed_dof, (size_t)im->n);
    free(im->prescribed_dof);
    im->prescribed_dof = mask;
    for (int v = 0; v < im->nobs; v++)
        if (obstacles[im->contact.overt_obstacle[v]].motion == RK_MOTION_FIXED)
            mask[im->n + 3 * v] = mask[im->n + 3 * v + 1] = mask[im->n + 3 * v + 2] = 1;
    free(im->newton_work);
    im->newton_work = rk_calloc(RK_NEWTON_WORK(nd), sizeof(double), err);
    im->g_barrier = rk_calloc(nd, sizeof(double), err);
    free(im->y);
    im->y = rk_calloc(nd, sizeof(double), err);
    im->obs_target = rk_calloc(3 * (size_t)im->nobs + 1, sizeof(double), err);
    im->al_lambda = rk_calloc(3 * (size_t)im->nobs + 1, sizeof(double), err);
    if (moving && o->obstacle_progress) im->og = rk_calloc(3 * (size_t)im->contact.onv + 1, sizeof(double), err);
    return im->newton_work && im->g_barrier && im->y && im->obs_target && im->al_lambda &&
                   (im->og || !moving || !o->obstacle_progress) ? 0 : -1;
}

/* Inertia mass, Rayleigh damping a M + b K0, and f_ext = m_v g + force. Gravity uses the lumped
 * vertex masses: for P1 they are the row sums of the consistent mass, so M g (consistent) gives
 * the same nodal forces. */
static int build_constants(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    const rk_fem *f = s->fem;
    if (rk_sparse_alloc_pattern(f, &im->M, err) || rk_sparse_alloc_pattern(f, &im->H, err)) return -1;
    rk_fem_add_mass(f, s->opt.lumped_mass, 1.0, &im->M);
    if (s->opt.rayleigh_mass > 0 || s->opt.rayleigh_stiffness > 0) {
        if (rk_sparse_alloc_pattern(f, &im->C, err)) return -1;
        rk_fem_add_mass(f, s->opt.lumped_mass, s->opt.rayleigh_mass, &im->C);
        rk_fem_add_rest_stiffness(f, s->opt.rayleigh_stiffness, &im->C);
    }
    for (int v = 0; v < f->nv; v++)
        for (int i = 0; i < 3; i++) im->f_ext[3 * v + i] = f->vertex_mass[v] * s->opt.gravity[i];
    if (s->opt.force) {
        memcpy(im->force, s->opt.force, (size_t)im->n * sizeof(double));
        for (int i = 0; i < im->n; i++) im->f_ext[i] += im->force[i];
        s->opt.force = im->force;
    }
    s->opt.velocity0 = NULL; /* read once, below; the caller's arrays need not outlive init */
    s->opt.position0 = NULL;
    return 0;
}

/* newton_tol <= 0: RK_FOM_DEFAULT_TOL times the bounding-box diagonal, per second; a static solve
 * then uses that times h as its |d|_inf bound in metres. A given newton_tol is used as is. */
static void resolve_tolerance(rk_fom *s)
{
    double diag = rk_points_diagonal(s->fem->X, s->fem->nv);
    if (s->opt.newton_tol > 0) {
        s->impl->tol_static = s->opt.newton_tol;
    } else {
        s->opt.newton_tol = RK_FOM_DEFAULT_TOL * diag;
        s->impl->tol_static = s->opt.newton_tol * s->opt.h;
    }
}

static int alloc_state(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    size_t n = (size_t)im->n;
    double **vecs[] = {&s->x, &s->v, &im->f_ext, &im->force, &im->work, &im->work2};
    for (size_t k = 0; k < sizeof vecs / sizeof vecs[0]; k++)
        if (!(*vecs[k] = rk_calloc(n, sizeof(double), err))) return -1;
    im->ndof = im->n;
    if (!(im->y = rk_calloc(n, sizeof(double), err))) return -1;
    if (!(im->newton_work = rk_calloc(RK_NEWTON_WORK(n), sizeof(double), err))) return -1;
    if (rk_stepper_init(&im->stepper, im->n, s->opt.integrator, s->opt.h, err)) return -1;
    im->prescribed_dof = rk_calloc(n, 1, err);
    return im->prescribed_dof ? 0 : -1;
}

/* The start must be free of intersections (exact test) and keep every barrier finite. */
static int check_start(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    if (!im->has_contact) return 0;
    int crossings = rk_fom_intersections(im, s->x, err);
    if (crossings < 0) return -1;
    if (crossings > 0)
        return rk_fail(err, "the start intersects itself, another object or an obstacle (%d crossings or points "
                       "behind a plane)", crossings);
    double d = rk_fom_min_distance(im, s->x, err);
    if (!(d > 0)) return rk_fail(err, "the start touches an obstacle or another surface (distance %g m)", d);
    return 0;
}

int rk_fom_init(rk_fom *s, const rk_fem *fem, const rk_fom_options *opt, rk_error *err)
{
    memset(s, 0, sizeof *s);
    if (rk_fom_check_options(opt, fem->nv, err)) return -1;
    s->fem = fem;
    s->opt = *opt;
    s->impl = rk_calloc(1, sizeof *s->impl, err);
    if (!s->impl) return -1;
    s->impl->n = 3 * fem->nv;
    if (alloc_state(s, err) || copy_prescribed(s, err) || copy_chambers(s, err) || build_constants(s, err))
        goto fail;
    memcpy(s->x, opt->position0 ? opt->position0 : fem->X, (size_t)s->impl->n * sizeof(double));
    if (opt->velocity0) memcpy(s->v, opt->velocity0, (size_t)s->impl->n * sizeof(double));
    if (init_contact(s, err) || check_start(s, err)) goto fail;
    resolve_tolerance(s);
    if (rk_newton_matrix_init(&s->impl->N, &s->impl->H, s->impl->nobs, err) || rk_fom_chol_analyze(s->impl, err))
        goto fail;
    rk_fom_sync_stats(s);
    return 0;
fail:
    rk_fom_free(s);
    return -1;
}

void rk_fom_free(rk_fom *s)
{
    rk_fom_impl *im = s->impl;
    if (im) {
        rk_fom_chol_free(im);
        rk_sparse_free(&im->M);
        rk_sparse_free(&im->C);
        rk_sparse_free(&im->H);
        if (im->groups)
            for (int k = 0; k < s->opt.nprescribed; k++) free(im->groups[k].verts);
        free(im->groups);
        if (im->chambers)
            for (int k = 0; k < s->opt.nchambers; k++) free(im->chambers[k].tris), free(im->chambers[k].keys);
        free(im->chambers);
        if (im->has_contact) rk_contact_free(&im->contact);
        rk_fom_embedding_free(&im->emb);
        rk_contact_set_free(&im->pairs);
        rk_newton_matrix_free(&im->N);
        free(im->g_barrier), free(im->y), free(im->obs_target), free(im->al_lambda), free(im->og);
        free(im->force);
        free(im->f_ext);
        free(im->prescribed_dof);
        rk_stepper_free(&im->stepper);
        free(im->newton_work), free(im->work), free(im->work2);
        free(im->iter_seconds), free(im->iter_factor);
        free(im);
    }
    free(s->x);
    free(s->v);
    memset(s, 0, sizeof *s);
}

int rk_fom_contact_measure(rk_fom *s, int *intersections, double *min_distance, rk_error *err)
{
    *intersections = 0;
    *min_distance = INFINITY;
    if (!s->impl->has_contact) return 0;
    return rk_contact_measure(&s->impl->contact, rk_fom_contact_x(s->impl, s->x), intersections, min_distance, err);
}

const rk_contact_stats *rk_fom_contact_stats(const rk_fom *s)
{
    return s->impl->has_contact ? &s->impl->contact.stats : NULL;
}
