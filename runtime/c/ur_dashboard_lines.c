/* <standalone> */
#include <string.h>
#include "ur_dashboard_lines.h"
#define UR_DASHBOARD_COMMAND_COUNT 1
#define UR_DASHBOARD_VERSION_COMMAND UR_DASHBOARD_NONE
extern const ur_dashboard_command_spec ur_dashboard_commands[UR_DASHBOARD_COMMAND_COUNT];
extern const int ur_dashboard_lookup[UR_DASHBOARD_COMMAND_COUNT];
extern const ur_dashboard_reply_spec ur_dashboard_banner;
extern const ur_dashboard_reply_spec ur_dashboard_common_replies[];
extern const size_t ur_dashboard_common_reply_count;
extern const char ur_dashboard_version_prefix[];
/* </standalone> */
/* ---- lines: splitting, commands, replies, versions ----------------------------------------- */

#define UR_DASHBOARD_E_SERIES_MAJOR 5u

uint32_t ur_dashboard_version(uint32_t major, uint32_t minor, uint32_t bugfix)
{
    if (minor > 999u)
        minor = 999u;
    if (bugfix > 999u)
        bugfix = 999u;
    return (major * 1000u + minor) * 1000u + bugfix;
}

void ur_dashboard_init(ur_dashboard_conversation *c, uint32_t version)
{
    memset(c, 0, sizeof *c);
    c->version = version;
}

static bool starts_with(ur_dashboard_view v, const char *text, size_t n)
{
    return v.len >= n && memcmp(v.ptr, text, n) == 0;
}

bool ur_dashboard_matches(const ur_dashboard_reply_spec *reply, ur_dashboard_view line)
{
    const char *first = reply->pieces[0];
    const char *last = reply->pieces[reply->piece_count - 1];
    size_t first_len = strlen(first), last_len = strlen(last), at, end, i;
    if (reply->piece_count == 1)
        return line.len == first_len && memcmp(line.ptr, first, first_len) == 0;
    if (line.len < first_len + last_len || !starts_with(line, first, first_len)
        || memcmp(line.ptr + line.len - last_len, last, last_len) != 0)
        return false;
    at = first_len;
    end = line.len - last_len;
    for (i = 1; i + 1 < reply->piece_count; i++) {
        const char *piece = reply->pieces[i];
        size_t len = strlen(piece);
        while (at + len <= end && memcmp(line.ptr + at, piece, len) != 0)
            at++;
        if (at + len > end)
            return false;
        at += len;
    }
    return true;
}

int ur_dashboard_find_command(ur_dashboard_view line, ur_dashboard_view *argument, bool *has_argument)
{
    size_t i;
    *has_argument = false;
    argument->ptr = line.ptr;
    argument->len = 0;
    for (i = 0; i < UR_DASHBOARD_COMMAND_COUNT; i++) {
        int index = ur_dashboard_lookup[i];
        const ur_dashboard_command_spec *command = &ur_dashboard_commands[index];
        size_t len = strlen(command->text);
        if (!starts_with(line, command->text, len))
            continue;
        if (line.len == len)
            return index;
        if (command->takes_argument && line.ptr[len] == ' ') {
            *has_argument = true;
            argument->ptr = line.ptr + len + 1;
            argument->len = line.len - len - 1;
            return index;
        }
    }
    return UR_DASHBOARD_NONE;
}

const ur_dashboard_reply_spec *ur_dashboard_classify(int command, ur_dashboard_view line)
{
    size_t i;
    for (i = 0; i < ur_dashboard_common_reply_count; i++)
        if (ur_dashboard_matches(&ur_dashboard_common_replies[i], line))
            return &ur_dashboard_common_replies[i];
    if (command == UR_DASHBOARD_NONE)
        return NULL;
    for (i = 0; i < ur_dashboard_commands[command].reply_count; i++)
        if (ur_dashboard_matches(&ur_dashboard_commands[command].replies[i], line))
            return &ur_dashboard_commands[command].replies[i];
    return NULL;
}

bool ur_dashboard_available(int command, uint32_t version)
{
    const ur_dashboard_command_spec *spec = &ur_dashboard_commands[command];
    uint32_t since = version >= ur_dashboard_version(UR_DASHBOARD_E_SERIES_MAJOR, 0, 0) ? spec->since_e_series
                                                                                       : spec->since_cb;
    return since != 0 && version >= since;
}

/* "URSoftware 5.11.1.108318 (...)" -> 5.11.1, or 0: the word after the prefix, split at its
 * dots, whose first two or three parts are 1 to 3 digits. */
static uint32_t version_in(ur_dashboard_view line)
{
    size_t prefix = strlen(ur_dashboard_version_prefix), i;
    uint32_t parts[3] = {0, 0, 0};
    size_t count = 0, digits = 0;
    if (!starts_with(line, ur_dashboard_version_prefix, prefix))
        return 0;
    for (i = prefix; i < line.len && line.ptr[i] != ' '; i++) {
        uint8_t ch = line.ptr[i];
        if (ch == '.') {
            if (digits == 0)
                return 0;
            digits = 0;
            if (++count == 3)
                break;
        } else if (ch >= '0' && ch <= '9' && digits < 3) {
            parts[count] = parts[count] * 10u + (uint32_t)(ch - '0');
            digits++;
        } else {
            return 0;
        }
    }
    if (count < 3) {
        if (digits == 0)
            return 0;
        count++;
    }
    return count >= 2 ? ur_dashboard_version(parts[0], parts[1], parts[2]) : 0;
}

static void read_command(ur_dashboard_conversation *c, ur_dashboard_record *rec)
{
    int command = ur_dashboard_find_command(rec->text, &rec->argument, &rec->has_argument);
    rec->type = UR_DASHBOARD_COMMAND;
    rec->command_name = command;
    rec->available = command == UR_DASHBOARD_NONE || c->version == 0 ? -1
                                                                      : ur_dashboard_available(command, c->version);
    if (c->count == UR_DASHBOARD_PENDING) {   /* the oldest is forgotten, as a bounded queue does */
        c->head = (c->head + 1) % UR_DASHBOARD_PENDING;
        c->count--;
    }
    c->pending[(c->head + c->count) % UR_DASHBOARD_PENDING] = (int16_t)command;
    c->count++;
}

static void read_reply(ur_dashboard_conversation *c, ur_dashboard_record *rec)
{
    int command = UR_DASHBOARD_NONE;
    rec->type = UR_DASHBOARD_REPLY;
    rec->command_name = UR_DASHBOARD_NONE;
    if (!c->greeted) {
        c->greeted = true;
        if (ur_dashboard_matches(&ur_dashboard_banner, rec->text)) {
            rec->reply_name = &ur_dashboard_banner;
            return;
        }
    }
    if (c->count > 0) {
        command = c->pending[c->head];
        c->head = (c->head + 1) % UR_DASHBOARD_PENDING;
        c->count--;
    }
    rec->command_name = command;
    rec->reply_name = ur_dashboard_classify(command, rec->text);
    rec->error = rec->reply_name != NULL && rec->reply_name->error;
    if (command != UR_DASHBOARD_NONE && command == UR_DASHBOARD_VERSION_COMMAND) {
        uint32_t version = version_in(rec->text);
        if (version != 0)
            c->version = version;
    }
}

size_t ur_dashboard_decode(ur_dashboard_conversation *c, bool from_robot, const uint8_t *buf, size_t n,
                           ur_dashboard_record *rec, bool *got)
{
    ur_dashboard_direction *d = from_robot ? &c->replies : &c->commands;
    size_t window = n < UR_DASHBOARD_MAX_LINE + 2 ? n : UR_DASHBOARD_MAX_LINE + 2;
    const uint8_t *newline;
    size_t used, len;
    *got = false;
    memset(rec, 0, sizeof *rec);
    rec->command_name = UR_DASHBOARD_NONE;
    rec->available = -1;
    rec->offset = d->offset;
    if (d->skipping) {
        newline = n ? memchr(buf, '\n', n) : NULL;
        used = newline ? (size_t)(newline - buf) + 1 : n;
        d->skipping = newline == NULL;
        d->offset += used;
        return used;
    }
    newline = window ? memchr(buf, '\n', window) : NULL;
    if (newline == NULL) {
        if (n <= UR_DASHBOARD_MAX_LINE + 1)
            return 0;                         /* not whole yet */
        d->skipping = true;
        used = window;
    } else {
        used = (size_t)(newline - buf) + 1;
    }
    len = newline ? used - 1 : used;
    if (len > 0 && buf[len - 1] == '\r' && newline)
        len--;
    *got = true;
    d->offset += used;
    if (newline == NULL || len > UR_DASHBOARD_MAX_LINE) {
        rec->type = UR_DASHBOARD_FAULT;
        rec->fault = UR_DASHBOARD_LINE_TOO_LONG;
        return used;
    }
    rec->text.ptr = buf;
    rec->text.len = len;
    if (from_robot)
        read_reply(c, rec);
    else
        read_command(c, rec);
    return used;
}

bool ur_dashboard_finish(ur_dashboard_conversation *c, bool from_robot, size_t n, ur_dashboard_record *rec)
{
    ur_dashboard_direction *d = from_robot ? &c->replies : &c->commands;
    if (n == 0 || d->skipping)
        return false;
    memset(rec, 0, sizeof *rec);
    rec->type = UR_DASHBOARD_FAULT;
    rec->fault = UR_DASHBOARD_NO_NEWLINE_AT_END;
    rec->command_name = UR_DASHBOARD_NONE;
    rec->available = -1;
    rec->offset = d->offset;
    rec->bytes = n;
    return true;
}
