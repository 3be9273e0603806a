/* Error reporting shared by every precompute stage.
 * A function that can fail returns int (0 on success, -1 on failure) and, on failure,
 * fills an rk_error with one message naming what failed and where (file and line,
 * element index, JSON key). Callers add context with rk_error_prefix. */
#ifndef RK_ERROR_H
#define RK_ERROR_H

#include <stddef.h>

typedef struct {
    char msg[1024];
} rk_error;

/* Writes the message (printf format) and returns -1, so callers can `return rk_fail(...)`. */
int rk_fail(rk_error *err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Puts "context: " in front of an existing message. Returns -1. */
int rk_error_prefix(rk_error *err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void rk_error_clear(rk_error *err);

/* Allocation that reports failure through err instead of crashing. */
void *rk_calloc(size_t count, size_t size, rk_error *err);

#endif
