/* The shown vertices' rest positions and basis columns, read from the asset's chunks: what the
 * runtime multiplies its reduced coordinates with (runtime/rows.c), in the file's precision. */
#include <stdlib.h>
#include <string.h>

#include "basis/basis.h"
#include "export/export.h"
#include "formats/rombin_read.h"

/* Real k of a chunk of the file's real type (read byte-wise: any alignment). */
static double real_at(const rombin_chunk *c, unsigned real_type, size_t k)
{
    if (real_type == ROMBIN_REAL_F64) {
        double v;
        memcpy(&v, c->data + 8 * k, 8);
        return v;
    }
    float v;
    memcpy(&v, c->data + 4 * k, 4);
    return v;
}

/* Chunk id, holding exactly `count` reals, or an error naming it. */
static int find_reals(const rombin_file *f, const char *id, size_t count, rombin_chunk *c, rk_error *err)
{
    size_t bytes = f->real_type == ROMBIN_REAL_F64 ? 8 : 4;
    if (!rombin_find(f, id, c)) return rk_fail(err, "the asset has no %s chunk", id);
    if (c->type != ROMBIN_TYPE_REAL || c->compression != ROMBIN_COMP_NONE || c->raw != count * bytes)
        return rk_fail(err, "chunk %s: %llu bytes where %zu stored reals were expected", id, (unsigned long long)c->raw,
                       count);
    return 0;
}

int rk_export_rows(const void *asset, size_t bytes, int koopman, int shown, int r, double *X, double *D, rk_error *err)
{
    rombin_file f;
    rombin_error e;
    rombin_chunk vert, rows, skin;
    if (rombin_open(&f, asset, bytes, NULL, &e)) return rk_fail(err, "%s", e.message);
    if (!koopman && rombin_find(&f, ROMBIN_ALRH, &rows))
        return rk_fail(err, "an adaptive linear ROM's basis changes every step, so its motion is not a fixed set of "
                       "morph targets; export of adaptive assets is not supported yet (romkit run --frames writes OBJ)");
    if (!rombin_find(&f, ROMBIN_VERT, &vert) || vert.raw % (3 * (f.real_type == ROMBIN_REAL_F64 ? 8 : 4)))
        return rk_fail(err, "the asset has no VERT chunk of whole vertices");
    size_t nv = vert.raw / (3 * (f.real_type == ROMBIN_REAL_F64 ? 8 : 4));
    if (shown < 1 || (size_t)shown > nv || r < 1)
        return rk_fail(err, "%d shown vertices and r = %d do not fit the asset's %zu stored vertices", shown, r, nv);
    for (size_t k = 0; k < 3 * (size_t)shown; k++) X[k] = real_at(&vert, f.real_type, k);
    size_t n3 = 3 * (size_t)shown;
    if (!koopman && rombin_find(&f, ROMBIN_SKIN, &skin) && !rombin_find(&f, ROMBIN_ROWS, &rows)) {
        /* a skinning basis stored as its weights: the rows formed from them, as the bake did */
        uint32_t H = skin.raw == 4 ? rombin_get_u32(skin.data) : 0;
        if (H < 1 || 12 * (size_t)H != (size_t)r) return rk_fail(err, "chunk SKIN: %u handles for r = %d", H, r);
        rombin_chunk wght;
        if (find_reals(&f, ROMBIN_WGHT, nv * H, &wght, err)) return -1;
        double *W = malloc(sizeof(double) * (size_t)shown * H + 1); /* shown x H, column-major */
        if (!W) return rk_fail(err, "out of memory for %d x %u skinning weights", shown, H);
        for (size_t v = 0; v < (size_t)shown; v++)
            for (size_t j = 0; j < H; j++) W[j * shown + v] = real_at(&wght, f.real_type, v * H + j);
        rk_skinning_to_U(W, shown, (int)H, X, D);
        free(W);
        return 0;
    }
    /* ROWS and KOUT: row 3v + a holds r reals, the vertex's coordinate a against each column */
    const char *id = koopman ? ROMBIN_KOUT : ROMBIN_ROWS;
    if (find_reals(&f, id, 3 * nv * (size_t)r, &rows, err)) return -1;
    for (size_t i = 0; i < n3; i++)
        for (size_t j = 0; j < (size_t)r; j++) D[j * n3 + i] = real_at(&rows, f.real_type, i * r + j);
    return 0;
}
