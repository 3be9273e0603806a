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

int rk_boxes_overlap(const double *a, const double *b)
{
    return !(a[0] > b[3] || a[3] < b[0] || a[1] > b[4] || a[4] < b[1] || a[2] > b[5] || a[5] < b[2]);
}

typedef struct {
    int *out;
    size_t n, cap;
} pair_list;

static int push_pair(pair_list *l, int a, int b)
{
    if (l->n == l->cap) {
        size_t cap = 2 * l->cap + 64;
        int *grown = realloc(l->out, 2 * cap * sizeof(int));
        if (!grown) return -1;
        l->out = grown, l->cap = cap;
    }
    l->out[2 * l->n] = a, l->out[2 * l->n + 1] = b;
    l->n++;
    return 0;
}

/* A hashed box covering more cells than this is tested against every query box instead. */
#define BIG_BOX_CELLS 512

/* How many cells box covers (as a double: a huge box overflows no integer). */
static double box_cells(const double *box, const double *origin, double size, long lo[3], long hi[3])
{
    cell_range(box, origin, size, lo, hi);
    return (double)(hi[0] - lo[0] + 1) * (double)(hi[1] - lo[1] + 1) * (double)(hi[2] - lo[2] + 1);
}

/* The (cell, box) list of B sorted by cell; boxes over BIG_BOX_CELLS marked in big[] instead. */
static int hash_boxes(const double *boxes_b, int nb, const double *origin, double size, char *big, cell_entry **out,
                      size_t *count, rk_error *err)
{
    size_t cap = 8 * (size_t)nb, n = 0;
    cell_entry *cells = malloc(cap * sizeof *cells);
    if (!cells) return rk_fail(err, "broad phase: out of memory");
    for (int b = 0; b < nb; b++) {
        long lo[3], hi[3];
        big[b] = box_cells(boxes_b + 6 * b, origin, size, lo, hi) > BIG_BOX_CELLS;
        if (big[b]) continue;
        for (long i = lo[0]; i <= hi[0]; i++)
            for (long j = lo[1]; j <= hi[1]; j++)
                for (long k = lo[2]; k <= hi[2]; k++) {
                    if (n == cap) {
                        cell_entry *grown = realloc(cells, 2 * cap * sizeof *cells);
                        if (!grown) {
                            free(cells);
                            return rk_fail(err, "broad phase: out of memory");
                        }
                        cells = grown;
                        cap *= 2;
                    }
                    cells[n++] = (cell_entry){cell_key(i, j, k), b};
                }
    }
    qsort(cells, n, sizeof *cells, cmp_entry);
    *out = cells;
    *count = n;
    return 0;
}

/* What hashing a set costs, about: the cells its boxes cover (a big box: a test per other box). */
static double hash_cost(const double *boxes, int n, int nother, const double *origin, double size)
{
    double total = 0;
    for (int b = 0; b < n; b++) {
        long lo[3], hi[3];
        double c = box_cells(boxes + 6 * b, origin, size, lo, hi);
        total += c > BIG_BOX_CELLS ? nother : c;
    }
    return total;
}

/* The pairs of query boxes Q against the hashed boxes B; pairs (q, b), or (b, q) when swapped. */
static int query(const double *boxes_q, int nq, const double *boxes_b, int nb, const char *big,
                 const cell_entry *cells, size_t count, const double *origin, double size, int swapped,
                 pair_list *list)
{
    for (int b = 0; b < nb; b++) /* B's big boxes against every query box */
        for (int q = 0; q < nq && big[b]; q++)
            if (rk_boxes_overlap(boxes_q + 6 * q, boxes_b + 6 * b) && push_pair(list, swapped ? b : q, swapped ? q : b))
                return -1;
    for (int q = 0; q < nq; q++) {
        const double *bq = boxes_q + 6 * q;
        long lo[3], hi[3];
        if (box_cells(bq, origin, size, lo, hi) > nb) { /* cheaper to test every (small) box of B */
            for (int b = 0; b < nb; b++)
                if (!big[b] && rk_boxes_overlap(bq, boxes_b + 6 * b) && push_pair(list, swapped ? b : q, swapped ? q : b))
                    return -1;
            continue;
        }
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
                        if (!rk_boxes_overlap(bq, bb)) continue;
                        /* report the pair once: in the cell of the larger of the two lower corners,
                         * which both boxes cover when they overlap */
                        long blo[3], bhi[3];
                        cell_range(bb, origin, size, blo, bhi);
                        if (i != (lo[0] > blo[0] ? lo[0] : blo[0]) || j != (lo[1] > blo[1] ? lo[1] : blo[1]) ||
                            k != (lo[2] > blo[2] ? lo[2] : blo[2]))
                            continue;
                        int b = cells[l].box;
                        if (push_pair(list, swapped ? b : q, swapped ? q : b)) return -1;
                    }
                }
    }
    return 0;
}

int rk_broad_phase(const double *boxes_a, int na, const double *boxes_b, int nb, int **pairs, int *npairs,
                   rk_error *err)
{
    *pairs = NULL;
    *npairs = 0;
    if (na == 0 || nb == 0) return 0;
    /* cell size: the mean box extent of both sets, so a box covers a handful of cells (cells far
     * apart may share a key: that only adds candidates, which the box test drops) */
    double origin[3] = {INFINITY, INFINITY, INFINITY}, extent = 0;
    const double *sets[2] = {boxes_a, boxes_b};
    int counts[2] = {na, nb};
    for (int s = 0; s < 2; s++)
        for (int i = 0; i < counts[s]; i++)
            for (int a = 0; a < 3; a++) {
                double lo = sets[s][6 * i + a], w = sets[s][6 * i + 3 + a] - lo;
                origin[a] = fmin(origin[a], lo);
                extent += w;
            }
    double size = fmax(extent / (3.0 * (na + nb)), 1e-12);
    /* hash the set that covers fewer cells (a few big obstacle triangles against many small
     * primitives: the small ones), query with the other */
    int swapped = hash_cost(boxes_a, na, nb, origin, size) < hash_cost(boxes_b, nb, na, origin, size);
    const double *hashed = swapped ? boxes_a : boxes_b, *queried = swapped ? boxes_b : boxes_a;
    int nh = swapped ? na : nb, nq = swapped ? nb : na;
    cell_entry *cells = NULL;
    size_t count = 0;
    char *big = malloc((size_t)nh);
    if (!big) return rk_fail(err, "broad phase: out of memory");
    if (hash_boxes(hashed, nh, origin, size, big, &cells, &count, err)) {
        free(big);
        return -1;
    }
    pair_list list = {0};
    int failed = query(queried, nq, hashed, nh, big, cells, count, origin, size, swapped, &list);
    free(cells), free(big);
    if (failed) {
        free(list.out);
        return rk_fail(err, "broad phase: out of memory");
    }
    if (list.n > 1) /* the callers' order, whatever the hash did (no pairs: list.out may be NULL) */
        qsort(list.out, list.n, 2 * sizeof(int), cmp_pair);
    *pairs = list.out;
    *npairs = (int)list.n;
    return 0;
}
