/* Canonical JSON Lines writer for urwire records (docs/canonical-json.md), built on the
 * library's visitor. Hand-written; part of the CLI, not of the parser. */
#ifndef URWIRE_JSON_H
#define URWIRE_JSON_H

#include <stdio.h>

#include "urwire.h"

#define JSON_WRITER_BUFFER 8192

/* A visitor that prints one record as one line of canonical JSON on out. */
typedef struct json_writer {
    FILE *out;
    int depth;
    unsigned char first[128];   /* per open object/array: nothing written in it yet */
    size_t len;                 /* bytes waiting in buf: handed to out when the record's last */
    char buf[JSON_WRITER_BUFFER]; /* object or array closes (depth 0 again) or buf fills */
} json_writer;

/* The visitor over w; it starts w's buffer empty. */
urwire_visitor json_visitor(json_writer *w);

/* float32: the shortest "%.{p}g" (p = 1..9) that reads back as x when read as a double and
 * rounded to float32 (the canonical rule; Python's reading).
 * float64: the shortest digits that read back as x, written as Python's repr() writes them
 * ("1.0", "1e-05"), so that lines equal the Python CLI's byte for byte.
 * Both cut the text to cap - 1 bytes and end it with a NUL, as snprintf does. */
void json_f32_text(float x, char *buf, size_t cap);
void json_f64_text(double x, char *buf, size_t cap);

/* Bytes as a JSON string: invalid UTF-8 replaced by U+FFFD exactly as Python's
 * bytes.decode("utf-8", "replace") does (one U+FFFD per maximal invalid subpart). */
void json_write_text(FILE *out, const unsigned char *p, size_t n);

#endif
