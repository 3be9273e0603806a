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
    o->newton_max_iter = 50;
    rk_contact_default_options(&o->contact); /* dhat 0: 1e-3 of the bounding-box diagonal */
}
