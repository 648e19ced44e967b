/* <standalone> */
/* Compiled alone (tests/native/test_lines_native.py) with the declarations the generated file
 * gives it: the handles, the preference and the spec's tables. */
#include <epan/packet.h>
#include <epan/conversation.h>
#include <epan/expert.h>
#include <epan/proto_data.h>
#include "match.c"
#include "../common/exchange.h"
static int proto_lines = -1;
static int hf_lines_command = -1, hf_lines_command_name = -1, hf_lines_argument = -1, hf_lines_available = -1;
static int hf_lines_reply = -1, hf_lines_reply_name = -1, hf_lines_error = -1;
static int hf_lines_response_in = -1, hf_lines_response_to = -1, hf_lines_time = -1;
static int ett_lines = -1;
static expert_field ei_lines_error_reply = EI_INIT, ei_lines_unknown_command = EI_INIT;
static expert_field ei_lines_unavailable = EI_INIT, ei_lines_too_long = EI_INIT;
static expert_field ei_lines_not_kept = EI_INIT, ei_lines_reply_not_kept = EI_INIT;
static const char *lines_version_preference = "";
extern const lines_spec_t lines_spec;
static int dissect_lines(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree, void *data);
/* </standalone> */
/* A dissector of text lines (the dashboard server, the driver's script sender), the twin of
 * runtime/lua/lines/dissect.lua: lines reassembled across TCP segments, each shown as a request
 * (command) or a reply, replies paired with their requests (and linked with them both ways:
 * runtime/epan/common/exchange.c) and the software version learnt per conversation, expert
 * infos for a reply that says an error, an unknown command, a command the version lacks, a line
 * too long. The first pass decides each line (which command, which reply,
 * whether the version has it) and keeps the decision with its frame, so that later passes, in
 * any order, show what the first one saw. */

#define LINES_PENDING_KEPT 256            /* commands awaiting a reply that a conversation keeps */

/* What the first pass decided about one line. */
typedef struct lines_decision {
    int command;                          /* the command, or the command a reply answers; LINES_NONE */
    long argument;                        /* commands: the argument's offset in the line, or -1 */
    int available;                        /* commands: 1 or 0 when the version is known, else -1 */
    const lines_reply_t *reply;           /* replies: the one it is, or NULL */
    bool not_kept;                        /* a command not kept, or a reply to one */
    ur_exchange_request_t *request;       /* commands: its frame, time and reply's frame */
    ur_exchange_reply_t link;             /* replies: the command's frame and the time since */
} lines_decision_t;

/* What a conversation has seen so far, in the first pass. A command that comes when
 * LINES_PENDING_KEPT await replies is not kept but counted lost, and so is every command behind a
 * lost one (replies come in order); a reply with none kept answers a lost one, and pairs with none. */
typedef struct lines_conversation {
    lines_decision_t *pending[LINES_PENDING_KEPT];   /* commands awaiting a reply, oldest at `first` */
    unsigned first, count, lost;
    bool greeted;                         /* a line came from the server */
    bool has_version;
    uint64_t version;                     /* lines_version(), when has_version */
    bool skipping[2];                     /* per direction (from the robot): inside a line too long */
} lines_conversation_t;

/* The decisions of one frame in one direction, by the line's offset in the data it came in. */
typedef struct lines_frame {
    bool skipping;                        /* the direction was inside a line too long when the frame came */
    wmem_tree_t *lines;                   /* lines_decision_t by offset; NULL until the first line */
} lines_frame_t;

/* The version preference ("5.11", "3.15.7", as every dissector reads it: runtime/c/common/
 * version_text.c, a vertical tab a blank as for Lua's %s) as a lines_version(); false for text that
 * is not a version. A major of ten digits or more is past every command's first version already,
 * and stops there (no overflow). */
static bool lines_parse_version(const char *text, uint64_t *version)
{
    urwire__version_text v;
    if (text == NULL || !urwire__read_version(text, text + strlen(text), true, true, &v))
        return false;
    *version = lines_version(MIN(v.part[0], 1000000000), v.part[1], v.part[2]);
    return true;
}

static lines_conversation_t *lines_conversation(packet_info *pinfo)
{
    conversation_t *conversation = find_or_create_conversation(pinfo);
    lines_conversation_t *c = (lines_conversation_t *)conversation_get_proto_data(conversation, proto_lines);
    if (c == NULL) {
        c = wmem_new0(wmem_file_scope(), lines_conversation_t);
        c->has_version = lines_parse_version(lines_version_preference, &c->version);
        conversation_add_proto_data(conversation, proto_lines, c);
    }
    return c;
}

/* A request awaits its reply (its decision: the command and its exchange); false when it is not
 * kept (see lines_conversation_t). */
static bool lines_keep(lines_conversation_t *c, lines_decision_t *request)
{
    if (!lines_spec.one_reply_per_request) {        /* only the latest request counts */
        c->first = 0;
        c->count = 1;
        c->pending[0] = request;
    } else if (c->lost > 0 || c->count == LINES_PENDING_KEPT) {
        c->lost++;
        return false;
    } else {
        c->pending[(c->first + c->count++) % LINES_PENDING_KEPT] = request;
    }
    return true;
}

/* The request a reply answers (NULL: none), *not_kept when it answers one not kept. */
static lines_decision_t *lines_answered(lines_conversation_t *c, bool *not_kept)
{
    lines_decision_t *request = NULL;
    *not_kept = false;
    if (c->count > 0 && lines_spec.one_reply_per_request) {
        request = c->pending[c->first];
        c->first = (c->first + 1) % LINES_PENDING_KEPT;
        c->count--;
    } else if (c->count > 0) {                      /* every answering line belongs to the latest request */
        request = c->pending[(c->first + c->count - 1) % LINES_PENDING_KEPT];
    } else if (c->lost > 0) {                       /* it answers a command that was not kept */
        *not_kept = true;
        c->lost--;
    }
    return request;
}

/* A line too long is still a line: a command the server answers, or the reply to one, so that
 * the pairing of the lines after it holds (and its exchange is linked, though not shown). */
static void lines_count_too_long(lines_conversation_t *c, bool requests, packet_info *pinfo)
{
    bool not_kept;
    if (requests) {
        lines_decision_t *d = wmem_new0(wmem_file_scope(), lines_decision_t);
        d->command = LINES_NONE;
        d->request = ur_exchange_request(pinfo);
        lines_keep(c, d);
    } else {
        lines_decision_t *request;
        ur_exchange_reply_t link;
        c->greeted = true;
        request = lines_answered(c, &not_kept);
        ur_exchange_reply(request != NULL ? request->request : NULL, pinfo, &link);
    }
}

static lines_decision_t *lines_decide_command(lines_conversation_t *c, packet_info *pinfo, const uint8_t *text,
                                              size_t len)
{
    lines_decision_t *d = wmem_new0(wmem_file_scope(), lines_decision_t);
    d->command = lines_find_command(&lines_spec, text, len, &d->argument);
    d->request = ur_exchange_request(pinfo);
    d->not_kept = !lines_keep(c, d);
    d->available = d->command != LINES_NONE && c->has_version
        ? lines_available(&lines_spec, d->command, c->version) : -1;
    d->reply = NULL;
    return d;
}

static lines_decision_t *lines_decide_reply(lines_conversation_t *c, packet_info *pinfo, const uint8_t *text,
                                            size_t len)
{
    lines_decision_t *d = wmem_new0(wmem_file_scope(), lines_decision_t);
    lines_decision_t *request;
    d->argument = -1;
    d->available = -1;
    d->command = LINES_NONE;
    d->not_kept = false;
    if (!c->greeted) {
        c->greeted = true;
        if (lines_spec.banner != NULL && lines_matches(lines_spec.banner, text, len)) {
            d->reply = lines_spec.banner;
            return d;
        }
    }
    request = lines_answered(c, &d->not_kept);
    d->command = request != NULL ? request->command : LINES_NONE;
    ur_exchange_reply(request != NULL ? request->request : NULL, pinfo, &d->link);
    if (d->command != LINES_NONE && d->command == lines_spec.version_command) {
        uint64_t version;
        if (lines_version_in(&lines_spec, text, len, &version)) {
            c->version = version;
            c->has_version = true;
        }
    }
    d->reply = lines_classify(&lines_spec, d->command, text, len);
    return d;
}

/* ---- the tree ---- */

/* Text as the tree and the Info column show it: UTF-8, each byte that is not replaced by U+FFFD
 * (Wireshark's ENC_UTF_8), so that every output of tshark is valid UTF-8. */
static const char *lines_text(packet_info *pinfo, tvbuff_t *tvb, int at, int len)
{
    return len > 0 ? (const char *)tvb_get_string_enc(pinfo->pool, tvb, at, len, ENC_UTF_8) : "";
}

static void lines_show_command(proto_tree *tree, packet_info *pinfo, tvbuff_t *tvb, int at, int len,
                               const char *text, const lines_decision_t *d)
{
    const int span = len > 0 ? len : 1;        /* an empty line: its newline */
    proto_item *item = proto_tree_add_item(tree, proto_lines, tvb, at, span, ENC_NA);
    proto_tree *line = proto_item_add_subtree(item, ett_lines);
    proto_tree_add_string(line, hf_lines_command, tvb, at, span, text);
    if (d->command != LINES_NONE) {
        proto_item_set_generated(proto_tree_add_string(line, hf_lines_command_name, tvb, at, span,
                                                       lines_spec.commands[d->command].name));
        if (d->argument >= 0)
            proto_tree_add_string(line, hf_lines_argument, tvb, at, span,
                                  lines_text(pinfo, tvb, at + (int)d->argument, len - (int)d->argument));
        if (d->available >= 0) {
            proto_item *available;
            available = proto_tree_add_boolean(line, hf_lines_available, tvb, at, span, d->available);
            proto_item_set_generated(available);
            if (!d->available)
                expert_add_info(pinfo, available, &ei_lines_unavailable);
        }
    } else {
        expert_add_info(pinfo, item, &ei_lines_unknown_command);
    }
    if (d->not_kept)
        expert_add_info(pinfo, item, &ei_lines_not_kept);
    ur_exchange_show_request(line, tvb, at, span, d->request, hf_lines_response_in);
    proto_item_append_text(item, ": %s", text);
}

static void lines_show_reply(proto_tree *tree, packet_info *pinfo, tvbuff_t *tvb, int at, int len,
                             const char *text, const lines_decision_t *d)
{
    const int span = len > 0 ? len : 1;        /* an empty line: its newline */
    proto_item *item = proto_tree_add_item(tree, proto_lines, tvb, at, span, ENC_NA);
    proto_tree *line = proto_item_add_subtree(item, ett_lines);
    proto_item *error;
    bool says_error = d->reply != NULL && d->reply->error;
    proto_tree_add_string(line, hf_lines_reply, tvb, at, span, text);
    if (d->command != LINES_NONE)
        proto_item_set_generated(proto_tree_add_string(line, hf_lines_command_name, tvb, at, span,
                                                       lines_spec.commands[d->command].name));
    if (d->reply != NULL)
        proto_item_set_generated(proto_tree_add_string(line, hf_lines_reply_name, tvb, at, span,
                                                       d->reply->name));
    error = proto_tree_add_boolean(line, hf_lines_error, tvb, at, span, says_error);
    proto_item_set_generated(error);
    if (says_error)
        expert_add_info(pinfo, error, &ei_lines_error_reply);
    if (d->not_kept)
        expert_add_info(pinfo, item, &ei_lines_reply_not_kept);
    ur_exchange_show_reply(line, tvb, at, span, &d->link, hf_lines_response_to, hf_lines_time);
    proto_item_append_text(item, ": %s", text);
}

/* Whether the line's items carry an expert info (those of lines_show_command and
 * lines_show_reply): they are added without a tree too, as the Lua twin adds them. */
static bool lines_has_expert(const lines_decision_t *d, bool command)
{
    if (d->not_kept)
        return true;
    if (command)
        return d->command == LINES_NONE || (d->available >= 0 && !d->available);
    return d->reply != NULL && d->reply->error;
}

/* ---- lines ---- */

/* The decisions of this frame in this direction: made now in the first pass, else those kept. */
static lines_frame_t *lines_frame(packet_info *pinfo, lines_conversation_t *c, bool from_robot)
{
    lines_frame_t *frame;
    frame = (lines_frame_t *)p_get_proto_data(wmem_file_scope(), pinfo, proto_lines, from_robot);
    if (frame == NULL) {
        frame = wmem_new(wmem_file_scope(), lines_frame_t);
        frame->skipping = c->skipping[from_robot];
        frame->lines = NULL;                          /* made with the frame's first line */
        p_add_proto_data(wmem_file_scope(), pinfo, proto_lines, from_robot, frame);
    }
    return frame;
}

/* The Info column: each line's "Command: <text>" or "Reply: <text>", joined by "; ", no longer
 * than the column shows; nothing without columns (info NULL). */
static void lines_info(wmem_strbuf_t *info, const char *what, const char *text)
{
    if (info == NULL || wmem_strbuf_get_len(info) >= COL_MAX_INFO_LEN)
        return;
    if (wmem_strbuf_get_len(info) > 0)
        wmem_strbuf_append(info, "; ");
    wmem_strbuf_append(info, what);
    wmem_strbuf_append(info, text);
}

static int dissect_lines(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree, void *data _U_)
{
    const int n = (int)tvb_captured_length(tvb);
    const uint8_t *buf = tvb_get_ptr(tvb, 0, n);
    /* The server sends from its port; the robot is the server but for the driver's sockets. */
    const bool from_server = pinfo->srcport == pinfo->match_uint;
    const bool from_robot = from_server != lines_spec.robot_is_client;
    const bool requests = from_robot == lines_spec.requests_from_robot;
    const bool first_pass = !PINFO_FD_VISITED(pinfo);
    lines_conversation_t *c = lines_conversation(pinfo);
    lines_frame_t *frame = lines_frame(pinfo, c, from_robot);
    bool skipping = frame->skipping;
    /* No columns (tshark's first pass): no Info text to build. */
    wmem_strbuf_t *info = pinfo->cinfo != NULL ? wmem_strbuf_new(pinfo->pool, "") : NULL;
    int at = 0;

    col_set_str(pinfo->cinfo, COL_PROTOCOL, lines_spec.column);
    while (at < n) {
        const uint8_t *newline = (const uint8_t *)memchr(buf + at, '\n', (size_t)(n - at));
        const int nl = newline != NULL ? (int)(newline - buf) : -1;   /* the newline's offset */
        if (skipping) {
            if (nl < 0)
                break;
            proto_item_set_text(proto_tree_add_item(tree, proto_lines, tvb, at, nl + 1 - at, ENC_NA),
                                "Rest of a line too long");
            skipping = false;
            at = nl + 1;
        } else if (nl < 0 && (size_t)(n - at) <= lines_spec.max_line + 1) {
            if (pinfo->can_desegment > 0) {
                pinfo->desegment_offset = at;
                pinfo->desegment_len = DESEGMENT_ONE_MORE_SEGMENT;
                break;
            }
            proto_item_set_text(proto_tree_add_item(tree, proto_lines, tvb, at, n - at, ENC_NA),
                                "Part of a line (reassembly is off)");
            at = n;
        } else {
            const int stop = nl >= 0 ? nl : n;      /* the end of the line's bytes */
            int len = stop - at;
            if (nl >= 0 && len > 0 && buf[stop - 1] == '\r')
                len--;
            if (nl < 0 || (size_t)len > lines_spec.max_line) {
                expert_add_info(pinfo, proto_tree_add_item(tree, proto_lines, tvb, at, stop - at, ENC_NA),
                                &ei_lines_too_long);
                lines_info(info, "Line too long", "");
                if (first_pass)
                    lines_count_too_long(c, requests, pinfo);
                skipping = nl < 0;
                at = nl >= 0 ? nl + 1 : n;
            } else {
                lines_decision_t *d = first_pass || frame->lines == NULL ? NULL
                    : (lines_decision_t *)wmem_tree_lookup32(frame->lines, (guint32)at);
                if (d == NULL) {
                    d = requests ? lines_decide_command(c, pinfo, buf + at, (size_t)len)
                                 : lines_decide_reply(c, pinfo, buf + at, (size_t)len);
                    if (frame->lines == NULL)
                        frame->lines = wmem_tree_new(wmem_file_scope());
                    wmem_tree_insert32(frame->lines, (guint32)at, d);
                }
                /* The text, only where it is shown; the line's items where there is a tree or
                 * an expert info to add (the expert tap, -z expert, builds no tree). */
                const bool items = tree != NULL || lines_has_expert(d, requests);
                if (info != NULL || items) {
                    const char *text = lines_text(pinfo, tvb, at, len);
                    lines_info(info, requests ? "Command: " : "Reply: ", text);
                    if (items)
                        (requests ? lines_show_command : lines_show_reply)(tree, pinfo, tvb, at, len, text, d);
                }
                at = nl + 1;
            }
        }
    }
    if (first_pass)
        c->skipping[from_robot] = skipping;
    if (info != NULL && wmem_strbuf_get_len(info) > 0)
        col_add_str(pinfo->cinfo, COL_INFO, wmem_strbuf_get_str(info));
    return n;
}
