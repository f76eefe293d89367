"""The calibration package's public names, which it imports on first use: each one listed in
``__all__`` is found, in the module the package says, and nothing else is."""

from __future__ import annotations

import importlib

import pytest

import batball.calibrate as package


def test_every_public_name_is_where_the_package_says() -> None:
    assert sorted(package.__all__) == sorted(package._SOURCES)
    for name in package.__all__:
        module = importlib.import_module(f"batball.calibrate.{package._SOURCES[name]}")
        assert getattr(package, name) is getattr(module, name)


def test_an_unknown_name_is_an_attribute_error() -> None:
    with pytest.raises(AttributeError, match="no attribute 'fit_everything'"):
        _ = package.fit_everything  # type: ignore[attr-defined]
