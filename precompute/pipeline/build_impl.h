/* Private to rk_scene_build (build.c) and the full-order bodies of point clouds (build_body.c). */
#ifndef RK_PIPELINE_BUILD_IMPL_H
#define RK_PIPELINE_BUILD_IMPL_H

#include "contact/contact.h"
#include "pipeline/pipeline.h"

/* The object's material, overridden by the last region that selects the place: its box or ball
 * holds p, or (tagged: the place carries a tag) its tag is `tag`. */
rk_material rk_scene_region_material(const rk_scene_object *o, const double p[3], int tagged, int tag);

/* The voxel g of a cloud's contact surface (X: its n points, unplaced): mesh.proxy_voxel, else the
 * cloud's RKPM sampling spacing, no finer than 1/RK_PROXY_VOXELS of its diagonal; and s, the
 * points' median nearest-neighbour spacing (0 for a cloud of under 4 points at a given voxel). */
int rk_cloud_proxy_spacing(const rk_scene_object *o, const double *X, int n, double *g, double *s, rk_error *err);

/* Cloud o's contact surface as a mesh (X: its n points, unplaced): the n points, then the surface's
 * vertices, with ghost tets whose rk_mesh_boundary is the surface. mesh.proxy "march" (the
 * default): rk_points_march_mesh at lattice edge RK_MARCH_LATTICE g, or where a point lies
 * farther than RK_PROXY_OUTSIDE s outside that, at g (warned), refused (naming the file) when
 * one still does; "voxels", or a cloud of under 4
 * points (no spacing to pull to): rk_points_proxy. */
int rk_cloud_surface(const rk_scene_object *o, const double *X, int n, rk_mesh *m, rk_error *err);

/* A cloud object's full-order body while the scene is built: its points and what ties them to it. */
typedef struct {
    double *X;                 /* the n points (placed once rk_cloud_body_place ran) */
    int n;
    int *tag;                  /* n, or NULL */
    int *tet_point;            /* the body's tets: the nearest point */
    double *proxy_X;           /* the voxel surface: the body's vertices where the reduced simulator's contact
                                * surface has them; the march surface: its vertices (embedded in the body) */
    int corners;               /* the body's vertices */
    int surface_nv;            /* proxy_X's vertices (the voxel surface: corners) */
    int march;                 /* proxy_X is the march surface, not the body's vertices */
    int nghost, *ghost;        /* the march surface's ghost cones: 0 their apex (point 0), 1 + i its vertex i */
    rk_points_body_report rep;
} rk_cloud_body;

/* Object o (a point cloud) as its body (rk_points_body), unplaced; m->tet_tag gets each tet's
 * nearest point's tag (so regions by tag select tets). */
int rk_cloud_body_load(const rk_scene_object *o, rk_mesh *m, rk_cloud_body *b, rk_error *err);
void rk_cloud_body_place(rk_cloud_body *b, double scale, const double translate[3]);
void rk_cloud_body_free(rk_cloud_body *b);
/* After the materials: each cloud body's tets' densities scaled so the body weighs what the cloud
 * does (sum of rho V / n over its points, as the reduced model's mass), its points embedded in its
 * tets, and out->layout made (the scene's vertices as rk_scene_build numbers them). bodies[k].n is
 * 0 for a mesh. */
int rk_cloud_bodies_finish(const rk_scene *s, rk_cloud_body *bodies, rk_scene_sim *out, rk_error *err);
/* After rk_cloud_bodies_finish, when a cloud collides through its march surface: out->contact, the
 * surface full order's contact runs on (rk_fom_contact_surface; build_contact.c); nothing (mesh.nv
 * 0) when no cloud does. */
int rk_cloud_contact_surface(const rk_scene *s, const rk_cloud_body *bodies, rk_scene_sim *out, rk_error *err);

#endif
