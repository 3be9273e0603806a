/* Calibrated pinhole views from JSON. Convention (video.h): x_cam = R X + t with R world ->
 * camera, pixel = K x_cam / z. R is checked to be a rotation, since a file written with the
 * inverse convention or a scaled matrix would otherwise give rays that silently miss. */
#include "video/video_impl.h"

#include <math.h>
#include <string.h>

/* rows x cols numbers of a nested array [[...], ...] (rows 1: a flat array) into out, row-major. */
static int matrix(const cJSON *a, int rows, int cols, double *out)
{
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != (rows > 1 ? rows : cols)) return -1;
    for (int i = 0; i < rows; i++) {
        const cJSON *row = rows > 1 ? cJSON_GetArrayItem(a, i) : a;
        if (!cJSON_IsArray(row) || cJSON_GetArraySize(row) != cols) return -1;
        for (int j = 0; j < cols; j++) {
            const cJSON *e = cJSON_GetArrayItem(row, j);
            if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble)) return -1;
            out[cols * i + j] = e->valuedouble;
        }
    }
    return 0;
}

static int camera_load(const cJSON *o, int i, rk_camera *c, rk_error *err)
{
    const cJSON *name = cJSON_GetObjectItem(o, "name"), *frames = cJSON_GetObjectItem(o, "frames");
    snprintf(c->name, sizeof c->name, "%s", cJSON_IsString(name) ? name->valuestring : "");
    if (frames && !cJSON_IsString(frames)) return rk_fail(err, "views[%d].frames: expected a printf pattern (a string)", i);
    if (frames && strlen(frames->valuestring) >= sizeof c->frames)
        return rk_fail(err, "views[%d].frames: longer than %zu characters", i, sizeof c->frames - 1);
    snprintf(c->frames, sizeof c->frames, "%s", frames ? frames->valuestring : "");
    double size[2] = {0, 0};
    if (matrix(cJSON_GetObjectItem(o, "K"), 3, 3, c->K)) return rk_fail(err, "views[%d].K: expected 3 x 3 numbers", i);
    if (matrix(cJSON_GetObjectItem(o, "R"), 3, 3, c->R)) return rk_fail(err, "views[%d].R: expected 3 x 3 numbers", i);
    if (matrix(cJSON_GetObjectItem(o, "t"), 1, 3, c->t)) return rk_fail(err, "views[%d].t: expected 3 numbers", i);
    const cJSON *sz = cJSON_GetObjectItem(o, "size");
    if (sz && (matrix(sz, 1, 2, size) || size[0] < 2 || size[1] < 2 || size[0] > 32768 ||
        size[1] > 32768 || size[0] != floor(size[0]) || size[1] != floor(size[1])))
        return rk_fail(err, "views[%d].size: expected [width, height] in pixels", i);
    c->w = (int)size[0], c->h = (int)size[1];
    const double *K = c->K, *R = c->R;
    if (!(K[0] > 0 && K[4] > 0) || K[3] || K[6] || K[7] || K[8] != 1)
        return rk_fail(err, "views[%d].K: expected [[fx, s, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0", i);
    double worst = 0;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double d = R[a] * R[b] + R[3 + a] * R[3 + b] + R[6 + a] * R[6 + b] - (a == b);
            worst = fmax(worst, fabs(d));
        }
    double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) + R[2] * (R[3] * R[7] - R[4] * R[6]);
    if (worst > 1e-6 || fabs(det - 1) > 1e-6)
        return rk_fail(err, "views[%d].R is not a rotation: |R^T R - I| = %.3g, det R = %.6g (expected 0 and 1; R maps "
                       "world to camera, x_cam = R X + t)", i, worst, det);
    return 0;
}

int rk_cameras_from_json(const cJSON *root, rk_cameras *c, rk_error *err)
{
    memset(c, 0, sizeof *c);
    const cJSON *views = cJSON_GetObjectItem(root, "views");
    if (!cJSON_IsArray(views) || cJSON_GetArraySize(views) < 1 || cJSON_GetArraySize(views) > RK_VIDEO_MAX_VIEWS)
        return rk_fail(err, "views: expected an array of 1..%d cameras", RK_VIDEO_MAX_VIEWS);
    c->n = cJSON_GetArraySize(views);
    for (int i = 0; i < c->n; i++)
        if (camera_load(cJSON_GetArrayItem(views, i), i, &c->cam[i], err)) return -1;
    const cJSON *dt = cJSON_GetObjectItem(root, "dt");
    if (dt && (!cJSON_IsNumber(dt) || !(dt->valuedouble > 0) || !isfinite(dt->valuedouble)))
        return rk_fail(err, "dt: expected the seconds between frames, a positive number");
    c->dt = dt ? dt->valuedouble : 0;
    return 0;
}

cJSON *rk_cameras_to_json(const rk_cameras *c)
{
    cJSON *root = cJSON_CreateObject(), *views = cJSON_AddArrayToObject(root, "views");
    for (int i = 0; i < c->n; i++) {
        const rk_camera *k = &c->cam[i];
        cJSON *o = cJSON_CreateObject(), *K = cJSON_AddArrayToObject(o, "K"), *R;
        int size[2] = {k->w, k->h};
        if (k->name[0]) cJSON_AddStringToObject(o, "name", k->name);
        if (k->frames[0]) cJSON_AddStringToObject(o, "frames", k->frames);
        R = cJSON_CreateArray();
        for (int r = 0; r < 3; r++) {
            cJSON_AddItemToArray(K, cJSON_CreateDoubleArray(k->K + 3 * r, 3));
            cJSON_AddItemToArray(R, cJSON_CreateDoubleArray(k->R + 3 * r, 3));
        }
        cJSON_AddItemToObject(o, "R", R);
        cJSON_AddItemToObject(o, "t", cJSON_CreateDoubleArray(k->t, 3));
        cJSON_AddItemToObject(o, "size", cJSON_CreateIntArray(size, 2));
        cJSON_AddItemToArray(views, o);
    }
    if (c->dt > 0) cJSON_AddNumberToObject(root, "dt", c->dt);
    return root;
}

int rk_cameras_load(const char *path, rk_cameras *c, rk_error *err)
{
    memset(c, 0, sizeof *c);
    cJSON *root = rk_video_json_load(path, err);
    if (!root) return -1;
    int rc = rk_cameras_from_json(root, c, err);
    cJSON_Delete(root);
    return rc ? rk_error_prefix(err, "%s", path) : 0;
}

double rk_camera_project(const rk_camera *c, const double X[3], double px[2])
{
    const double *R = c->R, *K = c->K;
    double x[3];
    for (int i = 0; i < 3; i++) x[i] = R[3 * i] * X[0] + R[3 * i + 1] * X[1] + R[3 * i + 2] * X[2] + c->t[i];
    px[0] = (K[0] * x[0] + K[1] * x[1]) / x[2] + K[2];
    px[1] = K[4] * x[1] / x[2] + K[5];
    return x[2];
}

void rk_camera_ray(const rk_camera *c, const double px[2], double origin[3], double dir[3])
{
    const double *R = c->R, *K = c->K;
    /* K^-1 [u; v; 1] for upper-triangular K, then R^T into the world */
    double y = (px[1] - K[5]) / K[4], x = (px[0] - K[2] - K[1] * y) / K[0], d[3] = {x, y, 1}, n = 0;
    for (int i = 0; i < 3; i++) {
        origin[i] = -(R[i] * c->t[0] + R[3 + i] * c->t[1] + R[6 + i] * c->t[2]);
        dir[i] = R[i] * d[0] + R[3 + i] * d[1] + R[6 + i] * d[2];
        n += dir[i] * dir[i];
    }
    for (int i = 0; i < 3; i++) dir[i] /= sqrt(n);
}
