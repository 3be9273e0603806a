/* precompute/basis: reduced bases, one interface for all of them. A basis is a 3n x r matrix U
 * (column-major, n = the vertices it is evaluated at) whose span is what a reduced model can
 * express, plus the eigenvalues or singular values that produced it. Skinning bases also keep
 * their scalar weights W (n x m) and build U from them by linear blend skinning (12 columns per
 * weight: the 3x4 affine handle Z_j of Eq. 1 of the freeform paper).
 *
 *   modes              K v = lambda M v over the free dofs (ARPACK shift-invert, eigen.c)
 *   modal_derivatives  linear modes plus Barbic & James 2005 derivatives, mass-PCA'd
 *   skinning           mesh skinning eigenmodes (Benchekroun et al. 2023): H_w v = lambda M_w v
 *   rkpm_skinning      the same on RKPM kernels, mesh-free (freeform paper Sec. 3.2)
 *   pod                mass-weighted SVD of full-order snapshot displacements */
#ifndef RK_BASIS_H
#define RK_BASIS_H

#include "fem/fem.h"
#include "mesh/mesh.h"
#include "util/util.h"

/* ==== RKPM: mesh-free reproducing-kernel shape functions, the discretization of the freeform
 * paper's RKPM skinning eigenmodes (Sec. 3.2, Eq. 6-17; construction in Sec. 7.1).
 *
 *   integration points   rk_rkpm_sample_mesh (a uniform grid clipped to a tet mesh) or
 *                        rk_rkpm_sample_cloud (a point cloud such as Gaussian-splat centres)
 *   kernel centres       rk_fps: farthest point sampling among the integration points
 *   kernels              rk_rkpm_init: tapered Gaussians, radius = distance to the 2nd nearest centre
 *   shape functions      rk_rkpm_eval: linearly corrected kernels phi_k (Eq. 7-11) and their gradients
 *   matrices             rk_rkpm_assemble: the weight-space Hessian H_w (Prop. 1) and the RKPM
 *                        mass (Eq. 14) for the eigenproblem H_w v = lambda M v (Eq. 15)
 *
 * Everything is deterministic: the same inputs give bit-identical outputs (fixed orders, no
 * randomness); the dense products in rk_rkpm_assemble go through OpenBLAS. */

/* ---- integration points ---------------------------------------------------------------- */

typedef struct {
    int n;
    double *X;       /* 3n positions */
    double *weight;  /* n integration weights (m^3); they sum to about the object's volume */
    int *tet;        /* rk_rkpm_sample_mesh: n containing tets (for per-element materials); else NULL */
    int *source;     /* rk_rkpm_sample_cloud: n indices into the input cloud; else NULL */
    double spacing;  /* mesh: the grid cell's edge (geometric mean); cloud: the voxel size of the volume estimate */
    double volume;   /* mesh: the sum of |tet volumes|; cloud: the occupancy volume estimate */
} rk_rkpm_points;

/* A uniform grid whose cells tile the mesh's bounding box (ceil(extent / s) cells per axis, s =
 * cbrt(mesh volume / target), a point at each cell's centre), keeping the grid points inside the
 * mesh (Sec. 7.1). Each tet's bounding box is rasterized onto the grid and its points tested by
 * barycentric coordinates (tolerance 1e-9), so a point on a shared face is kept once, in the
 * containing tet of lowest index (recorded in p->tet). Every weight is its cell's volume. Points
 * are ordered by grid index (x fastest). Fails when no grid point falls inside (a mesh thinner
 * than s everywhere). On failure *p is empty. */
int rk_rkpm_sample_mesh(const rk_mesh *m, int target, rk_rkpm_points *p, rk_error *err);

/* count points uniformly random inside the mesh (tets picked by volume, uniform within each;
 * splitmix64 from seed: the same seed, the same points), each weighted volume / count: the
 * "random" sampling of the freeform paper's Table 4. p->tet holds each point's tet. */
int rk_rkpm_sample_mesh_random(const rk_mesh *m, int count, unsigned long long seed, rk_rkpm_points *p, rk_error *err);

/* The cloud's points (3n coordinates) used directly as integration points (Sec. 7.1, "for 3DGS").
 * When n > max_points, a deterministic voxel-grid downsampling keeps the lowest-index point of
 * each occupied voxel, with the voxel size bisected so that at most max_points remain (as many
 * as the bisection finds). Weights are uniform, volume / count, where the volume is an occupancy
 * estimate over all n input points (so it does not depend on max_points): g = 2 x their median
 * nearest-neighbour distance (zeros ignored); volume = (number of voxels of edge g holding a point)
 * x g^3. A voxel twice the typical spacing is almost always occupied inside a sampled region yet
 * rarely bridges a gap, so the estimate follows the sampled region and overshoots by at most about
 * half a voxel layer along its boundary. Caveat: Gaussian-splat centres mostly sit near the
 * surface, so for splats this is the volume of a thick shell, not of the enclosed solid (a uniform
 * scale of all weights leaves the eigenvectors and eigenvalues of H_w v = lambda M v unchanged).
 * Non-finite coordinates fail, naming the point. Needs at least 4 points, not all coincident.
 * On failure *p is empty. */
int rk_rkpm_sample_cloud(const double *X, int n, int max_points, rk_rkpm_points *p, rk_error *err);

void rk_rkpm_points_free(rk_rkpm_points *p);

/* Farthest point sampling: chosen[K] indices into X (3n coordinates). The first is the point
 * farthest from the centroid; each next one maximizes the distance to those already chosen;
 * ties go to the lowest index. Fails when K > n, when fewer than K points are distinct, or on a
 * non-finite coordinate (named). */
int rk_fps(const double *X, int n, int K, int *chosen, rk_error *err);

/* ---- kernels and shape functions ------------------------------------------------------- */

/* Kernels g_k(X) = exp(-|X - p_k|^2 / r_k^2) (the paper's Gaussian varphi_k, Sec. 3.2) times a
 * C^2 taper S(t), t = (d - A r_k) / ((B - A) r_k) clamped to [0, 1],
 * S = 1 - (10 t^3 - 15 t^4 + 6 t^5), A = RK_RKPM_TAPER_START, B = RK_RKPM_TAPER_END: kernel k
 * is non-zero exactly for d = |X - p_k| < B r_k (its support; X is then "covered" by k).
 * Why: a Gaussian never vanishes, and compact support is what makes H_w and M sparse and each
 * evaluation cheap; S is C^2, so the gradients stay continuous; and the Gaussian is already
 * exp(-6.25) = 1.9e-3 at 2.5 r, so the taper barely changes its shape.
 * r_k = the distance from p_k to its 2nd nearest other centre ("the minimal distance to reach two
 * other centers", Sec. 7.1). */
#define RK_RKPM_TAPER_START 2.5
#define RK_RKPM_TAPER_END 3.5
/* A point is rejected (too sparse) when the moment matrix M(X) of Eq. 10, in the scaled local
 * basis below, has a reciprocal 1-norm condition number below this. */
#define RK_RKPM_MIN_RCOND 1e-12
/* Tolerant interpolation (rk_rkpm_interpolate with `regularized`): below this reciprocal
 * condition number, the linear block of M(X) gets RK_RKPM_REGULARIZE * M_00 added to its
 * diagonal instead of failing. */
#define RK_RKPM_REGULARIZE_RCOND 1e-6
#define RK_RKPM_REGULARIZE 1e-4

/* Private: a uniform grid of cells over a point set (counting-sorted). */
typedef struct {
    double origin[3];
    double h;         /* cell edge */
    int dim[3];
    int *start;       /* dim[0]*dim[1]*dim[2] + 1 */
    int *item;        /* point indices, cell by cell, ascending within a cell */
} rk_rkpm_grid;

/* The clamp mask (rk_rkpm_set_clamp, rkpm_clamp.c): the fixed region as simplices of a mesh, or
 * as balls around the fixed points of a cloud. */
typedef struct {
    int n;            /* fixed points; 0: no mask */
    double *X;        /* 3n positions */
    double *reach;    /* n ball radii rho_i (all 0 when the region comes from tets) */
    int ntri, ntet;   /* the mesh's triangles and tets with every vertex fixed (0 without a mesh) */
    double *tri;      /* 9 ntri corner coordinates */
    double *tet;      /* 12 ntet corner coordinates */
    double *centre;   /* 3 (n + ntri + ntet): each piece's centre (points, triangles, tets), hashed */
    double extent;    /* the largest distance from a piece's centre to its farthest point */
    double rise;      /* the mask rises from 0 to 1 over this distance from the region */
    rk_rkpm_grid hash; /* private: the pieces' centres hashed */
} rk_rkpm_clamp;

/* A lifting field (rkpm_lift.c, rom.clamp "lifted"): w_L = d_0 / (d_0 + d_1), d_0 and d_1 the
 * distances to the region held still (the fixed groups) and to the moving prescribed region, so
 * w_L = 0 exactly on the first, 1 exactly on the second, between them the relative distance (a
 * bar's linear ramp). It carries the moving region's prescribed motion into the body. */
typedef struct {
    rk_rkpm_clamp zero, one; /* the regions where w_L is 0 (none: w_L = 1 everywhere) and 1 */
    double range;            /* farther than any distance asked for (twice the points' bounding box) */
} rk_lift;

typedef struct {
    int K;
    double *centers;  /* 3K kernel centres p_k (a copy) */
    double *radius;   /* K Gaussian radii r_k */
    double *support;  /* K support radii RK_RKPM_TAPER_END * r_k */
    double max_support_radius;
    int max_support;  /* upper bound on the kernels covering any point (rk_rkpm_max_support) */
    rk_rkpm_grid hash; /* private: the centres hashed with cells of about max_support_radius */
    rk_rkpm_clamp clamp; /* clamp.n > 0: every shape function is masked, d(X) phi_k (rk_rkpm_set_clamp) */
    int lift_column;     /* 1 + the column of c that rk_rkpm_interpolate adds the lift to; 0: none */
    rk_lift lift;
} rk_rkpm;

/* Copies the K centres (3K coordinates), computes the radii and the spatial hash. Needs K >= 4
 * finite, pairwise distinct centres (coincident ones are named). On failure *k is empty. */
int rk_rkpm_init(rk_rkpm *k, const double *centers, int K, rk_error *err);
void rk_rkpm_free(rk_rkpm *k);

/* Clamps the shape functions to a fixed region (essential boundary conditions by Kantorovich /
 * R-function weighting, rkpm_clamp.c): from now on rk_rkpm_eval, rk_rkpm_interpolate and
 * rk_rkpm_assemble give d(X) phi_k(X) and its gradient (product rule), d = 0 on the region
 * (exactly 0 at its points, so every weight vanishes there) and 1 beyond `rise` from it. The
 * region: the n points X (3n) flagged in fixed, with the tets (4 nt indices into X, or NULL)
 * whose vertices are all fixed and their triangles; without tets, balls around the fixed points
 * bounded by the free ones. No fixed point: no mask. Fails when every point is fixed. Masked
 * functions no longer reproduce constants or linear fields (the clamp forbids those motions). */
int rk_rkpm_set_clamp(rk_rkpm *k, const double *X, int n, const unsigned char *fixed, const int *tets, int nt,
                      double rise, rk_error *err);
/* The lifting field w_L of the n points X (3n) between the region flagged in zero (may be NULL or
 * empty: w_L = 1 everywhere) and the one flagged in one (regions as rk_rkpm_set_clamp builds them:
 * with tets, their simplices; without, balls). Fails, naming the point, when a point is in both,
 * and when no point is in `one`. */
int rk_lift_init(rk_lift *L, const double *X, int n, const unsigned char *zero, const unsigned char *one,
                 const int *tets, int nt, rk_error *err);
/* w_L at X and its gradient grad[3]. */
double rk_lift_at(const rk_lift *L, const double X[3], double grad[3]);
void rk_lift_free(rk_lift *L);
/* From now on rk_rkpm_interpolate adds w_L (and its gradient) to column `column` of what it
 * evaluates (whose nodal values the caller keeps at 0): the lifting handle of a skinning basis.
 * Takes L over (also on failure). */
int rk_rkpm_set_lift(rk_rkpm *k, rk_lift *L, int column, rk_error *err);

/* The rise of the mask in kernel radii (their mean): measured on the beam of
 * tests/unit/test_pipeline_meshfree_beam.c (rkpm_clamp.c). */
#define RK_RKPM_CLAMP_RISE 2.0

/* An upper bound on the number of kernels covering any one point, for sizing the buffers of
 * rk_rkpm_eval: max over k of #{l : |p_k - p_l| < R_k + R_l} (R = support radius). */
int rk_rkpm_max_support(const rk_rkpm *k);

/* The shape functions (Eq. 7-11) non-zero at X: returns their count n (or -1 with err);
 * idx[n] kernel indices (ascending), phi[n] the values phi_k(X), grad[3n] (may be NULL) their
 * gradients (x, y, z per kernel). cap is the room in the buffers (rk_rkpm_max_support always
 * suffices). Linear completeness: sum phi_k = 1, sum phi_k p_k = X, sum grad phi_k = 0,
 * sum p_k grad phi_k^T = I, to roundoff.
 * Numerics: the basis P(X) = [1, x, y, z] is replaced by the shifted and scaled
 * Q_k = [1, (p_k - X)/h] (h: the kernels' weighted mean radius), which spans the same linear
 * functions and keeps M(X) well conditioned; then C(X) = M^-1 e_1 and phi_k = g_k Q_k^T C.
 * Gradients are analytic (derivation in rkpm_shape.c).
 * Fails, saying the point cloud is too sparse for its kernels, when fewer than 4 kernels cover X
 * or when M(X) is singular or ill-conditioned (coplanar kernels; RK_RKPM_MIN_RCOND). */
int rk_rkpm_eval(const rk_rkpm *k, const double X[3], int cap, int *idx, double *phi, double *grad,
                 rk_error *err);

/* W (n x m, column-major) = sum_k phi_k(X_i) c_k (Eq. 6) for nodal values c (K x m,
 * column-major) at the n points X (3n): skinning weights wherever they are needed. A point that
 * fails (non-finite, or too sparsely covered) is named by its index. regularized NULL: strict,
 * like rk_rkpm_eval. Otherwise tolerant: a point covered by at least one kernel whose moment
 * matrix is (nearly) singular (a mesh vertex at the tip of a feature thinner than the kernel
 * spacing) is evaluated with the damped moment matrix (constants still exact, see
 * rkpm_shape.c) and counted in *regularized; only a point no kernel covers fails.
 * dW (may be NULL): the analytic gradients, 3n x m column-major: dW[3 i + b + 3 n j] = d W^j/dX_b
 * at point i. */
int rk_rkpm_interpolate(const rk_rkpm *k, const double *X, int n, const double *c, int m, double *W,
                        double *dW, int *regularized, rk_error *err);

/* ---- matrices -------------------------------------------------------------------------- */

/* Assembles, over the n integration points X (3n) with weights v (n) and coefficients coef (n),
 *   H[k][l] = sum_i v_i coef_i grad phi_k(X_i) . grad phi_l(X_i)   (Prop. 1 / Eq. 17: coef = lambda + 4 mu)
 *   M[k][l] = sum_i v_i phi_k(X_i) phi_l(X_i)                      (Eq. 14)
 * as K x K symmetric rk_sparse matrices (upper triangle, CSC, sorted rows, CHOLMOD stype = 1)
 * with one pattern: every pair of kernels that both cover some integration point, plus the
 * diagonal. The caller computes coef_i = lambda(X_i) + 4 mu(X_i) (heterogeneous materials).
 * v and coef must be finite and >= 0 (the point is named otherwise); every kernel must cover at
 * least one integration point (else M would be singular; the kernel is named). H and M are
 * allocated here (free with rk_sparse_free); on failure both are empty. regularized: NULL for
 * strict evaluation, else tolerant as in rk_rkpm_interpolate (points in features thinner than
 * the kernel spacing are damped and counted). */
int rk_rkpm_assemble(const rk_rkpm *k, const double *X, const double *v, const double *coef, int n,
                     rk_sparse *H, rk_sparse *M, int *regularized, rk_error *err);

/* ==== bases ==================================================================================== */

typedef enum {
    RK_BASIS_MODES = 0,
    RK_BASIS_MODAL_DERIVATIVES = 1,
    RK_BASIS_SKINNING = 2,
    RK_BASIS_RKPM_SKINNING = 3,
    RK_BASIS_POD = 4
} rk_basis_type;

const char *rk_basis_type_name(rk_basis_type t);
/* -1 when the name is not one of the five. */
int rk_basis_type_parse(const char *name, rk_basis_type *t);

/* What a scene's rom entry asks of the basis (its keys: basis, size, tolerance, modes, kernels,
 * integration_points). */
typedef struct {
    rk_basis_type type;
    int size;               /* columns (modes, modal_derivatives, pod) or weights m (skinning); 0: by tolerance */
    double tolerance;       /* relative M-norm projection error of the scene's full-order frames; 0: by size */
    int modes;              /* modal_derivatives: linear modes to differentiate (0: automatic) */
    int kernels;            /* rkpm_skinning: kernel centres (default 1000, Sec. 7.1) */
    int integration_points; /* rkpm_skinning: grid points inside a mesh, or the cloud's cap (default 40000) */
    int from_vertices;      /* rkpm_skinning on a mesh: its vertices taken as a point cloud (no tet used), as a
                             * cloud sampled from the mesh would be */
    int clamp_penalty;      /* rom.clamp "penalty": skinning weights free on the fixed region, which the reduced
                             * model holds by its penalty alone (before issue 37); default 0, "dirichlet": the
                             * weights vanish there (rk_basis_skinning, rk_basis_rkpm_skinning) */
    int clamp_lifted;       /* rom.clamp "lifted": the fixed groups clamped as "dirichlet", and the one moving
                             * group held exactly too, by a lifting handle (rk_basis_rkpm_skinning_lifted) */
} rk_basis_options;

/* Defaults: no type chosen, size and tolerance 0, 1000 kernels, 40000 integration points. */
void rk_basis_default_options(rk_basis_options *o);
/* Whether building this basis needs full-order frames (POD, or a size by tolerance). */
int rk_basis_needs_frames(const rk_basis_options *o);

typedef struct rk_basis {
    rk_basis_type type;
    int n;           /* vertices */
    int r;           /* columns of U */
    double *U;       /* 3n x r, column-major; zero rows at constrained vertices for modes */
    /* modes, modal derivatives: the eigenvalues of K v = lambda M v (ascending, nvalues of them);
     * skinning: the weight-space eigenvalues of H_w v = lambda M v (the constant mode's first);
     * pod: the mass-weighted singular values (descending). */
    int nvalues;
    double *values;
    /* How many leading eigenvalues are zero up to roundoff: the rigid modes of a free object
     * (six per free piece), or the constant weight of a skinning basis. */
    int nzero;
    /* skinning bases: m weights (the constant one first), W is n x m column-major. */
    int m;
    double *W;
    /* rkpm_skinning: the kernels and their nodal values C (K x m), so weights can be
     * evaluated anywhere later (rk_rkpm_interpolate): cubature points, splat centres. */
    rk_rkpm *rkpm;
    double *C;
    int damped_points; /* integration and evaluation points in features thinner than the kernel
                        * spacing, where the weights reproduce constants but not every linear
                        * field (the RKPM section above, tolerant evaluation) */
    /* Several objects (rk_basis_join): each its own skinning basis over its own vertices, their
     * handles one after another (an object's weights are zero on every other object); the parts
     * keep their kernels for evaluation elsewhere. nparts = 0 for one object. */
    /* rom.clamp "lifted" (rkpm_lift.c): 1 + the handle whose weight is the lifting field w_L
     * (the last one; its 12 coordinates are the moving region's prescribed motion, not unknowns);
     * 0: none */
    int lift_handle;
    int nparts;
    struct rk_basis *part;     /* nparts, each over its object's vertices */
    int *part_vertex;          /* nparts + 1: the first vertex of each part */
    int *part_handle;          /* nparts + 1: its first weight */
} rk_basis;

/* Joins the skinning bases of nparts objects (part k over the nv vertices from first_vertex[k] to
 * first_vertex[k + 1]) into one over all nv (X: their rest positions): W block-diagonal, U its
 * linear blend skinning, values and zero counts one after another. Takes the parts over (array and
 * all, also on failure). */
int rk_basis_join(rk_basis *parts, int nparts, const int *first_vertex, const double *X, int nv, rk_basis *out,
                  rk_error *err);

void rk_basis_free(rk_basis *b);

/* Linear modes (count of them) over the free dofs; constrained: nv flags or NULL. U has zero
 * rows at constrained vertices and is M-orthonormal. */
int rk_basis_modes(const rk_fem *f, const unsigned char *constrained, int lumped, int count,
                   rk_basis *b, rk_error *err);

/* Modal derivatives (Barbic & James 2005): k linear modes psi_i (k = nmodes, or 0 to pick the
 * smallest k whose modes and derivatives number 1.5 (r - rigid)), the derivatives
 * K Psi_ij = -(H : psi_i) psi_j for i <= j over the free dofs, then the rigid modes (free
 * objects) followed by the mass-PCA of the scaled set {lambda_1/lambda_i psi_i,
 * lambda_1^2/(lambda_i lambda_j) Psi_ij} down to r columns. values: the k (+ rigid) linear
 * eigenvalues. */
int rk_basis_modal_derivatives(const rk_fem *f, const unsigned char *constrained, int lumped,
                               int r, int nmodes, rk_basis *b, rk_error *err);

/* The raw derivatives of the `k` modes in U (ndof x k, the first `nrigid` rigid and skipped):
 * Psi (ndof x npairs, pairs (i <= j) of non-rigid modes in row-major order) and the largest
 * relative residual |K Psi - rhs| / |rhs| of their equations. */
int rk_modal_derivatives(const rk_fem *f, const unsigned char *constrained, int lumped,
                         const double *U, int k, int nrigid, double *Psi, double *residual,
                         rk_error *err);

/* out = (H : a) b, the derivative of the tangent stiffness along displacement a applied to b
 * (3 nv vectors): per element, Richardson-extrapolated central differences of the element
 * Hessian (error O(eps^4), eps scaled to 1e-3 of the element size). */
void rk_stiffness_derivative(const rk_fem *f, const double *a, const double *b, double *out);

/* Skinning eigenmodes on a mesh (Benchekroun et al. 2023): the weight-space Hessian
 * H_w = K_xx + K_yy + K_zz of the rest stiffness (= the integral of (lambda + 4 mu) grad w . grad w,
 * freeform paper Prop. 1, for P1 weights) and the scalar mass M_w (consistent or lumped);
 * m + 1 weights (the constant one first, not counted in m, as in the paper), U = 12 (m + 1)
 * LBS columns. fixed (nv flags, or NULL / none set): a clamp, the fixed vertices a Dirichlet
 * boundary: H_w v = lambda M_w v over the free vertices only, the weights exactly 0 at every fixed
 * vertex; there is no constant weight then (it would move the clamp), so the m + 1 weights are
 * all eigen-weights of the clamped problem (r stays 12 (m + 1)), and a fixed vertex gets a zero
 * row of U (a reduced model holds it without a penalty). */
int rk_basis_skinning(const rk_fem *f, const unsigned char *fixed, int lumped, int m, rk_basis *b, rk_error *err);
/* The same for a mesh of nparts objects (vertices first_vertex[k] to first_vertex[k + 1] - 1 are
 * object k's, no tet joins two): each object's own m + 1 weights, from the pencil restricted to its
 * vertices (free, or clamped where it has fixed ones), side by side (rk_basis_join): a disconnected
 * body has no single constant weight, and one eigenproblem over all of them would hand the weights
 * to whichever piece is softest. */
int rk_basis_skinning_objects(const rk_fem *f, const unsigned char *fixed, int lumped, int m, const int *first_vertex,
                              int nparts, rk_basis *b, rk_error *err);

/* Seconds spent in each part of an RKPM skinning build (for make bench). */
typedef struct {
    double fps, kernels, assemble, eigs, evaluate;
} rk_rkpm_timing;

/* RKPM skinning eigenmodes (freeform paper Sec. 3.2, 7.1): `kernels` centres by farthest point
 * sampling of the integration points, H_w (Prop. 1, coef = lambda + 4 mu per point) and the RKPM
 * mass (Eq. 14), the m + 1 smallest generalized eigenvectors (Eq. 15) as nodal values, the
 * weights interpolated at the n points Xeval (mesh vertices, splat centres) and LBS columns
 * there. fixed (n flags over Xeval, or NULL / none set): a clamp, as in rk_basis_skinning, by
 * masking the shape functions (rk_rkpm_set_clamp with the tets over Xeval, or NULL for a cloud;
 * rise RK_RKPM_CLAMP_RISE mean kernel radii):
 * the m + 1 weights all vanish at the fixed points (exactly) and on the region between them, and
 * the mask stays with b->rkpm, so weights evaluated later anywhere are the same functions.
 * Kernels the mask leaves without mass (inside the region) get nodal values 0. timing may be
 * NULL. */
int rk_basis_rkpm_skinning(const rk_rkpm_points *pts, const double *coef, int kernels, int m,
                           const double *Xeval, int n, const unsigned char *fixed, const int *tets, int nt,
                           rk_basis *b, rk_rkpm_timing *timing, rk_error *err);
/* The same with a moving prescribed region (moving: n flags over Xeval; rom.clamp "lifted"): the
 * mask covers the fixed and the moving points, so the m + 1 eigen-weights vanish on both, and
 * one more weight, the lifting field w_L of rkpm_lift.c (1 on the moving points, 0 on the fixed
 * ones), is appended as handle m + 2 (b->lift_handle; its nodal values 0, b->rkpm adds w_L
 * wherever weights are evaluated): b->m = m + 2, r = 12 (m + 2), 12 (m + 1) of them free. Needs
 * the tets (the regions are their simplices). */
int rk_basis_rkpm_skinning_lifted(const rk_rkpm_points *pts, const double *coef, int kernels, int m,
                                  const double *Xeval, int n, const unsigned char *fixed, const unsigned char *moving,
                                  const int *tets, int nt, rk_basis *b, rk_rkpm_timing *timing, rk_error *err);

/* POD: the r leading mass-weighted left singular vectors of snapshot displacements D (3n x T,
 * column-major: T frames one after another, the layout of a T x n x 3 array). M is the 3n x 3n
 * mass; with tol > 0 the smallest r <= max_r whose discarded energy is <= tol. */
int rk_basis_pod(const double *D, int n, int T, const rk_sparse *M, int max_r, double tol,
                 rk_basis *b, rk_error *err);

/* --- building blocks, each in its own file --- */

/* Smallest `count` eigenpairs of the symmetric pencil (A, B), B positive definite, both upper
 * CSC of the same size, by ARPACK shift-invert (mode 3) around sigma with a CHOLMOD
 * factorization of A - sigma B (LL^T, or LDL^T when that is indefinite). sigma = NAN picks
 * -1e-6 tr(A)/tr(B): below every eigenvalue of a semi-definite A, so singular problems (free
 * objects, the constant weight) work. values ascending; vectors (n x count, column-major,
 * may be NULL) B-orthonormal. */
int rk_eigs_smallest(const rk_sparse *A, const rk_sparse *B, int count, double sigma,
                     double *values, double *vectors, rk_error *err);

/* Keeps the rows and columns i with keep[i] >= 0, renumbered to keep[i]. */
/* How many of the ascending eigenvalues are zero up to roundoff, relative to the spectral
 * scale tr(A)/tr(B) of the pencil they came from. */
int rk_count_zero_eigenvalues(const double *values, int count, double scale);

int rk_sparse_restrict(const rk_sparse *S, const int *keep, int nkeep, rk_sparse *out, rk_error *err);

/* x^T M y over n entries (M NULL: the plain dot product). */
double rk_mass_dot(const rk_sparse *M, const double *x, const double *y, int n);

/* Mass-weighted PCA / SVD of the columns of A (rows x cols, column-major) in the inner product
 * <a, b> = a^T M b (M NULL: identity; M with 3n rows for displacement fields). Returns up to
 * `max_r` M-orthonormal directions in U (rows x r) and the singular values sigma (descending,
 * all min(rows, cols) of them in sigma_all when not NULL). With tol > 0, r is the smallest
 * size whose discarded energy sqrt(sum_{i>r} s_i^2 / sum s_i^2) <= tol; *r_out gets r. */
int rk_mass_pca(const double *A, int rows, int cols, const rk_sparse *M, int max_r, double tol,
                double *U, int *r_out, double *sigma_all, rk_error *err);

/* The m + 1 smallest weight-space eigenpairs (H_w c = lambda M c, c^T M c = I): values and C
 * (size x (m+1)). Free (clamped = 0): fails, naming the count, when the constant mode is not
 * simple (the object falls into several disconnected pieces). Clamped (the pencil restricted or
 * masked to vanish on a fixed region): fails when any eigenvalue is zero (a piece with no fixed
 * point). Both fail when m + 1 >= size. */
int rk_weight_eigs(const rk_sparse *Hw, const rk_sparse *Mw, int m, int clamped, double *values, double *C,
                   int *nzero, rk_error *err);
/* rk_weight_eigs over the unknowns keep[c] >= 0 of the pencil (nkept of them, numbered by keep),
 * expanded into C (n x (m + 1)) with zeros at the others: with clamped set, the Dirichlet clamp of
 * mesh skinning (fixed vertices) and RKPM skinning (masked-out kernels); free, one object of
 * several (its own vertices: the constant weight of that piece alone). */
int rk_weight_eigs_restricted(const rk_sparse *Hw, const rk_sparse *Mw, const int *keep, int nkept, int m,
                              int clamped, double *values, double *C, int *nzero, rk_error *err);

/* Relative M-norm error of projecting the T frames D (3n x T) onto the span of U's first
 * columns, err[g] for the first (g + 1) * group columns, g < r / group: one pass of
 * M-Gram-Schmidt over U (columns that add nothing new are skipped). */
int rk_projection_errors(const double *U, int rows, int r, int group, const double *D, int T,
                         const rk_sparse *M, double *err_out, rk_error *err);

/* Keeps the first r columns (skinning: the first r / 12 weights and their values). */
void rk_basis_truncate(rk_basis *b, int r);

/* Weights (n x m) at rest positions X (3n) into the linear-blend-skinning basis U (3n x 12m):
 * column 12j + 4a + b moves coordinate a of vertex i by W[i, j] * Xbar_b, Xbar = (x, y, z, 1). */
void rk_skinning_to_U(const double *W, int n, int m, const double *X, double *U);

#endif
