/* A stand-in for the generated part of ur_realtime.c, so that runtime/c/sized_packets/ur_realtime_decode.c
 * compiles on its own: the header's types and a made-up spec of one 20-byte layout (a size field
 * and two doubles) sent by two version ranges, with the tables the runtime walks. */
#ifndef UR_REALTIME_RUNTIME_SPEC_H
#define UR_REALTIME_RUNTIME_SPEC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#define UR_REALTIME_SIZE_FIELD_BYTES 4
#define UR_REALTIME_MIN_MESSAGE_SIZE 12
#define UR_REALTIME_MAX_MESSAGE_SIZE 200

typedef enum ur_realtime_error {
    UR_REALTIME_OK = 0,
    UR_REALTIME_E_SHORT,
    UR_REALTIME_E_SIZE_BELOW,
    UR_REALTIME_E_SIZE_ABOVE,
    UR_REALTIME_E_UNKNOWN_SIZE
} ur_realtime_error;

typedef enum ur_realtime_layout { UR_REALTIME_UNKNOWN = -1, UR_REALTIME_ONE, UR_REALTIME_LAYOUT_COUNT } ur_realtime_layout;
typedef enum ur_realtime_field { UR_REALTIME_F_MODE, UR_REALTIME_F_PAIR, UR_REALTIME_FIELD_COUNT } ur_realtime_field;
typedef enum ur_realtime_enum { UR_REALTIME_ENUM_MODE, UR_REALTIME_ENUM_COUNT } ur_realtime_enum;

typedef struct ur_realtime_packet {
    int32_t message_size;
    ur_realtime_layout layout;
    int form;
    double mode;
    double pair[1];
    const uint8_t *raw;
    size_t raw_length;
} ur_realtime_packet;

typedef struct ur_realtime_slot {
    ur_realtime_field field;
    uint16_t offset;
    uint16_t count;
} ur_realtime_slot;

typedef struct ur_realtime_field_info {
    const char *name;
    const char *label;
    const char *unit;
    size_t member;
    uint16_t count;
    int enum_id;
} ur_realtime_field_info;

const char *ur_realtime_error_name(ur_realtime_error e);
uint32_t ur_realtime_version(unsigned major, unsigned minor, unsigned bugfix);
ur_realtime_error ur_realtime_frame(const uint8_t *buf, size_t len, int32_t *size);
ur_realtime_error ur_realtime_decode(const uint8_t *buf, size_t len, uint32_t version, ur_realtime_packet *out);
const char *ur_realtime_layout_name(ur_realtime_layout layout);
size_t ur_realtime_layout_fields(ur_realtime_layout layout, const ur_realtime_slot **slots);
const ur_realtime_field_info *ur_realtime_field_info_of(ur_realtime_field field);
bool ur_realtime_has(const ur_realtime_packet *p, ur_realtime_field field);
const double *ur_realtime_values(const ur_realtime_packet *p, ur_realtime_field field);
const char *ur_realtime_enum_name(const ur_realtime_packet *p, ur_realtime_field field, double value);

/* The generated decoders read with runtime/c/common/loads.h, which the runtime includes after
 * this file: a stand-in decoder reads the bytes itself. */
static void ur_realtime__decode_one(const uint8_t *p, ur_realtime_packet *out)
{
    uint64_t bits[2] = {0, 0};
    int i;
    for (i = 0; i < 16; i++)
        bits[i / 8] = bits[i / 8] << 8 | p[4 + i];
    memcpy(&out->mode, &bits[0], sizeof out->mode);
    memcpy(&out->pair[0], &bits[1], sizeof out->pair[0]);
}

static void (*const ur_realtime__decoders[UR_REALTIME_LAYOUT_COUNT])(const uint8_t *, ur_realtime_packet *) = {
    ur_realtime__decode_one,
};

static const ur_realtime_field_info ur_realtime__fields[UR_REALTIME_FIELD_COUNT] = {
    {"mode", "Mode", "", offsetof(ur_realtime_packet, mode), 1, UR_REALTIME_ENUM_MODE},
    {"pair", "Pair", "m", offsetof(ur_realtime_packet, pair), 1, -1},
};

static const ur_realtime_slot ur_realtime__slots_one[] = {{UR_REALTIME_F_MODE, 4, 1}, {UR_REALTIME_F_PAIR, 12, 1}};

typedef struct ur_realtime__layout_info {
    const char *name;
    int32_t size;
    const ur_realtime_slot *slots;
    size_t count;
} ur_realtime__layout_info;

static const ur_realtime__layout_info ur_realtime__layouts[UR_REALTIME_LAYOUT_COUNT] = {
    {"one", 20, ur_realtime__slots_one, 2},
};

typedef struct ur_realtime__name {
    int value;
    const char *name;
} ur_realtime__name;

typedef struct ur_realtime__names {
    const ur_realtime__name *entries;
    size_t count;
} ur_realtime__names;

static const ur_realtime__name ur_realtime__mode_old[] = {{0, "OLD_ZERO"}};
static const ur_realtime__name ur_realtime__mode_new[] = {{0, "NEW_ZERO"}};

typedef struct ur_realtime__form {
    int32_t size;
    uint32_t low, high;
    ur_realtime_layout layout;
    ur_realtime__names names[UR_REALTIME_ENUM_COUNT];
} ur_realtime__form;

#define UR_REALTIME__FORM_COUNT 2

static const ur_realtime__form ur_realtime__forms[UR_REALTIME__FORM_COUNT] = {
    {20, 1000000u, 1999999u, UR_REALTIME_ONE, {{ur_realtime__mode_old, 1}}},
    {20, 2000000u, 2999999u, UR_REALTIME_ONE, {{ur_realtime__mode_new, 1}}},
};

#endif
