/* The environments romkit motions builds around an object (motions.h has the sizes and why):
 * a pachinko board of staggered pegs, and a dryer's octagonal drum. */
#include <math.h>
#include <stdlib.h>

#include "motions/motions_impl.h"

#define PEG_RADIUS 0.1   /* L */
#define PEG_SPACING 2.4  /* L, along the board: a gap of 2.2 L between pegs */
#define ROW_PITCH 1.6    /* L, down the board */
#define ROWS 5
#define BOARD_HALF 2     /* peg spacings each side of the object */
#define CLEARANCE 0.25   /* L: every obstacle this far from the object's box at the start */
#define DRUM_SIDES 8

double rk_motions_peg_spacing(const rk_motions_frame *F) { return PEG_SPACING * F->L; }

double rk_motions_drum_radius(const rk_motions_frame *F) { return 0.5 * F->D + CLEARANCE * F->L; }

void rk_motions_point(const rk_motions_frame *F, double alpha, double upsilon, double beta, double out[3])
{
    for (int k = 0; k < 3; k++) out[k] = F->c[k] + alpha * F->a[k] + upsilon * F->u[k] + beta * F->b[k];
}

static void add_plane(cJSON *arr, const rk_motions_frame *F, double alpha, double upsilon, double beta,
                      const double *dir, double sign)
{
    double p[3], n[3];
    rk_motions_point(F, alpha, upsilon, beta, p);
    for (int k = 0; k < 3; k++) n[k] = sign * dir[k];
    cJSON *o = cJSON_CreateObject(), *pl = cJSON_AddObjectToObject(o, "plane");
    cJSON_AddItemToObject(pl, "point", cJSON_CreateDoubleArray(p, 3));
    cJSON_AddItemToObject(pl, "normal", cJSON_CreateDoubleArray(n, 3));
    cJSON_AddItemToArray(arr, o);
}

cJSON *rk_motions_board(const rk_motions_frame *F, rk_motions_report *rep)
{
    const double L = F->L, r = PEG_RADIUS * L, s = rk_motions_peg_spacing(F), half = BOARD_HALF * s;
    const double depth = 0.5 * F->ext[2] + CLEARANCE * L; /* the front and back walls, from c */
    cJSON *arr = cJSON_CreateArray();
    double row = 0;
    rep->pegs = 0;
    for (int i = 0; i < ROWS; i++) {
        /* the first row's tops CLEARANCE below the object's box; odd rows shifted half a spacing */
        row = -(0.5 * F->ext[1] + CLEARANCE * L + r) - i * ROW_PITCH * L;
        double shift = (i % 2) * 0.5 * s;
        for (int j = -BOARD_HALF; j <= BOARD_HALF; j++) {
            double alpha = shift + j * s;
            if (fabs(alpha) + r > half - CLEARANCE * L) continue;
            double pa[3], pb[3];
            rk_motions_point(F, alpha, row, -depth, pa);
            rk_motions_point(F, alpha, row, depth, pb);
            cJSON *o = cJSON_CreateObject(), *cap = cJSON_AddObjectToObject(o, "capsule");
            cJSON_AddItemToObject(cap, "a", cJSON_CreateDoubleArray(pa, 3));
            cJSON_AddItemToObject(cap, "b", cJSON_CreateDoubleArray(pb, 3));
            cJSON_AddNumberToObject(cap, "radius", r);
            cJSON_AddItemToArray(arr, o);
            rep->pegs++;
        }
    }
    add_plane(arr, F, 0, row - ROW_PITCH * L, 0, F->u, 1);   /* the floor */
    add_plane(arr, F, -half, 0, 0, F->a, 1);                 /* the side walls */
    add_plane(arr, F, half, 0, 0, F->a, -1);
    add_plane(arr, F, 0, 0, -depth, F->b, 1);                /* the front and back */
    add_plane(arr, F, 0, 0, depth, F->b, -1);
    return arr;
}

int rk_motions_drum_surface(const rk_motions_frame *F, rk_surface *s, rk_motions_report *rep, rk_error *err)
{
    const int n = DRUM_SIDES;
    const double inner = rk_motions_drum_radius(F);
    const double corner = inner / cos(M_PI / n), half = inner;
    s->nv = 2 * n + 2;
    s->nf = 4 * n;
    s->X = malloc(sizeof(double) * 3 * (size_t)s->nv);
    s->tris = malloc(sizeof(int) * 3 * (size_t)s->nf);
    if (!s->X || !s->tris) {
        rk_surface_free(s);
        return rk_fail(err, "out of memory for the drum");
    }
    /* ring vertices k (back, beta = -half) and n + k (front); a flat side at the bottom */
    for (int k = 0; k < n; k++) {
        double th = -M_PI / 2 + M_PI / n + 2 * M_PI * k / n;
        rk_motions_point(F, corner * cos(th), corner * sin(th), -half, s->X + 3 * k);
        rk_motions_point(F, corner * cos(th), corner * sin(th), half, s->X + 3 * (n + k));
    }
    rk_motions_point(F, 0, 0, -half, s->X + 3 * (2 * n));
    rk_motions_point(F, 0, 0, half, s->X + 3 * (2 * n + 1));
    int *t = s->tris;
    for (int k = 0; k < n; k++) {
        int k1 = (k + 1) % n;
        int q[4][3] = {{k, k1, n + k1}, {k, n + k1, n + k}, {2 * n, k1, k}, {2 * n + 1, n + k, n + k1}};
        for (int j = 0; j < 4; j++, t += 3) t[0] = q[j][0], t[1] = q[j][1], t[2] = q[j][2];
    }
    rep->drum_radius = inner;
    /* closed and 2-manifold by construction; faced outward whichever way a, u, b turn */
    if (rk_surface_check_and_orient(s, "the drum", NULL, err)) {
        rk_surface_free(s);
        return -1;
    }
    return 0;
}

cJSON *rk_motions_drum(const rk_motions_frame *F, const char *file, double spin)
{
    cJSON *arr = cJSON_CreateArray(), *o = cJSON_CreateObject();
    cJSON *m = cJSON_AddObjectToObject(o, "mesh"), *tw = cJSON_AddObjectToObject(o, "twist");
    cJSON_AddStringToObject(m, "file", file);
    cJSON_AddItemToObject(tw, "axis", cJSON_CreateDoubleArray(F->b, 3));
    cJSON_AddNumberToObject(tw, "degrees_per_second", spin);
    cJSON_AddItemToObject(tw, "center", cJSON_CreateDoubleArray(F->c, 3));
    cJSON_AddItemToArray(arr, o);
    return arr;
}
