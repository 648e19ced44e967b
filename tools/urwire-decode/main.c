/* urwire-decode: a raw stream of one UR interface in, canonical JSON Lines out.
 *
 *     urwire-decode [--protocol ur|ur_realtime|rtde|ur_dashboard|...] [--version-hint 5.9|5.25.1] FILE|-
 *                   [--to-robot FILE2]
 *
 * A .pcap or .pcapng FILE (told by its header, as `urwire decode` tells it) is read for the primary
 * interface's conversations, each record in its conversation's envelope (capture_json.h).
 *
 * Exit status: 0 all decoded, 1 the output holds error records, 2 usage or I/O error. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "capture_json.h"
#include "cell_streams.h"
#include "envelope.h"
#include "records.h"
#include "rtde_json.h"
#include "ur_realtime_json.h"
#include "urwire.h"

static const char usage[] =
    "usage: urwire-decode [--protocol NAME] [--version-hint MAJOR.MINOR[.BUGFIX]] FILE|- [--to-robot FILE2]\n"
    "Decode a raw stream of a Universal Robots interface (FILE, or - for stdin) and print\n"
    "one canonical JSON record per line. A .pcap or .pcapng FILE gives the records of its primary\n"
    "interface's conversations (30001, 30002, 30011, 30012), each in its envelope, as\n"
    "`urwire decode --protocol ur CAPTURE` does.\n"
    "  --protocol NAME   the interface the stream is from: ur (primary/secondary, 30001/30002,\n"
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

static int run_realtime(FILE *in, urwire_sw_version version, bool hinted)
{
    uint32_t number = hinted ? ur_realtime_version((unsigned)version.major, (unsigned)version.minor,
                                                   (unsigned)version.bugfix) : 0u;
    return ur_realtime_print_stream(in, stdout, number);
}

/* RTDE: the client's stream (when given) and then the robot's, through one connection's state, so
 * that a data package is read with the recipe the client set up. With the robot's stream alone,
 * data packages come out whole, with an error, as in `urwire decode --protocol rtde`. */
static rtde_json_stream rtde_connection;

static int feed_rtde(FILE *in, bool from_robot, int *faults)
{
    for (;;) {
        size_t n = fread(chunk, 1, sizeof chunk, in);
        *faults += rtde_json_feed(&rtde_connection, chunk, n, from_robot, stdout);
        if (n < sizeof chunk)
            return ferror(in) ? 2 : 0;
    }
}

static int run_rtde(const cell_inputs *in, urwire_sw_version version, bool hinted)
{
    int faults = 0;
    (void)version;
    (void)hinted;
    rtde_json_stream_init(&rtde_connection);
    rtde_connection.envelope[0] = in->to_robot;
    rtde_connection.envelope[1] = in->from_robot;
    if (in->client && feed_rtde(in->client, false, &faults) == 2)
        return 2;
    if (feed_rtde(in->robot, true, &faults) == 2)
        return 2;
    faults += rtde_json_close(&rtde_connection, stdout);
    return faults ? 1 : 0;
}

/* The interfaces this command reads, by the name --protocol takes (the Wireshark protocol's). An
 * interface adds its row: its runner gets the open inputs, the version and whether it was given. */
typedef int (*protocol_runner)(const cell_inputs *in, urwire_sw_version version, bool hinted);

static int run_primary_row(const cell_inputs *in, urwire_sw_version version, bool hinted)
{
    (void)hinted;
    return run_primary(NULL, 0, in->robot, version);
}

static int run_realtime_row(const cell_inputs *in, urwire_sw_version version, bool hinted)
{
    return run_realtime(in->robot, version, hinted);
}

/* The dashboard server and the driver's sockets: the client's stream, when given, and the
 * robot's; the hint is the software version of the dashboard and the driver release of the
 * sockets. */
#define CELL_ROW(P)                                                                               \
    static int run_##P(const cell_inputs *in, urwire_sw_version version, bool hinted)            \
    {                                                                                              \
        return P##_print_streams(in, stdout, (unsigned)version.major, (unsigned)version.minor,    \
                                 (unsigned)version.bugfix, hinted);                                \
    }
CELL_ROW(ur_dashboard)
CELL_ROW(ur_script_sender)
CELL_ROW(ur_interpreter)
CELL_ROW(robotiq_gripper)
CELL_ROW(ur_reverse)
CELL_ROW(ur_trajectory)
CELL_ROW(ur_script_command)

/* both_directions: the interface decodes what the client sends too (--to-robot), as in the
 * Python `Interface.both_directions` (python/urwire/interfaces.py). */
static const struct {
    const char *name;
    protocol_runner run;
    bool both_directions;
} protocols[] = {
    {"ur", run_primary_row, false},
    {"ur_realtime", run_realtime_row, false},
    {"rtde", run_rtde, true},
    {"ur_dashboard", run_ur_dashboard, true},
    {"ur_script_sender", run_ur_script_sender, true},
    {"ur_interpreter", run_ur_interpreter, true},
    {"robotiq_gripper", run_robotiq_gripper, true},
    {"ur_reverse", run_ur_reverse, true},
    {"ur_trajectory", run_ur_trajectory, true},
    {"ur_script_command", run_ur_script_command, true},
};

static int fail(const char *what, const char *detail)
{
    fprintf(stderr, "urwire-decode: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    return 2;
}

int main(int argc, char **argv)
{
    const char *path = NULL, *to_robot = NULL, *hint = NULL, *protocol = "ur";
    urwire_sw_version version = URWIRE_DEFAULT_VERSION;
    protocol_runner run = NULL;
    bool both_directions = false;
    envelope from_robot_envelope, to_robot_envelope;
    cell_inputs in = {NULL, NULL, NULL, NULL};
    size_t p;
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
    for (p = 0; p < sizeof protocols / sizeof protocols[0]; p++)
        if (strcmp(protocols[p].name, protocol) == 0) {
            run = protocols[p].run;
            both_directions = protocols[p].both_directions;
        }
    if (!run) {
        fprintf(stderr, "urwire-decode: unknown protocol: %s (known:", protocol);
        for (p = 0; p < sizeof protocols / sizeof protocols[0]; p++)
            fprintf(stderr, " %s", protocols[p].name);
        fputs(")\n", stderr);
        return 2;
    }
    if (!path)
        return fail("no input: give a FILE or - for stdin; try --help", NULL);
    if (hint && !urwire_parse_version(hint, &version))
        return fail("not a software version (expected e.g. 5.9 or 5.25.1)", hint);
    if (to_robot && !both_directions) {
        fprintf(stderr, "urwire-decode: --to-robot: %s reads the robot's stream only; the protocols that read "
                "both directions:", protocol);
        for (p = 0; p < sizeof protocols / sizeof protocols[0]; p++)
            if (protocols[p].both_directions)
                fprintf(stderr, " %s", protocols[p].name);
        fputs("\n", stderr);
        return 2;
    }
    in.robot = strcmp(path, "-") == 0 ? stdin : fopen(path, "rb");
    if (!in.robot)
        return fail(path, strerror(errno));
    if (to_robot) {
        /* As `urwire decode` names them: the interface, the direction, the file as given. */
        in.client = fopen(to_robot, "rb");
        if (!in.client) {
            int opening = errno;
            if (in.robot != stdin)
                (void)fclose(in.robot);
            return fail(to_robot, strerror(opening));
        }
        from_robot_envelope.interface = to_robot_envelope.interface = protocol;
        from_robot_envelope.direction = "from_robot";
        to_robot_envelope.direction = "to_robot";
        from_robot_envelope.conversation = path;
        to_robot_envelope.conversation = to_robot;
        in.from_robot = &from_robot_envelope;
        in.to_robot = &to_robot_envelope;
    }
    if (run == run_primary_row && !to_robot) {
        uint8_t head[12];
        size_t got = fread(head, 1, sizeof head, in.robot);
        status = capture_json_is_capture(head, got) ? capture_json_print(head, got, in.robot, stdout, version)
                                                    : run_primary(head, got, in.robot, version);
    } else {
        status = run(&in, version, hint != NULL);
    }
    if (in.robot != stdin)
        (void)fclose(in.robot);     /* read only: closing loses nothing */
    if (in.client)
        (void)fclose(in.client);
    if (status == 2)
        return fail(path, "read error");
    /* The records' writes are not checked one by one: a stream's error indicator stays set, and
     * is checked here, once, with the flush of what is left. */
    if (fflush(stdout) != 0 || ferror(stdout))
        return fail("write error", strerror(errno));
    return status;
}
