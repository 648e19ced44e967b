/* ---- a data package's values read where the caller reads them: inline, one per value type ---- */

/* A program knows the types its recipe asked for: rtde_data_double(d, i, &x),
 * rtde_data_vector6d(d, i, q) and one reader per value type after them, inline in the caller, read
 * value i as that type. Each is a check (a value there, of that type) and byte-swapped loads at the
 * offset the recipe computed at setup, with the type and its size constants at every call, so a
 * compiler makes them the loads a hand-written reader of the layout makes. They return false, and
 * write nothing, when the index is past the recipe or the value is of another type; the names
 * resolve to indexes once (rtde_recipe_index). rtde_data_value reads any type into an rtde_value. */

/* Where value `index` starts in the package, when it is there and of this type; else NULL. */
URWIRE__INLINE const uint8_t *rtde__value_bytes(const rtde_data *d, size_t index, uint8_t type)
{
    const struct rtde_recipe *recipe = d->recipe;
    if (recipe == NULL || d->bytes == NULL || index >= recipe->count || recipe->types[index] != type)
        return NULL;
    return d->bytes + recipe->offset[index];
}
