/* Tracked dots of calibrated views lifted to 3D markers on a rest surface (Sec. 7.5 films dots
 * on real objects; here their material points come from the model's own rest shape, since the
 * object is at rest in the first frame).
 *
 * Frame 0: each view's dots are ray-cast onto the rest surface (the nearest hit); dots of
 * different views whose hits lie within tol of each other are one marker. Every frame: the
 * marker's position is the point nearest, in least squares, to the rays of the views that still
 * track it (the midpoint method: sum_v (I - d_v d_v^T) (P - o_v) = 0), so calibration and
 * tracking errors spread over the views instead of trusting one. A dot seen by one view only
 * is dropped: one ray gives no depth, and the model's depth would be the answer fitted back. */
#include "video/video.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rk_video_markers_free(rk_video_markers *m)
{
    free(m->tri);
    free(m->bary);
    free(m->disp);
    memset(m, 0, sizeof *m);
}

/* Moller-Trumbore: the ray's parameter at triangle (a, b, c), barycentrics of b and c; -1 on a miss. */
static double ray_triangle(const double o[3], const double d[3], const double *a, const double *b, const double *c,
                           double *u, double *v)
{
    double e1[3], e2[3], p[3], q[3], s[3];
    for (int i = 0; i < 3; i++) e1[i] = b[i] - a[i], e2[i] = c[i] - a[i], s[i] = o[i] - a[i];
    p[0] = d[1] * e2[2] - d[2] * e2[1], p[1] = d[2] * e2[0] - d[0] * e2[2], p[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (fabs(det) < 1e-300) return -1;
    *u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    q[0] = s[1] * e1[2] - s[2] * e1[1], q[1] = s[2] * e1[0] - s[0] * e1[2], q[2] = s[0] * e1[1] - s[1] * e1[0];
    *v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    const double eps = 1e-9;
    if (*u < -eps || *v < -eps || *u + *v > 1 + eps) return -1;
    return (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
}

typedef struct {
    int tri;          /* -1: missed the surface */
    double bary[3], p[3];
} hit;

static hit cast(const rk_camera *c, const double px[2], const double *X, const int *tris, int ntris)
{
    double o[3], d[3], best = INFINITY;
    hit h = {-1, {0, 0, 0}, {0, 0, 0}};
    rk_camera_ray(c, px, o, d);
    for (int f = 0; f < ntris; f++) {
        const int *t = tris + 3 * f;
        double u, v, s = ray_triangle(o, d, X + 3 * t[0], X + 3 * t[1], X + 3 * t[2], &u, &v);
        if (s > 0 && s < best) {
            best = s;
            h.tri = f, h.bary[0] = 1 - u - v, h.bary[1] = u, h.bary[2] = v;
            for (int i = 0; i < 3; i++) h.p[i] = o[i] + s * d[i];
        }
    }
    return h;
}

/* The least-squares point of the rays of the views in member[] (-1: none) that track it at frame t. */
static int midpoint(const rk_tracks *tr, const rk_cameras *c, const int *member, int t, double P[3])
{
    double A[9] = {0}, b[3] = {0};
    int n = 0;
    for (int v = 0; v < tr->nviews; v++) {
        int i = member[v];
        if (i < 0 || (tr->v[v].lost[i] >= 0 && t >= tr->v[v].lost[i])) continue;
        double o[3], d[3];
        rk_camera_ray(&c->cam[v], tr->v[v].xy + (size_t)2 * (tr->T * i + t), o, d);
        for (int r = 0; r < 3; r++)
            for (int s = 0; s < 3; s++) {
                double m = (r == s) - d[r] * d[s];
                A[3 * r + s] += m, b[r] += m * o[s];
            }
        n++;
    }
    if (n < 2) return n;
    /* Cramer's rule on the 3 x 3 (symmetric positive definite when the rays are not parallel) */
    double det = A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) + A[2] * (A[3] * A[7] - A[4] * A[6]);
    if (!(fabs(det) > 1e-12)) return 0;
    for (int k = 0; k < 3; k++) {
        double M[9];
        memcpy(M, A, sizeof M);
        for (int r = 0; r < 3; r++) M[3 * r + k] = b[r];
        P[k] = (M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
                M[2] * (M[3] * M[7] - M[4] * M[6])) / det;
    }
    return n;
}

typedef struct {
    int member[RK_VIDEO_MAX_VIEWS];
    hit h[RK_VIDEO_MAX_VIEWS];
    int nmembers;
} marker;

static int check_views(const rk_tracks *tr, const rk_cameras *c, rk_error *err)
{
    if (tr->nviews != c->n)
        return rk_fail(err, "the tracks have %d views, the cameras %d (view i is filmed by camera i)", tr->nviews, c->n);
    if (tr->nviews < 2) return rk_fail(err, "one view gives no depth: at least two calibrated views are needed");
    for (int v = 0; v < c->n; v++)
        if (c->cam[v].w && (tr->v[v].w != c->cam[v].w || tr->v[v].h != c->cam[v].h)) /* w = 0: no "size" given */
            return rk_fail(err, "view %d: the frames are %d x %d pixels, camera %d (%s) is calibrated for %d x %d", v,
                           tr->v[v].w, tr->v[v].h, v, c->cam[v].name, c->cam[v].w, c->cam[v].h);
    return 0;
}

/* Frame 0's dots grouped into markers by their surface hits. */
static marker *group(const rk_tracks *tr, const rk_cameras *c, const double *X, const int *tris, int ntris, double tol,
                     int *nm, rk_video_markers *out, rk_error *err)
{
    int total = 0;
    for (int v = 0; v < tr->nviews; v++) total += tr->v[v].n;
    marker *m = rk_calloc((size_t)(total ? total : 1), sizeof(marker), err);
    if (!m) return NULL;
    *nm = 0;
    for (int v = 0; v < tr->nviews; v++) {
        out->dots[v] = tr->v[v].n;
        for (int i = 0; i < tr->v[v].n; i++) {
            hit h = cast(&c->cam[v], tr->v[v].xy + (size_t)2 * tr->T * i, X, tris, ntris);
            if (h.tri < 0) continue;
            out->hit++;
            int best = -1;
            double bd = tol;
            for (int j = 0; j < *nm; j++) {
                if (m[j].member[v] >= 0) continue;
                int f = 0;
                while (m[j].member[f] < 0) f++;
                double dd = sqrt(pow(h.p[0] - m[j].h[f].p[0], 2) + pow(h.p[1] - m[j].h[f].p[1], 2) +
                                 pow(h.p[2] - m[j].h[f].p[2], 2));
                if (dd <= bd) bd = dd, best = j;
            }
            if (best < 0) {
                best = (*nm)++;
                for (int w = 0; w < RK_VIDEO_MAX_VIEWS; w++) m[best].member[w] = -1;
            }
            m[best].member[v] = i, m[best].h[v] = h, m[best].nmembers++;
        }
    }
    return m;
}

int rk_video_lift(const rk_tracks *tr, const rk_cameras *c, const double *X, int nv, const int *tris, int ntris,
                  double tol, rk_video_markers *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    if (check_views(tr, c, err)) return -1;
    for (int i = 0; i < 3 * ntris; i++)
        if (tris[i] < 0 || tris[i] >= nv) return rk_fail(err, "surface triangle %d names vertex %d of %d", i / 3, tris[i], nv);
    int nm = 0, T = tr->T;
    out->nviews = tr->nviews;
    marker *m = group(tr, c, X, tris, ntris, tol, &nm, out, err);
    if (!m) return -1;
    out->T = T;
    out->tri = rk_calloc((size_t)3 * (nm ? nm : 1), sizeof(int), err);
    out->bary = rk_calloc((size_t)3 * (nm ? nm : 1), sizeof(double), err);
    out->disp = rk_calloc((size_t)3 * (nm ? nm : 1) * T, sizeof(double), err);
    double *P = rk_calloc((size_t)3 * T, sizeof(double), err), sq = 0;
    long nres = 0;
    if (!out->tri || !out->bary || !out->disp || !P) goto fail;
    for (int j = 0; j < nm; j++) {
        if (m[j].nmembers < 2) {
            out->single_view++;
            continue;
        }
        out->matched++;
        int t = 0;
        while (t < T && midpoint(tr, c, m[j].member, t, P + 3 * t) >= 2) t++;
        if (t < T) {
            out->lost++;
            continue;
        }
        /* the material point: the surface hit nearest the triangulated rest position */
        int bv = -1, k = out->k;
        double bd = INFINITY;
        for (int v = 0; v < tr->nviews; v++) {
            if (m[j].member[v] < 0) continue;
            double dd = sqrt(pow(m[j].h[v].p[0] - P[0], 2) + pow(m[j].h[v].p[1] - P[1], 2) + pow(m[j].h[v].p[2] - P[2], 2));
            if (dd < bd) bd = dd, bv = v;
            for (int w = 0; w < v; w++)
                if (m[j].member[w] >= 0)
                    out->match_max = fmax(out->match_max, sqrt(pow(m[j].h[v].p[0] - m[j].h[w].p[0], 2) +
                                                               pow(m[j].h[v].p[1] - m[j].h[w].p[1], 2) +
                                                               pow(m[j].h[v].p[2] - m[j].h[w].p[2], 2)));
        }
        for (int i = 0; i < 3; i++) {
            out->tri[3 * k + i] = tris[3 * m[j].h[bv].tri + i];
            out->bary[3 * k + i] = m[j].h[bv].bary[i];
        }
        for (t = 0; t < T; t++) {
            for (int v = 0; v < tr->nviews; v++) {
                int i = m[j].member[v];
                if (i < 0 || (tr->v[v].lost[i] >= 0 && t >= tr->v[v].lost[i])) continue;
                double px[2];
                const double *xy = tr->v[v].xy + (size_t)2 * (T * i + t);
                rk_camera_project(&c->cam[v], P + 3 * t, px);
                double r = hypot(px[0] - xy[0], px[1] - xy[1]);
                sq += r * r, nres++;
                out->reproj_max = fmax(out->reproj_max, r);
            }
        }
        out->k++;
        /* the positions marker by marker for now; made frame-major displacements below */
        memcpy(out->disp + (size_t)3 * T * k, P, sizeof(double) * 3 * (size_t)T);
    }
    out->triangulated = out->k;
    out->reproj_rms = nres ? sqrt(sq / (double)nres) : 0;
    /* marker-major (3 T per marker) to frame-major (3 k per frame), displacements from frame 0 */
    double *d = rk_calloc((size_t)3 * (out->k ? out->k : 1) * T, sizeof(double), err);
    if (!d) goto fail;
    for (int k = 0; k < out->k; k++)
        for (int t = 0; t < T; t++)
            for (int i = 0; i < 3; i++)
                d[(size_t)3 * (out->k * t + k) + i] = out->disp[(size_t)3 * (T * k + t) + i] - out->disp[(size_t)3 * T * k + i];
    free(out->disp);
    out->disp = d;
    free(P);
    free(m);
    if (!out->k) {
        rk_video_markers_free(out);
        return rk_fail(err, "no marker left to fit: %d dots hit the rest surface, %d markers matched across views "
                       "(within %g), %d seen by one view only, %d lost by all but one view", out->hit, out->matched, tol,
                       out->single_view, out->lost);
    }
    return 0;
fail:
    free(P);
    free(m);
    rk_video_markers_free(out);
    return -1;
}
