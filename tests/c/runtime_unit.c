/* Unit checks of the hand-written C runtime (runtime/c/) on its own: every
 * runtime .c file compiled standalone (its private functions external, see private.h) and
 * linked with this file, over the made-up protocol of runtime_spec.h and runtime_support.h.
 * Prints one line per failed check; exit 1 if any failed. */
#include <stdio.h>

#include "runtime_support.h"

static int failures;

#define CHECK(cond)                                                          \
    do {                                                                     \
        if (!(cond)) {                                                       \
            printf("FAILED %s:%d: %s\n", __FILE__, __LINE__, #cond);         \
            failures++;                                                      \
        }                                                                    \
    } while (0)

static int text_is(const urwire_error *e, const char *want)
{
    char buf[URWIRE_PATH_MAX + 128];
    urwire_error_text(e, buf, sizeof buf);
    if (strcmp(buf, want) != 0)
        printf("  text: \"%s\"\n  want: \"%s\"\n", buf, want);
    return strcmp(buf, want) == 0;
}

/* Whether the error's text names `want` as its field: the text starts "want at offset". */
static int path_is(const urwire_error *e, const char *want)
{
    char buf[URWIRE_PATH_MAX + 128];
    size_t n = strlen(want);
    urwire_error_text(e, buf, sizeof buf);
    return strncmp(buf, want, n) == 0 && strncmp(buf + n, " at offset", 10) == 0;
}

static void loads_and_stores(void)
{
    uint8_t b[17];
    float f = -1.5f, g;
    double d = 6.02214076e23, e;
    size_t at;
    memset(b, 0xee, sizeof b);
    for (at = 0; at < 2; at++) {  /* aligned and not */
        urwire__put_u16(b + at, 0x0102);
        CHECK(b[at] == 0x01 && b[at + 1] == 0x02 && urwire__u16(b + at) == 0x0102);
        urwire__put_u32(b + at, 0x01020304u);
        CHECK(b[at] == 0x01 && b[at + 3] == 0x04 && urwire__u32(b + at) == 0x01020304u);
        urwire__put_u64(b + at, 0x0102030405060708u);
        CHECK(b[at] == 0x01 && b[at + 7] == 0x08 && urwire__u64(b + at) == 0x0102030405060708u);
        urwire__put_i16(b + at, -2);
        CHECK(b[at] == 0xff && b[at + 1] == 0xfe && urwire__i16(b + at) == -2);
        urwire__put_i32(b + at, INT32_MIN);
        CHECK(b[at] == 0x80 && b[at + 3] == 0x00 && urwire__i32(b + at) == INT32_MIN);
        urwire__put_i64(b + at, -3);
        CHECK(b[at] == 0xff && b[at + 7] == 0xfd && urwire__i64(b + at) == -3);
        urwire__put_i8(b + at, -128);
        CHECK(b[at] == 0x80 && urwire__i8(b + at) == -128 && urwire__u8(b + at) == 0x80);
        urwire__put_f32(b + at, f);
        g = urwire__f32(b + at);
        CHECK(b[at] == 0xbf && b[at + 1] == 0xc0 && memcmp(&f, &g, sizeof f) == 0);
        urwire__put_f64(b + at, d);
        e = urwire__f64(b + at);
        CHECK(memcmp(&d, &e, sizeof d) == 0);
    }
    b[0] = 0x7f, b[1] = 0x80, b[2] = 0x00, b[3] = 0x00;  /* +inf, read as its bit pattern */
    CHECK(urwire__u32(b) == 0x7f800000u && urwire__f32(b) > 3.4e38f);
    CHECK(urwire__swap16(0x1234) == 0x3412 && urwire__swap32(0x12345678u) == 0x78563412u);
    CHECK(urwire__swap64(0x0102030405060708u) == 0x0807060504030201u);
}

static void versions(void)
{
    urwire_sw_version v = {0, 0, 0, false};
    urwire__versions up_to_3_2 = {false, {0, 0, 0, false}, true, {3, 2, 999, false}};
    urwire__versions from_3_3 = {true, {3, 3, 0, false}, false, {0, 0, 0, false}};
    urwire__versions ranges[2];
    CHECK(urwire_parse_version("5.9", &v) && v.major == 5 && v.minor == 9 && v.bugfix == 0 && !v.assumed);
    CHECK(urwire_parse_version(" 5.10.1\n", &v) && v.major == 5 && v.minor == 10 && v.bugfix == 1);
    CHECK(urwire_parse_version("3.15", &v) && v.major == 3 && v.minor == 15 && v.bugfix == 0);
    v.major = 7;
    CHECK(!urwire_parse_version("5", &v) && !urwire_parse_version("5.", &v) && !urwire_parse_version(".9", &v));
    CHECK(!urwire_parse_version("5..9", &v) && !urwire_parse_version("5.9b", &v) && !urwire_parse_version("", &v));
    CHECK(!urwire_parse_version("1.2.3.4", &v) && !urwire_parse_version("5.9.", &v));
    CHECK(!urwire_parse_version("1234567.1", &v) && v.major == 7);  /* untouched on failure */
    v.major = 5, v.minor = 9, v.bugfix = 0;
    CHECK(urwire__version_cmp(v, 5, 9, 0) == 0 && urwire__version_cmp(v, 5, 10, 0) < 0);
    CHECK(urwire__version_cmp(v, 4, 99, 0) > 0 && urwire__version_cmp(v, 5, 8, 999) > 0);
    CHECK(urwire__version_cmp(v, 5, 9, 1) < 0);
    CHECK(!urwire__in_versions(v, &up_to_3_2) && urwire__in_versions(v, &from_3_3));
    v.major = 3, v.minor = 2, v.bugfix = 7;  /* "up to 3.2" holds any 3.2.x */
    CHECK(urwire__in_versions(v, &up_to_3_2) && !urwire__in_versions(v, &from_3_3));
    v.bugfix = 1000;  /* but a 3.2.x beyond the bound's 999 is past it, as the spec's tuples compare */
    CHECK(!urwire__in_versions(v, &up_to_3_2) && !urwire__in_versions(v, &from_3_3));
    ranges[0] = up_to_3_2, ranges[1] = from_3_3;
    CHECK(urwire__table_index(v, ranges, 2) == 1);  /* in none: the last */
    v.bugfix = 0;
    CHECK(urwire__table_index(v, ranges, 2) == 0);
    CHECK(URWIRE_DEFAULT_VERSION.major == 5 && URWIRE_DEFAULT_VERSION.minor == 9 && URWIRE_DEFAULT_VERSION.assumed);
}

static const urwire__form *choose(const urwire__form_table *t, int major, int minor, int bugfix, size_t size,
                                  urwire_sw_version *use, bool *by_length)
{
    use->major = major, use->minor = minor, use->bugfix = bugfix, use->assumed = true;
    return urwire__choose(t, 1, urwire__segment(urwire__version_key(*use)), size, use, by_length);
}

static size_t segment(int major, int minor, int bugfix)
{
    urwire_sw_version v;
    v.major = major, v.minor = minor, v.bugfix = bugfix, v.assumed = false;
    return urwire__segment(urwire__version_key(v));
}

static void forms(void)
{
    /* An open-ended form (at least 2 bytes) up to 3.2, and one of exactly 4 from 3.3. */
    static const urwire__form open_forms[] = {
        {URWIRE_LAYOUT_TALLY, 0, {0, 0}, 2u, {3, 2, 999, false}},
        {URWIRE_LAYOUT_COUNTER, 1, {4, 0}, 4u, {5, 9, 0, false}},
    };
    static const urwire__recognised open_by_length[] = {{4u, 1}};   /* the open-ended one: none */
    static const urwire__forms open_codes[] = {{NULL, NULL, 0, 0}, {open_forms, open_by_length, 2, 1}};
    urwire__form_table open = {open_forms, open_codes, 2, urwire__package_mine};
    const urwire__form_table *t = &urwire__package_form_table;
    urwire_sw_version use;
    bool by_length, nearest;
    /* The segments: below 0.0.0, up to 3.2.999, 3.2.1000 to 3.3.0, from 3.3.0, past every
     * version; the parts of a version beyond what the spec names compare as its limits. */
    CHECK(segment(-1, 0, 0) == 0 && segment(0, 0, 0) == 1 && segment(3, 2, 999) == 1);
    CHECK(segment(3, 2, 1000) == 2 && segment(3, 2, 2147483647) == 2 && segment(3, 3, -5) == 2);
    CHECK(segment(3, 3, 0) == 3 && segment(10, 0, 0) == 3 && segment(1048576, 0, 0) == 3);
    CHECK(segment(1048576, 0, 1) == 4 && segment(2147483647, -1, 0) == 4);
    CHECK(urwire__version_key(URWIRE_DEFAULT_VERSION) == URWIRE__V(5, 9, 0));
    CHECK(urwire__mine(t, 1, 1, &nearest) == &urwire__package_form_list[0] && !nearest);
    CHECK(urwire__mine(t, 2, 1, &nearest) == &urwire__package_form_list[0] && nearest);
    CHECK(urwire__mine(t, 0, 1, &nearest) == NULL && !nearest);
    /* The version's form when it fits: the version stays. */
    CHECK(choose(t, 3, 2, 0, 2, &use, &by_length)->layout == URWIRE_LAYOUT_TALLY && !by_length);
    CHECK(use.major == 3 && use.minor == 2 && use.bugfix == 0 && use.assumed);
    CHECK(choose(t, 5, 9, 0, 4, &use, &by_length)->layout == URWIRE_LAYOUT_COUNTER && !by_length);
    /* Else the one form of that exact size, in the version it stands for. */
    CHECK(choose(t, 5, 9, 0, 2, &use, &by_length)->layout == URWIRE_LAYOUT_TALLY && by_length);
    CHECK(use.major == 3 && use.minor == 2 && use.bugfix == 999 && use.assumed);
    CHECK(choose(t, 3, 2, 1000, 4, &use, &by_length)->layout == URWIRE_LAYOUT_COUNTER && by_length);
    /* Else the version's form, short or with extra bytes; with none, the last. */
    CHECK(choose(t, 5, 9, 0, 3, &use, &by_length)->layout == URWIRE_LAYOUT_COUNTER && !by_length);
    CHECK(use.major == 5 && use.minor == 9);
    CHECK(choose(t, 3, 0, 0, 9, &use, &by_length)->layout == URWIRE_LAYOUT_TALLY && !by_length);
    /* A version no form is sent in: the nearest form below, read as the version it stands for. */
    CHECK(choose(t, 3, 2, 1000, 3, &use, &by_length)->layout == URWIRE_LAYOUT_TALLY && !by_length);
    CHECK(use.major == 3 && use.minor == 2 && use.bugfix == 999);
    /* An open-ended form fits any length from its least, but is never recognised by length. */
    CHECK(choose(&open, 3, 0, 0, 40, &use, &by_length)->layout == URWIRE_LAYOUT_TALLY && !by_length);
    CHECK(choose(&open, 5, 9, 0, 40, &use, &by_length)->layout == URWIRE_LAYOUT_COUNTER && !by_length);
    CHECK(choose(&open, 3, 0, 0, 4, &use, &by_length)->layout == URWIRE_LAYOUT_TALLY && !by_length);
    CHECK(choose(&open, 3, 0, 0, 1, &use, &by_length)->layout == URWIRE_LAYOUT_TALLY && !by_length);
}

static void error_texts(void)
{
    urwire_error e;
    char small[8], digits[24], field[URWIRE_PATH_MAX + 8], want[URWIRE_PATH_MAX + 64];
    size_t k;
    CHECK(urwire__digits(digits, INT64_MIN) == 20 && memcmp(digits, "-9223372036854775808", 20) == 0);
    CHECK(!urwire__short(&e, "speed", 27, 8, 34));
    CHECK(e.status == URWIRE_E_SHORT && text_is(&e, "speed at offset 27: needs 8 bytes, 7 left"));
    CHECK(urwire_error_text(&e, small, sizeof small) == 41 && strcmp(small, "speed a") == 0);
    CHECK(urwire_error_text(&e, small, 0) == 41);
    urwire__fail(&e, URWIRE_E_TERMINATOR, 9, "values[0]", 0x0b, 0x0a);
    CHECK(text_is(&e, "values[0] at offset 9: expected terminator 0x0a, found 0x0b"));
    urwire__fail(&e, URWIRE_E_PACKAGE_LENGTH_LOW, 5, "package", 4, 0);
    CHECK(text_is(&e, "package at offset 5: length 4 is below 5"));
    urwire__fail(&e, URWIRE_E_LENGTH_HIGH, 0, "", 1048577, 0);
    CHECK(text_is(&e, "length 1048577 is above 1048576"));
    urwire__fail(&e, URWIRE_E_TOO_MANY_ITEMS, 17, "variables[0]", 32767, 5);
    CHECK(text_is(&e, "variables[0] at offset 17: 32767 items need more than the 5 bytes left"));
    urwire__fail(&e, URWIRE_E_EMPTY_ROWS, 17, "variables[0]", 32767, 0);
    CHECK(text_is(&e, "variables[0] at offset 17: 32767 rows of 0 columns"));
    urwire__fail(&e, URWIRE_E_TOO_LONG, 0, "title", 300, 255);
    CHECK(text_is(&e, "title: 300 bytes do not fit the length prefix (max 255)"));
    CHECK(strcmp(urwire_status_name(URWIRE_OK), "URWIRE_OK") == 0);
    CHECK(strcmp(urwire_status_name(URWIRE_E_TOO_DEEP), "URWIRE_E_TOO_DEEP") == 0);
    CHECK(strcmp(urwire_status_name(URWIRE_E_TOO_LONG), "URWIRE_E_TOO_LONG") == 0);  /* the last */
    CHECK(strcmp(urwire_status_name((urwire_status)99), "URWIRE_E_UNKNOWN") == 0);
    {
        /* A run of a field, a group of 3 elements of two fields (one repeat row) and a field. */
        static const urwire__span run[] = {
            URWIRE__SPAN("head", 0, 2, URWIRE__NO_INDEX), URWIRE__SPAN("g[].a", 2, 4, 0),
            URWIRE__SPAN("g[].b", 6, 1, 0), URWIRE__SPAN(NULL, 5, URWIRE__REPEAT | 3, 2),
            URWIRE__SPAN("tail", 17, 8, URWIRE__NO_INDEX), URWIRE__SPAN(NULL, 0, 0, 0),
        };
        CHECK(!urwire__short_in_run(&e, run, 100, 101) && e.offset == 100 && path_is(&e, "head"));
        CHECK(!urwire__short_in_run(&e, run, 100, 106) && e.offset == 106 && path_is(&e, "g[0].b"));
        CHECK(!urwire__short_in_run(&e, run, 100, 111) && e.offset == 111 && path_is(&e, "g[1].b"));
        CHECK(!urwire__short_in_run(&e, run, 100, 115) && e.offset == 112 && path_is(&e, "g[2].a"));
        CHECK(e.value == 4 && e.left == 3);
        CHECK(!urwire__short_in_run(&e, run, 100, 124) && e.offset == 117 && path_is(&e, "tail"));
    }
    /* Paths are joined from the inside out, as the decoders unwind. */
    urwire__fail(&e, URWIRE_E_VALUE_TYPE, 40, ".type", 99, 0);
    urwire__within2(&e, "", 2, 0, true);
    urwire__within(&e, "variables", 1);
    CHECK(text_is(&e, "variables[1][2][0].type at offset 40: unknown value type 99"));
    urwire__short(&e, "label_name", 12, 2, 13);
    urwire__within(&e, "threads", 3);
    CHECK(text_is(&e, "threads[3].label_name at offset 12: needs 2 bytes, 1 left"));
    /* A path at its limit is cut in the text, never overflows. */
    memset(field, 'x', sizeof field - 1);
    field[sizeof field - 1] = '\0';
    urwire__short(&e, field, 0, 1, 0);
    urwire__within(&e, "variables", 1);
    memcpy(want, "variables[1].", 13);
    memset(want + 13, 'x', URWIRE_PATH_MAX - 1 - 13);
    strcpy(want + URWIRE_PATH_MAX - 1, " at offset 0: needs 1 bytes, 0 left");
    CHECK(text_is(&e, want));
    /* A path deeper than URWIRE_PATH_STEPS keeps its innermost steps. */
    urwire__fail(&e, URWIRE_E_VALUE_TYPE, 40, ".type", 99, 0);
    for (k = 0; k <= URWIRE_PATH_STEPS; k++)
        urwire__within(&e, "", k);
    CHECK(text_is(&e, "[3][2][1][0].type at offset 40: unknown value type 99"));
}

static void texts(void)
{
    static const uint8_t prefixed[] = {0x00, 0x03, 'a', 'b', 'c', 0xff, 0xfe};
    static const uint8_t names[] = {'a', 0, 'b', 'c', 0, 'x'};
    urwire_bytes b;
    urwire_seq seq;
    urwire_error e;
    size_t at = 0;
    CHECK(urwire__read_prefixed(prefixed, &at, sizeof prefixed, 2, true, "name", &b, &e));
    CHECK(at == 5 && b.len == 3 && memcmp(b.ptr, "abc", 3) == 0);
    CHECK(!urwire__read_prefixed(prefixed, &at, sizeof prefixed, 2, true, "name", &b, &e));
    CHECK(text_is(&e, "name at offset 5: negative length -2"));
    at = 5;  /* the same bytes unsigned: 65534, past the end */
    CHECK(!urwire__read_prefixed(prefixed, &at, sizeof prefixed, 2, false, "name", &b, &e));
    CHECK(text_is(&e, "name at offset 7: needs 65534 bytes, 0 left"));
    at = 0;
    urwire__read_texts(names, &at, sizeof names, 0, &seq);
    CHECK(at == 5 && seq.count == 2);  /* "x" has no terminator: it is extra, not a name */
    CHECK(urwire_next_text(&seq, &b) && b.len == 1 && b.ptr[0] == 'a');
    CHECK(urwire_next_text(&seq, &b) && b.len == 2 && b.ptr[0] == 'b');
    CHECK(!urwire_next_text(&seq, &b));
}

static void values(void)
{
    static const uint8_t good[] = {
        15, 0, 0, 0, 7, '\n',                      /* INT 7 */
        17, 0, 2, 13, 1, 3, 0, 2, 'h', 'i', '\n',  /* LIST of BOOL true and CONST_STRING "hi" */
        0, '\n',                                   /* NONE */
    };
    static const uint8_t deep[] = {17, 0, 1, 17, 0, 1, 17, 0, 1, 17, 0, 0, '\n'};
    static const uint8_t old_list[] = {17, '\n'};  /* 17 is not a type up to 3.2 */
    static const uint8_t long_list[] = {17, 0, 4, 0, 0, '\n'};            /* 4 items, 3 bytes left */
    static const uint8_t empty_rows[] = {18, 0x7f, 0xff, 0, 0, '\n'};     /* 32767 rows of no columns */
    static const uint8_t no_rows[] = {18, 0, 0, 0x7f, 0xff, '\n'};        /* columns but no rows: legal */
    static const uint8_t big_matrix[] = {18, 0, 2, 0, 3, 0, 0, 0, '\n'};  /* 6 items, 4 bytes left */
    static const uint8_t fitting[] = {17, 0, 3, 0, 0, '\n', '\n'};         /* 3 NONE, terminator, '\n' */
    urwire_sw_version v59 = {5, 9, 0, false}, v32 = {3, 2, 0, false};
    urwire_seq seq, items;
    urwire_value val, item;
    urwire_error e;
    size_t at = 0;
    CHECK(urwire__values_of(v32)->count == 2 && urwire__values_of(v59)->count == 8);
    CHECK(urwire__read_values(good, &at, sizeof good, &v59, '\n', "values", &seq, &e));
    CHECK(at == sizeof good && seq.count == 3);
    CHECK(urwire_next_value(&seq, &val) && val.kind == URWIRE_VALUE_INT && val.as.integer == 7);
    CHECK(urwire_next_value(&seq, &val) && val.kind == URWIRE_VALUE_LIST && val.rows == 2);
    items = val.items;
    CHECK(urwire_next_value(&items, &item) && item.kind == URWIRE_VALUE_BOOL && item.as.boolean == 1);
    CHECK(urwire_next_value(&items, &item) && strcmp(item.type_name, "CONST_STRING") == 0 && item.as.text.len == 2);
    CHECK(!urwire_next_value(&items, &item));
    CHECK(urwire_next_value(&seq, &val) && val.kind == URWIRE_VALUE_NONE && !urwire_next_value(&seq, &val));
    at = 0;
    CHECK(!urwire__read_values(deep, &at, sizeof deep, &v59, '\n', "values", &seq, &e));
    CHECK(text_is(&e, "values[0][0][0][0] at offset 9: nesting deeper than 3"));
    at = 0;
    CHECK(!urwire__read_values(old_list, &at, sizeof old_list, &v32, '\n', "values", &seq, &e));
    CHECK(text_is(&e, "values[0].type at offset 0: unknown value type 17"));
    at = 0;
    CHECK(!urwire__read_values(good, &at, 4, &v59, '\n', "values", &seq, &e));
    CHECK(text_is(&e, "values[0] at offset 1: needs 4 bytes, 3 left"));
    /* Counts are weighed against the bytes left, one byte a value at the least (NONE). */
    at = 0;
    CHECK(!urwire__read_values(long_list, &at, sizeof long_list, &v59, '\n', "values", &seq, &e));
    CHECK(e.status == URWIRE_E_TOO_MANY_ITEMS);
    CHECK(text_is(&e, "values[0] at offset 1: 4 items need more than the 3 bytes left"));
    at = 0;
    CHECK(!urwire__read_values(empty_rows, &at, sizeof empty_rows, &v59, '\n', "values", &seq, &e));
    CHECK(text_is(&e, "values[0] at offset 1: 32767 rows of 0 columns"));
    at = 0;
    CHECK(urwire__read_values(no_rows, &at, sizeof no_rows, &v59, '\n', "values", &seq, &e));
    CHECK(urwire_next_value(&seq, &val) && val.rows == 0 && val.cols == 32767 && val.items.count == 0);
    at = 0;
    CHECK(!urwire__read_values(big_matrix, &at, sizeof big_matrix, &v59, '\n', "values", &seq, &e));
    CHECK(text_is(&e, "values[0] at offset 1: 6 items need more than the 4 bytes left"));
    /* Exactly as many bytes as items is not refused by the count: the items then decide. */
    at = 0;
    CHECK(!urwire__read_values(fitting, &at, sizeof fitting, &v59, '\n', "values", &seq, &e));
    CHECK(text_is(&e, "values[0][2].type at offset 5: unknown value type 10"));
}

static void puts_and_lengths(void)
{
    uint8_t out[8];
    urwire_bytes abc = {(const uint8_t *)"abc", 3};
    urwire_error e;
    size_t pos = 0;
    CHECK(urwire__put_prefixed(out, sizeof out, &pos, 2, 32767, abc, "name", &e));
    CHECK(pos == 5 && out[0] == 0 && out[1] == 3 && memcmp(out + 2, "abc", 3) == 0);
    CHECK(!urwire__put_prefixed(out, sizeof out, &pos, 1, 2, abc, "name", &e));
    CHECK(text_is(&e, "name: 3 bytes do not fit the length prefix (max 2)"));
    CHECK(urwire__put_view(out, sizeof out, &pos, abc, &e) && pos == 8);
    CHECK(!urwire__put_view(out, sizeof out, &pos, abc, &e));
    CHECK(text_is(&e, " at offset 8: needs 3 bytes, 0 left in the output"));
}

/* The made-up protocol's state message: a counter (type 1, 4 bytes) and a type with no
 * layout (9); and one with a tally (type 1, 2 bytes: the layout up to 3.2). */
static const uint8_t state[] = {
    0, 0, 0, 24, 16,
    0, 0, 0, 9, 1, 0, 0, 1, 0,
    0, 0, 0, 10, 9, 'r', 'a', 'w', '!', '!',
};

static const uint8_t old_state[] = {
    0, 0, 0, 19, 16,
    0, 0, 0, 7, 1, 0, 3,
    0, 0, 0, 7, 1, 0, 4,
};

/* A counter (on the fast path of 5.9), a tally (by its length: 3.2, which has no fast path),
 * then a counter again. */
static const uint8_t mixed_state[] = {
    0, 0, 0, 30, 16,
    0, 0, 0, 9, 1, 0, 0, 1, 0,
    0, 0, 0, 7, 1, 0, 3,
    0, 0, 0, 9, 1, 0, 0, 0, 5,
};

static void fast_path(void)
{
    urwire_message m;
    urwire_robot_state rs;
    urwire_sw_version v59 = {5, 9, 0, false};
    /* Known 5.9: the tally is read by the general rule in its own version (a known version is
     * not overruled), and the loop goes back to the fast path for the second counter. */
    CHECK(urwire_decode_robot_state_message(mixed_state, sizeof mixed_state, v59, &m, &rs));
    CHECK(m.packages.count == 3 && !m.implied && rs.unknown == 0 && rs.present == URWIRE_BIT(1));
    CHECK(rs.layouts == (URWIRE_BIT(URWIRE_LAYOUT_COUNTER) | URWIRE_BIT(URWIRE_LAYOUT_TALLY)));
    CHECK(rs.counter.count == 5 && rs.counter.version.minor == 9 && rs.tally.count == 3);
    CHECK(rs.tally.version.major == 3 && rs.tally.version.minor == 2);
    /* Assumed: the tally implies 3.2, which leaves the fast path; the general rule reads the
     * second counter by its length, which implies 5.9 again. */
    CHECK(urwire_decode_robot_state_message(mixed_state, sizeof mixed_state, URWIRE_DEFAULT_VERSION, &m, &rs));
    CHECK(m.packages.count == 3 && m.implied && m.implied_version.minor == 9 && m.implied_version.assumed);
    CHECK(rs.counter.count == 5 && rs.tally.count == 3 && rs.tally.version.minor == 2);
    /* A body of the fast case's size that is cut short is framed out: the rest is raw. */
    CHECK(!urwire_decode_robot_state_message(mixed_state, sizeof mixed_state - 1, v59, &m, &rs));
    CHECK(m.failed && m.packages.count == 2 && m.packages.end == 21 && rs.counter.count == 256);
}

static void messages(void)
{
    urwire_message m;
    urwire_robot_state rs;
    urwire_package pkg;
    urwire_seq seq;
    urwire_error e;
    urwire_sw_version v32 = {3, 2, 0, false};
    uint8_t out[64], cut[sizeof state];
    CHECK(urwire_decode_robot_state_message(state, sizeof state, URWIRE_DEFAULT_VERSION, &m, &rs));
    CHECK(m.kind == URWIRE_KIND_STATE && m.packages.count == 2 && rs.unknown == 1 && !m.implied);
    CHECK(rs.present == URWIRE_BIT(1) && rs.layouts == URWIRE_BIT(URWIRE_LAYOUT_COUNTER) && rs.counter.count == 256);
    CHECK(urwire_decode_message(state, sizeof state, URWIRE_DEFAULT_VERSION, &m) && !urwire_message_has_error(&m));
    seq = m.packages;
    CHECK(urwire_next_package(&seq, &pkg) && pkg.known && !pkg.failed && pkg.as.counter.count == 256);
    CHECK(pkg.layout == URWIRE_LAYOUT_COUNTER && pkg.version.minor == 9);
    CHECK(urwire_next_package(&seq, &pkg) && !pkg.known && pkg.type == 9 && pkg.raw.len == 5);
    CHECK(!urwire_next_package(&seq, &pkg));
    CHECK(urwire_encode_message(&m, out, sizeof out, &e) == sizeof state && memcmp(out, state, sizeof state) == 0);
    CHECK(urwire_encode_message(&m, out, 10, &e) == 0 && e.status == URWIRE_E_NO_SPACE);
    /* A sub-package whose length runs past the message: framing stops, the rest is raw. */
    memcpy(cut, state, sizeof state);
    cut[17] = 11;
    CHECK(!urwire_decode_message(cut, sizeof cut, URWIRE_DEFAULT_VERSION, &m) && m.failed);
    CHECK(text_is(&m.error, "package at offset 14: length 11 exceeds the 10 bytes left") && m.raw.len == 10);
    CHECK(urwire_encode_message(&m, out, sizeof out, &e) == sizeof cut && memcmp(out, cut, sizeof cut) == 0);
    CHECK(urwire_decode_message(state, 4, URWIRE_DEFAULT_VERSION, &m) == false);
    CHECK(m.kind == URWIRE_KIND_UNKNOWN_MESSAGE && text_is(&m.error, "length at offset 0: needs 5 bytes, 4 left"));

    /* Under an assumed version, a tally's length shows 3.2 for the rest of the message. */
    CHECK(urwire_decode_robot_state_message(old_state, sizeof old_state, URWIRE_DEFAULT_VERSION, &m, &rs));
    CHECK(rs.layouts == URWIRE_BIT(URWIRE_LAYOUT_TALLY) && rs.tally.count == 4 && rs.tally.version.minor == 2);
    CHECK(m.implied && m.implied_version.major == 3 && m.implied_version.minor == 2 && m.implied_version.assumed);
    CHECK(urwire_decode_message(old_state, sizeof old_state, URWIRE_DEFAULT_VERSION, &m) && m.implied);
    seq = m.packages;
    CHECK(urwire_next_package(&seq, &pkg) && pkg.layout == URWIRE_LAYOUT_TALLY && pkg.version.minor == 2);
    CHECK(seq.version.minor == 2 && seq.version.assumed);  /* the next package starts from it */
    CHECK(urwire_encode_message(&m, out, sizeof out, &e) == sizeof old_state);
    CHECK(memcmp(out, old_state, sizeof old_state) == 0);
    /* A known version is not overruled: the tally is read in its own version all the same. */
    CHECK(urwire_decode_robot_state_message(old_state, sizeof old_state, v32, &m, &rs) && !m.implied);
    v32.major = 5;
    CHECK(urwire_decode_robot_state_message(old_state, sizeof old_state, v32, &m, &rs) && !m.implied);
    CHECK(rs.tally.version.minor == 2 && rs.tally.version.major == 3);
}

static void framer(void)
{
    static uint8_t buf[64];
    uint8_t stream[5 + 2 * sizeof state];
    urwire_framer f;
    urwire_frame fr;
    memcpy(stream, "\x01\x02", 2);  /* garbage, then two messages */
    memcpy(stream + 2, state, sizeof state);
    memcpy(stream + 2 + sizeof state, state, sizeof state);
    urwire_framer_init(&f, buf, sizeof buf, URWIRE_DEFAULT_VERSION);
    CHECK(urwire_framer_feed(&f, stream, 2 + 2 * sizeof state) == 2 + 2 * sizeof state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_FAULT && fr.offset == 0);
    CHECK(text_is(&fr.fault, "length 16908288 is above 1048576"));
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE && fr.offset == 2 && fr.length == sizeof state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE && fr.offset == 2 + sizeof state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_NEED_MORE);
    CHECK(urwire_framer_feed(&f, state, 7) == 7);
    urwire_framer_finish(&f);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_FAULT);
    CHECK(text_is(&fr.fault, "truncated message: length 24, 7 bytes left"));
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_END);

    /* A stream that ends inside a message: the fault, then the whole messages in its span. */
    memcpy(stream, "\x00\x00\x00\x3c\x10", 5);  /* length 60, 53 bytes in the stream */
    memcpy(stream + 5, state, sizeof state);
    memcpy(stream + 5 + sizeof state, state, sizeof state);
    urwire_framer_init(&f, buf, sizeof buf, URWIRE_DEFAULT_VERSION);
    CHECK(urwire_framer_feed(&f, stream, 5 + 2 * sizeof state) == 5 + 2 * sizeof state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_NEED_MORE);
    urwire_framer_finish(&f);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_FAULT && fr.offset == 0);
    CHECK(text_is(&fr.fault, "truncated message: length 60, 53 bytes left"));
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE && fr.offset == 5 && fr.length == sizeof state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE && fr.offset == 5 + sizeof state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_END);

    /* Restarted after a gap: no longer finished, the part of a message before the gap dropped,
     * the offsets the caller's. */
    urwire_framer_restart(&f, 1000);
    CHECK(urwire_framer_feed(&f, state, 7) == 7);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_NEED_MORE);
    urwire_framer_restart(&f, 2000);
    CHECK(urwire_framer_feed(&f, state, sizeof state) == sizeof state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE && fr.offset == 2000 && fr.length == sizeof state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_NEED_MORE);
}

/* The version a stream's layout sizes show carries on to its next messages, while it is only
 * assumed; a hint is never overruled. */
static void implied_version(void)
{
    static uint8_t buf[64];
    urwire_framer f;
    urwire_frame fr;
    urwire_sw_version hint = {5, 9, 0, false};
    urwire_framer_init(&f, buf, sizeof buf, URWIRE_DEFAULT_VERSION);
    CHECK(urwire_framer_feed(&f, old_state, sizeof old_state) == sizeof old_state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE && fr.version.major == 5 && fr.version.assumed);
    CHECK(urwire_framer_feed(&f, state, sizeof state) == sizeof state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE);
    CHECK(fr.version.major == 3 && fr.version.minor == 2 && fr.version.bugfix == 999 && fr.version.assumed);
    CHECK(!f.version_seen);
    /* The counter's length shows 3.3 and later again (its form's version: 5.9). */
    CHECK(urwire_framer_feed(&f, old_state, sizeof old_state) == sizeof old_state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE && fr.version.major == 5 && fr.version.minor == 9);
    urwire_framer_init(&f, buf, sizeof buf, hint);
    CHECK(urwire_framer_feed(&f, old_state, sizeof old_state) == sizeof old_state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE && fr.version.major == 5);
    CHECK(urwire_framer_feed(&f, state, sizeof state) == sizeof state);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE && fr.version.major == 5 && !fr.version.assumed);
}

/* Handed the robot state it framed, decoded in its frame's version (urwire_framer_learn), the
 * framer takes the version its sizes show from that decoding and walks nothing itself; any
 * other message leaves the walk to the framer. */
static void learning_from_the_decoded_message(void)
{
    static uint8_t buf[64];
    uint8_t stream[3 * sizeof old_state], copy[sizeof old_state];
    urwire_framer f;
    urwire_frame fr;
    urwire_message m;
    memcpy(stream, old_state, sizeof old_state);
    memcpy(stream + sizeof old_state, old_state, sizeof old_state);
    memcpy(stream + 2 * sizeof old_state, old_state, sizeof old_state);
    urwire_framer_init(&f, buf, sizeof buf, URWIRE_DEFAULT_VERSION);
    CHECK(urwire_framer_feed(&f, stream, sizeof stream) == sizeof stream);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE);
    CHECK(urwire_decode_message(fr.bytes, fr.length, fr.version, &m) && m.implied);
    urwire_framer_learn(&f, &m);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE);
    CHECK(fr.version.major == 3 && fr.version.minor == 2 && fr.version.bugfix == 999 && fr.version.assumed);
    /* What the framer learns is the decoding's word: told no version, it keeps its own. */
    urwire_framer_init(&f, buf, sizeof buf, URWIRE_DEFAULT_VERSION);
    CHECK(urwire_framer_feed(&f, stream, sizeof stream) == sizeof stream);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE);
    CHECK(urwire_decode_message(fr.bytes, fr.length, fr.version, &m) && m.implied);
    m.implied = false;
    urwire_framer_learn(&f, &m);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE && fr.version.major == 5 && fr.version.minor == 9);
    /* The frame decoded in another version, or the same bytes elsewhere, are not that frame:
     * the framer walks it. */
    CHECK(urwire_decode_message(fr.bytes, fr.length, (urwire_sw_version){5, 9, 0, false}, &m) && !m.implied);
    urwire_framer_learn(&f, &m);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE);
    CHECK(fr.version.major == 3 && fr.version.minor == 2 && fr.version.bugfix == 999 && fr.version.assumed);
    urwire_framer_init(&f, buf, sizeof buf, URWIRE_DEFAULT_VERSION);
    CHECK(urwire_framer_feed(&f, stream, sizeof stream) == sizeof stream);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE);
    memcpy(copy, fr.bytes, fr.length);
    CHECK(urwire_decode_message(copy, fr.length, fr.version, &m) && m.implied);
    m.implied = false;
    urwire_framer_learn(&f, &m);
    CHECK(urwire_framer_next(&f, &fr) == URWIRE_FRAME_MESSAGE);
    CHECK(fr.version.major == 3 && fr.version.minor == 2 && fr.version.bugfix == 999 && fr.version.assumed);
}

int main(void)
{
    loads_and_stores();
    versions();
    forms();
    error_texts();
    texts();
    values();
    puts_and_lengths();
    messages();
    framer();
    implied_version();
    fast_path();
    learning_from_the_decoded_message();
    if (failures)
        return 1;
    printf("all runtime checks passed\n");
    return 0;
}
