/* rk_scene -> something to simulate: meshes loaded (surfaces tetrahedralized), placed and
 * concatenated; one material per element (regions override by element centroid, in order);
 * the FEM model; full-order options with prescribed vertex groups, loads and initial velocities. */
#include "pipeline/build_impl.h"
#include "util/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The cage around o's surface file (mesh.cage), the surface kept in *surface. */
static int load_cage(const rk_scene_object *o, rk_mesh *m, rk_surface *surface, rk_cage_report *cr, rk_error *err)
{
    int flipped;
    if (rk_surface_load(o->file, surface, err) || rk_surface_check_and_orient(surface, o->file, &flipped, err))
        return -1;
    rk_cage_options co = {.max_tets = o->cage_tets, .quality = o->quality};
    if (rk_cage_build(surface, &co, m, cr, err)) return rk_error_prefix(err, "cage");
    return 0;
}

/* The object's mesh, checked for simulation: flat tets dropped with a warning (mesh.h); rep gets
 * what the check repaired. A caged object's mesh is its cage, its surface in *surface. */
static int load_unrefined_mesh(const rk_scene_object *o, int k, rk_mesh *m, rk_mesh_report *rep, int *cloud_points,
                               int **point_tag, rk_surface *surface, rk_cage_report *cr, rk_cloud_body *body,
                               rk_error *err)
{
    memset(m, 0, sizeof *m);
    memset(rep, 0, sizeof *rep);
    if (body && o->shape == RK_SHAPE_POINTS) /* full order: the tets filling its contact surface */
        return rk_cloud_body_load(o, m, body, err) || rk_mesh_check(m, o->file, RK_MESH_KEEP_FLAT, rep, err) ? -1 : 0;
    if (o->cage_tets)
        return load_cage(o, m, surface, cr, err) || rk_mesh_check(m, o->file, RK_MESH_DROP_FLAT, rep, err) ? -1 : 0;
    switch (o->shape) {
    case RK_SHAPE_BOX:
        return rk_mesh_box(o->box_size, o->box_cells, m, err);
    case RK_SHAPE_POINTS: {
        /* the cloud's points first, in file order, then its contact surface's vertices (ghost tets) */
        double *X = NULL;
        int n = 0;
        if (rk_points_load_tagged(o->file, &X, &n, point_tag, err)) return -1;
        int rc = rk_cloud_surface(o, X, n, m, err);
        free(X);
        *cloud_points = n;
        (void)k;
        return rc;
    }
    case RK_SHAPE_FILE:
        break;
    }
    if (rk_path_is_surface(o->file)) {
        rk_surface s;
        if (rk_surface_load(o->file, &s, err)) return -1;
        int rc = rk_surface_check(&s, o->file, err);
        if (!rc) rc = rk_tetrahedralize(&s, o->quality, o->max_volume, m, err);
        rk_surface_free(&s);
        if (!rc) rc = rk_mesh_check(m, o->file, RK_MESH_DROP_FLAT, rep, err);
        return rc;
    }
    return rk_mesh_load(o->file, RK_MESH_DROP_FLAT, m, rep, err);
}

/* The object's mesh, refined o->refine times (mesh.refine) after its check; the refined mesh is
 * checked again (children of a sliver are slivers; a tet near the flat threshold may cross it),
 * whatever that check repairs added to rep. */
static int load_object_mesh(const rk_scene_object *o, int k, rk_mesh *m, rk_mesh_report *rep, int *cloud_points,
                            int **point_tag, rk_surface *surface, rk_cage_report *cr, rk_cloud_body *body,
                            rk_error *err)
{
    if (load_unrefined_mesh(o, k, m, rep, cloud_points, point_tag, surface, cr, body, err)) return -1;
    if (o->refine == 0) return 0;
    rk_mesh fine;
    if (rk_mesh_refine(m, o->refine, &fine, err)) { /* "refine: ..." after "objects[k].mesh: " */
        rk_mesh_free(m);
        return -1;
    }
    rk_mesh_free(m);
    *m = fine;
    rk_mesh_report again;
    if (rk_mesh_check(m, o->file[0] ? o->file : "box", RK_MESH_DROP_FLAT, &again, err)) {
        rk_mesh_free(m);
        return rk_error_prefix(err, "refine: %d levels", o->refine);
    }
    rep->reoriented += again.reoriented;
    rep->unused_removed += again.unused_removed;
    rep->flat_dropped += again.flat_dropped;
    rep->ghosts += again.ghosts;
    rep->orphans_removed += again.orphans_removed;
    return 0;
}

/* Appends b to a (vertices, tets, ghost tets, tags). */
static int append_mesh(rk_mesh *a, const rk_mesh *b, rk_error *err)
{
    double *X = realloc(a->X, sizeof(double) * 3 * (size_t)(a->nv + b->nv));
    if (X) a->X = X;
    int *T = realloc(a->tets, sizeof(int) * 4 * (size_t)(a->nt + b->nt + 1)); /* (+1: point clouds have no tets,
                                                                                 * and realloc to 0 bytes frees) */
    if (T) a->tets = T;
    int *G = b->nghost ? realloc(a->ghost, sizeof(int) * 4 * (size_t)(a->nghost + b->nghost)) : a->ghost;
    if (G) a->ghost = G;
    if (!X || !T || (b->nghost && !G)) return rk_fail(err, "out of memory joining the scene's meshes");
    memcpy(a->X + 3 * (size_t)a->nv, b->X, sizeof(double) * 3 * (size_t)b->nv);
    for (size_t i = 0; i < 4 * (size_t)b->nt; i++) a->tets[4 * (size_t)a->nt + i] = b->tets[i] + a->nv;
    for (size_t i = 0; i < 4 * (size_t)b->nghost; i++) a->ghost[4 * (size_t)a->nghost + i] = b->ghost[i] + a->nv;
    a->nv += b->nv;
    a->nt += b->nt;
    a->nghost += b->nghost;
    free(a->tet_tag); /* tags are per file; a joined mesh has none */
    a->tet_tag = NULL;
    return 0;
}

/* The object's tags after the scene's (0 for a file without): its tets' (m->tet_tag), and a point
 * cloud's first `points` vertices' (point_tag, or NULL). The regions that select by tag read them per
 * object (assign_materials), so two files may use the same numbers. */
static int append_tags(rk_scene_sim *out, const rk_mesh *m, const int *point_tag, int points, rk_error *err)
{
    int *T = realloc(out->tet_tag, sizeof(int) * ((size_t)out->mesh.nt + m->nt + 1));
    if (T) out->tet_tag = T;
    int *P = realloc(out->point_tag, sizeof(int) * ((size_t)out->mesh.nv + m->nv + 1));
    if (P) out->point_tag = P;
    if (!T || !P) return rk_fail(err, "out of memory keeping the meshes' tags");
    for (int t = 0; t < m->nt; t++) T[out->mesh.nt + t] = m->tet_tag ? m->tet_tag[t] : 0;
    for (int v = 0; v < m->nv; v++) P[out->mesh.nv + v] = point_tag && v < points ? point_tag[v] : 0;
    return 0;
}

static void free_surfaces(rk_surface *surfaces, int n)
{
    for (int k = 0; surfaces && k < n; k++) rk_surface_free(&surfaces[k]);
    free(surfaces);
}

static void transform_surface(rk_surface *s, double scale, const double translate[3])
{
    for (int v = 0; v < s->nv; v++)
        for (int i = 0; i < 3; i++) s->X[3 * v + i] = scale * s->X[3 * v + i] + translate[i];
}

/* An uncaged object's boundary as a surface over its own vertices (placed), so that a scene with a
 * cage shows it too: embedded like a caged surface, each vertex lands in a tet of its own, at
 * barycentric coordinates 1 and 0. */
static int boundary_surface(const rk_scene_sim *sim, int k, rk_surface *sf, rk_error *err)
{
    rk_object_view ov;
    int *tris = NULL, nf = 0;
    if (rk_scene_object_view(sim, k, &ov, err)) return -1;
    int rc = rk_mesh_boundary(&ov.mesh, &tris, &nf, err);
    int *local = rc ? NULL : rk_calloc((size_t)ov.mesh.nv + 1, sizeof(int), err);
    free(ov.mesh.tets);
    if (!local) {
        free(tris);
        return -1;
    }
    for (int v = 0; v < ov.mesh.nv; v++) local[v] = -1;
    for (int i = 0; i < 3 * nf; i++)
        if (local[tris[i]] < 0) local[tris[i]] = sf->nv++;
    sf->X = rk_calloc(3 * (size_t)sf->nv + 1, sizeof(double), err);
    if (!sf->X) {
        free(tris);
        free(local);
        return -1;
    }
    for (int v = 0; v < ov.mesh.nv; v++)
        if (local[v] >= 0) memcpy(sf->X + 3 * (size_t)local[v], ov.mesh.X + 3 * (size_t)v, 3 * sizeof(double));
    for (int i = 0; i < 3 * nf; i++) tris[i] = local[tris[i]];
    sf->tris = tris;
    sf->nf = nf;
    free(local);
    return 0;
}

/* Each caged object's surface embedded in its own tets (rk_cage_embed), and every other object's
 * boundary likewise, joined into out->embedded (scene tet numbers); vertices outside the cage are
 * counted and warned about. */
static int embed_surfaces(const rk_scene *s, const rk_surface *surfaces, rk_scene_sim *out, rk_error *err)
{
    rk_embedded_surface *E = &out->embedded;
    int nv = 0, nf = 0;
    for (int k = 0; k < s->nobjects; k++) nv += surfaces[k].nv, nf += surfaces[k].nf;
    E->X = rk_calloc(3 * (size_t)nv, sizeof(double), err);
    E->tris = rk_calloc(3 * (size_t)nf, sizeof(int), err);
    E->tet = rk_calloc((size_t)nv, sizeof(int), err);
    E->bary = rk_calloc(4 * (size_t)nv, sizeof(double), err);
    out->embedded_first = rk_calloc((size_t)s->nobjects + 1, sizeof(int), err);
    if (!E->X || !E->tris || !E->tet || !E->bary || !out->embedded_first) return -1;
    for (int k = 0; k < s->nobjects; k++) {
        out->embedded_first[k] = E->nv;
        const rk_surface *sf = &surfaces[k];
        rk_object_view ov;
        rk_embedding e;
        if (rk_scene_object_view(out, k, &ov, err)) return -1;
        int rc = rk_cage_embed(&ov.mesh, sf->X, sf->nv, &e, err);
        free(ov.mesh.tets);
        if (rc) return rk_error_prefix(err, "%s: objects[%d].mesh.cage", s->path, k);
        memcpy(E->X + 3 * (size_t)E->nv, sf->X, sizeof(double) * 3 * (size_t)sf->nv);
        memcpy(E->bary + 4 * (size_t)E->nv, e.bary, sizeof(double) * 4 * (size_t)sf->nv);
        for (int i = 0; i < sf->nv; i++) E->tet[E->nv + i] = ov.t0 + e.tet[i];
        for (int i = 0; i < 3 * sf->nf; i++) E->tris[3 * (size_t)E->nf + i] = E->nv + sf->tris[i];
        if (e.outside)
            rk_warn("%s: objects[%d].mesh.cage: %d of %d surface vertices are outside the cage (the farthest, vertex "
                    "%d, %.3g m away): each is carried by its nearest tet", s->path, k, e.outside, sf->nv,
                    e.worst_point, e.worst_distance);
        out->embedded_outside += e.outside;
        out->embedded_worst = fmax(out->embedded_worst, e.worst_distance);
        E->nv += sf->nv;
        E->nf += sf->nf;
        rk_embedding_free(&e);
    }
    out->embedded_first[s->nobjects] = E->nv;
    return 0;
}

static int region_holds(const rk_scene_region *g, const double p[3], int tagged, int tag)
{
    if (g->by_tag) return tagged && tag == g->tag;
    if (g->by_ball) {
        double d[3] = {p[0] - g->center[0], p[1] - g->center[1], p[2] - g->center[2]};
        return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= g->radius * g->radius;
    }
    return rk_box_contains(&g->box, p, 0);
}

rk_material rk_scene_region_material(const rk_scene_object *o, const double p[3], int tagged, int tag)
{
    rk_material m = o->material;
    for (int r = 0; r < o->nregions; r++)
        if (region_holds(&o->regions[r], p, tagged, tag)) m = o->regions[r].material;
    return m;
}

rk_material rk_scene_material_at(const rk_scene_object *o, const double p[3]) { return rk_scene_region_material(o, p, 0, 0); }

rk_material rk_scene_point_material(const rk_scene *s, const rk_scene_sim *sim, int k, int v)
{
    return rk_scene_region_material(&s->objects[k], &sim->mesh.X[3 * (size_t)v], sim->point_tag != NULL,
                           sim->point_tag ? sim->point_tag[v] : 0);
}

rk_material rk_scene_sample_material(const rk_scene *s, const rk_scene_sim *sim, int k, const rk_rkpm_points *pts, int i)
{
    int t0 = sim->object_first_tet[k], t1 = sim->object_first_tet[k + 1];
    if (pts->tet) return sim->materials[t0 + pts->tet[i]];
    if (pts->source && t1 > t0) { /* a mesh's vertex: the material of a tet around it */
        int v = sim->object_first_vertex[k] + pts->source[i];
        for (int t = t0; t < t1; t++)
            for (int a = 0; a < 4; a++)
                if (sim->mesh.tets[4 * t + a] == v) return sim->materials[t];
    }
    if (pts->source && t1 == t0) /* a point cloud's point: its tag too */
        return rk_scene_point_material(s, sim, k, sim->object_first_vertex[k] + pts->source[i]);
    return rk_scene_material_at(&s->objects[k], pts->X + 3 * (size_t)i);
}

int rk_scene_clouds(const rk_scene *s)
{
    int clouds = 0;
    for (int k = 0; k < s->nobjects; k++) clouds += s->objects[k].shape == RK_SHAPE_POINTS;
    return clouds;
}

/* The distinct tags of tag[from, to), for a message: "1, 3, 7" (the first 8), or "none". */
static void list_tags(const int *tag_of, int from, int to, char *buf, size_t size)
{
    int seen[8], n = 0, more = 0;
    for (int t = from; t < to; t++) {
        int tag = tag_of[t], j = 0;
        while (j < n && seen[j] != tag) j++;
        if (j < n) continue;
        if (n < 8) seen[n++] = tag;
        else more = 1;
    }
    if (n == 0 || (n == 1 && seen[0] == 0)) {
        snprintf(buf, size, "none (the file has no region tags)");
        return;
    }
    size_t used = 0;
    buf[0] = 0;
    for (int j = 0; j < n && used < size; j++)
        used += (size_t)snprintf(buf + used, size - used, "%s%d", j ? ", " : "", seen[j]);
    if (more && used < size) snprintf(buf + used, size - used, ", ...");
}

/* One material per tet: the object's, then each region in order where it selects the tet (its
 * centroid in the box, or its tag; the last one wins). A tag no tet of the object carries is
 * refused, naming the tags there are: a typo must not leave the object silently of one material. */
static int assign_materials(const rk_scene *s, rk_scene_sim *out, rk_error *err)
{
    const rk_mesh *m = &out->mesh;
    for (int k = 0; k < s->nobjects; k++) {
        const rk_scene_object *o = &s->objects[k];
        int cloud = out->object_first_tet[k + 1] == out->object_first_tet[k]; /* its points carry the tags */
        const int *tags = cloud ? out->point_tag : out->tet_tag;
        int from = cloud ? out->object_first_vertex[k] : out->object_first_tet[k];
        int to = cloud ? from + out->object_points[k] : out->object_first_tet[k + 1];
        for (int r = 0; r < o->nregions; r++) {
            int count = 0;
            for (int i = from; o->regions[r].by_tag && i < to; i++) count += tags[i] == o->regions[r].tag;
            if (o->regions[r].by_tag && count == 0) {
                char listed[160];
                list_tags(tags, from, to, listed, sizeof listed);
                return rk_fail(err, "%s: objects[%d].regions[%d]: no %s has tag %d (its tags: %s)", s->path, k, r,
                               cloud ? "point of the cloud" : "tet of the mesh", o->regions[r].tag, listed);
            }
        }
        for (int t = out->object_first_tet[k]; t < out->object_first_tet[k + 1]; t++) {
            double c[3] = {0, 0, 0};
            for (int a = 0; a < 4; a++)
                for (int i = 0; i < 3; i++) c[i] += 0.25 * m->X[3 * m->tets[4 * t + a] + i];
            out->materials[t] = rk_scene_region_material(o, c, 1, out->tet_tag[t]);
        }
    }
    return 0;
}

/* Prescribed groups: each "fixed"/"moving" box selects the object's vertices inside it. A vertex
 * claimed by an earlier group stays there (fixed entries come first). An empty selection is an error. */
static int build_prescribed(const rk_scene *s, rk_scene_sim *out, double slack, rk_error *err)
{
    int total = 0;
    for (int k = 0; k < s->nobjects; k++) total += s->objects[k].nmotions;
    rk_fom_options *opt = &out->options;
    opt->prescribed = rk_calloc((size_t)total, sizeof *opt->prescribed, err);
    char *claimed = rk_calloc((size_t)out->mesh.nv, 1, err);
    if (!opt->prescribed || !claimed) {
        free(claimed);
        return -1;
    }
    for (int k = 0; k < s->nobjects; k++) {
        const rk_scene_object *o = &s->objects[k];
        int v0 = out->object_first_vertex[k], v1 = out->object_first_vertex[k + 1];
        int nfixed = 0, nmoving = 0;
        for (int j = 0; j < o->nmotions; j++) {
            const rk_scene_motion *mo = &o->motions[j];
            int is_fixed = mo->kind == RK_MOTION_FIXED;
            int label = is_fixed ? nfixed++ : nmoving++;
            rk_prescribed *p = &opt->prescribed[opt->nprescribed];
            p->verts = rk_calloc((size_t)(v1 - v0), sizeof(int), err);
            if (!p->verts) {
                free(claimed);
                return -1;
            }
            opt->nprescribed++;
            double centroid[3] = {0, 0, 0};
            for (int v = v0; v < v1; v++) {
                if (claimed[v] || !rk_box_contains(&mo->box, &out->mesh.X[3 * v], slack)) continue;
                claimed[v] = 1;
                p->verts[p->count++] = v;
                for (int i = 0; i < 3; i++) centroid[i] += out->mesh.X[3 * v + i];
            }
            if (p->count == 0) {
                free(claimed);
                return rk_fail(err, "%s: objects[%d].%s[%d].box selects no vertex of the object", s->path, k,
                               is_fixed ? "fixed" : "moving", label);
            }
            p->kind = mo->kind;
            memcpy(p->axis, mo->axis, sizeof p->axis);
            memcpy(p->velocity, mo->velocity, sizeof p->velocity);
            p->rate = mo->rate;
            for (int i = 0; i < 3; i++) p->center[i] = mo->has_center ? mo->center[i] : centroid[i] / p->count;
        }
    }
    free(claimed);
    return 0;
}

/* Loads: a total force per box, shared among the selected vertices in proportion to their mass. */
static int build_loads_and_velocities(const rk_scene *s, rk_scene_sim *out, double slack, rk_error *err)
{
    int nv = out->mesh.nv;
    rk_fom_options *opt = &out->options;
    opt->force = rk_calloc(3 * (size_t)nv, sizeof(double), err);
    opt->velocity0 = rk_calloc(3 * (size_t)nv, sizeof(double), err);
    if (!opt->force || !opt->velocity0) return -1;
    for (int k = 0; k < s->nobjects; k++) {
        const rk_scene_object *o = &s->objects[k];
        int v0 = out->object_first_vertex[k], v1 = out->object_first_vertex[k + 1];
        for (int v = v0; v < v1; v++)
            for (int i = 0; i < 3; i++) opt->velocity0[3 * v + i] = o->velocity[i];
        for (int j = 0; j < o->nloads; j++) {
            double mass = 0;
            for (int v = v0; v < v1; v++)
                if (rk_box_contains(&o->loads[j].box, &out->mesh.X[3 * v], slack)) mass += out->fem.vertex_mass[v];
            if (!(mass > 0))
                return rk_fail(err, "%s: objects[%d].loads[%d].box selects no vertex of the object", s->path, k, j);
            for (int v = v0; v < v1; v++)
                if (rk_box_contains(&o->loads[j].box, &out->mesh.X[3 * v], slack))
                    for (int i = 0; i < 3; i++)
                        opt->force[3 * v + i] += o->loads[j].force[i] * out->fem.vertex_mass[v] / mass;
        }
    }
    return 0;
}

/* Chambers: each one's box selects the object's boundary faces whose centroid it holds (rk_chamber);
 * they must close a void (rk_chamber_check). */
static int build_chambers(const rk_scene *s, rk_scene_sim *out, double slack, rk_error *err)
{
    int n = 0;
    for (int k = 0; k < s->nobjects; k++) n += s->objects[k].nchambers;
    if (n == 0) return 0;
    int *tris = NULL, nf = 0, rc = -1;
    rk_chamber *ch = rk_calloc((size_t)n, sizeof *ch, err);
    out->chamber_name = rk_calloc((size_t)n, sizeof *out->chamber_name, err);
    if (!ch || !out->chamber_name) {
        free(ch);
        return -1;
    }
    out->options.chambers = ch;
    out->options.nchambers = n;
    if (rk_mesh_boundary(&out->mesh, &tris, &nf, err)) return -1;
    for (int k = 0, c = 0; k < s->nobjects; k++) {
        int v0 = out->object_first_vertex[k], v1 = out->object_first_vertex[k + 1];
        for (int j = 0; j < s->objects[k].nchambers; j++, c++) {
            const rk_scene_chamber *sc = &s->objects[k].chambers[j];
            snprintf(out->chamber_name[c], sizeof out->chamber_name[c], "%s", sc->name);
            ch[c].pressure = sc->pressure;
            ch[c].nkeys = sc->nkeys;
            ch[c].keys = sc->keys; /* the scene's: rk_fom_init copies them */
            if (!(ch[c].tris = rk_calloc(3 * (size_t)nf + 1, sizeof(int), err))) goto done;
            for (int t = 0; t < nf; t++) {
                const int *f = &tris[3 * t];
                double cen[3] = {0, 0, 0};
                for (int q = 0; q < 3; q++)
                    for (int i = 0; i < 3; i++) cen[i] += out->mesh.X[3 * f[q] + i] / 3;
                if (f[0] >= v0 && f[0] < v1 && rk_box_contains(&sc->box, cen, slack))
                    memcpy(&ch[c].tris[3 * ch[c].nf++], f, 3 * sizeof(int));
            }
            if (ch[c].nf == 0) {
                rk_fail(err, "%s: objects[%d].chambers[%d] (\"%s\"): its box holds no boundary face of the object "
                        "(a chamber is the walls of a void: mesh.voids)", s->path, k, j, sc->name);
                goto done;
            }
            if (rk_chamber_check(&ch[c], out->mesh.nv, err)) {
                rk_error_prefix(err, "%s: objects[%d].chambers[%d] (\"%s\"): %d faces", s->path, k, j, sc->name,
                                ch[c].nf);
                goto done;
            }
        }
    }
    rc = 0;
done:
    free(tris);
    return rc;
}

/* Obstacles: meshes loaded and placed, the contact options completed (dhat: 1e-3 of the rest
 * bounding-box diagonal unless given), and every vertex strictly on the free side of every plane
 * (the simulator checks every other intersection exactly when it starts). */
static int build_obstacles(const rk_scene *s, rk_scene_sim *out, double diag, rk_error *err)
{
    int n = s->nobstacles;
    rk_fom_options *opt = &out->options;
    out->obstacles = rk_calloc((size_t)n + 1, sizeof *out->obstacles, err);
    out->obstacle_meshes = rk_calloc((size_t)n + 1, sizeof *out->obstacle_meshes, err);
    if (!out->obstacles || !out->obstacle_meshes) return -1;
    opt->obstacles = out->obstacles;
    opt->nobstacles = n; /* before the meshes load, so a failure frees those that did */
    for (int k = 0; k < n; k++) {
        const rk_scene_obstacle *so = &s->obstacles[k];
        rk_obstacle *o = &out->obstacles[k];
        *o = so->shape;
        if (o->kind == RK_OBSTACLE_MESH) {
            rk_surface *m = &out->obstacle_meshes[k];
            if (rk_surface_load(so->file, m, err)) return rk_error_prefix(err, "%s: obstacles[%d].mesh", s->path, k);
            for (int v = 0; v < m->nv; v++)
                for (int i = 0; i < 3; i++) m->X[3 * v + i] = so->scale * m->X[3 * v + i] + so->translate[i];
            o->nv = m->nv;
            o->nf = m->nf;
            o->X = m->X;
            o->tris = m->tris;
        }
        if (o->kind != RK_OBSTACLE_PLANE) continue;
        for (int v = 0; v < out->mesh.nv; v++) {
            const double *x = &out->mesh.X[3 * v];
            double d = 0;
            for (int i = 0; i < 3; i++) d += (x[i] - o->point[i]) * o->normal[i];
            if (!(d > 0))
                return rk_fail(err, "%s: obstacles[%d]: vertex %d starts on or behind the plane (distance %g m)",
                               s->path, k, v, d);
        }
    }
    opt->contact = s->contact;
    if (opt->contact.dhat == 0) opt->contact.dhat = 1e-3 * diag;
    opt->nobjects = s->nobjects;
    opt->object_first_vertex = out->object_first_vertex;
    return 0;
}

/* The model of a scene with point clouds: the meshes' tets as elements (rk_fem_init's masses), each
 * cloud's n points weighing rho V / n with V its occupancy volume (rk_rkpm_sample_cloud), which the
 * penalty of pins and the scene's loads go by; a cloud's contact surface weighs nothing (a
 * mesh-free entry integrates the clouds' energy and mass). */
static int cloud_fem(const rk_scene *s, rk_scene_sim *out, rk_error *err)
{
    double *mass = rk_calloc((size_t)out->mesh.nv, sizeof(double), err);
    if (!mass) return -1;
    for (int k = 0; k < s->nobjects; k++) {
        if (s->objects[k].shape != RK_SHAPE_POINTS) continue;
        rk_rkpm_points pts;
        int v0 = out->object_first_vertex[k], n = out->object_points[k];
        if (rk_rkpm_sample_cloud(out->mesh.X + 3 * (size_t)v0, n, n, &pts, err)) {
            free(mass);
            return rk_error_prefix(err, "%s: objects[%d].mesh.points", s->path, k);
        }
        for (int v = v0; v < v0 + n; v++)
            mass[v] = rk_scene_point_material(s, out, k, v).density * pts.volume / n;
        rk_rkpm_points_free(&pts);
    }
    int rc = rk_fem_init_points(&out->fem, &out->mesh, out->materials, mass, err);
    free(mass);
    return rc;
}

static void free_bodies(rk_cloud_body *bodies, int n)
{
    for (int k = 0; bodies && k < n; k++) rk_cloud_body_free(&bodies[k]);
    free(bodies);
}

/* full_order: each point cloud as its body (build_body.c), the scene's own vertices in out->layout */
static int scene_build(const rk_scene *s, rk_scene_sim *out, int full_order, rk_error *err)
{
    memset(out, 0, sizeof *out);
    rk_cloud_body *bodies = NULL;
    out->object_first_vertex = rk_calloc((size_t)s->nobjects + 1, sizeof(int), err);
    out->object_first_tet = rk_calloc((size_t)s->nobjects + 1, sizeof(int), err);
    if (!out->object_first_vertex || !out->object_first_tet) goto fail;
    int clouds = rk_scene_clouds(s);
    if (full_order && clouds) {
        if (!(bodies = rk_calloc((size_t)s->nobjects, sizeof *bodies, err))) goto fail;
        clouds = 0; /* every object has tets */
    }
    if (clouds && !(out->object_points = rk_calloc((size_t)s->nobjects, sizeof(int), err))) goto fail;
    rk_mesh_report repaired = {0}; /* what the objects' own checks changed */
    int caged = 0;
    for (int k = 0; k < s->nobjects; k++) caged += s->objects[k].cage_tets > 0;
    if (caged && (clouds || bodies)) {
        rk_fail(err, "%s: a scene with a caged object (mesh.cage) has no point cloud, for now", s->path);
        goto fail;
    }
    rk_surface *surfaces = caged ? rk_calloc((size_t)s->nobjects, sizeof *surfaces, err) : NULL;
    if (caged && !surfaces) goto fail;
    for (int k = 0; k < s->nobjects; k++) {
        rk_mesh m;
        rk_mesh_report rep;
        int points = 0, *point_tag = NULL;
        if (load_object_mesh(&s->objects[k], k, &m, &rep, &points, &point_tag, caged ? &surfaces[k] : NULL, &out->cage,
                             bodies ? &bodies[k] : NULL, err)) {
            rk_error_prefix(err, "%s: objects[%d].mesh", s->path, k);
            free_surfaces(surfaces, s->nobjects);
            goto fail;
        }
        if (caged) transform_surface(&surfaces[k], s->objects[k].scale, s->objects[k].translate);
        if (bodies) rk_cloud_body_place(&bodies[k], s->objects[k].scale, s->objects[k].translate);
        repaired.reoriented += rep.reoriented;
        repaired.unused_removed += rep.unused_removed;
        repaired.flat_dropped += rep.flat_dropped;
        repaired.ghosts += rep.ghosts;
        repaired.orphans_removed += rep.orphans_removed;
        rk_mesh_transform(&m, s->objects[k].scale, s->objects[k].translate);
        if (rk_mesh_carve(&m, s->objects[k].voids, s->objects[k].nvoids, err)) {
            rk_error_prefix(err, "%s: objects[%d].mesh.voids", s->path, k);
            rk_mesh_free(&m);
            free(point_tag);
            free_surfaces(surfaces, s->nobjects);
            goto fail;
        }
        int rc = append_tags(out, &m, point_tag, points, err) || append_mesh(&out->mesh, &m, err);
        rk_mesh_free(&m);
        free(point_tag);
        if (rc) {
            free_surfaces(surfaces, s->nobjects);
            goto fail;
        }
        out->object_first_vertex[k + 1] = out->mesh.nv;
        if (out->object_points) out->object_points[k] = points;
        out->cloud_points += points;
        out->object_first_tet[k + 1] = out->mesh.nt;
    }
    /* Each object was checked (and its flat tets dropped) on its own, before its vertices were
     * numbered in the scene: this check of the whole measures it and drops nothing, which would
     * renumber the vertices the objects own. A point cloud has no tets to check, and its points
     * belong to none: a scene with a cloud is not checked whole (each mesh was, on its own). */
    int cloud = clouds > 0;
    if (!cloud && rk_mesh_check(&out->mesh, s->path, RK_MESH_KEEP_FLAT, &out->mesh_report, err)) {
        free_surfaces(surfaces, s->nobjects);
        goto fail;
    }
    if (caged) {
        int rc = 0;
        for (int k = 0; k < s->nobjects && rc == 0; k++)
            if (!s->objects[k].cage_tets) rc = boundary_surface(out, k, &surfaces[k], err);
        if (rc == 0) rc = embed_surfaces(s, surfaces, out, err);
        free_surfaces(surfaces, s->nobjects);
        if (rc) goto fail;
    }
    out->mesh_report.reoriented += repaired.reoriented;
    out->mesh_report.unused_removed += repaired.unused_removed;
    out->mesh_report.flat_dropped += repaired.flat_dropped;
    out->mesh_report.ghosts += repaired.ghosts;
    out->mesh_report.orphans_removed += repaired.orphans_removed;
    out->materials = rk_calloc((size_t)out->mesh.nt, sizeof(rk_material), err);
    if (!out->materials) goto fail;
    if (assign_materials(s, out, err)) goto fail;
    if (bodies && (rk_cloud_bodies_finish(s, bodies, out, err) || rk_cloud_contact_surface(s, bodies, out, err)))
        goto fail;
    if (cloud ? cloud_fem(s, out, err) : rk_fem_init(&out->fem, &out->mesh, out->materials, err)) goto fail;

    rk_fom_options *opt = &out->options;
    rk_fom_default_options(opt);
    opt->h = s->h;
    out->steps = (int)floor(s->duration / s->h + 0.5);
    opt->steps = out->steps;
    opt->integrator = s->integrator;
    opt->is_static = s->is_static;
    opt->lumped_mass = s->lumped_mass;
    memcpy(opt->gravity, s->gravity, sizeof opt->gravity);
    opt->rayleigh_mass = s->damping_mass;
    opt->rayleigh_stiffness = s->damping_stiffness;
    if (s->newton_tol > 0) opt->newton_tol = s->newton_tol;
    if (s->newton_max_iter > 0) opt->newton_max_iter = s->newton_max_iter;
    double diag = rk_points_diagonal(out->mesh.X, out->mesh.nv);
    double slack = 1e-9 * diag; /* a box edge on a vertex layer selects that layer */
    if (build_prescribed(s, out, slack, err)) goto fail;
    if (build_loads_and_velocities(s, out, slack, err)) goto fail;
    if (build_obstacles(s, out, diag, err)) goto fail;
    if (build_chambers(s, out, slack, err)) goto fail;
    if (out->contact.mesh.nv) opt->contact_surface = &out->contact;
    free_bodies(bodies, s->nobjects);
    return 0;
fail:
    free_bodies(bodies, s->nobjects);
    rk_scene_sim_free(out);
    return -1;
}

int rk_scene_build(const rk_scene *s, rk_scene_sim *out, rk_error *err) { return scene_build(s, out, 0, err); }

int rk_scene_build_full_order(const rk_scene *s, rk_scene_sim *out, rk_error *err)
{
    return scene_build(s, out, 1, err);
}

int rk_scene_object_view(const rk_scene_sim *sim, int k, rk_object_view *ov, rk_error *err)
{
    memset(ov, 0, sizeof *ov);
    ov->v0 = sim->object_first_vertex[k];
    ov->t0 = sim->object_first_tet[k];
    ov->mesh.nv = sim->object_first_vertex[k + 1] - ov->v0;
    ov->mesh.nt = sim->object_first_tet[k + 1] - ov->t0;
    ov->mesh.X = sim->mesh.X + 3 * (size_t)ov->v0;
    ov->points = sim->object_points ? sim->object_points[k] : 0;
    ov->mesh.tets = rk_calloc(4 * (size_t)ov->mesh.nt + 1, sizeof(int), err);
    if (!ov->mesh.tets) return -1;
    for (size_t i = 0; i < 4 * (size_t)ov->mesh.nt; i++) ov->mesh.tets[i] = sim->mesh.tets[4 * (size_t)ov->t0 + i] - ov->v0;
    return 0;
}

void rk_scene_sim_free(rk_scene_sim *out)
{
    rk_fem_free(&out->fem);
    rk_mesh_free(&out->mesh);
    free(out->materials);
    free(out->tet_tag);
    free(out->point_tag);
    for (int i = 0; i < out->options.nprescribed; i++) free(out->options.prescribed[i].verts);
    free(out->options.prescribed);
    free(out->options.force);
    for (int c = 0; out->options.chambers && c < out->options.nchambers; c++)
        free(out->options.chambers[c].tris);
    free((rk_chamber *)out->options.chambers);
    free(out->chamber_name);
    free(out->options.velocity0);
    for (int k = 0; out->obstacle_meshes && k < out->options.nobstacles; k++) rk_surface_free(&out->obstacle_meshes[k]);
    free(out->obstacle_meshes);
    free(out->obstacles);
    free(out->object_first_vertex);
    free(out->object_first_tet);
    free(out->object_points);
    free(out->embedded.X);
    free(out->embedded.tris);
    free(out->embedded.tet);
    free(out->embedded.bary);
    free(out->embedded_first);
    free(out->layout.vertex);
    free(out->layout.weight);
    free(out->layout.offset);
    rk_mesh_free(&out->contact.mesh);
    free((int *)out->contact.vertex);
    free((double *)out->contact.weight);
    free((double *)out->contact.offset);
    free((int *)out->contact.object_first_vertex);
    memset(out, 0, sizeof *out);
}

int rk_scene_build_reference(const rk_scene *s, const rk_scene_sim *sim, int levels, rk_scene_sim *out, int **map,
                             rk_error *err)
{
    memset(out, 0, sizeof *out);
    *map = NULL;
    rk_scene fine = *s; /* shares everything but the objects, which differ in their refine */
    fine.objects = rk_calloc((size_t)s->nobjects, sizeof *fine.objects, err);
    if (!fine.objects) return -1;
    for (int k = 0; k < s->nobjects; k++) {
        fine.objects[k] = s->objects[k];
        fine.objects[k].refine += levels;
    }
    int rc = rk_scene_build(&fine, out, err);
    free(fine.objects);
    if (rc) return rk_error_prefix(err, "reference (refine %d)", levels);
    int *m = rk_calloc((size_t)sim->mesh.nv + 1, sizeof *m, err);
    if (!m) goto fail;
    for (int k = 0; k < s->nobjects; k++) {
        int first = sim->object_first_vertex[k], n = sim->object_first_vertex[k + 1] - first;
        int fine_first = out->object_first_vertex[k];
        if (out->object_first_vertex[k + 1] - fine_first < n) {
            rk_fail(err, "reference (refine %d): objects[%d] has %d vertices refined, fewer than its %d", levels, k,
                    out->object_first_vertex[k + 1] - fine_first, n);
            goto fail;
        }
        for (int i = 0; i < n; i++) {
            const double *a = sim->mesh.X + 3 * (size_t)(first + i), *b = out->mesh.X + 3 * (size_t)(fine_first + i);
            if (a[0] != b[0] || a[1] != b[1] || a[2] != b[2]) {
                rk_fail(err, "reference (refine %d): objects[%d] vertex %d at (%g, %g, %g) is the refined mesh's "
                             "vertex %d at (%g, %g, %g): the refined mesh's check renumbered the vertices, so the "
                             "errors cannot be taken at the scene mesh's vertices", levels, k, i, a[0], a[1], a[2],
                        i, b[0], b[1], b[2]);
                goto fail;
            }
            m[first + i] = fine_first + i;
        }
    }
    *map = m;
    return 0;
fail:
    free(m);
    rk_scene_sim_free(out);
    return -1;
}
