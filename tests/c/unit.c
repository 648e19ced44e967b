/* Unit checks of the C API that the stream tests do not reach: messages built by hand and
 * encoded (lengths computed), encode-side errors and their texts, names, version parsing.
 * Prints one line per failed check; exit 1 if any failed. */
#include <stdio.h>
#include <string.h>

#include "urwire.h"

static int failures;

#define CHECK(cond)                                                          \
    do {                                                                     \
        if (!(cond)) {                                                       \
            printf("FAILED %s:%d: %s\n", __FILE__, __LINE__, #cond);         \
            failures++;                                                      \
        }                                                                    \
    } while (0)

static urwire_bytes view(const char *s)
{
    urwire_bytes b;
    b.ptr = (const uint8_t *)s;
    b.len = strlen(s);
    return b;
}

static int text_is(const urwire_error *e, const char *want)
{
    char buf[URWIRE_PATH_MAX + 128];
    urwire_error_text(e, buf, sizeof buf);
    if (strcmp(buf, want) != 0)
        printf("  text: \"%s\"\n  want: \"%s\"\n", buf, want);
    return strcmp(buf, want) == 0;
}

static void key_message_built_by_hand(void)
{
    static char long_title[300];
    uint8_t out[512];
    urwire_message m, back;
    urwire_error err;
    size_t n;
    memset(&m, 0, sizeof m);
    m.kind = URWIRE_KIND_KEY;
    m.message_type = URWIRE_MESSAGE_TYPE_ROBOT_MESSAGE;
    m.version = URWIRE_DEFAULT_VERSION;
    m.header.robot_message.timestamp = 42;
    m.header.robot_message.source = URWIRE_MESSAGE_SOURCE_ROBOTINTERFACE;
    m.header.robot_message.robot_message_type = URWIRE_ROBOT_MESSAGE_TYPE_KEY;
    m.as.key.robot_message_code = 7;
    m.as.key.title = view("PROGRAM_XXX_STARTED");
    m.as.key.text = view("demo");
    n = urwire_encode_message(&m, out, sizeof out, &err);
    CHECK(n == 5 + 8 + 1 + 1 + 4 + 4 + 1 + 19 + 4);
    CHECK(out[0] == 0 && out[3] == n && out[4] == 20);   /* the length is computed */
    CHECK(urwire_decode_message(out, n, URWIRE_DEFAULT_VERSION, &back));
    CHECK(back.kind == URWIRE_KIND_KEY && back.header.robot_message.timestamp == 42);
    CHECK(back.header.robot_message.source == -2 && back.as.key.robot_message_code == 7);
    CHECK(back.as.key.title.len == 19 && memcmp(back.as.key.title.ptr, "PROGRAM_XXX_STARTED", 19) == 0);
    CHECK(back.as.key.text.len == 4 && back.as.key.extra.len == 0);

    /* One byte short of room: fails, names the field, writes nothing past cap. */
    memset(out, 0xAA, sizeof out);
    CHECK(urwire_encode_message(&m, out, n - 1, &err) == 0);
    CHECK(err.status == URWIRE_E_NO_SPACE);
    CHECK(out[n - 1] == 0xAA);

    /* A title longer than its uint8 length prefix. */
    memset(long_title, 'x', sizeof long_title - 1);
    m.as.key.title = view(long_title);
    CHECK(urwire_encode_message(&m, out, sizeof out, &err) == 0);
    CHECK(err.status == URWIRE_E_TOO_LONG);
    CHECK(text_is(&err, "title: 299 bytes do not fit the length prefix (max 255)"));
}

static void program_threads_built_by_hand(void)
{
    uint8_t threads[256], out[512];
    urwire_program_thread t;
    urwire_message m, back;
    urwire_seq it;
    urwire_error err;
    size_t pos = 0, n, count = 0;
    t.label_id = 3;
    t.label_name = view("MoveJ");
    t.thread_name = view("main");
    CHECK(urwire_append_program_thread(&t, threads, sizeof threads, &pos, &err));
    t.label_id = 9;
    t.thread_name = view("thread_2");
    CHECK(urwire_append_program_thread(&t, threads, sizeof threads, &pos, &err));
    memset(&m, 0, sizeof m);
    m.kind = URWIRE_KIND_PROGRAM_THREADS;
    m.message_type = URWIRE_MESSAGE_TYPE_ROBOT_MESSAGE;
    m.version = URWIRE_DEFAULT_VERSION;
    m.header.robot_message.robot_message_type = URWIRE_ROBOT_MESSAGE_TYPE_PROGRAM_LABEL_THREADS;
    m.as.program_threads.threads.msg = threads;
    m.as.program_threads.threads.pos = 0;
    m.as.program_threads.threads.end = pos;
    n = urwire_encode_message(&m, out, sizeof out, &err);
    CHECK(n == 15 + pos);
    CHECK(urwire_decode_message(out, n, URWIRE_DEFAULT_VERSION, &back));
    CHECK(back.kind == URWIRE_KIND_PROGRAM_THREADS && back.as.program_threads.threads.count == 2);
    it = back.as.program_threads.threads;
    while (urwire_next_program_thread(&it, &t))
        count++;
    CHECK(count == 2 && t.label_id == 9 && t.thread_name.len == 8);
}

static void names_and_versions(void)
{
    urwire_sw_version v = {0, 0}, v50 = {5, 0}, v59 = {5, 9}, v32 = {3, 2};
    CHECK(strcmp(urwire_robot_mode_name(-1), "NO_CONTROLLER") == 0);
    CHECK(urwire_robot_mode_name(99) == NULL);
    CHECK(strcmp(urwire_report_level_name(133), "DEVL_CRITICAL_FAULT") == 0);
    CHECK(strcmp(urwire_message_source_name(-5), "GUI") == 0);
    CHECK(strcmp(urwire_value_type_name(v50, 12), "BOOL") == 0);
    CHECK(strcmp(urwire_value_type_name(v59, 12), "POSE") == 0);
    CHECK(strcmp(urwire_value_type_name(v32, 3), "STRING") == 0);
    CHECK(urwire_value_type_name(v59, 5) == NULL);
    CHECK(strcmp(urwire_status_name(URWIRE_E_TOO_DEEP), "URWIRE_E_TOO_DEEP") == 0);
    CHECK(urwire_parse_version("5.10", &v) && v.major == 5 && v.minor == 10);
    CHECK(urwire_parse_version(" 3.15.2 ", &v) && v.major == 3 && v.minor == 15);
    CHECK(!urwire_parse_version("5", &v) && !urwire_parse_version("5.x", &v) && !urwire_parse_version("", &v));
    CHECK(!urwire_parse_version("5..9", &v) && !urwire_parse_version("-5.9", &v));
    CHECK(v.major == 3 && v.minor == 15);  /* untouched by the failures */
    CHECK(URWIRE_DEFAULT_VERSION.major == 5 && URWIRE_DEFAULT_VERSION.minor == 9);
}

static void error_texts_cut_to_fit(void)
{
    urwire_error e;
    char small[10];
    memset(&e, 0, sizeof e);
    e.status = URWIRE_E_TRUNCATED_MESSAGE;
    e.value = 1000;
    e.left = 12;
    CHECK(text_is(&e, "truncated message: length 1000, 12 bytes left"));
    CHECK(urwire_error_text(&e, small, sizeof small) == strlen("truncated message: length 1000, 12 bytes left"));
    CHECK(strcmp(small, "truncated") == 0);
}

int main(void)
{
    key_message_built_by_hand();
    program_threads_built_by_hand();
    names_and_versions();
    error_texts_cut_to_fit();
    if (failures == 0)
        printf("all unit checks passed\n");
    return failures ? 1 : 0;
}
