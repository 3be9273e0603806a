/* Contact candidates and the active pairs (contact.h): the broad phase over the boundary
 * primitives' boxes (grown by dhat for proximity, swept along a step for CCD), then the stencils
 * that may touch: object points against object and obstacle triangles, obstacle points (sphere
 * and capsule centres, box and mesh corners) against object triangles, and object edges against
 * object and obstacle edges. Pairs within one object need self-contact on and no shared vertex. */
#include "contact/pairs_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

void rk_contact_set_free(rk_contact_set *s)
{
    free(s->pairs);
    memset(s, 0, sizeof *s);
}

static int push(rk_contact_set *s, rk_contact_pair p, rk_error *err)
{
    if (s->n == s->cap) {
        int cap = s->cap ? 2 * s->cap : 256;
        rk_contact_pair *grown = realloc(s->pairs, (size_t)cap * sizeof *grown);
        if (!grown) return rk_fail(err, "contact: out of memory for %d pairs", cap);
        s->pairs = grown;
        s->cap = cap;
    }
    s->pairs[s->n++] = p;
    return 0;
}

/* Position of stencil id: a mesh vertex, or an obstacle vertex (id < 0). */
const double *rk_contact_point(const rk_contact *c, const double *x, const double *ox, int id)
{
    return id >= 0 ? &x[3 * id] : &ox[3 * (-1 - id)];
}

/* The box of n points (ids), over x and, when dx is given, x + dx too; grown by grow. */
static void box_of(const rk_contact *c, const rk_motion_frame *f, const int *ids, int n, double grow, double *box)
{
    for (int a = 0; a < 3; a++) box[a] = INFINITY, box[3 + a] = -INFINITY;
    for (int k = 0; k < n; k++) {
        const double *p = rk_contact_point(c, f->x, f->ox, ids[k]);
        const double *d = ids[k] >= 0 ? (f->dx ? &f->dx[3 * ids[k]] : NULL) : (f->odx ? &f->odx[3 * (-1 - ids[k])] : NULL);
        for (int a = 0; a < 3; a++) {
            box[a] = fmin(box[a], p[a]);
            box[3 + a] = fmax(box[3 + a], p[a]);
            if (d) {
                box[a] = fmin(box[a], p[a] + d[a]);
                box[3 + a] = fmax(box[3 + a], p[a] + d[a]);
            }
        }
    }
    for (int a = 0; a < 3; a++) box[a] -= grow, box[3 + a] += grow;
}

/* The primitives of one kind: their stencil ids (1, 2 or 3 per primitive) and thickness. */
typedef struct {
    int n, size;     /* primitives, points each */
    int *ids;        /* n x size */
    double *xi;      /* n, or NULL: 0 */
    double *boxes;   /* n x 6 */
} primitives;

static void primitives_free(primitives *p)
{
    free(p->ids), free(p->xi), free(p->boxes);
    memset(p, 0, sizeof *p);
}

static int primitives_alloc(primitives *p, int n, int size, int thick, rk_error *err)
{
    memset(p, 0, sizeof *p);
    p->n = n;
    p->size = size;
    p->ids = rk_calloc((size_t)n * size + 1, sizeof(int), err);
    p->boxes = rk_calloc(6 * (size_t)n + 1, sizeof(double), err);
    p->xi = thick ? rk_calloc((size_t)n + 1, sizeof(double), err) : NULL;
    return p->ids && p->boxes && (!thick || p->xi) ? 0 : -1;
}

/* The object's points, edges, triangles and the obstacles' (ids < 0), with boxes. */
static int build_primitives(const rk_contact *c, const rk_motion_frame *f, double grow, primitives P[6], rk_error *err)
{
    if (primitives_alloc(&P[OBJ_POINTS], c->nv, 1, 0, err) || primitives_alloc(&P[OBJ_EDGES], c->ne, 2, 0, err) ||
        primitives_alloc(&P[OBJ_FACES], c->nf, 3, 0, err) || primitives_alloc(&P[OBS_POINTS], c->onv, 1, 1, err) ||
        primitives_alloc(&P[OBS_EDGES], c->one, 2, 1, err) || primitives_alloc(&P[OBS_FACES], c->onf, 3, 1, err))
        return -1;
    memcpy(P[OBJ_POINTS].ids, c->vertex, sizeof(int) * (size_t)c->nv);
    memcpy(P[OBJ_EDGES].ids, c->edges, sizeof(int) * 2 * (size_t)c->ne);
    memcpy(P[OBJ_FACES].ids, c->faces, sizeof(int) * 3 * (size_t)c->nf);
    for (int v = 0; v < c->onv; v++) {
        P[OBS_POINTS].ids[v] = -1 - v;
        P[OBS_POINTS].xi[v] = c->othick[c->overt_obstacle[v]];
    }
    for (int e = 0; e < c->one; e++) {
        for (int k = 0; k < 2; k++) P[OBS_EDGES].ids[2 * e + k] = -1 - c->oedges[2 * e + k];
        P[OBS_EDGES].xi[e] = c->othick[c->overt_obstacle[c->oedges[2 * e]]];
    }
    for (int t = 0; t < c->onf; t++)
        for (int k = 0; k < 3; k++) P[OBS_FACES].ids[3 * t + k] = -1 - c->ofaces[3 * t + k];
    for (int k = 0; k < 6; k++)
        for (int i = 0; i < P[k].n; i++)
            box_of(c, f, P[k].ids + (size_t)P[k].size * i, P[k].size, grow + (P[k].xi ? P[k].xi[i] : 0),
                   P[k].boxes + 6 * i);
    return 0;
}

static int shares(const int *a, int na, const int *b, int nb)
{
    for (int i = 0; i < na; i++)
        for (int j = 0; j < nb; j++)
            if (a[i] == b[j]) return 1;
    return 0;
}

/* Whether two object primitives may touch: different objects, or self-contact on and no shared vertex. */
static int object_pair_allowed(const rk_contact *c, const int *a, int na, const int *b, int nb)
{
    if (shares(a, na, b, nb)) return 0;
    return c->object[a[0]] != c->object[b[0]] || c->opt.self;
}

/* The rest |e|^2 of an edge (mesh or obstacle vertex ids). */
static double edge_rest2(const rk_contact *c, const int *ids)
{
    const double *p = ids[0] >= 0 ? &c->X[3 * ids[0]] : &c->oX[3 * (-1 - ids[0])];
    const double *q = ids[1] >= 0 ? &c->X[3 * ids[1]] : &c->oX[3 * (-1 - ids[1])];
    return (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
}

static int cmp_index_pair(const void *a, const void *b)
{
    const int *x = a, *y = b;
    if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
    return (x[1] > y[1]) - (x[1] < y[1]);
}

/* The n primitives (size mesh vertex ids each, boxes 6 n) grouped by object (counting sort,
 * stable): order (n) their indices, first (nobj + 1) each object's start, sorted (6 n) their boxes
 * in that order. */
static int group_by_object(const rk_contact *c, const double *boxes, const int *ids, int size, int n, int nobj,
                           int **order, int **first, double **sorted, rk_error *err)
{
    *order = rk_calloc((size_t)n + 1, sizeof(int), err);
    *first = rk_calloc((size_t)nobj + 1, sizeof(int), err);
    *sorted = rk_calloc(6 * (size_t)n + 1, sizeof(double), err);
    int *at = rk_calloc((size_t)nobj + 1, sizeof(int), err);
    if (!*order || !*first || !*sorted || !at) {
        free(at);
        return -1;
    }
    for (int i = 0; i < n; i++) (*first)[c->object[ids[(size_t)size * i]] + 1]++;
    for (int o = 0; o < nobj; o++) (*first)[o + 1] += (*first)[o];
    memcpy(at, *first, sizeof(int) * (size_t)nobj);
    for (int i = 0; i < n; i++) {
        int k = at[c->object[ids[(size_t)size * i]]]++;
        (*order)[k] = i;
        memcpy(*sorted + 6 * (size_t)k, boxes + 6 * (size_t)i, 6 * sizeof(double));
    }
    free(at);
    return 0;
}

int rk_contact_object_broad_phase(const rk_contact *c, const double *boxes_a, const int *ids_a, int size_a, int na,
                                  const double *boxes_b, const int *ids_b, int size_b, int nb, int **pairs, int *np,
                                  rk_error *err)
{
    if (c->opt.self) return rk_broad_phase(boxes_a, na, boxes_b, nb, pairs, np, err);
    *pairs = NULL;
    *np = 0;
    int nobj = 0;
    for (int v = 0; v < c->nmesh; v++) nobj = c->object[v] >= nobj ? c->object[v] + 1 : nobj;
    int *oa = NULL, *fa = NULL, *ob = NULL, *fb = NULL, *out = NULL, rc = -1;
    double *ba = NULL, *bb = NULL;
    size_t n = 0, cap = 0;
    if (group_by_object(c, boxes_a, ids_a, size_a, na, nobj, &oa, &fa, &ba, err) ||
        group_by_object(c, boxes_b, ids_b, size_b, nb, nobj, &ob, &fb, &bb, err))
        goto done;
    for (int i = 0; i < nobj; i++)
        for (int j = 0; j < nobj; j++) {
            if (i == j || fa[i + 1] == fa[i] || fb[j + 1] == fb[j]) continue;
            int *p = NULL, k = 0;
            if (rk_broad_phase(ba + 6 * (size_t)fa[i], fa[i + 1] - fa[i], bb + 6 * (size_t)fb[j], fb[j + 1] - fb[j], &p,
                               &k, err))
                goto done;
            if (n + (size_t)k > cap) {
                size_t grown = 2 * (n + (size_t)k);
                int *bigger = realloc(out, 2 * grown * sizeof(int));
                if (!bigger) {
                    free(p);
                    rk_fail(err, "broad phase: out of memory");
                    goto done;
                }
                out = bigger, cap = grown;
            }
            for (int q = 0; q < k; q++, n++)
                out[2 * n] = oa[fa[i] + p[2 * q]], out[2 * n + 1] = ob[fb[j] + p[2 * q + 1]];
            free(p);
        }
    if (n > 1) qsort(out, n, 2 * sizeof(int), cmp_index_pair);
    *pairs = out, *np = (int)n;
    out = NULL;
    rc = 0;
done:
    free(oa), free(fa), free(ba), free(ob), free(fb), free(bb), free(out);
    return rc;
}

int rk_contact_candidates(rk_contact *c, const rk_motion_frame *f, double grow, rk_contact_set *s, rk_error *err)
{
    primitives P[6];
    memset(P, 0, sizeof P);
    s->n = 0;
    int rc = build_primitives(c, f, grow, P, err);
    /* the classes of pairs: A side, B side, kind */
    static const int classes[5][3] = {{OBJ_POINTS, OBJ_FACES, RK_PAIR_POINT_TRIANGLE},
                                      {OBJ_EDGES, OBJ_EDGES, RK_PAIR_EDGE_EDGE},
                                      {OBJ_POINTS, OBS_FACES, RK_PAIR_POINT_TRIANGLE},
                                      {OBS_POINTS, OBJ_FACES, RK_PAIR_POINT_TRIANGLE},
                                      {OBJ_EDGES, OBS_EDGES, RK_PAIR_EDGE_EDGE}};
    for (int k = c->mesh_pairs ? 0 : 2; k < 5 && !rc; k++) {
        const primitives *A = &P[classes[k][0]], *B = &P[classes[k][1]];
        int *pairs = NULL, np = 0;
        if (k < 2 ? rk_contact_object_broad_phase(c, A->boxes, A->ids, A->size, A->n, B->boxes, B->ids, B->size, B->n,
                                                  &pairs, &np, err)
                  : rk_broad_phase(A->boxes, A->n, B->boxes, B->n, &pairs, &np, err)) {
            rc = -1;
            break;
        }
        for (int p = 0; p < np && !rc; p++) {
            int a = pairs[2 * p], b = pairs[2 * p + 1];
            const int *ia = A->ids + (size_t)A->size * a, *ib = B->ids + (size_t)B->size * b;
            int object_object = k < 2;
            if (object_object && (!object_pair_allowed(c, ia, A->size, ib, B->size) || (k == 1 && a >= b))) continue;
            rk_contact_pair q = {.kind = (rk_pair_kind)classes[k][2]};
            memcpy(q.id, ia, sizeof(int) * (size_t)A->size);
            memcpy(q.id + A->size, ib, sizeof(int) * (size_t)B->size);
            q.xi = A->xi ? A->xi[a] : B->xi ? B->xi[b] : 0;
            if (q.kind == RK_PAIR_EDGE_EDGE) q.eps = 1e-3 * edge_rest2(c, ia) * edge_rest2(c, ib);
            rc = push(s, q, err);
        }
        free(pairs);
    }
    for (int k = 0; k < 6; k++) primitives_free(&P[k]);
    return rc;
}

/* The stencil's four points at x (mesh) and ox (obstacles). */
void rk_contact_stencil(const rk_contact *c, const rk_contact_pair *p, const double *x, const double *ox,
                        const double *out[4])
{
    for (int k = 0; k < 4; k++) out[k] = rk_contact_point(c, x, ox, p->id[k]);
}

double rk_contact_pair_distance2(const rk_contact *c, const rk_contact_pair *p, const double *x, const double *ox)
{
    const double *pts[4];
    rk_contact_stencil(c, p, x, ox, pts);
    rk_distance_case k = p->kind == RK_PAIR_EDGE_EDGE ? rk_edge_edge_case(pts) : rk_point_triangle_case(pts);
    return rk_contact_distance2(k, pts, NULL, NULL);
}

double rk_contact_plane_distance(const rk_contact *c, int plane, const double *p)
{
    const double *pl = &c->oplane[6 * plane];
    return pl[3] * (p[0] - pl[0]) + pl[4] * (p[1] - pl[1]) + pl[5] * (p[2] - pl[2]);
}

/* The largest distance any collision vertex or obstacle vertex has moved since the cache. */
static double moved_since_cache(const rk_contact *c, const double *x)
{
    double m2 = 0;
    for (int i = 0; i < c->nv; i++) {
        const double *p = &x[3 * c->vertex[i]], *q = &c->cache_x[3 * i];
        double d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
        if (d2 > m2) m2 = d2;
    }
    for (int i = 0; i < c->onv; i++) {
        const double *p = &c->ox[3 * i], *q = &c->cache_ox[3 * i];
        double d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
        if (d2 > m2) m2 = d2;
    }
    return sqrt(m2);
}

/* How far rk_contact_gather grows each box of its cache (the one place: cache_slack's guarantees
 * rest on it). */
static double cache_growth(const rk_contact *c)
{
    return 2 * c->opt.dhat;
}

/* The cache's growth less what has moved since, with a little room for the boxes' rounding: what a
 * caller's own reach may use of it. Negative: the cache is not there. */
static double cache_slack(const rk_contact *c, const double *x)
{
    return c->cache_valid ? 0.99 * cache_growth(c) - moved_since_cache(c, x) : -1;
}

/* The largest move of a collision or obstacle vertex over the step (dx indexed by mesh vertex). */
static double largest_step(const rk_contact *c, const rk_motion_frame *f)
{
    double m2 = 0;
    for (int i = 0; i < c->nv && f->dx; i++) {
        const double *d = &f->dx[3 * c->vertex[i]];
        m2 = fmax(m2, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    for (int i = 0; i < c->onv && f->odx; i++) {
        const double *d = &f->odx[3 * i];
        m2 = fmax(m2, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    return sqrt(m2);
}

/* A cached pair's two primitives' boxes as build_primitives makes them (an obstacle's grown by its
 * thickness, the pair's xi). */
static void pair_boxes(const rk_contact *c, const rk_motion_frame *f, const rk_contact_pair *p, double *a, double *b)
{
    int na = p->kind == RK_PAIR_EDGE_EDGE ? 2 : 1, nb = 4 - na;
    box_of(c, f, p->id, na, p->id[0] < 0 ? p->xi : 0, a);
    box_of(c, f, p->id + na, nb, p->id[na] < 0 ? p->xi : 0, b);
}

int rk_contact_step_candidates_cached(rk_contact *c, const rk_motion_frame *f, rk_contact_set *s, rk_error *err)
{
    /* a primitive's swept box lies within its box at the cache grown by the largest move since and
     * the largest step; while those stay within the cache's growth every pair whose swept boxes
     * overlap is a cached pair, and the cache keeps the broad phase's order */
    double slack = cache_slack(c, f->x);
    if (slack <= 0 || largest_step(c, f) > slack) return 0;
    s->n = 0;
    for (int i = 0; i < c->cache.n; i++) {
        double a[6], b[6];
        pair_boxes(c, f, &c->cache.pairs[i], a, b);
        if (rk_boxes_overlap(a, b) && push(s, c->cache.pairs[i], err)) return -1;
    }
    return 1;
}

double rk_contact_cached_closest(const rk_contact *c, const double *x, double reach)
{
    /* a pair outside the cache was more than 2 cache_growth + xi apart along some axis where the cache
     * was built and each side has moved at most `moved` since, so its distance less xi exceeds
     * 2 slack; a smallest cached value at or below that is the smallest of every pair, and one at or
     * below 2 reach is in reach's list (its boxes, grown by reach each, overlap) */
    double slack = cache_slack(c, x), closest = INFINITY;
    if (slack <= 0) return NAN;
    for (int i = 0; i < c->cache.n; i++) {
        const rk_contact_pair *p = &c->cache.pairs[i];
        closest = fmin(closest, sqrt(rk_contact_pair_distance2(c, p, x, c->ox)) - p->xi);
    }
    return closest <= 2 * slack && closest <= 2 * reach ? closest : NAN;
}

int rk_contact_gather(rk_contact *c, const double *x, rk_contact_set *s, rk_error *err)
{
    double dhat = c->opt.dhat;
    /* a pair's distance changes by at most twice the largest move: the list grown by dhat holds
     * every pair within dhat while nothing has moved dhat / 2 */
    if (!c->cache_valid || 2 * moved_since_cache(c, x) > dhat) {
        double t0 = rk_now();
        rk_motion_frame f = {x, NULL, c->ox, NULL};
        if (rk_contact_candidates(c, &f, cache_growth(c), &c->cache, err)) return -1;
        for (int i = 0; i < c->nv; i++) memcpy(&c->cache_x[3 * i], &x[3 * c->vertex[i]], 3 * sizeof(double));
        memcpy(c->cache_ox, c->ox, sizeof(double) * 3 * (size_t)c->onv);
        c->cache_valid = 1;
        c->stats.seconds_broad += rk_now() - t0;
    }
    /* keep the stencils within dhat (plus thickness) */
    s->n = 0;
    for (int i = 0; i < c->cache.n; i++) {
        const rk_contact_pair *p = &c->cache.pairs[i];
        double reach = dhat + p->xi;
        if (rk_contact_pair_distance2(c, p, x, c->ox) < reach * reach && push(s, *p, err)) return -1;
    }
    for (int k = 0; k < c->nobstacles; k++) {
        if (c->obstacles[k].kind != RK_OBSTACLE_PLANE) continue;
        for (int i = 0; i < c->nv; i++) {
            int v = c->vertex[i];
            if (rk_contact_plane_distance(c, k, &x[3 * v]) < dhat &&
                push(s, (rk_contact_pair){.kind = RK_PAIR_POINT_PLANE, .id = {v, k, -1, -1}}, err))
                return -1;
        }
    }
    c->stats.gathers++;
    c->stats.pairs += s->n;
    if (s->n > c->stats.max_pairs) c->stats.max_pairs = s->n;
    return 0;
}
