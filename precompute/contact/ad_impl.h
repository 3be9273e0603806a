/* Private to precompute/contact: second-order forward-mode automatic differentiation over up to 12
 * variables (the coordinates of a contact stencil: point and triangle, or two edges). A value
 * carries its gradient and its full Hessian; the distances are rational functions of the
 * coordinates, so +, -, * and / give their exact derivatives with no hand-expanded formulas. */
#ifndef RK_CONTACT_AD_IMPL_H
#define RK_CONTACT_AD_IMPL_H

#include <string.h>

#define RK_AD_MAX 12

typedef struct {
    int n;                          /* active variables */
    double v;                       /* value */
    double g[RK_AD_MAX];            /* gradient */
    double h[RK_AD_MAX * RK_AD_MAX];/* Hessian, row-major n x n in the first n*n entries */
} rk_ad;

static inline void rk_ad_const(rk_ad *a, int n, double v)
{
    a->n = n;
    a->v = v;
    memset(a->g, 0, sizeof(double) * (size_t)n);
    memset(a->h, 0, sizeof(double) * (size_t)n * n);
}

/* Variable i of n with value v. */
static inline void rk_ad_var(rk_ad *a, int n, int i, double v)
{
    rk_ad_const(a, n, v);
    a->g[i] = 1;
}

/* out = a + s b (out may alias a or b). */
static inline void rk_ad_axpy(rk_ad *out, const rk_ad *a, double s, const rk_ad *b)
{
    int n = a->n;
    out->n = n;
    out->v = a->v + s * b->v;
    for (int i = 0; i < n; i++) out->g[i] = a->g[i] + s * b->g[i];
    for (int i = 0; i < n * n; i++) out->h[i] = a->h[i] + s * b->h[i];
}

static inline void rk_ad_add(rk_ad *out, const rk_ad *a, const rk_ad *b) { rk_ad_axpy(out, a, 1, b); }
static inline void rk_ad_sub(rk_ad *out, const rk_ad *a, const rk_ad *b) { rk_ad_axpy(out, a, -1, b); }

/* out = a b (out must not alias a or b). */
static inline void rk_ad_mul(rk_ad *out, const rk_ad *a, const rk_ad *b)
{
    int n = a->n;
    out->n = n;
    out->v = a->v * b->v;
    for (int i = 0; i < n; i++) out->g[i] = a->v * b->g[i] + b->v * a->g[i];
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            out->h[n * i + j] = a->v * b->h[n * i + j] + b->v * a->h[n * i + j] + a->g[i] * b->g[j] + a->g[j] * b->g[i];
}

/* out = a / b (out must not alias a or b; b->v != 0). */
static inline void rk_ad_div(rk_ad *out, const rk_ad *a, const rk_ad *b)
{
    int n = a->n;
    double q = a->v / b->v, ib = 1 / b->v;
    double gq[RK_AD_MAX];
    out->n = n;
    out->v = q;
    for (int i = 0; i < n; i++) gq[i] = (a->g[i] - q * b->g[i]) * ib;
    /* q b = a  =>  H_q = (H_a - q H_b - g_q g_b^T - g_b g_q^T) / b */
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            out->h[n * i + j] =
                (a->h[n * i + j] - q * b->h[n * i + j] - gq[i] * b->g[j] - b->g[i] * gq[j]) * ib;
    memcpy(out->g, gq, sizeof(double) * (size_t)n);
}

/* Vectors of three rk_ad. */
typedef struct {
    rk_ad c[3];
} rk_ad3;

/* The point of 3 coordinates at variables [3k, 3k + 3) of n. */
static inline void rk_ad3_point(rk_ad3 *p, int n, int k, const double x[3])
{
    for (int i = 0; i < 3; i++) rk_ad_var(&p->c[i], n, 3 * k + i, x[i]);
}

/* A fixed point (no variables). */
static inline void rk_ad3_fixed(rk_ad3 *p, int n, const double x[3])
{
    for (int i = 0; i < 3; i++) rk_ad_const(&p->c[i], n, x[i]);
}

static inline void rk_ad3_sub(rk_ad3 *out, const rk_ad3 *a, const rk_ad3 *b)
{
    for (int i = 0; i < 3; i++) rk_ad_sub(&out->c[i], &a->c[i], &b->c[i]);
}

/* out = a . b */
static inline void rk_ad3_dot(rk_ad *out, const rk_ad3 *a, const rk_ad3 *b)
{
    rk_ad t;
    rk_ad_mul(out, &a->c[0], &b->c[0]);
    for (int i = 1; i < 3; i++) {
        rk_ad_mul(&t, &a->c[i], &b->c[i]);
        rk_ad_add(out, out, &t);
    }
}

/* out = a x b (out must not alias a or b). */
static inline void rk_ad3_cross(rk_ad3 *out, const rk_ad3 *a, const rk_ad3 *b)
{
    rk_ad s, t;
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        rk_ad_mul(&s, &a->c[j], &b->c[k]);
        rk_ad_mul(&t, &a->c[k], &b->c[j]);
        rk_ad_sub(&out->c[i], &s, &t);
    }
}

#endif
