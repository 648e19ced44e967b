"""The optional C extension urwire._ccore: the generated C parser (generated/c) and the C
runtime's canonical JSON writer (runtime/c/json) behind a small CPython module (ext/ccore).

It is optional: where no compiler is at hand, `pip install .` still installs the pure-Python
package, which then decodes on its own (urwire.backend() says which one runs). Everything else
about the package is in pyproject.toml.
"""
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

# The extension's C files, one per line: the Makefile and the sanitized test build read them too.
SOURCES = (Path(__file__).resolve().parent / "ext" / "ccore" / "sources.txt").read_text().split()


class OptionalBuildExt(build_ext):
    """Builds the extension where it can; a failed build leaves the pure-Python package."""

    def run(self):
        try:
            super().run()
        except Exception as exc:  # no compiler, no Python headers: setuptools raises several kinds
            print(f"urwire: the C extension is not built ({exc}); the package decodes in pure Python")

    def build_extension(self, ext):
        try:
            super().build_extension(ext)
        except Exception as exc:
            print(f"urwire: the C extension {ext.name} is not built ({exc}); the package decodes in pure Python")


setup(
    ext_modules=[Extension(
        "urwire._ccore",
        sources=SOURCES,
        include_dirs=["ext/ccore", "generated/c", "runtime/c/json", "runtime/c/capture"],
        extra_compile_args=["-std=c99", "-O2"],
        optional=True,
    )],
    cmdclass={"build_ext": OptionalBuildExt},
)
