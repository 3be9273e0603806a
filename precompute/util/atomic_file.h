/* Atomic file output: nothing is ever written half-way (DESIGN.md, Errors).
 * rk_atomic_open creates PATH.tmp.PID beside the target; rk_atomic_commit flushes and renames
 * it onto PATH; rk_atomic_abort removes it. Every writer in the toolchain goes through this. */
#ifndef RK_ATOMIC_FILE_H
#define RK_ATOMIC_FILE_H

#include <stdio.h>

#include "util/error.h"

typedef struct {
    char final_path[4096];
    char tmp_path[4160];
    FILE *fp;
} rk_atomic_file;

int rk_atomic_open(rk_atomic_file *f, const char *path, rk_error *err);
int rk_atomic_commit(rk_atomic_file *f, rk_error *err);
void rk_atomic_abort(rk_atomic_file *f);

#endif
