/* ---- the variable table, read row by row -------------------------------------------------- */

static const char *rtde__variable_word(uint8_t index)
{
    return (const char *)&rtde__variable_text + rtde__variable_words[index];
}

bool rtde_variable_at(size_t index, rtde_variable *out)
{
    const char *text = (const char *)&rtde__variable_text;
    if (index >= RTDE_VARIABLE_COUNT)
        return false;
    out->name = text + rtde__variable_rows[index].name;
    out->type = rtde__variable_rows[index].type;
    out->output = rtde__variable_rows[index].output;
    out->label = text + rtde__variable_rows[index].label;
    out->unit = rtde__variable_rows[index].unit ? rtde__variable_word(rtde__variable_rows[index].unit) : NULL;
    out->since_cb3 = rtde__variable_word(rtde__variable_rows[index].since[0]);
    out->since_eseries = rtde__variable_word(rtde__variable_rows[index].since[1]);
    out->since_polyscope_x = rtde__variable_word(rtde__variable_rows[index].since[2]);
    return true;
}
