/* <standalone> */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
/* </standalone> */
/* ---- lines: the tables of a text-line interface ------------------------------------------ */
/* The types of the spec's tables (the generated part writes them), which the matcher
 * (runtime/c/lines/match.c) reads, for the C library and the Wireshark dissector alike. Guarded:
 * two interfaces' headers may meet in one file. */
#ifndef URWIRE_LINES_MATCH_H
#define URWIRE_LINES_MATCH_H

#define LINES_NONE (-1)                   /* no command: an unknown one, or a reply with none pending */

/* A reply pattern: literal pieces, each placeholder between two of them taking any text. */
typedef struct lines_reply {
    const char *name;
    const char *const *pieces;
    size_t piece_count;
    bool error;                           /* the reply says that the command failed */
} lines_reply_t;

typedef struct lines_command {
    const char *name;
    const char *text;                     /* the words that open the line */
    bool takes_argument;
    uint64_t since_cb;                    /* lines_version() of the first CB2/CB3 version; 0: none */
    uint64_t since_e_series;              /* the same for the e-Series (5.x); 0: none */
    uint64_t since_polyscope_x;           /* the same for PolyScope X (10.x); 0: none */
    const lines_reply_t *replies;
    size_t reply_count;
} lines_command_t;

/* One interface's tables, as the generator writes them from its spec. */
typedef struct lines_spec {
    const char *column;                   /* the Protocol column */
    size_t max_line;                      /* longer lines are flagged and skipped up to their newline */
    const lines_reply_t *banner;          /* the line the server greets a client with, or NULL */
    bool robot_is_client;                 /* the robot connects to the port (the driver's sockets) */
    bool requests_from_robot;             /* the robot asks and the other side answers */
    bool one_reply_per_request;           /* else every answering line belongs to the latest request */
    const lines_reply_t *common;          /* replies any command may get, read before its own */
    size_t common_count;
    const lines_command_t *commands;      /* spec order */
    size_t command_count;
    const int *lookup;                    /* command indices in the order a line is tried: longest text first */
    int version_command;                  /* the command whose reply tells the version, or LINES_NONE */
    const char *version_prefix;           /* the text before the version in that reply */
    uint64_t e_series_from;               /* lines_version(5, 0, 0): the first read from since_e_series */
    uint64_t polyscope_x_from;            /* lines_version(10, 0, 0): the first read from since_polyscope_x */
} lines_spec_t;

#endif
