/* The tables the real-time dissector walks, as the generated part of packet-ur-realtime.c fills
 * them from the spec: each layout's slots (a field's offset and count of doubles), the forms (a
 * layout as one range of software versions sends it, with that range's enum names) and, for each
 * packet size, its forms in the order the spec's same-size rule tries them. */
/* <standalone> */
#include <epan/packet.h>
#define UR_REALTIME_ENUMS 4
/* </standalone> */

typedef struct {
    int *hf;                    /* the field, or its named items' fields (`named`), one per double */
    gboolean named;
    gint *ett;                  /* an array's subtree; NULL for one double */
    const char *group;          /* an array's subtree text: the label and its unit */
    guint16 offset;             /* in the packet, size field included */
    guint16 count;              /* doubles */
    gint8 names;                /* the field's enum, an index into a form's names; -1 none */
    int *flags;                 /* the flags a double's whole value carries, one per named bit; NULL none */
    guint8 n_flags;
    gint *flags_ett;            /* their subtree */
} ur_realtime_slot;

typedef struct {
    const char *name;           /* the Layout field and the Info column's word */
    const ur_realtime_slot *slots;
    guint n_slots;
    gint info_at;               /* where the robot mode the Info column reads sits; -1: not sent */
    gint8 info_names;           /* its enum, an index into a form's names; -1 none */
} ur_realtime_layout;

typedef struct {
    guint32 low, high;          /* the software versions that send it, as version numbers */
    const ur_realtime_layout *layout;
    const value_string *names[UR_REALTIME_ENUMS];   /* each enum's names in these versions, or NULL */
} ur_realtime_form;

typedef struct {
    gint32 size;
    guint first, count;         /* its forms in ur_realtime_forms, in the order the rule tries them */
} ur_realtime_size_forms;
