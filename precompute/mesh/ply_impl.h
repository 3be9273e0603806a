/* Private to precompute/mesh: the one PLY header parser (ply_header.c), shared by the surface and
 * point-cloud reader (surface_ply.c) and the Gaussian-splat reader (splats_read.c).
 *
 * rk_ply_open reads the whole file and its header: the format (ascii, binary_little_endian,
 * binary_big_endian), the elements in header order with their counts and their properties (scalar
 * or list, with their types). The reader then stands at the first row of the first element, in the
 * file's mode (tokens or raw bytes), so rows are parsed with rk_read_real / rk_read_integer the
 * same way for ASCII and binary files. */
#ifndef RK_MESH_PLY_H
#define RK_MESH_PLY_H

#include <stdint.h>

#include "mesh/binary_reader_impl.h"

#define RK_PLY_MAX_ELEMENTS 16
/* Properties of one element: far more than any PLY carries (a degree-3 Gaussian splat has 62). */
#define RK_PLY_MAX_PROPS 4096

typedef struct {
    rk_token name;          /* points into the file buffer */
    rk_scalar type;         /* of the value, or of the list items */
    int is_list;
    rk_scalar count_type;   /* of the list length */
} rk_ply_property;

typedef struct {
    rk_token name;
    int64_t count;
    int nprops;
    size_t cap;
    rk_ply_property *props; /* nprops, malloc'ed */
} rk_ply_element;

typedef struct {
    rk_reader r;
    int binary, big_endian;
    int nelements;
    rk_ply_element elements[RK_PLY_MAX_ELEMENTS];
} rk_ply_file;

/* Reads the file and its header. On failure everything is released (nothing to close). */
int rk_ply_open(rk_ply_file *p, const char *path, rk_error *err);
void rk_ply_close(rk_ply_file *p);
/* Guards e's row count by the least a row can take (before anything is allocated for it): the
 * message names the element and says the file is truncated. */
int rk_ply_check_rows(rk_ply_file *p, const rk_ply_element *e);
/* Reads past a list property's length and items (a row's list of an element we do not keep). */
int rk_ply_skip_list(rk_ply_file *p, const rk_ply_property *q);
/* Reads past every row of e. */
int rk_ply_skip_rows(rk_ply_file *p, const rk_ply_element *e);
/* The PLY name of a scalar type: char uchar short ushort int uint float double (int64 and uint64,
 * which PLY has no name for, as "int64" and "uint64"). */
const char *rk_ply_type_name(rk_scalar t);

#endif
