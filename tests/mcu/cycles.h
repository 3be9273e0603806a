/* cycles.h: a deterministic instruction counter for the Cortex-M4F harness under qemu. */
#ifndef ROMKIT_MCU_CYCLES_H
#define ROMKIT_MCU_CYCLES_H

#include <stdint.h>

/* Starts the counter (call once). */
void cycles_init(void);
/* The counter now, in instructions since cycles_init (resolution: see cycles.c). */
uint64_t cycles_now(void);

#endif
