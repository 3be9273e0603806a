/* romkit basis SCENE.json: builds the reduced basis the scene's rom section asks for and writes
 * it (and its report) without baking an asset. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"
#include "commands.h"
#include "stage_inputs.h"
#include "util/util.h"

static void basis_usage(FILE *out)
{
    fprintf(out,
            "usage: romkit basis SCENE.json [--entry K] [--basis U.npy] [--weights W.npy]\n"
            "                    [--report R.json] [--quiet] [--training S.npy | --training-run S.npy ...]\n\n"
            "Builds the reduced basis of the scene's rom section (entry K of a list, default 0):\n"
            "modes, modal_derivatives, skinning, rkpm_skinning or pod, of rom.size, or the\n"
            "smallest that meets rom.tolerance on the scene's own full-order frames.\n"
            "  --basis U.npy     the basis, n x 3 x r float64 (vertex, coordinate, column)\n"
            "  --weights W.npy   skinning weights at the vertices, n x m float64 (constant first)\n"
            "  --report R.json   sizes, eigenvalues or singular values, errors, timings\n"
            "  --training S.npy  the scene's own full-order run (romkit fom --snapshots), not run here\n"
            "  --training-run S.npy  one per item of the entry's training list: the frames a pod basis\n"
            "                    or a tolerance trains on, as romkit build trains them (romkit plan)\n"
            "  --quiet           no progress line on stderr\n"
            "Nothing is written when the build fails.\n\n"
            "example:\n"
            "  romkit basis examples/scenes/cantilever_small.json --basis U.npy --report basis.json\n");
}

static cJSON *make_report(const rk_basis *b, const rk_scene_basis_info *info, double seconds)
{
    cJSON *r = cJSON_CreateObject();
    cJSON_AddNumberToObject(r, "vertices", info->vertices);
    cJSON_AddNumberToObject(r, "tets", info->tets);
    cJSON *jb = cJSON_AddObjectToObject(r, "basis");
    cJSON_AddStringToObject(jb, "type", rk_basis_type_name(b->type));
    cJSON_AddNumberToObject(jb, "size", b->r);
    if (b->type == RK_BASIS_POD) {
        cJSON_AddItemToObject(jb, "singular_values", rk_json_array(b->values, b->nvalues));
    } else {
        cJSON_AddItemToObject(jb, "eigenvalues", rk_json_array(b->values, b->nvalues));
        cJSON_AddNumberToObject(jb, "zero_eigenvalues", b->nzero);
    }
    if (b->W) cJSON_AddNumberToObject(jb, "weights", b->m);
    if (b->type == RK_BASIS_RKPM_SKINNING) {
        cJSON_AddNumberToObject(jb, "kernels", info->kernels);
        cJSON_AddNumberToObject(jb, "integration_points", info->integration_points);
        cJSON_AddNumberToObject(jb, "damped_points", b->damped_points);
    }
    if (info->fom_frames) {
        cJSON_AddNumberToObject(jb, "training_frames", info->fom_frames);
        cJSON_AddNumberToObject(jb, "projection_error", info->projection_error);
    }
    cJSON *sec = cJSON_AddObjectToObject(r, "seconds");
    cJSON_AddNumberToObject(sec, "total", seconds);
    cJSON_AddNumberToObject(sec, "fom", info->seconds_fom);
    cJSON_AddNumberToObject(sec, "basis", info->seconds_basis);
    if (b->type == RK_BASIS_RKPM_SKINNING) {
        cJSON *k = cJSON_AddObjectToObject(sec, "rkpm");
        cJSON_AddNumberToObject(k, "farthest_point_sampling", info->rkpm.fps);
        cJSON_AddNumberToObject(k, "kernels", info->rkpm.kernels);
        cJSON_AddNumberToObject(k, "assemble", info->rkpm.assemble);
        cJSON_AddNumberToObject(k, "eigensolve", info->rkpm.eigs);
        cJSON_AddNumberToObject(k, "evaluate", info->rkpm.evaluate);
    }
    return r;
}

/* The first `rows` rows of a column-major matrix with leading dimension ld, written row by row, as
 * an array of the given shape (whose entries multiply to rows x cols): U (3n x r) as n x 3 x r, W
 * (n x m) as n x m; a point cloud's first rows are its points, the rest its contact proxy's. */
static int write_rows(const char *path, const double *A, size_t rows, size_t ld, int cols, int ndim, const long *shape,
                      rk_error *err)
{
    double *T = rk_calloc(rows * cols, sizeof(double), err);
    if (!T) return -1;
    for (size_t i = 0; i < rows; i++)
        for (int j = 0; j < cols; j++) T[i * cols + j] = A[(size_t)j * ld + i];
    int rc = rk_npy_write(path, T, ndim, shape, err);
    free(T);
    return rc;
}

int cmd_basis(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            basis_usage(stdout);
            return 0;
        }
    const char *scene_path, *entry = "0", *basis_out = NULL, *weights_out = NULL, *report_out = NULL;
    int quiet = 0;
    tool_stage st = {0};
    const cli_option opts[] = {{"--entry", &entry, NULL},     {"--basis", &basis_out, NULL},
                               {"--weights", &weights_out, NULL}, {"--report", &report_out, NULL},
                               {"--training", &st.training, NULL}, {"--quiet", NULL, &quiet},
                               {NULL, NULL, NULL}};
    if (tool_stage_args("basis", &argc, argv, &st) || cli_parse("basis", argc, argv, opts, &scene_path, "scene file")) {
        basis_usage(stderr);
        return 2;
    }
    long index;
    if (cli_whole(entry, 0, 1000, &index)) {
        fprintf(stderr, "romkit basis: --entry must be a whole number, got '%s'\n", entry);
        return 2;
    }
    rk_progress_set_quiet(quiet);
    double t0 = rk_now();
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    const rk_rom_entry *e;
    rk_basis b;
    rk_scene_basis_info info = {0};
    int have_scene = 0, have_sim = 0, have_basis = 0, rc = 1;
    if (rk_scene_load(scene_path, &scene, &err)) goto done;
    have_scene = 1;
    if (rk_scene_entry(&scene, (int)index, &e, &err)) goto done;
    if (rk_scene_build(&scene, &sim, &err)) goto done;
    have_sim = 1;
    /* with training files given, the frames romkit build would train this basis on (its training
     * list or the scene's own run); without, the basis runs the scene itself where it needs to */
    double *frames = NULL;
    int T = 0;
    const char *trained_on;
    rk_bake_request req = {0};
    if ((st.training || st.nruns) && (tool_stage_load(&st, &scene, e, &req, &err) ||
                                      rk_scene_entry_frames(&scene, &sim, e, &req, &frames, &T, &trained_on, &err)))
        goto done;
    int failed = rk_scene_basis(&scene, have_sim ? &sim : NULL, &e->basis, frames, T, &b, &info, &err);
    free(frames);
    if (failed) goto done;
    have_basis = 1;
    if (weights_out && !b.W) {
        rk_fail(&err, "--weights: a %s basis has no skinning weights", rk_basis_type_name(b.type));
        goto done;
    }
    int shown = sim.cloud_points ? sim.cloud_points : b.n;
    long ushape[3] = {shown, 3, b.r}, wshape[2] = {shown, b.m};
    if (basis_out && write_rows(basis_out, b.U, 3 * (size_t)shown, 3 * (size_t)b.n, b.r, 3, ushape, &err)) goto done;
    if (weights_out && write_rows(weights_out, b.W, (size_t)shown, (size_t)b.n, b.m, 2, wshape, &err)) goto done;
    cJSON *report = make_report(&b, &info, rk_now() - t0);
    if (report_out && rk_json_write_file(report_out, report, &err)) {
        cJSON_Delete(report);
        goto done;
    }
    cJSON_Delete(report);
    printf("%s: %s basis, %d columns", scene_path, rk_basis_type_name(b.type), b.r);
    if (b.W) printf(" (%d weights, the constant one included)", b.m);
    printf(" on %d vertices in %.3g s", info.vertices, info.seconds_basis);
    if (info.fom_frames)
        printf("; %d full-order frames (%.3g s), projection error %.3g", info.fom_frames, info.seconds_fom,
               info.projection_error);
    printf("\n");
    if (b.nvalues && b.type != RK_BASIS_POD)
        printf("eigenvalues: %.6g .. %.6g (%d zero)\n", b.values[0], b.values[b.nvalues - 1], b.nzero);
    rc = 0;
done:
    if (rc) fprintf(stderr, "romkit basis: %s\n", err.msg);
    tool_stage_free(&st);
    if (have_basis) rk_basis_free(&b);
    rk_scene_basis_info_free(&info);
    if (have_sim) rk_scene_sim_free(&sim);
    if (have_scene) rk_scene_free(&scene);
    return rc;
}
