/* romrt.h's conventions (its header comment), checked on an app compiled against the installed
 * header and library (tests/integration/install.sh): the signatures (size_t capacities and
 * indices, a romrt_error * last), one error channel (every fallible call, given bad arguments,
 * returns a status and fills the optional romrt_error with the same status and a message; NULL
 * for it is accepted), out-structs that carry their size (the library writes no byte past the
 * caller's size, zeroes fields it does not know, refuses a size below the 3.0 struct), and
 * limits read from the library with no macro in the header to disagree with it.
 * Usage: api_contract ASSET.rombin (an asset of a reduced model with a "tip" group). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "romrt.h"

#if defined(ROMRT_MAX_R) || defined(ROMRT_MAX_COLLIDERS) || defined(ROMRT_MESH_MAX_COUNT)
#error "romrt.h defines a limit as a macro: limits are the library's (romrt_get_limits)"
#endif

/* The signatures: a function whose parameters changed fails to compile here (-Werror). */
static romrt_status (*const positions)(const romrt_model *, romrt_real *, size_t, size_t, romrt_error *) = romrt_positions;
static romrt_status (*const rest)(const romrt_model *, romrt_real *, size_t, size_t, romrt_error *) = romrt_rest_positions;
static romrt_status (*const rows)(const romrt_model *, romrt_real *, size_t, romrt_error *) = romrt_basis_rows;
static romrt_status (*const grads)(const romrt_model *, romrt_real *, size_t, romrt_error *) = romrt_deformation_gradients;
static romrt_status (*const tris)(const romrt_model *, int32_t *, size_t, romrt_error *) = romrt_triangles;
static romrt_status (*const collision)(const romrt_model *, romrt_real *, size_t, romrt_error *) = romrt_collision_positions;
static romrt_status (*const coords)(const romrt_model *, romrt_real *, size_t, romrt_error *) = romrt_reduced_coordinates;
static romrt_status (*const get_state)(const romrt_model *, romrt_real *, size_t, romrt_error *) = romrt_get_state;
static romrt_status (*const set_state)(romrt_model *, const romrt_real *, size_t, romrt_error *) = romrt_set_state;
static romrt_status (*const find)(const romrt_model *, const char *, size_t *, romrt_error *) = romrt_find_group;
static romrt_status (*const name)(const romrt_model *, size_t, const char **, romrt_error *) = romrt_group_name;
static romrt_status (*const force)(romrt_model *, size_t, const romrt_real *, romrt_error *) = romrt_add_force;
static romrt_status (*const vforce)(romrt_model *, size_t, const romrt_real *, romrt_error *) = romrt_add_vertex_force;
static romrt_status (*const clear)(romrt_model *, romrt_error *) = romrt_clear_forces;
static romrt_status (*const reset)(romrt_model *, romrt_error *) = romrt_reset;
static romrt_status (*const newton)(romrt_model *, size_t, romrt_error *) = romrt_set_newton_iterations;
static romrt_status (*const reuse)(romrt_model *, size_t, romrt_error *) = romrt_set_hessian_reuse;
static romrt_status (*const collider)(romrt_model *, size_t, const romrt_collider *, romrt_error *) = romrt_set_collider;
static romrt_status (*const remove_collider)(romrt_model *, size_t, romrt_error *) = romrt_remove_collider;
static romrt_status (*const last)(const romrt_model *, romrt_step_info *, romrt_error *) = romrt_last_step;
static romrt_status (*const index_size)(size_t, size_t, size_t *, romrt_error *) = romrt_mesh_index_size;
static size_t (*const shown)(const romrt_model *) = romrt_shown_count;

static int failures;
static void check(int ok, const char *what)
{
    printf("%s %s\n", ok ? "ok" : "FAIL", what);
    failures += !ok;
}

/* A refused call: the status, err's status the same, and a message. */
static void refused(romrt_status st, const romrt_error *err, romrt_status want, const char *what)
{
    char line[400];
    snprintf(line, sizeof line, "%s: status %d, err %d \"%s\"", what, (int)st, (int)err->status, err->message);
    check(st == want && err->status == want && err->message[0] != 0, line);
}

#define NULL_MODEL(call, what)                                                                                         \
    do {                                                                                                               \
        memset(&err, 0, sizeof err);                                                                                   \
        refused((call), &err, ROMRT_E_ARGUMENT, what);                                                                 \
    } while (0)

int main(int argc, char **argv)
{
    romrt_error err;
    romrt_real buf[64] = {0}, f[3] = {0, 0, 1};
    int32_t ibuf[16];
    const char *nm = NULL;
    size_t g = 0, bytes = 0, n;
    romrt_collider c;
    memset(&c, 0, sizeof c);
    c.kind = ROMRT_COLLIDER_SPHERE;

    /* every fallible call on a NULL model */
    NULL_MODEL(positions(NULL, buf, 64, 3, &err), "positions");
    NULL_MODEL(rest(NULL, buf, 64, 3, &err), "rest_positions");
    NULL_MODEL(rows(NULL, buf, 64, &err), "basis_rows");
    NULL_MODEL(grads(NULL, buf, 64, &err), "deformation_gradients");
    NULL_MODEL(tris(NULL, ibuf, 16, &err), "triangles");
    NULL_MODEL(collision(NULL, buf, 64, &err), "collision_positions");
    NULL_MODEL(coords(NULL, buf, 64, &err), "reduced_coordinates");
    NULL_MODEL(get_state(NULL, buf, 64, &err), "get_state");
    NULL_MODEL(set_state(NULL, buf, 64, &err), "set_state");
    NULL_MODEL(find(NULL, "tip", &g, &err), "find_group");
    NULL_MODEL(name(NULL, 0, &nm, &err), "group_name");
    NULL_MODEL(force(NULL, 0, f, &err), "add_force");
    NULL_MODEL(vforce(NULL, 0, f, &err), "add_vertex_force");
    NULL_MODEL(clear(NULL, &err), "clear_forces");
    NULL_MODEL(reset(NULL, &err), "reset");
    NULL_MODEL(newton(NULL, 1, &err), "set_newton_iterations");
    NULL_MODEL(reuse(NULL, 1, &err), "set_hessian_reuse");
    NULL_MODEL(collider(NULL, 0, &c, &err), "set_collider");
    NULL_MODEL(remove_collider(NULL, 0, &err), "remove_collider");
    NULL_MODEL(romrt_step(NULL, &err), "step");
    NULL_MODEL(romrt_jump(NULL, 1, &err), "jump");
    NULL_MODEL(index_size(0, 0, &bytes, &err), "mesh_index_size of nothing");
    /* the error is optional: NULL is accepted and the status still says it */
    check(positions(NULL, buf, 64, 3, NULL) == ROMRT_E_ARGUMENT && romrt_reset(NULL, NULL) == ROMRT_E_ARGUMENT,
          "a NULL romrt_error is accepted");
    check(shown(NULL) == 0, "a size of no model is 0");

    /* limits from the library, with the size rule */
    {
        romrt_limits lim;
        memset(&lim, 0, sizeof lim);
        lim.size = sizeof lim - 1;
        refused(romrt_get_limits(&lim, &err), &err, ROMRT_E_ARGUMENT, "limits with a size below the 3.0 struct");
        lim.size = sizeof lim;
        check(romrt_get_limits(&lim, &err) == ROMRT_OK && lim.max_reduced_size >= 8 && lim.collider_slots >= 1 &&
                  lim.mesh_max_count > 0 && lim.size == sizeof lim,
              "limits read from the library");
        printf("# limits: r up to %lu, %lu collider slots, meshes of %lu; version %d\n",
               (unsigned long)lim.max_reduced_size, (unsigned long)lim.collider_slots,
               (unsigned long)lim.mesh_max_count, romrt_version());
        check(romrt_version() == ROMRT_VERSION_NUMBER, "the library's version is the header's");
    }

    if (argc != 2) return printf("usage: api_contract ASSET.rombin\n"), 2;
    {
        FILE *fp = fopen(argv[1], "rb");
        static double asset[1 << 20];
        size_t asset_bytes = fp ? fread(asset, 1, sizeof asset, fp) : 0, need = 0;
        void *arena;
        romrt_model *m = NULL;
        struct { /* an app built against a newer header: two more fields the library does not know */
            romrt_step_info info;
            size_t future[2];
        } newer;
        unsigned char older[sizeof(romrt_step_info) + 16];
        romrt_step_info *info = (romrt_step_info *)(void *)older;
        size_t k;
        int past = 0;
        if (fp) fclose(fp);
        if (romrt_arena_size(asset, asset_bytes, &need, &err) || !(arena = malloc(need)) ||
            romrt_open(asset, asset_bytes, arena, need, &m, &err))
            return printf("FAIL open %s: %s\n", argv[1], err.message), 1;
        n = romrt_shown_count(m);
        check(romrt_find_group(m, "tip", &g, &err) == ROMRT_OK && romrt_add_force(m, g, f, &err) == ROMRT_OK,
              "find_group and add_force on \"tip\"");
        refused(romrt_find_group(m, "no such group", &g, &err), &err, ROMRT_E_ARGUMENT, "an unknown group");
        refused(romrt_add_force(m, romrt_group_count(m), f, &err), &err, ROMRT_E_ARGUMENT, "a group past the end");
        check(romrt_step(m, &err) == ROMRT_OK, "a step");
        /* the size rule on romrt_step_info: nothing written past the caller's size ... */
        memset(older, 0xA5, sizeof older);
        info->size = sizeof(romrt_step_info);
        check(last(m, info, &err) == ROMRT_OK && info->newton_iterations > 0 && info->factorizations > 0,
              "last_step: iterations and factorizations counted");
        for (k = sizeof(romrt_step_info); k < sizeof older; k++) past |= older[k] != 0xA5;
        check(!past, "last_step writes nothing past the caller's size");
        /* ... fields the library does not know set to 0 ... */
        memset(&newer, 0xA5, sizeof newer);
        newer.info.size = sizeof newer;
        check(last(m, &newer.info, &err) == ROMRT_OK && newer.future[0] == 0 && newer.future[1] == 0 &&
                  newer.info.newton_iterations == info->newton_iterations,
              "a newer header's longer struct: the unknown fields read 0");
        /* ... and a size below the 3.0 struct refused */
        info->size = sizeof(romrt_step_info) - 1;
        refused(last(m, info, &err), &err, ROMRT_E_ARGUMENT, "last_step with a size below the 3.0 struct");
        info->size = 0;
        refused(last(m, info, &err), &err, ROMRT_E_ARGUMENT, "last_step with size 0 (unset)");
        /* capacities in reals: 3 n - 1 refused, nothing written; 3 n taken */
        {
            romrt_real *xyz = (romrt_real *)malloc(sizeof(romrt_real) * (3 * n + 1));
            xyz[3 * n - 1] = -1;
            refused(positions(m, xyz, 3 * n - 1, 3, &err), &err, ROMRT_E_ARGUMENT, "positions one real short");
            check(xyz[3 * n - 1] == -1, "a refused call wrote nothing");
            check(positions(m, xyz, 3 * n, 3, &err) == ROMRT_OK, "positions with 3 n reals");
            free(xyz);
        }
        free(arena);
    }
    printf("# api_contract: %d failed\n", failures);
    return failures != 0;
}
