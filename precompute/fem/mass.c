/* Mass matrices: consistent P1 (rho vol / 20 (1 + delta_ab) I3 per vertex pair of a tet) or
 * lumped (rho vol / 4 per vertex, the row sums of the consistent one). */
#include "fem/element.h"

void rk_fem_add_mass(const rk_fem *f, int lumped, double scale, rk_sparse *M)
{
    if (lumped) {
        for (int v = 0; v < f->nv; v++)
            for (int i = 0; i < 3; i++) M->val[rk_fem_diag_slot(M, v, i, i)] += scale * f->vertex_mass[v];
        return;
    }
    for (int t = 0; t < f->nt; t++) {
        double m = scale * f->density[t] * f->vol[t] / 20.0;
        const int *s = &f->slot[RK_TET_SLOTS * t];
        for (int p = 0; p < 12; p++)
            for (int q = p; q < 12; q++, s++)
                if (p % 3 == q % 3) M->val[*s] += p == q ? 2 * m : m; /* only like components couple */
    }
}
