/* urwire-decode: a raw primary/secondary stream in, canonical JSON Lines out.
 *
 *     urwire-decode [--version-hint 5.9|5.25.1] FILE|-
 *
 * Exit status: 0 all decoded, 1 the output holds error records, 2 usage or I/O error. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "urwire.h"

static const char usage[] =
    "usage: urwire-decode [--version-hint MAJOR.MINOR[.BUGFIX]] FILE|-\n"
    "Decode a raw Universal Robots primary/secondary stream (FILE, or - for stdin) and print\n"
    "one canonical JSON record per line.\n"
    "  --version-hint V  the software version (5.9, 5.25.1) until the stream shows a Version\n"
    "                    message: it chooses each part's layout and the global-variable value\n"
    "                    types (default: 5.9 and later, or what the layout sizes show)\n"
    "Exit status: 0 all decoded, 1 the output holds error records, 2 usage or I/O error.\n";

static uint8_t framer_buffer[URWIRE_FRAMER_MIN_BUFFER];
static uint8_t chunk[1 << 16];

static int fail(const char *what, const char *detail)
{
    fprintf(stderr, "urwire-decode: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    return 2;
}

/* Print every record the framer has ready; returns true when one held an error. */
static bool drain(urwire_framer *fr, const urwire_visitor *v, json_writer *w)
{
    urwire_frame frame;
    urwire_message m;
    bool errors = false;
    for (;;) {
        urwire_frame_kind kind = urwire_framer_next(fr, &frame);
        if (kind == URWIRE_FRAME_NEED_MORE || kind == URWIRE_FRAME_END)
            return errors;
        w->depth = 0;
        if (kind == URWIRE_FRAME_FAULT) {
            urwire_visit_fault(&frame.fault, v);
            errors = true;
        } else {
            urwire_decode_message(frame.bytes, frame.length, frame.version, &m);
            urwire_framer_learn(fr, &m);
            urwire_visit_message(&m, v);
            errors |= urwire_message_has_error(&m);
        }
        putc('\n', w->out);
    }
}

int main(int argc, char **argv)
{
    const char *path = NULL, *hint = NULL;
    urwire_sw_version version = URWIRE_DEFAULT_VERSION;
    urwire_framer fr;
    urwire_visitor v;
    json_writer w;
    FILE *in;
    bool errors = false;
    int i;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) {
            fputs(usage, stdout);
            return 0;
        } else if (strcmp(argv[i], "--version-hint") == 0) {
            if (++i >= argc)
                return fail("--version-hint needs a value such as 5.9 or 5.25.1", NULL);
            hint = argv[i];
        } else if (strncmp(argv[i], "--version-hint=", 15) == 0) {
            hint = argv[i] + 15;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            return fail("unknown option", argv[i]);
        } else if (path) {
            return fail("one input only; try --help", NULL);
        } else {
            path = argv[i];
        }
    }
    if (!path)
        return fail("no input: give a FILE or - for stdin; try --help", NULL);
    if (hint && !urwire_parse_version(hint, &version))
        return fail("not a software version (expected e.g. 5.9 or 5.25.1)", hint);
    in = strcmp(path, "-") == 0 ? stdin : fopen(path, "rb");
    if (!in)
        return fail(path, strerror(errno));

    memset(&w, 0, sizeof w);
    w.out = stdout;
    v = json_visitor(&w);
    urwire_framer_init(&fr, framer_buffer, sizeof framer_buffer, version);
    for (;;) {
        size_t n = fread(chunk, 1, sizeof chunk, in), off = 0;
        while (off < n) {
            off += urwire_framer_feed(&fr, chunk + off, n - off);
            errors |= drain(&fr, &v, &w);
        }
        if (n < sizeof chunk) {
            if (ferror(in))
                return fail(path, "read error");
            break;
        }
    }
    urwire_framer_finish(&fr);
    errors |= drain(&fr, &v, &w);
    if (in != stdin)
        fclose(in);
    if (fflush(stdout) != 0)
        return fail("write error", strerror(errno));
    return errors ? 1 : 0;
}
