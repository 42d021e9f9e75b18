r"""A result as one self-contained HTML file that works offline: ``mechatron size|tolerance|linkage --report FILE``.

A report is content first, HTML second. Every :class:`~mechatron.report.result.Result` says what its report holds
with :meth:`~mechatron.report.result.Result.report`, a :class:`Report`: a title and :class:`Section` s of items —

- :class:`Text`: a paragraph;
- :class:`Code`: preformatted text (a text report);
- :class:`Method`: a docstring of the code that computed the result, with its equations and citations;
- :class:`Table`: a pandas DataFrame;
- :class:`Chart`: a matplotlib Figure;

the default being the result's text report, table and chart; an analysis overrides it to add its method, its checks
and a drawing of the mechanism. :func:`write_report` puts the inputs first (the command's options, the mechanism,
the input files) and the references last: every ``[Key, …]`` cited anywhere in the report resolved to the full
reference of ``docs/references.md`` (:data:`~mechatron.report.references.REFERENCES`), and writes the file whole or
not at all (:func:`mechatron.io.output.write_text`).

Self-contained: charts are PNG images inside the file (``data:`` URLs), the style sheet and the one script are
inline, and a Content-Security-Policy allows nothing else (``data:`` images, and that style sheet and script by their
SHA-256), so the file shows the same without a network. Everything that comes from the user (names in files,
options, file contents) is escaped; were something to slip through, the policy would still keep it from running or
loading anything. The script only checks,
once the page has loaded, that every chart decoded: it sets ``data-charts-shown="N of M"`` on ``<body>`` and shows a
warning when N < M.
"""

from __future__ import annotations

import base64
import hashlib
import html
import inspect
import io
import math
import re
import sys
import textwrap
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from .references import REFERENCES

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.figure import Figure

    from ..model.mechanism import Mechanism

#: Resolution of the charts (dots per inch).
DPI = 96
#: Input files larger than this (bytes) are named, not embedded.
LARGEST_EMBEDDED_FILE = 1_000_000
#: Rows a table shows at most (the rest is in ``--csv``).
LARGEST_TABLE = 2000


# ------------------------------------------------------------------------------------------------- the content
@dataclass(frozen=True)
class Text:
    """A paragraph of plain text; ``[Key, …]`` citations link to the references."""

    text: str


@dataclass(frozen=True)
class Code:
    """Preformatted text, e.g. a text report."""

    text: str


@dataclass(frozen=True)
class Method:
    """A docstring (reStructuredText as the code writes it): paragraphs, ``-`` lists, indented equations and
    ``====`` tables; roles such as ``:func:`~a.b``` become ``b``."""

    text: str


@dataclass(frozen=True)
class Table:
    """A DataFrame shown as a table (numbers to 6 significant digits, a ``pass`` column as PASS/FAIL). ``name``
    becomes its ``data-table`` attribute."""

    frame: pd.DataFrame
    caption: str = ""
    name: str = ""


@dataclass(frozen=True)
class Chart:
    """A matplotlib figure, embedded as a PNG."""

    figure: Figure
    caption: str = ""


Item = Text | Code | Method | Table | Chart


@dataclass
class Section:
    """A titled part of a report."""

    title: str
    items: list[Item] = field(default_factory=list)


@dataclass
class Report:
    """What a report holds: a title, a one-line summary (the verdict) and sections, in order."""

    title: str
    sections: list[Section] = field(default_factory=list)
    summary: str = ""


# ---------------------------------------------------------------------------------------------------- writing
class Reportable(Protocol):
    """What has a report: a :class:`~mechatron.report.result.Result` (a protocol, so that this module needs no
    import of the results, which import it)."""

    def report(self, mechanism: Mechanism | None = None, **context: Any) -> Report: ...


def write_report(result: Reportable, path: str | Path, *, inputs: Mapping[str, Any] | None = None,
                 files: Iterable[str | Path] = (), mechanism: Mechanism | None = None, **context: Any) -> Path:
    """Write the HTML report of ``result`` (:meth:`~mechatron.report.result.Result.report`, given ``mechanism``
    and ``context``) to ``path``, whole or not at all: the inputs — ``inputs`` (option → value), the mechanism
    and the text of ``files`` — then the result's sections, then the references it cites."""
    from ..io.output import write_text

    report = result.report(mechanism=mechanism, **context)
    return write_text(path, render(report, inputs_section(inputs, mechanism, files)))


def render(report: Report, inputs: Section | None = None) -> str:
    """The report as one HTML document: ``inputs`` (if given) first, then the report's sections, then the
    references cited in any of them."""
    sections = ([inputs] if inputs is not None and inputs.items else []) + list(report.sections)
    ids = _Ids()
    cited: list[str] = []
    bodies = [(ids.new(s.title), s.title, "".join(_item(item, cited) for item in s.items)) for s in sections]
    if cited:
        bodies.append((ids.new("References"), "References", _references(cited)))
    contents = "".join(f'<li><a href="#{key}">{_escape(title)}</a></li>' for key, title, _ in bodies)
    parts = [f'<section id="{key}"><h2>{_escape(title)}</h2>{body}</section>' for key, title, body in bodies]
    version = getattr(sys.modules.get("mechatron"), "__version__", "")
    summary = f'<p class="summary">{_cite(_escape(report.summary), cited)}</p>' if report.summary else ""
    return (f"<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<meta http-equiv=\"Content-Security-Policy\" content=\"{_POLICY}\">\n"
            f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
            f"<meta name=\"generator\" content=\"mechatron {_escape(version)}\">\n"
            f"<link rel=\"icon\" href=\"data:,\">\n<title>{_escape(report.title)}</title>\n"
            f"<style>{_STYLE}</style>\n</head>\n<body>\n<header><h1>{_escape(report.title)}</h1>{summary}"
            f"<p class=\"warning\" id=\"charts-warning\" hidden>Some charts of this report could not be shown.</p>"
            f"</header>\n<nav><ol>{contents}</ol></nav>\n<main>\n" + "\n".join(parts) +
            f"\n</main>\n<footer>mechatron {_escape(version)}; SI units unless a column or axis says otherwise."
            f"</footer>\n<script>{_SCRIPT}</script>\n</body>\n</html>\n")


def inputs_section(inputs: Mapping[str, Any] | None, mechanism: Mechanism | None = None,
                   files: Iterable[str | Path] = ()) -> Section:
    """The inputs of an analysis: the options given (``inputs``: name → value; None shown as "default"), the
    mechanism (name, description, source, joints and geometric parameters, SI) and the text of its source file and
    of each of ``files`` that exists, once each (larger ones only named)."""
    import pandas as pd

    items: list[Item] = []
    if inputs:
        items.append(Table(pd.DataFrame({"option": list(inputs), "value": [_option(v) for v in inputs.values()]}),
                           "options", "options"))
    if mechanism is not None:
        about = [("name", mechanism.name), ("description", mechanism.description),
                 ("source", mechanism.source or "built in"), ("joints", len(mechanism.joint_names)),
                 ("actuated coordinates", ", ".join(mechanism.actuated)),
                 ("closed loops (closures)", len(mechanism.closures))]
        items.append(Table(pd.DataFrame(about, columns=["mechanism", "value"]), "mechanism", "mechanism"))
        joints = pd.DataFrame({"joint": mechanism.joint_names,
                               "kind": [mechanism.joint_kind(n) for n in mechanism.joint_names]})
        items.append(Table(joints, "joints", "joints"))
        if mechanism.parameters:
            items.append(Table(pd.DataFrame(
                [(p.name, p.value, p.unit, p.description) for p in mechanism.parameters.values()],
                columns=["parameter", "value", "unit", "description"]), "geometric parameters (SI)", "parameters"))
    source = [mechanism.source] if mechanism is not None and mechanism.source else []
    for path in {Path(p).resolve(): Path(p) for p in [*source, *files] if Path(p).is_file()}.values():
        size = path.stat().st_size
        text = _read(path) if size <= LARGEST_EMBEDDED_FILE else None
        items.append(Code(f"# {path}\n{text}") if text is not None else Text(f"{path}: {size} bytes, not embedded"))
    return Section("Inputs", items)


def _read(path: Path) -> str | None:
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None


def _option(value: Any) -> str:
    if value is None:
        return "default"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (list, tuple)):
        return ", ".join(str(v) for v in value)
    return str(value)


# ---------------------------------------------------------------------------------------------------- the items
def _item(item: Item, cited: list[str]) -> str:
    if isinstance(item, Text):
        return f"<p>{_cite(_escape(item.text), cited)}</p>"
    if isinstance(item, Code):
        return f"<pre>{_cite(_escape(item.text), cited)}</pre>"
    if isinstance(item, Method):
        return f'<div class="method">{_method(item.text, cited)}</div>'
    if isinstance(item, Table):
        return _table(item)
    if isinstance(item, Chart):
        return _chart(item)
    raise TypeError(f"a report item cannot be a {type(item).__name__}")


_ROLE = re.compile(r":[a-z]+:`(~?)([^`<]*?)(?:\s*<([^`>]+)>)?`")
_LITERAL = re.compile(r"``(.+?)``")
_RULE = re.compile(r"^\s*=+(\s+=+)*\s*$")


def _method(docstring: str, cited: list[str]) -> str:
    """A docstring as HTML: blank-line separated blocks; a block with a ``====`` rule or all indented is
    preformatted (tables, equations), ``-`` lines are list items (indented lines continue them), the rest
    paragraphs."""
    out = []
    for block in re.split(r"\n\s*\n", inspect.cleandoc(docstring or "")):
        lines = block.splitlines()
        if not lines:
            continue
        if any(_RULE.match(line) for line in lines):
            out.append(_simple_table(lines, cited))
            continue
        if all(line.startswith(" ") for line in lines):
            out.append(f"<pre>{_inline(textwrap.dedent(block).strip(chr(10)), cited, code=True)}</pre>")
            continue
        paragraph: list[str] = []
        items: list[list[str]] = []
        for line in lines:
            if line.startswith("- "):
                out.append(_paragraph(paragraph, cited))
                items.append([line[2:]])
            elif items and line.startswith(" "):
                items[-1].append(line.strip())
            else:
                out.append(_list(items, cited))
                paragraph.append(line.strip())
        out += [_paragraph(paragraph, cited), _list(items, cited)]
    return "".join(out)


def _simple_table(lines: list[str], cited: list[str]) -> str:
    """A reStructuredText simple table (columns under the ``===`` runs of its rules; a line whose first column is
    empty continues the row above; the rows above the second rule are the header) as an HTML table."""
    rules = [i for i, line in enumerate(lines) if _RULE.match(line)]
    spans = [m.span() for m in re.finditer(r"=+", lines[rules[0]])]
    spans[-1] = (spans[-1][0], max(len(line) for line in lines))
    rows: list[list[str]] = []
    header = 0
    for i, line in enumerate(lines):
        if i in rules:
            header = len(rows) if len(rules) > 2 and i == rules[1] else header
            continue
        cells = [line[a:b].strip() for a, b in spans]
        if rows and not cells[0] and i - 1 not in rules:
            rows[-1] = [f"{old} {new}".strip() for old, new in zip(rows[-1], cells)]
        else:
            rows.append(cells)
    body = []
    for k, row in enumerate(rows):
        tag = "th" if k < header else "td"
        body.append("<tr>" + "".join(f"<{tag}>{_inline(cell, cited)}</{tag}>" for cell in row) + "</tr>")
    return '<table class="equations">' + "".join(body) + "</table>"


def _paragraph(lines: list[str], cited: list[str]) -> str:
    """A paragraph of the lines gathered so far (emptied); nothing if there are none."""
    text = " ".join(lines)
    lines.clear()
    return f"<p>{_inline(text, cited)}</p>" if text else ""


def _list(items: list[list[str]], cited: list[str]) -> str:
    """A list of the items gathered so far (emptied); nothing if there are none."""
    out = "".join(f"<li>{_inline(' '.join(item), cited)}</li>" for item in items)
    items.clear()
    return f"<ul>{out}</ul>" if out else ""


def _inline(text: str, cited: list[str], code: bool = False) -> str:
    """Escape ``text``, turn roles and double-backquoted literals into ``<code>``, ``**strong**`` and ``*emphasis*``
    into ``<strong>`` and ``<em>``, link citations."""
    def role(match: re.Match) -> str:
        target = match.group(3) or match.group(2)
        shown = match.group(2).strip() if match.group(3) else (target.rsplit(".", 1)[-1] if match.group(1)
                                                                  else target)
        return f"\x00{shown}\x01"

    text = _LITERAL.sub(lambda m: f"\x00{m.group(1)}\x01", _ROLE.sub(role, text))
    text = _cite(_escape(text), cited)
    if not code:
        text = _EMPHASIS.sub(r"<em>\1</em>", _STRONG.sub(r"<strong>\1</strong>", text))
    return text.replace("\x00", "" if code else "<code>").replace("\x01", "" if code else "</code>")


_CITATION = re.compile(r"\[(" + "|".join(re.escape(k) for k in sorted(REFERENCES, key=len, reverse=True))
                       + r")((?:, [^\[\]<>]*)?)\]")


def _cite(escaped: str, cited: list[str]) -> str:
    """Link every ``[Key, …]`` of a known key in (escaped) text to its reference, noting the key in ``cited``."""
    def link(match: re.Match) -> str:
        key = match.group(1)
        if key not in cited:
            cited.append(key)
        return f'<a class="citation" href="#{_reference_id(key)}">{match.group(0)}</a>'

    return _CITATION.sub(link, escaped)


def _reference_id(key: str) -> str:
    return "ref-" + re.sub(r"[^A-Za-z0-9]+", "-", key)


_STRONG = re.compile(r"(?<![\w*])\*\*(?=\S)([^*]+?)(?<=\S)\*\*(?![\w*])")
_EMPHASIS = re.compile(r"(?<![\w*])\*(?=\S)([^*]+?)(?<=\S)\*(?![\w*])")
_BACKQUOTED = re.compile(r"`([^`]+)`")


def _references(cited: Sequence[str]) -> str:
    """The full references of the cited keys, in the order first cited."""
    entries = []
    for key in cited:
        text = _BACKQUOTED.sub(r"<code>\1</code>", _EMPHASIS.sub(r"<em>\1</em>", _escape(REFERENCES[key])))
        entries.append(f'<li id="{_reference_id(key)}"><strong>[{_escape(key)}]</strong> {text}</li>')
    return '<ul class="references">' + "".join(entries) + "</ul>"


def _table(table: Table) -> str:
    frame = table.frame
    shown = frame.head(LARGEST_TABLE)
    columns = [str(c) for c in shown.columns]
    head = "".join(f'<th scope="col">{_escape(c)}</th>' for c in columns)
    rows = []
    for values in shown.itertuples(index=False, name=None):
        cells = []
        for column, value in zip(columns, values):
            text, css = _cell(value, column)
            cells.append(f'<td class="{css}">{_escape(text)}</td>' if css else f"<td>{_escape(text)}</td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    more = len(frame) - len(shown)
    caption = table.caption + (f" (the first {len(shown)} of {len(frame)} rows)" if more else "")
    name = f' data-table="{_escape(table.name)}"' if table.name else ""
    return (f'<div class="table"><table{name}>' + (f"<caption>{_escape(caption)}</caption>" if caption else "")
            + f"<thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table></div>")


def _cell(value: Any, column: str) -> tuple[str, str]:
    """(text, CSS class) of one table cell: numbers to 6 significant digits, NaN and None empty, yes/no for
    booleans but PASS/FAIL in a ``pass`` column."""
    import numpy as np

    if value is None:
        return "", ""
    if isinstance(value, (bool, np.bool_)):
        if column == "pass":
            return ("PASS", "pass") if value else ("FAIL", "fail")
        return ("yes" if value else "no"), ""
    if isinstance(value, (int, np.integer)):
        return str(int(value)), "number"
    if isinstance(value, (float, np.floating)):
        return ("", "") if math.isnan(value) else (f"{float(value):.6g}", "number")
    return str(value), ""


def _chart(chart: Chart) -> str:
    buffer = io.BytesIO()
    chart.figure.savefig(buffer, format="png", dpi=DPI)
    data = base64.b64encode(buffer.getvalue()).decode("ascii")
    caption = _escape(chart.caption)
    return (f'<figure><img src="data:image/png;base64,{data}" alt="{caption}">'
            + (f"<figcaption>{caption}</figcaption>" if caption else "") + "</figure>")


def _escape(text: Any) -> str:
    return html.escape(str(text), quote=True)


class _Ids:
    """Unique HTML ids made of letters, digits and dashes."""

    def __init__(self) -> None:
        self.used: set[str] = set()

    def new(self, title: str) -> str:
        base = "s-" + (re.sub(r"[^a-z0-9]+", "-", title.lower()).strip("-") or "section")
        key, n = base, 1
        while key in self.used:
            n += 1
            key = f"{base}-{n}"
        self.used.add(key)
        return key


_STYLE = """
body{font-family:system-ui,sans-serif;max-width:72rem;margin:0 auto;padding:1rem 1.5rem;color:#1a1a1a;
line-height:1.45}
h1{font-size:1.5rem}h2{font-size:1.2rem;border-bottom:1px solid #ccc;padding-bottom:.2rem;margin-top:2rem}
table{border-collapse:collapse;margin:.8rem 0;font-size:.85rem}caption{text-align:left;font-weight:600;
padding:.3rem 0}th,td{border:1px solid #ccc;padding:.2rem .5rem;vertical-align:top}th{background:#f2f2f2}
td.number{text-align:right;font-variant-numeric:tabular-nums}td.pass{color:#176f2c;font-weight:600}
td.fail{color:#fff;background:#b3261e;font-weight:600}pre{background:#f7f7f7;padding:.6rem;overflow-x:auto;
font-size:.8rem}figure{margin:1rem 0}img{max-width:100%;height:auto}figcaption{font-size:.85rem;color:#444}
.summary{font-weight:600}.warning{color:#b3261e;font-weight:600}.method{border-left:3px solid #ddd;
padding-left:1rem}nav ol{columns:2;font-size:.9rem}footer{margin-top:2rem;font-size:.8rem;color:#666}
div.table{overflow-x:auto;max-width:100%}
@media print{nav{display:none}section{break-inside:avoid-page}}
"""
_SCRIPT = """
window.addEventListener("load", function () {
  var images = document.images, shown = 0;
  for (var i = 0; i < images.length; i++) {
    if (images[i].complete && images[i].naturalWidth > 0) { shown++; }
  }
  document.body.setAttribute("data-charts-shown", shown + " of " + images.length);
  var page = document.documentElement;
  document.body.setAttribute("data-page-width", page.scrollWidth <= page.clientWidth ? "fits" : "overflows");
  if (shown < images.length) { document.getElementById("charts-warning").hidden = false; }
});
"""


def _digest(text: str) -> str:
    return "'sha256-" + base64.b64encode(hashlib.sha256(text.encode("utf-8")).digest()).decode("ascii") + "'"


#: Nothing but ``data:`` images, the report's own style sheet and its own script (by their hashes): a name in a
#: file that escaped escaping still could neither run nor load anything.
_POLICY = f"default-src 'none'; img-src data:; style-src {_digest(_STYLE)}; script-src {_digest(_SCRIPT)}"
