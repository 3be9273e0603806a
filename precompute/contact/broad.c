/* The broad phase (contact.h): which boxes of one set overlap which boxes of another, by a
 * spatial hash. Every box of set B is listed in the grid cells it covers (cell, box) and the list
 * is sorted by cell; each box of set A then looks up the cells it covers. A pair found in
 * several cells is reported once. */
#include "contact/contact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    uint64_t cell;
    int box;
} cell_entry;

static int cmp_entry(const void *a, const void *b)
{
    const cell_entry *x = a, *y = b;
    if (x->cell != y->cell) return x->cell < y->cell ? -1 : 1;
    return (x->box > y->box) - (x->box < y->box);
}

static int cmp_pair(const void *a, const void *b)
{
    const int *x = a, *y = b;
    if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
    return (x[1] > y[1]) - (x[1] < y[1]);
}

static uint64_t cell_key(long i, long j, long k)
{
    /* 21 bits per axis (cells are relative to the boxes' own lower corner, so non-negative) */
    return ((uint64_t)(i & 0x1FFFFF) << 42) | ((uint64_t)(j & 0x1FFFFF) << 21) | (uint64_t)(k & 0x1FFFFF);
}

/* The cell range [lo, hi] a box covers. */
static void cell_range(const double *box, const double *origin, double size, long lo[3], long hi[3])
{
    for (int a = 0; a < 3; a++) {
        lo[a] = (long)floor((box[a] - origin[a]) / size);
        hi[a] = (long)floor((box[3 + a] - origin[a]) / size);
    }
}

int rk_broad_phase(const double *boxes_a, int na, const double *boxes_b, int nb, int **pairs, int *npairs,
                   rk_error *err)
{
    *pairs = NULL;
    *npairs = 0;
    if (na == 0 || nb == 0) return 0;
    /* cell size: the mean box extent of B, so each box covers a handful of cells, but no box more
     * than 32 along an axis (cells far apart may share a key: that only adds candidates, which
     * the box test below drops) */
    double origin[3] = {INFINITY, INFINITY, INFINITY}, extent = 0, widest = 0;
    for (int i = 0; i < nb; i++)
        for (int a = 0; a < 3; a++) {
            origin[a] = fmin(origin[a], boxes_b[6 * i + a]);
            extent += boxes_b[6 * i + 3 + a] - boxes_b[6 * i + a];
            widest = fmax(widest, boxes_b[6 * i + 3 + a] - boxes_b[6 * i + a]);
        }
    for (int i = 0; i < na; i++)
        for (int a = 0; a < 3; a++) {
            origin[a] = fmin(origin[a], boxes_a[6 * i + a]);
            widest = fmax(widest, boxes_a[6 * i + 3 + a] - boxes_a[6 * i + a]);
        }
    double size = fmax(fmax(extent / (3.0 * nb), widest / 32), 1e-12);
    size_t cap = 8 * (size_t)nb, count = 0;
    cell_entry *cells = malloc(cap * sizeof *cells);
    if (!cells) return rk_fail(err, "broad phase: out of memory");
    for (int b = 0; b < nb; b++) {
        long lo[3], hi[3];
        cell_range(boxes_b + 6 * b, origin, size, lo, hi);
        for (long i = lo[0]; i <= hi[0]; i++)
            for (long j = lo[1]; j <= hi[1]; j++)
                for (long k = lo[2]; k <= hi[2]; k++) {
                    if (count == cap) {
                        cell_entry *grown = realloc(cells, 2 * cap * sizeof *cells);
                        if (!grown) {
                            free(cells);
                            return rk_fail(err, "broad phase: out of memory");
                        }
                        cells = grown;
                        cap *= 2;
                    }
                    cells[count++] = (cell_entry){cell_key(i, j, k), b};
                }
    }
    qsort(cells, count, sizeof *cells, cmp_entry);
    size_t pcap = 4 * (size_t)na + 16, np = 0;
    int *out = malloc(2 * pcap * sizeof(int));
    if (!out) {
        free(cells);
        return rk_fail(err, "broad phase: out of memory");
    }
    for (int a = 0; a < na; a++) {
        const double *ba = boxes_a + 6 * a;
        long lo[3], hi[3];
        cell_range(ba, origin, size, lo, hi);
        for (long i = lo[0]; i <= hi[0]; i++)
            for (long j = lo[1]; j <= hi[1]; j++)
                for (long k = lo[2]; k <= hi[2]; k++) {
                    uint64_t key = cell_key(i, j, k);
                    size_t l = 0, r = count; /* first entry with this cell */
                    while (l < r) {
                        size_t m = (l + r) / 2;
                        if (cells[m].cell < key) l = m + 1;
                        else r = m;
                    }
                    for (; l < count && cells[l].cell == key; l++) {
                        const double *bb = boxes_b + 6 * cells[l].box;
                        if (ba[0] > bb[3] || ba[3] < bb[0] || ba[1] > bb[4] || ba[4] < bb[1] || ba[2] > bb[5] ||
                            ba[5] < bb[2])
                            continue;
                        if (np == pcap) {
                            int *grown = realloc(out, 4 * pcap * sizeof(int));
                            if (!grown) {
                                free(cells);
                                free(out);
                                return rk_fail(err, "broad phase: out of memory");
                            }
                            out = grown;
                            pcap *= 2;
                        }
                        out[2 * np] = a;
                        out[2 * np + 1] = cells[l].box;
                        np++;
                    }
                }
    }
    free(cells);
    qsort(out, np, 2 * sizeof(int), cmp_pair);
    size_t u = 0;
    for (size_t p = 0; p < np; p++)
        if (u == 0 || out[2 * p] != out[2 * (u - 1)] || out[2 * p + 1] != out[2 * (u - 1) + 1]) {
            out[2 * u] = out[2 * p];
            out[2 * u + 1] = out[2 * p + 1];
            u++;
        }
    *pairs = out;
    *npairs = (int)u;
    return 0;
}
