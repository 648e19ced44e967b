/* The dashboard server, interpreter mode, the gripper's socket and the ROS driver's sockets in
 * urwire-decode (cell_streams.h). */
#include "cell_streams.h"

#include <string.h>

#include "robotiq_gripper.h"
#include "ur_dashboard.h"
#include "ur_interpreter.h"
#include "ur_reverse.h"
#include "ur_script_command.h"
#include "ur_script_sender.h"
#include "ur_trajectory.h"

#define HELD (1u << 16)

static unsigned char held[2 * HELD];
static char line[6 * HELD + 256];

/* The direction's envelope: the client's stream is read first, then the robot's. */
static const envelope *envelope_of(const cell_inputs *in, bool from_robot)
{
    return from_robot ? in->from_robot : in->to_robot;
}

/* A text-line interface: lines split in the held bytes, one JSON line per record. The two
 * interfaces of this kind have the same API under their own prefixes. P##_read_stream reads one
 * direction to its end and leaves in *tail the bytes of an unended line, which P##_finish reports
 * once both streams are read (the client's first, as the Python decoder closes them), each in its
 * own direction's envelope. */
#define LINES_PRINT_STREAMS(P, UPPER)                                                                 \
    static int P##_read_stream(P##_conversation *c, const cell_inputs *in, bool from_robot, FILE *out, \
                               size_t *tail)                                                       \
    {                                                                                              \
        P##_record rec;                                                                            \
        FILE *stream = from_robot ? in->robot : in->client;                                        \
        size_t len = 0, used, at;                                                                  \
        bool got, errors = false;                                                                  \
        for (;;) {                                                                                 \
            size_t n = fread(held + len, 1, HELD, stream);                                         \
            len += n;                                                                              \
            at = 0;                                                                                \
            while ((used = P##_decode(c, from_robot, held + at, len - at, &rec, &got)) > 0 || got) { \
                if (got) {                                                                         \
                    P##_json(&rec, line, sizeof line);                                             \
                    envelope_line(out, envelope_of(in, from_robot), line);                         \
                    errors |= rec.type == UPPER##_FAULT || rec.not_kept;                           \
                }                                                                                  \
                at += used;                                                                        \
            }                                                                                      \
            memmove(held, held + at, len - at);                                                    \
            len -= at;                                                                             \
            if (n == 0) {                                                                          \
                if (ferror(stream))                                                                \
                    return 2;                                                                      \
                break;                                                                             \
            }                                                                                      \
        }                                                                                          \
        *tail = len;                                                                               \
        return errors ? 1 : 0;                                                                     \
    }                                                                                              \
                                                                                                   \
    int P##_print_streams(const cell_inputs *in, FILE *out, unsigned major, unsigned minor,      \
                          unsigned bugfix, bool given)                                             \
    {                                                                                              \
        P##_conversation c;                                                                        \
        P##_record rec;                                                                            \
        size_t tail[2] = {0, 0};                                                                   \
        int status = 0, k;                                                                         \
        static int16_t queue[UPPER##_PENDING_RAW]; /* the client's file is read first */           \
        P##_init(&c, given ? P##_version(major, minor, bugfix) : 0u);                              \
        P##_keep_pending(&c, queue, UPPER##_PENDING_RAW);                                          \
        for (k = in->client ? 0 : 1; k < 2; k++) {                                                 \
            int read = P##_read_stream(&c, in, k == 1, out, &tail[k]);                             \
            if (read == 2)                                                                         \
                return 2;                                                                          \
            status |= read;                                                                        \
        }                                                                                          \
        for (k = in->client ? 0 : 1; k < 2; k++) {                                                 \
            if (P##_finish(&c, k == 1, tail[k], &rec)) {                                           \
                P##_json(&rec, line, sizeof line);                                                 \
                envelope_line(out, envelope_of(in, k == 1), line);                                 \
                status = 1;                                                                        \
            }                                                                                      \
        }                                                                                          \
        return status;                                                                             \
    }

LINES_PRINT_STREAMS(ur_dashboard, UR_DASHBOARD)
LINES_PRINT_STREAMS(ur_script_sender, UR_SCRIPT_SENDER)
LINES_PRINT_STREAMS(ur_interpreter, UR_INTERPRETER)
LINES_PRINT_STREAMS(robotiq_gripper, ROBOTIQ_GRIPPER)

/* An int32-record interface, through the three functions every one of them has. */
typedef struct records_api {
    size_t (*record_size)(bool from_robot, uint32_t release);
    size_t (*record_json)(bool from_robot, const uint8_t *buf, size_t n, uint32_t release, char *out, size_t cap);
    size_t (*tail_json)(bool from_robot, uint64_t offset, size_t left, uint32_t release, char *out, size_t cap);
    uint32_t default_release;
} records_api;

/* What one direction's stream leaves at its end: bytes short of a record, or, where nothing is
 * specified that way, every byte (counted, not decoded). */
typedef struct records_tail {
    uint64_t offset;
    size_t left;
} records_tail;

static int records_read_stream(const records_api *api, const cell_inputs *in, bool from_robot, uint32_t release,
                               FILE *out, records_tail *tail)
{
    FILE *stream = from_robot ? in->robot : in->client;
    size_t len = 0, size = api->record_size(from_robot, release), at;
    uint64_t offset = 0;
    for (;;) {
        size_t n = fread(held + len, 1, HELD, stream);
        len += n;
        at = 0;
        if (size == 0) {        /* nothing is specified this way: the bytes are only counted */
            offset += len;
            len = 0;
        }
        while (size > 0 && len - at >= size) {
            api->record_json(from_robot, held + at, size, release, line, sizeof line);
            envelope_line(out, envelope_of(in, from_robot), line);
            at += size;
        }
        memmove(held, held + at, len - at);
        len -= at;
        offset += at;
        if (n == 0) {
            if (ferror(stream))
                return 2;
            break;
        }
    }
    tail->offset = size == 0 ? 0 : offset;
    tail->left = size == 0 ? (size_t)offset : len;
    return 0;
}

static int records_print_streams(const records_api *api, const cell_inputs *in, FILE *out, unsigned major,
                                 unsigned minor, unsigned bugfix, bool given)
{
    uint32_t release = given ? (major * 1000u + minor) * 1000u + bugfix : api->default_release;
    records_tail tail[2] = {{0, 0}, {0, 0}};
    int status = 0, k;
    for (k = in->client ? 0 : 1; k < 2; k++)
        if (records_read_stream(api, in, k == 1, release, out, &tail[k]) == 2)
            return 2;
    for (k = in->client ? 0 : 1; k < 2; k++) {
        if (tail[k].left > 0) {
            api->tail_json(k == 1, tail[k].offset, tail[k].left, release, line, sizeof line);
            envelope_line(out, envelope_of(in, k == 1), line);
            status = 1;
        }
    }
    return status;
}

#define RECORDS_PRINT_STREAMS(P, UPPER)                                                           \
    int P##_print_streams(const cell_inputs *in, FILE *out, unsigned major, unsigned minor,      \
                          unsigned bugfix, bool given)                                             \
    {                                                                                              \
        static const records_api api = {P##_record_size, P##_record_json, P##_tail_json,          \
                                         UPPER##_DEFAULT_RELEASE};                                 \
        return records_print_streams(&api, in, out, major, minor, bugfix, given);                  \
    }

RECORDS_PRINT_STREAMS(ur_reverse, UR_REVERSE)
RECORDS_PRINT_STREAMS(ur_trajectory, UR_TRAJECTORY)
RECORDS_PRINT_STREAMS(ur_script_command, UR_SCRIPT_COMMAND)
