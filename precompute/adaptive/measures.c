/* The oracle's error and progress measures (adaptive-subspace paper, Sec. 3.3-3.5): the per-vertex
 * scales and the nodal and modal forms. */
#include "adaptive/adaptive.h"

#include <math.h>
#include <string.h>

/* The 2-norm of the energy density's Hessian d2W/dF2 at F = I. Every romkit model has the linear
 * tangent there, C = mu (I + T) + lambda vec(I) vec(I)^T (T: the transposition), whose eigenvalues
 * are 2 mu (symmetric deviatoric), 0 (skew) and 2 mu + 3 lambda (dilation). */
static double rest_hessian_norm(double mu, double lambda)
{
    return fmax(2 * mu, fabs(2 * mu + 3 * lambda));
}

static double triangle_area(const double *a, const double *b, const double *c)
{
    double u[3], v[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
    }
    double n0 = u[1] * v[2] - u[2] * v[1], n1 = u[2] * v[0] - u[0] * v[2], n2 = u[0] * v[1] - u[1] * v[0];
    return 0.5 * sqrt(n0 * n0 + n1 * n1 + n2 * n2);
}

void rk_adaptive_vertex_scales(const rk_fem *f, double *psi_bar, double *area, double *volume)
{
    memset(psi_bar, 0, sizeof(double) * (size_t)f->nv);
    memset(area, 0, sizeof(double) * (size_t)f->nv);
    memset(volume, 0, sizeof(double) * (size_t)f->nv);
    /* psi_bar: a plain average over the vertex's elements; the count kept in area until the end */
    for (int t = 0; t < f->nt; t++) {
        const int *v = &f->tets[4 * t];
        double psi = rest_hessian_norm(f->mu[t], f->lambda[t]);
        for (int k = 0; k < 4; k++) {
            psi_bar[v[k]] += psi;
            area[v[k]] += 1;
        }
    }
    for (int i = 0; i < f->nv; i++) {
        if (area[i] > 0) psi_bar[i] /= area[i];
        area[i] = 0;
    }
    for (int t = 0; t < f->nt; t++) {
        const int *v = &f->tets[4 * t];
        for (int k = 0; k < 4; k++) {
            /* the face opposite vertex k: the other three */
            const double *p[3];
            for (int j = 0, m = 0; j < 4; j++)
                if (j != k) p[m++] = &f->X[3 * v[j]];
            area[v[k]] += triangle_area(p[0], p[1], p[2]);
            volume[v[k]] += 0.25 * f->vol[t];
        }
    }
}

void rk_adaptive_nodal_error(int nv, const double *g, const double *area, const double *psi_bar, double alpha,
                             double *G)
{
    for (int i = 0; i < nv; i++) {
        double s = area[i] * psi_bar[i];
        double n = sqrt(g[3 * i] * g[3 * i] + g[3 * i + 1] * g[3 * i + 1] + g[3 * i + 2] * g[3 * i + 2]);
        G[i] = s > 0 ? alpha * n / s : 0;
    }
}

double rk_adaptive_modal_error(int nv, const double *Um, int k, const double *g, const double *area,
                               const double *psi_bar, double alpha, double *work)
{
    int n = 3 * nv;
    memset(work, 0, sizeof(double) * (size_t)n);
    for (int j = 0; j < k; j++) { /* Eq. 16: the gradient projected on each column of the block */
        const double *u = Um + (size_t)j * n;
        double uu = 0, ug = 0;
        for (int i = 0; i < n; i++) {
            uu += u[i] * u[i];
            ug += u[i] * g[i];
        }
        if (uu <= 0) continue;
        double c = ug / uu;
        for (int i = 0; i < n; i++) work[i] += c * u[i];
    }
    double G = 0; /* Eq. 14: the largest scaled vertex norm */
    for (int i = 0; i < nv; i++) {
        double s = area[i] * psi_bar[i];
        if (!(s > 0)) continue;
        const double *w = &work[3 * i];
        G = fmax(G, alpha * sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) / s);
    }
    return G;
}

double rk_adaptive_modal_progress(int nv, const double *Um, int k, const double *dE, const double *volume,
                                  const double *psi_bar, double alpha)
{
    int n = 3 * nv;
    double E = 0;
    for (int j = 0; j < k; j++) { /* Eq. 17: dE projected on each column's per-vertex average */
        const double *u = Um + (size_t)j * n;
        double bb = 0, bdE = 0;
        for (int i = 0; i < nv; i++) {
            double b = (u[3 * i] + u[3 * i + 1] + u[3 * i + 2]) / 3;
            bb += b * b;
            bdE += b * dE[i];
        }
        if (bb <= 0) continue;
        double c = bdE / bb;
        for (int i = 0; i < nv; i++) { /* Eq. 15: summed over the vertices, each scaled by c_i */
            double s = volume[i] * psi_bar[i];
            if (s > 0) E += alpha * c * (u[3 * i] + u[3 * i + 1] + u[3 * i + 2]) / 3 / s;
        }
    }
    return E;
}

void rk_adaptive_tolerance_scale(const rk_fem *f, double h, double tol, double *s, double *p)
{
    for (int i = 0; i < f->nv; i++) {
        s[i] = f->vertex_mass[i] * tol / h;
        p[i] = 0.5 * f->vertex_mass[i] * tol * tol;
    }
}

double rk_adaptive_own_tolerance(double accuracy, double diagonal, double h, int steps, double newton_tol)
{
    if (!(accuracy > 0) || steps < 1 || !(h > 0)) return newton_tol;
    double n = steps;
    return fmax(newton_tol, 2 * accuracy * diagonal / (h * n * (n + 1)));
}
