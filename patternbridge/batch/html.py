"""``OUT/index.html``: a static page of a batch, one row per character, one column per garment.

Served by nothing: the page reads no file at run time, the table is in the
HTML and a small script sorts, filters and opens a case's pictures, pattern
and Pareto front in a dialog. Links are relative to OUT/, so the folder can
be moved or copied whole.
"""

from __future__ import annotations

import html
import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

__all__ = ["index_html", "write_index"]

_STYLE = """
body{font:14px system-ui,sans-serif;margin:1.2em;color:#222}
h1{font-size:1.3em;margin:0 0 .3em}
.bar{display:flex;gap:1em;align-items:center;margin:.6em 0;flex-wrap:wrap}
table{border-collapse:collapse}
th,td{border:1px solid #ccc;padding:4px 6px;vertical-align:top}
th{background:#f3f3f3;cursor:pointer;user-select:none;white-space:nowrap}
th[aria-sort=ascending]::after{content:" \\25B2"}
th[aria-sort=descending]::after{content:" \\25BC"}
td.case{cursor:pointer;min-width:150px}
td.case:hover{background:#f7f9ff}
td.case img{width:140px;height:140px;object-fit:contain;display:block;background:#fafafa}
.fig{font-size:12px;line-height:1.35}
.badge{display:inline-block;padding:0 6px;border-radius:8px;font-size:12px;color:#fff;background:#888}
.ok{background:#2a7d2a}.flawed{background:#c07a00}.failed,.lost{background:#b42318}.done{background:#4a6fa5}
.err{color:#b42318;font-size:12px;max-width:200px;overflow-wrap:anywhere}
dialog{max-width:95vw}
dialog img{max-width:420px;max-height:420px;margin:4px;border:1px solid #ddd}
"""

_SCRIPT = """
(function(){
  const table=document.getElementById('cases');
  const body=table.tBodies[0];
  const metric=document.getElementById('metric');
  const filter=document.getElementById('filter');
  const status=document.getElementById('status');
  const data=JSON.parse(document.getElementById('batch-data').textContent);
  function value(row,col){
    if(col<0){return row.dataset.character;}
    const cell=row.cells[col+1];
    const v=cell.dataset[metric.value];
    return (v===undefined||v==='')?null:parseFloat(v);
  }
  function sortBy(th){
    const col=parseInt(th.dataset.col,10);
    const asc=th.getAttribute('aria-sort')!=='ascending';
    for(const h of table.tHead.rows[0].cells){h.removeAttribute('aria-sort');}
    th.setAttribute('aria-sort',asc?'ascending':'descending');
    const rows=Array.from(body.rows);
    rows.sort(function(a,b){
      const x=value(a,col),y=value(b,col);
      if(x===null&&y===null){return 0;} if(x===null){return 1;} if(y===null){return -1;}
      const c=(typeof x==='string')?x.localeCompare(y):x-y;
      return asc?c:-c;
    });
    for(const r of rows){body.appendChild(r);}
  }
  for(const th of table.tHead.rows[0].cells){th.addEventListener('click',function(){sortBy(th);});}
  metric.addEventListener('change',function(){
    const th=table.querySelector('th[aria-sort]');
    if(th){th.setAttribute('aria-sort',th.getAttribute('aria-sort')==='ascending'?'descending':'ascending');sortBy(th);}
  });
  function applyFilter(){
    const text=filter.value.trim().toLowerCase();
    const want=status.value;
    for(const row of body.rows){
      const name=row.dataset.character.toLowerCase();
      const states=Array.from(row.cells).slice(1).map(function(c){return c.dataset.state;});
      const match=(!text||name.includes(text))&&(want==='all'||states.includes(want));
      row.hidden=!match;
    }
  }
  filter.addEventListener('input',applyFilter);
  status.addEventListener('change',applyFilter);
  const dialog=document.getElementById('detail');
  function openCase(key){
    const c=data.cases.find(function(x){return x.folder===key;});
    if(!c){return;}
    const box=document.getElementById('detail-body');
    box.textContent='';
    const h=document.createElement('h2');
    h.textContent=c.character+' \\u00d7 '+c.garment+' \\u2014 '+(c.verdict||c.status);
    box.appendChild(h);
    if(c.error){const p=document.createElement('p');p.className='err';p.textContent=c.error;box.appendChild(p);}
    for(const name of c.files){
      if(name.endsWith('.png')){
        const a=document.createElement('a');a.href=c.folder+'/'+name;a.target='_blank';
        const img=document.createElement('img');img.src=c.folder+'/'+name;img.alt=name;img.title=name;
        a.appendChild(img);box.appendChild(a);
      }
    }
    const list=document.createElement('ul');
    for(const name of c.files){
      if(name.endsWith('.png')){continue;}
      const li=document.createElement('li');const a=document.createElement('a');
      a.href=c.folder+'/'+name;a.textContent=name;li.appendChild(a);list.appendChild(li);
    }
    box.appendChild(list);
    dialog.showModal();
  }
  for(const cell of body.querySelectorAll('td.case')){
    cell.addEventListener('click',function(){openCase(cell.dataset.key);});
  }
  document.getElementById('close').addEventListener('click',function(){dialog.close();});
})();
"""


def _num(value: Any, fmt: str) -> str:
    return "–" if value is None else format(value, fmt)


def _cell(case: Mapping[str, Any] | None) -> str:
    if case is None:
        return '<td class="empty" data-state="none">not run</td>'
    fig = case.get("figures") or {}
    state = case.get("verdict") or case["status"]
    files = case.get("files") or []
    thumb = next((n for n in ("fit_front.png", "pattern.png") if n in files), None)
    attrs = {
        "key": case["folder"], "state": state,
        "mean": fig.get("mean_error_cm"), "shape": fig.get("shape_error"),
        "gap": fig.get("seam_gap_before_weld_mm"), "time": case.get("seconds") if case["status"] == "done" else None,
    }
    data = " ".join(f'data-{k}="{html.escape("" if v is None else str(v))}"' for k, v in attrs.items())
    parts = [f'<td class="case" {data}>']
    if thumb:
        src = html.escape(f"{case['folder']}/{thumb}")
        parts.append(f'<img src="{src}" alt="{html.escape(thumb)}" loading="lazy">')
    parts.append(f'<span class="badge {html.escape(state)}">{html.escape(state)}</span>')
    if fig:
        shape_vs = f"{_num(fig.get('shape_error'), '.4f')} (prop. {_num(fig.get('baseline_shape_error'), '.4f')})"
        parts.append(
            '<div class="fig">'
            f"measurement {_num(fig.get('mean_error_cm'), '.2f')} cm (max {_num(fig.get('max_error_cm'), '.2f')})<br>"
            f"shape {shape_vs}<br>"
            f"seam gap before weld {_num(fig.get('seam_gap_before_weld_mm'), '.1f')} mm<br>"
            f"time {_num(case.get('seconds'), '.0f')} s</div>"
        )
    if case.get("error"):
        parts.append(f'<div class="err">{html.escape(case["error"])}</div>')
    parts.append("</td>")
    return "".join(parts)


def index_html(manifest: Mapping[str, Any]) -> str:
    """The page of a batch manifest (the ``batch.json`` object)."""
    cases = list(manifest.get("cases", []))
    characters = [c["name"] for c in manifest["inputs"]["characters"]]
    garments = [g["name"] for g in manifest["inputs"]["garments"]]
    by_key = {(c["character"], c["garment"]): c for c in cases}
    head = '<th data-col="-1">character</th>' + "".join(
        f'<th data-col="{i}">{html.escape(g)}</th>' for i, g in enumerate(garments)
    )
    rows = "\n".join(
        f'<tr data-character="{html.escape(ch)}"><th scope="row">{html.escape(ch)}</th>'
        + "".join(_cell(by_key.get((ch, g))) for g in garments) + "</tr>"
        for ch in characters
    )
    counts = ", ".join(f"{n} {s}" for s, n in sorted(manifest.get("counts", {}).items()))
    blob = json.dumps({"cases": cases}).replace("</", "<\\/")
    seed = html.escape(str(manifest.get("seed")))
    written = html.escape(str(manifest.get("written", "")))
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>PatternBridge batch</title>
<link rel="icon" href="data:,">
<style>{_STYLE}</style></head>
<body>
<h1>PatternBridge batch: {len(characters)} characters × {len(garments)} garments</h1>
<div>{html.escape(counts)}; seed {seed}; written {written}</div>
<div class="bar">
<label>character <input id="filter" type="search" placeholder="filter"></label>
<label>show <select id="status"><option value="all">all</option><option value="ok">ok</option>
<option value="flawed">flawed</option><option value="failed">failed</option><option value="lost">lost</option>
<option value="done">done (no verdict)</option></select></label>
<label>sort garments by <select id="metric"><option value="mean">measurement error</option>
<option value="shape">shape error</option><option value="gap">seam gap before weld</option>
<option value="time">time</option></select></label>
</div>
<table id="cases"><thead><tr>{head}</tr></thead>
<tbody>
{rows}
</tbody></table>
<dialog id="detail"><button id="close">close</button><div id="detail-body"></div></dialog>
<script type="application/json" id="batch-data">{blob}</script>
<script>{_SCRIPT}</script>
</body></html>
"""


def write_index(out_dir: Path, manifest: Mapping[str, Any]) -> Path:
    """Write ``OUT/index.html`` atomically."""
    from ..atomic import write_text

    return write_text(Path(out_dir) / "index.html", index_html(manifest))
