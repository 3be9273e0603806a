/* The runtime's broad phase of the collision surface against itself (runtime/contact_surface.c),
 * compiled here in double with the contact code it feeds, on surfaces made by hand: two crumpled
 * sheets (two objects) and one sheet (self-contact), each moved several times so that the kept
 * orders are re-sorted from nearly sorted. Against brute force over every pair of primitives
 * (the same box test, the same rules: point-triangle and edge-edge only, no shared vertex, two
 * objects or self-contact): the gather keeps exactly the stencils within grow, and the swept
 * query visits exactly the stencils whose swept boxes touch, each once. */
#define ROMRT_DOUBLE 1
#include "runtime/dense.c"
#include "runtime/rows.c"
#include "runtime/physics.c"
#include "runtime/contact.c"
#include "runtime/contact_broad.c"
#include "runtime/contact_friction.c"
#include "runtime/contact_progress.c"
#include "runtime/contact_pull.c"
#include "runtime/contact_surface.c"
#include "runtime/mesh_move.c"

#include <stdlib.h>

#include "testlib.h"

#define N 7                     /* a sheet's vertices per side */
#define SHEETS 2
#define NV (SHEETS * N * N)
#define NE (SHEETS * (3 * (N - 1) * (N - 1) + 2 * (N - 1)))
#define NT (SHEETS * 2 * (N - 1) * (N - 1))
#define NP (NV + NE + NT)
#define CAP 200000

typedef struct {
    romrt_model m;
    double X[3 * NV], rows[3 * NV], x[3 * NV], dx[3 * NV], boxes[6 * NP], stat[10 * (SHEETS + 1)];
    uint32_t cv[NV], obj[NV], edges[2 * NE], tris[3 * NT], order[3 * NP], sobj[NP], first[SHEETS + 2];
    int32_t cand[5 * CAP];
} hand;

static double uniform(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return (double)((*s >> 8) & 0xFFFFFF) / 16777216.0;
}

/* `sheets` grids of N x N vertices 5 cm apart over z = 0 and z = 3 cm, each vertex moved by up to
 * `noise`; their triangles (two a cell) and edges (each once). */
static void make(hand *h, int sheets, int self, double noise, unsigned seed)
{
    romrt_model *m = &h->m;
    int nv = 0, ne = 0, nt = 0;
    memset(h, 0, sizeof *h);
    for (int s = 0; s < sheets; s++) {
        int base = nv;
        for (int i = 0; i < N; i++)
            for (int j = 0; j < N; j++, nv++) {
                h->X[3 * nv] = 0.05 * i + noise * (uniform(&seed) - 0.5);
                h->X[3 * nv + 1] = 0.05 * j + noise * (uniform(&seed) - 0.5);
                h->X[3 * nv + 2] = 0.03 * s + noise * (uniform(&seed) - 0.5);
                h->cv[nv] = (uint32_t)nv, h->obj[nv] = (uint32_t)s;
            }
        for (int i = 0; i < N; i++)
            for (int j = 0; j < N; j++) {
                uint32_t a = (uint32_t)(base + i * N + j);
                if (i + 1 < N) h->edges[2 * ne] = a, h->edges[2 * ne + 1] = a + N, ne++;
                if (j + 1 < N) h->edges[2 * ne] = a, h->edges[2 * ne + 1] = a + 1, ne++;
                if (i + 1 < N && j + 1 < N) {
                    h->edges[2 * ne] = a, h->edges[2 * ne + 1] = a + N + 1, ne++;
                    uint32_t t[6] = {a, a + N, a + N + 1, a, a + N + 1, a + 1};
                    memcpy(h->tris + 3 * nt, t, sizeof t);
                    nt += 2;
                }
            }
    }
    m->r = 1, m->nv = nv, m->ncv = nv, m->ncedge = ne, m->nctri = nt;
    m->X = h->X, m->rows = h->rows, m->cv = h->cv, m->cedges = h->edges, m->ctris = h->tris;
    m->cv_obj = sheets > 1 ? h->obj : NULL, m->nobjects = sheets > 1 ? sheets : 0, m->self_contact = self;
    m->ocx = h->x, m->ocdx = h->dx, m->sboxes = h->boxes, m->sorder = h->order, m->sobj = h->sobj, m->sfirst = h->first,
    m->sstat = h->stat;
    m->cand = h->cand, m->pair_cap = CAP;
    int n = nv + ne + nt;
    for (int a = 0; a < 3; a++)
        for (int i = 0; i < n; i++) h->order[a * n + i] = (uint32_t)i;
}

/* Stencils as 5 ints (kind, ids), sorted, for comparing sets. */
static int cmp5(const void *a, const void *b)
{
    return memcmp(a, b, 5 * sizeof(int32_t)); /* any fixed order will do */
}

typedef struct {
    int32_t *out;
    int n;
} collected;

static void collect(romrt_model *m, int edge_edge, const int32_t id[4], void *ctx)
{
    collected *c = ctx;
    (void)m;
    if (c->n >= CAP) return;
    c->out[5 * c->n] = edge_edge;
    memcpy(c->out + 5 * c->n + 1, id, 4 * sizeof(int32_t));
    c->n++;
}

/* Brute force: every pair of primitives (p < q) whose boxes (grown by grow, swept over dx when
 * swept) touch and whose stencil the rules allow; within grow of each other when !swept. */
static int brute(hand *h, double grow, int swept, int32_t *out)
{
    romrt_model *m = &h->m;
    int n = m->ncv + m->ncedge + m->nctri, count = 0;
    double *B = malloc(6 * sizeof(double) * (size_t)n);
    for (int p = 0; p < n; p++) {
        uint32_t ids[3];
        int np = prim_ids(m, (uint32_t)p, ids);
        for (int a = 0; a < 3; a++) B[6 * p + a] = INFINITY, B[6 * p + 3 + a] = -INFINITY;
        for (int k = 0; k < np; k++)
            for (int a = 0; a < 3; a++) {
                double x = h->x[3 * ids[k] + a], e = swept ? x + h->dx[3 * ids[k] + a] : x;
                B[6 * p + a] = fmin(B[6 * p + a], fmin(x, e));
                B[6 * p + 3 + a] = fmax(B[6 * p + 3 + a], fmax(x, e));
            }
        for (int a = 0; a < 3; a++) B[6 * p + a] -= grow, B[6 * p + 3 + a] += grow;
    }
    for (int p = 0; p < n; p++)
        for (int q = p + 1; q < n; q++) {
            const double *a = B + 6 * p, *b = B + 6 * q;
            int32_t id[4];
            int ee;
            if (a[0] > b[3] || a[3] < b[0] || a[1] > b[4] || a[4] < b[1] || a[2] > b[5] || a[5] < b[2]) continue;
            if (!stencil_of(m, (uint32_t)p, (uint32_t)q, id, &ee)) continue;
            if (!swept) {
                const double *pts[4];
                rt_obstacles_stencil(m, id, pts);
                if (!(RT_PHYS(contact_distance2)(ee ? RT_PHYS(edge_edge_case)(pts) : RT_PHYS(point_triangle_case)(pts), pts, 0,
                                                 0) < grow * grow))
                    continue;
            }
            out[5 * count] = ee;
            memcpy(out + 5 * count + 1, id, 4 * sizeof(int32_t));
            count++;
        }
    free(B);
    return count;
}

static int32_t want[5 * CAP], got[5 * CAP];

static void compare(hand *h, const char *label, double grow, int swept)
{
    int nw = brute(h, grow, swept, want), ng;
    if (swept) {
        collected c = {got, 0};
        rt_surface_stencils(&h->m, 0, 1, collect, &c);
        ng = c.n;
    } else {
        h->m.ncand = 0;
        CHECK(rt_surface_stencils(&h->m, grow, 0, NULL, NULL) == 0, "%s: overflow", label);
        ng = h->m.ncand;
        memcpy(got, h->m.cand, 5 * sizeof(int32_t) * (size_t)ng);
    }
    qsort(want, (size_t)nw, 5 * sizeof(int32_t), cmp5);
    qsort(got, (size_t)ng, 5 * sizeof(int32_t), cmp5);
    printf("# %s: %d stencils (brute force %d)\n", label, ng, nw);
    CHECK(nw > 0, "%s: the case should have stencils", label);
    CHECK(ng == nw && memcmp(want, got, 5 * sizeof(int32_t) * (size_t)nw) == 0, "%s: %d stencils, brute force %d", label,
          ng, nw);
}

static void run_case(int sheets, int self, unsigned seed)
{
    static hand h;
    char label[96];
    unsigned start = seed;
    make(&h, sheets, self, 0.04, seed);
    for (int round = 0; round < 4; round++) {
        /* the surface where X puts it, moved a little more each round; a step dx of up to 2 cm */
        for (int i = 0; i < 3 * NV; i++) {
            h.x[i] = h.X[i] + 0.01 * round * (uniform(&seed) - 0.5);
            h.dx[i] = 0.04 * (uniform(&seed) - 0.5);
        }
        snprintf(label, sizeof label, "%d sheet(s), self %d, seed %u, round %d, gather", sheets, self, start, round);
        compare(&h, label, 0.025, 0);
        snprintf(label, sizeof label, "%d sheet(s), self %d, seed %u, round %d, swept", sheets, self, start, round);
        compare(&h, label, 0, 1);
    }
}

TEST(two_objects_match_brute_force)
{
    run_case(2, 0, 1u);
    run_case(2, 0, 7u);
}

TEST(two_objects_with_self_contact_match_brute_force) { run_case(2, 1, 3u); }

TEST(one_sheet_self_contact_matches_brute_force) { run_case(1, 1, 5u); }

int main(void)
{
    RUN(two_objects_match_brute_force);
    RUN(two_objects_with_self_contact_match_brute_force);
    RUN(one_sheet_self_contact_matches_brute_force);
    return test_finish();
}
