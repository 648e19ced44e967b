/* Prints i32r_scaled (runtime/c/int32_records/records.c) of every "raw decimals" pair on stdin,
 * one per line, for tests/c/test_c_kind_runtimes.py to hold against Python's repr(raw / 10**d). */
#include <stdio.h>

#include "../../runtime/c/common/buffer.c"
#include "../../runtime/c/int32_records/records.c"

int main(void)
{
    long raw;
    unsigned decimals;
    char buf[64];
    while (scanf("%ld %u", &raw, &decimals) == 2) {
        urwire__text o;
        o.out = buf;
        o.cap = sizeof buf;
        o.n = 0;
        i32r_scaled(&o, (int32_t)raw, decimals);
        urwire__end(&o);
        puts(buf);
    }
    return 0;
}
