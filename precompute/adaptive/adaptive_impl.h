/* Private to precompute/adaptive: the running reduced model and the pieces of a Newton iteration. */
#ifndef RK_ADAPTIVE_IMPL_H
#define RK_ADAPTIVE_IMPL_H

#include "adaptive/adaptive.h"
#include "contact/contact.h"
#include "fem/fem.h"

/* A subdomain: the elements of one METIS part (an element belongs to its first vertex's part),
 * over the local vertices they touch. */
typedef struct {
    int ne, *elem;
    int nv, *vert;          /* local vertex -> mesh vertex */
    int *local;             /* 4 ne: each element's vertices, local */
    int exact;              /* holds an enriched vertex: integrated exactly (Sec. 3.9) */
    double *B;              /* a x a: its BFGS elastic subspace Hessian; when exact, the masked exact one */
    double *Bu;             /* a x a: when exact, the unmasked exact one (the oracle's) */
    double *proj;           /* a: U_l^T grad Psi_l at the last iterate (the secant's y, Eq. 20) */
    int have_proj;
} rk_subdomain;

/* The full symmetric pattern (both triangles, rows sorted) of the fem pattern, and where each
 * upper-stored entry k lands: up[k] at (row, col), lo[k] at (col, row) (the same on the diagonal). */
typedef struct {
    int n, nnz;
    int *rowptr, *col;
    int *up, *lo;
} rk_full_pattern;

struct rk_adaptive_impl {
    const rk_fem *f;
    int nv, n;                  /* vertices, 3 nv */
    rk_fom_view view;
    /* the candidate basis, prescribed rows zeroed (the subspace cannot move what is prescribed) */
    double *U;                  /* n x r */
    int r, nblocks;
    /* the measures' scales (measures.c) and the oracle's per-vertex buffers */
    double *psi_bar, *area, *volume;
    double *G, *dE, *e0, *e1;   /* nv */
    double *prog;               /* nv: the nodal progress E_i at the last oracle evaluation */
    char *solved_enriched;      /* nv: the enrichment the last step's solve ended with (before downdating) */
    double *gscale, *gpsi;      /* nv: the error's scale as area and psi_bar (paper units: those; else
                                 * rk_adaptive_tolerance_scale and ones) */
    double *pscale;             /* nv: the progress's scale as volume, with gpsi (paper: volume; else
                                 * rk_adaptive_tolerance_scale's progress scale) */
    double length;              /* the rest bounding-box diagonal (downdating, Sec. 3.11) */
    /* the partition */
    int *part;                  /* nv: METIS part of each vertex */
    int L;
    rk_subdomain *sub;
    int *part_first, *part_vert;/* the vertices of each part (L + 1 offsets) */
    /* the active model */
    char *block_on;             /* nblocks */
    int a, *cols;               /* active columns of U */
    double *Ua;                 /* n x a, unmasked */
    double *Ba;                 /* n x a, masked at enriched dofs */
    char *enriched;             /* nv */
    int nx, *xdof;              /* enriched dofs (free ones), ascending */
    int *xindex;                /* n: position in xdof or -1 */
    double *q_total;            /* r: each column's coordinate summed over the step (downdating) */
    /* the system's pieces */
    rk_full_pattern P;
    double *Mf, *Cf;            /* M and C on the full pattern */
    double *Hf;                 /* w_i M + w_d C + the exact elements' Hessians, full pattern */
    double *UMU, *UCU;          /* a x a: U_a^T M U_a, U_a^T C U_a */
    double *BMB, *BCB;          /* a x a: masked */
    double *MU, *CU;            /* n x a: M U_a, C U_a */
    int columns_valid;          /* MU, CU, UMU, UCU are for the current columns */
    int inertia_valid;          /* BMB, BCB are for the current columns and mask */
    double *Ha, *Hq;            /* a x a: unmasked (the oracle's) and masked (the system's) */
    double *Lq;                 /* a x a Cholesky factor of Hq */
    char *elem_exact;           /* nt: in an exact subdomain */
    double *He;                 /* nt x 78: the element Hessians computed this iteration (exact ones) */
    /* the Schur system over the enriched dofs */
    int *hx_rowptr, *hx_col;    /* the enriched dofs' rows restricted to enriched columns */
    double *hx_val;
    int hx_cap;
    int ncoup, *coup_dof;       /* enriched dofs coupled to the modal dofs: C's columns */
    double *Cq;                 /* a x ncoup */
    double *c_part;             /* a per chunk of C's columns: C x's partial sums (system.c) */
    double *Dinv;               /* 9 per enriched vertex: the block-Jacobi preconditioner */
    int nctri, capctri, *ctri_r;/* contact entries among enriched dofs: (row, column) pairs */
    double *ctri_v;             /* and their values */
    int *coup_pos;              /* n: each enriched dof's column in Cq or -1 */
    int *block_size;            /* n: the preconditioner's block at its first dof */
    char *part_mark_dofs;       /* n */
    /* scratch */
    double *gq, *dq, *dx, *rhs, *work, *pcg_work, *xtry, *sc_a;
    double *sc1, *sc2, *sc3, *sc4;  /* n each */
    double *elem_e;             /* nt element energies (the oracle's scratch) */
    double *elem_psi, *elem_g;  /* nt, 12 nt: each element's elastic energy and gradient at the iterate */
    char *part_mark;            /* L */
    char *fixed_vertex;         /* nv: every dof prescribed (never enriched) */
    int free_vertices;          /* nv less the fixed ones: what full_fraction is a share of */
    int go_full;                /* this step's enrichment passed opt.full_fraction: full order finishes it */
    int stepped_full;           /* the last step was finished by full order */
    int oracle_this_step;       /* the oracle ran in this step (its G and prog are this step's) */
    int full_this_step;         /* some solve of this step went to full order (a prescribed motion's safe
                                 * moves and friction's lagged solves are several solves of one step) */
    int full_wait, full_backoff;/* steps still to hand to full order at once; how many the next switch sets */
    double *x_start;            /* n: where the step's Newton started (full order starts there too) */
    int model_dirty;            /* downdating changed the model: rebuild before the next solve */
    /* the Newton iteration the solver is in */
    const rk_fom_terms *T;
    double *g, *x_prev, *d_last;/* n: the gradient, the iterate and direction of the last Hessian */
    int have_prev;
    double *newton_work;        /* RK_NEWTON_WORK(n + kcap) */
    double *x_moved;            /* n: what the step's Newton iterations moved x by (downdating; Newton
                                 * may start from the prediction, which no coordinate accounts for) */
    rk_contact_set pairs;       /* the oracle's own contact pairs */
    int first_iteration;        /* the next Newton iteration is a solve's first (BFGS restarts) */
    double *dq_last;            /* a: alpha d_q of the last Newton step (the secant's s) */
    int have_step;
    /* moving obstacles (obstacles.c): each one's progress s_k along the step's way is unknown n + k
     * beside x (k < way->n) */
    rk_obstacle_way *way;       /* the step's way while a joint solve runs, else NULL */
    double mass;                /* the body's (the pull's scale) */
    int kcap;                   /* progress unknowns the arrays below have room for (rk_adaptive_progress_room) */
    double *y;                  /* n + kcap: x and s */
    char *prescribed_y;         /* n + kcap: the prescribed dofs, and s free */
    double *hxs, *sx, *dq_b;    /* n kcap, n kcap, r kcap: d2/dx ds_k, its solve and that solve's d_q (column k) */
    double *hss;                /* kcap x kcap: d2/ds2 at the last Hessian (leading dimension way->n) */
};

/* partition.c */
int rk_adaptive_partition(rk_adaptive_impl *im, int parts, rk_error *err);
void rk_adaptive_partition_free(rk_adaptive_impl *im);
int rk_full_pattern_init(rk_full_pattern *P, const rk_sparse *upper, rk_error *err);
void rk_full_pattern_free(rk_full_pattern *P);
/* y = A x on the full pattern's values val. */
void rk_full_mul(const rk_full_pattern *P, const double *val, const double *x, double *y);

/* model.c: the active columns and the mask */
int rk_adaptive_set_columns(rk_adaptive *a, rk_error *err);
void rk_adaptive_update_mask(rk_adaptive *a);
int rk_adaptive_enrich_part(rk_adaptive *a, int part);

/* hessian.c: the subspace Hessians Ha and Hq at x (g: the full gradient there) */
int rk_adaptive_element_hessians(rk_adaptive *a, const double *x, int all, rk_error *err);
int rk_adaptive_subspace_hessian(rk_adaptive *a, const rk_fom_terms *T, const double *x, rk_error *err);
/* The BFGS secant pairs from the elastic gradient at x, element by element in im->elem_g (the step
 * that led here: im->dq_last). */
void rk_adaptive_bfgs_update(rk_adaptive *a, const double *x);
/* Exact subspace Hessians of every subdomain at x into their BFGS matrices (a solve's start, a
 * change of the active columns). */
int rk_adaptive_bfgs_restart(rk_adaptive *a, const double *x, rk_error *err);

/* oracle.c */
/* The subspace systems' diagonal shifts tried before giving up (rk_spd_solve_shifted): up to
 * 1e2 times the largest diagonal entry, for a masked H_q that is near zero. */
#define RK_ADAPTIVE_SHIFTS 8
int rk_adaptive_oracle(rk_adaptive *a, const rk_fom_terms *T, const double *x, double E, const double *g,
                       int *changed_modes, int *changed_nodes, rk_error *err);
void rk_adaptive_downdate(rk_adaptive *a);

/* obstacles.c: the joint solve of x and the obstacles' progress s (contact.h, rk_obstacle_way) */
/* Adds the pull and d/ds into E and g[n] at y (obstacles placed at y[n]); with hessian, d2/ds2
 * and d2/dx ds from the potential's contact blocks (im->view, fresh). */
double rk_adaptive_obstacle_terms(rk_adaptive *a, const double *y, double *g, int hessian, double *magnitude);
/* d (n + k) for the bordered system [H hxs; hxs^T hss] by k + 1 Schur solves (Eq. 19's with g,
 * then with each column of hxs): Eq. 19's d_q and d_x, and d_s. */
int rk_adaptive_solve_bordered(rk_adaptive *a, const rk_fom_terms *T, const double *g, double *d, rk_error *err);
/* Room in y, prescribed_y, newton_work and the bordered solve's arrays for k progress unknowns. */
int rk_adaptive_progress_room(rk_adaptive_impl *im, int k, rk_error *err);

/* system.c: d (n) from Eq. 19 by the Schur complement */
/* y (n) = A c for A n x a (column-major), rows on the threads, each row summed in column order. */
void rk_adaptive_combine(int n, int a, const double *A, const double *c, double *y);
int rk_adaptive_solve(rk_adaptive *a, const rk_fom_terms *T, const double *g, double *d, rk_error *err);

/* Dense helpers (OpenBLAS): C = A^T B with A n x a, B n x b (column-major); fixed blocks of C's
 * columns on the threads (hessian.c). */
void rk_dense_atb(int n, int a, int b, const double *A, const double *B, double *C);
/* The per-vertex one-ring potential e (nv) at x (energy.c); +INFINITY where undefined. */
int rk_adaptive_vertex_energy(rk_adaptive *a, const rk_fom_terms *T, const double *x, const double *elem_psi,
                              double *e, rk_error *err);
/* The elastic energy's terms at x, element by element, into im->elem_psi and elem_g (energy.c);
 * returns their sum (+INFINITY where undefined) and adds the gradient into g. */
double rk_adaptive_elastic(rk_adaptive *a, const double *x, double *g);
/* The elastic energy at x, each element's into elem (nt); +INFINITY where undefined. */
double rk_adaptive_elastic_energy(rk_adaptive *a, const double *x, double *elem);

#endif
