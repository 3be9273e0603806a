/* An entry's training set (pipeline.h, rk_scene_training_set): other full-order runs of the same
 * object, as scenes run here or as snapshot files a job scheduler produced with romkit fom. */
#include "pipeline/pipeline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Appends T frames (3 nv each) to *D (*have frames so far). */
static int append(double **D, int *have, const double *frames, int T, int n, rk_error *err)
{
    double *grown = realloc(*D, sizeof(double) * (size_t)n * ((size_t)*have + T));
    if (!grown) return rk_fail(err, "out of memory for %d training frames", *have + T);
    memcpy(grown + (size_t)n * *have, frames, sizeof(double) * (size_t)n * T);
    *D = grown;
    *have += T;
    return 0;
}

static int same_object(const rk_scene_sim *a, const rk_scene_sim *b, rk_error *err)
{
    if (a->mesh.nv != b->mesh.nv)
        return rk_fail(err, "has %d vertices, the scene %d: not the same object", b->mesh.nv, a->mesh.nv);
    for (int i = 0; i < 3 * a->mesh.nv; i++)
        if (fabs(a->mesh.X[i] - b->mesh.X[i]) > 1e-9 * (1 + fabs(a->mesh.X[i])))
            return rk_fail(err, "vertex %d rests at another place than in the scene: not the same object", i / 3);
    return 0;
}

static int from_scene(const rk_scene_sim *sim, const char *file, double **D, int *T, rk_error *err)
{
    rk_scene sc;
    rk_scene_sim other;
    if (rk_scene_load(file, &sc, err)) return -1;
    int rc = rk_scene_build(&sc, &other, err);
    if (!rc) {
        double *frames = NULL;
        int n = 0;
        rc = same_object(sim, &other, err) || rk_scene_training_frames(&other, &frames, &n, err) ||
             append(D, T, frames, n, 3 * sim->mesh.nv, err);
        free(frames);
        rk_scene_sim_free(&other);
    }
    rk_scene_free(&sc);
    return rc ? -1 : 0;
}

static int from_snapshots(const rk_scene_sim *sim, const char *file, double **D, int *T, rk_error *err)
{
    double *data = NULL;
    int ndim;
    long shape[4];
    if (rk_npy_read(file, &data, &ndim, shape, err)) return -1;
    int nv = sim->mesh.nv, n = 3 * nv, rc = 0;
    if (ndim != 3 || shape[1] != nv || shape[2] != 3 || shape[0] < 2)
        rc = rk_fail(err, "%s: snapshots must be (T + 1) x %d x 3 with T >= 1 (romkit fom --snapshots of this object)",
                     file, nv);
    for (long t = 1; !rc && t < shape[0]; t++) { /* frame 0 is the start */
        double *f = data + (size_t)t * n;
        for (int i = 0; i < n; i++) {
            if (!isfinite(f[i])) {
                rc = rk_fail(err, "%s: frame %ld, vertex %d is not finite", file, t, i / 3);
                break;
            }
            f[i] -= sim->mesh.X[i];
        }
    }
    if (!rc) rc = append(D, T, data + n, (int)shape[0] - 1, n, err);
    free(data);
    return rc;
}

int rk_scene_training_set(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, double **D, int *T,
                          rk_error *err)
{
    return rk_scene_training_set_from(scene, sim, e, NULL, D, T, err);
}

/* A scene item's frames from its snapshot file are the frames of running it here bit for bit:
 * romkit fom writes the positions x in float64 and both subtract the same rest positions (the
 * same object: same_object's check, which a plan's item scene meets exactly). */
int rk_scene_training_set_from(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                               const char *const *files, double **D, int *T, rk_error *err)
{
    *D = NULL;
    *T = 0;
    for (int k = 0; k < e->ntraining; k++) {
        const char *file = files && files[k] ? files[k] : e->training[k].file;
        int rc = e->training[k].snapshots || (files && files[k]) ? from_snapshots(sim, file, D, T, err)
                                                                 : from_scene(sim, file, D, T, err);
        if (rc) {
            free(*D);
            *D = NULL;
            *T = 0;
            return rk_error_prefix(err, "%s.training[%d] (%s)", e->path, k, file);
        }
    }
    (void)scene;
    return 0;
}
