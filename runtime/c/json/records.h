/* The records a framer has ready, printed as canonical JSON Lines: the record loop of
 * urwire-decode and of urwire._ccore's JSON lines, in a file of its own so that both, the tests
 * and the fuzzer run the same code. C runtime beside the parser, not joined into it. */
#ifndef URWIRE_RECORDS_H
#define URWIRE_RECORDS_H

#include <stdbool.h>

#include "json.h"
#include "urwire.h"

/* Print every record the framer has ready, one line each, through v (a json_visitor of w);
 * returns true when one of them held an error. */
bool print_ready_records(urwire_framer *fr, const urwire_visitor *v, json_writer *w);

#endif
