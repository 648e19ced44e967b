/* The interfaces of a UR cell that urwire-decode reads, each as one kind of conversation: bytes of
 * either direction in as they arrive, canonical JSON Lines out, in the order the Python
 * `Conversation` of python/urwire/interfaces.py gives its records. The command feeds a
 * conversation from raw files (main.c) or from a capture's reassembled TCP streams
 * (capture_json.c) through the same functions, so that each interface's reading lives in one
 * place. Part of the CLI. */
#ifndef URWIRE_CELL_INTERFACE_H
#define URWIRE_CELL_INTERFACE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "envelope.h"
#include "urwire.h"

/* Where a conversation's records go: the stream, each direction's envelope ([1]: from the robot;
 * NULL: the record as it is) and whether a record written so far held an error. `text` and
 * `size` are the memory stream the primary interface writes a record into before its envelope. */
typedef struct cell_output {
    FILE *out;
    const envelope *envelope[2];
    bool errors;
    char *text;
    size_t size;
} cell_output;

/* Nonzero from a step: memory ran out (URWIRE_CAPTURE_NO_MEMORY's value). */
#define CELL_NO_MEMORY (-1)

/* One interface: its name (the Wireshark protocol's, a record's "interface"), the ports it listens
 * on, and its conversation's state (`size` bytes, the caller's: static for a raw stream, one
 * allocation a capture's conversation) with the steps of interfaces.py's Conversation. */
typedef struct cell_interface {
    const char *name;
    const uint16_t *ports;
    size_t n_ports;
    bool both_directions;           /* what the client sends is decoded too */
    bool robot_is_client;           /* the robot connects to the port (the ROS driver's sockets) */
    size_t size;
    /* A conversation with nothing read; `hinted`: the version was given (--version-hint). */
    void (*init)(void *state, urwire_sw_version version, bool hinted);
    int (*feed)(void *state, const uint8_t *data, size_t n, bool from_robot, cell_output *out);
    /* The end of one direction's stream: what it leaves, as an error record. */
    int (*close)(void *state, bool from_robot, cell_output *out);
    /* Bytes of one direction are missing before its stream offset `offset`: what it holds is given
     * up as close gives it, and it is read afresh from there. */
    int (*lost)(void *state, bool from_robot, uint64_t offset, cell_output *out);
    /* Optional (NULL): the software version a Version message announced (false: none yet), and
     * the version another conversation of the same robot announced. */
    bool (*announced)(const void *state, urwire_sw_version *version);
    void (*learn)(void *state, urwire_sw_version version);
    /* Optional: a raw file's queue of commands awaiting replies (the client's file comes first). */
    void (*keep_pending)(void *state, int16_t *queue, size_t n);
} cell_interface;

/* Every interface, the primary first, as python/urwire/interfaces.py lists them. */
extern const cell_interface *const cell_interfaces[];
extern const size_t cell_interface_count;

/* The interface of this name, or NULL. */
const cell_interface *cell_interface_named(const char *name);

/* State for one conversation of any interface, for a raw stream (static: only the pages the
 * interface uses are touched), and a queue for keep_pending. */
void *cell_raw_state(void);
int16_t *cell_raw_queue(size_t *n);

/* The interfaces' kinds, each in its own file. */
extern const cell_interface cell_primary;       /* capture_json.c */
extern const cell_interface cell_ur_realtime;   /* ur_realtime_json.c */
extern const cell_interface cell_rtde;          /* rtde_json.c */
extern const cell_interface cell_ur_dashboard, cell_ur_interpreter, cell_robotiq_gripper, cell_ur_reverse,
    cell_ur_script_sender, cell_ur_trajectory, cell_ur_script_command;  /* cell_streams.c */

#endif
