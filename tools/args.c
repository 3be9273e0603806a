/* Option parsing shared by the subcommands. */
#include "args.h"

#include "formats/rombin.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int cli_parse(const char *cmd, int argc, char **argv, const cli_option *opts, const char **positional,
              const char *what_positional)
{
    *positional = NULL;
    for (int i = 1; i < argc; i++) {
        const cli_option *o = opts;
        while (o->name && strcmp(o->name, argv[i]) != 0) o++;
        if (o->name) {
            if (o->flag) {
                *o->flag = 1;
                continue;
            }
            if (i + 1 >= argc) {
                fprintf(stderr, "romkit %s: %s needs a value\n", cmd, argv[i]);
                return -1;
            }
            *o->value = argv[++i];
        } else if (argv[i][0] == '-' && argv[i][1]) {
            fprintf(stderr, "romkit %s: unknown option '%s'\n", cmd, argv[i]);
            return -1;
        } else if (!*positional) {
            *positional = argv[i];
        } else {
            fprintf(stderr, "romkit %s: unexpected argument '%s'\n", cmd, argv[i]);
            return -1;
        }
    }
    if (!*positional) {
        fprintf(stderr, "romkit %s: no %s given\n", cmd, what_positional);
        return -1;
    }
    return 0;
}

int cli_whole(const char *text, long lo, long hi, long *out)
{
    char *end;
    long v = text ? strtol(text, &end, 10) : 0;
    if (!text || end == text || *end || v < lo || v > hi) return -1;
    *out = v;
    return 0;
}

int cli_real(const char *text, double lo, double hi, double *out)
{
    char *end;
    double v = text ? strtod(text, &end) : NAN;
    if (!text || end == text || *end || !isfinite(v) || v < lo || v > hi) return -1;
    *out = v;
    return 0;
}

int cli_precision(const char *cmd, const char *text, int *given, int *real_type)
{
    *given = text != NULL;
    if (!text) return 0;
    if (strcmp(text, "float32") == 0) *real_type = ROMBIN_REAL_F32;
    else if (strcmp(text, "float64") == 0) *real_type = ROMBIN_REAL_F64;
    else {
        fprintf(stderr, "romkit %s: --precision must be float32 or float64, got '%s'\n", cmd, text);
        return -1;
    }
    return 0;
}

int cli_take_all(const char *cmd, int *argc, char **argv, const char *name, const char **out, int max)
{
    int n = 0, k = 1;
    for (int i = 1; i < *argc; i++) {
        if (strcmp(argv[i], name) != 0) {
            argv[k++] = argv[i];
            continue;
        }
        if (i + 1 >= *argc) {
            fprintf(stderr, "romkit %s: %s needs a value\n", cmd, name);
            return -1;
        }
        if (n == max) {
            fprintf(stderr, "romkit %s: %s given more than %d times\n", cmd, name, max);
            return -1;
        }
        out[n++] = argv[++i];
    }
    *argc = k;
    argv[k] = NULL;
    return n;
}
