/* libFuzzer harness for generated/c/ur_dashboard.{h,c}: the line splitter, the command lookup, the
 * reply classification and the JSON writer on any bytes, cut into segments of both directions.
 *
 * Input: byte 0 picks the version known at the start (0: none, else a CB3 or e-Series one); then
 * segments, each a control byte (bit 0: from the robot; bits 1-7: the segment's length) and up
 * to that many bytes. Each direction is held in a buffer of its own, as a caller holds it.
 * Checks: no crash or sanitizer report; every record's JSON fits the bound its line gives it;
 * a record's views lie inside the caller's buffer; no call uses more bytes than it was given. */
#include <stdlib.h>
#include <string.h>

#include "ur_dashboard.h"

#define HELD (UR_DASHBOARD_MAX_LINE * 2 + 256)

typedef struct held {
    uint8_t bytes[HELD];
    size_t len;
} held;

static char json[HELD * 6 + 256];

static void check_view(ur_dashboard_view v, const uint8_t *buf, size_t n)
{
    if (v.len > 0 && (v.ptr < buf || v.ptr + v.len > buf + n))
        abort();
}

static void drain(ur_dashboard_conversation *c, bool from_robot, held *h)
{
    size_t at = 0, used;
    ur_dashboard_record rec;
    bool got;
    while ((used = ur_dashboard_decode(c, from_robot, h->bytes + at, h->len - at, &rec, &got)) > 0 || got) {
        if (used > h->len - at)
            abort();
        if (got) {
            size_t len;
            check_view(rec.text, h->bytes + at, used);
            check_view(rec.argument, h->bytes + at, used);
            len = ur_dashboard_json(&rec, json, sizeof json);
            /* 6 bytes of JSON per byte of text at most (a control byte is \u001e), twice for an
             * argument, and names */
            if (len >= sizeof json || len > 12 * rec.text.len + 256 || strlen(json) != len)
                abort();
        }
        at += used;
    }
    memmove(h->bytes, h->bytes + at, h->len - at);
    h->len -= at;
    if (h->len > UR_DASHBOARD_MAX_LINE + 1)
        abort();      /* a line not whole yet is never longer than that */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static held directions[2];
    static const uint32_t versions[4] = {0, 3015000u, 5004000u, 5011000u};
    ur_dashboard_conversation c;
    ur_dashboard_record rec;
    size_t at = 1;
    if (size == 0)
        return 0;
    directions[0].len = directions[1].len = 0;
    ur_dashboard_init(&c, versions[data[0] & 3u]);
    while (at < size) {
        bool from_robot = (data[at] & 1u) != 0;
        size_t n = (size_t)(data[at] >> 1), take;
        held *h = &directions[from_robot ? 1 : 0];
        at++;
        take = n < size - at ? n : size - at;
        memcpy(h->bytes + h->len, data + at, take);
        h->len += take;
        at += take;
        drain(&c, from_robot, h);
    }
    if (ur_dashboard_finish(&c, false, directions[0].len, &rec))
        (void)ur_dashboard_json(&rec, json, sizeof json);
    if (ur_dashboard_finish(&c, true, directions[1].len, &rec))
        (void)ur_dashboard_json(&rec, json, sizeof json);
    return 0;
}
