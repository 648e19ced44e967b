"""UR's own client library (URCL, github.com/UniversalRobots/Universal_Robots_Client_Library) as
a test client: `primary_client(source, out)` builds tests/urcl/primary_client.cpp against the
primary-interface part of a URCL checkout, `rtde_dashboard_client(source, out)` builds
tests/urcl/rtde_dashboard_client.cpp against its RTDE and dashboard parts, each once per checkout
and program change.

No package registry ships URCL (Debian's, PyPI and npm have none of it), so the tests and the benches
that use it take a checkout: the one URCL_SOURCE names, else one beside this checkout (DEFAULT).
Run as a script, it prints the checkout for make, or says on stderr why there is none.
"""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path
from typing import Optional

ROOT = Path(__file__).resolve().parents[2]
# Where a URCL checkout is looked for when URCL_SOURCE is not set:
#   git clone https://github.com/UniversalRobots/Universal_Robots_Client_Library ../Universal_Robots_Client_Library
DEFAULT = ROOT.parent / "Universal_Robots_Client_Library"
PROGRAM = ROOT / "tests" / "urcl" / "primary_client.cpp"
# What the primary parser and its stream need: the packages, the socket, the log.
SOURCES = ["src/comm/tcp_socket.cpp", "src/log.cpp", "src/default_log_handler.cpp", "src/helpers.cpp",
           "src/types.cpp", "src/ur/version_information.cpp", "src/primary/primary_package.cpp",
           "src/primary/robot_message.cpp", "src/primary/robot_state.cpp"]
SOURCE_DIRS = ["src/primary/robot_message", "src/primary/robot_state"]
# URCL's CMake writes this header; the primary parser reads one flag of it (off: URCL's default).
COMPILE_OPTIONS = """#pragma once
#define PRIMARY_CLIENT_STRICT_PARSING_ 0
namespace urcl
{
struct CompileOptions
{
  constexpr static bool PRIMARY_CLIENT_STRICT_PARSING = static_cast<bool>(PRIMARY_CLIENT_STRICT_PARSING_);
};
inline constexpr CompileOptions COMPILE_OPTIONS;
}  // namespace urcl
"""


def _looked_at() -> Path:
    path = os.environ.get("URCL_SOURCE")
    return Path(path) if path else DEFAULT


def source_dir() -> Optional[Path]:
    """The URCL checkout named by URCL_SOURCE, else the one at DEFAULT; None when it is not one."""
    path = _looked_at()
    return path if (path / "include" / "ur_client_library").is_dir() else None


def why_not() -> str:
    """Why source_dir() is None, in a sentence."""
    if os.environ.get("URCL_SOURCE"):
        return f"URCL_SOURCE={_looked_at()} has no include/ur_client_library: it is not a checkout of URCL"
    return (f"URCL_SOURCE is not set and {DEFAULT} holds no checkout of URCL (no package registry ships its "
            "source: clone it there, or name a checkout with URCL_SOURCE)")


def describe(source: Path) -> str:
    """The checkout and, when it is a git work tree of its own, its commit."""
    if not (source / ".git").exists():
        return str(source)
    commit = subprocess.run(["git", "-C", str(source), "rev-parse", "--short=8", "HEAD"], capture_output=True,
                            text=True)
    return f"{source}" + (f" at {commit.stdout.strip()}" if commit.returncode == 0 else "")


def primary_client(source: Path, out: Path) -> Path:
    files = [source / s for s in SOURCES] + sorted(p for d in SOURCE_DIRS for p in (source / d).glob("*.cpp"))
    return build(PROGRAM, files, source, out)


RTDE_DASHBOARD_PROGRAM = ROOT / "tests" / "urcl" / "rtde_dashboard_client.cpp"
# What RTDEClient and DashboardClient need: the socket, the log, every RTDE package, both dashboard
# implementations (the client chooses one at run time).
RTDE_DASHBOARD_SOURCES = ["src/comm/tcp_socket.cpp", "src/log.cpp", "src/default_log_handler.cpp", "src/helpers.cpp",
                          "src/types.cpp", "src/ur/version_information.cpp", "src/ur/dashboard_client.cpp",
                          "src/ur/dashboard_client_implementation_g5.cpp",
                          "src/ur/dashboard_client_implementation_x.cpp"]


def rtde_dashboard_client(source: Path, out: Path) -> Path:
    files = [source / s for s in RTDE_DASHBOARD_SOURCES] + sorted((source / "src" / "rtde").glob("*.cpp"))
    return build(RTDE_DASHBOARD_PROGRAM, files, source, out)


def build(program: Path, files: list, source: Path, out: Path) -> Path:
    stamp = hashlib.sha256(b"".join(f.read_bytes() for f in [program, *files])).hexdigest()[:16]
    binary = out / f"{program.stem}-{stamp}"
    if binary.exists():
        return binary
    generated = out / "include" / "ur_client_library"
    generated.mkdir(parents=True, exist_ok=True)
    (generated / "compile_options.h").write_text(COMPILE_OPTIONS)
    subprocess.run(["g++", "-std=c++17", "-O1", "-pthread", f"-I{source / 'include'}", f"-I{out / 'include'}",
                    f"-I{source / '3rdparty'}", "-o", str(binary), str(program), *map(str, files)],
                   check=True, capture_output=True, text=True)
    return binary


if __name__ == "__main__":
    found = source_dir()
    if found is None:
        print(f"URCL not compared: {why_not()}", file=sys.stderr)
    else:
        print(f"URCL compared: built from {describe(found)}", file=sys.stderr)
        print(found)
