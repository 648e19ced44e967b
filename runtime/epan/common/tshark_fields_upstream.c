/* <standalone> */
#include "tshark_fields.h"
/* </standalone> */
/* Wireshark's own copy of the dissectors reads no command line, where urwire's plugin reads tshark's
 * to tell a tshark -T fields run, which prints no label: here no run is taken for one, so every item
 * keeps its label whole. */

/* The arguments of a tshark -T fields run: never known here. */
const GPtrArray *
ur_tshark_fields_arguments(void)
{
    return NULL;
}
