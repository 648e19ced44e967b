/* <standalone> */
#ifndef URWIRE_EPAN_EXCHANGE_H
#define URWIRE_EPAN_EXCHANGE_H
#include <epan/packet.h>
/* </standalone> */
/* Request/response tracking, as Wireshark's request/response protocols show it (dns.response_in,
 * dns.response_to, dns.time), the twin of runtime/lua/common/exchange.lua. On the first pass a
 * request keeps its frame and time; the reply the dissector pairs with it links both ways: the
 * request gets the frame of its first reply, the reply the request's frame and the time between.
 * Which reply answers which request is the dissector's; these are only the links, kept in
 * wmem_file_scope() with the first pass's decisions, so that later passes (tshark -2, the GUI) show a
 * request's reply too. The fields are the dissector's (codegen/exchanges.py): passed in by handle.
 * Declared here and defined in exchange.c, once for every dissector (packet-ur-common.h and .c). */

typedef struct {
    guint32 frame;              /* the request's */
    nstime_t at;                /* its capture time */
    guint32 response_in;        /* the frame of its first reply; 0: none seen */
} ur_exchange_request_t;

typedef struct {
    guint32 response_to;        /* the request's frame; 0: no request (the capture starts after it) */
    nstime_t elapsed;           /* from the request to the reply */
} ur_exchange_reply_t;

/* A request as this frame holds it. */
ur_exchange_request_t *ur_exchange_request(packet_info *pinfo);

/* A reply's link to the request it answers (NULL: none), and the request's to its first reply. */
void ur_exchange_reply(ur_exchange_request_t *request, packet_info *pinfo, ur_exchange_reply_t *reply);

/* The generated items: a request's reply, once one is seen; a reply's request and the time since. */
void ur_exchange_show_request(proto_tree *tree, tvbuff_t *tvb, int at, int len, const ur_exchange_request_t *request,
                              int hf_response_in);
void ur_exchange_show_reply(proto_tree *tree, tvbuff_t *tvb, int at, int len, const ur_exchange_reply_t *reply,
                            int hf_response_to, int hf_time);
/* <standalone> */
#endif
/* </standalone> */
