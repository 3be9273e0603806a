/* The registry of methods (method.h): one line per method, in the order their keys are checked.
 * Tests may add a method of their own (rk_method_register) after these. */
#include "pipeline/method.h"

#include <string.h>

#include "pipeline/method_adaptive_linear.h"
#include "pipeline/method_adaptive_subspace.h"
#include "pipeline/method_fixed.h"
#include "pipeline/method_koopman.h"
#include "pipeline/parse_impl.h"

static const rk_method *const builtin[] = {
    &rk_method_fixed,
    &rk_method_koopman,
    &rk_method_adaptive_subspace,
    &rk_method_adaptive_linear,
};
#define NBUILTIN ((int)(sizeof builtin / sizeof builtin[0]))

/* Registered later (tests): few, and never removed. Not thread-safe: register before loading scenes. */
#define MAX_EXTRA 4
static const rk_method *extra[MAX_EXTRA];
static int nextra;

int rk_method_count(void)
{
    return NBUILTIN + nextra;
}

const rk_method *rk_method_at(int i)
{
    if (i < 0 || i >= rk_method_count()) return NULL;
    return i < NBUILTIN ? builtin[i] : extra[i - NBUILTIN];
}

const rk_method *rk_method_find(const char *name)
{
    for (int i = 0; i < rk_method_count(); i++)
        if (!rk_method_at(i)->implied_by && strcmp(rk_method_at(i)->name, name) == 0) return rk_method_at(i);
    return NULL;
}

int rk_method_register(const rk_method *m)
{
    if (nextra == MAX_EXTRA || !m->name || !m->compare) return -1;
    for (int i = 0; i < rk_method_count(); i++)
        if (strcmp(rk_method_at(i)->name, m->name) == 0) return -1;
    extra[nextra++] = m;
    return 0;
}

const void *rk_method_options(const rk_rom_entry *e, const rk_method *m)
{
    return e->method == m ? (const void *)e->own : NULL;
}

void *rk_method_measures(rk_compare_method *m, const rk_method *method)
{
    return m->method == method ? (void *)m->own : NULL;
}

int rk_method_number(const rk_json_ctx *c, const cJSON *e, const char *path, const char *key, double *out)
{
    return rk_json_number(c, e, path, key, 0, out);
}

int rk_method_fail(const rk_json_ctx *c, const char *path, const char *message)
{
    return rk_json_fail(c, path, "%s", message);
}
