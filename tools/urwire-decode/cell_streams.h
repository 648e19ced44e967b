/* The dashboard server (29999), interpreter mode (30020), the Robotiq gripper's socket (63352) and
 * the ROS driver's sockets (50001-50004) as canonical JSON
 * Lines: the raw streams of a connection, read record by record and written as the Python decoder
 * writes it (docs/dashboard.md, docs/driver-sockets.md). Part of the CLI. */
#ifndef URWIRE_CELL_STREAMS_H
#define URWIRE_CELL_STREAMS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "envelope.h"

/* The streams of one connection: the robot's, and the client's (NULL: not given), which is read
 * first. With the client's, each record comes in its direction's envelope, and so does what the
 * end of each stream leaves, as `urwire decode --to-robot` writes it. */
typedef struct cell_inputs {
    FILE *robot;
    FILE *client;
    const envelope *from_robot;         /* NULL without the client's stream */
    const envelope *to_robot;
} cell_inputs;

/* Each returns 0 when all decoded, 1 when the output holds error records, 2 on a read error.
 * `version` is major.minor.bugfix as the interface counts it: a software version for the text
 * lines (0: unknown), a driver release for the int32 records (0: the newest the spec knows). */
int ur_dashboard_print_streams(const cell_inputs *in, FILE *out, unsigned major, unsigned minor, unsigned bugfix,
                               bool given);
int ur_script_sender_print_streams(const cell_inputs *in, FILE *out, unsigned major, unsigned minor,
                                   unsigned bugfix, bool given);
int ur_interpreter_print_streams(const cell_inputs *in, FILE *out, unsigned major, unsigned minor,
                                 unsigned bugfix, bool given);
int robotiq_gripper_print_streams(const cell_inputs *in, FILE *out, unsigned major, unsigned minor,
                                  unsigned bugfix, bool given);
int ur_reverse_print_streams(const cell_inputs *in, FILE *out, unsigned major, unsigned minor, unsigned bugfix,
                             bool given);
int ur_trajectory_print_streams(const cell_inputs *in, FILE *out, unsigned major, unsigned minor, unsigned bugfix,
                                bool given);
int ur_script_command_print_streams(const cell_inputs *in, FILE *out, unsigned major, unsigned minor,
                                    unsigned bugfix, bool given);

#endif
