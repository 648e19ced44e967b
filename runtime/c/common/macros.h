/* <standalone> */
#ifndef URWIRE_RUNTIME_MACROS_H
#define URWIRE_RUNTIME_MACROS_H
#include <stddef.h>   /* compiled alone: C wants a declaration, and a file of macros has none */
/* </standalone> */
/* ---- how the runtime declares its own functions ------------------------------------------ */

/* Private functions live in the generated .c file that joins them, a copy in each. */
#define URWIRE__PRIVATE static
/* <standalone> */
#undef URWIRE__PRIVATE
#define URWIRE__PRIVATE /* a runtime file compiled on its own exports them to its unit tests */
/* </standalone> */

/* What must be inlined to be fast (byte loads, version keys): gcc does so on its own at -O2 and
 * -O3 but, at -Os, takes the shifts of a load for more code than a call and calls them;
 * always_inline says what `inline` means here. Unused ones never warn (gcc does not warn on an
 * unused static inline function, clang does in a .c file unless told `unused`). */
#if defined(__GNUC__)
#define URWIRE__INLINE static inline __attribute__((always_inline, unused))
#else
#define URWIRE__INLINE static inline
#endif
/* <standalone> */
#endif
/* </standalone> */
