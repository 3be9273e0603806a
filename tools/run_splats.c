/* romkit run --splats (run_splats.h). */
#include "run_splats.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "formats/rombin_read.h"

/* The SPLY chunk's bytes through a private temporary file: the splat reader reads files. */
static int read_stored_splats(const rombin_chunk *c, rk_splats *s, rk_error *err)
{
    char path[] = "/tmp/romkit_splats_XXXXXX";
    int fd = mkstemp(path);
    if (fd < 0) return rk_fail(err, "--splats: cannot create a temporary file: %s", strerror(errno));
    FILE *fp = fdopen(fd, "wb");
    int ok = fp && fwrite(c->data, 1, (size_t)c->raw, fp) == (size_t)c->raw;
    if (fp) ok = fclose(fp) == 0 && ok;
    else close(fd);
    int rc = ok ? rk_splats_read(path, s, err) : rk_fail(err, "--splats: cannot write a temporary file");
    remove(path);
    return rc;
}

int run_splats_open(run_splats *o, const char *dir, const unsigned char *asset, size_t bytes, const romrt_model *m,
                    rk_error *err)
{
    memset(o, 0, sizeof *o);
    o->dir = dir;
    rombin_file f;
    rombin_chunk c;
    rombin_error e;
    if (rombin_open(&f, asset, bytes, NULL, &e) != ROMBIN_OK) return rk_fail(err, "--splats: %s", e.message);
    if (!rombin_find(&f, ROMBIN_SPLY, &c) || c.compression != ROMBIN_COMP_NONE)
        return rk_fail(err, "--splats: the asset holds no Gaussian splats (SPLY): bake it from a point cloud "
                       "scene (mesh.points)");
    if (read_stored_splats(&c, &o->splats, err)) return -1;
    int n = o->splats.n;
    if ((size_t)n != romrt_shown_count(m)) {
        run_splats_close(o);
        return rk_fail(err, "--splats: the asset's splat file has %d splats, but it shows %zu points", n,
                       romrt_shown_count(m));
    }
    o->x = calloc(3 * (size_t)n + 1, sizeof(double));
    o->F = calloc(9 * (size_t)n + 1, sizeof(double));
    o->Fr = calloc(9 * (size_t)n + 1, sizeof(romrt_real));
    if (!o->x || !o->F || !o->Fr) {
        run_splats_close(o);
        return rk_fail(err, "--splats: out of memory for %d splats", n);
    }
    romrt_error rerr;
    if (romrt_deformation_gradients(m, o->Fr, 9 * (size_t)n, &rerr) != ROMRT_OK) {
        run_splats_close(o);
        return rk_fail(err, "--splats: %s", rerr.message);
    }
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        run_splats_close(o);
        return rk_fail(err, "%s: cannot create the splats folder: %s", dir, strerror(errno));
    }
    return 0;
}

int run_splats_frame(run_splats *o, const romrt_model *m, long k, const romrt_real *xyz, rk_error *err)
{
    int n = o->splats.n;
    romrt_error rerr;
    if (romrt_deformation_gradients(m, o->Fr, 9 * (size_t)n, &rerr) != ROMRT_OK)
        return rk_fail(err, "--splats: frame %ld: %s", k, rerr.message);
    for (size_t i = 0; i < 3 * (size_t)n; i++) o->x[i] = (double)xyz[i];
    for (size_t i = 0; i < 9 * (size_t)n; i++) o->F[i] = (double)o->Fr[i];
    char path[4200];
    snprintf(path, sizeof path, "%s/frame_%05ld.ply", o->dir, k);
    return rk_splats_write(path, &o->splats, o->x, o->F, err);
}

void run_splats_close(run_splats *o)
{
    rk_splats_free(&o->splats);
    free(o->x);
    free(o->F);
    free(o->Fr);
    memset(o, 0, sizeof *o);
}
