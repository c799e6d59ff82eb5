"""The built HTML book, read as a reader would: offline, from disk, in a real browser.

Run by ``make browsercheck`` (part of ``make test``) after the strict build, on
``book/_build/html``. Two kinds of checks:

* static, on the HTML files (no browser needed): no page refers to a network address for a
  script, a style sheet, a font or an image, and every internal link and ``#anchor``
  resolves to a built page and an element id in it;
* in headless Chromium (Debian's ``chromium`` and ``chromium-driver``, driven by Selenium),
  each page opened from ``file://`` with no network: equations typeset by MathJax (a
  ``mjx-container`` for every math element, no raw ``\\(``, ``\\[`` or ``$$`` left in the
  visible text outside code), every image loaded, no error in the console, and no request
  for anything but local files;
* how the book reads, at 1400 x 900: no output block (also inside folded dropdowns, opened
  for the check), display equation or visible code block wider than its column; per page the
  visible words (the article's ``innerText``), the visible code lines (displayed
  ``.cell_input`` blocks) and the distance from the top of the article to its first loaded
  image, printed as a table; the first figure of every page that has one within
  :data:`FIRST_FIGURE_PX`, the landing page showing a figure, and the whole book within
  :data:`MAX_CODE_LINES` visible code lines and :data:`MAX_WORDS` visible words.

Without Chromium the browser checks are skipped with a message saying how to install it.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import tempfile
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

ROOT = Path(__file__).resolve().parents[2]
HTML = Path(os.environ.get("PROJTRACK_BOOK_HTML", ROOT / "book" / "_build" / "html"))
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")
INSTALL_HINT = ("install Debian's chromium and chromium-driver (apt-get install chromium chromium-driver) "
                "to run the browser checks of the built book")

# Pages Sphinx writes that are not pages of the book.
_SKIP = {"genindex.html", "search.html", "py-modindex.html"}

#: The reading budget of the whole book (issue: the result first, nothing cut off, details folded).
MAX_CODE_LINES = 800
MAX_WORDS = 45_000
FIRST_FIGURE_PX = 1500
WINDOW = (1400, 900)
#: Reference pages (the API reference) are not counted in the reading budget.
_REFERENCE = ("api", "_autosummary", "generated")


def _pages() -> list[Path]:
    if not (HTML / "index.html").is_file():
        return []
    return sorted(p for p in HTML.rglob("*.html")
                  if "_static" not in p.parts and "_sources" not in p.parts and p.name not in _SKIP)


PAGES = _pages()


@pytest.fixture(scope="module", autouse=True)
def _built_book():
    if not PAGES:
        pytest.fail(f"no built book at {HTML}: run `make bookcheck` (or `make html`) first")


class _Refs(HTMLParser):
    """Collect element ids and every referenced URL (with the tag and attribute)."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.ids: set[str] = set()
        self.refs: list[tuple[str, str, str, str]] = []  # (tag, attr, value, rel)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(a["id"])
        if tag == "a" and a.get("name"):
            self.ids.add(a["name"])
        for attr in ("href", "src"):
            if a.get(attr):
                self.refs.append((tag, attr, a[attr], a.get("rel") or ""))


_PARSED: dict[Path, _Refs] = {}


def _parse(path: Path) -> _Refs:
    if path not in _PARSED:
        p = _Refs()
        p.feed(path.read_text(encoding="utf-8"))
        _PARSED[path] = p
    return _PARSED[path]


def _is_external(url: str) -> bool:
    return urlsplit(url).scheme in ("http", "https") or url.startswith("//")


_CSS_URL = re.compile(r"url\(\s*['\"]?(https?:)?//", re.I)
_CSS_IMPORT = re.compile(r"@import\s+(url\()?\s*['\"]?(https?:)?//", re.I)


def test_no_page_loads_anything_from_the_network():
    problems = []
    for page in PAGES:
        for tag, attr, url, rel in _parse(page).refs:
            loads = (tag in ("script", "img", "iframe", "source", "video", "audio", "embed")
                     or (tag == "link" and rel not in ("canonical", "alternate")))
            if loads and _is_external(url):
                problems.append(f"{page.relative_to(HTML)}: <{tag} {attr}={url!r}>")
    for css in HTML.rglob("*.css"):
        text = css.read_text(encoding="utf-8", errors="replace")
        if _CSS_URL.search(text) or _CSS_IMPORT.search(text):
            problems.append(f"{css.relative_to(HTML)}: a style sheet loads a network address")
    assert not problems, "pages refer to network addresses:\n" + "\n".join(problems[:20])


def test_mathjax_is_served_from_the_book():
    assert (HTML / "_static" / "mathjax" / "tex-chtml.js").is_file()
    with_math = [p for p in PAGES if 'class="math' in p.read_text(encoding="utf-8")]
    assert with_math, "no page has math: the math check below would be empty"
    for page in with_math:
        srcs = [u for t, a, u, _ in _parse(page).refs if t == "script" and "mathjax" in u.lower()]
        assert srcs and all(not _is_external(u) for u in srcs), f"{page.relative_to(HTML)}: MathJax {srcs}"


def test_every_internal_link_and_anchor_resolves():
    problems = []
    for page in PAGES:
        for tag, attr, url, _ in _parse(page).refs:
            if tag != "a" or _is_external(url) or url.startswith(("mailto:", "javascript:", "data:")):
                continue
            parts = urlsplit(url)
            target = page if not parts.path else (page.parent / unquote(parts.path)).resolve()
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                problems.append(f"{page.relative_to(HTML)}: link {url!r} -> missing file")
                continue
            if parts.fragment and target.suffix == ".html":
                if unquote(parts.fragment) not in _parse(target).ids:
                    problems.append(f"{page.relative_to(HTML)}: link {url!r} -> no element #{parts.fragment}")
    assert not problems, f"{len(problems)} broken internal links:\n" + "\n".join(problems[:30])


# -- in a real browser -------------------------------------------------------------------

@pytest.fixture(scope="module")
def browser():
    if not (CHROMIUM and CHROMEDRIVER):
        msg = f"CHROMIUM NOT FOUND: the browser checks of the built book were NOT run; {INSTALL_HINT}"
        print("\n" + "!" * 80 + "\n" + msg + "\n" + "!" * 80)
        pytest.skip(msg)
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    profile = tempfile.mkdtemp(prefix="projtrack-chromium-")
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                "--disable-dev-shm-usage", f"--window-size={WINDOW[0]},{WINDOW[1]}", f"--user-data-dir={profile}"):
        opts.add_argument(arg)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)
    driver.set_script_timeout(60)
    driver.set_page_load_timeout(60)
    yield driver
    driver.quit()
    shutil.rmtree(profile, ignore_errors=True)


_WAIT_FOR_MATHJAX = """
const done = arguments[arguments.length - 1];
const settle = () => Promise.all(Array.from(document.images).map(img => img.complete ? null :
    new Promise(r => { img.onload = img.onerror = r; })));
// MathJax is loaded asynchronously: on a busy machine its script may not have run yet
// when the page's load event fires, so wait (up to 30 s) for it to start.
const wantsMath = !!document.querySelector('script[src*="mathjax" i]');
const t0 = Date.now();
(function poll() {
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
    MathJax.startup.promise.then(settle).then(() => done('mathjax'), e => done('error: ' + e));
  } else if (wantsMath && Date.now() - t0 < 30000) {
    setTimeout(poll, 50);
  } else {
    settle().then(() => done(wantsMath ? 'mathjax did not start within 30 s' : 'no-mathjax'));
  }
})();
"""

_PAGE_FACTS = """
const body = document.body.cloneNode(true);
body.querySelectorAll('pre, code, script, style, mjx-container, .highlight, textarea').forEach(e => e.remove());
const text = body.textContent;
return {
  math: document.querySelectorAll('.math').length,
  typeset: document.querySelectorAll('mjx-container').length,
  mathErrors: document.querySelectorAll('mjx-merror, [data-mjx-error]').length,
  raw: ['\\\\(', '\\\\[', '$$'].filter(s => text.includes(s)),
  badImages: Array.from(document.images).filter(i => !(i.complete && i.naturalWidth > 0))
                  .map(i => i.getAttribute('src')),
};
"""


_READING = r"""
const art = document.querySelector('article.bd-article') || document.querySelector('main') || document.body;
window.scrollTo(0, 0);
const top = art.getBoundingClientRect().top;
const shown = e => !!(e.offsetParent || e.getClientRects().length) && !e.closest('details:not([open])');
const words = (art.innerText.match(/\S+/g) || []).length;
let code = 0;
art.querySelectorAll('.cell_input').forEach(c => { if (shown(c)) code += c.innerText.split('\n').filter(l => l.trim()).length; });
const img = Array.from(art.querySelectorAll('img')).find(i => shown(i) && i.complete && i.naturalWidth > 0);
const wide = [];
const right = art.getBoundingClientRect().right - parseFloat(getComputedStyle(art).paddingRight) + 2;
const check = (sel, kind) => art.querySelectorAll(sel).forEach(e => {
  if (!shown(e)) return;
  const r = e.getBoundingClientRect();
  if (e.scrollWidth > e.clientWidth + 2 || r.right > right) {
    wide.push(kind + ': ' + (e.innerText || e.getAttribute('src') || '').trim().slice(0, 70).replace(/\s+/g, ' '));
  }
});
// outputs, including those in folded dropdowns and collapsed cells: open everything first
art.querySelectorAll('details').forEach(d => d.open = true);
art.querySelectorAll('.toggle-hidden').forEach(e => e.classList.remove('toggle-hidden'));
check('.cell_output .output, .cell_output pre, .cell_output table, .cell_output img, table, img, mjx-container[display="true"]', 'output');
return {words: words, code: code, figure: img ? Math.round(img.getBoundingClientRect().top - top) : null, wide: wide};
"""

_CODE_WIDTH = r"""
const art = document.querySelector('article.bd-article') || document.body;
const shown = e => !!(e.offsetParent || e.getClientRects().length) && !e.closest('details:not([open])');
const out = [];
art.querySelectorAll('.cell_input pre, div.highlight pre').forEach(e => {
  if (shown(e) && e.scrollWidth > e.clientWidth + 2) out.push('code: ' + e.innerText.trim().split('\n')[0].slice(0, 70));
});
return out;
"""

#: Per-page reading facts gathered by the page test, checked and printed by the budget test.
READING: dict[str, dict] = {}


@pytest.mark.parametrize("page", PAGES, ids=[p.relative_to(HTML).as_posix() for p in PAGES])
def test_page_reads_offline_in_chromium(browser, page):
    browser.get_log("browser"), browser.get_log("performance")  # drop earlier pages' logs
    from selenium.webdriver.support.ui import WebDriverWait

    browser.execute_script("window.__projtrackPreviousPage = true;")
    browser.get(page.as_uri())
    # make sure the scripts below run in the new page, fully loaded, not in the previous one
    # (the marker set above exists only in the previous page's window object)
    WebDriverWait(browser, 60).until(lambda d: d.execute_script(
        "return document.readyState === 'complete' && !window.__projtrackPreviousPage;"))
    state = browser.execute_async_script(_WAIT_FOR_MATHJAX)
    facts = browser.execute_script(_PAGE_FACTS)
    problems = []
    if state.startswith("error"):
        problems.append(f"MathJax failed: {state}")
    if facts["math"] and state != "mathjax":
        problems.append(f"{facts['math']} math elements but MathJax did not load ({state})")
    if facts["typeset"] < facts["math"]:
        problems.append(f"only {facts['typeset']} of {facts['math']} math elements typeset")
    if facts["mathErrors"]:
        problems.append(f"{facts['mathErrors']} MathJax errors")
    if facts["raw"]:
        problems.append(f"raw TeX delimiters in the visible text: {facts['raw']}")
    if facts["badImages"]:
        problems.append(f"images not loaded: {facts['badImages'][:5]}")
    errors = [e["message"] for e in browser.get_log("browser") if e["level"] == "SEVERE"]
    if errors:
        problems.append(f"console errors: {errors[:3]}")
    remote = []
    for entry in browser.get_log("performance"):
        msg = json.loads(entry["message"])["message"]
        if msg.get("method") == "Network.requestWillBeSent":
            url = msg["params"]["request"]["url"]
            if _is_external(url) or url.startswith(("ws:", "wss:", "ftp:")):
                remote.append(url)
    if remote:
        problems.append(f"network requests: {remote[:5]}")
    # how it reads: measured on the page as a reader first sees it (code width), then with every
    # dropdown opened (outputs)
    code_wide = browser.execute_script(_CODE_WIDTH)
    facts = browser.execute_script(_READING)
    rel = page.relative_to(HTML).as_posix()
    READING[rel] = {**facts, "wide": code_wide + facts["wide"]}
    if READING[rel]["wide"]:
        problems.append(f"{len(READING[rel]['wide'])} blocks wider than the column, e.g. {READING[rel]['wide'][:3]}")
    if facts["figure"] is not None and facts["figure"] > FIRST_FIGURE_PX and not rel.startswith(_REFERENCE):
        problems.append(f"the first figure is {facts['figure']} px below the top of the article "
                        f"(at most {FIRST_FIGURE_PX})")
    if rel in ("index.html", "intro.html") and facts["figure"] is None:
        problems.append("the landing page shows no figure")
    assert not problems, f"{rel}: " + "; ".join(problems)


def _is_redirect(page: Path) -> bool:
    """Sphinx's root index.html only redirects to the landing page: counting it would count
    the landing page twice."""
    return page.read_text(errors="replace").lstrip().lower().startswith('<meta http-equiv="refresh"')


def test_reading_budget_of_the_whole_book(browser):
    """Totals over the book's pages (the API reference apart), printed per page."""
    if len(READING) < len(PAGES):
        pytest.skip("run with the page tests (the whole module) to measure the whole book")
    lines = [f"{'page':58s} {'words':>7s} {'code':>5s} {'1st fig px':>10s}"]
    words = code = 0
    for rel, f in sorted(READING.items()):
        if rel.startswith(_REFERENCE) or _is_redirect(HTML / rel):
            continue
        words += f["words"]
        code += f["code"]
        lines.append(f"{rel:58s} {f['words']:7d} {f['code']:5d} {'-' if f['figure'] is None else f['figure']:>10}")
    lines.append(f"{'total (budget: ' + str(MAX_WORDS) + ' words, ' + str(MAX_CODE_LINES) + ' code lines)':58s} "
                 f"{words:7d} {code:5d}")
    table = "\n".join(lines)
    out = Path(os.environ.get("PROJTRACK_READING_REPORT", ROOT / ".cache" / "reading.txt"))
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(table + "\n")
    print("\n" + table)
    assert code <= MAX_CODE_LINES, f"{code} visible code lines (at most {MAX_CODE_LINES})"
    assert words <= MAX_WORDS, f"{words} visible words (at most {MAX_WORDS})"
