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
#include "pipeline/pipeline.h"
#include "util/util.h"

static void neural_dmd_usage(FILE *f)
{
    fprintf(f,
            "usage: romkit neural-dmd FAMILY.json --scene S.json [--gamma G1,G2,...] -o OUT.rombin\n"
            "                         [--precision float32|float64] [--compress] [--report R.json] [--quiet]\n"
            "  trains the neural DMD (modes as a network of rest position and shape code gamma, eigenvalues\n"
            "  as a network of gamma) on every member of the family, then bakes its operator on the mesh of\n"
            "  S.json at shape code gamma into OUT.rombin for the runtime.\n"
            "  FAMILY.json  {\"members\": [{\"scene\": \"a.json\", \"snapshots\": \"a.npy\", \"gamma\": [0.14]}, ...],\n"
            "               \"rank\": R, \"network\": {\"hidden\": 64, \"depth\": 3, \"eig_hidden\": 32, \"eig_depth\": 2},\n"
            "               \"training\": {\"pretrain_epochs\": 300, \"epochs\": 400, \"learning_rate\": 2e-4,\n"
            "               \"window\": 1, \"init_member\": -1}, \"seed\": 0}: each member a scene (mesh, material,\n"
            "               fixed vertices, forcing, time step), its run by romkit fom --snapshots and its\n"
            "               shape code (g numbers, the same g for all; none: g = 0); paths relative to\n"
            "               FAMILY.json; every key but members and rank optional (the defaults shown)\n"
            "  --scene      the mesh to bake on (its forcing and start go into the asset; the family's time step)\n"
            "  --gamma      its shape code, g comma-separated numbers inside the members' range (needed when g > 0)\n"
            "  --precision  real type of the asset's arrays: float32 (default) or float64\n"
            "  --compress   deflate the asset's chunks\n"
            "  --report R.json  the training loss, each member's rollout error (%% MSE against its snapshots),\n"
            "               the asset's rank, eigenvalues and max |lambda|\n"
            "  --quiet      no progress on stderr\n\n"
            "example (a family of beams of three thicknesses, baked at an unseen one, against its own run):\n"
            "  romkit fom b14.json --snapshots b14.npy   (and b18, b22; family.json lists the three)\n"
            "  romkit neural-dmd family.json --scene b20.json --gamma 0.20 -o b20.rombin --report r.json\n"
            "  romkit fom b20.json --snapshots b20.npy\n"
            "  romkit run b20.rombin --steps 100 --reference b20.npy\n");
}

typedef struct {
    const char *family, *scene, *gamma, *out, *report, *precision;
    int compress, quiet;
} nd_args;

/* --gamma: exactly g finite numbers, each inside the members' range. */
static int parse_gamma(const char *text, const rk_family *f, double *gamma, rk_error *err)
{
    if (!f->g) return text ? rk_fail(err, "--gamma: the family has no shape code (no member has a gamma)") : 0;
    if (!text) return rk_fail(err, "--gamma is required: the family's shape code has %d values", f->g);
    const char *p = text;
    for (int j = 0; j < f->g; j++) {
        char *end;
        gamma[j] = strtod(p, &end);
        if (end == p || !isfinite(gamma[j]) || (j + 1 < f->g ? *end != ',' : *end != '\0'))
            return rk_fail(err, "--gamma '%s': need %d comma-separated finite numbers (the family's shape code)", text,
                           f->g);
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i < f->nmembers; i++) lo = fmin(lo, f->member[i].gamma[j]), hi = fmax(hi, f->member[i].gamma[j]);
        if (gamma[j] < lo || gamma[j] > hi)
            return rk_fail(err, "--gamma '%s': value %d (%g) is outside the members' range [%g, %g]", text, j,
                           gamma[j], lo, hi);
        p = end + 1;
    }
    return 0;
}

/* Each member's rollout against its own snapshots, into the report and onto stdout. */
static int member_errors(const rk_koopman_neural *nk, const rk_family *f, cJSON *arr, int quiet, rk_error *err)
{
    for (int i = 0; i < f->nmembers; i++) {
        const rk_family_member *m = &f->member[i];
        rk_koopman k;
        double pct, peak;
        if (rk_koopman_neural_operator(nk, m->sim.mesh.X, m->sim.mesh.nv, f->g ? m->gamma : NULL, &k, err))
            return rk_error_prefix(err, "members[%d]", i);
        int rc = rk_koopman_rollout_error(&k, &m->run.t, &pct, &peak, err);
        rk_koopman_free(&k);
        if (rc) return rk_error_prefix(err, "members[%d]: %s", i, m->snapshots);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "snapshots", m->snapshots);
        cJSON_AddItemToObject(o, "gamma", rk_json_array(m->gamma, f->g));
        cJSON_AddNumberToObject(o, "mse_percent", pct);
        cJSON_AddNumberToObject(o, "peak_relative_error", peak);
        cJSON_AddItemToArray(arr, o);
        if (!quiet) printf("  member %d (%s): rollout %.4g%% MSE, peak %.3g of the largest displacement\n", i,
                           m->snapshots, pct, peak);
    }
    return 0;
}

/* The trained model on the scene's mesh at gamma, baked; the report gets the training's part. */
static int bake(const rk_koopman_neural *nk, const rk_koopman_neural_report *tr, const rk_family *f,
                const rk_scene_sim *sim, const double *gamma, const rk_asset_options *ao, rk_baked *out, rk_error *err)
{
    rk_scene_koopman sk;
    memset(&sk, 0, sizeof sk);
    sk.info.trajectories = f->nmembers;
    int rc = rk_koopman_neural_operator(nk, sim->mesh.X, sim->mesh.nv, f->g ? gamma : NULL, &sk.k, err) ||
             rk_scene_koopman_geometry(sim, &sk, err);
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

/* Train, measure, bake, save: the asset and the report written only when everything succeeded. */
static int neural_dmd(const nd_args *a, const rk_asset_options *ao, rk_error *err)
{
    rk_family f;
    rk_scene sc;
    rk_scene_sim sim;
    double gamma[RK_KOOPMAN_SHAPE_MAX] = {0};
    if (rk_family_load(a->family, &f, err)) return -1;
    int rc = -1, built = 0;
    if (parse_gamma(a->gamma, &f, gamma, err)) goto done;
    if (rk_scene_load(a->scene, &sc, err)) goto done;
    if (rk_scene_build(&sc, &sim, err)) {
        rk_scene_free(&sc);
        goto done;
    }
    built = 1;
    if (sim.options.h != f.options.h) {
        rk_fail(err, "--scene %s steps %g s, the family's members %g s", a->scene, sim.options.h, f.options.h);
        goto done;
    }
    rk_koopman_neural nk;
    rk_koopman_neural_report tr;
    int blas = rk_threads_blas(1); /* the same sums, so the same weights, on any thread count */
    rc = rk_koopman_neural_train(f.mesh, f.nmembers, &f.options, &nk, &tr, err);
    rk_threads_blas(blas);
    if (rc) goto done;
    if (!a->quiet) printf("neural DMD on %d members, rank %d: loss %.4g after the regression, %.4g after %d steps (%.1f s)\n",
                          f.nmembers, nk.r, tr.pretrained_loss, tr.final_loss, f.options.epochs, tr.seconds);
    rk_baked baked;
    rc = bake(&nk, &tr, &f, &sim, gamma, ao, &baked, err);
    if (!rc) {
        rc = member_errors(&nk, &f, cJSON_GetObjectItem(cJSON_GetObjectItem(baked.report, "neural"), "member_errors"),
                           a->quiet, err) ||
             rombin_save(a->out, baked.data, baked.bytes, err) || (a->report && rk_json_write_file(a->report, baked.report, err));
        if (!rc) printf("%s: %s\n", a->out, baked.summary);
        rk_baked_free(&baked);
    }
    rk_koopman_neural_free(&nk);
done:
    if (built) {
        rk_scene_sim_free(&sim);
        rk_scene_free(&sc);
    }
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
                               {"--quiet", NULL, &a.quiet},         {NULL, NULL, NULL}};
    if (cli_parse("neural-dmd", argc, argv, opts, &a.family, "family file")) {
        neural_dmd_usage(stderr);
        return 2;
    }
    if (!a.scene || !a.out) {
        fprintf(stderr, "romkit neural-dmd: --scene and -o are required\n");
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
