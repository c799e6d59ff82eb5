"""Packaging for library users: licence, citation, version, and the light core dependencies."""

from __future__ import annotations

import tomllib
from pathlib import Path

import yaml

import projtrack

ROOT = Path(__file__).resolve().parents[1]
META = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]


def test_license_file_is_the_declared_licence():
    assert META["license"] == {"text": "BSD-3-Clause"}
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("BSD 3-Clause License")
    assert "Neither the name of the copyright holder" in text


def test_citation_cites_the_project_and_the_three_source_documents():
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0"
    for key in ("message", "title", "authors", "version", "license"):
        assert cff.get(key), key
    assert cff["version"] == META["version"]
    assert cff["license"] == "BSD-3-Clause"
    refs = cff["references"]
    titles = [r["title"] for r in refs]
    assert titles == ["Reconstructing ellipsoids from projections", "Trajectory estimation on manifolds",
                      "Time-Sequential Optical Data Processing"]
    for r in refs:
        assert r["type"] in ("article", "report") and r["authors"] and r["year"]


def test_version_comes_from_the_installed_metadata():
    assert projtrack.__version__ == META["version"]


def test_core_dependencies_are_light_and_every_extra_is_in_the_book_extra():
    assert sorted(d.split(">")[0] for d in META["dependencies"]) == ["numpy", "scipy"]
    extras = META["optional-dependencies"]
    for name in ("sdp", "fast", "kalman", "learn"):
        assert set(extras[name]) <= set(extras["book"]), name
        assert set(extras[name]) <= set(extras["all"]), name


def test_readme_has_the_library_section():
    text = (ROOT / "README.md").read_text()
    assert "## Using only the library" in text
    assert "pip install .  " in text and 'pip install ".[kalman' in text


def test_readme_library_example_runs(capsys):
    text = (ROOT / "README.md").read_text()
    section = text.split("## Using only the library", 1)[1].split("\n## ", 1)[0]
    code = section.split("```python\n", 1)[1].split("```", 1)[0]
    assert len(code.strip().splitlines()) <= 12
    exec(compile(code, "README.md", "exec"), {})
    out = capsys.readouterr().out
    assert out.startswith("[3.")
