/* rk_rom_model_init: the reduced matrices, loads, penalty and contact rows of rom.h, projected
 * once from the full-order setup. */
#include "rom/rom_impl.h"
#include "util/util.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Out = U^T S U (r x r, column-major) for a symmetric sparse S; SU is 3n x r scratch. */
static void project_matrix(const rk_sparse *S, const double *U, int ndof, int r, double *SU, double *out)
{
    for (int j = 0; j < r; j++) rk_sparse_mul(S, U + (size_t)ndof * j, SU + (size_t)ndof * j);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, r, ndof, 1.0, U, ndof, SU, ndof, 0.0, out, r);
    for (int j = 0; j < r; j++) /* exact symmetry: the Newton matrix goes to Cholesky */
        for (int i = 0; i < j; i++) out[i + (size_t)r * j] = out[j + (size_t)r * i] =
            0.5 * (out[i + (size_t)r * j] + out[j + (size_t)r * i]);
}

/* The basis moves vertex v when one of its 3 rows is not zero. */
static int basis_moves(const double *U, int ndof, int r, int v)
{
    for (int j = 0; j < r; j++)
        for (int a = 0; a < 3; a++)
            if (U[(size_t)ndof * j + 3 * v + a] != 0) return 1;
    return 0;
}

/* M_r = sum_p rho_p v_p U_p^T U_p over mesh-free integration points (freeform paper: the mass is
 * integrated at the same points as the energy). With U_p the skinning rows of point p, U_p^T U_p =
 * (z z^T) (x) I_3 in the (a, j, c) order, z_(j, c) = W_j(X_p) X̄_c: one 4H x 4H sum, spread over
 * the three rows a. f_r gets gravity the same way. */
static void point_mass(rk_rom_model *m, const rk_skin_points *P, const double gravity[3], double *f)
{
    int H = P->H, n4 = 4 * H, r = m->r;
    double *S = calloc((size_t)n4 * n4 + n4, sizeof(double)), *z = S ? S + (size_t)n4 * n4 : NULL;
    if (!S) return; /* caller checks m->M */
    double total = 0;
    for (int p = 0; p < P->n; p++) {
        double mp = P->density[p] * P->volume[p];
        const double *X = P->X + 3 * (size_t)p;
        for (int j = 0; j < H; j++) {
            double w = P->W[(size_t)p + (size_t)P->n * j];
            for (int c = 0; c < 4; c++) z[4 * j + c] = w * (c < 3 ? X[c] : 1.0);
        }
        cblas_dsyr(CblasColMajor, CblasUpper, n4, mp, z, 1, S, n4);
        for (int k = 0; k < n4; k++)
            for (int a = 0; a < 3; a++) f[12 * (k / 4) + 4 * a + k % 4] += mp * z[k] * gravity[a];
        total += mp;
    }
    for (int y = 0; y < n4; y++)
        for (int x = 0; x <= y; x++) {
            double v = S[x + (size_t)n4 * y];
            for (int a = 0; a < 3; a++) {
                int i = 12 * (x / 4) + 4 * a + x % 4, j = 12 * (y / 4) + 4 * a + y % 4;
                m->M[i + (size_t)r * j] = m->M[j + (size_t)r * i] = v;
            }
        }
    m->mass = total;
    free(S);
}

static int build_matrices(rk_rom_model *m, const rk_fem *fem, const rk_fom_options *opt, const double *U,
                          const rk_skin_points *points, rk_error *err)
{
    int r = m->r, ndof = 3 * fem->nv;
    rk_sparse S = {0};
    double *SU = rk_calloc((size_t)ndof * r, sizeof(double), err);
    double *fext = rk_calloc((size_t)ndof, sizeof(double), err);
    int damped = opt->rayleigh_mass > 0 || opt->rayleigh_stiffness > 0;
    m->M = rk_calloc((size_t)r * r, sizeof(double), err);
    m->M_chol = rk_calloc((size_t)r * r, sizeof(double), err);
    m->C = damped ? rk_calloc((size_t)r * r, sizeof(double), err) : NULL;
    m->f = rk_calloc((size_t)r, sizeof(double), err);
    if (!SU || !fext || !m->M || !m->M_chol || (damped && !m->C) || !m->f || rk_sparse_alloc_pattern(fem, &S, err)) {
        free(SU);
        free(fext);
        rk_sparse_free(&S);
        return -1;
    }
    if (points) {
        /* full-order states project in the fem's own mass (rk_rom_project), when it has one */
        rk_fem_add_mass(fem, opt->lumped_mass, 1.0, &S);
        /* and a cloud's points' (no element holds them: without this U^T M U was singular for a
         * cloud and M_r served, which full-order states are not measured in) */
        rk_fem_add_point_mass(fem, 1.0, &S);
        m->M_proj_chol = rk_calloc((size_t)r * r, sizeof(double), err);
        if (!m->M_proj_chol) {
            free(SU), free(fext), rk_sparse_free(&S);
            return -1;
        }
        project_matrix(&S, U, ndof, r, SU, m->M_proj_chol);
        if (LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'U', r, m->M_proj_chol, r) != 0) {
            free(m->M_proj_chol); /* (a cloud whose points cannot hold every column: M_r serves) */
            m->M_proj_chol = NULL;
        }
        rk_sparse_zero(&S);
        m->mass = -1;
        point_mass(m, points, opt->gravity, m->f);
        if (m->mass < 0) {
            free(SU);
            free(fext);
            rk_sparse_free(&S);
            return rk_fail(err, "out of memory integrating the mass at %d points", points->n);
        }
    } else {
        rk_fem_add_mass(fem, opt->lumped_mass, 1.0, &S);
        project_matrix(&S, U, ndof, r, SU, m->M);
    }
    memcpy(m->M_chol, m->M, sizeof(double) * r * r);
    int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'U', r, m->M_chol, r);
    if (info != 0) {
        free(SU);
        free(fext);
        rk_sparse_free(&S);
        return rk_fail(err, "U^T M U is not positive definite (pivot %d): the basis has dependent columns", info);
    }
    if (damped && points) {
        /* C_r = a M_r + b K_r(0), the rest stiffness integrated at the same points */
        double *q0 = rk_calloc((size_t)r, sizeof(double), err);
        if (!q0) {
            free(SU), free(fext), rk_sparse_free(&S);
            return -1;
        }
        rk_quadrature_eval(&m->quad, q0, NULL, m->C, 0);
        free(q0);
        for (size_t k = 0; k < (size_t)r * r; k++) m->C[k] = opt->rayleigh_mass * m->M[k] + opt->rayleigh_stiffness * m->C[k];
    } else if (damped) {
        rk_sparse_zero(&S);
        rk_fem_add_mass(fem, opt->lumped_mass, opt->rayleigh_mass, &S);
        rk_fem_add_rest_stiffness(fem, opt->rayleigh_stiffness, &S);
        project_matrix(&S, U, ndof, r, SU, m->C);
    }
    /* Gravity with the lumped masses, as the full-order model applies it (mesh-free: at the
     * integration points, above); the scene's loads on the vertices. */
    for (int v = 0; v < fem->nv; v++)
        for (int i = 0; i < 3; i++)
            fext[3 * v + i] = (points ? 0 : fem->vertex_mass[v] * opt->gravity[i]) + (opt->force ? opt->force[3 * v + i] : 0);
    cblas_dgemv(CblasColMajor, CblasTrans, ndof, r, 1.0, U, ndof, fext, 1, 1.0, m->f, 1);
    free(SU);
    free(fext);
    rk_sparse_free(&S);
    return 0;
}

/* Penalty rows of every prescribed vertex the basis can move (rom.h: A and each group's T). A
 * vertex that must move and that the basis cannot move is an error: its target is out of reach. */
static int build_pins(rk_rom_model *m, const rk_fem *fem, const rk_fom_options *opt, const double *U,
                      const rk_skin_points *points, rk_error *err)
{
    int r = m->r, ndof = 3 * fem->nv;
    double stiff = 0;
    for (int t = 0; t < fem->nt; t++)
        stiff = fmax(stiff, (fem->lambda[t] + 2 * fem->mu[t]) / fem->density[t]);
    /* mesh-free: the material is at the integration points (a point cloud has no element, and a
     * stiffness of 0 would leave its pins without any hold) */
    for (int p = 0; points && p < points->n; p++)
        if (points->density[p] > 0) stiff = fmax(stiff, (points->lambda[p] + 2 * points->mu[p]) / points->density[p]);
    double L = rk_points_diagonal(fem->X, fem->nv);
    m->pin_k = (opt->pin_stiffness > 0 ? opt->pin_stiffness : RK_ROM_PIN_STIFFNESS) * stiff / (L * L);
    m->A = rk_calloc((size_t)r * r, sizeof(double), err);
    m->pins = rk_calloc((size_t)(opt->nprescribed > 0 ? opt->nprescribed : 1), sizeof *m->pins, err);
    if (!m->A || !m->pins) return -1;
    m->npins = opt->nprescribed;
    for (int g = 0; g < opt->nprescribed; g++) {
        const rk_prescribed *p = &opt->prescribed[g];
        rk_rom_pin *pin = &m->pins[g];
        pin->motion = *p;
        pin->motion.verts = NULL;
        pin->T = rk_calloc((size_t)r * 12, sizeof(double), err);
        if (!pin->T) return -1;
        for (int k = 0; k < p->count && g != opt->lift_group - 1; k++) { /* (the lifted group: no penalty) */
            int v = p->verts[k];
            if (v < 0 || v >= fem->nv)
                return rk_fail(err, "prescribed group %d: vertex %d out of range (the mesh has %d)", g, v, fem->nv);
            if (!basis_moves(U, ndof, r, v)) {
                if (p->kind != RK_MOTION_FIXED)
                    return rk_fail(err, "prescribed group %d: vertex %d must move, but the basis holds it "
                                   "at rest (build the basis with only the fixed vertices constrained)", g, v);
                continue;
            }
            m->pinned_vertices++;
            double mv = fem->vertex_mass[v];
            const double *X = &fem->X[3 * v];
            for (int a = 0; a < 3; a++) {
                const double *row = U + 3 * v + a; /* stride ndof */
                cblas_dsyr(CblasColMajor, CblasUpper, r, m->pin_k * mv, row, ndof, m->A, r);
                for (int b = 0; b < 3; b++) cblas_daxpy(r, m->pin_k * mv * X[b], row, ndof, pin->T + (size_t)r * (3 * a + b), 1);
                cblas_daxpy(r, m->pin_k * mv, row, ndof, pin->T + (size_t)r * (9 + a), 1);
            }
        }
    }
    for (int j = 0; j < r; j++) /* dsyr filled the upper triangle */
        for (int i = j + 1; i < r; i++) m->A[i + (size_t)r * j] = m->A[j + (size_t)r * i];
    return 0;
}

/* The lifting handle (rom.h): a moving group, a handle among the columns, and nothing the lifted
 * coordinates would have to give way to (contact moves the body by its barrier alone). */
static int set_lift(rk_rom_model *m, const rk_fom_options *opt, int r, rk_error *err)
{
    if (opt->lift_handle == 0 && opt->lift_group == 0) return 0;
    int g = opt->lift_group - 1, h = opt->lift_handle - 1;
    if (g < 0 || g >= opt->nprescribed || opt->prescribed[g].kind == RK_MOTION_FIXED)
        return rk_fail(err, "the lifted group %d is not a moving prescribed group (%d groups)", g, opt->nprescribed);
    if (h < 0 || 12 * (h + 1) > r || r % 12)
        return rk_fail(err, "the lifting handle %d is not a skinning handle of the %d columns", h, r);
    if (m->has_contact)
        return rk_fail(err, "a lifted moving group (clamp \"lifted\") with contact: not yet (the prescribed "
                       "coordinates cannot give way to the barrier); use clamp \"dirichlet\"");
    m->lift_handle = h + 1;
    m->lift_motion = opt->prescribed[g];
    m->lift_motion.verts = NULL;
    m->lift_motion.count = 0;
    /* lift_fix: the M-orthogonal projection with the lifted coordinates given is the free one
     * corrected by -P_ff^-1 P_fL dq_L; P is the projection's mass (rk_rom_project's factor) */
    int nf = r - 12, l0 = 12 * h;
    double *P = rk_calloc((size_t)r * r, sizeof(double), err), *Pff = rk_calloc((size_t)nf * nf + 1, sizeof(double), err);
    m->lift_fix = rk_calloc((size_t)r * 12, sizeof(double), err);
    int rc = -1;
    if (!P || !Pff || !m->lift_fix) goto out;
    if (m->M_proj_chol) { /* P = R^T R from its upper factor (dpotrf left the lower triangle as it was) */
        for (int j = 0; j < r; j++)
            for (int i = 0; i <= j; i++) P[i + (size_t)r * j] = m->M_proj_chol[i + (size_t)r * j];
        double *Rf = P;
        P = rk_calloc((size_t)r * r, sizeof(double), err);
        if (P) cblas_dsyrk(CblasColMajor, CblasUpper, CblasTrans, r, r, 1.0, Rf, r, 0.0, P, r);
        free(Rf);
        if (!P) goto out;
    } else
        memcpy(P, m->M, sizeof(double) * r * r);
    for (int j = 0; j < r; j++) /* both triangles */
        for (int i = j + 1; i < r; i++) P[i + (size_t)r * j] = P[j + (size_t)r * i];
    double *B = rk_calloc((size_t)nf * 12 + 1, sizeof(double), err);
    if (!B) goto out;
    for (int j = 0, jj = 0; j < r; j++) {
        if (j >= l0 && j < l0 + 12) continue;
        for (int i = 0, ii = 0; i < r; i++) {
            if (i >= l0 && i < l0 + 12) continue;
            Pff[ii++ + (size_t)nf * jj] = P[i + (size_t)r * j];
        }
        for (int c = 0; c < 12; c++) B[jj + (size_t)nf * c] = -P[j + (size_t)r * (l0 + c)];
        jj++;
    }
    if (nf > 0 && LAPACKE_dposv(LAPACK_COL_MAJOR, 'U', nf, 12, Pff, nf, B, nf) != 0) {
        free(B);
        rk_fail(err, "the lifting handle: the other coordinates' mass is singular");
        goto out;
    }
    for (int i = 0, ii = 0; i < r; i++)
        if (i < l0 || i >= l0 + 12)
            for (int c = 0, k = ii++; c < 12; c++) m->lift_fix[i + (size_t)r * c] = B[k + (size_t)nf * c];
    free(B);
    rc = 0;
out:
    free(P);
    free(Pff);
    return rc;
}

void rk_rom_lift_values(const rk_rom_model *m, double t, double ql[12])
{
    double R[9], shift[3];
    rk_prescribed_transform(&m->lift_motion, t, R, shift);
    /* column 12 j + 4 a + b of rk_skinning_to_U moves x_a by w_j X_b (b < 3) or w_j (b = 3) */
    for (int a = 0; a < 3; a++) {
        for (int b = 0; b < 3; b++) ql[4 * a + b] = R[3 * a + b] - (a == b);
        ql[4 * a + 3] = shift[a];
    }
}

void rk_rom_lift(const rk_rom_model *m, double t, double *q)
{
    if (m->lift_handle) rk_rom_lift_values(m, t, q + 12 * (size_t)(m->lift_handle - 1));
}

int rk_rom_model_init(rk_rom_model *m, const rk_fem *fem, const rk_fom_options *opt, const double *U,
                      int r, rk_quadrature *quad, const rk_skin_points *points, rk_error *err)
{
    memset(m, 0, sizeof *m);
    m->quad = *quad;
    memset(quad, 0, sizeof *quad);
    if (points && r != 12 * points->H) {
        rk_rom_model_free(m);
        return rk_fail(err, "reduced model: %d columns, but the integration points carry %d handles", r, points->H);
    }
    if (r < 1 || m->quad.r != r) {
        rk_rom_model_free(m);
        return rk_fail(err, "reduced model: %d columns, but the quadrature has %d", r, m->quad.r);
    }
    if (rk_fom_check_options(opt, fem->nv, err)) {
        rk_rom_model_free(m);
        return rk_error_prefix(err, "reduced model");
    }
    if (opt->nchambers > 0) {
        rk_rom_model_free(m);
        return rk_fail(err, "reduced model: pressure chambers act at full order and on Koopman models (romkit fom, "
                       "control), not on a reduced model yet (%d given)", opt->nchambers);
    }
    for (size_t i = 0; i < (size_t)3 * fem->nv * r; i++)
        if (!isfinite(U[i])) {
            rk_rom_model_free(m);
            return rk_fail(err, "reduced model: basis entry (%zu, %zu) is not finite", i % (3 * (size_t)fem->nv),
                           i / (3 * (size_t)fem->nv));
        }
    m->r = r;
    m->nv = fem->nv;
    m->h = opt->h;
    m->static_time = opt->steps * opt->h;
    m->integrator = opt->integrator;
    m->is_static = opt->is_static;
    m->newton_max_iter = rk_fom_max_iter(opt, 1); /* what the asset's HEAD carries */
    for (int v = 0; v < fem->nv; v++) m->mass += fem->vertex_mass[v];
    double tol = opt->newton_tol > 0 ? opt->newton_tol : RK_FOM_DEFAULT_TOL * rk_points_diagonal(fem->X, fem->nv);
    m->newton_tol = tol * opt->h;
    if (build_matrices(m, fem, opt, U, points, err) || build_pins(m, fem, opt, U, points, err) ||
        rk_rom_contact_init(m, fem, opt, U, err) || set_lift(m, opt, r, err)) {
        rk_rom_model_free(m);
        return rk_error_prefix(err, "reduced model");
    }
    return 0;
}

void rk_rom_model_free(rk_rom_model *m)
{
    free(m->M);
    free(m->M_chol);
    free(m->M_proj_chol);
    free(m->lift_fix);
    free(m->C);
    free(m->f);
    free(m->A);
    for (int g = 0; m->pins && g < m->npins; g++) free(m->pins[g].T);
    free(m->pins);
    if (m->has_contact || m->colliders_contact) rk_contact_free(&m->contact);
    free(m->cv_rows);
    free(m->cv_of);
    free(m->cv);
    free(m->cv_X);
    rk_quadrature_free(&m->quad);
    memset(m, 0, sizeof *m);
}
