/* The model's accessors: sizes, the clock, positions, rest positions and basis rows, triangles,
 * groups and forces, state, status texts, the version. */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

const char *romrt_status_string(romrt_status status)
{
#ifdef ROMRT_NO_STRINGS
    (void)status;
    return "";
#else
    static const char *const names[ROMRT_STATUS_COUNT] = {
        "ok", "bad argument", "damaged asset", "unsupported format version", "wrong platform",
        "unsupported asset feature", "inconsistent model", "above the runtime's limits", "arena too small or misaligned",
        "step diverged"};
    return (unsigned)status < (unsigned)ROMRT_STATUS_COUNT ? names[status] : "unknown status";
#endif
}

static romrt_status with_message(romrt_error *err, romrt_status status, const char *chunk, int numbers,
                                 const char *t1, uint64_t n, const char *t2, uint64_t n2, const char *t3)
{
    rombin_error e;
    if (!err) return status;
#ifdef ROMRT_NO_STRINGS
    t1 = t2 = t3 = "";
#endif
    if (numbers == 0) rombin_fail(&e, (int)status, chunk, t1);
    else if (numbers == 1) rombin_fail_n(&e, (int)status, chunk, t1, n, t2);
    else rombin_fail_nn(&e, (int)status, chunk, t1, n, t2, n2, t3);
    return rt_error_from(err, status, &e);
}

romrt_status rt_error_from(romrt_error *err, romrt_status status, const rombin_error *e)
{
    if (!err) return status;
    err->status = status;
    memcpy(err->chunk, e->chunk, sizeof err->chunk);
    memcpy(err->message, e->message, ROMRT_MESSAGE_BYTES);
    err->message[ROMRT_MESSAGE_BYTES - 1] = 0;
    return status;
}

romrt_status rt_fail(romrt_error *err, romrt_status status, const char *chunk, const char *text)
{
    return with_message(err, status, chunk, 0, text, 0, 0, 0, 0);
}

romrt_status rt_fail_n(romrt_error *err, romrt_status status, const char *chunk, const char *text1, uint64_t n,
                       const char *text2)
{
    return with_message(err, status, chunk, 1, text1, n, text2, 0, 0);
}

romrt_status rt_fail_nn(romrt_error *err, romrt_status status, const char *chunk, const char *text1, uint64_t n,
                        const char *text2, uint64_t n2, const char *text3)
{
    return with_message(err, status, chunk, 2, text1, n, text2, n2, text3);
}

/* The argument checks every public call makes: a NULL model or buffer, a capacity too small. */
static romrt_status no_model(romrt_error *err) { return rt_fail(err, ROMRT_E_ARGUMENT, 0, "the model is NULL"); }
static romrt_status no_buffer(romrt_error *err, const char *what) /* what: "X is NULL" */
{
    return rt_fail(err, ROMRT_E_ARGUMENT, 0, what);
}
static romrt_status short_buffer(romrt_error *err, const char *what, size_t capacity, size_t need)
{
    return rt_fail_nn(err, ROMRT_E_ARGUMENT, 0, what, (uint64_t)capacity, " elements, below the ", (uint64_t)need,
                      " needed");
}

void rt_initial_state(romrt_model *m)
{
    int i;
    memset(m->q, 0, sizeof m->q);
    memset(m->v, 0, sizeof m->v);
    memset(m->q_prev, 0, sizeof m->q_prev);
    memset(m->v_prev, 0, sizeof m->v_prev);
    for (i = 0; m->v0 && i < m->r; i++) m->v[i] = m->v0[i];
}

romrt_status romrt_reset(romrt_model *m, romrt_error *err)
{
    if (!m) return no_model(err);
    rt_initial_state(m);
    memset(m->f_app, 0, sizeof m->f_app);
    memset(&m->last, 0, sizeof m->last);
    m->t0 = 0;
    m->steps = 0;
    m->have_prev = 0;
    m->obs_behind = 0; /* the obstacles where the clock puts them */
    m->hessian_age = -1; /* a kept Newton matrix belongs to the motion it was built in */
    memset(m->colliders, 0, sizeof m->colliders); /* the app's colliders go: they may overlap the rest shape */
    m->ncolliders = 0;
    if (m->nmeshes) { /* their pairs go with them */
        m->nmeshes = 0;
        m->cache_valid = 0;
        m->nfric = 0;
    }
    if (m->kind == ROMRT_KIND_KOOPMAN) rt_koopman_reset(m);
    if (m->alrom) rt_alrom_reset(m);
    return ROMRT_OK;
}

romrt_kind romrt_model_kind(const romrt_model *m) { return m ? m->kind : ROMRT_KIND_REDUCED; }
int romrt_version(void) { return ROMRT_VERSION_NUMBER; }

/* Writes an out-struct (romrt.h): out begins with the caller's size, which must be at least this
 * library's struct (3.0's, `bytes`); ours is copied over it, its size field kept, and the bytes
 * past ours up to the caller's size (fields of a newer header) are set to 0. */
static romrt_status write_out(void *out, const void *ours, size_t bytes, const char *what, romrt_error *err)
{
    size_t given;
    memcpy(&given, out, sizeof given);
    if (given < bytes)
        return rt_fail_nn(err, ROMRT_E_ARGUMENT, 0, what, (uint64_t)given, " bytes, below the ", (uint64_t)bytes,
                          " of its first version (set size to sizeof the struct)");
    memset(out, 0, given);
    memcpy(out, ours, bytes);
    memcpy(out, &given, sizeof given);
    return ROMRT_OK;
}

romrt_status romrt_get_limits(romrt_limits *limits, romrt_error *err)
{
    romrt_limits ours;
    if (!limits) return no_buffer(err, "limits is NULL");
    memset(&ours, 0, sizeof ours);
    ours.max_reduced_size = ROMRT_MAX_R;
    ours.collider_slots = ROMRT_MAX_COLLIDERS;
    ours.mesh_max_count = ROMRT_MESH_MAX_COUNT;
    return write_out(limits, &ours, sizeof ours, "limits.size is ", err);
}

size_t romrt_reduced_size(const romrt_model *m) { return m ? (size_t)m->r : 0; }
size_t romrt_shown_count(const romrt_model *m) { return m ? (size_t)m->shown : 0; }
size_t romrt_triangle_count(const romrt_model *m) { return m ? (size_t)m->ntris : 0; }
size_t romrt_group_count(const romrt_model *m) { return m ? (size_t)m->ngroups : 0; }
double romrt_time(const romrt_model *m) { return m ? rt_clock(m, 0) : 0; }
romrt_real romrt_time_step(const romrt_model *m) { return m ? m->h : 0; }

/* The clock: a step count and the time it counts from, t = t0 + steps h with one rounding (a
 * running sum of h in float reads 7183.14 s after 432,000 steps of 1/60 s, 16.9 s short). A count
 * that would wrap folds into t0 first. */
double rt_clock(const romrt_model *m, unsigned long ahead)
{
    return m->t0 + ((double)m->steps + (double)ahead) * (double)m->h;
}

void rt_clock_rebase(romrt_model *m)
{
    m->t0 = rt_clock(m, 0);
    m->steps = 0;
}

void rt_clock_advance(romrt_model *m, unsigned long n)
{
    if (n > (unsigned long)-1 - m->steps) rt_clock_rebase(m);
    m->steps += n;
}

/* Positions are computed in romrt_real: keep them below its largest value with room to spare. */
#ifdef ROMRT_DOUBLE
#define RT_POSITION_LIMIT 1e300
#else
#define RT_POSITION_LIMIT 1e37
#endif

void rt_position_bounds(romrt_model *m)
{
    int i, j;
    m->row_bound = m->x_bound = 0;
    for (i = 0; i < 3 * m->shown; i++) {
        double s = 0;
        if (m->w) /* sum_j |w_j| |X̄| over the handles of row a */
            for (j = 0; j < m->skin; j++) {
                const romrt_real *X = m->X + 3 * (size_t)(i / 3);
                s += fabs((double)rt_weight(m, (uint32_t)(i / 3), j)) *
                     (fabs((double)X[0]) + fabs((double)X[1]) + fabs((double)X[2]) + 1);
            }
        else
            for (j = 0; j < m->r; j++) s += fabs((double)m->rows[(size_t)i * (size_t)m->r + (size_t)j]);
        if (s > m->row_bound) m->row_bound = s;
        if (fabs((double)m->X[i]) > m->x_bound) m->x_bound = fabs((double)m->X[i]);
    }
}

int rt_showable(const romrt_model *m, const romrt_real *q)
{
    double top = 0;
    int j;
    for (j = 0; j < m->r; j++)
        if (fabs((double)q[j]) > top) top = fabs((double)q[j]);
    return top * m->row_bound + m->x_bound < RT_POSITION_LIMIT;
}

/* Whether a vertex buffer of `capacity` reals, vertices `stride` reals apart, takes every shown vertex. */
static romrt_status holds_shown(const romrt_model *m, const romrt_real *xyz, size_t capacity, size_t stride,
                                romrt_error *err)
{
    if (!m) return no_model(err);
    if (!xyz) return no_buffer(err, "the vertex buffer is NULL");
    if (stride < 3 || stride > ((size_t)-1 - 3) / ROMRT_MAX_VERTICES)
        return rt_fail_n(err, ROMRT_E_ARGUMENT, 0, "a stride of ", (uint64_t)stride, " reals (3 at least)");
    if (m->shown > 0 && capacity < stride * (size_t)(m->shown - 1) + 3)
        return short_buffer(err, "the vertex buffer holds ", capacity, stride * (size_t)(m->shown - 1) + 3);
    return ROMRT_OK;
}

romrt_status romrt_positions(const romrt_model *m, romrt_real *xyz, size_t capacity, size_t stride, romrt_error *err)
{
    int i, a;
    if (holds_shown(m, xyz, capacity, stride, err)) return ROMRT_E_ARGUMENT;
    for (i = 0; i < m->shown; i++) {
        romrt_real *x = xyz + stride * (size_t)i;
        if (m->alrom) rt_alrom_position(m, (uint32_t)i, x); /* formed here, not each step */
        else
            for (a = 0; a < 3; a++) x[a] = m->X[3 * (size_t)i + (size_t)a] + rt_row_dot(m, (uint32_t)i, a, m->q);
    }
    return ROMRT_OK;
}

romrt_status romrt_rest_positions(const romrt_model *m, romrt_real *xyz, size_t capacity, size_t stride,
                                  romrt_error *err)
{
    int i, a;
    if (holds_shown(m, xyz, capacity, stride, err)) return ROMRT_E_ARGUMENT;
    for (i = 0; i < m->shown; i++) /* an adaptive linear ROM's X is the step's reference */
        for (a = 0; a < 3; a++)
            xyz[stride * (size_t)i + (size_t)a] = (m->alrom ? m->al.X0 : m->X)[3 * (size_t)i + (size_t)a];
    return ROMRT_OK;
}

romrt_status romrt_basis_rows(const romrt_model *m, romrt_real *rows, size_t capacity, romrt_error *err)
{
    int i, a;
    size_t r;
    if (!m) return no_model(err);
    if (!rows) return no_buffer(err, "rows is NULL");
    r = (size_t)m->r; /* 3 shown r <= 3 2^24 256: no overflow */
    if (capacity < 3 * (size_t)m->shown * r) return short_buffer(err, "rows holds ", capacity, 3 * (size_t)m->shown * r);
    for (i = 0; i < m->shown; i++)
        for (a = 0; a < 3; a++) {
            romrt_real *out = rows + (3 * (size_t)i + (size_t)a) * r;
            if (m->alrom) rt_alrom_row(m, (uint32_t)i, a, out);
            else rt_row(m, (uint32_t)i, a, out);
        }
    return ROMRT_OK;
}

romrt_status romrt_deformation_gradients(const romrt_model *m, romrt_real *F, size_t capacity, romrt_error *err)
{
    int i, j, a, b, H;
    if (!m) return no_model(err);
    if (!F) return no_buffer(err, "F is NULL");
    if (!m->grad)
        return rt_fail(err, ROMRT_E_UNSUPPORTED, ROMBIN_GRAD, "the asset stores no weight gradients (GRAD: point clouds)");
    if (capacity < 9 * (size_t)m->shown) return short_buffer(err, "F holds ", capacity, 9 * (size_t)m->shown);
    H = m->skin;
    for (i = 0; i < m->shown; i++) {
        const romrt_real *X = m->X + 3 * (size_t)i;
        romrt_real *Fi = F + 9 * (size_t)i;
        for (a = 0; a < 9; a++) Fi[a] = (romrt_real)(a % 4 == 0);
        for (j = 0; j < H; j++) {
            romrt_real w = rt_weight(m, (uint32_t)i, j);
            const romrt_real *dw = m->grad + ((size_t)i * (size_t)H + (size_t)j) * 3;
            for (a = 0; a < 3; a++) {
                const romrt_real *A = m->q + 12 * j + 4 * a; /* row a of handle j */
                romrt_real ax = A[0] * X[0] + A[1] * X[1] + A[2] * X[2] + A[3];
                for (b = 0; b < 3; b++) Fi[3 * a + b] += ax * dw[b] + A[b] * w;
            }
        }
    }
    return ROMRT_OK;
}

romrt_status romrt_triangles(const romrt_model *m, int32_t *tri, size_t capacity, romrt_error *err)
{
    size_t i;
    if (!m) return no_model(err);
    if (!tri) return no_buffer(err, "tri is NULL");
    if (capacity < 3 * (size_t)m->ntris) return short_buffer(err, "tri holds ", capacity, 3 * (size_t)m->ntris);
    for (i = 0; i < 3 * (size_t)m->ntris; i++) tri[i] = (int32_t)m->tris[i];
    return ROMRT_OK;
}

size_t romrt_collision_count(const romrt_model *m)
{
    return m && m->kind != ROMRT_KIND_KOOPMAN && m->cv ? (size_t)m->ncv : 0;
}

romrt_status romrt_collision_positions(const romrt_model *m, romrt_real *xyz, size_t capacity, romrt_error *err)
{
    size_t n = romrt_collision_count(m), i;
    if (!m) return no_model(err);
    if (!xyz) return no_buffer(err, "the vertex buffer is NULL");
    if (capacity < 3 * n) return short_buffer(err, "the vertex buffer holds ", capacity, 3 * n);
    for (i = 0; i < n; i++) /* as romrt_positions forms a shown vertex */
        if (m->alrom) rt_alrom_position(m, m->cv[i], xyz + 3 * i);
        else rt_vertex_position(m, m->cv[i], m->q, xyz + 3 * i);
    return ROMRT_OK;
}

romrt_status romrt_find_group(const romrt_model *m, const char *name, size_t *group, romrt_error *err)
{
    int g;
    if (!m) return no_model(err);
    if (!name || !group) return no_buffer(err, name ? "group is NULL" : "name is NULL");
    for (g = 0; g < m->ngroups; g++)
        if (strncmp(m->names + ROMBIN_GROUP_NAME_BYTES * g, name, ROMBIN_GROUP_NAME_BYTES) == 0) {
            *group = (size_t)g;
            return ROMRT_OK;
        }
    return rt_fail_n(err, ROMRT_E_ARGUMENT, ROMBIN_GRPS, "no group of that name among the asset's ",
                     (uint64_t)m->ngroups, "");
}

static romrt_status bad_group(const romrt_model *m, size_t group, romrt_error *err)
{
    return rt_fail_nn(err, ROMRT_E_ARGUMENT, 0, "group ", (uint64_t)group, " out of range (the asset has ",
                      (uint64_t)m->ngroups, ")");
}

romrt_status romrt_group_name(const romrt_model *m, size_t group, const char **name, romrt_error *err)
{
    if (!m) return no_model(err);
    if (!name) return no_buffer(err, "name is NULL");
    if (group >= (size_t)m->ngroups) return bad_group(m, group, err);
    *name = m->names + ROMBIN_GROUP_NAME_BYTES * group;
    return ROMRT_OK;
}

/* f_app += B_v^T f for stored vertex v (a Koopman asset: its impulse rows, KIMP). */
static void push(romrt_model *m, uint32_t v, const romrt_real f[3])
{
    int a, j;
    for (a = 0; a < 3; a++) {
        const romrt_real *row;
        if (m->kind == ROMRT_KIND_REDUCED) {
            rt_row_axpy(m, v, a, f[a], m->f_app); /* B_v^T f */
            continue;
        }
        /* Only a Koopman model has force_rows; a reduced one leaves it NULL, and forming
         * NULL + offset is undefined behaviour even unread (UBSan, fuzz regression
         * push_null_force_rows). */
        row = m->force_rows + ((size_t)3 * v + (size_t)a) * (size_t)m->r;
        for (j = 0; j < m->r; j++) m->f_app[j] += row[j] * f[a];
    }
}

static int finite3(const romrt_real f[3]) { return isfinite(f[0]) && isfinite(f[1]) && isfinite(f[2]); }

static romrt_status overflows(romrt_error *err)
{
    return rt_fail(err, ROMRT_E_ARGUMENT, 0, "the applied forces would overflow: the force is refused");
}

/* Keeps the applied forces finite: a push whose sum overflows is undone and refused. */
static romrt_status checked(romrt_model *m, const romrt_real *before, romrt_error *err)
{
    int j;
    for (j = 0; j < m->r; j++)
        if (!isfinite(m->f_app[j])) {
            memcpy(m->f_app, before, sizeof(romrt_real) * (size_t)m->r);
            return overflows(err);
        }
    return ROMRT_OK;
}

static romrt_status bad_force(const romrt_real f[3], romrt_error *err)
{
    return f ? rt_fail(err, ROMRT_E_ARGUMENT, 0, "the force is not finite") : no_buffer(err, "the force is NULL");
}

romrt_status romrt_add_force(romrt_model *m, size_t group, const romrt_real f[3], romrt_error *err)
{
    uint32_t k, first, count;
    romrt_real share[3], before[ROMRT_MAX_R];
    if (!m) return no_model(err);
    if (group >= (size_t)m->ngroups) return bad_group(m, group, err);
    if (!f || !finite3(f)) return bad_force(f, err);
    memcpy(before, m->f_app, sizeof(romrt_real) * (size_t)m->r);
    first = m->groups[2 * group];
    count = m->groups[2 * group + 1];
    for (k = 0; k < 3; k++) share[k] = f[k] / (romrt_real)count;
    if (m->alrom) { /* all or nothing */
        for (k = 0; k < count; k++)
            if (rt_alrom_push(m, m->gverts[first + k], share, 0)) return overflows(err);
        for (k = 0; k < count; k++) rt_alrom_push(m, m->gverts[first + k], share, 1);
        return ROMRT_OK;
    }
    for (k = 0; k < count; k++) push(m, m->gverts[first + k], share);
    return checked(m, before, err);
}

romrt_status romrt_add_vertex_force(romrt_model *m, size_t shown_vertex, const romrt_real f[3], romrt_error *err)
{
    romrt_real before[ROMRT_MAX_R];
    if (!m) return no_model(err);
    if (shown_vertex >= (size_t)m->shown)
        return rt_fail_nn(err, ROMRT_E_ARGUMENT, 0, "vertex ", (uint64_t)shown_vertex, " out of range (the asset shows ",
                          (uint64_t)m->shown, ")");
    if (!f || !finite3(f)) return bad_force(f, err);
    if (m->alrom) return rt_alrom_push(m, (uint32_t)shown_vertex, f, 1) ? overflows(err) : ROMRT_OK;
    memcpy(before, m->f_app, sizeof(romrt_real) * (size_t)m->r);
    push(m, (uint32_t)shown_vertex, f);
    return checked(m, before, err);
}

romrt_status romrt_clear_forces(romrt_model *m, romrt_error *err)
{
    if (!m) return no_model(err);
    memset(m->f_app, 0, sizeof m->f_app);
    if (m->alrom) memset(m->al.f_app, 0, sizeof(romrt_real) * 3 * (size_t)m->nv);
    return ROMRT_OK;
}

/* State layout: the clock as a pair t_hi + t_lo (t_hi the clock rounded to romrt_real, t_lo what
 * is left, so a float state keeps the double clock), have_prev, then q, v, q_prev, v_prev, f_app
 * (3 + 5 r reals); an adaptive linear ROM's (alrom.c) after the same three. */
#define RT_STATE_HEAD 3
#ifdef ROMRT_DOUBLE
#define RT_TOWARD_ZERO(x) nextafter((x), 0.0)
#else
#define RT_TOWARD_ZERO(x) nextafterf((x), 0.0f)
#endif
size_t romrt_state_size(const romrt_model *m)
{
    if (!m) return 0;
    return (size_t)(m->alrom ? RT_STATE_HEAD + rt_alrom_state_size(m) : RT_STATE_HEAD + 5 * m->r);
}

static romrt_status state_args(const romrt_model *m, const romrt_real *state, size_t count, int exact, romrt_error *err)
{
    if (!m) return no_model(err);
    if (!state) return no_buffer(err, "the state is NULL");
    if (exact ? count != romrt_state_size(m) : count < romrt_state_size(m))
        return rt_fail_nn(err, ROMRT_E_ARGUMENT, 0, "a state of ", (uint64_t)count, " reals where this model's has ",
                          (uint64_t)romrt_state_size(m), "");
    return ROMRT_OK;
}

void rt_split(double x, romrt_real *pair)
{
    double rest;
    romrt_real lo;
    pair[0] = (romrt_real)x;
    rest = x - (double)pair[0]; /* exact */
    lo = (romrt_real)rest;
    /* rounded toward zero, so hi + lo rounds back to hi and the pair reads back the same */
    if (fabs((double)lo) > fabs(rest)) lo = RT_TOWARD_ZERO(lo);
    /* A zero lo takes hi's sign, so hi + lo == hi bit for bit and the pair reads back the same:
     * an exact x leaves rest = +0, and -0 + +0 = +0 would read a -0 back as +0; a tiny negative
     * rest under a positive hi rounds to lo = -0, read back as +0 (fuzz regressions
     * state_round_trip_negative_zero, state_round_trip_underflowed_lo). */
    if (lo == 0) lo = 0 * pair[0];
    pair[1] = lo;
}

romrt_status romrt_get_state(const romrt_model *m, romrt_real *state, size_t capacity, romrt_error *err)
{
    int r;
    if (state_args(m, state, capacity, 0, err)) return ROMRT_E_ARGUMENT;
    r = m->r;
    rt_split(rt_clock(m, 0), state);
    state[2] = (romrt_real)m->have_prev;
    if (m->alrom) {
        rt_alrom_get_state(m, state + RT_STATE_HEAD);
        return ROMRT_OK;
    }
    memcpy(state + RT_STATE_HEAD, m->q, sizeof(romrt_real) * (size_t)r);
    memcpy(state + RT_STATE_HEAD + r, m->v, sizeof(romrt_real) * (size_t)r);
    memcpy(state + RT_STATE_HEAD + 2 * r, m->q_prev, sizeof(romrt_real) * (size_t)r);
    memcpy(state + RT_STATE_HEAD + 3 * r, m->v_prev, sizeof(romrt_real) * (size_t)r);
    memcpy(state + RT_STATE_HEAD + 4 * r, m->f_app, sizeof(romrt_real) * (size_t)r);
    return ROMRT_OK;
}

romrt_status romrt_set_state(romrt_model *m, const romrt_real *state, size_t count, romrt_error *err)
{
    size_t i;
    int r;
    if (state_args(m, state, count, 1, err)) return ROMRT_E_ARGUMENT;
    for (i = 0; i < count; i++)
        if (!isfinite(state[i]))
            return rt_fail_n(err, ROMRT_E_ARGUMENT, 0, "state real ", (uint64_t)i, " is not finite");
    if (!(state[2] == 0 || state[2] == 1))
        return rt_fail(err, ROMRT_E_ARGUMENT, 0, "state real 2 (whether there is a previous step) is not 0 or 1");
    if (m->alrom) {
        if (rt_alrom_set_state(m, state + RT_STATE_HEAD))
            return rt_fail(err, ROMRT_E_ARGUMENT, 0, "the adaptive model's state is out of range");
    } else if (!rt_showable(m, state + RT_STATE_HEAD)) { /* q would draw as Inf */
        return rt_fail(err, ROMRT_E_ARGUMENT, 0, "the state's q would put the shown vertices past the reals' range");
    }
    r = m->r;
    m->hessian_age = -1;
    m->obs_behind = 0; /* the state holds no obstacle lag: they go where its clock puts them */
    m->t0 = (double)state[0] + (double)state[1];
    m->steps = 0;
    m->have_prev = state[2] == 1;
    if (m->alrom) return ROMRT_OK;
    memcpy(m->q, state + RT_STATE_HEAD, sizeof(romrt_real) * (size_t)r);
    memcpy(m->v, state + RT_STATE_HEAD + r, sizeof(romrt_real) * (size_t)r);
    memcpy(m->q_prev, state + RT_STATE_HEAD + 2 * r, sizeof(romrt_real) * (size_t)r);
    memcpy(m->v_prev, state + RT_STATE_HEAD + 3 * r, sizeof(romrt_real) * (size_t)r);
    memcpy(m->f_app, state + RT_STATE_HEAD + 4 * r, sizeof(romrt_real) * (size_t)r);
    return ROMRT_OK;
}

romrt_status romrt_reduced_coordinates(const romrt_model *m, romrt_real *q, size_t capacity, romrt_error *err)
{
    if (!m) return no_model(err);
    if (!q) return no_buffer(err, "q is NULL");
    if (capacity < (size_t)m->r) return short_buffer(err, "q holds ", capacity, (size_t)m->r);
    memcpy(q, m->q, sizeof(romrt_real) * (size_t)m->r);
    return ROMRT_OK;
}

romrt_status romrt_last_step(const romrt_model *m, romrt_step_info *info, romrt_error *err)
{
    romrt_step_info ours;
    if (!m) return no_model(err);
    if (!info) return no_buffer(err, "info is NULL");
    ours = m->last;
    ours.hessian_reuse = (size_t)rt_reuse_steps(m);
    ours.pair_capacity = (size_t)m->pair_cap;
    return write_out(info, &ours, sizeof ours, "info.size is ", err);
}
