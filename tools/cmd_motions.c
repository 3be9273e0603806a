/* romkit motions TEMPLATE.json --kind pachinko|dryer -o DIR [--count N] [--seed S] [--duration T]
 *                [--speed V] [--quiet]
 *
 * Training motions for the methods that learn from other runs (precompute/motions/motions.h): the
 * template's one object dropped through a pachinko board of pegs, or tumbled in a turning drum,
 * N scenes with their own draws, for romkit fom to run and rom.training to list. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "motions/motions.h"

static void motions_usage(FILE *f)
{
    fprintf(f,
            "usage: romkit motions TEMPLATE.json --kind pachinko|dryer -o DIR [--count N] [--seed S]\n"
            "                      [--duration T] [--speed V] [--quiet]\n"
            "  writes N scenes (DIR/<kind>_<k>.json) of the template's one object (free, under gravity):\n"
            "  pachinko  dropped through 5 staggered rows of pegs between walls onto a floor, each from its\n"
            "            own place along the board with its own velocity\n"
            "  dryer     tumbled in a turning octagonal drum (DIR/drum.obj), each with its own velocity\n"
            "            and the drum's own rate (0.3-0.7 of the rate that pins it to the wall) and sense\n"
            "  sized by the object's largest extent L: pegs of radius 0.1 L, 2.4 L apart; the drum's inner\n"
            "  radius its half diagonal plus 0.25 L. The template's time, contact, damping and newton\n"
            "  sections are kept (friction 0.3 unless given); its rom, reference and obstacles go.\n"
            "  --count     scenes, 1 to 1000 (default 4)\n"
            "  --seed      the draws' seed (default 1): the same seed writes the same files\n"
            "  --duration  seconds each (default: the template's time.duration)\n"
            "  --speed     the largest initial speed drawn, m/s (default 1)\n"
            "  Nothing is written when it fails.\n\n"
            "example:\n"
            "  romkit motions tests/data/demo_small.json --kind pachinko --count 8 -o motions\n"
            "  for s in motions/*.json; do romkit fom $s --snapshots ${s%%.json}.npy; done\n"
            "  then list them in a rom entry: \"training\": [{\"snapshots\": \"motions/pachinko_0.npy\"}, ...]\n");
}

int cmd_motions(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            motions_usage(stdout);
            return 0;
        }
    const char *path, *out = NULL, *kind = NULL, *count = "4", *seed = "1", *duration = NULL, *speed = NULL;
    int quiet = 0;
    const cli_option opts[] = {{"-o", &out, NULL},          {"--kind", &kind, NULL},         {"--count", &count, NULL},
                               {"--seed", &seed, NULL},     {"--duration", &duration, NULL}, {"--speed", &speed, NULL},
                               {"--quiet", NULL, &quiet},   {NULL, NULL, NULL}};
    if (cli_parse("motions", argc, argv, opts, &path, "template scene")) {
        motions_usage(stderr);
        return 2;
    }
    rk_motions_options o = {0};
    long n, s;
    const char *bad = !out ? "-o DIR is required"
                      : !kind || (strcmp(kind, "pachinko") && strcmp(kind, "dryer")) ? "--kind must be pachinko or dryer"
                      : cli_whole(count, 1, RK_MOTIONS_MAX, &n) ? "--count must be a whole number from 1 to 1000"
                      : cli_whole(seed, 0, 2147483647L, &s) ? "--seed must be a whole number from 0 to 2147483647"
                      : duration && cli_real(duration, 1e-6, 1e6, &o.duration) ? "--duration must be a number of seconds in (0, 1e6]"
                      : speed && cli_real(speed, 0, 1e3, &o.speed) ? "--speed must be a number of m/s in [0, 1000]"
                      : NULL;
    if (bad) {
        fprintf(stderr, "romkit motions: %s\n", bad);
        motions_usage(stderr);
        return 2;
    }
    o.kind = strcmp(kind, "dryer") ? RK_MOTIONS_PACHINKO : RK_MOTIONS_DRYER;
    o.count = (int)n;
    o.seed = (uint64_t)s;
    rk_motions_report *rep = malloc(sizeof *rep);
    rk_error err = {{0}};
    if (!rep || rk_motions_write(path, &o, out, rep, &err)) {
        fprintf(stderr, "romkit motions: %s\n", rep ? err.msg : "out of memory");
        free(rep);
        return 1;
    }
    if (!quiet) {
        printf("%s: %d %s scenes of %s (L = %.4g m, %d obstacle%s each", out, o.count, kind, path, rep->extent, rep->obstacles,
               rep->obstacles == 1 ? "" : "s");
        if (o.kind == RK_MOTIONS_PACHINKO) printf(": %d pegs and 5 planes)\n", rep->pegs);
        else printf(": a drum of inner radius %.4g m, %s/drum.obj)\n", rep->drum_radius, out);
        if (rep->replaced) printf("  the template's %d obstacles are not in them\n", rep->replaced);
        for (int k = 0; k < o.count; k++) {
            const rk_motions_draw *d = &rep->draw[k];
            printf("  %s/%s_%d.json: velocity [%.3g, %.3g, %.3g] m/s", out, kind, k, d->velocity[0], d->velocity[1],
                   d->velocity[2]);
            if (o.kind == RK_MOTIONS_PACHINKO) printf(", %.3g m along the board\n", d->offset);
            else printf(", drum at %.3g deg/s\n", d->spin);
        }
    }
    free(rep);
    return 0;
}
