/* subtrees_from_zero.h: what lets the out-of-tree build take subtree handles declared as Wireshark's
 * development branch declares them (`static int ett_x;`, zero) where the Wireshark it builds
 * against is older than 4.2: there proto_register_subtree_array refuses a handle that is not -1
 * ("subtree item type (ett_...) not -1"). A zero handle is given -1 as it is registered, so that a
 * handle registered twice still fails as it should. The config.h of the out-of-tree build
 * (dissector/native/CMakeLists.txt) includes this file before each dissector's own includes; in
 * Wireshark's tree it is not needed. */
#ifndef URWIRE_SUBTREES_FROM_ZERO_H
#define URWIRE_SUBTREES_FROM_ZERO_H
#include <epan/proto.h>

static inline void
urwire_register_subtrees_from_zero(int *const *indices, const int num_indices)
{
    for (int i = 0; i < num_indices; i++)
        if (*indices[i] == 0)
            *indices[i] = -1;
    proto_register_subtree_array(indices, num_indices);
}

#define proto_register_subtree_array(indices, num_indices) urwire_register_subtrees_from_zero(indices, num_indices)
#endif
