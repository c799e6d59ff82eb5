"""Keep the built book self-contained and free of console errors when read offline.

Jupyter Book 1 always loads sphinx-thebe, which adds an inline script declaring
``THEBE_JS_URL`` (a CDN address) to every page, twice: the second declaration is a
JavaScript ``SyntaxError`` in the browser console. The book does not offer live code
(``launch_buttons.thebe`` is false: a live kernel needs the network), so this extension
removes sphinx-thebe's scripts from every page, and drops any repeated script, so that no
page refers to a network address for scripts, styles or fonts.
"""

from __future__ import annotations


def _is_thebe(js) -> bool:
    name = getattr(js, "filename", None) or str(js)
    body = (getattr(js, "attributes", None) or {}).get("body", "")
    return "sphinx-thebe" in str(name) or "THEBE_JS_URL" in body


def _clean_scripts(app, pagename, templatename, context, doctree):
    scripts = context.get("script_files")
    if not scripts:
        return
    seen, kept = set(), []
    for js in scripts:
        key = (str(getattr(js, "filename", js)), repr(sorted((getattr(js, "attributes", None) or {}).items())))
        if _is_thebe(js) or key in seen:
            continue
        seen.add(key)
        kept.append(js)
    scripts[:] = kept


def setup(app):
    app.connect("html-page-context", _clean_scripts, priority=900)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
