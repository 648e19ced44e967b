/* The dashboard server and the ROS driver's sockets in urwire-decode (cell_streams.h). */
#include "cell_streams.h"

#include <string.h>

#include "ur_dashboard.h"
#include "ur_reverse.h"
#include "ur_script_command.h"
#include "ur_script_sender.h"
#include "ur_trajectory.h"

#define HELD (1u << 16)

static unsigned char held[2 * HELD];
static char line[6 * HELD + 256];

/* A text-line interface: lines split in the held bytes, one JSON line per record. The two
 * interfaces of this kind have the same API under their own prefixes. */
#define LINES_PRINT_STREAM(P, UPPER)                                                                  \
    int P##_print_stream(FILE *in, FILE *out, unsigned major, unsigned minor, unsigned bugfix,   \
                         bool given)                                                               \
    {                                                                                              \
        P##_conversation c;                                                                        \
        P##_record rec;                                                                            \
        size_t len = 0, used, at;                                                                  \
        bool got, errors = false;                                                                  \
        P##_init(&c, given ? P##_version(major, minor, bugfix) : 0u);                              \
        for (;;) {                                                                                 \
            size_t n = fread(held + len, 1, HELD, in);                                             \
            len += n;                                                                              \
            at = 0;                                                                                \
            while ((used = P##_decode(&c, true, held + at, len - at, &rec, &got)) > 0 || got) {    \
                if (got) {                                                                         \
                    P##_json(&rec, line, sizeof line);                                             \
                    fprintf(out, "%s\n", line);                                                    \
                    errors |= rec.type == UPPER##_FAULT;                                           \
                }                                                                                  \
                at += used;                                                                        \
            }                                                                                      \
            memmove(held, held + at, len - at);                                                    \
            len -= at;                                                                             \
            if (n == 0) {                                                                          \
                if (ferror(in))                                                                    \
                    return 2;                                                                      \
                break;                                                                             \
            }                                                                                      \
        }                                                                                          \
        if (P##_finish(&c, true, len, &rec)) {                                                     \
            P##_json(&rec, line, sizeof line);                                                     \
            fprintf(out, "%s\n", line);                                                            \
            errors = true;                                                                         \
        }                                                                                          \
        return errors ? 1 : 0;                                                                     \
    }

LINES_PRINT_STREAM(ur_dashboard, UR_DASHBOARD)
LINES_PRINT_STREAM(ur_script_sender, UR_SCRIPT_SENDER)

/* An int32-record interface, through the three functions every one of them has. */
typedef struct records_api {
    size_t (*record_size)(bool from_robot, uint32_t release);
    size_t (*record_json)(bool from_robot, const uint8_t *buf, size_t n, uint32_t release, char *out, size_t cap);
    size_t (*tail_json)(bool from_robot, uint64_t offset, size_t left, uint32_t release, char *out, size_t cap);
    uint32_t default_release;
} records_api;

static int records_print_stream(const records_api *api, FILE *in, FILE *out, unsigned major, unsigned minor,
                                unsigned bugfix, bool given)
{
    uint32_t release = given ? (major * 1000u + minor) * 1000u + bugfix : api->default_release;
    size_t len = 0, size = api->record_size(true, release), at;
    uint64_t offset = 0;
    for (;;) {
        size_t n = fread(held + len, 1, HELD, in);
        len += n;
        at = 0;
        if (size == 0) {        /* nothing is specified from the robot: the bytes are only counted */
            offset += len;
            len = 0;
        }
        while (size > 0 && len - at >= size) {
            api->record_json(true, held + at, size, release, line, sizeof line);
            fprintf(out, "%s\n", line);
            at += size;
        }
        memmove(held, held + at, len - at);
        len -= at;
        offset += at;
        if (n == 0) {
            if (ferror(in))
                return 2;
            break;
        }
    }
    if (size == 0 && offset > 0) {
        api->tail_json(true, 0, (size_t)offset, release, line, sizeof line);
        fprintf(out, "%s\n", line);
        return 1;
    }
    if (len > 0) {
        api->tail_json(true, offset, len, release, line, sizeof line);
        fprintf(out, "%s\n", line);
        return 1;
    }
    return 0;
}

#define RECORDS_PRINT_STREAM(P, UPPER)                                                            \
    int P##_print_stream(FILE *in, FILE *out, unsigned major, unsigned minor, unsigned bugfix,   \
                         bool given)                                                               \
    {                                                                                              \
        static const records_api api = {P##_record_size, P##_record_json, P##_tail_json,          \
                                         UPPER##_DEFAULT_RELEASE};                                 \
        return records_print_stream(&api, in, out, major, minor, bugfix, given);                   \
    }

RECORDS_PRINT_STREAM(ur_reverse, UR_REVERSE)
RECORDS_PRINT_STREAM(ur_trajectory, UR_TRAJECTORY)
RECORDS_PRINT_STREAM(ur_script_command, UR_SCRIPT_COMMAND)
