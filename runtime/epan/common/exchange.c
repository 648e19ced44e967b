/* <standalone> */
/* Compiled alone (tests/native/test_exchanges_native.py) as every packet-*.c that joins it does. */
#include <epan/packet.h>
/* </standalone> */
/* Request/response tracking, as Wireshark's request/response protocols show it (dns.response_in,
 * dns.response_to, dns.time), the twin of runtime/lua/common/exchange.lua. On the first pass a
 * request keeps its frame and time; the reply the dissector pairs with it links both ways: the
 * request gets the frame of its first reply, the reply the request's frame and the time between.
 * Which reply answers which request is the dissector's; these are only the links, kept in
 * wmem_file_scope() with the first pass's decisions, so that later passes (tshark -2, the GUI) show a
 * request's reply too. The fields are the dissector's (codegen/exchanges.py): passed in by handle. */

typedef struct {
    guint32 frame;              /* the request's */
    nstime_t at;                /* its capture time */
    guint32 response_in;        /* the frame of its first reply; 0: none seen */
} exchange_request_t;

typedef struct {
    guint32 response_to;        /* the request's frame; 0: no request (the capture starts after it) */
    nstime_t time;              /* from the request to the reply */
} exchange_reply_t;

/* A request as this frame holds it. */
static exchange_request_t *
exchange_request(packet_info *pinfo)
{
    exchange_request_t *request = wmem_new(wmem_file_scope(), exchange_request_t);
    request->frame = pinfo->num;
    request->at = pinfo->abs_ts;
    request->response_in = 0;
    return request;
}

/* A reply's link to the request it answers (NULL: none), and the request's to its first reply. */
static void
exchange_reply(exchange_request_t *request, packet_info *pinfo, exchange_reply_t *reply)
{
    reply->response_to = 0;
    nstime_set_zero(&reply->time);
    if (request == NULL)
        return;
    if (request->response_in == 0)
        request->response_in = pinfo->num;
    reply->response_to = request->frame;
    nstime_delta(&reply->time, &pinfo->abs_ts, &request->at);
}

/* The generated items: a request's reply, once one is seen; a reply's request and the time since. */
static void
exchange_show_request(proto_tree *tree, tvbuff_t *tvb, int at, int len, const exchange_request_t *request,
                      int hf_response_in)
{
    if (request != NULL && request->response_in != 0)
        proto_item_set_generated(proto_tree_add_uint(tree, hf_response_in, tvb, at, len, request->response_in));
}

static void
exchange_show_reply(proto_tree *tree, tvbuff_t *tvb, int at, int len, const exchange_reply_t *reply,
                    int hf_response_to, int hf_time)
{
    if (reply->response_to == 0)
        return;
    proto_item_set_generated(proto_tree_add_uint(tree, hf_response_to, tvb, at, len, reply->response_to));
    proto_item_set_generated(proto_tree_add_time(tree, hf_time, tvb, at, len, &reply->time));
}
