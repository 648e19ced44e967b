"""docs/recording-view.md shows the commands `make docs-pictures` runs, word for word, and the picture
they made (docs/img/recording-view.png): small, and drawn by the urwire and Matplotlib the page
names, as the PNG's own texts say; its figures of plot's memory bounds are the code's."""
import os
import re
import struct
import subprocess
import zlib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "recording-view.md"
SCRIPT = ROOT / "scripts" / "recording-view.sh"
PICTURE = ROOT / "docs" / "img" / "recording-view.png"
MARKER = "# ---- the commands of docs/recording-view.md"
MAX_PICTURE_BYTES = 200_000


def page() -> str:
    return PAGE.read_text(encoding="utf-8")


def png_texts(path: Path) -> dict[str, str]:
    """The tEXt chunks of a PNG (keyword -> text), read chunk by chunk."""
    data, texts, at = path.read_bytes(), {}, 8
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        assert struct.unpack(">I", data[at + 8 + length:at + 12 + length])[0] == zlib.crc32(kind + body)
        if kind == b"tEXt":
            key, _, text = body.partition(b"\0")
            texts[key.decode("latin-1")] = text.decode("latin-1")
        at += 12 + length
    return texts


def test_the_page_shows_the_commands_the_target_runs():
    block = page().split("## The commands that made it", 1)[1].split("```sh\n", 1)[1].split("```", 1)[0]
    script = SCRIPT.read_text(encoding="utf-8").split(MARKER + "\n", 1)[1]
    assert block == script
    # Run under `make test` too, whose MAKEFLAGS would have the inner make name its directory.
    env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MAKELEVEL", "MFLAGS")}
    dry = subprocess.run(["make", "-n", "--no-print-directory", "docs-pictures"], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=60)
    assert dry.returncode == 0 and dry.stdout.split("\n") == ["bash scripts/recording-view.sh", ""], dry.stderr
    assert "--out docs/img/recording-view.png" in block and "--mcap build/recording-view.mcap" in block


def test_the_picture_is_there_small_and_drawn_by_what_the_page_names():
    assert "](img/recording-view.png)" in page()
    assert PICTURE.stat().st_size < MAX_PICTURE_BYTES
    texts = png_texts(PICTURE)
    matplotlib = re.fullmatch(r"Matplotlib version\s*([0-9.]+), .*", texts["Software"]).group(1)
    urwire = re.fullmatch(r"urwire ([0-9.]+) \(urwire plot\)", texts["Source"]).group(1)
    assert f"`urwire plot` of urwire {urwire}, with Matplotlib {matplotlib} " in " ".join(page().split())


def test_the_memory_bounds_the_page_gives_are_the_codes():
    from urwire.data.decimate import MAX_BUCKETS
    from urwire.data.plot_mcap import PATH_POINTS

    text = " ".join(page().split())
    assert f"at most {MAX_BUCKETS} runs of points" in text and f"at most {PATH_POINTS}." in text


def test_mcap_md_links_the_page():
    assert "(recording-view.md)" in (ROOT / "docs" / "mcap.md").read_text(encoding="utf-8")
