/* How well a surface carried by a cage moves (issue 32): a cantilever small enough to run at full
 * order both ways. The fine mesh is a box of 60 x 6 x 6 cells (12,960 tets); its boundary surface,
 * written as an OBJ, is caged (mesh.cage, at most 6,000 tets: 4,687) and embedded. Both run at full
 * order; the embedded surface's motion (the cage's solution at each surface vertex's barycentrics)
 * is compared with the fine mesh's own at the same vertices, beside the cage's own end:
 *   static sag under gravity: the cage's end within 10% of the fine mesh's (measured -7.6%, the
 *     carried surface's the same; a plain 40 x 4 x 4 box of 3,840 tets sags 11% less than the fine
 *     mesh: linear tets are stiff in bending when coarse, and that, not the embedding, is most of it;
 *     the cage's margin, 0.05% of the diagonal on each side, thickens the beam by 1% and stiffens
 *     it by 2%);
 *   a dynamic run (30 steps of 0.01 s from rest, about 1.5 periods of the first bending mode):
 *     the relative error over the run of the embedded surface against the fine mesh (measured
 *     0.097), and of the cage's own end (0.088); both must stay below 0.15. */
#include "scene_run.h"

#define LEN 1.0
#define SIDE 0.1
#define CAGE_TETS 6000

static const char *material = "\"material\": {\"model\": \"neohookean\", \"young\": 1e8, \"poisson\": 0.3, \"density\": 1000}";

/* The scene JSON for a mesh key, static or 30 steps. */
static void scene_json(char *out, size_t cap, const char *mesh, int dynamic)
{
    snprintf(out, cap,
             "{\"objects\": [{\"mesh\": %s, %s, \"fixed\": [{\"box\": [[-1, -1, -1], [0, 1, 1]]}]}],"
             " \"gravity\": [0, -9.81, 0], \"time\": %s}",
             mesh, material, dynamic ? "{\"step\": 0.01, \"duration\": 0.3}" : "{\"static\": true}");
}

typedef struct {
    scene_run fine, cage;
    int n;          /* surface vertices */
    int *fine_of;   /* surface vertex -> fine mesh vertex at the same rest position */
} beam_pair;

static int pair_open(beam_pair *p, int dynamic, rk_error *err)
{
    memset(p, 0, sizeof *p);
    static char obj[512];
    char mesh[700], json[2048];
    double size[3] = {LEN, SIDE, SIDE};
    int cells[3] = {60, 6, 6};
    rk_mesh box;
    if (rk_mesh_box(size, cells, &box, err)) return -1;
    tl_scratch(obj, sizeof obj, "cage_beam.obj");
    int rc = rk_mesh_write(obj, &box, NULL, err); /* .obj: the boundary surface */
    rk_mesh_free(&box);
    if (rc) return -1;
    snprintf(mesh, sizeof mesh, "{\"box\": {\"size\": [%g, %g, %g], \"cells\": [60, 6, 6]}}", LEN, SIDE, SIDE);
    scene_json(json, sizeof json, mesh, dynamic);
    if (scene_run_open(&p->fine, json, err)) return -1;
    snprintf(mesh, sizeof mesh, "{\"file\": \"%s\", \"cage\": {\"max_tets\": %d}}", obj, CAGE_TETS);
    scene_json(json, sizeof json, mesh, dynamic);
    rc = scene_run_open(&p->cage, json, err);
    remove(obj);
    if (rc) return -1;
    const rk_embedded_surface *E = &p->cage.sim.embedded;
    p->n = E->nv;
    p->fine_of = calloc((size_t)E->nv, sizeof(int));
    if (!p->fine_of) return rk_fail(err, "out of memory");
    const rk_mesh *F = &p->fine.sim.mesh;
    for (int i = 0; i < E->nv; i++) {
        p->fine_of[i] = -1;
        for (int v = 0; v < F->nv && p->fine_of[i] < 0; v++)
            if (memcmp(F->X + 3 * v, E->X + 3 * i, 3 * sizeof(double)) == 0) p->fine_of[i] = v;
        if (p->fine_of[i] < 0) return rk_fail(err, "surface vertex %d is no fine mesh vertex", i);
    }
    return 0;
}

static void pair_close(beam_pair *p)
{
    scene_run_close(&p->fine);
    scene_run_close(&p->cage);
    free(p->fine_of);
}

/* The embedded surface vertex i's displacement from the cage's state. */
static void embedded_u(const beam_pair *p, int i, double *u)
{
    const rk_embedded_surface *E = &p->cage.sim.embedded;
    const int *t = p->cage.sim.mesh.tets + 4 * E->tet[i];
    const double *x = p->cage.fom.x, *X = p->cage.sim.mesh.X;
    for (int a = 0; a < 3; a++) {
        u[a] = 0;
        for (int k = 0; k < 4; k++) u[a] += E->bary[4 * i + k] * (x[3 * t[k] + a] - X[3 * t[k] + a]);
    }
}

/* Mean downward displacement of the vertices at x >= LEN - slack (the free end). */
static double end_sag(const scene_run *r, double slack)
{
    double sum = 0;
    int n = 0;
    for (int v = 0; v < r->sim.mesh.nv; v++)
        if (r->sim.mesh.X[3 * v] >= LEN - slack) sum += r->sim.mesh.X[3 * v + 1] - r->fom.x[3 * v + 1], n++;
    return n ? sum / n : NAN;
}

/* The embedded surface's mean downward displacement at the free end face. */
static double embedded_end_sag(const beam_pair *p)
{
    double sum = 0, u[3];
    int n = 0;
    for (int i = 0; i < p->n; i++)
        if (p->cage.sim.embedded.X[3 * i] >= LEN - 1e-9) embedded_u(p, i, u), sum -= u[1], n++;
    return sum / n;
}

TEST(cage_sags_like_the_fine_mesh)
{
    rk_error err;
    beam_pair p;
    int rc = pair_open(&p, 0, &err);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(p.cage.sim.mesh.nt <= CAGE_TETS && p.cage.sim.embedded_outside == 0, "cage of %d tets, %d vertices outside",
          p.cage.sim.mesh.nt, p.cage.sim.embedded_outside);
    rc = rk_fom_static(&p.fine.fom, &err) || rk_fom_static(&p.cage.fom, &err);
    if (rc) pair_close(&p);
    CHECK(rc == 0, "static solve: %s", err.msg);
    /* the cage's end face is its vertices beyond the surface's end (the offset moves it out) */
    double fine = end_sag(&p.fine, 1e-9), cage = end_sag(&p.cage, 0), carried = embedded_end_sag(&p);
    printf("# cantilever %g x %g x %g m, fine %d tets, cage %d tets (%d vertices): end sag fine %.5e m, cage's own end "
           "%.5e m (%+.1f%%), the surface it carries %.5e m (%+.1f%%)\n", LEN, SIDE, SIDE, p.fine.sim.mesh.nt,
           p.cage.sim.mesh.nt, p.cage.sim.mesh.nv, fine, cage, 100 * (cage / fine - 1), carried, 100 * (carried / fine - 1));
    pair_close(&p);
    CHECK(fabs(cage / fine - 1) < 0.10, "the cage's sag is %.1f%% off the fine mesh's", 100 * (cage / fine - 1));
    CHECK(fabs(carried / fine - 1) < 0.10, "the carried surface's sag is %.1f%% off", 100 * (carried / fine - 1));
}

TEST(embedded_surface_follows_the_fine_motion)
{
    rk_error err;
    beam_pair p;
    int rc = pair_open(&p, 1, &err);
    CHECK(rc == 0, "%s", err.msg);
    double num = 0, den = 0, tip_num = 0, tip_den = 0;
    for (int step = 0; step < p.fine.sim.steps && rc == 0; step++) {
        rc = rk_fom_step(&p.fine.fom, &err) || rk_fom_step(&p.cage.fom, &err);
        for (int i = 0; i < p.n && rc == 0; i++) {
            double u[3];
            embedded_u(&p, i, u);
            const double *xf = p.fine.fom.x + 3 * p.fine_of[i], *Xf = p.fine.sim.mesh.X + 3 * p.fine_of[i];
            for (int a = 0; a < 3; a++) {
                double uf = xf[a] - Xf[a];
                num += (u[a] - uf) * (u[a] - uf);
                den += uf * uf;
            }
        }
        double ft = end_sag(&p.fine, 1e-9), ct = end_sag(&p.cage, 0);
        tip_num += (ct - ft) * (ct - ft);
        tip_den += ft * ft;
    }
    pair_close(&p);
    CHECK(rc == 0, "step: %s", err.msg);
    double e_surface = sqrt(num / den), e_tip = sqrt(tip_num / tip_den);
    printf("# 30 steps of 0.01 s from rest: the embedded surface's displacement against the fine mesh's at the same "
           "vertices, relative error %.3f over the run; the cage's own end against the fine end %.3f\n",
           e_surface, e_tip);
    CHECK(e_surface < 0.15 && e_tip < 0.15, "errors %.3f (surface) and %.3f (the cage's end)", e_surface, e_tip);
}

int main(void)
{
    RUN(cage_sags_like_the_fine_mesh);
    RUN(embedded_surface_follows_the_fine_motion);
    return test_finish();
}
