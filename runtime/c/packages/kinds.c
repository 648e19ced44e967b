/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- the tables of kinds ------------------------------------------------------------------ */
/* Lookups in the generated tables: urwire__message_types (top-level types with a layout),
 * urwire__message_kinds (by urwire_message_kind) and urwire__package_kinds (by
 * urwire_package_layout). decode.c, encode.c and visit.c walk them. */

/* NULL for a type with no layout. */
URWIRE__PRIVATE const urwire__message_type *urwire__message_type_of(uint8_t code)
{
    size_t k;
    for (k = 0; k < URWIRE__COUNT(urwire__message_types); k++)
        if (urwire__message_types[k].code == code)
            return &urwire__message_types[k];
    return NULL;
}

/* NULL for a value outside the enum. */
URWIRE__PRIVATE const urwire__message_kind *urwire__message_kind_of(urwire_message_kind kind)
{
    return (size_t)kind < URWIRE__COUNT(urwire__message_kinds) ? &urwire__message_kinds[kind] : NULL;
}

/* NULL for a value outside the enum. */
URWIRE__PRIVATE const urwire__package_kind *urwire__package_kind_of(urwire_package_layout layout)
{
    return (size_t)layout < URWIRE__COUNT(urwire__package_kinds) ? &urwire__package_kinds[layout] : NULL;
}

/* The header functions of a type of urwire__message_types. */
URWIRE__PRIVATE const urwire__message_header *urwire__header_of(const urwire__message_type *t)
{
    return &urwire__message_headers[t - urwire__message_types];
}

/* The type whose header m carries: its layout's, or for an unknown subtype its message
 * type's; NULL when there is none. */
URWIRE__PRIVATE const urwire__message_type *urwire__header_type(const urwire_message *m)
{
    const urwire__message_kind *k = urwire__message_kind_of(m->kind);
    const urwire__message_type *t;
    if (m->kind == URWIRE_KIND_UNKNOWN_SUBTYPE) {
        t = urwire__message_type_of(m->message_type);
        return t != NULL && !t->packages ? t : NULL;
    }
    return k != NULL && k->type != NULL && !k->type->packages ? k->type : NULL;
}
