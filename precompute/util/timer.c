#include "util/timer.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

double rk_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int progress_quiet = 0;

void rk_progress_set_quiet(int quiet) { progress_quiet = quiet; }

static int progress_enabled(void) { return !progress_quiet && isatty(fileno(stderr)); }

void rk_progress(const char *stage, long done, long total)
{
    if (!progress_enabled()) return;
    fprintf(stderr, "\r%s: %ld/%ld (%3.0f%%)", stage, done, total,
            total > 0 ? 100.0 * (double)done / (double)total : 0.0);
    fflush(stderr);
}

void rk_progress_done(const char *stage)
{
    if (!progress_enabled()) return;
    fprintf(stderr, "\r%s: done%20s\n", stage, "");
}
