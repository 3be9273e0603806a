/* The collision geometry (contact.h): the objects' boundary surface and the obstacles' vertices,
 * edges and triangles, and where the moving obstacles are at a time. */
#include "contact/pairs_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

/* IPC's kappa bounds (supplement Sec. 3.3): kappa_min makes a pair at 1e-8 of the bounding-box
 * diagonal push like 1e11 times the average vertex mass would; kappa_max = 100 kappa_min. */
#define KAPPA_MIN_SCALE 1e11
#define KAPPA_MAX_RATIO 100

void rk_contact_default_options(rk_contact_options *o)
{
    memset(o, 0, sizeof *o);
    o->eps_v = 1e-3;
    o->friction_iterations = 3;
}

static int cmp_edge(const void *a, const void *b)
{
    const int *x = a, *y = b;
    return x[0] != y[0] ? (x[0] > y[0]) - (x[0] < y[0]) : (x[1] > y[1]) - (x[1] < y[1]);
}

/* The unique edges of nf triangles (2 ne, each smaller id first). */
static int edges_of(const int *tris, int nf, int **edges, int *ne, rk_error *err)
{
    int *e = rk_calloc((size_t)6 * nf + 2, sizeof(int), err);
    if (!e) return -1;
    for (int f = 0; f < nf; f++)
        for (int k = 0; k < 3; k++) {
            int a = tris[3 * f + k], b = tris[3 * f + (k + 1) % 3];
            e[6 * f + 2 * k] = a < b ? a : b;
            e[6 * f + 2 * k + 1] = a < b ? b : a;
        }
    qsort(e, (size_t)3 * nf, 2 * sizeof(int), cmp_edge);
    int n = 0;
    for (int i = 0; i < 3 * nf; i++)
        if (n == 0 || e[2 * i] != e[2 * (n - 1)] || e[2 * i + 1] != e[2 * (n - 1) + 1]) {
            e[2 * n] = e[2 * i];
            e[2 * n + 1] = e[2 * i + 1];
            n++;
        }
    *edges = e;
    *ne = n;
    return 0;
}

static int finite_all(const double *a, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

static int check_obstacle(const rk_obstacle *o, int k, rk_error *err)
{
    double nn = o->normal[0] * o->normal[0] + o->normal[1] * o->normal[1] + o->normal[2] * o->normal[2];
    switch (o->kind) {
    case RK_OBSTACLE_PLANE:
        if (!finite_all(o->point, 3) || !(nn > 0 && isfinite(nn)))
            return rk_fail(err, "obstacle %d: a plane needs a finite point and a non-zero normal", k);
        break;
    case RK_OBSTACLE_SPHERE:
    case RK_OBSTACLE_CAPSULE:
        if (!finite_all(o->center, 3) || !(o->radius > 0 && isfinite(o->radius)) ||
            (o->kind == RK_OBSTACLE_CAPSULE && !finite_all(o->end, 3)))
            return rk_fail(err, "obstacle %d: a %s needs finite points and a positive radius, got radius %g", k,
                           o->kind == RK_OBSTACLE_SPHERE ? "sphere" : "capsule", o->radius);
        break;
    case RK_OBSTACLE_BOX:
        for (int i = 0; i < 3; i++)
            if (!(isfinite(o->min[i]) && isfinite(o->max[i]) && o->min[i] < o->max[i]))
                return rk_fail(err, "obstacle %d: a box needs finite min < max on every axis (axis %d: %g, %g)", k, i,
                               o->min[i], o->max[i]);
        break;
    case RK_OBSTACLE_MESH:
        if (o->nv < 3 || o->nf < 1 || !o->X || !o->tris)
            return rk_fail(err, "obstacle %d: a mesh needs vertices and triangles (%d, %d)", k, o->nv, o->nf);
        if (!finite_all(o->X, 3 * o->nv)) return rk_fail(err, "obstacle %d: a vertex is not finite", k);
        for (int i = 0; i < 3 * o->nf; i++)
            if (o->tris[i] < 0 || o->tris[i] >= o->nv)
                return rk_fail(err, "obstacle %d: triangle %d names vertex %d of %d", k, i / 3, o->tris[i], o->nv);
        break;
    default:
        return rk_fail(err, "obstacle %d: unknown kind %d", k, (int)o->kind);
    }
    if (o->motion == RK_MOTION_TWIST) {
        double aa = o->axis[0] * o->axis[0] + o->axis[1] * o->axis[1] + o->axis[2] * o->axis[2];
        if (!(aa > 0 && isfinite(aa) && isfinite(o->rate) && finite_all(o->motion_center, 3)))
            return rk_fail(err, "obstacle %d: a twist needs a non-zero axis, a finite rate and center", k);
    } else if (o->motion == RK_MOTION_TRANSLATE && !finite_all(o->velocity, 3)) {
        return rk_fail(err, "obstacle %d: its velocity is not finite", k);
    } else if (o->motion != RK_MOTION_FIXED && o->motion != RK_MOTION_TWIST && o->motion != RK_MOTION_TRANSLATE) {
        return rk_fail(err, "obstacle %d: unknown motion %d", k, (int)o->motion);
    }
    return 0;
}

/* The box's 8 corners (bit i of the corner index: max on axis i) and 12 outward triangles. */
static const int box_tris[36] = RK_BOX_TRIANGLES;

/* Counts (count_only) or appends obstacle o's vertices and triangles (and a capsule's segment). */
static void obstacle_geometry(rk_contact *c, const rk_obstacle *o, int count_only, int *nv, int *nf, int *nseg)
{
    int v0 = *nv;
    switch (o->kind) {
    case RK_OBSTACLE_PLANE:
        return;
    case RK_OBSTACLE_SPHERE:
        if (!count_only) memcpy(&c->oX[3 * v0], o->center, 3 * sizeof(double));
        *nv += 1;
        return;
    case RK_OBSTACLE_CAPSULE:
        if (!count_only) {
            memcpy(&c->oX[3 * v0], o->center, 3 * sizeof(double));
            memcpy(&c->oX[3 * v0 + 3], o->end, 3 * sizeof(double));
            c->oedges[2 * *nseg] = v0;
            c->oedges[2 * *nseg + 1] = v0 + 1;
        }
        *nv += 2;
        *nseg += 1;
        return;
    case RK_OBSTACLE_BOX:
        if (!count_only) {
            for (int i = 0; i < 8; i++)
                for (int a = 0; a < 3; a++) c->oX[3 * (v0 + i) + a] = (i >> a) & 1 ? o->max[a] : o->min[a];
            for (int i = 0; i < 36; i++) c->ofaces[3 * *nf + i] = v0 + box_tris[i];
        }
        *nv += 8;
        *nf += 12;
        return;
    case RK_OBSTACLE_MESH:
        if (!count_only) {
            memcpy(&c->oX[3 * v0], o->X, sizeof(double) * 3 * (size_t)o->nv);
            for (int i = 0; i < 3 * o->nf; i++) c->ofaces[3 * *nf + i] = v0 + o->tris[i];
        }
        *nv += o->nv;
        *nf += o->nf;
        return;
    }
}

int rk_contact_build_obstacles(rk_contact *c, const rk_obstacle *obstacles, int n, rk_error *err)
{
    c->nobstacles = n;
    c->obstacles = rk_calloc((size_t)n + 1, sizeof *c->obstacles, err);
    c->othick = rk_calloc((size_t)n + 1, sizeof(double), err);
    c->oplane = rk_calloc(6 * (size_t)n + 1, sizeof(double), err);
    c->oplane_to = rk_calloc(6 * (size_t)n + 1, sizeof(double), err);
    if (!c->obstacles || !c->othick || !c->oplane || !c->oplane_to) return -1;
    int nv = 0, nf = 0, nseg = 0;
    for (int k = 0; k < n; k++) {
        if (check_obstacle(&obstacles[k], k, err)) return -1;
        c->obstacles[k] = obstacles[k];
        c->obstacles[k].X = NULL; /* the geometry is copied below; the caller's arrays may go */
        c->obstacles[k].tris = NULL;
        if (obstacles[k].kind == RK_OBSTACLE_SPHERE || obstacles[k].kind == RK_OBSTACLE_CAPSULE)
            c->othick[k] = obstacles[k].radius;
        if (obstacles[k].kind == RK_OBSTACLE_PLANE) {
            double *pl = &c->obstacles[k].normal[0], len = sqrt(pl[0] * pl[0] + pl[1] * pl[1] + pl[2] * pl[2]);
            for (int i = 0; i < 3; i++) pl[i] /= len;
        }
        obstacle_geometry(c, &obstacles[k], 1, &nv, &nf, &nseg);
    }
    c->onv = nv;
    c->onf = nf;
    c->oX = rk_calloc(3 * (size_t)nv + 1, sizeof(double), err);
    c->ox = rk_calloc(3 * (size_t)nv + 1, sizeof(double), err);
    c->ox_to = rk_calloc(3 * (size_t)nv + 1, sizeof(double), err);
    c->overt_obstacle = rk_calloc((size_t)nv + 1, sizeof(int), err);
    c->ofaces = rk_calloc(3 * (size_t)nf + 1, sizeof(int), err);
    int *segs = rk_calloc(2 * (size_t)nseg + 1, sizeof(int), err);
    if (!c->oX || !c->ox || !c->ox_to || !c->overt_obstacle || !c->ofaces || !segs) {
        free(segs);
        return -1;
    }
    c->oedges = segs;
    nv = nf = nseg = 0;
    for (int k = 0; k < n; k++) {
        int v0 = nv;
        obstacle_geometry(c, &obstacles[k], 0, &nv, &nf, &nseg);
        for (int v = v0; v < nv; v++) c->overt_obstacle[v] = k;
    }
    /* the triangles' edges, and the capsules' segments */
    int *tri_edges, ntri_edges;
    if (edges_of(c->ofaces, nf, &tri_edges, &ntri_edges, err)) return -1;
    int *all = rk_calloc(2 * (size_t)(ntri_edges + nseg) + 2, sizeof(int), err);
    if (!all) {
        free(tri_edges);
        return -1;
    }
    memcpy(all, tri_edges, sizeof(int) * 2 * (size_t)ntri_edges);
    memcpy(all + 2 * ntri_edges, segs, sizeof(int) * 2 * (size_t)nseg);
    free(tri_edges);
    free(segs);
    c->oedges = all;
    c->one = ntri_edges + nseg;
    memcpy(c->ox, c->oX, sizeof(double) * 3 * (size_t)nv);
    rk_contact_set_time(c, 0);
    c->scene_obstacles = n, c->scene_onv = nv, c->scene_one = c->one, c->scene_onf = nf;
    return 0;
}

int rk_contact_init(rk_contact *c, const rk_mesh *mesh, const int *object_first_vertex, int nobjects,
                    const rk_obstacle *obstacles, int nobstacles, const rk_contact_options *o, double average_mass,
                    rk_error *err)
{
    memset(c, 0, sizeof *c);
    c->opt = *o;
    c->nmesh = mesh->nv;
    c->min_distance_last = NAN;
    if (!(o->dhat > 0 && isfinite(o->dhat))) return rk_fail(err, "contact: dhat = %g must be positive", o->dhat);
    if (!(o->kappa >= 0 && isfinite(o->kappa))) return rk_fail(err, "contact: kappa = %g must not be negative", o->kappa);
    if (!(o->friction >= 0 && isfinite(o->friction)))
        return rk_fail(err, "contact: friction = %g must not be negative", o->friction);
    if (!(o->eps_v > 0 && isfinite(o->eps_v))) return rk_fail(err, "contact: eps_v = %g must be positive", o->eps_v);
    if (nobstacles < 0 || (nobstacles > 0 && !obstacles))
        return rk_fail(err, "contact: %d obstacles given without data", nobstacles);
    c->bbox_diagonal = rk_points_diagonal(mesh->X, mesh->nv);
    int *tris = NULL, nf = 0;
    if (rk_mesh_boundary(mesh, &tris, &nf, err)) goto fail;
    c->faces = tris;
    c->nf = nf;
    if (edges_of(tris, nf, &c->edges, &c->ne, err)) goto fail;
    c->X = rk_calloc(3 * (size_t)mesh->nv + 1, sizeof(double), err);
    char *on = rk_calloc((size_t)mesh->nv + 1, 1, err);
    c->vertex = rk_calloc((size_t)mesh->nv + 1, sizeof(int), err);
    c->object = rk_calloc((size_t)mesh->nv + 1, sizeof(int), err);
    if (!c->X || !on || !c->vertex || !c->object) {
        free(on);
        goto fail;
    }
    memcpy(c->X, mesh->X, sizeof(double) * 3 * (size_t)mesh->nv);
    for (int i = 0; i < 3 * nf; i++) on[tris[i]] = 1;
    /* object of every mesh vertex, kept in c->object indexed by mesh vertex */
    for (int k = 0; object_first_vertex && k < nobjects; k++)
        for (int v = object_first_vertex[k]; v < object_first_vertex[k + 1]; v++) c->object[v] = k;
    c->mesh_pairs = (object_first_vertex && nobjects > 1) || o->self;
    for (int v = 0; v < mesh->nv; v++)
        if (on[v]) c->vertex[c->nv++] = v;
    free(on);
    if (rk_contact_build_obstacles(c, obstacles, nobstacles, err)) goto fail;
    c->cache_x = rk_calloc(3 * (size_t)c->nv + 1, sizeof(double), err);
    c->cache_ox = rk_calloc(3 * (size_t)c->onv + 1, sizeof(double), err);
    if (!c->cache_x || !c->cache_ox) goto fail;
    /* IPC's kappa_min: 4 d0 b''(d0) kappa_min = 1e11 m_avg, with d0 = (1e-8 diagonal)^2 */
    double d0 = 1e-8 * c->bbox_diagonal, d2;
    d0 *= d0;
    rk_barrier(d0, o->dhat * o->dhat, NULL, &d2);
    c->kappa_min = KAPPA_MIN_SCALE * average_mass / (4 * d0 * d2);
    c->kappa_max = KAPPA_MAX_RATIO * c->kappa_min;
    c->kappa = o->kappa > 0 ? o->kappa : c->kappa_min;
    c->kappa_set = o->kappa > 0;
    return 0;
fail:
    rk_contact_free(c);
    return -1;
}

void rk_contact_free(rk_contact *c)
{
    free(c->vertex), free(c->object), free(c->edges), free(c->faces), free(c->X);
    free(c->obstacles), free(c->oX), free(c->ox), free(c->overt_obstacle), free(c->oedges), free(c->ofaces);
    free(c->othick), free(c->oplane), free(c->ox_to), free(c->oplane_to);
    free(c->cache_x), free(c->cache_ox);
    rk_contact_set_free(&c->cache);
    rk_contact_set_free(&c->friction_pairs);
    free(c->friction), free(c->fx0), free(c->fox0);
    memset(c, 0, sizeof *c);
}

static void obstacle_transform(const rk_obstacle *o, double t, double R[9], double shift[3])
{
    if (o->posed) { /* an app's: where its pose puts it, at any time */
        memcpy(shift, o->pose, 3 * sizeof(double));
        memcpy(R, o->pose + 3, 9 * sizeof(double));
        return;
    }
    rk_motion(o->motion, o->axis, o->motion_center, o->rate, o->velocity, t, R, shift);
}

/* Where the obstacles are at time t: vertices into ox (3 onv), planes into pl (6 per obstacle,
 * or NULL). */
static void obstacles_at(const rk_contact *c, double t, double *ox, double *pl)
{
    for (int v = 0; v < c->onv; v++) {
        double R[9], s[3];
        obstacle_transform(&c->obstacles[c->overt_obstacle[v]], t, R, s);
        const double *X = &c->oX[3 * v];
        for (int i = 0; i < 3; i++) ox[3 * v + i] = R[3 * i] * X[0] + R[3 * i + 1] * X[1] + R[3 * i + 2] * X[2] + s[i];
    }
    for (int k = 0; pl && k < c->nobstacles; k++) {
        const rk_obstacle *o = &c->obstacles[k];
        if (o->kind != RK_OBSTACLE_PLANE) continue;
        double R[9], s[3], *p = &pl[6 * k];
        obstacle_transform(o, t, R, s);
        for (int i = 0; i < 3; i++) {
            p[i] = R[3 * i] * o->point[0] + R[3 * i + 1] * o->point[1] + R[3 * i + 2] * o->point[2] + s[i];
            p[3 + i] = R[3 * i] * o->normal[0] + R[3 * i + 1] * o->normal[1] + R[3 * i + 2] * o->normal[2];
        }
    }
}

void rk_contact_obstacles_at(const rk_contact *c, double t, double *out)
{
    obstacles_at(c, t, out, NULL);
}

void rk_contact_set_time(rk_contact *c, double t)
{
    obstacles_at(c, t, c->ox, c->oplane);
}

void rk_contact_obstacle_targets(rk_contact *c, double t)
{
    obstacles_at(c, t, c->ox_to, c->oplane_to);
}

void rk_contact_move_obstacles(rk_contact *c, double t, double fraction)
{
    if (fraction >= 1) {
        rk_contact_set_time(c, t);
        return;
    }
    rk_contact_obstacle_targets(c, t);
    for (int i = 0; i < 3 * c->onv; i++) c->ox[i] += fraction * (c->ox_to[i] - c->ox[i]);
    for (int i = 0; i < 6 * c->nobstacles; i++) c->oplane[i] += fraction * (c->oplane_to[i] - c->oplane[i]);
    for (int k = 0; k < c->nobstacles; k++) { /* keep plane normals unit */
        double *n = &c->oplane[6 * k + 3], len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len > 0)
            for (int i = 0; i < 3; i++) n[i] /= len;
    }
}
