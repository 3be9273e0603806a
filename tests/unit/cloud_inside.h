/* Shared by the tests of several objects colliding (in the reduced simulator and the runtime):
 * whether a point lies inside another object's closed surface (its boundary, or a cloud's voxel
 * proxy, deformed), by the parity of the crossings of a long segment from the point with that
 * surface's triangles, each crossing decided exactly (rk_segment_triangle_intersect); and the
 * lattices of points the cloud tests drop on each other. */
#ifndef RK_TEST_CLOUD_INSIDE_H
#define RK_TEST_CLOUD_INSIDE_H

#include <math.h>
#include <stdio.h>

#include "contact/contact.h"

/* The boundary triangles (tris, over positions x) of one object: their indices and bounding box. */
typedef struct {
    const int *tris;
    int *sel, n;
    double lo[3], hi[3];
} cloud_surface;

/* The triangles of tris (nf) whose first vertex lies in [v0, v1), and their box at positions x. */
static inline int cloud_surface_init(cloud_surface *s, const int *tris, int nf, int v0, int v1)
{
    s->tris = tris;
    s->n = 0;
    s->sel = malloc(sizeof(int) * (size_t)(nf > 0 ? nf : 1));
    if (!s->sel) return -1;
    for (int t = 0; t < nf; t++)
        if (tris[3 * t] >= v0 && tris[3 * t] < v1) s->sel[s->n++] = t;
    return 0;
}

static inline void cloud_surface_box(cloud_surface *s, const double *x)
{
    for (int a = 0; a < 3; a++) s->lo[a] = INFINITY, s->hi[a] = -INFINITY;
    for (int k = 0; k < s->n; k++)
        for (int c = 0; c < 3; c++)
            for (int a = 0; a < 3; a++) {
                double v = x[3 * s->tris[3 * s->sel[k] + c] + a];
                s->lo[a] = fmin(s->lo[a], v), s->hi[a] = fmax(s->hi[a], v);
            }
}

/* Whether p is inside s at positions x (cloud_surface_box called at x first). The segment runs off
 * every axis, past the box, so it never runs along a lattice row or a voxel face. */
static inline int cloud_surface_inside(const cloud_surface *s, const double *x, const double *p)
{
    for (int a = 0; a < 3; a++)
        if (p[a] < s->lo[a] || p[a] > s->hi[a]) return 0;
    double L = 2 * (s->hi[0] - s->lo[0]) + 1, q[3] = {p[0] + L, p[1] + 0.00123 * L, p[2] + 0.00071 * L};
    double slo[3], shi[3];
    for (int a = 0; a < 3; a++) slo[a] = fmin(p[a], q[a]), shi[a] = fmax(p[a], q[a]);
    int count = 0;
    for (int k = 0; k < s->n; k++) {
        const int *T = s->tris + 3 * s->sel[k];
        const double *A = x + 3 * T[0], *B = x + 3 * T[1], *C = x + 3 * T[2];
        int apart = 0; /* the triangle's box and the segment's do not meet: no crossing */
        for (int a = 0; a < 3 && !apart; a++)
            apart = fmax(A[a], fmax(B[a], C[a])) < slo[a] || fmin(A[a], fmin(B[a], C[a])) > shi[a];
        if (!apart) count += rk_segment_triangle_intersect(p, q, A, B, C);
    }
    return count % 2;
}

/* An nx x ny x nz lattice of points h apart from corner o, as an ASCII PLY at path. */
static inline int cloud_write_lattice(const char *path, int nx, int ny, int nz, double h, const double o[3])
{
    FILE *fp = fopen(path, "w");
    if (!fp) return -1;
    fprintf(fp, "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
            nx * ny * nz);
    for (int i = 0; i < nx; i++)
        for (int j = 0; j < ny; j++)
            for (int k = 0; k < nz; k++) fprintf(fp, "%g %g %g\n", o[0] + h * i, o[1] + h * j, o[2] + h * k);
    return fclose(fp);
}

/* The two-cloud scene of test_pipeline_clouds_collide and test_runtime_objects: a slab of 11 x 3 x 11
 * points 4 cm apart lying over the plane y = -0.05, and a block of 5 x 5 x 5 such points whose corner
 * is at (0.1, block_y, 0.1), written to the PLY files slab and block; `damping` is JSON members
 * put before the obstacles ("" or "\"damping\": {...},"). The scene's JSON into json (n bytes). */
static inline int cloud_slab_block_scene(char *json, size_t n, const char *slab, const char *block, double block_y,
                                         const char *damping)
{
    const double o1[3] = {0, 0, 0}, o2[3] = {0.1, block_y, 0.1};
    if (cloud_write_lattice(slab, 11, 3, 11, 0.04, o1) || cloud_write_lattice(block, 5, 5, 5, 0.04, o2)) return -1;
    int w = snprintf(json, n,
                     "{\"objects\": [{\"mesh\": {\"points\": \"%s\"}, \"material\": {\"model\": \"neohookean\", \"young\": 1e5,"
                     " \"poisson\": 0.4, \"density\": 1000}},"
                     " {\"mesh\": {\"points\": \"%s\"}, \"material\": {\"model\": \"neohookean\", \"young\": 5e4, \"poisson\": 0.4,"
                     " \"density\": 1000}}],"
                     " \"gravity\": [0, -9.81, 0], %s\"obstacles\": [{\"plane\": {\"point\": [0, -0.05, 0], \"normal\": [0, 1, 0]}}],"
                     " \"contact\": {\"dhat\": 0.002}, \"time\": {\"step\": 0.01, \"duration\": 0.5},"
                     " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 2, \"kernels\": 40}}",
                     slab, block, damping);
    return w > 0 && (size_t)w < n ? 0 : -1;
}

static inline void cloud_surface_free(cloud_surface *s)
{
    free(s->sel);
    s->sel = NULL;
}

#endif
