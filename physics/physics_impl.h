/* physics_impl.h: every line of per-element physics, written once (see physics.h).
 *
 * The includer defines, before including:
 *   PHYS_REAL       the scalar type (float or double)
 *   PHYS_FN(name)   the public name of each function, e.g. rk_##name
 *   PHYS_FLOAT      (only when PHYS_REAL is float) selects sqrtf/fabsf and float epsilon
 * Optionally PHYS_API, the storage class of the public functions (default: none, external).
 *
 * There is deliberately NO include guard: a translation unit may include this file once per
 * precision (with a different PHYS_FN prefix each time; #undef PHYS_REAL, PHYS_FN and
 * PHYS_FLOAT in between). Helpers are static and named through PHYS_FN too, so two copies
 * never collide. Internal macros (PHYS_..._) are #undef'd at the end.
 *
 * Pure C99 (-std=c99 -pedantic), only <math.h> and <string.h>, no malloc, no global or static
 * mutable state. Conventions as in physics.h: F[3*i + j] = F_ij, dPdF[9*(3i+j) + (3k+l)] =
 * dP_ij/dF_kl, vec(M)[3*i + j] = M_ij, so "dP = dPdF vec(dF)". */

#if !defined(PHYS_REAL) || !defined(PHYS_FN)
#error "define PHYS_REAL and PHYS_FN(name) before including physics_impl.h"
#endif

#include <math.h>
#include <string.h>

#include "physics/physics.h" /* rk_material_model, shared by every precision */

#ifndef PHYS_API
#define PHYS_API
#define PHYS_API_DEFAULTED_
#endif

#define PHYS_K_(x) ((PHYS_REAL)(x)) /* a literal in the working precision (no double promotion) */
#ifdef PHYS_FLOAT
#define PHYS_SQRT_ sqrtf
#define PHYS_FABS_ fabsf
#define PHYS_LOG_ logf
#define PHYS_COS_ cosf
#define PHYS_SIN_ sinf
#define PHYS_ATAN2_ atan2f
#define PHYS_MATH_TYPE_ float
#define PHYS_EPS_ PHYS_K_(1.1920928955078125e-7) /* FLT_EPSILON */
#define PHYS_SQRT_EPS_ PHYS_K_(3.4526698e-4)
#else
#define PHYS_SQRT_ sqrt
#define PHYS_FABS_ fabs
#define PHYS_LOG_ log
#define PHYS_COS_ cos
#define PHYS_SIN_ sin
#define PHYS_ATAN2_ atan2
#define PHYS_MATH_TYPE_ double
#define PHYS_EPS_ PHYS_K_(2.220446049250313e-16) /* DBL_EPSILON */
#define PHYS_SQRT_EPS_ PHYS_K_(1.4901161193847656e-8)
#endif

/* Compile-time check that PHYS_FLOAT agrees with PHYS_REAL (a negative array size fails). */
typedef char PHYS_FN(precision_check_)[sizeof(PHYS_REAL) == sizeof(PHYS_MATH_TYPE_) ? 1 : -1];

/* Prototypes of the public functions (the double ones repeat physics.h). */
PHYS_API void PHYS_FN(lame)(PHYS_REAL young, PHYS_REAL poisson, PHYS_REAL *mu, PHYS_REAL *lambda);
PHYS_API PHYS_REAL PHYS_FN(psi)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda,
                                const PHYS_REAL F[9]);
PHYS_API void PHYS_FN(pk1)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda,
                           const PHYS_REAL F[9], PHYS_REAL P[9]);
PHYS_API PHYS_REAL PHYS_FN(psi_h)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda, const PHYS_REAL Hd[9]);
PHYS_API void PHYS_FN(pk1_h)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda, const PHYS_REAL Hd[9],
                             PHYS_REAL P[9]);
PHYS_API void PHYS_FN(dpdf)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda,
                            const PHYS_REAL F[9], PHYS_REAL dPdF[81], int project);
PHYS_API void PHYS_FN(dpdf_p)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda, PHYS_REAL pres,
                              const PHYS_REAL F[9], PHYS_REAL dPdF[81], int project);
PHYS_API PHYS_REAL PHYS_FN(volume_h)(rk_material_model model, const PHYS_REAL Hd[9], PHYS_REAL dtheta[9]);
PHYS_API void PHYS_FN(tet_F)(const PHYS_REAL x[12], const PHYS_REAL Dm_inv[9], PHYS_REAL F[9]);
PHYS_API PHYS_REAL PHYS_FN(tet_energy)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda,
                                       const PHYS_REAL x[12], const PHYS_REAL Dm_inv[9],
                                       PHYS_REAL vol);
PHYS_API void PHYS_FN(tet_gradient)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda,
                                    const PHYS_REAL x[12], const PHYS_REAL Dm_inv[9], PHYS_REAL vol,
                                    PHYS_REAL g[12]);
PHYS_API void PHYS_FN(tet_hessian)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda,
                                   const PHYS_REAL x[12], const PHYS_REAL Dm_inv[9], PHYS_REAL vol,
                                   PHYS_REAL H[144], int project);
PHYS_API PHYS_REAL PHYS_FN(tet_rest)(const PHYS_REAL X[12], PHYS_REAL Dm_inv[9]);
PHYS_API void PHYS_FN(sym_eig)(int n, const PHYS_REAL *A, PHYS_REAL *w, PHYS_REAL *V);
PHYS_API void PHYS_FN(project_psd)(int n, PHYS_REAL *A);
PHYS_API PHYS_REAL PHYS_FN(det3)(const PHYS_REAL A[9]);
PHYS_API PHYS_REAL PHYS_FN(barrier)(PHYS_REAL d, PHYS_REAL dhat, PHYS_REAL *d1, PHYS_REAL *d2);
PHYS_API PHYS_REAL PHYS_FN(barrier_distance)(PHYS_REAL d, PHYS_REAL dhat, PHYS_REAL *f1, PHYS_REAL *f2);
PHYS_API void PHYS_FN(motion)(rk_motion_kind kind, const PHYS_REAL axis[3], const PHYS_REAL center[3],
                              PHYS_REAL rate, const PHYS_REAL velocity[3], double t, PHYS_REAL R[9],
                              PHYS_REAL shift[3]);
PHYS_API int PHYS_FN(collider_check)(int kind, const PHYS_REAL *shape);
PHYS_API PHYS_REAL PHYS_FN(collider_distance)(int kind, const PHYS_REAL *shape, const PHYS_REAL x[3], PHYS_REAL n[3],
                                              PHYS_REAL closest[3]);
PHYS_API PHYS_REAL PHYS_FN(collider_step)(int kind, const PHYS_REAL *shape, const PHYS_REAL x[3], const PHYS_REAL dx[3]);
PHYS_API void PHYS_FN(collider_pose_at)(const PHYS_REAL *from, const PHYS_REAL *to, PHYS_REAL s, PHYS_REAL *out);
PHYS_API PHYS_REAL PHYS_FN(collider_motion_step)(int kind, const PHYS_REAL *from, const PHYS_REAL *to,
                                                 const PHYS_REAL x[3]);
PHYS_API void PHYS_FN(collider_path_velocity)(const PHYS_REAL *from, const PHYS_REAL *to, PHYS_REAL s,
                                              const PHYS_REAL local[3], PHYS_REAL v[3]);
PHYS_API PHYS_REAL PHYS_FN(collider_joint_step)(int kind, const PHYS_REAL *from, const PHYS_REAL *to, PHYS_REAL s,
                                                PHYS_REAL ds, const PHYS_REAL x[3], const PHYS_REAL dx[3]);
PHYS_API void PHYS_FN(tangent_basis)(const PHYS_REAL n[3], PHYS_REAL T[6]);
PHYS_API PHYS_REAL PHYS_FN(friction_smoothed)(const PHYS_REAL u[2], PHYS_REAL eps, PHYS_REAL *f1_over_y,
                                              PHYS_REAL M[4]);

PHYS_API rk_distance_case PHYS_FN(point_triangle_case)(const PHYS_REAL *const x[4]);
PHYS_API rk_distance_case PHYS_FN(edge_edge_case)(const PHYS_REAL *const x[4]);
PHYS_API PHYS_REAL PHYS_FN(contact_distance2)(rk_distance_case c, const PHYS_REAL *const x[4], PHYS_REAL *g,
                                              PHYS_REAL *H);
PHYS_API void PHYS_FN(contact_closest_weights)(rk_distance_case c, const PHYS_REAL *const x[4], PHYS_REAL w[4]);
PHYS_API PHYS_REAL PHYS_FN(edge_edge_mollifier)(const PHYS_REAL *const x[4], PHYS_REAL eps, PHYS_REAL *g,
                                                PHYS_REAL *H);
PHYS_API PHYS_REAL PHYS_FN(pair_barrier)(int edge_edge, const PHYS_REAL *const x[4], PHYS_REAL xi, PHYS_REAL dhat,
                                         PHYS_REAL eps, PHYS_REAL *g, PHYS_REAL *H, PHYS_REAL *dist);
PHYS_API void PHYS_FN(pair_project)(const int dof[4], PHYS_REAL *H);
PHYS_API PHYS_REAL PHYS_FN(pair_friction_lag)(int edge_edge, const PHYS_REAL *const x[4], PHYS_REAL xi,
                                              PHYS_REAL dhat, PHYS_REAL eps, PHYS_REAL kappa, PHYS_REAL w[4],
                                              PHYS_REAL T[6]);
PHYS_API PHYS_REAL PHYS_FN(friction_slip)(const PHYS_REAL T[6], const PHYS_REAL rel[3], PHYS_REAL eps,
                                          PHYS_REAL scale, PHYS_REAL g[3], PHYS_REAL B[9]);
PHYS_API int PHYS_FN(ccd_stencil)(int edge_edge, const PHYS_REAL *const x[4], const PHYS_REAL *const dx[4],
                                  PHYS_REAL xi, PHYS_REAL tmax, PHYS_REAL *toi);

/* ------------------------------------------------------------------------------------------
 * Small 3x3 helpers (row-major).
 * ------------------------------------------------------------------------------------------ */

/* C = A B */
static void PHYS_FN(m3_mul)(const PHYS_REAL A[9], const PHYS_REAL B[9], PHYS_REAL C[9])
{
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

/* C = A^T B */
static void PHYS_FN(m3_mul_tn)(const PHYS_REAL A[9], const PHYS_REAL B[9], PHYS_REAL C[9])
{
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            C[3 * i + j] = A[i] * B[j] + A[3 + i] * B[3 + j] + A[6 + i] * B[6 + j];
}

/* C = A B^T */
static void PHYS_FN(m3_mul_nt)(const PHYS_REAL A[9], const PHYS_REAL B[9], PHYS_REAL C[9])
{
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            C[3 * i + j] =
                A[3 * i] * B[3 * j] + A[3 * i + 1] * B[3 * j + 1] + A[3 * i + 2] * B[3 * j + 2];
}

static PHYS_REAL PHYS_FN(m3_det)(const PHYS_REAL A[9])
{
    return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
           A[2] * (A[3] * A[7] - A[4] * A[6]);
}

PHYS_API PHYS_REAL PHYS_FN(det3)(const PHYS_REAL A[9]) { return PHYS_FN(m3_det)(A); }

/* Cofactor matrix, cof_ij = dDet/dA_ij = A_{i+1,j+1} A_{i+2,j+2} - A_{i+1,j+2} A_{i+2,j+1}
 * (indices mod 3); A^-1 = cof^T / det. */
static void PHYS_FN(m3_cofactor)(const PHYS_REAL A[9], PHYS_REAL C[9])
{
    int i, j;
    for (i = 0; i < 3; i++) {
        int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        for (j = 0; j < 3; j++) {
            int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            C[3 * i + j] = A[3 * i1 + j1] * A[3 * i2 + j2] - A[3 * i1 + j2] * A[3 * i2 + j1];
        }
    }
}

/* Ainv = A^-1; returns det A. A singular A (det == 0) gives Ainv = 0. */
static PHYS_REAL PHYS_FN(m3_inv)(const PHYS_REAL A[9], PHYS_REAL Ainv[9])
{
    PHYS_REAL C[9], det = PHYS_FN(m3_det)(A);
    int i, j;
    if (det == PHYS_K_(0)) {
        memset(Ainv, 0, 9 * sizeof(PHYS_REAL));
        return det;
    }
    PHYS_FN(m3_cofactor)(A, C);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) Ainv[3 * i + j] = C[3 * j + i] / det;
    return det;
}

/* Levi-Civita symbol for indices in {0, 1, 2}. */
static int PHYS_FN(levi)(int a, int b, int c)
{
    return (a - b) * (b - c) * (c - a) / 2;
}

/* ------------------------------------------------------------------------------------------
 * Symmetric eigen-decomposition: cyclic Jacobi (Golub & Van Loan, Alg. 8.5.3, with the
 * rotation formulas of Numerical Recipes' jacobi) for n <= 3 (F^T F, the SVD below), and
 * Householder tridiagonalization with implicit QL for 3 < n <= 12 (the contact pairs' Hessians,
 * the 9x9 dP/dF projection), several times cheaper there.
 * ------------------------------------------------------------------------------------------ */

#define PHYS_JACOBI_MAX_N_ 12
#define PHYS_JACOBI_MAX_SWEEPS_ 60

/* A = V diag(w) V^T, w ascending, eigenvectors in V's columns (row-major, V[n*r + c]).
 * n outside 1..12 does nothing. */
/* One Jacobi rotation of the 3 x 3 symmetric a (row-major) in the (p, q) plane, o the third
 * index, V <- V J; the arithmetic of sym_eig's general loop, unrolled (so 3 x 3 results are the
 * same to the bit, several times faster: the SVD of every element's F goes through here).
 * Returns whether it rotated. */
static int PHYS_FN(jacobi3_rotate)(PHYS_REAL a[9], PHYS_REAL V[9], int p, int q, int o, PHYS_REAL scale)
{
    PHYS_REAL apq = a[3 * p + q], app = a[3 * p + p], aqq = a[3 * q + q], theta, t, c, s, akp, akq, vkp, vkq;
    int k;
    if (PHYS_FABS_(apq) <= PHYS_K_(0.01) * PHYS_EPS_ * (PHYS_FABS_(app) + PHYS_FABS_(aqq)) ||
        PHYS_FABS_(apq) <= PHYS_EPS_ * PHYS_EPS_ * scale) {
        a[3 * p + q] = a[3 * q + p] = PHYS_K_(0);
        return 0;
    }
    theta = (aqq - app) / (PHYS_K_(2) * apq);
    if (PHYS_FABS_(theta) > PHYS_K_(1))
        t = PHYS_K_(1) / (PHYS_FABS_(theta) * (PHYS_K_(1) + PHYS_SQRT_(PHYS_K_(1) + PHYS_K_(1) / (theta * theta))));
    else
        t = PHYS_K_(1) / (PHYS_FABS_(theta) + PHYS_SQRT_(theta * theta + PHYS_K_(1)));
    if (theta < PHYS_K_(0)) t = -t;
    c = PHYS_K_(1) / PHYS_SQRT_(t * t + PHYS_K_(1));
    s = t * c;
    akp = a[3 * o + p];
    akq = a[3 * o + q];
    a[3 * o + p] = a[3 * p + o] = c * akp - s * akq;
    a[3 * o + q] = a[3 * q + o] = s * akp + c * akq;
    a[3 * p + p] = app - t * apq;
    a[3 * q + q] = aqq + t * apq;
    a[3 * p + q] = a[3 * q + p] = PHYS_K_(0);
    for (k = 0; k < 3; k++) {
        vkp = V[3 * k + p];
        vkq = V[3 * k + q];
        V[3 * k + p] = c * vkp - s * vkq;
        V[3 * k + q] = s * vkp + c * vkq;
    }
    return 1;
}

/* sqrt(a^2 + b^2) without overflow or underflow of the squares (the 1e-300 scales of a Hessian
 * far inside dhat's tail). */
static PHYS_REAL PHYS_FN(hypot_)(PHYS_REAL a, PHYS_REAL b)
{
    PHYS_REAL x = PHYS_FABS_(a), y = PHYS_FABS_(b), t;
    if (x < y) t = x, x = y, y = t;
    if (x == PHYS_K_(0)) return PHYS_K_(0);
    t = y / x;
    return x * PHYS_SQRT_(PHYS_K_(1) + t * t);
}

/* The eigen-decomposition of the symmetric a (n x n, row-major, overwritten) for 3 < n <= 12:
 * Householder reduction to tridiagonal form, A = V T V^T (Golub & Van Loan, Alg. 8.3.1), then
 * the implicit QL iteration with Wilkinson's shift on T, its rotations accumulated into V (Bowdler,
 * Martin, Reinsch & Wilkinson 1968, tql2). About 9 n^3 flops with the vectors against cyclic
 * Jacobi's ~6 sweeps of 4 n^3 at n = 12; the contact pairs' 12 x 12 (and 9 x 9, 6 x 6)
 * Hessians spent a third of a many-object runtime step in Jacobi. w unsorted. */
static void PHYS_FN(tridiag_ql)(int n, PHYS_REAL *a, PHYS_REAL *w, PHYS_REAL *V, PHYS_REAL big)
{
    PHYS_REAL e[PHYS_JACOBI_MAX_N_], v[PHYS_JACOBI_MAX_N_], p[PHYS_JACOBI_MAX_N_];
    int i, j, k, l, m, iter;
    for (k = 0; k + 2 < n; k++) { /* zero column k below its subdiagonal: P = I - beta v v^T on k+1.. */
        PHYS_REAL top = PHYS_K_(0), norm = PHYS_K_(0), alpha, beta, K;
        for (i = k + 1; i < n; i++) top = PHYS_FABS_(a[n * i + k]) > top ? PHYS_FABS_(a[n * i + k]) : top;
        if (top == PHYS_K_(0)) continue;
        for (i = k + 1; i < n; i++) v[i] = a[n * i + k] / top, norm += v[i] * v[i];
        norm = PHYS_SQRT_(norm);
        alpha = v[k + 1] < PHYS_K_(0) ? norm : -norm; /* the sign that avoids cancellation in v */
        beta = PHYS_K_(1) / (norm * (norm + PHYS_FABS_(v[k + 1])));
        v[k + 1] -= alpha;
        /* A22 <- P A22 P = A22 - v q^T - q v^T, p = beta A22 v, q = p - (beta p.v / 2) v */
        for (i = k + 1, K = PHYS_K_(0); i < n; i++) {
            PHYS_REAL t = PHYS_K_(0);
            for (j = k + 1; j < n; j++) t += a[n * i + j] * v[j];
            p[i] = beta * t;
            K += p[i] * v[i];
        }
        K *= PHYS_K_(0.5) * beta;
        for (i = k + 1; i < n; i++) p[i] -= K * v[i];
        for (i = k + 1; i < n; i++)
            for (j = k + 1; j < n; j++) a[n * i + j] -= v[i] * p[j] + p[i] * v[j];
        a[n * (k + 1) + k] = a[n * k + k + 1] = alpha * top;
        for (i = k + 2; i < n; i++) a[n * i + k] = a[n * k + i] = PHYS_K_(0);
        for (i = 0; i < n; i++) { /* V <- V P */
            PHYS_REAL t = PHYS_K_(0);
            for (j = k + 1; j < n; j++) t += V[n * i + j] * v[j];
            t *= beta;
            for (j = k + 1; j < n; j++) V[n * i + j] -= t * v[j];
        }
    }
    for (i = 0; i < n; i++) w[i] = a[n * i + i], e[i] = i + 1 < n ? a[n * (i + 1) + i] : PHYS_K_(0);
    for (l = 0; l < n; l++)
        for (iter = 0; iter < PHYS_JACOBI_MAX_SWEEPS_; iter++) {
            PHYS_REAL g, r, s, c, f, b, q = PHYS_K_(0);
            /* the first negligible subdiagonal entry at or after l (relative to its neighbours, or
             * to A's largest entry big) splits T there */
            for (m = l; m + 1 < n; m++)
                if (PHYS_FABS_(e[m]) <= PHYS_EPS_ * (PHYS_FABS_(w[m]) + PHYS_FABS_(w[m + 1])) ||
                    PHYS_FABS_(e[m]) <= PHYS_EPS_ * PHYS_EPS_ * big)
                    break;
            if (m == l) break; /* w[l] is an eigenvalue */
            g = (w[l + 1] - w[l]) / (PHYS_K_(2) * e[l]);
            r = PHYS_FN(hypot_)(g, PHYS_K_(1));
            g = w[m] - w[l] + e[l] / (g + (g < PHYS_K_(0) ? -r : r)); /* Wilkinson's shift, implicit */
            s = c = PHYS_K_(1);
            for (i = m - 1; i >= l; i--) { /* chase the bulge up with Givens rotations */
                f = s * e[i], b = c * e[i];
                r = PHYS_FN(hypot_)(f, g);
                e[i + 1] = r;
                if (r == PHYS_K_(0)) { /* underflow: T splits at i + 1 */
                    w[i + 1] -= q;
                    e[m] = PHYS_K_(0);
                    break;
                }
                s = f / r, c = g / r;
                g = w[i + 1] - q;
                r = (w[i] - g) * s + PHYS_K_(2) * c * b;
                q = s * r;
                w[i + 1] = g + q;
                g = c * r - b;
                for (k = 0; k < n; k++) {
                    f = V[n * k + i + 1];
                    V[n * k + i + 1] = s * V[n * k + i] + c * f;
                    V[n * k + i] = c * V[n * k + i] - s * f;
                }
            }
            if (r == PHYS_K_(0) && i >= l) continue;
            w[l] -= q, e[l] = g, e[m] = PHYS_K_(0);
        }
}

PHYS_API void PHYS_FN(sym_eig)(int n, const PHYS_REAL *A, PHYS_REAL *w, PHYS_REAL *V)
{
    PHYS_REAL a[PHYS_JACOBI_MAX_N_ * PHYS_JACOBI_MAX_N_], scale = PHYS_K_(0);
    int i, j, k, p, q, sweep;
    if (n < 1 || n > PHYS_JACOBI_MAX_N_) return;
    if (n == 3) {
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++) {
                a[3 * i + j] = PHYS_K_(0.5) * (A[3 * i + j] + A[3 * j + i]);
                V[3 * i + j] = i == j ? PHYS_K_(1) : PHYS_K_(0);
                scale += a[3 * i + j] * a[3 * i + j];
            }
        scale = PHYS_SQRT_(scale);
        for (sweep = 0; sweep < PHYS_JACOBI_MAX_SWEEPS_; sweep++) {
            int rotated = PHYS_FN(jacobi3_rotate)(a, V, 0, 1, 2, scale);
            rotated |= PHYS_FN(jacobi3_rotate)(a, V, 0, 2, 1, scale);
            rotated |= PHYS_FN(jacobi3_rotate)(a, V, 1, 2, 0, scale);
            if (!rotated) break;
        }
        goto sort;
    }
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) { /* symmetrize: only A's symmetric part is decomposed */
            a[n * i + j] = PHYS_K_(0.5) * (A[n * i + j] + A[n * j + i]);
            V[n * i + j] = i == j ? PHYS_K_(1) : PHYS_K_(0);
            scale += a[n * i + j] * a[n * i + j];
        }
    scale = PHYS_SQRT_(scale);
    if (n > 3) {
        PHYS_REAL big = PHYS_K_(0);
        for (i = 0; i < n * n; i++) big = PHYS_FABS_(a[i]) > big ? PHYS_FABS_(a[i]) : big;
        if (!(big - big == PHYS_K_(0))) { /* a NaN or an infinity in A: all NaN out */
            for (i = 0; i < n * n; i++) V[i] = (PHYS_REAL)NAN;
            for (i = 0; i < n; i++) w[i] = (PHYS_REAL)NAN;
            return;
        }
        if (big > PHYS_K_(0)) { /* scaled by a power of two (exactly) to a largest entry in [1, 2):
                                   * the reduction's small entries stay clear of underflow, whose
                                   * rotations would lose V's orthogonality */
            PHYS_REAL f = PHYS_K_(1);
            while (big * f < PHYS_K_(1) && f * PHYS_K_(2) < (PHYS_REAL)INFINITY) f *= PHYS_K_(2);
            while (big * f >= PHYS_K_(2) && f > PHYS_K_(0)) f *= PHYS_K_(0.5);
            for (i = 0; i < n * n; i++) a[i] *= f;
            PHYS_FN(tridiag_ql)(n, a, w, V, big * f);
            for (i = 0; i < n; i++) w[i] /= f;
        } else {
            for (i = 0; i < n; i++) w[i] = PHYS_K_(0);
        }
        goto sorted;
    }
    for (sweep = 0; sweep < PHYS_JACOBI_MAX_SWEEPS_; sweep++) {
        int rotated = 0;
        for (p = 0; p < n - 1; p++)
            for (q = p + 1; q < n; q++) {
                PHYS_REAL apq = a[n * p + q], app = a[n * p + p], aqq = a[n * q + q];
                PHYS_REAL theta, t, c, s;
                /* Negligible next to the diagonal (relative) or to the whole matrix: zero. */
                if (PHYS_FABS_(apq) <=
                        PHYS_K_(0.01) * PHYS_EPS_ * (PHYS_FABS_(app) + PHYS_FABS_(aqq)) ||
                    PHYS_FABS_(apq) <= PHYS_EPS_ * PHYS_EPS_ * scale) {
                    a[n * p + q] = a[n * q + p] = PHYS_K_(0);
                    continue;
                }
                rotated = 1;
                /* t = tan of the rotation angle, the smaller root of t^2 + 2 t theta - 1 = 0,
                 * written without overflow for large |theta|. */
                theta = (aqq - app) / (PHYS_K_(2) * apq);
                if (PHYS_FABS_(theta) > PHYS_K_(1))
                    t = PHYS_K_(1) /
                        (PHYS_FABS_(theta) *
                         (PHYS_K_(1) + PHYS_SQRT_(PHYS_K_(1) + PHYS_K_(1) / (theta * theta))));
                else
                    t = PHYS_K_(1) / (PHYS_FABS_(theta) + PHYS_SQRT_(theta * theta + PHYS_K_(1)));
                if (theta < PHYS_K_(0)) t = -t;
                c = PHYS_K_(1) / PHYS_SQRT_(t * t + PHYS_K_(1));
                s = t * c;
                /* A <- J^T A J, J the rotation in the (p, q) plane; V <- V J. */
                for (k = 0; k < n; k++) {
                    PHYS_REAL akp, akq;
                    if (k == p || k == q) continue;
                    akp = a[n * k + p];
                    akq = a[n * k + q];
                    a[n * k + p] = a[n * p + k] = c * akp - s * akq;
                    a[n * k + q] = a[n * q + k] = s * akp + c * akq;
                }
                a[n * p + p] = app - t * apq;
                a[n * q + q] = aqq + t * apq;
                a[n * p + q] = a[n * q + p] = PHYS_K_(0);
                for (k = 0; k < n; k++) {
                    PHYS_REAL vkp = V[n * k + p], vkq = V[n * k + q];
                    V[n * k + p] = c * vkp - s * vkq;
                    V[n * k + q] = s * vkp + c * vkq;
                }
            }
        if (!rotated) break;
    }
sort:
    for (i = 0; i < n; i++) w[i] = a[n * i + i];
sorted:
    /* Sort ascending (selection sort, swapping eigenvector columns along). */
    for (i = 0; i < n - 1; i++) {
        int m = i;
        for (j = i + 1; j < n; j++)
            if (w[j] < w[m]) m = j;
        if (m != i) {
            PHYS_REAL tmp = w[i];
            w[i] = w[m];
            w[m] = tmp;
            for (k = 0; k < n; k++) {
                tmp = V[n * k + i];
                V[n * k + i] = V[n * k + m];
                V[n * k + m] = tmp;
            }
        }
    }
}

/* A <- V max(w, 0) V^T. An A that is already positive semi-definite is left untouched. */
/* 1 when a Cholesky factorization of A + shift I succeeds: then no eigenvalue of A is below
 * -shift. About n^3/6 multiplies, far cheaper than the Jacobi sweeps; project_psd tries it first. */
static int PHYS_FN(is_positive_definite)(int n, const PHYS_REAL *A, PHYS_REAL shift)
{
    PHYS_REAL L[PHYS_JACOBI_MAX_N_ * PHYS_JACOBI_MAX_N_];
    int i, j, k;
    for (j = 0; j < n; j++) {
        PHYS_REAL d = A[n * j + j] + shift;
        for (k = 0; k < j; k++) d -= L[n * j + k] * L[n * j + k];
        if (!(d > PHYS_K_(0))) return 0;
        L[n * j + j] = PHYS_SQRT_(d);
        for (i = j + 1; i < n; i++) {
            PHYS_REAL v = A[n * i + j];
            for (k = 0; k < j; k++) v -= L[n * i + k] * L[n * j + k];
            L[n * i + j] = v / L[n * j + j];
        }
    }
    return 1;
}

PHYS_API void PHYS_FN(project_psd)(int n, PHYS_REAL *A)
{
    PHYS_REAL w[PHYS_JACOBI_MAX_N_], V[PHYS_JACOBI_MAX_N_ * PHYS_JACOBI_MAX_N_];
    int i, j, k;
    if (n < 1 || n > PHYS_JACOBI_MAX_N_) return;
    {
        /* Element tensors are often only semi-definite (at rest, rotations are a null space), so
         * test A + shift I with shift a rounding-level fraction of A's scale: when that is
         * definite, A's negative eigenvalues are at most rounding noise and A is kept as is. */
        PHYS_REAL scale = PHYS_K_(0);
        for (i = 0; i < n; i++) scale = PHYS_FABS_(A[n * i + i]) > scale ? PHYS_FABS_(A[n * i + i]) : scale;
        if (PHYS_FN(is_positive_definite)(n, A, PHYS_K_(64) * PHYS_EPS_ * scale)) return;
    }
    PHYS_FN(sym_eig)(n, A, w, V);
    if (w[0] >= PHYS_K_(0)) return; /* ascending: nothing to clamp */
    for (i = 0; i < n; i++)
        for (j = i; j < n; j++) {
            PHYS_REAL sum = PHYS_K_(0);
            for (k = 0; k < n; k++)
                if (w[k] > PHYS_K_(0)) sum += V[n * i + k] * w[k] * V[n * j + k];
            A[n * i + j] = A[n * j + i] = sum;
        }
}

#undef PHYS_JACOBI_MAX_SWEEPS_

/* ------------------------------------------------------------------------------------------
 * Signed ("rotation variant") SVD of a 3x3 F = U diag(s) V^T with det U = det V = +1,
 * s0 >= s1 >= |s2| and s2 < 0 exactly when det F < 0 (Irving et al. 2004, McAdams et al. 2011).
 * V from the Jacobi eigenvectors of F^T F; U by Gram-Schmidt on the columns of F V in order
 * of decreasing singular value, u2 = u0 x u1 (so det U = +1); s_i = u_i . (F v_i). This keeps
 * U a rotation even when F is singular or zero (any completing direction is then valid).
 * ------------------------------------------------------------------------------------------ */

static void PHYS_FN(svd3)(const PHYS_REAL F[9], PHYS_REAL U[9], PHYS_REAL s[3], PHYS_REAL V[9])
{
    PHYS_REAL C[9], w[3], E[9], B[9], u[3][3], b[3][3], norm2 = PHYS_K_(0), tol, nrm, d;
    int i, j;
    PHYS_FN(m3_mul_tn)(F, F, C);
    PHYS_FN(sym_eig)(3, C, w, E);
    for (i = 0; i < 3; i++) /* descending order: V's column j = E's column 2 - j */
        for (j = 0; j < 3; j++) V[3 * i + j] = E[3 * i + 2 - j];
    if (PHYS_FN(m3_det)(V) < PHYS_K_(0))
        for (i = 0; i < 3; i++) V[3 * i + 2] = -V[3 * i + 2];
    PHYS_FN(m3_mul)(F, V, B);
    for (i = 0; i < 9; i++) norm2 += F[i] * F[i];
    tol = PHYS_EPS_ * PHYS_EPS_ * PHYS_SQRT_(norm2);
    for (j = 0; j < 3; j++)
        for (i = 0; i < 3; i++) b[j][i] = B[3 * i + j]; /* b[j] = F v_j */
    /* u0 = b0 / |b0|, or e_x when F ~ 0 */
    nrm = PHYS_SQRT_(b[0][0] * b[0][0] + b[0][1] * b[0][1] + b[0][2] * b[0][2]);
    for (i = 0; i < 3; i++)
        u[0][i] = nrm > tol ? b[0][i] / nrm : (i == 0 ? PHYS_K_(1) : PHYS_K_(0));
    /* u1 = b1 minus its u0 part, normalized; or any unit vector orthogonal to u0 */
    d = u[0][0] * b[1][0] + u[0][1] * b[1][1] + u[0][2] * b[1][2];
    for (i = 0; i < 3; i++) u[1][i] = b[1][i] - d * u[0][i];
    nrm = PHYS_SQRT_(u[1][0] * u[1][0] + u[1][1] * u[1][1] + u[1][2] * u[1][2]);
    if (!(nrm > tol)) { /* u0 x (the axis least aligned with u0) */
        int ax = 0;
        PHYS_REAL e[3] = {PHYS_K_(0), PHYS_K_(0), PHYS_K_(0)};
        for (i = 1; i < 3; i++)
            if (PHYS_FABS_(u[0][i]) < PHYS_FABS_(u[0][ax])) ax = i;
        e[ax] = PHYS_K_(1);
        u[1][0] = u[0][1] * e[2] - u[0][2] * e[1];
        u[1][1] = u[0][2] * e[0] - u[0][0] * e[2];
        u[1][2] = u[0][0] * e[1] - u[0][1] * e[0];
        nrm = PHYS_SQRT_(u[1][0] * u[1][0] + u[1][1] * u[1][1] + u[1][2] * u[1][2]);
    }
    for (i = 0; i < 3; i++) u[1][i] /= nrm;
    u[2][0] = u[0][1] * u[1][2] - u[0][2] * u[1][1];
    u[2][1] = u[0][2] * u[1][0] - u[0][0] * u[1][2];
    u[2][2] = u[0][0] * u[1][1] - u[0][1] * u[1][0];
    for (j = 0; j < 3; j++) {
        s[j] = u[j][0] * b[j][0] + u[j][1] * b[j][1] + u[j][2] * b[j][2];
        for (i = 0; i < 3; i++) U[3 * i + j] = u[j][i];
    }
}

/* Polar decomposition F = R S with R = U V^T a rotation (det R = +1 also for inverted F) and
 * S = V diag(s) V^T symmetric; also returns the signed singular values. */
static void PHYS_FN(polar3)(const PHYS_REAL F[9], PHYS_REAL R[9], PHYS_REAL s[3])
{
    PHYS_REAL U[9], V[9];
    PHYS_FN(svd3)(F, U, s, V);
    PHYS_FN(m3_mul_nt)(U, V, R);
}

/* ------------------------------------------------------------------------------------------
 * Materials.
 * ------------------------------------------------------------------------------------------ */

/* Lame parameters: mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)). */
PHYS_API void PHYS_FN(lame)(PHYS_REAL young, PHYS_REAL poisson, PHYS_REAL *mu, PHYS_REAL *lambda)
{
    *mu = young / (PHYS_K_(2) * (PHYS_K_(1) + poisson));
    *lambda = young * poisson / ((PHYS_K_(1) + poisson) * (PHYS_K_(1) - PHYS_K_(2) * poisson));
}

/* Stable Neo-Hookean constants of Eq. 16 (freeform paper; Eq. 11 of Smith et al. 2018):
 * lambda_bar = lambda + mu, mu_bar = mu, gamma = 1 + mu_bar / lambda_bar ("gam" in the code,
 * as <math.h> may declare gamma()), and E0 with Psi(I) = 0:
 * lambda_bar (1 - gamma)^2 + 3 mu - E0 = 0, so E0 = mu^2 / lambda_bar + 3 mu. */
static void PHYS_FN(snh_constants)(PHYS_REAL mu, PHYS_REAL lambda, PHYS_REAL *lbar, PHYS_REAL *gam,
                                   PHYS_REAL *E0)
{
    *lbar = lambda + mu;
    *gam = PHYS_K_(1) + mu / *lbar;
    *E0 = mu * mu / *lbar + PHYS_K_(3) * mu;
}

/* Energy and stress are written on the displacement gradient Hd = F - I, so that small strains
 * keep their digits: F and cof F are both ~I, and forming |F|^2 - 3, J - 1 or F - cof F from
 * them loses everything below machine epsilon of 1 -- in float32, a strain of 1e-4 keeps about
 * three digits of stress and none of energy. With Hd the same quantities are exact polynomials
 * in small numbers:
 *   J - 1      = tr Hd + i2(Hd) + det Hd        (i2: the sum of the principal 2x2 minors)
 *   cof F - I  = tr(Hd) I - Hd^T + cof(Hd)
 *   |F|^2 - 3  = 2 tr Hd + |Hd|^2. */
/* The higher-order part of J - 1: i2(Hd) + det Hd. */
static PHYS_REAL PHYS_FN(j_rest)(const PHYS_REAL Hd[9])
{
    PHYS_REAL i2 = Hd[0] * Hd[4] + Hd[4] * Hd[8] + Hd[0] * Hd[8] - Hd[1] * Hd[3] - Hd[2] * Hd[6] - Hd[5] * Hd[7];
    return i2 + PHYS_FN(m3_det)(Hd);
}

static PHYS_REAL PHYS_FN(j_minus_one)(const PHYS_REAL Hd[9])
{
    return (Hd[0] + Hd[4] + Hd[8]) + PHYS_FN(j_rest)(Hd);
}

static void PHYS_FN(cof_minus_identity)(const PHYS_REAL Hd[9], PHYS_REAL C[9])
{
    PHYS_REAL tr = Hd[0] + Hd[4] + Hd[8];
    int i, j;
    PHYS_FN(m3_cofactor)(Hd, C);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) C[3 * i + j] += (i == j ? tr : PHYS_K_(0)) - Hd[3 * j + i];
}

/* E (Green-Lagrange for StVK, small strain for linear) from Hd. */
static void PHYS_FN(strain)(rk_material_model model, const PHYS_REAL Hd[9], PHYS_REAL e[9])
{
    int i, j, k;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            PHYS_REAL q = PHYS_K_(0);
            if (model == RK_MAT_STVK)
                for (k = 0; k < 3; k++) q += Hd[3 * k + i] * Hd[3 * k + j];
            e[3 * i + j] = PHYS_K_(0.5) * (Hd[3 * i + j] + Hd[3 * j + i] + q);
        }
}

PHYS_API PHYS_REAL PHYS_FN(psi_h)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda, const PHYS_REAL Hd[9])
{
    PHYS_REAL e[9], tr, sum = PHYS_K_(0);
    int i;
    switch (model) {
    case RK_MAT_LINEAR: /* Psi = mu eps:eps + lambda/2 tr(eps)^2 */
    case RK_MAT_STVK:   /* Psi = mu E:E + lambda/2 tr(E)^2 */
        PHYS_FN(strain)(model, Hd, e);
        for (i = 0; i < 9; i++) sum += e[i] * e[i];
        tr = e[0] + e[4] + e[8];
        return mu * sum + PHYS_K_(0.5) * lambda * tr * tr;
    case RK_MAT_COROTATED: { /* mu sum (s_i - 1)^2 + lambda/2 (sum s_i - 3)^2, s the signed singular values */
        PHYS_REAL F[9], R[9], s[3];
        for (i = 0; i < 9; i++) F[i] = Hd[i] + (PHYS_REAL)(i % 4 == 0);
        PHYS_FN(polar3)(F, R, s);
        tr = s[0] + s[1] + s[2] - PHYS_K_(3);
        for (i = 0; i < 3; i++) sum += (s[i] - PHYS_K_(1)) * (s[i] - PHYS_K_(1));
        return mu * sum + PHYS_K_(0.5) * lambda * tr * tr;
    }
    case RK_MAT_NEOHOOKEAN: {
        /* Eq. 16, 1/2 [lambda_bar (J - gamma)^2 + mu |F|^2 - E0] with gamma = 1 + mu/lambda_bar and
         * E0 = mu^2/lambda_bar + 3 mu, expanded with j = J - 1: the constant and first-order terms
         * cancel exactly, leaving 1/2 [lambda_bar j^2 - 2 mu (i2 + det Hd) + mu |Hd|^2]. */
        PHYS_REAL lbar = lambda + mu, j = PHYS_FN(j_minus_one)(Hd);
        for (i = 0; i < 9; i++) sum += Hd[i] * Hd[i];
        return PHYS_K_(0.5) * (lbar * j * j - PHYS_K_(2) * mu * PHYS_FN(j_rest)(Hd) + mu * sum);
    }
    default:
        return PHYS_K_(0);
    }
}

PHYS_API void PHYS_FN(pk1_h)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda, const PHYS_REAL Hd[9],
                             PHYS_REAL P[9])
{
    PHYS_REAL e[9], tr;
    int i, j;
    switch (model) {
    case RK_MAT_LINEAR: /* P = 2 mu eps + lambda tr(eps) I */
        PHYS_FN(strain)(model, Hd, e);
        tr = e[0] + e[4] + e[8];
        for (i = 0; i < 9; i++) P[i] = PHYS_K_(2) * mu * e[i] + (i % 4 == 0 ? lambda * tr : PHYS_K_(0));
        return;
    case RK_MAT_STVK: { /* P = F S = S + Hd S, S = 2 mu E + lambda tr(E) I */
        PHYS_REAL S[9], HS[9];
        PHYS_FN(strain)(model, Hd, e);
        tr = e[0] + e[4] + e[8];
        for (i = 0; i < 9; i++) S[i] = PHYS_K_(2) * mu * e[i] + (i % 4 == 0 ? lambda * tr : PHYS_K_(0));
        PHYS_FN(m3_mul)(Hd, S, HS);
        for (i = 0; i < 9; i++) P[i] = S[i] + HS[i];
        return;
    }
    case RK_MAT_COROTATED: { /* P = 2 mu (F - R) + lambda tr(R^T F - I) R */
        PHYS_REAL F[9], R[9], s[3];
        for (i = 0; i < 9; i++) F[i] = Hd[i] + (PHYS_REAL)(i % 4 == 0);
        PHYS_FN(polar3)(F, R, s);
        tr = s[0] + s[1] + s[2] - PHYS_K_(3);
        for (i = 0; i < 9; i++) P[i] = PHYS_K_(2) * mu * (F[i] - R[i]) + lambda * tr * R[i];
        return;
    }
    case RK_MAT_NEOHOOKEAN: {
        /* P = mu F + lambda_bar (J - gamma) cof F = mu (Hd - C) + lambda_bar j (I + C), C = cof F - I
         * (the mu I terms cancel exactly), Hd - C = Hd + Hd^T - tr(Hd) I - cof(Hd). */
        PHYS_REAL lbar = lambda + mu, jm = PHYS_FN(j_minus_one)(Hd), C[9];
        PHYS_FN(cof_minus_identity)(Hd, C);
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++) {
                int k = 3 * i + j;
                P[k] = mu * (Hd[k] - C[k]) + lbar * jm * ((PHYS_REAL)(i == j) + C[k]);
            }
        return;
    }
    default:
        memset(P, 0, 9 * sizeof(PHYS_REAL));
        return;
    }
}

/* The F forms: one implementation, on Hd = F - I. */
PHYS_API PHYS_REAL PHYS_FN(psi)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda, const PHYS_REAL F[9])
{
    PHYS_REAL Hd[9];
    int i;
    for (i = 0; i < 9; i++) Hd[i] = F[i] - (PHYS_REAL)(i % 4 == 0);
    return PHYS_FN(psi_h)(model, mu, lambda, Hd);
}

PHYS_API void PHYS_FN(pk1)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda, const PHYS_REAL F[9],
                           PHYS_REAL P[9])
{
    PHYS_REAL Hd[9];
    int i;
    for (i = 0; i < 9; i++) Hd[i] = F[i] - (PHYS_REAL)(i % 4 == 0);
    PHYS_FN(pk1_h)(model, mu, lambda, Hd, P);
}

/* dP/dF for each model, written in full: D[9*(3i+j) + 3k+l] = dP_ij/dF_kl. Products of two
 * entries are parenthesised, x * (a_p * a_k), so that D is exactly symmetric in floating point.
 * Linearization at the rest state (checked by the tests): at F = I every model reduces to the
 * linear elasticity tensor mu (d_ik d_jl + d_il d_jk) + lambda d_ij d_kl:
 *  - StVK: S = 0, so D = mu F_il F_kj + mu (F F^T)_ik d_jl + lambda F_ij F_kl -> linear.
 *  - corotated: R = I, tr = 0, s = 1: D = 2 mu I - 2 mu skew + lambda I (x) I, and
 *    2 mu (id - skew) = 2 mu sym -> linear.
 *  - Neo-Hookean: D = mu I + lambda_bar cof (x) cof + lambda_bar (J - gamma) d2J/dF2 with
 *    cof = I, J - gamma = -mu/lambda_bar and d2J/dF_ij dF_kl = e_ikm e_jlm = d_ij d_kl - d_il d_jk,
 *    so D = mu d_ik d_jl + (lambda + mu) d_ij d_kl - mu (d_ij d_kl - d_il d_jk) -> linear. */
static void PHYS_FN(dpdf_raw)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda, PHYS_REAL pres,
                              const PHYS_REAL F[9], PHYS_REAL D[81])
{
    int i, j, k, l;
    memset(D, 0, 81 * sizeof(PHYS_REAL));
    switch (model) {
    case RK_MAT_LINEAR: /* mu (d_ik d_jl + d_il d_jk) + lambda d_ij d_kl */
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++) {
                D[9 * (3 * i + j) + 3 * i + j] += mu;
                D[9 * (3 * i + j) + 3 * j + i] += mu;
                if (i == j)
                    for (k = 0; k < 3; k++) D[9 * (3 * i + i) + 3 * k + k] += lambda;
            }
        return;
    case RK_MAT_STVK: {
        /* dP = dF S + F dS, dS = 2 mu dE + lambda tr(dE) I, dE = (dF^T F + F^T dF)/2:
         * dP_ij/dF_kl = d_ik S_lj + mu F_il F_kj + mu (F F^T)_ik d_jl + lambda F_ij F_kl */
        PHYS_REAL C[9], S[9], FFt[9], tr;
        PHYS_FN(m3_mul_tn)(F, F, C);
        PHYS_FN(m3_mul_nt)(F, F, FFt);
        tr = PHYS_K_(0.5) * (C[0] + C[4] + C[8] - PHYS_K_(3));
        for (i = 0; i < 9; i++)
            S[i] = mu * (C[i] - (i % 4 == 0 ? PHYS_K_(1) : PHYS_K_(0))) +
                   (i % 4 == 0 ? lambda * tr + pres : PHYS_K_(0));
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++)
                for (k = 0; k < 3; k++)
                    for (l = 0; l < 3; l++)
                        D[9 * (3 * i + j) + 3 * k + l] =
                            (i == k ? S[3 * l + j] : PHYS_K_(0)) +
                            mu * (F[3 * i + l] * F[3 * k + j]) +
                            (j == l ? mu * FFt[3 * i + k] : PHYS_K_(0)) +
                            lambda * (F[3 * i + j] * F[3 * k + l]);
        return;
    }
    case RK_MAT_COROTATED: {
        /* P = 2 mu (F - R) + lambda tr(S - I) R. With dF = dR S + R dS and R^T dR skew,
         * tr(R^T dF) = tr(dS) (tr(skew S) = 0), so
         *   dP = 2 mu dF + (lambda tr(S - I) - 2 mu) dR + lambda (R : dF) R.
         * dR/dF from the SVD F = U diag(s) V^T: in the rotated frame dF^ = U^T dF V,
         * dR^ = U^T dR V is skew with dR^_ij = (dF^_ij - dF^_ji) / (s_i + s_j), i.e.
         *   dR = sum_{i<j} 2 / (s_i + s_j) T_ij (T_ij : dF),  T_ij = (u_i v_j^T - u_j v_i^T)/sqrt 2
         * (the "twist" eigenmatrices of Smith et al. 2019). s_i + s_j >= 0 for the signed SVD;
         * it reaches 0 only where R itself is discontinuous (two singular values of opposite
         * sign and equal size), so the denominator is clamped to sqrt(eps) there. */
        PHYS_REAL U[9], V[9], R[9], s[3], tr, T[9], coef;
        int a, b, p;
        PHYS_FN(svd3)(F, U, s, V);
        PHYS_FN(m3_mul_nt)(U, V, R);
        tr = s[0] + s[1] + s[2] - PHYS_K_(3);
        for (p = 0; p < 9; p++) {
            D[10 * p] += PHYS_K_(2) * mu;
            for (k = 0; k < 9; k++) D[9 * p + k] += lambda * (R[p] * R[k]);
        }
        for (a = 0; a < 2; a++)
            for (b = a + 1; b < 3; b++) {
                PHYS_REAL den = s[a] + s[b];
                if (den < PHYS_SQRT_EPS_) den = PHYS_SQRT_EPS_;
                coef = (lambda * tr + pres - PHYS_K_(2) * mu) * PHYS_K_(2) / den;
                for (i = 0; i < 3; i++) /* T = (u_a v_b^T - u_b v_a^T) / sqrt 2 */
                    for (j = 0; j < 3; j++)
                        T[3 * i + j] = PHYS_K_(0.70710678118654752440) *
                                       (U[3 * i + a] * V[3 * j + b] - U[3 * i + b] * V[3 * j + a]);
                for (p = 0; p < 9; p++)
                    for (k = 0; k < 9; k++) D[9 * p + k] += coef * (T[p] * T[k]);
            }
        return;
    }
    case RK_MAT_NEOHOOKEAN: {
        /* P = mu F + lambda_bar (J - gamma) cof(F):
         * D = mu I + lambda_bar cof (x) cof + lambda_bar (J - gamma) d2J/dF2, with
         * d2J/dF_ij dF_kl = e_ikm e_jln F_mn (m, n the remaining indices). */
        PHYS_REAL lbar, gam, E0, cof[9], J = PHYS_FN(m3_det)(F), h;
        int m, n;
        PHYS_FN(snh_constants)(mu, lambda, &lbar, &gam, &E0);
        PHYS_FN(m3_cofactor)(F, cof);
        h = lbar * (J - gam) + pres;
        for (i = 0; i < 9; i++) {
            D[10 * i] += mu;
            for (k = 0; k < 9; k++) D[9 * i + k] += lbar * (cof[i] * cof[k]);
        }
        for (i = 0; i < 3; i++)
            for (k = 0; k < 3; k++) {
                if (i == k) continue;
                m = 3 - i - k;
                for (j = 0; j < 3; j++)
                    for (l = 0; l < 3; l++) {
                        if (j == l) continue;
                        n = 3 - j - l;
                        D[9 * (3 * i + j) + 3 * k + l] +=
                            h * (PHYS_REAL)(PHYS_FN(levi)(i, k, m) * PHYS_FN(levi)(j, l, n)) *
                            F[3 * m + n];
                    }
            }
        return;
    }
    default:
        return;
    }
}

/* D += c vec(M) vec(M)^T */
static void PHYS_FN(add_outer9)(PHYS_REAL D[81], PHYS_REAL c, const PHYS_REAL M[9])
{
    int a, b;
    for (a = 0; a < 9; a++)
        for (b = 0; b < 9; b++) D[9 * a + b] += c * (M[a] * M[b]);
}

/* Linear elasticity's fixed eigensystem: 2 mu on the 5 deviatoric symmetric directions,
 * 2 mu + 3 lambda on the volumetric one, 0 on the 3 skew ones. Clamped when negative. */
static void PHYS_FN(project_linear)(PHYS_REAL mu, PHYS_REAL lambda, PHYS_REAL D[81])
{
    PHYS_REAL dev = PHYS_K_(2) * mu, vol = PHYS_K_(2) * mu + PHYS_K_(3) * lambda;
    int i, j;
    if (dev >= 0 && vol >= 0) return;
    dev = dev > 0 ? dev : PHYS_K_(0);
    vol = vol > 0 ? vol : PHYS_K_(0);
    memset(D, 0, 81 * sizeof(PHYS_REAL));
    for (i = 0; i < 3; i++) /* dev (Sym - Vol) + vol Vol, Sym = (d_ik d_jl + d_il d_jk)/2, Vol = d_ij d_kl / 3 */
        for (j = 0; j < 3; j++) {
            D[9 * (3 * i + j) + 3 * i + j] += PHYS_K_(0.5) * dev;
            D[9 * (3 * i + j) + 3 * j + i] += PHYS_K_(0.5) * dev;
        }
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) D[9 * (4 * i) + 4 * j] += (vol - dev) / PHYS_K_(3);
}

/* dP/dF projected to PSD through the analytic eigensystem of the isotropic energy (Smith, de Goes
 * and Kim 2019, "Analytic eigensystems for isotropic distortion energies"; Teran et al. 2005),
 * from the signed SVD F = U diag(s) V^T and the energy as Psi(s), psi_i = dPsi/ds_i:
 *  - scaling: the 3 x 3 Hessian A = d2Psi/ds2, its eigenvectors e_k giving U diag(e_k) V^T;
 *  - for each pair (i, j): the flip (u_i v_j^T + u_j v_i^T)/sqrt 2 with eigenvalue
 *    (psi_i - psi_j)/(s_i - s_j), and the twist (u_i v_j^T - u_j v_i^T)/sqrt 2 with
 *    (psi_i + psi_j)/(s_i + s_j), written per model with the division cancelled where it
 *    cancels (so repeated singular values need no special case).
 * D holds the raw dP/dF on entry and is left exactly as it is when no eigenvalue is negative (as
 * the Jacobi projection leaves it); otherwise it is rebuilt from the clamped eigensystem. */
static void PHYS_FN(project_dpdf)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda, PHYS_REAL pres,
                                  const PHYS_REAL F[9], PHYS_REAL D[81])
{
    static const int pair[3][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}}; /* i, j and the third */
    PHYS_REAL U[9], V[9], s[3], A[9], wA[3], E[9], flip[3], twist[3], M[9];
    int p, a, b, k;
    if (model == RK_MAT_LINEAR) {
        PHYS_FN(project_linear)(mu, lambda, D);
        return;
    }
    if (model != RK_MAT_STVK && model != RK_MAT_COROTATED && model != RK_MAT_NEOHOOKEAN) return;
    PHYS_FN(svd3)(F, U, s, V);
    if (model == RK_MAT_STVK) { /* Psi = mu/4 sum (s_i^2 - 1)^2 + lambda/8 (sum s_i^2 - 3)^2 */
        PHYS_REAL half_li = PHYS_K_(0.5) * lambda * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] - PHYS_K_(3)) + pres;
        for (a = 0; a < 3; a++)
            for (b = 0; b < 3; b++)
                A[3 * a + b] = lambda * (s[a] * s[b]) + (a == b ? mu * (PHYS_K_(3) * s[a] * s[a] - PHYS_K_(1)) + half_li : 0);
        for (p = 0; p < 3; p++) {
            PHYS_REAL si = s[pair[p][0]], sj = s[pair[p][1]], q = si * si + sj * sj - PHYS_K_(1);
            flip[p] = mu * (q + si * sj) + half_li;
            twist[p] = mu * (q - si * sj) + half_li;
        }
    } else if (model == RK_MAT_COROTATED) { /* Psi = mu sum (s_i - 1)^2 + lambda/2 (sum s_i - 3)^2 */
        PHYS_REAL tr = s[0] + s[1] + s[2] - PHYS_K_(3);
        for (a = 0; a < 9; a++) A[a] = lambda + (a % 4 == 0 ? PHYS_K_(2) * mu : PHYS_K_(0));
        for (p = 0; p < 3; p++) {
            PHYS_REAL den = s[pair[p][0]] + s[pair[p][1]];
            if (den < PHYS_SQRT_EPS_) den = PHYS_SQRT_EPS_; /* as dpdf_raw: R jumps where s_i + s_j = 0 */
            flip[p] = PHYS_K_(2) * mu;
            twist[p] = PHYS_K_(2) * mu + PHYS_K_(2) * (lambda * tr + pres - PHYS_K_(2) * mu) / den;
        }
    } else { /* stable Neo-Hookean: Psi = lambda_bar/2 (J - gamma)^2 + mu/2 sum s_i^2 - E0/2 */
        PHYS_REAL lbar, gam, E0, g[3], h;
        PHYS_FN(snh_constants)(mu, lambda, &lbar, &gam, &E0);
        g[0] = s[1] * s[2], g[1] = s[0] * s[2], g[2] = s[0] * s[1]; /* dJ/ds */
        h = lbar * (s[0] * g[0] - gam) + pres;                      /* lambda_bar (J - gamma) + pres */
        for (a = 0; a < 3; a++)
            for (b = 0; b < 3; b++) A[3 * a + b] = lbar * (g[a] * g[b]) + (a == b ? mu : h * s[3 - a - b]);
        for (p = 0; p < 3; p++) {
            PHYS_REAL sk = s[pair[p][2]];
            flip[p] = mu - h * sk;
            twist[p] = mu + h * sk;
        }
    }
    /* D holds every mode with its eigenvalue (the raw dP/dF is exactly their sum), so when the
     * negative ones are few and small next to the positive ones (usually a twist or two: the
     * rotations' eigenvalues are 0 at rest and take either sign under any deformation) the
     * projection subtracts them, and A's eigenvectors are needed only when A is indefinite. When
     * a negative eigenvalue dominates (a corotated twist near s_i + s_j = 0 reaches 1/sqrt(eps)),
     * subtracting it would leave its rounding behind, and D is rebuilt from the positive modes. */
    {
        PHYS_REAL neg = PHYS_K_(0), pos = PHYS_K_(0), scale;
        int a_definite;
        for (p = 0; p < 3; p++) {
            neg = -flip[p] > neg ? -flip[p] : neg;
            neg = -twist[p] > neg ? -twist[p] : neg;
            pos = flip[p] > pos ? flip[p] : pos;
            pos = twist[p] > pos ? twist[p] : pos;
        }
        scale = PHYS_FABS_(A[0]) > PHYS_FABS_(A[4]) ? PHYS_FABS_(A[0]) : PHYS_FABS_(A[4]);
        scale = PHYS_FABS_(A[8]) > scale ? PHYS_FABS_(A[8]) : scale;
        a_definite = PHYS_FN(is_positive_definite)(3, A, PHYS_K_(64) * PHYS_EPS_ * scale);
        if (a_definite) {
            for (k = 0; k < 3; k++) pos = A[4 * k] > pos ? A[4 * k] : pos; /* A's diagonal: below its largest eigenvalue */
        } else {
            PHYS_FN(sym_eig)(3, A, wA, E);
            neg = -wA[0] > neg ? -wA[0] : neg;
            pos = wA[2] > pos ? wA[2] : pos;
        }
        if (!(neg > 0)) return;
        if (neg <= pos) {
            for (p = 0; p < 3; p++) {
                int i = pair[p][0], j = pair[p][1], twisting;
                for (twisting = 0; twisting < 2; twisting++) {
                    PHYS_REAL w = twisting ? twist[p] : flip[p], sign = twisting ? PHYS_K_(-1) : PHYS_K_(1);
                    if (!(w < 0)) continue;
                    for (a = 0; a < 3; a++)
                        for (b = 0; b < 3; b++)
                            M[3 * a + b] = PHYS_K_(0.70710678118654752440) *
                                           (U[3 * a + i] * V[3 * b + j] + sign * U[3 * a + j] * V[3 * b + i]);
                    PHYS_FN(add_outer9)(D, -w, M);
                }
            }
            if (a_definite) return;
            for (k = 0; k < 3; k++) {
                if (!(wA[k] < 0)) continue;
                for (a = 0; a < 3; a++) /* U diag(e_k) V^T */
                    for (b = 0; b < 3; b++)
                        M[3 * a + b] = U[3 * a] * E[3 * 0 + k] * V[3 * b] + U[3 * a + 1] * E[3 * 1 + k] * V[3 * b + 1] +
                                       U[3 * a + 2] * E[3 * 2 + k] * V[3 * b + 2];
                PHYS_FN(add_outer9)(D, -wA[k], M);
            }
            return;
        }
        if (a_definite) PHYS_FN(sym_eig)(3, A, wA, E);
    }
    memset(D, 0, 81 * sizeof(PHYS_REAL));
    for (k = 0; k < 3; k++) {
        if (!(wA[k] > 0)) continue;
        for (a = 0; a < 3; a++) /* U diag(e_k) V^T */
            for (b = 0; b < 3; b++)
                M[3 * a + b] = U[3 * a] * E[3 * 0 + k] * V[3 * b] + U[3 * a + 1] * E[3 * 1 + k] * V[3 * b + 1] +
                               U[3 * a + 2] * E[3 * 2 + k] * V[3 * b + 2];
        PHYS_FN(add_outer9)(D, wA[k], M);
    }
    for (p = 0; p < 3; p++) {
        int i = pair[p][0], j = pair[p][1], twisting;
        for (twisting = 0; twisting < 2; twisting++) {
            PHYS_REAL w = twisting ? twist[p] : flip[p], sign = twisting ? PHYS_K_(-1) : PHYS_K_(1);
            if (!(w > 0)) continue;
            for (a = 0; a < 3; a++)
                for (b = 0; b < 3; b++)
                    M[3 * a + b] = PHYS_K_(0.70710678118654752440) * (U[3 * a + i] * V[3 * b + j] + sign * U[3 * a + j] * V[3 * b + i]);
            PHYS_FN(add_outer9)(D, w, M);
        }
    }
}

PHYS_API void PHYS_FN(dpdf_p)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda, PHYS_REAL pres,
                              const PHYS_REAL F[9], PHYS_REAL dPdF[81], int project)
{
    PHYS_FN(dpdf_raw)(model, mu, lambda, pres, F, dPdF);
    if (project == RK_PROJECT_JACOBI) PHYS_FN(project_psd)(9, dPdF);
    else if (project) PHYS_FN(project_dpdf)(model, mu, lambda, pres, F, dPdF);
}

PHYS_API void PHYS_FN(dpdf)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda,
                            const PHYS_REAL F[9], PHYS_REAL dPdF[81], int project)
{
    PHYS_FN(dpdf_p)(model, mu, lambda, PHYS_K_(0), F, dPdF, project);
}

/* The volume measure theta of each model (physics.h, rk_volume_h): every model's energy is
 * Psi(mu, lambda; F) = Psi(mu, 0; F) + lambda/2 theta(F)^2, which the pressure projection
 * (precompute/cubature/volume.c) rests on:
 *  - linear: tr eps = tr Hd, dtheta/dF = I;
 *  - StVK: tr E = tr Hd + |Hd|^2 / 2, dtheta/dF = F;
 *  - corotated: sum s_i - 3 = tr(R^T F) - 3, dtheta/dF = R;
 *  - stable Neo-Hookean: J - 1, dtheta/dF = cof F. Its Eq. 11 (Smith et al. 2018), expanded as in
 *    psi_h, is 1/2 [lambda_bar j^2 - 2 mu (i2 + det Hd) + mu |Hd|^2] with lambda_bar = lambda + mu, so
 *    Psi(mu, lambda) - Psi(mu, 0) = lambda/2 j^2 exactly: the split keeps the mu j^2 / 2 (the
 *    rest-stability part, gamma's mu / lambda_bar shift) with the shear, and only the Lame lambda,
 *    the part that locks as lambda / mu grows, goes on the projected volume. */
PHYS_API PHYS_REAL PHYS_FN(volume_h)(rk_material_model model, const PHYS_REAL Hd[9], PHYS_REAL dtheta[9])
{
    int i;
    switch (model) {
    case RK_MAT_STVK: {
        PHYS_REAL sum = PHYS_K_(0);
        for (i = 0; i < 9; i++) {
            sum += Hd[i] * Hd[i];
            dtheta[i] = Hd[i] + (PHYS_REAL)(i % 4 == 0);
        }
        return Hd[0] + Hd[4] + Hd[8] + PHYS_K_(0.5) * sum;
    }
    case RK_MAT_COROTATED: {
        PHYS_REAL F[9], s[3];
        for (i = 0; i < 9; i++) F[i] = Hd[i] + (PHYS_REAL)(i % 4 == 0);
        PHYS_FN(polar3)(F, dtheta, s);
        return s[0] + s[1] + s[2] - PHYS_K_(3);
    }
    case RK_MAT_NEOHOOKEAN:
        PHYS_FN(cof_minus_identity)(Hd, dtheta);
        for (i = 0; i < 9; i += 4) dtheta[i] += PHYS_K_(1);
        return PHYS_FN(j_minus_one)(Hd);
    default: /* linear */
        for (i = 0; i < 9; i++) dtheta[i] = (PHYS_REAL)(i % 4 == 0);
        return Hd[0] + Hd[4] + Hd[8];
    }
}

/* ------------------------------------------------------------------------------------------
 * Linear tetrahedron. Ds = [b-a, c-a, d-a] (columns), F = Ds Dm^-1. With Dm^-1 = M,
 * dF_ij/dx_{v,k} = d_ik D_v[j], D_v = row v-1 of M for v = b, c, d and D_a = -(sum of rows):
 * this D_v fully describes B = dvec(F)/dx (9x12).
 * ------------------------------------------------------------------------------------------ */

/* The four rows D_v (v = a, b, c, d), D[3*v + j]. */
static void PHYS_FN(tet_shape)(const PHYS_REAL Dm_inv[9], PHYS_REAL D[12])
{
    int j;
    for (j = 0; j < 3; j++) {
        D[3 + j] = Dm_inv[j];
        D[6 + j] = Dm_inv[3 + j];
        D[9 + j] = Dm_inv[6 + j];
        D[j] = -(Dm_inv[j] + Dm_inv[3 + j] + Dm_inv[6 + j]);
    }
}

/* Dm^-1 and the signed rest volume det(Dm)/6; a degenerate tet gives Dm^-1 = 0, volume 0. */
PHYS_API PHYS_REAL PHYS_FN(tet_rest)(const PHYS_REAL X[12], PHYS_REAL Dm_inv[9])
{
    PHYS_REAL Dm[9];
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) Dm[3 * i + j] = X[3 * (j + 1) + i] - X[i];
    return PHYS_FN(m3_inv)(Dm, Dm_inv) / PHYS_K_(6);
}

PHYS_API void PHYS_FN(tet_F)(const PHYS_REAL x[12], const PHYS_REAL Dm_inv[9], PHYS_REAL F[9])
{
    PHYS_REAL Ds[9];
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) Ds[3 * i + j] = x[3 * (j + 1) + i] - x[i];
    PHYS_FN(m3_mul)(Ds, Dm_inv, F);
}

PHYS_API PHYS_REAL PHYS_FN(tet_energy)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda,
                                       const PHYS_REAL x[12], const PHYS_REAL Dm_inv[9],
                                       PHYS_REAL vol)
{
    PHYS_REAL F[9];
    PHYS_FN(tet_F)(x, Dm_inv, F);
    return vol * PHYS_FN(psi)(model, mu, lambda, F);
}

/* g[3v + k] += vol sum_j P_kj D_v[j]  (= vol B^T vec(P)) */
PHYS_API void PHYS_FN(tet_gradient)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda,
                                    const PHYS_REAL x[12], const PHYS_REAL Dm_inv[9], PHYS_REAL vol,
                                    PHYS_REAL g[12])
{
    PHYS_REAL F[9], P[9], D[12];
    int v, k;
    PHYS_FN(tet_F)(x, Dm_inv, F);
    PHYS_FN(pk1)(model, mu, lambda, F, P);
    PHYS_FN(tet_shape)(Dm_inv, D);
    for (v = 0; v < 4; v++)
        for (k = 0; k < 3; k++)
            g[3 * v + k] += vol * (P[3 * k] * D[3 * v] + P[3 * k + 1] * D[3 * v + 1] +
                                   P[3 * k + 2] * D[3 * v + 2]);
}

/* H[3v + k][3w + l] = vol sum_{j,n} D_v[j] dP_kj/dF_ln D_w[n]  (= vol B^T dPdF B), written
 * (not added); the upper triangle is computed and mirrored so H is exactly symmetric. */
PHYS_API void PHYS_FN(tet_hessian)(rk_material_model model, PHYS_REAL mu, PHYS_REAL lambda,
                                   const PHYS_REAL x[12], const PHYS_REAL Dm_inv[9], PHYS_REAL vol,
                                   PHYS_REAL H[144], int project)
{
    PHYS_REAL F[9], A[81], D[12];
    int r, c, j, n;
    PHYS_FN(tet_F)(x, Dm_inv, F);
    PHYS_FN(dpdf)(model, mu, lambda, F, A, project);
    PHYS_FN(tet_shape)(Dm_inv, D);
    for (r = 0; r < 12; r++)
        for (c = r; c < 12; c++) {
            int v = r / 3, k = r % 3, w = c / 3, l = c % 3;
            PHYS_REAL sum = PHYS_K_(0);
            for (j = 0; j < 3; j++)
                for (n = 0; n < 3; n++)
                    sum += D[3 * v + j] * A[9 * (3 * k + j) + 3 * l + n] * D[3 * w + n];
            H[12 * r + c] = H[12 * c + r] = vol * sum;
        }
}

/* ---- Ground contact and prescribed motion (shared by the full-order, reduced and runtime steps) ---- */

/* The IPC log barrier (Li et al. 2020) b(d) = -(d - dhat)^2 log(d / dhat) for 0 < d < dhat, with
 * b'(d) and b''(d) when asked (d1, d2 may be NULL). */
PHYS_API PHYS_REAL PHYS_FN(barrier)(PHYS_REAL d, PHYS_REAL dhat, PHYS_REAL *d1, PHYS_REAL *d2)
{
    PHYS_REAL r = (d - dhat) / d, lg = PHYS_LOG_(d / dhat);
    if (d1) *d1 = -PHYS_K_(2) * (d - dhat) * lg - (d - dhat) * (d - dhat) / d;
    if (d2) *d2 = -PHYS_K_(2) * lg - PHYS_K_(4) * r + r * r; /* each term >= 0 for d < dhat */
    return -(d - dhat) * (d - dhat) * lg;
}

/* The contact barrier of a point at signed distance d from a surface it may not cross (a plane, a
 * sphere, a capsule, a box), as IPC takes it: b(d^2, dhat^2) (the barrier on squared distances,
 * as between meshes), so 0 for d >= dhat; with f1 = d/dd and f2 = its second derivative, clamped
 * at 0 (the PSD projection of the point's 3 x 3 block f2 n n^T). The caller treats d <= 0 as a
 * crossing (its energy is infinite). */
PHYS_API PHYS_REAL PHYS_FN(barrier_distance)(PHYS_REAL d, PHYS_REAL dhat, PHYS_REAL *f1, PHYS_REAL *f2)
{
    PHYS_REAL b1, b2, b;
    if (d >= dhat) {
        if (f1) *f1 = 0;
        if (f2) *f2 = 0;
        return 0;
    }
    b = PHYS_FN(barrier)(d * d, dhat * dhat, &b1, &b2);
    if (f1) *f1 = PHYS_K_(2) * d * b1;
    if (f2) {
        *f2 = PHYS_K_(4) * d * d * b2 + PHYS_K_(2) * b1;
        if (*f2 < 0) *f2 = 0;
    }
    return b;
}

/* Where a prescribed group's vertices are at time t: x = R X + shift. Fixed: R = I, shift = 0;
 * translate: shift = velocity t; twist: rotation by rate t (rad) about the axis (any length)
 * through center, by Rodrigues: R = cos I + sin [k]x + (1 - cos) k k^T, shift = c - R c, plus
 * velocity t (zero for a plain twist; a twist that also translates is a screw). t is a double in
 * every precision (the runtime's clock), and the products with it are taken in double; in float the
 * angle is reduced to one turn first (cosf of 9e4 rad, two hours at 720 degrees a second, would be
 * off by a float's spacing there, 8e-3 rad). In double this is rate * t as it always was. */
PHYS_API void PHYS_FN(motion)(rk_motion_kind kind, const PHYS_REAL axis[3], const PHYS_REAL center[3],
                              PHYS_REAL rate, const PHYS_REAL velocity[3], double t, PHYS_REAL R[9],
                              PHYS_REAL shift[3])
{
    int i, j;
    for (i = 0; i < 9; i++) R[i] = (PHYS_REAL)(i % 4 == 0);
    for (i = 0; i < 3; i++) shift[i] = PHYS_K_(0);
    if (kind == RK_MOTION_TRANSLATE) {
        for (i = 0; i < 3; i++) shift[i] = (PHYS_REAL)((double)velocity[i] * t);
    } else if (kind == RK_MOTION_TWIST) {
        PHYS_REAL len = PHYS_SQRT_(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        PHYS_REAL k[3], cross[9], c, sn;
        double angle = (double)rate * t;
#ifdef PHYS_FLOAT
        angle = fmod(angle, 6.283185307179586);
#endif
        for (i = 0; i < 3; i++) k[i] = axis[i] / len;
        c = PHYS_COS_((PHYS_REAL)angle);
        sn = PHYS_SIN_((PHYS_REAL)angle);
        cross[0] = 0; cross[1] = -k[2]; cross[2] = k[1];
        cross[3] = k[2]; cross[4] = 0; cross[5] = -k[0];
        cross[6] = -k[1]; cross[7] = k[0]; cross[8] = 0;
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++)
                R[3 * i + j] = (PHYS_REAL)(i == j) * c + sn * cross[3 * i + j] + (PHYS_K_(1) - c) * k[i] * k[j];
        for (i = 0; i < 3; i++)
            shift[i] = center[i] - (R[3 * i] * center[0] + R[3 * i + 1] * center[1] + R[3 * i + 2] * center[2]) +
                       (PHYS_REAL)((double)velocity[i] * t); /* a screw when the twist also translates */
    }
}

#include "physics/collider_impl.h"
#include "physics/contact_impl.h" /* after collider_impl.h: shares its dot3_ */

#undef PHYS_JACOBI_MAX_N_
#undef PHYS_K_
#undef PHYS_SQRT_
#undef PHYS_FABS_
#undef PHYS_LOG_
#undef PHYS_COS_
#undef PHYS_SIN_
#undef PHYS_ATAN2_
#undef PHYS_MATH_TYPE_
#undef PHYS_EPS_
#undef PHYS_SQRT_EPS_
#ifdef PHYS_API_DEFAULTED_
#undef PHYS_API
#undef PHYS_API_DEFAULTED_
#endif
