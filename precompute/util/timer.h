/* Wall-clock timing and terminal progress for long stages. */
#ifndef RK_TIMER_H
#define RK_TIMER_H

/* Seconds from a monotonic clock. */
double rk_now(void);

/* Progress on stderr, only when stderr is a terminal and not silenced (DESIGN.md: quiet otherwise). */
void rk_progress_set_quiet(int quiet);
void rk_progress(const char *stage, long done, long total);
void rk_progress_done(const char *stage);

#endif
