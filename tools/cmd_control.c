/* romkit control SCENE.json --target T.npy --inputs GROUP:AXES[,...]: the forces on named vertex
 * groups that make a Koopman model follow a target trajectory (koopman-dmd-log-linear paper,
 * Sec. 7.3, Figs. 14-15), checked by running the full-order model under them.
 *
 * Why a scene and not a .rombin: the control needs the fitted operator in double precision with
 * its lifted basis (rk_koopman; an asset holds only the runtime's real form, in float32 by
 * default), training runs that show the model each input's push, and the full-order model to
 * check the answer against. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "pipeline/control.h"
#include "util/util.h"

/* --regularize's default: lambda = 0.2 sigma_max(A) (rk_lstsq_tikhonov). Measured on
 * cli_control.sh's beam: the axial input (tip:xyz, rank 60) drifts up to 405 N and the loop misses by
 * 48% unregularised, by 3.5% at 0.1, 0.56% at 0.2; the bending inputs alone (tip:yz) go from
 * 0.025% to 0.036%. The price: a solve shrinks the input along A's strongest direction by
 * rho^2 / (1 + rho^2), 4% here, which the next frame's solve makes up (the first frame's forces
 * are 4.5% short, the later ones within 1.8%). */
#define CONTROL_REGULARIZE 0.2

static void control_usage(FILE *f)
{
    fprintf(f,
            "usage: romkit control SCENE.json --target T.npy --inputs GROUP:AXES|CHAMBER:p[,...]\n"
            "                      [--follow GROUP[,GROUP...]] [--horizon H] [--train-force N] [--nonnegative]\n"
            "                      [--train-pressure PA]\n"
            "                      [--regularize RHO]\n"
            "                      [--report R.json] [--forces C.npy] [--snapshots S.npy] [--quiet]\n"
            "  solves for forces on the scene's named vertex groups (rom.asset.groups of the first rom\n"
            "  entry with a koopman section) that make its Koopman model follow a target trajectory\n"
            "  (Sec. 7.3), then runs the full-order model under those forces and reports the error.\n"
            "  T.npy        T x n x 3 positions, frame 0 the scene's start, one frame per scene time step\n"
            "               (romkit fom --snapshots of the same object under other loads)\n"
            "  --inputs     the controlled forces: tip:xyz is three inputs, tip's total force along x, y\n"
            "               and z (newtons, spread over the group's vertices by mass); c0:p is chamber\n"
            "               c0's pressure (pascals; objects[].chambers), a follower load on its walls whose\n"
            "               map A(X) is updated from the predicted state, 5 solves a frame (Sec. 7.3)\n"
            "  --follow     the groups whose vertices must follow the target (default: the inputs' groups;\n"
            "               required with a pressure input)\n"
            "  --horizon    each frame's force is the constant one that meets the target H frames later,\n"
            "               applied for one step, solved again at the next frame (default 1)\n"
            "  --train-force  newtons held on each input during its training run (default: the group's weight)\n"
            "  --train-pressure  pascals held in each chamber during its training run (required with one)\n"
            "  --nonnegative  forces and pressures >= 0 (NNLS)\n"
            "  --regularize   RHO >= 0: each frame minimises |A C - b|^2 + lambda^2 |C|^2 with lambda = RHO times\n"
            "               A's largest singular value (Tikhonov), so that an input the model barely\n"
            "               responds to (a pull along a stiff beam) is not spent on model error\n"
            "               (default 0.2; 0: plain least squares)\n"
            "  --report     per-frame errors (%% of the target's largest displacement, every vertex):\n"
            "               full order under the forces vs target, model vs target, model vs full order\n"
            "  --forces     the solved forces, (T - 1) x inputs (row t acts from frame t to t + 1)\n"
            "  --snapshots  the full-order run under them, T x n x 3 positions\n"
            "  Nothing is written when anything fails.\n\n"
            "example (follow the tip of a run pushed by a load, with forces on the tip alone):\n"
            "  romkit fom pushed.json --snapshots target.npy\n"
            "  romkit control beam.json --target target.npy --inputs tip:xyz --report control.json\n");
}

typedef struct {
    const char *scene, *target, *inputs, *follow, *horizon, *train_force, *train_pressure, *regularize, *report, *forces,
        *snapshots;
    int nonnegative, quiet;
} control_args;

static int group_index(const rk_rom_entry *e, const char *name, size_t len, rk_error *err)
{
    for (int q = 0; q < e->asset.ngroups; q++)
        if (strlen(e->asset.groups[q].name) == len && !strncmp(e->asset.groups[q].name, name, len)) return q;
    return rk_fail(err, "no group \"%.*s\" in %s.asset.groups (%d named)", (int)len, name, e->path, e->asset.ngroups);
}

/* Whether the scene has a chamber of that name (objects[].chambers). */
static int has_chamber(const rk_scene *s, const char *name, size_t len)
{
    for (int k = 0; k < s->nobjects; k++)
        for (int j = 0; j < s->objects[k].nchambers; j++)
            if (strlen(s->objects[k].chambers[j].name) == len && !strncmp(s->objects[k].chambers[j].name, name, len))
                return 1;
    return 0;
}

/* "tip:xyz,base:y,c0:p" into inputs (CHAMBER:p a chamber's pressure); "tip,base" into follow groups. */
static int parse_inputs(const rk_scene *s, const rk_rom_entry *e, const char *text, rk_control_options *o,
                        rk_error *err)
{
    for (const char *p = text; *p;) {
        const char *end = strchr(p, ','), *colon = strchr(p, ':');
        if (!end) end = p + strlen(p);
        if (!colon || colon > end || colon + 1 == end)
            return rk_fail(err, "--inputs: '%.*s' is not GROUP:AXES (axes among x, y, z) or CHAMBER:p", (int)(end - p),
                           p);
        if (end == colon + 2 && colon[1] == 'p') { /* a chamber's pressure */
            size_t len = (size_t)(colon - p);
            if (!has_chamber(s, p, len))
                return rk_fail(err, "--inputs: '%.*s': the scene has no chamber \"%.*s\" (objects[].chambers)",
                               (int)(end - p), p, (int)len, p);
            if (o->ninputs == RK_CONTROL_MAX_INPUTS) return rk_fail(err, "--inputs: at most %d", RK_CONTROL_MAX_INPUTS);
            rk_control_input *in = &o->input[o->ninputs++];
            memset(in, 0, sizeof *in);
            snprintf(in->chamber, sizeof in->chamber, "%.*s", (int)len, p);
            p = *end ? end + 1 : end;
            continue;
        }
        int q = group_index(e, p, (size_t)(colon - p), err);
        if (q < 0) return rk_error_prefix(err, "--inputs");
        for (const char *a = colon + 1; a < end; a++) {
            if (*a < 'x' || *a > 'z') return rk_fail(err, "--inputs: axis '%c' in '%.*s' is not x, y or z", *a, (int)(end - p), p);
            if (o->ninputs == RK_CONTROL_MAX_INPUTS) return rk_fail(err, "--inputs: at most %d", RK_CONTROL_MAX_INPUTS);
            o->input[o->ninputs++] = (rk_control_input){.group = q, .axis = *a - 'x'};
        }
        p = *end ? end + 1 : end;
    }
    return o->ninputs ? 0 : rk_fail(err, "--inputs names no input");
}

static int parse_follow(const rk_rom_entry *e, const char *text, rk_control_options *o, rk_error *err)
{
    for (const char *p = text; *p;) {
        const char *end = strchr(p, ',');
        if (!end) end = p + strlen(p);
        int q = group_index(e, p, (size_t)(end - p), err);
        if (q < 0) return rk_error_prefix(err, "--follow");
        if (o->nfollow < RK_ASSET_MAX_GROUPS) o->follow[o->nfollow++] = q;
        p = *end ? end + 1 : end;
    }
    return 0;
}

/* The target as displacements (3 nv x T) from the scene's rest positions; its shape checked. */
static int load_target(const char *path, const rk_scene_sim *sim, double **u, int *T, rk_error *err)
{
    int ndim, nv = sim->mesh.nv;
    long shape[4] = {0};
    if (rk_npy_read(path, u, &ndim, shape, err)) return rk_error_prefix(err, "--target");
    if (ndim != 3 || shape[1] != nv || shape[2] != 3 || shape[0] < 2) {
        char got[96] = "";
        for (int i = 0; i < ndim && i < 4; i++)
            snprintf(got + strlen(got), sizeof got - strlen(got), "%s%ld", i ? " x " : "", shape[i]);
        free(*u);
        *u = NULL;
        return rk_fail(err, "--target %s: shape %s; expected T x %d x 3 positions of the scene's %d vertices, T >= 2 "
                       "(romkit fom --snapshots of the same object)", path, got, nv, nv);
    }
    *T = (int)shape[0];
    for (size_t i = 0; i < (size_t)3 * nv * *T; i++) {
        if (!isfinite((*u)[i])) {
            free(*u);
            *u = NULL;
            return rk_fail(err, "--target %s: frame %zu vertex %zu is not finite", path, i / (3 * (size_t)nv), i / 3 % nv);
        }
        (*u)[i] -= sim->mesh.X[i % (3 * (size_t)nv)];
    }
    return 0;
}

/* Every output, only once all of them are ready. */
static int write_outputs(const control_args *a, const rk_control_result *r, const rk_scene_sim *sim, cJSON *rep,
                         rk_error *err)
{
    int n3 = 3 * sim->mesh.nv, rc = 0;
    if (a->forces) {
        long shape[2] = {r->T - 1, r->inputs};
        rc = rk_npy_write(a->forces, r->C, 2, shape, err);
    }
    if (!rc && a->snapshots) {
        double *x = rk_calloc((size_t)n3 * r->T, sizeof(double), err);
        if (!x) return -1;
        for (size_t i = 0; i < (size_t)n3 * r->T; i++) x[i] = r->u_fom[i] + sim->mesh.X[i % n3];
        long shape[3] = {r->T, sim->mesh.nv, 3};
        rc = rk_npy_write(a->snapshots, x, 3, shape, err);
        free(x);
    }
    if (!rc && a->report) rc = rk_json_write_file(a->report, rep, err);
    return rc;
}

static int run_control(const control_args *a, rk_error *err)
{
    rk_scene scene;
    rk_scene_sim sim;
    rk_control_options o;
    rk_control_result r;
    memset(&o, 0, sizeof o);
    memset(&r, 0, sizeof r);
    const rk_rom_entry *e = NULL;
    double *target = NULL;
    int T = 0, rc = -1;
    long h = 1;
    if (rk_scene_load(a->scene, &scene, err)) return -1;
    for (int i = 0; i < scene.nentries && !e; i++)
        if (rk_koopman_of(&scene.entries[i])) e = &scene.entries[i];
    if (!e) {
        rk_fail(err, "%s: no rom entry has a koopman section", a->scene);
        rk_scene_free(&scene);
        return -1;
    }
    if (a->horizon && cli_whole(a->horizon, 1, 100000, &h)) {
        rk_fail(err, "--horizon must be a whole number >= 1, got '%s'", a->horizon);
        goto done_scene;
    }
    o.horizon = (int)h;
    o.nonnegative = a->nonnegative;
    if (a->train_force && cli_real(a->train_force, 1e-300, 1e300, &o.train_force)) {
        rk_fail(err, "--train-force must be a positive number of newtons, got '%s'", a->train_force);
        goto done_scene;
    }
    o.regularize = CONTROL_REGULARIZE;
    if (a->regularize && cli_real(a->regularize, 0, 1e6, &o.regularize)) {
        rk_fail(err, "--regularize must be a number >= 0 (relative to the largest singular value), got '%s'",
                a->regularize);
        goto done_scene;
    }
    if (a->train_pressure && cli_real(a->train_pressure, 1e-300, 1e300, &o.train_pressure)) {
        rk_fail(err, "--train-pressure must be a positive number of pascals, got '%s'", a->train_pressure);
        goto done_scene;
    }
    if (parse_inputs(&scene, e, a->inputs, &o, err) || (a->follow && parse_follow(e, a->follow, &o, err))) goto done_scene;
    if (rk_scene_build(&scene, &sim, err)) goto done_scene;
    if (load_target(a->target, &sim, &target, &T, err)) goto done_sim;
    int n3 = 3 * sim.mesh.nv;
    double mx[3];
    if (!(rk_control_target_scale(target, n3, T) > 0)) {
        rk_fail(err, "--target %s never leaves the rest positions: nothing to follow", a->target);
        goto done_sim;
    }
    if (rk_scene_control(&sim, e, &o, target, T, &r, err)) goto done_sim;
    cJSON *rep = rk_control_report(e, &o, &r, target, n3, mx);
    if (!write_outputs(a, &r, &sim, rep, err)) {
        const cJSON *fe = cJSON_GetObjectItem(cJSON_GetObjectItem(rep, "error"), "fom_vs_target");
        int under2 = cJSON_GetObjectItem(fe, "frames_under_2_percent")->valueint;
        printf("control: %d frames, %d inputs, Koopman rank %d; per-frame error in %% of the target's largest "
               "displacement: full order under the solved %s vs target max %.3g%% (%d of %d frames under 2%%), "
               "model vs target max %.3g%%, model vs full order max %.3g%%\n",
               T, o.ninputs, r.rank, a->train_pressure ? "inputs" : "forces", mx[0], under2, T, mx[1], mx[2]);
        rc = 0;
    }
    cJSON_Delete(rep);
    rk_control_result_free(&r);
done_sim:
    free(target);
    rk_scene_sim_free(&sim);
done_scene:
    rk_scene_free(&scene);
    return rc;
}

int cmd_control(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            control_usage(stdout);
            return 0;
        }
    control_args a;
    memset(&a, 0, sizeof a);
    const cli_option opts[] = {{"--target", &a.target, NULL},   {"--inputs", &a.inputs, NULL},
                               {"--follow", &a.follow, NULL},   {"--horizon", &a.horizon, NULL},
                               {"--train-force", &a.train_force, NULL}, {"--nonnegative", NULL, &a.nonnegative},
                               {"--train-pressure", &a.train_pressure, NULL},
                               {"--regularize", &a.regularize, NULL},
                               {"--report", &a.report, NULL},   {"--forces", &a.forces, NULL},
                               {"--snapshots", &a.snapshots, NULL}, {"--quiet", NULL, &a.quiet},
                               {NULL, NULL, NULL}};
    if (cli_parse("control", argc, argv, opts, &a.scene, "scene file")) {
        control_usage(stderr);
        return 2;
    }
    if (!a.target || !a.inputs) {
        fprintf(stderr, "romkit control: --target and --inputs are required\n");
        control_usage(stderr);
        return 2;
    }
    rk_progress_set_quiet(a.quiet);
    rk_error err = {{0}};
    if (run_control(&a, &err)) {
        fprintf(stderr, "romkit control: %s\n", err.msg);
        return 1;
    }
    return 0;
}
