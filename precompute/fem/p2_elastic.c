/* Quadratic (P2, 10-node) tets for a nonlinear, dynamic full-order reference: the element's elastic
 * energy, gradient and Hessian for any material model of physics/, and its exact consistent mass
 * (issue 37: Table 1's bend and twist need a reference converged past what P1 runs here).
 *
 * Shape functions as p2.c: vertex a, N_a = L_a (2 L_a - 1); edge (a, b), N_ab = 4 L_a L_b. The
 * elastic energy sum_q w_q Psi(F(X_q)) uses p2.c's 4-point rule of degree 2, the rule P2 stiffness
 * is integrated with (exact for linear elasticity, and the quadrature error of a smooth Psi is of the
 * order of P2's own discretization error). The mass integrates products of two quadratics (degree 4),
 * which no 4-point rule does: it is integrated exactly from the monomial formula
 *   int_T L0^a L1^b L2^c L3^d dV = 6 V a! b! c! d! / (a + b + c + d + 3)!. */
#include "fem/fem.h"

#include <math.h>
#include <string.h>

#include "fem/p2_impl.h"

/* A shape function as a sum of at most two monomials in (L0, L1, L2, L3). */
typedef struct {
    int terms;
    double coef[2];
    int pow[2][4];
} p2_poly;

static p2_poly shape_poly(int i)
{
    p2_poly p;
    memset(&p, 0, sizeof p);
    if (i < 4) { /* 2 L_a^2 - L_a */
        p.terms = 2;
        p.coef[0] = 2;
        p.pow[0][i] = 2;
        p.coef[1] = -1;
        p.pow[1][i] = 1;
    } else { /* 4 L_a L_b */
        p.terms = 1;
        p.coef[0] = 4;
        p.pow[0][RK_P2_EDGE[i - 4][0]] = 1;
        p.pow[0][RK_P2_EDGE[i - 4][1]] = 1;
    }
    return p;
}

static double factorial(int n)
{
    double f = 1;
    for (int k = 2; k <= n; k++) f *= k;
    return f;
}

void rk_p2_mass_element(double vol, double density, double Me[100])
{
    for (int i = 0; i < 10; i++)
        for (int j = 0; j < 10; j++) {
            p2_poly a = shape_poly(i), b = shape_poly(j);
            double sum = 0;
            for (int s = 0; s < a.terms; s++)
                for (int t = 0; t < b.terms; t++) {
                    double num = 1;
                    int total = 0;
                    for (int k = 0; k < 4; k++) {
                        int e = a.pow[s][k] + b.pow[t][k];
                        num *= factorial(e);
                        total += e;
                    }
                    sum += a.coef[s] * b.coef[t] * 6 * num / factorial(total + 3);
                }
            Me[10 * i + j] = density * vol * sum;
        }
}

void rk_p2_barycentric_gradients(const double Dm_inv[9], double dL[12])
{
    /* dL_k / dX_c for k = 1..3 is row k-1 of Dm^-1; dL_0 = -(their sum) */
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++) dL[3 * (k + 1) + c] = Dm_inv[3 * k + c];
    for (int c = 0; c < 3; c++) dL[c] = -(dL[3 + c] + dL[6 + c] + dL[9 + c]);
}

double rk_p2_element_elastic(rk_material_model model, double mu, double lambda, const double dL[12], double vol,
                             const double u[30], double g[30], double H[900], int project)
{
    double energy = 0;
    if (g) memset(g, 0, 30 * sizeof(double));
    if (H) memset(H, 0, 900 * sizeof(double));
    for (int q = 0; q < 4; q++) {
        double L[4], dN[30], w = vol / 4;
        rk_p2_quadrature_point(q, L);
        rk_p2_shape_gradients(L, dL, dN);
        /* the displacement gradient Hd = F - I = sum_a u_a dN_a^T (keeps small strains exact) */
        double Hd[9] = {0};
        for (int a = 0; a < 10; a++)
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) Hd[3 * i + j] += u[3 * a + i] * dN[3 * a + j];
        energy += w * rk_psi_h(model, mu, lambda, Hd);
        if (g) {
            double P[9];
            rk_pk1_h(model, mu, lambda, Hd, P);
            for (int a = 0; a < 10; a++)
                for (int i = 0; i < 3; i++)
                    g[3 * a + i] += w * (P[3 * i] * dN[3 * a] + P[3 * i + 1] * dN[3 * a + 1] + P[3 * i + 2] * dN[3 * a + 2]);
        }
        if (H) {
            double F[9], D[81];
            for (int k = 0; k < 9; k++) F[k] = Hd[k] + (k % 4 == 0);
            rk_dpdf(model, mu, lambda, F, D, project);
            /* H_(a i),(b k) = w sum_jl D[(i j),(k l)] dN_a,j dN_b,l: first DB = D (row ij) times dN_b */
            for (int b = 0; b < 10; b++) {
                const double *nb = &dN[3 * b];
                double DB[27]; /* DB[(3i + j) * 3 + k] = sum_l D[(ij),(kl)] dN_b,l */
                for (int ij = 0; ij < 9; ij++)
                    for (int k = 0; k < 3; k++)
                        DB[3 * ij + k] = D[9 * ij + 3 * k] * nb[0] + D[9 * ij + 3 * k + 1] * nb[1] +
                                         D[9 * ij + 3 * k + 2] * nb[2];
                for (int a = 0; a < 10; a++) {
                    const double *na = &dN[3 * a];
                    for (int i = 0; i < 3; i++)
                        for (int k = 0; k < 3; k++)
                            H[30 * (3 * a + i) + 3 * b + k] +=
                                w * (na[0] * DB[3 * (3 * i) + k] + na[1] * DB[3 * (3 * i + 1) + k] +
                                     na[2] * DB[3 * (3 * i + 2) + k]);
                }
            }
        }
    }
    return energy;
}
