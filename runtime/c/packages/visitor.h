/* <standalone> */
#ifndef URWIRE_RUNTIME_VISITOR_H
#define URWIRE_RUNTIME_VISITOR_H
#include "runtime_spec.h"
/* </standalone> */
/* ---- visiting: the canonical record shape, for JSON writers and the like ------------------ */

/* Called in canonical JSON order; key is NULL inside arrays. */
typedef struct urwire_visitor {
    void *ctx;
    void (*begin_object)(void *ctx, const char *key);
    void (*end_object)(void *ctx);
    void (*begin_array)(void *ctx, const char *key);
    void (*end_array)(void *ctx);
    void (*on_int)(void *ctx, const char *key, int64_t v);
    void (*on_uint)(void *ctx, const char *key, uint64_t v);
    void (*on_bool)(void *ctx, const char *key, bool v);
    void (*on_f32)(void *ctx, const char *key, float v);
    void (*on_f64)(void *ctx, const char *key, double v);
    void (*on_text)(void *ctx, const char *key, urwire_bytes utf8);  /* may hold invalid UTF-8 */
    void (*on_hex)(void *ctx, const char *key, urwire_bytes bytes);
    void (*on_null)(void *ctx, const char *key);
    /* Optional (NULL: not called). Before each sub-package of a robot state, the package as
     * urwire_next_package gives it: true when the visitor has written it itself, and it is not
     * walked; false to have it walked as usual. A package's record depends only on its type,
     * version and bytes: the CLI's JSON writer keeps the text of each type and writes it again
     * while they recur, as a robot's configuration and kinematics do from state to state. */
    bool (*package)(void *ctx, const urwire_package *pkg);
} urwire_visitor;

/* One message as its canonical record. */
void urwire_visit_message(const urwire_message *m, const urwire_visitor *v);
/* A stream fault as its canonical record {"type": "error", "offset": N, "error": TEXT}. */
void urwire_visit_fault(const urwire_error *fault, const urwire_visitor *v);
/* <standalone> */
#endif
/* </standalone> */
