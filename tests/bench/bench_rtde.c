/* RTDE data packages decoded by their recipe in C, side by side with memcpy of the same bytes.
 *
 *     bench_rtde CLIENT ROBOT [ROUNDS]
 *
 * (make bench-rtde builds it at -O2; tests/bench/bench_rtde.py writes the files and runs it.)
 * CLIENT is what the client sent on one RTDE connection (its protocol request, the output setup,
 * start), ROBOT what the robot sent (the replies, then the data packages). Each round makes a
 * fresh caller-owned rtde_conversation, decodes the client's messages, then reads ROBOT a
 * megabyte at a time, as a program reading a socket or a file would, and decodes every message
 * with rtde_decode, reading every value of every data package (rtde_data_value). The baseline
 * reads the same file the same way and copies each chunk with memcpy, in the same run. Prints
 * one line: packages, best seconds decoding, best seconds copying (CPU time of the round).
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rtde.h"

#define CHUNK (1u << 20)

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static volatile double sink;

/* Decode the whole messages at buf[0..length) in one direction; returns the bytes used and
 * counts the data packages. Exits on a decoding error: the input is made to be valid. */
static size_t decode_messages(rtde_conversation *c, const uint8_t *buf, size_t length, bool from_robot,
                              unsigned long *packages)
{
    size_t pos = 0, size, offset, i, n;
    rtde_message msg;
    rtde_value value;
    double sum = 0;
    while (rtde_message_size(buf + pos, length - pos, &size) == RTDE_OK && size <= length - pos) {
        rtde_error e = rtde_decode(c, buf + pos, size, from_robot, &msg, &offset);
        if (e != RTDE_OK) {
            fprintf(stderr, "bench_rtde: %s at message offset %lu\n", rtde_error_text(e), (unsigned long)offset);
            exit(1);
        }
        if (msg.layout == RTDE_LAYOUT_DATA_PACKAGE) {
            const rtde_data *d = &msg.u.data_package.values;
            n = rtde_data_count(d);
            for (i = 0; i < n; i++)
                if (rtde_data_value(d, i, &value))
                    sum += value.type == RTDE_VT_DOUBLE || value.type == RTDE_VT_VECTOR6D ? value.item[0].f64
                                                                                          : (double)value.item[0].u64;
            ++*packages;
        }
        pos += size;
    }
    sink += sum;
    return pos;
}

static uint8_t *slurp(const char *path, size_t *length)
{
    FILE *f = fopen(path, "rb");
    uint8_t *buf = NULL;
    size_t got;
    *length = 0;
    if (!f)
        return NULL;
    for (;;) {
        buf = realloc(buf, *length + CHUNK);
        got = fread(buf + *length, 1, CHUNK, f);
        if (got == 0)
            break;
        *length += got;
    }
    fclose(f);
    return buf;
}

/* One round over ROBOT: decoding (copy == NULL) or copying each chunk into copy. */
static double round_over(const char *robot, const uint8_t *client, size_t client_length, uint8_t *buf,
                         uint8_t *copy, unsigned long *packages)
{
    static rtde_conversation c;
    FILE *f = fopen(robot, "rb");
    size_t held = 0, got, used;
    double start = cpu_now();
    unsigned long client_packages = 0;
    if (!f) {
        perror(robot);
        exit(2);
    }
    rtde_conversation_init(&c);
    decode_messages(&c, client, client_length, false, &client_packages);
    *packages = 0;
    while ((got = fread(buf + held, 1, CHUNK, f)) > 0) {
        held += got;
        if (copy) {
            memcpy(copy, buf, held);
            sink += copy[held - 1];
            held = 0;
            continue;
        }
        used = decode_messages(&c, buf, held, true, packages);
        memmove(buf, buf + used, held - used);
        held -= used;
    }
    fclose(f);
    return cpu_now() - start;
}

int main(int argc, char **argv)
{
    size_t client_length;
    uint8_t *client, *buf, *copy;
    int rounds = argc > 3 ? atoi(argv[3]) : 3, r;
    double best_decode = 1e30, best_copy = 1e30, t;
    unsigned long packages = 0, copied;
    if (argc < 3 || !(client = slurp(argv[1], &client_length))) {
        fprintf(stderr, "usage: bench_rtde CLIENT ROBOT [ROUNDS]\n");
        return 2;
    }
    buf = malloc(2 * CHUNK + 65536);
    copy = malloc(2 * CHUNK + 65536);
    for (r = 0; r < rounds; r++) {
        t = round_over(argv[2], client, client_length, buf, NULL, &packages);
        if (t < best_decode)
            best_decode = t;
        t = round_over(argv[2], client, client_length, buf, copy, &copied);
        if (t < best_copy)
            best_copy = t;
    }
    printf("%lu %.6f %.6f\n", packages, best_decode, best_copy);
    free(buf);
    free(copy);
    free(client);
    return 0;
}
