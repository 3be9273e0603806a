/* precompute/grassmann: the CROM decoder trained on a two-parameter family of displacement fields
 * learns it (the loss falls 20x), its Jacobian is the derivative of its decoder (central
 * differences), training is deterministic, and data it cannot train on is refused by name. */
#include "grassmann/grassmann.h"
#include "testlib.h"

enum { NV = 27, N = 3 * NV, T = 64, R = 2 };

/* A 3 x 3 x 3 grid of points and fields u = a bend(X) + b^2 squeeze(X) over (a, b) in [-1, 1]^2. */
static void family(double *X, double *D)
{
    for (int v = 0; v < NV; v++) {
        X[3 * v] = v % 3;
        X[3 * v + 1] = (v / 3) % 3;
        X[3 * v + 2] = v / 9;
    }
    for (int t = 0; t < T; t++) {
        double a = -1 + 2.0 * (t % 8) / 7, b = -1 + 2.0 * (t / 8) / 7;
        for (int v = 0; v < NV; v++) {
            double x = X[3 * v], y = X[3 * v + 1];
            D[(size_t)t * N + 3 * v] = 0.05 * b * b * x;
            D[(size_t)t * N + 3 * v + 1] = 0.1 * a * x * x;
            D[(size_t)t * N + 3 * v + 2] = 0.02 * a * b * y;
        }
    }
}

TEST(crom_learns_a_two_parameter_family)
{
    static double X[3 * NV], D[(size_t)N * T];
    family(X, D);
    rk_crom_options o;
    rk_crom_default_options(&o);
    o.encoder_width = 32;
    o.decoder_width = 32;
    o.decoder_layers = 3;
    o.epochs = 300;
    o.base_lr = 1e-3;
    o.points = 16;
    rk_crom_report rep;
    rk_decoder dec, again;
    rk_error err;
    CHECK_OK(rk_crom_train(D, T, X, NV, R, &o, &dec, &rep, &err));
    CHECK(rep.final_loss < rep.first_loss / 20, "loss %g -> %g", rep.first_loss, rep.final_loss);
    /* the Jacobian against central differences of the decoder, at a trained code */
    double p[R], J[N * R], up[N], um[N];
    CHECK_OK(dec.encode(dec.ctx, D + (size_t)20 * N, p, &err));
    CHECK_OK(dec.jacobian(dec.ctx, p, J, &err));
    for (int k = 0; k < R; k++) {
        double e = 1e-5, q[R];
        memcpy(q, p, sizeof q);
        q[k] += e;
        CHECK_OK(dec.decode(dec.ctx, q, up, &err));
        q[k] -= 2 * e;
        CHECK_OK(dec.decode(dec.ctx, q, um, &err));
        for (int i = 0; i < N; i++) {
            double fd = (up[i] - um[i]) / (2 * e);
            CHECK(fabs(fd - J[k * N + i]) < 1e-6 * (1e-3 + fabs(fd)) + 1e-9, "dg_%d/dp_%d %g vs %g", i, k, J[k * N + i], fd);
        }
    }
    /* the same seed, the same network */
    CHECK_OK(rk_crom_train(D, T, X, NV, R, &o, &again, NULL, &err));
    CHECK_OK(dec.decode(dec.ctx, p, up, &err));
    CHECK_OK(again.decode(again.ctx, p, um, &err));
    CHECK(memcmp(up, um, sizeof up) == 0, "two trainings with one seed differ");
    rk_decoder_free(&dec);
    rk_decoder_free(&again);
}

TEST(untrainable_data_is_refused_by_name)
{
    static double X[3 * NV], D[(size_t)N * T];
    family(X, D);
    rk_crom_options o;
    rk_crom_default_options(&o);
    o.epochs = 1;
    rk_decoder dec;
    rk_error err;
    CHECK(rk_crom_train(D, 1, X, NV, R, &o, &dec, NULL, &err) != 0 && strstr(err.msg, "1 snapshots cannot train 2"),
          "fewer snapshots than r: %s", err.msg);
    D[(size_t)5 * N + 7] = NAN;
    CHECK(rk_crom_train(D, T, X, NV, R, &o, &dec, NULL, &err) != 0 && strstr(err.msg, "snapshot 5, vertex 2"),
          "NaN: %s", err.msg);
    memset(D, 0, sizeof D);
    CHECK(rk_crom_train(D, T, X, NV, R, &o, &dec, NULL, &err) != 0 && strstr(err.msg, "rest shape"), "zeros: %s", err.msg);
    CHECK(dec.ctx == NULL, "a refused training left a decoder");
}

int main(void)
{
    RUN(crom_learns_a_two_parameter_family);
    RUN(untrainable_data_is_refused_by_name);
    return test_finish();
}
