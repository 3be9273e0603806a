/* The stored vertices of an asset and the chunks that list them (bake_impl.h). */
#include "asset/bake_impl.h"
#include "util/util.h"

#include <stdlib.h>
#include <string.h>



void rk_bake_state_free(rk_bake_state *s)
{
    free(s->stored);
    free(s->source);
    free(s->need);
    free(s->tris);
    free(s->group_first);
    free(s->group_count);
    free(s->group_verts);
}

/* Which source vertices the asset stores, and in which order: the shown ones (o->show over the
 * boundary triangles s->tris), then the `extra` ones and those of the named groups. */
int rk_bake_select(int nv, const double *X, const int *extra, int nextra, const rk_asset_options *o, rk_bake_state *s,
                   rk_error *err)
{
    s->nv = nv;
    s->need = rk_calloc((size_t)nv, 1, err);
    s->stored = rk_calloc((size_t)nv, sizeof(int), err);
    s->source = rk_calloc((size_t)nv, sizeof(int), err);
    s->group_first = rk_calloc((size_t)o->ngroups + 1, sizeof(int), err);
    s->group_count = rk_calloc((size_t)o->ngroups + 1, sizeof(int), err);
    s->group_verts = rk_calloc((size_t)nv * (o->ngroups > 0 ? o->ngroups : 1), sizeof(int), err);
    if (!s->need || !s->stored || !s->source || !s->group_first || !s->group_count || !s->group_verts) return -1;
    if (o->show == RK_SHOW_FIRST)
        memset(s->need, 1, (size_t)(o->show_first < nv ? o->show_first : nv));
    else if (o->show == RK_SHOW_ALL || (o->show == RK_SHOW_SURFACE && s->nf == 0))
        memset(s->need, 1, (size_t)nv); /* no surface known: every vertex is shown */
    else if (o->show == RK_SHOW_SURFACE)
        for (int k = 0; k < 3 * s->nf; k++) s->need[s->tris[k]] = 1;
    for (int i = 0; i < nextra; i++)
        if (!s->need[extra[i]]) s->need[extra[i]] = 2;
    double slack = 1e-9 * rk_points_diagonal(X, nv); /* as the scene's own boxes */
    for (int g = 0; g < o->ngroups; g++) {
        s->group_first[g] = s->group_total;
        for (int v = 0; v < nv; v++)
            if (rk_box_contains(&o->groups[g].box, &X[3 * v], slack)) {
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

int rk_bake_add_u32s(rombin_writer *w, const char *id, int critical, const int *v, size_t n, rk_error *err)
{
    uint32_t *u = rk_calloc(n ? n : 1, sizeof(uint32_t), err);
    if (!u) return -1;
    for (size_t i = 0; i < n; i++) u[i] = (uint32_t)v[i];
    int rc = rombin_add_u32(w, id, critical, u, n, err);
    free(u);
    return rc;
}

int rk_bake_add_groups_and_surface(const rk_asset_options *o, rk_bake_state *s, rombin_writer *w, rk_error *err)
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
        int rc = rk_bake_add_u32s(w, ROMBIN_GRPS, 0, table, (size_t)2 * o->ngroups, err) ||
                 rk_bake_add_u32s(w, ROMBIN_GVTX, 0, s->group_verts, (size_t)s->group_total, err) ||
                 rombin_add_bytes(w, ROMBIN_GNAM, 0, names, (size_t)ROMBIN_GROUP_NAME_BYTES * o->ngroups, err);
        free(table);
        free(names);
        if (rc) return -1;
    }
    if (o->show == RK_SHOW_NONE || s->nf == 0) return 0;
    for (int k = 0; k < 3 * s->nf; k++) s->tris[k] = s->stored[s->tris[k]];
    return rk_bake_add_u32s(w, ROMBIN_SURF, 0, s->tris, (size_t)3 * s->nf, err);
}


int rk_bake_add_vertices(const double *X, const rk_bake_state *s, rombin_writer *w, rk_error *err)
{
    double *P = rk_calloc((size_t)3 * s->count, sizeof(double), err);
    if (!P) return -1;
    for (int i = 0; i < s->count; i++)
        for (int a = 0; a < 3; a++) P[3 * i + a] = X[3 * s->source[i] + a];
    int rc = rombin_add_reals(w, ROMBIN_VERT, 1, P, (size_t)3 * s->count, err) ||
             rk_bake_add_u32s(w, ROMBIN_VMAP, 0, s->source, (size_t)s->count, err);
    free(P);
    return rc ? -1 : 0;
}
