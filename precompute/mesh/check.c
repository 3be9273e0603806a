/* rk_mesh_check: validates and repairs a tet mesh in place (see mesh.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh_impl.h"

static int check_indices(const rk_mesh *m, const char *what, rk_error *err)
{
    for (int t = 0; t < m->nt; t++) {
        const int *v = m->tets + 4 * (size_t)t;
        for (int k = 0; k < 4; k++) {
            if (v[k] < 0 || v[k] >= m->nv)
                return rk_fail(err, "%s: tet %d references vertex %d, but there are %d vertices", what, t, v[k], m->nv);
            for (int j = 0; j < k; j++)
                if (v[j] == v[k])
                    return rk_fail(err, "%s: tet %d (vertices %d %d %d %d) uses vertex %d twice: it is not a "
                                        "tetrahedron",
                                   what, t, v[0], v[1], v[2], v[3], v[k]);
        }
    }
    return 0;
}

static int check_finite(const rk_mesh *m, const char *what, rk_error *err)
{
    for (int i = 0; i < m->nv; i++) {
        const double *p = m->X + 3 * (size_t)i;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return rk_fail(err, "%s: vertex %d has a non-finite coordinate (%g, %g, %g)", what, i, p[0], p[1], p[2]);
    }
    return 0;
}

/* Bounding box of the vertices used by some tet. */
static void bounding_box(const rk_mesh *m, rk_mesh_report *rep)
{
    for (int k = 0; k < 3; k++) {
        rep->bbox_min[k] = HUGE_VAL;
        rep->bbox_max[k] = -HUGE_VAL;
    }
    for (size_t i = 0; i < 4 * (size_t)m->nt; i++) {
        const double *p = m->X + 3 * (size_t)m->tets[i];
        for (int k = 0; k < 3; k++) {
            rep->bbox_min[k] = fmin(rep->bbox_min[k], p[k]);
            rep->bbox_max[k] = fmax(rep->bbox_max[k], p[k]);
        }
    }
}

/* The sliver volume of the mesh, RK_MESH_SLIVER * diagonal^3 (sliver.c), once the box is known. */
static int sliver_volume(const char *what, rk_mesh_report *rep, rk_error *err)
{
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = rep->bbox_max[k] - rep->bbox_min[k];
    double diag = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    rep->sliver_volume = RK_MESH_SLIVER * diag * diag * diag;
    if (!isfinite(rep->sliver_volume))
        return rk_fail(err, "%s: coordinates too large (bounding-box diagonal %g): volumes would overflow", what, diag);
    return 0;
}

/* Flips inverted tets (a flat one whose rounding made it negative too: its sign means nothing,
 * but then every tet leaves the check with volume >= 0). */
static void orient(rk_mesh *m, rk_mesh_report *rep)
{
    for (int t = 0; t < m->nt; t++) {
        int *v = m->tets + 4 * (size_t)t;
        double vol = rk_tet_signed_volume(m->X + 3 * (size_t)v[0], m->X + 3 * (size_t)v[1], m->X + 3 * (size_t)v[2],
                                          m->X + 3 * (size_t)v[3]);
        if (vol < 0) {
            int swap = v[2];
            v[2] = v[3];
            v[3] = swap;
            rep->reoriented++;
        }
    }
}

static int remove_unused(rk_mesh *m, rk_mesh_report *rep, rk_error *err)
{
    int *remap = rk_calloc((size_t)m->nv, sizeof *remap, err);
    if (!remap) return -1;
    for (size_t i = 0; i < 4 * (size_t)m->nt; i++) remap[m->tets[i]] = 1;
    int kept = 0;
    for (int i = 0; i < m->nv; i++) {
        if (!remap[i]) {
            remap[i] = -1;
            continue;
        }
        if (kept != i) memcpy(m->X + 3 * (size_t)kept, m->X + 3 * (size_t)i, 3 * sizeof *m->X);
        remap[i] = kept++;
    }
    for (size_t i = 0; i < 4 * (size_t)m->nt; i++) m->tets[i] = remap[m->tets[i]];
    /* A ghost's vertices are all used by tets (sliver.c makes none of a vertex of its own). */
    for (size_t i = 0; i < 4 * (size_t)m->nghost; i++) m->ghost[i] = remap[m->ghost[i]];
    rep->unused_removed = m->nv - kept - rep->orphans_removed; /* those were used, by dropped tets */
    m->nv = kept;
    free(remap);
    return 0;
}

static int find_root(int *parent, int i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

/* Tets sharing a vertex are connected: union-find over vertices. */
static int count_components(const rk_mesh *m, rk_mesh_report *rep, rk_error *err)
{
    int *parent = rk_calloc((size_t)m->nv, sizeof *parent, err);
    if (!parent) return -1;
    for (int i = 0; i < m->nv; i++) parent[i] = i;
    for (int t = 0; t < m->nt; t++) {
        const int *v = m->tets + 4 * (size_t)t;
        int r0 = find_root(parent, v[0]);
        for (int k = 1; k < 4; k++) {
            int rk = find_root(parent, v[k]);
            if (rk != r0) parent[rk] = r0;
        }
    }
    rep->components = 0;
    for (int i = 0; i < m->nv; i++) rep->components += parent[i] == i;
    free(parent);
    return 0;
}

/* Volume range and radius ratios of the tets kept. */
static void measure(const rk_mesh *m, rk_mesh_report *rep)
{
    double sum = 0;
    rep->min_quality = 1;
    rep->min_volume = HUGE_VAL;
    rep->max_volume = 0;
    for (int t = 0; t < m->nt; t++) {
        const int *v = m->tets + 4 * (size_t)t;
        const double *a = m->X + 3 * (size_t)v[0], *b = m->X + 3 * (size_t)v[1], *c = m->X + 3 * (size_t)v[2],
                     *d = m->X + 3 * (size_t)v[3];
        double q = rk_tet_radius_ratio(a, b, c, d), vol = rk_tet_signed_volume(a, b, c, d);
        rep->min_quality = fmin(rep->min_quality, q);
        rep->min_volume = fmin(rep->min_volume, vol);
        rep->max_volume = fmax(rep->max_volume, vol);
        sum += q;
    }
    rep->mean_quality = sum / m->nt;
}

int rk_mesh_check(rk_mesh *m, const char *what, rk_mesh_flat_policy flat, rk_mesh_report *rep, rk_error *err)
{
    rk_mesh_report local;
    if (!rep) rep = &local;
    memset(rep, 0, sizeof *rep);
    if (m->nv < 0 || m->nt < 0 || m->nv > RK_MESH_MAX_COUNT || m->nt > RK_MESH_MAX_COUNT)
        return rk_fail(err, "%s: bad counts (%d vertices, %d tets)", what, m->nv, m->nt);
    if (m->nt == 0 || !m->tets) return rk_fail(err, "%s: no tetrahedra", what);
    if (m->nv == 0 || !m->X) return rk_fail(err, "%s: no vertices", what);
    if (check_indices(m, what, err) || check_finite(m, what, err)) return -1;
    bounding_box(m, rep);
    if (sliver_volume(what, rep, err)) return -1;
    orient(m, rep);
    if (rk_mesh_slivers(m, what, flat, rep, err)) return -1;
    if (rep->flat_dropped) bounding_box(m, rep); /* of what is left */
    if (remove_unused(m, rep, err) || count_components(m, rep, err)) return -1;
    measure(m, rep);
    return 0;
}
