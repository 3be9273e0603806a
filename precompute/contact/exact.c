/* The sign of orient3d in exact arithmetic (contact.h): a floating-point evaluation where its error
 * bound settles the sign, else the determinant as a floating-point expansion (Shewchuk 1997,
 * "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates"): every
 * difference, product and sum is kept exactly as a sum of non-overlapping doubles. */
#include "contact/contact.h"

#include <float.h>
#include <math.h>

/* An expansion: up to 192 components, smallest magnitude first. */
typedef struct {
    int n;
    double e[192];
} expansion;

static void two_sum(double a, double b, double *x, double *y)
{
    *x = a + b;
    double bv = *x - a, av = *x - bv;
    *y = (a - av) + (b - bv);
}

static void two_diff(double a, double b, double *x, double *y) { two_sum(a, -b, x, y); }

/* Product a b = x + y exactly (fma gives the rounding error). */
static void two_product(double a, double b, double *x, double *y)
{
    *x = a * b;
    *y = fma(a, b, -*x);
}

/* h = e + b (Shewchuk's GROW-EXPANSION, Theorem 10): nonoverlapping and increasing when e is;
 * zero components dropped. */
static void grow_expansion(const expansion *e, double b, expansion *h)
{
    expansion out = {0};
    double q = b, hh;
    for (int i = 0; i < e->n; i++) {
        two_sum(q, e->e[i], &q, &hh);
        if (hh != 0) out.e[out.n++] = hh;
    }
    if (q != 0 || out.n == 0) out.e[out.n++] = q;
    *h = out;
}

/* h = e + f (EXPANSION-SUM, Theorem 12: e grown by every component of f). */
static void expansion_sum(const expansion *e, const expansion *f, expansion *h)
{
    expansion acc = *e;
    for (int j = 0; j < f->n; j++) grow_expansion(&acc, f->e[j], &acc);
    *h = acc;
}

/* h = b e (scale an expansion by a double). */
static void scale_expansion(const expansion *e, double b, expansion *h)
{
    expansion out = {0};
    if (e->n == 0) {
        *h = out;
        return;
    }
    double q, hh;
    two_product(e->e[0], b, &q, &hh);
    if (hh != 0) out.e[out.n++] = hh;
    for (int i = 1; i < e->n; i++) {
        double p1, p0, s;
        two_product(e->e[i], b, &p1, &p0);
        two_sum(q, p0, &s, &hh);
        if (hh != 0) out.e[out.n++] = hh;
        two_sum(p1, s, &q, &hh);
        if (hh != 0) out.e[out.n++] = hh;
    }
    if (q != 0 || out.n == 0) out.e[out.n++] = q;
    *h = out;
}

/* h = e f */
static void expansion_product(const expansion *e, const expansion *f, expansion *h)
{
    expansion acc = {0}, part;
    for (int j = 0; j < f->n; j++) {
        scale_expansion(e, f->e[j], &part);
        expansion_sum(&acc, &part, &acc);
    }
    *h = acc;
}

static void diff_expansion(double a, double b, expansion *h)
{
    double x, y;
    two_diff(a, b, &x, &y);
    h->n = 0;
    if (y != 0) h->e[h->n++] = y;
    if (x != 0 || h->n == 0) h->e[h->n++] = x;
}

static int sign_of(const expansion *e)
{
    double top = e->n ? e->e[e->n - 1] : 0; /* the largest component decides */
    return (top > 0) - (top < 0);
}

int rk_orient3d_sign(const double *a, const double *b, const double *c, const double *d)
{
    double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    double det = adx * (bdy * cdz - bdz * cdy) + bdx * (cdy * adz - cdz * ady) + cdx * (ady * bdz - adz * bdy);
    double permanent = (fabs(bdy * cdz) + fabs(bdz * cdy)) * fabs(adx) + (fabs(cdy * adz) + fabs(cdz * ady)) * fabs(bdx) +
                       (fabs(ady * bdz) + fabs(adz * bdy)) * fabs(cdx);
    double bound = (7.0 + 56.0 * DBL_EPSILON / 2) * (DBL_EPSILON / 2) * permanent; /* Shewchuk's o3derrboundA */
    if (det > bound) return 1;
    if (-det > bound) return -1;
    /* exact: every difference is a two-component expansion, then the cofactor expansion */
    expansion X[3][3], t1, t2, m, term, sum = {0};
    const double *p[3] = {a, b, c};
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) diff_expansion(p[r][k], d[k], &X[r][k]);
    /* det = X0 . (X1 x X2), with (X1 x X2)_k = X1_k1 X2_k2 - X1_k2 X2_k1 */
    for (int k = 0; k < 3; k++) {
        int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        expansion_product(&X[1][k1], &X[2][k2], &t1);
        expansion_product(&X[1][k2], &X[2][k1], &t2);
        for (int i = 0; i < t2.n; i++) t2.e[i] = -t2.e[i];
        expansion_sum(&t1, &t2, &m);
        expansion_product(&X[0][k], &m, &term);
        expansion_sum(&sum, &term, &sum);
    }
    return sign_of(&sum);
}
