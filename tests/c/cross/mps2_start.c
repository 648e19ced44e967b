/* The start of the test harness on QEMU's MPS2 Cortex-M boards (mk/cross.mk's mps2-an386 run):
 * the vector table QEMU reads the first stack pointer and the reset address from, linked at 0
 * (-Wl,--section-start=.vectors=0). Reset turns the FPU on and enters newlib's rdimon crt0
 * (_start), which takes the stack, argv, stdin and stdout from the host through semihosting. A
 * fault ends the run with a message and a failing exit status instead of a hang. Unaligned
 * accesses are not trapped (CCR.UNALIGN_TRP): newlib's own memcpy for ARMv7-M makes them. Test
 * harness only: the library never sees it. */
#include <stdint.h>

extern void _start(void);

#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)
#define CPACR_CP10_CP11 (0xFu << 20)

/* Semihosting SYS_WRITE0 (0x04) then SYS_EXIT (0x18) with ADP_Stopped_RunTimeErrorUnknown. */
static void semihost(uint32_t op, const void *arg)
{
    register uint32_t r0 __asm("r0") = op;
    register const void *r1 __asm("r1") = arg;
    __asm volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
}

static void fault(void)
{
    semihost(0x04u, "mps2_start: fault\n");
    semihost(0x18u, (const void *)0x20023u);
    for (;;)
        ;
}

static void reset(void)
{
    SCB_CPACR |= CPACR_CP10_CP11;
    __asm volatile("dsb\n\tisb" ::: "memory");
    _start();
}

/* The first stack pointer: the top of the board's 4 MiB SSRAM2/3 (crt0 moves to the stack the
 * semihosting host gives); then reset and the faults (NMI, HardFault, MemManage, BusFault,
 * UsageFault). */
__attribute__((section(".vectors"), used)) static void (*const vectors[])(void) = {
    (void (*)(void))0x20400000u, reset, fault, fault, fault, fault, fault,
};
