/* Canonical JSON Lines writer for urwire records (docs/canonical-json.md), built on the
 * library's visitor, and the texts every JSON writer in C shares (strings, floats, hex). C runtime
 * beside the parser, not joined into it: urwire-decode and urwire._ccore compile it. */
#ifndef URWIRE_JSON_H
#define URWIRE_JSON_H

#include <stdio.h>

#include "urwire.h"

#define JSON_WRITER_BUFFER 8192

/* The text of a sub-package, kept with what it depends on: its version and body bytes (the
 * slot is its type). A robot sends most sub-packages unchanged from one state to the next. */
#define JSON_KEPT_TYPES 32      /* the types kept: every robot-state sub-package type so far */
#define JSON_KEPT_BODY 1024     /* larger bodies are written anew every time */
#define JSON_KEPT_TEXT 4096
typedef struct json_kept_package {
    urwire_sw_version version;
    size_t body_length;
    size_t text_length;         /* 0: nothing kept */
    uint8_t body[JSON_KEPT_BODY];
    char text[JSON_KEPT_TEXT];
} json_kept_package;

/* A visitor that prints one record as one line of canonical JSON on out. */
typedef struct json_writer {
    FILE *out;
    int depth;
    unsigned char first[128];   /* per open object/array: nothing written in it yet */
    size_t len;                 /* bytes waiting in buf: handed to out when the record's last */
    char buf[JSON_WRITER_BUFFER]; /* object or array closes (depth 0 again) or buf fills */
    unsigned long flushes;      /* times buf went to out */
    json_kept_package *keeping; /* the package being written, whose text is kept when it ends, */
    int keeping_depth;          /* from keeping_from in buf, unless buf went to out meanwhile */
    size_t keeping_from;
    unsigned long keeping_flushes;
    json_kept_package kept[JSON_KEPT_TYPES];
} json_writer;

/* The visitor over w; it starts w's buffer empty and w's kept texts forgotten. */
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

/* Bytes as a JSON string of lowercase hex digits, two a byte. */
void json_write_hex(FILE *out, const unsigned char *p, size_t n);

/* A float64 as json_f64_text writes it. */
void json_write_f64(FILE *out, double x);

#endif
