/* Energies of the current state. */
#include "fom/fom_impl.h"

double rk_fom_kinetic_energy(const rk_fom *s) { return 0.5 * rk_sparse_dot(&s->impl->M, s->v, s->v); }

double rk_fom_elastic_energy(const rk_fom *s) { return rk_fem_energy(s->fem, s->x); }
