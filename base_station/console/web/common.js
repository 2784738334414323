// Cairn console: helpers the pages share (index.html, report.html). Plain JS, no build step.
"use strict";

function el(tag, attrs = {}, children = []) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "text") e.textContent = v;
    else e.setAttribute(k, v);
  }
  for (const c of children) e.appendChild(c);
  return e;
}

function fmtTime(seconds) {
  const s = Math.max(0, Math.floor(seconds || 0));
  const h = Math.floor(s / 3600), m = Math.floor((s % 3600) / 60), r = s % 60;
  return `${String(h).padStart(2, "0")}:${String(m).padStart(2, "0")}:${String(r).padStart(2, "0")}`;
}

function fmtBytes(n) {
  if (n === undefined || n === null) return "–";
  if (n < 1024) return `${Math.round(n)} B`;  // rates are fractional
  if (n < 1024 * 1024) return `${(n / 1024).toFixed(1)} kB`;
  return `${(n / 1024 / 1024).toFixed(1)} MB`;
}

function replaceRows(tbody, rows, emptyText, columns) {
  tbody.replaceChildren();
  if (rows.length === 0) {
    tbody.appendChild(el("tr", {}, [el("td", { colspan: columns, class: "empty", text: emptyText })]));
    return;
  }
  rows.forEach((r) => tbody.appendChild(r));
}

// Revalidated: the base answers an unchanged list with a 304 (ETag), which reaches us as the
// cached answer.
async function getJson(path) {
  const res = await fetch(path, { cache: "no-cache" });
  if (!res.ok) throw new Error(`${path}: HTTP ${res.status}`);
  return res.json();
}
