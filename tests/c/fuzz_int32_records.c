/* libFuzzer harness for an int32-record interface's generated C, built once per interface with
 * -DPREFIX=ur_reverse_ -DHEADER='"ur_reverse.h"' (and ur_trajectory, ur_script_command).
 *
 * Input: byte 0 picks the driver release (the oldest, a middle and the newest the specs name,
 * or one between); then segments as in fuzz_ur_dashboard.c (a control byte: bit 0 from the
 * robot, bits 1-7 the length). Each direction is cut into whole records as a caller does.
 * Checks: no crash or sanitizer report; every record's JSON fits a bound and is as long as said;
 * a tail of either direction gives a fault line. */
#include <stdlib.h>
#include <string.h>

#include HEADER

#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)
#define FN(name) CAT(PREFIX, name)
#define HELD 4096

static char json[1 << 14];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const uint32_t releases[8] = {1u, 400000u, 1000000u, 1003001u, 1003002u, 1005000u, 2010000u, 2014000u};
    static uint8_t held[2][HELD];
    size_t len[2] = {0, 0}, at = 1, d;
    uint64_t offset[2] = {0, 0};
    uint32_t release;
    if (size == 0)
        return 0;
    release = releases[data[0] & 7u];
    while (at < size) {
        bool from_robot = (data[at] & 1u) != 0;
        size_t n = (size_t)(data[at] >> 1), take, unit, used = 0;
        d = from_robot ? 1 : 0;
        at++;
        take = n < size - at ? n : size - at;
        if (len[d] + take > HELD)
            take = HELD - len[d];
        memcpy(held[d] + len[d], data + at, take);
        len[d] += take;
        at += take;
        unit = FN(record_size)(from_robot, release);
        while (unit > 0 && len[d] - used >= unit) {
            size_t out = FN(record_json)(from_robot, held[d] + used, unit, release, json, sizeof json);
            if (out == 0 || out >= sizeof json || strlen(json) != out || json[0] != '{' || json[out - 1] != '}')
                abort();
            used += unit;
        }
        memmove(held[d], held[d] + used, len[d] - used);
        len[d] -= used;
        offset[d] += used;
        if (unit == 0)
            len[d] = 0;   /* nothing is specified that way: the bytes are only counted */
    }
    for (d = 0; d < 2; d++)
        if (FN(tail_json)(d == 1, offset[d], len[d], release, json, sizeof json) >= sizeof json)
            abort();
    return 0;
}
