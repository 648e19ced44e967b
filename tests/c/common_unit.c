/* Unit checks of what every kind's C runtime shares (runtime/c/common/): the big-endian loads,
 * the bounded output buffer and the reader of a version's text, compiled alone. Built and run by tests/c/test_c_common.py;
 * prints one line per failed check and "all common checks passed" at the end. */
#include <stdio.h>

#include "macros.h"
#include "loads.h"
#include "buffer.h"
#include "version_text.h"

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

static int reads(const char *text, bool whole, bool vt_blank, uint64_t a, uint64_t b, uint64_t c)
{
    urwire__version_text v;
    return urwire__read_version(text, text + strlen(text), whole, vt_blank, &v) && v.part[0] == a
           && v.part[1] == b && v.part[2] == c;
}

static int refused(const char *text, bool whole)
{
    urwire__version_text v;
    return !urwire__read_version(text, text + strlen(text), whole, false, &v);
}

static void version_text(void)
{
    urwire__version_text v;
    const char *reply = "5.11.1.108318 (Nov 26 2021)", *dotted = "5.1.";
    /* whole: ^%s*(%d+)%.(%d+)%.?(%d*)%s*$, as the Lua dissectors read a preference */
    CHECK(reads(" 3.15.7 ", true, false, 3, 15, 7) && reads("5.11", true, false, 5, 11, 0));
    CHECK(reads("5.1234", true, false, 5, 1234, 0));
    CHECK(urwire__read_version(dotted, dotted + 4, true, false, &v) && v.parts == 2 && v.dot_after);
    CHECK(refused("", true) && refused("5", true) && refused("5.11.1.2", true) && refused("x5.11", true));
    CHECK(refused("5.11 1", true) && refused("5.9.x", true) && refused("5.", true) && refused(".5", true));
    /* not whole: the text may go on after the version; a third number needs its digit */
    CHECK(reads("5.9 (CB3)", false, false, 5, 9, 0) && reads("5.9.x", false, false, 5, 9, 0));
    CHECK(reads(" 3.2.", false, false, 3, 2, 0) && reads("10.7.5000", false, false, 10, 7, 5000));
    CHECK(refused("abc", false) && refused("5.", false));
    /* a vertical tab is a blank only when asked */
    CHECK(reads("\v5.9\v", true, true, 5, 9, 0) && refused("\v5.9", true));
    /* a part stops growing at its first thirteen digits: no overflow */
    CHECK(reads("123456789012345678901.1", true, false, 1234567890123u, 1, 0));
    /* what was read: a dashboard reply's version, then its build */
    CHECK(urwire__read_version(reply, reply + strlen(reply), false, false, &v) && v.parts == 3 && v.longest == 2);
    CHECK(v.part[0] == 5 && v.part[1] == 11 && v.part[2] == 1 && v.end == reply + 6 && *v.end == '.');
    /* the end bounds the text: no NUL needed */
    CHECK(urwire__read_version(reply, reply + 4, true, false, &v) && v.part[1] == 11 && v.parts == 2);
}

int main(void)
{
    loads();
    buffer();
    version_text();
    if (failures)
        return 1;
    puts("all common checks passed");
    return 0;
}
