/* <standalone> */
/* Compiled alone (tests/native/test_exchanges_native.py) as packet-ur-common.c, which joins it. */
#include "exchange.h"
/* </standalone> */
/* Request/response tracking (exchange.h): the links, kept in wmem_file_scope(). */

ur_exchange_request_t *
ur_exchange_request(packet_info *pinfo)
{
    ur_exchange_request_t *request = wmem_new(wmem_file_scope(), ur_exchange_request_t);
    request->frame = pinfo->num;
    request->at = pinfo->abs_ts;
    request->response_in = 0;
    return request;
}

void
ur_exchange_reply(ur_exchange_request_t *request, packet_info *pinfo, ur_exchange_reply_t *reply)
{
    reply->response_to = 0;
    nstime_set_zero(&reply->elapsed);
    if (request == NULL)
        return;
    if (request->response_in == 0)
        request->response_in = pinfo->num;
    reply->response_to = request->frame;
    nstime_delta(&reply->elapsed, &pinfo->abs_ts, &request->at);
}

void
ur_exchange_show_request(proto_tree *tree, tvbuff_t *tvb, int at, int len, const ur_exchange_request_t *request,
                         int hf_response_in)
{
    if (request != NULL && request->response_in != 0)
        proto_item_set_generated(proto_tree_add_uint(tree, hf_response_in, tvb, at, len, request->response_in));
}

void
ur_exchange_show_reply(proto_tree *tree, tvbuff_t *tvb, int at, int len, const ur_exchange_reply_t *reply,
                       int hf_response_to, int hf_time)
{
    if (reply->response_to == 0)
        return;
    proto_item_set_generated(proto_tree_add_uint(tree, hf_response_to, tvb, at, len, reply->response_to));
    proto_item_set_generated(proto_tree_add_time(tree, hf_time, tvb, at, len, &reply->elapsed));
}
