/* Prints i32r_scaled (runtime/c/int32_records/records.c) of every "raw decimals" pair on stdin,
 * one per line, for tests/c/test_c_kind_runtimes.py to hold against Python's repr(raw / 10**d). */
#include <stdio.h>

#include "../../runtime/c/int32_records/records.c"

int main(void)
{
    long raw;
    unsigned decimals;
    char buf[64];
    while (scanf("%ld %u", &raw, &decimals) == 2) {
        i32r_out o;
        o.buf = buf;
        o.cap = sizeof buf;
        o.len = 0;
        i32r_scaled(&o, (int32_t)raw, decimals);
        i32r_end(&o);
        puts(buf);
    }
    return 0;
}
