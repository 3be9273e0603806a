/* Cubature point selection: Lawson-Hanson NNLS against brute force over every passive set and
 * the KKT conditions, warm starts, and the greedy selection recovering an exact quadrature rule
 * on [-1, 1] (Caratheodory: at most `rows` points suffice), its stopping rules, reproducibility
 * under sampling, and bad input. */
#include "cubature/cubature.h"
#include "testlib.h"
#include "util/util.h"

#include <cblas.h>
#include <lapacke.h>

/* The project's generator (util/util.h), so the problems are the same everywhere. */
static uint64_t rng_state;

static double uniform(double lo, double hi) { return lo + (hi - lo) * rk_uniform(&rng_state); }

/* A small dense problem A (m x k, column-major), b, and its normal equations. */
typedef struct {
    int m, k;
    double A[10 * 6], b[10], gram[6 * 6], atb[6];
} dense;

static void normal_equations(dense *d)
{
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, d->k, d->k, d->m, 1.0, d->A, d->m, d->A, d->m,
                0.0, d->gram, d->k);
    cblas_dgemv(CblasColMajor, CblasTrans, d->m, d->k, 1.0, d->A, d->m, d->b, 1, 0.0, d->atb, 1);
}

static void random_dense(dense *d, uint64_t seed)
{
    rng_state = seed;
    d->m = 10;
    d->k = 6;
    for (int i = 0; i < d->m * d->k; i++) d->A[i] = uniform(-1, 1);
    for (int i = 0; i < d->m; i++) d->b[i] = uniform(-1, 1);
    normal_equations(d);
}

/* |A w - b|^2 straight from A. */
static double objective(const dense *d, const double *w)
{
    double r[10], s = 0;
    memcpy(r, d->b, sizeof(double) * d->m);
    cblas_dgemv(CblasColMajor, CblasNoTrans, d->m, d->k, 1.0, d->A, d->m, w, 1, -1.0, r, 1);
    for (int i = 0; i < d->m; i++) s += r[i] * r[i];
    return s;
}

/* Unconstrained least squares on the columns in `mask` (LAPACK dgels); x gets 0 elsewhere. */
static int ls_on(const dense *d, unsigned mask, double *x)
{
    double Ap[10 * 6], bp[10];
    int cols[6], np = 0;
    for (int j = 0; j < d->k; j++) {
        x[j] = 0;
        if (mask >> j & 1u) cols[np++] = j;
    }
    if (np == 0) return 0;
    for (int c = 0; c < np; c++) memcpy(Ap + c * d->m, d->A + cols[c] * d->m, sizeof(double) * d->m);
    memcpy(bp, d->b, sizeof(double) * d->m);
    if (LAPACKE_dgels(LAPACK_COL_MAJOR, 'N', d->m, np, 1, Ap, d->m, bp, d->m) != 0) return -1;
    for (int c = 0; c < np; c++) x[cols[c]] = bp[c];
    return 0;
}

/* The NNLS optimum by enumeration: the best of the unconstrained solutions on every passive
 * set that happen to be non-negative (the optimum is one of them). */
static double brute_force(const dense *d)
{
    double best = INFINITY, x[6];
    for (unsigned mask = 0; mask < 1u << d->k; mask++) {
        if (ls_on(d, mask, x)) continue;
        int feasible = 1;
        for (int j = 0; j < d->k; j++) feasible &= x[j] >= 0;
        if (feasible) best = fmin(best, objective(d, x));
    }
    return best;
}

/* The worst KKT violation of w relative to max_j |a_j| |b|: negative weights, positive duals
 * A^T (b - A w) at zero weights, non-zero duals at positive weights. */
static double kkt_violation(const dense *d, const double *w)
{
    double r[10], dual[6], worst = 0, scale = 0;
    memcpy(r, d->b, sizeof(double) * d->m);
    cblas_dgemv(CblasColMajor, CblasNoTrans, d->m, d->k, -1.0, d->A, d->m, w, 1, 1.0, r, 1);
    cblas_dgemv(CblasColMajor, CblasTrans, d->m, d->k, 1.0, d->A, d->m, r, 1, 0.0, dual, 1);
    for (int j = 0; j < d->k; j++) scale = fmax(scale, test_norm(d->A + j * d->m, d->m) * test_norm(d->b, d->m));
    for (int j = 0; j < d->k; j++) {
        if (w[j] < 0) return INFINITY;
        worst = fmax(worst, w[j] > 0 ? fabs(dual[j]) : fmax(dual[j], 0));
    }
    return worst / scale;
}

TEST(nnls_matches_brute_force_and_satisfies_kkt)
{
    rk_error err;
    int seeds = 12, constrained = 0, mixed = 0;
    double worst_obj = 0, worst_kkt = 0;
    for (int s = 0; s < seeds; s++) {
        dense d;
        random_dense(&d, 1000 + s);
        double w[6] = {0}, x[6];
        CHECK_OK(rk_nnls_normal(d.k, d.gram, d.atb, w, 0, &err));
        double best = brute_force(&d), f = objective(&d, w);
        worst_obj = fmax(worst_obj, fabs(f - best) / best);
        worst_kkt = fmax(worst_kkt, kkt_violation(&d, w));
        CHECK(ls_on(&d, (1u << d.k) - 1, x) == 0, "dgels failed");
        int negative = 0, zeros = 0;
        for (int j = 0; j < d.k; j++) { negative += x[j] < 0; zeros += w[j] == 0; }
        constrained += negative > 0;
        mixed += zeros > 0 && zeros < d.k;
    }
    printf("# NNLS on %d random 10x6 problems: objective vs brute force %.2g, KKT violation %.2g\n",
           seeds, worst_obj, worst_kkt);
    /* The comparison only means something when the bounds bind and the answer is not trivial. */
    CHECK(constrained >= seeds / 2 && mixed >= seeds / 2,
          "only %d problems had a negative unconstrained solution, %d a mixed active set", constrained, mixed);
    CHECK(worst_obj <= 1e-10, "NNLS objective differs from the brute-force optimum by %.3g relative", worst_obj);
    CHECK(worst_kkt <= 1e-12, "KKT conditions violated by %.3g (relative)", worst_kkt);
}

TEST(nnls_returns_a_nonnegative_unconstrained_solution)
{
    rk_error err;
    dense d;
    random_dense(&d, 77);
    for (int i = 0; i < d.m; i++) {
        d.b[i] *= 0.01;
        for (int j = 0; j < d.k; j++) d.b[i] += d.A[j * d.m + i] * (0.5 + 0.1 * j);
    }
    normal_equations(&d);
    double x[6], w[6] = {0};
    CHECK(ls_on(&d, (1u << d.k) - 1, x) == 0, "dgels failed");
    for (int j = 0; j < d.k; j++) CHECK(x[j] > 0, "setup: unconstrained weight %d is %g", j, x[j]);
    CHECK_OK(rk_nnls_normal(d.k, d.gram, d.atb, w, 0, &err));
    double diff = 0;
    for (int j = 0; j < d.k; j++) diff = fmax(diff, fabs(w[j] - x[j]));
    CHECK(diff <= 1e-10 * test_norm(x, d.k), "NNLS differs from dgels by %.3g", diff);
}

TEST(nnls_warm_start_gives_the_cold_solution)
{
    rk_error err;
    dense d;
    random_dense(&d, 1003);
    double cold[6] = {0};
    CHECK_OK(rk_nnls_normal(d.k, d.gram, d.atb, cold, 0, &err));
    int zeros = 0;
    for (int j = 0; j < d.k; j++) zeros += cold[j] == 0;
    CHECK(zeros > 0 && zeros < d.k, "setup: the cold solution has %d zero weights of %d", zeros, d.k);
    /* From the answer itself, from everything passive, from a wrong passive set (negative
     * entries count as 0). */
    double starts[3][6] = {{0}, {1, 1, 1, 1, 1, 1}, {0, 2, -1, 0, 3, 0}};
    memcpy(starts[0], cold, sizeof cold);
    for (int s = 0; s < 3; s++) {
        double w[6];
        memcpy(w, starts[s], sizeof w);
        CHECK_OK(rk_nnls_normal(d.k, d.gram, d.atb, w, 0, &err));
        double diff = 0;
        for (int j = 0; j < d.k; j++) diff = fmax(diff, fabs(w[j] - cold[j]));
        CHECK(diff <= 1e-12 * test_norm(cold, d.k), "warm start %d lands %.3g from the cold solution", s, diff);
        for (int j = 0; j < d.k; j++)
            CHECK((w[j] == 0) == (cold[j] == 0), "warm start %d: weight %d is %g, cold %g", s, j, w[j], cold[j]);
    }
}

/* Column 5 duplicates column 1 and column 4 = column 0 + column 2, so some passive Gram blocks
 * are singular: the entering index that would make one must be refused, and a warm start on
 * all six columns must fall back to a cold start. */
TEST(nnls_survives_dependent_columns)
{
    rk_error err;
    int tried = 0;
    double worst_obj = 0, worst_kkt = 0;
    for (int s = 0; s < 8; s++) {
        dense d;
        random_dense(&d, 3000 + s);
        for (int i = 0; i < d.m; i++) {
            d.A[5 * d.m + i] = d.A[1 * d.m + i];
            d.A[4 * d.m + i] = d.A[0 * d.m + i] + d.A[2 * d.m + i];
            d.b[i] = fabs(d.b[i]) + d.A[4 * d.m + i];
        }
        normal_equations(&d);
        double best = brute_force(&d);
        double starts[2][6] = {{0}, {1, 1, 1, 1, 1, 1}};
        for (int k = 0; k < 2; k++, tried++) {
            CHECK_OK(rk_nnls_normal(d.k, d.gram, d.atb, starts[k], 0, &err));
            worst_obj = fmax(worst_obj, fabs(objective(&d, starts[k]) - best) / best);
            worst_kkt = fmax(worst_kkt, kkt_violation(&d, starts[k]));
        }
    }
    /* Normal equations no real A has (a_2 = a_0 + a_1 but atb_2 != atb_0 + atb_1): from w = 0,
     * index 2 enters, then 0, and then index 1 would make the passive block exactly singular,
     * so it is refused and the weights stay where they were. */
    double gram[9] = {1, 0, 1, 0, 1, 1, 1, 1, 2}, atb[3] = {2, 1, 2.5}, w[3] = {0, 0, 0};
    CHECK_OK(rk_nnls_normal(3, gram, atb, w, 0, &err));
    CHECK(fabs(w[0] - 1.5) < 1e-14 && w[1] == 0 && fabs(w[2] - 0.5) < 1e-14,
          "singular entry: w = (%g, %g, %g), expected (1.5, 0, 0.5)", w[0], w[1], w[2]);
    printf("# NNLS with dependent columns (%d solves): objective vs brute force %.2g, KKT %.2g\n",
           tried, worst_obj, worst_kkt);
    CHECK(worst_obj <= 1e-10, "objective differs from the brute-force optimum by %.3g relative", worst_obj);
    CHECK(worst_kkt <= 1e-12, "KKT conditions violated by %.3g (relative)", worst_kkt);
}

/* Monomials x^0..x^(rows-1) at candidate points; counts the callback calls. */
typedef struct {
    int n, rows, calls, fail_at, nan_at;
    double x[200];
} monomials;

static int monomial_column(void *ctx, int c, double *col, rk_error *err)
{
    monomials *m = ctx;
    m->calls++;
    if (c == m->fail_at) return rk_fail(err, "disk read failed for point %d", c);
    double p = 1;
    for (int i = 0; i < m->rows; i++, p *= m->x[c]) col[i] = p;
    if (c == m->nan_at) col[m->rows - 1] = NAN;
    return 0;
}

/* 200 points uniform in [-1, 1]; b = the exact integrals of the monomials over [-1, 1]. */
static void quadrature_problem(monomials *m, double *b, rk_cubature_problem *p)
{
    rng_state = 2024;
    m->n = 200;
    m->rows = 10;
    m->calls = 0;
    m->fail_at = m->nan_at = -1;
    for (int c = 0; c < m->n; c++) m->x[c] = uniform(-1, 1);
    for (int i = 0; i < m->rows; i++) b[i] = i % 2 ? 0 : 2.0 / (i + 1);
    *p = (rk_cubature_problem){.rows = m->rows, .candidates = m->n, .column = monomial_column, .ctx = m,
                               .b = b, .tolerance = 1e-10, .max_points = m->n, .sample = 0, .seed = 1};
}

/* |A_S w - b| / |b| recomputed here from the points. */
static double recomputed_error(const monomials *m, const double *b, const rk_cubature_set *s)
{
    double r[10];
    for (int i = 0; i < m->rows; i++) {
        r[i] = -b[i];
        for (int j = 0; j < s->count; j++) r[i] += s->weight[j] * pow(m->x[s->index[j]], i);
    }
    return test_norm(r, m->rows) / test_norm(b, m->rows);
}

TEST(greedy_recovers_an_exact_quadrature_rule)
{
    rk_error err;
    monomials m;
    double b[10];
    rk_cubature_problem p;
    quadrature_problem(&m, b, &p);
    rk_cubature_set s;
    CHECK_OK(rk_cubature_greedy(&p, &s, &err));
    double sum = 0, wmin = INFINITY, rec = recomputed_error(&m, b, &s);
    int ascending = 1;
    for (int j = 0; j < s.count; j++) {
        sum += s.weight[j];
        wmin = fmin(wmin, s.weight[j]);
        if (j > 0) ascending &= s.index[j] > s.index[j - 1];
    }
    printf("# exact rule for degree 9 on [-1, 1] from 200 points: %d points, %d iterations, "
           "relative error %.3g\n", s.count, s.iterations, s.relative_error);
    int count = s.count, reached = s.reached;
    double rel = s.relative_error;
    rk_cubature_set_free(&s);
    CHECK(reached && rel <= 1e-10, "tolerance not reached: relative error %.3g with %d points", rel, count);
    CHECK(count >= 1 && count <= 10, "%d points (a rule with at most 10 exists)", count);
    CHECK(wmin > 0, "smallest weight %g", wmin);
    CHECK(ascending, "indices are not ascending");
    CHECK(fabs(sum - 2) <= 1e-9, "weights sum to %.15g, the length of [-1, 1] is 2", sum);
    CHECK(fabs(rec - rel) <= 1e-13, "reported error %.3g, recomputed %.3g", rel, rec);
}

/* Pruning after the greedy selection: the set only shrinks, its error (recomputed from the
 * points) stays within the tolerance, the greedy count is reported, and the same input gives the
 * same set. Several tolerances, with sampling (the greedy set then has more slack). */
TEST(pruning_keeps_the_tolerance_with_no_more_points)
{
    rk_error err;
    monomials m;
    double b[10], tols[3] = {1e-2, 1e-4, 1e-8};
    rk_cubature_problem p;
    for (int t = 0; t < 3; t++) {
        rk_cubature_set plain, pruned, again;
        quadrature_problem(&m, b, &p);
        p.tolerance = tols[t];
        p.sample = 20;
        CHECK_OK(rk_cubature_greedy(&p, &plain, &err));
        p.prune = 1;
        CHECK_OK(rk_cubature_greedy(&p, &pruned, &err));
        CHECK_OK(rk_cubature_greedy(&p, &again, &err));
        double rec = recomputed_error(&m, b, &pruned);
        printf("# tolerance %g: greedy %d points (error %.3g), pruned %d (error %.3g)\n", tols[t], plain.count,
               plain.relative_error, pruned.count, pruned.relative_error);
        CHECK(pruned.greedy_count == plain.count, "greedy count %d, the unpruned run has %d", pruned.greedy_count, plain.count);
        CHECK(pruned.count <= plain.count && pruned.count >= 1, "pruned %d, greedy %d", pruned.count, plain.count);
        CHECK(pruned.reached && rec <= tols[t] * (1 + 1e-9), "pruned error %.3g over tolerance %g", rec, tols[t]);
        CHECK(fabs(rec - pruned.relative_error) <= 1e-12, "reported %.3g, recomputed %.3g", pruned.relative_error, rec);
        CHECK(again.count == pruned.count && memcmp(again.index, pruned.index, sizeof(int) * pruned.count) == 0 &&
                  memcmp(again.weight, pruned.weight, sizeof(double) * pruned.count) == 0,
              "two pruned runs differ");
        rk_cubature_set_free(&plain);
        rk_cubature_set_free(&pruned);
        rk_cubature_set_free(&again);
    }
}

/* Columns of a small dense matrix (column-major, 3 rows). */
static int dense_column(void *ctx, int c, double *col, rk_error *err)
{
    const double *A = ctx;
    (void)err;
    memcpy(col, A + 3 * c, 3 * sizeof(double));
    return 0;
}

/* A case the greedy order leaves a droppable point in: b = a1 + a2 + 0.05 a3; the first pick is
 * the column pointing most along b, c0 = a1 + a2 + a3, then a1 and a2 make the fit exact with c0
 * at weight 0.05. The tolerance 0.05 allows a1 and a2 alone (error 0.035): pruning drops c0. */
TEST(pruning_drops_the_point_the_tolerance_does_without)
{
    rk_error err;
    double A[12] = {1, 1, 1, 1, 0, 0, 0, 1, 0, 0, 0, 1}, b[3] = {1, 1, 0.05};
    rk_cubature_problem p = {.rows = 3, .candidates = 4, .column = dense_column, .ctx = A, .b = b,
                             .tolerance = 0.05, .max_points = 4, .sample = 0, .seed = 1, .prune = 1};
    rk_cubature_set s;
    CHECK_OK(rk_cubature_greedy(&p, &s, &err));
    printf("# greedy %d points, pruned to %d: indices %d %d, error %.4f\n", s.greedy_count, s.count, s.index[0],
           s.count > 1 ? s.index[1] : -1, s.relative_error);
    CHECK(s.greedy_count == 3 && s.count == 2 && s.index[0] == 1 && s.index[1] == 2,
          "greedy %d, pruned %d, first index %d", s.greedy_count, s.count, s.index[0]);
    CHECK(fabs(s.relative_error - 0.05 / sqrt(2.0025)) < 1e-12 && s.reached, "error %.6f", s.relative_error);
    rk_cubature_set_free(&s);
}

TEST(greedy_honours_max_points_and_stops_at_its_floor)
{
    rk_error err;
    monomials m;
    double b[10];
    rk_cubature_problem p;
    quadrature_problem(&m, b, &p);
    p.max_points = 3;
    rk_cubature_set s;
    CHECK_OK(rk_cubature_greedy(&p, &s, &err));
    double rec = recomputed_error(&m, b, &s);
    int count = s.count, reached = s.reached;
    double rel = s.relative_error, wmin = INFINITY;
    for (int j = 0; j < s.count; j++) wmin = fmin(wmin, s.weight[j]);
    rk_cubature_set_free(&s);
    printf("# with at most 3 points: relative error %.3g\n", rel);
    CHECK(count >= 1 && count <= 3, "%d points with max_points 3", count);
    CHECK(!reached && rel > p.tolerance, "reached = %d with relative error %.3g", reached, rel);
    CHECK(wmin > 0, "smallest weight %g", wmin);
    CHECK(fabs(rec - rel) <= 1e-13, "reported error %.3g, recomputed %.3g", rel, rec);
    /* Tolerance 0 cannot be met in floating point: the run must end when an iteration stops
     * helping (the re-fit keeps at most `rows` points, so max_points would never stop it), with
     * an error no worse than the 1e-10 run that took the same path. */
    p.max_points = m.n;
    CHECK_OK(rk_cubature_greedy(&p, &s, &err));
    double rel_tol = s.relative_error;
    rk_cubature_set_free(&s);
    p.tolerance = 0;
    CHECK_OK(rk_cubature_greedy(&p, &s, &err));
    int iterations = s.iterations;
    count = s.count;
    reached = s.reached;
    rel = s.relative_error;
    rk_cubature_set_free(&s);
    printf("# tolerance 0: %d points, %d iterations, relative error %.3g\n", count, iterations, rel);
    CHECK(!reached && iterations <= 2 * m.rows && count <= m.rows,
          "tolerance 0: reached %d, %d iterations, %d points", reached, iterations, count);
    CHECK(rel <= rel_tol, "tolerance 0 ended at %.3g, worse than the %.3g it passed", rel, rel_tol);
}

/* Columns in R^4 given in a table. */
typedef struct { double col[4][4]; } table;

static int table_column(void *ctx, int c, double *col, rk_error *err)
{
    memcpy(col, ((table *)ctx)->col[c], sizeof(double) * 4);
    return 0;
}

TEST(greedy_scores_by_direction_and_drops_points_the_refit_zeroes)
{
    rk_error err;
    /* Candidate 0 is long but off the target's direction, candidate 1 short and nearly along
     * it: the score is a cosine, so 1 is picked. */
    table t = {{{10, 0, 0, 0}, {1, 0.9, 0, 0}}};
    double b[4] = {1, 1, 0, 0.1};
    rk_cubature_problem p = {.rows = 4, .candidates = 2, .column = table_column, .ctx = &t, .b = b,
                             .tolerance = 1e-12, .max_points = 1};
    rk_cubature_set s;
    CHECK_OK(rk_cubature_greedy(&p, &s, &err));
    int first = s.count == 1 ? s.index[0] : -1;
    rk_cubature_set_free(&s);
    CHECK(first == 1, "picked candidate %d, expected 1 (the better direction)", first);
    /* b = a_1 + a_2 + 0.1 a_3 is the only exact fit. Candidate 0 = (1, 1, 0.5, 0) points best
     * along b and is picked first, then 1 and 2; the re-fit after the third pick sets its weight
     * to 0, so it must leave the set, and the fourth pick (3) is fitted with the Gram matrix
     * compacted after that drop. */
    t = (table){{{1, 1, 0.5, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0, 1}}};
    p.candidates = 4;
    p.max_points = 4;
    CHECK_OK(rk_cubature_greedy(&p, &s, &err));
    int count = s.count, iterations = s.iterations, reached = s.reached, same = count == 3;
    const int want_index[3] = {1, 2, 3};
    const double want_weight[3] = {1, 1, 0.1};
    for (int j = 0; same && j < 3; j++)
        same = s.index[j] == want_index[j] && fabs(s.weight[j] - want_weight[j]) < 1e-12;
    rk_cubature_set_free(&s);
    CHECK(iterations == 4 && reached, "%d iterations, reached %d", iterations, reached);
    CHECK(same, "kept %d points, expected 1, 2, 3 with weights 1, 1, 0.1", count);
}

TEST(greedy_with_sampling_is_reproducible)
{
    rk_error err;
    monomials m;
    double b[10];
    rk_cubature_problem p;
    quadrature_problem(&m, b, &p);
    p.sample = 20;
    p.seed = 12345;
    rk_cubature_set s1, s2, s3;
    CHECK_OK(rk_cubature_greedy(&p, &s1, &err));
    int calls = m.calls;
    CHECK_OK(rk_cubature_greedy(&p, &s2, &err));
    p.seed = 54321;
    CHECK_OK(rk_cubature_greedy(&p, &s3, &err));
    int same = s1.count == s2.count && s1.iterations == s2.iterations &&
               memcmp(s1.index, s2.index, sizeof(int) * s1.count) == 0 &&
               memcmp(s1.weight, s2.weight, sizeof(double) * s1.count) == 0 &&
               memcmp(&s1.relative_error, &s2.relative_error, sizeof(double)) == 0;
    int other_same = s1.count == s3.count && memcmp(s1.index, s3.index, sizeof(int) * s1.count) == 0;
    double rec = recomputed_error(&m, b, &s1), rel = s1.relative_error;
    int iterations = s1.iterations, reached = s1.reached;
    double wmin = INFINITY;
    for (int j = 0; j < s1.count; j++) wmin = fmin(wmin, s1.weight[j]);
    printf("# sampling 20 of 200: %d points, %d iterations, relative error %.3g; another seed: %d points (%s set)\n",
           s1.count, iterations, rel, s3.count, other_same ? "the same" : "a different");
    rk_cubature_set_free(&s1);
    rk_cubature_set_free(&s2);
    rk_cubature_set_free(&s3);
    CHECK(same, "two runs with the same seed differ");
    CHECK(fabs(rec - rel) <= 1e-13, "reported error %.3g, recomputed %.3g", rel, rec);
    /* Exactly `sample` columns fetched per iteration: the subset is really drawn. */
    CHECK(calls == 20 * iterations, "%d column calls in %d iterations of 20", calls, iterations);
    CHECK(reached, "sampling did not reach the tolerance (relative error %.3g)", rel);
    CHECK(wmin > 0, "smallest weight %g", wmin);
}

/* Candidate 0 is a zero column, the others (1, x) for x in (0, 1]; b has a negative first
 * entry, so no column points along it. */
static int half_line_column(void *ctx, int c, double *col, rk_error *err)
{
    ((int *)ctx)[c]++;
    col[0] = c ? 1 : 0;
    col[1] = c ? c / 10.0 : 0;
    return 0;
}

TEST(greedy_skips_zero_columns_and_stops_without_a_positive_score)
{
    rk_error err;
    double b[2] = {1, 0.35};
    int calls[11] = {0};
    rk_cubature_problem p = {.rows = 2, .candidates = 11, .column = half_line_column, .ctx = calls,
                             .b = b, .tolerance = 1e-12, .max_points = 11};
    rk_cubature_set s;
    CHECK_OK(rk_cubature_greedy(&p, &s, &err));
    int count = s.count, has_zero = count > 0 && s.index[0] == 0, reached = s.reached;
    double rel = s.relative_error;
    rk_cubature_set_free(&s);
    CHECK(reached && count <= 2 && !has_zero, "%d points (zero column chosen: %d), error %.3g", count, has_zero, rel);
    /* A zero column is found once and then left out of the scoring. */
    CHECK(calls[0] == 1 && calls[1] > 1, "zero column fetched %d times, another %d", calls[0], calls[1]);
    b[0] = -1;
    CHECK_OK(rk_cubature_greedy(&p, &s, &err));
    count = s.count;
    reached = s.reached;
    rel = s.relative_error;
    rk_cubature_set_free(&s);
    CHECK(count == 0 && !reached && rel == 1, "outside the cone: %d points, error %.3g", count, rel);
}

/* Candidate 0 is zero to rounding (1e-27, an element whose vertices are all held) and points
 * exactly along b, so its cosine is the best; 1 and 2 fit b exactly. Scored by its cosine it was
 * picked first and the greedy ended there (the armadillo's bend: 3 points, force error 0.63,
 * against 300 points and 0.01 once such columns leave the pool). */
static int rounding_column(void *ctx, int c, double *col, rk_error *err)
{
    (void)ctx;
    (void)err;
    col[0] = c == 0 ? 1e-27 : c == 1 ? 1 : 0;
    col[1] = c == 0 ? 1e-27 : c == 2 ? 1 : 0;
    col[2] = 0;
    return 0;
}

TEST(greedy_leaves_out_columns_that_are_zero_to_rounding)
{
    rk_error err;
    double b[3] = {1, 1, 0};
    rk_cubature_problem p = {.rows = 3, .candidates = 3, .column = rounding_column, .b = b,
                             .tolerance = 1e-12, .max_points = 3};
    rk_cubature_set s;
    CHECK_OK(rk_cubature_greedy(&p, &s, &err));
    int count = s.count, reached = s.reached, has_tiny = 0;
    double wmax = 0;
    for (int j = 0; j < s.count; j++) {
        has_tiny |= s.index[j] == 0;
        wmax = fmax(wmax, s.weight[j]);
    }
    rk_cubature_set_free(&s);
    CHECK(reached && count == 2 && !has_tiny && fabs(wmax - 1) < 1e-12,
          "%d points (the rounding column among them: %d), largest weight %g, reached %d", count, has_tiny, wmax,
          reached);
}

TEST(bad_input_is_an_error_not_a_crash)
{
    rk_error err;
    monomials m;
    double b[10];
    rk_cubature_problem p;
    rk_cubature_set s;
    quadrature_problem(&m, b, &p);
    b[3] = NAN;
    int nan_b = rk_cubature_greedy(&p, &s, &err) != 0 && strstr(err.msg, "not finite") && s.index == NULL;
    CHECK(nan_b, "NaN in b: %s", err.msg);
    quadrature_problem(&m, b, &p);
    m.fail_at = 17;
    int failing = rk_cubature_greedy(&p, &s, &err) != 0 && strstr(err.msg, "disk read failed for point 17");
    CHECK(failing, "failing callback: %s", err.msg);
    m.fail_at = -1;
    m.nan_at = 5;
    int nan_col = rk_cubature_greedy(&p, &s, &err) != 0 && strstr(err.msg, "candidate 5");
    CHECK(nan_col, "NaN in a column: %s", err.msg);
    memset(b, 0, sizeof b);
    m.nan_at = -1;
    int zero_b = rk_cubature_greedy(&p, &s, &err) != 0 && strstr(err.msg, "zero");
    CHECK(zero_b, "zero target: %s", err.msg);
    double gram[4] = {1, 0, 0, NAN}, atb[2] = {1, 1}, w[2] = {0, 0};
    int nan_gram = rk_nnls_normal(2, gram, atb, w, 0, &err) != 0 && strstr(err.msg, "not finite");
    CHECK(nan_gram, "NaN in the Gram matrix: %s", err.msg);
}

int main(void)
{
    RUN(nnls_matches_brute_force_and_satisfies_kkt);
    RUN(nnls_returns_a_nonnegative_unconstrained_solution);
    RUN(nnls_warm_start_gives_the_cold_solution);
    RUN(nnls_survives_dependent_columns);
    RUN(greedy_recovers_an_exact_quadrature_rule);
    RUN(pruning_keeps_the_tolerance_with_no_more_points);
    RUN(pruning_drops_the_point_the_tolerance_does_without);
    RUN(greedy_honours_max_points_and_stops_at_its_floor);
    RUN(greedy_scores_by_direction_and_drops_points_the_refit_zeroes);
    RUN(greedy_with_sampling_is_reproducible);
    RUN(greedy_skips_zero_columns_and_stops_without_a_positive_score);
    RUN(greedy_leaves_out_columns_that_are_zero_to_rounding);
    RUN(bad_input_is_an_error_not_a_crash);
    return test_finish();
}
