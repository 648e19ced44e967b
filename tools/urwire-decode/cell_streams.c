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

static char line[6 * CELL_HELD + 256];     /* one record's JSON, written out before the next */

/* The next bytes of `data` the held bytes take (all of them, or what fits); how many. */
static size_t hold(cell_held *h, const uint8_t *data, size_t n)
{
    size_t room = sizeof h->bytes - h->length, take = n < CELL_HELD ? n : CELL_HELD;
    take = take < room ? take : room;
    memcpy(h->bytes + h->length, data, take);
    h->length += take;
    return take;
}

/* The bytes before `at` read: the rest moves to the front. */
static void drop(cell_held *h, size_t at)
{
    memmove(h->bytes, h->bytes + at, h->length - at);
    h->length -= at;
}

static void write_line(cell_output *out, bool from_robot)
{
    envelope_line(out->out, out->envelope[from_robot ? 1 : 0], line);
}

/* A text-line interface: lines split in the held bytes of their direction, one JSON line per
 * record. The four interfaces of this kind have the same API under their own prefixes. What a
 * direction leaves without a newline is a fault record when it ends (P##_finish); bytes lost
 * give up the line they cut, and the conversation splits lines afresh after them and marks what
 * the gap leaves unsure (P##_lost: text_lines.py's LinesConversation.lost). */
#define LINES_INTERFACE(P, UPPER, ROBOT_IS_CLIENT)                                                                  \
    static void P##_init_state(void *state, urwire_sw_version v, bool hinted)                     \
    {                                                                                              \
        cell_lines_state *s = state;                                                               \
        P##_init(&s->lines, hinted ? P##_version((uint32_t)v.major, (uint32_t)v.minor, (uint32_t)v.bugfix) : 0u); \
        s->held[0].length = s->held[1].length = 0;                                                 \
    }                                                                                              \
                                                                                                   \
    static int P##_feed_state(void *state, const uint8_t *data, size_t n, bool from_robot, cell_output *out) \
    {                                                                                              \
        cell_lines_state *s = state;                                                               \
        cell_held *h = &s->held[from_robot ? 1 : 0];                                               \
        P##_record rec;                                                                            \
        size_t used, at;                                                                           \
        bool got;                                                                                  \
        while (n > 0) {                                                                            \
            size_t took = hold(h, data, n);                                                        \
            data += took;                                                                          \
            n -= took;                                                                             \
            at = 0;                                                                                \
            while ((used = P##_decode(&s->lines, from_robot, h->bytes + at, h->length - at, &rec, &got)) > 0 \
                   || got) {                                                                       \
                if (got) {                                                                         \
                    P##_json(&rec, line, sizeof line);                                             \
                    write_line(out, from_robot);                                                   \
                    out->errors |= P##_failed(&rec);                                               \
                }                                                                                  \
                at += used;                                                                        \
            }                                                                                      \
            drop(h, at);                                                                           \
        }                                                                                          \
        return 0;                                                                                  \
    }                                                                                              \
                                                                                                   \
    static int P##_close_state(void *state, bool from_robot, cell_output *out)                    \
    {                                                                                              \
        cell_lines_state *s = state;                                                               \
        cell_held *h = &s->held[from_robot ? 1 : 0];                                               \
        P##_record rec;                                                                            \
        if (P##_finish(&s->lines, from_robot, h->length, &rec)) {                                  \
            P##_json(&rec, line, sizeof line);                                                     \
            write_line(out, from_robot);                                                           \
            out->errors = true;                                                                    \
        }                                                                                          \
        h->length = 0;                                                                             \
        return 0;                                                                                  \
    }                                                                                              \
                                                                                                   \
    static int P##_lost_state(void *state, bool from_robot, uint64_t offset, cell_output *out)    \
    {                                                                                              \
        (void)P##_close_state(state, from_robot, out);                                             \
        P##_lost(&((cell_lines_state *)state)->lines, from_robot, offset);                         \
        return 0;                                                                                  \
    }                                                                                              \
                                                                                                   \
    static void P##_keep(void *state, int16_t *queue, size_t n)                                    \
    {                                                                                              \
        P##_keep_pending(&((cell_lines_state *)state)->lines, queue, n);                           \
    }                                                                                              \
                                                                                                   \
    static const uint16_t P##_ports[] = {UPPER##_PORT};                                            \
    const cell_interface cell_##P = {#P, P##_ports, 1, true, ROBOT_IS_CLIENT, sizeof(cell_lines_state), \
                                     P##_init_state, P##_feed_state, P##_close_state, P##_lost_state, NULL, NULL, \
                                     P##_keep};

/* The script sender is a driver's socket: the robot connects to it. */
LINES_INTERFACE(ur_dashboard, UR_DASHBOARD, false)
LINES_INTERFACE(ur_script_sender, UR_SCRIPT_SENDER, true)
LINES_INTERFACE(ur_interpreter, UR_INTERPRETER, false)
LINES_INTERFACE(robotiq_gripper, ROBOTIQ_GRIPPER, false)

/* An int32-record interface, through the three functions every one of them has. */
typedef struct records_api {
    size_t (*record_size)(bool from_robot, uint32_t release);
    size_t (*record_json)(bool from_robot, const uint8_t *buf, size_t n, uint32_t release, char *out, size_t cap);
    size_t (*tail_json)(bool from_robot, uint64_t offset, size_t left, uint32_t release, char *out, size_t cap);
    uint32_t default_release;
} records_api;

static void records_init(const records_api *api, void *state, urwire_sw_version v, bool hinted)
{
    cell_records_state *s = state;
    memset(s->way, 0, sizeof s->way);
    s->release = hinted ? ((uint32_t)v.major * 1000u + (uint32_t)v.minor) * 1000u + (uint32_t)v.bugfix
                        : api->default_release;
}

/* After bytes lost: the bytes dropped up to the next record's start, named once it is reached
 * (or the stream ends): they end a record whose start is lost (int32_records.py's _realigned). */
static void realigned(cell_records_state *s, bool from_robot, cell_output *out)
{
    char error[128];
    int k = from_robot ? 1 : 0;
    (void)snprintf(error, sizeof error, "%llu bytes after bytes lost from the capture: the end of a record whose "
                   "start is lost", (unsigned long long)s->way[k].skipped);
    envelope_error(out->out, out->envelope[k], (int64_t)(s->way[k].offset - s->way[k].skipped), error);
    out->errors = true;
    s->way[k].skip = s->way[k].skipped = 0;
}

/* Whole records out of the held bytes, one JSON line each; where nothing is specified this way,
 * the bytes are only counted (held.length stays 0, skipped counts them), to be named at the end. */
static int records_feed(const records_api *api, void *state, const uint8_t *data, size_t n, bool from_robot,
                        cell_output *out)
{
    cell_records_state *s = state;
    int k = from_robot ? 1 : 0;
    cell_held *h = &s->way[k].held;
    size_t size = api->record_size(from_robot, s->release), at;
    if (size == 0) {
        s->way[k].skipped += n;
        return 0;
    }
    while (n > 0 && s->way[k].skip > 0) {
        size_t drop_n = s->way[k].skip < n ? (size_t)s->way[k].skip : n;
        data += drop_n;
        n -= drop_n;
        s->way[k].skip -= drop_n;
        s->way[k].skipped += drop_n;
        s->way[k].offset += drop_n;
        if (s->way[k].skip == 0)
            realigned(s, from_robot, out);
    }
    while (n > 0) {
        size_t took = hold(h, data, n);
        data += took;
        n -= took;
        for (at = 0; h->length - at >= size; at += size) {
            api->record_json(from_robot, h->bytes + at, size, s->release, line, sizeof line);
            write_line(out, from_robot);
        }
        drop(h, at);
        s->way[k].offset += at;
    }
    return 0;
}

static int records_close(const records_api *api, void *state, bool from_robot, cell_output *out)
{
    cell_records_state *s = state;
    int k = from_robot ? 1 : 0;
    size_t size = api->record_size(from_robot, s->release);
    size_t left = size == 0 ? (size_t)s->way[k].skipped : s->way[k].held.length;
    if (size > 0 && s->way[k].skipped > 0) {     /* the stream ended before the next record's start */
        realigned(s, from_robot, out);
        return 0;
    }
    if (left == 0)
        return 0;
    api->tail_json(from_robot, s->way[k].offset, left, s->release, line, sizeof line);
    write_line(out, from_robot);
    out->errors = true;
    s->way[k].offset += left;
    s->way[k].held.length = 0;
    s->way[k].skipped = 0;
    return 0;
}

static int records_lost(const records_api *api, void *state, bool from_robot, uint64_t offset, cell_output *out)
{
    cell_records_state *s = state;
    int k = from_robot ? 1 : 0;
    size_t size = api->record_size(from_robot, s->release);
    (void)records_close(api, state, from_robot, out);
    s->way[k].offset = offset;
    s->way[k].skip = size == 0 ? 0 : (size - offset % size) % size;
    return 0;
}

#define RECORDS_INTERFACE(P, UPPER)                                                                \
    static const records_api P##_api = {P##_record_size, P##_record_json, P##_tail_json,          \
                                        UPPER##_DEFAULT_RELEASE};                                  \
    static void P##_init_state(void *state, urwire_sw_version v, bool hinted)                     \
    {                                                                                              \
        records_init(&P##_api, state, v, hinted);                                                  \
    }                                                                                              \
    static int P##_feed_state(void *state, const uint8_t *data, size_t n, bool from_robot, cell_output *out) \
    {                                                                                              \
        return records_feed(&P##_api, state, data, n, from_robot, out);                            \
    }                                                                                              \
    static int P##_close_state(void *state, bool from_robot, cell_output *out)                    \
    {                                                                                              \
        return records_close(&P##_api, state, from_robot, out);                                    \
    }                                                                                              \
    static int P##_lost_state(void *state, bool from_robot, uint64_t offset, cell_output *out)    \
    {                                                                                              \
        return records_lost(&P##_api, state, from_robot, offset, out);                             \
    }                                                                                              \
    static const uint16_t P##_ports[] = {UPPER##_PORT};                                            \
    const cell_interface cell_##P = {#P, P##_ports, 1, true, true, sizeof(cell_records_state), P##_init_state, \
                                     P##_feed_state, P##_close_state, P##_lost_state, NULL, NULL, NULL};

RECORDS_INTERFACE(ur_reverse, UR_REVERSE)
RECORDS_INTERFACE(ur_trajectory, UR_TRAJECTORY)
RECORDS_INTERFACE(ur_script_command, UR_SCRIPT_COMMAND)
