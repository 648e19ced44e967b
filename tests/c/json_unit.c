/* The C runtime's JSON writer on its own (runtime/c/json). Float texts (json_f64_text,
 * json_f32_text over shortest.c) on hard cases, each with the text Python prints (repr for
 * float64, canonical.f32_text for float32), then properties over pseudo-random bit patterns: every text reads back as its
 * float and is the correctly rounded decimal of its length. Then the writer's record buffer:
 * records longer than it, a key longer than it, each record whole in out when it ends. Then
 * string escapes and invalid UTF-8.
 * Prints "all json checks passed". */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "shortest.h"

static int failures;

static double f64_of(uint64_t bits)
{
    double x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

static float f32_of(uint32_t bits)
{
    float x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

static void report(const char *kind, unsigned long long bits, const char *got, const char *want)
{
    if (strcmp(got, want) != 0) {
        printf("%s %llx: got %s, want %s\n", kind, bits, got, want);
        failures++;
    }
}

static void expect_f64(double x, const char *want)
{
    uint64_t bits;
    char got[64];
    memcpy(&bits, &x, sizeof bits);
    json_f64_text(x, got, sizeof got);
    report("float64", bits, got, want);
}

static void expect_f32(float x, const char *want)
{
    uint32_t bits;
    char got[64];
    memcpy(&bits, &x, sizeof bits);
    json_f32_text(x, got, sizeof got);
    report("float32", bits, got, want);
}

static void float64_cases(void)
{
    const uint64_t max_mantissa = (UINT64_C(1) << 52) - 1;
    /* Zeros and the non-finite. */
    expect_f64(f64_of(0), "0.0");
    expect_f64(f64_of(UINT64_C(1) << 63), "-0.0");
    expect_f64(f64_of(UINT64_C(0x7ff0000000000000)), "Infinity");
    expect_f64(f64_of(UINT64_C(0xfff0000000000000)), "-Infinity");
    expect_f64(f64_of(UINT64_C(0x7ff8000000000000)), "NaN");
    expect_f64(f64_of(UINT64_C(0xfff0000000000001)), "NaN");
    /* Subnormals: the smallest, the largest; then the smallest normal and the largest double. */
    expect_f64(f64_of(1), "5e-324");
    expect_f64(f64_of(UINT64_C(0x8000000000000001)), "-5e-324");
    expect_f64(f64_of(max_mantissa), "2.225073858507201e-308");
    expect_f64(f64_of(UINT64_C(1) << 52), "2.2250738585072014e-308");
    expect_f64(f64_of(UINT64_C(0x7fefffffffffffff)), "1.7976931348623157e+308");
    expect_f64(4.940656e-318, "4.940656e-318");
    expect_f64(1.18575755e-316, "1.18575755e-316");
    expect_f64(2.989102097996e-312, "2.989102097996e-312");
    /* Powers of ten, and where repr() switches between fixed and scientific. */
    expect_f64(1.0, "1.0");
    expect_f64(0.1, "0.1");
    expect_f64(1e-4, "0.0001");
    expect_f64(1e-5, "1e-05");
    expect_f64(1e15, "1000000000000000.0");
    expect_f64(1e16, "1e+16");
    expect_f64(9999999999999998.0, "9999999999999998.0");
    expect_f64(1e22, "1e+22");
    expect_f64(1e23, "1e+23");
    expect_f64(1e-300, "1e-300");
    /* Powers of two (their rounding interval is lopsided) and the ends of binades. */
    expect_f64(0.015625, "0.015625");
    expect_f64(4503599627370496.0, "4503599627370496.0");   /* 2^52 */
    expect_f64(9007199254740992.0, "9007199254740992.0");   /* 2^53 */
    expect_f64(f64_of(UINT64_C(0x43e0000000000000)), "9.223372036854776e+18"); /* 2^63 */
    expect_f64(f64_of(UINT64_C(0x7fe0000000000000)), "8.98846567431158e+307"); /* 2^1023 */
    expect_f64(f64_of(UINT64_C(4) << 52), "1.7800590868057611e-307");
    expect_f64(f64_of((UINT64_C(6) << 52) | max_mantissa), "1.4240472694446087e-306");
    expect_f64(f64_of(UINT64_C(41) << 52), "2.446494580089078e-296");
    expect_f64(f64_of((UINT64_C(40) << 52) | max_mantissa), "2.4464945800890778e-296");
    expect_f64(f64_of(UINT64_C(1077) << 52), "1.8014398509481984e+16");
    expect_f64(f64_of((UINT64_C(1076) << 52) | max_mantissa), "1.8014398509481982e+16");
    expect_f64(f64_of(UINT64_C(307) << 52), "2.900835519859558e-216");
    expect_f64(f64_of((UINT64_C(306) << 52) | max_mantissa), "2.9008355198595575e-216");
    expect_f64(f64_of((UINT64_C(934) << 52) | UINT64_C(0x000fa7161a4d6e0c)), "3.196104012172126e-27");
    expect_f64(-6.243497100631985e+144, "-6.243497100631985e+144");
    expect_f64(7.291122019556398e-304, "7.291122019556398e-304");
    /* Seventeen significant digits, and sixteen. */
    expect_f64(0.30000000000000004, "0.30000000000000004");
    expect_f64(1.0 / 3, "0.3333333333333333");
    expect_f64(123456789012345680.0, "1.2345678901234568e+17");
    expect_f64(5.384497165679932, "5.384497165679932");
    expect_f64(-2.109808898695963e16, "-2.109808898695963e+16");
    expect_f64(9.0608011534336e15, "9060801153433600.0");
    expect_f64(4.708356024711512e18, "4.708356024711512e+18");
    expect_f64(9.409340012568248e18, "9.409340012568248e+18");
    /* Mantissas that are multiples of 5^22, where the scale's exactness check matters. */
    expect_f64(f64_of(UINT64_C(0x4830f0cf064dd592)), "5.764607523034235e+39");
    expect_f64(f64_of(UINT64_C(0x4840f0cf064dd592)), "1.152921504606847e+40");
    expect_f64(f64_of(UINT64_C(0x4850f0cf064dd592)), "2.305843009213694e+40");
    /* A decimal exactly on an end of the interval: in for an even mantissa, out for an odd
     * one. 2^54 + 6 lies midway between 2^54 + 4 (odd) and 2^54 + 8 (even). */
    expect_f64(18014398509481988.0, "1.8014398509481988e+16");
    expect_f64(18014398509481992.0, "1.801439850948199e+16");
}

static void float32_cases(void)
{
    expect_f32(f32_of(0), "0.0");
    expect_f32(f32_of(0x80000000u), "-0.0");
    expect_f32(f32_of(0x7f800000u), "Infinity");
    expect_f32(f32_of(0xff800000u), "-Infinity");
    expect_f32(f32_of(0x7fc00000u), "NaN");
    /* Subnormals, the smallest normal, the largest float32 and its neighbour. */
    expect_f32(f32_of(0x00000001u), "1e-45");
    expect_f32(f32_of(0x80000001u), "-1e-45");
    expect_f32(f32_of(0x00000002u), "3e-45");
    expect_f32(f32_of(0x00400000u), "5.877472e-39");
    expect_f32(f32_of(0x007fffffu), "1.1754942e-38");
    expect_f32(f32_of(0x00800000u), "1.1754944e-38");
    expect_f32(f32_of(0x7f7fffffu), "3.4028235e+38");
    expect_f32(f32_of(0xff7fffffu), "-3.4028235e+38");
    expect_f32(f32_of(0x7f7ffffeu), "3.4028233e+38");
    /* Laid out as float64 is: a decimal point from 1e-4 up to 1e16, an exponent outside (not
     * "%g"'s, which goes to an exponent at as many places as it has digits: 3e+01). */
    expect_f32(0.1f, "0.1");
    expect_f32(1.0f, "1.0");
    expect_f32(1.5f, "1.5");
    expect_f32(30.0f, "30.0");
    expect_f32(31.0f, "31.0");
    expect_f32(-30.0f, "-30.0");
    expect_f32(100.0f, "100.0");
    expect_f32(123.0f, "123.0");
    expect_f32(1e-4f, "0.0001");
    expect_f32(1e-5f, "1e-05");
    expect_f32(1.5e-5f, "1.5e-05");
    expect_f32(1e-7f, "1e-07");
    expect_f32(1e10f, "10000000000.0");
    expect_f32(1e15f, "1000000000000000.0");
    expect_f32(9.999999e15f, "9999999000000000.0");
    expect_f32(1e16f, "1e+16");
    expect_f32(1.5e20f, "1.5e+20");
    expect_f32(47.9f, "47.9");
    expect_f32(-0.333f, "-0.333");
    /* Powers of two, and ones where the lopsided interval needs a longer text than the
     * shortest decimal inside it (the correctly rounded 8 digits fall outside). */
    expect_f32(f32_of(0x4b800000u), "16777216.0");   /* 2^24 */
    expect_f32(f32_of(0x4c000000u), "33554432.0");   /* 2^25 */
    expect_f32(f32_of(0x7f000000u), "1.7014118e+38"); /* 2^127 */
    expect_f32(f32_of(0x0f800000u), "1.26217745e-29"); /* 2^-96 */
    expect_f32(f32_of(0x6b000000u), "1.54742505e+26"); /* 2^87 */
    expect_f32(f32_of(0x6c800000u), "1.23794004e+27"); /* 2^90 */
    /* Eight and nine digits. */
    expect_f32(f32_of(0x3f800001u), "1.0000001");
    expect_f32(f32_of(0x3eaaaaabu), "0.33333334");
    /* Ties on an end of the interval: 134219000 lies midway between 134218992 (odd mantissa:
     * out) and 134219008 (even: in). */
    expect_f32(134218992.0f, "134218990.0");
    expect_f32(134219008.0f, "134219000.0");
    /* 7.038531e-26 lies within half a double ulp of the midpoint between these two: read as a
     * double it is the midpoint, which rounds to the even one (0x15ae43fe), as Python reads it. */
    expect_f32(f32_of(0x15ae43fdu), "7.0385307e-26");
    expect_f32(f32_of(0x15ae43feu), "7.038531e-26");
}

/* Texts are cut as snprintf cuts them. */
static void cut_texts(void)
{
    char small[6];
    json_f64_text(0.30000000000000004, small, sizeof small);
    if (strcmp(small, "0.300") != 0) {
        printf("cut float64 text: %s\n", small);
        failures++;
    }
    json_f32_text(-3.4028235e38f, small, 1);
    if (small[0] != '\0') {
        printf("cut float32 text to nothing: %s\n", small);
        failures++;
    }
}

static uint64_t rng_state = UINT64_C(0x9e3779b97f4a7c15);

static uint64_t next_random(void)  /* splitmix64 */
{
    uint64_t z = (rng_state += UINT64_C(0x9e3779b97f4a7c15));
    z = (z ^ (z >> 30)) * UINT64_C(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94d049bb133111eb);
    return z ^ (z >> 31);
}

static int digit_count(uint64_t n)
{
    int k = 1;
    while (n >= 10) {
        n /= 10;
        k++;
    }
    return k;
}

/* Every text reads back as its float; its digits are the correctly rounded ones of their
 * length (printf's %.*g gives them) and end in no zero. A float32 text is laid out as the
 * float64 text of the double its %.*g reads as: that double has no shorter text (it would read
 * back as the same float32), so its text has the same digits. */
static void properties(long count)
{
    long i;
    char text[64], rounded[64], as_double[64];
    for (i = 0; i < count && failures < 20; i++) {
        uint64_t bits = next_random();
        double d = f64_of(bits);
        float f = f32_of((uint32_t)(bits >> 32));
        if (isfinite(d) && d != 0) {
            shortest_decimal dec = shortest_f64(d);
            json_f64_text(d, text, sizeof text);
            if (strtod(text, NULL) != d || dec.digits % 10 == 0) {
                printf("float64 %016llx: %s does not read back\n", (unsigned long long)bits, text);
                failures++;
            }
        }
        if (isfinite(f) && f != 0) {
            shortest_decimal dec = shortest_f32(f);
            int p = digit_count(dec.digits);
            json_f32_text(f, text, sizeof text);
            snprintf(rounded, sizeof rounded, "%.*g", p, (double)f);
            json_f64_text(strtod(rounded, NULL), as_double, sizeof as_double);
            if ((float)strtod(text, NULL) != f || strcmp(text, as_double) != 0 || dec.digits % 10 == 0) {
                printf("float32 %08lx: %s (%%.%dg: %s)\n", (unsigned long)(bits >> 32), text, p, rounded);
                failures++;
            }
        }
    }
}

/* What out holds, from its start. */
static char *contents(FILE *out, size_t *n)
{
    long size;
    char *text;
    fflush(out);
    size = ftell(out);
    text = malloc((size_t)size + 1);
    rewind(out);
    *n = fread(text, 1, (size_t)size, out);
    text[*n] = '\0';
    fseek(out, 0, SEEK_END);
    return text;
}

static void expect_output(FILE *out, const char *want, const char *what)
{
    size_t n;
    char *got = contents(out, &n);
    if (n != strlen(want) || memcmp(got, want, n) != 0) {
        printf("writer, %s: got %.80s... (%lu bytes), want %.80s... (%lu bytes)\n", what, got,
               (unsigned long)n, want, (unsigned long)strlen(want));
        failures++;
    }
    free(got);
}

/* Records through the visitor, as main.c writes them. */
static void writer_records(void)
{
    enum { LONG = JSON_WRITER_BUFFER + 100, HEX = 3 * JSON_WRITER_BUFFER };
    static char key[LONG + 1], want[2 * HEX + 2 * LONG + 256];
    static unsigned char raw[HEX];
    json_writer w;
    urwire_visitor v;
    urwire_bytes b;
    FILE *out = tmpfile();
    size_t i, at;
    if (!out) {
        puts("writer: no tmpfile");
        failures++;
        return;
    }
    w.out = out;
    w.depth = 0;
    w.len = 12345;  /* whatever was there: json_visitor starts the buffer empty */
    v = json_visitor(&w);

    v.begin_object(v.ctx, NULL);
    v.on_int(v.ctx, "a", -9223372036854775807 - 1);
    v.on_uint(v.ctx, "b", UINT64_MAX);
    v.begin_array(v.ctx, "c");
    v.on_f64(v.ctx, NULL, 0.5);
    v.on_f32(v.ctx, NULL, -2.5f);
    v.on_bool(v.ctx, NULL, true);
    v.on_null(v.ctx, NULL);
    v.end_array(v.ctx);
    expect_output(out, "", "a record before it ends");
    v.end_object(v.ctx);
    expect_output(out, "{\"a\": -9223372036854775808, \"b\": 18446744073709551615, \"c\": [0.5, -2.5, true, null]}",
                  "a record when it ends");

    /* A key longer than the buffer, first in its record, then bytes as hex three times the
     * buffer's size. */
    for (i = 0; i < LONG; i++)
        key[i] = (char)('a' + i % 26);
    for (i = 0; i < HEX; i++)
        raw[i] = (unsigned char)(i * 7);
    b.ptr = raw;
    b.len = HEX;
    putc('\n', out);
    w.depth = 0;
    v.begin_object(v.ctx, NULL);
    v.on_uint(v.ctx, key, 7);
    v.on_int(v.ctx, "n", 1);
    v.on_hex(v.ctx, "raw", b);
    v.end_object(v.ctx);
    at = (size_t)sprintf(want, "{\"a\": -9223372036854775808, \"b\": 18446744073709551615, \"c\": [0.5, -2.5, true, null]}\n"
                               "{\"%s\": 7, \"n\": 1, \"raw\": \"", key);
    for (i = 0; i < HEX; i++)
        at += (size_t)sprintf(want + at, "%02x", raw[i]);
    strcpy(want + at, "\"}");
    expect_output(out, want, "records longer than the buffer");
    fclose(out);
}

static void expect_text(const char *bytes, size_t n, const char *want)
{
    FILE *out = tmpfile();
    if (!out) {
        puts("text: no tmpfile");
        failures++;
        return;
    }
    json_write_text(out, (const unsigned char *)bytes, n);
    expect_output(out, want, "a string");
    fclose(out);
}

/* Strings as Python's json.dumps(bytes.decode("utf-8", "replace"), ensure_ascii=False) writes
 * them: the short escapes, \u00XX for the other control bytes, UTF-8 kept, and one U+FFFD per
 * maximal invalid subpart (a lone continuation byte, a cut sequence, an overlong form, a
 * surrogate, a code point above U+10FFFF). Then the hex and float64 texts of the FILE helpers. */
static void text_escapes(void)
{
    FILE *out;
    static const unsigned char raw[] = {0x00, 0x7f, 0xab, 0xff};
    expect_text("plain", 5, "\"plain\"");
    expect_text("q\"b\\s/", 6, "\"q\\\"b\\\\s/\"");
    expect_text("\n\r\t\b\f\0\x01\x1f\x7f", 9, "\"\\n\\r\\t\\b\\f\\u0000\\u0001\\u001f\x7f\"");
    expect_text("\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80", 9, "\"\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80\"");
    expect_text("\x80", 1, "\"\xef\xbf\xbd\"");
    expect_text("a\xe2\x82", 3, "\"a\xef\xbf\xbd\"");
    expect_text("\xc0\xaf", 2, "\"\xef\xbf\xbd\xef\xbf\xbd\"");
    expect_text("\xed\xa0\x80", 3, "\"\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd\"");
    expect_text("\xf4\x90\x80\x80", 4, "\"\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd\"");
    expect_text("\xf0\x9f\x98", 3, "\"\xef\xbf\xbd\"");
    expect_text("\xe2\x82\xac\xff", 4, "\"\xe2\x82\xac\xef\xbf\xbd\"");
    out = tmpfile();
    if (!out) {
        puts("text: no tmpfile");
        failures++;
        return;
    }
    json_write_hex(out, raw, sizeof raw);
    fputc(' ', out);
    json_write_f64(out, 1e-5);
    fputc(' ', out);
    json_write_f64(out, -0.0);
    expect_output(out, "\"007fabff\" 1e-05 -0.0", "hex and float64 texts");
    fclose(out);
}

int main(int argc, char **argv)
{
    float64_cases();
    float32_cases();
    cut_texts();
    properties(argc > 1 ? atol(argv[1]) : 200000);
    writer_records();
    text_escapes();
    if (failures) {
        printf("%d json checks failed\n", failures);
        return 1;
    }
    puts("all json checks passed");
    return 0;
}
