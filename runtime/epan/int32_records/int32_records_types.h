/* The tables a dissector of fixed int32 records walks (the ROS driver's reverse, trajectory and
 * script command sockets), as the generated part of each packet-<name>.c fills them from its
 * spec: each direction's record, its layouts along the driver-release axis, and each layout's
 * slots (a field, its first int32, how many, its power-of-ten scale). */
/* <standalone> */
#include <epan/packet.h>
/* </standalone> */

typedef struct {
    int *hf;                    /* the field: a double when scaled, else the int32 itself */
    int *hf_raw;                /* a scaled field's raw int32; NULL when not scaled */
    guint16 first;              /* its first int32 in the record */
    guint16 count;
    gint32 scale;               /* the wire holds round(value * scale); 0: not scaled */
    const char *scale_name;     /* the driver's constant for the scale (MULT_JOINTSTATE) */
} int32_records_slot;

typedef struct {
    guint size;                 /* bytes */
    const int32_records_slot *slots;
    guint n_slots;
} int32_records_layout;

typedef struct {
    const char *label;          /* the record's tree item and the Info column's words */
    const guint32 *starts;      /* the first release of every layout but the first */
    guint n_starts;
    const int32_records_layout *layouts;
} int32_records_record;

typedef struct {
    int *proto;
    gint *ett;                  /* a record's subtree */
    gint *ett_scaled;           /* a scaled value's subtree, holding its raw int32 */
    const int32_records_record *to_robot;      /* what the control PC sends; NULL: nothing is specified */
    const int32_records_record *from_robot;    /* what the robot sends; NULL: nothing is specified */
} int32_records_interface;
