/* render_dots: a synthetic video of dot markers on a deforming box mesh, for romkit track's tests
 * (tests/integration/cli_track.sh). A test tool rather than a romkit subcommand: its shading,
 * texture and dot painting are made up to give Lucas-Kanade gradients, nothing a user's footage
 * has, so it stays out of the shipped command line.
 *
 *   render_dots --snapshots S.npy --box SX,SY,SZ --cells CX,CY,CZ --cameras CAMS.json
 *               --dots V.txt --radius R --out DIR          (frames DIR/cam<v>/<t>.png, 4 digits)
 *   render_dots --snapshots S.npy ... --check TRACKS.json  (the tracks against the projected truth)
 *   render_dots --snapshots S.npy ... --truth TRACKS.json  (the projected truth as tracks)
 *   render_dots --occlude 'DIR/%04d.png' --rect X0,Y0,X1,Y1 --from F --frames T  (a flat patch from F on)
 *
 * The mesh is rk_mesh_box's (the scene's box, same vertex order); S.npy its T x n x 3 positions.
 * Each listed surface vertex carries a dark disc of radius R painted in material coordinates (so
 * it deforms with the surface); the surface has a smooth material texture under Lambert shading,
 * the background a fixed one. Rasterized per boundary triangle at 2 x 2 samples per pixel with
 * perspective-correct barycentrics and a depth buffer; a disc's rim is anti-aliased over one
 * sample. --check prints, per view, the dots found within 0.5 px of a tracked dot in frame 0,
 * the worst frame-0 distance, and the worst distance over all frames of the tracks kept. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "mesh/mesh.h"
#include "video/video.h"

#define SS 2 /* samples per pixel each way */

static double texture(const double *X)
{
    return 0.72 + 0.1 * sin(41 * X[0] + 3 * X[2]) * cos(37 * X[1] + 29 * X[2]) + 0.06 * sin(13 * X[0] - 23 * X[1]) +
           0.05 * cos(61 * X[2] + 17 * X[0]);
}

static double background(double x, double y) { return 0.55 + 0.08 * sin(x / 9.0) * cos(y / 7.0) + 0.04 * sin((x + y) / 23.0); }

typedef struct {
    const rk_mesh *mesh;
    const int *tris;
    int ntris;
    const double *X0;     /* rest positions */
    const int *dot;       /* dot vertices */
    int ndots;
    double radius;
} scene;

/* One frame of view c (positions x) into im. */
static void render(const scene *s, const rk_camera *c, const double *x, rk_image *im, float *hi, float *depth,
                   const float *bg)
{
    int W = c->w * SS, H = c->h * SS;
    rk_camera k = *c; /* the supersampled camera: sample (2u + 1/2) is pixel u's centre at SS = 2 */
    k.K[0] *= SS, k.K[1] *= SS, k.K[4] *= SS;
    k.K[2] = SS * k.K[2] + 0.5 * (SS - 1), k.K[5] = SS * k.K[5] + 0.5 * (SS - 1);
    memcpy(hi, bg, sizeof(float) * (size_t)W * H);
    for (int p = 0; p < W * H; p++) depth[p] = INFINITY;
    double light[3] = {0.3, 0.8, 0.52}, ln = sqrt(0.09 + 0.64 + 0.2704);
    for (int f = 0; f < s->ntris; f++) {
        const int *t = s->tris + 3 * f;
        double px[3][2], z[3];
        for (int a = 0; a < 3; a++) z[a] = rk_camera_project(&k, x + 3 * t[a], px[a]);
        if (z[0] <= 0 || z[1] <= 0 || z[2] <= 0) continue;
        double area = (px[1][0] - px[0][0]) * (px[2][1] - px[0][1]) - (px[2][0] - px[0][0]) * (px[1][1] - px[0][1]);
        if (fabs(area) < 1e-12) continue;
        /* Lambert shading from the deformed triangle's normal (either side lit) */
        const double *A = x + 3 * t[0], *B = x + 3 * t[1], *C = x + 3 * t[2];
        double e1[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]}, e2[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]};
        double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        double shade = 0.7 + 0.3 * fabs(n[0] * light[0] + n[1] * light[1] + n[2] * light[2]) / (ln * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]));
        int x0 = (int)floor(fmin(px[0][0], fmin(px[1][0], px[2][0]))), x1 = (int)ceil(fmax(px[0][0], fmax(px[1][0], px[2][0])));
        int y0 = (int)floor(fmin(px[0][1], fmin(px[1][1], px[2][1]))), y1 = (int)ceil(fmax(px[0][1], fmax(px[1][1], px[2][1])));
        x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0, x1 = x1 >= W ? W - 1 : x1, y1 = y1 >= H ? H - 1 : y1;
        for (int v = y0; v <= y1; v++)
            for (int u = x0; u <= x1; u++) {
                double l[3];
                for (int a = 0; a < 3; a++) {
                    const double *p = px[(a + 1) % 3], *q = px[(a + 2) % 3];
                    l[a] = ((q[0] - p[0]) * (v - p[1]) - (u - p[0]) * (q[1] - p[1])) / area;
                }
                if (l[0] < -1e-9 || l[1] < -1e-9 || l[2] < -1e-9) continue;
                /* perspective-correct: barycentrics weighted by 1/z */
                double w[3], sw = 0;
                for (int a = 0; a < 3; a++) w[a] = l[a] / z[a], sw += w[a];
                double zz = 1 / sw;
                if (zz >= depth[v * W + u]) continue;
                depth[v * W + u] = (float)zz;
                double X[3] = {0, 0, 0};
                for (int a = 0; a < 3; a++)
                    for (int d = 0; d < 3; d++) X[d] += w[a] / sw * s->X0[3 * t[a] + d];
                double cover = 0, sample_len = zz / k.K[0]; /* a sample's size on the surface, about */
                double reach = (s->radius + sample_len) * (s->radius + sample_len);
                for (int i = 0; i < s->ndots; i++) {
                    const double *D = s->X0 + 3 * s->dot[i];
                    double d2 = (X[0] - D[0]) * (X[0] - D[0]) + (X[1] - D[1]) * (X[1] - D[1]) + (X[2] - D[2]) * (X[2] - D[2]);
                    if (d2 < reach) cover = fmax(cover, fmin(1, fmax(0, (s->radius - sqrt(d2)) / sample_len + 0.5)));
                }
                hi[v * W + u] = (float)((1 - cover) * shade * texture(X) + cover * 0.1);
            }
    }
    for (int v = 0; v < c->h; v++)
        for (int u = 0; u < c->w; u++) {
            double a = 0;
            for (int j = 0; j < SS; j++)
                for (int i = 0; i < SS; i++) a += hi[(SS * v + j) * W + SS * u + i];
            im->px[v * c->w + u] = (float)(a / (SS * SS));
        }
}

static int read_ints(const char *path, int **v, int *n, int nv)
{
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    *v = calloc((size_t)nv, sizeof(int));
    *n = 0;
    int x;
    while (*n < nv && fscanf(f, "%d", &x) == 1) (*v)[(*n)++] = x;
    fclose(f);
    return *n ? 0 : -1;
}

/* The projected dot vertices of every view and frame as tracks (a perfect tracker's output). */
static int truth(const char *path, const rk_cameras *cams, const double *S, int T, int nv, const int *dot, int ndots)
{
    rk_tracks tr;
    rk_error err = {{0}};
    memset(&tr, 0, sizeof tr);
    tr.T = T, tr.nviews = cams->n;
    for (int v = 0; v < cams->n; v++) {
        rk_view_tracks *w = &tr.v[v];
        snprintf(w->source, sizeof w->source, "render_dots truth");
        w->w = cams->cam[v].w, w->h = cams->cam[v].h, w->n = ndots, w->dots.kept = ndots;
        w->xy = calloc((size_t)2 * T * ndots, sizeof(double));
        w->lost = calloc((size_t)ndots, sizeof(int));
        for (int i = 0; i < ndots; i++) {
            w->lost[i] = -1;
            for (int t = 0; t < T; t++) rk_camera_project(&cams->cam[v], S + (size_t)3 * nv * t + 3 * dot[i], w->xy + (size_t)2 * (T * i + t));
        }
    }
    int rc = rk_tracks_save(path, &tr, &err);
    if (rc) fprintf(stderr, "render_dots: %s\n", err.msg);
    rk_tracks_free(&tr);
    return rc ? 1 : 0;
}

/* Frame-0 dots of each view against the projected truth, and the kept tracks over all frames. */
static int check(const char *path, const rk_cameras *cams, const double *S, int T, int nv, const int *dot, int ndots)
{
    rk_tracks tr;
    rk_error err = {{0}};
    if (rk_tracks_load(path, &tr, &err)) {
        fprintf(stderr, "render_dots: %s\n", err.msg);
        return 1;
    }
    int bad = 0;
    for (int v = 0; v < tr.nviews && v < cams->n; v++) {
        int found = 0, visible = 0;
        double worst0 = 0, worst = 0;
        for (int i = 0; i < ndots; i++) {
            double px[2], best = INFINITY;
            rk_camera_project(&cams->cam[v], S + 3 * dot[i], px);
            if (px[0] < 0 || px[1] < 0 || px[0] > cams->cam[v].w - 1 || px[1] > cams->cam[v].h - 1) continue;
            visible++;
            int bj = -1;
            for (int j = 0; j < tr.v[v].n; j++) {
                const double *q = tr.v[v].xy + (size_t)2 * tr.T * j;
                double d = hypot(q[0] - px[0], q[1] - px[1]);
                if (d < best) best = d, bj = j;
            }
            if (best > 0.5) continue;
            found++;
            worst0 = fmax(worst0, best);
            int len = tr.v[v].lost[bj] < 0 ? tr.T : tr.v[v].lost[bj];
            double off[2] = {0, 0};
            for (int t = 0; t < len && t < T; t++) {
                rk_camera_project(&cams->cam[v], S + (size_t)3 * nv * t + 3 * dot[i], px);
                const double *q = tr.v[v].xy + (size_t)2 * (tr.T * bj + t);
                if (!t) off[0] = q[0] - px[0], off[1] = q[1] - px[1];
                /* the motion's error: frame 0's offset (the centroid's) taken out, as the lift does */
                double e = hypot(q[0] - px[0] - off[0], q[1] - px[1] - off[1]);
                worst = fmax(worst, e);
                if (getenv("RENDER_DOTS_TRACE") && t % 10 == 0) printf("trace view %d dot %d frame %d: %.3f px\n", v, i, t, e);
            }
        }
        printf("view %d: %d of %d dots found within 0.5 px in frame 0 (worst %.3f px), %d tracks in all; "
               "worst error of the tracked motion (from frame 0) over %d frames %.3f px\n", v, found, visible, worst0, tr.v[v].n, tr.T, worst);
        bad |= found != ndots;
    }
    rk_tracks_free(&tr);
    return bad;
}

/* --occlude PATTERN --rect X0,Y0,X1,Y1 --from F --frames T: frames F..T-1 of PATTERN painted over by a
 * flat light rectangle (something passing in front of the camera), in place. */
static int occlude(const char *pattern, const char *rect, int from, int T)
{
    int r[4];
    rk_error err = {{0}};
    if (sscanf(rect, "%d,%d,%d,%d", r, r + 1, r + 2, r + 3) != 4) return 2;
    for (int t = from; t < T; t++) {
        char path[4096];
        rk_image im;
        snprintf(path, sizeof path, pattern, t);
        if (rk_image_load(path, &im, &err)) {
            fprintf(stderr, "render_dots: %s\n", err.msg);
            return 1;
        }
        for (int y = r[1]; y <= r[3] && y < im.h; y++)
            for (int x = r[0]; x <= r[2] && x < im.w; x++)
                if (x >= 0 && y >= 0) im.px[y * im.w + x] = 0.9f;
        int rc = rk_image_save_png(path, &im, &err);
        rk_image_free(&im);
        if (rc) {
            fprintf(stderr, "render_dots: %s\n", err.msg);
            return 1;
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 9 && !strcmp(argv[1], "--occlude") && !strcmp(argv[3], "--rect") && !strcmp(argv[5], "--from") &&
        !strcmp(argv[7], "--frames"))
        return occlude(argv[2], argv[4], atoi(argv[6]), atoi(argv[8]));
    const char *snap = NULL, *box = NULL, *cells = NULL, *camf = NULL, *dots = NULL, *out = NULL, *chk = NULL, *tru = NULL;
    double radius = 0.02;
    for (int i = 1; i + 1 < argc; i += 2) {
        const char *a = argv[i], *v = argv[i + 1];
        if (!strcmp(a, "--snapshots")) snap = v;
        else if (!strcmp(a, "--box")) box = v;
        else if (!strcmp(a, "--cells")) cells = v;
        else if (!strcmp(a, "--cameras")) camf = v;
        else if (!strcmp(a, "--dots")) dots = v;
        else if (!strcmp(a, "--radius")) radius = atof(v);
        else if (!strcmp(a, "--out")) out = v;
        else if (!strcmp(a, "--check")) chk = v;
        else if (!strcmp(a, "--truth")) tru = v;
        else {
            fprintf(stderr, "render_dots: unknown option %s\n", a);
            return 2;
        }
    }
    double size[3];
    int cell[3];
    if (!snap || !box || !cells || !camf || !dots || (!out && !chk && !tru) || sscanf(box, "%lf,%lf,%lf", size, size + 1, size + 2) != 3 ||
        sscanf(cells, "%d,%d,%d", cell, cell + 1, cell + 2) != 3) {
        fprintf(stderr, "usage: render_dots --snapshots S.npy --box SX,SY,SZ --cells CX,CY,CZ --cameras C.json --dots V.txt "
                        "[--radius R] (--out DIR | --check TRACKS.json)\n");
        return 2;
    }
    rk_error err = {{0}};
    rk_mesh mesh;
    rk_cameras cams;
    double *S = NULL;
    int ndim, *tris = NULL, ntris = 0, *dot = NULL, ndots = 0;
    long shape[4];
    if (rk_mesh_box(size, cell, &mesh, &err) || rk_mesh_boundary(&mesh, &tris, &ntris, &err) ||
        rk_cameras_load(camf, &cams, &err) || rk_npy_read(snap, &S, &ndim, shape, &err)) {
        fprintf(stderr, "render_dots: %s\n", err.msg);
        return 1;
    }
    if (ndim != 3 || shape[1] != mesh.nv || shape[2] != 3 || read_ints(dots, &dot, &ndots, mesh.nv)) {
        fprintf(stderr, "render_dots: %s is not T x %d x 3, or %s lists no vertex\n", snap, mesh.nv, dots);
        return 1;
    }
    int T = (int)shape[0];
    if (chk) return check(chk, &cams, S, T, mesh.nv, dot, ndots);
    if (tru) return truth(tru, &cams, S, T, mesh.nv, dot, ndots);
    scene s = {&mesh, tris, ntris, mesh.X, dot, ndots, radius};
    for (int v = 0; v < cams.n; v++) {
        char dir[4096], path[4200];
        snprintf(dir, sizeof dir, "%s/cam%d", out, v);
        mkdir(out, 0777);
        mkdir(dir, 0777);
        rk_image im;
        rk_image_alloc(&im, cams.cam[v].w, cams.cam[v].h, &err);
        size_t n = (size_t)cams.cam[v].w * cams.cam[v].h * SS * SS;
        float *hi = calloc(n, sizeof(float)), *depth = calloc(n, sizeof(float)), *bg = calloc(n, sizeof(float));
        int W = cams.cam[v].w * SS;
        for (size_t p = 0; p < n; p++) bg[p] = (float)background((double)(p % W) / SS, (double)(p / W) / SS); /* fixed */
        for (int t = 0; t < T; t++) {
            render(&s, &cams.cam[v], S + (size_t)3 * mesh.nv * t, &im, hi, depth, bg);
            snprintf(path, sizeof path, "%s/%04d.png", dir, t);
            if (rk_image_save_png(path, &im, &err)) {
                fprintf(stderr, "render_dots: %s\n", err.msg);
                return 1;
            }
        }
        free(hi);
        free(depth);
        free(bg);
        rk_image_free(&im);
    }
    printf("render_dots: %d frames of %d views, %d dots\n", T, cams.n, ndots);
    free(S);
    free(tris);
    free(dot);
    rk_mesh_free(&mesh);
    return 0;
}
