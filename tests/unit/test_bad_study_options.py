"""The studies' own options (reproduce, calibrate, fit-bat, the calibration routes), given values
they cannot take: exit 2, one line that names the option first, nothing run and nothing written.
The lab tests' options have their registry-made cases in test_bad_options.py."""

from __future__ import annotations

from pathlib import Path

import pytest

from batball.cli import main

#: (arguments, the option the error names first). ``FILE`` becomes a file that exists, ``DATA``
#: a folder without route data; every output goes under the test's own folder.
CASES = [
    (["reproduce", "--out", "FILE"], "out"),
    (["reproduce", "--runs-dir", "FILE"], "runs-dir"),
    (["reproduce", "--out", "FILE/report"], "out"),
    (["reproduce", "--bogus"], "unrecognized arguments"),
    (["calibrate", "--model", "nope"], "model"),
    (["calibrate", "--global-points", "x"], "global-points"),
    (["calibrate", "--global-points", "-1"], "global-points"),
    (["calibrate", "--max-evaluations", "0"], "max-evaluations"),
    (["calibrate", "--coarse-divisions", "1"], "coarse-divisions"),
    (["calibrate", "--fine-divisions", "41"], "fine-divisions"),
    (["calibrate", "--quick", "--fine-divisions", "8"], "fine-divisions"),
    (["calibrate", "--workers", "-1"], "workers"),
    (["calibrate", "--study", "."], "study"),
    (["calibrate", "--study", "FILE/x.db"], "study"),
    (["calibrate", "--save", "."], "save"),
    (["calibrate", "--fit-speeds", "95"], "fit-speeds"),
    (["calibrate", "--free", "young"], "free"),
    (["calibrate", "--bound", "g0=1:2"], "bounds"),
    (["calibrate", "--targets", "FILE"], "targets"),
    (["fit-bat", "--to", "nope"], "to"),
    (["fit-bat", "--hoop", "x"], "hoop"),
    (["fit-bat", "--hoop", "1950 Hz", "1450 Hz"], "hoop"),
    (["fit-bat", "--weight", "0 oz"], "weight"),
    (["fit-bat", "--balance-point", "40 in"], "balance-point"),
    (["fit-bat", "--output", "."], "output"),
    (["fit-bat", "--runs-dir", "FILE"], "runs-dir"),
    (["fit-bat", "--free", "angle:nosuch"], "free"),
    (["compare-calibrations", "--model", "mat057"], "model"),
    (["compare-calibrations", "--prony-terms", "0"], "prony-terms"),
    (["compare-calibrations", "--global-points", "-2"], "global-points"),
    (["compare-calibrations", "--max-evaluations", "0"], "max-evaluations"),
    (["compare-calibrations", "--workers", "-3"], "workers"),
    (["compare-calibrations", "--poisson-ratio", "0.7"], "poisson-ratio"),
    (["compare-calibrations", "--dma-modulus", "bulk"], "dma-modulus"),
    (["compare-calibrations", "--time-step-scale", "3"], "time-step-scale"),
    (["compare-calibrations", "--runs-dir", "FILE"], "runs-dir"),
    (["compare-calibrations", "--use", "flat=x.toml"], "use"),
    (["synthetic-data", "--truth", "type1", "--out", "FILE"], "out"),
    (["synthetic-data", "--truth", "type1", "--out", "o", "--runs-dir", "FILE"], "runs-dir"),
    (["synthetic-data", "--truth", "type1", "--out", "o", "--speeds", "95"], "speeds"),
    (["synthetic-noise", "--source", "DATA", "--out", "o"], "source"),
    (["synthetic-noise", "--source", "DATA", "--out", "o", "--seeds", "x"], "seeds"),
    (["synthetic-noise", "--out", "FILE", "--seeds", "1"], "out"),
    (["synthetic-noise", "--source", "DATA", "--out", "o", "--dma-sd", "x"], "dma-sd"),
]


@pytest.mark.parametrize(("argv", "field"), CASES, ids=[" ".join(a) for a, _ in CASES])
def test_a_bad_study_option_is_one_line_naming_it_and_nothing_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch,
    argv: list[str], field: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "FILE").write_text("not a folder, not a study\n")
    (tmp_path / "DATA").mkdir()
    if argv[0] == "synthetic-noise" and "--source" not in argv:
        argv = [*argv, "--source", str(exact_route_data(tmp_path))]
    before = sorted(p.name for p in tmp_path.rglob("*"))
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith(f"batball: error: {field}"), captured.err
    assert captured.err.count("\n") == 1 and captured.out == ""
    assert sorted(p.name for p in tmp_path.rglob("*")) == before  # nothing written


def exact_route_data(folder: Path) -> Path:
    """A folder with one route's data file, as ``batball synthetic-data`` writes it."""
    source = folder / "source"
    source.mkdir()
    (source / "ccor-targets.toml").write_text(
        '[[targets]]\nquantity = "ccor"\nspeed = "95 mph"\nvalue = 0.4\n'
    )
    return source
