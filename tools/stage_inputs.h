/* The files a split bake's step reads (romkit plan): --training (the scene's own run),
 * --training-run (the entry's training list, item by item), --basis and --cubature, loaded into a
 * bake request, shared by romkit build, basis and cubature. */
#ifndef ROMKIT_STAGE_INPUTS_H
#define ROMKIT_STAGE_INPUTS_H

#include "pipeline/method_fixed.h"
#include "pipeline/method_koopman.h"

typedef struct {
    const char *training, *basis, *cubature;  /* set by the command's own option table */
    const char *runs[RK_MAX_TRAINING];
    int nruns;
    const char *traj[RK_KOOPMAN_MAX_TRAJECTORIES]; /* --trajectory-run: a Koopman entry's trajectories */
    int ntraj;
    double *snapshots;
    rk_basis b;
    rk_cubature_set c;
    int have_basis, have_cubature;
} tool_stage;

/* Takes the --training-run and --trajectory-run pairs out of argv (before cli_parse). -1 after a
 * message. */
int tool_stage_args(const char *cmd, int *argc, char **argv, tool_stage *s);
/* Reads the files into req for entry e, checking that e can take them (a fixed-basis entry of a
 * modes, modal_derivatives or pod basis, not mesh-free, for --basis; one with rom.cubature for
 * --cubature; as many --training-run files as its training list). */
int tool_stage_load(tool_stage *s, const rk_scene *scene, const rk_rom_entry *e, rk_bake_request *req, rk_error *err);
void tool_stage_free(tool_stage *s);

#endif
