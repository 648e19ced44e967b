/* The start of the test harness on QEMU's MPS2 Cortex-M boards (mk/cross.mk's mps2-an386 run):
 * the vector table QEMU reads the first stack pointer and the reset address from, linked at 0
 * (-Wl,--section-start=.vectors=0). Reset turns the FPU on, makes every unaligned load and store
 * fault (CCR.UNALIGN_TRP), as a Cortex-M0+ always does, and enters newlib's rdimon crt0
 * (_start), which takes the stack, argv, stdin and stdout from the host through semihosting. A
 * fault ends the run with a message and a failing exit status instead of a hang. Test harness
 * only: the library never sees it. */
#include <stddef.h>
#include <stdint.h>

extern void _start(void);

#define SCB_CCR (*(volatile uint32_t *)0xE000ED14u)
#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)
#define CPACR_CP10_CP11 (0xFu << 20)
#define CCR_UNALIGN_TRP (1u << 3)

/* newlib's memcpy and memmove for ARMv7-M load and store words at any address, which the trap
 * would stop: the harness's own, a byte at a time (volatile, so that the compiler does not make
 * them a call to themselves), are linked before the C library's. */
void *memcpy(void *restrict dst, const void *restrict src, size_t n);
void *memmove(void *dst, const void *src, size_t n);

/* Overlapping or not; volatile, so that the compiler does not make the loops a call to memcpy. */
static void copy_bytes(volatile unsigned char *d, const volatile unsigned char *s, size_t n)
{
    size_t i;
    if (d < s)
        for (i = 0; i < n; i++)
            d[i] = s[i];
    else
        for (i = n; i-- > 0;)
            d[i] = s[i];
}

void *memcpy(void *restrict dst, const void *restrict src, size_t n)
{
    copy_bytes(dst, src, n);
    return dst;
}

void *memmove(void *dst, const void *src, size_t n)
{
    copy_bytes(dst, src, n);
    return dst;
}

/* Semihosting SYS_WRITE0 (0x04) then SYS_EXIT (0x18) with ADP_Stopped_RunTimeErrorUnknown. */
static void semihost(uint32_t op, const void *arg)
{
    register uint32_t r0 __asm("r0") = op;
    register const void *r1 __asm("r1") = arg;
    __asm volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
}

static void fault(void)
{
    semihost(0x04u, "mps2_start: fault (an unaligned access, or a bad address)\n");
    semihost(0x18u, (const void *)0x20023u);
    for (;;)
        ;
}

static void reset(void)
{
    SCB_CPACR |= CPACR_CP10_CP11;
    SCB_CCR |= CCR_UNALIGN_TRP;
    __asm volatile("dsb\n\tisb" ::: "memory");
    _start();
}

/* The first stack pointer: the top of the board's 4 MiB SSRAM2/3 (crt0 moves to the stack the
 * semihosting host gives); then reset and the faults (NMI, HardFault, MemManage, BusFault,
 * UsageFault). */
__attribute__((section(".vectors"), used)) static void (*const vectors[])(void) = {
    (void (*)(void))0x20400000u, reset, fault, fault, fault, fault, fault,
};
