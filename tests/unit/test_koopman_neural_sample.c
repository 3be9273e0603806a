/* Neural DMD at resolution (issue 35; koopman-dmd-log-linear paper, Sec. 5, Fig. 3):
 *   1. a mesh's vertex sample (rk_koopman_neural_sample): distinct vertices in the mesh's order,
 *      each carrying its own rest position, frames and forcing; all of them when asked for as many;
 *      the same sample for the same seed;
 *   2. the modes evaluated in blocks (rk_koopman_neural_modes over more than one block of
 *      RK_KOOPMAN_NEURAL_BLOCK vertices) equal the network's output at each point;
 *   3. a model trained on a sample of a beam's vertices (options.vertices), rolled out at all of
 *      them against the full-order run, is about as good as one trained on all of them. */
#include "testlib.h"
#include "koopman_beam.h"

TEST(a_sample_is_the_mesh_at_its_vertices)
{
    rk_error err;
    beam b;
    CHECK_OK(beam_open(&b, 16, 4, 4, 0.1, &err));
    rk_koopman_neural_mesh m = beam_mesh(&b, NULL);
    int nv = m.nv, d = 3 * nv, S = 100, T = m.traj[0].frames;
    rk_koopman_neural_sample s, again, other, all;
    CHECK_OK(rk_koopman_neural_sample_init(&m, S, 5, &s, &err));
    CHECK_OK(rk_koopman_neural_sample_init(&m, S, 5, &again, &err));
    CHECK_OK(rk_koopman_neural_sample_init(&m, S, 6, &other, &err));
    CHECK_OK(rk_koopman_neural_sample_init(&m, nv + 3, 5, &all, &err));
    int order = 1, same = 1, differs = 0, data = 1, whole = all.mesh.nv == nv;
    for (int i = 0; i < S; i++) {
        int p = s.index[i];
        order &= p >= 0 && p < nv && (i == 0 || p > s.index[i - 1]);
        same &= p == again.index[i];
        differs |= p != other.index[i];
        for (int c = 0; c < 3 && order; c++) {
            data &= s.mesh.X[3 * i + c] == m.X[3 * p + c];
            data &= s.mesh.traj[0].accel[3 * i + c] == m.traj[0].accel[3 * p + c];
            for (int f = 0; f < T; f++) data &= s.mesh.traj[0].u[(size_t)3 * S * f + 3 * i + c] == m.traj[0].u[(size_t)d * f + 3 * p + c];
        }
    }
    for (int i = 0; whole && i < nv; i++) whole = all.index[i] == i;
    whole = whole && !memcmp(all.mesh.X, m.X, sizeof(double) * d) &&
            !memcmp(all.mesh.traj[0].u, m.traj[0].u, sizeof(double) * d * T);
    CHECK(s.mesh.nv == S && s.mesh.ntraj == 1 && s.mesh.traj[0].frames == T, "sample: %d vertices, %d trajectories",
          s.mesh.nv, s.mesh.ntraj);
    rk_koopman_neural_sample_free(&s);
    rk_koopman_neural_sample_free(&again);
    rk_koopman_neural_sample_free(&other);
    rk_koopman_neural_sample_free(&all);
    beam_close(&b);
    CHECK(order, "the sample's vertices are not distinct, in range and in the mesh's order");
    CHECK(data, "a sampled vertex's rest position, frames or forcing differ from the mesh's");
    CHECK(same && differs, "seed 5 twice: %s; seeds 5 and 6: %s", same ? "the same" : "different",
          differs ? "different" : "the same");
    CHECK(whole, "asking for more vertices than the mesh has gives the mesh itself");
}

TEST(modes_in_blocks_are_the_network_at_each_point)
{
    rk_error err;
    rk_koopman_neural nk;
    memset(&nk, 0, sizeof nk);
    int sizes[4] = {3, 16, 16, 6 * 4}, nv = RK_KOOPMAN_NEURAL_BLOCK + 905, r = 4;
    CHECK_OK(rk_mlp_init(&nk.net, 4, sizes, 3, &err));
    nk.r = r;
    nk.scale = 2;
    nk.center[1] = 0.5;
    double *X = calloc(3 * (size_t)nv, sizeof(double)), *Phi = calloc(6 * (size_t)nv * r, sizeof(double));
    uint64_t st = 11;
    for (int i = 0; i < 3 * nv; i++) X[i] = rk_uniform(&st);
    CHECK_OK(rk_koopman_neural_modes(&nk, X, nv, NULL, Phi, &err));
    rk_mlp_work w;
    CHECK_OK(rk_mlp_work_init(&w, &nk.net, 1, 0, &err));
    double worst = 0, in[3], y[24];
    size_t D = 6 * (size_t)nv;
    for (int p = 0; p < nv; p += 97) { /* every 97th point, across the block boundary */
        for (int c = 0; c < 3; c++) in[c] = (X[3 * p + c] - nk.center[c]) / nk.scale;
        CHECK_OK(rk_mlp_forward(&nk.net, &w, 1, in, y, &err));
        for (int j = 0; j < r; j++)
            for (int c = 0; c < 6; c++) {
                size_t row = c < 3 ? 3 * (size_t)p + c : 3 * (size_t)nv + 3 * (size_t)p + c - 3;
                worst = fmax(worst, fabs(Phi[D * j + row] - y[6 * j + c]));
            }
    }
    rk_mlp_work_free(&w);
    rk_mlp_free(&nk.net);
    free(X);
    free(Phi);
    CHECK(worst < 1e-12, "a mode's value differs from the network at its point by %.3g", worst);
}

/* Trained on 120 of a 425-vertex beam's vertices and on all 425, both rolled out at all of them
 * from the run's start. Measured: see the printed line; the bound asks the sample for no worse
 * than twice the whole mesh's error plus 0.5% MSE. */
TEST(a_sample_trains_a_model_for_every_vertex)
{
    rk_error err;
    beam b;
    CHECK_OK(beam_open(&b, 16, 4, 4, 0.6, &err));
    rk_koopman_neural_mesh m = beam_mesh(&b, NULL);
    double pct[2] = {0, 0}, peak[2] = {0, 0}, secs[2] = {0, 0};
    static const int vertices[2] = {0, 120};
    int rc = 0;
    for (int v = 0; v < 2 && !rc; v++) {
        rk_koopman_neural_options o;
        rk_koopman_neural_default_options(&o);
        o.rank = 8;
        o.vertices = vertices[v];
        rk_koopman_neural nk;
        rk_koopman_neural_report rep;
        rk_koopman k;
        if ((rc = rk_koopman_neural_train(&m, 1, &o, &nk, &rep, &err))) break;
        secs[v] = rep.seconds;
        rc = rk_koopman_neural_operator(&nk, m.X, m.nv, NULL, &k, &err);
        rk_koopman_neural_free(&nk);
        if (rc) break;
        rc = rollout_error(&k, &b.run, &pct[v], &peak[v], &err);
        rk_koopman_free(&k);
    }
    int nv = m.nv;
    beam_close(&b);
    CHECK(rc == 0, "%s", err.msg);
    printf("# rollout at all %d vertices: trained on all %.4g%% MSE (peak %.3g, %.2f s), on a sample of %d %.4g%% "
           "MSE (peak %.3g, %.2f s)\n", nv, pct[0], peak[0], secs[0], vertices[1], pct[1], peak[1], secs[1]);
    CHECK(pct[1] <= 2 * pct[0] + 0.5, "sampled %.4g%% MSE, all vertices %.4g%%", pct[1], pct[0]);
}

int main(void)
{
    setenv("OPENBLAS_NUM_THREADS", "1", 0);
    RUN(a_sample_is_the_mesh_at_its_vertices);
    RUN(modes_in_blocks_are_the_network_at_each_point);
    RUN(a_sample_trains_a_model_for_every_vertex);
    return test_finish();
}
