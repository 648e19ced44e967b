/* <standalone> */
#include <string.h>
#include "../common/macros.h"
#include "../common/version_text.c"  /* NOLINT(bugprone-suspicious-include): one unit, as joined */
#include "match.h"
/* </standalone> */
/* ---- lines: which command, which reply, which version ------------------------------------- */
/* Lines, commands and replies of a text-line interface, as the spec's tables say: which command a
 * line is, which reply a line is (the common replies first, then the command's own), whether a
 * software version has a command, and the version a version reply tells. Pure functions of the
 * tables and the line's bytes, the one matcher of the C library (runtime/c/lines/lines.c) and the
 * Wireshark dissector (runtime/epan/lines/lines_dissect.c); runtime/lua/lines/match.lua is their
 * twin. */

/* Versions as one number: (major * 1000 + minor) * 1000 + bugfix, minor and bugfix at most 999. */
URWIRE__PRIVATE uint64_t lines_version(uint64_t major, uint64_t minor, uint64_t bugfix)
{
    return (major * 1000 + (minor < 999 ? minor : 999)) * 1000 + (bugfix < 999 ? bugfix : 999);
}

/* The whole text is the pattern: its first piece opens it, its last ends it, the others follow in
 * order between them, and each placeholder takes any text. */
URWIRE__PRIVATE bool lines_matches(const lines_reply_t *reply, const uint8_t *text, size_t len)
{
    const char *first = reply->pieces[0], *last = reply->pieces[reply->piece_count - 1];
    size_t first_len = strlen(first), last_len = strlen(last), at, end, i;
    if (reply->piece_count == 1)
        return len == first_len && memcmp(text, first, first_len) == 0;
    if (len < first_len + last_len || memcmp(text, first, first_len) != 0
        || memcmp(text + len - last_len, last, last_len) != 0)
        return false;
    at = first_len;
    end = len - last_len;
    for (i = 1; i + 1 < reply->piece_count; i++) {
        size_t piece_len = strlen(reply->pieces[i]);
        while (at + piece_len <= end && memcmp(text + at, reply->pieces[i], piece_len) != 0)
            at++;
        if (at + piece_len > end)
            return false;
        at += piece_len;
    }
    return true;
}

/* The command a line is (its index in spec->commands) or LINES_NONE; *argument is the offset of
 * its argument in the line (the text after the words and a space, perhaps empty), or -1. A command
 * with no text (interpreter mode's statement), tried last, is any line, its argument the whole. */
URWIRE__PRIVATE int lines_find_command(const lines_spec_t *spec, const uint8_t *text, size_t len,
                                       long *argument)
{
    size_t i;
    *argument = -1;
    for (i = 0; i < spec->command_count; i++) {
        const lines_command_t *command = &spec->commands[spec->lookup[i]];
        size_t words = strlen(command->text);
        if (words == 0) {
            *argument = 0;
            return spec->lookup[i];
        }
        if (len == words && memcmp(text, command->text, words) == 0)
            return spec->lookup[i];
        if (command->takes_argument && len > words && memcmp(text, command->text, words) == 0
            && text[words] == ' ') {
            *argument = (long)words + 1;
            return spec->lookup[i];
        }
    }
    return LINES_NONE;
}

/* The reply a line is, given the command it answers (an index or LINES_NONE), or NULL. */
URWIRE__PRIVATE const lines_reply_t *lines_classify(const lines_spec_t *spec, int command, const uint8_t *text,
                                                    size_t len)
{
    size_t i;
    for (i = 0; i < spec->common_count; i++)
        if (lines_matches(&spec->common[i], text, len))
            return &spec->common[i];
    if (command == LINES_NONE)
        return NULL;
    for (i = 0; i < spec->commands[command].reply_count; i++)
        if (lines_matches(&spec->commands[command].replies[i], text, len))
            return &spec->commands[command].replies[i];
    return NULL;
}

/* Whether the software version (a lines_version()) has the command. */
URWIRE__PRIVATE bool lines_available(const lines_spec_t *spec, int command, uint64_t version)
{
    const lines_command_t *c = &spec->commands[command];
    uint64_t since = version >= spec->polyscope_x_from ? c->since_polyscope_x
                     : version >= spec->e_series_from ? c->since_e_series : c->since_cb;
    return since != 0 && version >= since;
}

/* "URSoftware 5.11.1.108318 (Nov 26 2021)" -> *version = lines_version(5, 11, 1), or false: the
 * word right after the prefix (runtime/c/common/version_text.c reads it), whose first two or three
 * numbers are 1 to 3 digits; the word ends there, or at a dot after the third (the build). */
URWIRE__PRIVATE bool lines_version_in(const lines_spec_t *spec, const uint8_t *text, size_t len,
                                      uint64_t *version)
{
    size_t prefix = strlen(spec->version_prefix);
    const char *at = (const char *)text + prefix, *end = (const char *)text + len;
    urwire__version_text v;
    if (len <= prefix || memcmp(text, spec->version_prefix, prefix) != 0 || *at < '0' || *at > '9'
        || !urwire__read_version(at, end, false, false, &v) || v.longest > 3)
        return false;
    if (v.end != end && *v.end != ' ' && !(v.parts == 3 && *v.end == '.'))
        return false;
    *version = lines_version(v.part[0], v.part[1], v.part[2]);
    return true;
}
