#!/usr/bin/env bash
# install-dissector.sh install|uninstall: the Wireshark dissectors into the personal plugin
# folders that `tshark -G folders` names, never the native plugin and the Lua files at once (they
# register the same protocols, and Wireshark refuses a second protocol of the same name).
#
# install: builds the native plugin (`make native-dissector`); when it builds, copies urwire.so
# into "Personal Plugins"/epan and removes the urwire Lua files from "Personal Lua Plugins";
# when it does not (no cmake, no wireshark-dev, a build error: said on stderr), or NATIVE=no,
# copies the Lua files and removes an installed urwire.so. NATIVE=yes fails instead of falling back.
# uninstall: removes both.
#
# Environment: NATIVE (auto, yes, no), TSHARK, MAKE, LUA_PLUGINS (the Lua files, space-separated).
set -uo pipefail
cd "$(dirname "$0")/.."

action=${1:?usage: install-dissector.sh install|uninstall}
NATIVE=${NATIVE:-auto}
TSHARK=${TSHARK:-tshark}
MAKE=${MAKE:-make}
LUA_PLUGINS=${LUA_PLUGINS:-$(ls generated/lua/*.lua)}
PLUGIN_NAME=urwire.so

folder() {  # the folder `tshark -G folders` lists under this name
    "$TSHARK" -G folders 2>/dev/null |
        awk -F'\t' -v name="$1:" '$1 ~ "^" name {gsub(/^[ \t]+/, "", $2); print $2; exit}'
}

native_dir=$(folder "Personal Plugins")
lua_dir=$(folder "Personal Lua Plugins")
if [ -z "$native_dir" ] || [ -z "$lua_dir" ]; then
    echo "install-dissector: cannot find the personal plugin folders with '$TSHARK -G folders'" >&2
    exit 2
fi
native_dir="$native_dir/epan"

remove_native() {
    if [ -f "$native_dir/$PLUGIN_NAME" ]; then
        rm -f "$native_dir/$PLUGIN_NAME" && echo "removed $native_dir/$PLUGIN_NAME"
    fi
}

remove_lua() {
    for file in $LUA_PLUGINS; do
        name=$(basename "$file")
        if [ -f "$lua_dir/$name" ]; then
            rm -f "$lua_dir/$name" && echo "removed $lua_dir/$name"
        fi
    done
}

install_lua() {
    mkdir -p "$lua_dir" || exit 2
    for file in $LUA_PLUGINS; do
        cp "$file" "$lua_dir/" && echo "installed $lua_dir/$(basename "$file")" || exit 2
    done
    remove_native
}

# The native plugin built now, or why not (on stderr); prints the .so's path.
build_native() {
    local log
    log=$(mktemp)
    if "$MAKE" --no-print-directory native-dissector >"$log" 2>&1; then
        sed -n 's/^native-dissector: //p' "$log" | tail -n 1
        rm -f "$log"
        return 0
    fi
    if grep -q "cmake is not installed" "$log"; then
        echo "install-dissector: cmake is not installed (scripts/setup.sh installs it)" >&2
    elif grep -q 'provided by "Wireshark"' "$log"; then
        echo "install-dissector: Wireshark's CMake package is missing (install wireshark-dev)" >&2
    elif grep -q "no packet-\*.c under" "$log"; then
        echo "install-dissector: no generated/epan/packet-*.c to build (make generate)" >&2
    else
        echo "install-dissector: the native plugin did not build:" >&2
        tail -n 15 "$log" >&2
    fi
    rm -f "$log"
    return 1
}

case "$action" in
install)
    if [ "$NATIVE" != no ]; then
        if library=$(build_native) && [ -f "$library" ]; then
            mkdir -p "$native_dir" && cp "$library" "$native_dir/$PLUGIN_NAME" || exit 2
            echo "installed $native_dir/$PLUGIN_NAME (the native plugin)"
            remove_lua
            if [ "$(id -u)" -eq 0 ]; then
                echo "install-dissector: warning: Wireshark does not load personal plugins when it runs as" \
                     "root; run it as your own user (or copy $PLUGIN_NAME into the global plugins folder)" >&2
            fi
            exit 0
        fi
        if [ "$NATIVE" = yes ]; then
            exit 1
        fi
        echo "install-dissector: installing the Lua dissectors instead" >&2
    fi
    install_lua
    ;;
uninstall)
    remove_native
    remove_lua
    ;;
*)
    echo "usage: install-dissector.sh install|uninstall" >&2
    exit 2
    ;;
esac
