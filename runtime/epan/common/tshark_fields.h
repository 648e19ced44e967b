/* <standalone> */
#ifndef URWIRE_EPAN_TSHARK_FIELDS_H
#define URWIRE_EPAN_TSHARK_FIELDS_H
#include <epan/packet.h>
/* </standalone> */
/* The arguments of this process when it is a `tshark -T fields` run, else NULL (runtime/epan/common/
 * tshark_fields.c): such a run prints no item's label, and no field that no argument names. */
const GPtrArray *ur_tshark_fields_arguments(void);
/* <standalone> */
#endif
/* </standalone> */
