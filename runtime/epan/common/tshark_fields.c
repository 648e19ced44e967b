/* <standalone> */
#include "tshark_fields.h"
/* </standalone> */
/* Whether this process is a `tshark -T fields` run, from its command line (/proc/self/cmdline, where
 * the system shows it). tshark 4.0 builds the tree visible for -T fields and primes none of the fields
 * it prints, so a dissector cannot tell from the tree that it prints field values only: no item's
 * label, and no field that no argument names. Joined into the packet-ur-common.c of urwire's own
 * plugin; Wireshark's copy reads no command line and joins tshark_fields_upstream.c instead. */

#define TSHARK_CMDLINE_MAX (1 << 16)    /* a longer command line is read as any other program's */

/* The arguments of this process, or NULL where the system does not show them. */
static GPtrArray *
tshark_command_line(void)
{
    gchar *text = NULL;
    gsize len = 0;
    if (!g_file_get_contents("/proc/self/cmdline", &text, &len, NULL) || len == 0 || len > TSHARK_CMDLINE_MAX) {
        g_free(text);
        return NULL;
    }
    GPtrArray *args = g_ptr_array_new_with_free_func(g_free);
    for (gsize p = 0; p < len;) {
        gsize z = p;
        while (z < len && text[z] != '\0')
            z++;
        g_ptr_array_add(args, g_strndup(text + p, z - p));
        p = z + 1;
    }
    g_free(text);
    return args;
}

/* Whether args are tshark's with -T fields. */
static gboolean
tshark_fields_run(const GPtrArray *args)
{
    if (args == NULL || args->len == 0)
        return FALSE;
    const char *program = g_ptr_array_index(args, 0);
    const char *slash = strrchr(program, '/');
    if (!g_str_has_prefix(slash ? slash + 1 : program, "tshark"))
        return FALSE;
    const char *format = NULL;
    for (guint i = 1; i < args->len; i++) {
        const char *a = g_ptr_array_index(args, i);
        if (strcmp(a, "-T") == 0)
            format = i + 1 < args->len ? g_ptr_array_index(args, i + 1) : NULL;
        else if (g_str_has_prefix(a, "-T"))
            format = a + 2;
    }
    return format != NULL && strcmp(format, "fields") == 0;
}

/* The arguments of this process when it is a tshark -T fields run, else NULL: found once, kept for
 * the life of the process. */
const GPtrArray *
ur_tshark_fields_arguments(void)
{
    static gboolean found;
    static GPtrArray *fields_run;
    if (!found) {
        GPtrArray *args = tshark_command_line();
        found = TRUE;
        if (tshark_fields_run(args))
            fields_run = args;
        else if (args != NULL)
            g_ptr_array_free(args, TRUE);
    }
    return fields_run;
}
