/* The basis rows of stored vertices (B_v: x_v = X_v + B_v q), read from ROWS, or for a skinning
 * basis stored as its weights (SKIN, WGHT) formed from them where they are needed and never stored:
 * row 3v + a holds w_j(v) X̄_c at column 12 j + 4 a + c, X̄ = (X_v, 1), zero elsewhere. A third of a
 * row's work, and no 3 nv r rows in the arena (the donut's 51,325 vertices at r = 84 took 52 MB). */
#include "runtime/loader_impl.h"

romrt_real rt_weight(const romrt_model *m, uint32_t v, int j)
{
    return m->w ? m->w[(size_t)v * (size_t)m->skin + (size_t)j] : m->rows[(size_t)3 * v * (size_t)m->r + (size_t)(12 * j + 3)];
}

romrt_real rt_row_dot(const romrt_model *m, uint32_t v, int a, const romrt_real *y)
{
    const romrt_real *X, *w;
    romrt_real s = 0;
    int j;
    if (!m->w) return rt_dot(m->r, m->rows + ((size_t)3 * v + (size_t)a) * (size_t)m->r, y);
    X = m->X + 3 * (size_t)v;
    w = m->w + (size_t)v * (size_t)m->skin;
    for (j = 0; j < m->skin; j++) {
        const romrt_real *yj = y + 12 * j + 4 * a;
        s += w[j] * (yj[0] * X[0] + yj[1] * X[1] + yj[2] * X[2] + yj[3]);
    }
    return s;
}

void rt_row_axpy(const romrt_model *m, uint32_t v, int a, romrt_real s, romrt_real *out)
{
    const romrt_real *X, *w;
    int j;
    if (!m->w) {
        const romrt_real *row = m->rows + ((size_t)3 * v + (size_t)a) * (size_t)m->r;
        for (j = 0; j < m->r; j++) out[j] += s * row[j];
        return;
    }
    X = m->X + 3 * (size_t)v;
    w = m->w + (size_t)v * (size_t)m->skin;
    for (j = 0; j < m->skin; j++) {
        romrt_real sw = s * w[j];
        romrt_real *oj = out + 12 * j + 4 * a;
        oj[0] += sw * X[0];
        oj[1] += sw * X[1];
        oj[2] += sw * X[2];
        oj[3] += sw;
    }
}

void rt_row(const romrt_model *m, uint32_t v, int a, romrt_real *out)
{
    int j;
    for (j = 0; j < m->r; j++) out[j] = 0;
    rt_row_axpy(m, v, a, 1, out);
}

void rt_vertex_position(const romrt_model *m, uint32_t v, const romrt_real *q, romrt_real x[3])
{
    int a;
    for (a = 0; a < 3; a++) x[a] = m->X[3 * (size_t)v + (size_t)a] + rt_row_dot(m, v, a, q);
}
