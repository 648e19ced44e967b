/* Wireshark's own copy of the dissector builds every robot-state package: it reads no command line
 * to find the packages a tshark -T fields run names, as urwire's plugin does, so such a run builds
 * the whole tree. */

static gboolean
ur_only_named_packages(void)
{
    return FALSE;
}

/* Asked only when ur_only_named_packages() is TRUE. */
static gboolean
ur_package_wanted(const ur_part *pk _U_)
{
    return TRUE;
}
