/* An adaptive linear ROM entry on the built scene (pipeline.h, rk_scene_alrom_init): its decoder
 * and the simulator under the scene's own options. The quadratic-manifold decoder: the entry's r
 * linear modes (computed with the fixed vertices held) and their modal derivatives, the pairs of
 * rigid modes left zero. */
#include "pipeline/method_adaptive_linear.h"
#include "pipeline/method_fixed.h"

#include <stdlib.h>
#include <string.h>

/* the entry's own options (the caller checked its method) */
#define AL(e) rk_adaptive_linear_of(e)

/* Decoder "quadratic_pod": the frames' POD and the quadratic term fitted to them. */
static int quadratic_pod_parts(const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames, int T,
                               double **Phi, double **Psi, rk_error *err)
{
    if (!AL(e)) return rk_fail(err, "%s is not method adaptive_linear", e->path);
    int r = e->basis.size, nv = sim->mesh.nv, n = 3 * nv, rc = -1;
    rk_basis pod = {0};
    rk_sparse M = {0};
    *Phi = *Psi = NULL;
    if (!frames || T < r) return rk_fail(err, "decoder quadratic_pod trains on at least r = %d frames, got %d", r, T);
    if (rk_sparse_alloc_pattern(&sim->fem, &M, err)) return -1;
    rk_fem_add_mass(&sim->fem, sim->options.lumped_mass, 1.0, &M);
    *Phi = malloc(sizeof(double) * (size_t)n * r);
    *Psi = malloc(sizeof(double) * (size_t)n * ((size_t)r * (r + 1) / 2) + 1);
    if (!*Phi || !*Psi) rk_fail(err, "out of memory for the quadratic decoder (%d x %d)", n, r);
    else if (!rk_basis_pod(frames, nv, T, &M, r, 0, &pod, err)) {
        if (pod.r < r) rk_fail(err, "the frames span only %d directions, fewer than r = %d", pod.r, r);
        else {
            memcpy(*Phi, pod.U, sizeof(double) * (size_t)n * r);
            rc = rk_quadratic_fit(n, r, *Phi, &M, frames, T, *Psi, NULL, NULL, err);
        }
    }
    if (rc) {
        free(*Phi);
        free(*Psi);
        *Phi = *Psi = NULL;
    }
    rk_basis_free(&pod);
    rk_sparse_free(&M);
    return rc;
}

int rk_scene_quadratic_parts(const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames, int T,
                             double **Phi, double **Psi, rk_error *err)
{
    if (AL(e)->quadratic_pod) return quadratic_pod_parts(sim, e, frames, T, Phi, Psi, err);
    int r = e->basis.size, nv = sim->mesh.nv, n = 3 * nv, rc = -1;
    unsigned char *fixed = rk_scene_fixed_vertices(sim, err);
    double *raw = NULL;
    rk_basis modes = {0};
    *Phi = *Psi = NULL;
    if (!fixed) return -1;
    int lumped = sim->options.lumped_mass;
    if (rk_basis_modes(&sim->fem, fixed, lumped, r, &modes, err)) goto out;
    int nrigid = modes.nzero, k = r - nrigid;
    size_t pairs = (size_t)r * (r + 1) / 2, raw_pairs = (size_t)k * (k + 1) / 2;
    *Psi = calloc((size_t)n * pairs + 1, sizeof(double));
    *Phi = malloc(sizeof(double) * (size_t)n * r);
    raw = calloc((size_t)n * raw_pairs + 1, sizeof(double));
    if (!*Psi || !*Phi || !raw) {
        rk_fail(err, "out of memory for %zu modal derivatives", pairs);
        goto out;
    }
    double residual;
    if (k > 0 && rk_modal_derivatives(&sim->fem, fixed, lumped, modes.U, r, nrigid, raw, &residual, err)) goto out;
    rk_quadratic_pairs(n, r, nrigid, raw, *Psi);
    memcpy(*Phi, modes.U, sizeof(double) * (size_t)n * r);
    rc = 0;
out:
    if (rc) {
        free(*Phi);
        free(*Psi);
        *Phi = *Psi = NULL;
    }
    rk_basis_free(&modes);
    free(raw);
    free(fixed);
    return rc;
}

static int quadratic(const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames, int T, rk_decoder *dec,
                     rk_error *err)
{
    double *Phi, *Psi, *own = NULL;
    rk_sparse M = {0};
    if (AL(e)->quadratic_pod && !frames) {
        if (rk_scene_training_frames(sim, &own, &T, err)) return -1;
        frames = own;
    }
    int parts = rk_scene_quadratic_parts(sim, e, frames, T, &Phi, &Psi, err);
    free(own);
    if (parts) return -1;
    int rc = rk_sparse_alloc_pattern(&sim->fem, &M, err);
    if (!rc) {
        rk_fem_add_mass(&sim->fem, sim->options.lumped_mass, 1.0, &M);
        rc = rk_quadratic_decoder(3 * sim->mesh.nv, e->basis.size, Phi, Psi, &M, dec, err);
    }
    rk_sparse_free(&M);
    free(Phi);
    free(Psi);
    return rc;
}

/* A CROM on the scene's full-order frames (run here when the caller has none). */
static int crom(const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames, int T, rk_decoder *dec,
                rk_error *err)
{
    double *own = NULL;
    if (!frames) {
        if (rk_scene_training_frames(sim, &own, &T, err)) return -1;
        frames = own;
    }
    rk_crom_report rep;
    int rc = rk_crom_train(frames, T, sim->mesh.X, sim->mesh.nv, e->basis.size, &AL(e)->crom_opt, dec, &rep, err);
    free(own);
    return rc;
}

int rk_scene_alrom_decoder(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames,
                           int T, rk_decoder *dec, rk_error *err)
{
    if (!AL(e)) return rk_fail(err, "%s is not method adaptive_linear", e->path);
    if (sim->cloud_points) return rk_fail(err, "%s: method adaptive_linear needs tetrahedral meshes, not point clouds", e->path);
    if (AL(e)->crom ? crom(sim, e, frames, T, dec, err) : quadratic(sim, e, frames, T, dec, err))
        return rk_error_prefix(err, "%s: the %s decoder", e->path, AL(e)->crom ? "CROM" : "quadratic-manifold");
    (void)scene;
    return 0;
}

int rk_scene_alrom_init(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames,
                        int T, rk_alrom *s, rk_decoder *dec, double *seconds_decoder, rk_error *err)
{
    double t0 = rk_now();
    if (rk_scene_alrom_decoder(scene, sim, e, frames, T, dec, err)) return -1;
    if (seconds_decoder) *seconds_decoder = rk_now() - t0;
    if (rk_alrom_init(s, &sim->fem, &sim->options, dec, &AL(e)->opt, err)) {
        rk_decoder_free(dec);
        return rk_error_prefix(err, "%s", e->path);
    }
    return 0;
}

/* Pose t of the moving basis' training: frame s (evenly spaced over the T frames), its code p =
 * e(u) and the decoder's basis dg/dp there, with the prescribed rows zero as every step's basis. */
typedef struct {
    const rk_decoder *dec;
    const double *frames;
    int T, poses;
    const unsigned char *prescribed; /* per dof */
    double *p;
} moving_ctx;

static int moving_pose(void *ctx, int t, double *u, double *U, rk_error *err)
{
    const moving_ctx *m = ctx;
    int n = m->dec->n, r = m->dec->r;
    long s = m->poses > 1 ? (long)t * (m->T - 1) / (m->poses - 1) : m->T - 1;
    memcpy(u, m->frames + (size_t)n * s, sizeof(double) * (size_t)n);
    if (m->dec->encode(m->dec->ctx, u, m->p, err) || m->dec->jacobian(m->dec->ctx, m->p, U, err))
        return rk_error_prefix(err, "the decoder at frame %ld", s);
    for (int j = 0; j < r; j++)
        for (int i = 0; i < n; i++)
            if (m->prescribed[i]) U[(size_t)n * j + i] = 0;
    return 0;
}

int rk_scene_alrom_cubature(const rk_scene_sim *sim, const rk_rom_entry *e, const rk_decoder *dec, const double *frames,
                            int T, int **element, double **weight, int *count, rk_moving_fit *fit, rk_error *err)
{
    *element = NULL;
    *weight = NULL;
    *count = 0;
    memset(fit, 0, sizeof *fit);
    if (!e->cubature) return 0;
    int nv = sim->mesh.nv, n = 3 * nv, r = e->basis.size, rc = -1;
    if (!frames || T < 1) return rk_fail(err, "%s: the cubature trains on the entry's frames, and there are none", e->path);
    if (dec->n != n || dec->r != r)
        return rk_fail(err, "%s: the decoder is %d x %d, the cubature needs %d x %d", e->path, dec->n, dec->r, n, r);
    moving_ctx m = {dec, frames, T, T < e->cub.poses ? T : e->cub.poses, NULL, NULL};
    unsigned char *pre = rk_calloc((size_t)n, 1, err);
    m.p = rk_calloc((size_t)r, sizeof(double), err);
    m.prescribed = pre;
    rk_cubature_set set = {0};
    if (!pre || !m.p) goto out;
    for (int g = 0; g < sim->options.nprescribed; g++)
        for (int k = 0; k < sim->options.prescribed[g].count; k++)
            memset(pre + 3 * (size_t)sim->options.prescribed[g].verts[k], 1, 3);
    rk_moving_poses P = {m.poses, moving_pose, &m};
    if (rk_cubature_train_moving(&sim->fem, r, &P, &e->cub, &set, fit, err)) {
        rk_error_prefix(err, "%s: the cubature (trained for the moving basis)", e->path);
        goto out;
    }
    *element = malloc(sizeof(int) * (size_t)(set.count + 1));
    *weight = malloc(sizeof(double) * (size_t)(set.count + 1));
    if (!*element || !*weight) {
        rk_fail(err, "out of memory for a cubature of %d elements", set.count);
        goto out;
    }
    memcpy(*element, set.index, sizeof(int) * (size_t)set.count);
    memcpy(*weight, set.weight, sizeof(double) * (size_t)set.count);
    *count = set.count;
    rc = 0;
out:
    rk_cubature_set_free(&set);
    free(pre);
    free(m.p);
    if (rc) {
        free(*element);
        free(*weight);
        *element = NULL;
        *weight = NULL;
    }
    return rc;
}
