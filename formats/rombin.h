/* formats/rombin.h: the on-disk constants and records of the .rombin container (ROMBIN.md is
 * the normative text; every number here is stated there). Pure C99, no dependencies: the
 * runtime, the validating reader and the toolchain's writer all include it. */
#ifndef ROMBIN_H
#define ROMBIN_H

#include <stdint.h>

/* 8 bytes: a non-ASCII byte (7-bit transfers), "ROM", CR LF (CRLF <-> LF conversion), ^Z
 * (stops a DOS "type"), LF (LF -> CRLF conversion). */
#define ROMBIN_SIGNATURE "\x89ROM\r\n\x1a\n"
#define ROMBIN_SIGNATURE_BYTES 8

#define ROMBIN_VERSION_MAJOR 1   /* a reader rejects any other major */
#define ROMBIN_VERSION_MINOR 11  /* a reader accepts any minor of its major (minors only add) */

#define ROMBIN_ENDIAN_SENTINEL 0x01020304u
#define ROMBIN_F32_SENTINEL (-1.5f)               /* bits 0xBFC00000 */
#define ROMBIN_F64_SENTINEL (0.1)                 /* bits 0x3FB999999999999A */

#define ROMBIN_HEADER_BYTES 64
#define ROMBIN_ENTRY_BYTES 40
#define ROMBIN_ALIGN 16          /* every payload offset is a multiple of this */
#define ROMBIN_MAX_CHUNKS 64

/* Header field offsets (bytes from the file start, little-endian). */
enum {
    ROMBIN_H_SIGNATURE = 0,      /* 8 bytes */
    ROMBIN_H_MAJOR = 8,          /* u16 */
    ROMBIN_H_MINOR = 10,         /* u16 */
    ROMBIN_H_ENDIAN = 12,        /* u32 ROMBIN_ENDIAN_SENTINEL */
    ROMBIN_H_F32 = 16,           /* f32 ROMBIN_F32_SENTINEL */
    ROMBIN_H_REAL = 20,          /* u32 ROMBIN_REAL_* of every real chunk */
    ROMBIN_H_F64 = 24,           /* f64 ROMBIN_F64_SENTINEL */
    ROMBIN_H_FILE_BYTES = 32,    /* u64 the whole file */
    ROMBIN_H_CHUNKS = 40,        /* u32 entries in the table */
    ROMBIN_H_FLAGS = 44,         /* u32 reserved, 0 */
    ROMBIN_H_TABLE_CRC = 48,     /* u32 CRC-32 of bytes [0, 48) and of the whole table */
    ROMBIN_H_RESERVED = 52       /* 12 bytes, 0 */
};

/* Chunk table entry field offsets (bytes from the entry start). */
enum {
    ROMBIN_E_ID = 0,             /* 4 bytes, printable ASCII */
    ROMBIN_E_FLAGS = 4,          /* u32 */
    ROMBIN_E_OFFSET = 8,         /* u64 from the file start, multiple of ROMBIN_ALIGN */
    ROMBIN_E_STORED = 16,        /* u64 bytes in the file */
    ROMBIN_E_RAW = 24,           /* u64 bytes once decoded (== stored when not compressed) */
    ROMBIN_E_CRC = 32,           /* u32 CRC-32 of the stored bytes */
    ROMBIN_E_RESERVED = 36       /* u32, 0 */
};

/* Real arrays: one type per file. */
enum { ROMBIN_REAL_F32 = 1, ROMBIN_REAL_F64 = 2 };

/* Entry flags. */
#define ROMBIN_FLAG_CRITICAL 0x1u              /* a reader that does not know the id rejects the file */
#define ROMBIN_TYPE_SHIFT 8                    /* bits 8..11: element type */
#define ROMBIN_TYPE_MASK (0xFu << ROMBIN_TYPE_SHIFT)
#define ROMBIN_COMP_SHIFT 16                   /* bits 16..19: compression */
#define ROMBIN_COMP_MASK (0xFu << ROMBIN_COMP_SHIFT)
#define ROMBIN_FLAGS_KNOWN (ROMBIN_FLAG_CRITICAL | ROMBIN_TYPE_MASK | ROMBIN_COMP_MASK)
enum { ROMBIN_TYPE_BYTES = 0, ROMBIN_TYPE_U32 = 1, ROMBIN_TYPE_REAL = 2 };
enum { ROMBIN_COMP_NONE = 0, ROMBIN_COMP_DEFLATE = 1 };

/* The reduced-model chunks of version 1 (ROMBIN.md, "Model chunks"). */
#define ROMBIN_HEAD "HEAD"   /* u32 x ROMBIN_HEAD_COUNT, critical */
#define ROMBIN_PARM "PARM"   /* real x ROMBIN_PARM_COUNT, critical */
#define ROMBIN_VERT "VERT"   /* real, vertices x 3: rest positions of the stored vertices */
#define ROMBIN_ROWS "ROWS"   /* real, vertices x 3 x r: their basis rows */
#define ROMBIN_MASS "MASS"   /* real, r x r: U^T M U */
#define ROMBIN_DAMP "DAMP"   /* real, r x r: U^T (a M + b K0) U (present iff damped) */
#define ROMBIN_LOAD "LOAD"   /* real, r: U^T f_ext */
#define ROMBIN_VEL0 "VEL0"   /* real, r: the reduced velocity at t = 0 (1.8, critical; absent: at rest) */
#define ROMBIN_PENA "PENA"   /* real, r x r: the pin penalty's quadratic term (present iff pins) */
#define ROMBIN_PINS "PINS"   /* real, pins x (12 + 12 r): motion, then T (r x 12) */
#define ROMBIN_LIFT "LIFT"   /* real, ROMBIN_LIFT_COUNT (1.11, critical): a lifted group's motion, then its handle's first column */
#define ROMBIN_ELEM "ELEM"   /* u32, elements x 5: 4 vertices, material model */
#define ROMBIN_ELMR "ELMR"   /* real, elements x 12: Dm^-1 (9), weight (m^3), mu, lambda */
#define ROMBIN_PLAN "PLAN"   /* real, planes x 6: point, unit normal */
#define ROMBIN_CONT "CONT"   /* u32, contacts x 2: vertex, plane */
#define ROMBIN_CVTX "CVTX"   /* u32: the collision vertices an app's colliders act on (1.1, optional) */
#define ROMBIN_FRIC "FRIC"   /* real x ROMBIN_FRIC_COUNT: friction (1.1, optional) */
#define ROMBIN_SKIN "SKIN"   /* u32 x 1: ROWS are linear blend skinning over this many handles (1.2, optional) */
#define ROMBIN_WGHT "WGHT"   /* real x vertices x handles: the skinning weights, in place of ROWS (1.2, critical) */
#define ROMBIN_IPNT "IPNT"   /* real, points x (6 + 4 H): mesh-free integration points (1.3, critical with points) */
#define ROMBIN_IPMD "IPMD"   /* u32, points: their material models (1.3, critical with points) */
#define ROMBIN_VPRS "VPRS"   /* real, (elements + points) x k: the projected volume's pressure functions (1.9, critical) */
#define ROMBIN_GRAD "GRAD"   /* real, shown x H x 3: the skinning weights' gradients at the shown vertices (1.3, optional) */
#define ROMBIN_SPLY "SPLY"   /* bytes: the source Gaussian-splat PLY, every attribute (1.3, optional; romkit run --splats) */
#define ROMBIN_GRPS "GRPS"   /* u32, groups x 2: first, count into GVTX (optional) */
#define ROMBIN_GVTX "GVTX"   /* u32: vertices of every group (optional) */
#define ROMBIN_GNAM "GNAM"   /* bytes, groups x 32: NUL-padded names (optional) */
#define ROMBIN_SURF "SURF"   /* u32, triangles x 3 over the shown vertices (optional) */
#define ROMBIN_VMAP "VMAP"   /* u32, vertices: the source mesh's vertex number (optional) */
#define ROMBIN_INFO "INFO"   /* bytes: JSON text about the build (optional) */
/* Several objects colliding with each other (ROMBIN.md "Object chunks"): COBJ (critical) names
 * each collision vertex's object; since 1.7 the objects touch through their collision surfaces
 * (CEDG, CTRI under OBHD). CRAD, 1.5's sphere proxies, is no longer written, and refused. */
#define ROMBIN_COBJ "COBJ"   /* u32, CVTX's count: the object of each collision vertex */
#define ROMBIN_CRAD "CRAD"   /* 1.5 only: real, objects: each object's proxy radius (refused since 1.7) */

/* The scene's obstacles other than planes (ROMBIN.md "Obstacle chunks", 1.6): spheres, capsules,
 * boxes and triangle meshes, static or moving, as the reduced simulator's contact stage holds them
 * (precompute/contact/collision.c), with a bounding volume hierarchy per obstacle, and the
 * collision surface of the object. All critical: a 1.5 reader refuses the asset rather than let
 * the object fall through them. */
#define ROMBIN_OBHD "OBHD"   /* u32, ROMBIN_OBHD_COUNT + obstacles x ROMBIN_OBST_COUNT: counts, then each obstacle's ranges */
#define ROMBIN_OBJS "OBJS"   /* real, obstacles x 4: thickness xi (a sphere's, a capsule's radius; else 0), 0, 0, 0 */
#define ROMBIN_OBMO "OBMO"   /* real, obstacles x ROMBIN_PIN_PARAMS: each obstacle's motion (kind, axis, center, rate, velocity, 0) */
#define ROMBIN_OBVX "OBVX"   /* real, vertices x 3: the obstacles' vertices at rest (t = 0) */
#define ROMBIN_OBED "OBED"   /* u32, edges x 2: obstacle edges (triangle edges, capsule segments) */
#define ROMBIN_OBTR "OBTR"   /* u32, triangles x 3: obstacle triangles (boxes and meshes) */
#define ROMBIN_OBVN "OBVN"   /* u32, nodes x 3: BVH nodes, (0, left, right) or (1, first item, items) */
#define ROMBIN_OBVB "OBVB"   /* real, nodes x 6: each node's box at rest (min xyz, max xyz), thickness included */
#define ROMBIN_OBIT "OBIT"   /* u32, items: a leaf's primitives, index << 2 | ROMBIN_ITEM_* */
#define ROMBIN_CEDG "CEDG"   /* u32, edges x 2: the collision surface's edges over CVTX's positions */
#define ROMBIN_CTRI "CTRI"   /* u32, triangles x 3: its triangles over CVTX's positions */
enum { ROMBIN_ITEM_VERTEX = 0, ROMBIN_ITEM_EDGE = 1, ROMBIN_ITEM_TRIANGLE = 2 };
enum {
    ROMBIN_OBHD_OBSTACLES = 0,   /* obstacles (not planes: those are PLAN) */
    ROMBIN_OBHD_VERTICES,        /* OBVX */
    ROMBIN_OBHD_EDGES,           /* OBED */
    ROMBIN_OBHD_TRIANGLES,       /* OBTR */
    ROMBIN_OBHD_NODES,           /* OBVN, OBVB */
    ROMBIN_OBHD_ITEMS,           /* OBIT */
    ROMBIN_OBHD_PAIRS,           /* the runtime's pair capacity (candidates and friction pairs each) */
    ROMBIN_OBHD_FLAGS,           /* 1.7: ROMBIN_OBHD_SELF; 1.10: ROMBIN_OBHD_COLLIDERS; other bits 0 */
    ROMBIN_OBHD_COUNT = 8
};
enum {
    ROMBIN_OBHD_SELF = 1u,       /* each object's surface also touches itself (contact.self) */
    ROMBIN_OBHD_COLLIDERS = 2u   /* the surface is there for the app's colliders alone (no obstacle,
                                  * one object, no self-contact; 1.10) */
};
enum {
    ROMBIN_OBST_KIND = 0,        /* 1 sphere, 2 capsule, 3 box, 4 mesh (precompute/contact's kinds) */
    ROMBIN_OBST_FIRST_VERTEX, ROMBIN_OBST_VERTICES,
    ROMBIN_OBST_FIRST_EDGE, ROMBIN_OBST_EDGES,
    ROMBIN_OBST_FIRST_TRIANGLE, ROMBIN_OBST_TRIANGLES,
    ROMBIN_OBST_ROOT,            /* its BVH's first node (the root); its nodes follow */
    ROMBIN_OBST_NODES,
    ROMBIN_OBST_COUNT = 10       /* the rest reserved, 0 */
};
#define ROMBIN_MAX_OBSTACLES 64u  /* OBHD obstacles a reader takes (ROMBIN.md "Limits") */
#define ROMBIN_BVH_DEPTH 48u      /* deeper BVHs are refused: the runtime's traversal stack */

/* An adaptive linear ROM (ROMBIN.md "Adaptive linear ROM chunks", 1.4): beside a reduced model's
 * chunks, whose ROWS are then the quadratic decoder's linear part at the stored vertices. */
#define ROMBIN_ALRH "ALRH"   /* u32 x ROMBIN_ALRH_COUNT, critical */
#define ROMBIN_ALRP "ALRP"   /* real x ROMBIN_ALRP_COUNT, critical */
#define ROMBIN_QDRV "QDRV"   /* real, vertices x 3 x pairs: the decoder's modal derivatives */
#define ROMBIN_VMSS "VMSS"   /* real, vertices: each stored vertex's mass (kg), the mesh's lumped onto them */
#define ROMBIN_VLOD "VLOD"   /* real, vertices x 3: the external force on each (N): gravity and loads */
#define ROMBIN_AMOV "AMOV"   /* u32, vertices: a stored vertex's prescribed motion, or ROMBIN_NO_MOTION */
#define ROMBIN_AMOT "AMOT"   /* real, motions x ROMBIN_PIN_PARAMS: kind, axis, center, rate, velocity, 0 */
#define ROMBIN_CRMS "CRMS"   /* u32: a CROM decoder's layer counts and sizes (1.4) */
#define ROMBIN_CRMX "CRMX"   /* real, vertices x 3: the decoder's normalised rest positions */
#define ROMBIN_CRMW "CRMW"   /* real: the encoder's, then the decoder's parameters, and the scale */
#define ROMBIN_NO_MOTION 0xFFFFFFFFu
#define ROMBIN_MAX_MOTIONS 64u   /* AMOT entries a reader takes (ROMBIN.md "Limits") */

enum {
    ROMBIN_ALRH_HISTORY = 0,     /* m: the steps the history basis spans */
    ROMBIN_ALRH_PAIRS,           /* r (r + 1) / 2: the modal derivatives per row */
    ROMBIN_ALRH_MOTIONS,         /* prescribed motions (AMOT) */
    ROMBIN_ALRH_DECODER,         /* 0: quadratic (QDRV), 1: CROM (CRMS, CRMX, CRMW) */
    ROMBIN_ALRH_CADENCE,         /* K: the basis refreshed every K steps, held between (0 or 1: every step) */
    ROMBIN_ALRH_ENCODER,         /* the encoder's Gauss-Newton iterations at most (0: 20) */
    ROMBIN_ALRH_COUNT = 8        /* the rest reserved, 0 */
};

enum {
    ROMBIN_ALRP_LAMBDA = 0,      /* the Grassmann interpolation parameter, 0..1 */
    ROMBIN_ALRP_REG,             /* P P^T's regularisation (1e-8) */
    ROMBIN_ALRP_DAMPING,         /* a of the mass-proportional damping a M */
    ROMBIN_ALRP_RIDGE,           /* the history basis' ridge toward the decoder's basis (0: Eq. 13) */
    ROMBIN_ALRP_BUDGET,          /* what the history may add to a step's growth factor (0: unbounded) */
    ROMBIN_ALRP_COUNT = 8        /* the rest reserved, 0 */
};

/* A Koopman operator (ROMBIN.md "Koopman chunks"): KHED and the chunks below, over the stored
 * vertices of VERT (with GRPS, GVTX, GNAM, SURF, VMAP and INFO); alone, or beside a reduced model
 * in the same asset. */
#define ROMBIN_KHED "KHED"   /* u32 x ROMBIN_KHED_COUNT, critical */
#define ROMBIN_KPRM "KPRM"   /* real x ROMBIN_KPRM_COUNT, critical */
#define ROMBIN_KEIG "KEIG"   /* real, r x 2: discrete-time eigenvalues (re, im) in block order */
#define ROMBIN_KOUT "KOUT"   /* real, vertices x 3 x r: output rows, x_v = X_v + rows y */
#define ROMBIN_KIMP "KIMP"   /* real, vertices x 3 x r: impulse rows over the vertex mass */
#define ROMBIN_KACC "KACC"   /* real, r: the constant acceleration's impulse per h h' */
#define ROMBIN_KINI "KINI"   /* real, r: the state at t = 0 */

enum {
    ROMBIN_HEAD_R = 0,           /* reduced coordinates */
    ROMBIN_HEAD_VERTICES,        /* stored vertices (rows) */
    ROMBIN_HEAD_SHOWN,           /* the first `shown` stored vertices are the ones an app draws */
    ROMBIN_HEAD_ELEMENTS,        /* quadrature elements */
    ROMBIN_HEAD_PINS,            /* prescribed groups held by the penalty */
    ROMBIN_HEAD_PLANES,
    ROMBIN_HEAD_CONTACTS,        /* (vertex, plane) barrier pairs */
    ROMBIN_HEAD_GROUPS,          /* named vertex groups an app may push */
    ROMBIN_HEAD_INTEGRATOR,      /* 0 backward Euler, 1 BDF2 */
    ROMBIN_HEAD_NEWTON_MAX_ITER,
    ROMBIN_HEAD_SOURCE_VERTICES, /* of the full mesh (information) */
    ROMBIN_HEAD_SOURCE_TETS,
    ROMBIN_HEAD_POINTS,          /* mesh-free integration points (IPNT; 1.3) */
    ROMBIN_HEAD_COUNT = 16       /* the rest reserved, 0 */
};

enum {
    ROMBIN_FRIC_MU = 0,          /* Coulomb coefficient */
    ROMBIN_FRIC_EPS_V,           /* slip speed below which friction is static (m/s) */
    ROMBIN_FRIC_ITERATIONS,      /* lagging iterations per step */
    ROMBIN_FRIC_COUNT = 4        /* the rest reserved, 0 */
};

enum {
    ROMBIN_KHED_R = 0,           /* eigen-coordinates */
    ROMBIN_KHED_VERTICES,        /* stored vertices */
    ROMBIN_KHED_SHOWN,
    ROMBIN_KHED_GROUPS,
    ROMBIN_KHED_SOURCE_VERTICES, /* information */
    ROMBIN_KHED_SOURCE_TETS,
    ROMBIN_KHED_TRAJECTORIES,    /* training trajectories (information) */
    ROMBIN_KHED_COUNT = 16       /* the rest reserved, 0 */
};

enum {
    ROMBIN_KPRM_H = 0,           /* the training data's time step (s) */
    ROMBIN_KPRM_COUNT = 8        /* the rest reserved, 0 */
};

enum {
    ROMBIN_PARM_H = 0,           /* time step (s) */
    ROMBIN_PARM_NEWTON_TOL,      /* on sqrt(dq^T M_r dq / mass) (m) */
    ROMBIN_PARM_MASS,            /* total mass (kg) */
    ROMBIN_PARM_DHAT,            /* barrier range (m) */
    ROMBIN_PARM_KAPPA,           /* barrier stiffness per kg */
    ROMBIN_PARM_COUNT = 8        /* the rest reserved, 0 */
};

#define ROMBIN_PIN_PARAMS 12     /* kind, axis (3), center (3), rate, velocity (3), 0 */
#define ROMBIN_LIFT_COUNT 13     /* LIFT: the motion (ROMBIN_PIN_PARAMS, as PINS's), the handle's first column */
#define ROMBIN_GROUP_NAME_BYTES 32

#endif
