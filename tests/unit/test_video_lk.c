/* precompute/video: pyramidal Lucas-Kanade recovers a known subpixel motion (a shift, and a shift
 * with a small rotation) of a smooth textured image to 0.05 px; dot centroids of anti-aliased
 * discs under noise land within 0.5 px; the forward-backward check drops a dot that is covered in
 * the second frame and keeps the others; images round-trip through PNG and PGM, RGBA as luminance. */
#include <png.h>

#include "testlib.h"
#include "video/video.h"

/* A smooth texture with gradients at many scales (what LK needs), luminance in about [0.2, 0.8]. */
static double texture(double x, double y)
{
    return 0.5 + 0.12 * sin(0.21 * x + 0.4) * cos(0.17 * y) + 0.08 * sin(0.05 * x + 0.09 * y) +
           0.06 * cos(0.37 * x - 0.29 * y + 1.0) + 0.04 * sin(0.61 * y + 0.2 * x);
}

/* J(p) = I(A^-1 (p - c - d) + c): the texture moved by rotation theta about c, then shifted by d. */
static void moved(rk_image *im, double theta, double dx, double dy, double cx, double cy)
{
    for (int y = 0; y < im->h; y++)
        for (int x = 0; x < im->w; x++) {
            double px = x - cx - dx, py = y - cy - dy, c = cos(theta), s = sin(theta);
            im->px[(size_t)y * im->w + x] = (float)texture(c * px + s * py + cx, -s * px + c * py + cy);
        }
}

static double worst_lk(double theta, double dx, double dy, int *status)
{
    rk_error err = {{0}};
    rk_image a, b;
    rk_pyramid P, Q;
    rk_lk_options o;
    rk_lk_default_options(&o);
    double cx = 80, cy = 60, worst = 0;
    *status = -1;
    if (rk_image_alloc(&a, 160, 120, &err) || rk_image_alloc(&b, 160, 120, &err)) return 1e9;
    moved(&a, 0, 0, 0, cx, cy);
    moved(&b, theta, dx, dy, cx, cy);
    rk_pyramid_build(&a, 3, &P, &err);
    rk_pyramid_build(&b, 3, &Q, &err);
    *status = 0;
    for (int k = 0; k < 9; k++) {
        double x = 50 + 30 * (k % 3), y = 35 + 25 * (k / 3), ox, oy;
        double ex = cos(theta) * (x - cx) - sin(theta) * (y - cy) + cx + dx;
        double ey = sin(theta) * (x - cx) + cos(theta) * (y - cy) + cy + dy;
        int s = rk_lk_track(&P, &Q, &o, x, y, &ox, &oy);
        if (s) *status = s;
        worst = fmax(worst, hypot(ox - ex, oy - ey));
    }
    rk_pyramid_free(&P);
    rk_pyramid_free(&Q);
    rk_image_free(&a);
    rk_image_free(&b);
    return worst;
}

TEST(lk_recovers_a_subpixel_shift)
{
    int s;
    double e = worst_lk(0, 3.37, -1.61, &s);
    printf("# LK, shift (3.37, -1.61) px: worst error %.4f px over 9 points\n", e);
    CHECK(s == RK_LK_OK, "status %d", s);
    CHECK(e < 0.05, "worst error %.4f px (limit 0.05)", e);
    e = worst_lk(0, 0.23, 0.41, &s);
    CHECK(s == RK_LK_OK && e < 0.05, "small shift: status %d, worst error %.4f px", s, e);
}

TEST(lk_recovers_a_shift_with_a_small_rotation)
{
    int s;
    double e = worst_lk(0.5 * M_PI / 180, 2.71, 1.28, &s);
    printf("# LK, 0.5 degrees and (2.71, 1.28) px: worst error %.4f px over 9 points\n", e);
    CHECK(s == RK_LK_OK, "status %d", s);
    CHECK(e < 0.05, "worst error %.4f px (limit 0.05)", e);
}

/* Dark discs of radius r at (x_i, y_i), anti-aliased (a pixel's cover ramps over one pixel of
 * distance across the rim), on the texture. */
static void disc_frame(rk_image *im, const double *cx, const double *cy, int n, double r, int skip)
{
    for (int y = 0; y < im->h; y++)
        for (int x = 0; x < im->w; x++) {
            double cover = 0;
            for (int i = 0; i < n; i++)
                if (i != skip) cover = fmax(cover, fmin(1, fmax(0, r - hypot(x - cx[i], y - cy[i]) + 0.5)));
            im->px[(size_t)y * im->w + x] = (float)((1 - cover) * (0.5 + 0.6 * (texture(x, y) - 0.5)) + cover * 0.08);
        }
}

TEST(dot_centroids_within_half_a_pixel_under_noise)
{
    rk_error err = {{0}};
    rk_image im;
    CHECK_OK(rk_image_alloc(&im, 160, 120, &err));
    double cx[5] = {30.3, 71.7, 120.45, 45.1, 100.8}, cy[5] = {25.6, 30.2, 40.9, 90.35, 85.55};
    disc_frame(&im, cx, cy, 5, 4.2, -1);
    uint64_t st = 7;
    for (size_t i = 0; i < (size_t)im.w * im.h; i++) { /* uniform noise of standard deviation 0.02 */
        double u = (double)(rk_splitmix64(&st) >> 11) / 9007199254740992.0;
        im.px[i] += (float)(0.02 * sqrt(12.0) * (u - 0.5));
    }
    rk_dot_options o;
    rk_dot_default_options(&o);
    rk_dot *d = NULL;
    rk_dot_counts c;
    int n = 0;
    double worst = 0;
    CHECK_OK(rk_dots_find(&im, &o, &d, &n, &c, &err));
    CHECK(n == 5, "%d dots found (%d components, %d too small)", n, c.components, c.too_small);
    for (int i = 0; i < 5; i++) {
        double best = 1e9;
        for (int j = 0; j < n; j++) best = fmin(best, hypot(d[j].x - cx[i], d[j].y - cy[i]));
        worst = fmax(worst, best);
        CHECK(best < 0.5, "dot %d at (%.2f, %.2f): nearest found %.3f px away", i, cx[i], cy[i], best);
    }
    printf("# dot centroids under noise 0.02: worst %.3f px\n", worst);
    free(d);
    /* a frame without dots: the error names the counts */
    disc_frame(&im, cx, cy, 0, 4.2, -1);
    CHECK(rk_dots_find(&im, &o, &d, &n, &c, &err) && strstr(err.msg, "no dots found"), "%s", err.msg);
    rk_image_free(&im);
}

TEST(forward_backward_drops_a_covered_dot)
{
    rk_error err = {{0}};
    rk_image a, b;
    CHECK_OK(rk_image_alloc(&a, 240, 180, &err));
    CHECK_OK(rk_image_alloc(&b, 240, 180, &err));
    double cx[4] = {30.3, 121.7, 200.45, 60.1}, cy[4] = {25.6, 90.2, 40.9, 145.35};
    double mx[4], my[4];
    for (int i = 0; i < 4; i++) mx[i] = cx[i] + 1.3, my[i] = cy[i] - 0.7;
    disc_frame(&a, cx, cy, 4, 4.2, -1);
    disc_frame(&b, mx, my, 4, 4.2, 1);
    /* dot 1 is covered by a flat occluder in the second frame */
    for (int y = 80; y < 102; y++)
        for (int x = 110; x < 134; x++) b.px[y * b.w + x] = 0.9f;
    rk_pyramid P, Q;
    rk_lk_options o;
    rk_lk_default_options(&o);
    CHECK_OK(rk_pyramid_build(&a, 3, &P, &err));
    CHECK_OK(rk_pyramid_build(&b, 3, &Q, &err));
    int kept = 0, lost1 = 0;
    for (int i = 0; i < 4; i++) {
        double ox, oy, fb;
        int s = rk_lk_track_fb(&P, &Q, &o, cx[i], cy[i], &ox, &oy, &fb);
        if (i == 1) lost1 = s != RK_LK_OK;
        else if (s == RK_LK_OK && hypot(ox - mx[i], oy - my[i]) < 0.1) kept++;
        else printf("# dot %d: status %d, off by %.3f px, round trip %.3f px\n", i, s, hypot(ox - mx[i], oy - my[i]), fb);
    }
    rk_pyramid_free(&P);
    rk_pyramid_free(&Q);
    rk_image_free(&a);
    rk_image_free(&b);
    CHECK(lost1, "the covered dot was kept");
    CHECK(kept == 3, "%d of the 3 visible dots kept within 0.1 px", kept);
}

TEST(images_round_trip_png_and_pgm)
{
    rk_error err = {{0}};
    rk_image a, b;
    CHECK_OK(rk_image_alloc(&a, 7, 5, &err));
    for (int i = 0; i < 35; i++) a.px[i] = (float)(i * 7 % 35) / 34.0f;
    char png[512], pgm[512];
    snprintf(png, sizeof png, "%s/romkit_%d_lk.png", tl_tmpdir(), (int)getpid());
    snprintf(pgm, sizeof pgm, "%s/romkit_%d_lk.pgm", tl_tmpdir(), (int)getpid());
    CHECK_OK(rk_image_save_png(png, &a, &err));
    CHECK_OK(rk_image_load(png, &b, &err));
    CHECK(b.w == 7 && b.h == 5, "%d x %d", b.w, b.h);
    double worst = 0;
    for (int i = 0; i < 35; i++) worst = fmax(worst, fabs(a.px[i] - b.px[i]));
    rk_image_free(&b);
    CHECK(worst <= 0.5 / 255 + 1e-6, "PNG round trip off by %g", worst);
    FILE *f = fopen(pgm, "wb");
    fprintf(f, "P5\n# comment\n7 5\n255\n");
    for (int i = 0; i < 35; i++) fputc((int)lrint(a.px[i] * 255), f);
    fclose(f);
    CHECK_OK(rk_image_load(pgm, &b, &err));
    CHECK(b.w == 7 && fabs(b.px[12] - a.px[12]) < 0.003, "PGM pixel 12: %g vs %g", b.px[12], a.px[12]);
    rk_image_free(&b);
    f = fopen(pgm, "wb");
    fprintf(f, "not an image");
    fclose(f);
    CHECK(rk_image_load(pgm, &b, &err) && strstr(err.msg, "neither a PNG nor"), "%s", err.msg);
    /* RGBA: gray pixels keep their value, green is brighter than red, red than blue; alpha ignored */
    unsigned char rgba[4 * 4] = {200, 200, 200, 255, 0, 255, 0, 128, 255, 0, 0, 255, 0, 0, 255, 0};
    png_image p;
    memset(&p, 0, sizeof p);
    p.version = PNG_IMAGE_VERSION, p.width = 2, p.height = 2, p.format = PNG_FORMAT_RGBA;
    CHECK(png_image_write_to_file(&p, png, 0, rgba, 0, NULL), "RGBA PNG not written: %s", p.message);
    CHECK_OK(rk_image_load(png, &b, &err));
    CHECK(b.w == 2 && b.h == 2 && fabs(b.px[0] - 200 / 255.0) < 0.01 && b.px[1] > b.px[2] && b.px[2] > b.px[3] &&
          b.px[3] > 0, "RGBA as luminance: %g %g %g %g", b.px[0], b.px[1], b.px[2], b.px[3]);
    rk_image_free(&b);
    remove(png);
    remove(pgm);
    CHECK(rk_image_load(png, &b, &err) && strstr(err.msg, "cannot open"), "%s", err.msg);
    rk_image_free(&a);
}

int main(void)
{
    RUN(lk_recovers_a_subpixel_shift);
    RUN(lk_recovers_a_shift_with_a_small_rotation);
    RUN(dot_centroids_within_half_a_pixel_under_noise);
    RUN(forward_backward_drops_a_covered_dot);
    RUN(images_round_trip_png_and_pgm);
    return test_finish();
}
