/* The reduced models of the make-bench rom programs (bench_rom.c, bench_runtime.c), built the one
 * way both time them. Every case: the soft neo-Hookean object of bench_scene, bottom 10% (in y)
 * fixed as one prescribed group, gravity, backward Euler at h = 0.01 s.
 *
 *   full order   one untimed warm-up step, then case.steps single steps, each timed (fom_s: their
 *                median, min and max: the spread over the steps of one run); every frame (the
 *                warm-up's and the timed ones) kept as a training snapshot
 *   basis        BENCH_MAX_R linear modes once per mesh; r uses the first r columns
 *   exact        the reduced model integrating every element
 *   cubature     trained (An et al. 2008, tolerance 0.01, 40 poses: the projected full-order
 *                frames and random ones) on the exact model, then put in its place
 *
 * Only the two largest boxes may be skipped, when their estimated cost (the last case's seconds
 * scaled by the tet ratio to the power 1.2) would take the run past a budget. */
#ifndef RK_BENCH_ROM_MODEL_H
#define RK_BENCH_ROM_MODEL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "basis/basis.h"
#include "bench_cases.h"
#include "cubature/cubature.h"
#include "fom/fom.h"
#include "rom/rom.h"
#include "pipeline/method_fixed.h"
#include "util/util.h"

#define BENCH_NR 4
#define BENCH_MAX_R 64
#define BENCH_MAX_SAMPLES 64       /* timed samples one bench_time_rom call may take */
#define BENCH_CUBATURE_SAMPLE 1000 /* candidates scored per greedy iteration (the default) */

static const int BENCH_R_VALUES[BENCH_NR] = {8, 16, 32, 64};

/* One mesh's shared part: its scene, the fixed group, the full-order run and the basis. */
typedef struct {
    rk_scene scene;
    rk_scene_sim sim;
    int nv, nt, ndof;
    unsigned char *fixed_flags; /* nv: 1 where the basis is held at zero */
    rk_prescribed fixed;        /* the same vertices, one prescribed group */
    rk_fom_options opt;         /* a copy of sim.options with that one group as its prescribed list */
    int nframes;                /* case.steps + 1 */
    double *frames;             /* ndof x nframes, column-major */
    bench_stat fom_s;           /* full-order s/step: median, min, max over the timed steps */
    rk_basis b;                 /* BENCH_MAX_R modes */
    rk_sparse M;                /* the inertia mass */
} bench_rom_case;

typedef struct {
    double start, budget_s;      /* the run's start and its budget (s) */
    double last_seconds, case_start;
    int last_nt;
} bench_budget;

/* 1 (after printing why) when the case is box_100k or box_200k and its estimated cost, after
 * `elapsed` seconds of the run, would take it past budget_s. last_seconds, last_nt: the last
 * case run (last_nt 0: none yet, never skip). */
static inline int bench_over_budget(const char *name, int nt, double elapsed, double last_seconds, int last_nt,
                                    double budget_s)
{
    if ((strcmp(name, "box_100k") && strcmp(name, "box_200k")) || last_nt <= 0) return 0;
    double estimate = last_seconds * pow((double)nt / last_nt, 1.2);
    if (elapsed + estimate <= budget_s) return 0;
    printf("%-14s %7d  skipped: estimated %.0f s (from %.0f s for %d tets) after %.0f s would exceed %.0f s\n", name, nt,
           estimate, last_seconds, last_nt, elapsed, budget_s);
    fflush(stdout);
    return 1;
}

/* Builds the case's scene only (to read its size before deciding to run it). */
static inline int bench_rom_case_scene(const bench_case *c, bench_rom_case *bc, rk_error *err)
{
    memset(bc, 0, sizeof *bc);
    if (bench_scene(c, &bc->scene, &bc->sim, err)) return -1;
    bc->nv = bc->sim.mesh.nv;
    bc->nt = bc->sim.mesh.nt;
    bc->ndof = 3 * bc->nv;
    if (bc->nv < 1 || bc->nt < 1) return rk_fail(err, "empty mesh (%d vertices, %d tets)", bc->nv, bc->nt);
    return 0;
}

/* After bench_rom_case_scene: the fixed group, the timed full-order run, the modes and the mass. */
static inline int bench_rom_case_prepare(const bench_case *c, bench_rom_case *bc, rk_error *err)
{
    rk_scene_sim *sim = &bc->sim;
    int nv = bc->nv, ndof = bc->ndof;
    /* Bottom 10% in y fixed: the flags for the basis and one prescribed group for both models
     * (in a copy of sim.options: rk_scene_sim_free frees sim.options.prescribed). */
    double lo = INFINITY, hi = -INFINITY;
    for (int v = 0; v < nv; v++) {
        lo = fmin(lo, sim->mesh.X[3 * v + 1]);
        hi = fmax(hi, sim->mesh.X[3 * v + 1]);
    }
    bc->fixed_flags = calloc((size_t)nv, 1);
    bc->fixed.kind = RK_MOTION_FIXED;
    bc->fixed.verts = malloc(sizeof(int) * (size_t)nv);
    if (!bc->fixed_flags || !bc->fixed.verts) return rk_fail(err, "out of memory");
    for (int v = 0; v < nv; v++)
        if (sim->mesh.X[3 * v + 1] <= lo + 0.1 * (hi - lo)) {
            bc->fixed_flags[v] = 1;
            bc->fixed.verts[bc->fixed.count++] = v;
        }
    bc->opt = sim->options;
    bc->opt.nprescribed = 1;
    bc->opt.prescribed = &bc->fixed;

    /* Full order: warm-up step, then case.steps timed ones; every frame kept as a snapshot. */
    int steps = c->steps;
    double fom_t[16];
    if (steps < 1 || steps > 16) return rk_fail(err, "%d full-order steps (1 to 16)", steps);
    bc->nframes = steps + 1;
    bc->frames = malloc(sizeof(double) * (size_t)ndof * bc->nframes);
    if (!bc->frames) return rk_fail(err, "out of memory");
    rk_fom fom;
    if (rk_fom_init(&fom, &sim->fem, &bc->opt, err)) return -1;
    if (rk_fom_step(&fom, err)) goto fom_fail;
    memcpy(bc->frames, fom.x, sizeof(double) * ndof);
    for (int s = 0; s < steps; s++) {
        double t0 = rk_now();
        if (rk_fom_step(&fom, err)) goto fom_fail;
        fom_t[s] = rk_now() - t0;
        memcpy(bc->frames + (size_t)ndof * (s + 1), fom.x, sizeof(double) * ndof);
    }
    bc->fom_s = bench_stat_of(fom_t, steps);
    rk_fom_free(&fom);

    /* BENCH_MAX_R linear modes; r uses the first r columns. */
    if (rk_basis_modes(&sim->fem, bc->fixed_flags, 0, BENCH_MAX_R, &bc->b, err)) return -1;
    if (bc->b.r < BENCH_MAX_R) return rk_fail(err, "only %d modes, %d needed", bc->b.r, BENCH_MAX_R);
    if (rk_sparse_alloc_pattern(&sim->fem, &bc->M, err)) return -1;
    rk_fem_add_mass(&sim->fem, bc->opt.lumped_mass, 1.0, &bc->M);
    return 0;
fom_fail:
    rk_fom_free(&fom);
    return -1;
}

static inline void bench_rom_case_free(bench_rom_case *bc);

/* Case c's scene and, unless the budget skips it, its full-order run and modes: 1 ready, 0
 * skipped (nothing to free), -1 failed. bench_budget_case_done records what it cost. */
static inline int bench_rom_case_open(const bench_case *c, bench_budget *B, bench_rom_case *bc, rk_error *err)
{
    B->case_start = rk_now();
    if (bench_rom_case_scene(c, bc, err)) return -1;
    if (bench_over_budget(c->name, bc->nt, rk_now() - B->start, B->last_seconds, B->last_nt, B->budget_s)) {
        bench_rom_case_free(bc);
        return 0;
    }
    return bench_rom_case_prepare(c, bc, err) ? -1 : 1;
}

static inline void bench_budget_case_done(bench_budget *B, int nt)
{
    B->last_seconds = rk_now() - B->case_start;
    B->last_nt = nt;
}

static inline void bench_rom_case_free(bench_rom_case *bc)
{
    rk_sparse_free(&bc->M);
    rk_basis_free(&bc->b);
    free(bc->frames);
    free(bc->fixed.verts);
    free(bc->fixed_flags);
    rk_scene_sim_free(&bc->sim);
    rk_scene_free(&bc->scene);
    memset(bc, 0, sizeof *bc);
}

/* The exact model at r (integrating every element) into *m, and the full-order frames in its
 * reduced coordinates into snap (r x nframes, malloc'd). */
static inline int bench_rom_exact_model(bench_rom_case *bc, int r, rk_rom_model *m, double **snap, rk_error *err)
{
    rk_quadrature Q;
    *snap = NULL;
    if (rk_quadrature_elements(&bc->sim.fem, bc->b.U, r, bc->nt, NULL, NULL, &Q, err)) return -1;
    if (rk_rom_model_init(m, &bc->sim.fem, &bc->opt, bc->b.U, r, &Q, NULL, err)) return -1;
    *snap = malloc(sizeof(double) * (size_t)r * bc->nframes);
    if (!*snap) return rk_fail(err, "out of memory");
    for (int f = 0; f < bc->nframes; f++)
        if (rk_rom_project(m, &bc->M, bc->b.U, bc->ndof, bc->sim.mesh.X, bc->frames + (size_t)bc->ndof * f,
                           *snap + (size_t)r * f, err))
            return -1;
    return 0;
}

/* Trains the cubature on the exact model m (its snapshots snap from bench_rom_exact_model) and
 * puts it in place of m's quadrature. set: the points chosen (the caller frees it); poses: the
 * training poses used; train_s: the training's seconds. */
static inline int bench_rom_cubature(bench_rom_case *bc, rk_rom_model *m, const double *snap, rk_cubature_set *set,
                                     int *poses, double *train_s, rk_error *err)
{
    rk_cubature_options co;
    rk_cubature_default_options(&co);
    co.tolerance = 0.01;
    co.poses = 40;
    co.sample = BENCH_CUBATURE_SAMPLE;
    *poses = 0;
    double t0 = rk_now();
    if (rk_cubature_train(&m->quad, m->M, m->mass, snap, bc->nframes, &co, set, poses, err)) return -1;
    *train_s = rk_now() - t0;
    rk_quadrature cub;
    if (rk_quadrature_elements(&bc->sim.fem, bc->b.U, m->r, set->count, set->index, set->weight, &cub, err)) return -1;
    rk_quadrature_free(&m->quad);
    m->quad = cub;
    return 0;
}

/* Keeps q (r reals) as column *taken of q_traj (r x ntraj) while *taken < ntraj; counts the step. */
static inline void bench_keep_q(double *q_traj, int ntraj, int *taken, const double *q, int r)
{
    if (q_traj && *taken < ntraj) memcpy(q_traj + (size_t)r * *taken, q, sizeof(double) * (size_t)r);
    (*taken)++;
}

/* Steps the model from rest: `warmup` untimed steps, then `samples` timed samples of `steps`
 * steps each; *sec: the median, min and max over the samples of their seconds per step. stats:
 * the work of the timed steps; q_end (r reals, may be NULL): q after the last step; q_traj (r x
 * ntraj, may be NULL): q after each of the first ntraj steps (warm-up ones included), for as many
 * steps as are taken. */
static inline int bench_time_rom(rk_rom_model *m, int warmup, int samples, int steps, bench_stat *sec,
                                 rk_rom_stats *stats, double *q_end, double *q_traj, int ntraj, rk_error *err)
{
    int taken = 0;
    rk_rom rom;
    double t[BENCH_MAX_SAMPLES];
    if (samples < 1 || samples > BENCH_MAX_SAMPLES || steps < 1)
        return rk_fail(err, "bench_time_rom: %d samples of %d steps", samples, steps);
    if (rk_rom_init(&rom, m, NULL, NULL, err)) return -1;
    for (int s = 0; s < warmup; s++) {
        if (rk_rom_step(&rom, err)) goto fail;
        bench_keep_q(q_traj, ntraj, &taken, rom.q, m->r);
    }
    rk_rom_stats before = rom.stats;
    for (int s = 0; s < samples; s++) {
        double t0 = rk_now();
        for (int k = 0; k < steps; k++) {
            if (rk_rom_step(&rom, err)) goto fail;
            bench_keep_q(q_traj, ntraj, &taken, rom.q, m->r);
        }
        t[s] = (rk_now() - t0) / steps;
    }
    *stats = rom.stats;
    stats->steps -= before.steps;
    stats->newton_iterations -= before.newton_iterations;
    stats->line_search_halvings -= before.line_search_halvings;
    stats->unconverged_steps -= before.unconverged_steps;
    stats->seconds_total -= before.seconds_total;
    if (q_end) memcpy(q_end, rom.q, sizeof(double) * (size_t)m->r);
    *sec = bench_stat_of(t, samples);
    rk_rom_free(&rom);
    return 0;
fail:
    rk_rom_free(&rom);
    return -1;
}

/* The relative error (util/util.h) of reduced trajectory q_traj (r x nf, from bench_time_rom)
 * against the full-order frames 0..nf-1 (both start from rest; frame f is after step f + 1). */
static inline double bench_rom_error(const bench_rom_case *bc, int r, const double *q_traj, int nf)
{
    int n = bc->ndof;
    double *x = malloc(sizeof(double) * (size_t)n);
    if (!x) return NAN;
    rk_run_error e;
    rk_run_error_init(&e, bc->sim.mesh.X, n / 3);
    for (int f = 0; f < nf && f < bc->nframes; f++) {
        rk_rom_positions(bc->b.U, n, r, bc->sim.mesh.X, q_traj + (size_t)r * f, x);
        rk_run_error_add(&e, x, bc->frames + (size_t)n * f);
    }
    free(x);
    return rk_relative_error(&e);
}

#endif
