/* Unit checks of what every kind's C runtime shares (runtime/c/common/): the big-endian loads,
 * the bounded output buffer, the UTF-8 decoder, the reader of a version's text and the bytes a
 * stream framer holds, compiled alone. Built and run by tests/c/test_c_common.py;
 * prints one line per failed check and "all common checks passed" at the end. */
#include <stdio.h>
#include <string.h>

#include "macros.h"
#include "loads.h"
#include "buffer.h"
#include "held.h"
#include "utf8.h"
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

/* U+FFFD, what each invalid part of a text becomes */
#define FFFD "\xef\xbf\xbd"

/* Whether the n bytes of in, each valid sequence kept and each maximal invalid subpart replaced
 * by U+FFFD as the JSON writers do, are want: what Python's bytes.decode("utf-8", "replace")
 * gives (every case below was checked against it). */
static int replaced(const char *in, size_t n, const char *want)
{
    char out[64];
    size_t i = 0, at = 0, len, bad;
    while (i < n) {
        bad = 0;
        len = urwire__utf8_sequence((const uint8_t *)in + i, n - i, &bad);
        if (len) {
            memcpy(out + at, in + i, len);
            at += len;
            i += len;
        } else {
            if (bad < 1 || bad > 3)
                return 0;
            memcpy(out + at, FFFD, 3);
            at += 3;
            i += bad;
        }
    }
    return at == strlen(want) && memcmp(out, want, at) == 0;
}

#define REPLACED(in, want) replaced(in, sizeof in - 1, want)

static void utf8(void)
{
    size_t bad = 0;
    /* valid: one to four bytes, the ends of each range Table 3-7 allows */
    CHECK(REPLACED("A\xc2\x80\xdf\xbf", "A\xc2\x80\xdf\xbf"));
    CHECK(REPLACED("\xe0\xa0\x80\xed\x9f\xbf\xee\x80\x80", "\xe0\xa0\x80\xed\x9f\xbf\xee\x80\x80"));
    CHECK(REPLACED("\xf0\x90\x80\x80\xf4\x8f\xbf\xbf", "\xf0\x90\x80\x80\xf4\x8f\xbf\xbf"));
    /* a continuation byte alone, and bytes that never start a sequence: one U+FFFD each */
    CHECK(REPLACED("\x80\xbf\xc0\xc1\xf5\xff", FFFD FFFD FFFD FFFD FFFD FFFD));
    /* overlong forms: no valid start longer than their lead byte, so one U+FFFD a byte */
    CHECK(REPLACED("\xc0\xaf", FFFD FFFD) && REPLACED("\xe0\x80\xaf", FFFD FFFD FFFD));
    CHECK(REPLACED("\xf0\x80\x80\xaf", FFFD FFFD FFFD FFFD));
    /* surrogates (ED A0..BF) and what lies past U+10FFFF (F4 90.., F5..): the same */
    CHECK(REPLACED("\xed\xa0\x80", FFFD FFFD FFFD) && REPLACED("\xed\xbf\xbf", FFFD FFFD FFFD));
    CHECK(REPLACED("\xf4\x90\x80\x80", FFFD FFFD FFFD FFFD) && REPLACED("\xf5\x80\x80\x80", FFFD FFFD FFFD FFFD));
    /* a valid start cut by a byte that cannot go on: one U+FFFD for the start, then that byte */
    CHECK(REPLACED("\xe2\x82" "A", FFFD "A") && REPLACED("\xf0\x9f\x98" " ", FFFD " "));
    CHECK(REPLACED("\xc3" "(", FFFD "(") && REPLACED("\xf0\x9f" "\xf0\x9f\x98\x80", FFFD "\xf0\x9f\x98\x80"));
    /* a valid start cut by the end of the text: one U+FFFD */
    CHECK(REPLACED("x\xc3", "x" FFFD) && REPLACED("x\xe2\x82", "x" FFFD) && REPLACED("x\xf0\x9f\x98", "x" FFFD));
    CHECK(REPLACED("\xf4\x8f\xbf", FFFD));
    /* n bounds what is read: the bytes after it are not looked at */
    CHECK(urwire__utf8_sequence((const uint8_t *)"\xe2\x82\xac", 2, &bad) == 0 && bad == 2);
    CHECK(urwire__utf8_sequence((const uint8_t *)"\xe2\x82\xac", 3, &bad) == 3);
    CHECK(urwire__utf8_sequence((const uint8_t *)"\xf0\x9f\x98\x80", 4, &bad) == 4);
    CHECK(urwire__utf8_sequence((const uint8_t *)"\xf0\x9f\x98\x80", 3, &bad) == 0 && bad == 3);
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

/* A framer holds bytes between feeds: what it framed is dropped and its offset kept, and a full
 * buffer takes only what fits. */
static void held(void)
{
    uint8_t buf[8];
    size_t head = 0, length = 0, taken;
    uint64_t base = 0;
    taken = urwire__hold(buf, sizeof buf, &head, &length, &base, (const uint8_t *)"abcdef", 6);
    CHECK(taken == 6 && length == 6 && base == 0 && memcmp(buf, "abcdef", 6) == 0);
    head = 4;   /* "abcd" framed */
    taken = urwire__hold(buf, sizeof buf, &head, &length, &base, (const uint8_t *)"ghijklmn", 8);
    CHECK(taken == 6 && head == 0 && length == 8 && base == 4 && memcmp(buf, "efghijkl", 8) == 0);
    taken = urwire__hold(buf, sizeof buf, &head, &length, &base, (const uint8_t *)"mn", 2);
    CHECK(taken == 0 && length == 8 && base == 4);   /* full, nothing framed since */
    head = 8;
    taken = urwire__hold(buf, sizeof buf, &head, &length, &base, (const uint8_t *)"mn", 2);
    CHECK(taken == 2 && length == 2 && base == 12 && memcmp(buf, "mn", 2) == 0);
    taken = urwire__hold(buf, sizeof buf, &head, &length, &base, NULL, 0);
    CHECK(taken == 0 && length == 2 && base == 12);
    /* More held than framed: the seven bytes after "m" move to the front in pieces, unharmed. */
    head = 0;
    taken = urwire__hold(buf, sizeof buf, &head, &length, &base, (const uint8_t *)"opqrst", 6);
    CHECK(taken == 6 && length == 8 && memcmp(buf, "mnopqrst", 8) == 0);
    head = 1;
    taken = urwire__hold(buf, sizeof buf, &head, &length, &base, (const uint8_t *)"u", 1);
    CHECK(taken == 1 && length == 8 && base == 13 && memcmp(buf, "nopqrstu", 8) == 0);
    head = 3;
    taken = urwire__hold(buf, sizeof buf, &head, &length, &base, NULL, 0);
    CHECK(taken == 0 && length == 5 && base == 16 && memcmp(buf, "qrstu", 5) == 0);
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
    utf8();
    held();
    version_text();
    if (failures)
        return 1;
    puts("all common checks passed");
    return 0;
}
