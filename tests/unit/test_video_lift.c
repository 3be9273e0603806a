/* precompute/video cameras and lift: the pinhole convention round-trips (a pixel's ray passes
 * through the point projected there); dots of two views on a unit cube's rest surface become
 * markers at the right surface points, their motion is recovered exactly from exact tracks, a
 * dot that one view sees alone and a marker that one view loses are dropped and counted; a
 * cameras file whose R is not a rotation is refused by name. */
#include "testlib.h"
#include "video/video.h"

/* A camera at eye looking at the origin region (x right, y down), as JSON. */
static void camera_json(FILE *f, const char *name, const double eye[3], const double at[3], int last)
{
    double z[3] = {at[0] - eye[0], at[1] - eye[1], at[2] - eye[2]}, up[3] = {0, 1, 0}, x[3], y[3];
    double n = sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    for (int i = 0; i < 3; i++) z[i] /= n;
    x[0] = z[1] * up[2] - z[2] * up[1], x[1] = z[2] * up[0] - z[0] * up[2], x[2] = z[0] * up[1] - z[1] * up[0];
    n = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (int i = 0; i < 3; i++) x[i] /= n;
    y[0] = z[1] * x[2] - z[2] * x[1], y[1] = z[2] * x[0] - z[0] * x[2], y[2] = z[0] * x[1] - z[1] * x[0];
    const double *R[3] = {x, y, z};
    fprintf(f, "{\"name\": \"%s\", \"K\": [[400, 0, 159.5], [0, 400, 119.5], [0, 0, 1]], \"size\": [320, 240], \"R\": [", name);
    for (int r = 0; r < 3; r++) fprintf(f, "[%.17g, %.17g, %.17g]%s", R[r][0], R[r][1], R[r][2], r < 2 ? ", " : "], ");
    fprintf(f, "\"t\": [%.17g, %.17g, %.17g]}%s\n", -(x[0] * eye[0] + x[1] * eye[1] + x[2] * eye[2]),
            -(y[0] * eye[0] + y[1] * eye[1] + y[2] * eye[2]), -(z[0] * eye[0] + z[1] * eye[1] + z[2] * eye[2]),
            last ? "" : ",");
}

static const char *cams_path(void)
{
    static char p[512];
    snprintf(p, sizeof p, "%s/romkit_%d_cams.json", tl_tmpdir(), (int)getpid());
    FILE *f = fopen(p, "w");
    double a[3] = {-0.6, 2.5, 3.0}, b[3] = {1.6, 2.5, 3.0}, at[3] = {0.5, 0.4, 0.5};
    fprintf(f, "{\"views\": [\n");
    camera_json(f, "a", a, at, 0);
    camera_json(f, "b", b, at, 1);
    fprintf(f, "]}\n");
    fclose(f);
    return p;
}

TEST(a_pixels_ray_passes_through_its_point)
{
    rk_error err = {{0}};
    rk_cameras c;
    const char *p = cams_path();
    CHECK_OK(rk_cameras_load(p, &c, &err));
    remove(p);
    CHECK(c.n == 2 && c.cam[1].w == 320, "%d cameras", c.n);
    double X[3] = {0.3, 0.9, 0.7}, px[2], o[3], d[3];
    CHECK(rk_camera_project(&c.cam[0], X, px) > 0, "the point is behind camera a");
    rk_camera_ray(&c.cam[0], px, o, d);
    double s = (X[0] - o[0]) * d[0] + (X[1] - o[1]) * d[1] + (X[2] - o[2]) * d[2], miss = 0;
    for (int i = 0; i < 3; i++) miss += pow(o[i] + s * d[i] - X[i], 2);
    CHECK(sqrt(miss) < 1e-12, "the ray misses the point by %g", sqrt(miss));
    /* the camera looks down at the cube: its top face's point projects above its bottom's */
    double top[3] = {0.5, 1, 0.5}, bottom[3] = {0.5, 0, 0.5}, pt[2], pb[2];
    rk_camera_project(&c.cam[0], top, pt);
    rk_camera_project(&c.cam[0], bottom, pb);
    CHECK(pt[1] < pb[1], "y is not down: top at %g, bottom at %g", pt[1], pb[1]);
}

/* The unit cube [0,1]^3: 8 vertices, 12 triangles. */
static const int cube_tris[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                  3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};

static void cube(double *X)
{
    for (int v = 0; v < 8; v++) X[3 * v] = (v == 1 || v == 2 || v == 5 || v == 6), X[3 * v + 1] = (v == 2 || v == 3 || v == 6 || v == 7), X[3 * v + 2] = v >= 4;
}

TEST(dots_become_markers_on_the_surface)
{
    rk_error err = {{0}};
    rk_cameras c;
    const char *p = cams_path();
    CHECK_OK(rk_cameras_load(p, &c, &err));
    remove(p);
    double X[24];
    cube(X);
    /* three dots: on the top face, on the front face (z = 1), and one more on top; view b also
     * sees a fourth dot (a speck only it sees); view b loses dot 2 at frame 3 */
    double P[4][3] = {{0.3, 1, 0.4}, {0.6, 0.5, 1}, {0.7, 1, 0.8}, {0.2, 0.3, 1}};
    enum { T = 5, K = 3 };
    rk_tracks tr;
    memset(&tr, 0, sizeof tr);
    tr.T = T, tr.nviews = 2;
    for (int v = 0; v < 2; v++) {
        rk_view_tracks *w = &tr.v[v];
        w->w = 320, w->h = 240, w->n = K + v;
        w->xy = calloc((size_t)2 * T * w->n, sizeof(double));
        w->lost = calloc((size_t)w->n, sizeof(int));
        for (int i = 0; i < w->n; i++) {
            w->lost[i] = v == 1 && i == 2 ? 3 : -1;
            for (int t = 0; t < T; t++) { /* a translation growing with t */
                double Q[3] = {P[i][0] + 0.01 * t, P[i][1] - 0.02 * t * t, P[i][2] + 0.005 * t};
                rk_camera_project(&c.cam[v], Q, w->xy + (size_t)2 * (T * i + t));
            }
        }
    }
    rk_video_markers m;
    int rc = rk_video_lift(&tr, &c, X, 8, cube_tris, 12, 0.01, &m, &err);
    rk_tracks_free(&tr);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(m.hit == 7 && m.matched == 3 && m.single_view == 1 && m.lost == 1 && m.k == 2,
          "hit %d, matched %d, single view %d, lost %d, kept %d", m.hit, m.matched, m.single_view, m.lost, m.k);
    for (int i = 0; i < 2; i++) {
        double at[3] = {0, 0, 0};
        for (int a = 0; a < 3; a++)
            for (int d = 0; d < 3; d++) at[d] += m.bary[3 * i + a] * X[3 * m.tri[3 * i + a] + d];
        CHECK(fabs(at[0] - P[i][0]) + fabs(at[1] - P[i][1]) + fabs(at[2] - P[i][2]) < 1e-9,
              "marker %d at (%g, %g, %g), dot at (%g, %g, %g)", i, at[0], at[1], at[2], P[i][0], P[i][1], P[i][2]);
        for (int t = 0; t < T; t++) {
            const double *u = m.disp + (size_t)3 * (m.k * t + i);
            CHECK(fabs(u[0] - 0.01 * t) + fabs(u[1] + 0.02 * t * t) + fabs(u[2] - 0.005 * t) < 1e-9,
                  "marker %d, frame %d: (%g, %g, %g)", i, t, u[0], u[1], u[2]);
        }
    }
    CHECK(m.reproj_max < 1e-6, "reprojection error %g px from exact tracks", m.reproj_max);
    rk_video_markers_free(&m);
}

TEST(a_camera_whose_R_is_not_a_rotation_is_refused)
{
    rk_error err = {{0}};
    rk_cameras c;
    char p[512];
    snprintf(p, sizeof p, "%s/romkit_%d_skew.json", tl_tmpdir(), (int)getpid());
    FILE *f = fopen(p, "w");
    fprintf(f, "{\"views\": [{\"K\": [[400, 0, 160], [0, 400, 120], [0, 0, 1]], \"size\": [320, 240],"
               " \"R\": [[1, 0, 0], [0, 1, 0], [0, 0, -1]], \"t\": [0, 0, 3]}]}\n");
    fclose(f);
    int rc = rk_cameras_load(p, &c, &err);
    remove(p);
    CHECK(rc && strstr(err.msg, "views[0].R is not a rotation") && strstr(err.msg, "det R = -1"), "%s", err.msg);
}

int main(void)
{
    RUN(a_pixels_ray_passes_through_its_point);
    RUN(dots_become_markers_on_the_surface);
    RUN(a_camera_whose_R_is_not_a_rotation_is_refused);
    return test_finish();
}
