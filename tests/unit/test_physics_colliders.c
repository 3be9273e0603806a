/* App colliders (physics/collider_impl.h): signed distances of planes, spheres, capsules and
 * boxes in random poses against independent formulas in world coordinates, their gradient (the
 * normal) against finite differences; the point step and the collider's motion step never let a
 * point inside or within 10% of its starting distance, checked by sampling the whole path; bad
 * colliders are named; friction's smoothing against finite differences. */
#include "testlib.h"
#include "physics/physics.h"
#include "util/util.h"

static uint64_t rng = 0x9e3779b97f4a7c15ULL;
static double urand(void) { return 2 * rk_uniform(&rng) - 1; }

/* A random rotation (Rodrigues about a random axis) into R (row-major). */
static void random_rotation(double *R)
{
    double axis[3] = {urand(), urand(), urand()}, zero[3] = {0, 0, 0}, shift[3];
    rk_motion(RK_MOTION_TWIST, axis, zero, 3.14159 * urand(), zero, 1.0, R, shift);
}

/* A random collider of the kind: pose in [-1, 1]^3, sizes 0.1 to 0.6 m. */
static void random_collider(int kind, double *c)
{
    for (int i = 0; i < 3; i++) c[i] = urand();
    random_rotation(c + 3);
    c[12] = 0.35 + 0.25 * urand();
    c[13] = 0.35 + 0.25 * urand();
    for (int i = 14; i < 17; i++) c[i] = 0.35 + 0.25 * urand();
    (void)kind;
}

/* R v + p, R^T (x - p). */
static void to_world(const double *c, const double *v, double *x)
{
    for (int i = 0; i < 3; i++) x[i] = c[i] + c[3 + 3 * i] * v[0] + c[4 + 3 * i] * v[1] + c[5 + 3 * i] * v[2];
}

static double point_segment(const double *x, const double *a, const double *b)
{
    double ab[3], t = 0, n = 0, d = 0;
    for (int k = 0; k < 3; k++) ab[k] = b[k] - a[k], t += ab[k] * (x[k] - a[k]), n += ab[k] * ab[k];
    t = fmax(0, fmin(1, t / n));
    for (int k = 0; k < 3; k++) d += (a[k] + t * ab[k] - x[k]) * (a[k] + t * ab[k] - x[k]);
    return sqrt(d);
}

/* The distance by other means, in world coordinates: plane and sphere directly, the capsule from
 * its world end points, the box from the six face planes (outside: the distance to the nearest
 * point found by clamping along the box's world axes; inside: the nearest face plane). */
static double reference_distance(int kind, const double *c, const double *x)
{
    double w[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
    if (kind == RK_COLLIDER_PLANE) {
        double nz[3] = {c[5], c[8], c[11]}; /* the local z axis: R's third column */
        return w[0] * nz[0] + w[1] * nz[1] + w[2] * nz[2];
    }
    if (kind == RK_COLLIDER_SPHERE) return sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) - c[12];
    if (kind == RK_COLLIDER_CAPSULE) {
        double ea[3] = {-c[13], 0, 0}, eb[3] = {c[13], 0, 0}, a[3], b[3];
        to_world(c, ea, a), to_world(c, eb, b);
        return point_segment(x, a, b) - c[12];
    }
    double q[3], outside2 = 0, inside = -INFINITY;
    for (int k = 0; k < 3; k++) { /* the box axis k is R's column k */
        double axis[3] = {c[3 + k], c[6 + k], c[9 + k]};
        q[k] = fabs(w[0] * axis[0] + w[1] * axis[1] + w[2] * axis[2]) - c[14 + k];
        outside2 += q[k] > 0 ? q[k] * q[k] : 0;
        inside = fmax(inside, q[k]);
    }
    return outside2 > 0 ? sqrt(outside2) : inside;
}

static const char *const kinds[4] = {"plane", "sphere", "capsule", "box"};

TEST(distances_match_world_formulas_and_their_gradients)
{
    for (int kind = 0; kind < 4; kind++) {
        double worst = 0, worst_n = 0, worst_closest = 0;
        for (int trial = 0; trial < 2000; trial++) {
            double c[RK_COLLIDER_REALS], x[3], n[3], cl[3], world[3];
            random_collider(kind, c);
            for (int i = 0; i < 3; i++) x[i] = c[i] + 1.5 * urand();
            double d = rk_collider_distance(kind, c, x, n, cl);
            worst = fmax(worst, fabs(d - reference_distance(kind, c, x)));
            /* n = grad d by central differences (away from the medial surfaces) */
            double fd[3], h = 1e-7, e = 0;
            for (int i = 0; i < 3; i++) {
                double xp[3] = {x[0], x[1], x[2]}, xm[3] = {x[0], x[1], x[2]};
                xp[i] += h, xm[i] -= h;
                fd[i] = (rk_collider_distance(kind, c, xp, NULL, NULL) - rk_collider_distance(kind, c, xm, NULL, NULL)) / (2 * h);
                e = fmax(e, fabs(fd[i] - n[i]));
            }
            if (e < 1e-3) worst_n = fmax(worst_n, e); /* a kink (inside a box, on a medial plane) */
            /* the closest point lies on the surface, |d| away from x */
            to_world(c, cl, world);
            double dist = sqrt((x[0] - world[0]) * (x[0] - world[0]) + (x[1] - world[1]) * (x[1] - world[1]) +
                               (x[2] - world[2]) * (x[2] - world[2]));
            worst_closest = fmax(worst_closest, fabs(dist - fabs(d)) + fabs(rk_collider_distance(kind, c, world, NULL, NULL)));
        }
        printf("# %-7s 2000 points: distance off by %.2g, normal vs finite differences %.2g, closest point %.2g\n",
               kinds[kind], worst, worst_n, worst_closest);
        CHECK(worst < 1e-12 && worst_n < 1e-6 && worst_closest < 1e-12, "%s: %g %g %g", kinds[kind], worst, worst_n,
              worst_closest);
    }
}

/* The least distance over n + 1 samples of the point's path x + t dx, t in [0, alpha]. */
static double least_on_path(int kind, const double *c, const double *x, const double *dx, double alpha, int n)
{
    double least = INFINITY;
    for (int k = 0; k <= n; k++) {
        double t = alpha * k / n, y[3] = {x[0] + t * dx[0], x[1] + t * dx[1], x[2] + t * dx[2]};
        least = fmin(least, rk_collider_distance(kind, c, y, NULL, NULL));
    }
    return least;
}

TEST(a_point_step_never_enters_a_collider)
{
    for (int kind = 0; kind < 4; kind++) {
        int stopped = 0, trials = 0;
        double worst = INFINITY;
        for (int trial = 0; trial < 2000; trial++) {
            double c[RK_COLLIDER_REALS], x[3], dx[3];
            random_collider(kind, c);
            for (int i = 0; i < 3; i++) x[i] = c[i] + 1.5 * urand();
            double d0 = rk_collider_distance(kind, c, x, NULL, NULL);
            if (!(d0 > 1e-3)) continue;
            /* aimed through the collider's position, often far past it: a thin box at speed */
            for (int i = 0; i < 3; i++) dx[i] = (c[i] - x[i]) * (1 + 3 * fabs(urand())) + 0.3 * urand();
            double alpha = rk_collider_step(kind, c, x, dx);
            double least = least_on_path(kind, c, x, dx, alpha, 400);
            worst = fmin(worst, least / d0);
            stopped += alpha < 1;
            trials++;
        }
        printf("# %-7s %d motions into it: %d stopped; the least distance on a path, over the start's: %.3f\n",
               kinds[kind], trials, stopped, worst);
        CHECK(worst >= 0.1 - 1e-9, "%s: a path came to %g of its starting distance", kinds[kind], worst);
        CHECK(stopped > trials / 2, "%s: only %d of %d motions through it stopped", kinds[kind], stopped, trials);
    }
    /* moving away: the whole step */
    double c[RK_COLLIDER_REALS], x[3] = {0, 0, 2}, dx[3] = {0, 0, 1};
    random_collider(RK_COLLIDER_SPHERE, c);
    c[0] = c[1] = c[2] = 0;
    CHECK(rk_collider_step(RK_COLLIDER_SPHERE, c, x, dx) == 1, "a point leaving a sphere was stopped");
}

TEST(a_moving_collider_never_reaches_a_point)
{
    for (int kind = 0; kind < 4; kind++) {
        int stopped = 0, trials = 0;
        double worst = INFINITY;
        for (int trial = 0; trial < 1000; trial++) {
            double from[RK_COLLIDER_REALS], to[RK_COLLIDER_REALS], x[3], pose[RK_COLLIDER_REALS];
            random_collider(kind, from);
            memcpy(to, from, sizeof to);
            for (int i = 0; i < 3; i++) x[i] = from[i] + 1.5 * urand();
            double d0 = rk_collider_distance(kind, from, x, NULL, NULL);
            if (!(d0 > 1e-3)) continue;
            /* toward the point and past it, turning up to 90 degrees */
            for (int i = 0; i < 3; i++) to[i] = from[i] + 2 * (x[i] - from[i]) + 0.2 * urand();
            double turn[9], axis[3] = {urand(), urand(), urand()}, zero[3] = {0, 0, 0}, shift[3];
            rk_motion(RK_MOTION_TWIST, axis, zero, 1.57 * urand(), zero, 1.0, turn, shift);
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    to[3 + 3 * i + j] = from[3 + 3 * i] * turn[j] + from[4 + 3 * i] * turn[3 + j] + from[5 + 3 * i] * turn[6 + j];
            double s = rk_collider_motion_step(kind, from, to, x), least = INFINITY;
            for (int k = 0; k <= 400; k++) {
                rk_collider_pose_at(from, to, s * k / 400, pose);
                least = fmin(least, rk_collider_distance(kind, pose, x, NULL, NULL));
            }
            worst = fmin(worst, least / d0);
            stopped += s < 1;
            trials++;
        }
        printf("# %-7s %d motions onto a point: %d stopped; the least distance on a path, over the start's: %.3f\n",
               kinds[kind], trials, stopped, worst);
        CHECK(worst >= 0.1 - 1e-9, "%s: a moving collider came to %g of the starting distance", kinds[kind], worst);
        CHECK(stopped > trials / 2, "%s: only %d of %d motions stopped", kinds[kind], stopped, trials);
    }
    /* the pose path ends exactly at the target and keeps a rotation on the way */
    double from[RK_COLLIDER_REALS], to[RK_COLLIDER_REALS], mid[RK_COLLIDER_REALS];
    random_collider(RK_COLLIDER_BOX, from);
    random_collider(RK_COLLIDER_BOX, to);
    rk_collider_pose_at(from, to, 1.0, mid);
    CHECK(memcmp(mid, to, sizeof to) == 0, "the path does not end at the target");
    rk_collider_pose_at(from, to, 0.37, mid);
    CHECK(rk_collider_check(RK_COLLIDER_BOX, mid) == 0, "a pose on the way is not a rotation");
}

/* A random move: 0.5 m and up to 90 degrees. */
static void random_move(const double *from, double *to)
{
    double turn[9], axis[3] = {urand(), urand(), urand()}, zero[3] = {0, 0, 0}, shift[3];
    memcpy(to, from, RK_COLLIDER_REALS * sizeof(double));
    for (int i = 0; i < 3; i++) to[i] = from[i] + 0.5 * urand();
    rk_motion(RK_MOTION_TWIST, axis, zero, 1.57 * urand(), zero, 1.0, turn, shift);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            to[3 + 3 * i + j] = from[3 + 3 * i] * turn[j] + from[4 + 3 * i] * turn[3 + j] + from[5 + 3 * i] * turn[6 + j];
}

TEST(the_path_velocity_and_a_joint_step)
{
    double worst_v = 0, worst_path = INFINITY;
    int stopped = 0, trials = 0;
    for (int trial = 0; trial < 1000; trial++) {
        int kind = trial % 4;
        double from[RK_COLLIDER_REALS], to[RK_COLLIDER_REALS], a[RK_COLLIDER_REALS], b[RK_COLLIDER_REALS];
        random_collider(kind, from);
        random_move(from, to);
        double local[3] = {urand(), urand(), urand()}, v[3], s = 0.1 + 0.8 * fabs(urand()), h = 1e-6, pa[3], pb[3];
        rk_collider_path_velocity(from, to, s, local, v);
        rk_collider_pose_at(from, to, s + h, a);
        rk_collider_pose_at(from, to, s - h, b);
        to_world(a, local, pa), to_world(b, local, pb);
        for (int i = 0; i < 3; i++) worst_v = fmax(worst_v, fabs((pa[i] - pb[i]) / (2 * h) - v[i]));
        /* the point and the collider both moving, toward each other */
        double x[3], dx[3], pose[RK_COLLIDER_REALS], ds = (1 - s) * fabs(urand());
        rk_collider_pose_at(from, to, s, pose);
        for (int i = 0; i < 3; i++) x[i] = pose[i] + 1.5 * urand();
        double d0 = rk_collider_distance(kind, pose, x, NULL, NULL);
        if (!(d0 > 1e-3)) continue;
        for (int i = 0; i < 3; i++) dx[i] = (pose[i] - x[i]) * 2 * fabs(urand());
        double alpha = rk_collider_joint_step(kind, from, to, s, ds, x, dx), least = INFINITY;
        for (int k = 0; k <= 400; k++) {
            double t = alpha * k / 400, y[3] = {x[0] + t * dx[0], x[1] + t * dx[1], x[2] + t * dx[2]};
            rk_collider_pose_at(from, to, s + t * ds, pose);
            least = fmin(least, rk_collider_distance(kind, pose, y, NULL, NULL));
        }
        worst_path = fmin(worst_path, least / d0);
        stopped += alpha < 1;
        trials++;
    }
    printf("# path velocity vs finite differences %.2g; %d joint motions, %d stopped, least distance over the "
           "start's %.3f\n", worst_v, trials, stopped, worst_path);
    CHECK(worst_v < 1e-8, "path velocity off by %g", worst_v);
    CHECK(worst_path >= 0.1 - 1e-9 && stopped > trials / 3, "least %g, stopped %d of %d", worst_path, stopped, trials);
}

TEST(bad_colliders_are_named)
{
    double c[RK_COLLIDER_REALS];
    random_collider(RK_COLLIDER_SPHERE, c);
    CHECK(rk_collider_check(RK_COLLIDER_SPHERE, c) == 0, "a good sphere refused");
    c[12] = -0.1;
    CHECK(rk_collider_check(RK_COLLIDER_SPHERE, c) == RK_COLLIDER_BAD_SIZE, "a negative radius passed");
    c[12] = 0.2, c[1] = NAN;
    CHECK(rk_collider_check(RK_COLLIDER_SPHERE, c) == RK_COLLIDER_NOT_FINITE, "NaN passed");
    c[1] = 0, c[3] = 2;
    CHECK(rk_collider_check(RK_COLLIDER_SPHERE, c) == RK_COLLIDER_NOT_ROTATION, "a scaled rotation passed");
    random_collider(RK_COLLIDER_BOX, c);
    CHECK(rk_collider_check(7, c) == RK_COLLIDER_UNKNOWN_KIND, "an unknown kind passed");
    c[15] = 0;
    CHECK(rk_collider_check(RK_COLLIDER_BOX, c) == RK_COLLIDER_BAD_SIZE, "a flat box passed");
}

TEST(friction_smoothing_matches_finite_differences)
{
    double eps = 1e-3, worst_g = 0, worst_M = 0;
    for (int trial = 0; trial < 400; trial++) {
        double scale = trial % 2 ? 0.5 * eps : 3 * eps; /* both sides of the smoothing */
        double u[2] = {scale * urand(), scale * urand()}, f1y, M[4], h = 1e-9;
        rk_friction_smoothed(u, eps, &f1y, M);
        for (int i = 0; i < 2; i++) {
            double up[2] = {u[0], u[1]}, um[2] = {u[0], u[1]}, a, Mp[4], Mm[4], gp, gm;
            up[i] += h, um[i] -= h;
            double fp = rk_friction_smoothed(up, eps, &gp, Mp), fm = rk_friction_smoothed(um, eps, &gm, Mm);
            worst_g = fmax(worst_g, fabs((fp - fm) / (2 * h) - f1y * u[i]));
            for (int j = 0; j < 2; j++) { /* d(f1/y u_j)/du_i */
                a = (gp * up[j] - gm * um[j]) / (2 * h);
                worst_M = fmax(worst_M, fabs(a - M[2 * j + i]) * eps);
            }
        }
    }
    /* C1 across the threshold */
    double below[2] = {eps * (1 - 1e-9), 0}, above[2] = {eps * (1 + 1e-9), 0}, gb, ga, M[4];
    double jump = fabs(rk_friction_smoothed(below, eps, &gb, M) - rk_friction_smoothed(above, eps, &ga, M));
    printf("# friction smoothing: gradient off by %.2g, Hessian by %.2g (times eps); f0 jumps %.2g at eps\n", worst_g,
           worst_M, jump);
    CHECK(worst_g < 1e-6 && worst_M < 1e-5 && jump < 1e-11 && fabs(gb * below[0] - ga * above[0]) < 1e-8,
          "gradient %g, Hessian %g, jump %g", worst_g, worst_M, jump);
}

int main(void)
{
    RUN(distances_match_world_formulas_and_their_gradients);
    RUN(a_point_step_never_enters_a_collider);
    RUN(a_moving_collider_never_reaches_a_point);
    RUN(the_path_velocity_and_a_joint_step);
    RUN(bad_colliders_are_named);
    RUN(friction_smoothing_matches_finite_differences);
    return test_finish();
}
