/* The app's colliders among the contact model's obstacles (contact.h, rk_contact_set_app_obstacles):
 * a reduced simulator's spheres, capsules and boxes on a model with a collision surface are the
 * scene's obstacles of those kinds (collision.c's geometry: a point or a segment with the radius
 * as thickness, a box's 8 corners and 12 triangles), given in their own frames and posed, so the
 * same barrier, friction and CCD act on them exactly (Li et al. 2020, Eq. 6-8) rather than on the
 * surface's vertices alone. They follow the scene's: the scene's obstacle vertex, edge and
 * triangle ids do not change when the app's do. */
#include "contact/pairs_impl.h"

#include <stdlib.h>
#include <string.h>

#include "util/util.h"

/* na items of a then nb of b (size bytes each) in a new array. */
static void *joined(const void *a, size_t na, const void *b, size_t nb, size_t size, rk_error *err)
{
    char *out = rk_calloc(na + nb + 1, size, err);
    if (!out) return NULL;
    if (na) memcpy(out, a, na * size);
    if (nb) memcpy(out + na * size, b, nb * size);
    return out;
}

int rk_contact_set_app_obstacles(rk_contact *c, const rk_obstacle *apps, int n, rk_error *err)
{
    rk_contact t; /* the app's obstacles alone, then moved in after the scene's */
    memset(&t, 0, sizeof t);
    for (int k = 0; k < n; k++)
        if (!apps[k].posed) return rk_fail(err, "app obstacle %d has no pose", k);
    if (rk_contact_build_obstacles(&t, apps, n, err)) {
        rk_contact_free(&t);
        return -1;
    }
    size_t ns = (size_t)c->scene_obstacles, nv = (size_t)c->scene_onv, ne = (size_t)c->scene_one, nf = (size_t)c->scene_onf;
    size_t tv = (size_t)t.onv, te = (size_t)t.one, tf = (size_t)t.onf;
    for (size_t v = 0; v < tv; v++) t.overt_obstacle[v] += (int)ns;
    for (size_t i = 0; i < 2 * te; i++) t.oedges[i] += (int)nv;
    for (size_t i = 0; i < 3 * tf; i++) t.ofaces[i] += (int)nv;
    rk_obstacle *obstacles = joined(c->obstacles, ns, t.obstacles, (size_t)n, sizeof *obstacles, err);
    double *othick = joined(c->othick, ns, t.othick, (size_t)n, sizeof(double), err);
    double *oplane = joined(c->oplane, 6 * ns, t.oplane, 6 * (size_t)n, sizeof(double), err);
    double *oplane_to = rk_calloc(6 * (ns + (size_t)n) + 1, sizeof(double), err);
    double *oX = joined(c->oX, 3 * nv, t.oX, 3 * tv, sizeof(double), err);
    double *ox = joined(c->ox, 3 * nv, t.ox, 3 * tv, sizeof(double), err); /* the scene's where they are */
    double *ox_to = rk_calloc(3 * (nv + tv) + 1, sizeof(double), err);
    int *overt = joined(c->overt_obstacle, nv, t.overt_obstacle, tv, sizeof(int), err);
    int *oedges = joined(c->oedges, 2 * ne, t.oedges, 2 * te, sizeof(int), err);
    int *ofaces = joined(c->ofaces, 3 * nf, t.ofaces, 3 * tf, sizeof(int), err);
    double *cache_ox = rk_calloc(3 * (nv + tv) + 1, sizeof(double), err);
    double *fox0 = c->fox0 ? joined(c->fox0, 3 * nv, t.ox, 3 * tv, sizeof(double), err) : NULL;
    rk_contact_free(&t);
    if (!obstacles || !othick || !oplane || !oplane_to || !oX || !ox || !ox_to || !overt || !oedges || !ofaces ||
        !cache_ox || (c->fox0 && !fox0)) {
        free(obstacles), free(othick), free(oplane), free(oplane_to), free(oX), free(ox), free(ox_to);
        free(overt), free(oedges), free(ofaces), free(cache_ox), free(fox0);
        return -1;
    }
    free(c->obstacles), free(c->othick), free(c->oplane), free(c->oplane_to), free(c->oX), free(c->ox), free(c->ox_to);
    free(c->overt_obstacle), free(c->oedges), free(c->ofaces), free(c->cache_ox), free(c->fox0);
    c->obstacles = obstacles, c->othick = othick, c->oplane = oplane, c->oplane_to = oplane_to;
    c->oX = oX, c->ox = ox, c->ox_to = ox_to, c->overt_obstacle = overt, c->oedges = oedges, c->ofaces = ofaces;
    c->cache_ox = cache_ox, c->fox0 = fox0;
    c->nobstacles = (int)ns + n, c->onv = (int)(nv + tv), c->one = (int)(ne + te), c->onf = (int)(nf + tf);
    /* the candidates and the lagged friction pairs may name obstacle vertices that moved */
    c->cache_valid = 0;
    c->nfriction = 0;
    return 0;
}

void rk_contact_pose_obstacle(rk_contact *c, int k, const double pose[12])
{
    memcpy(c->obstacles[k].pose, pose, sizeof c->obstacles[k].pose);
}
