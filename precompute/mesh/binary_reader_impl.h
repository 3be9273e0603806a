/* Private to precompute/mesh: the bounds-checked binary cursor over an rk_reader's buffer,
 * and number reads that work in either mode (token in text mode, raw bytes in binary mode),
 * so a format whose ASCII and binary variants carry the same fields (Gmsh, VTK, PLY) is
 * parsed by one piece of code. */
#ifndef RK_MESH_BINARY_READER_H
#define RK_MESH_BINARY_READER_H

#include "mesh/text_reader_impl.h"

typedef enum { RK_I8, RK_U8, RK_I16, RK_U16, RK_I32, RK_U32, RK_I64, RK_U64, RK_F32, RK_F64 } rk_scalar;

size_t rk_scalar_size(rk_scalar t);
/* Switches between token (0) and raw-byte (1) numbers at the current position. */
void rk_reader_set_binary(rk_reader *r, int binary, int big_endian);

/* Fails with "truncated: <what> needs N bytes, M remain" unless n bytes are left. */
int rk_bin_need(rk_reader *r, size_t n, const char *what);
/* Raw bytes, bounds-checked. */
int rk_bin_bytes(rk_reader *r, void *out, size_t n, const char *what);

/* A number of type t: binary reads its bytes in the reader's byte order; text reads a token.
 * rk_read_integer rejects non-integral and out-of-range values (a float type must hold an
 * integer); rk_read_real converts any type to double. */
int rk_read_integer(rk_reader *r, rk_scalar t, int64_t *v, const char *what);
int rk_read_real(rk_reader *r, rk_scalar t, double *v, const char *what);

/* 1 on a little-endian host. */
int rk_host_little_endian(void);

#endif
