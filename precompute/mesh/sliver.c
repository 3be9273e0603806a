/* Slivers and flat tets: what is one (rk_tet_is_flat, RK_MESH_SLIVER, mesh.h) and what
 * rk_mesh_check does with them (rk_mesh_slivers). The one place that policy lives. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh_impl.h"

/* Each flat tet dropped gets its own warning up to this many, then one line for the rest. */
#define WARN_EACH 10

static void sub(const double *a, const double *b, double *out)
{
    for (int k = 0; k < 3; k++) out[k] = a[k] - b[k];
}

static void cross(const double *u, const double *v, double *out)
{
    out[0] = u[1] * v[2] - u[2] * v[1];
    out[1] = u[2] * v[0] - u[0] * v[2];
    out[2] = u[0] * v[1] - u[1] * v[0];
}

static double norm(const double *u) { return sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]); }

int rk_tet_is_flat(const double *a, const double *b, const double *c, const double *d, double *thickness,
                   double *size)
{
    const double *p[4] = {a, b, c, d};
    double u[3], v[3], w[3], n[3], bc[3], bd[3];
    sub(b, a, u);
    sub(c, a, v);
    sub(d, a, w);
    sub(c, b, bc);
    sub(d, b, bd);
    /* Twice the area of each face; the largest gives the smallest height. */
    double area2 = 0;
    cross(v, w, n);
    double det = u[0] * n[0] + u[1] * n[1] + u[2] * n[2];
    area2 = fmax(area2, norm(n));
    cross(w, u, n);
    area2 = fmax(area2, norm(n));
    cross(u, v, n);
    area2 = fmax(area2, norm(n));
    cross(bc, bd, n);
    area2 = fmax(area2, norm(n));
    double h = fabs(det) / area2; /* 0/0 (collinear or coincident vertices) is NaN: flat below */
    /* The size that bounds the rounding: the longest edge (the edge vectors and the determinant
     * are computed to a few DBL_EPSILON of it) or the largest coordinate (the file rounded each
     * coordinate to DBL_EPSILON of itself, at best). */
    double s = fmax(fmax(norm(u), norm(v)), fmax(norm(w), fmax(norm(bc), norm(bd))));
    double cd[3];
    sub(d, c, cd);
    s = fmax(s, norm(cd));
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 3; k++) s = fmax(s, fabs(p[i][k]));
    if (thickness) *thickness = h;
    if (size) *size = s;
    return !(h > RK_MESH_FLAT * s);
}

/* use[i]: 1 when a kept tet uses vertex i, 2 when only flat ones do (it goes with them), 0 when no
 * tet does. The vertices only flat tets use are counted and named in a warning. */
static void orphans(const rk_mesh *m, const char *flat, unsigned char *use, const char *what, rk_mesh_report *rep)
{
    for (int t = 0; t < m->nt; t++)
        for (int k = 0; k < 4; k++) use[m->tets[4 * (size_t)t + k]] |= flat[t] ? 2 : 1;
    char list[256] = "";
    size_t len = 0;
    for (int i = 0; i < m->nv; i++) {
        if (use[i] != 2) continue;
        if (rep->orphans_removed++ < 8 && len < sizeof list - 16)
            len += (size_t)snprintf(list + len, sizeof list - len, " %d", i);
    }
    if (rep->orphans_removed == 1)
        rk_warn("%s: vertex%s used only by dropped flat tets: removed with them", what, list);
    else if (rep->orphans_removed > 1)
        rk_warn("%s: %d vertices (%s%s) used only by dropped flat tets: removed with them", what, rep->orphans_removed,
                list + 1, rep->orphans_removed > 8 ? " ..." : "");
}

static int find_root(int *parent, int i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

/* Which flat tets become ghosts (flat[t] = 2): those of a group of flat tets (joined by shared
 * faces) that has no boundary face and no vertex of its own. Dropping such a group outright would
 * leave a closed zero-width pocket in the boundary (its faces, now unmatched, on both sides of a
 * flat region); a group on the boundary leaves faces that lie where its boundary faces lay. */
static int find_ghosts(const rk_mesh *m, char *flat, const unsigned char *use, rk_error *err)
{
    size_t nt = (size_t)m->nt;
    int *partner = rk_calloc(4 * nt, sizeof *partner, err), *parent = rk_calloc(nt, sizeof *parent, err);
    char *open = rk_calloc(nt, 1, err);
    int rc = !partner || !parent || !open ? -1 : rk_mesh_face_partners(m, partner, err);
    for (size_t t = 0; rc == 0 && t < nt; t++) parent[t] = (int)t;
    for (size_t t = 0; rc == 0 && t < nt; t++)
        for (int l = 0; flat[t] && l < 4; l++) {
            int p = partner[4 * t + l];
            if (p >= 0 && flat[p]) parent[find_root(parent, (int)t)] = find_root(parent, p);
        }
    for (size_t t = 0; rc == 0 && t < nt; t++)
        for (int l = 0; flat[t] && l < 4; l++) {
            int r = find_root(parent, (int)t);
            open[r] |= partner[4 * t + l] < 0 || use[m->tets[4 * t + (size_t)l]] == 2;
        }
    for (size_t t = 0; rc == 0 && t < nt; t++)
        if (flat[t] && !open[find_root(parent, (int)t)]) flat[t] = 2;
    free(partner);
    free(parent);
    free(open);
    return rc;
}

/* Moves the flat tets out of the tets (and their tags), keeping the order of the rest; those marked
 * 2 are appended to the ghosts. */
static int compact(rk_mesh *m, const char *flat, int nghost, rk_error *err)
{
    if (nghost > 0) {
        int *g = realloc(m->ghost, sizeof(int) * 4 * (size_t)(m->nghost + nghost));
        if (!g) return rk_fail(err, "out of memory keeping %d ghost tets", nghost);
        m->ghost = g;
    }
    int kept = 0;
    for (int t = 0; t < m->nt; t++) {
        if (flat[t] == 2) memcpy(m->ghost + 4 * (size_t)m->nghost++, m->tets + 4 * (size_t)t, 4 * sizeof *m->tets);
        if (flat[t]) continue;
        if (kept != t) {
            memcpy(m->tets + 4 * (size_t)kept, m->tets + 4 * (size_t)t, 4 * sizeof *m->tets);
            if (m->tet_tag) m->tet_tag[kept] = m->tet_tag[t];
        }
        kept++;
    }
    m->nt = kept;
    return 0;
}

/* Flat tets as RK_MESH_DROP_FLAT says: which are ghosts, the warnings, the vertices they take along. */
static int drop_flat(rk_mesh *m, const char *what, char *flat, rk_mesh_report *rep, rk_error *err)
{
    if (rep->flat == m->nt) return rk_fail(err, "%s: all %d tets are flat: nothing is left to simulate", what, m->nt);
    unsigned char *use = rk_calloc((size_t)m->nv, 1, err);
    if (!use) return -1;
    int rc = 0, warned = 0;
    orphans(m, flat, use, what, rep);
    if (find_ghosts(m, flat, use, err)) rc = -1;
    for (int t = 0; rc == 0 && t < m->nt; t++) {
        if (!flat[t]) continue;
        rep->ghosts += flat[t] == 2;
        if (warned++ >= WARN_EACH) continue;
        const int *v = m->tets + 4 * (size_t)t;
        const double *a = m->X + 3 * (size_t)v[0], *b = m->X + 3 * (size_t)v[1], *c = m->X + 3 * (size_t)v[2],
                     *d = m->X + 3 * (size_t)v[3];
        double h, s;
        rk_tet_is_flat(a, b, c, d, &h, &s);
        rk_warn("%s: tet %d (vertices %d %d %d %d) is flat: volume %.3g, thickness %.3g <= %.3g x its size %.3g, "
                "so its rest shape is rounding noise: dropped from the model%s",
                what, t, v[0], v[1], v[2], v[3], rk_tet_signed_volume(a, b, c, d), h, RK_MESH_FLAT, s,
                flat[t] == 2 ? " (inside the body: its faces still close the boundary)" : "");
    }
    if (rc == 0 && rep->flat > WARN_EACH)
        rk_warn("%s: %d more flat tets dropped from the model (%d in all)", what, rep->flat - WARN_EACH, rep->flat);
    if (rc == 0) rc = compact(m, flat, rep->ghosts, err);
    if (rc == 0) rep->flat_dropped = rep->flat;
    free(use);
    return rc;
}

/* Counts and lists the slivers of an oriented mesh (rep->sliver_volume set) and, under
 * RK_MESH_DROP_FLAT, removes the flat tets with a warning for each. Vertices that only dropped
 * tets used are counted (rep->orphans_removed) and named here; rk_mesh_check's removal of unused
 * vertices then takes them out. They are dropped, not kept attached: such a vertex has no mass
 * and no stiffness left, a singular row in every system, and a flat tet contributes no volume, so
 * the body loses nothing but that vertex (typically a stray point coplanar with a boundary face). */
int rk_mesh_slivers(rk_mesh *m, const char *what, rk_mesh_flat_policy policy, rk_mesh_report *rep, rk_error *err)
{
    char *flat = rk_calloc((size_t)m->nt, 1, err);
    if (!flat) return -1;
    for (int t = 0; t < m->nt; t++) {
        const int *v = m->tets + 4 * (size_t)t;
        const double *a = m->X + 3 * (size_t)v[0], *b = m->X + 3 * (size_t)v[1], *c = m->X + 3 * (size_t)v[2],
                     *d = m->X + 3 * (size_t)v[3];
        double vol = rk_tet_signed_volume(a, b, c, d);
        flat[t] = (char)rk_tet_is_flat(a, b, c, d, NULL, NULL);
        if (!flat[t] && !(vol <= rep->sliver_volume)) continue;
        rep->flat += flat[t];
        if (rep->nlisted < RK_MESH_LISTED) {
            rk_mesh_sliver *l = &rep->listed[rep->nlisted++];
            l->tet = t;
            memcpy(l->v, v, sizeof l->v);
            l->volume = vol;
            l->flat = flat[t];
        }
        rep->slivers++;
    }
    int rc = policy == RK_MESH_DROP_FLAT && rep->flat > 0 ? drop_flat(m, what, flat, rep, err) : 0;
    free(flat);
    return rc;
}
