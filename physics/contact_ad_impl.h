/* contact_ad_impl.h: second-order forward-mode automatic differentiation over up to 12 variables
 * (the coordinates of a contact stencil: point and triangle, or two edges), private to
 * contact_impl.h and included by it (same rules as physics_impl.h: C99, both precisions, no
 * include guard, names through PHYS_FN). A value carries its gradient and its full Hessian; the
 * distances are rational functions of the coordinates, so +, -, * and / give their exact
 * derivatives with no hand-expanded formulas. */

#define PHYS_AD_MAX_ 12

typedef struct {
    int n;                               /* active variables */
    PHYS_REAL v;                         /* value */
    PHYS_REAL g[PHYS_AD_MAX_];           /* gradient */
    PHYS_REAL h[PHYS_AD_MAX_ * PHYS_AD_MAX_]; /* Hessian, row-major n x n in the first n*n entries */
} PHYS_FN(ad_);

/* Vectors of three. */
typedef struct {
    PHYS_FN(ad_) c[3];
} PHYS_FN(ad3_);

static void PHYS_FN(ad_const_)(PHYS_FN(ad_) *a, int n, PHYS_REAL v)
{
    a->n = n;
    a->v = v;
    memset(a->g, 0, sizeof(PHYS_REAL) * (size_t)n);
    memset(a->h, 0, sizeof(PHYS_REAL) * (size_t)n * (size_t)n);
}

/* Variable i of n with value v. */
static void PHYS_FN(ad_var_)(PHYS_FN(ad_) *a, int n, int i, PHYS_REAL v)
{
    PHYS_FN(ad_const_)(a, n, v);
    a->g[i] = 1;
}

/* out = a + s b (out may alias a or b). */
static void PHYS_FN(ad_axpy_)(PHYS_FN(ad_) *out, const PHYS_FN(ad_) *a, PHYS_REAL s, const PHYS_FN(ad_) *b)
{
    int n = a->n, i;
    out->n = n;
    out->v = a->v + s * b->v;
    for (i = 0; i < n; i++) out->g[i] = a->g[i] + s * b->g[i];
    for (i = 0; i < n * n; i++) out->h[i] = a->h[i] + s * b->h[i];
}

static void PHYS_FN(ad_add_)(PHYS_FN(ad_) *out, const PHYS_FN(ad_) *a, const PHYS_FN(ad_) *b)
{
    PHYS_FN(ad_axpy_)(out, a, 1, b);
}

static void PHYS_FN(ad_sub_)(PHYS_FN(ad_) *out, const PHYS_FN(ad_) *a, const PHYS_FN(ad_) *b)
{
    PHYS_FN(ad_axpy_)(out, a, -1, b);
}

/* out = a b (out must not alias a or b). */
static void PHYS_FN(ad_mul_)(PHYS_FN(ad_) *out, const PHYS_FN(ad_) *a, const PHYS_FN(ad_) *b)
{
    int n = a->n, i, j;
    out->n = n;
    out->v = a->v * b->v;
    for (i = 0; i < n; i++) out->g[i] = a->v * b->g[i] + b->v * a->g[i];
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++)
            out->h[n * i + j] = a->v * b->h[n * i + j] + b->v * a->h[n * i + j] + a->g[i] * b->g[j] + a->g[j] * b->g[i];
}

/* out = a / b (out must not alias a or b; b->v != 0). */
static void PHYS_FN(ad_div_)(PHYS_FN(ad_) *out, const PHYS_FN(ad_) *a, const PHYS_FN(ad_) *b)
{
    int n = a->n, i, j;
    PHYS_REAL q = a->v / b->v, ib = 1 / b->v;
    PHYS_REAL gq[PHYS_AD_MAX_];
    out->n = n;
    out->v = q;
    for (i = 0; i < n; i++) gq[i] = (a->g[i] - q * b->g[i]) * ib;
    /* q b = a  =>  H_q = (H_a - q H_b - g_q g_b^T - g_b g_q^T) / b */
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++)
            out->h[n * i + j] = (a->h[n * i + j] - q * b->h[n * i + j] - gq[i] * b->g[j] - b->g[i] * gq[j]) * ib;
    memcpy(out->g, gq, sizeof(PHYS_REAL) * (size_t)n);
}

/* The point of 3 coordinates at variables [3k, 3k + 3) of n. */
static void PHYS_FN(ad3_point_)(PHYS_FN(ad3_) *p, int n, int k, const PHYS_REAL x[3])
{
    int i;
    for (i = 0; i < 3; i++) PHYS_FN(ad_var_)(&p->c[i], n, 3 * k + i, x[i]);
}

static void PHYS_FN(ad3_sub_)(PHYS_FN(ad3_) *out, const PHYS_FN(ad3_) *a, const PHYS_FN(ad3_) *b)
{
    int i;
    for (i = 0; i < 3; i++) PHYS_FN(ad_sub_)(&out->c[i], &a->c[i], &b->c[i]);
}

/* out = a . b */
static void PHYS_FN(ad3_dot_)(PHYS_FN(ad_) *out, const PHYS_FN(ad3_) *a, const PHYS_FN(ad3_) *b)
{
    PHYS_FN(ad_) t;
    int i;
    PHYS_FN(ad_mul_)(out, &a->c[0], &b->c[0]);
    for (i = 1; i < 3; i++) {
        PHYS_FN(ad_mul_)(&t, &a->c[i], &b->c[i]);
        PHYS_FN(ad_add_)(out, out, &t);
    }
}

/* out = a x b (out must not alias a or b). */
static void PHYS_FN(ad3_cross_)(PHYS_FN(ad3_) *out, const PHYS_FN(ad3_) *a, const PHYS_FN(ad3_) *b)
{
    PHYS_FN(ad_) s, t;
    int i;
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        PHYS_FN(ad_mul_)(&s, &a->c[j], &b->c[k]);
        PHYS_FN(ad_mul_)(&t, &a->c[k], &b->c[j]);
        PHYS_FN(ad_sub_)(&out->c[i], &s, &t);
    }
}

#undef PHYS_AD_MAX_
