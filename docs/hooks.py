"""MkDocs hooks: every page of the site that can be generated is generated here, at build time.

* **Gallery** -- every ``examples/*.toml`` is run through ``rodstab analyze FILE --plot``; a
  design that is a ring of identical rods (:func:`rodstab.multistable.states.ring_of` accepts it)
  also through ``rodstab states FILE --plot``; and every line of its header comment that is a
  ``rodstab`` command is run too (``continue`` on a coarse mesh, :data:`FAST_OPTIONS`). One page per
  example: the header, the design file, each command, what it printed and every picture it
  wrote. A command that exits non-zero fails the build.
* **Tutorials** -- every ``docs/tutorials/*.py`` is executed; its page is its docstring, its
  source, what it printed and the figures it saved. An exception fails the build.
* **Paper vs rodstab** -- the rows of :data:`rodstab.checks.REGISTRY`. With ``RODSTAB_RESULTS``
  naming a ``results.json`` of ``rodstab reproduce``, its computed rows (numbers, statuses,
  notes); otherwise the check definitions, which cost nothing: ids, sections, equations and
  claims read from the check functions' source, statuses from each module's ``EXPECTED``.
  Theory pages pull their section's rows with ``<!-- rodstab:claims SECTION -->``.
* **Live commands** -- a fenced block of language ``rodstab`` in any page (one command per
  line, without the leading ``rodstab``) is replaced by the command and what it printed.
* **API reference** -- one mkdocstrings page per public module of the package: its docstring,
  then its public functions, classes (the result types among them) and constants, in that
  order (:func:`api_page`); the nav groups the pages by layer (:data:`API_GROUPS`), each
  titled by its name below its section's package (:func:`api_title`).
* **Design-file format** -- the reference of every table and key a design file may hold,
  generated from the schema the design reader validates against
  (:func:`rodstab.io.schema.reference_markdown`), as ``design-format.md``.
* **Math** -- MathJax is served from the site itself: the hook copies it from the installed
  ``django-static-mathjax`` package (the docs extra; MathJax 3 only, no Django), so pages
  render their equations without the network (:func:`mathjax_files`).

An example that needs an optional extra which is not installed (``examples/polygon_section.toml``
needs ``rodstab[sections]``) gets a page that shows its design file and says so, instead of
failing the build.

Commands run in this process through :func:`rodstab.cli.main` (imports paid once), in a
temporary directory holding a copy of ``examples/``, so each is shown as a user types it from
the repository root.
"""

from __future__ import annotations

import ast
import contextlib
import dataclasses
import functools
import importlib
import importlib.util
import inspect
import io
import json
import logging
import os
import pkgutil
import re
import runpy
import shlex
import shutil
import tempfile
import time
from pathlib import Path
from typing import Any

from mkdocs.config.defaults import MkDocsConfig
from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File, Files
from mkdocs.structure.pages import Page

import rodstab
from rodstab import checks, cli
from rodstab.errors import RodstabInputError
from rodstab.io.design import Design, load_design
from rodstab.io.schema import reference_markdown
from rodstab.multistable.states import ring_of

log = logging.getLogger("mkdocs.hooks.rodstab")

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
TUTORIALS = Path(__file__).resolve().parent / "tutorials"
#: Environment variable naming a ``results.json`` written by ``rodstab reproduce``.
RESULTS_ENV = "RODSTAB_RESULTS"
#: Options added to a command from an example's header so that the docs build stays fast.
FAST_OPTIONS = {"continue": ["--elements", "8", "--branch-steps", "4", "--no-error-estimate",
                             "--no-progress"]}
#: Modules left out of the API reference: the CLI has its own page, generated from click.
NOT_IN_API = ("rodstab.cli",)
#: The design-file format reference, generated from rodstab.io.schema.
DESIGN_FORMAT = "design-format.md"
#: Placeholder entries of the nav in mkdocs.yml that the hook fills with generated pages.
GENERATED_SECTIONS = ("gallery/index.md", "tutorials/index.md", "api/index.md")

# rename_map: off (old paths on purpose)
#: Modules moved in issue 20 (the package's layout), old -> new: a page's cross-reference to an
#: old path (``[`ring_of`][rodstab.states.ring_of]``) is pointed at the new one
#: (:func:`moved_identifier`), so that pages written before the move still build.
MOVED_MODULES = {
    "rodstab.design": "rodstab.io.design", "rodstab.outputs": "rodstab.io.outputs",
    "rodstab.states": "rodstab.multistable.states", "rodstab.atlas": "rodstab.multistable.atlas",
    "rodstab.nonlinear.discover": "rodstab.multistable.discover",
    "rodstab.nonlinear.mep": "rodstab.multistable.string_method",
    "rodstab.nonlinear.transitions": "rodstab.multistable.transitions",
    "rodstab.nonlinear.barrier": "rodstab.multistable.barrier",
    "rodstab.plots": "rodstab.plot.plots", "rodstab.ribbons": "rodstab.plot.ribbons",
    "rodstab.transition_plot": "rodstab.plot.transition_graph",
}
#: Names that left a module that was split (issue 20): (old module, name) -> new module.
MOVED_NAMES = {
    **{("rodstab.design", n): "rodstab.io.outline" for n in ("load_polygon", "DXF_SAGITTA")},
    **{("rodstab.design", n): "rodstab.io.vary" for n in (
        "set_design_value", "VarySpec", "parse_vary", "value_kind", "vary_in_units",
        "model_value")},
    **{("rodstab.nonlinear.discover", n): "rodstab.nonlinear.constraint" for n in (
        "chart_size", "restore_positions", "restore_inextensible", "retract_step")},
}
# rename_map: on
_CROSS_REFERENCE = re.compile(r"\]\[(rodstab(?:\.\w+)+)\]")

_CLAIMS_MARK = re.compile(r"^<!-- rodstab:claims (\S+) -->$", re.M)
_DOCSTRING_MARK = re.compile(r"^<!-- rodstab:docstring (\S+) -->$", re.M)
#: A reST literal block: a paragraph ending in "::", a blank line, then indented lines.
_LITERAL = re.compile(r"::\n\n((?:    .*\n|\n)+)")
_LIVE_BLOCK = re.compile(r"^```rodstab\n(.*?)\n```$", re.M | re.S)
_HEADER_COMMAND = re.compile(r"^\s*rodstab \S.*$", re.M)
#: How rodstab names an optional extra that is not installed (sections.py, design.py, ...).
_MISSING_EXTRA = re.compile(r'pip install "rodstab\[(\w+)\]"')


# --- running rodstab -----------------------------------------------------------------------

@dataclasses.dataclass(frozen=True)
class Ran:
    """One command as run: its arguments, exit status, output and the pictures it wrote."""

    args: tuple[str, ...]
    status: int
    stdout: str
    stderr: str
    pictures: tuple[Path, ...]
    seconds: float

    @property
    def command(self) -> str:
        """The command line as typed."""
        return shlex.join(("rodstab", *self.args))


def run_rodstab(args: list[str], cwd: Path) -> Ran:
    """Run ``rodstab ARGS`` in ``cwd`` in this process; raise PluginError unless it exits 0."""
    before = set(cwd.rglob("*.png"))
    out, err = io.StringIO(), io.StringIO()
    t0 = time.perf_counter()
    with contextlib.chdir(cwd), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            cli.main(list(args))
            status = 0
        except SystemExit as exc:
            status = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    ran = Ran(tuple(args), status, out.getvalue(), err.getvalue(),
              tuple(sorted(set(cwd.rglob("*.png")) - before)), time.perf_counter() - t0)
    if status != 0:
        raise PluginError(f"docs: `{ran.command}` exited {status}:\n{ran.stderr}{ran.stdout}")
    log.info("%s: %.2f s", ran.command, ran.seconds)
    return ran


def console(ran: Ran) -> str:
    """Markdown of a command and what it printed."""
    return f"```console\n$ {ran.command}\n{ran.stdout.rstrip()}\n```\n"


def _workdir() -> Path:
    """Return a fresh temporary directory holding a copy of ``examples/``."""
    work = Path(tempfile.mkdtemp(prefix="rodstab-docs-"))
    shutil.copytree(EXAMPLES, work / "examples")
    return work


# --- gallery -------------------------------------------------------------------------------

def header_comment(text: str) -> str:
    """Return the leading comment block of a TOML file, without the ``#`` marks."""
    lines = []
    for line in text.splitlines():
        if not line.startswith("#"):
            break
        lines.append(line[1:].removeprefix(" "))
    return "\n".join(lines)


def _is_ring(design: Design) -> bool:
    try:
        ring_of(design.assembly)
    except ValueError:
        return False
    return True


def example_commands(path: Path) -> list[list[str]]:
    """Return the commands the gallery runs for the example at ``path``."""
    rel, stem = f"examples/{path.name}", path.stem
    design = load_design(path)
    commands = []
    if any(s.natural_curvature != 0.0 for s in design.assembly.segments):
        commands.append(["analyze", rel, "--plot", f"{stem}-analyze.png"])
    if _is_ring(design):
        commands.append(["states", rel, "--plot", f"{stem}-states.png"])
    for line in _HEADER_COMMAND.findall(header_comment(path.read_text())):
        args = shlex.split(line)[1:]
        args += FAST_OPTIONS.get(args[0], [])
        if args[0] == "continue":
            args += ["--out", f"{stem}-continue"]
        commands.append(args)
    return commands


def _escape(text: str) -> str:
    """Plain text safe inside Markdown (a table cell or a paragraph)."""
    text = text.replace("\\", "\\\\").replace("|", "\\|").replace("*", "\\*")
    return text.replace("_", "\\_").replace("<", "&lt;").replace("$", "\\$")


def missing_extra(exc: RodstabInputError) -> str | None:
    """Return the optional extra that ``exc`` says is not installed (None: another error)."""
    m = _MISSING_EXTRA.search(str(exc))
    return m.group(1) if m else None


def gallery_page(path: Path, runs: list[Ran], pictures: dict[Path, str],
                 skipped: str | None = None) -> str:
    """Markdown of one example's gallery page.

    ``skipped``: why its commands were not run in this build (an optional extra missing).
    """
    text = path.read_text()
    header = header_comment(text)
    lines = [f"# examples/{path.name}", ""]
    lines += ["> " + _escape(h) if h.strip() else ">" for h in header.splitlines()]
    lines += ["", f'??? note "examples/{path.name}"', "", "    ```toml"]
    lines += ["    " + t if t else "" for t in text.rstrip().splitlines()]
    lines += ["    ```", ""]
    if skipped:
        lines += ['!!! warning "Not run in this build"', "", f"    {skipped}", ""]
    for ran in runs:
        lines += [f"## rodstab {ran.args[0]}", "", console(ran)]
        fast = FAST_OPTIONS.get(ran.args[0])
        if fast:
            lines += [f"Run here with `{shlex.join(fast)}` to keep the docs build fast: on the "
                      "coarse mesh its numbers differ from the converged ones (the nonlinear "
                      "rod converges at second order in the element size): drop these options "
                      "for the command's default mesh and its error estimate.", ""]
        lines += [f"![{pictures[p]}]({pictures[p]})\n" for p in ran.pictures]
    return "\n".join(lines) + "\n"


def build_gallery(config: MkDocsConfig, files: Files, work: Path) -> list[Path]:
    """Run every example; add its page and pictures to ``files``; return the examples."""
    examples = sorted(EXAMPLES.glob("*.toml"))
    rows = ["# Gallery", "",
            "Every design file in `examples/`, run at docs-build time through the commands "
            "below (a broken example breaks the build). Each page shows the commands, what "
            "they printed and the pictures they wrote.", "",
            "| example | what it is | commands |", "|---|---|---|"]
    for path in examples:
        skipped = None
        try:
            commands = example_commands(path)
        except RodstabInputError as exc:
            extra = missing_extra(exc)
            if extra is None:
                raise PluginError(f"docs: examples/{path.name}: {exc}") from exc
            why = str(exc).replace(str(path), f"examples/{path.name}")  # no build path
            skipped = (f"This example needs the optional `{extra}` extra, which is not "
                       f"installed where this site was built ({why}). Build the docs with "
                       f'`pip install ".[docs,{extra}]"` to run it here.')
            log.info("gallery: examples/%s not run: the %s extra is missing", path.name, extra)
            commands = []
        runs = [run_rodstab(args, work) for args in commands]
        pictures: dict[Path, str] = {}
        for ran in runs:
            for p in ran.pictures:
                name = str(p.relative_to(work)).replace(os.sep, "-")
                pictures[p] = name
                files.append(File.generated(config, f"gallery/{name}", content=p.read_bytes()))
        files.append(File.generated(config, f"gallery/{path.stem}.md",
                                    content=gallery_page(path, runs, pictures, skipped)))
        first = re.split(r"\.\s+(?=[A-Z])", header_comment(path.read_text()))[0]
        first = first.replace("\n", " ")
        ran = ", ".join(f"`{r.args[0]}`" for r in runs) if not skipped else (
            "not run in this build (an optional extra is missing)")
        rows.append(f"| [{path.name}]({path.stem}.md) | {_escape(first)} | {ran} |")
    files.append(File.generated(config, "gallery/index.md", content="\n".join(rows) + "\n"))
    return examples


# --- tutorials -----------------------------------------------------------------------------

def run_tutorial(script: Path, work: Path) -> tuple[str, list[Path]]:
    """Execute ``script`` in ``work`` (which holds ``examples/``).

    Returns what it printed and the figures it saved there.
    """
    out = io.StringIO()
    before = set(work.glob("*.png"))
    with contextlib.chdir(work), contextlib.redirect_stdout(out):
        try:
            runpy.run_path(str(script), run_name="__main__")
        except Exception as exc:  # any failure of a tutorial fails the build
            raise PluginError(f"docs: tutorial {script.name} failed: {exc!r}") from exc
    return out.getvalue(), sorted(set(work.glob("*.png")) - before)


def build_tutorials(config: MkDocsConfig, files: Files, work: Path) -> list[Path]:
    """Run every tutorial script; add its page and figures to ``files``."""
    scripts = sorted(TUTORIALS.glob("*.py"))
    rows = ["# Tutorials", "",
            "Short scripts run at docs-build time: each page is the script, what it printed "
            "and the figures it saved. Run one yourself from the repository root, e.g. "
            "`python docs/tutorials/ring_states.py` (example paths are relative to it).", ""]
    for script in scripts:
        source = script.read_text()
        doc = ast.get_docstring(ast.parse(source)) or script.stem
        title, intro = _tutorial_title(script), doc.partition("\n")[2]
        t0 = time.perf_counter()
        output, figures = run_tutorial(script, work)
        log.info("tutorial %s: %.2f s", script.name, time.perf_counter() - t0)
        body = [f"# {title}", "", intro.strip(), "",
                f"[Download {script.name}]({script.name})", "",
                "## The script", "", "```python", source.rstrip(), "```", "",
                "## What it prints", "", "```text", output.rstrip(), "```", ""]
        for fig in figures:
            name = f"{script.stem}-{fig.name}"
            files.append(File.generated(config, f"tutorials/{name}", content=fig.read_bytes()))
            body += [f"![{fig.stem}]({name})", ""]
        files.append(File.generated(config, f"tutorials/{script.stem}.md",
                                    content="\n".join(body)))
        rows.append(f"- [{title}]({script.stem}.md)")
    files.append(File.generated(config, "tutorials/index.md", content="\n".join(rows) + "\n"))
    return scripts


# --- paper vs rodstab ----------------------------------------------------------------------

@dataclasses.dataclass(frozen=True)
class ClaimRow:
    """One row of the claims table: a check's definition, and its results if computed."""

    id: str
    section: str
    equation: str
    statement: str
    expected: str
    computed: dict[str, Any] | None = None


_UNKNOWN = "…"
#: AST nodes an f-string field may use to be evaluated in the check module's namespace.
_SAFE_NODES = (ast.Expression, ast.Name, ast.Load, ast.Subscript, ast.Attribute, ast.Constant)


def _field(node: ast.expr, env: dict[str, Any]) -> str:
    """Return the text of a Claim argument, or "…".

    A string, an f-string whose fields are evaluated in ``env`` when they are plain names,
    attributes or subscripts (else "…"), or a sum of those.
    """
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        return _field(node.left, env) + _field(node.right, env)
    if not isinstance(node, ast.JoinedStr):
        return _UNKNOWN
    parts = []
    for v in node.values:
        if isinstance(v, ast.FormattedValue):
            expr = ast.Expression(v.value)
            try:
                if not all(isinstance(n, _SAFE_NODES) for n in ast.walk(expr)):
                    raise ValueError("not a plain name")
                value = eval(compile(expr, "<claim>", "eval"), dict(env))  # noqa: S307
                spec = _field(v.format_spec, env) if v.format_spec else ""
                value = repr(value) if v.conversion == ord("r") else value
                parts.append(format(value, spec))
            except Exception:  # a field computed inside the check: unknown until it runs
                parts.append(_UNKNOWN)
        else:
            parts.append(_field(v, env))
    return "".join(parts)


def _id_pattern(node: ast.expr) -> tuple[re.Pattern[str], list[str | None], int] | None:
    """Return a regex of the ids a Claim's first argument produces (None if it cannot).

    With it, the names its fields bind and its number of literal characters (the more, the more
    specific).
    """
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return re.compile(re.escape(node.value)), [], len(node.value)
    if not isinstance(node, ast.JoinedStr):
        return None
    regex, names, literal = "", [], 0
    for v in node.values:
        if isinstance(v, ast.FormattedValue):
            regex += "(.+?)"
            names.append(v.value.id if isinstance(v.value, ast.Name) else None)
        elif isinstance(v, ast.Constant):
            regex += re.escape(str(v.value))
            literal += len(str(v.value))
    return re.compile(regex), names, literal


def claim_definitions() -> list[ClaimRow]:
    """Every row of :data:`rodstab.checks.REGISTRY` without running a check.

    Ids and expected statuses from each entry's ``expected``; section, equation and claim from
    the ``Claim(...)`` calls in its module's source (the most specific one whose id matches;
    fields that are computed when the check runs show as "…").
    """
    rows = []
    for check in checks.REGISTRY:
        module = importlib.import_module(check.produce.__module__)
        tree = ast.parse(inspect.getsource(module))
        calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call)
                 and isinstance(n.func, ast.Name) and n.func.id == "Claim" and len(n.args) >= 4]
        calls.sort(key=lambda n: (n.lineno, n.col_offset))
        for cid, status in check.expected.items():
            best: tuple[int, ast.Call, dict[str, str]] | None = None
            for call in calls:
                pat = _id_pattern(call.args[0])
                if pat is None:
                    continue
                regex, names, literal = pat
                m = regex.fullmatch(cid)
                if m and (best is None or literal >= best[0]):  # ties: the later call
                    bound = {n: g for n, g in zip(names, m.groups(), strict=True) if n}
                    best = (literal, call, bound)
            if best is None:
                rows.append(ClaimRow(cid, _UNKNOWN, _UNKNOWN, _UNKNOWN, status))
                continue
            env = {**vars(module), **best[2]}
            sec, eq, statement = (_field(a, env) for a in best[1].args[1:4])
            rows.append(ClaimRow(cid, sec, eq, statement, status))
    return rows


def claim_rows(results: Path | None) -> list[ClaimRow]:
    """Return the definitions, each with its computed row from ``results`` if given."""
    rows = claim_definitions()
    if results is None:
        return rows
    computed = {c["id"]: c for c in json.loads(results.read_text())["claims"]}
    return [dataclasses.replace(r, section=computed[r.id]["section"],
                                equation=computed[r.id]["equation"],
                                statement=computed[r.id]["statement"],
                                computed=computed[r.id]) if r.id in computed else r
            for r in rows]


def results_path() -> Path | None:
    """Return the results.json named by ``RODSTAB_RESULTS`` (None if unset).

    Raises PluginError if it names no file.
    """
    value = os.environ.get(RESULTS_ENV)
    if not value:
        return None
    path = Path(value)
    if path.is_dir():
        path = path / "results.json"
    if not path.is_file():
        raise PluginError(f"docs: {RESULTS_ENV}={value!r}: no results.json there")
    return path


def in_section(row: ClaimRow, section: str) -> bool:
    """Whether ``row`` belongs to ``section`` ("3" holds "3.1", "3.2", ...)."""
    return row.section == section or row.section.startswith(section + ".")


def claims_table(rows: list[ClaimRow], results: Path | None) -> str:
    """Markdown table of ``rows``: computed columns if ``results`` was given."""
    if results is None:
        out = ["| id | § | eq. | claim | status (claimed) |", "|---|---|---|---|---|"]
        out += [f"| {r.id} | {r.section} | {_escape(r.equation)} | {_escape(r.statement)} | "
                f"**{r.expected}** |" for r in rows]
        return "\n".join(out) + "\n"
    out = ["| id | § | eq. | claim | paper | rodstab | second method | status | note |",
           "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        c = r.computed
        if c is None:
            out.append(f"| {r.id} | {r.section} | {_escape(r.equation)} | "
                       f"{_escape(r.statement)} | | | | not in this results.json "
                       f"(claimed: {r.expected}) | |")
            continue
        second = c["second"] + (f" ({c['second_method']})"
                                if c["second_method"] not in ("", "-") else "")
        status = f"**{c['status']}**" + ("" if c["status"] == r.expected
                                         else f" (claimed: {r.expected})")
        out.append("| " + " | ".join([r.id, r.section] + [_escape(x) for x in (
            r.equation, r.statement, c["paper"], c["rodstab"], second)]
            + [status, _escape(c["note"])]) + " |")
    return "\n".join(out) + "\n"


def source_note(results: Path | None) -> str:
    """Where the table's contents come from."""
    if results is None:
        return ("Generated from the check definitions in `rodstab.checks` (ids, sections, "
                "equations and claims from the check functions, statuses as the project claims "
                "them in each module's `EXPECTED`). The numbers, the computed statuses and the "
                "evidence come from `rodstab reproduce` (`results/report.md`); build the docs "
                f"with `{RESULTS_ENV}=results/results.json mkdocs build` to show them here. "
                "\"…\" marks a part of a claim that is computed when its check runs.")
    version = json.loads(results.read_text()).get("version", "?")
    return (f"Computed by `rodstab reproduce` (rodstab {version}, `{results.name}` given by "
            f"`{RESULTS_ENV}`). Status *reproduced*: rodstab and an independent second method "
            "both give the paper's value; *differs*: the printed equation or value does not "
            "follow from the paper's own equations (the note gives the evidence).")


def paper_page(results: Path | None) -> str:
    """Markdown of the paper-vs-rodstab page."""
    rows = claim_rows(results)
    if results is None:
        n_diff = sum(r.expected == checks.DIFFERS for r in rows)
        counts = f"{n_diff} claimed to differ from the printed text"
    else:
        n_diff = sum((r.computed or {}).get("status") == checks.DIFFERS for r in rows)
        counts = f"{n_diff} where rodstab differs from the printed text"
    return "\n".join([
        "# Paper vs rodstab", "",
        f"Every checked statement of the paper (Sections 2-5) and beyond it: {len(rows)} rows, "
        f"{counts}.", "",
        source_note(results), "", claims_table(rows, results)])


# --- API reference -------------------------------------------------------------------------

@functools.cache
def public_modules() -> list[str]:
    """Every module of the package whose dotted name has no private part."""
    names = [m.name for m in pkgutil.walk_packages(rodstab.__path__, "rodstab.")]
    return ["rodstab"] + sorted(n for n in names if not any(p.startswith("_")
                                                             for p in n.split("."))
                                and not any(n == m or n.startswith(m + ".")
                                            for m in NOT_IN_API))


#: The API reference's sections in the nav and on its index, by layer from the bottom up:
#: (layer, part of the layer or "", module prefixes). A module goes to the first row one of
#: whose prefixes is its name or a package above it; a module no row claims goes to "Other
#: modules" (so none is ever left out; tests/test_docs.py checks that none is there).
API_GROUPS: tuple[tuple[str, str, tuple[str, ...]], ...] = (
    ("Numerics", "", ("rodstab.numerics",)),
    ("Cross-sections", "", ("rodstab.sections",)),
    ("Model, designs and units", "", ("rodstab", "rodstab.model", "rodstab.kinematics",
                                      "rodstab.units", "rodstab.io", "rodstab.results",
                                      "rodstab.errors")),
    ("Engines", "Closed forms", ("rodstab.analytic",)),
    ("Engines", "Transfer matrices", ("rodstab.transfer",)),
    ("Engines", "Linear FE", ("rodstab.linear",)),
    ("Engines", "Nonlinear rod", ("rodstab.nonlinear",)),
    ("Multistable rings", "", ("rodstab.multistable",)),
    ("The paper's structures", "", ("rodstab.problems",)),
    ("Pictures", "", ("rodstab.plot",)),
    ("Checks and report", "", ("rodstab.checks", "rodstab.report")),
    ("Sweeps, limits, execution", "", ("rodstab.sweep", "rodstab.executor", "rodstab.limits")),
)
_OTHER_GROUP = ("Other modules", "")
#: API page sections, in page order: griffe's kind of member -> heading.
API_KINDS = (("function", "Functions"), ("class", "Classes"), ("type alias", "Type aliases"),
             ("attribute", "Constants and attributes"))


def _claims(prefix: str, module: str) -> bool:
    """Whether ``prefix`` is ``module`` or a package above it ("rodstab": the package only)."""
    return module == prefix or (prefix != "rodstab" and module.startswith(prefix + "."))


def api_group(module: str) -> tuple[str, str]:
    """Return the API section ``(layer, part)`` (:data:`API_GROUPS`) of ``module``."""
    for layer, part, prefixes in API_GROUPS:
        if any(_claims(p, module) for p in prefixes):
            return layer, part
    return _OTHER_GROUP


def api_groups() -> list[tuple[str, str, list[str]]]:
    """Return the public modules by API section, in :data:`API_GROUPS` order (none empty)."""
    sections = [(layer, part) for layer, part, _ in API_GROUPS] + [_OTHER_GROUP]
    grouped: dict[tuple[str, str], list[str]] = {s: [] for s in sections}
    for name in public_modules():
        grouped[api_group(name)].append(name)
    order = {(layer, part): prefixes for layer, part, prefixes in API_GROUPS}

    def rank(module: str, prefixes: tuple[str, ...]) -> tuple[int, str]:
        """Modules in the order of their section's prefixes, then by name."""
        return next((i for i, p in enumerate(prefixes) if _claims(p, module)), 0), module

    return [(layer, part, sorted(grouped[layer, part],
                                 key=lambda m, s=(layer, part): rank(m, order.get(s, ()))))
            for layer, part in sections if grouped[layer, part]]


def api_title(module: str) -> str:
    """Return the nav title of ``module``'s page: its name below the package of its section.

    ``rodstab.nonlinear.continuation.branches`` is ``continuation.branches`` under the
    section of ``rodstab.nonlinear``; a package and a module of its own row keep their full
    name (``rodstab.nonlinear``, ``rodstab.model``).
    """
    for _, _, prefixes in API_GROUPS:
        above = [p for p in prefixes if p != "rodstab" and module.startswith(p + ".")]
        if above:
            return module[len(max(above, key=len)) + 1:]
        if any(_claims(p, module) for p in prefixes):
            return module
    return module


@functools.cache
def _griffe_package() -> Any:
    """Load the package as mkdocstrings sees it (griffe's static analysis of ``src/``)."""
    import griffe

    return griffe.load("rodstab", search_paths=[str(ROOT / "src")], docstring_parser="numpy")


def api_members(module: str) -> dict[str, list[str]]:
    """Return the members an API page documents, by kind (:data:`API_KINDS`), in source order.

    As mkdocstrings' own selection with ``filters: ["!^_"]``: public names defined in the
    module, and imported ones only where the module exports them (``__all__``); submodules
    have their own pages.
    """
    package = _griffe_package()
    obj = package if module == "rodstab" else package[module.removeprefix("rodstab.")]
    out: dict[str, list[str]] = {kind: [] for kind, _ in API_KINDS}
    for name, member in obj.members.items():
        if name.startswith("_") or (member.is_alias and not member.is_public):
            continue
        try:
            kind = member.kind.value
        except Exception:  # an export whose target griffe cannot resolve: not documented
            continue
        if kind in out:
            out[kind].append(name)
    return out


def api_page(module: str) -> str:
    """Markdown of one module's API page.

    The module's docstring first (``members: false``), then one directive per public member
    under a heading per kind: functions, then classes (the result types), then constants. One
    directive for the whole module would put its constants first: mkdocstrings orders by
    category with attributes first.
    """
    lines = [f"::: {module}", "    options:", "      members: false", ""]
    for kind, heading in API_KINDS:
        names = api_members(module)[kind]
        if not names:
            continue
        lines += [f"## {heading}", ""]
        for name in names:
            lines += [f"::: {module}.{name}", "    options:", "      heading_level: 3",
                      "      show_root_full_path: false", ""]
    return "\n".join(lines)


def build_api(config: MkDocsConfig, files: Files) -> list[str]:
    """One page per public module (:func:`api_page`) and an index, grouped by package."""
    modules = public_modules()
    index = ["# API reference", "",
             "Generated from the docstrings (numpy style) of every public module. Each page "
             "gives the module's docstring, then its public functions, classes (the result "
             "types among them) and constants. The modules are grouped by layer, each using "
             "only the layers above it here. The command line is documented in the "
             "[CLI reference](../cli.md), design files in the "
             "[design-file format reference](../design-format.md).", ""]
    for name in modules:
        files.append(File.generated(config, f"api/{name}.md", content=api_page(name)))
    layer = None
    for this, part, names in api_groups():
        if this != layer:
            index += [f"## {this}", ""]
            layer = this
        if part:
            index += [f"### {part}", ""]
        for name in names:
            summary = (importlib.import_module(name).__doc__ or "").strip().split("\n")[0]
            index.append(f"- [`{name}`]({name}.md): {_escape(summary)}")
        index.append("")
    files.append(File.generated(config, "api/index.md", content="\n".join(index) + "\n"))
    return modules


# --- math, served by the site --------------------------------------------------------------

#: Where the site serves MathJax from (mkdocs.yml's extra_javascript loads
#: ``mathjax/tex-mml-chtml.js``; MathJax finds its fonts and extensions beside that file).
MATHJAX_DIR = "mathjax"
#: The one combined MathJax component the pages load (TeX and MathML in, CommonHTML out).
MATHJAX_COMPONENT = "tex-mml-chtml.js"
_MATHJAX_MISSING = ('docs: math needs MathJax from the docs extra: pip install ".[docs]" '
                    "(the django-static-mathjax package: MathJax 3's files, no Django)")


def mathjax_root() -> Path:
    """Return the ``es5`` directory of the installed MathJax 3 copy (django-static-mathjax).

    That package installs the MathJax distribution as ``mathjax/static/mathjax/``. Raises
    PluginError when it is not installed (or is another package named ``mathjax``).
    """
    spec = importlib.util.find_spec("mathjax")
    locations = list(spec.submodule_search_locations or []) if spec else []
    for location in locations:
        es5 = Path(location) / "static" / "mathjax" / "es5"
        if (es5 / MATHJAX_COMPONENT).is_file():
            return es5
    raise PluginError(_MATHJAX_MISSING)


def mathjax_files(config: MkDocsConfig) -> list[File]:
    """Return the MathJax files the site serves under :data:`MATHJAX_DIR`.

    The combined component and every directory it loads from on demand (fonts, TeX
    extensions, the menu, accessibility and speech), and MathJax's licence; the other
    combined components and the Node.js adaptors are left out.
    """
    es5 = mathjax_root()
    sources = [es5 / MATHJAX_COMPONENT]
    sources += sorted(f for d in es5.iterdir() if d.is_dir() and d.name != "adaptors"
                      for f in d.rglob("*") if f.is_file())
    out = [File.generated(config, f"{MATHJAX_DIR}/{f.relative_to(es5).as_posix()}",
                          abs_src_path=str(f)) for f in sources]
    licence = es5.parent / "LICENSE"
    if licence.is_file():
        out.append(File.generated(config, f"{MATHJAX_DIR}/LICENSE", abs_src_path=str(licence)))
    return out


# --- hooks ---------------------------------------------------------------------------------

def _tutorial_title(script: Path) -> str:
    """Return the first line of a tutorial's docstring, without its full stop."""
    doc = ast.get_docstring(ast.parse(script.read_text())) or script.stem
    return doc.split("\n")[0].rstrip(".")


def _generated_nav() -> dict[str, list[dict[str, Any]]]:
    """Each generated section of the nav: its pages, each ``{title: path}``."""
    return {
        "gallery/index.md": [{p.name: f"gallery/{p.stem}.md"}
                             for p in sorted(EXAMPLES.glob("*.toml"))],
        "tutorials/index.md": [{_tutorial_title(p): f"tutorials/{p.stem}.md"}
                               for p in sorted(TUTORIALS.glob("*.py"))],
        "api/index.md": _api_nav(),
    }


def _api_nav() -> list[dict[str, Any]]:
    """Return the API section of the nav: a section per layer, a subsection per part."""
    nav: list[dict[str, Any]] = []
    for layer, part, names in api_groups():
        pages = [{api_title(m): f"api/{m}.md"} for m in names]
        if not nav or layer not in nav[-1]:
            nav.append({layer: []})
        nav[-1][layer] += [{part: pages}] if part else pages
    return nav


def _unquoted(text: str):
    """(index, character) of every character of ``text`` outside string literals."""
    quote = ""
    for i, ch in enumerate(text):
        if quote:
            if ch == quote and text[i - 1] != "\\":
                quote = ""
        elif ch in "'\"":
            quote = ch
        else:
            yield i, ch


def _top_level_split(text: str) -> list[str]:
    """Split ``text`` at the commas outside brackets and string literals."""
    parts, depth, start = [], 0, 0
    for i, ch in _unquoted(text):
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts if p.strip()]


def format_signature(code: str, line_length: int) -> str:
    """Lay out ``def NAME(PARAMS) -> RET: pass`` for an API page, in this process.

    mkdocstrings formats a long signature with ruff in a subprocess per signature (~800 of
    them: 7 s of the build's CPU) when ruff is installed, and not at all when it is not (the
    ``docs`` extra alone): the site then differs with the environment. This layout is the
    same everywhere: a signature up to ``line_length`` stays on one line, a longer one gets a
    parameter per line, as ruff would put it.
    """
    code = code.strip()
    open_, close, depth = -1, -1, 0
    for i, ch in _unquoted(code):
        if ch == "(":
            open_ = i if open_ < 0 else open_
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                close = i
                break
    params = _top_level_split(code[open_ + 1:close]) if close > open_ >= 0 else []
    if len(code) <= line_length or not params:
        return code + "\n"
    body = "".join(f"    {p},\n" for p in params)
    return f"{code[:open_ + 1]}\n{body}{code[close:]}\n"


def _use_in_process_signature_layout() -> None:
    """Make mkdocstrings-python lay out signatures with :func:`format_signature`.

    Its formatter is a private function (``_get_formatter``); if a release renames it, its
    own layout is kept (the pages still build).
    """
    with contextlib.suppress(ImportError):
        from mkdocstrings_handlers.python._internal import rendering

        if callable(getattr(rendering, "_get_formatter", None)):
            rendering._get_formatter = lambda: format_signature


def on_config(config: MkDocsConfig) -> MkDocsConfig:
    """Expand the nav's generated sections into their pages."""
    pages = _generated_nav()
    _use_in_process_signature_layout()

    def expand(items: list[Any]) -> list[Any]:
        out = []
        for item in items:
            if isinstance(item, dict):
                (title, value), = item.items()
                if isinstance(value, list):
                    out.append({title: expand(value)})
                elif value in pages:
                    out.append({title: [value, *pages[value]]})
                else:
                    out.append(item)
            else:
                out.append(item)
        return out

    config.nav = expand(config.nav or [])
    return config


_state: dict[str, Any] = {}


def on_files(files: Files, config: MkDocsConfig) -> Files:
    """Run the examples and tutorials; add the generated pages and pictures."""
    t0 = time.perf_counter()
    work = _workdir()
    try:
        build_gallery(config, files, work)
        build_tutorials(config, files, work)
        results = results_path()
        files.append(File.generated(config, "paper-vs-rodstab.md", content=paper_page(results)))
        files.append(File.generated(config, DESIGN_FORMAT, content=reference_markdown()))
        build_api(config, files)
        for f in mathjax_files(config):
            files.append(f)
        _state["results"] = results
        _state["rows"] = claim_rows(results)
        _state["work"] = _workdir()
    finally:
        shutil.rmtree(work, ignore_errors=True)
    log.info("rodstab: generated pages in %.1f s", time.perf_counter() - t0)
    return files


def docstring_markdown(module: str, language: str = "toml") -> str:
    """Return a module's docstring as Markdown, for a page that shows it as in the code.

    reST literal blocks (``...::`` and an indented block) become fenced blocks of
    ``language``; double backquotes become code. Sphinx roles stay as they are: the page's
    HTML gets them as cross-references (:func:`on_page_content`).
    """
    doc = inspect.cleandoc(importlib.import_module(module).__doc__ or "") + "\n"

    def fence(m: re.Match[str]) -> str:
        block = inspect.cleandoc("\n".join(line[4:] for line in m.group(1).splitlines()))
        return f":\n\n```{language}\n{block}\n```\n\n"

    doc = re.sub(r"(?<!`)``([^`]+)``(?!`)", r"`\1`", doc)
    return _LITERAL.sub(fence, doc)


def on_page_markdown(markdown: str, page: Page, config: MkDocsConfig, files: Files) -> str:
    """Expand ``rodstab`` blocks, claims markers and docstring markers.

    A ``rodstab`` block is run and replaced by its output, a claims marker by its section's
    rows, ``<!-- rodstab:docstring MODULE -->`` by that module's docstring. Cross-references
    to a module's path before issue 20 are pointed at its new path.
    """
    def claims(m: re.Match[str]) -> str:
        rows = [r for r in _state["rows"] if in_section(r, m.group(1))]
        if not rows:
            raise PluginError(f"docs: {page.file.src_uri}: no check rows in section "
                              f"{m.group(1)!r}")
        return (claims_table(rows, _state["results"]) + "\n"
                + "*From the same checks as the report: see [Paper vs rodstab]"
                f"({'../' * page.file.src_uri.count('/')}paper-vs-rodstab.md).*\n")

    def live(m: re.Match[str]) -> str:
        return "\n".join(console(run_rodstab(shlex.split(line), _state["work"]))
                         for line in m.group(1).splitlines() if line.strip())

    def docstring(m: re.Match[str]) -> str:
        _state.setdefault("docstring_pages", {})[page.file.src_uri] = m.group(1)
        return docstring_markdown(m.group(1))

    markdown = _CROSS_REFERENCE.sub(lambda m: f"][{moved_identifier(m.group(1))}]", markdown)
    markdown = _CLAIMS_MARK.sub(claims, markdown)
    markdown = _DOCSTRING_MARK.sub(docstring, markdown)
    return _LIVE_BLOCK.sub(live, markdown)


def moved_identifier(dotted: str) -> str:
    """Return the path that ``dotted`` has since issue 20 (:data:`MOVED_MODULES`), else itself."""
    for old in sorted(MOVED_MODULES, key=len, reverse=True):
        if dotted == old or dotted.startswith(old + "."):
            name = dotted[len(old) + 1:].split(".")[0]
            new = MOVED_NAMES.get((old, name), MOVED_MODULES[old])
            return new + dotted[len(old):]
    return dotted


def _exists(dotted: str) -> bool:
    """Return whether ``dotted`` names a module or an attribute of one."""
    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for part in parts[i:]:
            if not hasattr(obj, part):
                return False
            obj = getattr(obj, part)
        return True
    return False


_ROLE = re.compile(r":(?:func|class|mod|data|meth|attr|exc|obj):<code>(~?)([\w.]+)</code>")


def identifier(name: str, module: str) -> str:
    """Return the full dotted name that ``name`` in a docstring of ``module`` refers to.

    Absolute names stay; ``.rules`` is resolved against the module's package; a bare name is
    looked up in the module (an object imported there is named where it is defined), else
    taken as the module's own attribute.
    """
    if name.startswith("rodstab."):
        return name
    mod = importlib.import_module(module)
    if name.startswith("."):
        package = module if hasattr(mod, "__path__") else module.rpartition(".")[0]
        target = importlib.util.resolve_name(name, package)
        if _exists(target):
            return target
        name = name.lstrip(".")  # Sphinx's ".name": any object of that name
    obj: Any = mod
    for part in name.split("."):
        obj = getattr(obj, part, None)
    if inspect.ismodule(obj):
        return obj.__name__
    home, qualname = getattr(obj, "__module__", None), getattr(obj, "__qualname__", None)
    if isinstance(home, str) and home.startswith("rodstab") and isinstance(qualname, str):
        return f"{home}.{qualname}"
    if obj is not None:
        return f"{module}.{name}"
    # Not in this module (e.g. a re-exported function's docstring on its package's page): the
    # module of the package that defines it, the nearest to this one if several do.
    first = name.split(".")[0]
    owners = [m for m in public_modules() if first in vars(importlib.import_module(m))
              and not inspect.ismodule(getattr(importlib.import_module(m), first))]
    if not owners:
        return f"{module}.{name}"
    near = max(owners, key=lambda m: len(os.path.commonprefix([m.split("."),
                                                               module.split(".")])))
    if near == module:  # it has the first part but not the rest (a dotted name): leave it
        return f"{module}.{name}"
    return identifier(name, near)


def on_page_content(html: str, page: Page, config: MkDocsConfig, files: Files) -> str:
    """Turn the docstrings' Sphinx roles (``:func:`name```) into cross-references.

    The API pages, and the pages that show a module's docstring, render them as a role
    followed by code; each becomes an optional autorefs link (a name that is not documented
    stays plain code, without a warning).
    """
    if page.file.src_uri.startswith("api/"):
        module = page.file.src_uri.removeprefix("api/").removesuffix(".md")
    elif page.file.src_uri in _state.get("docstring_pages", {}):
        module = _state["docstring_pages"][page.file.src_uri]
    else:
        return html

    def link(m: re.Match[str]) -> str:
        tilde, name = m.groups()  # "~": show the last component only (Sphinx's convention)
        shown = name.rpartition(".")[2] if tilde else name
        return (f'<autoref identifier="{identifier(name, module)}" optional>'
                f"<code>{shown}</code></autoref>")

    return _ROLE.sub(link, html)


def on_post_build(config: MkDocsConfig) -> None:
    """Remove the working directory of the live commands."""
    work = _state.pop("work", None)
    if work is not None:
        shutil.rmtree(work, ignore_errors=True)
