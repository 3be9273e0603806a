/* make bench, scale part (issue 16): the modes and the full-order steps of a mesh of about 400k
 * tets, made by uniform 1:8 refinement (rk_mesh_refine, the scene key mesh.refine) of a shared
 * mesh, and how much memory each takes.
 *
 * Cases: bunny_19k x 8 (155,032 tets) and dinosaur_bin x 8 (399,784 tets); with
 * ROMKIT_BENCH_SCALE_LARGE set, also bunny_19k x 64 (1,240,256 tets: about 9 more minutes, 6.5 GiB).
 * The issue asks for about 440k from the armadillo or the bunny; of the shared meshes, 1:8
 * refinement reaches 30k (armadillo_4k), 238k (armadillo twice), 155k (bunny) and 1.24M (bunny
 * twice), and the bunny's own surface tetrahedralized by TetGen at its default quality already
 * gives 109k-158k tets (a 55k-tet bunny to refine would be a worse mesh than the one shipped). The
 * dinosaur (49,973 tets) refined once is the shared mesh closest to 440k; the bunny x 8 is the
 * issue's bunny, and the bunny x 64 shows what three times the size costs.
 *
 * Every case, the same scene as bench_fom.c: a soft neo-Hookean object (E = 1e5 Pa, nu = 0.4,
 * 1000 kg/m^3), bottom 10% (in y) fixed, gravity, backward Euler at h = 0.01 s. Each measurement
 * runs in a child process of its own (fork), so its peak resident memory (ru_maxrss from wait4)
 * is its own and not the largest so far:
 *   refine   load the mesh, then rk_mesh_refine REFINE_REPEATS times: refine_s (median, min, max)
 *   modes    the scene built (load, refine, check, FEM model: build_s), then 32 linear modes
 *            (rk_basis_modes: ARPACK shift-invert around a CHOLMOD factorization, the bottom 10%
 *            fixed) case.mode_repeats times: modes32_s; modes_rss_mib covers the build and modes
 *   fom      the scene built, rk_fom_init, one warm-up step, then case.steps steps, each timed:
 *            s_per_step (median over the steps of one run, min, max), the shares of CHOLMOD's
 *            numeric factorization, its triangular solves and assembly (energy, gradient,
 *            PSD-projected Hessian) in the timed steps, Newton iterations per step
 * A child that dies (out of memory, say) fails the bench with its signal named.
 *
 * Threads: one each (OPENBLAS_NUM_THREADS, OMP_NUM_THREADS and OMP_THREAD_LIMIT = 1, set here
 * and the bench re-executed when any is unset, as bench_contact.c does; the JSON records them).
 * OMP_THREAD_LIMIT caps CHOLMOD's supernodal factorization, which asks OpenMP for 4 threads on this
 * shared 2-core machine; set all three to measure with more.
 *
 * ROMKIT_BENCH_QUICK: the bunny only, one modes run, 2 steps.
 * Writes bench/results/scale.{csv,json}. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include "basis/basis.h"
#include "bench_cases.h"
#include "fom/fom.h"
#include "mesh/mesh.h"
#include "pipeline/pipeline.h"
#include "util/util.h"

#define REFINE_REPEATS 5
#define MAX_SAMPLES 8
#define MEMORY_BUDGET_GIB 24.0

typedef struct {
    const char *name;
    const char *file;  /* under the mesh folder */
    int levels;
    int mode_repeats;
    int steps;         /* timed full-order steps after the warm-up */
} scale_case;

static const scale_case CASES[] = {
    {"bunny_19k_x8", "bunny_19k.msh", 1, 3, 3},
    {"dinosaur_50k_x8", "dinosaur_bin.msh", 1, 3, 3},
    {"bunny_19k_x64", "bunny_19k.msh", 2, 1, 2}, /* ROMKIT_BENCH_SCALE_LARGE only */
};

/* What a child sends back through its pipe. */
typedef struct {
    int ok;
    char msg[512];
    int nv, nt, nv0, nt0;
    int nsamples;
    double samples[MAX_SAMPLES];
    double build_s;
    double lambda1, lambda32; /* modes: the smallest and the 32nd eigenvalue */
    double factor_share, solve_share, assemble_share, newton_per_step;
    long unconverged;
} phase_result;

typedef enum { PHASE_REFINE, PHASE_MODES, PHASE_FOM } phase_kind;
static const char *const PHASE_NAME[] = {"refine", "modes", "fom"};

static void mesh_json(const char *data, const scale_case *c, bench_case *bc)
{
    bc->name = c->name;
    bc->steps = c->steps;
    snprintf(bc->mesh_json, sizeof bc->mesh_json, "{\"file\": \"%s/%s\", \"refine\": %d}", data, c->file, c->levels);
}

static unsigned char *bottom_fixed(const rk_mesh *m)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int v = 0; v < m->nv; v++) {
        lo = fmin(lo, m->X[3 * (size_t)v + 1]);
        hi = fmax(hi, m->X[3 * (size_t)v + 1]);
    }
    unsigned char *f = calloc((size_t)m->nv, 1);
    if (f)
        for (int v = 0; v < m->nv; v++) f[v] = m->X[3 * (size_t)v + 1] <= lo + 0.1 * (hi - lo);
    return f;
}

static int run_refine(const char *data, const scale_case *c, phase_result *r, rk_error *err)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", data, c->file);
    rk_mesh m;
    if (rk_mesh_load(path, RK_MESH_DROP_FLAT, &m, NULL, err)) return -1;
    r->nv0 = m.nv;
    r->nt0 = m.nt;
    for (int k = 0; k < REFINE_REPEATS; k++) {
        rk_mesh fine;
        double t0 = rk_now();
        if (rk_mesh_refine(&m, c->levels, &fine, err)) {
            rk_mesh_free(&m);
            return -1;
        }
        r->samples[r->nsamples++] = rk_now() - t0;
        r->nv = fine.nv;
        r->nt = fine.nt;
        rk_mesh_free(&fine);
    }
    rk_mesh_free(&m);
    return 0;
}

static int build(const char *data, const scale_case *c, rk_scene *scene, rk_scene_sim *sim, phase_result *r,
                 rk_error *err)
{
    bench_case bc;
    mesh_json(data, c, &bc);
    double t0 = rk_now();
    if (bench_scene(&bc, scene, sim, err)) return -1;
    r->build_s = rk_now() - t0;
    r->nv = sim->mesh.nv;
    r->nt = sim->mesh.nt;
    return 0;
}

static int run_modes(const char *data, const scale_case *c, phase_result *r, rk_error *err)
{
    rk_scene scene;
    rk_scene_sim sim;
    if (build(data, c, &scene, &sim, r, err)) return -1;
    unsigned char *fixed = bottom_fixed(&sim.mesh);
    int rc = fixed ? 0 : rk_fail(err, "out of memory");
    for (int k = 0; k < c->mode_repeats && !rc; k++) {
        rk_basis b;
        double t0 = rk_now();
        rc = rk_basis_modes(&sim.fem, fixed, 0, 32, &b, err);
        if (rc) break;
        r->samples[r->nsamples++] = rk_now() - t0;
        r->lambda1 = b.values[0];
        r->lambda32 = b.values[b.nvalues - 1];
        rk_basis_free(&b);
    }
    free(fixed);
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    return rc;
}

static int run_fom(const char *data, const scale_case *c, phase_result *r, rk_error *err)
{
    rk_scene scene;
    rk_scene_sim sim;
    if (build(data, c, &scene, &sim, r, err)) return -1;
    unsigned char *flag = bottom_fixed(&sim.mesh);
    rk_prescribed fixed = {.kind = RK_MOTION_FIXED};
    fixed.verts = malloc(sizeof(int) * (size_t)sim.mesh.nv);
    int rc = flag && fixed.verts ? 0 : rk_fail(err, "out of memory");
    for (int v = 0; !rc && v < sim.mesh.nv; v++)
        if (flag[v]) fixed.verts[fixed.count++] = v;
    free(flag);
    rk_fom fom = {0};
    rk_fom_options opt = sim.options;
    opt.nprescribed = 1;
    opt.prescribed = &fixed;
    if (!rc) rc = rk_fom_init(&fom, &sim.fem, &opt, err);
    if (!rc) rc = rk_fom_step(&fom, err); /* warm-up: the symbolic analysis happens here */
    rk_fom_stats before = fom.stats;
    for (int s = 0; s < c->steps && !rc; s++) {
        double t0 = rk_now();
        rc = rk_fom_step(&fom, err);
        if (!rc) r->samples[r->nsamples++] = rk_now() - t0;
    }
    if (!rc) {
        double total = fom.stats.seconds_total - before.seconds_total;
        r->factor_share = (fom.stats.seconds_factor - before.seconds_factor) / total;
        r->solve_share = (fom.stats.seconds_solve - before.seconds_solve) / total;
        r->assemble_share = (fom.stats.seconds_assemble - before.seconds_assemble) / total;
        r->newton_per_step = (double)(fom.stats.newton_iterations - before.newton_iterations) / c->steps;
        r->unconverged = fom.stats.unconverged_steps;
    }
    if (fom.impl) rk_fom_free(&fom);
    free(fixed.verts);
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    return rc;
}

/* Runs one phase in a child; *rss_mib gets the child's peak resident memory. */
static int run_phase(phase_kind kind, const char *data, const scale_case *c, phase_result *r, double *rss_mib)
{
    int fd[2];
    memset(r, 0, sizeof *r);
    if (pipe(fd)) {
        perror("bench_scale: pipe");
        return -1;
    }
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) {
        perror("bench_scale: fork");
        return -1;
    }
    if (pid == 0) {
        close(fd[0]);
        rk_error err = {{0}};
        phase_result out = {0};
        int rc = kind == PHASE_REFINE ? run_refine(data, c, &out, &err)
                 : kind == PHASE_MODES ? run_modes(data, c, &out, &err)
                                       : run_fom(data, c, &out, &err);
        out.ok = rc == 0;
        if (rc) snprintf(out.msg, sizeof out.msg, "%s", err.msg);
        ssize_t w = write(fd[1], &out, sizeof out);
        _exit(w == (ssize_t)sizeof out ? 0 : 3);
    }
    close(fd[1]);
    size_t got = 0;
    while (got < sizeof *r) {
        ssize_t n = read(fd[0], (char *)r + got, sizeof *r - got);
        if (n <= 0) break;
        got += (size_t)n;
    }
    close(fd[0]);
    int status;
    struct rusage ru;
    if (wait4(pid, &status, 0, &ru) < 0) {
        perror("bench_scale: wait4");
        return -1;
    }
    *rss_mib = ru.ru_maxrss / 1024.0; /* Linux: kilobytes */
    if (WIFSIGNALED(status)) {
        fprintf(stderr, "bench_scale: %s: %s: the child died of signal %d (%s) at %.0f MiB\n", c->name,
                PHASE_NAME[kind], WTERMSIG(status), strsignal(WTERMSIG(status)), *rss_mib);
        return -1;
    }
    if (got != sizeof *r || !r->ok) {
        fprintf(stderr, "bench_scale: %s: %s: %s\n", c->name, PHASE_NAME[kind], got == sizeof *r ? r->msg : "no result");
        return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    bench_pin_one_thread(argv, "bench_scale");
    rk_progress_set_quiet(1);
    const char *data = argc > 1 ? argv[1] : "tests/data/meshes";
    const char *out_dir = argc > 2 ? argv[2] : "bench/results";
    int quick = getenv("ROMKIT_BENCH_QUICK") != NULL;
    int large = getenv("ROMKIT_BENCH_SCALE_LARGE") != NULL;
    int ncases = quick ? 1 : large ? 3 : 2;
    FILE *csv, *json;
    if (bench_open_results(out_dir, "scale",
                           "case,source,levels,source_vertices,source_tets,vertices,tets,refine_s,refine_s_min,"
                           "refine_s_max,refine_rss_mib,build_s,modes32_s,modes32_s_min,modes32_s_max,lambda1,"
                           "lambda32,modes_rss_mib,steps,s_per_step,s_per_step_min,s_per_step_max,factor_share,"
                           "solve_share,assemble_share,newton_per_step,fom_rss_mib",
                           &csv, &json))
        return 1;
    printf("threads: OPENBLAS_NUM_THREADS=%s OMP_NUM_THREADS=%s OMP_THREAD_LIMIT=%s\n", getenv("OPENBLAS_NUM_THREADS"),
           getenv("OMP_NUM_THREADS"), getenv("OMP_THREAD_LIMIT"));
    printf("%-16s %8s %8s %20s %8s %20s %8s %20s %6s %6s %6s %8s\n", "case", "verts", "tets", "refine s (min..max)",
           "MiB", "32 modes s (min..max)", "MiB", "s/step (min..max)", "factor", "newton", "steps", "MiB");
    double worst_gib = 0;
    for (int k = 0; k < ncases; k++) {
        scale_case c = CASES[k];
        if (quick) {
            c.mode_repeats = 1;
            c.steps = 2;
        }
        phase_result ref, modes, fom;
        double rss_ref, rss_modes, rss_fom;
        if (run_phase(PHASE_REFINE, data, &c, &ref, &rss_ref) || run_phase(PHASE_MODES, data, &c, &modes, &rss_modes) ||
            run_phase(PHASE_FOM, data, &c, &fom, &rss_fom))
            return 1;
        bench_stat t_ref = bench_stat_of(ref.samples, ref.nsamples);
        bench_stat t_modes = bench_stat_of(modes.samples, modes.nsamples);
        bench_stat t_step = bench_stat_of(fom.samples, fom.nsamples);
        worst_gib = fmax(worst_gib, fmax(rss_ref, fmax(rss_modes, rss_fom)) / 1024);
        printf("%-16s %8d %8d %8.3g (%.3g..%.3g) %8.0f %8.4g (%.4g..%.4g) %8.0f %8.4g (%.4g..%.4g) %5.0f%% %6.1f %6d %8.0f\n",
               c.name, modes.nv, modes.nt, BENCH_STAT3(t_ref), rss_ref, BENCH_STAT3(t_modes), rss_modes,
               BENCH_STAT3(t_step), 100 * fom.factor_share, fom.newton_per_step, c.steps, rss_fom);
        fflush(stdout);
        fprintf(csv,
                "%s,%s,%d,%d,%d,%d,%d,%.6g,%.6g,%.6g,%.1f,%.6g,%.6g,%.6g,%.6g,%.10g,%.10g,%.1f,%d,%.6g,%.6g,%.6g,"
                "%.4f,%.4f,%.4f,%.2f,%.1f\n",
                c.name, c.file, c.levels, ref.nv0, ref.nt0, modes.nv, modes.nt, BENCH_STAT3(t_ref), rss_ref,
                modes.build_s, BENCH_STAT3(t_modes), modes.lambda1, modes.lambda32, rss_modes, c.steps,
                BENCH_STAT3(t_step), fom.factor_share, fom.solve_share, fom.assemble_share, fom.newton_per_step,
                rss_fom);
        fprintf(json,
                "%s  {\"case\": \"%s\", \"source\": \"%s\", \"levels\": %d, \"source_vertices\": %d,"
                " \"source_tets\": %d, \"vertices\": %d, \"tets\": %d, \"refine_seconds\": %.6g,"
                " \"refine_seconds_min\": %.6g, \"refine_seconds_max\": %.6g, \"refine_rss_mib\": %.1f,"
                " \"build_seconds\": %.6g, \"modes32_seconds\": %.6g, \"modes32_seconds_min\": %.6g,"
                " \"modes32_seconds_max\": %.6g, \"mode_runs\": %d, \"lambda1\": %.10g, \"lambda32\": %.10g,"
                " \"modes_rss_mib\": %.1f, \"steps\": %d, \"seconds_per_step\": %.6g,"
                " \"seconds_per_step_min\": %.6g, \"seconds_per_step_max\": %.6g, \"factorization_share\": %.4f,"
                " \"solve_share\": %.4f, \"assemble_share\": %.4f, \"newton_per_step\": %.2f,"
                " \"unconverged_steps\": %ld, \"fom_rss_mib\": %.1f, \"openblas_threads\": \"%s\","
                " \"omp_threads\": \"%s\", \"omp_thread_limit\": \"%s\"}\n",
                k ? "," : "", c.name, c.file, c.levels, ref.nv0, ref.nt0, modes.nv, modes.nt, BENCH_STAT3(t_ref),
                rss_ref, modes.build_s, BENCH_STAT3(t_modes), c.mode_repeats, modes.lambda1, modes.lambda32,
                rss_modes, c.steps, BENCH_STAT3(t_step), fom.factor_share, fom.solve_share, fom.assemble_share,
                fom.newton_per_step, fom.unconverged, rss_fom, getenv("OPENBLAS_NUM_THREADS"),
                getenv("OMP_NUM_THREADS"), getenv("OMP_THREAD_LIMIT"));
    }
    fprintf(json, "]\n");
    fclose(csv);
    fclose(json);
    printf("largest peak resident memory: %.2f GiB (budget %.0f GiB)\n", worst_gib, MEMORY_BUDGET_GIB);
    if (worst_gib > MEMORY_BUDGET_GIB) {
        fprintf(stderr, "bench_scale: a phase took %.2f GiB, above the %.0f GiB budget\n", worst_gib, MEMORY_BUDGET_GIB);
        return 1;
    }
    return 0;
}
