"""Sphinx configuration of the dptbd documentation site.

Build: ``bash scripts/setup.sh docs`` (or ``.venv/bin/python -m sphinx -W -b html docs
build/site``); the HTML lands in ``build/site``. ``tests/docs/test_site.py`` builds it with
warnings as errors, so a broken cross-reference or a stale docstring fails the suite.

Why Sphinx (with myst-parser and numpydoc) rather than MkDocs: the docstrings are written in
reST with numpydoc sections and cross-reference roles (``:func:`~dptbd.model.fixed.run_fixed```,
``:data:``, ``:attr:``); Sphinx resolves those roles natively and reports each one that does
not resolve (``nitpicky``), which is what lets the build fail on a stale docstring;
mkdocstrings would need the docstrings rewritten in Markdown. myst-parser renders the existing
Markdown documents unchanged, and sphinx-argparse documents the CLI from the parsers the
``dptbd`` command itself builds.
"""

from __future__ import annotations

import pathlib
import pkgutil
import re
import shutil
import types

import functools

import numpydoc.docscrape_sphinx
import numpydoc.numpydoc
from docutils import nodes

project = "dptbd"
author = "the dptbd authors"
copyright = "the dptbd authors, MIT licence"

extensions = [
    "myst_parser",              # the Markdown documents in docs/ and the README
    "sphinx.ext.autodoc",       # the API reference from the docstrings
    "sphinx.ext.autosummary",   # one page per module of dptbd.model/.hw/.sim/.dsp
    "numpydoc",                 # the docstrings' numpydoc sections
    "sphinxarg.ext",            # the CLI reference from dptbd.cli.build_parser
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
templates_path = ["_templates"]
exclude_patterns = ["_build", "figures"]

# Every cross-reference must resolve: a reference to a renamed or removed object fails the
# build (the test builds with -W).
nitpicky = True

# No typographic quotes and dashes: ``--rtl-frames`` in a help text or a document stays two
# hyphens (the documents write their own Unicode where they mean it).
smartquotes = False

# MyST: heading anchors so that links to "#a-section" in the documents resolve.
myst_heading_anchors = 4
myst_enable_extensions = ["dollarmath"]

# autodoc / autosummary: one page per module (docs/_templates/autosummary/module.rst),
# generated at build time into docs/api/generated (not committed).
autosummary_generate = True
autosummary_imported_members = False
# Each object is documented once, on the page of the module that defines it, with everything
# public that module defines (``ignore-module-all``: a package's ``__all__`` re-exports are not
# described again; a reference through the package, ``dptbd.config.DPConfig``, still resolves,
# see _resolve_as_python below).
autodoc_default_options = {"members": True, "undoc-members": True, "ignore-module-all": True,
                           "member-order": "bysource"}
# Modules autosummary cannot reach by name, documented at the end of their package's page
# instead (docs/_templates/autosummary/module.rst): a package attribute of the same name
# shadows the first two (``from .segmenter import segmenter``), and the third is private but
# defines the public ``SceneError``.
autosummary_context = {"appended_modules": {
    "dptbd.hw.wide": ["segmenter"],
    "dptbd.sim.coverage.bins": ["table"],
    "dptbd.scenes": ["_checks"],
}}
autodoc_typehints = "none"          # the docstrings describe the types in their own words
autoclass_content = "class"
# No signature from a docstring's first line (that is for extension modules): a dataclass
# without a docstring has a generated one (see _autodoc_signature below).
autodoc_docstring_signature = False

# numpydoc: the class pages list their members through autodoc, not numpydoc's tables. The
# gateware's components document their ports in a "Members" section (Amaranth's name for a
# signature's members), which numpydoc does not know and would drop with only a Python
# warning: _members_in / _members_out below hand it to numpydoc as "Attributes" and title the
# result "Members" again.
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

# References into the standard library, numpy, Amaranth and systemrdl-compiler: no
# intersphinx (the build is offline and no inventory is vendored), so they cannot resolve;
# they render as code, unlinked. Only these namespaces are exempt: a reference into dptbd
# that does not resolve fails the build.
nitpick_ignore_regex = [
    (r"py:.*", r"(os|math|ctypes|pkgutil|importlib|json|pathlib|argparse|numpy|amaranth|"
               r"systemrdl)(\..*)?"),
]




# --- References by the name a module sees -------------------------------------------------
# The docstrings refer to objects as their module sees them: ``:class:`DPCore``` where
# ``DPCore`` is imported, ``:class:`dptbd.config.AxiStoreConfig``` for a name a package
# re-exports. Sphinx looks such a name up only among the names objects are documented under
# (the module that defines them), so a reference that Python resolves fails. This handler
# resolves the reference the way Python does (importing the path from the docstring's module)
# and links to where that object is documented. It resolves nothing else: a name Python does
# not find, or an object the site does not document, still fails the build.

def _canonical(path: str, obj: object) -> str | None:
    if isinstance(obj, types.ModuleType):
        return obj.__name__
    module, qualname = getattr(obj, "__module__", None), getattr(obj, "__qualname__", None)
    if isinstance(module, str) and isinstance(qualname, str) and "<" not in qualname:
        return f"{module}.{qualname}"
    return None


def _lookup(path: str):
    try:
        return True, pkgutil.resolve_name(path)
    except (ImportError, AttributeError, ValueError):
        return False, None


def _resolve_as_python(app, env, node, contnode):
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip(".~")
    module, cls = node.get("py:module"), node.get("py:class")
    paths = [p for p in (f"{module}.{cls}.{target}" if module and cls else None,
                         f"{module}.{target}" if module else None, target) if p]
    domain = env.get_domain("py")
    for path in paths:
        found, obj = _lookup(path)
        if not found:
            continue
        names = []
        canonical = _canonical(path, obj)
        if canonical is not None:
            names.append(canonical)
        elif "." in path:
            parent_path, last = path.rsplit(".", 1)
            parent_found, parent = _lookup(parent_path)
            parent_canonical = _canonical(parent_path, parent) if parent_found else None
            if parent_canonical is not None:
                names.append(f"{parent_canonical}.{last}")
            # a constant has no name of its own: the documented names that are this object
            names += [name for name in domain.objects
                      if name.endswith("." + last) and _lookup(name)[1] is obj]
        for name in names:
            if name in domain.objects:
                plain = node.deepcopy()
                plain["reftarget"] = name
                plain["refspecific"] = False
                return domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"],
                                           name, plain, contnode)
        break
    # Not visible from the docstring's module (a name the prose mentions, ``DPConfig.axi_store``
    # in a module that does not import DPConfig): the one documented object of that role whose
    # name ends with it, as Sphinx does for a reference written ``.DPConfig.axi_store``; none,
    # or more than one, fails the build.
    matches = domain.find_obj(env, None, None, target, node["reftype"], searchmode=1)
    if len(matches) == 1:
        plain = node.deepcopy()
        plain["reftarget"] = matches[0][0]
        plain["refspecific"] = False
        return domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"],
                                   matches[0][0], plain, contnode)
    return None


def _clear_generated(app):
    """Start from no stub pages, so a removed or renamed module leaves none behind."""
    shutil.rmtree(pathlib.Path(app.srcdir) / "api" / "generated", ignore_errors=True)


# --- ``docs/NAME.md`` as a link -----------------------------------------------------------
# The documents, the README and the docstrings name a document as code, ``docs/gateware.md``
# (what reads right on GitHub and in a terminal); in the site each such name links to its page.

_DOC_NAME = re.compile(r"docs/([A-Za-z0-9_]+)\.md")


def _link_document_names(app, doctree, docname):
    for literal in list(doctree.findall(nodes.literal)):
        match = _DOC_NAME.fullmatch(literal.astext())
        if match is None or match.group(1) not in app.env.all_docs \
                or isinstance(literal.parent, nodes.reference):
            continue
        uri = app.builder.get_relative_uri(docname, match.group(1))
        reference = nodes.reference("", "", internal=True, refuri=uri)
        literal.replace_self(reference)
        reference.append(literal)


# --- The components' "Members" sections -------------------------------------------------------

_MEMBERS_AS_ATTRIBUTES: set[str] = set()


def _members_in(app, what, name, obj, options, lines):
    """Before numpydoc (priority 500): a "Members" section becomes "Attributes"."""
    for i in range(len(lines) - 1):
        if lines[i].strip() == "Members" and set(lines[i + 1].strip()) == {"-"}:
            indent = lines[i][:len(lines[i]) - len(lines[i].lstrip())]
            lines[i], lines[i + 1] = indent + "Attributes", indent + "----------"
            _MEMBERS_AS_ATTRIBUTES.add(name)


def _members_out(app, what, name, obj, options, lines):
    """After numpydoc: the section it rendered is titled "Members" again."""
    if name in _MEMBERS_AS_ATTRIBUTES:
        lines[:] = [":Members:" + line[len(":Attributes:"):] if line.startswith(":Attributes:")
                    else line for line in lines]


@functools.lru_cache(maxsize=None)
def _numpydoc_template(builder):
    """numpydoc's docstring template as its ``get_doc_object`` loads it, loaded once."""
    from jinja2.sandbox import SandboxedEnvironment
    from sphinx.jinja2glue import BuiltinTemplateLoader

    loader = BuiltinTemplateLoader()
    loader.init(builder, dirs=[str(pathlib.Path(numpydoc.docscrape_sphinx.__file__).parent
                                   / "templates")])
    return SandboxedEnvironment(loader=loader).get_template("numpydoc_docstring.rst")


def _numpydoc_doc_object(obj, what=None, doc=None, config=None, builder=None):
    """numpydoc 1.11's ``get_doc_object`` with its template loaded once, not once per
    docstring (a new Jinja environment each time: about a tenth of the build)."""
    config = {} if config is None else config
    config["template"] = _numpydoc_template(builder)
    d = numpydoc.docscrape_sphinx
    return d.get_doc_object_orig(obj, what=what, doc=doc, config=config,
                                 class_doc=d.SphinxClassDoc, func_doc=d.SphinxFunctionDoc,
                                 obj_doc=d.SphinxObjDoc)


def _numpydoc_for_dptbd(app, what, name, obj, options, lines):
    module = getattr(obj, "__module__", None)
    if isinstance(module, str) and not module.startswith("dptbd"):
        return
    numpydoc.numpydoc.mangle_docstrings(app, what, name, obj, options, lines)


def setup(app):
    app.connect("autodoc-process-docstring", _members_in, priority=400)
    app.connect("autodoc-process-docstring", _members_out, priority=600)
    app.connect("doctree-resolved", _link_document_names)
    app.connect("builder-inited", _clear_generated, priority=400)  # before autosummary (500)
    # numpydoc's signature handler replaces autodoc's signature (no annotations:
    # autodoc_typehints = "none") with one it reads from the raw docstring: with the annotations
    # of a dataclass's generated docstring (``notes: 'tuple[str, ...]'``, which Sphinx splits
    # at the comma into a broken reference), and a warning on stderr for each section it does
    # not know (the components' "Members", Amaranth's "Platform Overrides"). The docstrings
    # carry no signatures of their own, so autodoc's stands.
    for listener in list(app.events.listeners.get("autodoc-process-signature", [])):
        if listener.handler is numpydoc.numpydoc.mangle_signature:
            app.disconnect(listener.id)
    # numpydoc's docstring handler only for dptbd's own objects: autodoc also hands it the
    # docstrings of imported names while it decides to leave them out (Amaranth's Memory, whose
    # "Platform Overrides" section numpydoc warns about on stderr); they are not rendered.
    for listener in list(app.events.listeners.get("autodoc-process-docstring", [])):
        if listener.handler is numpydoc.numpydoc.mangle_docstrings:
            app.disconnect(listener.id)
            app.connect("autodoc-process-docstring", _numpydoc_for_dptbd, priority=listener.priority)
    app.connect("missing-reference", _resolve_as_python)
    numpydoc.numpydoc.get_doc_object = _numpydoc_doc_object


html_theme = "alabaster"
html_title = "dptbd"
html_static_path: list[str] = []

# No intersphinx: the build is offline (CI has no network).
