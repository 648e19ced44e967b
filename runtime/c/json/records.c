/* The records a framer has ready, as JSON Lines. See records.h. */
#include "records.h"

bool print_ready_records(urwire_framer *fr, const urwire_visitor *v, json_writer *w)
{
    urwire_frame frame;
    urwire_message m;
    bool errors = false;
    for (;;) {
        urwire_frame_kind kind = urwire_framer_next(fr, &frame);
        if (kind == URWIRE_FRAME_NEED_MORE || kind == URWIRE_FRAME_END)
            return errors;
        w->depth = 0;
        if (kind == URWIRE_FRAME_FAULT) {
            urwire_visit_fault(&frame.fault, v);
            errors = true;
        } else {
            urwire_decode_message(frame.bytes, frame.length, frame.version, &m);
            urwire_framer_learn(fr, &m);
            urwire_visit_message(&m, v);
            errors |= urwire_message_has_error(&m);
        }
        putc('\n', w->out);
    }
}
