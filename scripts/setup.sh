#!/usr/bin/env bash
# Installs what urwire's tests and demo need on a Debian machine: system packages (tshark, the
# Wireshark GUI, compilers, Lua), then the Python packages. Safe to run again: it skips what is there.
set -euo pipefail
# Debian marks its Python as externally managed; this project installs into it on purpose.
export PIP_BREAK_SYSTEM_PACKAGES=1
cd "$(dirname "$0")/.."

# wireshark-qt, xvfb, xdotool and imagemagick: the GUI smoke test and `make screenshots` run the
# real Wireshark GUI on a virtual X server.
# cmake and wireshark-dev (headers, libwireshark-dev, WiresharkConfig.cmake): the native plugin,
# built against the installed Wireshark by `make native-dissector`.
# openjdk-17-jre-headless: the JVM that `urwire spark`'s tests run Spark local[2] on.
# python3-dev: the headers the C extension urwire._ccore builds against.
APT_PACKAGES=(tshark clang lua5.2 lua5.3 lua5.4 libclang-rt-14-dev llvm make gcc
              wireshark-qt xvfb xdotool imagemagick cmake wireshark-dev
              openjdk-17-jre-headless python3-dev)

missing=()
for pkg in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  # tshark asks whether non-root users may capture; answer for it.
  echo "wireshark-common wireshark-common/install-setuid boolean false" | $SUDO debconf-set-selections
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi

python3 -m pip install -q --disable-pip-version-check -r requirements-dev.txt
python3 -m pip install -q --disable-pip-version-check .
# Foxglove's TypeScript MCAP reader, pinned by its lock file, for tests/python/test_mcap_node.py (Node.js 20).
if command -v npm >/dev/null; then npm ci --prefix tests/node --no-audit --no-fund --silent; fi
# The C extension in place too, for the tree's Python (PYTHONPATH=python:generated/python).
make --no-print-directory python-ext PYTHON=python3
echo "setup: done"
