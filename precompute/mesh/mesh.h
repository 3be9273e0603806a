/* precompute/mesh: tetrahedral and surface meshes in, checked, out.
 *
 * Readers (chosen by file extension in rk_mesh_load):
 *   .msh        Gmsh 2.2 and 4.1, ASCII and binary (tetrahedra = element type 4)
 *   .mesh       MEDIT (Vertices / Tetrahedra; Triangles ignored)
 *   .node/.ele  TetGen, 0- or 1-based (either file name may be given)
 *   .vtk        legacy VTK unstructured grid, ASCII and binary (cell type 10)
 * Surface readers (rk_surface_load): .obj .off .stl (ASCII/binary) .ply (ASCII/binary).
 *
 * Every load runs rk_mesh_check: indices in range, finite coordinates, inverted tets
 * reoriented (counted in the report), degenerate tets rejected by index, unused vertices
 * removed, connected components counted. Errors name the file and the line or byte offset. */
#ifndef RK_MESH_H
#define RK_MESH_H

#include "util/error.h"

typedef struct {
    int nv;          /* vertices */
    int nt;          /* tetrahedra */
    double *X;       /* 3*nv rest positions, metres */
    int *tets;       /* 4*nt vertex indices, 0-based, positively oriented after the check */
    int *tet_tag;    /* nt region tags from the file (Gmsh physical / MEDIT ref), or NULL */
} rk_mesh;

typedef struct {
    int nv;
    int nf;
    double *X;       /* 3*nv */
    int *tris;       /* 3*nf, 0-based, counter-clockwise seen from outside */
} rk_surface;

/* What rk_mesh_check found and fixed. */
typedef struct {
    int reoriented;        /* inverted tets flipped to positive orientation */
    int unused_removed;    /* vertices referenced by no tet, removed */
    int components;        /* connected components (tets sharing a vertex) */
    double min_volume, max_volume;
    double min_quality;    /* worst radius ratio 3*r_in/r_out in (0, 1], 1 = regular */
    double mean_quality;
    double bbox_min[3], bbox_max[3];
} rk_mesh_report;

int rk_mesh_load(const char *path, rk_mesh *m, rk_mesh_report *rep, rk_error *err);
/* Checks and repairs a mesh in place (see above); `what` names it in messages (a file path). */
int rk_mesh_check(rk_mesh *m, const char *what, rk_mesh_report *rep, rk_error *err);
void rk_mesh_free(rk_mesh *m);

/* A procedural box [0,size] split into cells[0]*cells[1]*cells[2] hexahedra of 6 tets each
 * (conforming across cells). */
int rk_mesh_box(const double size[3], const int cells[3], rk_mesh *m, rk_error *err);

/* Scales then translates the rest positions. */
void rk_mesh_transform(rk_mesh *m, double scale, const double translate[3]);

/* Boundary faces (triangles used by exactly one tet), oriented outward. *tris malloc'ed. */
int rk_mesh_boundary(const rk_mesh *m, int **tris, int *nf, rk_error *err);

/* Writers, atomic (util/atomic_file.h). By extension: .mesh (MEDIT), .vtk (legacy ASCII,
 * ParaView), .msh (Gmsh 4.1 ASCII), .node (TetGen, writes .node and .ele), .obj / .ply
 * (boundary surface only). `x` may replace the rest positions (deformed frames); NULL = rest. */
int rk_mesh_write(const char *path, const rk_mesh *m, const double *x, rk_error *err);

int rk_surface_load(const char *path, rk_surface *s, rk_error *err);
/* Closed, edge-manifold, consistently oriented, outward (positive volume), finite. */
int rk_surface_check(const rk_surface *s, const char *what, rk_error *err);
void rk_surface_free(rk_surface *s);

/* Tetrahedralizes a checked surface with the tetgen command.
 * max_radius_edge: quality bound (tetgen -q), <= 0 for the default 1.4.
 * max_volume: volume bound (tetgen -a), <= 0 for none. */
int rk_tetrahedralize(const rk_surface *s, double max_radius_edge, double max_volume,
                      rk_mesh *out, rk_error *err);

/* Point clouds (PLY vertices with x, y, z; Gaussian-splat PLY included). *X malloc'ed, 3*n. */
int rk_points_load(const char *path, double **X, int *n, rk_error *err);

#endif
