/* Mass matrices: consistent P1 (rho vol / 20 (1 + delta_ab) I3 per vertex pair of a tet) or
 * lumped (rho vol / 4 per vertex, the row sums of the consistent one); with unit density, the
 * volume mass that skinning weights are normalized in (freeform paper Eq. 14). */
#include "fem/element_impl.h"

static void add_mass(const rk_fem *f, int lumped, int unit_density, double scale, rk_sparse *M)
{
    for (int t = 0; t < f->nt; t++) {
        double m = scale * (unit_density ? 1.0 : f->density[t]) * f->vol[t] / 20.0;
        if (lumped) { /* row sums: 5 m per vertex */
            for (int a = 0; a < 4; a++)
                for (int i = 0; i < 3; i++) M->val[rk_fem_diag_slot(M, f->tets[4 * t + a], i, i)] += 5 * m;
            continue;
        }
        const int *s = &f->slot[RK_TET_SLOTS * t];
        for (int p = 0; p < 12; p++)
            for (int q = p; q < 12; q++, s++)
                if (p % 3 == q % 3) M->val[*s] += p == q ? 2 * m : m; /* only like components couple */
    }
}

void rk_fem_add_mass(const rk_fem *f, int lumped, double scale, rk_sparse *M)
{
    add_mass(f, lumped, 0, scale, M);
}

void rk_fem_add_point_mass(const rk_fem *f, double scale, rk_sparse *M)
{
    for (int v = 0; f->point_mass && v < f->nv; v++)
        if (f->point_mass[v] > 0)
            for (int i = 0; i < 3; i++) M->val[rk_fem_diag_slot(M, v, i, i)] += scale * f->point_mass[v];
}

void rk_fem_add_volume_mass(const rk_fem *f, int lumped, double scale, rk_sparse *M)
{
    add_mass(f, lumped, 1, scale, M);
}
