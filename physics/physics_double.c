/* The double-precision rk_* physics used by precompute (declared in physics.h): the one
 * implementation in physics_impl.h, instantiated with PHYS_REAL = double. */
#include "physics/physics.h"

#define PHYS_REAL double
#define PHYS_FN(name) rk_##name
#include "physics/physics_impl.h"
