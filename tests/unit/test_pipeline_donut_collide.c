/* The donut's Gaussian splats dropped onto a second object in the reduced simulator
 * (examples/scenes/donut_on_object.json): the splat capture falls flat onto a block of points that
 * rests on a plane, each object with its own RKPM skinning basis, colliding through the contact
 * stage on their voxel proxies. On every frame: no exact crossing between the proxies
 * (rk_rom_contact_measure), no splat centre inside the block's deformed proxy and no block point
 * inside the donut's (ray parity, cloud_inside.h), and the donut's splats written as a 3DGS PLY
 * (rk_scene_splats_write: F from the skinning weights, rk_splats_write) and read back as a viewer
 * would: unit quaternions, positive finite scales, every value finite. At the end the donut rests
 * on the block, not short of it.
 *
 * The test runs a deterministic downsampling of the capture (every ROMKIT_DONUT_EVERY-th splat,
 * default 8, every attribute kept); ROMKIT_DONUT_EVERY=1 runs the whole capture (45,624 splats),
 * and ROMKIT_DONUT_SPLATS=DIR keeps every frame's PLY there (DIR/frame_NNNNN.ply). */
#include <math.h>
#include <stdio.h>
#include <sys/stat.h>

#include "testlib.h"
#include "cloud_inside.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"
#include "util/util.h"

#define SCENE "examples/scenes/donut_on_object.json"
#define DONUT "../../tests/data/meshes/donut_3dgs.ply"

/* Every k-th splat of src (from the first), all its properties, written to path by the one writer
 * (no x, no F: every value copied bit for bit). */
static int downsample(const rk_splats *src, int k, const char *path, rk_error *err)
{
    rk_splats sub = *src;
    sub.n = (src->n + k - 1) / k;
    sub.X = malloc(sizeof(double) * 3 * (size_t)sub.n);
    sub.values = malloc(sizeof(double) * (size_t)src->nprop * sub.n);
    if (!sub.X || !sub.values) {
        free(sub.X), free(sub.values);
        return rk_fail(err, "out of memory");
    }
    for (int i = 0; i < sub.n; i++) {
        memcpy(sub.X + 3 * (size_t)i, src->X + 3 * (size_t)i * k, 3 * sizeof(double));
        memcpy(sub.values + (size_t)i * src->nprop, src->values + (size_t)i * k * src->nprop,
               sizeof(double) * src->nprop);
    }
    int rc = rk_splats_write(path, &sub, NULL, NULL, err);
    free(sub.X), free(sub.values);
    return rc;
}

/* The scene file's text with the donut replaced by path (NULL: as written). */
static char *scene_text(const char *path, rk_error *err)
{
    FILE *fp = fopen(SCENE, "rb");
    if (!fp) return rk_fail(err, "cannot open %s", SCENE), NULL;
    char *text = calloc(1 << 16, 1), *out = calloc(1 << 16, 1);
    size_t n = text && out ? fread(text, 1, (1 << 16) - 1, fp) : 0;
    fclose(fp);
    char *at = n ? strstr(text, DONUT) : NULL;
    if (!at) {
        free(text), free(out);
        return rk_fail(err, "%s does not name %s", SCENE, DONUT), NULL;
    }
    if (!path) {
        free(out);
        return text;
    }
    *at = '\0';
    snprintf(out, 1 << 16, "%s%s%s", text, path, at + strlen(DONUT));
    free(text);
    return out;
}

/* The lowest and highest coordinate along axis a of vertices v0 .. v1 - 1 at x. */
static void extent(const double *x, int v0, int v1, int a, double *lo, double *hi)
{
    *lo = INFINITY, *hi = -INFINITY;
    for (int v = v0; v < v1; v++) *lo = fmin(*lo, x[3 * v + a]), *hi = fmax(*hi, x[3 * v + a]);
}

TEST(donut_splats_land_on_a_block_of_points)
{
    rk_error err = {{0}};
    const char *every_env = getenv("ROMKIT_DONUT_EVERY"), *keep = getenv("ROMKIT_DONUT_SPLATS");
    int every = every_env ? atoi(every_env) : 8;
    CHECK(every >= 1, "ROMKIT_DONUT_EVERY=%s", every_env);
    char small_path[512], frame_path[512];
    const char *small = tl_scratch(small_path, sizeof small_path, "donut_small.ply"),
               *frame_tmp = tl_scratch(frame_path, sizeof frame_path, "donut_frame.ply");
    rk_splats src;
    CHECK_OK(rk_splats_read("tests/data/meshes/donut_3dgs.ply", &src, &err));
    int full = src.n;
    if (every > 1) CHECK_OK(downsample(&src, every, small, &err));
    rk_splats_free(&src);
    char *json = scene_text(every > 1 ? small : NULL, &err);
    CHECK(json, "%s", err.msg);
    if (keep) mkdir(keep, 0777);

    double t0 = rk_now();
    rk_scene scene;
    rk_scene_sim sim;
    rk_scene_rom R;
    rk_rom s;
    rk_scene_splats sp;
    CHECK_OK(rk_scene_parse(json, SCENE, &scene, &err));
    free(json);
    CHECK_OK(rk_scene_build(&scene, &sim, &err));
    CHECK_OK(rk_scene_rom_build(&scene, &sim, &scene.entries[0], NULL, 0, &R, &err));
    double t_build = rk_now() - t0;
    CHECK(R.basis.nparts == 2 && R.model.has_contact, "%d parts, contact %d", R.basis.nparts, R.model.has_contact);
    CHECK_OK(rk_scene_splats_open(&scene, &sim, &R, 0, &sp, &err));
    int nd = sim.object_points[0], v1 = sim.object_first_vertex[1], np = sim.object_points[1];
    int nv = sim.mesh.nv, ndof = 3 * nv;
    CHECK(nd == (full + every - 1) / every, "%d splats simulated", nd);

    int *tris = NULL, nf = 0;
    CHECK_OK(rk_mesh_boundary(&sim.mesh, &tris, &nf, &err));
    cloud_surface donut_proxy, block_proxy;
    CHECK(cloud_surface_init(&donut_proxy, tris, nf, 0, v1) == 0 && cloud_surface_init(&block_proxy, tris, nf, v1, nv) == 0,
          "surfaces");
    CHECK(donut_proxy.n > 0 && block_proxy.n > 0, "%d and %d proxy triangles", donut_proxy.n, block_proxy.n);
    CHECK_OK(rk_rom_init(&s, &R.model, NULL, NULL, &err));
    int frames = sim.steps, worst_inter = 0, splat_inside = 0, block_inside = 0, bad_values = 0, bad_scales = 0;
    double *x = calloc((size_t)ndof, sizeof(double)), min_d = INFINITY, worst_q = 0, t_step = 0, t_write = 0;
    CHECK(x, "memory");
    for (int f = 0; f <= frames; f++) {
        if (f) {
            double t = rk_now();
            CHECK_OK(rk_rom_step(&s, &err));
            t_step += rk_now() - t;
            int inter;
            double d;
            CHECK_OK(rk_rom_contact_measure(&s, &inter, &d, &err));
            worst_inter = inter > worst_inter ? inter : worst_inter;
            min_d = fmin(min_d, d);
        }
        rk_rom_positions(R.basis.U, ndof, R.model.r, sim.mesh.X, s.q, x);
        cloud_surface_box(&donut_proxy, x);
        cloud_surface_box(&block_proxy, x);
        for (int v = 0; v < nd; v++) splat_inside += cloud_surface_inside(&block_proxy, x, x + 3 * v);
        for (int v = v1; v < v1 + np; v++) block_inside += cloud_surface_inside(&donut_proxy, x, x + 3 * v);

        char path[1200];
        if (keep) snprintf(path, sizeof path, "%s/frame_%05d.ply", keep, f);
        else snprintf(path, sizeof path, "%s", frame_tmp);
        double t = rk_now();
        CHECK_OK(rk_scene_splats_write(&sp, &R, s.q, x, path, &err));
        t_write += rk_now() - t;
        rk_splats back;
        CHECK_OK(rk_splats_read(path, &back, &err));
        CHECK(back.n == nd && back.nprop == sp.splats.nprop && back.has_splat_attributes, "frame %d: %d splats", f, back.n);
        for (int i = 0; i < nd; i++) {
            const double *v = back.values + (size_t)i * back.nprop;
            double q2 = 0;
            for (int c = 0; c < 4; c++) q2 += v[back.rot[c]] * v[back.rot[c]];
            worst_q = fmax(worst_q, fabs(sqrt(q2) - 1));
            for (int c = 0; c < 3; c++) { /* 3DGS stores log scales: exp must be positive and finite */
                double sc = exp(v[back.scale[c]]);
                bad_scales += !(sc > 0 && isfinite(sc));
            }
            for (int p = 0; p < back.nprop; p++) bad_values += !isfinite(v[p]);
            /* the file's centre is the simulated splat's, to float rounding */
            for (int c = 0; c < 3; c++)
                bad_values += fabs(v[back.xyz[c]] - x[3 * i + c]) > 1e-6 * (1 + fabs(x[3 * i + c]));
        }
        rk_splats_free(&back);
    }
    if (!keep) remove(frame_tmp);
    if (every > 1) remove(small);
    /* where it came to rest, along the fall (z): the donut's lowest splat centre and proxy vertex
     * against the block's highest point and proxy vertex */
    double donut_low, donut_high, proxy_low, proxy_high, block_low, block_top, block_proxy_low, block_proxy_top, X0lo, X0hi;
    extent(x, 0, nd, 2, &donut_low, &donut_high);
    extent(x, nd, v1, 2, &proxy_low, &proxy_high);
    extent(x, v1, v1 + np, 2, &block_low, &block_top);
    extent(x, v1 + np, nv, 2, &block_proxy_low, &block_proxy_top);
    extent(sim.mesh.X, 0, nd, 2, &X0lo, &X0hi);
    printf("# %d of %d splats (every %d), %d frames: %d exact crossings at most, smallest distance %.3g m, "
           "%d splat-in-block and %d block-point-in-donut events, |q| - 1 at most %.2g, %d bad scales, %d bad values;"
           " at the end the donut's lowest splat %.4f m over the block's highest point %.4f m (it fell from %.4f),"
           " its proxy %.4f m over the block's proxy %.4f m; r = %d, %d integration points, %d collision vertices, build %.1f s,"
           " %.3f s/step (%.1f Newton iterations a step), %.3f s/frame to write\n",
           nd, full, every, frames, worst_inter, min_d, splat_inside, block_inside, worst_q, bad_scales, bad_values,
           donut_low, block_top, X0lo, proxy_low, block_proxy_top, R.model.r, R.model.quad.count, R.model.ncv, t_build,
           t_step / frames, (double)s.stats.newton_iterations / frames,
           t_write / (frames + 1));
    CHECK(worst_inter == 0, "%d crossings", worst_inter);
    CHECK(min_d > 0, "smallest distance %g", min_d);
    CHECK(splat_inside == 0, "%d times a splat centre was inside the block", splat_inside);
    CHECK(block_inside == 0, "%d times a block point was inside the donut", block_inside);
    CHECK(worst_q < 1e-6, "quaternion norm off by %g", worst_q);
    CHECK(bad_scales == 0 && bad_values == 0, "%d bad scales, %d bad values", bad_scales, bad_values);
    /* Landed: the donut's lowest surface vertex within the barrier's reach (dhat) of the block's
     * highest (its surface is not flat: rk_points_proxy moves each vertex in toward the points as
     * far as is safe, so the lowest may sit beside the block's highest and below it; that they
     * never cross is checked every frame above); and each object's points lie inside its surface,
     * which sits from about g/2 to s/2 off them (s their spacing; the voxel surface: anywhere up
     * to g), so the lowest splat is at most g_donut + dhat + g_block over the block's highest
     * point, g taken as twice the reach of the rest surface below the lowest rest point. */
    double rest_lo, rest_hi, rest_proxy_lo, rest_proxy_hi;
    extent(sim.mesh.X, nd, v1, 2, &rest_proxy_lo, &rest_proxy_hi);
    double g_donut = 2 * (X0lo - rest_proxy_lo);
    extent(sim.mesh.X, v1, v1 + np, 2, &rest_lo, &rest_hi);
    extent(sim.mesh.X, v1 + np, nv, 2, &rest_proxy_lo, &rest_proxy_hi);
    double g_block = 2 * (rest_lo - rest_proxy_lo), dhat = scene.contact.dhat, gap = proxy_low - block_proxy_top;
    const rk_contact_stats *cs = &R.model.contact.stats;
    printf("# proxy voxels: the donut's %.4f m, the block's %.4f m; dhat %g m; contact pairs %.0f a gather (at most %ld);"
           " of the steps' %.1f s: broad phase %.1f s, barrier %.1f s\n", g_donut, g_block, dhat,
           cs->gathers ? (double)cs->pairs / cs->gathers : 0.0, cs->max_pairs, t_step,
           cs->seconds_broad, cs->seconds_potential);
    CHECK(gap < dhat, "the donut's proxy rests %g m over the block's (dhat %g)", gap, dhat);
    CHECK(donut_low > block_top && donut_low < block_top + g_donut + dhat + g_block,
          "the donut's lowest splat %g, the block's top %g", donut_low, block_top);
    /* and the block stays on the plane, within the barrier's reach of it */
    const rk_obstacle *plane = &sim.obstacles[0];
    CHECK(plane->kind == RK_OBSTACLE_PLANE && block_proxy_low > plane->point[2] && block_proxy_low < plane->point[2] + dhat,
          "the block's proxy bottom at %g", block_proxy_low);
    free(x);
    free(tris);
    cloud_surface_free(&donut_proxy);
    cloud_surface_free(&block_proxy);
    rk_scene_splats_free(&sp);
    rk_rom_free(&s);
    rk_scene_rom_free(&R);
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
}

int main(void)
{
    RUN(donut_splats_land_on_a_block_of_points);
    return test_finish();
}
