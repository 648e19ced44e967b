#!/usr/bin/env bash
# Runs the Python tests on the lowest and the highest Python the package claims (pyproject's
# requires-python), each in its own venv under build/python-range/. Usage:
#   scripts/test-python-range.sh [VERSION...]   (default: 3.10 3.13)
# urx (the baseline of `make bench`, not a test) is left out: it has no wheel and no test needs it.
# pyspark is left out too: `make test` runs the Spark job's tests on the system Python, and its
# 450 MB would be installed twice more for code that is the same on every Python.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -gt 0 ] || set -- 3.10 3.13
VERSIONS=("$@")
PYENV_ROOT="${PYENV_ROOT:-$HOME/.pyenv}"

find_python() {  # the interpreter of one minor version: pyenv's first, then the system's
  local version=$1 candidate
  for candidate in "$PYENV_ROOT"/versions/"$version".*/bin/python"$version" \
                   /usr/bin/python"$version" /usr/local/bin/python"$version"; do
    if [ -x "$candidate" ] && "$candidate" -c pass 2>/dev/null; then
      echo "$candidate"
      return 0
    fi
  done
  return 1
}

requirements=build/python-range/requirements.txt
mkdir -p build/python-range
grep -v -e '^urx' -e '^pyspark' requirements-dev.txt >"$requirements"
echo 'dpkt>=1.9.8' >>"$requirements"   # the package's own dependencies (pyproject.toml)
echo 'tqdm>=4.60' >>"$requirements"

for version in "${VERSIONS[@]}"; do
  if ! python=$(find_python "$version"); then
    echo "test-python-range: no python$version found (looked in $PYENV_ROOT/versions and /usr/bin)" >&2
    exit 1
  fi
  venv=build/python-range/$version
  stamp=$venv/installed-requirements.txt
  if ! cmp -s "$requirements" "$stamp"; then
    echo "== python$version ($python): installing the test requirements into $venv"
    rm -rf "$venv"
    "$python" -m venv "$venv"
    "$venv"/bin/python -m pip install -q --disable-pip-version-check -r "$requirements"
    cp "$requirements" "$stamp"
  fi
  echo "== python$version: pytest tests/python tests/codegen (not the long sweeps: they ask nothing of the Python)"
  # A test file per process at a time over every core (pytest-xdist), as `make test` runs them.
  # No C extension is built for these Pythons: the tests that need it skip instead of failing.
  URWIRE_TESTS_WITHOUT_CCORE=1 "$venv"/bin/python -m pytest -q -p no:cacheprovider -n auto --dist loadfile -m "not deep" \
    tests/python tests/codegen
done
