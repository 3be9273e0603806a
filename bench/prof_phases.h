/* The runtime's profiling hooks for the benches that split a step into phases (bench_pour.c,
 * bench_alrom_split.c). They link against the runtime's sources compiled with -DROMRT_PROFILE,
 * whose RT_PROF_BEGIN/END hooks call rt_prof_enter/rt_prof_leave: each interval between two hooks
 * is charged to the innermost open phase (romrt_impl.h's RT_PROF_* order), so the phases and the
 * rest add up to the step. The clock is the includer's now(). Include in one file of a program;
 * before a timed step set prof_depth = 0 and prof_last = now(). */
#ifndef BENCH_PROF_PHASES_H
#define BENCH_PROF_PHASES_H

#define PROF_PHASES 6 /* romrt_impl.h's RT_PROF_PHASES */
#define PROF_DEPTH 16

static double now(void);

static double prof_s[PROF_PHASES], prof_last;
static int prof_stack[PROF_DEPTH], prof_depth;

void rt_prof_enter(int phase);
void rt_prof_leave(int phase);

/* the interval since the last hook to the innermost open phase (none open: the rest's) */
static void prof_charge(void)
{
    double t = now();
    if (prof_depth > 0 && prof_depth <= PROF_DEPTH && prof_stack[prof_depth - 1] >= 0 &&
        prof_stack[prof_depth - 1] < PROF_PHASES)
        prof_s[prof_stack[prof_depth - 1]] += t - prof_last;
    prof_last = t;
}

void rt_prof_enter(int phase)
{
    prof_charge();
    if (prof_depth < PROF_DEPTH) prof_stack[prof_depth] = phase;
    prof_depth++;
}

void rt_prof_leave(int phase)
{
    (void)phase;
    prof_charge();
    prof_depth--;
}

#endif
