/* rk_mesh_refine: uniform 1:8 refinement. Volume, orientation, counts (8 nt tets, V + E vertices),
 * conformity (faces matched here by sorting, independently of rk_mesh_boundary), the boundary
 * (4x the triangles, the same area and enclosed volume), quality against the parent, determinism,
 * tags and ghost tets, and the errors. On one tet, on armadillo_4k (two levels) and bunny_19k. */
#include <stdint.h>

#include "testlib.h"
#include "test_mesh_formats.h"

static const double unit_tet[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};

static double tet_volume(const rk_mesh *m, int t)
{
    const int *v = m->tets + 4 * (size_t)t;
    return rk_tet_signed_volume(m->X + 3 * (size_t)v[0], m->X + 3 * (size_t)v[1], m->X + 3 * (size_t)v[2],
                                m->X + 3 * (size_t)v[3]);
}

static double tet_quality(const rk_mesh *m, int t)
{
    const int *v = m->tets + 4 * (size_t)t;
    return rk_tet_radius_ratio(m->X + 3 * (size_t)v[0], m->X + 3 * (size_t)v[1], m->X + 3 * (size_t)v[2],
                               m->X + 3 * (size_t)v[3]);
}

/* Total volume, smallest tet volume (signed), in a compensated sum so round-off is the tets' own. */
static double total_volume(const rk_mesh *m, double *min_vol)
{
    double s = 0, c = 0;
    *min_vol = INFINITY;
    for (int t = 0; t < m->nt; t++) {
        double v = tet_volume(m, t);
        if (v < *min_vol) *min_vol = v;
        double y = v - c, u = s + y;
        c = (u - s) - y;
        s = u;
    }
    return s;
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* Distinct edges of the tets, counted by sorting (a, b) keys. */
static long count_edges(const rk_mesh *m)
{
    static const int E[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    size_t n = 6 * (size_t)m->nt;
    int64_t *k = malloc(n * sizeof *k);
    for (size_t t = 0; t < (size_t)m->nt; t++)
        for (int e = 0; e < 6; e++) {
            int64_t a = m->tets[4 * t + E[e][0]], b = m->tets[4 * t + E[e][1]];
            k[6 * t + e] = a < b ? a * m->nv + b : b * m->nv + a;
        }
    qsort(k, n, sizeof *k, cmp_i64);
    long u = 0;
    for (size_t i = 0; i < n; i++) u += i == 0 || k[i] != k[i - 1];
    free(k);
    return u;
}

typedef struct {
    int key[3];
    int parity; /* 0/1: whether the outward winding is an even permutation of the sorted key */
} face;

static int cmp_face(const void *a, const void *b)
{
    const int *x = ((const face *)a)->key, *y = ((const face *)b)->key;
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

/* What the face matching found: faces used once (boundary), twice with opposite windings
 * (interior), and anything else (bad). Boundary area and enclosed volume from the once-used ones,
 * oriented as their tets see them from outside. */
typedef struct {
    long boundary, interior, bad;
    double area, enclosed;
} faces_found;

static faces_found match_faces(const rk_mesh *m)
{
    static const int local[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    size_t n = 4 * (size_t)m->nt;
    face *f = malloc(n * sizeof *f);
    for (size_t t = 0; t < (size_t)m->nt; t++)
        for (int l = 0; l < 4; l++) {
            face *x = &f[4 * t + l];
            int w[3];
            for (int k = 0; k < 3; k++) w[k] = m->tets[4 * t + local[l][k]];
            /* sort by swaps, counting them: the parity of the winding relative to the key */
            int s = 0;
            for (int i = 0; i < 3; i++) x->key[i] = w[i];
            for (int i = 1; i < 3; i++)
                for (int j = i; j > 0 && x->key[j - 1] > x->key[j]; j--) {
                    int tmp = x->key[j];
                    x->key[j] = x->key[j - 1];
                    x->key[j - 1] = tmp;
                    s ^= 1;
                }
            x->parity = s;
        }
    qsort(f, n, sizeof *f, cmp_face);
    faces_found r = {0};
    const double *o = m->X;
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && cmp_face(&f[i], &f[j]) == 0) j++;
        if (j - i == 1) {
            r.boundary++;
            const double *a = m->X + 3 * (size_t)f[i].key[0], *b = m->X + 3 * (size_t)f[i].key[1],
                         *c = m->X + 3 * (size_t)f[i].key[2];
            double u[3], v[3];
            for (int k = 0; k < 3; k++) {
                u[k] = b[k] - a[k];
                v[k] = c[k] - a[k];
            }
            double cr[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
            r.area += 0.5 * sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
            double vol = rk_tet_signed_volume(o, a, b, c);
            r.enclosed += f[i].parity ? -vol : vol;
        } else if (j - i == 2 && f[i].parity != f[i + 1].parity) {
            r.interior++;
        } else {
            r.bad++;
        }
        i = j;
    }
    free(f);
    return r;
}

/* Every check of one refinement level of `in` into `out` (the messages say which failed). */
static int check_level(const rk_mesh *in, const rk_mesh *out, char *why, size_t cap)
{
    double min_in, min_out;
    double v_in = total_volume(in, &min_in), v_out = total_volume(out, &min_out);
    if (out->nt != 8 * in->nt) return snprintf(why, cap, "%d tets from %d", out->nt, in->nt), -1;
    long edges = count_edges(in);
    if (out->nv != in->nv + edges)
        return snprintf(why, cap, "%d vertices, expected %d + %ld edges", out->nv, in->nv, edges), -1;
    if (!(min_out > 0)) return snprintf(why, cap, "a child has volume %g", min_out), -1;
    if (fabs(v_out - v_in) > 1e-13 * fabs(v_in))
        return snprintf(why, cap, "volume %.17g, parent %.17g (relative %.3g)", v_out, v_in, fabs(v_out / v_in - 1)), -1;
    /* each child 1/8 of its parent, to the round-off of the volume formula */
    for (int t = 0; t < in->nt; t++)
        for (int c = 0; c < 8; c++) {
            double ratio = tet_volume(out, 8 * t + c) / tet_volume(in, t);
            if (fabs(ratio - 0.125) > 1e-9)
                return snprintf(why, cap, "child %d of tet %d has %.12g of its volume", c, t, ratio), -1;
        }
    faces_found a = match_faces(in), b = match_faces(out);
    if (b.bad) return snprintf(why, cap, "%ld faces are neither boundary nor shared by two tets", b.bad), -1;
    if (b.boundary != 4 * a.boundary)
        return snprintf(why, cap, "%ld boundary faces, parent %ld", b.boundary, a.boundary), -1;
    if (2 * b.interior != 4L * out->nt - b.boundary)
        return snprintf(why, cap, "%ld interior faces for %d tets and %ld boundary faces", b.interior, out->nt,
                        b.boundary), -1;
    if (fabs(b.area - a.area) > 1e-12 * a.area)
        return snprintf(why, cap, "boundary area %.17g, parent %.17g", b.area, a.area), -1;
    if (fabs(b.enclosed - v_out) > 1e-12 * fabs(v_out))
        return snprintf(why, cap, "boundary encloses %.17g, tets %.17g", b.enclosed, v_out), -1;
    int *tris, nf;
    rk_error err;
    if (rk_mesh_boundary(out, &tris, &nf, &err)) return snprintf(why, cap, "rk_mesh_boundary: %s", err.msg), -1;
    free(tris);
    if (nf != b.boundary) return snprintf(why, cap, "rk_mesh_boundary finds %d faces, the test %ld", nf, b.boundary), -1;
    return 0;
}

/* Worst child/parent radius-ratio over every tet, and the worst of each mesh. */
static void quality_ratio(const rk_mesh *in, const rk_mesh *out, double *per_tet, double *worst_in, double *worst_out)
{
    *per_tet = INFINITY;
    *worst_in = *worst_out = 1;
    for (int t = 0; t < in->nt; t++) {
        double qp = tet_quality(in, t);
        *worst_in = fmin(*worst_in, qp);
        for (int c = 0; c < 8; c++) {
            double q = tet_quality(out, 8 * t + c);
            *worst_out = fmin(*worst_out, q);
            *per_tet = fmin(*per_tet, q / qp);
        }
    }
}

TEST(one_tet_gives_eight_of_an_eighth_each)
{
    rk_error err;
    /* the reference tet, a regular one, and three stretched ones whose shortest octahedron
     * diagonal is each of the three in turn (m01-m23, m02-m13, m03-m12) */
    const double s = 1 / sqrt(2.0);
    double shapes[5][12] = {{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1},
                            {1, 0, -s, -1, 0, -s, 0, -1, s, 0, 1, s},
                            {0, 0, 0, 3, 0, 0, 3, 1, 0, 0, 0.2, 1},
                            {0, 0, 0, 1, 0.1, 0, 0, 3, 0, 0.2, 3, 1},
                            {0, 0, 0, 1, 0, 0, 0.3, 1, 0, 0.5, 0.4, 3}};
    int tet[4] = {0, 1, 2, 3}, seen[3] = {0, 0, 0};
    for (int k = 0; k < 5; k++) {
        rk_mesh m = make_mesh(4, shapes[k], 1, tet), r;
        CHECK(tet_volume(&m, 0) > 0, "shape %d is inverted", k);
        CHECK_OK(rk_mesh_refine(&m, 1, &r, &err));
        char why[256] = "";
        int rc = check_level(&m, &r, why, sizeof why);
        int nv = r.nv;
        double q_inner = 1, q_corner = 1;
        for (int c = 0; c < 8; c++) {
            if (c < 4) q_corner = fmin(q_corner, tet_quality(&r, c));
            else q_inner = fmin(q_inner, tet_quality(&r, c));
        }
        double qp = tet_quality(&m, 0);
        /* the diagonal the inner children share: midpoints 4..9 are those of edges 01 02 03 12 13 23 */
        int d0 = r.tets[16], d1 = r.tets[17];
        for (int d = 0; d < 3; d++) seen[d] += d0 == 4 + d && d1 == 9 - d;
        rk_mesh_free(&m);
        rk_mesh_free(&r);
        CHECK(rc == 0, "shape %d: %s", k, why);
        CHECK(nv == 10, "shape %d: %d vertices", k, nv);
        CHECK_CLOSE(q_corner, qp, 1e-12); /* corners are the parent scaled by 1/2 */
        /* a regular tet's octahedron is regular: its four tets have radius ratio 0.8038 */
        if (k == 1) CHECK(fabs(q_inner - 0.80384757729) < 1e-9, "regular tet: inner quality %.12g", q_inner);
    }
    CHECK(seen[0] && seen[1] && seen[2], "diagonals taken: %d %d %d times", seen[0], seen[1], seen[2]);
}

TEST(armadillo_two_levels)
{
    rk_error err;
    rk_mesh m, r1, r2, r2b;
    CHECK_OK(rk_mesh_load(test_data("meshes/armadillo_4k.node"), RK_MESH_KEEP_FLAT, &m, NULL, &err));
    int rc = rk_mesh_refine(&m, 1, &r1, &err);
    if (!rc) rc = rk_mesh_refine(&r1, 1, &r2, &err);
    if (!rc) rc = rk_mesh_refine(&m, 2, &r2b, &err);
    if (rc) rk_mesh_free(&m);
    CHECK(rc == 0, "rk_mesh_refine: %s", err.msg);
    char why[256] = "";
    int rc1 = check_level(&m, &r1, why, sizeof why);
    int rc2 = rc1 ? 0 : check_level(&r1, &r2, why, sizeof why);
    /* two levels at once are one level twice, bit for bit */
    int same = r2.nv == r2b.nv && r2.nt == r2b.nt && !memcmp(r2.X, r2b.X, sizeof(double) * 3 * (size_t)r2.nv) &&
               !memcmp(r2.tets, r2b.tets, sizeof(int) * 4 * (size_t)r2.nt);
    double per1, in1, out1, per2, in2, out2;
    quality_ratio(&m, &r1, &per1, &in1, &out1);
    quality_ratio(&r1, &r2, &per2, &in2, &out2);
    printf("# armadillo_4k: %d tets -> %d -> %d; worst radius ratio %.4f -> %.4f -> %.4f; worst child/parent "
           "%.3f, %.3f\n", m.nt, r1.nt, r2.nt, in1, out1, out2, per1, per2);
    rk_mesh_free(&m);
    rk_mesh_free(&r1);
    rk_mesh_free(&r2);
    rk_mesh_free(&r2b);
    CHECK(rc1 == 0 && rc2 == 0, "level %d: %s", rc1 ? 1 : 2, why);
    CHECK(same, "refining twice differs from two levels at once");
    /* Each child is the affine image of one of a fixed set of children of the reference tet, so
     * its shape is bounded by its parent's, by a constant factor that is small for the radius ratio
     * (0.002 over 20,000 random tets); over real meshes the children keep much more (armadillo:
     * 0.097 per tet at both levels; the mesh's worst 0.0045 -> 0.0036 -> 0.0036: a second level
     * makes no worse shapes than the first, as with a bounded set of similarity classes) */
    CHECK(out1 >= 0.25 * in1 && out2 >= 0.25 * in2, "worst quality %.3g -> %.3g -> %.3g", in1, out1, out2);
}

TEST(bunny_one_level_is_deterministic)
{
    rk_error err;
    rk_mesh m, a, b;
    CHECK_OK(rk_mesh_load(test_data("meshes/bunny_19k.msh"), RK_MESH_KEEP_FLAT, &m, NULL, &err));
    int rc = rk_mesh_refine(&m, 1, &a, &err);
    if (!rc) rc = rk_mesh_refine(&m, 1, &b, &err);
    if (rc) rk_mesh_free(&m);
    CHECK(rc == 0, "rk_mesh_refine: %s", err.msg);
    char why[256] = "";
    int rc1 = check_level(&m, &a, why, sizeof why);
    int same = a.nv == b.nv && a.nt == b.nt && !memcmp(a.X, b.X, sizeof(double) * 3 * (size_t)a.nv) &&
               !memcmp(a.tets, b.tets, sizeof(int) * 4 * (size_t)a.nt);
    double per, qin, qout;
    quality_ratio(&m, &a, &per, &qin, &qout);
    printf("# bunny_19k: %d tets -> %d, %d vertices -> %d; worst radius ratio %.4f -> %.4f; worst child/parent "
           "%.3f\n", m.nt, a.nt, m.nv, a.nv, qin, qout, per);
    /* the refined mesh passes the check untouched: nothing reoriented, unused or flat */
    rk_mesh_report rep;
    int rc2 = rk_mesh_check(&a, "refined bunny", RK_MESH_DROP_FLAT, &rep, &err);
    rk_mesh_free(&m);
    rk_mesh_free(&a);
    rk_mesh_free(&b);
    CHECK(rc1 == 0, "%s", why);
    CHECK(same, "two refinements of the same mesh differ");
    /* measured: 0.073 per tet, the worst (a sliver of 4.8e-5) keeps 0.97 */
    CHECK(per >= 0.05 && qout >= 0.5 * qin, "child/parent %.3g, worst %.3g -> %.3g", per, qin, qout);
    CHECK(rc2 == 0, "rk_mesh_check: %s", err.msg);
    CHECK(rep.reoriented == 0 && rep.unused_removed == 0 && rep.flat == 0 && rep.components == 1,
          "check: reoriented %d, unused %d, flat %d, components %d", rep.reoriented, rep.unused_removed, rep.flat,
          rep.components);
}

TEST(tags_follow_parents_and_ghosts_are_split)
{
    rk_error err;
    double size[3] = {3, 3, 3};
    int cells[3] = {3, 3, 3};
    rk_mesh box;
    CHECK_OK(rk_mesh_box(size, cells, &box, &err));
    box.tet_tag = malloc(sizeof(int) * (size_t)box.nt);
    for (int t = 0; t < box.nt; t++) box.tet_tag[t] = 10 + t;
    /* A tet of the middle cell (the first of cell 13) becomes a ghost: the body then has a pocket
     * where it was, which the ghost closes (rk_mesh_boundary counts ghost faces); refined, it must
     * still close it. It is moved to the end first so the tags stay 10 + t / 8. */
    int gt = 6 * 13;
    for (int k = 0; k < 4; k++) {
        int s = box.tets[4 * gt + k];
        box.tets[4 * gt + k] = box.tets[4 * (box.nt - 1) + k];
        box.tets[4 * (box.nt - 1) + k] = s;
    }
    int *before_tris, nf_before;
    CHECK_OK(rk_mesh_boundary(&box, &before_tris, &nf_before, &err));
    free(before_tris);
    box.nghost = 1;
    box.ghost = malloc(4 * sizeof(int));
    memcpy(box.ghost, box.tets + 4 * (box.nt - 1), 4 * sizeof(int));
    box.nt--;
    rk_mesh r;
    int rc = rk_mesh_refine(&box, 1, &r, &err);
    if (rc) rk_mesh_free(&box);
    CHECK(rc == 0, "rk_mesh_refine: %s", err.msg);
    int tags_ok = r.tet_tag != NULL, ghost_ok = r.nghost == 8, nghost = r.nghost;
    for (int t = 0; tags_ok && t < r.nt; t++) tags_ok = r.tet_tag[t] == 10 + t / 8;
    for (int g = 0; ghost_ok && g < 8 * 4; g++) ghost_ok = r.ghost[g] >= 0 && r.ghost[g] < r.nv;
    int *tris, nf;
    rc = rk_mesh_boundary(&r, &tris, &nf, &err);
    rk_mesh_free(&box);
    rk_mesh_free(&r);
    CHECK(rc == 0, "rk_mesh_boundary: %s", err.msg);
    free(tris);
    CHECK(tags_ok, "a child does not carry its parent's tag");
    CHECK(ghost_ok, "%d ghosts after refinement", nghost);
    CHECK(nf == 4 * nf_before, "%d boundary faces after, %d before the ghost", nf, nf_before);
}

TEST(zero_levels_copy)
{
    rk_error err;
    int tet[4] = {0, 1, 2, 3};
    rk_mesh m = make_mesh(4, unit_tet, 1, tet), r;
    CHECK_OK(rk_mesh_refine(&m, 0, &r, &err));
    int same = r.nv == 4 && r.nt == 1 && r.X != m.X && !memcmp(r.X, m.X, sizeof unit_tet) && !memcmp(r.tets, tet, sizeof tet);
    rk_mesh_free(&m);
    rk_mesh_free(&r);
    CHECK(same, "0 levels is not a copy");
}

TEST(bad_input_is_refused_by_name)
{
    rk_error err;
    int tet[4] = {0, 1, 2, 3};
    rk_mesh m = make_mesh(4, unit_tet, 1, tet), r;
    int neg = rk_mesh_refine(&m, -1, &r, &err);
    int neg_msg = strstr(err.msg, "-1 levels") != NULL;
    int five = rk_mesh_refine(&m, 5, &r, &err);
    int five_msg = strstr(err.msg, "0 to 4") != NULL;
    m.tets[2] = 7;
    int idx = rk_mesh_refine(&m, 1, &r, &err);
    int idx_msg = strstr(err.msg, "tet 0 references vertex 7") != NULL;
    m.tets[2] = 1;
    int twice = rk_mesh_refine(&m, 1, &r, &err);
    int twice_msg = strstr(err.msg, "uses vertex 1 twice") != NULL;
    rk_mesh_free(&m);
    CHECK(neg && neg_msg && five && five_msg, "levels -1 and 5: %s", err.msg);
    CHECK(idx && idx_msg && twice && twice_msg, "bad tets: %s", err.msg);
    CHECK(r.X == NULL && r.nt == 0, "output left behind");
    /* above the cap: 5,184 tets x 8^4 = 21.2 million; refused before anything is allocated */
    double size[3] = {1, 1, 1};
    int cells[3] = {12, 12, 6};
    rk_mesh box;
    CHECK_OK(rk_mesh_box(size, cells, &box, &err));
    int cap = rk_mesh_refine(&box, 4, &r, &err);
    rk_mesh_free(&box);
    CHECK(cap && strstr(err.msg, "5184 tets into 21233664"), "cap: %s", err.msg);
    /* a ghost with an edge no tet has */
    double X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
    rk_mesh g = make_mesh(5, X, 1, tet);
    g.nghost = 1;
    g.ghost = malloc(4 * sizeof(int));
    int gv[4] = {1, 2, 3, 4};
    memcpy(g.ghost, gv, sizeof gv);
    int ghost = rk_mesh_refine(&g, 1, &r, &err);
    rk_mesh_free(&g);
    CHECK(ghost && strstr(err.msg, "ghost tet 0") && strstr(err.msg, "level 1 of 1"), "ghost: %s", err.msg);
}

int main(void)
{
    RUN(one_tet_gives_eight_of_an_eighth_each);
    RUN(armadillo_two_levels);
    RUN(bunny_one_level_is_deterministic);
    RUN(tags_follow_parents_and_ghosts_are_split);
    RUN(zero_levels_copy);
    RUN(bad_input_is_refused_by_name);
    return test_finish();
}
