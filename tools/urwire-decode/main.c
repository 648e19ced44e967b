/* urwire-decode: a raw stream of one UR interface, or a capture of a cell, in; canonical JSON
 * Lines out.
 *
 *     urwire-decode [--protocol ur|ur_realtime|rtde|ur_dashboard|...] [--version-hint 5.9|5.25.1] FILE|-
 *                   [--to-robot FILE2]
 *
 * A .pcap or .pcapng FILE (told by its header, as `urwire decode` tells it) is read for every
 * interface's conversations (--protocol's only, when given), each record in its conversation's
 * envelope (capture_json.h). Every interface reads a raw stream and a capture's conversation
 * through the same conversation (cell_interface.h).
 *
 * Exit status: 0 all decoded, 1 the output holds error records, 2 usage or I/O error. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "capture_json.h"
#include "cell_interface.h"
#include "envelope.h"
#include "json.h"
#include "records.h"
#include "urwire.h"

static const char usage[] =
    "usage: urwire-decode [--protocol NAME] [--version-hint MAJOR.MINOR[.BUGFIX]] FILE|- [--to-robot FILE2]\n"
    "Decode a raw stream of a Universal Robots interface (FILE, or - for stdin) and print\n"
    "one canonical JSON record per line. A .pcap or .pcapng FILE gives the records of every TCP\n"
    "conversation an interface of the cell reads, by its port, each in its envelope (interface,\n"
    "direction, conversation), as `urwire decode CAPTURE` does.\n"
    "  --protocol NAME   the interface the stream is from (of a capture: read only its\n"
    "                    conversations): ur (primary/secondary, 30001/30002,\n"
    "                    the default), ur_realtime (real-time, 30003), rtde (RTDE, 30004:\n"
    "                    the robot's stream; its recipes come from the client's: --to-robot),\n"
    "                    ur_dashboard (29999), ur_interpreter (30020), robotiq_gripper (63352),\n"
    "                    or the driver's ur_reverse, ur_script_sender,\n"
    "                    ur_trajectory, ur_script_command (50001-50004, whose hint is the driver\n"
    "                    release)\n"
    "  --version-hint V  the software version (5.9, 5.25.1) until the stream shows a Version\n"
    "                    message: it chooses each part's layout and the global-variable value\n"
    "                    types (default: 5.9 and later, or what the layout sizes show)\n"
    "  --to-robot FILE2  the client's stream of the same connection (rtde, the text lines and the\n"
    "                    driver's sockets), read first; each record then names its interface,\n"
    "                    direction and file\n"
    "Exit status: 0 all decoded, 1 the output holds error records, 2 usage or I/O error.\n";

static uint8_t framer_buffer[URWIRE_FRAMER_MIN_BUFFER];
static uint8_t chunk[1 << 16];

/* The primary/secondary stream, `head` (n_head bytes already read from it) and the rest of `in`:
 * framed and printed record by record. 0, 1 (error records) or 2 (read error). */
static int run_primary(const uint8_t *head, size_t n_head, FILE *in, urwire_sw_version version)
{
    urwire_framer fr;
    urwire_visitor v;
    json_writer w;
    bool errors = false;
    memset(&w, 0, sizeof w);
    w.out = stdout;
    v = json_visitor(&w);
    urwire_framer_init(&fr, framer_buffer, sizeof framer_buffer, version);
    while (n_head) {
        size_t took = urwire_framer_feed(&fr, head, n_head);
        head += took;
        n_head -= took;
        errors |= print_ready_records(&fr, &v, &w);
    }
    for (;;) {
        size_t n = fread(chunk, 1, sizeof chunk, in), off = 0;
        while (off < n) {
            off += urwire_framer_feed(&fr, chunk + off, n - off);
            errors |= print_ready_records(&fr, &v, &w);
        }
        if (n < sizeof chunk) {
            if (ferror(in))
                return 2;
            break;
        }
    }
    urwire_framer_finish(&fr);
    errors |= print_ready_records(&fr, &v, &w);
    return errors ? 1 : 0;
}

/* A file's bytes (after `head`, n_head bytes already read from it) into the conversation, as one
 * direction's. 0, or 2 on a read error. */
static int feed_file(const cell_interface *kind, void *state, const uint8_t *head, size_t n_head, FILE *in,
                     bool from_robot, cell_output *out)
{
    if (n_head)
        (void)kind->feed(state, head, n_head, from_robot, out);
    for (;;) {
        size_t n = fread(chunk, 1, sizeof chunk, in);
        if (n)
            (void)kind->feed(state, chunk, n, from_robot, out);
        if (n < sizeof chunk)
            return ferror(in) ? 2 : 0;
    }
}

/* The raw streams of one connection through its interface's conversation, as cell.py's
 * records_of_raw_protocol reads them: the client's file first (what a client asks, an RTDE recipe,
 * comes before what the robot sends for it), then the robot's, then each one's end, the client's
 * first. With the client's file, each record comes in its direction's envelope. */
static int run_streams(const cell_interface *kind, const uint8_t *head, size_t n_head, FILE *robot, FILE *client,
                       const envelope *envelopes, urwire_sw_version version, bool hinted)
{
    void *state = cell_raw_state();
    cell_output out;
    memset(&out, 0, sizeof out);
    out.out = stdout;
    if (client) {
        out.envelope[0] = &envelopes[0];
        out.envelope[1] = &envelopes[1];
    }
    kind->init(state, version, hinted);
    if (kind->keep_pending) {
        size_t n;
        int16_t *queue = cell_raw_queue(&n);
        kind->keep_pending(state, queue, n);
    }
    if (client && feed_file(kind, state, NULL, 0, client, false, &out) == 2)
        return 2;
    if (feed_file(kind, state, head, n_head, robot, true, &out) == 2)
        return 2;
    (void)kind->close(state, false, &out);
    (void)kind->close(state, true, &out);
    return out.errors ? 1 : 0;
}

static int fail(const char *what, const char *detail)
{
    fprintf(stderr, "urwire-decode: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    return 2;
}

int main(int argc, char **argv)
{
    const char *path = NULL, *to_robot = NULL, *hint = NULL, *protocol = NULL;
    urwire_sw_version version = URWIRE_DEFAULT_VERSION;
    const cell_interface *kind;
    envelope envelopes[2];          /* [1]: from the robot */
    FILE *robot, *client = NULL;
    uint8_t head[12];
    size_t p, got = 0;
    int i, status;
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
        } else if (strcmp(argv[i], "--protocol") == 0) {
            if (++i >= argc)
                return fail("--protocol needs a name such as ur or ur_realtime", NULL);
            protocol = argv[i];
        } else if (strncmp(argv[i], "--protocol=", 11) == 0) {
            protocol = argv[i] + 11;
        } else if (strcmp(argv[i], "--to-robot") == 0) {
            if (++i >= argc)
                return fail("--to-robot needs the file of the client's stream", NULL);
            to_robot = argv[i];
        } else if (strncmp(argv[i], "--to-robot=", 11) == 0) {
            to_robot = argv[i] + 11;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            return fail("unknown option", argv[i]);
        } else if (path) {
            return fail("one input only; try --help", NULL);
        } else {
            path = argv[i];
        }
    }
    kind = cell_interface_named(protocol ? protocol : "ur");
    if (!kind) {
        fprintf(stderr, "urwire-decode: unknown protocol: %s (known:", protocol);
        for (p = 0; p < cell_interface_count; p++)
            fprintf(stderr, " %s", cell_interfaces[p]->name);
        fputs(")\n", stderr);
        return 2;
    }
    if (!path)
        return fail("no input: give a FILE or - for stdin; try --help", NULL);
    if (hint && !urwire_parse_version(hint, &version))
        return fail("not a software version (expected e.g. 5.9 or 5.25.1)", hint);
    if (to_robot && !kind->both_directions) {
        fprintf(stderr, "urwire-decode: --to-robot: %s reads the robot's stream only; the protocols that read "
                "both directions:", kind->name);
        for (p = 0; p < cell_interface_count; p++)
            if (cell_interfaces[p]->both_directions)
                fprintf(stderr, " %s", cell_interfaces[p]->name);
        fputs("\n", stderr);
        return 2;
    }
    robot = strcmp(path, "-") == 0 ? stdin : fopen(path, "rb");
    if (!robot)
        return fail(path, strerror(errno));
    if (to_robot) {
        /* As `urwire decode` names them: the interface, the direction, the file as given. */
        client = fopen(to_robot, "rb");
        if (!client) {
            int opening = errno;
            if (robot != stdin)
                (void)fclose(robot);
            return fail(to_robot, strerror(opening));
        }
        envelopes[0].interface = envelopes[1].interface = kind->name;
        envelopes[1].direction = "from_robot";
        envelopes[0].direction = "to_robot";
        envelopes[1].conversation = path;
        envelopes[0].conversation = to_robot;
    } else {
        got = fread(head, 1, sizeof head, robot);
    }
    if (!to_robot && capture_json_is_capture(head, got))
        status = capture_json_print(head, got, robot, stdout, protocol ? kind : NULL, version, hint != NULL);
    else if (kind == &cell_primary && !to_robot)
        status = run_primary(head, got, robot, version);
    else
        status = run_streams(kind, head, got, robot, client, envelopes, version, hint != NULL);
    if (robot != stdin)
        (void)fclose(robot);     /* read only: closing loses nothing */
    if (client)
        (void)fclose(client);
    if (status == 2)
        return fail(path, "read error");
    /* The records' writes are not checked one by one: a stream's error indicator stays set, and
     * is checked here, once, with the flush of what is left. */
    if (fflush(stdout) != 0 || ferror(stdout))
        return fail("write error", strerror(errno));
    return status;
}
