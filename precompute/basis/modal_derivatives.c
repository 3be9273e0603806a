/* Modal derivatives (Barbic & James 2005, Sec. 3-4). K Psi_ij = -(H : psi_i) psi_j over the free
 * dofs, one factorization of K for all pairs. A free object's K is singular (rigid modes): its
 * right-hand sides are projected off the rigid modes (they are not exactly orthogonal to the
 * infinitesimal rotations, because rotations are only linearized), solved with a tiny negative
 * shift plus two steps of iterative refinement, and the solutions made M-orthogonal to the
 * rigid modes. */
#include "basis/basis.h"
#include "basis/free_system_impl.h"
#include "basis/shifted_impl.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "util/util.h"

/* x -= R (R^T M x) for the M-orthonormal rigid modes R (free vectors), or R (R^T x) on the
 * right-hand-side side: y -= M R (R^T y). */
static void project_rigid(const rk_free_system *s, const double *R, int nrigid, double *x, int rhs,
                          double *tmp)
{
    for (int q = 0; q < nrigid; q++) {
        const double *rq = R + (size_t)q * s->nfree;
        if (rhs) {
            double c = cblas_ddot(s->nfree, rq, 1, x, 1);
            rk_sparse_mul(&s->M, rq, tmp);
            cblas_daxpy(s->nfree, -c, tmp, 1, x, 1);
        } else {
            double c = rk_sparse_dot(&s->M, rq, x);
            cblas_daxpy(s->nfree, -c, rq, 1, x, 1);
        }
    }
}

/* The derivatives over an already assembled free system (shared by the basis builder, which
 * has the system from computing the modes). */
static int derivatives_on(const rk_free_system *s, const rk_fem *f, const double *U, int k, int nrigid,
                          double *Psi, double *residual, rk_error *err)
{
    rk_shifted fac;
    double sigma = nrigid ? -1e-8 * rk_sparse_trace(&s->K) / rk_sparse_trace(&s->M) : 0.0;
    int rc = -1, have_fac = 0;
    size_t nd = (size_t)s->ndof, nf = (size_t)s->nfree;
    double *R = rk_calloc(nf * (nrigid ? nrigid : 1), sizeof(double), err);
    double *full = rk_calloc(nd, sizeof(double), err);
    double *rhs = rk_calloc(nf, sizeof(double), err), *x = rk_calloc(nf, sizeof(double), err);
    double *res = rk_calloc(nf, sizeof(double), err), *tmp = rk_calloc(nf, sizeof(double), err);
    if (!R || !full || !rhs || !x || !res || !tmp) goto out;
    if (rk_shifted_init(&fac, &s->K, &s->M, sigma, err)) { rk_error_prefix(err, "modal derivatives"); goto out; }
    have_fac = 1;
    for (int q = 0; q < nrigid; q++) rk_free_system_gather(s, U + (size_t)q * nd, R + (size_t)q * nf);
    *residual = 0;
    int pair = 0;
    for (int i = nrigid; i < k; i++)
        for (int j = i; j < k; j++, pair++) {
            rk_progress("modal derivatives", pair + 1, (long)(k - nrigid) * (k - nrigid + 1) / 2);
            rk_stiffness_derivative(f, U + (size_t)i * nd, U + (size_t)j * nd, full);
            rk_free_system_gather(s, full, rhs);
            cblas_dscal((int)nf, -1.0, rhs, 1);
            project_rigid(s, R, nrigid, rhs, 1, tmp);
            double rnorm = cblas_dnrm2((int)nf, rhs, 1);
            memset(x, 0, nf * sizeof(double));
            memcpy(res, rhs, nf * sizeof(double));
            /* x += K_shifted^{-1} (rhs - K x): exact in one pass when sigma = 0, and each pass
             * shrinks the shift's error by |sigma| / lambda_min otherwise. */
            for (int pass = 0; pass < (nrigid ? 3 : 1); pass++) {
                if (rk_shifted_solve(&fac, res, tmp, err)) goto out;
                cblas_daxpy((int)nf, 1.0, tmp, 1, x, 1);
                project_rigid(s, R, nrigid, x, 0, tmp);
                rk_sparse_mul(&s->K, x, res);
                for (size_t q = 0; q < nf; q++) res[q] = rhs[q] - res[q];
            }
            double rel = rnorm > 0 ? cblas_dnrm2((int)nf, res, 1) / rnorm : 0;
            if (rel > *residual) *residual = rel;
            rk_free_system_expand(s, x, Psi + (size_t)pair * nd);
        }
    rk_progress_done("modal derivatives");
    rc = 0;
out:
    if (have_fac) rk_shifted_free(&fac);
    free(R); free(full); free(rhs); free(x); free(res); free(tmp);
    return rc;
}

int rk_modal_derivatives(const rk_fem *f, const unsigned char *constrained, int lumped,
                         const double *U, int k, int nrigid, double *Psi, double *residual,
                         rk_error *err)
{
    rk_free_system s;
    if (rk_free_system_init(&s, f, constrained, lumped, err)) return -1;
    int rc = derivatives_on(&s, f, U, k, nrigid, Psi, residual, err);
    rk_free_system_free(&s);
    return rc;
}

int rk_basis_modal_derivatives(const rk_fem *f, const unsigned char *constrained, int lumped,
                               int r, int nmodes, rk_basis *b, rk_error *err)
{
    memset(b, 0, sizeof *b);
    rk_free_system s;
    if (rk_free_system_init(&s, f, constrained, lumped, err)) return -1;
    size_t nd = (size_t)s.ndof;
    int rc = -1, nrigid = 0, k = 0;
    double *values = NULL, *U = NULL, *cand = NULL, *Psi = NULL, residual = 0;
    /* First pass: how many rigid modes (six per free piece)? */
    int probe = 7 < s.nfree - 1 ? 7 : s.nfree - 1;
    values = rk_calloc(64, sizeof(double), err);
    U = rk_calloc(nd * 64, sizeof(double), err);
    if (!values || !U) goto out;
    if (rk_free_system_modes(&s, probe, values, U, &nrigid, err)) goto out;
    if (nrigid == probe) {
        rk_fail(err, "modal derivatives: the object has at least %d rigid modes (several free pieces)", probe);
        goto out;
    }
    int want = r - nrigid;
    if (want < 1) { rk_fail(err, "modal derivatives: size %d leaves no room beside %d rigid modes", r, nrigid); goto out; }
    k = nmodes;
    if (k <= 0)
        for (k = 1; k + k * (k + 1) / 2 < (3 * want + 1) / 2; k++) {}
    if (k + nrigid > 64) { rk_fail(err, "modal derivatives: %d linear modes asked, at most %d", k, 64 - nrigid); goto out; }
    if (rk_free_system_modes(&s, k + nrigid, values, U, &nrigid, err)) goto out;
    int npairs = k * (k + 1) / 2, ncand = k + npairs;
    if (want > ncand) {
        rk_fail(err, "modal derivatives: size %d needs more than the %d modes and %d derivatives of "
                "%d linear modes (raise rom.modes)", r, k, npairs, k);
        goto out;
    }
    Psi = rk_calloc(nd * npairs, sizeof(double), err);
    cand = rk_calloc(nd * ncand, sizeof(double), err);
    b->U = rk_calloc(nd * r, sizeof(double), err);
    b->values = rk_calloc((size_t)(k + nrigid), sizeof(double), err);
    if (!Psi || !cand || !b->U || !b->values) goto out;
    if (derivatives_on(&s, f, U, k + nrigid, nrigid, Psi, &residual, err)) goto out;
    /* Barbic & James scale modes by lambda_1 / lambda_i and derivatives by
     * lambda_1^2 / (lambda_i lambda_j) so low frequencies dominate the PCA. */
    double l1 = values[nrigid];
    for (int i = 0; i < k; i++)
        for (size_t q = 0; q < nd; q++) cand[i * nd + q] = l1 / values[nrigid + i] * U[(nrigid + i) * nd + q];
    int p = 0;
    for (int i = 0; i < k; i++)
        for (int j = i; j < k; j++, p++) {
            double sc = l1 * l1 / (values[nrigid + i] * values[nrigid + j]);
            for (size_t q = 0; q < nd; q++) cand[(k + p) * nd + q] = sc * Psi[p * nd + q];
        }
    int got = 0;
    memcpy(b->U, U, nd * nrigid * sizeof(double));
    if (rk_mass_pca(cand, (int)nd, ncand, &s.Mfull, want, 0, b->U + nd * nrigid, &got, NULL, err)) {
        rk_error_prefix(err, "modal derivatives");
        goto out;
    }
    b->type = RK_BASIS_MODAL_DERIVATIVES;
    b->n = f->nv;
    b->r = r;
    b->nvalues = k + nrigid;
    b->nzero = nrigid;
    memcpy(b->values, values, sizeof(double) * (k + nrigid));
    rc = 0;
out:
    rk_free_system_free(&s);
    free(values); free(U); free(cand); free(Psi);
    if (rc) rk_basis_free(b);
    return rc;
}
