"""The documentation site (docs/conf.py) builds with every warning an error, offline, and holds
what the README promises: the documents, the README's figures, the API reference of the four
sub-packages, the register reference and the CLI reference of every sub-command."""

from __future__ import annotations

import ast
import pathlib
import re
import subprocess
import sys

from dptbd.cli import COMMANDS

ROOT = pathlib.Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"


def _conf() -> dict:
    """docs/conf.py's top-level assignments, read without running it."""
    tree = ast.parse((DOCS / "conf.py").read_text())
    values = {}
    for node in tree.body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 \
                and isinstance(node.targets[0], ast.Name):
            try:
                values[node.targets[0].id] = ast.literal_eval(node.value)
            except ValueError:
                pass
    return values


def test_conf_fails_on_every_unresolved_dptbd_reference():
    conf = _conf()
    assert conf["nitpicky"] is True
    assert "nitpick_ignore" not in conf
    # the only exemption: references into the standard library, numpy, Amaranth and
    # systemrdl-compiler (no intersphinx); never one into dptbd
    patterns = [pattern for _, pattern in conf["nitpick_ignore_regex"]]
    assert patterns == [r"(os|math|ctypes|pkgutil|importlib|json|pathlib|argparse|numpy|amaranth|"
                        r"systemrdl)(\..*)?"]
    assert not any(re.fullmatch(pattern, target) for pattern in patterns
                   for target in ("dptbd", "dptbd.hw.register_map.FIELD_KINDS", "FIELD_KINDS"))
    assert "sphinx.ext.intersphinx" not in conf["extensions"]


def _text(page: pathlib.Path) -> str:
    return re.sub(r"<[^>]+>", "", page.read_text())


def test_the_site_builds_with_warnings_as_errors_and_holds_what_the_readme_promises(tmp_path):
    # One test, one build: the build writes its API stub pages into docs/api/generated, so two
    # xdist workers must not each build it (a module fixture would be built once per worker).
    html = tmp_path / "html"
    # a fresh doctree cache: every page read, so every warning reported
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
           "-d", str(tmp_path / "doctrees"), str(DOCS), str(html)]
    # stderr must be empty: a Python warning (an extension dropping a section) fails too
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr[-20000:]

    # every document is a page
    for md in sorted(DOCS.glob("*.md")):
        assert (html / md.with_suffix(".html").name).is_file(), md.name
    assert "Registers of" in _text(html / "registers.html")

    # the README's figure and every figure of the documents
    images = {p.name for p in (html / "_images").iterdir()}
    readme = (html / "readme.html").read_text()
    assert '<img alt="Pd vs SNR' in readme and 'src="_images/compare_pd.png"' in readme
    for md in sorted(DOCS.glob("*.md")):
        for line in md.read_text().splitlines():
            if "](figures/" in line:
                name = line.split("](figures/", 1)[1].split(")", 1)[0]
                assert name in images, (md.name, name)

    # document names link to their pages: the README's "(`docs/table1.md`)", and
    # docs/gateware.md names docs/arithmetic.md the same way
    assert re.search(r'<a class="reference internal" href="table1.html"><code[^>]*>'
                     r'<span class="pre">docs/table1.md</span>', readme)
    assert re.search(r'href="arithmetic.html"><code[^>]*><span class="pre">docs/arithmetic.md',
                     (html / "gateware.html").read_text())

    # the API reference of the four sub-packages, from the docstrings
    api = html / "api" / "generated"
    for package in ("dptbd.model", "dptbd.hw", "dptbd.sim", "dptbd.dsp"):
        assert (api / f"{package}.html").is_file(), package
    assert 'id="dptbd.model.fixed.run_fixed"' in (api / "dptbd.model.fixed.html").read_text()
    # numpydoc does not know "Members" (Amaranth's name for a signature's members);
    # docs/conf.py hands it over as Attributes and titles it Members again
    fifo = _text(api / "dptbd.hw.thermometer_fifo.html")
    assert "Members:" in fifo and "Writes; w.ready is a register" in fifo

    # the CLI reference: every sub-command's usage line; options keep their two hyphens
    cli = _text(html / "cli.html")
    for name in COMMANDS:
        assert f"dptbd {name} [-h]" in cli, name
    assert "--rtl-frames" in cli and "\u2013rtl-frames" not in cli


def _mini_site(tmp_path: pathlib.Path, body: str) -> subprocess.CompletedProcess:
    """A one-page site with docs/conf.py's settings and handlers (not its pages), documenting
    ``dptbd.config.axi_store``, which defines ``AxiStoreConfig`` (re-exported by
    ``dptbd.config``)."""
    src = tmp_path / "src"
    src.mkdir()
    # the module's docstrings refer to DPConfig, which this one page does not document
    (src / "conf.py").write_text(f"exec(open({str(DOCS / 'conf.py')!r}).read())\n"
                                 "templates_path = []\n"
                                 "nitpick_ignore_regex.append(('py:.*', '(dptbd[.]config[.])?DPConfig[.].*'))\n")
    (src / "index.rst").write_text("Mini\n====\n\n" + body
                                   + "\n\n.. automodule:: dptbd.config.axi_store\n")
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
           str(src), str(tmp_path / "html")]
    return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)


def test_a_reference_to_an_object_that_does_not_exist_fails_the_build(tmp_path):
    proc = _mini_site(tmp_path, ":class:`dptbd.config.NoSuchConfig`")
    assert proc.returncode != 0
    assert "py:class reference target not found: dptbd.config.NoSuchConfig" in proc.stderr


def test_a_reference_through_a_re_export_links_to_the_defining_module(tmp_path):
    proc = _mini_site(tmp_path, ":class:`dptbd.config.AxiStoreConfig`")
    assert proc.returncode == 0, proc.stderr
    page = (tmp_path / "html" / "index.html").read_text()
    assert 'href="#dptbd.config.axi_store.AxiStoreConfig"' in page
