/* precompute/pipeline: a rom entry's method as a table of operations. Each method is one module
 * (method_<name>.c with its header) that says which scene keys are its own, parses them into the
 * entry's method-owned block, runs the entry for romkit compare, bakes it and writes its rows of
 * the compare report. methods.c lists them, one line each; nothing else chooses by method.
 *
 * Why a fixed block (rk_rom_entry.own) and not a union or a pointer: a union would list every
 * method's options in the scene header, so adding a method would edit it; a pointer needs a free
 * and a deep copy wherever an entry is copied by value (alrom.c trains its cubature on a copy).
 * The block is copied with the entry, and each method's _Static_assert checks its options fit. */
#ifndef RK_PIPELINE_METHOD_H
#define RK_PIPELINE_METHOD_H

#include <stdio.h>

#include <cjson/cJSON.h>

#include "pipeline/pipeline.h"

/* The scene parser's context (parse_impl.h, private to this folder): methods outside it take no
 * keys of their own, or go through the keys-only helpers there. */
typedef struct rk_json_ctx rk_json_ctx;

/* ---- what romkit compare measures a method with (compare.h runs them) ---- */

/* A full-order run kept frame by frame. */
typedef struct {
    int ndof, T;
    const int *map;  /* NULL: every vertex of the run; else the run's vertex kept as vertex i (ndof / 3) */
    const rk_scene_layout *layout; /* else, when not NULL: the run taken back to the scene's vertices
                                    * (a scene with point clouds run on their bodies) */
    double *x, *v;   /* ndof x (T + 1): the start, then after every step */
    double *step_seconds;
    double min_distance;   /* contact over the frames: closest surfaces (m), most crossings */
    int intersections;
} rk_fom_frames;

/* The bytes of a compare result a method keeps for its own measurements. */
#define RK_COMPARE_OWN_BYTES 512

typedef struct {
    char name[96];
    const struct rk_method *method;
    rk_basis_type type;
    char basis_name[32];           /* the report's basis.type: the basis type's name unless the method says */
    int size;                      /* rom.size as built: columns, or weights m for skinning */
    int r;                         /* reduced coordinates */
    int cubature_points;           /* 0: exact */
    double cubature_error;
    double normalized_mse, normalized_max_error, max_error_m, relative_error, relative_online_error; /* util/util.h */
    double fit_normalized_mse;     /* the basis fitting residual (FreeForm Eq. 36, Table 6): every reference frame
                                    * fitted by the subspace in least squares, normalized MSE; NAN where the
                                    * method has no fixed linear basis (Koopman, adaptive) */
    double seconds_per_step, speedup;
    double seconds_basis, seconds_cubature, seconds_training_run; /* the last: 0 unless the basis needed frames */
    double seconds_fit;            /* Koopman: the DMD fit */
    long newton_iterations, unconverged_steps;
    double contact_min_distance;   /* over the free run's frames (INFINITY without contact) */
    int contact_intersections;     /* the most exact crossings in a frame (0) */
    int realign_clipped;           /* online error: steps whose projected start lay beyond contact
                                    * (the realignment stopped short where CCD did) */
    int training_frames;           /* the full-order frames its data-driven parts trained on */
    double reference_nmse;
    char reference_source[96];
    char basis_reason[256], cubature_reason[256];
    char volume_warning[256];      /* rk_scene_rom's: a volume that locks, or empty */
    char failure[1024];            /* empty when it ran; else why it did not (the error message) */
    /* what only this method measures (its header's type, read through rk_method_measures) */
    _Alignas(max_align_t) unsigned char own[RK_COMPARE_OWN_BYTES];
} rk_compare_method;

/* What a method's compare operation runs on: the built scene, its own full-order run (what
 * methods train on, D its displacement frames) and the reference errors are measured against
 * (the same run, or the refined one at the scene mesh's vertices). */
typedef struct {
    const rk_scene *scene;
    const rk_scene_sim *sim;
    const rk_fom_frames *fom, *ref;
    const double *D;               /* 3 nv x fom->T */
    const rk_sparse *M;            /* the scene's mass matrix */
    double fom_seconds_total;
    void **cache;                  /* the method's own, kept from entry to entry (rk_method.compare_free) */
    /* the training set last built (rk_compare_training), kept for the next entry with the same list */
    const rk_rom_entry *training_from;
    double *training_D;
    int training_T;
} rk_compare_ctx;

/* What entry e trains on: its training set when it lists one (built once for entries that list
 * the same runs), else the scene's own run (ctx->D, ctx->fom->T). Sets m->training_frames. */
int rk_compare_training(rk_compare_ctx *c, const rk_rom_entry *e, const double **D, int *T, rk_compare_method *m,
                        rk_error *err);
/* Whether two entries list the same training runs (the same files, in the same order). */
int rk_compare_same_training(const rk_rom_entry *a, const rk_rom_entry *b);
/* A free run's errors (util/util.h) into m: normalized MSE, max error, relative error. */
void rk_compare_record_errors(rk_compare_method *m, const rk_run_error *e);
/* The method did not run: why, and its numbers NAN. */
void rk_compare_record_failure(rk_compare_method *m, const rk_error *err);
/* m->fit_normalized_mse (basis_fit.c): each frame of ref after the start fitted by X + U q in
 * least squares over the vertices (FreeForm Eq. 36), measured as a free run is. */
int rk_compare_basis_fit(const double *U, int ndof, int r, const double *X, const rk_fom_frames *ref,
                         rk_compare_method *m, rk_error *err);

/* ---- the table ---- */

typedef struct rk_method {
    const char *name;              /* rom[i].method's value; the compare report's "kind" is kind */
    const char *kind;
    /* an entry naming no method (or "fixed") with this key is this method (koopman's section);
     * such a method is not chosen by name */
    const char *implied_by;
    const char *const *keys;       /* entry keys only this method takes (NULL-terminated, or NULL) */
    int basis_required;            /* the entry must name its basis */
    int training_needs_pod;        /* a "training" list needs basis pod */
    int reduced_model;             /* builds a fixed-basis reduced model (rom.c): takes pin_stiffness */
    int measures_contact;          /* its runs report contact (the Koopman operator models none) */
    const char *table_cubature;    /* the compare table's cub column (NULL: the cubature's size) */
    /* Checks before the shared keys are read (keys that would be misread); may be NULL. */
    int (*check)(const rk_json_ctx *c, const cJSON *e, const char *path);
    /* The method's own keys into o->own (the basis keys are parsed already; h: the time step). */
    int (*parse)(const rk_json_ctx *c, const cJSON *e, const char *path, double h, rk_rom_entry *o);
    /* The entry's name when it gives none. */
    void (*default_name)(const rk_rom_entry *e, char *name, size_t size);
    /* romkit compare: the free run (errors against c->ref, time per step) and the realigned one. */
    int (*compare)(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);
    void (*compare_free)(void *cache);
    /* rk_scene_bake of the entry (options ao: the entry's, with the request's overrides). */
    int (*bake)(const rk_scene *scene, const rk_rom_entry *e, const rk_bake_request *req, const rk_asset_options *ao,
                rk_baked *out, rk_error *err);
    /* The method's own keys of its compare report object, and its line under the table (NULL: the
     * basis and cubature reasons). Only for a method that ran. */
    void (*report)(const rk_compare_method *m, cJSON *j);
    void (*print)(const rk_compare_method *m, FILE *f);
} rk_method;

/* The methods, in registration order (methods.c), and how many. */
const rk_method *rk_method_at(int i);
int rk_method_count(void);
/* The method named name (not one a key implies), or NULL. */
const rk_method *rk_method_find(const char *name);
/* Adds m after the built-in methods (tests: a toy method); at most a few. Returns 0, or -1 when
 * full or m's name is taken. */
int rk_method_register(const rk_method *m);
/* The method's own options block of e, or NULL when e is another method's. */
const void *rk_method_options(const rk_rom_entry *e, const rk_method *m);
/* The method's own measurements in m (RK_COMPARE_OWN_BYTES), or NULL when m is another method's. */
void *rk_method_measures(rk_compare_method *m, const rk_method *method);

/* For a method's parse outside this folder (its parse gets an opaque context): a finite number
 * under key (absent: *out unchanged), and a failure "<file>: <path>: <message>" (returns -1). */
int rk_method_number(const rk_json_ctx *c, const cJSON *e, const char *path, const char *key, double *out);
int rk_method_fail(const rk_json_ctx *c, const char *path, const char *message);

/* Shared by fixed and Koopman entries: the default name of a basis entry ("<basis>-<size|tol>
 * [-meshfree][-cubature]"), and the bake of its reduced model and/or Koopman operator. */
void rk_method_basis_name(const rk_rom_entry *e, char *name, size_t size);
int rk_method_bake_models(const rk_scene *scene, const rk_rom_entry *e, const rk_bake_request *req,
                          const rk_asset_options *ao, rk_baked *out, rk_error *err);

#endif
