/* Test driver for tests/c: exercises the library where the CLI cannot.
 *
 *   driver chunks K FILE [CAP]  print the records like urwire-decode, feeding K bytes at a time
 *                            (K = 0: sizes from 1 to 97 in a fixed pseudo-random order), with a
 *                            framer buffer of CAP bytes (default URWIRE_FRAMER_MIN_BUFFER)
 *   driver roundtrip FILE [V]  encode(decode(m)) == m for every framed message and sub-package
 *                            (V: the version hint, e.g. 5.12);
 *                            prints "messages N packages P" or the first mismatch (exit 1)
 *   driver text              stdin bytes -> one JSON string (UTF-8 replaced as Python does)
 *   driver f32 | f64         stdin big-endian floats -> their canonical texts, one per line
 *   driver batch             stdin: inputs, each a big-endian uint32 length and a version hint
 *                            ("" for none), then a uint32 length and a stream; each answered
 *                            with the lines urwire-decode prints for it (the command's own
 *                            records.c, fed 64 KiB at a time as it reads) and "=CODE", its exit
 *                            status (2: the hint is not a version), flushed: one process for
 *                            many inputs
 *   driver batch chunks K [CAP]  the same inputs, each answered as `chunks K` prints it, then
 *                            "=CODE" (1: error records, 2: the hint is not a version)
 *   driver batch roundtrip   the same inputs, each answered as `roundtrip` prints it, then
 *                            "=CODE" (0: every part encodes back, 1: a mismatch)
 *   driver batch text        the same inputs, each stream answered as `text` prints it, "=0"
 */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "records.h"
#include "state_members.h"
#include "urwire.h"

static uint8_t framer_buffer[URWIRE_FRAMER_MIN_BUFFER];
static uint8_t encoded[URWIRE_MAX_MESSAGE_LENGTH + 64];

static uint8_t *slurp(FILE *in, size_t *len)
{
    size_t cap = 1 << 16, n = 0, got;
    uint8_t *buf = malloc(cap);
    while (buf && (got = fread(buf + n, 1, cap - n, in)) > 0) {
        n += got;
        if (n == cap)
            buf = realloc(buf, cap *= 2);
    }
    *len = n;
    return buf;
}

static uint8_t *read_file(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    uint8_t *buf;
    if (!f) {
        perror(path);
        exit(2);
    }
    buf = slurp(f, len);
    fclose(f);
    return buf;
}

typedef int (*frame_fn)(const urwire_frame *frame, void *ctx);

/* Frame data in chunks of k bytes (k = 0: varying sizes), calling fn on every frame. */
static size_t framer_cap = sizeof framer_buffer;
static urwire_sw_version hint = URWIRE_DEFAULT_VERSION_INIT;

static int frame_all(const uint8_t *data, size_t len, size_t k, frame_fn fn, void *ctx)
{
    urwire_framer fr;
    urwire_frame frame;
    size_t off = 0, step = 0, rc = 0;
    urwire_framer_init(&fr, framer_buffer, framer_cap, hint);
    for (;;) {
        size_t want = k ? k : 1 + (step++ * 37) % 97;
        if (off < len) {
            if (want > len - off)
                want = len - off;
            off += urwire_framer_feed(&fr, data + off, want);
        } else {
            urwire_framer_finish(&fr);
        }
        for (;;) {
            urwire_frame_kind kind = urwire_framer_next(&fr, &frame);
            if (kind == URWIRE_FRAME_END)
                return (int)rc;
            if (kind == URWIRE_FRAME_NEED_MORE)
                break;
            rc |= (size_t)fn(&frame, ctx);
        }
    }
}

static int print_frame(const urwire_frame *frame, void *ctx)
{
    json_writer *w = (json_writer *)ctx;
    urwire_visitor v = json_visitor(w);
    urwire_message m;
    int err;
    w->depth = 0;
    if (frame->kind == URWIRE_FRAME_FAULT) {
        urwire_visit_fault(&frame->fault, &v);
        err = 1;
    } else {
        urwire_decode_message(frame->bytes, frame->length, frame->version, &m);
        urwire_visit_message(&m, &v);
        err = urwire_message_has_error(&m);
    }
    putc('\n', w->out);
    return err;
}

typedef struct counts {
    size_t messages;
    size_t packages;
} counts;

static int mismatch(const char *what, const urwire_frame *frame, size_t n)
{
    printf("MISMATCH %s at stream offset %lu (length %lu, encoded %lu)\n", what, (unsigned long)frame->offset,
           (unsigned long)frame->length, (unsigned long)n);
    return 1;
}

/* Where each layout's member lies in a urwire_robot_state, and its size (state_members.h). */
#define MEMBER_AT(layout, member) [layout] = offsetof(urwire_robot_state, member),
#define MEMBER_SIZE(layout, member) [layout] = sizeof(((urwire_robot_state *)0)->member),
#define MEMBER_VERSION(layout, member) [layout] = offsetof(urwire_robot_state, member.version),
#define MEMBER_EXTRA(layout, member) [layout] = offsetof(urwire_robot_state, member.extra),
static const size_t member_at[URWIRE_LAYOUT_COUNT] = {STATE_MEMBERS(MEMBER_AT)};
static const size_t member_size[URWIRE_LAYOUT_COUNT] = {STATE_MEMBERS(MEMBER_SIZE)};
static const size_t member_version[URWIRE_LAYOUT_COUNT] = {STATE_MEMBERS(MEMBER_VERSION)};
static const size_t member_extra[URWIRE_LAYOUT_COUNT] = {STATE_MEMBERS(MEMBER_EXTRA)};

/* The same software version, part by part (a struct's padding may differ). */
static int same_version(const urwire_sw_version *a, const urwire_sw_version *b)
{
    return a->major == b->major && a->minor == b->minor && a->bugfix == b->bugfix && a->assumed == b->assumed;
}

/* The robot state that the one-pass decoder filled (its fast paths included) against the
 * iterator, which reads each sub-package by the general rule alone: the same bits and unknown
 * count; and the last sub-package of each type was read in the same form (the same version,
 * the same count of extra bytes) to the same values (encoded from its member of the state, it
 * gives the bytes it encodes to from the iterator's struct). */
static int state_matches_iterator(const urwire_message *m, const urwire_robot_state *state)
{
    static uint8_t mine[URWIRE_MAX_MESSAGE_LENGTH + 64];
    urwire_package pkg, last[32], from_state;
    uint32_t present = 0, malformed = 0, layouts = 0, seen = 0;
    size_t unknown = 0, n, t;
    urwire_error err;
    urwire_seq seq = m->packages;
    while (urwire_next_package(&seq, &pkg)) {
        if (!pkg.known) {
            unknown++;
            continue;
        }
        layouts |= (uint32_t)URWIRE_BIT(pkg.layout);
        if (pkg.failed)
            malformed |= (uint32_t)URWIRE_BIT(pkg.type);
        else
            present |= (uint32_t)URWIRE_BIT(pkg.type);
        last[pkg.type] = pkg;
        seen |= (uint32_t)URWIRE_BIT(pkg.type);
    }
    if (present != state->present || malformed != state->malformed || layouts != state->layouts ||
        unknown != state->unknown)
        return 0;
    for (t = 0; t < 32; t++) {
        size_t at, extra;
        if (!(seen & URWIRE_BIT(t)) || last[t].failed)
            continue;
        at = member_at[last[t].layout];
        extra = member_extra[last[t].layout] - at;  /* where extra lies within the member */
        if (!same_version((const urwire_sw_version *)((const char *)state + member_version[last[t].layout]),
                          &last[t].version) ||
            ((const urwire_bytes *)((const char *)state + at + extra))->len !=
                ((const urwire_bytes *)((const char *)&last[t].as + extra))->len)
            return 0;
        from_state = last[t];
        memcpy(&from_state.as, (const char *)state + at, member_size[last[t].layout]);
        n = urwire_encode_package(&last[t], encoded, sizeof encoded, &err);
        if (urwire_encode_package(&from_state, mine, sizeof mine, &err) != n || memcmp(mine, encoded, n) != 0)
            return 0;
    }
    return 1;
}

static int roundtrip_frame(const urwire_frame *frame, void *ctx)
{
    counts *c = (counts *)ctx;
    urwire_message m;
    urwire_package pkg;
    urwire_robot_state state, state2;
    urwire_message m2;
    urwire_seq seq;
    urwire_error err;
    size_t n;
    if (frame->kind != URWIRE_FRAME_MESSAGE)
        return 0;
    urwire_decode_message(frame->bytes, frame->length, frame->version, &m);
    n = urwire_encode_message(&m, encoded, sizeof encoded, &err);
    if (n != frame->length || memcmp(encoded, frame->bytes, n) != 0)
        return mismatch("message", frame, n);
    /* Too little room must fail cleanly, never write past cap. */
    if (n > 5 && urwire_encode_message(&m, encoded, n - 1, &err) != 0)
        return mismatch("encode into a short buffer succeeded", frame, n);
    c->messages++;
    if (m.kind == URWIRE_KIND_ROBOT_STATE) {
        seq = m.packages;
        while (urwire_next_package(&seq, &pkg)) {
            n = urwire_encode_package(&pkg, encoded, sizeof encoded, &err);
            if (n != pkg.raw.len + 5 || memcmp(encoded, frame->bytes + pkg.offset, n) != 0)
                return mismatch("package", frame, n);
            c->packages++;
        }
        /* The all-at-once decoder agrees with the iterator about errors. */
        if (urwire_decode_robot_state(&m, &state) == urwire_message_has_error(&m))
            return mismatch("urwire_decode_robot_state disagrees with urwire_message_has_error", frame, 0);
        /* And the one-pass decoder with the two calls. */
        if (urwire_decode_robot_state_message(frame->bytes, frame->length, frame->version, &m2, &state2) ==
                urwire_message_has_error(&m) ||
            state2.present != state.present || state2.malformed != state.malformed ||
            state2.unknown != state.unknown || m2.failed != m.failed || m2.packages.count != m.packages.count ||
            m2.packages.end != m.packages.end || m2.raw.len != m.raw.len ||
            ((state.present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_JOINT_DATA)) &&
             (memcmp(&state2.joint_data.joints[5].q_actual, &state.joint_data.joints[5].q_actual, sizeof(double)) ||
              state2.joint_data.joints[5].joint_mode != state.joint_data.joints[5].joint_mode)))
            return mismatch("urwire_decode_robot_state_message disagrees with the two calls", frame, 0);
        if (!state_matches_iterator(&m2, &state2))
            return mismatch("the robot state disagrees with the iterator", frame, 0);
    }
    return 0;
}

/* A big-endian uint32 length, then that many bytes (NUL-terminated); NULL at the end of input. */
static uint8_t *read_part(FILE *in, size_t *len)
{
    uint8_t head[4], *buf;
    if (fread(head, 1, 4, in) != 4)
        return NULL;
    *len = (size_t)head[0] << 24 | (size_t)head[1] << 16 | (size_t)head[2] << 8 | head[3];
    buf = malloc(*len + 1);
    if (!buf || fread(buf, 1, *len, in) != *len) {
        fprintf(stderr, "batch: input cut short\n");
        exit(2);
    }
    buf[*len] = 0;
    return buf;
}

/* urwire-decode's work on one stream, as its main() does it, minus the reading: the stream is
 * fed in the command's reads of 64 KiB. */
#define COMMAND_READ ((size_t)1 << 16)
static int decode_like_the_command(const char *hint_text, const uint8_t *data, size_t len)
{
    urwire_sw_version version = URWIRE_DEFAULT_VERSION;
    urwire_framer fr;
    urwire_visitor v;
    json_writer w;
    size_t taken = 0;
    bool errors = false;
    if (hint_text[0] && !urwire_parse_version(hint_text, &version))
        return 2;
    memset(&w, 0, sizeof w);
    w.out = stdout;
    v = json_visitor(&w);
    urwire_framer_init(&fr, framer_buffer, sizeof framer_buffer, version);
    while (taken < len) {
        size_t n = len - taken < COMMAND_READ ? len - taken : COMMAND_READ, off = 0;
        while (off < n) {
            off += urwire_framer_feed(&fr, data + taken + off, n - off);
            errors |= print_ready_records(&fr, &v, &w);
        }
        taken += n;
    }
    urwire_framer_finish(&fr);
    errors |= print_ready_records(&fr, &v, &w);
    return errors ? 1 : 0;
}

/* The version hint of one batch input for frame_all ("": the default); false if no version. */
static bool set_hint(const char *hint_text)
{
    hint = URWIRE_DEFAULT_VERSION;
    return !hint_text[0] || urwire_parse_version(hint_text, &hint);
}

/* `chunks K` on one batch input, K and CAP from the command line. */
static size_t batch_chunk;
static int chunks_answer(const char *hint_text, const uint8_t *data, size_t len)
{
    json_writer w;
    if (!set_hint(hint_text))
        return 2;
    memset(&w, 0, sizeof w);
    w.out = stdout;
    return frame_all(data, len, batch_chunk, print_frame, &w) ? 1 : 0;
}

/* `roundtrip` on one batch input. */
static int roundtrip_answer(const char *hint_text, const uint8_t *data, size_t len)
{
    counts c = {0, 0};
    int rc;
    if (!set_hint(hint_text))
        return 2;
    rc = frame_all(data, len, 0, roundtrip_frame, &c);
    printf("messages %lu packages %lu\n", (unsigned long)c.messages, (unsigned long)c.packages);
    return rc;
}

/* `text` on one batch input (its hint unused). */
static int text_answer(const char *hint_text, const uint8_t *data, size_t len)
{
    (void)hint_text;
    json_write_text(stdout, data, len);
    putchar('\n');
    return 0;
}

typedef int (*answer_fn)(const char *hint_text, const uint8_t *data, size_t len);

static int batch(answer_fn answer)
{
    uint8_t *hint_text, *data;
    size_t hint_len, len;
    while ((hint_text = read_part(stdin, &hint_len)) != NULL) {
        if ((data = read_part(stdin, &len)) == NULL)
            return 2;
        printf("=%d\n", answer((const char *)hint_text, data, len));
        fflush(stdout);
        free(hint_text);
        free(data);
    }
    return 0;
}

int main(int argc, char **argv)
{
    size_t len, i;
    uint8_t *data;
    json_writer w;
    char buf[64];
    if ((argc == 4 || argc == 5) && strcmp(argv[1], "chunks") == 0) {
        if (argc == 5 && (size_t)atol(argv[4]) < framer_cap)
            framer_cap = (size_t)atol(argv[4]);
        data = read_file(argv[3], &len);
        memset(&w, 0, sizeof w);
        w.out = stdout;
        i = (size_t)frame_all(data, len, (size_t)atol(argv[2]), print_frame, &w);
        free(data);
        return i ? 1 : 0;
    }
    if ((argc == 3 || argc == 4) && strcmp(argv[1], "roundtrip") == 0) {
        counts c = {0, 0};
        int rc;
        if (argc == 4 && !urwire_parse_version(argv[3], &hint))
            return 2;
        data = read_file(argv[2], &len);
        rc = frame_all(data, len, 0, roundtrip_frame, &c);
        printf("messages %lu packages %lu\n", (unsigned long)c.messages, (unsigned long)c.packages);
        free(data);
        return rc;
    }
    if (argc == 2 && strcmp(argv[1], "text") == 0) {
        data = slurp(stdin, &len);
        json_write_text(stdout, data, len);
        putchar('\n');
        free(data);
        return 0;
    }
    if (argc == 2 && (strcmp(argv[1], "f32") == 0 || strcmp(argv[1], "f64") == 0)) {
        bool wide = argv[1][1] == '6';
        size_t size = wide ? 8 : 4;
        data = slurp(stdin, &len);
        for (i = 0; i + size <= len; i += size) {
            uint64_t bits = 0;
            size_t k;
            for (k = 0; k < size; k++)
                bits = bits << 8 | data[i + k];
            if (wide) {
                double d;
                memcpy(&d, &bits, sizeof d);
                json_f64_text(d, buf, sizeof buf);
            } else {
                uint32_t b32 = (uint32_t)bits;
                float f;
                memcpy(&f, &b32, sizeof f);
                json_f32_text(f, buf, sizeof buf);
            }
            puts(buf);
        }
        free(data);
        return 0;
    }
    if (argc == 2 && strcmp(argv[1], "batch") == 0)
        return batch(decode_like_the_command);
    if ((argc == 4 || argc == 5) && strcmp(argv[1], "batch") == 0 && strcmp(argv[2], "chunks") == 0) {
        batch_chunk = (size_t)atol(argv[3]);
        if (argc == 5 && (size_t)atol(argv[4]) < framer_cap)
            framer_cap = (size_t)atol(argv[4]);
        return batch(chunks_answer);
    }
    if (argc == 3 && strcmp(argv[1], "batch") == 0 && strcmp(argv[2], "roundtrip") == 0)
        return batch(roundtrip_answer);
    if (argc == 3 && strcmp(argv[1], "batch") == 0 && strcmp(argv[2], "text") == 0)
        return batch(text_answer);
    fprintf(stderr, "usage: driver chunks K FILE [CAP] | roundtrip FILE [V] | text | f32 | f64 | batch"
                    " [chunks K [CAP] | roundtrip | text]\n");
    return 2;
}
