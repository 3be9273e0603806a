#include <inttypes.h>
#include <stdlib.h>

#include "mesh/mesh_impl.h"

typedef struct {
    int64_t tag;
    int index;
} tag_pair;

static int by_tag(const void *a, const void *b)
{
    int64_t x = ((const tag_pair *)a)->tag, y = ((const tag_pair *)b)->tag;
    return (x > y) - (x < y);
}

int rk_tag_map_build(rk_tag_map *tm, const int64_t *tags, size_t n, rk_error *err)
{
    *tm = (rk_tag_map){0};
    tm->n = n;
    tm->contiguous = 1;
    tm->first = n ? tags[0] : 0;
    for (size_t i = 1; i < n && tm->contiguous; i++)
        if (tags[i - 1] == INT64_MAX || tags[i] != tags[i - 1] + 1) tm->contiguous = 0;
    if (tm->contiguous) return 0; /* the common case: no table needed */

    tag_pair *pairs = rk_calloc(n, sizeof *pairs, err);
    tm->tag = rk_calloc(n, sizeof *tm->tag, err);
    tm->index = rk_calloc(n, sizeof *tm->index, err);
    if (!pairs || !tm->tag || !tm->index) {
        free(pairs);
        rk_tag_map_free(tm);
        return -1;
    }
    for (size_t i = 0; i < n; i++) pairs[i] = (tag_pair){tags[i], (int)i};
    qsort(pairs, n, sizeof *pairs, by_tag);
    for (size_t i = 0; i < n; i++) {
        if (i > 0 && pairs[i].tag == pairs[i - 1].tag) {
            int64_t dup = pairs[i].tag;
            free(pairs);
            rk_tag_map_free(tm);
            return rk_fail(err, "node tag %" PRId64 " appears twice", dup);
        }
        tm->tag[i] = pairs[i].tag;
        tm->index[i] = pairs[i].index;
    }
    free(pairs);
    return 0;
}

int rk_tag_map_find(const rk_tag_map *tm, int64_t tag)
{
    if (tm->contiguous) {
        if (tm->n == 0 || tag < tm->first || (uint64_t)tag - (uint64_t)tm->first >= tm->n) return -1;
        return (int)((uint64_t)tag - (uint64_t)tm->first);
    }
    size_t lo = 0, hi = tm->n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (tm->tag[mid] < tag) lo = mid + 1;
        else hi = mid;
    }
    return lo < tm->n && tm->tag[lo] == tag ? tm->index[lo] : -1;
}

void rk_tag_map_free(rk_tag_map *tm)
{
    free(tm->tag);
    free(tm->index);
    tm->tag = NULL;
    tm->index = NULL;
    tm->n = 0;
}
