/* Where a layout of an RTDE dissector (packet-rtde.c) stands in the request/response pairs (the
 * spec's exchanges.pairs): the generator writes one per layout, in the order of rtde_layouts, and
 * runtime/epan/typed_messages/rtde_exchanges.c reads them. */
/* <standalone> */
#include <glib.h>
/* </standalone> */

typedef struct {
    int pair;                   /* the pair it is in, or -1 (data packages, text messages) */
    gboolean reply;             /* it answers the pair's requests */
} rtde_exchange_role;
