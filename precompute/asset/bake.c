/* rk_asset_bake: the reduced model's chunks (asset.h, formats/ROMBIN.md "Model chunks"), and a
 * Koopman operator's beside them when there is one. */
#include "asset/bake_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The collision vertices the asset keeps: the boundary, for the scene's planes and an app's colliders. */
static int collision_vertices(const rk_rom_model *m, const rk_asset_options *o)
{
    return o->colliders || m->has_contact ? m->ncv : 0;
}

/* The reduced model stores, beyond the shown vertices, those of its cubature elements and collisions.
 * X: the rest positions of the mesh's vertices, then of the embedded surface's (R->embedded). */
static int select_vertices(const rk_asset_rom *R, const double *X, const rk_asset_options *o, rk_bake_state *s,
                           rk_error *err)
{
    const rk_rom_model *m = R->model;
    const rk_embedded_surface *E = R->embedded;
    int every = R->alrom && R->alrom->crom ? R->fem->nv : 0; /* a CROM's encoder reads every vertex */
    int ncontact = collision_vertices(m, o), nelem = R->points ? 0 : m->quad.count, nextra = 4 * nelem + ncontact + every,
        k = 0;
    int *extra = rk_calloc((size_t)nextra + 1, sizeof(int), err);
    if (!extra) return -1;
    if (E) { /* the embedded surface is shown: its vertices numbered after the mesh's */
        s->nf = E->nf;
        s->tris = rk_calloc(3 * (size_t)E->nf + 1, sizeof(int), err);
        if (!s->tris) {
            free(extra);
            return -1;
        }
        for (int i = 0; i < 3 * E->nf; i++) s->tris[i] = R->fem->nv + E->tris[i];
    } else if (!R->points_shown && rk_mesh_boundary(R->mesh, &s->tris, &s->nf, err)) {
        free(extra);
        return -1;
    }
    for (int i = 0; i < nelem; i++)
        for (int c = 0; c < 4; c++) extra[k++] = R->fem->tets[4 * m->quad.source[i] + c];
    for (int c = 0; c < ncontact; c++) extra[k++] = m->cv[c];
    for (int v = 0; v < every; v++) extra[k++] = v;
    rk_asset_options shown = *o;
    if (R->points_shown) shown.show = RK_SHOW_FIRST, shown.show_first = R->points_shown;
    if (E && shown.show != RK_SHOW_NONE) shown.show = RK_SHOW_SURFACE; /* the surface, not the cage */
    int rc = rk_bake_select(R->fem->nv + (E ? E->nv : 0), X, extra, nextra, &shown, s, err);
    free(extra);
    return rc;
}

/* The basis entry at row 3v + a, column col, for source vertex v: the mesh's own row, or for an
 * embedded vertex (v >= the mesh's count) the skinning rows of the weights evaluated at it
 * (R->embedded_W: RKPM weights exist anywhere), else its barycentric combination of its tet's four
 * rows. A skinning basis's weight column (12 j + 3, row 3v) so becomes w_j at the point, exactly
 * or as the tet interpolates it. */
static double basis_at(const rk_asset_rom *R, int v, int a, int col)
{
    size_t ndof = 3 * (size_t)R->fem->nv;
    if (v < R->fem->nv) return R->U[ndof * col + 3 * (size_t)v + a];
    const rk_embedded_surface *E = R->embedded;
    int i = v - R->fem->nv;
    if (R->embedded_W) { /* skinning weights evaluated at the point: its rows w_j(X) X̄_c */
        int j = col / 12, a_col = col % 12 / 4, c = col % 4;
        double w = R->embedded_W[(size_t)E->nv * j + i];
        return a_col != a ? 0 : c == 3 ? w : w * E->X[3 * (size_t)i + c];
    }
    const int *t = R->fem->tets + 4 * (size_t)E->tet[i];
    double sum = 0;
    for (int k = 0; k < 4; k++) sum += E->bary[4 * (size_t)i + k] * R->U[ndof * col + 3 * (size_t)t[k] + a];
    return sum;
}

/* A basis the bake may store as skinning weights (ROMBIN.md, SKIN and WGHT): its handle count when
 * the basis says it is linear blend skinning and every stored row of the mesh is, to the bit
 * (column 12 j + 4 a + c of row 3v + a is w_j(v) X̄_c, the weight being the entry at c = 3, every
 * other entry 0); 0 otherwise (the rows are stored as they are). An embedded vertex stores the
 * weights at its point, which the runtime turns into the skinning rows there. */
static int skinning_handles(const rk_asset_rom *R, const rk_bake_state *s)
{
    int r = R->model->r, H = R->skin_handles;
    size_t ndof = 3 * (size_t)R->fem->nv;
    if (H <= 0 || r != 12 * H) return 0;
    for (int i = 0; i < s->count; i++) {
        int v = s->source[i];
        if (v >= R->fem->nv) continue; /* embedded: weights at the point (basis_at) */
        const double *X = R->fem->X + 3 * (size_t)v;
        for (int a = 0; a < 3; a++)
            for (int col = 0; col < r; col++) {
                int j = col / 12, a_col = col % 12 / 4, c = col % 4;
                double u = R->U[ndof * col + 3 * v + a];
                double wj = R->U[ndof * (12 * j + 4 * a + 3) + 3 * v + a];
                double want = a_col != a ? 0 : c == 3 ? wj : wj * X[c];
                if (u != want) return 0;
            }
    }
    return H;
}

/* VERT, then the basis: a skinning basis as its weights (SKIN, WGHT: H reals a vertex instead of
 * 36 H, the runtime rebuilds the rows), any other as its rows (ROWS). X as select_vertices'. */
static int add_geometry(const rk_asset_rom *R, const double *X, const rk_bake_state *s, rombin_writer *w, rk_error *err)
{
    int r = R->model->r, H = skinning_handles(R, s);
    size_t count = H ? (size_t)s->count * H : (size_t)3 * s->count * r;
    double *vals = rk_calloc(count, sizeof(double), err);
    if (!vals) return -1;
    for (int i = 0; i < s->count; i++) {
        if (H) {
            for (int j = 0; j < H; j++) vals[(size_t)i * H + j] = basis_at(R, s->source[i], 0, 12 * j + 3);
            continue;
        }
        for (int a = 0; a < 3; a++)
            for (int j = 0; j < r; j++) vals[(size_t)(3 * i + a) * r + j] = basis_at(R, s->source[i], a, j);
    }
    int rc = rk_bake_add_vertices(X, s, w, err) ||
             (H ? rk_bake_add_u32s(w, ROMBIN_SKIN, 0, &H, 1, err) || rombin_add_reals(w, ROMBIN_WGHT, 1, vals, count, err)
                : rombin_add_reals(w, ROMBIN_ROWS, 1, vals, count, err));
    free(vals);
    return rc ? -1 : 0;
}

void rk_bake_motion_params(const rk_prescribed *p, double *out)
{
    memset(out, 0, sizeof(double) * ROMBIN_PIN_PARAMS);
    out[0] = p->kind;
    memcpy(out + 1, p->axis, sizeof p->axis);
    memcpy(out + 4, p->center, sizeof p->center);
    out[7] = p->rate;
    memcpy(out + 8, p->velocity, sizeof p->velocity);
}

static int add_operators(const rk_rom_model *m, const double *velocity0, int penalty, rombin_writer *w, rk_error *err)
{
    size_t rr = (size_t)m->r * m->r;
    if (rombin_add_reals(w, ROMBIN_MASS, 1, m->M, rr, err) || rombin_add_reals(w, ROMBIN_LOAD, 1, m->f, (size_t)m->r, err))
        return -1;
    if (velocity0 && rombin_add_reals(w, ROMBIN_VEL0, 1, velocity0, (size_t)m->r, err)) return -1;
    if (m->C && rombin_add_reals(w, ROMBIN_DAMP, 1, m->C, rr, err)) return -1;
    if (m->lift_handle) { /* the lifted group's motion and handle (1.11): set, not penalised */
        double lift[ROMBIN_LIFT_COUNT];
        rk_bake_motion_params(&m->lift_motion, lift);
        lift[ROMBIN_PIN_PARAMS] = 12.0 * (m->lift_handle - 1);
        if (rombin_add_reals(w, ROMBIN_LIFT, 1, lift, ROMBIN_LIFT_COUNT, err)) return -1;
    }
    if (!penalty) return 0; /* the basis holds every prescribed vertex (or the runtime moves them): no penalty */
    size_t per = ROMBIN_PIN_PARAMS + 12 * (size_t)m->r;
    double *pins = rk_calloc(per * m->npins, sizeof(double), err);
    if (!pins) return -1;
    for (int g = 0; g < m->npins; g++) {
        double *o = pins + per * g;
        rk_bake_motion_params(&m->pins[g].motion, o);
        memcpy(o + ROMBIN_PIN_PARAMS, m->pins[g].T, sizeof(double) * 12 * m->r);
    }
    int rc = rombin_add_reals(w, ROMBIN_PENA, 1, m->A, rr, err) || rombin_add_reals(w, ROMBIN_PINS, 1, pins, per * m->npins, err);
    free(pins);
    return rc ? -1 : 0;
}

static int add_elements(const rk_fem *fem, const rk_quadrature *Q, const rk_bake_state *s, rombin_writer *w, rk_error *err)
{
    int *elem = rk_calloc((size_t)5 * Q->count, sizeof(int), err);
    double *real = rk_calloc((size_t)12 * Q->count, sizeof(double), err);
    int rc = -1;
    if (elem && real) {
        for (int i = 0; i < Q->count; i++) {
            int e = Q->source[i];
            for (int k = 0; k < 4; k++) elem[5 * i + k] = s->stored[fem->tets[4 * e + k]];
            elem[5 * i + 4] = (int)Q->model[i];
            memcpy(real + 12 * i, fem->Dm_inv + 9 * (size_t)e, 9 * sizeof(double));
            real[12 * i + 9] = Q->weight[i];
            real[12 * i + 10] = Q->mu[i];
            real[12 * i + 11] = Q->lambda[i];
        }
        rc = rk_bake_add_u32s(w, ROMBIN_ELEM, 1, elem, (size_t)5 * Q->count, err) ||
             rombin_add_reals(w, ROMBIN_ELMR, 1, real, (size_t)12 * Q->count, err);
    }
    free(elem);
    free(real);
    return rc ? -1 : 0;
}

/* Mesh-free integration points (IPNT, IPMD): X, weight, mu, lambda, then (w_j, dw_j/dX) per handle. */
static int add_points(const rk_skin_points *P, const rk_quadrature *Q, rombin_writer *w, rk_error *err)
{
    int H = P->H, per = 6 + 4 * H;
    int *model = rk_calloc((size_t)Q->count + 1, sizeof(int), err);
    double *real = rk_calloc((size_t)per * Q->count + 1, sizeof(double), err);
    int rc = -1;
    if (model && real) {
        for (int i = 0; i < Q->count; i++) {
            int p = Q->source[i];
            double *o = real + (size_t)per * i;
            memcpy(o, P->X + 3 * (size_t)p, 3 * sizeof(double));
            o[3] = Q->weight[i];
            o[4] = Q->mu[i];
            o[5] = Q->lambda[i];
            for (int j = 0; j < H; j++) {
                o[6 + 4 * j] = P->W[(size_t)p + (size_t)P->n * j];
                for (int b = 0; b < 3; b++) o[7 + 4 * j + b] = P->dW[3 * (size_t)p + b + 3 * (size_t)P->n * j];
            }
            model[i] = (int)Q->model[i];
        }
        rc = rk_bake_add_u32s(w, ROMBIN_IPMD, 1, model, (size_t)Q->count, err) ||
             rombin_add_reals(w, ROMBIN_IPNT, 1, real, (size_t)per * Q->count, err);
    }
    free(model);
    free(real);
    return rc ? -1 : 0;
}

/* A point cloud's extras: the weights' gradients at its points (GRAD: an app's F at each splat)
 * and its source splat file (SPLY: every attribute, for romkit run --splats). */
static int add_cloud(const rk_asset_rom *R, const rk_bake_state *s, rombin_writer *w, rk_error *err)
{
    int n = R->points_shown, H = R->skin_handles, rc = 0;
    if (!n) return 0;
    if (R->shown_grad) {
        if (s->shown != n) return rk_fail(err, "GRAD: %d points, but %d shown vertices", n, s->shown);
        double *g = rk_calloc((size_t)3 * n * H + 1, sizeof(double), err);
        if (!g) return -1;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < H; j++)
                for (int b = 0; b < 3; b++) g[((size_t)i * H + j) * 3 + b] = R->shown_grad[3 * (size_t)i + b + 3 * (size_t)n * j];
        rc = rombin_add_reals(w, ROMBIN_GRAD, 0, g, (size_t)3 * n * H, err);
        free(g);
    }
    if (!rc && R->splat_file) {
        unsigned char *data = NULL;
        size_t bytes = 0;
        rc = rombin_read_file(R->splat_file, &data, &bytes, err) || rombin_add_bytes(w, ROMBIN_SPLY, 0, data, bytes, err);
        free(data);
    }
    return rc ? -1 : 0;
}

/* The scene's planes (PLAN) and every (boundary vertex, plane) pair (CONT): what the runtime's
 * barrier acts on. The other obstacles: bake_obstacles.c. */
static int add_contacts(const rk_rom_model *m, const rk_bake_state *s, rombin_writer *w, rk_error *err)
{
    if (!m->has_contact) return 0;
    const rk_contact *c = &m->contact;
    double planes[6 * 16];
    int np = 0;
    for (int k = 0; k < c->nobstacles; k++) {
        if (c->obstacles[k].kind != RK_OBSTACLE_PLANE) continue; /* bake_obstacles.c */
        if (c->obstacles[k].motion != RK_MOTION_FIXED)
            return rk_fail(err, "plane %d moves: the runtime's scene planes are static (an app moves its colliders)", k);
        if (np == 16) return rk_fail(err, "at most 16 planes, the scene has more");
        memcpy(planes + 6 * np, c->obstacles[k].point, 3 * sizeof(double));
        memcpy(planes + 6 * np + 3, c->obstacles[k].normal, 3 * sizeof(double));
        np++;
    }
    /* several objects, and one touching itself, collide through the collision surface
     * (bake_obstacles.c, bake_objects.c) */
    if (np == 0) return 0;
    int *pairs = rk_calloc((size_t)2 * c->nv * np + 1, sizeof(int), err);
    if (!pairs) return -1;
    for (int k = 0; k < np; k++)
        for (int i = 0; i < c->nv; i++) {
            pairs[2 * (k * c->nv + i)] = s->stored[c->vertex[i]];
            pairs[2 * (k * c->nv + i) + 1] = k;
        }
    int rc = rombin_add_reals(w, ROMBIN_PLAN, 1, planes, (size_t)6 * np, err) ||
             rk_bake_add_u32s(w, ROMBIN_CONT, 1, pairs, (size_t)2 * c->nv * np, err);
    free(pairs);
    return rc ? -1 : 0;
}

/* The collision vertices (CVTX) and the friction (FRIC) of the scene's planes and an app's colliders. */
static int add_collisions(const rk_rom_model *m, const rk_asset_options *o, const rk_bake_state *s, rombin_writer *w,
                          rk_error *err)
{
    int n = collision_vertices(m, o);
    if (n == 0) return 0;
    int *ids = rk_calloc((size_t)n, sizeof(int), err);
    if (!ids) return -1;
    for (int i = 0; i < n; i++) ids[i] = s->stored[m->cv[i]];
    int rc = rk_bake_add_u32s(w, ROMBIN_CVTX, 0, ids, (size_t)n, err);
    free(ids);
    if (rc || !(m->contact_options.friction > 0)) return rc ? -1 : 0;
    double fric[ROMBIN_FRIC_COUNT] = {0};
    fric[ROMBIN_FRIC_MU] = m->contact_options.friction;
    fric[ROMBIN_FRIC_EPS_V] = m->contact_options.eps_v;
    fric[ROMBIN_FRIC_ITERATIONS] = m->contact_options.friction_iterations;
    return rombin_add_reals(w, ROMBIN_FRIC, 0, fric, ROMBIN_FRIC_COUNT, err) ? -1 : 0;
}

/* Contact pairs the asset stores (the CONT count). */
static int contact_count(const rk_rom_model *m)
{
    int np = 0;
    for (int k = 0; m->has_contact && k < m->contact.nobstacles; k++) np += m->contact.obstacles[k].kind == RK_OBSTACLE_PLANE;
    return np * (m->has_contact ? m->contact.nv : 0);
}

/* Planes the asset stores. */
static int plane_count(const rk_rom_model *m)
{
    return m->has_contact && m->contact.nv ? contact_count(m) / m->contact.nv : 0;
}

int rk_asset_bake(const rk_asset_rom *R, const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *o,
                  const char *info, rombin_writer *w, rk_asset_summary *summary, rk_error *err)
{
    const rk_rom_model *m = R->model;
    if (m->is_static)
        return rk_fail(err, "asset: the runtime steps dynamic models, and this scene asks for a static solve (time.static)");
    if (m->quad.vol_k > m->r)
        return rk_fail(err, "asset: the projected volume keeps %d pressure functions, more than r = %d (VPRS holds at "
                       "most r)", m->quad.vol_k, m->r);
    if (m->quad.vol_k && R->alrom)
        return rk_fail(err, "asset: an adaptive linear ROM does not take a projected volume (rom.volume \"projected\")");
    rk_bake_state s;
    memset(&s, 0, sizeof s);
    const rk_embedded_surface *E = R->embedded;
    if (E && (k || R->alrom || R->points_shown))
        return rk_fail(err, "asset: an embedded surface (mesh.cage) is baked with a reduced model only, not with %s",
                       k ? "a Koopman operator" : R->alrom ? "an adaptive linear ROM" : "a point cloud");
    /* the rest positions of the mesh's vertices, then the embedded surface's */
    double *Xall = E ? rk_calloc(3 * ((size_t)R->fem->nv + E->nv), sizeof(double), err) : NULL;
    if (E && !Xall) return -1;
    if (E) {
        memcpy(Xall, R->fem->X, sizeof(double) * 3 * (size_t)R->fem->nv);
        memcpy(Xall + 3 * (size_t)R->fem->nv, E->X, sizeof(double) * 3 * (size_t)E->nv);
    }
    const double *X = E ? Xall : R->fem->X;
    int rc = select_vertices(R, X, o, &s, err);
    if (!rc && R->points && (R->points->H != R->skin_handles || !skinning_handles(R, &s)))
        rc = rk_fail(err, "mesh-free integration points need a linear-blend-skinning basis over %d handles",
                     R->points->H);
    if (!rc) {
        uint32_t head[ROMBIN_HEAD_COUNT] = {0};
        head[ROMBIN_HEAD_R] = (uint32_t)m->r;
        head[ROMBIN_HEAD_VERTICES] = (uint32_t)s.count;
        head[ROMBIN_HEAD_SHOWN] = (uint32_t)s.shown;
        head[ROMBIN_HEAD_ELEMENTS] = R->points ? 0 : (uint32_t)m->quad.count;
        head[ROMBIN_HEAD_POINTS] = R->points ? (uint32_t)m->quad.count : 0;
        /* an adaptive linear ROM moves its prescribed vertices itself (AMOT), with no penalty */
        int pins = m->pinned_vertices && !R->alrom;
        head[ROMBIN_HEAD_PINS] = (uint32_t)(pins ? m->npins : 0);
        head[ROMBIN_HEAD_PLANES] = (uint32_t)plane_count(m);
        head[ROMBIN_HEAD_CONTACTS] = (uint32_t)contact_count(m);
        head[ROMBIN_HEAD_GROUPS] = (uint32_t)o->ngroups;
        head[ROMBIN_HEAD_INTEGRATOR] = (uint32_t)m->integrator;
        head[ROMBIN_HEAD_NEWTON_MAX_ITER] = (uint32_t)m->newton_max_iter;
        head[ROMBIN_HEAD_SOURCE_VERTICES] = (uint32_t)R->fem->nv;
        head[ROMBIN_HEAD_SOURCE_TETS] = (uint32_t)R->fem->nt;
        double parm[ROMBIN_PARM_COUNT] = {0};
        parm[ROMBIN_PARM_H] = m->h;
        parm[ROMBIN_PARM_NEWTON_TOL] = m->newton_tol;
        parm[ROMBIN_PARM_MASS] = m->mass;
        int collide = collision_vertices(m, o) > 0; /* the barrier of the planes and the colliders */
        parm[ROMBIN_PARM_DHAT] = collide ? m->contact_options.dhat : 0;
        parm[ROMBIN_PARM_KAPPA] = collide ? m->contact_options.kappa : 0;
        rc = rombin_add_u32(w, ROMBIN_HEAD, 1, head, ROMBIN_HEAD_COUNT, err) ||
             rombin_add_reals(w, ROMBIN_PARM, 1, parm, ROMBIN_PARM_COUNT, err) ||
             add_geometry(R, X, &s, w, err) || add_operators(m, R->velocity0, pins, w, err) ||
             (R->points ? add_points(R->points, &m->quad, w, err) : add_elements(R->fem, &m->quad, &s, w, err)) ||
             (m->quad.vol_k && rombin_add_reals(w, ROMBIN_VPRS, 1, m->quad.vol_phi, (size_t)m->quad.count * m->quad.vol_k, err)) ||
             add_contacts(m, &s, w, err) || rk_bake_obstacles(m, R->fem, o, w, err) || add_cloud(R, &s, w, err) ||
             add_collisions(m, o, &s, w, err) || rk_bake_objects(m, collision_vertices(m, o), w, err) || (R->alrom && rk_bake_alrom_chunks(R, &s, w, err)) ||
             (k && rk_bake_koopman_chunks(k, g, o, &s, w, err)) || rk_bake_add_groups_and_surface(o, &s, w, err) ||
             (info && rombin_add_bytes(w, ROMBIN_INFO, 0, info, strlen(info), err));
    }
    if (!rc && summary) {
        summary->vertices = s.count;
        summary->shown = s.shown;
        summary->elements = m->quad.count;
        summary->contacts = contact_count(m);
        summary->groups = o->ngroups;
        summary->triangles = o->show == RK_SHOW_NONE ? 0 : s.nf;
    }
    rk_bake_state_free(&s);
    free(Xall);
    return rc ? (rk_error_prefix(err, "asset"), -1) : 0;
}
