/* runtime romrt_deformation_gradients: F at a point cloud's shown points (GRAD, what deformed
 * Gaussian splats are made of), against I + G q formed here in double from the precompute's side
 * of the same model: the cloud's weights (f.R.basis.W), their gradients (f.R.cloud_grad) and the
 * runtime's own q,
 *   F = I + sum_j A_j (X̄ grad W_j^T + W_j [I; 0]),   A_j[a][c] = q[12 j + 4 a + c]
 * (freeform paper Eq. 21). Relative to the largest |F - I| over the run: 1e-4 in the float build,
 * 1e-10 in the double one (this file compiled with -DROMRT_DOUBLE, test_runtime_point_gradients_double).
 * Also: an asset without GRAD (a mesh) is ROMRT_E_UNSUPPORTED, bad arguments ROMRT_E_ARGUMENT. */
#include "runtime_fixture.h"

#ifdef ROMRT_DOUBLE
#define F_TOL 1e-10
#define ASSET_REAL ROMBIN_REAL_F64
#else
#define F_TOL 1e-4
#define ASSET_REAL ROMBIN_REAL_F32
#endif

#define NX 13
#define NY 4
#define NZ 4

/* A 13 x 4 x 4 lattice of spacing 0.05 (listed in a scrambled order), hanging from its left end. */
/* %s: the cloud's file */
static const char *sagging_cloud =
    "{\"objects\": [{\"mesh\": {\"points\": \"%s\"},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 2e4, \"poisson\": 0.4, \"density\": 1000},"
    " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}]}],"
    " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.1, \"integrator\": \"backward_euler\"},"
    " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 4, \"kernels\": 40}}";

static int write_cloud(const char *path)
{
    int n = NX * NY * NZ;
    FILE *fp = fopen(path, "w");
    if (!fp) return -1;
    fprintf(fp, "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n", n);
    for (int q = 0; q < n; q++) {
        int i = (q * 37) % n; /* 37 is prime to 208: a permutation */
        fprintf(fp, "%g %g %g\n", 0.05 * (i % NX), 0.05 * (i / NX % NY) - 0.075, 0.05 * (i / (NX * NY)) - 0.075);
    }
    return fclose(fp);
}

/* F (row-major) at cloud point src from q, in double. */
static void reference_F(const rt_fixture *f, int src, const double *q, double F[9])
{
    int H = f->R.basis.m, n = f->sim.cloud_points, nb = f->R.basis.n;
    const double *X = &f->sim.mesh.X[3 * src];
    for (int k = 0; k < 9; k++) F[k] = k % 4 == 0;
    for (int j = 0; j < H; j++) {
        double w = f->R.basis.W[src + (size_t)nb * j];
        const double *dw = &f->R.cloud_grad[3 * (size_t)src + 3 * (size_t)n * j];
        for (int a = 0; a < 3; a++) {
            const double *A = &q[12 * j + 4 * a];
            double ax = A[0] * X[0] + A[1] * X[1] + A[2] * X[2] + A[3];
            for (int b = 0; b < 3; b++) F[3 * a + b] += ax * dw[b] + A[b] * w;
        }
    }
}

TEST(cloud_F_matches_the_weights_gradients)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    char cloud[512], json[2048];
    tl_scratch(cloud, sizeof cloud, "point_gradients.ply");
    snprintf(json, sizeof json, sagging_cloud, cloud);
    CHECK(write_cloud(cloud) == 0, "cannot write %s", cloud);
    int rc = rt_fixture_open(&f, json, ASSET_REAL, &err, &rerr);
    remove(cloud);
    CHECK(rc == 0, "%s", err.msg);
    int n = romrt_shown_count(f.m), r = romrt_reduced_size(f.m), H = f.R.basis.m;
    CHECK(n == NX * NY * NZ && f.sim.cloud_points == n && f.R.cloud_grad != NULL && r == 12 * H,
          "shown %d, cloud %d, r %d, H %d", n, f.sim.cloud_points, r, H);
    romrt_real *F = calloc(9 * (size_t)n + 9, sizeof(romrt_real)), *qr = calloc((size_t)r, sizeof(romrt_real));
    double *q = calloc((size_t)r, sizeof(double)), worst = 0, motion = 0, worst_abs = 0;
    for (int step = 0; step < 10; step++) {
        CHECK(romrt_step(f.m, &rerr) == ROMRT_OK, "step %d: %s", step, rerr.message);
        CHECK(romrt_reduced_coordinates(f.m, qr, r, NULL) == ROMRT_OK, "reduced coordinates");
        for (int k = 0; k < r; k++) q[k] = (double)qr[k];
        for (int k = 0; k < 9; k++) F[9 * n + k] = (romrt_real)-7; /* sentinel past the end */
        CHECK(romrt_deformation_gradients(f.m, F, 9 * (size_t)n, NULL) == ROMRT_OK, "romrt_deformation_gradients");
        for (int k = 0; k < 9; k++) CHECK(F[9 * n + k] == (romrt_real)-7, "wrote past count");
        for (int i = 0; i < n; i++) {
            double Fr[9];
            reference_F(&f, (int)f.vmap[i], q, Fr);
            for (int k = 0; k < 9; k++) {
                worst_abs = fmax(worst_abs, fabs((double)F[9 * i + k] - Fr[k]));
                motion = fmax(motion, fabs(Fr[k] - (k % 4 == 0)));
            }
        }
    }
    worst = worst_abs / motion;
    /* the cloud hangs from its fixed end: those points stay while the far end sags */
    romrt_real *xyz = calloc(3 * (size_t)n, sizeof(romrt_real));
    double held = 0, sag = 0;
    CHECK(romrt_positions(f.m, xyz, 3 * (size_t)n, 3, NULL) == ROMRT_OK, "positions");
    for (int i = 0; i < n; i++) {
        const double *X = &f.sim.mesh.X[3 * (int)f.vmap[i]];
        double d = fabs((double)xyz[3 * i + 1] - X[1]);
        if (X[0] < 0.01) held = fmax(held, d);
        else sag = fmax(sag, d);
    }
    free(xyz);
    printf("# fixed points moved %.3g m, the rest up to %.3g m (free fall over the run 0.054 m)\n", held, sag);
    CHECK(held < 0.1 * sag, "the fixed end fell %.3g m with the rest (%.3g m): the pins do not hold", held, sag);
    printf("# %d points, r = %d, 10 steps: |F_runtime - (I + G q)| = %.3g, %.3g of max |F - I| = %.3g (tol %g)\n", n, r,
           worst_abs, worst, motion, (double)F_TOL);
    CHECK(motion > 1e-3, "the cloud hardly deformed (max |F - I| = %g): nothing to compare", motion);
    CHECK(worst <= F_TOL, "F differs from I + G q by %.3g of max |F - I|", worst);
    /* a capacity (reals) below 9 per shown point is refused and nothing written; a larger one
     * gets the shown points' 9 n and nothing past them */
    size_t cap = 9 * (size_t)n;
    for (size_t k = 0; k < cap; k++) F[k] = (romrt_real)-7;
    CHECK(romrt_deformation_gradients(f.m, F, cap - 1, &rerr) == ROMRT_E_ARGUMENT && strstr(rerr.message, "needed"),
          "one real short: %s", rerr.message);
    CHECK(romrt_deformation_gradients(f.m, F, 0, NULL) == ROMRT_E_ARGUMENT, "capacity 0");
    int untouched = 1;
    for (size_t k = 0; k < cap; k++) untouched &= F[k] == (romrt_real)-7;
    CHECK(untouched, "a refused call wrote F");
    romrt_real *G = calloc(cap + 9, sizeof *G);
    for (size_t k = 0; k < cap + 9; k++) G[k] = (romrt_real)-7;
    CHECK(G && romrt_deformation_gradients(f.m, G, cap + 9, NULL) == ROMRT_OK && G[cap - 1] != (romrt_real)-7 &&
              G[cap] == (romrt_real)-7,
          "a larger capacity: wrote %s", G && G[cap] == (romrt_real)-7 ? "too little" : "past 9 n");
    free(G);
    /* bad arguments */
    CHECK(romrt_deformation_gradients(NULL, F, cap, NULL) == ROMRT_E_ARGUMENT, "NULL model");
    CHECK(romrt_deformation_gradients(f.m, NULL, cap, NULL) == ROMRT_E_ARGUMENT, "NULL F");
    free(F), free(qr), free(q);
    rt_fixture_close(&f);
}

/* A skinned mesh (SKIN, no GRAD): no gradients to give. */
static const char *skinned_bar =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.4, 0.1, 0.1], \"cells\": [4, 1, 1]}},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.3, \"density\": 1000},"
    " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}]}],"
    " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.03, \"integrator\": \"backward_euler\"},"
    " \"rom\": {\"basis\": \"skinning\", \"size\": 2}}";

TEST(a_mesh_has_no_gradients)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, skinned_bar, ASSET_REAL, &err, &rerr));
    int n = romrt_shown_count(f.m);
    romrt_real *F = calloc(9 * (size_t)n, sizeof(romrt_real));
    CHECK(romrt_deformation_gradients(f.m, F, 9 * (size_t)n, NULL) == ROMRT_E_UNSUPPORTED, "a mesh asset gave gradients");
    CHECK(romrt_deformation_gradients(f.m, F, 9, &rerr) == ROMRT_E_UNSUPPORTED && strcmp(rerr.chunk, "GRAD") == 0,
          "a mesh asset gave gradients, or the refusal does not name GRAD: %s", rerr.chunk);
    CHECK(romrt_deformation_gradients(f.m, NULL, 9, NULL) == ROMRT_E_ARGUMENT, "NULL F");
    free(F);
    rt_fixture_close(&f);
}

int main(void)
{
    RUN(cloud_F_matches_the_weights_gradients);
    RUN(a_mesh_has_no_gradients);
    return test_finish();
}
