/* startup.c: reset path for the Cortex-M4F harness (MPS2-AN386 under qemu, newlib + rdimon
 * semihosting, linked with -nostartfiles so nothing of crt0 runs). */
#include <stdint.h>
#include <stdio.h>

extern uint32_t __stack_top, __data_load, __data_start, __data_end, __bss_start__, __bss_end__;
extern int main(void);
extern void initialise_monitor_handles(void);
void Reset_Handler(void);
void romkit_mcu_exit(int code);

/* Any fault or stray interrupt: say so (semihosting SYS_WRITE0, no stdio from a handler) and
 * stop with a failure code, instead of spinning until the qemu timeout. */
static void Fault_Handler(void)
{
    static const char text[] = "error fault: hard fault or unexpected exception on the MCU\n";
    register uint32_t r0 __asm__("r0") = 0x04u;
    register const char *r1 __asm__("r1") = text;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    romkit_mcu_exit(128);
}

/* The vector table: initial SP, reset, then the 14 system exceptions (NMI .. SysTick). */
__attribute__((section(".vectors"), used))
static void (*const vectors[16])(void) = {
    (void (*)(void))&__stack_top, Reset_Handler,
    Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
    0, 0, 0, 0,
    Fault_Handler, Fault_Handler, 0, Fault_Handler, Fault_Handler,
};

/* Semihosting SYS_EXIT_EXTENDED (0x20): plain SYS_EXIT on 32-bit ARM can only say success or
 * failure, the extended call carries the exit code, which qemu passes on as its own status. */
void romkit_mcu_exit(int code)
{
    uint32_t block[2] = {0x20026u /* ADP_Stopped_ApplicationExit */, (uint32_t)code};
    register uint32_t r0 __asm__("r0") = 0x20u;
    register uint32_t *r1 __asm__("r1") = block;
    for (;;)
        __asm__ volatile("bkpt 0xab" : : "r"(r0), "r"(r1) : "memory");
}

/* newlib's own exit() ends here (after running atexit handlers and flushing stdio). */
void _exit(int code)
{
    romkit_mcu_exit(code);
}

/* crti/crtn are not linked (-nostartfiles); __libc_init_array still calls these. */
void _init(void) {}
void _fini(void) {}

extern void __libc_init_array(void);

void Reset_Handler(void)
{
    /* Full access to CP10/CP11 (the FPU) before any float instruction; the barriers make
     * sure the enable has taken effect before the next instruction. */
    volatile uint32_t *cpacr = (volatile uint32_t *)0xE000ED88u;
    *cpacr |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");

    uint32_t *src = &__data_load, *dst = &__data_start;
    while (dst < &__data_end)
        *dst++ = *src++;
    for (dst = &__bss_start__; dst < &__bss_end__;)
        *dst++ = 0;

    __libc_init_array();
    initialise_monitor_handles();
    int rc = main();
    fflush(NULL);
    romkit_mcu_exit(rc);
}
