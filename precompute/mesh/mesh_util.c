#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh_impl.h"

int rk_path_has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    if (n < e) return 0;
    for (size_t i = 0; i < e; i++) {
        char a = path[n - e + i], b = ext[i];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (b >= 'A' && b <= 'Z') b = (char)(b - 'A' + 'a');
        if (a != b) return 0;
    }
    return 1;
}

int rk_path_with_ext(const char *path, const char *ext, char *out, size_t cap, rk_error *err)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(path, '.');
    size_t stem = (dot && (!slash || dot > slash)) ? (size_t)(dot - path) : strlen(path);
    if (stem + strlen(ext) + 1 > cap) return rk_fail(err, "%s: path too long", path);
    memcpy(out, path, stem);
    strcpy(out + stem, ext);
    return 0;
}

int rk_grow(void *p, size_t *cap, size_t need, size_t elem, rk_error *err)
{
    if (need <= *cap) return 0;
    size_t n = *cap ? *cap : 64;
    while (n < need) {
        if (n > ((size_t)-1 / 2) / elem) return rk_fail(err, "array of %zu elements is too large", need);
        n *= 2;
    }
    /* p points at some T* (not necessarily void*): read and write it through memcpy. */
    void *old;
    memcpy(&old, p, sizeof old);
    void *grown = realloc(old, n * elem);
    if (!grown) return rk_fail(err, "out of memory growing an array to %zu elements", n);
    memcpy(p, &grown, sizeof grown);
    *cap = n;
    return 0;
}


int rk_box_contains(const rk_box *b, const double *p, double slack)
{
    for (int i = 0; i < 3; i++)
        if (p[i] < b->min[i] - slack || p[i] > b->max[i] + slack) return 0;
    return 1;
}
