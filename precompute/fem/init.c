/* rk_fem_init / rk_fem_free: per-element rest data and materials, lumped masses, the pattern. */
#include "fem/element_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int check_material(const rk_material *m, int t, rk_error *err)
{
    if ((int)m->model < (int)RK_MAT_LINEAR || (int)m->model > (int)RK_MAT_NEOHOOKEAN)
        return rk_fail(err, "element %d: unknown material model %d", t, (int)m->model);
    if (!(isfinite(m->young) && m->young > 0))
        return rk_fail(err, "element %d: Young's modulus %g must be positive and finite", t, m->young);
    if (!(isfinite(m->poisson) && m->poisson > -1 && m->poisson < 0.5))
        return rk_fail(err, "element %d: Poisson's ratio %g must lie in (-1, 0.5)", t, m->poisson);
    if (!(isfinite(m->density) && m->density > 0))
        return rk_fail(err, "element %d: density %g must be positive and finite", t, m->density);
    return 0;
}

static int alloc_arrays(rk_fem *f, rk_error *err)
{
    size_t nt = (size_t)f->nt;
    f->Dm_inv = rk_calloc(9 * nt, sizeof(double), err);
    f->vol = rk_calloc(nt, sizeof(double), err);
    f->model = rk_calloc(nt, sizeof(rk_material_model), err);
    f->mu = rk_calloc(nt, sizeof(double), err);
    f->lambda = rk_calloc(nt, sizeof(double), err);
    f->density = rk_calloc(nt, sizeof(double), err);
    f->vertex_mass = rk_calloc((size_t)f->nv, sizeof(double), err);
    return f->Dm_inv && f->vol && f->model && f->mu && f->lambda && f->density && f->vertex_mass ? 0 : -1;
}

static int init_elements(rk_fem *f, const rk_material *mats, rk_error *err)
{
    for (int t = 0; t < f->nt; t++) {
        const int *v = &f->tets[4 * t];
        for (int a = 0; a < 4; a++)
            if (v[a] < 0 || v[a] >= f->nv)
                return rk_fail(err, "element %d references vertex %d (the mesh has %d)", t, v[a], f->nv);
        if (check_material(&mats[t], t, err)) return -1;
        double xe[12];
        rk_fem_gather(f, t, f->X, xe);
        double vol = rk_tet_rest(xe, &f->Dm_inv[9 * t]);
        if (!(vol > 0) || !isfinite(vol))
            return rk_fail(err, "element %d has non-positive volume (%g)", t, vol);
        f->vol[t] = vol;
        f->model[t] = mats[t].model;
        f->density[t] = mats[t].density;
        rk_lame(mats[t].young, mats[t].poisson, &f->mu[t], &f->lambda[t]);
        double quarter = 0.25 * mats[t].density * vol;
        for (int a = 0; a < 4; a++) f->vertex_mass[v[a]] += quarter;
    }
    return 0;
}

int rk_fem_init(rk_fem *f, const rk_mesh *m, const rk_material *mats, rk_error *err)
{
    memset(f, 0, sizeof *f);
    if (m->nv <= 0 || m->nt <= 0)
        return rk_fail(err, "mesh has %d vertices and %d elements; need at least one element", m->nv, m->nt);
    f->nv = m->nv;
    f->nt = m->nt;
    f->X = m->X;
    f->tets = m->tets;
    f->nghost = m->nghost;
    f->ghost = m->ghost;
    if (alloc_arrays(f, err) || init_elements(f, mats, err) || rk_fem_build_pattern(f, err)) {
        rk_fem_free(f);
        return -1;
    }
    for (int v = 0; v < f->nv; v++)
        if (!(f->vertex_mass[v] > 0)) { /* would make the mass matrix singular */
            rk_fem_free(f);
            return rk_fail(err, "vertex %d belongs to no element", v);
        }
    return 0;
}

int rk_fem_init_points(rk_fem *f, const rk_mesh *m, const rk_material *mats, const double *vertex_mass, rk_error *err)
{
    memset(f, 0, sizeof *f);
    if (m->nv <= 0 || m->nt < 0 || (m->nt > 0 && !mats))
        return rk_fail(err, "point model: %d vertices and %d elements%s", m->nv, m->nt,
                       m->nt > 0 && !mats ? " given without their materials" : "");
    f->nv = m->nv;
    f->nt = m->nt;
    f->X = m->X;
    f->tets = m->tets;
    f->nghost = m->nghost;
    f->ghost = m->ghost;
    if (alloc_arrays(f, err) || init_elements(f, mats, err) || rk_fem_build_pattern(f, err)) {
        rk_fem_free(f);
        return -1;
    }
    f->point_mass = rk_calloc((size_t)m->nv, sizeof(double), err);
    if (!f->point_mass) {
        rk_fem_free(f);
        return -1;
    }
    for (int v = 0; v < m->nv; v++) {
        if (!(vertex_mass[v] >= 0 && isfinite(vertex_mass[v]))) {
            rk_fem_free(f);
            return rk_fail(err, "point model: vertex %d has mass %g", v, vertex_mass[v]);
        }
        f->vertex_mass[v] += vertex_mass[v];
        f->point_mass[v] = vertex_mass[v];
    }
    return 0;
}

void rk_fem_free(rk_fem *f)
{
    free(f->Dm_inv);
    free(f->vol);
    free(f->model);
    free(f->mu);
    free(f->lambda);
    free(f->density);
    free(f->vertex_mass);
    free(f->point_mass);
    free(f->pattern.colptr);
    free(f->pattern.rowind);
    free(f->pattern.val);
    free(f->slot);
    memset(f, 0, sizeof *f);
}
