/* rk_asset_bake: the reduced model's chunks (asset.h, formats/ROMBIN.md "Model chunks"). */
#include "asset/asset.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    int nv, count, shown;
    int *stored;         /* nv: stored index of a source vertex, or -1 */
    int *source;         /* count: source vertex of a stored one */
    unsigned char *need; /* nv: 1 shown, 2 needed otherwise */
    int *tris, nf;       /* boundary triangles (source numbers) */
    int *group_first, *group_count, *group_verts, group_total;
} bake_state;

static void state_free(bake_state *s)
{
    free(s->stored);
    free(s->source);
    free(s->need);
    free(s->tris);
    free(s->group_first);
    free(s->group_count);
    free(s->group_verts);
}

/* Which source vertices the asset stores, and in which order. */
static int select_vertices(const rk_scene_sim *sim, const rk_scene_rom *R, const rk_asset_options *o, bake_state *s,
                           rk_error *err)
{
    const rk_fem *fem = &sim->fem;
    const rk_rom_model *m = &R->model;
    int nv = fem->nv;
    s->nv = nv;
    s->need = rk_calloc((size_t)nv, 1, err);
    s->stored = rk_calloc((size_t)nv, sizeof(int), err);
    s->source = rk_calloc((size_t)nv, sizeof(int), err);
    s->group_first = rk_calloc((size_t)o->ngroups + 1, sizeof(int), err);
    s->group_count = rk_calloc((size_t)o->ngroups + 1, sizeof(int), err);
    s->group_verts = rk_calloc((size_t)nv * (o->ngroups > 0 ? o->ngroups : 1), sizeof(int), err);
    if (!s->need || !s->stored || !s->source || !s->group_first || !s->group_count || !s->group_verts) return -1;
    if (rk_mesh_boundary(&sim->mesh, &s->tris, &s->nf, err)) return -1;
    if (o->show == RK_SHOW_ALL)
        memset(s->need, 1, (size_t)nv);
    else if (o->show == RK_SHOW_SURFACE)
        for (int k = 0; k < 3 * s->nf; k++) s->need[s->tris[k]] = 1;
    for (int i = 0; i < m->quad.count; i++)
        for (int k = 0; k < 4; k++) {
            int v = fem->tets[4 * m->quad.source[i] + k];
            if (!s->need[v]) s->need[v] = 2;
        }
    for (int c = 0; c < m->ncontacts; c++)
        if (!s->need[m->contact_vertex[c]]) s->need[m->contact_vertex[c]] = 2;
    double slack = 1e-9 * rk_points_diagonal(fem->X, nv); /* as the scene's own boxes */
    for (int g = 0; g < o->ngroups; g++) {
        s->group_first[g] = s->group_total;
        for (int v = 0; v < nv; v++)
            if (rk_box_contains(&o->groups[g].box, &fem->X[3 * v], slack)) {
                s->group_verts[s->group_total++] = v;
                if (!s->need[v]) s->need[v] = 2;
            }
        s->group_count[g] = s->group_total - s->group_first[g];
        if (s->group_count[g] == 0)
            return rk_fail(err, "asset group \"%s\": its box holds no vertex", o->groups[g].name);
    }
    for (int pass = 1; pass <= 2; pass++)
        for (int v = 0; v < nv; v++)
            if (s->need[v] == pass) {
                s->stored[v] = s->count;
                s->source[s->count++] = v;
            }
    for (int v = 0; v < nv; v++)
        if (!s->need[v]) s->stored[v] = -1;
    for (int v = 0; v < nv; v++) s->shown += s->need[v] == 1;
    return 0;
}

static int add_u32s(rombin_writer *w, const char *id, int critical, const int *v, size_t n, rk_error *err)
{
    uint32_t *u = rk_calloc(n ? n : 1, sizeof(uint32_t), err);
    if (!u) return -1;
    for (size_t i = 0; i < n; i++) u[i] = (uint32_t)v[i];
    int rc = rombin_add_u32(w, id, critical, u, n, err);
    free(u);
    return rc;
}

static int add_geometry(const rk_scene_sim *sim, const rk_scene_rom *R, const bake_state *s, rombin_writer *w,
                        rk_error *err)
{
    int r = R->model.r, ndof = 3 * s->nv;
    double *X = rk_calloc((size_t)3 * s->count, sizeof(double), err);
    double *rows = rk_calloc((size_t)3 * s->count * r, sizeof(double), err);
    int rc = -1;
    if (X && rows) {
        for (int i = 0; i < s->count; i++)
            for (int a = 0; a < 3; a++) {
                int src = 3 * s->source[i] + a;
                X[3 * i + a] = sim->fem.X[src];
                for (int j = 0; j < r; j++) rows[(size_t)(3 * i + a) * r + j] = R->basis.U[(size_t)ndof * j + src];
            }
        rc = rombin_add_reals(w, ROMBIN_VERT, 1, X, (size_t)3 * s->count, err) ||
             rombin_add_reals(w, ROMBIN_ROWS, 1, rows, (size_t)3 * s->count * r, err) ||
             add_u32s(w, ROMBIN_VMAP, 0, s->source, (size_t)s->count, err);
    }
    free(X);
    free(rows);
    return rc ? -1 : 0;
}

static int add_operators(const rk_rom_model *m, rombin_writer *w, rk_error *err)
{
    size_t rr = (size_t)m->r * m->r;
    if (rombin_add_reals(w, ROMBIN_MASS, 1, m->M, rr, err) || rombin_add_reals(w, ROMBIN_LOAD, 1, m->f, (size_t)m->r, err))
        return -1;
    if (m->C && rombin_add_reals(w, ROMBIN_DAMP, 1, m->C, rr, err)) return -1;
    if (m->pinned_vertices == 0) return 0; /* the basis holds every prescribed vertex: no penalty */
    size_t per = ROMBIN_PIN_PARAMS + 12 * (size_t)m->r;
    double *pins = rk_calloc(per * m->npins, sizeof(double), err);
    if (!pins) return -1;
    for (int g = 0; g < m->npins; g++) {
        const rk_prescribed *p = &m->pins[g].motion;
        double *o = pins + per * g;
        o[0] = p->kind;
        memcpy(o + 1, p->axis, sizeof p->axis);
        memcpy(o + 4, p->center, sizeof p->center);
        o[7] = p->rate;
        memcpy(o + 8, p->velocity, sizeof p->velocity);
        memcpy(o + ROMBIN_PIN_PARAMS, m->pins[g].T, sizeof(double) * 12 * m->r);
    }
    int rc = rombin_add_reals(w, ROMBIN_PENA, 1, m->A, rr, err) || rombin_add_reals(w, ROMBIN_PINS, 1, pins, per * m->npins, err);
    free(pins);
    return rc ? -1 : 0;
}

static int add_elements(const rk_fem *fem, const rk_quadrature *Q, const bake_state *s, rombin_writer *w, rk_error *err)
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
        rc = add_u32s(w, ROMBIN_ELEM, 1, elem, (size_t)5 * Q->count, err) ||
             rombin_add_reals(w, ROMBIN_ELMR, 1, real, (size_t)12 * Q->count, err);
    }
    free(elem);
    free(real);
    return rc ? -1 : 0;
}

static int add_contacts(const rk_rom_model *m, const rk_obstacles *ob, const bake_state *s, rombin_writer *w,
                        rk_error *err)
{
    if (ob->count == 0) return 0;
    double planes[6 * 16];
    if (ob->count > 16) return rk_fail(err, "asset: at most 16 planes, the scene has %d", ob->count);
    for (int k = 0; k < ob->count; k++) {
        const rk_plane *p = &ob->planes[k];
        double len = sqrt(p->normal[0] * p->normal[0] + p->normal[1] * p->normal[1] + p->normal[2] * p->normal[2]);
        for (int i = 0; i < 3; i++) {
            planes[6 * k + i] = p->point[i];
            planes[6 * k + 3 + i] = p->normal[i] / len;
        }
    }
    int *pairs = rk_calloc((size_t)2 * m->ncontacts + 1, sizeof(int), err);
    if (!pairs) return -1;
    for (int c = 0; c < m->ncontacts; c++) {
        pairs[2 * c] = s->stored[m->contact_vertex[c]];
        pairs[2 * c + 1] = m->contact_plane[c];
    }
    int rc = rombin_add_reals(w, ROMBIN_PLAN, 1, planes, (size_t)6 * ob->count, err) ||
             add_u32s(w, ROMBIN_CONT, 1, pairs, (size_t)2 * m->ncontacts, err) ||
             rombin_add_reals(w, ROMBIN_CMAS, 1, m->contact_mass, (size_t)m->ncontacts, err);
    free(pairs);
    return rc ? -1 : 0;
}

static int add_groups_and_surface(const rk_asset_options *o, bake_state *s, rombin_writer *w, rk_error *err)
{
    if (o->ngroups > 0) {
        int *table = rk_calloc((size_t)2 * o->ngroups, sizeof(int), err);
        char *names = rk_calloc((size_t)ROMBIN_GROUP_NAME_BYTES * o->ngroups, 1, err);
        if (!table || !names) {
            free(table);
            free(names);
            return -1;
        }
        for (int g = 0; g < o->ngroups; g++) {
            table[2 * g] = s->group_first[g];
            table[2 * g + 1] = s->group_count[g];
            memcpy(names + ROMBIN_GROUP_NAME_BYTES * g, o->groups[g].name, strlen(o->groups[g].name));
        }
        for (int k = 0; k < s->group_total; k++) s->group_verts[k] = s->stored[s->group_verts[k]];
        int rc = add_u32s(w, ROMBIN_GRPS, 0, table, (size_t)2 * o->ngroups, err) ||
                 add_u32s(w, ROMBIN_GVTX, 0, s->group_verts, (size_t)s->group_total, err) ||
                 rombin_add_bytes(w, ROMBIN_GNAM, 0, names, (size_t)ROMBIN_GROUP_NAME_BYTES * o->ngroups, err);
        free(table);
        free(names);
        if (rc) return -1;
    }
    if (o->show == RK_SHOW_NONE || s->nf == 0) return 0;
    for (int k = 0; k < 3 * s->nf; k++) s->tris[k] = s->stored[s->tris[k]];
    return add_u32s(w, ROMBIN_SURF, 0, s->tris, (size_t)3 * s->nf, err);
}

int rk_asset_bake(const rk_scene_sim *sim, const rk_scene_rom *R, const rk_asset_options *o, const char *info,
                  rombin_writer *w, rk_asset_summary *summary, rk_error *err)
{
    const rk_rom_model *m = &R->model;
    if (m->is_static)
        return rk_fail(err, "asset: the runtime steps dynamic models, and this scene asks for a static solve (time.static)");
    bake_state s;
    memset(&s, 0, sizeof s);
    int rc = select_vertices(sim, R, o, &s, err);
    if (!rc) {
        uint32_t head[ROMBIN_HEAD_COUNT] = {0};
        head[ROMBIN_HEAD_R] = (uint32_t)m->r;
        head[ROMBIN_HEAD_VERTICES] = (uint32_t)s.count;
        head[ROMBIN_HEAD_SHOWN] = (uint32_t)s.shown;
        head[ROMBIN_HEAD_ELEMENTS] = (uint32_t)m->quad.count;
        head[ROMBIN_HEAD_PINS] = (uint32_t)(m->pinned_vertices ? m->npins : 0);
        head[ROMBIN_HEAD_PLANES] = (uint32_t)sim->options.obstacles.count;
        head[ROMBIN_HEAD_CONTACTS] = (uint32_t)m->ncontacts;
        head[ROMBIN_HEAD_GROUPS] = (uint32_t)o->ngroups;
        head[ROMBIN_HEAD_INTEGRATOR] = (uint32_t)m->integrator;
        head[ROMBIN_HEAD_NEWTON_MAX_ITER] = (uint32_t)m->newton_max_iter;
        head[ROMBIN_HEAD_SOURCE_VERTICES] = (uint32_t)sim->fem.nv;
        head[ROMBIN_HEAD_SOURCE_TETS] = (uint32_t)sim->fem.nt;
        double parm[ROMBIN_PARM_COUNT] = {0};
        parm[ROMBIN_PARM_H] = m->h;
        parm[ROMBIN_PARM_NEWTON_TOL] = m->newton_tol;
        parm[ROMBIN_PARM_MASS] = m->mass;
        parm[ROMBIN_PARM_DHAT] = m->dhat;
        parm[ROMBIN_PARM_KAPPA] = m->kappa;
        rc = rombin_add_u32(w, ROMBIN_HEAD, 1, head, ROMBIN_HEAD_COUNT, err) ||
             rombin_add_reals(w, ROMBIN_PARM, 1, parm, ROMBIN_PARM_COUNT, err) ||
             add_geometry(sim, R, &s, w, err) || add_operators(m, w, err) ||
             add_elements(&sim->fem, &m->quad, &s, w, err) || add_contacts(m, &sim->options.obstacles, &s, w, err) ||
             add_groups_and_surface(o, &s, w, err) ||
             (info && rombin_add_bytes(w, ROMBIN_INFO, 0, info, strlen(info), err));
    }
    if (!rc && summary) {
        summary->vertices = s.count;
        summary->shown = s.shown;
        summary->elements = m->quad.count;
        summary->contacts = m->ncontacts;
        summary->groups = o->ngroups;
        summary->triangles = o->show == RK_SHOW_NONE ? 0 : s.nf;
    }
    state_free(&s);
    return rc ? (rk_error_prefix(err, "asset"), -1) : 0;
}
