/* The FreeForm paper's 5 x 1 x 1 m beam, its first 0.5 m fixed, linear material, static sag under a
 * tenth of gravity, as a mesh-free reduced model, and Timoshenko's tip deflection for it
 * (test_pipeline_meshfree_beam.c says how they compare). For the tests that build it. */
#ifndef TEST_MESHFREE_BEAM_H
#define TEST_MESHFREE_BEAM_H

#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "freeform_beam.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"

static inline double timoshenko_tip(double nu) { return beam_timoshenko_tip(nu); }

/* The three smallest eigenvalues of the reduced stiffness at rest with the clamp's penalty, K(0) + A
 * (both the model's), into eig. */
static inline void lowest_eigenvalues(rk_rom_model *M, double eig[3])
{
    int r = M->r;
    double *H = calloc((size_t)r * r, sizeof *H), *w = calloc(r, sizeof *w), *q = calloc(r, sizeof *q);
    rk_quadrature_eval(&M->quad, q, NULL, H, 0);
    for (size_t k = 0; k < (size_t)r * r; k++) H[k] += M->A[k];
    LAPACKE_dsyev(LAPACK_COL_MAJOR, 'N', 'U', r, H, r, w);
    for (int k = 0; k < 3; k++) eig[k] = w[k];
    free(H);
    free(w);
    free(q);
}

/* The static equilibrium of the scene's mesh-free m-weight model: mean downward displacement of
 * the free end's vertices; *held (may be NULL) the largest displacement of a fixed vertex, which
 * the penalty clamp holds back (pin > 0: "clamp": "penalty" at rom.pin_stiffness pin; 0: the
 * Dirichlet clamp, the default, which holds them exactly); further rom keys (may be NULL), and
 * with eig lowest_eigenvalues. model_tip_keys builds the rom object; model_tip_rom takes it whole. */
/* The same for any rom object (rom: its keys without the braces, e.g. "\"basis\": \"skinning\", \"size\": 9"). */
static inline double model_tip_rom(double nu, const char *rom_keys, double *held, double *eig, rk_error *err, int *ok)
{
    char json[1400];
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [5, 1, 1], \"cells\": [20, 4, 4]}},"
             " \"material\": {\"model\": \"linear\", \"young\": %g, \"poisson\": %g, \"density\": %g},"
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0.5, 2, 2]]}]}],"
             " \"gravity\": [0, %g, 0], \"time\": {\"static\": true}, \"rom\": {%s}}",
             BEAM_YOUNG, nu, BEAM_DENSITY, -BEAM_GRAVITY, rom_keys);
    rk_scene scene;
    rk_scene_sim sim;
    rk_scene_rom R;
    rk_rom rom = {0};
    double tip = NAN;
    *ok = 0;
    if (rk_scene_parse(json, "beam.json", &scene, err)) return NAN;
    if (rk_scene_build(&scene, &sim, err)) goto no_sim;
    if (rk_scene_rom_build(&scene, &sim, &scene.entries[0], NULL, 0, &R, err)) goto no_rom;
    if (eig) lowest_eigenvalues(&R.model, eig);
    if (rk_rom_init(&rom, &R.model, NULL, NULL, err) || rk_rom_step(&rom, err)) goto out;
    int nv = sim.mesh.nv, count = 0;
    double sum = 0;
    if (held) *held = 0;
    for (int v = 0; v < nv; v++) {
        double d[3] = {0, 0, 0}; /* rows 3 v .. 3 v + 2 of x - X = U q */
        for (int j = 0; j < R.basis.r; j++)
            for (int c = 0; c < 3; c++) d[c] += R.basis.U[(size_t)3 * nv * j + 3 * v + c] * rom.q[j];
        if (held && sim.mesh.X[3 * v] <= 0.5 + 1e-9) *held = fmax(*held, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        if (sim.mesh.X[3 * v] < 5 - 1e-9) continue;
        sum -= d[1];
        count++;
    }
    tip = sum / count;
    *ok = count > 0;
out:
    rk_rom_free(&rom);
    rk_scene_rom_free(&R);
no_rom:
    rk_scene_sim_free(&sim);
no_sim:
    rk_scene_free(&scene);
    return tip;
}

static inline double model_tip_keys(double nu, int m, double pin, const char *keys, double *held, double *eig, rk_error *err,
                                    int *ok)
{
    char rom[600], pin_key[160] = "";
    if (pin > 0) snprintf(pin_key, sizeof pin_key, ", \"clamp\": \"penalty\", \"pin_stiffness\": %g", pin);
    if (keys) snprintf(pin_key + strlen(pin_key), sizeof pin_key - strlen(pin_key), ", %s", keys);
    snprintf(rom, sizeof rom, "\"basis\": \"rkpm_skinning\", \"size\": %d, \"mesh_free\": {\"points\": 5000}%s", m,
             pin_key);
    return model_tip_rom(nu, rom, held, eig, err, ok);
}

static inline double model_tip_held(double nu, int m, double pin, double *held, rk_error *err, int *ok)
{
    return model_tip_keys(nu, m, pin, NULL, held, NULL, err, ok);
}

static inline double model_tip(double nu, int m, rk_error *err, int *ok)
{
    return model_tip_held(nu, m, 0, NULL, err, ok);
}

#endif
