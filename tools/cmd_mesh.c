/* romkit mesh IN -o OUT [--quality Q] [--max-volume V] [--cage-tets N] [--refine N] [--quiet]
 *
 * A tet mesh in (.msh .mesh .node/.ele .vtk) is checked, repaired and converted to OUT's
 * format; a surface in (.obj .off .stl .ply .gltf .glb) is checked (flipped if merely inside out) and
 * tetrahedralized with tetgen, or with --cage-tets N a simulation cage of at most N tets is made
 * around it (precompute/cage: simplified, tetrahedralized, its boundary moved out, every surface
 * vertex located; those outside reported). --refine N then splits every tet into 8, N times
 * (rk_mesh_refine), and checks the result again. A summary goes to stdout unless --quiet. A
 * conversion never drops a tet: slivers and flat tets are written as they are and listed in the
 * summary (a simulation drops the flat ones, with a warning; mesh/mesh.h).
 * argv[0] is the subcommand name, as romkit's main passes it. Returns the exit code:
 * 0 done, 1 failed ("romkit mesh: <message>" on stderr), 2 bad usage. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "cage/cage.h"
#include "mesh/mesh.h"
#include "util/util.h"

int cmd_mesh(int argc, char **argv);

static void usage(FILE *out)
{
    fprintf(out,
            "usage: romkit mesh IN -o OUT [--quality Q] [--max-volume V] [--cage-tets N] [--refine N] [--quiet]\n"
            "\n"
            "Checks a tetrahedral mesh and converts it, or tetrahedralizes a closed surface.\n"
            "  IN    tet mesh: .msh (Gmsh 2.2/4.1), .mesh (MEDIT), .node/.ele (TetGen), .vtk\n"
            "        surface:  .obj .off .stl .ply .gltf .glb (closed, manifold; tetrahedralized with tetgen;\n"
            "                  glTF: every triangle primitive of the default scene, node transforms applied)\n"
            "  OUT   .msh .mesh .node .vtk (tets), or .obj .ply .off .stl (boundary surface)\n"
            "  --quality Q      surface input: radius-edge bound for tetgen -q (default 1.4, >= 1)\n"
            "  --max-volume V   surface input: largest tet volume, in the surface's units cubed\n"
            "  --cage-tets N    surface input: instead of filling the surface, a coarse cage of at\n"
            "                   most N tets around it (simplified with meshoptimizer, offset outward\n"
            "                   until every surface vertex is inside, tetrahedralized; N >= 100)\n"
            "  --refine N       split every tet into 8 at its edge midpoints, N times (0 to 4;\n"
            "                   8^N times the tets, at most 16,777,216)\n"
            "  --quiet          print nothing on success\n"
            "\n"
            "Inverted tets are flipped and unused vertices dropped; every tet is written, slivers\n"
            "(near-zero volume) and flat tets (volume at rounding level) too, listed in the summary\n"
            "(a simulation keeps slivers and drops flat tets with a warning). A tet that uses a\n"
            "vertex twice or a missing one is an error.\n"
            "Exit status 1 when the mesh is unusable, 2 on bad usage.\n"
            "\n"
            "example:\n"
            "  romkit mesh tests/data/meshes/decimated-knight.off -o knight.msh --quality 1.4\n"
            "  romkit mesh tests/data/meshes/bunny_19k.msh -o bunny.vtk\n"
            "  romkit mesh tests/data/meshes/spot.obj -o spot_cage.msh --cage-tets 2000\n"
            "  romkit mesh tests/data/meshes/dinosaur_bin.msh -o dinosaur_400k.msh --refine 1\n");
}

static int usage_error(const char *what, const char *arg)
{
    fprintf(stderr, "romkit mesh: %s%s%s (see romkit mesh --help)\n", what, arg ? " " : "", arg ? arg : "");
    return 2;
}

/* 1 when path ends in one of the space-separated extensions (case-insensitive). */
static int has_ext(const char *path, const char *list)
{
    const char *dot = strrchr(path, '.');
    if (!dot || strchr(dot, '/')) return 0;
    size_t n = strlen(dot);
    for (const char *e = list; *e; e += strcspn(e, " "), e += *e == ' ') {
        size_t len = strcspn(e, " ");
        if (len != n) continue;
        size_t i = 0;
        while (i < n && tolower((unsigned char)dot[i]) == e[i]) i++;
        if (i == n) return 1;
    }
    return 0;
}

/* what rk_mesh_write writes as a surface (glTF is read, not written, here) */
static int is_surface(const char *path) { return has_ext(path, ".obj .off .stl .ply"); }

/* Slivers and flat tets, kept by the conversion: how many, under which thresholds, the first few. */
static void slivers(const rk_mesh_report *rep)
{
    printf("  slivers      %d (volume <= %.3g = %g x bounding-box diagonal^3, or flat; written as they are)\n",
           rep->slivers, rep->sliver_volume, RK_MESH_SLIVER);
    printf("  flat         %d (thickness <= %.3g x the tet's size: no rest shape, dropped when simulated)\n", rep->flat,
           RK_MESH_FLAT);
    for (int i = 0; i < rep->nlisted; i++) {
        const rk_mesh_sliver *l = &rep->listed[i];
        printf("    tet %d (vertices %d %d %d %d) volume %.3g%s\n", l->tet, l->v[0], l->v[1], l->v[2], l->v[3],
               l->volume, l->flat ? " flat" : "");
    }
    if (rep->slivers > rep->nlisted) printf("    ... %d more\n", rep->slivers - rep->nlisted);
}

static void summary(const char *in, const char *out, const rk_mesh *m, const rk_mesh_report *rep)
{
    double total = 0;
    for (int t = 0; t < m->nt; t++) {
        const int *v = m->tets + 4 * t;
        total += rk_tet_signed_volume(m->X + 3 * v[0], m->X + 3 * v[1], m->X + 3 * v[2], m->X + 3 * v[3]);
    }
    printf("%s -> %s\n", in, out);
    printf("  vertices     %d\n", m->nv);
    printf("  tetrahedra   %d\n", m->nt);
    printf("  reoriented   %d (inverted tets flipped)\n", rep->reoriented);
    printf("  unused       %d (vertices in no tet, removed)\n", rep->unused_removed);
    printf("  components   %d\n", rep->components);
    printf("  quality      min %.4g, mean %.4g (radius ratio; 1 = regular tet)\n", rep->min_quality, rep->mean_quality);
    printf("  volume       min %.4g, max %.4g, total %.6g\n", rep->min_volume, rep->max_volume, total);
    printf("  bounding box (%.6g, %.6g, %.6g) - (%.6g, %.6g, %.6g)\n", rep->bbox_min[0], rep->bbox_min[1],
           rep->bbox_min[2], rep->bbox_max[0], rep->bbox_max[1], rep->bbox_max[2]);
    slivers(rep);
}

/* The cage around s: made, its fit said (every vertex inside, or how many are not). */
static int cage_surface(const char *in, const rk_surface *s, double quality, int max_tets, int quiet, rk_mesh *m,
                        rk_error *err)
{
    rk_cage_options o = {.max_tets = max_tets, .quality = quality};
    rk_cage_report rep;
    if (rk_cage_build(s, &o, m, &rep, err)) return -1;
    if (rep.outside)
        fprintf(stderr, "romkit mesh: warning: %d of %d surface vertices of %s are outside the cage (the farthest %.3g "
                        "away); a simulation embeds them in the nearest tet\n", rep.outside, s->nv, in, rep.worst_distance);
    if (!quiet)
        printf("%s: cage of %d tets (at most %d) over a %d-triangle simplification (meshopt error %.3g), %d tetgen "
               "run%s; boundary moved out by up to %.3g in %d round%s; %d of %d surface vertices inside\n", in, rep.tets,
               max_tets, rep.triangles, rep.simplify_error, rep.tetgen_runs, rep.tetgen_runs == 1 ? "" : "s",
               rep.max_offset, rep.inflate_rounds, rep.inflate_rounds == 1 ? "" : "s", s->nv - rep.outside, s->nv);
    return 0;
}

/* Loads the surface, orients it and fills it with tets (or a cage of at most cage_tets). */
static int tetrahedralize_file(const char *in, double quality, double max_volume, int cage_tets, int quiet, rk_mesh *m,
                               rk_error *err)
{
    rk_surface s;
    int flipped = 0;
    if (rk_surface_load(in, &s, err) || rk_surface_check_and_orient(&s, in, &flipped, err)) {
        rk_surface_free(&s);
        return -1;
    }
    if (!quiet) {
        printf("%s: surface with %d vertices, %d triangles, enclosed volume %.6g\n", in, s.nv, s.nf, rk_surface_volume(&s));
        if (flipped) printf("  the surface was inside out: every face was reversed\n");
    }
    int rc = cage_tets ? cage_surface(in, &s, quality, cage_tets, quiet, m, err)
                       : rk_tetrahedralize(&s, quality, max_volume, m, err);
    rk_surface_free(&s);
    return rc;
}

int cmd_mesh(int argc, char **argv)
{
    const char *in = NULL, *out = NULL;
    double quality = 0, max_volume = 0;
    int quiet = 0, surface_options = 0, levels = 0, cage_tets = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "-o") == 0) {
            if (++i == argc) return usage_error("-o needs a file name", NULL);
            out = argv[i];
        } else if (strcmp(a, "--quality") == 0) {
            if (++i == argc || cli_real(argv[i], -INFINITY, INFINITY, &quality) || quality < 1.0)
                return usage_error("--quality needs a number >= 1, got", i < argc ? argv[i] : "nothing");
            surface_options = 1;
        } else if (strcmp(a, "--max-volume") == 0) {
            if (++i == argc || cli_real(argv[i], -INFINITY, INFINITY, &max_volume) || max_volume <= 0)
                return usage_error("--max-volume needs a positive number, got", i < argc ? argv[i] : "nothing");
            surface_options = 1;
        } else if (strcmp(a, "--cage-tets") == 0) {
            long n;
            if (++i == argc || cli_whole(argv[i], RK_CAGE_MIN_TETS, 1L << 24, &n))
                return usage_error("--cage-tets needs a whole number of tets from 100 to 16777216, got",
                                   i < argc ? argv[i] : "nothing");
            cage_tets = (int)n;
            surface_options = 1;
        } else if (strcmp(a, "--refine") == 0) {
            long n;
            if (++i == argc || cli_whole(argv[i], 0, RK_MESH_REFINE_MAX_LEVELS, &n))
                return usage_error("--refine needs a whole number of levels from 0 to 4, got", i < argc ? argv[i] : "nothing");
            levels = (int)n;
        } else if (strcmp(a, "--quiet") == 0) {
            quiet = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            return usage_error("unknown option", a);
        } else if (!in) {
            in = a;
        } else {
            return usage_error("more than one input:", a);
        }
    }
    if (!in) return usage_error("no input mesh given", NULL);
    if (!out) return usage_error("no output given (-o OUT)", NULL);
    if (!is_surface(out) && !has_ext(out, ".msh .mesh .node .ele .vtk"))
        return usage_error("unknown output format (use .msh .mesh .node .vtk .obj .ply .off .stl):", out);
    if (surface_options && !rk_path_is_surface(in))
        return usage_error("--quality, --max-volume and --cage-tets apply to surface input only, not", in);
    if (cage_tets && max_volume > 0)
        return usage_error("--max-volume and --cage-tets do not go together (the cage picks its own volume bound)", NULL);
    rk_progress_set_quiet(quiet);

    rk_error err;
    rk_mesh m = {0};
    rk_mesh_report rep;
    int rc = rk_path_is_surface(in) ? tetrahedralize_file(in, quality, max_volume, cage_tets, quiet, &m, &err) ||
                                  rk_mesh_check(&m, "tetgen output", RK_MESH_KEEP_FLAT, &rep, &err)
                            : rk_mesh_load(in, RK_MESH_KEEP_FLAT, &m, &rep, &err);
    if (rc == 0 && levels > 0) {
        rk_mesh fine;
        double t0 = rk_now();
        rc = rk_mesh_refine(&m, levels, &fine, &err);
        if (rc == 0) {
            if (!quiet)
                printf("%s: refined %d time%s: %d -> %d tets, %d -> %d vertices in %.3g s\n", in, levels,
                       levels > 1 ? "s" : "", m.nt, fine.nt, m.nv, fine.nv, rk_now() - t0);
            rk_mesh_free(&m);
            m = fine;
            /* the summary is the refined mesh's: checked again, converting (nothing dropped); the
             * repairs of the input's check are kept in it */
            rk_mesh_report before = rep;
            rc = rk_mesh_check(&m, "refined mesh", RK_MESH_KEEP_FLAT, &rep, &err);
            rep.reoriented += before.reoriented;
            rep.unused_removed += before.unused_removed;
        }
    }
    if (rc == 0) rc = rk_mesh_write(out, &m, NULL, &err);
    if (rc) {
        fprintf(stderr, "romkit mesh: %s\n", err.msg);
        rk_mesh_free(&m);
        return 1;
    }
    if (!quiet) summary(in, out, &m, &rep);
    rk_mesh_free(&m);
    return 0;
}
