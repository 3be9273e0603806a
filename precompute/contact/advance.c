/* Prescribed motion under contact (contact.h, rk_contact_advance): whatever the simulator moves
 * by prescription (obstacles, prescribed vertices) goes to its target in moves, each as far as CCD
 * allows and each followed by a solve that pushes the free surface clear (IPC's kinematic boundary
 * conditions, by continuation rather than a penalty). */
#include "contact/contact.h"

/* A motion that CCD lets advance less than this fraction this many times running is locked: the
 * free vertices cannot get out of the way (a vertex pinned between obstacles). */
#define STALL_FRACTION 1e-6
#define STALL_LIMIT 8
#define MAX_MOVES 1000

int rk_contact_advance(void *ctx, double t, rk_advance_fraction fraction, rk_advance_move move, rk_error *err)
{
    int stalls = 0;
    for (int k = 0; k < MAX_MOVES; k++) {
        double alpha = fraction(ctx, t, err);
        if (alpha < 0) return -1;
        int last = alpha >= 1;
        if (move(ctx, t, last ? 1 : alpha, err)) return -1;
        if (last) return 0;
        stalls = alpha < STALL_FRACTION ? stalls + 1 : 0;
        if (stalls >= STALL_LIMIT)
            return rk_fail(err, "the prescribed motion cannot go on to where it is at t = %g s: the free surface "
                           "cannot get out of its way (pinned between obstacles?)", t);
    }
    return rk_fail(err, "the prescribed motion to t = %g s needed more than %d safe moves", t, MAX_MOVES);
}
