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
# cppcheck and clang-tidy: the static analysis of the C (make static-c).
APT_PACKAGES=(tshark clang lua5.2 lua5.3 lua5.4 libclang-rt-14-dev llvm make gcc
              wireshark-qt xvfb xdotool imagemagick cmake wireshark-dev
              openjdk-17-jre-headless python3-dev cppcheck clang-tidy)
# The cross compilers and QEMU of `make cross` and tests/c/test_cross.py (mk/cross.mk): installed
# without their recommends, which would bring qemu-system a desktop.
CROSS_PACKAGES=(gcc-arm-none-eabi libnewlib-arm-none-eabi gcc-riscv64-unknown-elf picolibc-riscv64-unknown-elf
                gcc-s390x-linux-gnu gcc-arm-linux-gnueabihf qemu-user qemu-system-arm)

# Each package of a list that is not installed yet.
missing_of() {
  local pkg
  for pkg in "$@"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || echo "$pkg"
  done
}
mapfile -t missing < <(missing_of "${APT_PACKAGES[@]}")
mapfile -t missing_cross < <(missing_of "${CROSS_PACKAGES[@]}")
if [ ${#missing[@]} -gt 0 ] || [ ${#missing_cross[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "setup: installing ${missing[*]} ${missing_cross[*]}"
  $SUDO apt-get update -qq
fi
if [ ${#missing[@]} -gt 0 ]; then
  # tshark asks whether non-root users may capture; answer for it.
  echo "wireshark-common wireshark-common/install-setuid boolean false" | $SUDO debconf-set-selections
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
if [ ${#missing_cross[@]} -gt 0 ]; then
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing_cross[@]}" >/dev/null
fi

python3 -m pip install -q --disable-pip-version-check -r requirements-dev.txt
python3 -m pip install -q --disable-pip-version-check .
# Foxglove's TypeScript MCAP reader and WebSocket protocol client, pinned by the lock file, for
# tests/python/test_mcap_node.py and test_foxglove_listen.py (Node.js 20).
if command -v npm >/dev/null; then npm ci --prefix tests/node --no-audit --no-fund --silent; fi
# The C extension in place too, for the tree's Python (PYTHONPATH=python:generated/python).
make --no-print-directory python-ext PYTHON=python3
echo "setup: done"
