/* Unit checks of what every kind's C runtime shares (runtime/c/common/): the big-endian loads
 * and the bounded output buffer, compiled alone. Built and run by tests/c/test_c_common.py;
 * prints one line per failed check and "all common checks passed" at the end. */
#include <stdio.h>

#include "macros.h"
#include "loads.h"
#include "buffer.h"

static int failures;

#define CHECK(cond)                                                          \
    do {                                                                     \
        if (!(cond)) {                                                       \
            printf("FAILED %s:%d: %s\n", __FILE__, __LINE__, #cond);         \
            failures++;                                                      \
        }                                                                    \
    } while (0)

static void loads(void)
{
    static const uint8_t b[] = {0x80, 0x00, 0x00, 0x01, 0x3f, 0xf0, 0, 0, 0, 0, 0, 0,
                                0xc0, 0x00, 0, 0, 0, 0, 0, 0, 0xff, 0xff, 0xff, 0xfe};
    double two[2];
    size_t n;
    CHECK(urwire__i32(b) == -2147483647);
    CHECK(urwire__i32(b + 20) == -2);
    CHECK(urwire__u32(b + 20) == 0xfffffffeu);
    /* urwire__uint reads any width from 1 to 8 bytes, as urwire__u16/u32/u64 do theirs */
    CHECK(urwire__uint(b, 1) == 0x80u);
    CHECK(urwire__uint(b, 2) == urwire__u16(b));
    CHECK(urwire__uint(b, 3) == 0x800000u);
    CHECK(urwire__uint(b, 4) == urwire__u32(b));
    CHECK(urwire__uint(b + 4, 8) == urwire__u64(b + 4));
    for (n = 1; n <= 4; n++)      /* the first n bytes of ff ff ff fe */
        CHECK(urwire__uint(b + 20, n) == 0xfffffffeu >> (8 * (4 - n)));
    CHECK(urwire__f64(b + 4) == 1.0);
    CHECK(urwire__f64_of(0xc000000000000000u) == -2.0);
    urwire__f64s(two, b + 4, 2);
    CHECK(two[0] == 1.0 && two[1] == -2.0);
}

/* The text "hello, world" written into a buffer of cap bytes. */
static size_t written(char *out, size_t cap)
{
    urwire__text t;
    t.out = out;
    t.cap = cap;
    t.n = 0;
    urwire__str(&t, "hello");
    urwire__bytes(&t, ", world!", 7);
    return urwire__end(&t);
}

static void buffer(void)
{
    char out[16];
    memset(out, 'x', sizeof out);
    CHECK(written(out, sizeof out) == 12 && strcmp(out, "hello, world") == 0);
    memset(out, 'x', sizeof out);
    CHECK(written(out, 13) == 12 && strcmp(out, "hello, world") == 0);     /* an exact fit */
    memset(out, 'x', sizeof out);
    CHECK(written(out, 12) == 12 && strcmp(out, "hello, worl") == 0);      /* cut, NUL-terminated */
    memset(out, 'x', sizeof out);
    CHECK(written(out, 1) == 12 && out[0] == '\0' && out[1] == 'x');
    memset(out, 'x', sizeof out);
    CHECK(written(out, 0) == 12 && out[0] == 'x');                          /* nothing written */
}

int main(void)
{
    loads();
    buffer();
    if (failures)
        return 1;
    puts("all common checks passed");
    return 0;
}
