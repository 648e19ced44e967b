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
    urwire_sw_version v = {0, 0, 0, false}, v50 = {5, 0, 0, false}, v59 = {5, 9, 0, false}, v32 = {3, 2, 0, false};
    urwire_sw_version v18 = {1, 8, 0, false}, v5251 = {5, 25, 1, false};
    CHECK(strcmp(urwire_robot_mode_name(v59, -1), "NO_CONTROLLER") == 0);
    CHECK(urwire_robot_mode_name(v59, 99) == NULL);
    /* A versioned enum names a code by the table of the version: robot mode 7 is RUNNING from
     * 3.0, NO_POWER on CB2, whose RUNNING is 0. The newest table keeps the plain names. */
    CHECK(strcmp(urwire_robot_mode_name(v59, URWIRE_ROBOT_MODE_RUNNING), "RUNNING") == 0);
    CHECK(strcmp(urwire_robot_mode_name(v18, 7), "NO_POWER") == 0);
    CHECK(strcmp(urwire_robot_mode_name(v18, URWIRE_ROBOT_MODE_UP_TO_1_8_RUNNING), "RUNNING") == 0);
    CHECK(URWIRE_ROBOT_MODE_UP_TO_1_8_RUNNING == 0 && URWIRE_ROBOT_MODE_RUNNING == 7);
    CHECK(strcmp(urwire_robot_mode_name(URWIRE_DEFAULT_VERSION, 7), "RUNNING") == 0);
    /* Package type 5 means laser pointer up to 1.7, kinematics info from 1.8. */
    CHECK(strcmp(urwire_package_type_name(v18, 5), "KINEMATICS_INFO") == 0);
    v.major = 1, v.minor = 7, v.bugfix = 3;
    CHECK(strcmp(urwire_package_type_name(v, URWIRE_PACKAGE_TYPE_UP_TO_1_7_LASER_POINTER), "LASER_POINTER") == 0);
    CHECK(strcmp(urwire_report_level_name(133), "DEVL_CRITICAL_FAULT") == 0);
    CHECK(strcmp(urwire_message_source_name(v59, -5), "GUI") == 0);
    CHECK(strcmp(urwire_value_type_name(v50, 12), "BOOL") == 0);
    CHECK(strcmp(urwire_value_type_name(v59, 12), "POSE") == 0);
    CHECK(strcmp(urwire_value_type_name(v32, 3), "STRING") == 0);
    CHECK(urwire_value_type_name(v59, 5) == NULL);
    /* An upper bound written 5.8 is any 5.8.x: 5.8.3 still reads the 3.3-5.8 value types. */
    v.major = 5, v.minor = 8, v.bugfix = 3;
    CHECK(strcmp(urwire_value_type_name(v, 12), "BOOL") == 0);
    CHECK(strcmp(urwire_value_type_name(v5251, 12), "POSE") == 0);
    CHECK(strcmp(urwire_status_name(URWIRE_E_TOO_DEEP), "URWIRE_E_TOO_DEEP") == 0);
}

static void version_parsing(void)
{
    urwire_sw_version v = {0, 0, 0, true};
    CHECK(urwire_parse_version("5.10", &v) && v.major == 5 && v.minor == 10 && v.bugfix == 0 && !v.assumed);
    CHECK(urwire_parse_version(" 3.15.2 ", &v) && v.major == 3 && v.minor == 15 && v.bugfix == 2);
    CHECK(urwire_parse_version("5.25.1", &v) && v.major == 5 && v.minor == 25 && v.bugfix == 1);
    CHECK(!urwire_parse_version("5", &v) && !urwire_parse_version("5.x", &v) && !urwire_parse_version("", &v));
    CHECK(!urwire_parse_version("5..9", &v) && !urwire_parse_version("-5.9", &v));
    CHECK(!urwire_parse_version("5.25.1.4", &v) && !urwire_parse_version("5.25.", &v));
    CHECK(v.major == 5 && v.minor == 25 && v.bugfix == 1);  /* untouched by the failures */
    CHECK(URWIRE_DEFAULT_VERSION.major == 5 && URWIRE_DEFAULT_VERSION.minor == 9);
    CHECK(URWIRE_DEFAULT_VERSION.bugfix == 0 && URWIRE_DEFAULT_VERSION.assumed);
}

/* Configuration data: 440 bytes of body up to 5.25.0, 444 from 5.25.1 (two int16 more). */
static size_t configuration_data_state(uint8_t *out, size_t body)
{
    size_t n = 5 + 5 + body;
    memset(out, 0, n);
    out[3] = (uint8_t)n;
    out[2] = (uint8_t)(n >> 8);
    out[4] = URWIRE_MESSAGE_TYPE_ROBOT_STATE;
    out[8] = (uint8_t)(5 + body);
    out[7] = (uint8_t)((5 + body) >> 8);
    out[9] = URWIRE_PACKAGE_TYPE_CONFIGURATION_DATA;
    out[5 + 5 + 440] = 0x12;  /* reserved_1, when there */
    out[5 + 5 + 441] = 0x34;
    return n;
}

static void layout_choice_by_version_and_length(void)
{
    uint8_t bytes[512];
    urwire_sw_version v5251 = {5, 25, 1, false}, v511 = {5, 11, 0, false};
    urwire_message m;
    urwire_robot_state state;
    urwire_package pkg;
    urwire_seq seq;
    size_t n;
    /* The version's form fits: read in it, with the version. */
    n = configuration_data_state(bytes, 444);
    CHECK(urwire_decode_robot_state_message(bytes, n, v5251, &m, &state));
    CHECK(state.configuration_data.reserved_1 == 0x1234 && state.configuration_data.extra.len == 0);
    CHECK(state.configuration_data.version.minor == 25 && state.configuration_data.version.bugfix == 1);
    CHECK(!m.implied);
    /* A known version whose form does not fit: the one form of that exact size is read, in
     * its own version, and the version of the rest of the stream stays as it was. */
    CHECK(urwire_decode_robot_state_message(bytes, n, v511, &m, &state));
    CHECK(state.configuration_data.reserved_1 == 0x1234 && state.configuration_data.extra.len == 0);
    CHECK(state.configuration_data.version.minor == 25 && state.configuration_data.version.bugfix == 1);
    CHECK(!m.implied && m.version.minor == 11);
    CHECK(state.layouts == URWIRE_BIT(URWIRE_LAYOUT_CONFIGURATION_DATA));
    /* An assumed version: the length shows the version, for this message and the stream. */
    CHECK(urwire_decode_robot_state_message(bytes, n, URWIRE_DEFAULT_VERSION, &m, &state));
    CHECK(m.implied && m.implied_version.minor == 25 && m.implied_version.bugfix == 1 && m.implied_version.assumed);
    CHECK(urwire_decode_message(bytes, n, URWIRE_DEFAULT_VERSION, &m) && m.implied);
    seq = m.packages;
    CHECK(urwire_next_package(&seq, &pkg) && pkg.known && pkg.layout == URWIRE_LAYOUT_CONFIGURATION_DATA);
    CHECK(pkg.version.minor == 25 && pkg.version.bugfix == 1 && pkg.as.configuration_data.reserved_1 == 0x1234);
    /* Neither fits (a size no form has): the version's form, its extra bytes reported. */
    n = configuration_data_state(bytes, 446);
    CHECK(urwire_decode_robot_state_message(bytes, n, v511, &m, &state));
    CHECK(state.configuration_data.version.minor == 11 && state.configuration_data.extra.len == 6);
    CHECK(state.configuration_data.reserved_1 == 0);  /* not in the 5.11 form */
}

/* Masterboard data: digital_input_bits is an int16 on CB2 and an int32 from 3.0, one member. */
static void a_repeated_name_is_one_member(void)
{
    uint8_t bytes[128];
    urwire_sw_version v18 = {1, 8, 0, false}, v32 = {3, 2, 0, false};
    urwire_message m;
    urwire_robot_state state;
    size_t n = 5 + 5 + 59;  /* 1.6-1.8 form, no euromap */
    memset(bytes, 0, sizeof bytes);
    bytes[3] = (uint8_t)n;
    bytes[4] = URWIRE_MESSAGE_TYPE_ROBOT_STATE;
    bytes[8] = 5 + 59;
    bytes[9] = URWIRE_PACKAGE_TYPE_MASTERBOARD_DATA;
    bytes[10] = 0xff, bytes[11] = 0xfe;  /* digital_input_bits -2 */
    bytes[12] = 0x00, bytes[13] = 0x05;  /* digital_output_bits 5 */
    CHECK(urwire_decode_robot_state_message(bytes, n, v18, &m, &state));
    CHECK(state.masterboard_data.digital_input_bits == -2 && state.masterboard_data.digital_output_bits == 5);
    CHECK(state.masterboard_data.safety_mode == 0 && state.masterboard_data.extra.len == 0);
    /* Decoded in the 3.2 form: the bytes are an int32 now. */
    n = 5 + 5 + 69;
    bytes[3] = (uint8_t)n;
    bytes[8] = 5 + 69;
    CHECK(urwire_decode_robot_state_message(bytes, n, v32, &m, &state));
    CHECK(state.masterboard_data.digital_input_bits == (int32_t)0xfffe0005);
}

static void a_version_message_sets_the_framer_version(void)
{
    /* 3.2: project name, 3, 2, svn revision, build date; then 5.25.1 in the 3.3 form. */
    static const uint8_t old[] = {0, 0, 0, 30, 20, 0, 0, 0, 0, 0, 0, 0, 0, 0xfe, 3, 1, 'U', 3, 2,
                                  0, 0, 0x4e, 0xcf, 'd', 'a', 't', 'e', '!', '!', '!'};
    static const uint8_t now[] = {0, 0, 0, 31, 20, 0, 0, 0, 0, 0, 0, 0, 0, 0xfe, 3, 1, 'U', 5, 25,
                                  0, 0, 0, 1, 0, 0, 0, 9, 'd', 'a', 't', 'e'};
    static uint8_t buf[256];
    urwire_framer fr;
    urwire_frame frame;
    urwire_message m;
    urwire_framer_init(&fr, buf, sizeof buf, URWIRE_DEFAULT_VERSION);
    CHECK(urwire_framer_feed(&fr, old, sizeof old) == sizeof old);
    CHECK(urwire_framer_next(&fr, &frame) == URWIRE_FRAME_MESSAGE && frame.version.assumed);
    CHECK(urwire_decode_message(frame.bytes, frame.length, frame.version, &m) && m.kind == URWIRE_KIND_VERSION);
    CHECK(m.version.major == 3 && m.version.minor == 2 && m.as.version.svn_revision == 0x4ecf);
    CHECK(m.as.version.build_date.len == 7 && m.as.version.bugfix_version == 0);
    CHECK(fr.version.major == 3 && fr.version.minor == 2 && fr.version.bugfix == 0 && !fr.version.assumed);
    CHECK(urwire_framer_feed(&fr, now, sizeof now) == sizeof now);
    CHECK(urwire_framer_next(&fr, &frame) == URWIRE_FRAME_MESSAGE);
    CHECK(urwire_decode_message(frame.bytes, frame.length, frame.version, &m) && m.as.version.bugfix_version == 1);
    CHECK(m.as.version.build_number == 9 && m.as.version.build_date.len == 4);
    CHECK(fr.version.major == 5 && fr.version.minor == 25 && fr.version.bugfix == 1 && fr.version_seen);
}
/* A bugfix below 0 or above URWIRE_BUGFIX_ANY cannot compare with the spec's bounds: the framer
 * goes on with major.minor.0 and flags it; the message keeps the number; a later Version
 * message in range clears the flag. */
static void a_version_bugfix_out_of_range_is_set_aside(void)
{
    static const int32_t bugfixes[] = {-1, INT32_MIN, URWIRE_BUGFIX_ANY + 1, INT32_MAX, URWIRE_BUGFIX_ANY};
    static uint8_t buf[256];
    uint8_t bytes[] = {0, 0, 0, 31, 20, 0, 0, 0, 0, 0, 0, 0, 0, 0xfe, 3, 1, 'U', 5, 0,
                       0, 0, 0, 0, 0, 0, 0, 9, 'd', 'a', 't', 'e'};
    urwire_framer fr;
    urwire_frame frame;
    urwire_message m;
    size_t k;
    urwire_framer_init(&fr, buf, sizeof buf, URWIRE_DEFAULT_VERSION);
    CHECK(!fr.version_out_of_range);
    for (k = 0; k < sizeof bugfixes / sizeof bugfixes[0]; k++) {
        uint32_t u = (uint32_t)bugfixes[k];
        bool in_range = bugfixes[k] == URWIRE_BUGFIX_ANY;
        bytes[19] = (uint8_t)(u >> 24);
        bytes[20] = (uint8_t)(u >> 16);
        bytes[21] = (uint8_t)(u >> 8);
        bytes[22] = (uint8_t)u;
        CHECK(urwire_framer_feed(&fr, bytes, sizeof bytes) == sizeof bytes);
        CHECK(urwire_framer_next(&fr, &frame) == URWIRE_FRAME_MESSAGE);
        CHECK(urwire_decode_message(frame.bytes, frame.length, frame.version, &m));
        CHECK(m.kind == URWIRE_KIND_VERSION && m.as.version.bugfix_version == bugfixes[k]);
        CHECK(fr.version.major == 5 && fr.version.minor == 0 && !fr.version.assumed && fr.version_seen);
        CHECK(fr.version.bugfix == (in_range ? URWIRE_BUGFIX_ANY : 0));
        CHECK(fr.version_out_of_range == !in_range);
    }
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
    version_parsing();
    layout_choice_by_version_and_length();
    a_repeated_name_is_one_member();
    a_version_message_sets_the_framer_version();
    a_version_bugfix_out_of_range_is_set_aside();
    error_texts_cut_to_fit();
    if (failures == 0)
        printf("all unit checks passed\n");
    return failures ? 1 : 0;
}
