/* Dot markers in one frame: pixels darker (or brighter) than a threshold, grouped into 4-connected
 * components; a component of a plausible size that does not touch the border is a dot, located at
 * its centroid weighted by how far each pixel is past the threshold (the anti-aliased rim counts
 * less than the core, so the centroid is subpixel). */
#include "video/video.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rk_dot_default_options(rk_dot_options *o)
{
    o->dark = 1;
    o->threshold = 0.3;
    o->min_area = 4;
    o->max_area = 2000;
}

int rk_dots_find(const rk_image *im, const rk_dot_options *o, rk_dot **dots, int *n, rk_dot_counts *c, rk_error *err)
{
    memset(c, 0, sizeof *c);
    *dots = NULL;
    *n = 0;
    size_t np = (size_t)im->w * im->h;
    double thr = o->dark ? o->threshold : 1 - o->threshold;
    c->threshold = thr;
    int *label = rk_calloc(np, sizeof(int), err), *stack = rk_calloc(np, sizeof(int), err), cap = 64;
    rk_dot *d = rk_calloc((size_t)cap, sizeof(rk_dot), err);
    if (!label || !stack || !d) goto fail;
    for (size_t s = 0; s < np; s++) {
        double depth = o->dark ? thr - im->px[s] : im->px[s] - thr;
        if (label[s] || depth <= 0) continue;
        /* flood fill the component from s, accumulating its weighted centroid */
        int top = 0, area = 0, border = 0;
        double sw = 0, sx = 0, sy = 0;
        stack[top++] = (int)s;
        label[s] = 1;
        while (top) {
            int p = stack[--top], x = p % im->w, y = p / im->w;
            double wgt = o->dark ? thr - im->px[p] : im->px[p] - thr;
            sw += wgt, sx += wgt * x, sy += wgt * y, area++;
            if (x == 0 || y == 0 || x == im->w - 1 || y == im->h - 1) border = 1;
            int nb[4] = {x > 0 ? p - 1 : -1, x < im->w - 1 ? p + 1 : -1, y > 0 ? p - im->w : -1,
                         y < im->h - 1 ? p + im->w : -1};
            for (int k = 0; k < 4; k++) {
                int q = nb[k];
                if (q < 0 || label[q]) continue;
                if ((o->dark ? thr - im->px[q] : im->px[q] - thr) <= 0) continue;
                label[q] = 1;
                stack[top++] = q;
            }
        }
        c->components++;
        if (area < o->min_area) c->too_small++;
        else if (area > o->max_area) c->too_large++;
        else if (border) c->on_border++;
        else {
            if (*n == cap) {
                rk_dot *g = realloc(d, sizeof(rk_dot) * (size_t)(cap *= 2));
                if (!g) {
                    rk_fail(err, "out of memory for %d dots", cap);
                    goto fail;
                }
                d = g;
            }
            d[(*n)++] = (rk_dot){sx / sw, sy / sw, area};
        }
    }
    c->kept = *n;
    free(label);
    free(stack);
    if (!*n) {
        free(d);
        return rk_fail(err, "no dots found: %d %s components past luminance threshold %.3g, %d smaller than %d pixels, "
                       "%d larger than %d, %d touching the border", c->components, o->dark ? "dark" : "bright", thr,
                       c->too_small, o->min_area, c->too_large, o->max_area, c->on_border);
    }
    *dots = d;
    return 0;
fail:
    free(label);
    free(stack);
    free(d);
    *n = 0;
    return -1;
}
