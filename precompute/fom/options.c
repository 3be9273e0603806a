/* Default simulator options (fom.h). */
#include "fom/fom.h"

#include <string.h>

void rk_fom_default_options(rk_fom_options *o)
{
    memset(o, 0, sizeof *o);
    o->h = 0.01;
    o->steps = 100;
    o->integrator = RK_BACKWARD_EULER;
    o->newton_tol = 0; /* resolved by rk_fom_init to RK_FOM_DEFAULT_TOL * bounding-box diagonal */
    o->newton_max_iter = 0; /* full order RK_FOM_DEFAULT_MAX_ITER, reduced solvers theirs (fom.h) */
    rk_contact_default_options(&o->contact); /* dhat 0: 1e-3 of the bounding-box diagonal */
}

int rk_fom_max_iter(const rk_fom_options *o, int reduced)
{
    if (o->newton_max_iter > 0) return o->newton_max_iter;
    return reduced ? RK_REDUCED_DEFAULT_MAX_ITER : RK_FOM_DEFAULT_MAX_ITER;
}
