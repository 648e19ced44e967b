/* <standalone> */
/* Compiled alone (tests/native/test_exchanges_native.py) with the declarations the generated file
 * gives it. */
#include <epan/packet.h>
#include "rtde_exchanges.h"
#include "../common/exchange.h"
#define RTDE_N_EXCHANGES 2
#define RTDE_MAX_PENDING_REQUESTS 8
enum { RTDE_HF_RESPONSE_IN, RTDE_HF_RESPONSE_TO, RTDE_HF_TIME, RTDE_HF_COUNT };
static int hf_rtde[RTDE_HF_COUNT];
typedef struct { const char *name; } rtde_layout;
static const rtde_layout rtde_layouts[] = { { "request" }, { "reply" } };
static const rtde_exchange_role rtde_exchange_roles[] = { { 0, FALSE }, { 0, TRUE } };
typedef struct { guint32 frame; guint32 place; } rtde_when;
typedef struct { struct rtde_exchanges *exchanges; } rtde_state;
/* </standalone> */
/* RTDE's request/response links (runtime/epan/common/exchange.h keeps the links themselves), the
 * twin of runtime/lua/typed_messages/exchanges.lua: a reply answers the oldest request of its pair
 * still awaiting one (rtde_exchange_roles, from the spec's exchanges.pairs), at most
 * RTDE_MAX_PENDING_REQUESTS kept per pair and conversation; one beyond is not linked, nor any
 * behind it until the replies catch up (replies come in order), and their replies link to none.
 * Only the messages of a pair cost memory: data packages and text messages are in none. */

typedef struct {
    ur_exchange_request_t *request;         /* a request's, NULL for a reply or a request not kept */
    ur_exchange_reply_t reply;              /* a reply's; response_to 0 for a request */
} rtde_link;

typedef struct rtde_exchanges {
    ur_exchange_request_t *pending[RTDE_N_EXCHANGES][RTDE_MAX_PENDING_REQUESTS];   /* oldest at first */
    guint first[RTDE_N_EXCHANGES], count[RTDE_N_EXCHANGES];
    guint64 lost[RTDE_N_EXCHANGES];         /* requests not kept, awaiting replies */
    wmem_tree_t *links;                     /* rtde_link by frame and place (rtde_when) */
} rtde_exchanges;

static rtde_exchanges *
rtde_exchanges_of(rtde_state *state)
{
    if (!state->exchanges) {
        state->exchanges = wmem_new0(wmem_file_scope(), rtde_exchanges);
        state->exchanges->links = wmem_tree_new(wmem_file_scope());
    }
    return state->exchanges;
}

/* A request awaits its reply; NULL when it is not kept (counted lost). */
static ur_exchange_request_t *
rtde_exchange_keep(rtde_exchanges *x, guint pair, packet_info *pinfo)
{
    ur_exchange_request_t *request;
    if (x->lost[pair] > 0 || x->count[pair] == RTDE_MAX_PENDING_REQUESTS) {
        x->lost[pair]++;
        return NULL;
    }
    request = ur_exchange_request(pinfo);
    x->pending[pair][(x->first[pair] + x->count[pair]++) % RTDE_MAX_PENDING_REQUESTS] = request;
    return request;
}

/* The request a reply answers: NULL when none awaits, or when it answers one not kept. */
static ur_exchange_request_t *
rtde_exchange_answered(rtde_exchanges *x, guint pair)
{
    ur_exchange_request_t *request = NULL;
    if (x->count[pair] > 0) {
        request = x->pending[pair][x->first[pair]];
        x->first[pair] = (x->first[pair] + 1) % RTDE_MAX_PENDING_REQUESTS;
        x->count[pair]--;
    } else if (x->lost[pair] > 0) {
        x->lost[pair]--;
    }
    return request;
}

/* On the first pass: what a message is to its pair, kept under its frame and place. */
static void
rtde_follow_exchange(rtde_state *state, const rtde_layout *layout, packet_info *pinfo, rtde_when when)
{
    const rtde_exchange_role *role = &rtde_exchange_roles[layout - rtde_layouts];
    rtde_exchanges *x;
    rtde_link *link;
    wmem_tree_key_t key[] = { { 1, &when.frame }, { 1, &when.place }, { 0, NULL } };
    if (role->pair < 0)
        return;
    x = rtde_exchanges_of(state);
    link = wmem_new0(wmem_file_scope(), rtde_link);
    if (role->reply)
        ur_exchange_reply(rtde_exchange_answered(x, (guint)role->pair), pinfo, &link->reply);
    else
        link->request = rtde_exchange_keep(x, (guint)role->pair, pinfo);
    wmem_tree_insert32_array(x->links, key, link);
}

/* The message's generated items: a request's reply, a reply's request and the time since (no
 * lookup for a message in no pair: a data package costs nothing here). */
static void
rtde_show_exchange(const rtde_state *state, const rtde_layout *layout, proto_tree *tree, tvbuff_t *tvb, int at,
                   rtde_when when)
{
    const rtde_link *link;
    wmem_tree_key_t key[] = { { 1, &when.frame }, { 1, &when.place }, { 0, NULL } };
    if (!state->exchanges || !tree || rtde_exchange_roles[layout - rtde_layouts].pair < 0)
        return;
    link = (const rtde_link *)wmem_tree_lookup32_array(state->exchanges->links, key);
    if (!link)
        return;
    ur_exchange_show_request(tree, tvb, at, 1, link->request, hf_rtde[RTDE_HF_RESPONSE_IN]);
    ur_exchange_show_reply(tree, tvb, at, 1, &link->reply, hf_rtde[RTDE_HF_RESPONSE_TO], hf_rtde[RTDE_HF_TIME]);
}
