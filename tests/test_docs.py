"""The documentation site (mkdocs.yml, docs/hooks.py) builds with ``--strict`` and holds what
it promises: a gallery page with its pictures for every example, a page per tutorial, every
check id on the paper-vs-rodstab page, every command on the CLI page, every public module in
the API reference (functions first, grouped by layer in the nav), the design-file format
reference generated from ``rodstab.io.schema`` with every key, ``rodstab.io.design``'s
docstring on the guide's page, and no script loaded from the network (MathJax is served by
the site). The build runs every example and tutorial, so a broken one fails it.

The README (a designer's first screen, at most 10,000 characters) is checked too: its
design file is the hexagram of ``examples/``, its Python block prints what it shows, and its
links point at files that exist.
"""

from __future__ import annotations

import importlib.util
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from rodstab import checks
from rodstab.checks import sec2
from rodstab.cli import cli
from rodstab.results import jsonable

pytest.importorskip("mkdocs", reason="the docs extra is not installed (pip install '.[docs]'; "
                                     "the test extra includes it)")

ROOT = Path(__file__).resolve().parent.parent
PNG = b"\x89PNG\r\n\x1a\n"


def _hooks():
    """docs/hooks.py as a module (it is a script of the site, not part of the package)."""
    spec = importlib.util.spec_from_file_location("rodstab_docs_hooks", ROOT / "docs" / "hooks.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while it loads
    spec.loader.exec_module(module)
    return module


hooks = _hooks()


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """``mkdocs build --strict`` into a temporary directory, without a results.json.

    The build conftest.py started in the background when the tests were collected, waited
    for here; else (this file run on its own in some other way) built now.
    """
    from conftest import DOCS_BUILD, docs_build_command

    proc = DOCS_BUILD.get("proc")
    if isinstance(proc, subprocess.Popen):
        stdout, stderr = proc.communicate()
        out = DOCS_BUILD["out"]
        assert isinstance(out, Path)
        assert proc.returncode == 0, stdout[-3000:] + stderr[-6000:]
        return out
    out = tmp_path_factory.mktemp("site")
    cmd, env = docs_build_command(out)
    assert hooks.RESULTS_ENV not in env
    r = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-6000:]
    return out


def _page(site: Path, path: str) -> str:
    page = site / path / "index.html"
    assert page.is_file(), f"no page {path}"
    return page.read_text()


def _images(html: str) -> list[str]:
    return re.findall(r'<img alt="[^"]*" src="([^"]+)"', html)


@pytest.mark.parametrize("example", sorted(p.stem for p in (ROOT / "examples").glob("*.toml")))
def test_every_example_has_a_gallery_page_with_its_picture(site, example):
    html = _page(site, f"gallery/{example}")
    assert f"examples/{example}.toml" in html
    images = _images(html)
    assert images, f"gallery/{example} shows no picture"
    for src in images:
        picture = (site / "gallery" / example / src).resolve()
        assert picture.read_bytes().startswith(PNG), src
    assert f'href="{example}/"' in _page(site, "gallery")


def test_every_tutorial_page_shows_its_output_and_figures(site):
    scripts = sorted((ROOT / "docs" / "tutorials").glob("*.py"))
    assert scripts
    for script in scripts:
        html = _page(site, f"tutorials/{script.stem}")
        assert "What it prints" in html and script.name in html
        images = _images(html)
        assert images, f"tutorials/{script.stem} shows no figure"  # each script saves one
        for src in images:
            assert (site / "tutorials" / script.stem / src).resolve().read_bytes().startswith(PNG)


def test_paper_page_lists_every_check_id(site):
    html = _page(site, "paper-vs-rodstab")
    cells = set(re.findall(r"<tr>\s*<td>([^<]+)</td>", html))
    assert set(checks.expected_statuses()) <= cells
    assert "rodstab reproduce" in html  # says where the numbers come from


def test_theory_pages_hold_their_sections_rows_and_live_output(site):
    html = _page(site, "theory/section4")
    assert "<td>4.8</td>" in html and "<td>3.9</td>" not in html
    text = re.sub(r"<[^>]+>", "", html)  # the console block is highlighted span by span
    assert "$ rodstab birod" in text and "lam_c = B3 kappa0 L/sqrt(B1 B2)" in text
    assert "arithmatex" in html  # the equations went through the math extension


def test_cli_page_documents_every_command(site):
    html = _page(site, "cli")
    for name in cli.commands:
        assert f"rodstab {name}" in html, name
    assert "UNSET" not in html  # click's sentinel shown as a default (mkdocs-click's tables)


def test_api_reference_has_every_public_module(site):
    modules = hooks.public_modules()
    assert "rodstab.linear.solve" in modules and "rodstab.cli" not in modules
    for name in modules:
        html = _page(site, f"api/{name}")
        assert f'id="{name}"' in html, name
        # the docstrings' Sphinx roles became cross-references (or plain code)
        assert not re.search(r":(func|class|mod|data|meth|attr):<code>", html), name
    assert 'href="../rodstab.model/#rodstab.model.Assembly"><code>Assembly</code>' in _page(
        site, "api/rodstab.linear.assembly")  # :class:`~rodstab.model.Assembly`


# --- the hook's parts, without a build --------------------------------------------------------

def test_a_long_signature_gets_a_parameter_per_line_commas_in_literals_kept():
    code = ("def xxxxxxxxxx(a: int, b: dict[str, tuple[int, int]] = {'a,b': (1, 2)}, *, "
            "c: str = 'x,)', **kw) -> tuple[int, str]: pass")
    assert hooks.format_signature(code, 60) == (
        "def xxxxxxxxxx(\n    a: int,\n    b: dict[str, tuple[int, int]] = {'a,b': (1, 2)},\n"
        "    *,\n    c: str = 'x,)',\n    **kw,\n) -> tuple[int, str]: pass\n")
    assert hooks.format_signature("def f(a) -> int: pass", 60) == "def f(a) -> int: pass\n"
    assert hooks.format_signature("def fffff() -> int: pass", 5) == "def fffff() -> int: pass\n"


def test_api_signatures_are_laid_out_without_a_subprocess(site):
    """A signature longer than the line gets a parameter per line, in this process whether
    or not ruff is installed (format_signature)."""
    html = _page(site, "api/rodstab.multistable.barrier")
    assert re.search(r"\(\s*\n\s{4}\S", re.sub(r"<[^>]+>", "", html)), "no multi-line signature"



def test_a_broken_example_fails_the_build(tmp_path):
    (tmp_path / "broken.toml").write_text("[section]\nshape = 'hexagon'\n")
    with pytest.raises(hooks.PluginError, match="exited 2"):
        hooks.run_rodstab(["analyze", "broken.toml"], tmp_path)


def test_claim_definitions_find_every_row_of_the_registry():
    rows = hooks.claim_definitions()
    assert [r.id for r in rows] == list(checks.expected_statuses())
    # every id matched a Claim(...) call of its check module: section and claim were read
    assert all(r.section != hooks._UNKNOWN and r.statement for r in rows)
    assert {r.section for r in rows} <= {"2", "2.1", "2.2", "3.1", "3.2", "3.3", "4", "5",
                                         "beyond", "contact"}
    by_id = {r.id: r for r in rows}
    assert by_id["E3.1-N3"].statement == "3-loop ring interval of M by the engine"
    assert by_id["PB-threshold-folded"].statement.startswith("folded six-sided ring: where")


def test_paper_page_from_a_results_file_shows_computed_rows(tmp_path):
    """A results.json as ``rodstab reproduce`` writes it, holding Section 2's computed rows."""
    rows = list(sec2.section2_checks(checks.Run()))
    path = tmp_path / "results.json"
    path.write_text(json.dumps(jsonable({"version": "test", "claims": rows})))
    page = hooks.paper_page(path)
    for r in rows:
        assert hooks._escape(r.rodstab) in page
        assert f"**{r.status}**" in page
    assert page.count("not in this results.json") == len(checks.expected_statuses()) - len(rows)
    assert "rodstab test" in page


def test_api_pages_lead_with_functions_then_classes_then_constants(site):
    html = _page(site, "api/rodstab.linear.solve")
    ids = re.findall(r'<h[1-3][^>]*id="([^"]+)"', html)
    assert ids[0] == "rodstab.linear.solve"
    assert ids.index("functions") < ids.index("classes") < ids.index("constants-and-attributes")
    first = ids[ids.index("functions") + 1]
    assert first.startswith("rodstab.linear.solve.") and first.split(".")[-1].islower()
    assert "rodstab.linear.solve.converged_stability" in ids
    assert "rodstab.linear.solve.LinearStability" in ids


def test_api_nav_groups_every_module_by_layer_with_readable_titles(site):
    groups = hooks.api_groups()
    listed = [m for _, _, names in groups for m in names]
    assert sorted(listed) == sorted(hooks.public_modules())  # each once, none left out
    assert hooks._OTHER_GROUP not in [(layer, part) for layer, part, _ in groups]
    layers = list(dict.fromkeys(layer for layer, _, _ in groups))
    assert layers[:7] == ["Numerics", "Cross-sections", "Model, designs and units", "Engines",
                          "Multistable rings", "The paper's structures", "Pictures"]
    by_part = {(layer, part): names for layer, part, names in groups}
    assert by_part["Engines", "Nonlinear rod"][0] == "rodstab.nonlinear"
    assert "rodstab.linear.solve" in by_part["Engines", "Linear FE"]
    assert "rodstab.io.schema" in by_part["Model, designs and units", ""]
    assert hooks.api_title("rodstab.nonlinear.continuation.branches") == "continuation.branches"
    assert hooks.api_title("rodstab.nonlinear") == "rodstab.nonlinear"
    assert hooks.api_title("rodstab.model") == "rodstab.model"
    html = _page(site, "api").replace("&#39;", "'")
    for layer, part, names in groups:
        assert layer in html and part in html, (layer, part)
        for name in names:
            assert f'href="{name}/"' in html
    # the sidebar: layers and parts as sections, each page titled below its section's package
    nav = _page(site, "api/rodstab.io.design").replace("&#39;", "'")
    assert re.search(r'href="\.\./rodstab\.nonlinear\.continuation\.branches/"[^>]*>\s*'
                     r'<span class="md-ellipsis">\s*continuation\.branches\s*</span>', nav)
    for layer in layers:
        assert f"{layer}\n" in re.sub(r"<[^>]+>", "", nav).replace("\n ", "\n").replace(
            "  ", ""), layer
    assert (site / "stylesheets" / "extra.css").is_file()  # long titles wrap, not cut


def test_design_file_page_renders_the_format_from_the_docstring(site):
    """The guide shows rodstab.io.design's docstring (its examples): literal blocks as TOML
    code, Sphinx roles as cross-references; it links to the generated format reference."""
    html = _page(site, "guide/design-files")
    section = html.split('id="the-format"')[1].split('id="how-a-design-is-solved"')[0]
    text = re.sub(r"<[^>]+>", "", section)
    assert "natural_radius" in text and "examples/steel_birod_fig7a.toml" in text
    assert '<div class="highlight">' in section and '<span class="k">[section]</span>' in section
    assert "::" not in text and ":class:" not in text and "``" not in text
    assert 'href="../../api/rodstab.model/#rodstab.model.Assembly"' in section
    assert 'href="../../design-format/"' in section


def test_design_format_page_lists_every_key_of_the_schema(site):
    """The generated reference: a section per table of rodstab.io.schema, every key in it
    (tests/test_design_schema.py: the schema's keys are the reader's)."""
    from rodstab.io.schema import TABLES

    html = _page(site, "design-format")
    parts = re.split(r"<h2 [^>]*>", html)[1:]
    assert len(parts) == len(TABLES)
    for table, part in zip(TABLES, parts, strict=True):
        heading = re.sub(r"<[^>]+>|&para;", "", part.split("</h2>")[0]).strip()
        assert heading == (table.header if table.name else "The file's top level"), heading
        cells = set(re.findall(r"<tr>\s*<td><code>([^<]+)</code></td>", part))
        assert cells == set(table.names), table.name
    assert 'href="../api/rodstab.units/' in html  # the autorefs link resolved
    assert "Design-file format" in _page(site, "cli")  # in the nav (Reference)


def test_built_pages_load_no_script_from_the_network(site):
    """Offline math: MathJax comes from the site (docs/hooks.py copies it from the docs extra's
    django-static-mathjax), and no page loads a script or stylesheet from another host."""
    pages = sorted(site.rglob("*.html"))
    assert len(pages) > 50
    remote = re.compile(r'<(?:script|link)\b[^>]*\b(?:src|href)="(?:https?:)?//[^"]*"')
    for page in pages:
        html = page.read_text()
        for tag in re.findall(r"<script\b[^>]*>", html) + re.findall(r"<link\b[^>]*>", html):
            if "stylesheet" in tag or tag.startswith("<script"):
                assert not remote.search(tag), f"{page.relative_to(site)}: {tag}"
    mathjax = site / hooks.MATHJAX_DIR
    assert (mathjax / hooks.MATHJAX_COMPONENT).is_file()
    assert list((mathjax / "output" / "chtml" / "fonts" / "woff-v2").glob("*.woff"))
    assert (mathjax / "input" / "tex" / "extensions" / "ams.js").is_file()
    html = _page(site, "theory/section4")
    assert 'src="../../mathjax/tex-mml-chtml.js"' in html and "arithmatex" in html


def test_gallery_shows_an_example_whose_extra_is_missing_without_running_it(tmp_path,
                                                                            monkeypatch):
    """Without the sections extra a polygon example is not run: its page says why."""
    import sys

    for name in [n for n in sys.modules if n.split(".")[0] in ("sectionproperties", "shapely")]:
        monkeypatch.setitem(sys.modules, name, None)
    for name in ("sectionproperties", "shapely"):
        monkeypatch.setitem(sys.modules, name, None)  # import fails: not installed
    example = tmp_path / "tee.toml"
    example.write_text("# A T section.\n[section]\npolygon = [[-1.25, 0.0], [1.25, 0.0], "
                       "[1.25, 0.5], [0.2, 0.5], [0.2, 2.5], [-0.2, 2.5], [-0.2, 0.5], "
                       "[-1.25, 0.5]]\n\n[[segment]]\nname = 'rod'\nlength = 1.0\n"
                       "natural_curvature = 1.0\n")
    with pytest.raises(hooks.RodstabInputError) as exc:
        hooks.example_commands(example)
    assert hooks.missing_extra(exc.value) == "sections"
    page = hooks.gallery_page(example, [], {}, skipped="needs the sections extra")
    assert "Not run in this build" in page and "polygon = " in page
    bad = tmp_path / "bad.toml"  # any other input error is not a missing extra: it fails
    bad.write_text("[section]\nshape = 'hexagon'\n")
    with pytest.raises(hooks.RodstabInputError) as other:
        hooks.example_commands(bad)
    assert hooks.missing_extra(other.value) is None


# --- the README ---------------------------------------------------------------------------------

README = (ROOT / "README.md").read_text()


def _blocks(language: str) -> list[str]:
    return re.findall(rf"^```{language}\n(.*?)^```$", README, re.M | re.S)


def test_readme_is_short_and_keeps_the_quick_start():
    assert len(README) <= 10_000, len(README)
    assert _blocks("bash")[0] == ("pip install . && rodstab reproduce --out results\n"
                                  'pip install ".[test]" && python -m pytest -q\n')
    for extra in ("test", "viz", "sections", "docs", "distributed", "bench"):
        assert f"| `{extra}` |" in README, extra  # the extras table lists pyproject's extras
    assert "Leanza" in README and "LICENSE" in README and (ROOT / "LICENSE").is_file()


def test_readme_links_point_at_files():
    for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", README):
        if not target.startswith("http"):
            assert (ROOT / target).exists(), target


def test_readme_ring_is_the_hexagram_and_its_python_prints_what_it_shows(tmp_path):
    """The design file of "Design your own ring" is examples/hexagram.toml's ring (same states,
    natural curvature and section), and the "From Python" block prints its text block."""
    import contextlib
    import io

    from rodstab.io.design import load_design
    from rodstab.multistable.states import ring_of

    (tmp_path / "ring.toml").write_text(_blocks("toml")[0])
    ours, theirs = (ring_of(load_design(p).assembly) for p in
                    (tmp_path / "ring.toml", ROOT / "examples" / "hexagram.toml"))
    assert ([(s.label, s.theta) for s in ours.states().states]
            == [(s.label, s.theta) for s in theirs.states().states])
    assert (ours.natural_curvature, ours.B1, ours.B2) == pytest.approx(
        (theirs.natural_curvature, theirs.B1, theirs.B2), rel=1e-12)
    code, = _blocks("python")
    shown = re.search(r"^```python\n.*?^```\n\n```text\n(.*?)^```$", README, re.M | re.S)
    assert shown is not None
    out = io.StringIO()
    with contextlib.chdir(tmp_path), contextlib.redirect_stdout(out):
        exec(compile(code, "README.md", "exec"), {})  # noqa: S102
    assert out.getvalue() == shown.group(1)
