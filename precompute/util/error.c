#include "util/util.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int rk_fail(rk_error *err, const char *fmt, ...)
{
    rk_progress_break(); /* the message will follow a progress line left open */
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return -1;
}

int rk_error_prefix(rk_error *err, const char *fmt, ...)
{
    if (!err) return -1;
    char prefix[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    char old[sizeof err->msg];
    memcpy(old, err->msg, sizeof old);
    size_t n = strlen(prefix);
    if (n > sizeof err->msg - 3) n = sizeof err->msg - 3;
    memcpy(err->msg, prefix, n);
    memcpy(err->msg + n, ": ", 2);
    size_t room = sizeof err->msg - n - 3;
    size_t m = strlen(old);
    if (m > room) m = room;
    memcpy(err->msg + n + 2, old, m);
    err->msg[n + 2 + m] = '\0';
    return -1;
}

void rk_error_clear(rk_error *err)
{
    if (err) err->msg[0] = '\0';
}

void *rk_calloc(size_t count, size_t size, rk_error *err)
{
    if (count == 0) count = 1;
    if (size != 0 && count > (size_t)-1 / size) {
        rk_fail(err, "allocation of %zu x %zu bytes overflows", count, size);
        return NULL;
    }
    void *p = calloc(count, size);
    if (!p) rk_fail(err, "out of memory allocating %zu x %zu bytes", count, size);
    return p;
}

void rk_warn(const char *fmt, ...)
{
    rk_progress_break(); /* the warning gets a line of its own */
    va_list ap;
    va_start(ap, fmt);
    fputs("warning: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}
