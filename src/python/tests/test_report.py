"""barnbench.report(): the HTML page of a run record, the same bytes as barn report writes."""

import subprocess

import pytest

import barnbench


def test_the_python_report_and_barn_report_of_one_record_are_identical(tmp_path, barn):
    # Worlds 0, 150 and 299 with the straight controller: at least one episode fails (it drives
    # into a wall), so the page also holds the re-simulated failure figures, drawn by the same
    # C++ in both callers.
    record = tmp_path / "record"
    summary = barnbench.run("straight", worlds="0:300:150", trials=1, jobs=2, seed=3, out=str(record))
    assert summary["summary"]["success_rate"] < 1.0
    from_python = tmp_path / "python.html"
    assert barnbench.report(record, from_python) == str(from_python)
    from_cli = tmp_path / "cli.html"
    subprocess.run([barn, "report", str(record), "--output", str(from_cli)], check=True,
                   capture_output=True)
    page = from_python.read_bytes()
    assert page == from_cli.read_bytes()
    assert b"straight on barnbench-generated worlds" in page
    assert b"failed_world" not in page  # scratch file names are not on the page; the figures are embedded
    assert page.count(b"data:image/png;base64,") >= 2  # the score bars and at least one failed world


def test_a_bad_record_or_output_is_an_input_error_naming_it(tmp_path):
    with pytest.raises(barnbench.InputError, match="nothing: neither a run record"):
        barnbench.report(tmp_path / "nothing", tmp_path / "page.html")
    assert not (tmp_path / "page.html").exists()
    with pytest.raises(barnbench.InputError, match=r"page\.pdf: expected a \.html file"):
        barnbench.report(tmp_path / "nothing", tmp_path / "page.pdf")
    with pytest.raises(barnbench.InputError, match="max_failures"):
        barnbench.report(tmp_path / "nothing", tmp_path / "page.html", max_failures=-1)
