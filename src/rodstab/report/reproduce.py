"""``rodstab reproduce``: evaluate every claim, draw the figures, write md/html/json."""

from __future__ import annotations

import base64
import html
import json
import time
from pathlib import Path
from typing import Any

from tqdm import tqdm

from .. import __version__, checks
from ..checks import REPRODUCED, Claim
from ..results import jsonable
from . import figures

#: Progress ticks: one per finished check of the parallel run (run serially, on one CPU, the
#: checks' own steps tick as well and the bar overruns) and one for the figures.
_STEPS = len(checks.REGISTRY) + 1


def _markdown(rows: list[Claim], figs: dict[str, Path], elapsed: float) -> str:
    n_rep = sum(r.status == REPRODUCED for r in rows)
    lines = [
        "# rodstab reproduction report",
        "",
        "Paper: Leanza, Zhao & Hutchinson, *On the elastic stability of folded rings in circular "
        "and straight states*, Sections 2-5.",
        f"rodstab {__version__}; {len(rows)} claims: {n_rep} reproduced, "
        f"{len(rows) - n_rep} differ (each explained). Computed in {elapsed:.1f} s.",
        "",
        "Status *reproduced*: rodstab and an independent second method both give the paper's "
        "value to its printed precision. *differs*: the printed equation or value does not follow "
        "from the paper's own equations; the note gives the evidence and the consequence.",
        "",
        "| id | § | eq. | claim | paper | rodstab | second method | status | note |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        cells = [r.id, r.section, r.equation, r.statement, r.paper, r.rodstab,
                 (f"{r.second} ({r.second_method})" if r.second_method not in ("-", "")
                  else r.second),
                 f"**{r.status}**", r.note]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    lines += ["", "## Figures", ""]
    for title, p in figs.items():
        lines += [f"### {title}", "", f"![{title}]({p.name})", ""]
    return "\n".join(lines) + "\n"


def _html(rows: list[Claim], figs: dict[str, Path], elapsed: float) -> str:
    n_rep = sum(r.status == REPRODUCED for r in rows)
    head = ["id", "§", "eq.", "claim", "paper", "rodstab", "second method", "status", "note"]
    body = []
    for r in rows:
        second = (f"{r.second}<br><small>{html.escape(r.second_method)}</small>"
                  if r.second_method not in ("-", "") else html.escape(r.second))
        cls = "ok" if r.status == REPRODUCED else "diff"
        cells = [html.escape(r.id), html.escape(r.section), html.escape(r.equation),
                 html.escape(r.statement), html.escape(r.paper), html.escape(r.rodstab), second,
                 f'<span class="{cls}">{r.status}</span>', html.escape(r.note)]
        body.append("<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    imgs = []
    for title, p in figs.items():
        data = base64.b64encode(p.read_bytes()).decode("ascii")
        imgs.append(f"<h3>{html.escape(title)}</h3><img alt='{html.escape(title)}' "
                    f"src='data:image/png;base64,{data}'>")
    return f"""<!doctype html><html><head><meta charset="utf-8">
<title>rodstab reproduction report</title><style>
body{{font-family:sans-serif;max-width:1200px;margin:auto;padding:1em}}
table{{border-collapse:collapse;font-size:13px}}td,th{{border:1px solid #ccc;padding:4px;
vertical-align:top}}.ok{{color:#17692a;font-weight:bold}}.diff{{color:#a15c00;font-weight:bold}}
img{{max-width:100%}}</style></head><body>
<h1>rodstab reproduction report</h1>
<p>Paper: Leanza, Zhao &amp; Hutchinson, <i>On the elastic stability of folded rings in circular
and straight states</i>, Sections 2-5. rodstab {__version__}; {len(rows)} claims: {n_rep}
reproduced, {len(rows) - n_rep} differ (each explained). Computed in {elapsed:.1f} s.</p>
<table><tr>{''.join(f'<th>{h}</th>' for h in head)}</tr>{''.join(body)}</table>
<h2>Figures</h2>{''.join(imgs)}</body></html>
"""


def run_reproduction(out_dir: str | Path, *, progress: bool = True) -> dict[str, Any]:
    """Evaluate every check of :data:`rodstab.checks.REGISTRY`, draw the figures, write the report.

    Writes ``report.md``, ``report.html`` (self-contained, figures embedded), ``results.json``
    and PNG/SVG figures into ``out_dir`` (created if missing). Returns a summary dict, with the
    CPU seconds of every check (``cpu_seconds``) and the wall seconds of the stages
    (``stage_seconds``: checks, figure data and drawing, writing).
    """
    t0 = time.perf_counter()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    bar = tqdm(total=_STEPS, desc="rodstab reproduce", disable=not progress, leave=False)
    tick = lambda: bar.update(1)  # noqa: E731
    run = checks.Run(progress=tick)
    rows = checks.evaluate(run)
    t_checks = time.perf_counter()
    # Every figure is drawn from data its check stored (computed in the parallel run).
    data = {key: run.figures[key]
            for key in ("fig3", "fig4", "fig5", "rings", "fig9", "beyond", "hexagram")}
    figs: dict[str, Path] = {}
    figs["Fig. 3 - clamped arcs: stable range of L kappa_n"] = figures.fig3(data["fig3"], out)[0]
    figs["Fig. 4 - sqrt(B1 B2)/B3 vs h/t"] = figures.fig4(data["fig4"], out)[0]
    figs["Fig. 5 - longest stable clamped arc of a straight rod"] = figures.fig5(data["fig5"],
                                                                                 out)[0]
    figs["New - stable ranges of N-loop rings vs h/t"] = figures.fig_rings(data["rings"], out)[0]
    figs["Fig. 9 - modes of the folded six-sided ring"] = figures.fig9(data["fig9"], out)[0]
    figs["Beyond - post-buckling and imperfections"] = figures.fig_beyond(data["beyond"],
                                                                          out)[0]
    figs["Beyond - curved-sided hexagram: stable bands of its four states vs h/t"] = (
        figures.fig_hexagram(data["hexagram"], out)[0])
    tick()
    bar.close()
    t_figures = time.perf_counter()
    elapsed = t_figures - t0
    md, htm, js = out / "report.md", out / "report.html", out / "results.json"
    md.write_text(_markdown(rows, figs, elapsed))
    htm.write_text(_html(rows, figs, elapsed))
    js.write_text(json.dumps(jsonable({"version": __version__, "claims": rows, "figures": data}),
                             indent=1, allow_nan=False))
    n_rep = sum(r.status == REPRODUCED for r in rows)
    return {"report_md": str(md), "report_html": str(htm), "results_json": str(js),
            "figures": [str(p) for p in figs.values()], "n_claims": len(rows),
            "n_reproduced": n_rep, "n_differs": len(rows) - n_rep,
            "seconds": round(elapsed, 2),
            "cpu_seconds": {k: round(v, 2) for k, v in run.cpu_seconds.items()},
            "stage_seconds": {"checks": round(t_checks - t0, 2),
                              "figures": round(t_figures - t_checks, 2),
                              "write": round(time.perf_counter() - t_figures, 2)}}
