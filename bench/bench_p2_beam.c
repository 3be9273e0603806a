/* The freeform beam's converged static sag by quadratic tets (issue 37): the 3D solid the reduced
 * models' static sag is measured against, where P1 tets cannot converge at a size this machine
 * runs (they lock in bending at nu = 0.45). For nu = 0 and 0.45: P2 on the Table-1 box mesh
 * (1,920 tets) and its 1:8 refinements up to LEVELS (default 2: 122,880 tets, 175k nodes, about 3
 * minutes and 7 GB on 2 cores), each level's sag, its change from the level before, and
 * Richardson's extrapolation from the last three levels (their observed rate), which is the
 * converged solid's sag with the last level's distance to it as the reference's own error.
 * Writes bench/results/p2_beam.csv (OUT_DIR to change). Usage: build/bench_p2_beam [LEVELS] */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "../tests/unit/freeform_beam.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    int levels = argc > 1 ? atoi(argv[1]) : 2;
    if (levels < 0 || levels > 3) {
        fprintf(stderr, "bench_p2_beam: LEVELS %d out of 0..3\n", levels);
        return 2;
    }
    const char *dir = getenv("OUT_DIR") ? getenv("OUT_DIR") : "bench/results";
    char path[512];
    snprintf(path, sizeof path, "%s/p2_beam.csv", dir);
    FILE *out = fopen(path, "w");
    if (!out) {
        fprintf(stderr, "bench_p2_beam: cannot write %s\n", path);
        return 1;
    }
    fprintf(out, "nu,level,tets,p2_nodes,seconds,sag_m,percent_of_timoshenko,change_from_previous,"
                 "richardson_sag_m,richardson_percent_of_timoshenko,level_distance_to_richardson\n");
    const double nus[2] = {0, 0.45};
    for (int k = 0; k < 2; k++) {
        double sag[4], t = beam_timoshenko_tip(nus[k]);
        for (int l = 0; l <= levels; l++) {
            rk_error err;
            int nodes = 0;
            double start = now();
            sag[l] = beam_p2_sag(nus[k], l, &nodes, &err);
            double seconds = now() - start;
            if (!(sag[l] == sag[l])) {
                fprintf(stderr, "bench_p2_beam: nu %g level %d: %s\n", nus[k], l, err.msg);
                fclose(out);
                return 1;
            }
            char change[32] = "", rich[32] = "", richp[32] = "", dist[32] = "";
            if (l > 0) snprintf(change, sizeof change, "%.3e", (sag[l] - sag[l - 1]) / sag[l]);
            if (l > 1) { /* the observed rate of the last two changes */
                double d1 = sag[l - 1] - sag[l - 2], d2 = sag[l] - sag[l - 1];
                if (d2 != 0 && d1 / d2 > 1) {
                    double s = sag[l] + d2 / (d1 / d2 - 1);
                    snprintf(rich, sizeof rich, "%.6f", s);
                    snprintf(richp, sizeof richp, "%.2f", 100 * s / t);
                    snprintf(dist, sizeof dist, "%.2e", (s - sag[l]) / s);
                }
            }
            fprintf(out, "%.2f,%d,%d,%d,%.1f,%.6f,%.2f,%s,%s,%s,%s\n", nus[k], l, 1920 << (3 * l), nodes, seconds,
                    sag[l], 100 * sag[l] / t, change, rich, richp, dist);
            fflush(out);
            printf("nu %.2f level %d: sag %.6f m (%.2f%% of Timoshenko %.5f), %.1f s\n", nus[k], l, sag[l],
                   100 * sag[l] / t, t, seconds);
        }
    }
    fclose(out);
    printf("%s\n", path);
    return 0;
}
