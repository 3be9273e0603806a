/* rk_asset_bake_koopman: a Koopman operator's chunks (asset.h, formats/ROMBIN.md). The operator is
 * stored in its real eigen-coordinates, so that the runtime steps it block by block. */
#include "asset/bake_impl.h"

#include <cblas.h>
#include <stdlib.h>
#include <string.h>

/* KOUT and KIMP of the stored vertices from the real form's out (n x r) and in (r x n). */
static int add_rows(const rk_koopman *k, const rk_koopman_geometry *g, const rk_bake_state *s, const double *out,
                    const double *in, rombin_writer *w, rk_error *err)
{
    int r = k->r, n = 3 * g->nv;
    double *rows = rk_calloc((size_t)3 * s->count * r, sizeof(double), err);
    double *imp = rk_calloc((size_t)3 * s->count * r, sizeof(double), err);
    int rc = -1;
    if (rows && imp) {
        for (int i = 0; i < s->count; i++) {
            int v = s->source[i];
            if (!(g->vertex_mass[v] > 0)) {
                rk_fail(err, "vertex %d has mass %g; a force needs a positive mass to push it", v, g->vertex_mass[v]);
                goto done;
            }
            for (int a = 0; a < 3; a++) {
                int src = 3 * v + a;
                for (int j = 0; j < r; j++) {
                    rows[(size_t)(3 * i + a) * r + j] = out[(size_t)n * j + src];
                    imp[(size_t)(3 * i + a) * r + j] = in[(size_t)r * src + j] / g->vertex_mass[v];
                }
            }
        }
        rc = rombin_add_reals(w, ROMBIN_KOUT, 1, rows, (size_t)3 * s->count * r, err) ||
             rombin_add_reals(w, ROMBIN_KIMP, 1, imp, (size_t)3 * s->count * r, err);
    }
done:
    free(rows);
    free(imp);
    return rc ? -1 : 0;
}

/* KEIG, KACC and KINI. */
static int add_dynamics(const rk_koopman *k, const rk_koopman_geometry *g, const double *in, const double *y0,
                        rombin_writer *w, rk_error *err)
{
    int r = k->r, n = 3 * g->nv;
    double *eig = rk_calloc((size_t)2 * r, sizeof(double), err), *acc = rk_calloc((size_t)r, sizeof(double), err);
    int rc = -1;
    if (eig && acc) {
        for (int j = 0; j < r; j++) {
            eig[2 * j] = k->lambda_re[j];
            eig[2 * j + 1] = k->lambda_im[j];
        }
        if (g->accel) cblas_dgemv(CblasColMajor, CblasNoTrans, r, n, 1.0, in, r, g->accel, 1, 0.0, acc, 1);
        rc = rombin_add_reals(w, ROMBIN_KEIG, 1, eig, (size_t)2 * r, err) ||
             rombin_add_reals(w, ROMBIN_KACC, 1, acc, (size_t)r, err) ||
             rombin_add_reals(w, ROMBIN_KINI, 1, y0, (size_t)r, err);
    }
    free(eig);
    free(acc);
    return rc ? -1 : 0;
}

int rk_bake_koopman_chunks(const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *o,
                           const rk_bake_state *s, rombin_writer *w, rk_error *err)
{
    int n = 3 * g->nv, r = k->r, rc = -1;
    double *out = NULL, *in = NULL, *y0 = NULL;
    if (k->n != n)
        return rk_fail(err, "the operator has %d values per frame, the geometry %d vertices (%d values)", k->n, g->nv, n);
    out = rk_calloc((size_t)n * r, sizeof(double), err);
    in = rk_calloc((size_t)n * r, sizeof(double), err);
    y0 = rk_calloc((size_t)r, sizeof(double), err);
    if (out && in && y0 && !rk_koopman_real_form(k, out, in, g->u0, g->u_prev, y0, err)) {
        uint32_t head[ROMBIN_KHED_COUNT] = {0};
        head[ROMBIN_KHED_R] = (uint32_t)r;
        head[ROMBIN_KHED_VERTICES] = (uint32_t)s->count;
        head[ROMBIN_KHED_SHOWN] = (uint32_t)s->shown;
        head[ROMBIN_KHED_GROUPS] = (uint32_t)o->ngroups;
        head[ROMBIN_KHED_SOURCE_VERTICES] = (uint32_t)g->nv;
        head[ROMBIN_KHED_SOURCE_TETS] = (uint32_t)g->source_tets;
        head[ROMBIN_KHED_TRAJECTORIES] = (uint32_t)g->trajectories;
        double parm[ROMBIN_KPRM_COUNT] = {0};
        parm[ROMBIN_KPRM_H] = k->h;
        rc = rombin_add_u32(w, ROMBIN_KHED, 1, head, ROMBIN_KHED_COUNT, err) ||
             rombin_add_reals(w, ROMBIN_KPRM, 1, parm, ROMBIN_KPRM_COUNT, err) || add_dynamics(k, g, in, y0, w, err) ||
             add_rows(k, g, s, out, in, w, err);
    }
    free(out);
    free(in);
    free(y0);
    return rc ? -1 : 0;
}

int rk_asset_bake_koopman(const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *o,
                          const char *info, rombin_writer *w, rk_asset_summary *summary, rk_error *err)
{
    rk_bake_state s;
    memset(&s, 0, sizeof s);
    s.nf = g->tris ? g->ntris : 0;
    s.tris = rk_calloc((size_t)3 * s.nf + 1, sizeof(int), err); /* the state owns (and renumbers) its copy */
    if (!s.tris) return -1;
    if (s.nf) memcpy(s.tris, g->tris, sizeof(int) * 3 * (size_t)s.nf);
    int rc = rk_bake_select(g->nv, g->X, NULL, 0, o, &s, err) || rk_bake_add_vertices(g->X, &s, w, err) ||
             rk_bake_koopman_chunks(k, g, o, &s, w, err) || rk_bake_add_groups_and_surface(o, &s, w, err) ||
             (info && rombin_add_bytes(w, ROMBIN_INFO, 0, info, strlen(info), err));
    if (!rc && summary) {
        memset(summary, 0, sizeof *summary);
        summary->vertices = s.count;
        summary->shown = s.shown;
        summary->groups = o->ngroups;
        summary->triangles = o->show == RK_SHOW_NONE ? 0 : s.nf;
    }
    rk_bake_state_free(&s);
    return rc ? (rk_error_prefix(err, "Koopman asset"), -1) : 0;
}

int rk_asset_koopman_serialized(const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *o,
                                const char *info, rk_asset_summary *summary, unsigned char **data, size_t *bytes,
                                rk_error *err)
{
    rombin_writer w;
    rombin_writer_init(&w, o->real_type, o->compress);
    int rc = rk_asset_bake_koopman(k, g, o, info, &w, summary, err) || rombin_serialize(&w, data, bytes, err);
    rombin_writer_free(&w);
    return rc ? -1 : 0;
}
