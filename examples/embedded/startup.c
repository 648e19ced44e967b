/* A device's start, as every Cortex-M and RISC-V firmware has its own (CMSIS's startup files,
 * a vendor's SDK): reset copies the initial values of data from flash to RAM, zeroes bss and
 * calls main, with no C library start code (no argv, atexit, exit or constructors, which a
 * firmware never uses). firmware.ld places what is here first in flash and gives the symbols.
 * The figures of `make bench-embedded` include it (scripts/bench_embedded.py links with
 * -nostartfiles and firmware.ld). */
#include <stdint.h>

int main(void);

/* firmware.ld's: where data's initial values are in flash and where data and bss are in RAM,
 * word-aligned, and the top of the stack. */
extern uint32_t __data_load[], __data_start[], __data_end[], __bss_start[], __bss_end[], __stack_top[];

void Reset_Handler(void);

/* Word loops, volatile, so that the compiler makes them no call to memcpy or memset (the
 * parser links no memset, and copies start its data). */
void Reset_Handler(void)
{
    const uint32_t *from = __data_load;
    volatile uint32_t *to;

    for (to = __data_start; to < __data_end;)
        *to++ = *from++;
    for (to = __bss_start; to < __bss_end;)
        *to++ = 0;
    main();
    for (;;)
        ;
}

#if defined(__arm__)
/* An exception the firmware does not handle stops here, for a debugger to see. */
static void Default_Handler(void)
{
    for (;;)
        ;
}

/* The Cortex-M vector table: the first stack pointer (a data pointer, apart: ISO C converts no
 * object pointer to a function pointer), reset, then the core's exceptions (NMI, HardFault,
 * MemManage, BusFault, UsageFault, four reserved, SVCall, DebugMonitor, one reserved, PendSV,
 * SysTick); a device's interrupts follow in a real board's. */
typedef struct vector_table {
    uint32_t *initial_stack;
    void (*handler[15])(void);
} vector_table;

__attribute__((section(".vectors"), used)) static const vector_table vectors = {
    __stack_top,
    {Reset_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, 0, 0, 0, 0,
     Default_Handler, Default_Handler, 0, Default_Handler, Default_Handler},
};
#elif defined(__riscv)
/* RISC-V starts at the first word of flash with no stack: the stack pointer and the global
 * pointer (which the linker relaxes small data's addresses against) are set first. */
__asm__(".section .vectors, \"ax\"\n"
        ".globl _start\n"
        "_start:\n"
        ".option push\n"
        ".option norelax\n"
        "    la gp, __global_pointer$\n"
        ".option pop\n"
        "    la sp, __stack_top\n"
        "    j Reset_Handler\n");
#else
#error "startup.c knows Cortex-M and RISC-V"
#endif
