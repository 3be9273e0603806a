/* romkit neural-dmd FAMILY.json --scene S.json --gamma G -o OUT.rombin: the neural, shape-conditioned
 * DMD (koopman-dmd-log-linear paper, Sec. 5) trained on a family of meshes (rk_family_load: each
 * member a scene, its full-order snapshots and its shape code), then its operator on another mesh
 * at a code inside the training range (rk_koopman_neural_operator) baked as romkit dmd bakes one
 * (rk_bake_koopman), for romkit run. Training runs OpenBLAS on one thread: a seed gives the same
 * weights on any machine's thread count. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "formats/rombin_write.h"
#include "neural_shape.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_koopman.h"
#include "pipeline/family.h"
#include "util/util.h"

static void neural_dmd_usage(FILE *f)
{
    fprintf(f,
            "usage: romkit neural-dmd FAMILY.json --scene S.json [--gamma G1,G2,...] -o OUT.rombin\n"
            "                         [--precision float32|float64] [--compress] [--report R.json] [--quiet]\n"
            "                         [--model M | --save-model M]\n"
            "       romkit neural-dmd FAMILY.json --objective VERTEX,AXIS --target T --steps N -o OUT.rombin\n"
            "                         [--gamma-start G1,G2,...] [the output options]\n"
            "       romkit neural-dmd FAMILY.json --lift X0,Y0,Z0,X1,Y1,Z1 --steps N -o OUT.rombin\n"
            "                         [--gamma-start G1,G2,...] [--scene-out S.json] [the output options]\n"
            "  trains the neural DMD (modes as a network of rest position and shape code gamma, eigenvalues\n"
            "  as a network of gamma) on every member of the family, then bakes its operator on the mesh of\n"
            "  S.json at shape code gamma into OUT.rombin for the runtime.\n"
            "  FAMILY.json  {\"members\": [{\"scene\": \"a.json\", \"snapshots\": \"a.npy\", \"gamma\": [0.14]}, ...],\n"
            "               \"rank\": R, \"network\": {\"hidden\": 64, \"depth\": 3, \"eig_hidden\": 32, \"eig_depth\": 2},\n"
            "               \"training\": {\"pretrain_epochs\": 300, \"epochs\": 400, \"learning_rate\": 2e-4,\n"
            "               \"window\": 1, \"init_member\": -1, \"polish\": 0, \"vertices\": 4096}, \"seed\": 1}:\n"
            "               polish is L-BFGS steps on the same loss after Adam's; vertices the most of a\n"
            "               member the training sees (a fixed random sample of a larger mesh; 0: all: the\n"
            "               modes are a field of the rest position, evaluated and baked at every vertex);\n"
            "               each member a scene (mesh, material, fixed vertices, forcing, time step),\n"
            "               its run by romkit fom --snapshots and its shape code (g numbers, the same g\n"
            "               for all; none: g = 0); paths relative to FAMILY.json; every key but members\n"
            "               and rank optional (the defaults shown)\n"
            "  --scene      the mesh to bake on (its forcing and start go into the asset; the family's time step)\n"
            "  --gamma      its shape code, g comma-separated numbers inside the members' range (needed when g > 0)\n"
            "  --precision  real type of the asset's arrays: float32 (default) or float64\n"
            "  --compress   deflate the asset's chunks\n"
            "  --report R.json  the training loss, each member's rollout error (%% MSE against its snapshots;\n"
            "               relative error and normalized MSE of the positions at all its vertices), the\n"
            "               asset's rank, eigenvalues and max |lambda|\n"
            "  --quiet      no progress on stderr\n"
            "  --save-model M  also save the trained model to M (written last, when all else succeeded)\n"
            "  --model M    a model saved by --save-model instead of training (it must match the family's\n"
            "               rank, shape code and time step; the family still gives the members' errors)\n"
            "  Shape optimisation (Sec. 7.4), instead of --scene and --gamma: the code whose mesh (the family's\n"
            "  \"shape\": {\"scene\": \"s.json\", \"size\": [x, y, z], \"size_per_gamma\": [[x, y, z], ...]}, its first\n"
            "  object a box of size size + sum_j gamma_j size_per_gamma[j]) puts a vertex where asked, found by\n"
            "  Newton on gamma through the model's closed-form N-step jump; the asset is baked there\n"
            "  --objective  VERTEX,AXIS: the vertex (index in the shape's mesh) and x, y or z\n"
            "  --target     the position (m) that coordinate should reach after --steps N steps from rest\n"
            "  --steps      N >= 1\n"
            "  --gamma-start  where the search starts (default: the middle of the members' range)\n"
            "  --lift       maximise instead the mean y displacement after --steps N steps of the vertices whose\n"
            "               rest positions lie in the box (Fig. 16's lift), by projected gradient ascent over the\n"
            "               members' range; the family's \"shape\" may also move any number of its scene by\n"
            "               \"keys\": [{\"key\": \"objects[0].mesh.voids[0].box[1][0]\", \"per_gamma\": [...]}]. A\n"
            "               chamber's pressure, held from t = 0, is each member's load. The report gives each\n"
            "               member's lift by the model and at full order; members with \"held_out\": true are\n"
            "               not trained on, and their error is the model's own\n"
            "  --scene-out  write the optimum's scene there (for romkit fom at the optimum)\n\n"
            "example (a family of beams of three thicknesses, baked at an unseen one, against its own run):\n"
            "  romkit fom b14.json --snapshots b14.npy   (and b18, b22; family.json lists the three)\n"
            "  romkit neural-dmd family.json --scene b20.json --gamma 0.20 -o b20.rombin --report r.json\n"
            "  romkit fom b20.json --snapshots b20.npy\n"
            "  romkit run b20.rombin --steps 100 --reference b20.npy\n"
            "example (a \"shape\" in family.json: the thickness whose tip corner, vertex 6, is 3.5 cm down at 1 s):\n"
            "  romkit neural-dmd family.json --objective 6,y --target -0.035 --steps 100 -o tip.rombin\n"
            "example (the pneumatic finger family of examples/shape_family: the chamber that lifts the tip most):\n"
            "  romkit neural-dmd family.json --lift 0.0795,-1,-1,0.081,1,1 --steps 40 -o opt.rombin\n"
            "                    --scene-out opt.json --report opt_report.json\n");
}

typedef struct {
    const char *family, *scene, *gamma, *out, *report, *precision;
    const char *model, *save_model; /* --model: a saved model instead of training; --save-model: save it */
    int compress, quiet;
    neural_shape_args sh;
} nd_args;

/* --gamma: needed exactly when the family has a shape code. */
static int bake_gamma(const char *text, const rk_family *f, double *gamma, rk_error *err)
{
    if (!f->g) return text ? rk_fail(err, "--gamma: the family has no shape code (no member has a gamma)") : 0;
    if (!text) return rk_fail(err, "--gamma is required: the family's shape code has %d values", f->g);
    return neural_gamma("--gamma", text, f, gamma, err);
}

/* The scene to bake on: the file given, or the family's shape at gamma; the family's time step. */
static int open_scene(const char *path, const rk_family *f, const double *gamma, rk_scene *sc, rk_scene_sim *sim,
                      rk_error *err)
{
    if (path ? rk_scene_load(path, sc, err) : rk_family_shape_scene(f, gamma, sc, err)) return -1;
    if (rk_scene_build(sc, sim, err)) {
        rk_scene_free(sc);
        return -1;
    }
    if (sim->options.h == f->options.h) return 0;
    rk_fail(err, "%s steps %g s, the family's members %g s", path ? path : f->shape_scene, sim->options.h, f->options.h);
    rk_scene_sim_free(sim);
    rk_scene_free(sc);
    return -1;
}

/* Each member's rollout against its own snapshots at every vertex, into the report and onto stdout:
 * the % MSE of the displacements, and the relative error and normalized MSE of the positions
 * (util's metrics, as romkit run --reference has them at the shown vertices only). */
static int member_errors(const rk_koopman_neural *nk, const rk_family *f, cJSON *arr, int quiet, rk_error *err)
{
    for (int i = 0; i < f->nmembers; i++) {
        const rk_family_member *m = &f->member[i];
        rk_koopman k;
        double pct, peak;
        rk_run_error e;
        if (rk_koopman_neural_operator(nk, m->sim.mesh.X, m->sim.mesh.nv, f->g ? m->gamma : NULL, &k, err))
            return rk_error_prefix(err, "members[%d]", i);
        int rc = rk_koopman_rollout_run_error(&k, &m->run.t, m->sim.mesh.X, &e, &pct, &peak, err);
        rk_koopman_free(&k);
        if (rc) return rk_error_prefix(err, "members[%d]: %s", i, m->snapshots);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "snapshots", m->snapshots);
        cJSON_AddBoolToObject(o, "held_out", m->held_out);
        cJSON_AddItemToObject(o, "gamma", rk_json_array(m->gamma, f->g));
        cJSON_AddNumberToObject(o, "mse_percent", pct);
        cJSON_AddNumberToObject(o, "peak_relative_error", peak);
        cJSON_AddNumberToObject(o, "vertices", m->sim.mesh.nv);
        cJSON_AddNumberToObject(o, "relative_error", rk_relative_error(&e));
        cJSON_AddNumberToObject(o, "normalized_mse", rk_normalized_mse(&e));
        cJSON_AddItemToArray(arr, o);
        if (!quiet)
            printf("  member %d (%s%s): rollout %.4g%% MSE, peak %.3g of the largest displacement; at all %d vertices "
                   "relative error %.3g, normalized MSE %.3g\n", i, m->snapshots, m->held_out ? ", held out" : "", pct, peak,
                   m->sim.mesh.nv, rk_relative_error(&e), rk_normalized_mse(&e));
    }
    return 0;
}

/* The trained model on the scene's mesh at gamma, baked; the report gets the training's part. */
static int bake(const rk_koopman_neural *nk, const rk_koopman_neural_report *tr, const rk_family *f,
                const rk_scene_sim *sim, const double *gamma, const rk_asset_options *ao, rk_baked *out, rk_error *err)
{
    rk_scene_koopman sk;
    memset(&sk, 0, sizeof sk);
    sk.info.trajectories = f->ntrain;
    int rc = rk_koopman_neural_operator(nk, sim->mesh.X, sim->mesh.nv, f->g ? gamma : NULL, &sk.k, err) ||
             rk_scene_koopman_geometry(sim, &sk, err) || rk_koopman_scene_pressure_accel(sim, sk.accel, err);
    cJSON *info = cJSON_CreateObject(), *members = cJSON_CreateArray();
    cJSON_AddStringToObject(info, "method", "koopman");
    cJSON_AddStringToObject(info, "source", "romkit neural-dmd");
    cJSON_AddNumberToObject(info, "rank", nk->r);
    cJSON_AddItemToObject(info, "gamma", rk_json_array(gamma, f->g));
    char *info_text = cJSON_PrintUnformatted(info);
    cJSON_Delete(info);
    if (!rc) rc = rk_bake_koopman(&sk.k, &sk.geometry, ao, info_text, out, err);
    free(info_text);
    rk_scene_koopman_free(&sk);
    if (!rc) {
        cJSON *n = cJSON_AddObjectToObject(out->report, "neural");
        cJSON_AddNumberToObject(n, "members", f->nmembers);
        cJSON_AddNumberToObject(n, "held_out", f->nmembers - f->ntrain);
        cJSON_AddNumberToObject(n, "shape_dim", f->g);
        cJSON_AddItemToObject(n, "gamma", rk_json_array(gamma, f->g));
        cJSON_AddNumberToObject(n, "pretrained_loss", tr->pretrained_loss);
        cJSON_AddNumberToObject(n, "final_loss", tr->final_loss);
        cJSON_AddNumberToObject(n, "seconds_training", tr->seconds);
        cJSON_AddItemToObject(n, "member_errors", members);
        cJSON_AddNumberToObject(out->report, "vertices", sim->mesh.nv);
        return 0;
    }
    cJSON_Delete(members);
    return -1;
}

/* A saved model in place of the training: it must be one this family could have trained (the same
 * rank, shape code length and time step). */
static int load_model(const char *path, const rk_family *f, rk_koopman_neural *nk, rk_koopman_neural_report *tr,
                      rk_error *err)
{
    if (rk_koopman_neural_read(path, nk, tr, err)) return rk_error_prefix(err, "--model");
    if (nk->r != f->options.rank || nk->g != f->g || fabs(nk->h - f->options.h) > 1e-12 * f->options.h) {
        rk_fail(err, "--model %s: rank %d, shape code of %d values, time step %g; the family has rank %d, %d values, "
                "time step %g", path, nk->r, nk->g, nk->h, f->options.rank, f->g, f->options.h);
        rk_koopman_neural_free(nk);
        return -1;
    }
    return 0;
}

/* Trains (or loads --model); with --objective finds the code. */
static int train(const nd_args *a, const rk_family *f, rk_koopman_neural *nk, rk_koopman_neural_report *tr,
                 double *gamma, cJSON *opt, rk_error *err)
{
    if (a->model) {
        if (load_model(a->model, f, nk, tr, err)) return -1;
        if (!a->quiet) printf("neural DMD from %s, rank %d: loss %.4g when it was trained\n", a->model, nk->r,
                              tr->final_loss);
    } else {
        int blas = rk_threads_blas(1); /* the same sums, so the same weights, on any thread count */
        int rc = rk_koopman_neural_train(f->train, f->ntrain, &f->options, nk, tr, err);
        rk_threads_blas(blas);
        if (rc) return -1;
        if (!a->quiet)
            printf("neural DMD on %d members, rank %d: loss %.4g after the regression, %.4g after %d steps (%.1f s)\n",
                   f->ntrain, nk->r, tr->pretrained_loss, tr->final_loss, f->options.epochs, tr->seconds);
    }
    if (neural_shape_wanted(&a->sh) && (neural_shape_optimize(&a->sh, nk, f, gamma, opt, err) ||
                                         neural_shape_members(&a->sh, nk, f, opt, a->quiet, err))) {
        rk_koopman_neural_free(nk);
        return -1;
    }
    return 0;
}

/* Measure, bake, save: the asset and the report written only when everything succeeded. */
static int bake_and_save(const nd_args *a, const rk_koopman_neural *nk, const rk_koopman_neural_report *tr,
                         const rk_family *f, const double *gamma, cJSON *opt, const rk_asset_options *ao, rk_error *err)
{
    rk_scene sc;
    rk_scene_sim sim;
    rk_baked baked;
    if (open_scene(neural_shape_wanted(&a->sh) ? NULL : a->scene, f, gamma, &sc, &sim, err)) return -1;
    int rc = bake(nk, tr, f, &sim, gamma, ao, &baked, err);
    rk_scene_sim_free(&sim);
    rk_scene_free(&sc);
    if (rc) return -1;
    if (neural_shape_wanted(&a->sh)) cJSON_AddItemReferenceToObject(baked.report, "shape_optimization", opt);
    rc = member_errors(nk, f, cJSON_GetObjectItem(cJSON_GetObjectItem(baked.report, "neural"), "member_errors"),
                       a->quiet, err) ||
         rombin_save(a->out, baked.data, baked.bytes, err) || (a->report && rk_json_write_file(a->report, baked.report, err)) ||
         (a->save_model && rk_koopman_neural_write(nk, tr, a->save_model, err));
    if (!rc) printf("%s: %s\n", a->out, baked.summary);
    rk_baked_free(&baked);
    return rc ? -1 : 0;
}

static int neural_dmd(const nd_args *a, const rk_asset_options *ao, rk_error *err)
{
    rk_family f;
    rk_koopman_neural nk;
    rk_koopman_neural_report tr;
    double gamma[RK_KOOPMAN_SHAPE_MAX] = {0};
    if (rk_family_load(a->family, &f, err)) return -1;
    rk_scene sc;
    rk_scene_sim sim;
    /* every input checked before the training: the code, the scene (or the shape at the start) */
    int shape = neural_shape_wanted(&a->sh);
    int rc = shape ? neural_shape_check(&a->sh, &f, err)
                   : bake_gamma(a->gamma, &f, gamma, err) || open_scene(a->scene, &f, gamma, &sc, &sim, err);
    if (!rc && !shape) rk_scene_sim_free(&sim), rk_scene_free(&sc);
    cJSON *opt = cJSON_CreateObject();
    if (!rc && !(rc = train(a, &f, &nk, &tr, gamma, opt, err))) {
        rc = bake_and_save(a, &nk, &tr, &f, gamma, opt, ao, err);
        rk_koopman_neural_free(&nk);
    }
    cJSON_Delete(opt);
    rk_family_free(&f);
    return rc ? -1 : 0;
}

int cmd_neural_dmd(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            neural_dmd_usage(stdout);
            return 0;
        }
    nd_args a;
    memset(&a, 0, sizeof a);
    const cli_option opts[] = {{"--scene", &a.scene, NULL},         {"--gamma", &a.gamma, NULL},
                               {"-o", &a.out, NULL},                {"--report", &a.report, NULL},
                               {"--precision", &a.precision, NULL}, {"--compress", NULL, &a.compress},
                               {"--quiet", NULL, &a.quiet},         {"--objective", &a.sh.objective, NULL},
                               {"--target", &a.sh.target, NULL},    {"--steps", &a.sh.steps, NULL},
                               {"--gamma-start", &a.sh.start, NULL}, {"--model", &a.model, NULL},
                               {"--save-model", &a.save_model, NULL}, {"--lift", &a.sh.lift, NULL},
                               {"--scene-out", &a.sh.scene_out, NULL}, {NULL, NULL, NULL}};
    if (cli_parse("neural-dmd", argc, argv, opts, &a.family, "family file")) {
        neural_dmd_usage(stderr);
        return 2;
    }
    int shape = neural_shape_wanted(&a.sh);
    const char *clash = !shape ? (a.sh.target     ? "--target"
                                  : a.sh.steps    ? "--steps"
                                  : a.sh.start    ? "--gamma-start"
                                  : a.sh.scene_out ? "--scene-out"
                                                  : NULL)
                      : a.scene                    ? "--scene"
                      : a.gamma                    ? "--gamma"
                      : a.sh.lift && a.sh.objective ? "--lift"
                      : a.sh.lift && a.sh.target   ? "--target"
                                                   : NULL;
    if (clash) {
        fprintf(stderr, "romkit neural-dmd: %s %s\n", clash,
                !shape ? "needs --objective or --lift"
                : a.sh.lift && (a.sh.objective || a.sh.target)
                    ? "does not go with --objective (--lift is an objective of its own, with no target)"
                    : "does not go with --objective or --lift (the optimum's code and the family's shape are baked)");
        neural_dmd_usage(stderr);
        return 2;
    }
    if (a.model && a.save_model) {
        fprintf(stderr, "romkit neural-dmd: --save-model does not go with --model (that model is saved already)\n");
        neural_dmd_usage(stderr);
        return 2;
    }
    if ((!a.scene && !shape) || !a.out) {
        fprintf(stderr, "romkit neural-dmd: -o and --scene (or --objective, or --lift) are required\n");
        neural_dmd_usage(stderr);
        return 2;
    }
    rk_progress_set_quiet(a.quiet);
    rk_asset_options ao;
    rk_asset_default_options(&ao);
    int has_real_type, real_type;
    if (cli_precision("neural-dmd", a.precision, &has_real_type, &real_type)) return 2;
    if (has_real_type) ao.real_type = real_type;
    ao.compress = a.compress;
    rk_error err = {{0}};
    if (neural_dmd(&a, &ao, &err)) {
        fprintf(stderr, "romkit neural-dmd: %s\n", err.msg);
        return 1;
    }
    return 0;
}
