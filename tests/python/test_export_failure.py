"""Every way `urwire export` writes (CSV or Parquet tables, an MCAP file, a dataset) says a file it
cannot read in the same words, with exit status 2 (data/export_failure.py)."""
import pytest

from urwire import cli

WAYS = {"csv": ["--format", "csv", "--out"], "mcap": ["--format", "mcap", "--out"], "dataset": ["--dataset"]}


@pytest.mark.parametrize("way", sorted(WAYS))
def test_a_missing_file_is_said_alike(way, tmp_path, capsys):
    if way != "csv":
        pytest.importorskip("mcap" if way == "mcap" else "pyarrow")
    missing = tmp_path / "missing.pcapng"
    assert cli.main(["export", str(missing), *WAYS[way], str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err.splitlines()[-1] == f"urwire export: {missing}: No such file or directory"


@pytest.mark.parametrize("way", sorted(WAYS))
def test_bytes_that_are_no_capture_are_said_alike(way, tmp_path, capsys, monkeypatch):
    if way != "csv":
        pytest.importorskip("mcap" if way == "mcap" else "pyarrow")
    from urwire.data import dataset, export, mcap_export

    def fails(*args, **kwargs):
        raise ValueError("bad bytes")

    for module, name in ((export, "records_of_file"), (mcap_export, "records_of_file"), (dataset, "parts_of")):
        monkeypatch.setattr(module, name, fails)
    odd = tmp_path / "odd.bin"
    odd.write_bytes(b"\x00" * 16)
    assert cli.main(["export", str(odd), *WAYS[way], str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err.splitlines()[-1] == f"urwire export: cannot read stream {odd}: bad bytes"
