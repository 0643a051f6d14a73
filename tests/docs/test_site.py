"""The documentation site (docs/conf.py) builds with every warning an error, offline, and holds
what the README promises: the documents, the README's figures, the API reference of the four
sub-packages, the register reference and the CLI reference of every sub-command."""

from __future__ import annotations

import ast
import pathlib
import re
import subprocess
import sys

import pytest

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
    # the only exemption: references into the standard library and Amaranth (no intersphinx)
    patterns = [pattern for _, pattern in conf["nitpick_ignore_regex"]]
    assert patterns == [r"(os|math|ctypes|pkgutil|importlib|json|pathlib|argparse|numpy|amaranth)(\..*)?"]
    assert "sphinx.ext.intersphinx" not in conf["extensions"]


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> pathlib.Path:
    out = tmp_path_factory.mktemp("site")
    html = out / "html"
    # a fresh doctree cache: every page read, so every warning reported
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
           "-d", str(out / "doctrees"), str(DOCS), str(html)]
    # stderr must be empty: a Python warning (an extension dropping a section) fails too
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr[-20000:]
    return html


def test_every_document_is_a_page(site):
    for md in sorted(DOCS.glob("*.md")):
        assert (site / md.with_suffix(".html").name).is_file(), md.name


def test_figures_of_the_readme_and_the_documents_are_in_the_site(site):
    images = {p.name for p in (site / "_images").iterdir()}
    assert '<img alt="Pd vs SNR' in (site / "readme.html").read_text()   # the README's figure
    assert 'src="_images/compare_pd.png"' in (site / "readme.html").read_text()
    for md in sorted(DOCS.glob("*.md")):
        for line in md.read_text().splitlines():
            if "](figures/" in line:
                name = line.split("](figures/", 1)[1].split(")", 1)[0]
                assert name in images, (md.name, name)


@pytest.mark.parametrize("package", ["dptbd.model", "dptbd.hw", "dptbd.sim", "dptbd.dsp"])
def test_api_reference_of_each_package(site, package):
    page = site / "api" / "generated" / f"{package}.html"
    assert page.is_file()


def test_api_reference_documents_the_golden_model_entry_point(site):
    page = (site / "api" / "generated" / "dptbd.model.fixed.html").read_text()
    assert 'id="dptbd.model.fixed.run_fixed"' in page


def _text(page: pathlib.Path) -> str:
    return re.sub(r"<[^>]+>", "", page.read_text())


def test_cli_reference_has_every_sub_command(site):
    text = _text(site / "cli.html")
    for name in COMMANDS:
        assert f"dptbd {name} [-h]" in text, name   # the sub-command's usage line
    # options keep their two hyphens (no typographic dashes)
    assert "--rtl-frames" in text and "\u2013rtl-frames" not in text


def test_document_names_link_to_their_pages(site):
    # README: "(`docs/table1.md`)"; docs/gateware.md names docs/arithmetic.md the same way
    assert re.search(r'<a class="reference internal" href="table1.html"><code[^>]*>'
                     r'<span class="pre">docs/table1.md</span>', (site / "readme.html").read_text())
    assert re.search(r'href="arithmetic.html"><code[^>]*><span class="pre">docs/arithmetic.md',
                     (site / "gateware.html").read_text())


def test_register_reference_is_a_page(site):
    assert "Registers of" in _text(site / "registers.html")


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


def test_the_components_members_sections_are_rendered(site):
    # numpydoc does not know "Members" (Amaranth's name for a signature's members); docs/conf.py
    # hands it over as Attributes and titles it Members again
    text = _text(site / "api" / "generated" / "dptbd.hw.thermometer_fifo.html")
    assert "Members:" in text
    assert "Writes; w.ready is a register" in text
