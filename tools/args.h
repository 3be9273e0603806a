/* Command-line options shared by the subcommands: "--name VALUE" options, "--flag" switches
 * and one positional argument. */
#ifndef ROMKIT_ARGS_H
#define ROMKIT_ARGS_H

typedef struct {
    const char *name;    /* "--report" */
    const char **value;  /* set to the next argument; NULL for a switch */
    int *flag;           /* set to 1 for a switch; NULL for an option with a value */
} cli_option;

/* Fills the options (terminated by a {NULL} entry) and *positional. Prints
 * "romkit CMD: ..." to stderr and returns -1 on an unknown option, a missing value, a second
 * positional argument or none at all (what_positional names it in that message). */
int cli_parse(const char *cmd, int argc, char **argv, const cli_option *opts, const char **positional,
              const char *what_positional);

/* The whole of text as a whole number in [lo, hi], or as a finite number in [lo, hi]: 0, or -1
 * (nothing printed: the caller names the option in its own message). */
int cli_whole(const char *text, long lo, long hi, long *out);
int cli_real(const char *text, double lo, double hi, double *out);

/* "--precision float32|float64" (text NULL: not given, *given = 0): the asset's real type
 * (formats/rombin.h). Prints "romkit CMD: ..." and returns -1 on another value. */
int cli_precision(const char *cmd, const char *text, int *given, int *real_type);

/* Takes every "NAME VALUE" pair out of argv (an option given once per item, e.g. --training-run),
 * the values into out (at most max) in order; *argc shrinks. Returns how many, or -1 after
 * printing "romkit CMD: ..." (a missing value, more than max). */
int cli_take_all(const char *cmd, int *argc, char **argv, const char *name, const char **out, int max);

#endif
