/* Follower pressure on a chamber's walls (koopman-dmd-log-linear paper, Sec. 7.3: F = A(X) C, the
 * force of pressure C from the deformed chamber faces). A chamber is a closed set of the mesh's
 * boundary faces, each oriented outward of the solid, i.e. into the void. A gauge pressure P pushes
 * every wall out of the void: face (a, b, c) with n2 = (x_b - x_a) x (x_c - x_a) (twice its area
 * times its unit normal) takes f = -P n2 / 2, split equally, -P n2 / 6 on each of its vertices.
 *
 * Why the chamber must be closed: then the force is conservative. The void's volume is
 *   V(x) = -1/6 sum_faces (x_a - o) . ((x_b - o) x (x_c - o))   (divergence theorem, any fixed o;
 * minus because the faces point into the void), and summed around each closed vertex fan,
 * dV/dx_a = -1/6 sum (x_b x x_c) equals -1/6 sum n2 (the edge terms of the neighbouring faces
 * cancel), so f = P dV/dx exactly and the load is the potential W = -P V (hydrostatic work). The
 * time step's incremental potential takes W, its gradient is exact, the line search sees the
 * pressure's work, and the load stiffness -P d2V/dx2 is symmetric. It is indefinite, so it goes
 * into the Newton matrix only with the elements' exact dP/dF (time steps, where the inertia keeps
 * the matrix definite almost always); where CHOLMOD finds that matrix indefinite, the projected one
 * it falls back to, and every static solve's, leaves it out (lagged: a few more Newton iterations
 * when P is a sizeable part of the stiffness). An open face set has no such W and is refused
 * (rk_chamber_check). */
#include "fom/fom.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void sub3(const double *a, const double *b, double *o)
{
    for (int i = 0; i < 3; i++) o[i] = a[i] - b[i];
}

static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

void rk_pressure_face(const double *xa, const double *xb, const double *xc, double P, double f[3], double J[27])
{
    double e1[3], e2[3], n2[3];
    sub3(xb, xa, e1);
    sub3(xc, xa, e2);
    cross3(e1, e2, n2);
    for (int i = 0; i < 3; i++) f[i] = -P * n2[i] / 6;
    if (!J) return;
    /* d n2 = [e2 - e1]x dx_a - [e2]x dx_b + [e1]x dx_c, [u]x the cross-product matrix (u x .) */
    double u[3][3];
    sub3(e2, e1, u[0]);
    for (int i = 0; i < 3; i++) u[1][i] = -e2[i], u[2][i] = e1[i];
    for (int w = 0; w < 3; w++) {
        const double *a = u[w];
        double X[9] = {0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0};
        for (int k = 0; k < 9; k++) J[9 * w + k] = -P * X[k] / 6;
    }
}

void rk_chamber_force(const rk_chamber *c, const double *x, double scale, double *f)
{
    for (int t = 0; t < c->nf; t++) {
        const int *v = &c->tris[3 * t];
        double fv[3];
        rk_pressure_face(&x[3 * v[0]], &x[3 * v[1]], &x[3 * v[2]], scale * c->pressure, fv, NULL);
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++) f[3 * v[k] + i] += fv[i];
    }
}

void rk_chamber_add_stiffness(const rk_chamber *c, const double *x, double scale, rk_sparse *H)
{
    for (int t = 0; t < c->nf; t++) {
        const int *v = &c->tris[3 * t];
        double f[3], J[27];
        rk_pressure_face(&x[3 * v[0]], &x[3 * v[1]], &x[3 * v[2]], scale * c->pressure, f, J);
        /* the potential's Hessian is -df/dx: vertex v[k] takes -J_w from vertex v[w]; only the upper
         * triangle is stored, which summed over the closed chamber is the symmetric whole's */
        for (int k = 0; k < 3; k++)
            for (int w = 0; w < 3; w++)
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++) {
                        int row = 3 * v[k] + i, col = 3 * v[w] + j;
                        if (row > col) continue;
                        int slot = rk_p2_slot(H, row, col); /* a face's vertices share a tet: in the pattern */
                        if (slot < H->colptr[col + 1] && H->rowind[slot] == row) H->val[slot] -= J[9 * w + 3 * i + j];
                    }
    }
}

double rk_chamber_volume(const rk_chamber *c, const double *x)
{
    if (c->nf == 0) return 0;
    const double *o = &x[3 * c->tris[0]]; /* a vertex of the surface: small differences, little rounding */
    double V = 0;
    for (int t = 0; t < c->nf; t++) {
        const int *v = &c->tris[3 * t];
        double a[3], b[3], d[3], bd[3];
        sub3(&x[3 * v[0]], o, a);
        sub3(&x[3 * v[1]], o, b);
        sub3(&x[3 * v[2]], o, d);
        cross3(b, d, bd);
        V -= (a[0] * bd[0] + a[1] * bd[1] + a[2] * bd[2]) / 6;
    }
    return V;
}

double rk_chamber_pressure_at(const rk_chamber *c, double t)
{
    if (c->nkeys == 0) return c->pressure;
    const double *k = c->keys;
    if (t <= k[0]) return k[1];
    for (int i = 1; i < c->nkeys; i++)
        if (t <= k[2 * i]) {
            double w = (t - k[2 * i - 2]) / (k[2 * i] - k[2 * i - 2]);
            return (1 - w) * k[2 * i - 1] + w * k[2 * i + 1];
        }
    return k[2 * c->nkeys - 1];
}

static int edge_cmp(const void *p, const void *q)
{
    const long long *a = p, *b = q;
    return *a < *b ? -1 : *a > *b;
}

int rk_chamber_check(const rk_chamber *c, int nv, rk_error *err)
{
    if (c->nf < 1 || !c->tris) return rk_fail(err, "has no faces");
    if (!isfinite(c->pressure)) return rk_fail(err, "pressure %g is not finite", c->pressure);
    if (c->nkeys < 0 || (c->nkeys > 0 && !c->keys)) return rk_fail(err, "%d pressure keys given without data", c->nkeys);
    for (int k = 0; k < c->nkeys; k++) {
        if (!isfinite(c->keys[2 * k]) || !isfinite(c->keys[2 * k + 1]))
            return rk_fail(err, "pressure key %d (%g s, %g Pa) is not finite", k, c->keys[2 * k], c->keys[2 * k + 1]);
        if (k > 0 && !(c->keys[2 * k] > c->keys[2 * k - 2]))
            return rk_fail(err, "pressure key %d at %g s does not come after key %d at %g s", k, c->keys[2 * k], k - 1,
                           c->keys[2 * k - 2]);
    }
    for (int t = 0; t < 3 * c->nf; t++)
        if (c->tris[t] < 0 || c->tris[t] >= nv)
            return rk_fail(err, "face %d: vertex %d out of range (the mesh has %d)", t / 3, c->tris[t], nv);
    /* Closed and consistently oriented: the directed edges a->b (fw) and their reverses b->a (bw)
     * are the same set, each once. */
    size_t n = 3 * (size_t)c->nf;
    long long *fw = rk_calloc(n, sizeof *fw, err), *bw = rk_calloc(n, sizeof *bw, err);
    if (!fw || !bw) {
        free(fw);
        free(bw);
        return -1;
    }
    for (size_t t = 0; t < (size_t)c->nf; t++)
        for (int k = 0; k < 3; k++) {
            long long a = c->tris[3 * t + k], b = c->tris[3 * t + (k + 1) % 3];
            fw[3 * t + k] = a * nv + b;
            bw[3 * t + k] = b * nv + a;
        }
    qsort(fw, n, sizeof *fw, edge_cmp);
    qsort(bw, n, sizeof *bw, edge_cmp);
    int rc = 0;
    for (size_t i = 0; i < n && !rc; i++) {
        if (i + 1 < n && fw[i] == fw[i + 1])
            rc = rk_fail(err, "edge %lld-%lld is used twice in the same direction: the faces are not one "
                         "consistently oriented surface", fw[i] / nv, fw[i] % nv);
        else if (fw[i] != bw[i]) {
            long long d = fw[i] < bw[i] ? fw[i] : bw[i];
            rc = rk_fail(err, "edge %lld-%lld has a face on one side only: the faces are not a closed surface "
                         "(a chamber is the whole boundary of a void)", d / nv, d % nv);
        }
    }
    free(fw);
    free(bw);
    return rc;
}
