"""The API reference (book/api/): one page per topic package, public names only, examples that run.

* every topic page documents exactly the package's public names (its ``__all__``), each once;
* the topic pages build with Sphinx's autodoc/autosummary/napoleon, warnings as errors and
  nitpicky references, and the built HTML holds no private name and renders maths;
* every main entry point has an Examples section, and its examples pass (doctest).

The whole book, API pages included, is also built strictly by ``make test`` (bookcheck).
"""

from __future__ import annotations

import doctest
import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
API = ROOT / "book" / "api"
TOPICS = ["ellipsoids", "dma", "correlators", "hough", "jpda", "neuralnet", "novelty"]
MAIN_ENTRY_POINTS = [
    "projtrack.ellipsoids.reconstruct",
    "projtrack.jpda.beta",
    "projtrack.jpda.mvm_from_positions",
    "projtrack.jpda.JPDATracker",
    "projtrack.hough.TrackInitiator",
    "projtrack.hough.find_peaks",
    "projtrack.dma.viterbi",
    "projtrack.novelty.NoveltyFilter",
    "projtrack.correlators.ProjectionCorrelationClassifier",
]
DIRECTIVE = re.compile(r"^\.\. auto(?:function|class|exception|data):: (\S+)", re.M)


def _documented(topic: str) -> list[str]:
    return DIRECTIVE.findall((API / f"{topic}.md").read_text())


@pytest.mark.parametrize("topic", TOPICS)
def test_topic_page_documents_exactly_the_public_names(topic):
    mod = importlib.import_module(f"projtrack.{topic}")
    names = _documented(topic)
    assert len(names) == len(set(names)), f"api/{topic}.md documents a name twice"
    assert not [n for n in names if n.startswith("_")], "a private name is documented"
    missing = sorted(set(mod.__all__) - set(names))
    extra = sorted(set(names) - set(mod.__all__))
    assert not missing, f"api/{topic}.md does not document {missing}"
    assert not extra, f"api/{topic}.md documents names that projtrack.{topic} does not export: {extra}"


def test_every_page_is_in_the_table_of_contents():
    toc = (ROOT / "book" / "_toc.yml").read_text()
    for page in sorted(API.glob("*.md")):
        assert f"file: api/{page.stem}" in toc, f"book/api/{page.name} is not listed in book/_toc.yml"


@pytest.mark.parametrize("name", MAIN_ENTRY_POINTS)
def test_main_entry_point_examples_pass(name):
    modname, attr = name.rsplit(".", 1)
    obj = getattr(importlib.import_module(modname), attr)
    assert "Examples\n" in (obj.__doc__ or ""), f"{name} has no Examples section"
    tests = [t for t in doctest.DocTestFinder(recurse=False).find(obj, name) if t.examples]
    assert tests, f"{name} has no doctest example"
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    for t in tests:
        runner.run(t)
    res = runner.summarize(verbose=False)
    assert res.failed == 0, f"{res.failed} example(s) of {name} failed (run pytest --doctest-modules to see them)"


CONF = '''
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.autosummary", "sphinx.ext.napoleon",
              "sphinx.ext.mathjax"]
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
autodoc_typehints = "none"
autodoc_member_order = "bysource"
autodoc_default_options = {"members": True}
autosummary_generate = False
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False
napoleon_use_ivar = True
strip_signature_backslash = True
# other libraries' names cannot be resolved offline; the book's own pages (scenes, experiments)
# are not part of this build (the full book build resolves them)
nitpick_ignore_regex = [("py:.*", r"(?!projtrack\\.).*"), ("py:.*", r"projtrack\\.(experiments|scenes)(\\..*)?")]
html_theme = "basic"
'''


@pytest.fixture(scope="module")
def built_pages(tmp_path_factory):
    """The topic pages built alone by sphinx-build -W -n (the book's settings for the API)."""
    src = tmp_path_factory.mktemp("api_src")
    (src / "conf.py").write_text(CONF)
    for topic in TOPICS:
        (src / f"{topic}.md").write_text((API / f"{topic}.md").read_text())
    (src / "index.rst").write_text("API\n===\n\n.. toctree::\n\n" + "".join(f"   {t}\n" for t in TOPICS))
    out = tmp_path_factory.mktemp("api_html")
    res = subprocess.run([sys.executable, "-m", "sphinx", "-W", "-n", "--keep-going", "-q", "-b", "html",
                          str(src), str(out)], capture_output=True, text=True)
    assert res.returncode == 0, f"the API pages do not build strictly:\n{res.stderr[-4000:]}"
    return {t: (out / f"{t}.html").read_text() for t in TOPICS}


@pytest.mark.parametrize("topic", TOPICS)
def test_built_page_has_public_names_only_and_renders_maths(built_pages, topic):
    html = built_pages[topic]
    ids = re.findall(r'<dt class="sig sig-object py" id="(projtrack\.[^"]+)"', html)
    assert ids, "no object was documented"
    private = sorted(i for i in ids if any(part.startswith("_") for part in i.split(".")))
    assert not private, f"private names on the {topic} page: {private}"
    mod = importlib.import_module(f"projtrack.{topic}")
    top = {i.split(".")[2] for i in ids if len(i.split(".")) >= 3}
    assert top == set(mod.__all__), sorted(top ^ set(mod.__all__))
    assert 'class="math' in html, "no maths rendered"
    # fitted attributes keep their trailing underscore (not read as a link)
    if topic == "novelty":
        assert "<strong>eigenvalues_</strong>" in html


def _section(doc: str, title: str) -> str | None:
    m = re.search(title + r"\n-+\n(.*?)(\n\n[A-Z][A-Za-z ]+\n-+\n|\Z)", doc, re.S)
    return m.group(1) if m else None


def _public_callables():
    import inspect

    for topic in TOPICS:
        mod = importlib.import_module(f"projtrack.{topic}")
        for name in mod.__all__:
            obj = getattr(mod, name)
            if not callable(obj) or (inspect.isclass(obj) and issubclass(obj, Warning)):
                continue
            try:
                sig = inspect.signature(obj)
            except (TypeError, ValueError):
                continue
            params = [p.name for p in sig.parameters.values() if p.name != "self"]
            if params:
                yield f"projtrack.{topic}.{name}", inspect.getdoc(obj) or "", params


@pytest.mark.parametrize("name,doc,params", list(_public_callables()), ids=lambda v: v if isinstance(v, str)
                         and v.startswith("projtrack.") else "")
def test_every_public_callable_documents_each_parameter(name, doc, params):
    text = (_section(doc, "Parameters") or "") + (_section(doc, "Attributes") or "")
    assert text, f"{name} has no Parameters section"
    listed = set()
    for line in text.splitlines():
        if line and not line.startswith(" "):
            listed |= {x.strip().lstrip("*") for x in line.split(" : ")[0].split(",")}
    missing = [p for p in params if p not in listed]
    assert not missing, f"{name} does not document {missing}"


@pytest.mark.parametrize("page,package", [("scenes", "scenes"), ("experiments", "experiments")])
def test_book_pages_list_every_module_of_the_scenes_and_the_studies(page, package):
    listed = set(re.findall(r"^\.\. automodule:: (\S+)", (API / f"{page}.md").read_text(), re.M))
    root = ROOT / "src" / "projtrack" / package
    present = {f"projtrack.{package}"}
    for path in root.rglob("*.py"):
        parts = path.relative_to(root).with_suffix("").parts
        if any(p.startswith("_") for p in parts if p != "__init__"):
            continue
        parts = parts[:-1] if parts[-1] == "__init__" else parts
        present.add(".".join(("projtrack", package) + parts))
    assert listed == present, (f"book/api/{page}.md: add {sorted(present - listed)}, "
                               f"remove {sorted(listed - present)}")
