/* rk_dmd_markers_load (dmd.h): the sparse-to-dense step of Sec. 7.5 from files. The paper's
 * neural fields evaluate the modes anywhere; here the modes are the scene's linear modes and the
 * markers are tracked mesh vertices, so the least squares of rk_koopman_marker_coords gives each
 * frame's modal coordinates and the modes give every vertex. */
#include "pipeline/dmd.h"

#include <cblas.h>
#include <errno.h>
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "basis/basis.h"
#include "koopman/koopman.h"
#include "mesh/mesh.h"
#include "pipeline/method_fixed.h"

void rk_dmd_markers_free(rk_dmd_markers *m)
{
    free(m->X);
    free(m->vertex_mass);
    free(m->u);
    free(m->Phi);
    free(m->Pin);
    free(m->weight);
    free(m->tris);
    rk_video_markers_free(&m->video);
    memset(m, 0, sizeof *m);
}

/* One line's vertex index into v[*k]: a whole number in 0..nv-1, not listed before. */
static int vertex_line(const char *path, int line, const char *text, int nv, int *v, int *first_line, int *k,
                       rk_error *err)
{
    char *end;
    errno = 0;
    long x = strtol(text, &end, 10);
    while (*end == ' ' || *end == '\t') end++;
    if (end == text || *end || errno) return rk_fail(err, "%s line %d: '%.40s' is not a vertex index", path, line, text);
    if (x < 0 || x >= nv) return rk_fail(err, "%s line %d: vertex %ld is outside 0..%d (the scene's mesh)", path, line, x, nv - 1);
    for (int i = 0; i < *k; i++)
        if (v[i] == x) return rk_fail(err, "%s line %d: vertex %ld is listed twice (line %d)", path, line, x, first_line[i]);
    first_line[*k] = line;
    v[(*k)++] = (int)x;
    return 0;
}

/* The tracked vertices, one index per line (blank lines and lines starting with # skipped). */
static int read_vertices(const char *path, int nv, int **vertex, int *k, rk_error *err)
{
    FILE *f = fopen(path, "r");
    if (!f) return rk_fail(err, "--marker-vertices: cannot open %s", path);
    int *v = rk_calloc((size_t)nv, sizeof(int), err), *lines = rk_calloc((size_t)nv, sizeof(int), err), rc = 0;
    char buf[256];
    *k = 0;
    for (int line = 1; v && lines && !rc && fgets(buf, sizeof buf, f); line++) {
        char *p = buf;
        while (*p == ' ' || *p == '\t') p++;
        p[strcspn(p, "\r\n")] = 0;
        if (*p == '#' || !*p) continue;
        if (*k == nv) rc = rk_fail(err, "%s line %d: more indices than the mesh's %d vertices", path, line, nv);
        else rc = vertex_line(path, line, p, nv, v, lines, k, err);
    }
    fclose(f);
    free(lines);
    if (!v) return -1;
    if (!rc && !*k) rc = rk_fail(err, "%s lists no vertex", path);
    if (rc) free(v);
    else *vertex = v;
    return rc ? -1 : 0;
}

/* A T x nv x 3 recording of every vertex: the listed vertices' columns, as a tracker would give them. */
static int pick_columns(double **x, int T, int nv, const int *vertex, int k, rk_error *err)
{
    double *p = rk_calloc((size_t)3 * k * T, sizeof(double), err);
    if (!p) return -1;
    for (int t = 0; t < T; t++)
        for (int i = 0; i < k; i++)
            memcpy(p + (size_t)3 * (k * t + i), *x + (size_t)3 * ((size_t)nv * t + vertex[i]), 3 * sizeof(double));
    free(*x);
    *x = p;
    return 0;
}

/* T x k x 3 marker positions (or T x nv x 3, every vertex: the listed ones taken) into
 * displacements (3k x T) from the tracked vertices' rest positions. */
static int read_markers(const char *path, int nv, const int *vertex, int k, const double *X, double **disp, int *T,
                        rk_error *err)
{
    int ndim;
    long shape[4] = {0};
    if (rk_npy_read(path, disp, &ndim, shape, err)) return rk_error_prefix(err, "--markers");
    if (ndim != 3 || (shape[1] != k && shape[1] != nv) || shape[2] != 3 || shape[0] < 3) {
        free(*disp);
        *disp = NULL;
        return rk_fail(err, "--markers %s: shape %ld x %ld x %ld (%d dimensions); expected T x %d x 3 positions of the %d "
                       "listed vertices (or T x %d x 3, every vertex of the scene), T >= 3", path, shape[0], shape[1],
                       shape[2], ndim, k, k, nv);
    }
    *T = (int)shape[0];
    if (shape[1] != k && pick_columns(disp, *T, nv, vertex, k, err)) return -1;
    for (size_t i = 0; i < (size_t)3 * k * *T; i++) {
        size_t t = i / (3 * (size_t)k), m = i / 3 % k;
        if (!isfinite((*disp)[i])) {
            free(*disp);
            *disp = NULL;
            return rk_fail(err, "--markers %s: frame %zu, marker %zu (vertex %d) is not finite", path, t, m, vertex[m]);
        }
        (*disp)[i] -= X[3 * (size_t)vertex[m] + i % 3];
    }
    return 0;
}

/* Pin = (Phi^T M Phi)^-1 Phi^T M (M the lumped masses): a left inverse of Phi, and the modal force
 * of an acceleration for Eq. 19's impulses (Phi^T M a in M-orthonormal modes). */
static int left_inverse(rk_dmd_markers *m, rk_error *err)
{
    int n3 = 3 * m->nv, b = m->b;
    double *G = rk_calloc((size_t)b * b, sizeof(double), err);
    m->Pin = rk_calloc((size_t)b * n3, sizeof(double), err);
    if (!G || !m->Pin) {
        free(G);
        return -1;
    }
    for (int i = 0; i < n3; i++)
        for (int j = 0; j < b; j++) m->Pin[(size_t)b * i + j] = m->Phi[(size_t)n3 * j + i] * m->vertex_mass[i / 3];
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, b, b, n3, 1.0, m->Pin, b, m->Phi, n3, 0.0, G, b);
    int info = LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', b, n3, G, b, m->Pin, b);
    free(G);
    return info ? rk_fail(err, "the %d modes' mass matrix is singular (LAPACK dposv info %d)", b, info) : 0;
}

/* omega_j / omega_1 = sqrt(lambda_j / lambda_1) for K v = lambda M v, lambda_1 the first nonzero
 * eigenvalue (a free body's rigid modes weigh as the first elastic one). */
static double *mode_weights(const rk_basis *B, rk_error *err)
{
    if (B->nvalues < B->r || B->nzero >= B->r || !(B->values[B->nzero] > 0)) {
        rk_fail(err, "the modes carry no positive eigenvalue to weigh the marker ridge by");
        return NULL;
    }
    double *w = rk_calloc((size_t)B->r, sizeof(double), err), l1 = B->values[B->nzero];
    for (int j = 0; w && j < B->r; j++) w[j] = sqrt(fmax(B->values[j], l1) / l1);
    return w;
}

/* The scene's first b linear modes, their weights, rest positions, masses and surface. */
static int scene_modes(const char *path, int b, rk_dmd_markers *m, rk_error *err)
{
    rk_scene scene;
    rk_scene_sim sim;
    if (rk_scene_load(path, &scene, err)) return -1;
    int rc = -1;
    if (rk_scene_build(&scene, &sim, err)) goto done_scene;
    rk_basis_options bo;
    rk_basis_default_options(&bo);
    bo.type = RK_BASIS_MODES;
    bo.size = b;
    rk_basis B;
    rk_scene_basis_info info;
    if (rk_scene_basis(&scene, &sim, &bo, NULL, 0, &B, &info, err)) goto done_sim;
    rk_scene_basis_info_free(&info);
    m->nv = sim.mesh.nv;
    m->b = B.r;
    if (!(m->weight = mode_weights(&B, err))) {
        rk_basis_free(&B);
        goto done_sim;
    }
    m->Phi = B.U; /* taken over */
    B.U = NULL;
    rk_basis_free(&B);
    m->X = rk_calloc((size_t)3 * m->nv, sizeof(double), err);
    m->vertex_mass = rk_calloc((size_t)m->nv, sizeof(double), err);
    if (m->X && m->vertex_mass && !rk_mesh_boundary(&sim.mesh, &m->tris, &m->ntris, err)) {
        memcpy(m->X, sim.mesh.X, sizeof(double) * 3 * (size_t)m->nv);
        memcpy(m->vertex_mass, sim.fem.vertex_mass, sizeof(double) * (size_t)m->nv);
        m->ntets = sim.mesh.nt;
        rc = m->b == b ? 0 : rk_fail(err, "%s: %d linear modes asked, %d found", path, b, m->b);
    }
done_sim:
    rk_scene_sim_free(&sim);
done_scene:
    rk_scene_free(&scene);
    return rc ? rk_error_prefix(err, "--scene") : 0;
}

/* max_t |S Phi q_t - m_t| / max_t |m_t|: how far b modes are from the tracked motion (S the
 * markers' rows: one vertex each, or with bary a barycentric mix of three). */
static double misfit(const rk_dmd_markers *m, const int *tri, const double *bary, const double *disp, const double *q)
{
    int n3 = 3 * m->nv, k = m->k, per = bary ? 3 : 1;
    double worst = 0, scale = 0;
    for (int t = 0; t < m->T; t++) {
        double e = 0, s = 0;
        for (int i = 0; i < k; i++)
            for (int c = 0; c < 3; c++) {
                double v = 0, d = disp[(size_t)3 * k * t + 3 * i + c];
                for (int a = 0; a < per; a++)
                    for (int j = 0; j < m->b; j++)
                        v += (bary ? bary[3 * i + a] : 1) * m->Phi[(size_t)n3 * j + 3 * tri[per * i + a] + c] *
                             q[(size_t)m->b * t + j];
                e += (v - d) * (v - d), s += d * d;
            }
        worst = fmax(worst, sqrt(e)), scale = fmax(scale, sqrt(s));
    }
    return scale > 0 ? worst / scale : 0;
}

/* The one fit of both entries: each frame's modal coordinates from the markers (k points: tri and
 * bary as rk_koopman_surface_coords takes them; disp 3k x T displacements), the dense frames. */
static int fit_markers(rk_dmd_markers *out, const int *tri, const double *bary, const double *disp, double ridge,
                       rk_error *err)
{
    int n3 = 3 * out->nv, b = out->b;
    if (left_inverse(out, err)) return -1;
    double *q = rk_calloc((size_t)b * out->T, sizeof(double), err);
    out->u = rk_calloc((size_t)n3 * out->T, sizeof(double), err);
    int rc = -1;
    if (q && out->u &&
        !rk_koopman_surface_coords(out->Phi, n3, b, tri, bary, out->k, disp, out->T, ridge, out->weight, q, err)) {
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n3, out->T, b, 1.0, out->Phi, n3, q, b, 0.0, out->u, n3);
        out->ridge = ridge;
        out->marker_misfit = misfit(out, tri, bary, disp, q);
        rc = 0;
    }
    free(q);
    return rc;
}

int rk_dmd_markers_load(const char *scene_path, const char *markers_path, const char *vertices_path, int b,
                     double ridge, rk_dmd_markers *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    int *vertex = NULL, rc = -1;
    double *disp = NULL;
    if (!scene_modes(scene_path, b, out, err) && !read_vertices(vertices_path, out->nv, &vertex, &out->k, err) &&
        !read_markers(markers_path, out->nv, vertex, out->k, out->X, &disp, &out->T, err))
        rc = fit_markers(out, vertex, NULL, disp, ridge, err);
    free(vertex);
    free(disp);
    if (rc) rk_dmd_markers_free(out);
    return rc;
}

int rk_dmd_markers_video(const char *scene_path, const char *tracks_path, const char *cameras_path, int b, double ridge,
                         double tol, rk_dmd_markers *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    rk_tracks tr;
    rk_cameras cams;
    int rc = -1;
    if (rk_tracks_load(tracks_path, &tr, err)) return rk_error_prefix(err, "--tracks");
    if (cameras_path ? rk_cameras_load(cameras_path, &cams, err) : !tr.calibrated) {
        if (cameras_path) rk_error_prefix(err, "--cameras");
        else rk_fail(err, "--tracks %s carries no cameras (tracked with --view): give --cameras", tracks_path);
        goto done;
    }
    if (!cameras_path) cams = tr.cams;
    if (scene_modes(scene_path, b, out, err)) goto done;
    if (tol <= 0) tol = 0.01 * rk_points_diagonal(out->X, out->nv);
    rk_video_markers *v = &out->video;
    if (rk_video_lift(&tr, &cams, out->X, out->nv, out->tris, out->ntris, tol, v, err)) {
        rk_error_prefix(err, "--tracks %s with %s%s", tracks_path, cameras_path ? "--cameras " : "its cameras",
                        cameras_path ? cameras_path : "");
        goto done;
    }
    out->from_video = 1;
    out->k = v->k;
    out->T = v->T;
    if (out->T < 3) {
        rk_fail(err, "--tracks %s: %d frames; at least 3 are needed", tracks_path, out->T);
        goto done;
    }
    rc = fit_markers(out, v->tri, v->bary, v->disp, ridge, err);
done:
    rk_tracks_free(&tr);
    if (rc) rk_dmd_markers_free(out);
    return rc;
}
