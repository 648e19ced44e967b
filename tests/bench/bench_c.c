/* C decode throughput on real robot-state messages, side by side with memcpy of the same bytes.
 *
 *     bench_c FILE [BYTES]
 *
 * (make bench-c builds it at -O3, -O2 and -Os and tests/bench/bench_c.py runs each in turn.)
 * FILE holds robot-state messages back to back (tests/bench/bench_c.py writes it from the
 * conformance captures). They are repeated into a buffer of BYTES (default 256 KiB, hot in
 * L2), which is then decoded whole many times with urwire_decode_robot_state_message: every
 * sub-package framed and every field of every sub-package decoded, into one caller-owned
 * struct; then the same through the streaming framer, with the version assumed and known. The
 * baseline copies the same buffer with memcpy in the same run. Each figure is the best of
 * several rounds, to shed the noise of a shared machine.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "urwire.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    size_t want = argc > 2 ? (size_t)atol(argv[2]) : 256u * 1024u;
    uint8_t *src, *buf, *dst;
    size_t srclen = 0, len = 0, nmsg = 0, *offsets, i, got;
    int round, rep, reps = 1, known_round;
    double best_decode = 1e9, best_copy = 1e9, best_frame = 1e9, best_known = 1e9, t;
    urwire_sw_version assumed = URWIRE_DEFAULT_VERSION, known;
    volatile double sink = 0;
    unsigned long present = 0;
    FILE *f;
    /* The same version as assumed, but known: a stream that began with its Version message. */
    urwire_parse_version("5.9", &known);
    if (argc < 2 || !(f = fopen(argv[1], "rb"))) {
        fprintf(stderr, "usage: bench_c FILE [BYTES]\n");
        return 2;
    }
    src = malloc(1 << 20);
    while ((got = fread(src + srclen, 1, (1 << 20) - srclen, f)) > 0)
        srclen += got;
    fclose(f);
    buf = malloc(want + srclen);
    dst = malloc(want + srclen);
    offsets = malloc(sizeof *offsets * (want / 5 + 1));
    /* Whole messages, repeated until the buffer is full. */
    while (len + srclen <= want || len == 0) {
        size_t pos = 0;
        while (pos + 5 <= srclen) {
            size_t n = (size_t)src[pos] << 24 | (size_t)src[pos + 1] << 16 | (size_t)src[pos + 2] << 8 | src[pos + 3];
            offsets[nmsg++] = len + pos;
            pos += n;
        }
        memcpy(buf + len, src, srclen);
        len += srclen;
    }
    /* Calibrate: about 50 ms per round. */
    for (t = 0; t < 0.05; reps *= 2) {
        double t0 = now();
        for (rep = 0; rep < reps; rep++)
            memcpy(dst, buf, len);
        t = now() - t0;
    }
    for (round = 0; round < 9; round++) {
        double t0 = now();
        urwire_message m;
        urwire_robot_state state;
        urwire_framer fr;
        urwire_frame frame;
        for (rep = 0; rep < reps / 8 + 1; rep++)
            for (i = 0; i < nmsg; i++) {
                size_t n = (size_t)buf[offsets[i]] << 24 | (size_t)buf[offsets[i] + 1] << 16 |
                           (size_t)buf[offsets[i] + 2] << 8 | buf[offsets[i] + 3];
                urwire_decode_robot_state_message(buf + offsets[i], n, URWIRE_DEFAULT_VERSION, &m, &state);
                present |= state.present;
                sink += state.joint_data.joints[5].q_actual + state.cartesian_info.x;
            }
        t = (now() - t0) / (double)(reps / 8 + 1);
        if (t < best_decode)
            best_decode = t;

        t0 = now();
        for (rep = 0; rep < reps; rep++) {
            memcpy(dst, buf, len);
            sink += dst[rep % len];
        }
        t = (now() - t0) / (double)reps;
        if (t < best_copy)
            best_copy = t;

        /* The same through the streaming framer: its copy into the framer buffer included, and the
         * decoded message handed back (urwire_framer_learn), as urwire-decode does. Twice: with
         * the version assumed (a capture that starts mid-stream: the framer learns it from the
         * layout sizes), then known. */
        for (known_round = 0; known_round < 2; known_round++) {
            t0 = now();
            for (rep = 0; rep < reps / 8 + 1; rep++) {
                size_t off = 0;
                urwire_framer_init(&fr, dst, len + 16, known_round ? known : assumed);
                while (off < len) {
                    off += urwire_framer_feed(&fr, buf + off, len - off);
                    while (urwire_framer_next(&fr, &frame) == URWIRE_FRAME_MESSAGE) {
                        urwire_decode_robot_state_message(frame.bytes, frame.length, frame.version, &m, &state);
#ifndef BENCH_C_WITHOUT_LEARN  /* a BENCH_C_BASE library older than the call */
                        urwire_framer_learn(&fr, &m);  /* the framer needs no walk of its own */
#endif
                        sink += state.joint_data.joints[0].q_actual;
                    }
                }
            }
            t = (now() - t0) / (double)(reps / 8 + 1);
            if (known_round && t < best_known)
                best_known = t;
            if (!known_round && t < best_frame)
                best_frame = t;
        }
    }
    printf("buffer: %lu bytes, %lu robot-state messages (%lu bytes each on average), packages seen 0x%lx\n",
           (unsigned long)len, (unsigned long)nmsg, (unsigned long)(len / nmsg), present);
    printf("decode (every field of every package): %8.0f MB/s  %10.0f messages/s\n", len / best_decode / 1e6,
           nmsg / best_decode);
    printf("framer + decode:                      %8.0f MB/s  %10.0f messages/s\n", len / best_frame / 1e6,
           nmsg / best_frame);
    printf("framer + decode, version known:       %8.0f MB/s  %10.0f messages/s\n", len / best_known / 1e6,
           nmsg / best_known);
    printf("memcpy of the same bytes:             %8.0f MB/s\n", len / best_copy / 1e6);
    printf("ratio decode / memcpy: %.3f   framer+decode / memcpy: %.3f   (checksum %g)\n",
           best_copy / best_decode, best_copy / best_frame, (double)sink * 0);
    printf("ns per state: decode %.1f  framer+decode %.1f  memcpy %.1f  known %.1f\n",
           best_decode / (double)nmsg * 1e9, best_frame / (double)nmsg * 1e9, best_copy / (double)nmsg * 1e9,
           best_known / (double)nmsg * 1e9);
    free(src);
    free(buf);
    free(dst);
    free(offsets);
    return 0;
}
