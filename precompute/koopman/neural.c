/* Neural, discretization-agnostic DMD (koopman.h; koopman-dmd-log-linear paper, Sec. 5, Eq. 22-24,
 * Fig. 6, with Sec. 5.2's realified operator): modes as an MLP of the rest position and the shape
 * code, phi(gamma, x); eigenvalues as bounded block parameters, free (g = 0) or the output of an
 * MLP of gamma, Lambda(gamma); trained on several meshes of one object or of a family at once. */
#include "koopman/koopman.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void rk_koopman_neural_default_options(rk_koopman_neural_options *o)
{
    memset(o, 0, sizeof *o);
    o->rank = 12;
    o->hidden = 64;
    o->depth = 3;
    o->init_mesh = -1;
    o->pretrain_epochs = 300;
    o->epochs = 400;
    o->base_lr = 2e-4;
    o->h = 0.01;
    o->seed = 1;
    o->window = 1;
    o->shape_dim = 0;
    o->eig_hidden = 32;
    o->eig_depth = 2;
    o->vertices = 4096;
}

void rk_koopman_neural_free(rk_koopman_neural *nk)
{
    free(nk->block);
    free(nk->eig);
    free(nk->gamma_lo);
    free(nk->gamma_hi);
    rk_mlp_free(&nk->net);
    rk_mlp_free(&nk->eignet);
    memset(nk, 0, sizeof *nk);
}

static double sigmoid(double s) { return 1 / (1 + exp(-s)); }
static double logit(double p) { return log(p / (1 - p)); }

/* Eq. 24 by construction: a real block's lambda = tanh(s); a pair's rho = sigmoid(s) < 1 at the
 * angle theta = pi sigmoid(t) in (0, pi), so b = rho sin theta > 0 as the classical real form has
 * it at a pair's first coordinate. */
static void eigenvalues(const rk_koopman_neural *nk, const double *raw, double *re, double *im)
{
    for (int j = 0; j < nk->r; j++) {
        if (nk->block[j] == 1) {
            re[j] = tanh(raw[j]);
            im[j] = 0;
        } else if (nk->block[j] == 2) {
            double rho = sigmoid(raw[j]), th = M_PI * sigmoid(raw[j + 1]);
            re[j] = re[j + 1] = rho * cos(th);
            im[j] = rho * sin(th);
            im[j + 1] = -im[j];
        }
    }
}

/* The normalised shape code (gamma - mid) / half over the training range, g values. */
static void shape_input(const rk_koopman_neural *nk, const double *gamma, double *in)
{
    for (int c = 0; c < nk->g; c++) {
        double half = 0.5 * (nk->gamma_hi[c] - nk->gamma_lo[c]);
        in[c] = (gamma[c] - 0.5 * (nk->gamma_hi[c] + nk->gamma_lo[c])) / (half > 0 ? half : 1);
    }
}

/* The raw eigenvalue parameters (r) at shape code gamma: the free ones with g = 0, else the
 * eigenvalue network's output Lambda(gamma) before Eq. 24's bounding maps (Sec. 5). */
static int raw_eigs(const rk_koopman_neural *nk, const double *gamma, double *raw, rk_error *err)
{
    if (nk->g == 0) {
        memcpy(raw, nk->eig, sizeof(double) * nk->r);
        return 0;
    }
    double in[RK_KOOPMAN_SHAPE_MAX];
    rk_mlp_work w;
    shape_input(nk, gamma, in);
    if (rk_mlp_work_init(&w, &nk->eignet, 1, 0, err)) return -1;
    int rc = rk_mlp_forward(&nk->eignet, &w, 1, in, raw, err);
    rk_mlp_work_free(&w);
    return rc;
}

/* A shape code as the model takes it: g finite values (NULL only when g = 0). */
static int check_gamma(const rk_koopman_neural *nk, const double *gamma, rk_error *err)
{
    if (nk->g > 0 && !gamma) return rk_fail(err, "neural DMD: no shape code given; the model takes %d values", nk->g);
    for (int c = 0; c < nk->g; c++)
        if (!isfinite(gamma[c])) return rk_fail(err, "neural DMD: shape code component %d is %g", c, gamma[c]);
    return 0;
}

int rk_koopman_neural_eigenvalues(const rk_koopman_neural *nk, const double *gamma, double *re, double *im,
                                  rk_error *err)
{
    if (check_gamma(nk, gamma, err)) return -1;
    double *raw = rk_calloc((size_t)nk->r, sizeof(double), err);
    int rc = raw ? raw_eigs(nk, gamma, raw, err) : -1;
    if (!rc) eigenvalues(nk, raw, re, im);
    free(raw);
    return rc;
}

/* B (r x r, column-major) from the raw parameters: the realified operator's blocks, y <- B y
 * (koopman.h's real form). */
static void block_matrix(const rk_koopman_neural *nk, const double *raw, double *B)
{
    int r = nk->r;
    memset(B, 0, sizeof(double) * (size_t)r * r);
    for (int j = 0; j < r; j++) {
        if (nk->block[j] == 1) {
            B[(size_t)r * j + j] = tanh(raw[j]);
        } else if (nk->block[j] == 2) { /* [[a, b], [-b, a]] */
            double rho = sigmoid(raw[j]), th = M_PI * sigmoid(raw[j + 1]);
            double a = rho * cos(th), b = rho * sin(th);
            B[(size_t)r * j + j] = B[(size_t)r * (j + 1) + j + 1] = a;
            B[(size_t)r * (j + 1) + j] = b;
            B[(size_t)r * j + j + 1] = -b;
        }
    }
}

/* dL/d(raw) from dL/dB (r x r, column-major), by the chain rule through the parametrisation. */
static void block_grad(const rk_koopman_neural *nk, const double *raw, const double *dB, double *g)
{
    int r = nk->r;
    for (int j = 0; j < r; j++) {
        if (nk->block[j] == 1) {
            double l = tanh(raw[j]);
            g[j] = dB[(size_t)r * j + j] * (1 - l * l);
        } else if (nk->block[j] == 2) {
            double sr = sigmoid(raw[j]), st = sigmoid(raw[j + 1]);
            double rho = sr, th = M_PI * st, c = cos(th), s = sin(th);
            double da = dB[(size_t)r * j + j] + dB[(size_t)r * (j + 1) + j + 1];
            double db = dB[(size_t)r * (j + 1) + j] - dB[(size_t)r * j + j + 1];
            double drho = da * c + db * s, dth = rho * (-da * s + db * c);
            g[j] = drho * sr * (1 - sr);
            g[j + 1] = dth * M_PI * st * (1 - st);
        }
    }
}

/* The modes network's input for rest positions X (3 nv) of shape gamma: [(x - center) / scale;
 * the normalised gamma] (Sec. 5: phi(gamma, x)), row-major nv x (3 + g). */
static void inputs(const rk_koopman_neural *nk, const double *X, int nv, const double *gamma, double *in)
{
    int w = 3 + nk->g;
    for (int p = 0; p < nv; p++) {
        for (int c = 0; c < 3; c++) in[(size_t)w * p + c] = (X[3 * p + c] - nk->center[c]) / nk->scale;
        if (nk->g) shape_input(nk, gamma, in + (size_t)w * p + 3);
    }
}

/* Network outputs of vertices p0 .. p0 + count - 1 (count x 6r, row-major) -> their rows of Phi
 * (6 nv x r, column-major). */
static void outputs_to_phi_rows(const double *Y, int nv, int p0, int count, int r, double *Phi)
{
    size_t D = 6 * (size_t)nv;
    for (int q = 0; q < count; q++)
        for (int j = 0; j < r; j++)
            for (int c = 0; c < 6; c++) {
                size_t p = (size_t)p0 + q, row = c < 3 ? 3 * p + c : 3 * (size_t)nv + 3 * p + c - 3;
                Phi[D * j + row] = Y[(size_t)6 * r * q + 6 * j + c];
            }
}

/* Network outputs (nv x 6r, row-major) <-> Phi (6 nv x r, column-major). */
static void outputs_to_phi(const double *Y, int nv, int r, double *Phi) { outputs_to_phi_rows(Y, nv, 0, nv, r, Phi); }

static void phi_to_outputs(const double *Phi, int nv, int r, double *Y)
{
    size_t D = 6 * (size_t)nv;
    for (int p = 0; p < nv; p++)
        for (int j = 0; j < r; j++)
            for (int c = 0; c < 6; c++) {
                size_t row = c < 3 ? 3 * (size_t)p + c : 3 * (size_t)nv + 3 * (size_t)p + c - 3;
                Y[(size_t)6 * r * p + 6 * j + c] = Phi[D * j + row];
            }
}

int rk_koopman_neural_modes(const rk_koopman_neural *nk, const double *X, int nv, const double *gamma, double *Phi,
                            rk_error *err)
{
    if (check_gamma(nk, gamma, err)) return -1;
    rk_mlp_work w;
    int nb = nv < RK_KOOPMAN_NEURAL_BLOCK ? nv : RK_KOOPMAN_NEURAL_BLOCK; /* rows per pass: bounded memory */
    double *in = rk_calloc((size_t)nb * (3 + nk->g), sizeof(double), err);
    double *Y = rk_calloc((size_t)nb * 6 * nk->r, sizeof(double), err);
    int rc = -1;
    if (!in || !Y || rk_mlp_work_init(&w, &nk->net, nb, 0, err)) goto done;
    rc = 0;
    for (int p0 = 0; !rc && p0 < nv; p0 += nb) {
        int count = nv - p0 < nb ? nv - p0 : nb;
        inputs(nk, X + 3 * (size_t)p0, count, gamma, in);
        rc = rk_mlp_forward(&nk->net, &w, count, in, Y, err);
        if (!rc) outputs_to_phi_rows(Y, nv, p0, count, nk->r, Phi);
    }
    rk_mlp_work_free(&w);
done:
    free(in);
    free(Y);
    return rc;
}

/* One mesh's training pairs in the scaled lifted space (as fit.c's snapshot_pairs, with beta):
 * Xp = X^+_t = [u_t; beta (u_t - u_{t-1} + a h^2)] (Eq. 18-19), Xn = X_{t+1}; 6 nv x M each. */
typedef struct {
    int nv, M, ntraj;
    const double *gamma;          /* the mesh's shape code (g values) */
    double *in, *Xp, *Xn, weight; /* weight: 1 / (M E_m) */
    double *F;                    /* 6 nv x ntraj: each trajectory's impulse [0; beta a h^2] (Eq. 19) */
    int *traj, *last;             /* M: a column's trajectory, and that trajectory's last column */
} mesh_data;

static int mesh_data_init(mesh_data *md, const rk_koopman_neural *nk, const rk_koopman_neural_mesh *m, rk_error *err)
{
    memset(md, 0, sizeof *md);
    int d = 3 * m->nv, M = 0;
    size_t D = 2 * (size_t)d;
    double beta = nk->vscale, h2 = nk->h * nk->h;
    for (int k = 0; k < m->ntraj; k++) {
        if (m->traj[k].frames < 3) return rk_fail(err, "trajectory %d has %d frames (3 at least)", k, m->traj[k].frames);
        M += m->traj[k].frames - 2;
    }
    if (check_gamma(nk, m->gamma, err)) return -1;
    md->nv = m->nv;
    md->M = M;
    md->gamma = m->gamma;
    md->in = rk_calloc((size_t)m->nv * (3 + nk->g), sizeof(double), err);
    md->Xp = rk_calloc(D * M, sizeof(double), err);
    md->Xn = rk_calloc(D * M, sizeof(double), err);
    md->ntraj = m->ntraj;
    md->F = rk_calloc(D * (size_t)m->ntraj, sizeof(double), err);
    md->traj = rk_calloc((size_t)M, sizeof(int), err);
    md->last = rk_calloc((size_t)M, sizeof(int), err);
    if (!md->in || !md->Xp || !md->Xn || !md->F || !md->traj || !md->last) return -1;
    for (int k = 0, c0 = 0; k < m->ntraj; c0 += m->traj[k].frames - 2, k++) {
        for (int c = c0; c < c0 + m->traj[k].frames - 2; c++) md->traj[c] = k, md->last[c] = c0 + m->traj[k].frames - 3;
        for (int i = 0; m->traj[k].accel && i < d; i++) md->F[D * k + d + i] = beta * m->traj[k].accel[i] * h2;
    }
    inputs(nk, m->X, m->nv, m->gamma, md->in);
    double e = 0;
    int c = 0;
    for (int k = 0; k < m->ntraj; k++)
        for (int t = 1; t + 1 < m->traj[k].frames; t++, c++) {
            const double *up = m->traj[k].u + (size_t)d * (t - 1), *u = up + d, *un = u + d, *a = m->traj[k].accel;
            double *x = md->Xp + D * c, *y = md->Xn + D * c;
            for (int i = 0; i < d; i++) {
                if (!isfinite(un[i]) || !isfinite(up[i])) return rk_fail(err, "trajectory %d frame %d: not finite", k, t);
                x[i] = u[i];
                x[d + i] = beta * (u[i] - up[i] + (a ? a[i] * h2 : 0));
                y[i] = un[i];
                y[d + i] = beta * (un[i] - u[i]);
                e += y[i] * y[i] + y[d + i] * y[d + i];
            }
        }
    if (!(e > 0)) return rk_fail(err, "the trajectories do not move");
    md->weight = 1 / e; /* 1 / (M E_m) with E_m = e / M */
    return 0;
}

static void mesh_data_free(mesh_data *md)
{
    free(md->F);
    free(md->traj);
    free(md->last);
    free(md->in);
    free(md->Xp);
    free(md->Xn);
}

/* L for one mesh (Eq. 22 + Eq. 23, see koopman.h) and, when dPhi is not NULL, its gradient with
 * respect to Phi (6 nv x r, written) and B (dB, r x r, added to), through the least-squares
 * projections:
 *   y = G^-1 Phi^T x, G = Phi^T Phi;  e = x - Phi y;  g = G^-1 Phi^T F (the impulse's coordinates);
 *   a_1 = B y,  a_{k+1} = B (a_k + g)  (the forced rollout of Eq. 19 over a window of K steps);
 *   s_k = Phi a_k - X_{t+k}  (k = 1..K while the trajectory lasts; K = 1 is Eq. 23 itself).
 * L = w (|e|^2 + (1/K) sum_k |s_k|^2). Reconstruction: y minimises |e|^2, so only its explicit
 * dependence counts: -2 e y^T. Rollout, by reverse accumulation through the recurrence:
 * l_k = dL/da_k = 2 Phi^T s_k / K + B^T l_{k+1};  dB += l_1 y^T + sum_{k>=2} l_k (a_{k-1} + g)^T;
 * dL/dy = B^T l_1 and dL/dg = sum_{k>=2} B^T l_k (summed over a trajectory's columns). Explicitly
 * dPhi += sum_k 2 s_k a_k^T / K; through a projection p = G^-1 Phi^T v with gradient h
 * (dp = G^-1 (dPhi^T (v - Phi p) - Phi^T dPhi p)): (v - Phi p) q^T - Phi q p^T, q = G^-1 h.
 * Everything times the mesh's weight w. */
static int mesh_loss(const mesh_data *md, int r, int K, const double *Phi, const double *B, double *dPhi, double *dB,
                     double *loss, rk_error *err)
{
    size_t D = 6 * (size_t)md->nv, RM = (size_t)r * md->M;
    int M = md->M, nt = md->ntraj, rc = -1;
    double w = md->weight, wk = 2.0 / K;
    double *G = rk_calloc((size_t)r * r, sizeof(double), err);
    double *Y = rk_calloc(RM, sizeof(double), err);
    double *g = rk_calloc((size_t)r * nt, sizeof(double), err);
    double *Gm = rk_calloc(RM, sizeof(double), err);      /* g of each column's trajectory */
    double *A = rk_calloc(RM * K, sizeof(double), err);   /* a_1 .. a_K */
    double *L = rk_calloc(RM * K, sizeof(double), err);   /* l_1 .. l_K */
    double *T = rk_calloc(RM, sizeof(double), err);
    double *E = rk_calloc(D * M, sizeof(double), err);
    double *S = rk_calloc(D * M, sizeof(double), err);
    double *EF = rk_calloc(D * nt, sizeof(double), err);
    double *dg = rk_calloc((size_t)r * nt, sizeof(double), err);
    double *QY = rk_calloc((size_t)r * r, sizeof(double), err);
    if (!G || !Y || !g || !Gm || !A || !L || !T || !E || !S || !EF || !dg || !QY) goto done;
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, r, (int)D, 1.0, Phi, (int)D, Phi, (int)D, 0.0, G, r);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, M, (int)D, 1.0, Phi, (int)D, md->Xp, (int)D, 0.0, Y, r);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, nt, (int)D, 1.0, Phi, (int)D, md->F, (int)D, 0.0, g, r);
    int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', r, G, r);
    if (info) {
        rk_fail(err, "the modes are linearly dependent on a mesh of %d vertices (Cholesky of Phi^T Phi, info %d)",
                md->nv, info);
        goto done;
    }
    LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', r, M, G, r, Y, r); /* y = Phi^* x (Eq. 22's least squares) */
    LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', r, nt, G, r, g, r);
    for (int c = 0; c < M; c++) memcpy(Gm + (size_t)r * c, g + (size_t)r * md->traj[c], sizeof(double) * r);
    memcpy(E, md->Xp, sizeof(double) * D * M);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, (int)D, M, r, -1.0, Phi, (int)D, Y, r, 1.0, E, (int)D);
    double le = cblas_ddot((int)(D * M), E, 1, E, 1), ls = 0;
    if (dPhi)
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, (int)D, r, M, -2 * w, E, (int)D, Y, r, 0.0, dPhi, (int)D);
    /* forward: a_k, s_k (columns whose step k runs past their trajectory: s = 0), l_k's own part */
    for (int k = 1; k <= K; k++) {
        double *a = A + RM * (k - 1);
        if (k == 1) {
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, r, M, r, 1.0, B, r, Y, r, 0.0, a, r);
        } else {
            for (size_t i = 0; i < RM; i++) T[i] = (a - RM)[i] + Gm[i];
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, r, M, r, 1.0, B, r, T, r, 0.0, a, r);
        }
        for (int c = 0; c < M; c++) {
            double *sc = S + D * c;
            if (c + k - 1 > md->last[c]) {
                memset(sc, 0, sizeof(double) * D);
                continue;
            }
            memcpy(sc, md->Xn + D * (c + k - 1), sizeof(double) * D);
            cblas_dgemv(CblasColMajor, CblasNoTrans, (int)D, r, 1.0, Phi, (int)D, a + (size_t)r * c, 1, -1.0, sc, 1);
        }
        ls += cblas_ddot((int)(D * M), S, 1, S, 1);
        if (dPhi) {
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, (int)D, r, M, wk * w, S, (int)D, a, r, 1.0, dPhi,
                        (int)D);
            cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, M, (int)D, wk, Phi, (int)D, S, (int)D, 0.0,
                        L + RM * (k - 1), r);
        }
    }
    *loss = w * (le + ls / K);
    if (dPhi) {
        /* backward through the recurrence */
        for (int k = K - 1; k >= 1; k--)
            cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, M, r, 1.0, B, r, L + RM * k, r, 1.0,
                        L + RM * (k - 1), r);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, r, r, M, w, L, r, Y, r, 1.0, dB, r);
        for (int k = 2; k <= K; k++) {
            for (size_t i = 0; i < RM; i++) T[i] = A[RM * (k - 2) + i] + Gm[i];
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, r, r, M, w, L + RM * (k - 1), r, T, r, 1.0, dB, r);
        }
        /* dL/dg per column: sum_{k>=2} B^T l_k, gathered per trajectory */
        memset(T, 0, sizeof(double) * RM);
        for (int k = 2; k <= K; k++)
            cblas_daxpy((int)RM, 1.0, L + RM * (k - 1), 1, T, 1);
        double *Tg = Gm; /* Gm is free now */
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, M, r, 1.0, B, r, T, r, 0.0, Tg, r);
        for (int c = 0; c < M; c++) cblas_daxpy(r, 1.0, Tg + (size_t)r * c, 1, dg + (size_t)r * md->traj[c], 1);
        /* dL/dy = B^T l_1 */
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, M, r, 1.0, B, r, L, r, 0.0, T, r);
        /* through y: e q^T - Phi q y^T, q = G^-1 dL/dy */
        LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', r, M, G, r, T, r);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, (int)D, r, M, w, E, (int)D, T, r, 1.0, dPhi, (int)D);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, r, r, M, 1.0, T, r, Y, r, 0.0, QY, r);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, (int)D, r, r, -w, Phi, (int)D, QY, r, 1.0, dPhi, (int)D);
        /* through g: e_F q_F^T - Phi q_F g^T */
        memcpy(EF, md->F, sizeof(double) * D * nt);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, (int)D, nt, r, -1.0, Phi, (int)D, g, r, 1.0, EF, (int)D);
        LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', r, nt, G, r, dg, r);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, (int)D, r, nt, w, EF, (int)D, dg, r, 1.0, dPhi, (int)D);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, r, r, nt, 1.0, dg, r, g, r, 0.0, QY, r);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, (int)D, r, r, -w, Phi, (int)D, QY, r, 1.0, dPhi, (int)D);
    }
    rc = 0;
done:
    free(G);
    free(Y);
    free(g);
    free(Gm);
    free(A);
    free(L);
    free(T);
    free(E);
    free(S);
    free(EF);
    free(dg);
    free(QY);
    return rc;
}

/* The raw eigenvalue parameters of every mesh (nmesh x r, row-major): the free ones repeated
 * (g = 0), or one batched pass of the eigenvalue network over the meshes' codes (its activations
 * stay in we for the backward pass). */
static int mesh_eigs(const rk_koopman_neural *nk, const mesh_data *md, int nmesh, rk_mlp_work *we, double *raw,
                     rk_error *err)
{
    int r = nk->r, g = nk->g;
    if (g == 0) {
        for (int m = 0; m < nmesh; m++) memcpy(raw + (size_t)r * m, nk->eig, sizeof(double) * r);
        return 0;
    }
    double *in = rk_calloc((size_t)nmesh * g, sizeof(double), err);
    if (!in) return -1;
    for (int m = 0; m < nmesh; m++) shape_input(nk, md[m].gamma, in + (size_t)g * m);
    int rc = rk_mlp_forward(&nk->eignet, we, nmesh, in, raw, err);
    free(in);
    return rc;
}

/* L over all meshes and (grad not NULL) its gradient: grad_net (the modes network's params
 * layout, zeroed here) and grad_eig (rk_koopman_neural_eig_params: r free parameters with g = 0,
 * accumulated through one dL/dB; else each mesh's dL/d(raw) run back through the eigenvalue
 * network). we: the eigenvalue network's workspace (g > 0, batch nmesh). */
static int total_loss(rk_koopman_neural *nk, mesh_data *md, int nmesh, rk_mlp_work *w, rk_mlp_work *we,
                      double *grad_net, double *grad_eig, double *loss, rk_error *err)
{
    int r = nk->r, rc = -1, maxnv = 0;
    for (int m = 0; m < nmesh; m++)
        if (md[m].nv > maxnv) maxnv = md[m].nv;
    size_t D = 6 * (size_t)maxnv;
    double *B = rk_calloc((size_t)r * r, sizeof(double), err), *dB = rk_calloc((size_t)r * r, sizeof(double), err);
    double *Yo = rk_calloc(D * r, sizeof(double), err), *Phi = rk_calloc(D * r, sizeof(double), err);
    double *dPhi = rk_calloc(D * r, sizeof(double), err);
    double *raw = rk_calloc((size_t)r * nmesh, sizeof(double), err), *draw = rk_calloc((size_t)r * nmesh, sizeof(double), err);
    if (!B || !dB || !Yo || !Phi || !dPhi || !raw || !draw || mesh_eigs(nk, md, nmesh, we, raw, err)) goto done;
    if (grad_net) memset(grad_net, 0, sizeof(double) * rk_mlp_params(&nk->net));
    *loss = 0;
    for (int m = 0; m < nmesh; m++) {
        double l;
        block_matrix(nk, raw + (size_t)r * m, B);
        if (nk->g) memset(dB, 0, sizeof(double) * r * r);
        if (rk_mlp_forward(&nk->net, w, md[m].nv, md[m].in, Yo, err)) goto done;
        outputs_to_phi(Yo, md[m].nv, r, Phi);
        if (mesh_loss(&md[m], r, nk->window, Phi, B, grad_net ? dPhi : NULL, dB, &l, err)) goto done;
        *loss += l;
        if (grad_net) {
            phi_to_outputs(dPhi, md[m].nv, r, Yo);
            if (rk_mlp_backward(&nk->net, w, Yo, grad_net, NULL, err)) goto done;
        }
        if (grad_eig && nk->g) block_grad(nk, raw + (size_t)r * m, dB, draw + (size_t)r * m);
    }
    if (grad_eig && !nk->g) block_grad(nk, raw, dB, grad_eig);
    if (grad_eig && nk->g) {
        memset(grad_eig, 0, sizeof(double) * rk_mlp_params(&nk->eignet));
        if (rk_mlp_backward(&nk->eignet, we, draw, grad_eig, NULL, err)) goto done;
    }
    rc = 0;
done:
    free(B);
    free(dB);
    free(Yo);
    free(Phi);
    free(dPhi);
    free(raw);
    free(draw);
    return rc;
}

double *rk_koopman_neural_eig_params(rk_koopman_neural *nk, long *count)
{
    *count = nk->g ? rk_mlp_params(&nk->eignet) : nk->r;
    return nk->g ? nk->eignet.params : nk->eig;
}

/* With g > 0: the eigenvalue network starts as the constant raw (r values): its output layer's
 * weights zero and its bias raw, so Lambda(gamma) is the classical start's spectrum at every
 * gamma and training learns the dependence (the output layer's gradient is not zero there). */
static void eignet_constant(rk_koopman_neural *nk, const double *raw)
{
    rk_mlp *e = &nk->eignet;
    int L = e->nlayers, out = e->sizes[L], in = e->sizes[L - 1];
    double *W = e->params + e->offset[L - 1];
    memset(W, 0, sizeof(double) * (size_t)out * in);
    memcpy(W + (size_t)out * in, raw, sizeof(double) * out);
}

/* With g > 0, after the regression at m0's code gamma0 (normalised, g values): the modes network
 * made independent of gamma without changing its output at gamma0, the first layer's gamma
 * weights folded into its bias (b += W_gamma gamma0) and zeroed. Every shape of the family then
 * starts from the same modes field, so that the codes between the training ones start from a
 * consistent basis (a mode's sign or a pair's phase is not fixed by the loss and could otherwise
 * drift apart from one training shape to the next). */
static void modes_shape_free(rk_koopman_neural *nk, const double *gamma0)
{
    int in = nk->net.sizes[0], out = nk->net.sizes[1];
    double *W = nk->net.params, *b = W + (size_t)in * out;
    for (int o = 0; o < out; o++)
        for (int c = 0; c < nk->g; c++) {
            b[o] += W[(size_t)in * o + 3 + c] * gamma0[c];
            W[(size_t)in * o + 3 + c] = 0;
        }
}

/* The start (koopman.h): a classical DMD of mesh m0 at rank r; its real modes U_r W (the scaled
 * lifted space), each real column and each pair scaled to unit RMS per vertex, are what the
 * network is first regressed onto (at m0's shape code); its eigenvalues (clamped inside the unit
 * circle) start B, or the eigenvalue network's constant output with g > 0. */
static int classical_start(rk_koopman_neural *nk, const rk_koopman_neural_mesh *m, const rk_koopman_neural_options *o,
                           rk_error *err)
{
    rk_koopman k;
    rk_koopman_options ko;
    rk_koopman_default_options(&ko);
    ko.rank = o->rank;
    ko.h = o->h;
    int r = o->rank, d = 3 * m->nv, rc = -1;
    size_t D = 2 * (size_t)d;
    if (rk_koopman_fit(m->traj, m->ntraj, d, &ko, &k, err)) return -1;
    double *Phi = rk_calloc(D * r, sizeof(double), err), *Y = rk_calloc(D * r, sizeof(double), err);
    if (!Phi || !Y) goto done;
    nk->vscale = k.vscale;
    memcpy(nk->block, k.block, sizeof(int) * r);
    if (k.block[r - 1] == 2) {
        rk_fail(err, "rank %d splits a complex pair of the classical start; take one more or one less", r);
        goto done;
    }
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, (int)D, r, r, 1.0, k.U, (int)D, k.W, r, 0.0, Phi, (int)D);
    for (int j = 0; j < r; j++) {
        if (k.block[j] == 0) continue;
        int w = k.block[j] == 2 ? 2 : 1;
        double s = cblas_dnrm2((int)(D * w), Phi + D * j, 1) / sqrt((double)m->nv * w);
        if (s > 0) cblas_dscal((int)(D * w), 1 / s, Phi + D * j, 1);
        const double cap = 1 - 1e-6;
        if (w == 1) {
            double l = fmax(-cap, fmin(cap, k.lambda_re[j]));
            nk->eig[j] = atanh(l);
        } else {
            double rho = fmin(cap, hypot(k.lambda_re[j], k.lambda_im[j]));
            double th = atan2(k.lambda_im[j], k.lambda_re[j]) / M_PI; /* in (0, 1): im > 0 at a pair's first */
            th = fmax(1e-9, fmin(1 - 1e-9, th));
            nk->eig[j] = logit(rho);
            nk->eig[j + 1] = logit(th);
        }
    }
    if (nk->g) eignet_constant(nk, nk->eig);
    phi_to_outputs(Phi, m->nv, r, Y);
    double *in = rk_calloc((size_t)m->nv * (3 + nk->g), sizeof(double), err);
    if (!in) goto done;
    inputs(nk, m->X, m->nv, m->gamma, in);
    rk_mlp_train_options to;
    rk_mlp_train_default_options(&to);
    to.epochs = o->pretrain_epochs;
    to.batch = 32;
    to.base_lr = 1e-3;
    to.seed = o->seed;
    rc = o->pretrain_epochs > 0 ? rk_mlp_train(&nk->net, in, Y, m->nv, &to, NULL, err) : 0;
    if (!rc && nk->g) modes_shape_free(nk, in + 3);
    free(in);
done:
    free(Phi);
    free(Y);
    rk_koopman_free(&k);
    return rc;
}

int rk_koopman_neural_loss(rk_koopman_neural *nk, const rk_koopman_neural_mesh *mesh, int nmesh, double *grad_net,
                           double *grad_eig, double *loss, rk_error *err)
{
    int maxnv = 0, rc = -1;
    mesh_data *md = rk_calloc((size_t)(nmesh > 0 ? nmesh : 1), sizeof *md, err);
    if (!md) return -1;
    rk_mlp_work w, we;
    memset(&w, 0, sizeof w);
    memset(&we, 0, sizeof we);
    for (int m = 0; m < nmesh; m++) {
        if (mesh_data_init(&md[m], nk, &mesh[m], err)) goto done;
        if (mesh[m].nv > maxnv) maxnv = mesh[m].nv;
    }
    if (rk_mlp_work_init(&w, &nk->net, maxnv, 0, err)) goto done;
    if (!nk->g || !rk_mlp_work_init(&we, &nk->eignet, nmesh, 0, err))
        rc = total_loss(nk, md, nmesh, &w, &we, grad_net, grad_eig, loss, err);
    rk_mlp_work_free(&w);
    if (nk->g) rk_mlp_work_free(&we);
done:
    for (int m = 0; m < nmesh; m++) mesh_data_free(&md[m]);
    free(md);
    return rc;
}

/* The training codes' range per component (what the network inputs are normalised by, and what a
 * shape optimisation may move in). */
static int shape_range(rk_koopman_neural *nk, const rk_koopman_neural_mesh *mesh, int nmesh, rk_error *err)
{
    if (!nk->g) return 0;
    nk->gamma_lo = rk_calloc((size_t)nk->g, sizeof(double), err);
    nk->gamma_hi = rk_calloc((size_t)nk->g, sizeof(double), err);
    if (!nk->gamma_lo || !nk->gamma_hi) return -1;
    for (int c = 0; c < nk->g; c++) {
        nk->gamma_lo[c] = nk->gamma_hi[c] = mesh[0].gamma[c];
        for (int m = 1; m < nmesh; m++) {
            nk->gamma_lo[c] = fmin(nk->gamma_lo[c], mesh[m].gamma[c]);
            nk->gamma_hi[c] = fmax(nk->gamma_hi[c], mesh[m].gamma[c]);
        }
    }
    return 0;
}

/* L as an objective of all trainable values, [the modes' network; the eigenvalues' parameters],
 * for the L-BFGS polish. */
typedef struct {
    rk_koopman_neural *nk;
    mesh_data *md;
    int nmesh;
    rk_mlp_work *w, *we;
    long np, ne;
    double *eig;
} polish_ctx;

static int polish_objective(void *ctx, const double *x, double *f, double *g, rk_error *err)
{
    polish_ctx *c = ctx;
    memcpy(c->nk->net.params, x, sizeof(double) * c->np);
    memcpy(c->eig, x + c->np, sizeof(double) * c->ne);
    return total_loss(c->nk, c->md, c->nmesh, c->w, c->we, g, g + c->np, f, err);
}

static int polish(rk_koopman_neural *nk, mesh_data *md, int nmesh, rk_mlp_work *w, rk_mlp_work *we, int iterations,
                  double *loss, int *taken, rk_error *err)
{
    long np = rk_mlp_params(&nk->net), ne;
    double *eig = rk_koopman_neural_eig_params(nk, &ne);
    double *x = rk_calloc((size_t)(np + ne), sizeof(double), err);
    if (!x) return -1;
    memcpy(x, nk->net.params, sizeof(double) * np);
    memcpy(x + np, eig, sizeof(double) * ne);
    polish_ctx c = {nk, md, nmesh, w, we, np, ne, eig};
    rk_lbfgs_options lo = {.iterations = iterations, .memory = 10, .tolerance = 0};
    rk_lbfgs_report rep;
    int rc = rk_lbfgs_minimize(np + ne, x, polish_objective, &c, &lo, &rep, err);
    if (!rc) { /* the best point, whatever the line search evaluated last */
        memcpy(nk->net.params, x, sizeof(double) * np);
        memcpy(eig, x + np, sizeof(double) * ne);
        *loss = rep.final;
        *taken = rep.iterations;
    }
    free(x);
    return rc ? rk_error_prefix(err, "L-BFGS polish") : 0;
}

int rk_koopman_neural_train(const rk_koopman_neural_mesh *mesh, int nmesh, const rk_koopman_neural_options *o,
                            rk_koopman_neural *nk, rk_koopman_neural_report *report, rk_error *err)
{
    memset(nk, 0, sizeof *nk);
    rk_koopman_neural_options def;
    if (!o) {
        rk_koopman_neural_default_options(&def);
        o = &def;
    }
    if (nmesh < 1 || o->rank < 1 || o->hidden < 1 || o->depth < 1 || o->epochs < 0 || o->polish < 0 || !(o->h > 0) ||
        !(o->base_lr > 0) || o->init_mesh >= nmesh || o->window < 1)
        return rk_fail(err, "neural DMD: bad options (%d meshes, rank %d, hidden %d x %d, epochs %d, h %g)", nmesh,
                       o->rank, o->hidden, o->depth, o->epochs, o->h);
    if (o->shape_dim < 0 || o->shape_dim > RK_KOOPMAN_SHAPE_MAX ||
        (o->shape_dim > 0 && (o->eig_hidden < 1 || o->eig_depth < 1 || o->eig_depth > 14)))
        return rk_fail(err, "neural DMD: bad shape options (code of %d values, 0 to %d; eigenvalue network %d x %d)",
                       o->shape_dim, RK_KOOPMAN_SHAPE_MAX, o->eig_hidden, o->eig_depth);
    for (int m = 0; m < nmesh; m++)
        for (int c = 0; c < o->shape_dim; c++)
            if (!mesh[m].gamma || !isfinite(mesh[m].gamma[c]))
                return rk_fail(err, "neural DMD: mesh %d: shape code component %d is %s", m, c,
                               mesh[m].gamma ? "not finite" : "missing (gamma NULL)");
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int r = o->rank, rc = -1, m0 = o->init_mesh < 0 ? nmesh - 1 : o->init_mesh, maxnv = 0;
    mesh_data *md = rk_calloc((size_t)nmesh, sizeof *md, err);
    rk_koopman_neural_sample *smp = rk_calloc((size_t)nmesh, sizeof *smp, err);
    rk_koopman_neural_mesh *sampled = rk_calloc((size_t)nmesh, sizeof *sampled, err);
    int sizes[16];
    if (!md || !smp || !sampled || o->depth > 14 || o->vertices < 0) goto fail;
    nk->r = r;
    nk->h = o->h;
    nk->window = o->window;
    nk->g = o->shape_dim;
    nk->block = rk_calloc((size_t)r, sizeof(int), err);
    nk->eig = rk_calloc((size_t)r, sizeof(double), err);
    if (!nk->block || !nk->eig || shape_range(nk, mesh, nmesh, err)) goto fail;
    /* the input frame: the start mesh's bounding box, centred, its half-diagonal 1 */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int p = 0; p < mesh[m0].nv; p++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], mesh[m0].X[3 * p + c]);
            hi[c] = fmax(hi[c], mesh[m0].X[3 * p + c]);
        }
    double diag = 0;
    for (int c = 0; c < 3; c++) {
        nk->center[c] = 0.5 * (lo[c] + hi[c]);
        diag += (hi[c] - lo[c]) * (hi[c] - lo[c]);
    }
    nk->scale = diag > 0 ? 0.5 * sqrt(diag) : 1;
    /* at resolution (the frame above is the whole start mesh's): every mesh of more than
     * o->vertices vertices trains on a fixed sample of them (neural_sample.c), the classical start
     * and every step of the loss alike; smaller meshes train on all their vertices */
    for (int m = 0; m < nmesh; m++) {
        sampled[m] = mesh[m];
        if (o->vertices > 0 && mesh[m].nv > o->vertices) {
            if (rk_koopman_neural_sample_init(&mesh[m], o->vertices, o->seed + 7919 * (unsigned long long)m, &smp[m],
                                              err)) {
                rk_error_prefix(err, "mesh %d", m);
                goto fail;
            }
            sampled[m] = smp[m].mesh;
        }
    }
    mesh = sampled;
    sizes[0] = 3 + nk->g; /* [x; gamma]: phi(gamma, x) (Sec. 5) */
    for (int l = 1; l <= o->depth; l++) sizes[l] = o->hidden;
    sizes[o->depth + 1] = 6 * r;
    if (rk_mlp_init(&nk->net, o->depth + 2, sizes, o->seed, err)) goto fail;
    if (nk->g) { /* Lambda(gamma): g -> r raw parameters, bounded by Eq. 24's maps */
        sizes[0] = nk->g;
        for (int l = 1; l <= o->eig_depth; l++) sizes[l] = o->eig_hidden;
        sizes[o->eig_depth + 1] = r;
        if (rk_mlp_init(&nk->eignet, o->eig_depth + 2, sizes, o->seed + 1, err)) goto fail;
    }
    if (classical_start(nk, &mesh[m0], o, err)) goto fail;
    for (int m = 0; m < nmesh; m++) {
        if (mesh_data_init(&md[m], nk, &mesh[m], err)) {
            rk_error_prefix(err, "mesh %d", m);
            goto fail;
        }
        if (mesh[m].nv > maxnv) maxnv = mesh[m].nv;
    }
    long np = rk_mlp_params(&nk->net), ne;
    double *eig = rk_koopman_neural_eig_params(nk, &ne);
    rk_mlp_work w, we;
    rk_adam an, ae;
    memset(&we, 0, sizeof we);
    double *gn = rk_calloc((size_t)np, sizeof(double), err), *ge = rk_calloc((size_t)ne, sizeof(double), err);
    if (!gn || !ge || rk_mlp_work_init(&w, &nk->net, maxnv, 0, err)) {
        free(gn);
        free(ge);
        goto fail;
    }
    double loss = 0;
    int ok = !rk_adam_init(&an, np, err) && !rk_adam_init(&ae, ne, err);
    if (ok && nk->g) ok = !rk_mlp_work_init(&we, &nk->eignet, nmesh, 0, err);
    if (ok) ok = !total_loss(nk, md, nmesh, &w, &we, NULL, NULL, &loss, err);
    if (report) report->pretrained_loss = loss;
    for (int e = 0; ok && e < o->epochs; e++) {
        double lr = rk_lr_phased(o->base_lr, e, o->epochs);
        ok = !total_loss(nk, md, nmesh, &w, &we, gn, ge, &loss, err) &&
             !rk_adam_step(&an, nk->net.params, gn, lr, err) && !rk_adam_step(&ae, eig, ge, lr, err);
        if (ok && !isfinite(loss)) ok = !rk_fail(err, "the loss turned non-finite at step %d", e);
    }
    if (ok) ok = !total_loss(nk, md, nmesh, &w, &we, NULL, NULL, &loss, err);
    if (report) report->adam_loss = loss;
    int taken = 0;
    if (ok && o->polish > 0) ok = !polish(nk, md, nmesh, &w, &we, o->polish, &loss, &taken, err);
    if (report) report->polish_iterations = taken;
    rk_adam_free(&an);
    rk_adam_free(&ae);
    rk_mlp_work_free(&w);
    rk_mlp_work_free(&we);
    free(gn);
    free(ge);
    if (!ok) goto fail;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (report) {
        report->final_loss = loss;
        report->seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    }
    rc = 0;
fail:
    for (int m = 0; md && m < nmesh; m++) mesh_data_free(&md[m]);
    for (int m = 0; smp && m < nmesh; m++) rk_koopman_neural_sample_free(&smp[m]);
    free(md);
    free(smp);
    free(sampled);
    if (rc) {
        rk_koopman_neural_free(nk);
        return rk_error_prefix(err, "neural DMD");
    }
    return 0;
}

int rk_koopman_neural_operator(const rk_koopman_neural *nk, const double *X, int nv, const double *gamma, rk_koopman *k,
                               rk_error *err)
{
    memset(k, 0, sizeof *k);
    if (check_gamma(nk, gamma, err)) return -1;
    int r = nk->r, d = 3 * nv, n2 = 2 * d;
    if (n2 < r) return rk_fail(err, "neural DMD: %d vertices carry fewer values than rank %d", nv, r);
    k->n = k->d = d;
    k->r = r;
    k->h = nk->h;
    k->vscale = nk->vscale;
    k->U = rk_calloc((size_t)n2 * r, sizeof(double), err);
    k->K = rk_calloc((size_t)r * r, sizeof(double), err);
    k->lambda_re = rk_calloc((size_t)r, sizeof(double), err);
    k->lambda_im = rk_calloc((size_t)r, sizeof(double), err);
    k->residual = rk_calloc((size_t)r, sizeof(double), err);
    k->W = rk_calloc((size_t)r * r, sizeof(double), err);
    k->Winv = rk_calloc((size_t)r * r, sizeof(double), err);
    k->block = rk_calloc((size_t)r, sizeof(int), err);
    k->singular = rk_calloc((size_t)r, sizeof(double), err);
    double *tau = rk_calloc((size_t)r, sizeof(double), err), *B = rk_calloc((size_t)r * r, sizeof(double), err);
    double *raw = rk_calloc((size_t)r, sizeof(double), err);
    int rc = -1, info;
    if (!k->U || !k->K || !k->lambda_re || !k->lambda_im || !k->residual || !k->W || !k->Winv || !k->block ||
        !k->singular || !tau || !B || !raw)
        goto done;
    if (rk_koopman_neural_modes(nk, X, nv, gamma, k->U, err) || raw_eigs(nk, gamma, raw, err)) goto done;
    /* Phi = Q R: U_r = Q, W = R, so z = Q^T X and y = R^-1 z = Phi^* X, the least-squares
     * coordinates of Eq. 22-23; K' = R B R^-1 steps z as B steps y. */
    info = LAPACKE_dgeqrf(LAPACK_COL_MAJOR, n2, r, k->U, n2, tau);
    for (int j = 0; !info && j < r; j++)
        for (int i = 0; i <= j; i++) k->W[(size_t)r * j + i] = k->U[(size_t)n2 * j + i];
    if (!info) info = LAPACKE_dorgqr(LAPACK_COL_MAJOR, n2, r, r, k->U, n2, tau);
    memcpy(k->Winv, k->W, sizeof(double) * r * r);
    for (int j = 0; !info && j < r; j++)
        if (!(fabs(k->W[(size_t)r * j + j]) > 1e-12 * fabs(k->W[0]))) info = j + 1;
    if (!info) info = LAPACKE_dtrtri(LAPACK_COL_MAJOR, 'U', 'N', r, k->Winv, r);
    if (info) {
        rk_fail(err, "neural DMD: the modes at these %d vertices are linearly dependent (QR info %d)", nv, info);
        goto done;
    }
    for (int j = 0; j < r; j++) k->singular[j] = fabs(k->W[(size_t)r * j + j]);
    k->nsingular = r;
    memcpy(k->block, nk->block, sizeof(int) * r);
    eigenvalues(nk, raw, k->lambda_re, k->lambda_im); /* Lambda(gamma) */
    block_matrix(nk, raw, B);
    double *T = k->K; /* K' = R B R^-1 */
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, r, r, r, 1.0, B, r, k->Winv, r, 0.0, T, r);
    cblas_dtrmm(CblasColMajor, CblasLeft, CblasUpper, CblasNoTrans, CblasNonUnit, r, r, 1.0, k->W, r, T, r);
    rc = 0;
done:
    free(tau);
    free(B);
    free(raw);
    if (rc) rk_koopman_free(k);
    return rc;
}
