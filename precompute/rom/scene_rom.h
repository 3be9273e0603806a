/* precompute/rom, scene side: a `rom` entry's reduced model for a scene (its basis, exact or
 * cubature integration) and the keys that say how it is built. */
#ifndef RK_SCENE_ROM_H
#define RK_SCENE_ROM_H

#include "basis/scene_basis.h"
#include "rom/rom.h"
#include "scene/scene.h"

typedef struct {
    rk_basis_options basis;
    int cubature;                  /* 0: exact integration over every element */
    rk_cubature_options cub;       /* rom.cubature.{tolerance, max_points, poses, sample} */
    char name[96];                 /* rom.name, or "<basis>-<size|tol>[-cubature]" */
    double reference_nmse;         /* rom.reference.normalized_mse: a published value to print beside ours; NAN if none */
    char reference_source[96];     /* rom.reference.source */
} rk_rom_options;

/* Entries in the rom section: 1 for an object, the length of an array, 0 when absent. */
int rk_rom_entries(const cJSON *rom);
/* Reads entry `index` (basis keys as rk_basis_options_parse, plus cubature, name, reference). */
int rk_rom_options_parse(const cJSON *rom, int index, const char *file, rk_rom_options *o, rk_error *err);

typedef struct {
    rk_basis basis;
    rk_scene_basis_info basis_info;
    rk_rom_model model;
    int cubature_points;           /* 0 for exact integration */
    double cubature_error;         /* relative force error on the training poses (NAN: exact) */
    int cubature_reached, cubature_poses;
    double seconds_basis, seconds_cubature;
    char basis_reason[256];        /* which option bound the basis size, with the numbers */
    char cubature_reason[256];     /* which option bound the cubature size */
} rk_scene_rom;

/* Builds the reduced model of entry o for the built scene sim. frames: the scene's full-order
 * displacements (3 nv x T, column-major) when they have been run, else NULL (then bases that
 * need them run their own, and the cubature trains on random poses only). */
int rk_scene_rom_build(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_options *o,
                       const double *frames, int T, rk_scene_rom *out, rk_error *err);
void rk_scene_rom_free(rk_scene_rom *r);

#endif
