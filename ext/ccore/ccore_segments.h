/* A run of one direction's bytes that came in several TCP segments, joined: CaptureStreams
 * (capture_streams.c) hands it over as python/urwire/capture.py's Segments, whose `stamps` are
 * these, one per segment in order, and PrimaryColumns.feed_segments (columns.c) reads it a
 * segment at a time, so that each record is dated by the segment that completes it. */
#ifndef URWIRE_CCORE_SEGMENTS_H
#define URWIRE_CCORE_SEGMENTS_H
#include <stdint.h>

typedef struct {
    int64_t end;        /* where the segment's bytes end in the run's */
    double time;        /* the capture time of its frame (seconds since the epoch) */
} ccore_segment_stamp;

#endif
