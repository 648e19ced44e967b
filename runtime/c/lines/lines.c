/* <standalone> */
#include <string.h>
#include "lines.h"
#define LINES_COMMAND_COUNT 1
#define LINES_VERSION_COMMAND LINES_NONE
extern const lines_command_spec lines_commands[LINES_COMMAND_COUNT];
extern const int lines_lookup[LINES_COMMAND_COUNT];
extern const lines_reply_spec *const lines_banner;
#define LINES_REQUESTS_FROM_ROBOT 0
#define LINES_ONE_REPLY_PER_REQUEST 1
extern const lines_reply_spec *const lines_common_replies;
extern const size_t lines_common_reply_count;
extern const char lines_version_prefix[];
/* </standalone> */
/* ---- lines: splitting, commands, replies, versions ----------------------------------------- */

#define LINES_E_SERIES_MAJOR 5u

uint32_t lines_version(uint32_t major, uint32_t minor, uint32_t bugfix)
{
    if (minor > 999u)
        minor = 999u;
    if (bugfix > 999u)
        bugfix = 999u;
    return (major * 1000u + minor) * 1000u + bugfix;
}

void lines_init(lines_conversation *c, uint32_t version)
{
    memset(c, 0, sizeof *c);
    c->version = version;
    c->kept = LINES_PENDING;
}

void lines_keep_pending(lines_conversation *c, int16_t *queue, size_t n)
{
    c->more = queue;
    c->kept = n;
}

static int16_t *queue_of(lines_conversation *c)
{
    return c->more != NULL ? c->more : c->pending;
}

static bool starts_with(lines_view v, const char *text, size_t n)
{
    return v.len >= n && memcmp(v.ptr, text, n) == 0;
}

bool lines_matches(const lines_reply_spec *reply, lines_view line)
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

int lines_find_command(lines_view line, lines_view *argument, bool *has_argument)
{
    size_t i;
    *has_argument = false;
    argument->ptr = line.ptr;
    argument->len = 0;
    for (i = 0; i < LINES_COMMAND_COUNT; i++) {
        int index = lines_lookup[i];
        const lines_command_spec *command = &lines_commands[index];
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
    return LINES_NONE;
}

const lines_reply_spec *lines_classify(int command, lines_view line)
{
    size_t i;
    for (i = 0; i < lines_common_reply_count; i++)
        if (lines_matches(&lines_common_replies[i], line))
            return &lines_common_replies[i];
    if (command == LINES_NONE)
        return NULL;
    for (i = 0; i < lines_commands[command].reply_count; i++)
        if (lines_matches(&lines_commands[command].replies[i], line))
            return &lines_commands[command].replies[i];
    return NULL;
}

bool lines_available(int command, uint32_t version)
{
    const lines_command_spec *spec = &lines_commands[command];
    uint32_t since = version >= lines_version(LINES_E_SERIES_MAJOR, 0, 0) ? spec->since_e_series
                                                                                       : spec->since_cb;
    return since != 0 && version >= since;
}

/* "URSoftware 5.11.1.108318 (...)" -> 5.11.1, or 0: the word after the prefix, split at its
 * dots, whose first two or three parts are 1 to 3 digits. */
static uint32_t version_in(lines_view line)
{
    size_t prefix = strlen(lines_version_prefix), i;
    uint32_t parts[3] = {0, 0, 0};
    size_t count = 0, digits = 0;
    if (!starts_with(line, lines_version_prefix, prefix))
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
    return count >= 2 ? lines_version(parts[0], parts[1], parts[2]) : 0;
}

/* A request awaits its reply; false when it is not kept (see lines_conversation). */
static bool keep(lines_conversation *c, int command)
{
    if (!LINES_ONE_REPLY_PER_REQUEST) {          /* only the latest request counts */
        queue_of(c)[0] = (int16_t)command;
        c->count = 1;
    } else if (c->lost > 0 || c->count == c->kept) {
        c->lost++;
        return false;
    } else {
        queue_of(c)[(c->head + c->count) % c->kept] = (int16_t)command;
        c->count++;
    }
    return true;
}

/* The request a reply answers (LINES_NONE: none), *not_kept when it answers one not kept. */
static int answered(lines_conversation *c, bool *not_kept)
{
    int command = LINES_NONE;
    *not_kept = false;
    if (c->count > 0 && LINES_ONE_REPLY_PER_REQUEST) {
        command = queue_of(c)[c->head];
        c->head = (c->head + 1) % c->kept;
        c->count--;
    } else if (c->count > 0) {    /* every answering line belongs to the latest request */
        command = queue_of(c)[(c->head + c->count - 1) % c->kept];
    } else if (c->lost > 0) {     /* it answers a command that was not kept */
        *not_kept = true;
        c->lost--;
    }
    return command;
}

static void read_command(lines_conversation *c, lines_record *rec)
{
    int command = lines_find_command(rec->text, &rec->argument, &rec->has_argument);
    rec->type = LINES_COMMAND;
    rec->command_name = command;
    rec->available = command == LINES_NONE || c->version == 0 ? -1
                                                                      : lines_available(command, c->version);
    rec->not_kept = !keep(c, command);
    rec->kept = c->kept;
}

static void read_reply(lines_conversation *c, lines_record *rec)
{
    int command;
    rec->type = LINES_REPLY;
    rec->command_name = LINES_NONE;
    if (!c->greeted) {
        c->greeted = true;
        if (lines_banner != NULL && lines_matches(lines_banner, rec->text)) {
            rec->reply_name = lines_banner;
            return;
        }
    }
    command = answered(c, &rec->not_kept);
    rec->kept = c->kept;
    rec->command_name = command;
    rec->reply_name = lines_classify(command, rec->text);
    rec->error = rec->reply_name != NULL && rec->reply_name->error;
    if (command != LINES_NONE && command == LINES_VERSION_COMMAND) {
        uint32_t version = version_in(rec->text);
        if (version != 0)
            c->version = version;
    }
}

size_t lines_decode(lines_conversation *c, bool from_robot, const uint8_t *buf, size_t n,
                           lines_record *rec, bool *got)
{
    bool requests = from_robot == (bool)LINES_REQUESTS_FROM_ROBOT;
    lines_direction *d = requests ? &c->commands : &c->replies;
    size_t window = n < LINES_MAX_LINE + 2 ? n : LINES_MAX_LINE + 2;
    const uint8_t *newline;
    size_t used, len;
    *got = false;
    memset(rec, 0, sizeof *rec);
    rec->command_name = LINES_NONE;
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
        if (n <= LINES_MAX_LINE + 1)
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
    if (newline == NULL || len > LINES_MAX_LINE) {
        /* Still a line: a command the server answers, or the reply to one, so that the pairing
         * of the lines after it holds. */
        bool not_kept;
        if (requests) {
            keep(c, LINES_NONE);
        } else {
            c->greeted = true;
            answered(c, &not_kept);
        }
        rec->type = LINES_FAULT;
        rec->fault = LINES_LINE_TOO_LONG;
        return used;
    }
    rec->text.ptr = buf;
    rec->text.len = len;
    if (requests)
        read_command(c, rec);
    else
        read_reply(c, rec);
    return used;
}

bool lines_finish(lines_conversation *c, bool from_robot, size_t n, lines_record *rec)
{
    bool requests = from_robot == (bool)LINES_REQUESTS_FROM_ROBOT;
    lines_direction *d = requests ? &c->commands : &c->replies;
    if (n == 0 || d->skipping)
        return false;
    memset(rec, 0, sizeof *rec);
    rec->type = LINES_FAULT;
    rec->fault = LINES_NO_NEWLINE_AT_END;
    rec->command_name = LINES_NONE;
    rec->available = -1;
    rec->offset = d->offset;
    rec->bytes = n;
    return true;
}
