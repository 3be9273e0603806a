/* Several objects colliding with each other (COBJ, CRAD; ROMBIN.md "Object chunks"). Each object's
 * collision vertices carry a sphere of its proxy radius rho; a pair of collision vertices of
 * different objects a and b is kept apart by the planes' barrier (physics' barrier_distance, the
 * asset's kappa and dhat) on d = |x_i - x_j| - (rho_a + rho_b), and the step filter keeps every
 * pair at 10% of its distance. rho is baked so that the spheres cover the object's surface at
 * rest (precompute/asset/bake_objects.c): a vertex of one object kept outside the other's spheres
 * never reaches its surface.
 *
 * The broad phase is a uniform grid of cell size at least the reach asked for, hashed into
 * grid_size buckets (a power of two >= 2 ncv) in the arena: each collision vertex is linked into
 * its cell's bucket, and a pair is visited from its lower vertex through the 27 cells around it,
 * only when the other vertex's own cell is the one scanned (two cells may share a bucket). Every
 * pair closer than the cell size is visited exactly once, in O(ncv) for spread-out vertices; the
 * grid is rebuilt at every call (positions change with every q), no pair list is kept, so none
 * can go stale. */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

#define NO_VERTEX 0xFFFFFFFFu
/* Cell coordinates are clamped here: only positions 2^30 cells from the origin share cells. */
#define CELL_LIMIT 1073741824.0
/* Cells a little wider than the reach, so a pair at the reach is never two cells apart by the
 * rounding of x / cell. */
#define CELL_SLACK RT_K(1.01)
/* The float runtime keeps pairs CONTACT_FLOOR dhat apart too, as the planes (potential.c). */
#ifdef ROMRT_DOUBLE
#define PAIR_FLOOR 0
#else
#define PAIR_FLOOR 1e-3f
#endif

/* The collision vertices' positions X + B q into m->cv_x; with dq, their moves B dq into m->cv_dx,
 * the largest length of which is returned. */
static romrt_real positions(romrt_model *m, const romrt_real *q, const romrt_real *dq)
{
    romrt_real most = 0;
    int i, a;
    for (i = 0; i < m->ncv; i++) {
        romrt_real len2 = 0;
        rt_vertex_position(m, m->cv[i], q, m->cv_x + 3 * (size_t)i);
        if (!dq) continue;
        for (a = 0; a < 3; a++) {
            romrt_real e = rt_row_dot(m, m->cv[i], a, dq);
            m->cv_dx[3 * (size_t)i + a] = e;
            len2 += e * e;
        }
        if (len2 > most) most = len2;
    }
    return RT_SQRT(most);
}

static int32_t cell_of(romrt_real x, romrt_real inv)
{
    double c = floor((double)x * (double)inv);
    return (int32_t)(c > CELL_LIMIT ? CELL_LIMIT : c < -CELL_LIMIT ? -CELL_LIMIT : c);
}

static uint32_t bucket(const romrt_model *m, int32_t x, int32_t y, int32_t z)
{
    return ((uint32_t)x * 73856093u ^ (uint32_t)y * 19349663u ^ (uint32_t)z * 83492791u) & (m->grid_size - 1);
}

/* The grid of cell size `cell` over m->cv_x; 0, or -1 when a position is not finite. */
static int grid_build(romrt_model *m, romrt_real cell)
{
    romrt_real inv = 1 / (CELL_SLACK * cell);
    uint32_t i, h;
    int a;
    for (i = 0; i < m->grid_size; i++) m->grid_head[i] = NO_VERTEX;
    for (i = 0; i < (uint32_t)m->ncv; i++) {
        int32_t *c = m->grid_cell + 3 * (size_t)i;
        for (a = 0; a < 3; a++) {
            if (!isfinite(m->cv_x[3 * (size_t)i + a])) return -1;
            c[a] = cell_of(m->cv_x[3 * (size_t)i + a], inv);
        }
        h = bucket(m, c[0], c[1], c[2]);
        m->grid_next[i] = m->grid_head[h];
        m->grid_head[h] = i;
    }
    return 0;
}

/* What a visit of the pairs does. */
typedef struct {
    const romrt_real *q;
    romrt_real *g, *H;
    int ld;
    romrt_real E;             /* energy (+INFINITY once a pair touches) */
    romrt_real alpha, floor;  /* the step filter's alpha and float's floor */
    romrt_real least;         /* the smallest d */
} pair_visit;

typedef int (*pair_fn)(romrt_model *m, uint32_t i, uint32_t j, pair_visit *v);

/* fn on every pair (i < j) of collision vertices of different objects in neighbouring cells of the
 * grid built last: every such pair closer than the cell size, once. Stops when fn returns nonzero. */
static void for_near_pairs(romrt_model *m, pair_fn fn, pair_visit *v)
{
    uint32_t i, j;
    int dx, dy, dz;
    for (i = 0; i < (uint32_t)m->ncv; i++) {
        const int32_t *ci = m->grid_cell + 3 * (size_t)i;
        for (dx = -1; dx <= 1; dx++)
            for (dy = -1; dy <= 1; dy++)
                for (dz = -1; dz <= 1; dz++) {
                    int32_t cx = ci[0] + dx, cy = ci[1] + dy, cz = ci[2] + dz;
                    for (j = m->grid_head[bucket(m, cx, cy, cz)]; j != NO_VERTEX; j = m->grid_next[j]) {
                        const int32_t *cj = m->grid_cell + 3 * (size_t)j;
                        if (j <= i || cj[0] != cx || cj[1] != cy || cj[2] != cz || m->cv_obj[i] == m->cv_obj[j]) continue;
                        if (fn(m, i, j, v)) return;
                    }
                }
    }
}

/* x_i - x_j into D, its length, and rho_a + rho_b. */
static romrt_real pair_gap(const romrt_model *m, uint32_t i, uint32_t j, romrt_real D[3], romrt_real *len)
{
    int a;
    for (a = 0; a < 3; a++) D[a] = m->cv_x[3 * (size_t)i + a] - m->cv_x[3 * (size_t)j + a];
    *len = RT_SQRT(D[0] * D[0] + D[1] * D[1] + D[2] * D[2]);
    return m->obj_rho[m->cv_obj[i]] + m->obj_rho[m->cv_obj[j]];
}

/* kappa b(d) and its derivatives in q: d's gradient is a = (B_i - B_j)^T n with n = D / |D|; the
 * Hessian is kappa b'' a a^T, Gauss-Newton: d's own curvature kappa b' (B_i - B_j)^T (I - n n^T)
 * (B_i - B_j) / |D| is negative semidefinite (b' < 0) and left out, as IPC's PSD projection of a
 * point-point pair would, so the Newton matrix stays positive definite. */
static int pair_energy(romrt_model *m, uint32_t i, uint32_t j, pair_visit *v)
{
    romrt_real D[3], len, R = pair_gap(m, i, j, D, &len), d = len - R, f1, f2, *A = m->pair_a;
    int a, k, l, r = m->r;
    if (!(d > 0)) {
        v->E = (romrt_real)INFINITY;
        return 1;
    }
    if (d >= m->dhat) return 0;
    v->E += m->kappa * RT_PHYS(barrier_distance)(d, m->dhat, &f1, &f2);
    if (!v->g && !v->H) return 0;
    for (k = 0; k < r; k++) A[k] = 0;
    for (a = 0; a < 3; a++) {
        rt_row_axpy(m, m->cv[i], a, D[a] / len, A);
        rt_row_axpy(m, m->cv[j], a, -D[a] / len, A);
    }
    if (v->g)
        for (k = 0; k < r; k++) v->g[k] += m->kappa * f1 * A[k];
    if (v->H)
        for (l = 0; l < r; l++)
            for (k = 0; k <= l; k++) v->H[k + (size_t)v->ld * l] += m->kappa * f2 * A[k] * A[l];
    return 0;
}

romrt_real rt_objects_energy(romrt_model *m, const romrt_real *q, romrt_real *g, romrt_real *H, int ld)
{
    pair_visit v;
    memset(&v, 0, sizeof v);
    v.q = q, v.g = g, v.H = H, v.ld = ld, v.E = 0;
    positions(m, q, 0);
    /* every pair with d < dhat (and every one with d <= 0) is closer than 2 rho_max + dhat */
    if (grid_build(m, 2 * m->rho_max + m->dhat)) return (romrt_real)INFINITY;
    for_near_pairs(m, pair_energy, &v);
    return v.E;
}

/* The largest alpha in [0, v->alpha] with |D + alpha e| >= target all along, e = dx_i - dx_j,
 * target = rho_a + rho_b + 0.1 d + 0.9 floor: the pair keeps 10% of its distance (conservative
 * advancement, exact: |D + alpha e|^2 is a quadratic in alpha, and its first crossing of target^2
 * is the smaller root). */
static int pair_step(romrt_model *m, uint32_t i, uint32_t j, pair_visit *v)
{
    romrt_real D[3], e[3], len, R = pair_gap(m, i, j, D, &len), d = len - R, target, a2, b, c, disc, root;
    int a;
    for (a = 0; a < 3; a++) e[a] = m->cv_dx[3 * (size_t)i + a] - m->cv_dx[3 * (size_t)j + a];
    a2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
    b = 2 * (D[0] * e[0] + D[1] * e[1] + D[2] * e[2]);
    if (!(b < 0)) return 0; /* moving apart (|D + alpha e| grows from alpha = 0), or not at all */
    target = R + RT_K(0.1) * d + RT_K(0.9) * v->floor;
    /* |D|^2 - target^2 as (|D| - target)(|D| + target), |D| - target = 0.9 (d - floor): no cancellation */
    c = RT_K(0.9) * (d - v->floor) * (len + target);
    if (!(c > 0)) {
        v->alpha = 0;
        return 1;
    }
    disc = b * b - 4 * a2 * c;
    if (disc < 0) return 0; /* it passes by, never that close */
    root = 2 * c / (-b + RT_SQRT(disc));
    if (root < v->alpha) v->alpha = root;
    return 0;
}

romrt_real rt_objects_max_step(romrt_model *m, const romrt_real *q, const romrt_real *dq)
{
    pair_visit v;
    romrt_real most = positions(m, q, dq), reach;
    memset(&v, 0, sizeof v);
    v.alpha = 1, v.floor = RT_K(PAIR_FLOOR) * m->dhat;
    /* A pair can shorten a step only if its relative move |e| <= 2 most reaches 0.9 (d - floor):
     * every such pair has d < floor + 2 most / 0.9, so is closer than this cell size. */
    reach = v.floor + 2 * most / RT_K(0.9);
    if (!isfinite(reach) || grid_build(m, 2 * m->rho_max + reach)) return 0;
    for_near_pairs(m, pair_step, &v);
    return v.alpha;
}

static int pair_least(romrt_model *m, uint32_t i, uint32_t j, pair_visit *v)
{
    romrt_real D[3], len, R = pair_gap(m, i, j, D, &len);
    if (len - R < v->least) v->least = len - R;
    return 0;
}

romrt_real rt_objects_min_distance(romrt_model *m, const romrt_real *q)
{
    pair_visit v;
    memset(&v, 0, sizeof v);
    v.least = (romrt_real)INFINITY;
    positions(m, q, 0);
    if (grid_build(m, 2 * m->rho_max + m->dhat)) return -(romrt_real)INFINITY;
    for_near_pairs(m, pair_least, &v);
    return v.least;
}
