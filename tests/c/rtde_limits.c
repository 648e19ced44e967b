/* An embedded caller past the limits of its RTDE state: rtde_conversation_init's (RTDE_MAX_*) and
 * rtde_conversation_init_in's. Prints what rtde_decode said of each step, for tests/c/test_rtde_c.py. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtde.h"

static rtde_conversation conversation;
static uint8_t message[65536];

static const char *said(rtde_error e)
{
    return e == RTDE_OK ? "ok" : e == RTDE_TOO_MANY ? "too many" : e == RTDE_UNKNOWN_RECIPE ? "unknown recipe"
                                                                                         : rtde_error_text(e);
}

static rtde_error feed(rtde_conversation *c, const uint8_t *p, size_t n, bool from_robot, rtde_message *m)
{
    size_t at;
    return rtde_decode(c, p, n, from_robot, m, &at);
}

/* A setup of `count` copies of name, or of the names given. */
static size_t setup(const char *name, size_t count)
{
    const char **names = malloc(count * sizeof *names);
    size_t i, n;
    for (i = 0; i < count; i++)
        names[i] = name;
    n = rtde_build_setup_outputs(message, sizeof message, 2, 125.0, names, count);
    free(names);
    return n;
}

/* A reply of recipe id with `count` copies of type. */
static size_t reply(uint8_t id, const char *type, size_t count)
{
    size_t n = 4, i, k = strlen(type);
    message[2] = 'O';
    message[3] = id;
    for (i = 0; i < count; i++) {
        if (i)
            message[n++] = ',';
        memcpy(message + n, type, k);
        n += k;
    }
    message[0] = (uint8_t)(n >> 8);
    message[1] = (uint8_t)(n & 0xff);
    return n;
}

static size_t data(uint8_t id, size_t values)
{
    size_t n = 4 + values;
    memset(message, 0, n);
    message[0] = (uint8_t)(n >> 8);
    message[1] = (uint8_t)(n & 0xff);
    message[2] = 'U';
    message[3] = id;
    return n;
}

int main(void)
{
    rtde_message m;
    rtde_value v;
    size_t n;
    int id;
    static char long_name[2101];
    rtde_limits small = {2, 4, 64}, huge = {RTDE_PROTOCOL_RECIPES + 1, 1, 1};
    void *storage;

    rtde_conversation_init(&conversation);
    n = setup("timestamp", 1);
    feed(&conversation, message, n, false, &m);
    n = reply(1, "DOUBLE", 1);
    feed(&conversation, message, n, true, &m);
    n = setup("timestamp", 65);
    feed(&conversation, message, n, false, &m);
    n = reply(1, "DOUBLE", 65);
    printf("65 variables: reply %s\n", said(feed(&conversation, message, n, true, &m)));
    n = data(1, 8);
    printf("data of recipe 1 after it: %s\n", said(feed(&conversation, message, n, true, &m)));

    memset(long_name, 'x', 2100);
    n = setup(long_name, 1);
    printf("2100 bytes of names: setup %s\n", said(feed(&conversation, message, n, false, &m)));
    n = setup("actual_q", 1);
    feed(&conversation, message, n, false, &m);
    n = reply(1, "DOUBLE", 1);
    printf("its reply: %s\n", said(feed(&conversation, message, n, true, &m)));
    n = reply(2, "VECTOR6D", 1);
    printf("the next setup's reply: %s", said(feed(&conversation, message, n, true, &m)));
    n = data(2, 48);
    if (feed(&conversation, message, n, true, &m) == RTDE_OK && rtde_data_find(&m.u.data_package.values, "actual_q", &v))
        printf(", recipe 2 reads actual_q\n");
    else
        printf(", recipe 2 does not read actual_q\n");

    for (id = 3; id <= 10; id++) {      /* recipe 1 is gone: 2 to 9 fill the 8 places */
        rtde_error e;
        n = setup("timestamp", 1);
        feed(&conversation, message, n, false, &m);
        n = reply((uint8_t)id, "DOUBLE", 1);
        e = feed(&conversation, message, n, true, &m);
        if (id < 10 && e != RTDE_OK)
            printf("recipe %d: %s\n", id, said(e));
        if (id == 9)
            printf("recipes 3 to 9: ok\n");
        if (id == 10)
            printf("recipe 10: reply %s\n", said(e));
    }
    n = data(10, 8);
    printf("data of recipe 10: %s\n", said(feed(&conversation, message, n, true, &m)));

    n = rtde_storage_size(&small);
    storage = malloc(n);
    printf("storage for 2 recipes of 4 variables and 64 bytes: %s\n",
           rtde_conversation_init_in(&conversation, &small, storage, n) ? "ok" : "refused");
    printf("storage one byte short: %s\n",
           rtde_conversation_init_in(&conversation, &small, storage, n - 1) ? "ok" : "refused");
    rtde_conversation_init_in(&conversation, &small, storage, n);
    for (id = 1; id <= 3; id++) {
        rtde_error e;
        size_t k = setup("timestamp", 4);
        feed(&conversation, message, k, false, &m);
        k = reply((uint8_t)id, "DOUBLE", 4);
        e = feed(&conversation, message, k, true, &m);
        if (id == 3)
            printf("a third recipe: reply %s\n", said(e));
        else if (e != RTDE_OK)
            printf("recipe %d: %s\n", id, said(e));
    }
    free(storage);
    printf("limits above the protocol's: %s\n", rtde_storage_size(&huge) ? "a storage size" : "no storage size");
    return 0;
}
