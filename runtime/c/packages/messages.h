/* <standalone> */
#ifndef URWIRE_RUNTIME_MESSAGES_H
#define URWIRE_RUNTIME_MESSAGES_H
#include "runtime_spec.h"
/* </standalone> */
/* ---- decoding messages -------------------------------------------------------------------- */

/* The bit of a sub-package type in urwire_robot_state.present and .malformed. */
#define URWIRE_BIT(code) (1ul << (code))

/* Decode one framed message (len = its declared length) of a stream of `version` (a frame's,
 * a hint, or URWIRE_DEFAULT_VERSION). Each part is read in the form of that version when it
 * fits its length, else in the one form of that exact length (in that form's version); while
 * the version is only assumed, such a form sets the version for the rest of a robot state
 * (out->implied). Never fails as a call: a message that cannot be read comes back failed with
 * error and raw. Returns !out->failed. */
bool urwire_decode_message(const uint8_t *bytes, size_t len, urwire_sw_version version, urwire_message *out);
/* The next sub-package of a robot state's seq; false at the end. */
bool urwire_next_package(urwire_seq *seq, urwire_package *out);
/* Every sub-package of a robot state into one struct; false when any failed or framing stopped. */
bool urwire_decode_robot_state(const urwire_message *m, urwire_robot_state *out);
/* urwire_decode_message and urwire_decode_robot_state in one pass over the bytes (the fast
 * path for a robot-state stream). Any other message is decoded into *m and false returned. */
bool urwire_decode_robot_state_message(const uint8_t *bytes, size_t len, urwire_sw_version version,
                                       urwire_message *m, urwire_robot_state *out);
/* True when the message is failed or holds a malformed sub-package (the CLI's exit code 1). */
bool urwire_message_has_error(const urwire_message *m);

/* ---- encoding ----------------------------------------------------------------------------- */

/* The message's bytes into out[0..cap): header and body, every length computed from the
 * fields. For a robot state, the sub-packages come from its seq and its unframed raw tail.
 * Returns the bytes written, or 0 with *err set. encode(decode(b)) == b. */
size_t urwire_encode_message(const urwire_message *m, uint8_t *out, size_t cap, urwire_error *err);
/* One sub-package, its header included. */
size_t urwire_encode_package(const urwire_package *pkg, uint8_t *out, size_t cap, urwire_error *err);
/* <standalone> */
#endif
/* </standalone> */
