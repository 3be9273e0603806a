/* Pyramidal Lucas-Kanade after J.-Y. Bouguet, "Pyramidal implementation of the Lucas Kanade
 * feature tracker" (Intel, 2000): at each level L from the coarsest, the point u / 2^L carries the
 * guess g^L from the level above; the window's spatial gradient matrix G (on I, fixed per level)
 * and the image mismatch b = sum dI [Ix; Iy], dI = I(x) - J(x + g + v), give the update
 * eta = G^-1 b, iterated until |eta| < epsilon; then g^(L-1) = 2 (g^L + v). Samples are
 * bilinear; the gradients are central differences on each level. */
#include "video/video.h"

#include <math.h>
#include <string.h>

#define RK_LK_MAX_WINDOW (41 * 41) /* half_window <= 20 */

void rk_lk_default_options(rk_lk_options *o)
{
    o->levels = 3;
    o->half_window = 7;
    o->iterations = 30;
    o->epsilon = 0.005;
    o->min_eigen = 1e-5;
    o->fb_threshold = 0.5;
}

void rk_pyramid_free(rk_pyramid *p)
{
    for (int l = 0; l < RK_LK_MAX_LEVELS; l++) {
        rk_image_free(&p->img[l]);
        rk_image_free(&p->gx[l]);
        rk_image_free(&p->gy[l]);
    }
    p->levels = 0;
}

static float at(const rk_image *im, int x, int y)
{
    x = x < 0 ? 0 : x >= im->w ? im->w - 1 : x;
    y = y < 0 ? 0 : y >= im->h ? im->h - 1 : y;
    return im->px[(size_t)y * im->w + x];
}

/* Bouguet's Eq. 2: I^L(x, y) from I^(L-1) around (2x, 2y) with weights 1/4, 1/8 (edges), 1/16. */
static void halve(const rk_image *a, rk_image *b)
{
    for (int y = 0; y < b->h; y++)
        for (int x = 0; x < b->w; x++) {
            double s = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++)
                    s += (dx ? 1 : 2) * (dy ? 1 : 2) * at(a, 2 * x + dx, 2 * y + dy);
            b->px[(size_t)y * b->w + x] = (float)(s / 16);
        }
}

int rk_pyramid_build(const rk_image *im, int levels, rk_pyramid *p, rk_error *err)
{
    memset(p, 0, sizeof *p);
    if (levels < 1 || levels > RK_LK_MAX_LEVELS) return rk_fail(err, "pyramid levels %d outside 1..%d", levels, RK_LK_MAX_LEVELS);
    for (int l = 0; l < levels; l++) {
        int w = l ? (p->img[l - 1].w + 1) / 2 : im->w, h = l ? (p->img[l - 1].h + 1) / 2 : im->h;
        if (w < 2 || h < 2) break;
        if (rk_image_alloc(&p->img[l], w, h, err) || rk_image_alloc(&p->gx[l], w, h, err) ||
            rk_image_alloc(&p->gy[l], w, h, err)) {
            rk_pyramid_free(p);
            return -1;
        }
        if (l) halve(&p->img[l - 1], &p->img[l]);
        else memcpy(p->img[0].px, im->px, sizeof(float) * (size_t)w * h);
        const rk_image *a = &p->img[l];
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                p->gx[l].px[(size_t)y * w + x] = 0.5f * (at(a, x + 1, y) - at(a, x - 1, y));
                p->gy[l].px[(size_t)y * w + x] = 0.5f * (at(a, x, y + 1) - at(a, x, y - 1));
            }
        p->levels = l + 1;
    }
    return 0;
}

int rk_lk_track(const rk_pyramid *I, const rk_pyramid *J, const rk_lk_options *o, double x, double y, double *ox,
                double *oy)
{
    int levels = I->levels < J->levels ? I->levels : J->levels, hw = o->half_window;
    double ti[RK_LK_MAX_WINDOW], tx[RK_LK_MAX_WINDOW], ty[RK_LK_MAX_WINDOW];
    if (hw < 1 || (2 * hw + 1) * (2 * hw + 1) > RK_LK_MAX_WINDOW) return RK_LK_FLAT;
    if (levels > o->levels) levels = o->levels;
    double gx = 0, gy = 0, vx = 0, vy = 0, npix = (2.0 * hw + 1) * (2.0 * hw + 1);
    *ox = x, *oy = y;
    for (int L = levels - 1; L >= 0; L--) {
        const rk_image *Ii = &I->img[L], *Ix = &I->gx[L], *Iy = &I->gy[L], *Jj = &J->img[L];
        double s = ldexp(1.0, -L), ux = x * s, uy = y * s;
        double gxx = 0, gxy = 0, gyy = 0;
        int m = 0; /* the template's samples, fixed for the level */
        for (int j = -hw; j <= hw; j++)
            for (int i = -hw; i <= hw; i++, m++) {
                double a = tx[m] = rk_image_sample(Ix, ux + i, uy + j), b = ty[m] = rk_image_sample(Iy, ux + i, uy + j);
                ti[m] = rk_image_sample(Ii, ux + i, uy + j);
                gxx += a * a, gxy += a * b, gyy += b * b;
            }
        double det = gxx * gyy - gxy * gxy, tr = gxx + gyy;
        double lmin = 0.5 * (tr - sqrt(fmax(0, tr * tr - 4 * det)));
        if (!(lmin / npix >= o->min_eigen)) return RK_LK_FLAT;
        vx = vy = 0;
        for (int k = 0; k < o->iterations; k++) {
            double bx = 0, by = 0;
            m = 0;
            for (int j = -hw; j <= hw; j++)
                for (int i = -hw; i <= hw; i++, m++) {
                    double dI = ti[m] - rk_image_sample(Jj, ux + gx + vx + i, uy + gy + vy + j);
                    bx += dI * tx[m], by += dI * ty[m];
                }
            double ex = (gyy * bx - gxy * by) / det, ey = (gxx * by - gxy * bx) / det;
            vx += ex, vy += ey;
            double px = ux + gx + vx, py = uy + gy + vy;
            if (!(px >= 0 && py >= 0 && px <= Jj->w - 1 && py <= Jj->h - 1)) return RK_LK_OUTSIDE;
            if (ex * ex + ey * ey < o->epsilon * o->epsilon) break;
        }
        if (L) gx = 2 * (gx + vx), gy = 2 * (gy + vy);
    }
    *ox = x + gx + vx, *oy = y + gy + vy;
    return RK_LK_OK;
}

int rk_lk_track_fb(const rk_pyramid *I, const rk_pyramid *J, const rk_lk_options *o, double x, double y, double *ox,
                   double *oy, double *fb)
{
    double bx, by;
    *fb = NAN;
    int s = rk_lk_track(I, J, o, x, y, ox, oy);
    if (s) return s;
    if ((s = rk_lk_track(J, I, o, *ox, *oy, &bx, &by))) return s;
    *fb = hypot(bx - x, by - y);
    return *fb > o->fb_threshold ? RK_LK_LOST_FB : RK_LK_OK;
}
