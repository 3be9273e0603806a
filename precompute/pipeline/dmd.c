/* romkit dmd's library (dmd.h): recordings into displacement trajectories, the POD fit, the bake
 * and its report. */
#include "pipeline/dmd.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "basis/basis.h"
#include "util/util.h"

void rk_dmd_recordings_free(rk_dmd_recordings *r)
{
    free(r->X);
    free(r->vertex_mass);
    for (int i = 0; i < r->ntraj; i++) {
        free(r->data[i]);
        free(r->accel[i]);
    }
    memset(r, 0, sizeof *r);
}

/* The recording's frames (d values each, padded to n), with frame 0 repeated first from rest. */
static int frames_of(const double *raw, int T, int d, int n, int from_rest, double **out, rk_error *err)
{
    int lead = from_rest ? 1 : 0;
    double *p = rk_calloc((size_t)n * (T + lead), sizeof(double), err);
    if (!p) return -1;
    for (int t = 0; t < T + lead; t++) memcpy(p + (size_t)n * t, raw + (size_t)d * (t < lead ? 0 : t - lead), sizeof(double) * d);
    *out = p;
    return 0;
}

static int load_files(const char *const *files, int nfiles, int from_rest, rk_dmd_recordings *r, rk_error *err)
{
    int first_d = 0;
    if (nfiles < 1 || nfiles > RK_DMD_MAX_RECORDINGS)
        return rk_fail(err, "%d recordings: from 1 to %d", nfiles, RK_DMD_MAX_RECORDINGS);
    for (int f = 0; f < nfiles; f++) {
        double *raw;
        int ndim;
        long shape[4];
        if (rk_npy_read(files[f], &raw, &ndim, shape, err)) return -1;
        r->ntraj++;
        r->data[f] = raw;
        int positions = ndim == 3 && shape[2] == 3, d = positions ? (int)(3 * shape[1]) : ndim == 2 ? (int)shape[1] : 0;
        if (!(ndim == 3 && shape[2] == 3) && ndim != 2)
            return rk_fail(err, "%s: shape must be T x n x 3 or T x d, got %d dimensions", files[f], ndim);
        if (f == 0) {
            first_d = d;
            r->positions = positions;
            r->d = d;
            r->nv = (d + 2) / 3;
        } else if (d != first_d || positions != r->positions) {
            return rk_fail(err, "%s: %d values per frame, %s has %d: every recording must have the same layout",
                           files[f], d, files[0], first_d);
        }
        int T = (int)shape[0], n = 3 * r->nv;
        if (T < 3) return rk_fail(err, "%s: %d frames; a trajectory needs at least 3", files[f], T);
        /* T x d observables are padded to whole points */
        if (frames_of(raw, T, d, n, from_rest, &r->data[f], err)) return -1;
        free(raw);
        r->traj[f] = (rk_koopman_trajectory){r->data[f], T + (from_rest ? 1 : 0), NULL};
    }
    return 0;
}

/* Rest positions, u = x - rest, vertex masses. */
static int rest_and_masses(const char *rest_file, double mass, rk_dmd_recordings *r, rk_error *err)
{
    int n = 3 * r->nv;
    r->X = rk_calloc((size_t)n, sizeof(double), err);
    r->vertex_mass = rk_calloc((size_t)r->nv, sizeof(double), err);
    if (!r->X || !r->vertex_mass) return -1;
    if (rest_file) {
        double *rest;
        int ndim;
        long shape[4];
        if (rk_npy_read(rest_file, &rest, &ndim, shape, err)) return -1;
        long count = ndim == 2 ? shape[0] * shape[1] : ndim == 1 ? shape[0] : -1;
        if (count != r->d) {
            free(rest);
            return rk_fail(err, "%s: %ld values, the recordings have %d per frame", rest_file, count, r->d);
        }
        memcpy(r->X, rest, sizeof(double) * (size_t)count);
        free(rest);
    } else if (r->positions) {
        memcpy(r->X, r->data[0], sizeof(double) * n);
    }
    for (int f = 0; f < r->ntraj; f++)
        for (size_t i = 0; i < (size_t)n * r->traj[f].frames; i++) r->data[f][i] -= r->X[i % n];
    for (int v = 0; v < r->nv; v++) r->vertex_mass[v] = mass;
    return 0;
}

int rk_dmd_recordings_load(const char *const *files, int nfiles, int from_rest, const char *rest_file,
                           double vertex_mass, rk_dmd_recordings *r, rk_error *err)
{
    memset(r, 0, sizeof *r);
    return load_files(files, nfiles, from_rest, r, err) || rest_and_masses(rest_file, vertex_mass, r, err) ? -1 : 0;
}

int rk_dmd_recordings_markers(rk_dmd_markers *m, int from_rest, rk_dmd_recordings *r, rk_error *err)
{
    memset(r, 0, sizeof *r);
    int n = 3 * m->nv;
    r->ntraj = 1;
    r->nv = m->nv;
    r->d = n;
    r->positions = 1;
    r->X = m->X; /* taken over */
    r->vertex_mass = m->vertex_mass;
    m->X = m->vertex_mass = NULL;
    if (frames_of(m->u, m->T, n, n, from_rest, &r->data[0], err)) return -1;
    r->traj[0] = (rk_koopman_trajectory){r->data[0], m->T + (from_rest ? 1 : 0), NULL};
    return 0;
}

int rk_dmd_recordings_accel(rk_dmd_recordings *r, const double *gravity, const double (*accel)[3], int naccel,
                            rk_error *err)
{
    int n = 3 * r->nv;
    for (int f = 0; f < r->ntraj; f++) {
        const double *g = naccel == 1 ? accel[0] : naccel > 1 ? accel[f] : gravity;
        if (!g) continue;
        if (!r->positions) return rk_fail(err, "--gravity and --accel act on T x n x 3 positions, not on T x d observables");
        r->accel[f] = rk_calloc((size_t)n, sizeof(double), err);
        if (!r->accel[f]) return -1;
        for (int i = 0; i < n; i++) r->accel[f][i] = g[i % 3];
        r->traj[f].accel = r->accel[f];
    }
    return 0;
}

int rk_koopman_fit_pod(const rk_koopman_trajectory *traj, int ntraj, int n, int P, const rk_koopman_options *o,
                       rk_koopman *k, rk_error *err)
{
    int T = 0, rc = -1;
    for (int f = 0; f < ntraj; f++) T += traj[f].frames;
    double *all = rk_calloc((size_t)n * T, sizeof(double), err), *s = rk_calloc((size_t)(n < T ? n : T), sizeof(double), err);
    double *Q = rk_calloc((size_t)n * P, sizeof(double), err), *Qt = rk_calloc((size_t)n * P, sizeof(double), err);
    int got = 0;
    if (all && s && Q && Qt) {
        for (int f = 0, c = 0; f < ntraj; c += traj[f].frames, f++)
            memcpy(all + (size_t)n * c, traj[f].u, sizeof(double) * n * traj[f].frames);
        if (P > (n < T ? n : T))
            rk_fail(err, "--pod %d: at most %d directions from %d frames of %d values", P, n < T ? n : T, T, n);
        else if (!rk_mass_pca(all, n, T, NULL, P, 0, Q, &got, s, err)) {
            for (int j = 0; j < got; j++)
                for (int i = 0; i < n; i++) Qt[(size_t)got * i + j] = Q[(size_t)n * j + i];
            rc = rk_koopman_fit_projected(traj, ntraj, n, Qt, Q, got, o, k, err);
        }
    }
    free(all);
    free(s);
    free(Q);
    free(Qt);
    return rc;
}

int rk_dmd_bake(const rk_koopman *k, const rk_dmd_recordings *r, const rk_dmd_markers *m, const int *tris, int ntris,
                int source_tets, const double *gravity, const rk_asset_options *ao, const char *source,
                double seconds_fit, rk_baked *out, rk_error *err)
{
    rk_koopman_geometry g = {.nv = r->nv, .X = r->X, .vertex_mass = r->vertex_mass, .trajectories = r->ntraj,
                             .tris = m ? m->tris : NULL, .ntris = m ? m->ntris : 0, .source_tets = m ? m->ntets : 0};
    if (tris) {
        g.tris = tris;
        g.ntris = ntris;
        g.source_tets = source_tets;
    }
    double *accel = NULL;
    if (gravity) {
        accel = rk_calloc((size_t)3 * r->nv, sizeof(double), err);
        if (!accel) return -1;
        for (int i = 0; i < 3 * r->nv; i++) accel[i] = gravity[i % 3];
        g.accel = accel;
    }
    /* the asset starts at the first recording's first frame, at rest (as a recording of a body
     * released or pushed from rest begins; step k of the runtime is then frame k) */
    g.u_prev = g.u0 = r->traj[0].u;
    cJSON *info = cJSON_CreateObject();
    cJSON_AddStringToObject(info, "method", "koopman");
    cJSON_AddStringToObject(info, "source", source);
    cJSON_AddNumberToObject(info, "rank", k->r);
    cJSON_AddNumberToObject(info, "trajectories", r->ntraj);
    char *info_text = cJSON_PrintUnformatted(info);
    cJSON_Delete(info);
    int rc = rk_bake_koopman(k, &g, ao, info_text, out, err);
    free(info_text);
    free(accel);
    if (rc) return -1;
    cJSON_AddNumberToObject(out->report, "vertices", r->nv);
    cJSON_AddNumberToObject(out->report, "trajectories", r->ntraj);
    if (m) {
        cJSON *mj = cJSON_AddObjectToObject(out->report, "markers");
        cJSON_AddNumberToObject(mj, "count", m->k);
        cJSON_AddNumberToObject(mj, "modes", m->b);
        cJSON_AddNumberToObject(mj, "frames", m->T);
        cJSON_AddNumberToObject(mj, "misfit", m->marker_misfit);
        cJSON_AddNumberToObject(mj, "ridge", m->ridge);
        if (m->from_video) {
            const rk_video_markers *v = &m->video;
            cJSON *vj = cJSON_AddObjectToObject(mj, "video"), *dots = cJSON_AddArrayToObject(vj, "dots");
            for (int i = 0; i < v->nviews; i++)
                cJSON_AddItemToArray(dots, cJSON_CreateNumber(v->dots[i]));
            cJSON_AddNumberToObject(vj, "on_surface", v->hit);
            cJSON_AddNumberToObject(vj, "matched", v->matched);
            cJSON_AddNumberToObject(vj, "single_view", v->single_view);
            cJSON_AddNumberToObject(vj, "lost", v->lost);
            cJSON_AddNumberToObject(vj, "triangulated", v->triangulated);
            cJSON_AddNumberToObject(vj, "match_max", v->match_max);
            cJSON_AddNumberToObject(vj, "reprojection_rms_px", v->reproj_rms);
            cJSON_AddNumberToObject(vj, "reprojection_max_px", v->reproj_max);
        }
    }
    cJSON *s = cJSON_AddObjectToObject(out->report, "seconds");
    cJSON_AddNumberToObject(s, "fit", seconds_fit);
    return 0;
}
