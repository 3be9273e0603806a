/* The project's one seeded generator: splitmix64 (Steele, Lea & Flood 2014, "Fast splittable
 * pseudorandom number generators"), tiny, and the same sequence on every platform and C library
 * (libc rand() is neither). Used by the cubature's subset draws and training poses, and by the
 * tests and benches that need random input.
 *
 * Header-only (static inline) on purpose: any stage, test or bench can include it without
 * linking util (the physics tests link only the physics stage). */
#ifndef RK_RANDOM_H
#define RK_RANDOM_H

#include <stdint.h>

/* One splitmix64 step: advances *state and returns the next 64 random bits. */
static inline uint64_t rk_splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1): the top 53 bits of one step, times 2^-53 (every value a multiple of 2^-53). */
static inline double rk_uniform(uint64_t *state)
{
    return (double)(rk_splitmix64(state) >> 11) * (1.0 / 9007199254740992.0);
}

#endif
