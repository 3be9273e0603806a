/* make bench, physics part: the cost of one dP/dF, raw, projected to PSD by the energy's analytic
 * eigensystem (physics_impl.h, Smith et al. 2019) and by the 9 x 9 Jacobi eigen-solve it replaced,
 * per material, in double (the precompute) and float (the runtime's physics), on 256 deformation
 * gradients (random within 30% of the rest shape, a fifth of them inverted). Each timing is the
 * median over REPEATS passes of the set with the fastest and slowest pass; the ratios are taken
 * in this run. Writes bench/results/physics.{csv,json}. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bench_cases.h"
#include "physics/physics.h"
#include "util/util.h"

/* The float physics, as the runtime compiles it. */
#define PHYS_REAL float
#define PHYS_FLOAT 1
#define PHYS_FN(name) f32_##name
#include "physics/physics_impl.h"
#undef PHYS_REAL
#undef PHYS_FLOAT
#undef PHYS_FN

#define NF 256
#define REPEATS 21

static const char *const names[4] = {"linear", "corotated", "stvk", "neohookean"};

/* Microseconds per dP/dF: median, min and max over the passes. */
static bench_stat time_double(rk_material_model model, const double F[NF][9], int project, double *sink)
{
    double t[REPEATS], D[81];
    for (int r = 0; r < REPEATS; r++) {
        double t0 = rk_now();
        for (int k = 0; k < NF; k++) {
            rk_dpdf(model, 1.0, 4.0, F[k], D, project);
            *sink += D[40];
        }
        t[r] = (rk_now() - t0) / NF * 1e6;
    }
    return bench_stat_of(t, REPEATS);
}

static bench_stat time_float(rk_material_model model, const float F[NF][9], int project, double *sink)
{
    double t[REPEATS];
    float D[81];
    for (int r = 0; r < REPEATS; r++) {
        double t0 = rk_now();
        for (int k = 0; k < NF; k++) {
            f32_dpdf(model, 1.0f, 4.0f, F[k], D, project);
            *sink += D[40];
        }
        t[r] = (rk_now() - t0) / NF * 1e6;
    }
    return bench_stat_of(t, REPEATS);
}

int main(int argc, char **argv)
{
    const char *out_dir = argc > 2 ? argv[2] : "bench/results";
    static double F[NF][9];
    static float Ff[NF][9];
    uint64_t rng = 3;
    double sink = 0;
    for (int k = 0; k < NF; k++) {
        for (int i = 0; i < 9; i++) F[k][i] = (i % 4 == 0) + 0.3 * (2 * rk_uniform(&rng) - 1);
        if (k % 5 == 0)
            for (int i = 6; i < 9; i++) F[k][i] = -F[k][i]; /* a reflected row: det F < 0 */
        for (int i = 0; i < 9; i++) Ff[k][i] = (float)F[k][i];
    }
    FILE *csv, *json;
    if (bench_open_results(out_dir, "physics", "material,precision,raw_us,raw_us_min,raw_us_max,analytic_us,analytic_us_min,"
                           "analytic_us_max,jacobi_us,jacobi_us_min,jacobi_us_max,jacobi_over_analytic", &csv, &json))
        return 1;
    printf("%-11s %-6s %24s %24s %24s %9s\n", "material", "", "raw us (min..max)", "analytic us", "Jacobi us", "speed-up");
    for (int m = 0; m < 4; m++)
        for (int prec = 0; prec < 2; prec++) {
            rk_material_model model = (rk_material_model)m;
            bench_stat raw = prec ? time_float(model, Ff, 0, &sink) : time_double(model, F, 0, &sink);
            bench_stat ana = prec ? time_float(model, Ff, 1, &sink) : time_double(model, F, 1, &sink);
            bench_stat jac = prec ? time_float(model, Ff, RK_PROJECT_JACOBI, &sink)
                                  : time_double(model, F, RK_PROJECT_JACOBI, &sink);
            const char *p = prec ? "float" : "double";
            printf("%-11s %-6s %8.3f (%.3f..%.3f) %8.3f (%.3f..%.3f) %8.3f (%.3f..%.3f) %8.1fx\n", names[m], p,
                   BENCH_STAT3(raw), BENCH_STAT3(ana), BENCH_STAT3(jac), jac.median / ana.median);
            fprintf(csv, "%s,%s,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.4g\n", names[m], p, BENCH_STAT3(raw),
                    BENCH_STAT3(ana), BENCH_STAT3(jac), jac.median / ana.median);
            fprintf(json, "%s  {\"material\": \"%s\", \"precision\": \"%s\", \"raw_us\": %.6g, \"analytic_us\": %.6g, "
                    "\"jacobi_us\": %.6g, \"jacobi_over_analytic\": %.4g}", m || prec ? ",\n" : "", names[m], p,
                    raw.median, ana.median, jac.median, jac.median / ana.median);
        }
    fprintf(json, "\n]\n");
    fclose(csv);
    fclose(json);
    return sink == 0.123 ? 2 : 0; /* keeps the work */
}
