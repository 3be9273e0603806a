/* Private to the runtime: the model that lives in the caller's arena, and the functions the
 * runtime's files share. C99, no allocation. */
#ifndef ROMRT_IMPL_H
#define ROMRT_IMPL_H

#include <stdint.h>

#include "formats/rombin_read.h"
#include "physics/physics.h"
#include "runtime/romrt.h"

#ifdef ROMRT_DOUBLE
#define ROMRT_REAL_TYPE ROMBIN_REAL_F64
#define RT_SQRT sqrt
#define RT_FABS fabs
/* The line search's round-off floor (physics.h): in double the precompute's own, so the runtime
 * takes the reduced simulator's iterates; in float, float's. */
#define RT_ENERGY_NOISE RK_ENERGY_NOISE_DOUBLE
#else
#define ROMRT_REAL_TYPE ROMBIN_REAL_F32
#define RT_SQRT sqrtf
#define RT_FABS fabsf
#define RT_ENERGY_NOISE RK_ENERGY_NOISE_FLOAT
#endif
#define RT_K(x) ((romrt_real)(x))
/* The build's limits (an app reads them with romrt_get_limits, never from here). The largest
 * reduced size: it sizes the r-long vectors of the model and the stack (the r x r buffers come from
 * the arena at the asset's own r); 512 is what the Makefile's desktop libraries and make install
 * ship (the Makefile reads it from this line), room for the freeform paper's largest model (m = 32
 * eigen-weights: r = 396); a build may set its own (the Cortex-M build: 32). The app's collider
 * slots. */
#ifndef ROMRT_MAX_R
#define ROMRT_MAX_R 512
#endif
#ifndef ROMRT_MAX_COLLIDERS
#define ROMRT_MAX_COLLIDERS 8
#endif
/* Vertices or triangles of an app's collider mesh at most (32-bit indices with room for 3 n). */
#define ROMRT_MESH_MAX_COUNT ((size_t)1 << 24)
/* The scene's moving obstacles at most (an asset with more is refused at open, naming OBMO; the
 * bake refuses them too): each has its own progress unknown in a step's joint solve
 * (contact_progress.c), as each app mesh moved by its pose has. */
#ifndef ROMRT_MAX_MOVING_OBSTACLES
#define ROMRT_MAX_MOVING_OBSTACLES RK_MAX_MOVING_OBSTACLES
#endif
/* A joint solve's movers: the scene's moving obstacles (0..), then the collider slots. */
#define RT_MOVERS (ROMRT_MAX_MOVING_OBSTACLES + ROMRT_MAX_COLLIDERS)
/* The Newton unknowns at most: q and the progress of each moved collider, or of each mover. */
#define ROMRT_MAX_N (ROMRT_MAX_R + RT_MOVERS)
#define RT_COLLIDER_REALS RK_COLLIDER_REALS
/* The r-long rows of the element kernels are padded with zeros to whole vectors of RT_LANES reals
 * (8 floats: one AVX register; 2 SSE or NEON ones), so their loops run without remainders. */
#define RT_LANES 8
#define RT_PAD(n) (((n) + RT_LANES - 1) / RT_LANES * RT_LANES)
/* C99's restrict: the kernels' rows never overlap. */
#define RT_RESTRICT restrict

/* Caps checked before any count is used (ROMBIN.md, "Limits"). */
#define ROMRT_MAX_VERTICES (1u << 24)
#define ROMRT_MAX_ELEMENTS (1u << 24)
#define ROMRT_MAX_PINS 64u
#define ROMRT_MAX_PLANES 16u
#define ROMRT_MAX_GROUPS 1024u
#define ROMRT_MAX_TRIANGLES (1u << 25)
#define ROMRT_MAX_NEWTON 1000u

/* The physics, compiled in this runtime's precision under the romrt_phys_ prefix. */
#define RT_PHYS(name) romrt_phys_##name
romrt_real romrt_phys_psi_h(rk_material_model model, romrt_real mu, romrt_real lambda, const romrt_real Hd[9]);
void romrt_phys_pk1_h(rk_material_model model, romrt_real mu, romrt_real lambda, const romrt_real Hd[9], romrt_real P[9]);
void romrt_phys_dpdf(rk_material_model model, romrt_real mu, romrt_real lambda, const romrt_real F[9],
                     romrt_real dPdF[81], int project);
void romrt_phys_dpdf_p(rk_material_model model, romrt_real mu, romrt_real lambda, romrt_real pres, const romrt_real F[9],
                       romrt_real dPdF[81], int project);
romrt_real romrt_phys_volume_h(rk_material_model model, const romrt_real Hd[9], romrt_real dtheta[9]);
romrt_real romrt_phys_barrier(romrt_real d, romrt_real dhat, romrt_real *d1, romrt_real *d2);
romrt_real romrt_phys_barrier_distance(romrt_real d, romrt_real dhat, romrt_real *f1, romrt_real *f2);
void romrt_phys_motion(rk_motion_kind kind, const romrt_real axis[3], const romrt_real center[3], romrt_real rate,
                       const romrt_real velocity[3], double t, romrt_real R[9], romrt_real shift[3]);
int romrt_phys_collider_check(int kind, const romrt_real *shape);
romrt_real romrt_phys_collider_distance(int kind, const romrt_real *shape, const romrt_real x[3], romrt_real n[3],
                                        romrt_real closest[3]);
romrt_real romrt_phys_collider_step(int kind, const romrt_real *shape, const romrt_real x[3], const romrt_real dx[3]);
void romrt_phys_collider_pose_at(const romrt_real *from, const romrt_real *to, romrt_real s, romrt_real *out);
void romrt_phys_collider_path_velocity(const romrt_real *from, const romrt_real *to, romrt_real s,
                                       const romrt_real local[3], romrt_real v[3]);
romrt_real romrt_phys_collider_joint_step(int kind, const romrt_real *from, const romrt_real *to, romrt_real s,
                                          romrt_real ds, const romrt_real x[3], const romrt_real dx[3]);
romrt_real romrt_phys_collider_motion_step(int kind, const romrt_real *from, const romrt_real *to, const romrt_real x[3]);
void romrt_phys_tangent_basis(const romrt_real n[3], romrt_real T[6]);
romrt_real romrt_phys_friction_smoothed(const romrt_real u[2], romrt_real eps, romrt_real *f1_over_y, romrt_real M[4]);
/* Contact per stencil (physics/contact_impl.h; physics.h documents the rk_ double versions). */
rk_distance_case romrt_phys_point_triangle_case(const romrt_real *const x[4]);
rk_distance_case romrt_phys_edge_edge_case(const romrt_real *const x[4]);
romrt_real romrt_phys_contact_distance2(rk_distance_case c, const romrt_real *const x[4], romrt_real *g, romrt_real *H);
void romrt_phys_contact_closest_weights(rk_distance_case c, const romrt_real *const x[4], romrt_real w[4]);
romrt_real romrt_phys_edge_edge_mollifier(const romrt_real *const x[4], romrt_real eps, romrt_real *g, romrt_real *H);
romrt_real romrt_phys_pair_barrier(int edge_edge, const romrt_real *const x[4], romrt_real xi, romrt_real dhat,
                                   romrt_real eps, romrt_real *g, romrt_real *H, romrt_real *dist);
void romrt_phys_pair_project(const int dof[4], romrt_real *H);
romrt_real romrt_phys_pair_friction_lag(int edge_edge, const romrt_real *const x[4], romrt_real xi, romrt_real dhat,
                                        romrt_real eps, romrt_real kappa, romrt_real w[4], romrt_real T[6]);
romrt_real romrt_phys_friction_slip(const romrt_real T[6], const romrt_real rel[3], romrt_real eps, romrt_real scale,
                                    romrt_real g[3], romrt_real B[9]);
int romrt_phys_ccd_stencil(int edge_edge, const romrt_real *const x[4], const romrt_real *const dx[4], romrt_real xi,
                           romrt_real tmax, romrt_real *toi);

/* An app's triangle mesh (romrt_mesh): its index, in the app's memory (mesh_index.c), holds the
 * unique edges, a BVH over the vertices, edges and triangles as the asset's (OBVN's nodes, OBIT's
 * items, local vertex indices) and the mesh's world positions while placed: x where it is, dx a
 * move's way (CCD), x0 where it was at the step's start (friction's start, and where a failed step
 * puts it back), cache where the pairs were gathered. part: x is on the way to the slot's target
 * pose (a move stopped short), not at its `now` pose. */
typedef struct {
    uint32_t magic, nv, nt, ne, nodes, items;
    const romrt_real *X;
    const int32_t *tri;
    uint32_t *edges, *node, *item;
    romrt_real *bounds, *x, *dx, *x0, *cache;
    int part, part_start, moving; /* moving: dx holds a move (boxes swept); part_start: part at the step's start */
    romrt_real xi;                /* thickness: 0 for an app's mesh, the radius of a sphere's or capsule's */
} rt_mesh;
/* Stencil ids of a mesh collider's vertices: obstacle vertex onv + (slot << RT_MESH_SHIFT) + v. */
#define RT_MESH_SHIFT 24

/* An analytic collider (sphere, capsule, box) as the scene's obstacles of that kind are baked
 * (precompute/contact/collision.c): a sphere its centre of thickness r, a capsule its segment of
 * thickness r, a box its 8 corners and 12 triangles; an rt_mesh over the runtime's own storage
 * (shape_collider.c), in the arena of an asset with a collision surface. Sized for the box: the
 * index's layout for 8 vertices and 12 triangles (mesh_index.c: 3 t edge slots, v + 4 t items,
 * one node more). */
#define RT_SHAPE_NV 8
#define RT_SHAPE_NT 12
#define RT_SHAPE_ITEMS (RT_SHAPE_NV + 4 * RT_SHAPE_NT)
typedef struct {
    union { /* the edges' sort keys (u64) take the bounds' space before the first refit */
        uint64_t align;
        romrt_real r[6 * (RT_SHAPE_ITEMS + 1)];
    } bounds;
    rt_mesh mesh;
    romrt_real X[3 * RT_SHAPE_NV], x[4 * 3 * RT_SHAPE_NV];
    int32_t tri[3 * RT_SHAPE_NT];
    uint32_t edges[2 * 3 * RT_SHAPE_NT], node[3 * (RT_SHAPE_ITEMS + 1)], item[RT_SHAPE_ITEMS];
} rt_shape;
/* Storages for the shapes: one per slot and a spare, so that a shape is built where no placed
 * collider reads and a refused placement changes nothing. */
#define RT_SHAPES (ROMRT_MAX_COLLIDERS + 1)

/* An application's collider slot (as precompute/rom's rk_rom_collider): where it is, where the app
 * wants it, where it was when the step began and when friction was lagged; a mesh's index. */
typedef struct {
    int active, kind;
    romrt_real now[RT_COLLIDER_REALS], target[RT_COLLIDER_REALS], start[RT_COLLIDER_REALS], lag[RT_COLLIDER_REALS];
    rt_mesh *mesh;
} rt_collider;

/* An adaptive linear ROM's data and state (alrom.c): the basis is rebuilt before every step from the
 * quadratic decoder at the latent code of the state and the history of the last m steps, over the
 * stored vertices only; a step is then the reduced model's Newton in the incremental form
 * x = x_ref + U q, with the model's X, rows, M, C and f pointing at the buffers below. */
typedef struct {
    int m, pairs, nmotions;
    romrt_real lambda, reg, damping, ridge, budget;
    int cadence;               /* K: the basis refreshed every K steps, held between (ALRH; 1: every step) */
    int encoder_iterations;    /* the encoder's Gauss-Newton iterations at most (ALRH) */
    int since;                 /* steps taken in the held basis since its refresh; -1: refresh next */
    int refreshed, held_ns;    /* whether this step refreshed it; the used vertices it was formed at */
    const romrt_real *X0;      /* nv x 3: rest positions (VERT) */
    const romrt_real *phi;     /* nv x 3 x r: the decoder's linear part (ROWS) */
    const romrt_real *psi;     /* nv x 3 x pairs: its modal derivatives (QDRV) */
    const romrt_real *mass;    /* nv (VMSS) */
    const romrt_real *load;    /* nv x 3 (VLOD) */
    const uint32_t *motion_of; /* nv (AMOV) */
    const romrt_real *motions; /* nmotions x 12 (AMOT) */
    /* state, in double in either build: displacements from rest (an absolute position in float
     * would lose the digits a step moves), velocities, and BDF2's history */
    double *u_t, *v, *u_prev, *v_prev; /* nv x 3 (the quadratic decoder: u_t's free rows held on the
                                        * used vertices only, the rest B c: rt_alrom_position) */
    double *u_ref;             /* nv x 3: the step's reference, u_t with the prescribed at their targets */
    romrt_real *f_app;         /* nv x 3: the app's forces on the stored vertices */
    double *D, *P;             /* (m + 1) slots of nv x 3 displacements and r latent codes: a ring */
    int count, head;           /* entries held (<= m), the slot the next step writes */
    /* the step's model: m->X, rows, M, C, f point here (x_ref = X0 + u_ref) */
    romrt_real *x_ref, *rows, *M, *C, *f;
    romrt_real *Hd0;           /* ne x 9: each element's F - I at x_ref */
    /* scratch: the basis is built in double in either build (the history's small systems are
     * conditioned far beyond float: P P^T + 1e-8 I, Q's rank decided at 1e-6) */
    double *U;                 /* nv x 3 x r: the decoder's basis */
    double *dd;                /* (m + 1)^2: the ring's inner products over the free rows (alrom_basis.c) */
    int dd_valid;              /* whether dd holds every held entry's (0 after a reset or a restore) */
    double *du;                /* (m + 1) x r: the held entries' D^T U */
    double *small;             /* 15 r x r: the step basis' Grams, factors and coefficients */
    double *u, *res;           /* nv x 3 */
    romrt_real *zr;            /* (m + 1 + r) x (r + 1): coef's Z and a row's z in the build's precision */
    double *coef;              /* (m + 1 + r) x r: the history basis' coefficients, (P P^T + reg I)^-1 p_e
                                * (then E_d's rows, and E_u^T after the count held: alrom_basis.c) */
    /* the quadratic decoder in r-space (alrom_decoder.c), R = r + pairs: B = [ROWS | QDRV]'s mass
     * Gram B^T W B and its Euclidean Gram over the free rows (R x R each, formed at open), S C(p)
     * (R x r), 4 R-vectors, and each ring entry's B^T d over the free rows ((m + 1) x R) */
    double *gram, *gram_free, *gram_c, *ext, *db;
    /* the quadratic decoder's state in K-space (issue 33; alrom.c): every basis it forms is B C
     * with C R x r (the Jacobian B C(p), the history's entries B c_e), so the free part of the
     * displacement is B c and its velocity B w (R each, with BDF2's previous two); the mass Gram of
     * B over the free rows (R x R) and B^T load there (R); each ring entry's mass coordinates
     * B^T W d over the free rows ((m + 1) x R); the step basis' C and B^T W B C (R x r each); the
     * rows that a step reads (rt_alrom_used: the cubature elements' and the contacts' vertices,
     * ns of them) and the ring's entries on them (3 ns x (m + 1), rt_alrom_ds) */
    double *c, *w, *c_prev, *w_prev, *gram_wfree, *load_c, *wdb, *cs, *wcs, *ds;
    /* a Newton matrix kept across steps (alrom_keep.c): the W_F C (by K-space row: R x r, a row's
     * r contiguous) and M_r of the step whose coordinates m->H's factor is in, M_r's factor (each step's, for its prediction: m->H is the
     * kept matrix's) and 4 r x r of scratch */
    double *wcs_keep, *keep_work;
    romrt_real *m_keep, *m_fac;
    uint32_t *sv, *s_of;       /* ns used vertices; nv: each vertex's index there, or ROMBIN_NO_MOTION */
    uint32_t *pv;              /* the npv prescribed vertices (AMOV's moved ones) */
    int npv;
    int ns, ns_base, ns_on;    /* the first ns_base always used, the first ns_on now (the rest: CVTX's) */
    double b_sum, x0_max;      /* max over rows of sum |B_i|, over shown coordinates of |X0|: x_bound */
    /* a CROM decoder (ALRH's decoder 1): layer counts, sizes (CRMS: encoder's then decoder's),
     * normalised rest positions (CRMX), parameters (CRMW), the widest layer's buffers */
    int decoder, enc_layers, dec_layers, widest;
    const uint32_t *enc_sizes, *dec_sizes;
    const romrt_real *crom_x, *enc_w, *dec_w;
    double u_scale;
    double *act[2], *tan[2];   /* widest; widest x r */
    double *work;              /* 4 r x r: the small matrices of the encoder and the interpolation */
    double p[ROMRT_MAX_R];
    double *u_new, *v_new;     /* nv x 3: a step's result before it is kept */
} rt_alrom;

struct romrt_model {
    romrt_kind kind;
    /* sizes and parameters (HEAD, PARM; a Koopman asset: KHED, KPRM) */
    int r, nv, shown, ne, np, npins, nplanes, ncontacts, ngroups, ntris, integrator, max_iter, ncv;
    romrt_real h, tol, mass, dhat, kappa;
    int fixed_iterations;     /* 0: Newton to the asset's tolerance; k: exactly k full steps (fixed cost) */
    int exact_hessian;        /* the elements' dP/dF unprojected (the fixed-cost mode's first try) */
    int hessian_reuse;        /* romrt_set_hessian_reuse: 0 or 1, a fresh Newton matrix every iteration;
                               * k >= 2, the factor in H kept for up to k steps (step.c) */
    int hessian_reuse_set;    /* 0 until the app calls romrt_set_hessian_reuse: the default (reuse_steps) */
    int hessian_age;          /* steps since H's factor was built for the body alone (-1: none kept) */
    romrt_real hessian_w;     /* the inertia weight that factor was built with */
    int contact_terms;        /* the barrier and friction terms acting in the last potential (planes,
                               * colliders, the collision surface): a matrix with them is not kept by
                               * default (step.c) */
    romrt_real mu, eps_v;     /* friction (FRIC; mu 0 without) */
    int friction_iterations;
    /* arrays: in the asset when its reals are this runtime's type, else converted into the arena */
    const romrt_real *X;      /* nv x 3 */
    const romrt_real *rows;   /* nv x 3 x r: row 3v+a of the basis (ROWS), or NULL with w */
    const romrt_real *w;      /* nv x skin: a skinning basis's weights (WGHT), its rows formed from them (rows.c) */
    const romrt_real *M, *C, *f, *A; /* r x r (column-major, symmetric), f: r; C, A may be NULL */
    const romrt_real *v0;     /* r: the velocity at t = 0 (VEL0), or NULL: at rest */
    const romrt_real *pins;   /* npins x (12 + 12 r) */
    /* a moving group held by a lifting handle (LIFT; rom.clamp "lifted"): its motion, and lift_col
     * the first of the handle's 12 coordinates, set to the motion's vec(R(t) - I), s(t) and left
     * out of every Newton step (potential.c, step.c); lift NULL: none */
    const romrt_real *lift;
    int lift_col;
    const romrt_real *elem_real; /* ne x 12: Dm^-1, weight, mu, lambda */
    const romrt_real *planes; /* nplanes x 6 */
    const uint32_t *elem;     /* ne x 5 */
    const romrt_real *pt;     /* np x (6 + 4 skin): mesh-free integration points (IPNT): X, weight, mu, lambda,
                               * then per handle j its weight and gradient (w_j, dw_j/dX) */
    const uint32_t *pt_model; /* np (IPMD) */
    int vk;                   /* the projected volume's pressure functions per element or point (VPRS), 0: pointwise */
    const romrt_real *vphi;   /* (ne + np) x vk, or NULL (VPRS) */
    romrt_real *vc, *vC, *vp, *vt, *vHd; /* its scratch: c (vk), C (vk x r, row-major), each element's or
                               * point's pressure (ne + np), one's dtheta/dq (r), each one's Hd (9 (ne + np),
                               * formed once by rt_volume_gather for the elastic loop) */
    const romrt_real *grad;   /* shown x skin x 3: dw_j/dX at the shown vertices (GRAD), or NULL */
    const uint32_t *contacts; /* ncontacts x 2 */
    const uint32_t *cv;       /* ncv collision vertices (CVTX), or NULL */
    const uint32_t *groups;   /* ngroups x 2 */
    const uint32_t *gverts;
    const uint32_t *tris;     /* ntris x 3 */
    const char *names;        /* ngroups x 32 */
    const romrt_real *force_rows; /* the rows a pushed force goes through: ROWS, or KIMP */
    double row_bound, x_bound;    /* max over shown coordinates of sum_j |row_j| and of |X|: positions stay
                                   * finite while max |q| row_bound + x_bound does (rt_showable) */
    /* Koopman assets: h above is the current step h_data * dt_scale */
    romrt_real h_data, dt_scale, damping;
    const romrt_real *eig;    /* r x 2 (KEIG) */
    const romrt_real *accel;  /* r (KACC) */
    const romrt_real *y0;     /* r (KINI) */
    romrt_real lam_re[ROMRT_MAX_R], lam_im[ROMRT_MAX_R]; /* the blocks at the current step and damping */
    romrt_real sum_re[ROMRT_MAX_R], sum_im[ROMRT_MAX_R]; /* what a constant forcing adds per step */
    /* each block's step factor mu = lam in polar form, log|mu| and arg mu, and 1 / (mu - 1), in
     * double for romrt_jump (koopman.c, set_blocks) */
    double jump_log[ROMRT_MAX_R], jump_arg[ROMRT_MAX_R], jump_inv_re[ROMRT_MAX_R], jump_inv_im[ROMRT_MAX_R];
    /* state; the clock is t = t0 + steps h in double (rt_clock), never a running float sum */
    double t0;
    unsigned long steps;
    int have_prev;
    romrt_real q[ROMRT_MAX_R], v[ROMRT_MAX_R], q_prev[ROMRT_MAX_R], v_prev[ROMRT_MAX_R];
    romrt_real f_app[ROMRT_MAX_R];   /* reduced forces the app applied */
    romrt_step_info last;
    /* the app's colliders, and friction's lag (q where it was lagged; q_t is the step's start) */
    rt_collider colliders[ROMRT_MAX_COLLIDERS];
    int ncolliders;
    romrt_real q_lag[ROMRT_MAX_R];
    /* a step's moved colliders: slot, where they started, their pull and path length */
    int nmoving, moving[ROMRT_MAX_COLLIDERS];
    romrt_real move_from[ROMRT_MAX_COLLIDERS][RT_COLLIDER_REALS], move_w[ROMRT_MAX_COLLIDERS], move_L[ROMRT_MAX_COLLIDERS];
    /* scratch of one step */
    romrt_real qt[ROMRT_MAX_R], qtilde[ROMRT_MAX_R], pin_b[ROMRT_MAX_R];
    romrt_real y[ROMRT_MAX_N], g[ROMRT_MAX_N], d[ROMRT_MAX_N], trial[ROMRT_MAX_N], tmp[ROMRT_MAX_R];
    /* scratch in the arena, sized by the asset's r (open.c) */
    romrt_real *H;            /* n x n (n = r + moved colliders), column-major, upper triangle */
    romrt_real *He;           /* RT_PAD(r) square: the elastic Hessian, accumulated in whole vectors */
    romrt_real *G, *AG;       /* 9 rows of RT_PAD(r): one element's dF/dq and w dP/dF dF/dq */
    romrt_real *G_all;        /* ne x 9 rows of RT_PAD(r): every cubature element's dF/dq, formed once at
                               * open for a basis of stored rows (a fixed linear map), once a step for
                               * an adaptive one (alrom_basis.c), or NULL */
    /* a skinning basis (SKIN): its handles, and 3 rows of RT_PAD(4 H) each for skinning.c */
    int skin, rows_from_weights;  /* rows_from_weights: formed from WGHT (m->w), not read from ROWS */
    romrt_real *skin_N, *skin_C, *skin_Q, *skin_gQ;
    /* several objects (COBJ; objects_load.c): each collision vertex's object; they touch through
     * the collision surface (contact_surface.c) */
    int nobjects;             /* 0: one object */
    const uint32_t *cv_obj;   /* ncv, or NULL */
    /* the scene's obstacles other than planes (OBHD and the rest; contact_load.c): the reduced
     * simulator's point-triangle and edge-edge pairs against them (contact_broad.c, contact.c,
     * contact_friction.c). Stencil ids as precompute/contact's: >= 0 a collision vertex (CVTX
     * index), < 0 obstacle vertex -1 - id. */
    int surface;              /* OBHD is there: the collision surface's contact is on (obstacles or not) */
    int self_contact;         /* OBHD's self flag: one object's surface touches itself */
    romrt_real *sboxes;       /* (ncv + ncedge + nctri) x 6: the surface sweep's boxes */
    uint32_t *sorder;         /* 3 x that: the primitives sorted by object, then box, on each axis */
    uint32_t *sobj;           /* each primitive's object (contact_surface.c) */
    uint32_t *sfirst;         /* nobjects + 1 (2 for one object): each object's run of the order */
    int ssorted;              /* bit a: sorder's axis a has been sorted once */
    romrt_real *sstat;        /* (nobjects or 1) x 10: each object's hull (lo 3, hi 3), widths (3), count */
    int nobs, onv, one, onf, onode, oitem, ncedge, nctri, obs_moving;
    const uint32_t *obs;      /* nobs x ROMBIN_OBST_COUNT: kind and ranges (OBHD after its counts) */
    const romrt_real *obs_xi; /* nobs x 4 (OBJS) */
    const romrt_real *obs_motion; /* nobs x ROMBIN_PIN_PARAMS (OBMO) */
    const romrt_real *oX;     /* onv x 3 (OBVX) */
    const uint32_t *oedges, *otris, *onodes, *oitems, *cedges, *ctris;
    const romrt_real *obounds_rest; /* onode x 6 (OBVB) */
    uint32_t *overt_obs;      /* onv: each obstacle vertex's obstacle */
    romrt_real *ox, *ox_to, *odx; /* onv x 3: where the obstacle vertices are, are going, the way there */
    romrt_real *ox_from;      /* onv x 3: where they were when the step began (contact_progress.c) */
    int nmovers, movers[ROMRT_MAX_MOVING_OBSTACLES]; /* the obstacles with a motion, ascending */
    int obs_joint;            /* a solve moves them too: the movers' progress s_u at y[r + nmoving + u],
                               * u < obs_joint (0: no joint solve) */
    int obs_unit[RT_MOVERS];  /* each mover's unknown u in it (-1: it stays this step) */
    int obs_behind;           /* the last step left them short of where the clock puts them */
    romrt_real obs_w[RT_MOVERS], obs_L[RT_MOVERS]; /* each progress's pull and its longest way */
    romrt_real obs_s[RT_MOVERS], obs_lambda[RT_MOVERS], obs_short[RT_MOVERS]; /* where a solve starts
                               * s, the pull's multiplier, the last round's shortfall */
    int obs_near[RT_MOVERS];  /* scratch (rt_obstacles_end_joint) */
    romrt_real *obounds;      /* onode x 6: the BVH boxes where the obstacles are (swept when asked) */
    romrt_real *ocx, *ocdx;   /* ncv x 3: the collision vertices at q, and their move along a step */
    romrt_real *cache_x, *cache_ox; /* ncv x 3, onv x 3: where the candidate pairs were gathered */
    romrt_real *fx0, *fox0;   /* ncv x 3, onv x 3: friction's step start */
    romrt_real *pair_J, *pair_JB; /* 12 rows of RT_PAD(r): a stencil's rows, and its block times them */
    romrt_real *pair_H;           /* 12 + r rows of RT_PAD(r): the stencil's rows and J^T B J on its columns */
    int32_t *cand;            /* pair_cap x 5: kind (0 point-triangle, 1 edge-edge), 4 ids */
    int32_t *fric_id;         /* pair_cap x 4: a lagged friction pair's ids */
    romrt_real *fric;         /* pair_cap x 11: its weights (4), tangent basis (6), normal force */
    int pair_cap, ncand, nfric, cache_valid, obs_overflow;
    double obs_time;          /* the time the obstacles were last put at (NAN: moved part way) */
    int nmeshes;              /* colliders on the obstacles' contact path: app meshes and shapes */
    rt_shape *shapes;         /* RT_SHAPES (an asset with a collision surface), or NULL: the vertex path */
    int alrom;                /* an adaptive linear ROM (ALRH): its data and state in al */
    rt_alrom al;
};

/* The incremental potential's weights (as rom_impl.h's rk_rom_terms, dynamics only). */
typedef struct {
    romrt_real w_inertia, w_damping;
    int friction;             /* the lagged friction of planes and colliders */
} rt_terms;

/* Potential at q; with g (r), its gradient; with H, its Hessian (upper triangle, leading
 * dimension ld >= r). The colliders where they are now, friction when T->friction. *magnitude:
 * the size of its terms, for the line search's round-off floor. +INFINITY when not finite. The
 * loads' work counts from m->qt (the step's start), so the value is the potential less a constant
 * of the step: only differences within one step mean anything. */
/* Every cubature element's G_e into m->G_all (allocated at open for a basis of stored rows), from
 * m->rows: again whenever an adaptive ROM forms its rows. */
void rt_form_element_G(romrt_model *m);
romrt_real rt_potential(romrt_model *m, const rt_terms *T, const romrt_real *q, romrt_real *g, romrt_real *H, int ld,
                        romrt_real *magnitude);
/* Cubature element e's constitutive part at F - I = Hd (potential.c, for both element paths;
 * e >= ne is integration point e - ne):
 * its energy density; P (may be NULL) and dP/dF into A (may be NULL), projected to PSD unless
 * m->exact_hessian. */
romrt_real rt_element_psi(const romrt_model *m, int e, const romrt_real Hd[9]);
/* The material of element e, or of integration point e - ne, with its mu and lambda at lame[0..1];
 * its weight (volume times cubature weight). */
rk_material_model rt_material(const romrt_model *m, int e, const romrt_real **lame);
romrt_real rt_point_weight(const romrt_model *m, int e);
/* The projected volume (volume.c; precompute/cubature/volume.c's, the same sums): before the
 * elastic loop, c = sum_e w_e theta_e Phi_e over every element or point's Hd (from hd, kept in vHd
 * for the loop), each one's
 * pressure p_e = Phi_e . c into vp, C zeroed when the Hessian is asked; returns 1/2 |c|^2. In the
 * loop, rt_element_psi and rt_element_stress then leave lambda to it and add p_e's terms, and
 * rt_volume_add takes each one's dtheta/dq (t, r) into C; after it, rt_volume_hessian adds C^T C
 * into H's upper triangle. */
typedef void (*rt_point_hd)(romrt_model *m, int e, const romrt_real *q, romrt_real Hd[9]);
romrt_real rt_volume_gather(romrt_model *m, const romrt_real *q, int hessian, rt_point_hd hd);
void rt_volume_add(romrt_model *m, int e, romrt_real w, const romrt_real *t);
void rt_volume_hessian(const romrt_model *m, romrt_real *H, int ld);
void rt_element_stress(const romrt_model *m, int e, const romrt_real Hd[9], romrt_real *P, romrt_real *A);
/* The elastic energy (gradient, Hessian) of a skinning basis through its weights (skinning.c). */
romrt_real rt_skin_elastic(romrt_model *m, const romrt_real *q, romrt_real *g, romrt_real *H, int ld);
/* The basis rows of stored vertex v (rows.c): row 3v + a dotted with y (r reals), s times it added
 * to out, or written out (r reals); weight j of a skinning basis. */
romrt_real rt_row_dot(const romrt_model *m, uint32_t v, int a, const romrt_real *y);
void rt_row_axpy(const romrt_model *m, uint32_t v, int a, romrt_real s, romrt_real *out);
void rt_row(const romrt_model *m, uint32_t v, int a, romrt_real *out);
romrt_real rt_weight(const romrt_model *m, uint32_t v, int j);
/* x = X_v + rows_v q of stored vertex v. */
void rt_vertex_position(const romrt_model *m, uint32_t v, const romrt_real *q, romrt_real x[3]);
/* H (leading dimension ld) += J_v^T B J_v for stored vertex v's rows J_v and a 3 x 3 block B; g += J_v^T gx. */
void rt_vertex_pull(const romrt_model *m, uint32_t v, const romrt_real gx[3], const romrt_real *B, romrt_real *g,
                    romrt_real *H, int ld);

/* The app's colliders (colliders.c): barrier and friction at q (colliders where they are now);
 * the largest step of q along dq against them (moved ones on their paths at y[r..] + d[r..]);
 * the derivatives in a moved collider's progress (g_s, H_ss, H_qs into column qs of H);
 * friction's lag; whether any is still short of its pose. */
romrt_real rt_colliders_energy(romrt_model *m, const romrt_real *q, int friction, romrt_real *g, romrt_real *H, int ld);
romrt_real rt_colliders_max_step(romrt_model *m, const romrt_real *y, const romrt_real *d);
void rt_colliders_path_terms(romrt_model *m, const romrt_real *q, int k, romrt_real sk, romrt_real *gs, romrt_real *hss,
                             romrt_real *hqs);
void rt_colliders_lag(romrt_model *m, const romrt_real *q, int start);
int rt_colliders_pending(const romrt_model *m);
/* The step's moved colliders (slots, start poses, pulls and path lengths) from the body at q. */
void rt_colliders_begin_move(romrt_model *m, const romrt_real *q);
/* The moved colliders at their progress y[r + k]; at the end of the step's solve, where it left
 * them (at their poses when within tol and the last bit is safe). */
void rt_colliders_place(romrt_model *m, const romrt_real *y);
void rt_colliders_end_move(romrt_model *m, const romrt_real *y);
/* The pins' linear term at time t into m->pin_b. */
void rt_pin_target(romrt_model *m, double t);
/* The lifted group's handle coordinates of q to where its motion is at time t (LIFT; none: nothing). */
void rt_lift(const romrt_model *m, double t, romrt_real *q);
/* The clock (access.c): t `ahead` steps from now; advancing it by n steps; restarting it from
 * t = rt_clock(m, 0) before the step h changes. */
double rt_clock(const romrt_model *m, unsigned long ahead);
/* How many steps a Newton matrix may be kept: the app's romrt_set_hessian_reuse, else the default. */
int rt_reuse_steps(const romrt_model *m);
void rt_clock_advance(romrt_model *m, unsigned long n);
void rt_clock_rebase(romrt_model *m);
/* The scene's obstacles other than planes (contact.c, contact_broad.c, contact_friction.c):
 *   rt_obstacles_at        the obstacles where their motions put them at time t (and the BVH's boxes);
 *                          rt_obstacles_target the same positions into ox_to alone
 *   rt_obstacles_energy    kappa sum_k m_k b(d_k^2 - xi^2, ...) over the pairs within dhat at q, with
 *                          friction when asked; +INFINITY where a pair touches or the pairs overflow
 *                          the capacity (m->obs_overflow set)
 *   rt_obstacles_max_step  the largest step of y along d that CCD allows (the obstacles still, or
 *                          in a joint solve along with the body, each mover by d[r + nmoving + u]
 *                          of its way)
 *   rt_obstacles_fraction  the fraction of the moving obstacles' way to ox_to (rt_obstacles_begin_joint's
 *                          target) and the app meshes' to their poses that CCD allows with the body
 *                          at q, of all of them (near NULL) or of the joint solve's unknowns u with
 *                          near[u] set; rt_obstacles_arrive puts them all where they are at t
 *   rt_obstacles_lag       friction's step start (start) and lagged pairs at q */
void rt_obstacles_at(romrt_model *m, double t);
void rt_obstacles_target(romrt_model *m, double t);
/* Whether the collision surface is in play: obstacles besides planes, other objects, self-contact
 * or an app collider on the obstacles' path. An asset may carry the surface for the app's colliders
 * alone (ROMBIN 1.9): until one is placed, its step is the planes-only step, kept matrix included. */
int rt_surface_on(const romrt_model *m);
romrt_real rt_obstacles_energy(romrt_model *m, const romrt_real *q, int friction, romrt_real *g, romrt_real *H, int ld);
romrt_real rt_obstacles_max_step(romrt_model *m, const romrt_real *y, const romrt_real *d);
romrt_real rt_obstacles_fraction(romrt_model *m, const romrt_real *q, const int *near);
void rt_obstacles_arrive(romrt_model *m, double t);
void rt_obstacles_lag(romrt_model *m, const romrt_real *q, int start);
/* contact_progress.c: the obstacles (the baked ones on their scripted motions, the app's meshes to
 * their poses) moving with the body in one solve.
 *   rt_obstacles_begin_joint  their way from where they are to where they are at t (ox_from,
 *                             ox_to; the meshes' from x0), each mover's unknown (obs_unit), pull
 *                             and length; the unknowns (obs_joint), 0 when nothing moves
 *   rt_obstacles_place        the obstacles at progress s (obs_joint of them) along it, with a CCD
 *                             move of ds of it in odx (ds NULL: none; the meshes' dx; boxes swept
 *                             when ds is given)
 *   rt_obstacles_end_joint    the obstacles where the solve left them (s), each at t when within
 *                             tol of it and its last bit is safe; 1 when one stays behind
 *   rt_obstacles_pull_progress, rt_obstacles_slip_progress
 *                             a barrier stencil's and a friction pair's derivatives in s, added
 *                             into g and H at index r + nmoving + u (as rt_obstacles_pull[_slip]
 *                             take) */
int rt_obstacles_begin_joint(romrt_model *m, double t);
/* A baked obstacle vertex's unknown in the joint solve (-1: its obstacle stays this step). */
int rt_obstacle_unit(const romrt_model *m, uint32_t o);
void rt_obstacles_place(romrt_model *m, const romrt_real *s, const romrt_real *ds);
int rt_obstacles_end_joint(romrt_model *m, const romrt_real *s, double t, romrt_real tol);
void rt_obstacles_pull_progress(romrt_model *m, const int32_t id[4], const romrt_real *gx, const romrt_real *B,
                                romrt_real *g, romrt_real *H, int ld);
void rt_obstacles_slip_progress(romrt_model *m, const int32_t id[4], const romrt_real w[4], const romrt_real gt[3],
                                const romrt_real *B3, romrt_real *g, romrt_real *H, int ld);
/* contact_broad.c: the collision vertices at q (and their move along dq) into ocx (ocdx); the
 * BVH boxes refitted over ox (and ox + odx when swept); the candidate pairs within 2 dhat into
 * m->cand, unless the cache still holds (0, or -1 on overflow); every stencil whose swept boxes,
 * each grown by grow, touch, handed to visit. */
void rt_obstacles_positions(romrt_model *m, const romrt_real *q, const romrt_real *dq);
void rt_obstacles_refit(romrt_model *m, int swept);
int rt_obstacles_gather(romrt_model *m);
typedef void (*rt_stencil_visit)(romrt_model *m, int edge_edge, const int32_t id[4], void *ctx);
void rt_obstacles_swept(romrt_model *m, int surface, romrt_real grow, rt_stencil_visit visit, void *ctx);
/* A gathered stencil kept in m->cand when within grow of its thickness: 0, or -1 (overflow
 * flagged) past the capacity. */
int rt_contact_keep(romrt_model *m, int edge_edge, const int32_t id[4], romrt_real grow);
/* contact_surface.c: the collision surface's stencils against itself (other objects', and its own
 * with self-contact) whose boxes grown by grow (swept over ocdx) touch: to visit, or (visit NULL)
 * kept by rt_contact_keep; -1 on overflow. */
int rt_surface_stencils(romrt_model *m, romrt_real grow, int swept, rt_stencil_visit visit, void *ctx);
/* Obstacle vertex o (a stencil id -1 - o): a baked one's (o < onv) in the arena, an app mesh's in
 * its index: where it is (RT_AT_NOW), its move (RT_AT_MOVE), friction's step start (RT_AT_START),
 * where the pairs were gathered (RT_AT_CACHE); its rest position (mesh frame for an app mesh). */
enum { RT_AT_NOW, RT_AT_MOVE, RT_AT_START, RT_AT_CACHE };
romrt_real *rt_obstacle_point(const romrt_model *m, uint32_t o, int which);
const romrt_real *rt_obstacle_rest(const romrt_model *m, uint32_t o);
/* App meshes (mesh_move.c): the step's start recorded / put back; whether one is short of its
 * pose; an app mesh vertex's (stencil id -1 - o) way from the step's start to its pose (0 when its
 * mesh does not move); the longest such way of slot k's mesh, squared; the moving meshes each at
 * its own progress s[u] of its way (u its joint unknown, obs_unit) with a CCD move ds[u] of it
 * (ds NULL: none; rt_meshes_at); the rest of the way into their dx (rt_meshes_way: those with
 * near[u] set, or all with near NULL); at the solve's end at their poses (arrive, and near[u] set
 * or near NULL) or left short of them; the BVH boxes refitted. */
void rt_meshes_begin(romrt_model *m);
void rt_meshes_abort(romrt_model *m);
int rt_meshes_pending(const romrt_model *m);
int rt_mesh_way(const romrt_model *m, uint32_t o, romrt_real D[3]);
romrt_real rt_mesh_longest_way2(const romrt_model *m, int k);
void rt_meshes_at(romrt_model *m, const romrt_real *s, const romrt_real *ds);
void rt_meshes_way(romrt_model *m, const int *near);
void rt_meshes_end(romrt_model *m, int arrive, const int *near);
void rt_mesh_refit(rt_mesh *M, int swept);
/* x = R X + p over the mesh's vertices (pose: position 3, rotation 9 row-major). */
void rt_mesh_world(const rt_mesh *M, const romrt_real *pose, romrt_real *x);
/* Slot's mesh leaves it (removed, reset or replaced): its pairs are dropped; whether an index was
 * built for mesh (mesh_index.c). */
void rt_mesh_leave(romrt_model *m, int slot);
/* M (its world positions in its index, a collider of `kind` at pose shape) placed in slot at
 * once: refused (ROMRT_E_ARGUMENT, naming romrt_set_mesh_collider for kind ROMRT_COLLIDER_MESH,
 * else romrt_set_collider) when it touches or crosses the body, or the pairs overflow
 * (ROMRT_E_LIMIT), the slot then as it was (mesh_collider.c). */
romrt_status rt_mesh_place(romrt_model *m, int slot, rt_mesh *M, int kind, const romrt_real *shape, romrt_error *err);
/* M's unique edges (from its triangles; with none, M->ne edges given), its BVH and its world
 * positions at its own frame: M's counts, X, tri and storage set (mesh_index.c). */
void rt_mesh_build(rt_mesh *M);
/* A sphere, capsule or box at pose shape placed in slot on the obstacles' path (shape_collider.c). */
romrt_status rt_shape_place(romrt_model *m, int slot, int kind, const romrt_real *shape, romrt_error *err);
int rt_mesh_index_of(const romrt_mesh *mesh);
/* The mesh's positions finite and its triangles' indices in range and distinct: ROMRT_OK, or
 * ROMRT_E_ARGUMENT naming the vertex or the triangle and corner (and the function: placing or
 * building). */
romrt_status rt_mesh_check(const romrt_mesh *mesh, int placing, romrt_error *err);
/* The mesh's items of `type` (ROMBIN_ITEM_*) whose boxes touch box (over its x): visit(their
 * local vertex ids); 1 as soon as a visit returns nonzero (contact_broad.c). */
int rt_mesh_query(const rt_mesh *M, const romrt_real box[6], int type, int (*visit)(const uint32_t *ids, void *ctx),
                  void *ctx);
/* A stencil's points at ocx / ox and its thickness and mollifier threshold. */
void rt_obstacles_stencil(const romrt_model *m, const int32_t id[4], const romrt_real *pts[4]);
romrt_real rt_obstacles_xi(const romrt_model *m, const int32_t id[4]);
romrt_real rt_obstacles_eps(const romrt_model *m, int edge_edge, const int32_t id[4]);
/* H (ld) += J^T B J and g += J^T gx over a stencil's collision vertices (B 12 x 12, gx 12; either
 * may be NULL); the slip's over its 3 rows sum_i w_i J_i (B3 3 x 3, gt 3) (contact_pull.c). */
void rt_obstacles_pull(romrt_model *m, const int32_t id[4], const romrt_real *gx, const romrt_real *B, romrt_real *g,
                       romrt_real *H, int ld);
void rt_obstacles_pull_slip(romrt_model *m, const int32_t id[4], const romrt_real w[4], const romrt_real gt[3],
                            const romrt_real *B3, romrt_real *g, romrt_real *H, int ld);
romrt_real rt_obstacles_friction(romrt_model *m, romrt_real *g, romrt_real *H, int ld);
romrt_real rt_contact_distance(const romrt_model *m, int c, const romrt_real *q);
romrt_real rt_contact_max_step(const romrt_model *m, const romrt_real *q, const romrt_real *dq);

/* Adaptive linear ROMs (alrom.c): the step's basis, inertia and forces before its solve, the state
 * moved on after it (or put back after a failed one); back to rest. */
romrt_status rt_alrom_begin(romrt_model *m, romrt_real *w_inertia, romrt_error *err);
romrt_status rt_alrom_commit(romrt_model *m, romrt_error *err);
void rt_alrom_abort(romrt_model *m);
void rt_alrom_reset(romrt_model *m);
/* Stored vertex v's position between steps (the quadratic decoder forms a vertex no step reads from
 * its K-space state only here: X0 + B_v c). */
void rt_alrom_position(const romrt_model *m, uint32_t v, romrt_real x[3]);
/* Row (v, a) of the last step's basis (r reals), for any shown vertex: a step forms only the rows
 * it reads. */
void rt_alrom_row(const romrt_model *m, uint32_t v, int a, romrt_real *out);
/* The collision vertices kept current from now on (a collider placed; rt_alrom_begin lets them go
 * while no collider and no collision surface reads them). */
void rt_alrom_take_collision_vertices(romrt_model *m);
/* Its state after the clock and have_prev (access.c's layout): rt_alrom_state_size reals; set
 * refuses (-1, changing nothing) ring counters out of range. */
int rt_alrom_state_size(const romrt_model *m);
void rt_alrom_get_state(const romrt_model *m, romrt_real *state);
int rt_alrom_set_state(romrt_model *m, const romrt_real *state);
/* A double as a pair of reals, hi + lo (hi the double rounded, lo the rest rounded toward zero):
 * exact in double, about 48 bits in float. */
void rt_split(double x, romrt_real *pair);
/* The app's force f on stored vertex v, kept in the full space (an adaptive basis changes every
 * step): added when apply; -1, adding nothing, when the sum would overflow. */
int rt_alrom_push(romrt_model *m, uint32_t v, const romrt_real f[3], int apply);

/* Koopman assets (koopman.c): their chunks, in the loader's passes; the step; back to t = 0. */
romrt_status rt_koopman_step(romrt_model *m, romrt_error *err);
void rt_koopman_reset(romrt_model *m);

/* The state at t = 0 (access.c; open and romrt_reset): at rest shape, with VEL0's velocity when
 * the asset has one. */
void rt_initial_state(romrt_model *m);

/* The shown positions' bounds (open.c, once): and whether positions X + rows q stay representable
 * for this q (steps refuse a state that would draw as Inf). */
void rt_position_bounds(romrt_model *m);
int rt_showable(const romrt_model *m, const romrt_real *q);

/* Dense kernels on r x r column-major matrices (dense.c). */
void rt_symv(int r, const romrt_real *S, const romrt_real *x, romrt_real *y); /* y = S x, S full */
romrt_real rt_dot(int r, const romrt_real *a, const romrt_real *b);
/* Cholesky of the upper triangle in place; 0, or the 1-based pivot that failed. */
int rt_cholesky(int r, romrt_real *H);
/* Solves (U^T U) x = b in place with the factor of rt_cholesky. */
void rt_cholesky_solve(int r, const romrt_real *U, romrt_real *b);
/* The same two in double whatever the build's precision. */
int rt_cholesky_wide(int r, double *H);
void rt_cholesky_solve_wide(int r, const double *U, double *b);

/* Writes status, chunk and message into err (which may be NULL). Returns status. */
romrt_status rt_error_from(romrt_error *err, romrt_status status, const rombin_error *e);
/* rt_error_from copies the container reader's message whole. */
typedef char rt_message_sizes_agree[ROMRT_MESSAGE_BYTES == ROMBIN_MESSAGE_BYTES ? 1 : -1];
romrt_status rt_fail(romrt_error *err, romrt_status status, const char *chunk, const char *text);
romrt_status rt_fail_n(romrt_error *err, romrt_status status, const char *chunk, const char *text1, uint64_t n,
                       const char *text2);
romrt_status rt_fail_nn(romrt_error *err, romrt_status status, const char *chunk, const char *text1, uint64_t n,
                        const char *text2, uint64_t n2, const char *text3);

/* Per-phase timing (bench/bench_pour.c, issue 30): the runtime has no clock, so a bench that
 * compiles the runtime's sources with -DROMRT_PROFILE supplies rt_prof_enter/rt_prof_leave; the
 * library compiles the hooks to nothing. Phases nest (a CCD visit inside a broad-phase query):
 * the bench charges each interval to the innermost open phase, and the rest of a step to Newton.
 *   RT_PROF_BROAD   the candidates: BVH refit and traversal against the obstacles, the surface's
 *                   sort and sweep, the Verlet list's box and distance filter (contact_broad.c,
 *                   contact_surface.c)
 *   RT_PROF_NARROW  per stencil: distance, barrier and its PSD projection, the pull into the
 *                   r x r system, friction, CCD, and the collision vertices' positions (contact.c,
 *                   contact_friction.c)
 * and an adaptive linear ROM's work around its Newton solve (bench/bench_alrom_split.c, issue 33):
 *   RT_PROF_ALROM_ENCODE  p = e(u), the quadratic decoder's Gauss-Newton (or CROM's networks)
 *   RT_PROF_ALROM_BASIS   U^T U, the history's Grams and basis, the thin QRs, the SVD and the
 *                         geodesic (alrom_basis.c, but the rows)
 *   RT_PROF_ALROM_ROWS    the step basis' K-space columns (C_s, W_F C_s), its rows at the used
 *                         vertices and the cubature elements' G_e
 *   RT_PROF_ALROM_TERMS   the step's reference, F(x_ref), M_r, f_r and the prediction, and the
 *                         commit (alrom.c) */
enum {
    RT_PROF_BROAD,
    RT_PROF_NARROW,
    RT_PROF_ALROM_ENCODE,
    RT_PROF_ALROM_BASIS,
    RT_PROF_ALROM_ROWS,
    RT_PROF_ALROM_TERMS,
    RT_PROF_PHASES
};
#ifdef ROMRT_PROFILE
void rt_prof_enter(int phase);
void rt_prof_leave(int phase);
#define RT_PROF_BEGIN(phase) rt_prof_enter(phase)
#define RT_PROF_END(phase) rt_prof_leave(phase)
#else
#define RT_PROF_BEGIN(phase) ((void)0)
#define RT_PROF_END(phase) ((void)0)
#endif

#endif
