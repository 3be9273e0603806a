/* Sorting doubles: one comparator for qsort, and the median of timings and distances. */
#ifndef RK_SORT_H
#define RK_SORT_H

/* qsort comparator, ascending. */
int rk_cmp_double(const void *a, const void *b);
/* Sorts v[0..n) in place and returns its median; NAN when n is 0. */
double rk_median(double *v, int n);

#endif
