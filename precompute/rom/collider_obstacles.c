/* The app's spheres, capsules and boxes on a model with a collision surface (rom.h, rom_impl.h):
 * obstacles of the contact model after the scene's (rk_contact_set_app_obstacles), as the runtime
 * makes them (runtime/shape_collider.c): a sphere its centre with thickness r, a capsule its
 * segment along its local x with thickness r (one of no length a sphere), a box its 8 corners and
 * the 12 triangles of physics.h's RK_BOX_TRIANGLES, all in the collider's own frame at its pose.
 * The barrier and friction are then the contact stage's, exact between the shape and the surface's
 * triangles (Li et al. 2020, Eq. 6-8), where the vertex path (colliders.c) sees only the surface's
 * vertices and lets a shape thinner than an edge pass between them. A move sets where the obstacle
 * is due; the step's joint solve takes it there with the scene's moving obstacles
 * (obstacle_solve.c: its vertices on straight lines at one progress s, as the runtime's app
 * meshes go, runtime/mesh_move.c). */
#include "rom/rom_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The obstacle of an app's collider (not a plane). */
static rk_obstacle obstacle_of(const rk_collider *c)
{
    rk_obstacle o;
    memset(&o, 0, sizeof o);
    const double *shape = c->shape;
    o.posed = 1;
    memcpy(o.pose, shape, sizeof o.pose);
    if (c->kind == RK_COLLIDER_BOX) {
        o.kind = RK_OBSTACLE_BOX;
        for (int a = 0; a < 3; a++) o.min[a] = -shape[14 + a], o.max[a] = shape[14 + a];
    } else if (c->kind == RK_COLLIDER_CAPSULE && shape[13] > 0) {
        o.kind = RK_OBSTACLE_CAPSULE;
        o.center[0] = -shape[13], o.end[0] = shape[13];
        o.radius = shape[12];
    } else { /* a sphere, or a capsule of no length */
        o.kind = RK_OBSTACLE_SPHERE;
        o.radius = shape[12];
    }
    return o;
}

/* The first vertex of obstacle k (an app's: after the scene's) and how many it has. */
static int vertices_of(const rk_contact *con, int k, int *count)
{
    int first = -1;
    *count = 0;
    for (int v = con->scene_onv; v < con->onv; v++)
        if (con->overt_obstacle[v] == k) {
            if (first < 0) first = v;
            ++*count;
        }
    return first;
}

/* The contact model's app obstacles: every exact slot's (slot `slot` as c, NULL: none), in slot
 * order, the others kept where they stand (part way to their poses, if the body held them back),
 * slot's at its pose, or at slot_ox (its vertices' positions) when given; the slots' obstacle
 * indices follow (the simulator's obstacle scratch has room for them all: rk_rom_init). */
static int rebuild(rk_rom *s, int slot, const rk_collider *c, const double *slot_ox, rk_error *err)
{
    rk_contact *con = &s->model->contact;
    rk_obstacle apps[RK_MAX_COLLIDERS];
    int n = 0, first[RK_MAX_COLLIDERS], count[RK_MAX_COLLIDERS];
    for (int k = 0; k < RK_MAX_COLLIDERS; k++) {
        rk_rom_collider *kc = &s->colliders[k];
        first[k] = -1;
        if (k == slot && c) {
            apps[n++] = obstacle_of(c);
        } else if (k != slot && kc->active && kc->exact) {
            rk_collider due = {.kind = kc->kind};
            memcpy(due.shape, kc->target, sizeof due.shape);
            apps[n++] = obstacle_of(&due);
            first[k] = vertices_of(con, kc->obstacle, &count[k]);
        }
    }
    int onv = con->onv;
    double *was = rk_calloc(3 * (size_t)onv + 1, sizeof(double), err);
    if (!was) return -1;
    memcpy(was, con->ox, sizeof(double) * 3 * (size_t)onv);
    if (rk_contact_set_app_obstacles(con, apps, n, err)) {
        free(was);
        return -1;
    }
    for (int k = 0, j = 0; k < RK_MAX_COLLIDERS; k++) {
        rk_rom_collider *kc = &s->colliders[k];
        if (!((k == slot && c) || (k != slot && kc->active && kc->exact))) continue;
        kc->obstacle = con->scene_obstacles + j++;
        int to, nv;
        if ((first[k] >= 0 || (k == slot && slot_ox)) && (to = vertices_of(con, kc->obstacle, &nv)) >= 0 &&
            (k == slot || nv == count[k]))
            memcpy(&con->ox[3 * to], k == slot ? slot_ox : &was[3 * first[k]], sizeof(double) * 3 * (size_t)nv);
    }
    free(was);
    return 0;
}

int rk_rom_collider_obstacles(rk_rom *s, int slot, const rk_collider *c, rk_error *err)
{
    rk_contact *con = &s->model->contact;
    rk_rom_collider *k = &s->colliders[slot];
    /* what the slot was, to go back to: its collider where it was due, its vertices where they stand */
    rk_collider old = {.kind = k->kind};
    double old_ox[3 * RK_COLLIDER_MAX_VERTICES];
    int was_exact = k->active && k->exact, nv = 0, first = was_exact ? vertices_of(con, k->obstacle, &nv) : -1;
    memcpy(old.shape, k->target, sizeof old.shape);
    if (first >= 0) memcpy(old_ox, &con->ox[3 * first], sizeof(double) * 3 * (size_t)nv);
    if (rebuild(s, slot, c, NULL, err)) return -1;
    if (!c) { /* gone from the obstacles */
        k->exact = 0;
        return 0;
    }
    /* placed at once, clear of the body: no crossing, and a finite barrier at q (a pair touching,
     * or a surface within a sphere's or capsule's radius, is refused) */
    int crossings = rk_rom_contact_intersections(s, s->q, err);
    double E = crossings == 0 ? rk_rom_contact_energy(s, s->q, 0, NULL, NULL, err) : 0;
    if (crossings != 0 || !isfinite(E)) {
        rk_error why = *err;
        if (rebuild(s, slot, was_exact ? &old : NULL, first >= 0 ? old_ox : NULL, err)) return -1;
        if (crossings < 0 || isnan(E)) {
            *err = why;
            return -1;
        }
        return rk_fail(err, "collider %d would touch or cross the body's surface: place it clear of the body, then "
                       "move it", slot);
    }
    rk_rom_collider_take(s, slot, c, 1);
    return 0;
}

void rk_rom_collider_obstacles_arrived(rk_rom *s)
{
    rk_contact *con = &s->model->contact;
    double at[3 * RK_COLLIDER_MAX_VERTICES];
    for (int k = 0; k < RK_MAX_COLLIDERS; k++) {
        rk_rom_collider *kc = &s->colliders[k];
        int nv, first;
        if (!kc->active || !kc->exact || (first = vertices_of(con, kc->obstacle, &nv)) < 0) continue;
        /* there when its vertices are where its pose puts them (rk_contact_set_time's arithmetic) */
        const double *R = kc->target + 3, *p = kc->target;
        int there = 1;
        for (int v = 0; v < nv && there; v++) {
            const double *X = &con->oX[3 * (first + v)];
            for (int i = 0; i < 3; i++) at[3 * v + i] = R[3 * i] * X[0] + R[3 * i + 1] * X[1] + R[3 * i + 2] * X[2] + p[i];
            there = !memcmp(&at[3 * v], &con->ox[3 * (first + v)], 3 * sizeof(double));
        }
        if (there) memcpy(kc->now, kc->target, sizeof kc->now);
    }
}
