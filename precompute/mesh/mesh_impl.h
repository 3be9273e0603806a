/* Private to precompute/mesh: the per-format readers and writers that load.c and write.c
 * dispatch to, and small helpers they share. */
#ifndef RK_MESH_INTERNAL_H
#define RK_MESH_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "mesh/mesh.h"

/* Largest vertex or element count accepted, so 4 * count and friends fit an int. */
#define RK_MESH_MAX_COUNT (INT32_MAX / 8)

/* Tet readers: fill m (vertices and tets as in the file, 0-based, unchecked: rk_mesh_load
 * runs rk_mesh_check after). On failure m is left empty. */
int rk_read_gmsh(const char *path, rk_mesh *m, rk_error *err);
int rk_read_medit(const char *path, rk_mesh *m, rk_error *err);
int rk_read_tetgen(const char *path, rk_mesh *m, rk_error *err); /* path: .node or .ele */
int rk_read_vtk(const char *path, rk_mesh *m, rk_error *err);

/* Surface readers (indices validated, topology not checked). */
int rk_read_obj(const char *path, rk_surface *s, rk_error *err);
int rk_read_gltf(const char *path, rk_surface *s, rk_error *err);
int rk_read_off(const char *path, rk_surface *s, rk_error *err);
int rk_read_stl(const char *path, rk_surface *s, rk_error *err);
/* PLY vertices (x, y, z) and, when want_faces, the face list (fan-triangulated). */
/* tag: NULL, or receives each vertex's "tag" property (NULL when the file has none). */
int rk_read_ply(const char *path, rk_surface *s, int want_faces, int **tag, rk_error *err);

/* Tet writers; X is 3*nv positions to write (rest or deformed). */
int rk_write_medit(const char *path, const rk_mesh *m, const double *X, rk_error *err);
int rk_write_gmsh(const char *path, const rk_mesh *m, const double *X, int binary, rk_error *err);
int rk_write_vtk(const char *path, const rk_mesh *m, const double *X, int binary, rk_error *err);
int rk_write_tetgen(const char *path, const rk_mesh *m, const double *X, rk_error *err);

/* Binary numbers in a chosen byte order (errors surface through ferror at commit). */
void rk_put_i32(FILE *fp, int32_t v, int big_endian);
void rk_put_u64(FILE *fp, uint64_t v, int big_endian);
void rk_put_f32(FILE *fp, float v, int big_endian);
void rk_put_f64(FILE *fp, double v, int big_endian);

/* rk_mesh_check's handling of slivers (sliver.c): counts and lists them in rep (its
 * sliver_volume set, every tet oriented) and, under RK_MESH_DROP_FLAT, drops the flat tets with a
 * warning naming each, counting the vertices only they used in rep->orphans_removed (left in
 * place, unused, for the check to remove). Fails when every tet is flat and they are to go. */
int rk_mesh_slivers(rk_mesh *m, const char *what, rk_mesh_flat_policy policy, rk_mesh_report *rep, rk_error *err);

/* partner[4 t + l] (4 nt ints): the tet across the face of tet t opposite its vertex l, -1 when
 * no tet is (a boundary face). Ghost tets are not counted. A face of three tets or more (not a
 * manifold) names the next of them, round. */
int rk_mesh_face_partners(const rk_mesh *m, int *partner, rk_error *err);

/* Checks that m can be written: counts, indices in range. */
int rk_mesh_validate_for_write(const char *path, const rk_mesh *m, rk_error *err);

/* "path.ext" -> 1 when the extension matches (case-insensitive, ext with its dot). */
int rk_path_has_ext(const char *path, const char *ext);
/* path with its extension (if any) replaced by ext: "a/b.node" + ".ele" -> "a/b.ele". */
int rk_path_with_ext(const char *path, const char *ext, char *out, size_t cap, rk_error *err);

/* A growable array: makes room for `need` elements of `elem` bytes in *p (capacity *cap). */
int rk_grow(void *p, size_t *cap, size_t need, size_t elem, rk_error *err);

/* Surfaces built a vertex and a polygon at a time (OBJ, OFF, STL, PLY). */
typedef struct {
    rk_surface s;
    size_t vcap, fcap;
} rk_surface_builder;
int rk_sb_vertex(rk_surface_builder *b, const double p[3], rk_error *err);
/* Adds the polygon idx[0..n) (n >= 3, indices already validated) as a triangle fan. */
int rk_sb_polygon(rk_surface_builder *b, const int *idx, int n, rk_error *err);
/* A surface from triangles given by their corners (9 doubles a triangle, finite): corners with
 * exactly equal coordinates become one vertex (STL and glTF store them apart). */
int rk_surface_weld(const double *corners, int nf, rk_surface *s, rk_error *err);

/* Maps arbitrary (sparse, unordered) node tags to 0-based indices in file order. */
typedef struct {
    int64_t *tag;   /* sorted */
    int *index;
    size_t n;
    int contiguous; /* tags are first..first+n-1 in order: index = tag - first */
    int64_t first;
} rk_tag_map;
/* Fails with "node tag T appears twice" on a duplicate. */
int rk_tag_map_build(rk_tag_map *tm, const int64_t *tags, size_t n, rk_error *err);
int rk_tag_map_find(const rk_tag_map *tm, int64_t tag); /* -1 when absent */
void rk_tag_map_free(rk_tag_map *tm);

/* Gaussian splats: spherical-harmonic rotation (sh_rotate.c) and the deformation of one splat
 * (splats_deform.c). */
/* Bands 1..3's rotation matrices, packed: band l's (2l+1)^2 column-major values at
 * rk_sh_band_offset(l) (0, 9, 34). */
#define RK_SH_ROTATION_SIZE (9 + 25 + 49)
int rk_sh_band_offset(int l);
/* The LU factors of each band's fitting matrix, made once and reused for every rotation. */
typedef struct {
    double lu[RK_SPLATS_MAX_DEGREE][49];
    int piv[RK_SPLATS_MAX_DEGREE][7];
} rk_sh_rotator;
int rk_sh_rotator_init(rk_sh_rotator *rot, rk_error *err);
/* M (RK_SH_ROTATION_SIZE) for the rotation R (row-major, det +1), bands 1..degree. */
void rk_sh_rotator_matrices(const rk_sh_rotator *rot, const double R[9], int degree, double *M);
/* One channel's K coefficients (bands 1..degree, band order): out = blockdiag(M) in (out != in). */
void rk_sh_apply(const double *M, int degree, const double *in, double *out);
/* Whether R is a rotation: finite, R^T R = I and det R = 1 to tol. */
int rk_rotation_check(const double R[9], double tol);

/* Polar decomposition F = R S with det R = +1 (also for det F <= 0: then R is the rotation
 * nearest to F, S symmetric but not positive), from the SVD F = U diag(sigma) V^T (one-sided
 * Jacobi, LAPACKE dgesvj): R = U diag(1, 1, det(U V^T)) V^T. 0, or -1 for a non-finite F or one
 * of rank below 2. */
int rk_polar_rotation(const double F[9], double R[9]);
/* The splat (unit-or-not quaternion q = w x y z of non-zero length, log scales s) deformed by F
 * (with RF its polar rotation): Sigma' = F R diag(exp(2 s)) R^T F^T written as a unit quaternion qo
 * (w >= 0) and log scales so. 0, or -1 when Sigma' is singular or not finite (a collapsed splat). */
int rk_splat_deform_covariance(const double F[9], const double RF[9], const double q[4], const double s[3],
                               double qo[4], double so[3]);
/* A normal under F: F^-T n normalized (the cofactor of F, signed by det F); zero stays zero. */
void rk_splat_deform_normal(const double F[9], const double n[3], double out[3]);
/* The rotation matrix (row-major) of the quaternion w x y z (normalized here; length > 0). */
void rk_quat_to_matrix(const double q[4], double R[9]);

#endif
