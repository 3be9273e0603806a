/* precompute/basis/rkpm.h: mesh-free reproducing-kernel (RKPM) shape functions, the discretization
 * of the freeform paper's RKPM skinning eigenmodes (Sec. 3.2, Eq. 6-17; construction in Sec. 7.1).
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
#ifndef RK_RKPM_H
#define RK_RKPM_H

#include "fem/fem.h"
#include "mesh/mesh.h"
#include "util/error.h"

/* ---- integration points ---------------------------------------------------------------- */

typedef struct {
    int n;
    double *X;       /* 3n positions */
    double *weight;  /* n integration weights (m^3); they sum to about the object's volume */
    int *tet;        /* rk_rkpm_sample_mesh: n containing tets (for per-element materials); else NULL */
    int *source;     /* rk_rkpm_sample_cloud: n indices into the input cloud; else NULL */
    double spacing;  /* mesh: the grid spacing; cloud: the voxel size of the volume estimate */
    double volume;   /* mesh: the sum of |tet volumes|; cloud: the occupancy volume estimate */
} rk_rkpm_points;

/* A uniform grid of spacing s = cbrt(mesh volume / target), centred on the mesh's bounding box,
 * keeping the grid points inside the mesh (Sec. 7.1). Each tet's bounding box is rasterized onto
 * the grid and its points tested by barycentric coordinates (tolerance 1e-9), so a point on a
 * shared face is kept once, in the containing tet of lowest index (recorded in p->tet). Every
 * weight is s^3. Points are ordered by grid index (x fastest). Fails when no grid point falls
 * inside (a mesh thinner than s everywhere). On failure *p is empty. */
int rk_rkpm_sample_mesh(const rk_mesh *m, int target, rk_rkpm_points *p, rk_error *err);

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

typedef struct {
    int K;
    double *centers;  /* 3K kernel centres p_k (a copy) */
    double *radius;   /* K Gaussian radii r_k */
    double *support;  /* K support radii RK_RKPM_TAPER_END * r_k */
    double max_support_radius;
    int max_support;  /* upper bound on the kernels covering any point (rk_rkpm_max_support) */
    rk_rkpm_grid hash; /* private: the centres hashed with cells of about max_support_radius */
} rk_rkpm;

/* Copies the K centres (3K coordinates), computes the radii and the spatial hash. Needs K >= 4
 * finite, pairwise distinct centres (coincident ones are named). On failure *k is empty. */
int rk_rkpm_init(rk_rkpm *k, const double *centers, int K, rk_error *err);
void rk_rkpm_free(rk_rkpm *k);

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
 * rkpm_shape.c) and counted in *regularized; only a point no kernel covers fails. */
int rk_rkpm_interpolate(const rk_rkpm *k, const double *X, int n, const double *c, int m, double *W,
                        int *regularized, rk_error *err);

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

#endif
