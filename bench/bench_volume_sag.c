/* The FreeForm beam's static sag per volume treatment and pressure space (issue 37): the mesh-free
 * rkpm_skinning model (tests/unit/meshfree_beam.h, the Dirichlet clamp) at each m and nu, against
 * the converged solid (P2, Richardson: 0.1220 m at nu = 0.45, docs/results/p2_beam.md) and
 * Timoshenko's tip (nu = 0, where P2 is 99.98% of it); then the same with the mesh skinning basis
 * on the 1,920 P1 tets (BASIS=rkpm_skinning or skinning: one of them). VOLUMES (a list of names)
 * picks rows; "default" is the model built with no volume key. Writes OUT_DIR/volume_sag.csv
 * (default dir bench/results). Usage: build/bench_volume_sag [NU,...] [M,...] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../tests/unit/meshfree_beam.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    static const char *const names[] = {"pointwise", "weights", "weights_affine", "constant", "default"};
    static const char *const keys[] = {"\"volume\": \"pointwise\"", "\"volume\": \"projected\", \"pressure\": \"weights\"",
                                       "\"volume\": \"projected\", \"pressure\": \"weights_affine\"",
                                       "\"volume\": \"projected\", \"pressure\": \"constant\"", NULL};
    double nus[8] = {0.45, 0};
    int ms[8] = {6, 9, 16, 20, 32}, nnu = 2, nm = 5;
    if (argc > 1) {
        nnu = 0;
        for (char *s = strtok(argv[1], ","); s && nnu < 8; s = strtok(NULL, ",")) nus[nnu++] = atof(s);
    }
    if (argc > 2) {
        nm = 0;
        for (char *s = strtok(argv[2], ","); s && nm < 8; s = strtok(NULL, ",")) ms[nm++] = atoi(s);
    }
    const char *only = getenv("VOLUMES");
    const char *basis = getenv("BASIS");
    const char *dir = getenv("OUT_DIR") ? getenv("OUT_DIR") : "bench/results";
    char path[512];
    snprintf(path, sizeof path, "%s/volume_sag.csv", dir);
    FILE *out = fopen(path, "w");
    if (!out) {
        fprintf(stderr, "bench_volume_sag: cannot write %s\n", path);
        return 1;
    }
    fprintf(out, "basis,nu,m,volume,tip_m,reference_m,percent_of_reference,seconds\n");
    for (int mesh = 0; mesh < 2; mesh++) {
        for (int a = 0; a < nnu; a++)
            for (int b = 0; b < nm; b++)
                for (int k = 0; k < 5; k++) {
                    if ((only && !strstr(only, names[k])) || (basis && strcmp(basis, mesh ? "skinning" : "rkpm_skinning")))
                        continue;
                    rk_error err;
                    int ok;
                    double ref = nus[a] == 0.45 ? 0.1220 : timoshenko_tip(nus[a]), start = now();
                    char rom[400];
                    snprintf(rom, sizeof rom, "\"basis\": \"skinning\", \"size\": %d%s%s", ms[b], keys[k] ? ", " : "",
                             keys[k] ? keys[k] : "");
                    double tip = mesh ? model_tip_rom(nus[a], rom, NULL, NULL, &err, &ok)
                                      : model_tip_keys(nus[a], ms[b], 0, keys[k], NULL, NULL, &err, &ok);
                    double seconds = now() - start;
                    if (!ok) {
                        fprintf(stderr, "bench_volume_sag: nu %g m %d %s: %s\n", nus[a], ms[b], names[k], err.msg);
                        continue;
                    }
                    fprintf(out, "%s,%.2f,%d,%s,%.6f,%.6f,%.2f,%.1f\n", mesh ? "skinning" : "rkpm_skinning", nus[a], ms[b],
                            names[k], tip, ref, 100 * tip / ref, seconds);
                    fflush(out);
                    printf("%-13s nu %.2f m %2d %-15s tip %.5f m, %6.2f%% of %s %.5f (%.1f s)\n",
                           mesh ? "skinning" : "rkpm_skinning", nus[a], ms[b], names[k], tip, 100 * tip / ref, nus[a] == 0.45 ? "the solid" : "Timoshenko", ref, seconds);
                    fflush(stdout);
                }
    }
    fclose(out);
    return 0;
}
