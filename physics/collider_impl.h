/* collider_impl.h: colliders an application owns (planes, spheres, capsules, boxes) against
 * points, written once for the runtime and the precompute's reduced simulator; included by
 * physics_impl.h (same rules: C99, both precisions, no include guard, its macros).
 *
 * A collider is a kind (physics.h, rk_collider_kind) and RK_COLLIDER_REALS reals: its pose,
 * position (3) and rotation (9, row-major, local to world), then its size: radius (sphere,
 * capsule), half length (capsule, along its local x), half extents (box). A plane passes through
 * the position with its normal along the local z. A point's signed distance d is positive
 * outside; the barrier acts on d as on the scene's planes (barrier_distance), its gradient is
 * the outward normal n at the closest surface point; the Newton matrix takes f2 n n^T only (the
 * surface's curvature term, f1 times a negative semidefinite matrix for these convex shapes, is
 * left out so that the matrix stays PSD without a projection). */

#define PHYS_COLLIDER_GAP_ PHYS_K_(0.1)  /* a step keeps 10% of the starting distance, as CCD */
#define PHYS_COLLIDER_ROUNDS_ 64         /* conservative-advancement rounds before stopping short */

static PHYS_REAL PHYS_FN(dot3_)(const PHYS_REAL *a, const PHYS_REAL *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static PHYS_REAL PHYS_FN(clamp_)(PHYS_REAL v, PHYS_REAL lo, PHYS_REAL hi) { return v < lo ? lo : v > hi ? hi : v; }

PHYS_API int PHYS_FN(collider_check)(int kind, const PHYS_REAL *shape)
{
    const PHYS_REAL *R = shape + 3;
    int i, j;
    for (i = 0; i < RK_COLLIDER_REALS; i++)
        if (!isfinite(shape[i])) return RK_COLLIDER_NOT_FINITE;
    if (kind < RK_COLLIDER_PLANE || kind > RK_COLLIDER_BOX) return RK_COLLIDER_UNKNOWN_KIND;
    if ((kind == RK_COLLIDER_SPHERE || kind == RK_COLLIDER_CAPSULE) && !(shape[12] > 0)) return RK_COLLIDER_BAD_SIZE;
    if (kind == RK_COLLIDER_CAPSULE && !(shape[13] >= 0)) return RK_COLLIDER_BAD_SIZE;
    if (kind == RK_COLLIDER_BOX && !(shape[14] > 0 && shape[15] > 0 && shape[16] > 0)) return RK_COLLIDER_BAD_SIZE;
    for (i = 0; i < 3; i++) /* R^T R = I to 1e-3 */
        for (j = 0; j < 3; j++) {
            PHYS_REAL s = R[i] * R[j] + R[3 + i] * R[3 + j] + R[6 + i] * R[6 + j] - (PHYS_REAL)(i == j);
            if (!(PHYS_FABS_(s) < PHYS_K_(1e-3))) return RK_COLLIDER_NOT_ROTATION;
        }
    return 0;
}

PHYS_API PHYS_REAL PHYS_FN(collider_distance)(int kind, const PHYS_REAL *shape, const PHYS_REAL x[3], PHYS_REAL n[3],
                                              PHYS_REAL closest[3])
{
    const PHYS_REAL *p = shape, *R = shape + 3;
    PHYS_REAL w[3], y[3], nl[3] = {0, 0, 1}, c[3], d, len;
    int i;
    for (i = 0; i < 3; i++) w[i] = x[i] - p[i];
    for (i = 0; i < 3; i++) y[i] = R[i] * w[0] + R[3 + i] * w[1] + R[6 + i] * w[2]; /* R^T (x - p) */
    if (kind == RK_COLLIDER_PLANE) {
        d = y[2];
        c[0] = y[0], c[1] = y[1], c[2] = 0;
    } else if (kind == RK_COLLIDER_BOX) {
        const PHYS_REAL *h = shape + 14;
        PHYS_REAL v[3];
        int outside = 0, k = 0;
        for (i = 0; i < 3; i++) {
            c[i] = PHYS_FN(clamp_)(y[i], -h[i], h[i]);
            v[i] = y[i] - c[i];
            outside |= v[i] != 0;
        }
        if (outside) {
            d = PHYS_SQRT_(PHYS_FN(dot3_)(v, v));
            for (i = 0; i < 3; i++) nl[i] = v[i] / d;
        } else { /* inside: the nearest face */
            for (i = 1; i < 3; i++)
                if (PHYS_FABS_(y[i]) - h[i] > PHYS_FABS_(y[k]) - h[k]) k = i;
            d = PHYS_FABS_(y[k]) - h[k];
            nl[0] = nl[1] = nl[2] = 0;
            nl[k] = y[k] < 0 ? PHYS_K_(-1) : PHYS_K_(1);
            c[k] = nl[k] * h[k];
        }
    } else { /* sphere: the center; capsule: the closest point of its axis segment */
        PHYS_REAL a[3] = {0, 0, 0};
        if (kind == RK_COLLIDER_CAPSULE) a[0] = PHYS_FN(clamp_)(y[0], -shape[13], shape[13]);
        for (i = 0; i < 3; i++) w[i] = y[i] - a[i];
        len = PHYS_SQRT_(PHYS_FN(dot3_)(w, w));
        if (len > 0)
            for (i = 0; i < 3; i++) nl[i] = w[i] / len;
        d = len - shape[12];
        for (i = 0; i < 3; i++) c[i] = a[i] + shape[12] * nl[i];
    }
    for (i = 0; i < 3; i++) {
        if (n) n[i] = R[3 * i] * nl[0] + R[3 * i + 1] * nl[1] + R[3 * i + 2] * nl[2];
        if (closest) closest[i] = c[i];
    }
    return d;
}

/* Conservative advancement: the largest s in [0, 1] along a path on which the point's distance
 * changes by at most speed per unit s, keeping PHYS_COLLIDER_GAP_ of d0; dist(s) evaluates it. */
#define PHYS_COLLIDER_ADVANCE_(dist_of_s, d0, speed, out)                                        \
    do {                                                                                          \
        PHYS_REAL s_ = 0, keep_ = PHYS_COLLIDER_GAP_ * (d0);                                      \
        int round_;                                                                               \
        (out) = 1;                                                                                \
        if (!((d0) > 0)) { (out) = 0; break; }                                                    \
        if (!((speed) > 0)) break;                                                                \
        for (round_ = 0; round_ < PHYS_COLLIDER_ROUNDS_; round_++) {                              \
            PHYS_REAL ds_ = PHYS_K_(0.9) * ((dist_of_s) - keep_) / (speed);                      \
            if (!(ds_ > 0)) break;                                                                \
            if (s_ + ds_ >= 1) { s_ = 1; break; }                                                 \
            s_ += ds_;                                                                            \
        }                                                                                         \
        (out) = s_;                                                                               \
    } while (0)

/* The rotation from `from` to `to` (R_from^T R_to) as a unit axis k and an angle theta in [0, pi]. */
static PHYS_REAL PHYS_FN(collider_turn_)(const PHYS_REAL *from, const PHYS_REAL *to, PHYS_REAL k[3])
{
    PHYS_REAL Q[9], w[3], s, c;
    int i;
    PHYS_FN(m3_mul_tn)(from + 3, to + 3, Q);
    w[0] = Q[7] - Q[5], w[1] = Q[2] - Q[6], w[2] = Q[3] - Q[1]; /* 2 sin(theta) k */
    s = PHYS_K_(0.5) * PHYS_SQRT_(PHYS_FN(dot3_)(w, w));
    c = PHYS_K_(0.5) * (Q[0] + Q[4] + Q[8] - 1);
    k[0] = 1, k[1] = 0, k[2] = 0;
    if (s > PHYS_EPS_) {
        for (i = 0; i < 3; i++) k[i] = w[i] / (2 * s);
    } else if (c < 0) { /* a half turn: the axis from the diagonal, signs from the symmetric part */
        int m = Q[4] > Q[0] ? (Q[8] > Q[4] ? 2 : 1) : (Q[8] > Q[0] ? 2 : 0);
        PHYS_REAL km = PHYS_SQRT_(PHYS_K_(0.5) * (Q[4 * m] + 1));
        for (i = 0; i < 3; i++) k[i] = i == m ? km : (Q[3 * m + i] + Q[3 * i + m]) / (4 * km);
        return PHYS_K_(3.14159265358979323846);
    }
    return PHYS_ATAN2_(s, c);
}

PHYS_API void PHYS_FN(collider_pose_at)(const PHYS_REAL *from, const PHYS_REAL *to, PHYS_REAL s, PHYS_REAL *out)
{
    PHYS_REAL k[3], theta = PHYS_FN(collider_turn_)(from, to, k), Rs[9], shift[3], zero[3] = {0, 0, 0}, R0[9];
    int i;
    for (i = 0; i < RK_COLLIDER_REALS; i++) out[i] = to[i]; /* the size is the target's */
    if (s >= 1) return;
    if (s < 0) s = 0;
    for (i = 0; i < 3; i++) out[i] = from[i] + s * (to[i] - from[i]);
    PHYS_FN(motion)(RK_MOTION_TWIST, k, zero, theta, zero, s, Rs, shift);
    for (i = 0; i < 9; i++) R0[i] = from[3 + i];
    PHYS_FN(m3_mul)(R0, Rs, out + 3); /* R_from Rot(k, s theta): the shortest turn */
}

PHYS_API void PHYS_FN(collider_path_velocity)(const PHYS_REAL *from, const PHYS_REAL *to, PHYS_REAL s,
                                              const PHYS_REAL local[3], PHYS_REAL v[3])
{
    PHYS_REAL k[3], theta = PHYS_FN(collider_turn_)(from, to, k), pose[RK_COLLIDER_REALS], w[3];
    const PHYS_REAL *R = pose + 3;
    int i;
    PHYS_FN(collider_pose_at)(from, to, s, pose);
    /* d/ds [p(s) + R_from Rot(k, s theta) c] = dp + R(s) (theta k x c) */
    w[0] = theta * (k[1] * local[2] - k[2] * local[1]);
    w[1] = theta * (k[2] * local[0] - k[0] * local[2]);
    w[2] = theta * (k[0] * local[1] - k[1] * local[0]);
    for (i = 0; i < 3; i++) v[i] = to[i] - from[i] + R[3 * i] * w[0] + R[3 * i + 1] * w[1] + R[3 * i + 2] * w[2];
}

PHYS_API PHYS_REAL PHYS_FN(collider_joint_step)(int kind, const PHYS_REAL *from, const PHYS_REAL *to, PHYS_REAL s,
                                                PHYS_REAL ds, const PHYS_REAL x[3], const PHYS_REAL dx[3])
{
    PHYS_REAL k[3], theta, dp[3], r[3], pose[RK_COLLIDER_REALS], y[3], n[3], move, rho, speed, alpha, d0;
    int i;
    PHYS_FN(collider_pose_at)(from, to, s, pose);
    d0 = PHYS_FN(collider_distance)(kind, pose, x, n, 0);
    if (!(d0 > 0)) return 0;
    if (ds == 0 && kind == RK_COLLIDER_PLANE) { /* exact: the distance is linear along the step */
        PHYS_REAL dd = PHYS_FN(dot3_)(n, dx);
        return dd < 0 && PHYS_K_(0.9) * d0 / -dd < 1 ? PHYS_K_(0.9) * d0 / -dd : PHYS_K_(1);
    }
    theta = PHYS_FN(collider_turn_)(from, to, k);
    for (i = 0; i < 3; i++) dp[i] = to[i] - from[i], r[i] = x[i] - from[i];
    /* The distance is 1-Lipschitz in the point, and on the pose path a surface point at rho from
     * the position moves at most |dp| + theta rho per unit s. The closest surface point lies
     * within |x - p| + d <= 2 |x - p| + half length of the position (d <= |x - p| + half length
     * for every kind), with |x(t) - p(s)| <= |x - p_from| + |dx| + |dp| on the way. */
    move = PHYS_SQRT_(PHYS_FN(dot3_)(dp, dp));
    rho = PHYS_SQRT_(PHYS_FN(dot3_)(r, r)) + PHYS_SQRT_(PHYS_FN(dot3_)(dx, dx)) + move;
    speed = move + theta * (2 * rho + PHYS_FABS_(from[13]) + PHYS_FABS_(to[13]));
    for (i = 12; i < RK_COLLIDER_REALS; i++) speed += PHYS_FABS_(to[i] - from[i]); /* a resize */
    speed = PHYS_SQRT_(PHYS_FN(dot3_)(dx, dx)) + PHYS_FABS_(ds) * speed;
    PHYS_COLLIDER_ADVANCE_((y[0] = x[0] + s_ * dx[0], y[1] = x[1] + s_ * dx[1], y[2] = x[2] + s_ * dx[2],
                            PHYS_FN(collider_pose_at)(from, to, s + s_ * ds, pose),
                            PHYS_FN(collider_distance)(kind, pose, y, 0, 0)),
                           d0, speed, alpha);
    return alpha;
}

PHYS_API PHYS_REAL PHYS_FN(collider_step)(int kind, const PHYS_REAL *shape, const PHYS_REAL x[3], const PHYS_REAL dx[3])
{
    return PHYS_FN(collider_joint_step)(kind, shape, shape, 0, 0, x, dx);
}

PHYS_API PHYS_REAL PHYS_FN(collider_motion_step)(int kind, const PHYS_REAL *from, const PHYS_REAL *to, const PHYS_REAL x[3])
{
    PHYS_REAL still[3] = {0, 0, 0};
    return PHYS_FN(collider_joint_step)(kind, from, to, 0, 1, x, still);
}

PHYS_API void PHYS_FN(tangent_basis)(const PHYS_REAL n[3], PHYS_REAL T[6])
{
    int k = PHYS_FABS_(n[0]) < PHYS_FABS_(n[1]) ? (PHYS_FABS_(n[0]) < PHYS_FABS_(n[2]) ? 0 : 2)
                                                : (PHYS_FABS_(n[1]) < PHYS_FABS_(n[2]) ? 1 : 2);
    PHYS_REAL e[3] = {0, 0, 0}, *t1 = T, *t2 = T + 3, l;
    int i;
    e[k] = 1; /* the axis least aligned with n */
    t1[0] = n[1] * e[2] - n[2] * e[1], t1[1] = n[2] * e[0] - n[0] * e[2], t1[2] = n[0] * e[1] - n[1] * e[0];
    l = PHYS_SQRT_(PHYS_FN(dot3_)(t1, t1));
    for (i = 0; i < 3; i++) t1[i] /= l;
    t2[0] = n[1] * t1[2] - n[2] * t1[1], t2[1] = n[2] * t1[0] - n[0] * t1[2], t2[2] = n[0] * t1[1] - n[1] * t1[0];
}

PHYS_API PHYS_REAL PHYS_FN(friction_smoothed)(const PHYS_REAL u[2], PHYS_REAL eps, PHYS_REAL *f1_over_y, PHYS_REAL M[4])
{
    PHYS_REAL y = PHYS_SQRT_(u[0] * u[0] + u[1] * u[1]), c;
    if (y >= eps) {
        PHYS_REAL y3 = y * y * y;
        *f1_over_y = 1 / y;
        M[0] = 1 / y - u[0] * u[0] / y3, M[1] = M[2] = -u[0] * u[1] / y3, M[3] = 1 / y - u[1] * u[1] / y3;
        return y;
    }
    *f1_over_y = 2 / eps - y / (eps * eps); /* f1 = 2 y / eps - y^2 / eps^2 */
    c = y > 0 ? -1 / (eps * eps * y) : 0;
    M[0] = *f1_over_y + c * u[0] * u[0], M[1] = M[2] = c * u[0] * u[1], M[3] = *f1_over_y + c * u[1] * u[1];
    return -y * y * y / (3 * eps * eps) + y * y / eps + eps / 3;
}

#undef PHYS_COLLIDER_GAP_
#undef PHYS_COLLIDER_ROUNDS_
#undef PHYS_COLLIDER_ADVANCE_
