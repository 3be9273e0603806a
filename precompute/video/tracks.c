/* romkit track's output as JSON, and the same file read back by romkit dmd --tracks. A file
 * written elsewhere (another tracker) is checked as it is read: every error names the view,
 * the track and the key. */
#include "video/video_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rk_tracks_free(rk_tracks *t)
{
    for (int v = 0; v < RK_VIDEO_MAX_VIEWS; v++) {
        free(t->v[v].xy);
        free(t->v[v].lost);
    }
    memset(t, 0, sizeof *t);
}

static cJSON *view_json(const rk_view_tracks *v, int T)
{
    cJSON *o = cJSON_CreateObject(), *d = cJSON_CreateObject(), *tr = cJSON_CreateArray();
    int size[2] = {v->w, v->h};
    cJSON_AddStringToObject(o, "source", v->source);
    cJSON_AddItemToObject(o, "size", cJSON_CreateIntArray(size, 2));
    cJSON_AddNumberToObject(d, "found", v->dots.kept);
    cJSON_AddNumberToObject(d, "components", v->dots.components);
    cJSON_AddNumberToObject(d, "too_small", v->dots.too_small);
    cJSON_AddNumberToObject(d, "too_large", v->dots.too_large);
    cJSON_AddNumberToObject(d, "on_border", v->dots.on_border);
    cJSON_AddNumberToObject(d, "threshold", v->dots.threshold);
    cJSON_AddItemToObject(o, "dots", d);
    int lost = 0;
    for (int i = 0; i < v->n; i++) {
        cJSON *t = cJSON_CreateObject();
        int len = v->lost[i] < 0 ? T : v->lost[i];
        lost += v->lost[i] >= 0;
        cJSON_AddNumberToObject(t, "lost", v->lost[i]);
        cJSON_AddItemToObject(t, "xy", cJSON_CreateDoubleArray(v->xy + (size_t)2 * T * i, 2 * len));
        cJSON_AddItemToArray(tr, t);
    }
    cJSON_AddNumberToObject(o, "lost", lost);
    cJSON_AddNumberToObject(o, "fb_max", v->fb_max);
    cJSON_AddItemToObject(o, "tracks", tr);
    return o;
}

int rk_tracks_save(const char *path, const rk_tracks *t, rk_error *err)
{
    cJSON *root = cJSON_CreateObject(), *views = cJSON_CreateArray();
    cJSON_AddNumberToObject(root, "frames", t->T);
    for (int v = 0; v < t->nviews; v++) cJSON_AddItemToArray(views, view_json(&t->v[v], t->T));
    cJSON_AddItemToObject(root, "views", views);
    if (t->calibrated) cJSON_AddItemToObject(root, "cameras", rk_cameras_to_json(&t->cams));
    char *text = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    if (!text) return rk_fail(err, "%s: out of memory writing the tracks", path);
    rk_atomic_file f;
    int rc = rk_atomic_open(&f, path, err);
    if (!rc) {
        fputs(text, f.fp);
        fputc('\n', f.fp);
        rc = rk_atomic_commit(&f, err);
    }
    free(text);
    return rc;
}

static char *slurp(const char *path, rk_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        rk_fail(err, "cannot open %s", path);
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = n >= 0 ? rk_calloc((size_t)n + 1, 1, err) : NULL;
    if (s && fread(s, 1, (size_t)n, f) != (size_t)n) {
        free(s);
        s = NULL;
        rk_fail(err, "cannot read %s", path);
    }
    fclose(f);
    return s;
}

cJSON *rk_video_json_load(const char *path, rk_error *err)
{
    char *s = slurp(path, err);
    if (!s) return NULL;
    cJSON *root = cJSON_Parse(s);
    if (!root) {
        const char *e = cJSON_GetErrorPtr();
        rk_fail(err, "%s: not JSON (at byte %ld)", path, e ? (long)(e - s) : -1L);
    }
    free(s);
    return root;
}

static int view_load(const cJSON *o, int vi, int T, rk_view_tracks *v, rk_error *err)
{
    const cJSON *src = cJSON_GetObjectItem(o, "source"), *size = cJSON_GetObjectItem(o, "size"),
                *tr = cJSON_GetObjectItem(o, "tracks"), *d = cJSON_GetObjectItem(o, "dots");
    if (cJSON_IsString(src)) snprintf(v->source, sizeof v->source, "%s", src->valuestring);
    if (!cJSON_IsArray(size) || cJSON_GetArraySize(size) != 2 || !cJSON_IsNumber(cJSON_GetArrayItem(size, 0)) ||
        !cJSON_IsNumber(cJSON_GetArrayItem(size, 1)))
        return rk_fail(err, "views[%d].size: expected [width, height]", vi);
    v->w = cJSON_GetArrayItem(size, 0)->valueint, v->h = cJSON_GetArrayItem(size, 1)->valueint;
    if (cJSON_IsNumber(cJSON_GetObjectItem(d, "found"))) v->dots.kept = cJSON_GetObjectItem(d, "found")->valueint;
    if (!cJSON_IsArray(tr)) return rk_fail(err, "views[%d].tracks: expected an array", vi);
    v->n = cJSON_GetArraySize(tr);
    v->xy = rk_calloc((size_t)2 * T * (v->n ? v->n : 1), sizeof(double), err);
    v->lost = rk_calloc((size_t)(v->n ? v->n : 1), sizeof(int), err);
    if (!v->xy || !v->lost) return -1;
    for (int i = 0; i < v->n; i++) {
        const cJSON *t = cJSON_GetArrayItem(tr, i), *lost = cJSON_GetObjectItem(t, "lost"), *xy = cJSON_GetObjectItem(t, "xy");
        if (!cJSON_IsNumber(lost) || lost->valueint < -1 || lost->valueint == 0 || lost->valueint >= T)
            return rk_fail(err, "views[%d].tracks[%d].lost: expected -1 or a frame in 1..%d", vi, i, T - 1);
        v->lost[i] = lost->valueint;
        int len = v->lost[i] < 0 ? T : v->lost[i];
        if (!cJSON_IsArray(xy) || cJSON_GetArraySize(xy) != 2 * len)
            return rk_fail(err, "views[%d].tracks[%d].xy: expected %d numbers (x, y of frames 0..%d)", vi, i, 2 * len,
                           len - 1);
        int j = 0;
        for (const cJSON *e = xy->child; e; e = e->next, j++) {
            if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
                return rk_fail(err, "views[%d].tracks[%d].xy[%d]: not a finite number", vi, i, j);
            v->xy[(size_t)2 * T * i + j] = e->valuedouble;
        }
    }
    return 0;
}

int rk_tracks_load(const char *path, rk_tracks *t, rk_error *err)
{
    memset(t, 0, sizeof *t);
    cJSON *root = rk_video_json_load(path, err);
    if (!root) return -1;
    const cJSON *T = cJSON_GetObjectItem(root, "frames"), *views = cJSON_GetObjectItem(root, "views");
    int rc = 0;
    if (!cJSON_IsNumber(T) || T->valueint < 2) rc = rk_fail(err, "frames: expected a number of frames >= 2");
    else if (!cJSON_IsArray(views) || cJSON_GetArraySize(views) < 1 || cJSON_GetArraySize(views) > RK_VIDEO_MAX_VIEWS)
        rc = rk_fail(err, "views: expected an array of 1..%d views", RK_VIDEO_MAX_VIEWS);
    else {
        t->T = T->valueint;
        t->nviews = cJSON_GetArraySize(views);
        for (int v = 0; v < t->nviews && !rc; v++) rc = view_load(cJSON_GetArrayItem(views, v), v, t->T, &t->v[v], err);
        const cJSON *cams = cJSON_GetObjectItem(root, "cameras");
        if (!rc && cams) {
            rc = rk_cameras_from_json(cams, &t->cams, err);
            if (rc) rk_error_prefix(err, "cameras");
            t->calibrated = !rc;
        }
    }
    cJSON_Delete(root);
    if (rc) {
        rk_tracks_free(t);
        return rk_error_prefix(err, "%s", path);
    }
    return 0;
}
