"""The warnings every lab test run carries (lab.protocol.run_warnings)."""

from __future__ import annotations

from pathlib import Path

import pytest


def test_run_warnings_flag_hourglass_energy_and_energy_balance() -> None:
    from batball.lab.protocol import run_warnings

    assert run_warnings({"hourglass_energy_fraction": 0.05, "energy_balance_error": 0.002}) == []
    (hourglass,) = run_warnings({"hourglass_energy_fraction": 0.28})
    assert "28.0 %" in hourglass and "over 10 %" in hourglass
    (balance,) = run_warnings({"energy_balance_error": 0.015})
    assert "1.50 %" in balance and "over 1 %" in balance
    assert run_warnings({"bbs_mph": 95.0}) == []  # a test without those numbers


def test_a_coarse_ccor_warns_about_its_hourglass_energy_on_stderr(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A 2-division ball loses about half its impact energy to hourglass control (the reason
    the seed's mesh has 12): the run says so, and --json carries the same sentence."""
    import json

    from batball.cli import main

    assert main(["ccor", "--divisions", "2", "--json", "--runs-dir", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert summary["hourglass_energy_fraction"] > 0.10
    assert any("hourglass energy" in w for w in summary["warnings"])
    assert "batball: warning: hourglass energy" in captured.err


def test_batball_alone_prints_its_help(capsys: pytest.CaptureFixture[str]) -> None:
    from batball.cli import main

    assert main([]) == 0
    out = capsys.readouterr().out
    assert out.startswith("usage: batball") and "reproduce" in out and "ccor" in out
