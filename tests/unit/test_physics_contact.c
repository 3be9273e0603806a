/* physics/contact_impl.h in both precisions: the rk_ double copy the precompute links and a float
 * copy instantiated here (prefix rkf_, as the runtime's romrt_phys_ one is built). Gradients and
 * Hessians of the distances, the mollifier, one pair's barrier and friction's slip against
 * central differences in double and in float, in every case (point-point, point-edge,
 * point-plane, line-line, mollified edge-edge); float against double; the projection on the
 * unknowns; friction's normal force against the barrier's gradient; and CCD's time of impact
 * against brute-force sampling of the motion (no sample before it comes closer than the bound). */
#include "physics/physics.h"
#include "testlib.h"
#include "util/util.h"

#define PHYS_REAL float
#define PHYS_FLOAT 1
#define PHYS_FN(name) rkf_##name
#include "physics/physics_impl.h"
#undef PHYS_REAL
#undef PHYS_FLOAT
#undef PHYS_FN

static uint64_t seed = 7;
static double rnd(void) { return 2 * rk_uniform(&seed) - 1; }

/* One precision behind double arrays: positions are rounded to it before every call. */
typedef struct {
    const char *name;
    double h;                                   /* central-difference step (stencils of size ~1) */
    double (*round)(double);
    rk_distance_case (*pt_case)(const double *const x[4]);
    rk_distance_case (*ee_case)(const double *const x[4]);
    double (*dist2)(rk_distance_case c, const double *const x[4], double *g, double *H);
    double (*moll)(const double *const x[4], double eps, double *g, double *H);
    double (*barrier)(int ee, const double *const x[4], double xi, double dhat, double eps, double *g, double *H,
                      double *dist);
    double (*slip)(const double T[6], const double rel[3], double eps, double scale, double g[3], double B[9]);
    int (*ccd)(int ee, const double *const x[4], const double *const dx[4], double xi, double tmax, double *toi);
} precision;

static double round_double(double v) { return v; }
static double round_float(double v) { return (float)v; }

/* Float wrappers: arguments to float, results back. */
static void to_float(const double *const x[4], float xf[4][3], const float *xp[4])
{
    for (int k = 0; k < 4; k++) {
        for (int a = 0; a < 3; a++) xf[k][a] = (float)x[k][a];
        xp[k] = xf[k];
    }
}
static void back(const float *f, double *d, int n)
{
    for (int i = 0; i < n && d; i++) d[i] = f[i];
}
static rk_distance_case f_pt_case(const double *const x[4])
{
    float xf[4][3];
    const float *xp[4];
    to_float(x, xf, xp);
    return rkf_point_triangle_case(xp);
}
static rk_distance_case f_ee_case(const double *const x[4])
{
    float xf[4][3];
    const float *xp[4];
    to_float(x, xf, xp);
    return rkf_edge_edge_case(xp);
}
static double f_dist2(rk_distance_case c, const double *const x[4], double *g, double *H)
{
    float xf[4][3], gf[12], Hf[144];
    const float *xp[4];
    to_float(x, xf, xp);
    double v = rkf_contact_distance2(c, xp, g ? gf : NULL, H ? Hf : NULL);
    back(gf, g, 12), back(Hf, H, 144);
    return v;
}
static double f_moll(const double *const x[4], double eps, double *g, double *H)
{
    float xf[4][3], gf[12], Hf[144];
    const float *xp[4];
    to_float(x, xf, xp);
    double v = rkf_edge_edge_mollifier(xp, (float)eps, g ? gf : NULL, H ? Hf : NULL);
    back(gf, g, 12), back(Hf, H, 144);
    return v;
}
static double f_barrier(int ee, const double *const x[4], double xi, double dhat, double eps, double *g, double *H,
                        double *dist)
{
    float xf[4][3], gf[12], Hf[144], df;
    const float *xp[4];
    to_float(x, xf, xp);
    double v = rkf_pair_barrier(ee, xp, (float)xi, (float)dhat, (float)eps, g ? gf : NULL, H ? Hf : NULL, &df);
    back(gf, g, 12), back(Hf, H, 144);
    if (dist) *dist = df;
    return v;
}
static double f_slip(const double T[6], const double rel[3], double eps, double scale, double g[3], double B[9])
{
    float Tf[6], rf[3], gf[3], Bf[9];
    for (int i = 0; i < 6; i++) Tf[i] = (float)T[i];
    for (int i = 0; i < 3; i++) rf[i] = (float)rel[i];
    double v = rkf_friction_slip(Tf, rf, (float)eps, (float)scale, g ? gf : NULL, B ? Bf : NULL);
    back(gf, g, 3), back(Bf, B, 9);
    return v;
}
static int f_ccd(int ee, const double *const x[4], const double *const dx[4], double xi, double tmax, double *toi)
{
    float xf[4][3], df[4][3], t;
    const float *xp[4], *dp[4];
    to_float(x, xf, xp);
    to_float(dx, df, dp);
    int hit = rkf_ccd_stencil(ee, xp, dp, (float)xi, (float)tmax, &t);
    *toi = t;
    return hit;
}

static const precision precisions[2] = {
    {"double", 1e-6, round_double, rk_point_triangle_case, rk_edge_edge_case, rk_contact_distance2,
     rk_edge_edge_mollifier, rk_pair_barrier, rk_friction_slip, rk_ccd_stencil},
    {"float", 1.0 / 256, round_float, f_pt_case, f_ee_case, f_dist2, f_moll, f_barrier, f_slip, f_ccd},
};

/* A random stencil in [-1, 1]^3, rounded to the precision. */
static void random_stencil(const precision *p, double P[4][3])
{
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 3; a++) P[k][a] = p->round(rnd());
}

/* What is differentiated: 0 the squared distance of a fixed case, 1 the mollifier (eps 1e-3 |ea|^2
 * |eb|^2 at the stencil), 2 one pair's barrier (edge_edge ee, thickness xi, dhat, and the
 * mollifier when ee). */
typedef struct {
    int what, ee;
    rk_distance_case c;
    double eps, xi, dhat;
} target;

static double eval(const precision *p, const target *t, const double *const x[4], double *g, double *H)
{
    if (t->what == 0) return p->dist2(t->c, x, g, H);
    if (t->what == 1) return p->moll(x, t->eps, g, H);
    return p->barrier(t->ee, x, t->xi, t->dhat, t->eps, g, H, NULL);
}

static int same_case(rk_distance_case a, rk_distance_case b)
{
    return a.kind == b.kind && a.v[0] == b.v[0] && a.v[1] == b.v[1] && a.v[2] == b.v[2] && a.v[3] == b.v[3];
}

/* The worst central-difference error of the gradient (from values) and of the Hessian (from
 * gradients), relative to the largest entry of each; -1 when the stencil's case changes within
 * a step (the function is only piecewise smooth there). */
static double fd_error(const precision *p, const target *t, double P[4][3], double h)
{
    const double *x[4] = {P[0], P[1], P[2], P[3]};
    double g[12], H[144], gmax = 0, Hmax = 0, worst = 0;
    rk_distance_case c0 = t->ee ? p->ee_case(x) : p->pt_case(x);
    eval(p, t, x, g, H);
    for (int i = 0; i < 12; i++) gmax = fmax(gmax, fabs(g[i]));
    for (int i = 0; i < 144; i++) Hmax = fmax(Hmax, fabs(H[i]));
    for (int k = 0; k < 12; k++) {
        double *coord = &P[k / 3][k % 3], keep = *coord, gp[12], gm[12];
        double xp = p->round(keep + h), xm = p->round(keep - h);
        *coord = xp;
        double vp = eval(p, t, x, gp, NULL);
        int switched = !same_case(c0, t->ee ? p->ee_case(x) : p->pt_case(x));
        *coord = xm;
        double vm = eval(p, t, x, gm, NULL);
        switched |= !same_case(c0, t->ee ? p->ee_case(x) : p->pt_case(x));
        *coord = keep;
        if (switched && t->what != 0) return -1;
        if (!isfinite(vp) || !isfinite(vm)) return -1;
        worst = fmax(worst, fabs((vp - vm) / (xp - xm) - g[k]) / (gmax + 1e-30));
        for (int j = 0; j < 12; j++) worst = fmax(worst, fabs((gp[j] - gm[j]) / (xp - xm) - H[12 * j + k]) / (Hmax + 1e-30));
    }
    return worst;
}

/* Two nearly parallel edges (angle ~0.02 rad), a distance ~0.1 apart: the mollifier is active. */
static void parallel_edges(const precision *p, double P[4][3])
{
    double dir[3] = {rnd(), rnd(), rnd()}, off[3] = {rnd(), rnd(), rnd()}, tilt[3] = {rnd(), rnd(), rnd()};
    for (int a = 0; a < 3; a++) {
        P[0][a] = p->round(-0.5 * dir[a]);
        P[1][a] = p->round(0.5 * dir[a]);
        P[2][a] = p->round(0.1 * off[a] - 0.4 * dir[a] - 0.01 * tilt[a]);
        P[3][a] = p->round(0.1 * off[a] + 0.6 * dir[a] + 0.01 * tilt[a]);
    }
}

static double mollifier_eps(double P[4][3])
{
    double ea = 0, eb = 0;
    for (int a = 0; a < 3; a++) {
        ea += (P[1][a] - P[0][a]) * (P[1][a] - P[0][a]);
        eb += (P[3][a] - P[2][a]) * (P[3][a] - P[2][a]);
    }
    return 1e-3 * ea * eb;
}

/* Worst differences in each of the distance cases, the mollifier and the barrier (point-triangle,
 * edge-edge, mollified edge-edge), over random stencils of precision p. */
static void derivative_errors(const precision *p, double worst[7], int tried[7])
{
    for (int i = 0; i < 7; i++) worst[i] = 0, tried[i] = 0;
    for (int n = 0; n < 600; n++) {
        double P[4][3];
        target t = {0};
        random_stencil(p, P);
        const double *x[4] = {P[0], P[1], P[2], P[3]};
        t.ee = n % 2;
        t.c = t.ee ? p->ee_case(x) : p->pt_case(x);
        double e = fd_error(p, &t, P, p->h);
        if (e >= 0) worst[t.c.kind] = fmax(worst[t.c.kind], e), tried[t.c.kind]++;
        /* the barrier: dhat 0.5 reaches most random stencils; every other one with a thickness; the
         * step a fraction of the gap (across which the log varies) and of what is left to the reach
         * (where the barrier and its first two derivatives fall to 0) */
        t.what = 2, t.xi = n % 4 < 2 ? 0 : 0.05, t.dhat = 0.5, t.eps = 0;
        double d2 = p->dist2(t.c, x, NULL, NULL), gap = sqrt(d2) - t.xi;
        if (gap > 0 && gap < t.dhat && (e = fd_error(p, &t, P, fmin(p->h, 0.05 * fmin(gap, t.dhat - gap)))) >= 0)
            worst[4 + t.ee] = fmax(worst[4 + t.ee], e), tried[4 + t.ee]++;
    }
    for (int n = 0; n < 100; n++) { /* nearly parallel edges: the mollifier, alone and in the barrier */
        double P[4][3];
        parallel_edges(p, P);
        target t = {1, 1, {RK_DIST_LINE_LINE, {0, 1, 2, 3}}, mollifier_eps(P), 0, 0};
        const double *x[4] = {P[0], P[1], P[2], P[3]};
        /* m'' jumps at x = eps (m is C1 there): stencils well inside, steps that stay there (|ea x
         * eb| < sqrt(eps) moves by about h per step); the barrier's steps as above */
        if (!(p->moll(x, t.eps, NULL, NULL) < 0.9)) continue;
        double h = fmin(p->h, 0.02 * sqrt(t.eps)), e = fd_error(p, &t, P, h);
        if (e < 0) continue;
        t.what = 2, t.dhat = 0.5;
        double gap = sqrt(p->dist2(p->ee_case(x), x, NULL, NULL));
        if (!(gap < t.dhat)) continue;
        double eb = fd_error(p, &t, P, fmin(h, 0.05 * fmin(gap, t.dhat - gap)));
        if (eb < 0) continue;
        worst[6] = fmax(worst[6], fmax(e, eb)), tried[6]++;
    }
}

static const char *const part_names[7] = {"point-point", "point-edge", "point-plane", "line-line",
                                          "barrier point-triangle", "barrier edge-edge",
                                          "mollified edge-edge"};

TEST(double_derivatives_match_finite_differences_in_every_case)
{
    double worst[7];
    int tried[7];
    derivative_errors(&precisions[0], worst, tried);
    printf("# double, worst central-difference error (relative to the largest entry):");
    for (int i = 0; i < 7; i++) printf(" %s %.1e (%d)", part_names[i], worst[i], tried[i]);
    printf("\n");
    for (int i = 0; i < 7; i++) CHECK(tried[i] >= 5 && worst[i] < 1e-6, "%s: %d tried, worst %g", part_names[i], tried[i], worst[i]);
}

TEST(float_derivatives_match_finite_differences_in_every_case)
{
    double worst[7];
    int tried[7];
    derivative_errors(&precisions[1], worst, tried);
    printf("# float (step 1/256), worst central-difference error:");
    for (int i = 0; i < 7; i++) printf(" %s %.1e (%d)", part_names[i], worst[i], tried[i]);
    printf("\n");
    for (int i = 0; i < 7; i++) CHECK(tried[i] >= 5 && worst[i] < 1e-2, "%s: %d tried, worst %g", part_names[i], tried[i], worst[i]);
}

/* |a - b| over the largest |b|, entrywise over n. */
static double rel_diff(const double *a, const double *b, int n)
{
    double m = 0, d = 0;
    for (int i = 0; i < n; i++) m = fmax(m, fabs(b[i])), d = fmax(d, fabs(a[i] - b[i]));
    return d / (m + 1e-30);
}

TEST(float_agrees_with_double)
{
    const precision *f = &precisions[1], *d = &precisions[0];
    double worst_d = 0, worst_b = 0, worst_w = 0;
    int cases = 0, mismatched = 0;
    for (int n = 0; n < 2000; n++) {
        double P[4][3];
        random_stencil(f, P); /* float-representable: both see the same points */
        const double *x[4] = {P[0], P[1], P[2], P[3]};
        int ee = n % 2;
        rk_distance_case cd = ee ? d->ee_case(x) : d->pt_case(x), cf = ee ? f->ee_case(x) : f->pt_case(x);
        cases++;
        if (!same_case(cd, cf)) { /* on a boundary between cases: both pieces agree there */
            mismatched++;
            continue;
        }
        double gd[12], Hd[144], gf[12], Hf[144], wd[4], wf[4];
        double vd = d->dist2(cd, x, gd, Hd), vf = f->dist2(cf, x, gf, Hf);
        worst_d = fmax(worst_d, fmax(fabs(vf - vd) / vd, fmax(rel_diff(gf, gd, 12), rel_diff(Hf, Hd, 144))));
        vd = d->barrier(ee, x, 0.02, 0.5, 0, gd, Hd, NULL), vf = f->barrier(ee, x, 0.02, 0.5, 0, gf, Hf, NULL);
        if (vd > 0 && isfinite(vd))
            worst_b = fmax(worst_b, fmax(fabs(vf - vd) / vd, fmax(rel_diff(gf, gd, 12), rel_diff(Hf, Hd, 144))));
        float xf[4][3];
        const float *xp[4];
        float wff[4];
        to_float(x, xf, xp);
        rk_contact_closest_weights(cd, x, wd);
        rkf_contact_closest_weights(cf, xp, wff);
        back(wff, wf, 4);
        worst_w = fmax(worst_w, rel_diff(wf, wd, 4));
    }
    printf("# float against double over %d stencils (%d on a case boundary): distance %.1e, barrier %.1e, weights %.1e\n",
           cases, mismatched, worst_d, worst_b, worst_w);
    CHECK(mismatched < cases / 100, "%d of %d stencils change case in float", mismatched, cases);
    CHECK(worst_d < 1e-4, "distances differ by %g", worst_d);
    CHECK(worst_b < 1e-3, "barriers differ by %g", worst_b);
    CHECK(worst_w < 1e-4, "closest-point weights differ by %g", worst_w);
}

TEST(the_barrier_has_its_reach_and_blows_up_on_contact)
{
    for (int i = 0; i < 2; i++) {
        const precision *p = &precisions[i];
        double P[4][3] = {{0.2, 0.2, 0.31}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, g[12], H[144], dist;
        const double *x[4] = {P[0], P[1], P[2], P[3]};
        double e = p->barrier(0, x, 0.1, 0.2, 0, g, H, &dist); /* d - xi = 0.21 > dhat */
        int zero = 1;
        for (int k = 0; k < 12; k++) zero &= g[k] == 0;
        for (int k = 0; k < 144; k++) zero &= H[k] == 0;
        CHECK(e == 0 && zero && fabs(dist - 0.21) < 1e-6, "%s: beyond the reach: %g, dist %g", p->name, e, dist);
        P[0][2] = 0.25;
        e = p->barrier(0, x, 0.1, 0.2, 0, g, H, &dist);
        CHECK(e > 0 && isfinite(e) && g[2] < 0, "%s: inside the reach: %g, push %g", p->name, e, g[2]);
        P[0][2] = 0.1;
        e = p->barrier(0, x, 0.1, 0.2, 0, NULL, NULL, &dist);
        CHECK(e == INFINITY && fabs(dist) < 1e-6, "%s: touching the thickness: %g", p->name, e);
    }
}

TEST(the_projection_keeps_the_unknowns_and_is_psd)
{
    int tried = 0;
    for (int n = 0; n < 200; n++) {
        double P[4][3], H[144], B[144], w[12], V[144];
        random_stencil(&precisions[0], P);
        const double *x[4] = {P[0], P[1], P[2], P[3]};
        if (!(rk_pair_barrier(n % 2, x, 0, 0.5, 0, NULL, H, NULL) > 0)) continue;
        rk_pair_barrier(n % 2, x, 0, 0.5, 0, NULL, H, NULL);
        int dof[4] = {1, n % 3 != 0, 1, n % 5 != 0};
        memcpy(B, H, sizeof B);
        rk_pair_project(dof, B);
        tried++;
        for (int k = 0; k < 4; k++)
            for (int i = 0; i < 3 && !dof[k]; i++)
                for (int j = 0; j < 12; j++)
                    CHECK(B[12 * (3 * k + i) + j] == 0 && B[12 * j + 3 * k + i] == 0, "point %d is no unknown", k);
        double top = 0;
        rk_sym_eig(12, B, w, V);
        for (int i = 0; i < 12; i++) top = fmax(top, fabs(w[i]));
        for (int i = 0; i < 12; i++) CHECK(w[i] > -1e-9 * top, "eigenvalue %g of %g", w[i], top);
        /* on the unknowns it only removed H's negative part: H - B is negative semidefinite there */
        for (int i = 0; i < 144; i++) {
            int r = i / 12 / 3, c = i % 12 / 3;
            B[i] = dof[r] && dof[c] ? H[i] - B[i] : 0;
        }
        rk_sym_eig(12, B, w, V);
        for (int i = 0; i < 12; i++) CHECK(w[i] < 1e-9 * top, "H - projection has eigenvalue %g", w[i]);
    }
    CHECK(tried > 50, "only %d stencils within reach", tried);
}

TEST(friction_normal_force_is_the_barrier_gradient)
{
    int tried = 0;
    for (int n = 0; n < 400; n++) {
        double P[4][3], g[12], w[4], T[6], kappa = 3;
        random_stencil(&precisions[0], P);
        const double *x[4] = {P[0], P[1], P[2], P[3]};
        int ee = n % 2;
        double lambda = rk_pair_friction_lag(ee, x, 0.01, 0.5, 0, kappa, w, T);
        double e = rk_pair_barrier(ee, x, 0.01, 0.5, 0, g, NULL, NULL);
        if (!(e > 0 && isfinite(e))) {
            CHECK(lambda == 0, "a force %g out of reach", lambda);
            continue;
        }
        tried++;
        /* moving the first feature (the point, or edge a) rigidly by v changes d by n . v: the sum of
         * its points' gradients is dE/dd n */
        double f[3] = {0, 0, 0}, nrm[3] = {0, 0, 0};
        for (int a = 0; a < 3; a++) {
            for (int k = 0; k < (ee ? 2 : 1); k++) f[a] += g[3 * k + a];
            for (int k = 0; k < 4; k++) nrm[a] += w[k] * x[k][a];
        }
        double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        CHECK(fabs(lambda - kappa * fl) <= 1e-9 * lambda, "normal force %.12g, barrier gradient %.12g", lambda, kappa * fl);
        for (int r = 0; r < 2; r++) {
            double tn = T[3 * r] * nrm[0] + T[3 * r + 1] * nrm[1] + T[3 * r + 2] * nrm[2];
            CHECK(fabs(tn) < 1e-12 * (1 + sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2])),
                  "tangent row %d is not orthogonal to the normal", r);
        }
    }
    CHECK(tried > 50, "only %d stencils within reach", tried);
}

/* |T rel| with rel[a] replaced by v. */
static double slip_norm(const double T[6], const double rel[3], int a, double v)
{
    double r[3] = {rel[0], rel[1], rel[2]}, u0, u1;
    r[a] = v;
    u0 = T[0] * r[0] + T[1] * r[1] + T[2] * r[2], u1 = T[3] * r[0] + T[4] * r[1] + T[5] * r[2];
    return sqrt(u0 * u0 + u1 * u1);
}

TEST(friction_slip_matches_finite_differences)
{
    for (int i = 0; i < 2; i++) {
        const precision *p = &precisions[i];
        double worst = 0, eps = 0.1, h = i ? 1e-3 : 1e-7;
        for (int n = 0; n < 200; n++) {
            double nrm[3] = {rnd(), rnd(), rnd()}, T[6], rel[3], g[3], B[9], l;
            l = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
            for (int a = 0; a < 3; a++) nrm[a] /= l;
            rk_tangent_basis(nrm, T);
            double size = n % 2 ? 0.05 : 0.3; /* static (|u| < eps) and sliding */
            for (int a = 0; a < 3; a++) rel[a] = p->round(size * rnd());
            p->slip(T, rel, eps, 2, g, B);
            double gmax = fmax(fabs(g[0]), fmax(fabs(g[1]), fabs(g[2]))), Bmax = 0;
            for (int k = 0; k < 9; k++) Bmax = fmax(Bmax, fabs(B[k]));
            for (int a = 0; a < 3; a++) {
                double keep = rel[a], rp = p->round(keep + h), rm = p->round(keep - h), gp[3], gm[3];
                rel[a] = rp;
                double ep = p->slip(T, rel, eps, 2, gp, NULL);
                rel[a] = rm;
                double em = p->slip(T, rel, eps, 2, gm, NULL);
                rel[a] = keep;
                /* f0 is C1 and M jumps at |u| = eps: skip steps that straddle it */
                if ((slip_norm(T, rel, a, rp) < eps) != (slip_norm(T, rel, a, rm) < eps)) continue;
                worst = fmax(worst, fabs((ep - em) / (rp - rm) - g[a]) / gmax);
                for (int b = 0; b < 3; b++) worst = fmax(worst, fabs((gp[b] - gm[b]) / (rp - rm) - B[3 * b + a]) / Bmax);
            }
        }
        printf("# friction slip, %s: worst central-difference error %.1e\n", p->name, worst);
        CHECK(worst < (i ? 2e-2 : 1e-5), "%s: %g", p->name, worst);
    }
}

/* The stencil's distance at x + t dx, in double (test_contact_distance holds it to an independent
 * closest-point construction). */
static double distance_at(int ee, double P[4][3], double D[4][3], double t)
{
    double Y[4][3];
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 3; a++) Y[k][a] = P[k][a] + t * D[k][a];
    const double *y[4] = {Y[0], Y[1], Y[2], Y[3]};
    rk_distance_case c = ee ? rk_edge_edge_case(y) : rk_point_triangle_case(y);
    return sqrt(rk_contact_distance2(c, y, NULL, NULL));
}

TEST(ccd_never_reports_an_impact_after_the_motion_came_close)
{
    for (int i = 0; i < 2; i++) {
        const precision *p = &precisions[i];
        int hits = 0, collide = 0, samples = 400;
        double ratio = 0, closest = INFINITY;
        for (int n = 0; n < 600; n++) {
            double P[4][3], D[4][3], toi;
            int ee = n % 2;
            random_stencil(p, P);
            for (int k = 0; k < 4; k++)
                for (int a = 0; a < 3; a++) D[k][a] = p->round(1.5 * rnd());
            if (n % 4 >= 2) /* aimed: the point, or edge a, driven through the other feature's middle */
                for (int a = 0; a < 3; a++) {
                    double to = ee ? (P[2][a] + P[3][a]) / 2 : (P[1][a] + P[2][a] + P[3][a]) / 3;
                    double from = ee ? (P[0][a] + P[1][a]) / 2 : P[0][a];
                    for (int k = 0; k < (ee ? 2 : 1); k++) D[k][a] = p->round(2 * (to - from) + 0.1 * rnd());
                }
            double xi = n % 3 == 0 ? p->round(0.05) : 0;
            const double *x[4] = {P[0], P[1], P[2], P[3]}, *dx[4] = {D[0], D[1], D[2], D[3]};
            double gap0 = distance_at(ee, P, D, 0) - xi;
            if (!(gap0 > 1e-3)) continue;
            int hit = p->ccd(ee, x, dx, xi, 1, &toi);
            double end = hit ? toi : 1, first_touch = INFINITY;
            for (int s = 0; s <= samples; s++) { /* the whole motion: where it first comes within xi */
                double t = (double)s / samples;
                if (distance_at(ee, P, D, t) - xi <= 0) {
                    first_touch = t;
                    break;
                }
            }
            for (int s = 0; s <= samples; s++) { /* before the reported time: never closer than the bound */
                double t = end * s / samples, gap = distance_at(ee, P, D, t) - xi;
                closest = fmin(closest, gap / gap0);
                CHECK(gap >= 0.01 * gap0 * (1 - 1e-4), "%s stencil %d: gap %g of %g at t %g, toi %g (hit %d)", p->name, n,
                      gap, gap0, t, end, hit);
            }
            hits += hit;
            if (isfinite(first_touch)) {
                collide++;
                CHECK(hit && toi < first_touch, "%s stencil %d: touches at %g, CCD says %d %g", p->name, n, first_touch,
                      hit, toi);
                ratio += toi / first_touch;
            }
        }
        printf("# ccd, %s: %d impacts reported, %d motions that touch: toi on average %.2f of the first touch; the "
               "closest sampled gap before toi %.3f of the starting gap\n",
               p->name, hits, collide, ratio / collide, closest);
        CHECK(collide > 50 && ratio / collide > 0.3, "%s: %d touching, toi/touch %g", p->name, collide, ratio / collide);
    }
}

int main(void)
{
    RUN(double_derivatives_match_finite_differences_in_every_case);
    RUN(float_derivatives_match_finite_differences_in_every_case);
    RUN(float_agrees_with_double);
    RUN(the_barrier_has_its_reach_and_blows_up_on_contact);
    RUN(the_projection_keeps_the_unknowns_and_is_psd);
    RUN(friction_normal_force_is_the_barrier_gradient);
    RUN(friction_slip_matches_finite_differences);
    RUN(ccd_never_reports_an_impact_after_the_motion_came_close);
    return test_finish();
}
