/* precompute/asset: a reduced model baked into a .rombin asset (formats/ROMBIN.md), holding only
 * what the runtime needs for the scene:
 *   - the reduced operators (M_r, C_r, f_r, the pin penalty) and step parameters;
 *   - the cubature elements, with the basis rows of exactly the vertices they touch;
 *   - the basis rows of the shown vertices (the boundary surface by default, not the interior),
 *     of the contact vertices and of the vertices of the named groups an app may push;
 *   - the surface triangles over the shown vertices, and where each stored vertex came from.
 * Stored vertices are ordered: shown ones first (ascending source number), then the rest. */
#ifndef RK_ASSET_H
#define RK_ASSET_H

#include "formats/rombin_write.h"
#include "grassmann/grassmann.h"
#include "koopman/koopman.h"
#include "mesh/mesh.h"
#include "rom/rom.h"

/* RK_SHOW_FIRST: the first show_first vertices, in order (a point cloud's points; set by the bake). */
typedef enum { RK_SHOW_SURFACE = 0, RK_SHOW_ALL = 1, RK_SHOW_NONE = 2, RK_SHOW_FIRST = 3 } rk_show;

typedef struct {
    char name[ROMBIN_GROUP_NAME_BYTES];
    rk_box box;
} rk_asset_group;

#define RK_ASSET_MAX_GROUPS 64

/* An asset's collision geometry for the app's colliders: none; the collision vertices (CVTX) and
 * the collision surface they span (OBHD, CEDG, CTRI), which a shape touches exactly (the default);
 * or the vertices alone (the smallest asset: a shape thinner than an edge passes between them). */
typedef enum { RK_COLLIDERS_NONE = 0, RK_COLLIDERS_SURFACE = 1, RK_COLLIDERS_VERTICES = 2 } rk_colliders;

typedef struct {
    int real_type;            /* ROMBIN_REAL_F32 (default) or ROMBIN_REAL_F64 */
    int compress;             /* deflate the chunks (default 0: the runtime opens stored chunks only) */
    rk_show show;
    int show_first;           /* RK_SHOW_FIRST: how many */
    int colliders;            /* what an app's colliders act on (rk_colliders; default RK_COLLIDERS_SURFACE) */
    int contact_pairs;        /* the runtime's obstacle pair capacity (OBHD; 0: sized at bake) */
    int ngroups;
    rk_asset_group groups[RK_ASSET_MAX_GROUPS];
} rk_asset_options;

/* float32, uncompressed, the surface shown, colliders, no groups. */
void rk_asset_default_options(rk_asset_options *o);

typedef struct {
    int vertices, shown, elements, contacts, groups, triangles;
} rk_asset_summary;

/* What a Koopman asset shows and how it is pushed, beyond the operator itself. */
typedef struct {
    int nv;                      /* vertices: the operator's values are 3 nv displacements */
    const double *X;             /* 3 nv rest positions */
    const double *vertex_mass;   /* nv (kg): an applied force over it is the impulse's acceleration */
    const int *tris;             /* boundary triangles (source numbers, 3 ntris), or NULL: every vertex is shown */
    int ntris;
    const double *accel;         /* 3 nv: the constant acceleration stepped along (gravity, loads
                                  * over mass), or NULL for none */
    const double *u0, *u_prev;   /* the first two displacement frames, or NULL: start at rest */
    int source_tets, trajectories; /* information for KHED */
} rk_koopman_geometry;

/* An adaptive linear ROM beside the reduced model (ROMBIN.md "Adaptive linear ROM chunks"): U is
 * then its quadratic decoder's linear part Phi, the model is built on Phi (its pin penalty is not
 * stored: the runtime moves prescribed vertices itself) and its quadrature is the cubature the
 * runtime integrates every step's basis with. */
typedef struct {
    int history;                 /* m */
    double lambda, reg, ridge, budget;
    const double *Psi;           /* 3 nv x r(r+1)/2, column-major: the quadratic decoder's second-order
                                  * term, or NULL with crom */
    const rk_crom_parts *crom;   /* a CROM decoder (every vertex is then stored: its encoder reads them
                                  * all), or NULL */
    const rk_fom_options *options; /* the prescribed motions, gravity, loads and damping it steps under */
    int cadence;                 /* K: the basis refreshed every K steps (0 or 1: every step) */
    int encoder_iterations;      /* the encoder's Gauss-Newton iterations at most (0: 20) */
} rk_asset_alrom;

/* A detailed surface embedded in the model's tets (a cage's original surface, precompute/cage): what
 * the asset shows instead of the mesh's boundary. Vertex i lies in tet tet[i] at barycentric
 * coordinates bary[4i..4i+3]; its basis rows are those coordinates over the tet's four rows, and a
 * skinning basis's weights likewise (linear in each tet), unless rk_asset_rom.embedded_W gives
 * them evaluated at the point (an RKPM basis). */
typedef struct {
    int nv, nf;
    double *X;                   /* 3 nv rest positions */
    int *tris;                   /* 3 nf, outward */
    int *tet;                    /* nv */
    double *bary;                /* 4 nv */
} rk_embedded_surface;

/* A reduced model of a mesh, as the bake reads it. */
typedef struct {
    const rk_mesh *mesh;         /* the source mesh: its boundary is what is shown */
    const rk_fem *fem;           /* the elements the cubature points are */
    const double *U;             /* 3 nv x r basis */
    const rk_rom_model *model;
    int skin_handles;            /* U is linear blend skinning over this many handles (rk_skinning_to_U
                                  * over the mesh's rest positions), 0 otherwise: the SKIN chunk */
    const rk_skin_points *points; /* mesh-free: the model's quadrature points are these integration
                                  * points (quad.source indexes them; IPNT), not elements; needs skinning */
    int points_shown;            /* a point cloud: the first points_shown vertices are shown, in order,
                                  * with no surface (0: the mesh's boundary by o->show) */
    const double *shown_grad;    /* a point cloud: the weights' gradients at those points (3 points_shown x H,
                                  * column-major, as rk_rkpm_interpolate's dW): GRAD, or NULL */
    const char *splat_file;      /* a point cloud from a Gaussian-splat PLY: stored whole (SPLY), or NULL */
    const rk_asset_alrom *alrom; /* an adaptive linear ROM (bake_alrom.c), or NULL */
    const rk_embedded_surface *embedded; /* shown instead of the mesh's boundary, or NULL: its vertices
                                  * are the shown ones (VMAP numbers vertex i source vertices + i), its
                                  * triangles SURF; the mesh's vertices the cubature and contact need
                                  * are stored after them */
    const double *embedded_W;    /* with embedded and skin_handles: the skinning weights evaluated at each
                                  * embedded vertex (embedded->nv x skin_handles, column-major; an RKPM
                                  * basis's exist anywhere), or NULL: interpolated in its tet */
    const double *velocity0;     /* r: the reduced velocity at t = 0 (VEL0), or NULL: at rest */
} rk_asset_rom;

/* Adds every chunk of reduced model R to w (its real type and compression are the writer's), and
 * with k (may be NULL) a Koopman operator over the same mesh beside it (an entry with both
 * cubature and koopman): one asset, two models; the runtime opens the reduced model by default
 * and the operator with romrt_open_kind. info: JSON text for the INFO chunk (may be NULL). */
int rk_asset_bake(const rk_asset_rom *R, const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *o,
                  const char *info, rombin_writer *w, rk_asset_summary *summary, rk_error *err);

/* Adds a Koopman asset's chunks (formats/ROMBIN.md "Koopman chunks") for operator k, whose
 * values are g's 3 nv displacements. */
int rk_asset_bake_koopman(const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *o,
                          const char *info, rombin_writer *w, rk_asset_summary *summary, rk_error *err);
/* The same chunks as a whole asset: a writer of o's real type and compression, serialized into
 * *data (malloc'd, *bytes long; the caller frees it). */
int rk_asset_koopman_serialized(const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *o,
                                const char *info, rk_asset_summary *summary, unsigned char **data, size_t *bytes,
                                rk_error *err);

#endif
