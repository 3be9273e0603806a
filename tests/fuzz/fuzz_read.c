/* libFuzzer entry points for the precompute's readers of outside files: one binary per reader,
 * chosen at compile time by -DFUZZ_READ_<NAME> (fuzz.mk builds fuzz-read-<name> for each):
 *   GMSH MEDIT VTK   rk_mesh_load on a .msh / .mesh / .vtk file (then rk_mesh_check)
 *   TETGEN           rk_mesh_load on a .node + .ele pair: the input is the .node text, a line
 *                    "@@ele" and the .ele text (no such line: the .ele is empty)
 *   OBJ OFF STL PLY  rk_surface_load, then rk_surface_check on what loaded
 *   GLTF             the same on a .gltf (JSON, data: URIs; a GLB's bytes are read by their magic)
 *   SPLATS           rk_splats_read (3DGS PLY)
 *   POINTS           rk_points_load (a PLY point cloud)
 *   SCENE            rk_scene_parse on the text (a scene's JSON; files it names are not read)
 * The readers take paths, so each input is written to a file in a private directory first. Besides
 * what ASan/UBSan catch, a broken contract traps: a failure with an empty message, or a success
 * whose result breaks what the header promises (indices out of range, a count below zero). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h> /* rmdir, unlink */

#include "mesh/mesh.h"
#if defined(FUZZ_READ_SCENE)
#include "pipeline/pipeline.h"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#if defined(FUZZ_READ_GMSH)
#define FUZZ_EXT ".msh"
#elif defined(FUZZ_READ_MEDIT)
#define FUZZ_EXT ".mesh"
#elif defined(FUZZ_READ_VTK)
#define FUZZ_EXT ".vtk"
#elif defined(FUZZ_READ_TETGEN)
#define FUZZ_EXT ".node"
#elif defined(FUZZ_READ_OBJ)
#define FUZZ_EXT ".obj"
#elif defined(FUZZ_READ_OFF)
#define FUZZ_EXT ".off"
#elif defined(FUZZ_READ_STL)
#define FUZZ_EXT ".stl"
#elif defined(FUZZ_READ_GLTF)
#define FUZZ_EXT ".gltf"
#elif defined(FUZZ_READ_PLY) || defined(FUZZ_READ_SPLATS) || defined(FUZZ_READ_POINTS)
#define FUZZ_EXT ".ply"
#elif defined(FUZZ_READ_SCENE)
#define FUZZ_EXT ".json"
#else
#error "define one FUZZ_READ_<NAME>"
#endif

#define BROKEN(why) broken(why, __LINE__)
static void broken(const char *why, int line)
{
    fprintf(stderr, "fuzz_read.c:%d: contract broken: %s\n", line, why);
    __builtin_trap();
}

/* A failure must say why. */
static void check_failure(int rc, const rk_error *err)
{
    if (rc != 0 && err->msg[0] == 0) BROKEN("a failure with an empty message");
}

#if !defined(FUZZ_READ_SCENE) /* the scene parser takes text */
static char dir[64];

/* At exit (libFuzzer's end of a run), the private folder goes; after a crash it stays. */
static void remove_dir(void)
{
    char path[96];
    snprintf(path, sizeof path, "%s/in%s", dir, FUZZ_EXT);
    unlink(path);
    snprintf(path, sizeof path, "%s/in.ele", dir);
    unlink(path);
    rmdir(dir);
}

/* The input written to dir/in<ext> (and dir/in.ele for TetGen); the path, or NULL. */
static const char *write_input(const uint8_t *data, size_t size)
{
    static char path[96];
    size_t first = size;
    FILE *fp;
    if (!dir[0]) {
        const char *base = getenv("FUZZ_TMPDIR");
        snprintf(dir, sizeof dir, "%s/romkit-fuzz-XXXXXX", base && base[0] ? base : "/tmp");
        if (!mkdtemp(dir)) {
            perror("fuzz_read: mkdtemp");
            abort();
        }
        atexit(remove_dir);
    }
#if defined(FUZZ_READ_TETGEN)
    {
        static const char mark[] = "@@ele";
        size_t i;
        for (i = 0; i + sizeof mark - 1 <= size; i++)
            if (memcmp(data + i, mark, sizeof mark - 1) == 0) {
                first = i;
                break;
            }
        snprintf(path, sizeof path, "%s/in.ele", dir);
        fp = fopen(path, "wb");
        if (!fp) abort();
        if (first < size) fwrite(data + first + sizeof mark - 1, 1, size - first - (sizeof mark - 1), fp);
        fclose(fp);
    }
#endif
    snprintf(path, sizeof path, "%s/in%s", dir, FUZZ_EXT);
    fp = fopen(path, "wb");
    if (!fp) abort();
    if (first) fwrite(data, 1, first, fp);
    fclose(fp);
    return path;
}
#endif

#if defined(FUZZ_READ_GMSH) || defined(FUZZ_READ_MEDIT) || defined(FUZZ_READ_VTK) || defined(FUZZ_READ_TETGEN)
static void run(const char *path)
{
    rk_mesh m;
    rk_mesh_report rep;
    rk_error err;
    int rc, i;
    memset(&err, 0, sizeof err);
    rc = rk_mesh_load(path, RK_MESH_KEEP_FLAT, &m, &rep, &err);
    check_failure(rc, &err);
    if (rc != 0) return;
    if (m.nv <= 0 || m.nt <= 0) BROKEN("a mesh loaded without vertices or tets");
    for (i = 0; i < 4 * m.nt; i++)
        if (m.tets[i] < 0 || m.tets[i] >= m.nv) BROKEN("a tet index out of range after the check");
    rk_mesh_free(&m);
}
#elif defined(FUZZ_READ_OBJ) || defined(FUZZ_READ_OFF) || defined(FUZZ_READ_STL) || defined(FUZZ_READ_PLY) || \
    defined(FUZZ_READ_GLTF)
static void run(const char *path)
{
    rk_surface s;
    rk_error err;
    int rc, i;
    memset(&err, 0, sizeof err);
    rc = rk_surface_load(path, &s, &err);
    check_failure(rc, &err);
    if (rc != 0) return;
    for (i = 0; i < 3 * s.nf; i++)
        if (s.tris[i] < 0 || s.tris[i] >= s.nv) BROKEN("a face index out of range");
    memset(&err, 0, sizeof err);
    check_failure(rk_surface_check(&s, path, &err), &err);
    rk_surface_free(&s);
}
#elif defined(FUZZ_READ_SPLATS)
static void run(const char *path)
{
    rk_splats s;
    rk_error err;
    int rc;
    memset(&err, 0, sizeof err);
    rc = rk_splats_read(path, &s, &err);
    check_failure(rc, &err);
    if (rc != 0) return;
    if (s.n < 0 || s.nprop < 3) BROKEN("splats read without x y z");
    if (s.xyz[0] < 0 || s.xyz[0] >= s.nprop) BROKEN("x's column out of range");
    rk_splats_free(&s);
}
#elif defined(FUZZ_READ_POINTS)
static void run(const char *path)
{
    double *X = NULL;
    int n = -1;
    rk_error err;
    int rc;
    memset(&err, 0, sizeof err);
    rc = rk_points_load(path, &X, &n, &err);
    check_failure(rc, &err);
    if (rc == 0 && n < 0) BROKEN("a negative point count");
    free(X);
}
#elif defined(FUZZ_READ_SCENE)
static void run_text(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    rk_scene s;
    rk_error err;
    int rc;
    if (!text) return;
    memcpy(text, data, size);
    text[size] = 0;
    memset(&err, 0, sizeof err);
    /* The path anchors relative file names; a directory without files keeps them unread. */
    rc = rk_scene_parse(text, "/nonexistent/fuzz/scene.json", &s, &err);
    check_failure(rc, &err);
    if (rc == 0) rk_scene_free(&s);
    free(text);
}
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
#if defined(FUZZ_READ_SCENE)
    run_text(data, size);
#else
    run(write_input(data, size));
#endif
    return 0;
}
