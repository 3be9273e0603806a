/* The one physics implementation (physics/physics_impl.h), compiled in the runtime's precision:
 * the runtime and the precompute integrate the same constitutive code. */
#include "runtime/romrt_impl.h"

#define PHYS_REAL romrt_real
#define PHYS_FN(name) romrt_phys_##name
#ifndef ROMRT_DOUBLE
#define PHYS_FLOAT 1
#endif
#include "physics/physics_impl.h"
