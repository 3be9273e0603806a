/* romrt.h: the romkit runtime, the one header an application includes.
 *
 * Steps a reduced-order model baked by `romkit build` into a .rombin asset. Pure C99 (also
 * compiles as C++), no dependency beyond libm, no malloc, no global state:
 *
 *   romrt_error err;                                          // optional: NULL is fine
 *   size_t bytes, n;
 *   romrt_model *m;
 *   if (romrt_arena_size(asset, asset_bytes, &bytes, &err)) fail(&err);     // ask
 *   if (romrt_open(asset, asset_bytes, arena, bytes, &m, &err)) fail(&err); // open in place
 *   n = romrt_shown_count(m);                                 // size the vertex buffer once
 *   for (;;) {
 *       if (romrt_step(m, &err)) fail(&err);                  // implicit Newton, or Koopman
 *       if (romrt_positions(m, xyz, 3 * n, 3, &err)) fail(&err); // xyz[3 * i + k]
 *   }
 *
 * Conventions, the same for every function:
 * - Every call that can fail returns a romrt_status (ROMRT_OK is 0) and takes a romrt_error * as
 *   its last argument, which may be NULL; on failure it holds the same status, the asset chunk
 *   involved and a message naming what and where (on success it is not written). Calls that
 *   cannot fail on an open model (its sizes, its clock) return their value; given NULL they
 *   return 0.
 * - Counts, capacities and indices are size_t. A buffer's capacity counts its elements: reals
 *   for a romrt_real buffer, int32_t for an index buffer, bytes only for the untyped memory of
 *   the arena and a mesh index. A capacity too small is refused with ROMRT_E_ARGUMENT before
 *   anything is written.
 * - Structs the library writes (romrt_step_info, romrt_limits) begin with `size`, which the
 *   caller sets to sizeof the struct it passes: the library writes only that many bytes, so an
 *   app compiled against an older minor version's shorter struct keeps working; fields the
 *   library does not know (a newer header) are set to 0. A size below the 3.0 struct is refused.
 *   Set it by assignment (romrt_step_info info; info.size = sizeof info;), which stays valid C and
 *   C++ without warnings when a minor version adds a field.
 * - Limits (the largest r, collider slots, ...) are the library's, read with romrt_get_limits:
 *   no macro of this header can disagree with the library an app links.
 *
 * The asset stays the caller's: it must outlive the model, stay unchanged, and start at an
 * address aligned to 8 bytes (16 recommended); it may sit in flash. The arena holds the model's
 * state and fixed-size r x r scratch (the library's largest r), plus a converted copy of the
 * asset's arrays when their precision differs from the runtime's. Everything is checked once, in
 * romrt_open; a bad asset is refused there with a status and a message naming the chunk and index.
 *
 * Precision: float by default; define ROMRT_DOUBLE (the same way for the runtime's sources and
 * for the application) for double. The precision is part of every function's link name (the
 * header maps romrt_step to romrt_f32_step, or with ROMRT_DOUBLE to romrt_f64_step), so an app
 * compiled for one precision and linked against the other library fails to link instead of
 * passing floats where doubles are read.
 *
 * Threads: the runtime has no global or static mutable state. A model belongs to one thread at a
 * time (calls on one model are not synchronized; hand a model to another thread only with the
 * app's own synchronization). Any number of models may step concurrently on different threads,
 * each in its own arena, and they may share one asset: the asset is only ever read. */
#ifndef ROMRT_H
#define ROMRT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The runtime's version (the Makefile's ROMRT_VERSION and the shared library's file name are read
 * from these lines); romrt_version() is the library's ROMRT_VERSION_NUMBER, to check at run time
 * that a shared library is the one the app was compiled against (same major version). */
#define ROMRT_VERSION_MAJOR 3
#define ROMRT_VERSION_MINOR 0
#define ROMRT_VERSION_PATCH 0
#define ROMRT_VERSION_NUMBER (ROMRT_VERSION_MAJOR * 10000 + ROMRT_VERSION_MINOR * 100 + ROMRT_VERSION_PATCH)

#ifdef ROMRT_DOUBLE
typedef double romrt_real;
#else
typedef float romrt_real;
#endif

/* Link names: every function below is romrt_f32_NAME in the float library and romrt_f64_NAME in the
 * double one (the names an app, a binding or a symbol table sees); write romrt_NAME in code. */
#ifdef ROMRT_DOUBLE
#define ROMRT_LINK_NAME(name) romrt_f64_##name
#else
#define ROMRT_LINK_NAME(name) romrt_f32_##name
#endif
#define romrt_add_force             ROMRT_LINK_NAME(add_force)
#define romrt_add_vertex_force      ROMRT_LINK_NAME(add_vertex_force)
#define romrt_arena_size            ROMRT_LINK_NAME(arena_size)
#define romrt_arena_size_kind       ROMRT_LINK_NAME(arena_size_kind)
#define romrt_basis_rows            ROMRT_LINK_NAME(basis_rows)
#define romrt_clear_forces          ROMRT_LINK_NAME(clear_forces)
#define romrt_deformation_gradients ROMRT_LINK_NAME(deformation_gradients)
#define romrt_find_group            ROMRT_LINK_NAME(find_group)
#define romrt_get_limits            ROMRT_LINK_NAME(get_limits)
#define romrt_get_state             ROMRT_LINK_NAME(get_state)
#define romrt_group_count           ROMRT_LINK_NAME(group_count)
#define romrt_group_name            ROMRT_LINK_NAME(group_name)
#define romrt_jump                  ROMRT_LINK_NAME(jump)
#define romrt_last_step             ROMRT_LINK_NAME(last_step)
#define romrt_mesh_index_build      ROMRT_LINK_NAME(mesh_index_build)
#define romrt_mesh_index_size       ROMRT_LINK_NAME(mesh_index_size)
#define romrt_model_kind            ROMRT_LINK_NAME(model_kind)
#define romrt_open                  ROMRT_LINK_NAME(open)
#define romrt_open_kind             ROMRT_LINK_NAME(open_kind)
#define romrt_positions             ROMRT_LINK_NAME(positions)
#define romrt_reduced_coordinates   ROMRT_LINK_NAME(reduced_coordinates)
#define romrt_reduced_size          ROMRT_LINK_NAME(reduced_size)
#define romrt_remove_collider       ROMRT_LINK_NAME(remove_collider)
#define romrt_reset                 ROMRT_LINK_NAME(reset)
#define romrt_rest_positions        ROMRT_LINK_NAME(rest_positions)
#define romrt_set_collider          ROMRT_LINK_NAME(set_collider)
#define romrt_set_damping           ROMRT_LINK_NAME(set_damping)
#define romrt_set_mesh_collider     ROMRT_LINK_NAME(set_mesh_collider)
#define romrt_set_newton_iterations ROMRT_LINK_NAME(set_newton_iterations)
#define romrt_set_hessian_reuse     ROMRT_LINK_NAME(set_hessian_reuse)
#define romrt_set_state             ROMRT_LINK_NAME(set_state)
#define romrt_set_time_step         ROMRT_LINK_NAME(set_time_step)
#define romrt_shown_count           ROMRT_LINK_NAME(shown_count)
#define romrt_state_size            ROMRT_LINK_NAME(state_size)
#define romrt_status_string         ROMRT_LINK_NAME(status_string)
#define romrt_step                  ROMRT_LINK_NAME(step)
#define romrt_takes_colliders       ROMRT_LINK_NAME(takes_colliders)
#define romrt_time                  ROMRT_LINK_NAME(time)
#define romrt_time_step             ROMRT_LINK_NAME(time_step)
#define romrt_triangle_count        ROMRT_LINK_NAME(triangle_count)
#define romrt_triangles             ROMRT_LINK_NAME(triangles)
#define romrt_collision_count       ROMRT_LINK_NAME(collision_count)
#define romrt_collision_positions   ROMRT_LINK_NAME(collision_positions)
#define romrt_version               ROMRT_LINK_NAME(version)

typedef enum {
    ROMRT_OK = 0,
    ROMRT_E_ARGUMENT,     /* a NULL pointer, an index out of range, a non-finite input */
    ROMRT_E_DAMAGED,      /* the container: truncated, bad signature, CRC, layout */
    ROMRT_E_VERSION,      /* a container major version this runtime does not read */
    ROMRT_E_PLATFORM,     /* byte order or float format of this machine */
    ROMRT_E_UNSUPPORTED,  /* an unknown critical chunk, a compressed chunk */
    ROMRT_E_MODEL,        /* chunks that are intact but inconsistent: sizes, indices, NaN */
    ROMRT_E_LIMIT,        /* a count above the library's limits (romrt_get_limits), a pair capacity */
    ROMRT_E_ARENA,        /* the arena is too small or misaligned, or the asset misaligned */
    ROMRT_E_DIVERGED,     /* a step produced a non-finite state or a Newton matrix that is not
                             positive definite; the state is left as it was before the step */
    ROMRT_STATUS_COUNT
} romrt_status;

/* A status's name, e.g. "damaged asset". Compiled to "" with ROMRT_NO_STRINGS. */
const char *romrt_status_string(romrt_status status);

#define ROMRT_MESSAGE_BYTES 160
typedef struct {
    romrt_status status;
    char chunk[5];                      /* the asset chunk involved, or "" */
    char message[ROMRT_MESSAGE_BYTES];  /* what and where; "" with ROMRT_NO_STRINGS */
} romrt_error; /* written on a failure before anything else is checked, so it carries no size: its
                * layout changes only with the major version */

typedef struct romrt_model romrt_model;

/* The library's ROMRT_VERSION_NUMBER: check at run time that a shared library has the major
 * version the app was compiled against. */
int romrt_version(void);

/* The limits of this library (the build's own; the Cortex-M build's are smaller). */
typedef struct {
    size_t size;             /* set by the caller: sizeof(romrt_limits) */
    size_t max_reduced_size; /* r: an asset with a larger one is refused at open (ROMRT_E_LIMIT) */
    size_t collider_slots;   /* slots for the app's colliders, 0 .. collider_slots - 1 */
    size_t mesh_max_count;   /* vertices, or triangles, of an app's collider mesh */
} romrt_limits;
romrt_status romrt_get_limits(romrt_limits *limits, romrt_error *err);

/* What an asset steps: a reduced model (implicit Newton on the cubature), or a Koopman operator
 * learned from trajectories (a linear map in real eigen-coordinates: romrt_jump and the time-step
 * and damping edits apply to it only). A reduced model may be an adaptive linear ROM (formats/
 * ROMBIN.md, ALRH): before each step it rebuilds its basis from a decoder and its last steps over
 * the stored vertices (runtime/alrom.c), which costs O(stored vertices x r^2) a step; its reduced
 * coordinates are then relative to the step's start, and its saved state is large (below). */
typedef enum { ROMRT_KIND_REDUCED = 0, ROMRT_KIND_KOOPMAN = 1 } romrt_kind;

/* Arena bytes romrt_open will need for this asset (validates the asset fully). */
romrt_status romrt_arena_size(const void *asset, size_t asset_bytes, size_t *arena_bytes, romrt_error *err);

/* Opens the asset in the caller's arena (at least romrt_arena_size bytes, 8-byte aligned) at
 * rest, t = 0. *model points into the arena; there is nothing to close. */
romrt_status romrt_open(const void *asset, size_t asset_bytes, void *arena, size_t arena_bytes,
                        romrt_model **model, romrt_error *err);

/* An asset may hold a reduced model and a Koopman operator of the same object (a rom entry with both
 * cubature and koopman); romrt_arena_size / romrt_open take the reduced model when there is one.
 * These take the model of the given kind (ROMRT_E_UNSUPPORTED, naming it, when the asset has none). */
romrt_status romrt_arena_size_kind(const void *asset, size_t asset_bytes, romrt_kind kind, size_t *arena_bytes,
                                   romrt_error *err);
romrt_status romrt_open_kind(const void *asset, size_t asset_bytes, romrt_kind kind, void *arena, size_t arena_bytes,
                             romrt_model **model, romrt_error *err);
romrt_kind romrt_model_kind(const romrt_model *m);

/* Advances one time step. A reduced model: q minimises the reduced incremental potential (the
 * same energy, integrator, pins and contacts as the precompute's reduced simulator), by
 * projected Newton on the r x r system with cubature; several objects (COBJ) and self-contact
 * touch through their collision surfaces as in the reduced simulator (ROMBIN 1.7; 1.5's sphere
 * proxies, CRAD, are refused at open). A Koopman asset: y <- B y + S h_data^2 c,
 * c the forcing of gravity and the applied forces taken as an impulse before each training step
 * (Eq. 19), S its sum over one step of the current size; O(r). On failure the state is unchanged
 * (ROMRT_E_DIVERGED: a non-finite state or a matrix that would not factor; ROMRT_E_LIMIT: more
 * contact pairs than the asset's capacity). */
romrt_status romrt_step(romrt_model *m, romrt_error *err);

/* Reduced models: how a step solves. 0 (the default): Newton with a line search until the step is
 * below the asset's tolerance (or its iteration limit), the same iterates as the precompute's
 * reduced simulator with a fresh Newton matrix (romrt_set_hessian_reuse(m, 1); its default may
 * keep one, to the same tolerance). k >= 1: a fixed cost, exactly k full Newton steps per step with
 * no line search and no convergence test (k = 1 is a linearly implicit step, as Vega's reduced StVK
 * runs by default): faster and predictable, further from the converged answer (docs/results gives
 * both errors); contacts still shorten the steps so nothing is crossed. Kept across romrt_reset.
 * ROMRT_E_ARGUMENT for k above 1000, ROMRT_E_UNSUPPORTED for a Koopman model. */
romrt_status romrt_set_newton_iterations(romrt_model *m, size_t iterations, romrt_error *err);

/* Reduced models: how often Newton's r x r matrix is built and factored. 0 or 1: at every Newton
 * iteration (fresh). k >= 2: a factor is kept for up to k time steps and each iteration
 * solves with it (a modified Newton step: only the potential and its gradient are evaluated, the
 * cubature's r x r Hessian and its Cholesky factorization are not). In the converged mode a fresh
 * matrix replaces it wherever its steps stop halving or its line search has to shorten one, so the
 * answer meets the same tolerance; in the fixed-cost mode it is replaced by age, and where its
 * step would not lower the incremental potential (a stale matrix overshooting; one energy more an
 * iteration), and the error against the converged answer grows with k
 * (docs/results/newton_modes.md). A kept factor is
 * dropped by romrt_reset, romrt_set_state, placing or removing a collider, a collider's move and
 * a change of the integrator's inertia weight (BDF2's first step), so a restored state's steps may
 * differ from the uninterrupted run's by up to the solve's tolerance. Kept across romrt_reset.
 * The default, until this is called, is the fastest mode that meets the asset's tolerance, chosen
 * per asset at open (docs/results/newton_modes.md): in the converged mode the matrix kept for up
 * to 10 steps (on bunny_19k at r = 20, a third of the fresh mode's time a step, every step to the
 * same tolerance); on an asset with a collision surface (obstacles other than planes, several
 * objects, self-contact) kept only while no contact term acts (objects apart), fresh at every
 * iteration where a barrier or friction term does, where a kept matrix took more iterations and
 * was no faster (docs/runtime.md); and fresh in the fixed-cost mode. romrt_step_info's hessian_reuse reads the mode in force. k = 1
 * gives the reduced simulator's own iterates everywhere. An adaptive model with the quadratic
 * decoder keeps its matrix too, with the same default: its basis moves every step, and the kept
 * matrix is carried into each new basis (the stiffness projected onto it, the inertia exact;
 * runtime/alrom_keep.c) while the gradient is the new basis' own. ROMRT_E_ARGUMENT for k above 1000,
 * ROMRT_E_UNSUPPORTED for a Koopman model or an adaptive one with a CROM decoder. */
romrt_status romrt_set_hessian_reuse(romrt_model *m, size_t steps, romrt_error *err);

/* Back to the start at t = 0: the rest shape, moving with the asset's initial velocity (VEL0: an
 * object the scene throws; else at rest), forces cleared, the app's colliders removed (a Koopman
 * asset keeps its time step and damping). romrt_open starts there too. */
romrt_status romrt_reset(romrt_model *m, romrt_error *err);

/* Koopman assets only (ROMRT_E_UNSUPPORTED otherwise): advances `steps` steps at once, the
 * applied forces held, at a cost independent of `steps` (about one romrt_step plus up to three
 * libm calls per eigen-block: each block's power in polar form, |lambda|^N and N arg lambda, and
 * the held forces' sum (lambda^N - 1) / (lambda - 1) in closed form, computed in double); equal
 * to that many romrt_step calls up to rounding (an error that may grow like steps x the double
 * epsilon, as the phase N arg lambda inherits arg lambda's rounding). */
romrt_status romrt_jump(romrt_model *m, unsigned long steps, romrt_error *err);
/* Koopman assets only: a new time step h (s) by the eigenvalue rescaling lambda^(h / h_data)
 * (Eq. 21 of the Koopman paper), which keeps each mode's frequency and decay per second; a force
 * held over the step acts as over h / h_data training steps (sum of lambda^t), so a step of
 * k h_data equals k steps of h_data under constant forces too. */
romrt_status romrt_set_time_step(romrt_model *m, romrt_real h, romrt_error *err);
/* Koopman assets only: every trained eigenvalue scaled by (1 - mu), 0 <= mu < 1 (Sec. 7.2): per
 * training step, so (1 - mu)^(h / h_data) per step of h, the same damping per second whatever h. */
romrt_status romrt_set_damping(romrt_model *m, romrt_real mu, romrt_error *err);

/* Sizes. */
size_t romrt_reduced_size(const romrt_model *m);   /* r */
size_t romrt_shown_count(const romrt_model *m);    /* vertices an app draws */
size_t romrt_triangle_count(const romrt_model *m); /* surface triangles over them (0 if none stored) */
size_t romrt_group_count(const romrt_model *m);    /* named vertex groups an app may push */
/* The model's clock (s), in double whatever the precision: the runtime counts steps and returns
 * t = t_start + steps h, so it does not drift (a float running sum of 1/60 s reads 7183.14 s
 * after two hours, and a float near 7200 s is only good to 0.5 ms, 3% of a step) and time-driven
 * pins (a scene's twist or translate) follow it. */
double romrt_time(const romrt_model *m);
romrt_real romrt_time_step(const romrt_model *m); /* s */

/* Positions (m) of all shown vertices, vertex i at xyz[stride * i + k], k = 0, 1, 2: stride 3 for a
 * packed array, more for an interleaved vertex buffer (the reals between are left alone). xyz holds
 * `capacity` reals: at least stride (shown - 1) + 3, and the stride at least 3. */
romrt_status romrt_positions(const romrt_model *m, romrt_real *xyz, size_t capacity, size_t stride, romrt_error *err);
/* Deforming on the GPU (x = X + U q in a vertex shader): the shown vertices' rest positions X (as
 * romrt_positions lays them out), and their basis rows U, 3 r reals a vertex: rows[(3 i + k) r + j]
 * is dx_ik/dq_j, so x_ik = X_ik + sum_j rows[(3 i + k) r + j] q_j with q from
 * romrt_reduced_coordinates, the same sum romrt_positions takes. A skinning basis stored as its
 * weights gives its rows formed from them (dense, as ROWS would hold them); a Koopman asset its
 * output rows (KOUT), q then being its eigen-coordinates y. rows holds at least 3 shown r reals.
 * The rows and X do not change while the model runs: upload them once, then q (r reals) per frame. */
romrt_status romrt_rest_positions(const romrt_model *m, romrt_real *xyz, size_t capacity, size_t stride,
                                  romrt_error *err);
romrt_status romrt_basis_rows(const romrt_model *m, romrt_real *rows, size_t capacity, romrt_error *err);
/* The deformation gradient F (row-major 3 x 3, F[9 i + 3 a + b] = dx_a/dX_b) at each shown vertex
 * (F holds at least 9 shown reals), for an asset that stores its skinning weights' gradients there
 * (GRAD: a point cloud's, so that a Gaussian splat's covariance Sigma becomes F Sigma F^T).
 * F = I + sum_j A_j (X grad w_j^T + w_j [I; 0]) with A_j the handles' affine maps (freeform paper
 * Eq. 21). ROMRT_E_UNSUPPORTED without GRAD. */
romrt_status romrt_deformation_gradients(const romrt_model *m, romrt_real *F, size_t capacity, romrt_error *err);
/* Surface triangles (indices into the shown vertices, outward): tri holds at least 3 triangle_count. */
romrt_status romrt_triangles(const romrt_model *m, int32_t *tri, size_t capacity, romrt_error *err);
/* The collision vertices (CVTX: what contact and colliders act on; 0 without), and their positions
 * (m) in CVTX's order, 3 reals each (xyz holds at least 3 collision_count): for a tool measuring
 * contact on the collision surface, which may hold vertices no app draws (a point cloud's contact
 * surface, whose stored vertices follow the shown ones). */
size_t romrt_collision_count(const romrt_model *m);
romrt_status romrt_collision_positions(const romrt_model *m, romrt_real *xyz, size_t capacity, romrt_error *err);
/* The reduced coordinates q (r of them; a Koopman model's eigen-coordinates y). */
romrt_status romrt_reduced_coordinates(const romrt_model *m, romrt_real *q, size_t capacity, romrt_error *err);

/* Pushing. A group is found by name (ROMRT_E_ARGUMENT naming it when the asset has none);
 * romrt_add_force spreads the total force f (N) evenly over the group's vertices,
 * romrt_add_vertex_force puts f on one shown vertex. Forces add up and act on every following step
 * until romrt_clear_forces. A force whose sum would overflow is refused (ROMRT_E_ARGUMENT) and
 * changes nothing. */
romrt_status romrt_find_group(const romrt_model *m, const char *name, size_t *group, romrt_error *err);
romrt_status romrt_group_name(const romrt_model *m, size_t group, const char **name, romrt_error *err);
romrt_status romrt_add_force(romrt_model *m, size_t group, const romrt_real f[3], romrt_error *err);
romrt_status romrt_add_vertex_force(romrt_model *m, size_t shown_vertex, const romrt_real f[3], romrt_error *err);
romrt_status romrt_clear_forces(romrt_model *m, romrt_error *err);

/* The whole dynamic state (time, reduced positions, velocities, integrator history, applied
 * forces) as romrt_state_size reals, to save and restore (undo, networking, replays). The time
 * takes two reals (a float pair holds the double clock to about 48 bits). A state with a
 * non-finite value, or of another count than this model's, is refused. An adaptive linear ROM's
 * state is its stored vertices' displacements, velocities and the last m steps' history (each
 * double as a pair of reals, so a float state reads back to about 48 bits): O(stored vertices x m)
 * reals. Restoring drops a kept Newton matrix (romrt_set_hessian_reuse), so where the default keeps
 * one a replay matches the uninterrupted run to the solve's tolerance; bit for bit needs k = 1. */
size_t romrt_state_size(const romrt_model *m);
romrt_status romrt_get_state(const romrt_model *m, romrt_real *state, size_t capacity, romrt_error *err);
romrt_status romrt_set_state(romrt_model *m, const romrt_real *state, size_t count, romrt_error *err);

/* Colliders the application owns: planes, spheres, capsules and boxes. On an asset with a
 * collision surface (OBHD: baked with a mesh obstacle, several objects or contact.self) spheres,
 * capsules and boxes collide as the scene's obstacles of those kinds and the app's meshes do:
 * a sphere is its centre and a capsule its segment, each with thickness r, a box its 12
 * triangles, against the surface's triangles and edges (the obstacles' barrier, CCD and lagged
 * friction; their pairs count against the asset's pair capacity, ROMRT_E_LIMIT past it), moved
 * as a mesh is (each vertex on a straight line to the new pose), so a shape thinner than the
 * surface's edges cannot pass between its vertices. Planes, and every kind on an asset without
 * a collision surface (CVTX only, as the Cortex-M build's), act on the collision vertices (its
 * boundary, CVTX) with the barrier of the scene's planes, the same step filter and, when the
 * asset has friction (FRIC), the same friction: exact for a plane, while a sphere, capsule or box
 * thinner than the surface's edges can pass between its vertices there. A collider has a pose,
 * position and rotation (row-major, local to world, orthonormal), and a size: a sphere's radius;
 * a capsule's radius and half length along its local x; a box's half extents. A plane passes
 * through the position with its normal along the local z (rotation's third column).
 *
 * romrt_set_collider on a free slot, or with another kind or size, places the collider there at
 * once: it must be clear of the body (ROMRT_E_ARGUMENT otherwise). On a slot holding one of the
 * same kind and size it is a move: the next step takes the collider there along the shortest
 * path, solving for the body and the collider together (the body is pushed ahead of it, never
 * crossed); where the body cannot give way the collider stops short (romrt_step_info's
 * colliders_behind) and goes on at the next step. A NaN, a non-positive size, a rotation that is
 * not orthonormal or a slot out of range (romrt_limits' collider_slots) is refused with
 * ROMRT_E_ARGUMENT and changes nothing; an asset without CVTX (baked with "colliders": false, or by
 * a romkit before 1.1) refuses every collider with ROMRT_E_UNSUPPORTED. romrt_reset removes them
 * all. The struct is read, never written; its layout changes only with the major version. */
typedef enum {
    ROMRT_COLLIDER_PLANE = 0,
    ROMRT_COLLIDER_SPHERE = 1,
    ROMRT_COLLIDER_CAPSULE = 2,
    ROMRT_COLLIDER_BOX = 3,
    ROMRT_COLLIDER_MESH = 4     /* placed by romrt_set_mesh_collider only */
} romrt_collider_kind;
typedef struct {
    romrt_collider_kind kind;
    romrt_real position[3];
    romrt_real rotation[9];
    romrt_real radius;          /* sphere, capsule */
    romrt_real half_length;     /* capsule */
    romrt_real half_extents[3]; /* box */
} romrt_collider;
romrt_status romrt_set_collider(romrt_model *m, size_t slot, const romrt_collider *c, romrt_error *err);
romrt_status romrt_remove_collider(romrt_model *m, size_t slot, romrt_error *err);
/* Whether the asset takes colliders (it holds CVTX, and no lifted group: LIFT). */
int romrt_takes_colliders(const romrt_model *m);

/* Triangle meshes the application owns (level geometry, a paddle) as colliders, in a slot of the
 * same collider_slots. The runtime copies nothing and allocates nothing: positions (m, in the
 * mesh's own frame, xyz per vertex), triangles (3 vertex indices each, any orientation, open or
 * closed) and the index are the app's, and must stay alive and unchanged while the mesh is placed
 * (until romrt_remove_collider, romrt_reset or another collider in its slot). The index is app
 * memory of romrt_mesh_index_size bytes (8-byte aligned) that romrt_mesh_index_build fills with
 * the mesh's edges and a BVH over its vertices, edges and triangles (built once, O(n log n); the
 * mesh moves rigidly, so only the BVH's boxes are refitted when it moves, O(n)), and in which the
 * runtime keeps the mesh's world positions while it is placed: one index per placed mesh, not
 * shared between slots or models, not moved in memory (it points into itself).
 *
 * Contact with it is the contact of the scene's baked mesh obstacles (the IPC barrier, friction
 * and CCD of the asset's collision surface: point-triangle and edge-edge stencils, thickness 0),
 * so the asset must hold its collision surface (OBHD: baked with mesh obstacles, several objects,
 * or contact.self; ROMRT_E_UNSUPPORTED otherwise) and the pairs count against its pair capacity.
 *
 * romrt_set_mesh_collider on a slot holding another collider (or none) places the mesh at the
 * pose (rotation row-major, local to world, orthonormal; position) at once: it must not touch
 * the body's collision surface nor cross it (an edge of either through a triangle of the other,
 * tested in this precision), ROMRT_E_ARGUMENT otherwise; a body wholly inside a closed mesh, or a
 * mesh wholly inside the body, is not detected: place it clear, then move it. On a slot holding
 * the same mesh it is a move: the next step takes the mesh's vertices on straight lines to the new
 * pose, solving for the body and the mesh's progress together so the body is pushed ahead (as the
 * scene's scripted obstacles move); where the body cannot give way the mesh stops short
 * (colliders_behind) and goes on at the next step. A bad pose, a NULL, a count of 0 or
 * above romrt_limits' mesh_max_count, a triangle index out of range or repeated within a triangle,
 * a non-finite position, an index too small, misaligned or not built for this mesh is refused with
 * ROMRT_E_ARGUMENT naming what and where, and nothing is placed. */
typedef struct {
    const romrt_real *positions; /* vertex_count x 3 */
    const int32_t *triangles;    /* triangle_count x 3 */
    size_t vertex_count, triangle_count;
    void *index;                 /* index_bytes bytes, filled by romrt_mesh_index_build */
    size_t index_bytes;
} romrt_mesh;
/* The bytes of a mesh's index: for a heightfield (half as many vertices as triangles) about 230
 * bytes a triangle in float and 365 in double. ROMRT_E_ARGUMENT for counts out of range. */
romrt_status romrt_mesh_index_size(size_t vertex_count, size_t triangle_count, size_t *index_bytes, romrt_error *err);
/* Validates the mesh and builds its index (mesh->index, mesh->index_bytes). */
romrt_status romrt_mesh_index_build(const romrt_mesh *mesh, romrt_error *err);
romrt_status romrt_set_mesh_collider(romrt_model *m, size_t slot, const romrt_mesh *mesh, const romrt_real position[3],
                                     const romrt_real rotation[9], romrt_error *err);

/* The work of the last step, for profiling and for an app's own checks. */
typedef struct {
    size_t size;                  /* set by the caller: sizeof(romrt_step_info) */
    size_t newton_iterations;
    size_t line_search_halvings;
    size_t factorizations;        /* Newton matrices built and factored (fewer than the iterations
                                   * where a kept one served: romrt_set_hessian_reuse) */
    size_t projected_hessians;    /* Newton iterations whose exact Hessian was not positive definite, so
                                   * the elements' dP/dF was projected to PSD (and every iteration of a
                                   * solve that moves colliders, which always projects) */
    size_t hessian_reuse;         /* the steps a Newton matrix may be kept in the mode in force (0: fresh) */
    size_t contact_pairs;         /* candidate contact pairs of the collision surface at the step's end */
    size_t friction_pairs;        /* of them, the lagged friction pairs */
    size_t pair_capacity;         /* the asset's capacity for them (a step above it fails, ROMRT_E_LIMIT) */
    int converged;                /* the converged mode met the tolerance (1 for a Koopman step) */
    int colliders_behind;         /* a moved collider, or the scene's moving obstacles, stopped short of
                                   * where they go (the body was in the way) */
} romrt_step_info;
romrt_status romrt_last_step(const romrt_model *m, romrt_step_info *info, romrt_error *err);

#ifdef __cplusplus
}
#endif

#endif
