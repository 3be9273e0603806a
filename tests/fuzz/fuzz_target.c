/* libFuzzer entry point for the runtime: arena size, open, a few steps and every call an
 * application makes on an opened model, on arbitrary bytes. Besides what the sanitizers catch,
 * it traps (so the fuzzer reports the input) when the API's own contract breaks:
 *   - a non-OK status without a message (unless ROMRT_NO_STRINGS), or err.status disagreeing
 *     (arena size, open, step: the calls that take a romrt_error);
 *   - an out-of-range vertex or group, or a wrong-sized state, accepted; a valid one refused;
 *   - a non-finite position after the steps (a failed step must leave the state as it was);
 *   - a state read back from the model refused by romrt_set_state, or not read back the same;
 *   - a byte of the asset changed.
 * Each input runs twice: as given, and with its CRCs recomputed, which lets mutations past the
 * CRC checks into the model's validation and the step. C99; replay.c runs the same function
 * without libFuzzer. */
#define _POSIX_C_SOURCE 200112L /* posix_memalign: exact sizes, so ASan sees an overrun by one byte */

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "formats/rombin_read.h"
#include "runtime/romrt.h"

/* Larger arenas are skipped: the fuzzer's inputs are small, and an asset that asks for more is
 * either legitimately big or a size computation worth a look on its own. */
#define FUZZ_ARENA_CAP ((size_t)64 << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A broken contract: say which (replay shows it; libFuzzer shows the stack) and trap. */
#define BROKEN(why) broken(why, __LINE__)
static void broken(const char *why, int line)
{
    fprintf(stderr, "fuzz_target.c:%d: API contract broken: %s\n", line, why);
    __builtin_trap();
}

/* Traps on a broken error contract; returns st. */
static romrt_status check(romrt_status st, const romrt_error *err)
{
    if (st != ROMRT_OK) {
        if (err->status != st) BROKEN("err.status differs from the returned status");
#ifndef ROMRT_NO_STRINGS
        if (err->message[0] == 0) BROKEN("a non-OK status with an empty message");
#endif
    }
    return st;
}

/* Exactly `bytes` (at least 1), aligned to 16; NULL on failure. */
static void *alloc16(size_t bytes)
{
    void *p = NULL;
    if (posix_memalign(&p, 16, bytes ? bytes : 1) != 0) return NULL;
    return p;
}

static void exercise(romrt_model *m)
{
    romrt_error err;
    /* small pushes: an asset may hold rows up to float's overflow, and a push whose sum overflows
     * is refused by contract (romrt.h); these must be taken by any asset that opens */
    romrt_real f[3] = {1e-20f, -2e-20f, 0.5e-20f};
    int shown = romrt_shown_count(m), tris = romrt_triangle_count(m), groups = romrt_group_count(m);
    int n = romrt_state_size(m), i;
    romrt_real *xyz, *state, *again;
    int *tri;

    memset(&err, 0, sizeof err);
    if (shown < 0 || tris < 0 || groups < 0 || n <= 0 || romrt_reduced_size(m) <= 0) BROKEN("a negative or zero size");
    if (shown > 0 && romrt_add_vertex_force(m, 0, f, NULL) != ROMRT_OK) BROKEN("force on vertex 0 refused");
    if (romrt_add_vertex_force(m, shown, f, NULL) == ROMRT_OK) BROKEN("force on vertex `shown` accepted");
    if (romrt_add_vertex_force(m, (size_t)-1, f, NULL) == ROMRT_OK) BROKEN("force on vertex -1 accepted");
    if (groups > 0) {
        const char *name = NULL;
        size_t g = 1;
        if (romrt_group_name(m, 0, &name, NULL) || romrt_find_group(m, name, &g, NULL) || g != 0)
            BROKEN("group 0 not found by its name");
        if (romrt_add_force(m, 0, f, NULL) != ROMRT_OK) BROKEN("force on group 0 refused");
    }
    if (romrt_add_force(m, groups, f, NULL) == ROMRT_OK) BROKEN("force on group `groups` accepted");

    {   /* colliders: bad ones refused whatever the asset; a sphere far off taken by one that takes
         * colliders (or refused as overlapping, if its rows are wild), moved toward the body */
        romrt_collider c;
        memset(&c, 0, sizeof c);
        c.kind = ROMRT_COLLIDER_SPHERE;
        c.rotation[0] = c.rotation[4] = c.rotation[8] = 1;
        c.position[1] = -100;
        c.radius = -1;
        if (romrt_set_collider(m, 0, &c, &err) == ROMRT_OK) BROKEN("a negative radius accepted");
        c.radius = 1;
        c.position[0] = (romrt_real)NAN;
        if (romrt_set_collider(m, 0, &c, &err) == ROMRT_OK) BROKEN("a NaN collider accepted");
        c.position[0] = 0;
        {
            romrt_limits lim;
            lim.size = sizeof lim;
            if (romrt_get_limits(&lim, NULL) || romrt_set_collider(m, lim.collider_slots, &c, &err) == ROMRT_OK)
                BROKEN("a slot past the end accepted");
        }
        if (romrt_takes_colliders(m) && check(romrt_set_collider(m, 1, &c, &err), &err) == ROMRT_OK) {
            c.position[1] = -50;
            if (check(romrt_set_collider(m, 1, &c, &err), &err) != ROMRT_OK) BROKEN("a collider's move refused");
        } else if (!romrt_takes_colliders(m) && romrt_set_collider(m, 1, &c, &err) != ROMRT_E_UNSUPPORTED) {
            BROKEN("a model without collision vertices did not refuse a collider as unsupported");
        }
    }
    for (i = 0; i < 3; i++)
        if (check(romrt_step(m, &err), &err) != ROMRT_OK) break;
    if (romrt_remove_collider(m, 1, &err) != ROMRT_OK) BROKEN("removing a collider refused");
    if (romrt_model_kind(m) == ROMRT_KIND_KOOPMAN) {
        /* a jump, the edits; each either works or leaves a finite state and says why */
        check(romrt_jump(m, 1000, &err), &err);
        if (check(romrt_set_time_step(m, romrt_time_step(m) * 3, &err), &err) != ROMRT_OK) BROKEN("a larger step refused");
        if (check(romrt_set_damping(m, (romrt_real)0.01, &err), &err) != ROMRT_OK) BROKEN("1% damping refused");
        if (romrt_set_damping(m, 1, &err) == ROMRT_OK) BROKEN("damping 1 accepted");
        check(romrt_step(m, &err), &err);
    } else if (romrt_jump(m, 10, &err) != ROMRT_E_UNSUPPORTED || romrt_set_time_step(m, 1, &err) != ROMRT_E_UNSUPPORTED) {
        BROKEN("a reduced model jumped or rescaled its step");
    }

    xyz = alloc16(sizeof(romrt_real) * 3 * (size_t)shown);
    if (xyz && shown > 0) {
        if (romrt_positions(m, xyz, 3 * (size_t)shown, 3, NULL) != ROMRT_OK) BROKEN("positions refused");
        /* A step either succeeds with a finite state or leaves the state as it was. */
        for (i = 0; i < 3 * shown; i++)
            if (xyz[i] - xyz[i] != 0) BROKEN("a non-finite position");
    }
    tri = alloc16(sizeof(int) * 3 * (size_t)tris);
    if (tri && tris > 0) {
        if (romrt_triangles(m, tri, 3 * (size_t)tris, NULL) != ROMRT_OK) BROKEN("triangles refused");
        for (i = 0; i < 3 * tris; i++)
            if (tri[i] < 0 || tri[i] >= shown) BROKEN("a triangle index out of range");
    }

    state = alloc16(2 * sizeof(romrt_real) * (size_t)n);
    if (state) {
        again = state + n;
        if (romrt_get_state(m, state, n, NULL) != ROMRT_OK) BROKEN("get_state refused");
        if (romrt_set_state(m, state, n, NULL) != ROMRT_OK) BROKEN("set_state refused the model's own state");
        if (romrt_get_state(m, again, n, NULL) != ROMRT_OK) BROKEN("get_state refused");
        if (memcmp(state, again, sizeof(romrt_real) * (size_t)n) != 0) BROKEN("state changed by a set/get round trip");
        if (romrt_set_state(m, state, n - 1, NULL) == ROMRT_OK) BROKEN("a state one short accepted");
    }
    romrt_clear_forces(m, NULL);
    romrt_reset(m, NULL);
    if (romrt_time(m) != 0) BROKEN("time not 0 after reset");
    free(xyz);
    free(tri);
    free(state);
}

/* Recomputes every CRC the table lets us find (payloads, then the table's own), so that mutated
 * inputs reach the model's validation and the step instead of dying at a CRC check. Returns
 * whether any byte changed. */
static int fix_crcs(unsigned char *p, size_t size)
{
    unsigned count, i, k;
    int changed = 0;
    uint32_t crc;
    if (size < ROMBIN_HEADER_BYTES) return 0;
    count = rombin_get_u32(p + ROMBIN_H_CHUNKS);
    if (count > ROMBIN_MAX_CHUNKS || ROMBIN_HEADER_BYTES + (size_t)count * ROMBIN_ENTRY_BYTES > size) return 0;
    for (i = 0; i <= count; i++) {
        unsigned char *at;
        if (i < count) {
            unsigned char *e = p + ROMBIN_HEADER_BYTES + (size_t)i * ROMBIN_ENTRY_BYTES;
            uint64_t off = rombin_get_u64(e + ROMBIN_E_OFFSET), stored = rombin_get_u64(e + ROMBIN_E_STORED);
            if (off > size || stored > size - off) continue;
            crc = rombin_crc32(0, p + off, (size_t)stored);
            at = e + ROMBIN_E_CRC;
        } else {
            crc = rombin_crc32(0, p, ROMBIN_H_TABLE_CRC);
            crc = rombin_crc32(crc, p + ROMBIN_HEADER_BYTES, (size_t)count * ROMBIN_ENTRY_BYTES);
            at = p + ROMBIN_H_TABLE_CRC;
        }
        if (rombin_get_u32(at) == crc) continue;
        for (k = 0; k < 4; k++) at[k] = (unsigned char)(crc >> (8 * k));
        changed = 1;
    }
    return changed;
}

/* Arena size, open, the calls on the model, and an arena one byte short. */
/* One model of the asset: kind -1 is romrt_open's choice, else romrt_open_kind's. */
static void run_kind(const void *asset, size_t size, int kind)
{
    void *arena = NULL, *small = NULL;
    size_t arena_bytes = 0;
    romrt_error err;
    romrt_model *m = NULL;
    romrt_status st;
    memset(&err, 0, sizeof err);
    st = kind < 0 ? romrt_arena_size(asset, size, &arena_bytes, &err)
                  : romrt_arena_size_kind(asset, size, (romrt_kind)kind, &arena_bytes, &err);
    if (check(st, &err) == ROMRT_OK && arena_bytes <= FUZZ_ARENA_CAP) {
        arena = alloc16(arena_bytes);
        memset(&err, 0, sizeof err);
        st = !arena ? ROMRT_E_ARENA : kind < 0 ? romrt_open(asset, size, arena, arena_bytes, &m, &err)
                                               : romrt_open_kind(asset, size, (romrt_kind)kind, arena, arena_bytes, &m, &err);
        if (arena && check(st, &err) == ROMRT_OK) {
            if (kind >= 0 && (int)romrt_model_kind(m) != kind) BROKEN("romrt_open_kind opened another kind");
            exercise(m);
        }
        /* An arena one byte short may be refused or may suffice, but must not be overrun. */
        small = arena_bytes > 1 ? alloc16(arena_bytes - 1) : NULL;
        if (small) check(romrt_open(asset, size, small, arena_bytes - 1, &m, &err), &err);
    }
    free(small);
    free(arena);
}

/* The default model, then the Koopman operator when the asset also holds one. */
static void run(const void *asset, size_t size)
{
    run_kind(asset, size, -1);
    run_kind(asset, size, ROMRT_KIND_KOOPMAN);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* The runtime wants the asset aligned (8, 16 recommended); the fuzzer's buffer is not. */
    unsigned char *asset = alloc16(size);
    if (!asset) return 0;
    if (size) memcpy(asset, data, size);
    run(asset, size);
    if (size && memcmp(asset, data, size) != 0) BROKEN("the runtime wrote into the (const) asset");
    /* Again with the CRCs made right (the asset copy is the same size, so ASan still bounds it). */
    if (fix_crcs(asset, size)) run(asset, size);
    free(asset);
    return 0;
}
