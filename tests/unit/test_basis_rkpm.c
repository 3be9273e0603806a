/* precompute/basis RKPM kernels (freeform paper Sec. 3.2): integration points, farthest point
 * sampling, linear reproduction of the corrected shape functions and their gradients, the
 * assembled H_w and M, and the errors for clouds too sparse for their kernels. */
#include "basis/basis.h"
#include "testlib.h"

static double rnd(unsigned *state) /* in [0, 1) */
{
    *state = *state * 1664525u + 1013904223u;
    return (double)(*state >> 8) / (double)(1u << 24);
}

/* Kernels from FPS of a grid sampling of the box [0,size] (cells 8x4x4). */
static int box_kernels(const double size[3], int target, int K, rk_mesh *m, rk_rkpm_points *p, rk_rkpm *k,
                       rk_error *err)
{
    int cells[3] = {8, 4, 4};
    if (rk_mesh_box(size, cells, m, err)) return -1;
    if (rk_rkpm_sample_mesh(m, target, p, err)) return -1;
    int *chosen = calloc((size_t)K, sizeof *chosen);
    double *C = calloc(3 * (size_t)K, sizeof *C);
    int rc = rk_fps(p->X, p->n, K, chosen, err);
    for (int c = 0; rc == 0 && c < K; c++) memcpy(&C[3 * c], &p->X[3 * chosen[c]], 3 * sizeof(double));
    if (rc == 0) rc = rk_rkpm_init(k, C, K, err);
    free(chosen);
    free(C);
    return rc;
}

static int cloud_kernels(int max_points, int K, rk_rkpm_points *p, rk_rkpm *k, rk_error *err)
{
    double *P;
    int n;
    if (rk_points_load(test_data("meshes/donut_3dgs.ply"), &P, &n, err)) return -1;
    int rc = rk_rkpm_sample_cloud(P, n, max_points, p, err);
    free(P);
    if (rc) return -1;
    int *chosen = calloc((size_t)K, sizeof *chosen);
    double *C = calloc(3 * (size_t)K, sizeof *C);
    rc = rk_fps(p->X, p->n, K, chosen, err);
    for (int c = 0; rc == 0 && c < K; c++) memcpy(&C[3 * c], &p->X[3 * chosen[c]], 3 * sizeof(double));
    if (rc == 0) rc = rk_rkpm_init(k, C, K, err);
    free(chosen);
    free(C);
    return rc;
}

/* Largest violation of the linear reproducing conditions (Eq. 8) and of their gradients at X. */
static int reproduction_error(const rk_rkpm *k, const double X[3], double *worst, rk_error *err)
{
    int cap = rk_rkpm_max_support(k);
    int *idx = calloc((size_t)cap, sizeof *idx);
    double *phi = calloc((size_t)cap, sizeof *phi), *grad = calloc(3 * (size_t)cap, sizeof *grad);
    int n = rk_rkpm_eval(k, X, cap, idx, phi, grad, err);
    if (n >= 0) {
        double s = 0, sx[3] = {0, 0, 0}, g[3] = {0, 0, 0}, J[3][3] = {{0}}, r = 0;
        for (int a = 0; a < n; a++) {
            const double *p = &k->centers[3 * idx[a]];
            s += phi[a];
            for (int i = 0; i < 3; i++) {
                sx[i] += phi[a] * p[i];
                g[i] += grad[3 * a + i];
                for (int j = 0; j < 3; j++) J[i][j] += p[i] * grad[3 * a + j];
            }
            r = fmax(r, k->radius[idx[a]]);
        }
        /* Positions and gradients are compared in units of the kernel radius. */
        double e = fabs(s - 1);
        for (int i = 0; i < 3; i++) {
            e = fmax(e, fabs(sx[i] - X[i]) / r);
            e = fmax(e, fabs(g[i]) * r);
            for (int j = 0; j < 3; j++) e = fmax(e, fabs(J[i][j] - (i == j)));
        }
        *worst = fmax(*worst, e);
    }
    free(idx), free(phi), free(grad);
    return n >= 0 ? 0 : -1;
}

TEST(grid_sampling_fills_a_box_mesh)
{
    rk_error err;
    rk_mesh m;
    rk_rkpm_points p;
    double size[3] = {2, 1, 1};
    int cells[3] = {8, 4, 4};
    CHECK_OK(rk_mesh_box(size, cells, &m, &err));
    CHECK_OK(rk_rkpm_sample_mesh(&m, 1000, &p, &err));
    CHECK(p.n > 700 && p.n < 1300, "%d points for a target of 1000", p.n);
    double sum = 0;
    for (int i = 0; i < p.n; i++) sum += p.weight[i];
    CHECK(fabs(sum - 2.0) < 0.05 * 2.0, "weights sum to %g, box volume 2", sum);
    CHECK_CLOSE(p.volume, 2.0, 1e-12);
    for (int i = 0; i < p.n; i++) {
        int t = p.tet[i];
        CHECK(t >= 0 && t < m.nt, "point %d: tet %d", i, t);
        const int *T = &m.tets[4 * t];
        const double *x = &p.X[3 * i];
        double vol = rk_tet_signed_volume(&m.X[3 * T[0]], &m.X[3 * T[1]], &m.X[3 * T[2]], &m.X[3 * T[3]]);
        for (int f = 0; f < 4; f++) { /* barycentric coordinate f: x replaces vertex f */
            const double *v[4];
            for (int c = 0; c < 4; c++) v[c] = c == f ? x : &m.X[3 * T[c]];
            double b = rk_tet_signed_volume(v[0], v[1], v[2], v[3]) / vol;
            CHECK(b >= -1e-9, "point %d (%g, %g, %g) is outside its tet %d (barycentric %g)", i, x[0], x[1], x[2], t, b);
        }
    }
    rk_rkpm_points_free(&p);
    rk_mesh_free(&m);
}

TEST(cloud_sampling_estimates_the_volume_and_downsamples)
{
    rk_error err;
    rk_rkpm_points p;
    /* A 20 x 10 x 10 lattice of spacing 0.1, listed in a scrambled order. */
    int n = 2000;
    double *X = calloc(3 * (size_t)n, sizeof *X);
    for (int q = 0; q < n; q++) {
        int i = (q * 7919) % n; /* 7919 is prime to 2000: a permutation */
        X[3 * q] = 0.1 * (i % 20), X[3 * q + 1] = 0.1 * ((i / 20) % 10), X[3 * q + 2] = 0.1 * (i / 200);
    }
    CHECK_OK(rk_rkpm_sample_cloud(X, n, 5000, &p, &err));
    CHECK(p.n == n && p.tet == NULL && p.source[17] == 17, "n %d", p.n);
    /* Voxels of edge 0.2 over [0,1.9]x[0,0.9]^2: 10 x 5 x 5 of them, 2.0 m^3. */
    CHECK_CLOSE(p.spacing, 0.2, 1e-12);
    CHECK_CLOSE(p.volume, 2.0, 1e-12);
    double sum = 0;
    for (int i = 0; i < p.n; i++) sum += p.weight[i];
    CHECK_CLOSE(sum, 2.0, 1e-12);
    rk_rkpm_points_free(&p);

    CHECK_OK(rk_rkpm_sample_cloud(X, n, 500, &p, &err));
    CHECK(p.n <= 500 && p.n >= 200, "downsampled to %d points (budget 500)", p.n);
    for (int i = 0; i < p.n; i++) {
        CHECK(p.source[i] >= 0 && p.source[i] < n && (i == 0 || p.source[i] > p.source[i - 1]), "source %d", i);
        CHECK(memcmp(&p.X[3 * i], &X[3 * p.source[i]], 3 * sizeof(double)) == 0, "point %d moved", i);
    }
    sum = 0;
    for (int i = 0; i < p.n; i++) sum += p.weight[i];
    CHECK_CLOSE(sum, 2.0, 1e-12); /* the volume comes from all the input points */
    rk_rkpm_points_free(&p);

    X[3 * 2 + 1] = NAN;
    CHECK(rk_rkpm_sample_cloud(X, n, 5000, &p, &err) != 0, "a NaN coordinate was accepted");
    CHECK(strstr(err.msg, "point 2 ") != NULL, "message does not name point 2: %s", err.msg);
    free(X);
}

TEST(fps_is_deterministic_and_spread)
{
    rk_error err;
    /* Points on a line 0..9 plus a far one: FPS starts at the far one, then the far end. */
    double X[33];
    for (int i = 0; i < 10; i++) X[3 * i] = i, X[3 * i + 1] = X[3 * i + 2] = 0;
    X[30] = 100, X[31] = X[32] = 0;
    int chosen[3];
    CHECK_OK(rk_fps(X, 11, 3, chosen, &err));
    CHECK(chosen[0] == 10 && chosen[1] == 0 && chosen[2] == 9, "chose %d %d %d", chosen[0], chosen[1], chosen[2]);
    CHECK(rk_fps(X, 11, 12, chosen, &err) != 0, "12 centres from 11 points");
    CHECK(strstr(err.msg, "12") && strstr(err.msg, "11"), "message: %s", err.msg);
    X[7] = INFINITY;
    CHECK(rk_fps(X, 11, 3, chosen, &err) != 0 && strstr(err.msg, "point 2 "), "inf accepted or not named: %s", err.msg);
    double same[12] = {0, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0};
    CHECK(rk_fps(same, 4, 3, chosen, &err) != 0 && strstr(err.msg, "distinct"), "duplicates: %s", err.msg);
}

TEST(box_kernels_reproduce_linear_fields)
{
    rk_error err;
    rk_mesh m;
    rk_rkpm_points p;
    rk_rkpm k;
    double size[3] = {2, 1, 1};
    CHECK_OK(box_kernels(size, 1000, 100, &m, &p, &k, &err));
    unsigned seed = 11u;
    double worst = 0;
    for (int q = 0; q < 200; q++) {
        double X[3] = {2 * rnd(&seed), rnd(&seed), rnd(&seed)};
        CHECK_OK(reproduction_error(&k, X, &worst, &err));
    }
    CHECK(worst < 1e-10, "linear reproduction violated by %g", worst);
    /* rk_rkpm_interpolate (Eq. 6) of two linear nodal fields at 50 points. */
    double *c = calloc(2 * (size_t)k.K, sizeof *c), X[150], W[100];
    for (int i = 0; i < k.K; i++) {
        const double *pk = &k.centers[3 * i];
        c[i] = 2 * pk[0] - pk[1] + 0.5;
        c[k.K + i] = pk[2] - 3;
    }
    for (int q = 0; q < 150; q++) X[q] = (q % 3 == 0 ? 2 : 1) * rnd(&seed);
    CHECK_OK(rk_rkpm_interpolate(&k, X, 50, c, 2, W, NULL, NULL, &err));
    for (int q = 0; q < 50; q++) {
        CHECK_CLOSE(W[q], 2 * X[3 * q] - X[3 * q + 1] + 0.5, 1e-10);
        CHECK_CLOSE(W[50 + q], X[3 * q + 2] - 3, 1e-10);
    }
    free(c);
    rk_rkpm_free(&k);
    rk_rkpm_points_free(&p);
    rk_mesh_free(&m);
}

TEST(splat_kernels_reproduce_linear_fields)
{
    rk_error err;
    rk_rkpm_points p;
    rk_rkpm k;
    CHECK_OK(cloud_kernels(20000, 500, &p, &k, &err));
    unsigned seed = 5u;
    double worst = 0;
    for (int q = 0; q < 200; q++) {
        /* Integration points, nudged by up to a tenth of the smallest kernel radius. */
        int i = (int)(rnd(&seed) * p.n);
        double X[3];
        for (int d = 0; d < 3; d++) X[d] = p.X[3 * i + d] + 0.1 * k.radius[0] * (2 * rnd(&seed) - 1);
        CHECK_OK(reproduction_error(&k, X, &worst, &err));
    }
    CHECK(worst < 1e-10, "linear reproduction violated by %g", worst);
    rk_rkpm_free(&k);
    rk_rkpm_points_free(&p);
}

/* phi_kid at X (0 when kid does not cover X). */
static double value_of(const rk_rkpm *k, const double X[3], int kid, int *idx, double *phi, rk_error *err)
{
    int n = rk_rkpm_eval(k, X, rk_rkpm_max_support(k), idx, phi, NULL, err);
    for (int a = 0; a < n; a++)
        if (idx[a] == kid) return phi[a];
    return n < 0 ? NAN : 0;
}

TEST(gradients_match_central_differences)
{
    rk_error err;
    rk_mesh m;
    rk_rkpm_points p;
    rk_rkpm k;
    double size[3] = {2, 1, 1};
    CHECK_OK(box_kernels(size, 1000, 100, &m, &p, &k, &err));
    int cap = rk_rkpm_max_support(&k);
    int *idx = calloc((size_t)cap, sizeof *idx), *idx2 = calloc((size_t)cap, sizeof *idx2);
    double *phi = calloc((size_t)cap, sizeof *phi), *grad = calloc(3 * (size_t)cap, sizeof *grad);
    double *phi2 = calloc((size_t)cap, sizeof *phi2);
    unsigned seed = 7u;
    double worst = 0;
    for (int q = 0; q < 20; q++) {
        double X[3] = {2 * rnd(&seed), rnd(&seed), rnd(&seed)};
        int n = rk_rkpm_eval(&k, X, cap, idx, phi, grad, &err);
        CHECK(n >= 4, "eval failed: %s", err.msg);
        double gmax = 0;
        for (int a = 0; a < 3 * n; a++) gmax = fmax(gmax, fabs(grad[a]));
        for (int a = 0; a < n; a++) {
            double h = 1e-6 * k.radius[idx[a]];
            for (int j = 0; j < 3; j++) {
                double Xp[3] = {X[0], X[1], X[2]}, Xm[3] = {X[0], X[1], X[2]};
                Xp[j] += h, Xm[j] -= h;
                double fd = (value_of(&k, Xp, idx[a], idx2, phi2, &err) - value_of(&k, Xm, idx[a], idx2, phi2, &err)) / (2 * h);
                worst = fmax(worst, fabs(fd - grad[3 * a + j]) / gmax);
            }
        }
    }
    CHECK(worst < 1e-6, "analytic and finite-difference gradients differ by %g (relative)", worst);
    free(idx), free(idx2), free(phi), free(grad), free(phi2);
    rk_rkpm_free(&k);
    rk_rkpm_points_free(&p);
    rk_mesh_free(&m);
}

TEST(assembled_matrices_integrate_constant_and_linear_fields)
{
    rk_error err;
    rk_mesh m;
    rk_rkpm_points p;
    rk_rkpm k;
    double size[3] = {2, 1, 1};
    CHECK_OK(box_kernels(size, 3000, 150, &m, &p, &k, &err));
    /* Heterogeneous coefficient (lambda + 4 mu varies along x). */
    double *coef = calloc((size_t)p.n, sizeof *coef), vsum = 0, cvsum = 0;
    for (int i = 0; i < p.n; i++) {
        coef[i] = 1e6 * (1 + 3 * p.X[3 * i]);
        vsum += p.weight[i];
        cvsum += p.weight[i] * coef[i];
    }
    rk_sparse H, M;
    CHECK_OK(rk_rkpm_assemble(&k, p.X, p.weight, coef, p.n, &H, &M, NULL, &err));
    CHECK(H.n == k.K && M.nnz == H.nnz && memcmp(H.rowind, M.rowind, (size_t)H.nnz * sizeof(int)) == 0,
          "H and M patterns differ");
    double hmax = 0;
    for (int c = 0; c < H.n; c++) {
        CHECK(H.colptr[c + 1] > H.colptr[c] && H.rowind[H.colptr[c + 1] - 1] == c, "column %d lacks its diagonal", c);
        for (int s = H.colptr[c]; s < H.colptr[c + 1]; s++) {
            CHECK(H.rowind[s] <= c && (s == H.colptr[c] || H.rowind[s] > H.rowind[s - 1]), "column %d unsorted", c);
            hmax = fmax(hmax, fabs(H.val[s]));
        }
    }
    CHECK(H.nnz < k.K * (k.K + 1) / 2, "pattern is dense (%d entries)", H.nnz);
    double *c = calloc((size_t)k.K, sizeof *c), *Hc = calloc((size_t)k.K, sizeof *Hc);
    for (int i = 0; i < k.K; i++) c[i] = 1;
    rk_sparse_mul(&H, c, Hc);
    double r = 0;
    for (int i = 0; i < k.K; i++) r = fmax(r, fabs(Hc[i]));
    CHECK(r <= 1e-10 * hmax, "the constant mode has energy: |H 1| = %g, max |H| = %g", r, hmax);
    CHECK_CLOSE(rk_sparse_dot(&M, c, c), vsum, 1e-10);
    /* c_k = a . p_k + b reproduces the linear field exactly: c^T H c = |a|^2 sum v_i coef_i. */
    double a[3] = {0.3, -1.2, 0.7}, a2 = 0.09 + 1.44 + 0.49;
    for (int i = 0; i < k.K; i++) c[i] = a[0] * k.centers[3 * i] + a[1] * k.centers[3 * i + 1] + a[2] * k.centers[3 * i + 2] + 5;
    CHECK_CLOSE(rk_sparse_dot(&H, c, c) / (a2 * cvsum), 1.0, 1e-10);
    /* Three columns against a direct sum over the integration points. */
    int cap = rk_rkpm_max_support(&k);
    int *idx = calloc((size_t)cap, sizeof *idx);
    double *phi = calloc((size_t)cap, sizeof *phi), *grad = calloc(3 * (size_t)cap, sizeof *grad);
    double *hc = calloc((size_t)k.K, sizeof *hc), *mc = calloc((size_t)k.K, sizeof *mc);
    int cols[3] = {0, k.K / 2, k.K - 1};
    for (int q = 0; q < 3; q++) {
        int col = cols[q];
        memset(hc, 0, (size_t)k.K * sizeof *hc);
        memset(mc, 0, (size_t)k.K * sizeof *mc);
        for (int i = 0; i < p.n; i++) {
            int n = rk_rkpm_eval(&k, &p.X[3 * i], cap, idx, phi, grad, &err);
            CHECK(n >= 4, "eval: %s", err.msg);
            int self = -1;
            for (int b = 0; b < n; b++) self = idx[b] == col ? b : self;
            if (self < 0) continue;
            const double *g = &grad[3 * self];
            for (int b = 0; b < n; b++) {
                hc[idx[b]] += p.weight[i] * coef[i] * (g[0] * grad[3 * b] + g[1] * grad[3 * b + 1] + g[2] * grad[3 * b + 2]);
                mc[idx[b]] += p.weight[i] * phi[self] * phi[b];
            }
        }
        double mmax = 0;
        for (int row = 0; row < k.K; row++) mmax = fmax(mmax, fabs(mc[row]));
        for (int row = 0; row < k.K; row++) {
            int s = row <= col ? rk_sparse_find(&H, row, col) : rk_sparse_find(&H, col, row);
            double h = s >= 0 ? H.val[s] : 0, mm = s >= 0 ? M.val[s] : 0;
            CHECK(fabs(h - hc[row]) <= 1e-10 * hmax, "H[%d][%d] = %g, direct sum %g", row, col, h, hc[row]);
            CHECK(fabs(mm - mc[row]) <= 1e-10 * mmax, "M[%d][%d] = %g, direct sum %g", row, col, mm, mc[row]);
        }
    }
    free(idx), free(phi), free(grad), free(hc), free(mc), free(c), free(Hc), free(coef);
    rk_sparse_free(&H);
    rk_sparse_free(&M);
    rk_rkpm_free(&k);
    rk_rkpm_points_free(&p);
    rk_mesh_free(&m);
}

TEST(too_sparse_clouds_are_named)
{
    rk_error err;
    rk_rkpm k;
    /* Four kernels on the plane z = 0: M is singular everywhere. */
    double square[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    CHECK_OK(rk_rkpm_init(&k, square, 4, &err));
    int idx[8];
    double phi[8], grad[24];
    double X[3] = {0.5, 0.5, 0.1};
    CHECK(rk_rkpm_eval(&k, X, 8, idx, phi, grad, &err) < 0, "coplanar kernels accepted");
    CHECK(strstr(err.msg, "too sparse") && strstr(err.msg, "coplanar") && strstr(err.msg, "(0.5, 0.5, 0.1)"),
          "message: %s", err.msg);
    /* A point beyond every support, named by its index by rk_rkpm_interpolate. */
    double pts[6] = {0.5, 0.5, 0, 50, 0, 0}, c[4] = {1, 1, 1, 1}, W[2];
    CHECK(rk_rkpm_interpolate(&k, pts, 2, c, 1, W, NULL, NULL, &err) != 0, "interpolation succeeded");
    CHECK(strstr(err.msg, "point 0 at (0.5, 0.5, 0)") && strstr(err.msg, "too sparse"), "message: %s", err.msg);
    /* Tolerant interpolation (weights at vertices of thin features): the coplanar point gets
     * the damped moment matrix, reproduces constants and the in-plane linear field exactly
     * enough, is counted; the far point still fails. */
    int damped = -1;
    double lin[8] = {1, 1, 1, 1, 0, 1, 0, 1}, W2[4];
    CHECK_OK(rk_rkpm_interpolate(&k, pts, 1, lin, 2, W2, NULL, &damped, &err));
    CHECK(damped == 1, "%d points damped, expected 1", damped);
    CHECK_CLOSE(W2[0], 1.0, 1e-12);
    CHECK(fabs(W2[1] - 0.5) < 1e-3, "in-plane linear field x at x = 0.5 gave %.6g", W2[1]);
    CHECK(rk_rkpm_interpolate(&k, pts, 2, lin, 2, W2, NULL, &damped, &err) != 0 && strstr(err.msg, "point 1"),
          "far point in tolerant mode: %s", err.msg);
    rk_rkpm_free(&k);

    double tet[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    CHECK_OK(rk_rkpm_init(&k, tet, 4, &err));
    CHECK_OK(rk_rkpm_interpolate(&k, pts, 1, c, 1, W, NULL, NULL, &err));
    CHECK_CLOSE(W[0], 1.0, 1e-12);
    CHECK(rk_rkpm_interpolate(&k, pts, 2, c, 1, W, NULL, NULL, &err) != 0, "a far point was accepted");
    CHECK(strstr(err.msg, "point 1 at (50, 0, 0) is covered by 0 kernels (4 needed for linear reproduction)") &&
              strstr(err.msg, "the point cloud is too sparse for its kernels"),
          "message: %s", err.msg);
    rk_rkpm_free(&k);

    double dup[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0};
    CHECK(rk_rkpm_init(&k, dup, 5, &err) != 0 && strstr(err.msg, "centres 1 and 4 coincide"), "message: %s", err.msg);
    dup[5] = NAN;
    CHECK(rk_rkpm_init(&k, dup, 5, &err) != 0 && strstr(err.msg, "centre 1 "), "message: %s", err.msg);
    CHECK(rk_rkpm_init(&k, tet, 3, &err) != 0, "3 kernels accepted");
}

TEST(a_kernel_without_integration_points_is_named)
{
    rk_error err;
    rk_rkpm k;
    /* Two tets of centres 100 m apart; the integration point is near the first. */
    double C[24] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 100, 0, 0, 101, 0, 0, 100, 1, 0, 100, 0, 1};
    CHECK_OK(rk_rkpm_init(&k, C, 8, &err));
    double X[3] = {0.2, 0.2, 0.2}, v = 1, coef = 1;
    rk_sparse H, M;
    CHECK(rk_rkpm_assemble(&k, X, &v, &coef, 1, &H, &M, NULL, &err) != 0, "assembly succeeded");
    CHECK(strstr(err.msg, "kernel 4 at (100, 0, 0) covers no integration point"), "message: %s", err.msg);
    rk_rkpm_free(&k);
}

/* The paper's beam (5 x 1 x 1 m) at the paper's sizes, ~40k integration points and 1000 kernels:
 * sampling, FPS, kernels and assembly all succeed and give matrices of the right size. How long
 * that takes is make bench's to say (bench/bench_basis.c: rkpm16_s, the same 40k points and 1000
 * kernels, median of 3, on every bench mesh). */
TEST(paper_beam_builds_at_full_size)
{
    rk_error err;
    rk_mesh m;
    rk_rkpm_points p;
    rk_rkpm k;
    double size[3] = {5, 1, 1};
    int cells[3] = {40, 8, 8}, K = 1000;
    CHECK_OK(rk_mesh_box(size, cells, &m, &err));
    CHECK_OK(rk_rkpm_sample_mesh(&m, 40000, &p, &err));
    CHECK(p.n > 0.7 * 40000 && p.n < 1.3 * 40000, "%d points for a target of 40000", p.n);
    int *chosen = calloc((size_t)K, sizeof *chosen);
    double *C = calloc(3 * (size_t)K, sizeof *C);
    CHECK_OK(rk_fps(p.X, p.n, K, chosen, &err));
    for (int c = 0; c < K; c++) memcpy(&C[3 * c], &p.X[3 * chosen[c]], 3 * sizeof(double));
    CHECK_OK(rk_rkpm_init(&k, C, K, &err));
    double *coef = calloc((size_t)p.n, sizeof *coef);
    for (int i = 0; i < p.n; i++) coef[i] = 1;
    rk_sparse H, M;
    CHECK_OK(rk_rkpm_assemble(&k, p.X, p.weight, coef, p.n, &H, &M, NULL, &err));
    printf("# rkpm beam: %d points, %d kernels (max support %d), nnz %d\n", p.n, K, rk_rkpm_max_support(&k), H.nnz);
    int hn = H.n, mn = M.n, hnnz = H.nnz, mnnz = M.nnz;
    free(chosen), free(C), free(coef);
    rk_sparse_free(&H);
    rk_sparse_free(&M);
    rk_rkpm_free(&k);
    rk_rkpm_points_free(&p);
    rk_mesh_free(&m);
    CHECK(hn == K && mn == K && hnnz == mnnz && hnnz >= K, "H %d x %d (%d nonzeros), M %d x %d (%d)", hn, hn, hnnz,
          mn, mn, mnnz);
}

int main(void)
{
    RUN(grid_sampling_fills_a_box_mesh);
    RUN(cloud_sampling_estimates_the_volume_and_downsamples);
    RUN(fps_is_deterministic_and_spread);
    RUN(box_kernels_reproduce_linear_fields);
    RUN(splat_kernels_reproduce_linear_fields);
    RUN(gradients_match_central_differences);
    RUN(assembled_matrices_integrate_constant_and_linear_fields);
    RUN(too_sparse_clouds_are_named);
    RUN(a_kernel_without_integration_points_is_named);
    RUN(paper_beam_builds_at_full_size);
    return test_finish();
}
