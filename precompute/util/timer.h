/* Wall-clock timing and terminal progress for long stages. */
#ifndef RK_TIMER_H
#define RK_TIMER_H

/* Seconds from a monotonic clock. */
double rk_now(void);

/* Progress on stderr, only when stderr is a terminal and not silenced (DESIGN.md: quiet otherwise).
 * rk_progress redraws one line ("stage: k/N (pct%)", or "stage: k" when total <= 0,
 * for loops of unknown length) at most every 0.1 s, so it may be called every iteration;
 * rk_progress_done ends the line. */
void rk_progress_set_quiet(int quiet);
void rk_progress(const char *stage, long done, long total);
void rk_progress_done(const char *stage);
/* Ends a progress line left open (a stage failed part-way), so what follows starts on its own
 * line; rk_fail calls it. */
void rk_progress_break(void);

#endif
