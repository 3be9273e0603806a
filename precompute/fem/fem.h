/* precompute/fem: P1 tetrahedral finite elements over a checked mesh.
 * Per-element materials (heterogeneous objects), consistent and lumped mass, the elastic
 * energy with its gradient and (optionally PSD-projected) Hessian, and the rest stiffness used for
 * Rayleigh damping and modal analysis (contact is precompute/contact's).
 * All element physics comes from physics/ (one source of truth, DESIGN.md). */
#ifndef RK_FEM_H
#define RK_FEM_H

#include <string.h>
#include <suitesparse/cholmod.h>

#include "mesh/mesh.h"
#include "physics/physics.h"
#include "util/util.h"

typedef struct {
    rk_material_model model;
    double young;    /* Pa */
    double poisson;  /* in (-1, 0.5) */
    double density;  /* kg/m^3 */
} rk_material;

/* Symmetric sparse matrix, compressed columns, upper triangle only (row <= col), the layout
 * CHOLMOD takes with stype = 1. Row indices sorted within each column. */
typedef struct {
    int n;
    int nnz;
    int *colptr;  /* n + 1 */
    int *rowind;  /* nnz */
    double *val;  /* nnz */
} rk_sparse;

typedef struct {
    int nv, nt;
    const double *X;     /* 3*nv rest positions (borrowed from the mesh) */
    const int *tets;     /* 4*nt (borrowed) */
    int nghost;          /* the mesh's ghost tets (borrowed): no material here, only their faces for */
    const int *ghost;    /* the boundary the contact stage builds from this model (rk_mesh.ghost) */
    double *Dm_inv;      /* 9*nt */
    double *vol;         /* nt rest volumes */
    rk_material_model *model; /* nt */
    double *mu, *lambda, *density; /* nt, Lame parameters and density per element */
    double *vertex_mass; /* nv lumped masses (kg): each tet gives rho*vol/4 to each vertex */
    double *point_mass;  /* nv masses beyond the elements' (rk_fem_init_points' vertex_mass: a
                          * cloud's points), included in vertex_mass; NULL from rk_fem_init */
    /* The 3nv x 3nv pattern of every matrix below: all tet couplings plus every vertex's
     * diagonal 3x3 block. slot[78*t + k] is where the k-th upper-triangle entry of tet t's
     * 12x12 block lands in val (k runs over (i <= j) row-major over the 12 dofs a0 a1 a2 b0 ...). */
    rk_sparse pattern;   /* colptr and rowind only; val is NULL */
    int *slot;
} rk_fem;

/* mats: nt materials (one per element). Fails on non-positive volume (the mesh must be
 * checked), nonsense parameters (E <= 0, nu outside (-1, 0.5), density <= 0, non-finite). */
int rk_fem_init(rk_fem *f, const rk_mesh *m, const rk_material *mats, rk_error *err);
/* A model whose vertices need not belong to an element: point clouds (whose elastic energy and
 * mass a mesh-free quadrature integrates), alone or beside tet meshes in one scene. The m->nt
 * elements (mats: their materials, NULL when there is none) as rk_fem_init; each vertex's lumped
 * mass is its elements' plus vertex_mass[v] (>= 0: a cloud's points weigh loads and pins; its
 * contact surface's vertices weigh nothing); the ghost tets kept for the boundary (a contact
 * surface). */
int rk_fem_init_points(rk_fem *f, const rk_mesh *m, const rk_material *mats, const double *vertex_mass,
                       rk_error *err);
void rk_fem_free(rk_fem *f);

/* A zeroed matrix with the fem pattern (shares nothing: its own arrays). */
int rk_sparse_alloc_pattern(const rk_fem *f, rk_sparse *S, rk_error *err);
void rk_sparse_free(rk_sparse *S);
void rk_sparse_zero(rk_sparse *S);
/* y = S x (S symmetric, upper stored). */
void rk_sparse_mul(const rk_sparse *S, const double *x, double *y);
/* x^T S y (S symmetric, upper stored); no scratch, so callable on const data. */
double rk_sparse_dot(const rk_sparse *S, const double *x, const double *y);
/* Sum of the diagonal entries. */
double rk_sparse_trace(const rk_sparse *S);
/* Index in val of entry (row, col) with row <= col, or -1 when outside the pattern. */
int rk_sparse_find(const rk_sparse *S, int row, int col);

/* Consistent mass (rho*vol/20 * (1 + delta_ab) per tet) or lumped (diagonal), added into M. */
void rk_fem_add_mass(const rk_fem *f, int lumped, double scale, rk_sparse *M);
/* The same with density 1: integral of phi_a phi_b over the volume (I3 per vertex pair). */
void rk_fem_add_volume_mass(const rk_fem *f, int lumped, double scale, rk_sparse *M);
/* The masses rk_fem_init_points gave vertices beyond their elements' (a cloud's points: rk_fem_add_mass
 * has only the elements'), times scale, on M's diagonal: the two make the model's whole mass. */
void rk_fem_add_point_mass(const rk_fem *f, double scale, rk_sparse *M);
/* Linear-elasticity stiffness at rest, added into K (scaled): each element's own model's
 * unprojected Hessian at x = X (all four models share the linear tangent at F = I). */
void rk_fem_add_rest_stiffness(const rk_fem *f, double scale, rk_sparse *K);

/* Elastic energy at positions x (3*nv). Returns +INFINITY if any value is not finite. */
double rk_fem_energy(const rk_fem *f, const double *x);
/* g += scale * dE/dx */
void rk_fem_add_gradient(const rk_fem *f, const double *x, double scale, double *g);
/* H += scale * d2E/dx2, each element's dP/dF projected to PSD when project != 0. */
void rk_fem_add_hessian(const rk_fem *f, const double *x, double scale, int project, rk_sparse *H);
/* Number of elements with det F <= 0 at x; *min_J (if not NULL) gets the smallest det F. */
int rk_fem_inverted(const rk_fem *f, const double *x, double *min_J);
/* out[v]: the largest principal Cauchy stress (Pa) at vertex v for positions x (3 nv), the stress
 * tensors of the tets around v averaged by rest volume (stress.c); 0 at a vertex in no tet. */
int rk_fem_principal_stress(const rk_fem *f, const double *x, double *out, rk_error *err);
/* The Cauchy stress sigma = P F^T / J (row-major, symmetrized) of a material at deformation
 * gradient F (rk_pk1), and a symmetric 3 x 3 tensor's largest eigenvalue. */
void rk_cauchy_stress(rk_material_model model, double mu, double lambda, const double F[9], double s[9]);
double rk_largest_principal(const double s[9]);

/* ==== quadratic (P2, 10-node) tets: converged references (p2.c, p2_elastic.c) ====
 * Where P1 cannot converge at a size this machine runs (the freeform beam at nu = 0.45 locks in
 * bending: issue 37), the same mesh with a node on every edge. Static, small-strain linear
 * elasticity (p2.c: the reference a reduced model's static sag is measured against), and the
 * nonlinear element and mass of the dynamic reference (p2_elastic.c; precompute/fom's p2_fom.c). */
#define RK_P2_MAX_NODES 200000000
typedef struct {
    int nn, nt, nv;  /* nodes: the mesh's nv vertices first (same numbering), then one per edge */
    double *X;       /* 3 nn rest positions (edge nodes at the midpoints) */
    int *elem;       /* 10 nt: the tet's four vertices, then its edges 01 02 03 12 13 23 */
} rk_p2_mesh;
/* The six edges of a tet in rk_p2_mesh's node order: node 4 + k sits on RK_P2_EDGE[k]'s two vertices. */
extern const int RK_P2_EDGE[6][2];
int rk_p2_mesh_init(rk_p2_mesh *p, const rk_mesh *m, rk_error *err);
void rk_p2_mesh_free(rk_p2_mesh *p);
/* u (3 nn) solving K u = f for the body force `body` (N/m^3: rho g) with u = u_fixed (3 nn, NULL:
 * 0) at every node where fixed[node] is set; one material. Fails naming a singular stiffness. */
int rk_p2_static_linear(const rk_p2_mesh *p, double young, double poisson, const double body[3],
                        const unsigned char *fixed, const double *u_fixed, double *u, rk_error *err);
/* The upper-triangle pattern of a P2 matrix over the free dofs (free_of[3 node + c] >= 0: the
 * dof's index among nfree; < 0: prescribed, left out), and Ke (30 x 30, row-major over the
 * element's nodes' dofs) times scale added into S at the free dofs of nodes. */
int rk_p2_pattern(const rk_p2_mesh *p, const int *free_of, int nfree, rk_sparse *S, rk_error *err);
int rk_p2_slot(const rk_sparse *S, int row, int col);
void rk_p2_scatter(rk_sparse *S, const int *free_of, const int nodes[10], const double Ke[900], double scale);
/* The nonlinear element (p2_elastic.c): the barycentric gradients dL (4 x 3) from P1's Dm^-1; the
 * elastic energy of a P2 tet of rest volume vol with node displacements u (30), its gradient g (30,
 * written; NULL: none) and Hessian H (30 x 30, written; NULL: none; PSD-projected per quadrature
 * point as rk_dpdf when project); and its exact consistent mass (10 x 10 over nodes, kg). */
void rk_p2_barycentric_gradients(const double Dm_inv[9], double dL[12]);
double rk_p2_element_elastic(rk_material_model model, double mu, double lambda, const double dL[12], double vol,
                             const double u[30], double g[30], double H[900], int project);
void rk_p2_mass_element(double vol, double density, double Me[100]);

/* Index in val of the diagonal-block entry (3v + i, 3v + j), i <= j: the diagonal block closes
 * every column of the vertex (rows are sorted and the column ends at its diagonal). */
static inline int rk_fem_diag_slot(const rk_sparse *S, int v, int i, int j)
{
    return S->colptr[3 * v + j + 1] - 1 - (j - i);
}

/* rk_sparse and plain vectors seen by CHOLMOD without copying: the one place that knows how an
 * upper-triangle CSC rk_sparse maps onto cholmod_sparse (stype = 1). Used by the full-order
 * Newton solver and the shift-invert eigensolver. */
static inline void rk_cholmod_sparse_view(const rk_sparse *S, cholmod_sparse *A)
{
    memset(A, 0, sizeof *A);
    A->nrow = A->ncol = (size_t)S->n;
    A->nzmax = (size_t)S->nnz;
    A->p = S->colptr;
    A->i = S->rowind;
    A->x = S->val;
    A->stype = 1; /* upper triangle stored */
    A->itype = CHOLMOD_INT;
    A->xtype = CHOLMOD_REAL;
    A->dtype = CHOLMOD_DOUBLE;
    A->sorted = 1;
    A->packed = 1;
}

static inline void rk_cholmod_dense_view(const double *x, int n, cholmod_dense *B)
{
    memset(B, 0, sizeof *B);
    B->nrow = B->d = B->nzmax = (size_t)n;
    B->ncol = 1;
    B->x = (void *)x;
    B->xtype = CHOLMOD_REAL;
    B->dtype = CHOLMOD_DOUBLE;
}

/* ==== the one sparse Cholesky (cholesky.c) ====
 *
 * CHOLMOD with one policy for every caller (the full-order Newton solver, the shift-invert
 * eigensolver and the modal derivatives): supernodal LL^T, ordered by AMD and by nested dissection
 * with the sparser factor kept, analysed once per pattern; numeric refactorizations into the same
 * factor; solves that reuse their workspaces; OpenBLAS threads only from RK_CHOL_THREADED_FLOPS on
 * (cholesky.c says why, with the measurements). A matrix found not positive definite is reported
 * (RK_CHOL_NOT_POSDEF, with a message) and the caller chooses: project and retry, fail, or factor
 * it as LDL^T (rk_chol_indefinite). The matrix is the caller's, wrapped without a copy. */

/* CHOLMOD's flop count from which the factorization and the solves get rk_threads() threads. */
#define RK_CHOL_THREADED_FLOPS 1e10
/* rk_chol_factor's result for a matrix that is not positive definite. */
#define RK_CHOL_NOT_POSDEF 1

typedef struct {
    cholmod_common cc;
    int started;
    const rk_sparse *S;     /* the caller's matrix (values read at each factorization) */
    cholmod_sparse A;       /* its view */
    cholmod_factor *L;
    cholmod_dense *sol, *Y, *E; /* cholmod_solve2's workspaces */
    int n, blas_threads, indefinite;
} rk_chol;

/* The symbolic analysis of S's pattern: the first call, on a zeroed c, starts CHOLMOD; a later
 * one (the pattern changed) analyses again. S must outlive c. */
int rk_chol_analyze(rk_chol *c, const rk_sparse *S, rk_error *err);
/* The numeric factorization of S's current values: 0, -1 on failure, RK_CHOL_NOT_POSDEF (with a
 * message naming the column) when S is not positive definite and c is not indefinite. */
int rk_chol_factor(rk_chol *c, rk_error *err);
/* From now on LDL^T (simplicial): analyses and factors S again. For a matrix known indefinite. */
int rk_chol_indefinite(rk_chol *c, rk_error *err);
/* x = S^{-1} b (x and b may alias). */
int rk_chol_solve(rk_chol *c, const double *b, double *x, rk_error *err);
/* The factor's pivot-ratio condition estimate (cholmod_rcond); 0 without a factor. */
double rk_chol_rcond(rk_chol *c);
/* Where the last factorization stopped (n when it completed). */
int rk_chol_minor(const rk_chol *c);
void rk_chol_free(rk_chol *c);

/* ==== one tet's 12 local dofs (a0 a1 a2 b0 ... d2) and the global vectors and matrices ==== */

/* Number of upper-triangle entries of a 12x12 element block (the slot map's stride). */
#define RK_TET_SLOTS 78

/* xe = the 12 coordinates of tet t's vertices taken from x (3*nv). */
static inline void rk_fem_gather(const rk_fem *f, int t, const double *x, double xe[12])
{
    const int *v = &f->tets[4 * t];
    for (int a = 0; a < 4; a++) {
        const double *p = &x[3 * v[a]];
        xe[3 * a] = p[0];
        xe[3 * a + 1] = p[1];
        xe[3 * a + 2] = p[2];
    }
}

/* g[dof] += scale * ge[local dof] for tet t. */
static inline void rk_fem_scatter_vector(const rk_fem *f, int t, const double ge[12], double scale,
                                         double *g)
{
    const int *v = &f->tets[4 * t];
    for (int a = 0; a < 4; a++) {
        double *p = &g[3 * v[a]];
        p[0] += scale * ge[3 * a];
        p[1] += scale * ge[3 * a + 1];
        p[2] += scale * ge[3 * a + 2];
    }
}

/* val[slot] += scale * He for the 78 upper entries (p <= q, row-major) of tet t's symmetric
 * 12x12 block He (row-major). */
static inline void rk_fem_scatter_block(const rk_fem *f, int t, const double He[144], double scale,
                                        double *val)
{
    const int *s = &f->slot[RK_TET_SLOTS * t];
    for (int p = 0; p < 12; p++)
        for (int q = p; q < 12; q++) val[*s++] += scale * He[12 * p + q];
}

#endif
