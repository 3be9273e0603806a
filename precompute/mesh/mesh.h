/* precompute/mesh: tetrahedral and surface meshes in, checked, out.
 *
 * Readers (chosen by file extension in rk_mesh_load, case-insensitive):
 *   .msh        Gmsh 2.x and 4.1, ASCII and binary, either byte order (tetrahedra = element
 *               type 4; a second-order tet, type 11, gives its 4 corners; other types skipped)
 *   .mesh       MEDIT (Vertices / Tetrahedra with refs; other sections skipped)
 *   .node/.ele  TetGen, 0- or 1-based (either file name may be given)
 *   .vtk        legacy VTK unstructured grid, ASCII and binary (cell type 10; classic CELLS
 *               or the 5.x OFFSETS/CONNECTIVITY layout)
 * Surface readers (rk_surface_load): .obj .off .stl (ASCII/binary) .ply (ASCII/binary) .gltf .glb
 * (glTF 2.0: every triangle primitive of the default scene, node transforms applied).
 *
 * Every load runs rk_mesh_check: indices in range, finite coordinates, inverted tets
 * reoriented (counted in the report), slivers and flat tets reported by index (and flat tets
 * dropped when the mesh is for a simulation), unused vertices removed, connected components
 * counted. Errors name the file and the line (ASCII) or byte offset (binary). A count in a header
 * is checked against the size of the file before anything is allocated for it. tet_tag is NULL
 * after a load when every tag is 0. */
#ifndef RK_MESH_H
#define RK_MESH_H

#include <float.h>

#include "util/util.h"

typedef struct {
    int nv;          /* vertices */
    int nt;          /* tetrahedra */
    double *X;       /* 3*nv rest positions, metres */
    int *tets;       /* 4*nt vertex indices, 0-based, positively oriented after the check (flat
                      * tets, kept by a conversion, have volume >= 0) */
    int *tet_tag;    /* nt region tags from the file (Gmsh physical / MEDIT ref), or NULL */
    /* Ghost tets: flat tets rk_mesh_check (RK_MESH_DROP_FLAT) dropped from inside the body. They
     * carry no material and are not among the nt tets (writers skip them), but rk_mesh_boundary
     * matches their faces, so the boundary stays the body's instead of gaining a zero-width closed
     * pocket where they were (which self-contact would see as two surfaces touching). */
    int nghost;
    int *ghost;      /* 4*nghost vertex indices, or NULL */
} rk_mesh;

typedef struct {
    int nv;
    int nf;
    double *X;       /* 3*nv */
    int *tris;       /* 3*nf, 0-based, counter-clockwise seen from outside */
} rk_surface;

/* Slivers and flat tets (sliver.c; the one place that decides what happens to them).
 *
 * A tet is a sliver when |volume| <= RK_MESH_SLIVER * (bounding-box diagonal)^3 (what conversion
 * used to refuse as degenerate), or when it is flat. It is flat when its thickness (its smallest
 * height, 6|V| / twice its largest face area) is at most RK_MESH_FLAT times its size s, the larger
 * of its longest edge and its largest coordinate magnitude: a vertex is only known to about
 * DBL_EPSILON * s (the file's rounding; the rounding of the edge vectors and the determinant), so
 * a flat tet's volume, orientation and rest-shape inverse Dm^-1 are rounding noise. RK_MESH_FLAT
 * is 1024 rounding units: Dm^-1 of a tet just thicker still has about 3 correct digits. Measured on
 * a 1 x 0.2 x 0.2 m stable Neo-Hookean cantilever (10 x 2 x 2 cells, 20 steps under gravity) with
 * one interior vertex moved toward a face so that a cap sliver is left with thickness/size t:
 * from t = 0.14 down to 9000 rounding units (2e-12), Newton takes exactly the iterations it takes
 * at t = 0.14 (31 at E = 1e9 Pa, 60 at 1e6, 566-571 over 100 steps at 1e5); at 900 units 33 (1e9),
 * at 90 36, at 9 37, and at 0.9 units 81 with 154 line-search halvings: the first change comes
 * just below the threshold. Above it, every sliver is kept. */
#define RK_MESH_SLIVER 1e-12
#define RK_MESH_FLAT (1024 * DBL_EPSILON)
/* How many slivers the report lists by index. */
#define RK_MESH_LISTED 5

/* What rk_mesh_check does with flat tets. */
typedef enum {
    /* Converting: every tet is kept exactly as it is (inverted ones reoriented), flat ones
     * included; slivers are only reported. */
    RK_MESH_KEEP_FLAT = 0,
    /* Simulating: flat tets are dropped from the mesh, each named in a warning on stderr
     * (rk_warn), and so are the vertices only they used; every sliver with a thickness above the
     * rounding is kept (stable Neo-Hookean is defined for any positive volume). A group of flat
     * tets (sharing faces) with no face on the boundary and no vertex of its own stays as ghost
     * tets (rk_mesh.ghost): no material, but the boundary is the same as with them. */
    RK_MESH_DROP_FLAT = 1
} rk_mesh_flat_policy;

/* A sliver in the report. */
typedef struct {
    int tet;               /* 0-based index among the input's tets */
    int v[4];              /* its vertices: 0-based input indices, in the order the check left them */
    double volume;         /* >= 0 (after reorientation) */
    int flat;
} rk_mesh_sliver;

/* What rk_mesh_check found and fixed. */
typedef struct {
    int reoriented;        /* inverted tets flipped to positive orientation */
    int unused_removed;    /* vertices referenced by no tet of the input, removed */
    int components;        /* connected components (tets sharing a vertex) */
    double min_volume, max_volume;  /* over the tets kept */
    double min_quality;    /* worst radius ratio 3*r_in/r_out in [0, 1], 1 = regular, 0 = flat */
    double mean_quality;
    double bbox_min[3], bbox_max[3];
    int slivers;           /* slivers among the input's tets, flat ones included */
    int flat;              /* flat tets among the input's tets */
    int flat_dropped;      /* flat tets removed (RK_MESH_DROP_FLAT; 0 otherwise), ghosts included */
    int ghosts;            /* of those, kept as ghost tets (inside the body) */
    int orphans_removed;   /* vertices used only by dropped tets, removed with them */
    double sliver_volume;  /* RK_MESH_SLIVER * diagonal^3 of this mesh */
    int nlisted;           /* the first min(slivers, RK_MESH_LISTED) slivers by index */
    rk_mesh_sliver listed[RK_MESH_LISTED];
} rk_mesh_report;

/* On failure *m is empty (nothing to free). rep may be NULL. flat: RK_MESH_KEEP_FLAT to convert
 * or inspect a file, RK_MESH_DROP_FLAT to simulate it. */
int rk_mesh_load(const char *path, rk_mesh_flat_policy flat, rk_mesh *m, rk_mesh_report *rep, rk_error *err);
/* Checks and repairs a mesh in place (see above); `what` names it in messages (a file path).
 * Errors: a tet that uses a vertex twice or one that does not exist, a non-finite coordinate,
 * no tets, and (RK_MESH_DROP_FLAT) a mesh whose tets are all flat. Inverted tets get their last
 * two vertices swapped; afterwards every tet has a signed volume >= 0 (> 0 unless flat). Slivers
 * are counted and listed, flat tets handled as `flat` says. rep may be NULL. On failure the mesh
 * may be partly repaired; free it. */
int rk_mesh_check(rk_mesh *m, const char *what, rk_mesh_flat_policy flat, rk_mesh_report *rep, rk_error *err);
void rk_mesh_free(rk_mesh *m);

/* A procedural box [0,size] split into cells[0]*cells[1]*cells[2] hexahedra of 6 tets each
 * (conforming across cells). */
int rk_mesh_box(const double size[3], const int cells[3], rk_mesh *m, rk_error *err);

/* Scales then translates the rest positions. */
void rk_mesh_transform(rk_mesh *m, double scale, const double translate[3]);

/* Uniform 1:8 ("red") refinement, `levels` times (precompute/mesh/refine.c): each tet is split at
 * its edges' midpoints into its four corners and the four tets around the shortest diagonal of the
 * octahedron between them. Every edge's midpoint is one new vertex (numbered after the old
 * vertices, in the order of the edges' sorted vertex pairs), so the result is conforming and the
 * same for the same input; a level makes 8 nt tets and nv + (edges) vertices, keeps the total
 * volume and the boundary surface (each boundary triangle split in four), gives each child its
 * parent's tag and orientation (positive after rk_mesh_check), and splits ghost tets alike. Children
 * are numbered 8 t .. 8 t + 7 after their parent t. levels = 0 copies. Errors: levels outside
 * [0, RK_MESH_REFINE_MAX_LEVELS], a result above RK_MESH_REFINE_MAX_TETS tets, a bad index or a
 * tet using a vertex twice, a ghost tet with an edge no tet has. *out must not be *in; on failure it
 * is empty. */
#define RK_MESH_REFINE_MAX_LEVELS 4
#define RK_MESH_REFINE_MAX_TETS (1 << 24)
int rk_mesh_refine(const rk_mesh *in, int levels, rk_mesh *out, rk_error *err);

/* Boundary faces (triangles used by exactly one tet, ghost tets counted), oriented outward.
 * A mesh of ghost tets only (a point cloud's contact proxy) has their outer faces as boundary.
 * *tris malloc'ed. */
int rk_mesh_boundary(const rk_mesh *m, int **tris, int *nf, rk_error *err);

/* Writers, atomic (util/util.h). By extension: .mesh (MEDIT), .vtk (legacy ASCII,
 * ParaView), .msh (Gmsh 4.1 ASCII), .node or .ele (TetGen, writes .node and .ele, 0-based),
 * .obj / .ply / .off / .stl (boundary surface only, through rk_surface_write). tet_tag is
 * written as the MEDIT ref, the Gmsh physical tag, the TetGen region attribute and a VTK
 * CELL_DATA "tag" array, and read back from each. `x` may replace the rest positions
 * (deformed frames); NULL = rest. */
int rk_mesh_write(const char *path, const rk_mesh *m, const double *x, rk_error *err);
/* As rk_mesh_write, but .msh is Gmsh 4.1 binary and .vtk legacy binary (big-endian);
 * other extensions are written as by rk_mesh_write. */
int rk_mesh_write_binary(const char *path, const rk_mesh *m, const double *x, rk_error *err);

/* Reads the faces (polygons fan-triangulated; STL vertices welded where exactly equal) and
 * checks that indices are in range; the topology is rk_surface_check's job. */
int rk_surface_load(const char *path, rk_surface *s, rk_error *err);
/* Whether rk_surface_load reads path (by its extension: a surface, not a tet mesh). */
int rk_path_is_surface(const char *path);
/* Closed, edge-manifold, consistently oriented, outward (positive volume), finite. The
 * message names the first bad edge (its two vertex indices) or face. A surface that is
 * inside out (everything right but the volume negative) is an error here; see below. */
int rk_surface_check(const rk_surface *s, const char *what, rk_error *err);
/* rk_surface_check, except that a surface that is merely inside out is flipped (every
 * face reversed) instead of rejected; *flipped (may be NULL) says whether it was. */
int rk_surface_check_and_orient(rk_surface *s, const char *what, int *flipped, rk_error *err);
/* Enclosed volume (sum of signed tets over the faces); positive when oriented outward. */
double rk_surface_volume(const rk_surface *s);
/* Atomic, by extension: .obj, .off, .ply (binary little-endian), .stl (binary). */
int rk_surface_write(const char *path, const rk_surface *s, rk_error *err);
void rk_surface_free(rk_surface *s);

/* Signed volume of the tet (a, b, c, d): positive when d sees a, b, c counter-clockwise. */
double rk_tet_signed_volume(const double *a, const double *b, const double *c, const double *d);
/* 3 * inradius / circumradius: 1 for a regular tet, 0 for a flat one. */
double rk_tet_radius_ratio(const double *a, const double *b, const double *c, const double *d);
/* Whether the tet is flat (RK_MESH_FLAT above): its volume is rounding noise. Coincident or
 * collinear vertices are flat too. *thickness and *size (may be NULL) get the two lengths compared. */
int rk_tet_is_flat(const double *a, const double *b, const double *c, const double *d, double *thickness,
                   double *size);

/* Tetrahedralizes a surface with the tetgen command (run in a private temporary directory;
 * the surface is checked first). The result has been through rk_mesh_check (RK_MESH_KEEP_FLAT).
 * The command is $ROMKIT_TETGEN when set, else tetgen on PATH; a missing or failing tetgen is an
 * error that says so (with its exit status and the end of its output).
 * max_radius_edge: quality bound (tetgen -q), <= 0 for the default 1.4.
 * max_volume: volume bound (tetgen -a), <= 0 for none. */
int rk_tetrahedralize(const rk_surface *s, double max_radius_edge, double max_volume,
                      rk_mesh *out, rk_error *err);

/* Point clouds (PLY vertices with x, y, z; Gaussian-splat PLY included, its other attributes read
 * past: rk_splats_read below keeps them). *X malloc'ed, 3*n. */
int rk_points_load(const char *path, double **X, int *n, rk_error *err);
/* The same, and *tag (malloc'ed, n) each point's whole-number PLY property "tag" (a layer or material
 * number, as a Gmsh physical group is a tet's), or NULL when the file has none. */
int rk_points_load_tagged(const char *path, double **X, int *n, int **tag, rk_error *err);

/* ==== Gaussian splats (3DGS PLY: Kerbl et al. 2023, the FreeForm paper's splat input) ====
 *
 * rk_splats_read keeps every property of the PLY's "vertex" element, in file order, as doubles
 * (exact for every PLY scalar type), with the PLY type it had, and resolves the ones 3DGS defines:
 *   x y z                centre (required; finite)
 *   scale_0..2           log standard deviations along the splat's axes
 *   rot_0..3             quaternion w x y z (any non-zero length: 3DGS normalizes on use)
 *   opacity              logit of the opacity
 *   f_dc_0..2            SH band 0, one per colour channel
 *   f_rest_0..(3K-1)     SH bands 1..deg, K = (deg+1)^2 - 1 per channel, channel-major:
 *                        f_rest[c*K + k] is coefficient k (band order) of channel c
 *   nx ny nz             normals (3DGS writes zeros)
 * An index is -1 when the property is absent; a group (scale, rot, f_dc, normal) is present whole
 * or not at all. A plain point cloud (x y z only) is valid, has_splat_attributes = 0. Other elements
 * (faces) are read past. Errors name the file and what is wrong: a missing x/y/z, part of a group,
 * an f_rest count that is not 3((d+1)^2 - 1) for d in 1..3, a list property in the vertex element,
 * a duplicated name, truncated data (byte offset), a non-finite coordinate or splat attribute at
 * vertex i, a quaternion of zero length at vertex i. */
#define RK_SPLATS_NAME_MAX 64
#define RK_SPLATS_MAX_DEGREE 3
#define RK_SPLATS_MAX_REST 45 /* 3 channels x 15 coefficients (degree 3) */
typedef struct {
    char name[RK_SPLATS_NAME_MAX];
    char type[8];            /* the PLY type: char uchar short ushort int uint float double */
} rk_splat_property;

typedef struct {
    int n;                   /* splats (vertices) */
    double *X;               /* 3n centres, a copy of the x y z columns */
    int nprop;               /* properties of the vertex element, in file order */
    rk_splat_property *prop; /* nprop */
    double *values;          /* n * nprop: values[i * nprop + j] = property j of splat i */
    /* Column indices into prop / values, -1 when absent. */
    int xyz[3];
    int scale[3];
    int rot[4];
    int opacity;
    int f_dc[3];
    int normal[3];
    int nrest;               /* f_rest properties: 3K */
    int f_rest[RK_SPLATS_MAX_REST]; /* f_rest[j] = column of f_rest_j */
    int sh_degree;           /* 0..3 */
    int has_splat_attributes; /* scale, rot, opacity and f_dc all present */
} rk_splats;

int rk_splats_read(const char *path, rk_splats *s, rk_error *err);
/* Writes s as a binary little-endian 3DGS PLY with the same properties in the same order (a
 * property the deformation changes that had an integer type is written as float), every splat
 * moved (splats_deform.c, PhysGaussian's kinematics):
 *   centre        x[3i..3i+2] (deformed centres); x NULL keeps X
 *   F             9n, F[9i..] the row-major deformation gradient at splat i; NULL = identity, then
 *                 only the centres change and every other value is copied bit for bit
 *   covariance    (with F, scales and rotations present) Sigma = R diag(exp(2 s)) R^T becomes
 *                 F Sigma F^T, written as a unit quaternion (w >= 0, det +1) and log scales
 *   colour        SH bands 1..deg rotated by R_F of F's polar decomposition F = R_F S (det R_F =
 *                 +1); band 0 unchanged
 *   normals       F^-T n, normalized (zero normals stay zero)
 * Opacity and every other property are copied. Atomic: on any error (a bad path, a non-finite x
 * or F, a singular F that collapses a splat) nothing is left at path. */
int rk_splats_write(const char *path, const rk_splats *s, const double *x, const double *F, rk_error *err);
void rk_splats_free(rk_splats *s);

/* Rotates real spherical-harmonic coefficients in the 3DGS basis (graphdeco-inria
 * gaussian-splatting utils/sh_utils.py: band 1 is (-C1 y, C1 z, -C1 x), bands 2 and 3 the C2, C3
 * polynomials in that order) so that the colour seen from direction R d with the new coefficients
 * is the colour seen from d with the old ones. coef: channels x K values (K = (degree+1)^2 - 1,
 * bands 1..degree, channel-major as f_rest), rotated in place. R: row-major, a rotation (det +1,
 * orthonormal to 1e-6, else an error). degree 0..3. */
int rk_sh_rotate(const double R[9], int degree, int channels, double *coef, rk_error *err);

/* An axis-aligned selection box (scenes select fixed, moving and loaded vertices, regions and
 * asset groups with them). */
typedef struct {
    double min[3], max[3];
} rk_box;
/* Whether p lies in b grown by slack on every side. */
int rk_box_contains(const rk_box *b, const double *p, double slack);

/* Cuts voids: drops the tets whose centroid lies in any of the boxes and the vertices only they used
 * (renumbering the rest, rk_mesh_check), so each void's walls become boundary faces (carve.c; a
 * pneumatic chamber's cavity). Fails when nothing is left. */
int rk_mesh_carve(rk_mesh *m, const rk_box *boxes, int nboxes, rk_error *err);

#endif
