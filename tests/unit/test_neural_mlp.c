/* The dense MLP stage: the parameter layout against a hand-written forward pass, reverse-mode
 * gradients and the forward-mode Jacobian against central finite differences and each other,
 * ELU's values, Adam on a convex quadratic, the phased learning rate, training that fits a smooth
 * function, bit-identical training for a seed, and inputs refused by name. */
#include "testlib.h"
#include "neural/neural.h"
#include "util/util.h"

static const int SIZES[] = {5, 7, 6, 3};
#define NSIZES 4

/* A 5-7-6-3 net with non-zero biases too (init leaves them 0, which would hide a wrong b). */
static int small_net(rk_mlp *m, rk_error *err)
{
    if (rk_mlp_init(m, NSIZES, SIZES, 42, err)) return -1;
    uint64_t s = 99;
    for (int l = 0; l < m->nlayers; l++) {
        int in = m->sizes[l], out = m->sizes[l + 1];
        double *b = m->params + m->offset[l] + (long)out * in;
        for (int o = 0; o < out; o++) b[o] = rk_uniform(&s) - 0.5;
    }
    return 0;
}

static void fill_uniform(double *x, int n, double lo, double hi, uint64_t seed)
{
    for (int i = 0; i < n; i++) x[i] = lo + (hi - lo) * rk_uniform(&seed);
}

/* max |a - b| / max |b| over n entries */
static double rel_err(const double *a, const double *b, long n)
{
    double num = 0, den = 0;
    for (long i = 0; i < n; i++) {
        num = fmax(num, fabs(a[i] - b[i]));
        den = fmax(den, fabs(b[i]));
    }
    return num / den;
}

TEST(elu_values)
{
    CHECK(rk_elu(0.0) == 0.0, "ELU(0) = %g", rk_elu(0.0));
    CHECK(rk_elu(2.5) == 2.5, "ELU(2.5) = %g", rk_elu(2.5));
    CHECK_CLOSE(rk_elu(-1.0), exp(-1.0) - 1.0, 1e-15);
    CHECK_CLOSE(rk_elu(-1e-10), -1e-10 + 5e-21, 1e-25); /* expm1: no cancellation near 0 */
    CHECK_CLOSE(rk_elu(-50.0), -1.0, 1e-15);
    CHECK(rk_elu_grad(0.0) == 1.0 && rk_elu_grad(3.0) == 1.0, "ELU'(0) = %g, ELU'(3) = %g", rk_elu_grad(0.0),
          rk_elu_grad(3.0));
    CHECK_CLOSE(rk_elu_grad(-2.0), exp(-2.0), 1e-15);
    /* inside a 1-1-1 net: ELU on the hidden unit, none on the output */
    rk_error err;
    rk_mlp m;
    rk_mlp_work w;
    const int sz[] = {1, 1, 1};
    CHECK_OK(rk_mlp_init(&m, 3, sz, 1, &err));
    CHECK_OK(rk_mlp_work_init(&w, &m, 2, 1, &err));
    double *p = m.params; /* W0, b0, W1, b1 */
    p[0] = 2.0, p[1] = -1.0, p[2] = 3.0, p[3] = -0.25;
    double x[2] = {-0.5, 1.0}, y[2];
    CHECK_OK(rk_mlp_forward(&m, &w, 2, x, y, &err));
    CHECK_CLOSE(y[0], 3.0 * (exp(-2.0) - 1.0) - 0.25, 1e-15);
    CHECK_CLOSE(y[1], 3.0 * 1.0 - 0.25, 1e-15);
    double J[2];
    CHECK_OK(rk_mlp_jacobian(&m, &w, 2, x, 0, 1, NULL, J, &err));
    CHECK_CLOSE(J[0], 3.0 * exp(-2.0) * 2.0, 1e-15);
    CHECK_CLOSE(J[1], 3.0 * 2.0, 1e-15);
    rk_mlp_work_free(&w);
    rk_mlp_free(&m);
}

TEST(layout_and_init)
{
    rk_error err;
    rk_mlp m, m2, m3;
    CHECK_OK(rk_mlp_init(&m, NSIZES, SIZES, 42, &err));
    CHECK(rk_mlp_params(&m) == 7 * 5 + 7 + 6 * 7 + 6 + 3 * 6 + 3, "%ld parameters", rk_mlp_params(&m));
    CHECK(m.offset[1] == 42 && m.offset[2] == 90, "offsets %ld %ld", m.offset[1], m.offset[2]);
    for (int l = 0; l < m.nlayers; l++) {
        int in = m.sizes[l], out = m.sizes[l + 1];
        double c = l + 1 < m.nlayers ? sqrt(6.0 / in) : sqrt(6.0 / (in + out)), wmax = 0;
        const double *W = m.params + m.offset[l];
        for (int i = 0; i < out * in; i++) wmax = fmax(wmax, fabs(W[i]));
        CHECK(wmax <= c && wmax > 0.5 * c, "layer %d: max |W| %g against the bound %g", l, wmax, c);
        for (int o = 0; o < out; o++) CHECK(W[out * in + o] == 0, "layer %d bias %d is %g", l, o, W[out * in + o]);
    }
    CHECK_OK(rk_mlp_init(&m2, NSIZES, SIZES, 42, &err));
    CHECK_OK(rk_mlp_init(&m3, NSIZES, SIZES, 43, &err));
    size_t bytes = sizeof(double) * (size_t)rk_mlp_params(&m);
    CHECK(memcmp(m.params, m2.params, bytes) == 0, "the same seed gave other weights");
    CHECK(memcmp(m.params, m3.params, bytes) != 0, "another seed gave the same weights");
    rk_mlp_free(&m2);
    rk_mlp_free(&m3);

    /* the forward pass by hand from the documented layout, against the dgemm one */
    rk_mlp_free(&m);
    CHECK_OK(small_net(&m, &err));
    rk_mlp_work w;
    CHECK_OK(rk_mlp_work_init(&w, &m, 4, 0, &err));
    double X[4 * 5], Y[4 * 3];
    fill_uniform(X, 20, -1.5, 1.5, 5);
    CHECK_OK(rk_mlp_forward(&m, &w, 4, X, Y, &err));
    for (int b = 0; b < 4; b++) {
        double a[8], z[8];
        memcpy(a, X + 5 * b, sizeof(double) * 5);
        for (int l = 0; l < m.nlayers; l++) {
            int in = m.sizes[l], out = m.sizes[l + 1];
            const double *W = m.params + m.offset[l], *bias = W + out * in;
            for (int o = 0; o < out; o++) {
                z[o] = bias[o];
                for (int i = 0; i < in; i++) z[o] += W[o * in + i] * a[i];
            }
            for (int o = 0; o < out; o++) a[o] = l + 1 < m.nlayers ? rk_elu(z[o]) : z[o];
        }
        for (int i = 0; i < 3; i++) CHECK_CLOSE(Y[3 * b + i], a[i], 1e-14);
    }
    rk_mlp_work_free(&w);
    rk_mlp_free(&m);
}

/* L = sum_{b,i} C[b,i] Y[b,i] for B inputs X: a scalar whose dL/dY is C. */
#define B_FD 4
static double probe_loss(const rk_mlp *m, rk_mlp_work *w, const double *X, const double *C)
{
    double Y[B_FD * 3], L = 0;
    rk_error err;
    if (rk_mlp_forward(m, w, B_FD, X, Y, &err)) return NAN;
    for (int i = 0; i < B_FD * 3; i++) L += C[i] * Y[i];
    return L;
}

TEST(parameter_gradient_matches_finite_differences)
{
    rk_error err;
    rk_mlp m;
    rk_mlp_work w;
    CHECK_OK(small_net(&m, &err));
    CHECK_OK(rk_mlp_work_init(&w, &m, B_FD, 0, &err));
    long P = rk_mlp_params(&m);
    double X[B_FD * 5], C[B_FD * 3], g[111] = {0}, fd[111];
    fill_uniform(X, B_FD * 5, -1.5, 1.5, 11);
    fill_uniform(C, B_FD * 3, -1, 1, 12);
    CHECK_OK(rk_mlp_forward(&m, &w, B_FD, X, NULL, &err));
    CHECK_OK(rk_mlp_backward(&m, &w, C, g, NULL, &err));
    const double h = 1e-5;
    for (long i = 0; i < P; i++) {
        double keep = m.params[i];
        m.params[i] = keep + h;
        double Lp = probe_loss(&m, &w, X, C);
        m.params[i] = keep - h;
        double Lm = probe_loss(&m, &w, X, C);
        m.params[i] = keep;
        fd[i] = (Lp - Lm) / (2 * h);
    }
    double e = rel_err(g, fd, P);
    CHECK(e < 1e-6, "dL/dparams off finite differences by %.3g (relative)", e);
    /* a second backward pass adds to the first */
    double g2[111];
    memcpy(g2, g, sizeof g);
    CHECK_OK(rk_mlp_forward(&m, &w, B_FD, X, NULL, &err));
    CHECK_OK(rk_mlp_backward(&m, &w, C, g2, NULL, &err));
    for (long i = 0; i < P; i++) CHECK_CLOSE(g2[i], 2 * g[i], 1e-14); /* dgemm's beta = 1 may round apart from 2 g */
    rk_mlp_work_free(&w);
    rk_mlp_free(&m);
}

TEST(input_gradient_matches_finite_differences)
{
    rk_error err;
    rk_mlp m;
    rk_mlp_work w;
    CHECK_OK(small_net(&m, &err));
    CHECK_OK(rk_mlp_work_init(&w, &m, B_FD, 0, &err));
    double X[B_FD * 5], C[B_FD * 3], g[111] = {0}, dX[B_FD * 5], fd[B_FD * 5];
    fill_uniform(X, B_FD * 5, -1.5, 1.5, 21);
    fill_uniform(C, B_FD * 3, -1, 1, 22);
    CHECK_OK(rk_mlp_forward(&m, &w, B_FD, X, NULL, &err));
    CHECK_OK(rk_mlp_backward(&m, &w, C, g, dX, &err));
    const double h = 1e-5;
    for (int i = 0; i < B_FD * 5; i++) {
        double keep = X[i];
        X[i] = keep + h;
        double Lp = probe_loss(&m, &w, X, C);
        X[i] = keep - h;
        double Lm = probe_loss(&m, &w, X, C);
        X[i] = keep;
        fd[i] = (Lp - Lm) / (2 * h);
    }
    double e = rel_err(dX, fd, B_FD * 5);
    CHECK(e < 1e-6, "dL/dX off finite differences by %.3g (relative)", e);
    rk_mlp_work_free(&w);
    rk_mlp_free(&m);
}

TEST(jacobian_matches_finite_differences_and_reverse_mode)
{
    rk_error err;
    rk_mlp m;
    rk_mlp_work w;
    CHECK_OK(small_net(&m, &err));
    enum { B = 3, FIRST = 1, K = 3 };
    CHECK_OK(rk_mlp_work_init(&w, &m, B, K, &err));
    double X[B * 5], Y[B * 3], J[B * 3 * K], fd[B * 3 * K], rev[B * 3 * K];
    fill_uniform(X, B * 5, -1.5, 1.5, 31);
    CHECK_OK(rk_mlp_jacobian(&m, &w, B, X, FIRST, K, Y, J, &err));
    double Yf[B * 3];
    CHECK_OK(rk_mlp_forward(&m, &w, B, X, Yf, &err));
    CHECK(memcmp(Y, Yf, sizeof Y) == 0, "the Jacobian's outputs differ from the forward pass's");
    /* finite differences: column j of input b's Jacobian from x_b[FIRST + j] +- h */
    const double h = 1e-5;
    for (int b = 0; b < B; b++)
        for (int j = 0; j < K; j++) {
            double Xp[B * 5], Xm[B * 5], Yp[B * 3], Ym[B * 3];
            memcpy(Xp, X, sizeof X);
            memcpy(Xm, X, sizeof X);
            Xp[b * 5 + FIRST + j] += h;
            Xm[b * 5 + FIRST + j] -= h;
            CHECK_OK(rk_mlp_forward(&m, &w, B, Xp, Yp, &err));
            CHECK_OK(rk_mlp_forward(&m, &w, B, Xm, Ym, &err));
            for (int i = 0; i < 3; i++) fd[(b * 3 + i) * K + j] = (Yp[b * 3 + i] - Ym[b * 3 + i]) / (2 * h);
        }
    double e = rel_err(J, fd, B * 3 * K);
    CHECK(e < 1e-6, "Jacobian off finite differences by %.3g (relative)", e);
    /* reverse mode: dY = e_i on every row gives row i of each input's Jacobian in dX */
    CHECK_OK(rk_mlp_forward(&m, &w, B, X, NULL, &err));
    for (int i = 0; i < 3; i++) {
        double dY[B * 3] = {0}, dX[B * 5], g[111] = {0};
        for (int b = 0; b < B; b++) dY[b * 3 + i] = 1;
        CHECK_OK(rk_mlp_backward(&m, &w, dY, g, dX, &err));
        for (int b = 0; b < B; b++)
            for (int j = 0; j < K; j++) rev[(b * 3 + i) * K + j] = dX[b * 5 + FIRST + j];
    }
    e = rel_err(J, rev, B * 3 * K);
    CHECK(e < 1e-13, "forward- and reverse-mode Jacobians differ by %.3g (relative)", e);
    rk_mlp_work_free(&w);

    /* one layer, no activation: the Jacobian is W's columns */
    const int one[] = {4, 2};
    rk_mlp lin;
    CHECK_OK(rk_mlp_init(&lin, 2, one, 3, &err));
    CHECK_OK(rk_mlp_work_init(&w, &lin, 1, 2, &err));
    double x[4] = {0.1, 0.2, 0.3, 0.4}, J2[4];
    CHECK_OK(rk_mlp_jacobian(&lin, &w, 1, x, 2, 2, NULL, J2, &err));
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) CHECK(J2[i * 2 + j] == lin.params[i * 4 + 2 + j], "J[%d][%d] = %g", i, j, J2[i * 2 + j]);
    rk_mlp_work_free(&w);
    rk_mlp_free(&lin);
    rk_mlp_free(&m);
}

TEST(adam_minimises_a_convex_quadratic)
{
    /* f(p) = 1/2 sum d_i (p_i - c_i)^2 with curvatures 1 to 1000 */
    enum { N = 6 };
    const double d[N] = {1, 3, 10, 30, 100, 1000}, c[N] = {1, -2, 0.5, 3, -0.25, 2};
    double p[N] = {0}, g[N];
    rk_error err;
    rk_adam a;
    CHECK_OK(rk_adam_init(&a, N, &err));
    /* the first step moves every parameter by lr against its gradient's sign (m / sqrt(v) = +-1) */
    for (int i = 0; i < N; i++) g[i] = d[i] * (p[i] - c[i]);
    CHECK_OK(rk_adam_step(&a, p, g, 0.01, &err));
    for (int i = 0; i < N; i++) CHECK_CLOSE(p[i], c[i] > 0 ? 0.01 : -0.01, 1e-9);
    double f0 = 0;
    for (int i = 0; i < N; i++) f0 += 0.5 * d[i] * c[i] * c[i];
    const int steps = 4000;
    for (int t = 1; t < steps; t++) {
        for (int i = 0; i < N; i++) g[i] = d[i] * (p[i] - c[i]);
        CHECK_OK(rk_adam_step(&a, p, g, rk_lr_phased(0.01, t, steps), &err));
    }
    double f = 0, dist = 0;
    for (int i = 0; i < N; i++) {
        f += 0.5 * d[i] * (p[i] - c[i]) * (p[i] - c[i]);
        dist = fmax(dist, fabs(p[i] - c[i]));
    }
    CHECK(f < 1e-8 * f0 && dist < 1e-3, "f %.3g (from %.3g), max |p - c| %.3g", f, f0, dist);
    rk_adam_free(&a);
}

TEST(phased_learning_rate)
{
    const int e[] = {0, 99, 100, 199, 200, 299, 300, 399, 400};
    const double want[] = {5, 5, 2, 2, 1, 1, 0.5, 0.5, 0.5};
    for (int i = 0; i < 9; i++) CHECK_CLOSE(rk_lr_phased(1e-4, e[i], 400), want[i] * 1e-4, 1e-15);
    /* 10 epochs: phases of 3, 2, 3, 2 */
    int count[4] = {0};
    for (int k = 0; k < 10; k++) {
        double lr = rk_lr_phased(1.0, k, 10);
        count[lr == 5 ? 0 : lr == 2 ? 1 : lr == 1 ? 2 : 3]++;
    }
    CHECK(count[0] == 3 && count[1] == 2 && count[2] == 3 && count[3] == 2, "phases %d %d %d %d", count[0], count[1],
          count[2], count[3]);
}

/* y = sin(x0) + x1^2 on 256 points of [-1.5, 1.5]^2 */
enum { NPTS = 256 };
static void smooth_data(double *X, double *Y)
{
    fill_uniform(X, 2 * NPTS, -1.5, 1.5, 77);
    for (int i = 0; i < NPTS; i++) Y[i] = sin(X[2 * i]) + X[2 * i + 1] * X[2 * i + 1];
}

static const int TINY[] = {2, 32, 32, 1};

static void tiny_options(rk_mlp_train_options *o)
{
    rk_mlp_train_default_options(o);
    o->epochs = 400;
    o->base_lr = 1e-3;
    o->seed = 5;
}

TEST(training_fits_a_smooth_function)
{
    rk_error err;
    rk_mlp m;
    double X[2 * NPTS], Y[NPTS];
    smooth_data(X, Y);
    CHECK_OK(rk_mlp_init(&m, 4, TINY, 8, &err));
    rk_mlp_train_options o;
    rk_mlp_train_report r;
    tiny_options(&o);
    CHECK(o.batch == 64, "default batch %d", o.batch);
    CHECK_OK(rk_mlp_train(&m, X, Y, NPTS, &o, &r, &err));
    /* against the initial loss, and against the best constant (Y's variance), which a random
     * network's large start would flatter less */
    double mean = 0, var = 0;
    for (int i = 0; i < NPTS; i++) mean += Y[i] / NPTS;
    for (int i = 0; i < NPTS; i++) var += (Y[i] - mean) * (Y[i] - mean) / NPTS;
    printf("# training: MSE %.3g -> %.3g (variance of y %.3g) in %ld steps, %.3f s\n", r.initial_loss, r.final_loss,
           var, r.steps, r.seconds);
    CHECK(r.final_loss < r.initial_loss / 100, "MSE %.3g -> %.3g: not 100x lower", r.initial_loss, r.final_loss);
    CHECK(r.final_loss < var / 100, "MSE %.3g: not 100x below the variance %.3g", r.final_loss, var);
    CHECK(r.steps == 400 * 4, "%ld steps", r.steps);
    rk_mlp_free(&m);
}

TEST(training_is_deterministic)
{
    rk_error err;
    rk_mlp a, b, c;
    double X[2 * NPTS], Y[NPTS];
    smooth_data(X, Y);
    rk_mlp_train_options o;
    tiny_options(&o);
    o.epochs = 40;
    CHECK_OK(rk_mlp_init(&a, 4, TINY, 8, &err));
    CHECK_OK(rk_mlp_init(&b, 4, TINY, 8, &err));
    CHECK_OK(rk_mlp_init(&c, 4, TINY, 8, &err));
    CHECK_OK(rk_mlp_train(&a, X, Y, NPTS, &o, NULL, &err));
    int before = rk_threads_blas(rk_threads()); /* training must not depend on the count it finds */
    CHECK_OK(rk_mlp_train(&b, X, Y, NPTS, &o, NULL, &err));
    rk_threads_blas(before);
    o.seed++;
    CHECK_OK(rk_mlp_train(&c, X, Y, NPTS, &o, NULL, &err));
    size_t bytes = sizeof(double) * (size_t)rk_mlp_params(&a);
    CHECK(memcmp(a.params, b.params, bytes) == 0, "two runs with the same seed gave different parameters");
    CHECK(memcmp(a.params, c.params, bytes) != 0, "another shuffling seed gave the same parameters");
    rk_mlp_free(&a);
    rk_mlp_free(&b);
    rk_mlp_free(&c);
}

#define CHECK_FAILS(call, want) CHECK((call) != 0 && strstr(err.msg, want), "%s: message \"%s\" lacks \"%s\"", #call, err.msg, want)

TEST(bad_inputs_are_refused_by_name)
{
    rk_error err;
    rk_mlp m, other;
    rk_mlp_work w;
    const int bad_size[] = {3, 0, 2};
    CHECK_FAILS(rk_mlp_init(&m, 3, bad_size, 1, &err), "layer size 1 is 0");
    CHECK_FAILS(rk_mlp_init(&m, 1, SIZES, 1, &err), "1 layer sizes given");

    double X[2 * NPTS], Y[NPTS];
    smooth_data(X, Y);
    CHECK_OK(rk_mlp_init(&m, 4, TINY, 8, &err));
    double *keep = malloc(sizeof(double) * (size_t)rk_mlp_params(&m));
    memcpy(keep, m.params, sizeof(double) * (size_t)rk_mlp_params(&m));
    rk_mlp_train_options o;
    tiny_options(&o);
    CHECK_FAILS(rk_mlp_train(&m, X, Y, 0, &o, NULL, &err), "0 training pairs");
    X[2 * 17 + 1] = NAN;
    CHECK_FAILS(rk_mlp_train(&m, X, Y, NPTS, &o, NULL, &err), "input X row 17 column 1 is nan");
    X[2 * 17 + 1] = 0;
    Y[200] = INFINITY;
    CHECK_FAILS(rk_mlp_train(&m, X, Y, NPTS, &o, NULL, &err), "target Y row 200 column 0 is inf");
    Y[200] = 0;
    o.batch = 0;
    CHECK_FAILS(rk_mlp_train(&m, X, Y, NPTS, &o, NULL, &err), "batch 0");
    tiny_options(&o);
    o.epochs = 0;
    CHECK_FAILS(rk_mlp_train(&m, X, Y, NPTS, &o, NULL, &err), "epochs 0");
    tiny_options(&o);
    o.base_lr = 0;
    CHECK_FAILS(rk_mlp_train(&m, X, Y, NPTS, &o, NULL, &err), "learning rate base_lr 0");
    o.base_lr = -1e-3;
    CHECK_FAILS(rk_mlp_train(&m, X, Y, NPTS, &o, NULL, &err), "learning rate base_lr -0.001");
    CHECK(memcmp(keep, m.params, sizeof(double) * (size_t)rk_mlp_params(&m)) == 0, "a refused run changed the network");
    free(keep);

    /* the workspace: its capacity and its shape */
    CHECK_OK(rk_mlp_work_init(&w, &m, 8, 1, &err));
    CHECK_FAILS(rk_mlp_forward(&m, &w, 9, X, NULL, &err), "9 rows; the workspace holds 1 to 8");
    CHECK_FAILS(rk_mlp_jacobian(&m, &w, 1, X, 0, 2, NULL, Y, &err), "2 columns; the workspace holds 1 to 1");
    CHECK_FAILS(rk_mlp_jacobian(&m, &w, 1, X, 2, 1, NULL, Y, &err), "inputs 2 to 2 are outside the network's 2 inputs");
    CHECK_OK(rk_mlp_init(&other, NSIZES, SIZES, 1, &err));
    CHECK_FAILS(rk_mlp_forward(&other, &w, 1, X, NULL, &err), "another shape");
    rk_mlp_work_free(&w);
    CHECK_OK(rk_mlp_work_init(&w, &other, 8, 0, &err));
    double dY[3] = {1, 1, 1}, g[111];
    CHECK_FAILS(rk_mlp_backward(&other, &w, dY, g, NULL, &err), "no forward pass");
    rk_mlp_work_free(&w);

    /* Adam: a non-finite gradient or a bad rate leaves everything as it was */
    rk_adam a;
    double p[3] = {1, 2, 3}, grad[3] = {0.5, NAN, 0.5};
    CHECK_OK(rk_adam_init(&a, 3, &err));
    CHECK_FAILS(rk_adam_step(&a, p, grad, 0.1, &err), "gradient 1 is nan");
    grad[1] = 0;
    CHECK_FAILS(rk_adam_step(&a, p, grad, 0, &err), "learning rate 0");
    CHECK(p[0] == 1 && p[1] == 2 && p[2] == 3 && a.step == 0 && a.m[0] == 0, "a refused step moved something");
    rk_adam_free(&a);
    rk_mlp_free(&other);
    rk_mlp_free(&m);
}

int main(void)
{
    RUN(elu_values);
    RUN(layout_and_init);
    RUN(parameter_gradient_matches_finite_differences);
    RUN(input_gradient_matches_finite_differences);
    RUN(jacobian_matches_finite_differences_and_reverse_mode);
    RUN(adam_minimises_a_convex_quadratic);
    RUN(phased_learning_rate);
    RUN(training_fits_a_smooth_function);
    RUN(training_is_deterministic);
    RUN(bad_inputs_are_refused_by_name);
    return test_finish();
}
