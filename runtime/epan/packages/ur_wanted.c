/* Which robot-state packages a `tshark -T fields` run needs, as the Lua twin finds them
 * (runtime/lua/packages/wanted.lua). tshark builds the tree visible for -T fields (Wireshark 4.0 primes no
 * output field), so every field counts as referenced and every package would be built to print
 * one field. The fields are named on tshark's command line (-e, -Y, -R, -z, -o): where the system
 * shows it (/proc/self/cmdline), a package is built when a field of it is named
 * ("ur.joint_data.q_actual" names joint_data), or its item ("ur.joint_data"). Every package is
 * built when the command line may need any: not tshark, or not -T fields; a display filter macro
 * or field reference ("$"), expert infos ("expert"); a ur name that is not a field of the spec
 * (ur.raw, ur.extra, ... show inside any package; ur.version is a preference); package headers
 * (ur.package.*); or when the ur.named_fields_only preference is off. The command line is
 * tshark_fields.c's. */

/* The ur names of a run, found once: NULL when it needs every package. */
typedef struct {
    gboolean found;
    GPtrArray *names;                   /* char *, kept for the life of the process */
    GHashTable *parts;                  /* const ur_part * -> GINT_TO_POINTER(1 + wanted) */
} ur_wanted_names;

static gboolean
ur_name_char(char c)
{
    return g_ascii_isalnum(c) || c == '_' || c == '.';
}

/* Whether name is a field of the spec (the dissector's own fields follow the spec's, from
 * UR_HF_RAW on). */
static gboolean
ur_spec_field(const char *name)
{
    for (int i = 0; i < UR_HF_RAW; i++)
        if (hf_ur[i] > 0 && strcmp(proto_registrar_get_nth(hf_ur[i])->abbrev, name) == 0)
            return TRUE;
    return FALSE;
}

/* Adds the ur names in arg ("ur." then letters, digits, '_' and '.', not ending in '.') to
 * names; FALSE when one of them may need every package. */
static gboolean
ur_add_names(const char *arg, GPtrArray *names)
{
    for (const char *p = strstr(arg, "ur."); p != NULL; p = strstr(p, "ur.")) {
        const char *e = p + 3;
        while (ur_name_char(*e))
            e++;
        while (e > p + 3 && e[-1] == '.')
            e--;
        if (e == p + 3) {
            p += 3;
            continue;
        }
        char *name = g_strndup(p, (size_t)(e - p));
        g_ptr_array_add(names, name);
        /* A ur name that is not a spec field (tshark refuses one that is no field at all), or a
         * package header's, may show in any package. */
        if (!ur_spec_field(name) || g_str_has_prefix(name, "ur.package."))
            return FALSE;
        p = e;
    }
    return TRUE;
}

/* The ur names of a tshark -T fields run's arguments (NULL: not such a run); NULL when it may need
 * any field. */
static GPtrArray *
ur_named_fields(const GPtrArray *args)
{
    if (args == NULL)
        return NULL;
    GPtrArray *names = g_ptr_array_new_with_free_func(g_free);
    for (guint i = 1; i < args->len; i++) {
        const char *a = g_ptr_array_index(args, i);
        if (strchr(a, '$') != NULL || strstr(a, "expert") != NULL || !ur_add_names(a, names)) {
            g_ptr_array_free(names, TRUE);
            return NULL;
        }
    }
    return names;
}

/* The names of this run, found on first use. */
static ur_wanted_names *
ur_wanted(void)
{
    static ur_wanted_names wanted;
    if (!wanted.found) {
        wanted.found = TRUE;
        wanted.names = ur_named_fields(ur_tshark_fields_arguments());
        wanted.parts = g_hash_table_new(g_direct_hash, g_direct_equal);
    }
    return &wanted;
}

/* Whether this run builds only the packages its command line names (ur_package_wanted). */
static gboolean
ur_only_named_packages(void)
{
    return ur_named_fields_only && ur_wanted()->names != NULL;
}

/* Whether a named-only run builds package pk: a name is its item's or one of its fields'. */
static gboolean
ur_package_wanted(const ur_part *pk)
{
    ur_wanted_names *wanted = ur_wanted();
    gpointer known = g_hash_table_lookup(wanted->parts, pk);
    if (known != NULL)
        return GPOINTER_TO_INT(known) - 1;
    char *own = g_strconcat("ur.", pk->name, NULL);
    size_t n = strlen(own);
    gboolean yes = FALSE;
    for (guint i = 0; i < wanted->names->len && !yes; i++) {
        const char *name = g_ptr_array_index(wanted->names, i);
        yes = strncmp(name, own, n) == 0 && (name[n] == '\0' || name[n] == '.');
    }
    g_free(own);
    g_hash_table_insert(wanted->parts, (gpointer)pk, GINT_TO_POINTER(1 + yes));
    return yes;
}
