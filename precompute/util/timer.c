#include "util/util.h"

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
static int progress_tty = -1;     /* isatty(stderr), asked once: loops call rk_progress every step */
static int progress_open = 0;     /* a progress line is on the terminal, not yet ended */
static double progress_last = 0;  /* when it was last redrawn */

/* Redraw at most this often: a terminal that gets a line per step slows a fast loop down. */
#define RK_PROGRESS_INTERVAL 0.1

void rk_progress_set_quiet(int quiet) { progress_quiet = quiet; }

static int progress_enabled(void)
{
    if (progress_quiet) return 0;
    if (progress_tty < 0) progress_tty = isatty(fileno(stderr));
    return progress_tty;
}

void rk_progress(const char *stage, long done, long total)
{
    if (!progress_enabled()) return;
    double now = rk_now();
    if (progress_open && done != total && now - progress_last < RK_PROGRESS_INTERVAL) return;
    progress_open = 1;
    progress_last = now;
    if (total > 0)
        fprintf(stderr, "\r%s: %ld/%ld (%3.0f%%)", stage, done, total, 100.0 * (double)done / (double)total);
    else
        fprintf(stderr, "\r%s: %ld", stage, done);
    fflush(stderr);
}

void rk_progress_done(const char *stage)
{
    if (!progress_enabled()) return;
    progress_open = 0;
    fprintf(stderr, "\r%s: done%20s\n", stage, "");
}

void rk_progress_break(void)
{
    if (!progress_open) return;
    progress_open = 0;
    fputc('\n', stderr);
}
