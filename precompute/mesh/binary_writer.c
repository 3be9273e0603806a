#include <string.h>

#include "mesh/binary_reader_impl.h"
#include "mesh/mesh_impl.h"

/* Writes the n bytes of a host-order value in the requested order. */
static void put(FILE *fp, const void *value, size_t n, int big_endian)
{
    unsigned char b[8];
    memcpy(b, value, n);
    if (big_endian == rk_host_little_endian())
        for (size_t i = 0; i < n / 2; i++) {
            unsigned char c = b[i];
            b[i] = b[n - 1 - i];
            b[n - 1 - i] = c;
        }
    fwrite(b, 1, n, fp);
}

void rk_put_i32(FILE *fp, int32_t v, int big_endian) { put(fp, &v, 4, big_endian); }
void rk_put_u64(FILE *fp, uint64_t v, int big_endian) { put(fp, &v, 8, big_endian); }
void rk_put_f32(FILE *fp, float v, int big_endian) { put(fp, &v, 4, big_endian); }
void rk_put_f64(FILE *fp, double v, int big_endian) { put(fp, &v, 8, big_endian); }
