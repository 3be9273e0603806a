/* precompute/koopman's own declarations, shared between fit.c and stabilize.c. */
#ifndef RK_KOOPMAN_IMPL_H
#define RK_KOOPMAN_IMPL_H

#include "koopman/koopman.h"

/* K = W B W^-1 from the eigenvalues as k->lambda holds them; work: r x r (fit.c). */
void rk_koopman_compose(rk_koopman *k, double *work);
/* Whether the training data's mechanical energy grows from its first frames to its last (stabilize.c). */
int rk_koopman_data_grows(const rk_koopman_trajectory *traj, int ntraj, int d, double h);
/* The eigenvalues refitted jointly under |lambda| <= 1, the modes W held; Z: the reduced data
 * (r x M), work: r x M (stabilize.c). */
int rk_koopman_stabilize(rk_koopman *k, const double *Z, int M, double *work, rk_error *err);

#endif
