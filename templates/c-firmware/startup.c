/* Minimal Cortex-M4 start-up of the C firmware template (and of the C ABI
 * test, tests/c/test_raymip.c) under QEMU mps2-an386 with newlib's
 * semihosting library (rdimon: console and exit code through the
 * debugger interface): a vector table at address 0 whose reset handler
 * enables the FPU and enters newlib's _start (which zeroes .bss, sets up
 * the heap and calls main, then exit with main's return value). For a
 * board: your part's vector table and clock set-up, and a console of
 * your own instead of semihosting. */
#include <stdint.h>

extern void _start(void);
extern uint32_t __stack_top;

static void reset(void) {
    /* CPACR: full access to CP10/CP11 (the FPU) before any float code. */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n isb");
    _start();
    for (;;) {
    }
}

static void fault(void) {
    for (;;) {
    }
}

__attribute__((section(".vectors"), used)) static const void *const vectors[16] = {
    &__stack_top, (const void *)reset, (const void *)fault, (const void *)fault,
    (const void *)fault, (const void *)fault, (const void *)fault,
};
