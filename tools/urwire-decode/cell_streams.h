/* The dashboard server (29999), interpreter mode (30020), the Robotiq gripper's socket (63352) and
 * the ROS driver's sockets (50001-50004) as conversations of cell_interface.h: each direction's
 * bytes read record by record and written as the Python decoder writes them (docs/dashboard.md,
 * docs/driver-sockets.md). Part of the CLI. */
#ifndef URWIRE_CELL_STREAMS_H
#define URWIRE_CELL_STREAMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "cell_interface.h"
#include "ur_dashboard.h"

/* The bytes of one direction not read yet: at most a line (or record) short of its end, and the
 * next piece of the stream after them. */
#define CELL_HELD (1u << 16)
typedef struct cell_held {
    size_t length;
    unsigned char bytes[2 * CELL_HELD + 2];
} cell_held;

/* A text-line conversation (the four interfaces of the kind share the library's types). */
typedef struct cell_lines_state {
    lines_conversation lines;
    cell_held held[2];              /* [1]: from the robot */
} cell_lines_state;

/* An int32-record conversation: each direction's bytes short of a record, where they start in
 * the stream, and, after bytes lost, the bytes to drop to the next record's start. */
typedef struct cell_records_state {
    uint32_t release;
    struct {
        cell_held held;
        uint64_t offset;
        uint64_t skip, skipped;
    } way[2];
} cell_records_state;

#endif
