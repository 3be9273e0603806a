/* romkit build SCENE.json -o OUT.rombin: the whole pipeline the scene's (first) rom entry asks
 * for, baked into an asset the runtime opens in place (precompute/asset, formats/ROMBIN.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "asset/asset.h"
#include "commands.h"
#include "koopman/scene_koopman.h"
#include "koopman_asset.h"
#include "formats/rombin_read.h"
#include "util/json_out.h"
#include "util/npy.h"
#include "util/timer.h"

static void build_usage(FILE *f)
{
    fprintf(f, "usage: romkit build SCENE.json -o OUT.rombin [--report R.json] [--precision float32|float64]\n"
               "                    [--compress] [--entry K] [--training S.npy] [--quiet]\n"
               "  builds the reduced model of one rom entry of the scene (basis, cubature) and bakes it\n"
               "  into OUT.rombin with only what the runtime needs: the reduced operators, the cubature\n"
               "  elements with the basis rows of the vertices they touch, and the rows of the shown\n"
               "  vertices (rom.asset.show, default the surface) and of the named groups (rom.asset.groups).\n"
               "  With rom.koopman the asset holds a Koopman operator instead, learned by DMD from the\n"
               "  scene's own full-order runs (rom.koopman.trajectories vary gravity, initial velocity and\n"
               "  loads; rom.koopman.project fits on the basis's coordinates; rank, energy, clamp).\n"
               "  --precision   real type of the asset's arrays (default rom.asset.precision, else float32)\n"
               "  --compress    deflate the chunks (smaller to ship; romkit run inflates, the runtime\n"
               "                itself opens stored chunks only)\n"
               "  --report      sizes, eigenvalues, cubature, the asset's chunks and bytes, timings\n"
               "  --entry K     bake entry K of the scene's rom list instead of the first (0)\n"
               "  --training    the scene's full-order frames from romkit fom --snapshots, used instead\n"
               "                of running the scene again (cubature, POD and tolerances train on them)\n"
               "  --quiet       no progress lines on stderr\n"
               "  Nothing is written when the build fails.\n\n"
               "example:\n"
               "  romkit build examples/scenes/cantilever_small.json -o cantilever.rombin --report build.json\n");
}

static cJSON *make_report(const rk_scene_sim *sim, const rk_scene_rom *R, const rk_asset_summary *sum,
                          const unsigned char *data, size_t bytes, double seconds)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "vertices", sim->mesh.nv);
    cJSON_AddNumberToObject(root, "tets", sim->mesh.nt);
    cJSON *b = cJSON_AddObjectToObject(root, "basis");
    cJSON_AddStringToObject(b, "type", rk_basis_type_name(R->basis.type));
    cJSON_AddNumberToObject(b, "size", R->basis.W ? R->basis.m : R->basis.r);
    cJSON_AddNumberToObject(b, "columns", R->basis.r);
    cJSON_AddItemToObject(b, R->basis.type == RK_BASIS_POD ? "singular_values" : "eigenvalues",
                          rk_json_array(R->basis.values, R->basis.nvalues));
    cJSON_AddStringToObject(b, "bound_by", R->basis_reason);
    cJSON *c = cJSON_AddObjectToObject(root, "cubature");
    cJSON_AddNumberToObject(c, "elements", R->model.quad.count);
    if (isfinite(R->cubature_error)) cJSON_AddNumberToObject(c, "relative_error", R->cubature_error);
    else cJSON_AddNullToObject(c, "relative_error");
    cJSON_AddStringToObject(c, "bound_by", R->cubature_reason);
    cJSON *a = cJSON_AddObjectToObject(root, "asset");
    cJSON_AddNumberToObject(a, "bytes", (double)bytes);
    cJSON_AddNumberToObject(a, "stored_vertices", sum->vertices);
    cJSON_AddNumberToObject(a, "shown_vertices", sum->shown);
    cJSON_AddNumberToObject(a, "triangles", sum->triangles);
    cJSON_AddNumberToObject(a, "contacts", sum->contacts);
    cJSON_AddNumberToObject(a, "groups", sum->groups);
    rombin_file f;
    rombin_error e;
    if (rombin_open(&f, data, bytes, NULL, &e) == ROMBIN_OK) {
        cJSON_AddStringToObject(a, "precision", f.real_type == ROMBIN_REAL_F32 ? "float32" : "float64");
        cJSON *chunks = cJSON_AddArrayToObject(a, "chunks");
        for (unsigned i = 0; i < f.count; i++) {
            rombin_chunk ch;
            rombin_chunk_get(&f, i, &ch);
            cJSON *j = cJSON_CreateObject();
            cJSON_AddStringToObject(j, "id", ch.id);
            cJSON_AddNumberToObject(j, "stored", (double)ch.stored);
            cJSON_AddNumberToObject(j, "raw", (double)ch.raw);
            cJSON_AddBoolToObject(j, "deflate", ch.compression == ROMBIN_COMP_DEFLATE);
            cJSON_AddItemToArray(chunks, j);
        }
    }
    cJSON *s = cJSON_AddObjectToObject(root, "seconds");
    cJSON_AddNumberToObject(s, "basis", R->seconds_basis);
    cJSON_AddNumberToObject(s, "cubature", R->seconds_cubature);
    cJSON_AddNumberToObject(s, "total", seconds);
    return root;
}

/* What the INFO chunk says: enough to tell where an asset came from, nothing time-dependent. */
static char *info_text(const char *scene_path, const rk_rom_options *o, const rk_scene_rom *R)
{
    cJSON *j = cJSON_CreateObject();
    const char *slash = strrchr(scene_path, '/');
    cJSON_AddStringToObject(j, "scene", slash ? slash + 1 : scene_path);
    cJSON_AddStringToObject(j, "method", o->name);
    cJSON_AddStringToObject(j, "basis", rk_basis_type_name(R->basis.type));
    cJSON_AddNumberToObject(j, "columns", R->basis.r);
    cJSON_AddNumberToObject(j, "cubature_elements", R->model.quad.count);
    char *text = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    return text;
}

/* A rom entry's Koopman operator and what baking it needs: the scene's constant acceleration, the
 * start (where the training runs start: X_0 = [0; h v_0]) and the boundary to show. */
typedef struct {
    rk_koopman k;
    rk_koopman_scene_info ki;
    double *accel, *u0, *u_prev;
    rk_koopman_geometry g;
} koopman_part;

static void koopman_part_free(koopman_part *p)
{
    rk_koopman_free(&p->k);
    free(p->accel);
    free(p->u0);
    free(p->u_prev);
    free(p->g.tris);
    memset(p, 0, sizeof *p);
}

static int koopman_part_build(const rk_scene *scene, const rk_scene_sim *sim, int entry, const rk_rom_options *o,
                              const double *frames, int T, koopman_part *p, rk_error *err)
{
    int nv = sim->mesh.nv;
    memset(p, 0, sizeof *p);
    if (rk_koopman_scene_build(scene, sim, entry, &o->basis, frames, T, &p->k, &p->ki, err)) return -1;
    p->accel = rk_calloc((size_t)3 * nv, sizeof(double), err);
    p->u0 = rk_calloc((size_t)3 * nv, sizeof(double), err);
    p->u_prev = rk_calloc((size_t)3 * nv, sizeof(double), err);
    if (!p->accel || !p->u0 || !p->u_prev) return koopman_part_free(p), -1;
    rk_koopman_scene_accel(sim, sim->options.gravity, sim->options.force, p->accel);
    rk_koopman_frame_before(sim, sim->options.velocity0, p->u_prev);
    p->g = (rk_koopman_geometry){nv, sim->mesh.X, sim->fem.vertex_mass, NULL, 0, p->accel, p->u0, p->u_prev,
                                 sim->mesh.nt, p->ki.trajectories};
    if (rk_mesh_boundary(&sim->mesh, &p->g.tris, &p->g.ntris, err)) return koopman_part_free(p), -1;
    return 0;
}

/* The report's training keys for a Koopman operator. */
static void add_training(cJSON *report, const rk_koopman_scene_info *ki)
{
    cJSON *tj = cJSON_AddObjectToObject(report, "training");
    cJSON_AddNumberToObject(tj, "trajectories", ki->trajectories);
    cJSON_AddNumberToObject(tj, "frames", ki->frames);
    cJSON_AddBoolToObject(tj, "projected", ki->projected);
}

/* rom.koopman without cubature: an asset holding the Koopman operator only. */
static int build_koopman(const char *scene_path, const rk_scene *scene, const rk_scene_sim *sim, int entry,
                         const rk_rom_options *o, const rk_asset_options *ao, const double *given, int given_T,
                         const char *out, const char *report_out, double t0, rk_error *err)
{
    koopman_part p;
    int nv = sim->mesh.nv, rc;
    if (koopman_part_build(scene, sim, entry, o, given, given_T, &p, err)) return -1;
    cJSON *report = cJSON_CreateObject(), *j = cJSON_CreateObject();
    const char *slash = strrchr(scene_path, '/');
    cJSON_AddStringToObject(j, "scene", slash ? slash + 1 : scene_path);
    cJSON_AddStringToObject(j, "method", "koopman");
    cJSON_AddNumberToObject(j, "rank", p.k.r);
    cJSON_AddNumberToObject(j, "trajectories", p.ki.trajectories);
    char *info = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    cJSON_AddNumberToObject(report, "vertices", nv);
    cJSON_AddNumberToObject(report, "tets", sim->mesh.nt);
    if (p.ki.projected) {
        cJSON *bj = cJSON_AddObjectToObject(report, "basis");
        cJSON_AddStringToObject(bj, "type", rk_basis_type_name(p.ki.basis_type));
        cJSON_AddNumberToObject(bj, "size", p.ki.basis_columns);
    }
    add_training(report, &p.ki);
    cJSON *sj = cJSON_AddObjectToObject(report, "seconds");
    cJSON_AddNumberToObject(sj, "fom", p.ki.seconds_fom);
    cJSON_AddNumberToObject(sj, "basis", p.ki.seconds_basis);
    cJSON_AddNumberToObject(sj, "fit", p.ki.seconds_fit);
    cJSON_AddNumberToObject(sj, "total", rk_now() - t0);
    rc = koopman_asset_write(&p.k, &p.g, ao, info, out, report_out, report, err);
    free(info);
    cJSON_Delete(report);
    koopman_part_free(&p);
    return rc;
}

/* --training S.npy: the scene's full-order run (romkit fom --snapshots: steps + 1 frames of every
 * vertex, the first at rest) as displacement frames after each step, instead of running it. */
static int load_training(const char *path, const rk_scene_sim *sim, double **frames, int *T, rk_error *err)
{
    double *x;
    int ndim;
    long shape[4];
    if (rk_npy_read(path, &x, &ndim, shape, err)) return -1;
    int n3 = 3 * sim->mesh.nv;
    if (ndim != 3 || shape[1] != sim->mesh.nv || shape[2] != 3 || shape[0] != sim->steps + 1) {
        free(x);
        return rk_fail(err, "--training %s: expected this scene's full-order frames, %d x %d x 3 (romkit fom --snapshots), "
                       "got %ld%s%ld%s%ld", path, sim->steps + 1, sim->mesh.nv, shape[0], ndim > 1 ? " x " : "",
                       ndim > 1 ? shape[1] : 0L, ndim > 2 ? " x " : "", ndim > 2 ? shape[2] : 0L);
    }
    *T = sim->steps;
    for (int t = 0; t < *T; t++)
        for (int i = 0; i < n3; i++) x[(size_t)n3 * t + i] = x[(size_t)n3 * (t + 1) + i] - sim->mesh.X[i];
    *frames = x;
    return 0;
}

int cmd_build(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            build_usage(stdout);
            return 0;
        }
    const char *scene_path, *out = NULL, *report_out = NULL, *precision = NULL, *entry_text = NULL, *training = NULL;
    int quiet = 0, compress = 0, entry = 0;
    const cli_option opts[] = {{"-o", &out, NULL},           {"--report", &report_out, NULL},
                               {"--precision", &precision, NULL}, {"--compress", NULL, &compress},
                               {"--entry", &entry_text, NULL}, {"--training", &training, NULL},
                               {"--quiet", NULL, &quiet},     {NULL, NULL, NULL}};
    if (cli_parse("build", argc, argv, opts, &scene_path, "scene file")) {
        build_usage(stderr);
        return 2;
    }
    if (!out) {
        fprintf(stderr, "romkit build: -o OUT.rombin is required\n");
        build_usage(stderr);
        return 2;
    }
    rk_progress_set_quiet(quiet);
    double t0 = rk_now();
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    rk_scene_rom R;
    koopman_part kp;
    rk_rom_options o;
    rk_asset_options ao;
    rk_asset_summary sum = {0};
    rombin_writer w;
    unsigned char *data = NULL;
    size_t bytes = 0;
    char *info = NULL;
    double *frames = NULL;
    int stage = 0, rc = 1, T = 0;
    rk_asset_default_options(&ao);
    if (rk_scene_load(scene_path, &scene, &err)) goto done;
    stage = 1;
    if (rk_rom_entries(scene.rom) < 1) {
        rk_fail(&err, "%s: the scene has no rom section (what should be baked?)", scene_path);
        goto done;
    }
    if (entry_text) {
        long e;
        if (cli_whole(entry_text, 0, rk_rom_entries(scene.rom) - 1, &e)) {
            rk_fail(&err, "--entry must be a rom entry of %s, 0..%d, got '%s'", scene_path, rk_rom_entries(scene.rom) - 1,
                    entry_text);
            goto done;
        }
        entry = (int)e;
    }
    if (rk_rom_options_parse(scene.rom, entry, scene_path, &o, &err) ||
        rk_asset_options_parse(scene.rom, entry, scene_path, &ao, &err))
        goto done;
    if (asset_flags("build", precision, compress, &ao)) {
        rc = 2;
        goto done;
    }
    if (rk_scene_build(&scene, &sim, &err)) goto done;
    stage = 2;
    if (training && load_training(training, &sim, &frames, &T, &err)) goto done;
    int with_koopman = rk_koopman_scene_present(scene.rom, entry);
    if (with_koopman && !o.cubature) {
        rc = build_koopman(scene_path, &scene, &sim, entry, &o, &ao, frames, T, out, report_out, t0, &err) ? 1 : 0;
        goto done;
    }
    /* The cubature trains on the scene's full-order run (and POD or a tolerance use it too): run it once. */
    if (!frames && (o.cubature || rk_basis_needs_frames(&o.basis)) &&
        rk_scene_training_frames(&sim, &frames, &T, &err))
        goto done;
    if (rk_scene_rom_build(&scene, &sim, &o, frames, T, &R, &err)) goto done;
    stage = 3;
    /* an entry with cubature and koopman: both models in one asset, trained on the same run */
    if (with_koopman && koopman_part_build(&scene, &sim, entry, &o, frames, T, &kp, &err)) goto done;
    stage = with_koopman ? 4 : 3;
    info = info_text(scene_path, &o, &R);
    rombin_writer_init(&w, ao.real_type, ao.compress);
    if (rk_asset_bake_with(&sim, &R, with_koopman ? &kp.k : NULL, with_koopman ? &kp.g : NULL, &ao, info, &w, &sum, &err) ||
        rombin_serialize(&w, &data, &bytes, &err)) {
        rombin_writer_free(&w);
        goto done;
    }
    rombin_writer_free(&w);
    if (rombin_save(out, data, bytes, &err)) goto done;
    if (report_out) {
        cJSON *report = make_report(&sim, &R, &sum, data, bytes, rk_now() - t0);
        if (with_koopman) {
            cJSON_AddItemToObject(report, "koopman", koopman_report(&kp.k));
            add_training(report, &kp.ki);
        }
        int bad = rk_json_write_file(report_out, report, &err);
        cJSON_Delete(report);
        if (bad) goto done;
    }
    printf("%s: %s, r = %d, %d cubature elements, %d of %d vertices stored (%d shown), %zu bytes\n", out, o.name,
           R.model.r, R.model.quad.count, sum.vertices, sim.mesh.nv, sum.shown, bytes);
    if (with_koopman)
        printf("  and a Koopman operator of rank %d beside it (romkit run --koopman, romrt_open_kind)\n", kp.k.r);
    rc = 0;
done:
    if (rc) fprintf(stderr, "romkit build: %s\n", err.msg);
    free(data);
    free(info);
    free(frames);
    if (stage >= 4) koopman_part_free(&kp);
    if (stage >= 3) rk_scene_rom_free(&R);
    if (stage >= 2) rk_scene_sim_free(&sim);
    if (stage >= 1) rk_scene_free(&scene);
    return rc;
}
