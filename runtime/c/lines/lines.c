/* <standalone> */
#include <string.h>
#include "match.c"  /* NOLINT(bugprone-suspicious-include): one unit, as joined */
#include "lines.h"
/* </standalone> */
/* ---- lines: splitting, pairing, versions ------------------------------------------------------ */
/* A conversation of the C library, over the interface's tables (spec), which the generated part
 * passes: its public functions, named after the interface, call these. */

URWIRE__PRIVATE void lines_init(lines_conversation *c, uint32_t version)
{
    memset(c, 0, sizeof *c);
    c->version = version;
    c->kept = LINES_PENDING;
}

URWIRE__PRIVATE void lines_keep_pending(lines_conversation *c, int16_t *queue, size_t n)
{
    c->more = queue;
    c->kept = n;
}

static int16_t *queue_of(lines_conversation *c)
{
    return c->more != NULL ? c->more : c->pending;
}

/* The command a line is (an index, or LINES_NONE), and its argument. */
URWIRE__PRIVATE int lines_command_of(const lines_spec_t *spec, lines_view line, lines_view *argument,
                                     bool *has_argument)
{
    long at;
    int command = lines_find_command(spec, line.ptr, line.len, &at);
    *has_argument = at >= 0;
    argument->ptr = line.ptr + (at >= 0 ? (size_t)at : 0);
    argument->len = at >= 0 ? line.len - (size_t)at : 0;
    return command;
}

/* A request awaits its reply; false when it is not kept for want of room, which its record says
 * (see lines_conversation). After bytes lost none is kept: its reply's record says why. */
static bool keep(const lines_spec_t *spec, lines_conversation *c, int command)
{
    if (!spec->one_reply_per_request) {          /* only the latest request counts */
        queue_of(c)[0] = (int16_t)command;
        c->count = 1;
        c->unknown = false;                      /* the lines after it answer it */
    } else if (c->unknown) {
        return true;
    } else if (c->lost > 0 || c->count == c->kept) {
        c->lost++;
        return false;
    } else {
        queue_of(c)[(c->head + c->count) % c->kept] = (int16_t)command;
        c->count++;
    }
    return true;
}

/* The request a reply answers (LINES_NONE: none), *not_kept when it answers one not kept,
 * *unknown when bytes lost leave it unknown. */
static int answered(const lines_spec_t *spec, lines_conversation *c, bool *not_kept, bool *unknown)
{
    int command = LINES_NONE;
    *not_kept = false;
    *unknown = false;
    if (c->count > 0 && spec->one_reply_per_request) {
        command = queue_of(c)[c->head];
        c->head = (c->head + 1) % c->kept;
        c->count--;
    } else if (c->unknown) {
        *unknown = true;
    } else if (c->count > 0) {    /* every answering line belongs to the latest request */
        command = queue_of(c)[(c->head + c->count - 1) % c->kept];
    } else if (c->lost > 0) {     /* it answers a command that was not kept */
        *not_kept = true;
        c->lost--;
    }
    return command;
}

static void read_command(const lines_spec_t *spec, lines_conversation *c, bool cut, lines_record *rec)
{
    int command = lines_command_of(spec, rec->text, &rec->argument, &rec->has_argument);
    rec->type = LINES_COMMAND;
    rec->cut = cut;
    rec->command_name = command;
    rec->available = command == LINES_NONE || c->version == 0 ? -1 : lines_available(spec, command, c->version);
    rec->not_kept = !keep(spec, c, command);
    rec->kept = c->kept;
}

static void read_reply(const lines_spec_t *spec, lines_conversation *c, bool cut, lines_record *rec)
{
    int command;
    rec->type = LINES_REPLY;
    rec->command_name = LINES_NONE;
    if (!c->greeted) {
        c->greeted = true;
        if (spec->banner != NULL && lines_matches(spec->banner, rec->text.ptr, rec->text.len)) {
            rec->reply_name = spec->banner;
            return;
        }
    }
    /* The end of a line begun in the lost bytes answers none of the commands seen since. */
    rec->cut = cut;
    command = cut ? LINES_NONE : answered(spec, c, &rec->not_kept, &rec->unknown);
    rec->kept = c->kept;
    rec->command_name = command;
    rec->reply_name = lines_classify(spec, command, rec->text.ptr, rec->text.len);
    rec->error = rec->reply_name != NULL && rec->reply_name->error;
    if (command != LINES_NONE && command == spec->version_command) {
        uint64_t version;
        if (lines_version_in(spec, rec->text.ptr, rec->text.len, &version) && version != 0)
            c->version = (uint32_t)version;
    }
}

/* One record from the front of buf, the next bytes of one direction: the bytes used, and *got
 * when rec holds a record (0 with *got false: the line is not whole yet). */
URWIRE__PRIVATE size_t lines_decode(const lines_spec_t *spec, lines_conversation *c, bool from_robot,
                                    const uint8_t *buf, size_t n, lines_record *rec, bool *got)
{
    bool requests = from_robot == spec->requests_from_robot;
    lines_direction *d = requests ? &c->commands : &c->replies;
    size_t window = n < spec->max_line + 2 ? n : spec->max_line + 2;
    const uint8_t *newline;
    size_t used, len;
    bool cut = d->cut;
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
        if (n <= spec->max_line + 1)
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
    d->cut = false;
    if (newline == NULL || len > spec->max_line) {
        /* Still a line: a command the server answers, or the reply to one, so that the pairing
         * of the lines after it holds. */
        bool not_kept, unknown;
        if (requests) {
            keep(spec, c, LINES_NONE);
        } else {
            c->greeted = true;
            answered(spec, c, &not_kept, &unknown);
        }
        rec->type = LINES_FAULT;
        rec->fault = LINES_LINE_TOO_LONG;
        return used;
    }
    rec->text.ptr = buf;
    rec->text.len = len;
    if (requests)
        read_command(spec, c, cut, rec);
    else
        read_reply(spec, c, cut, rec);
    return used;
}

/* Bytes of one direction are lost before its stream offset `offset` (the caller has given up the
 * line they cut with lines_finish): its lines are split afresh from there, the first one marked
 * cut. Lost commands leave every later reply's unknown (those kept came before them, and their
 * replies first); lost replies may have answered those awaiting, unless none awaited. */
URWIRE__PRIVATE void lines_lost(const lines_spec_t *spec, lines_conversation *c, bool from_robot, uint64_t offset)
{
    bool requests = from_robot == spec->requests_from_robot;
    lines_direction *d = requests ? &c->commands : &c->replies;
    d->offset = offset;
    d->skipping = false;
    d->cut = true;
    if (requests) {
        c->unknown = true;
    } else if (spec->one_reply_per_request && (c->count > 0 || c->lost > 0)) {
        c->head = c->count = 0;
        c->unknown = true;
    }
}

/* At the end of a direction: its n bytes left without a newline as a fault record (true). */
URWIRE__PRIVATE bool lines_finish(const lines_spec_t *spec, lines_conversation *c, bool from_robot, size_t n,
                                  lines_record *rec)
{
    bool requests = from_robot == spec->requests_from_robot;
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
