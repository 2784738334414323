// Cairn mission report: one printable page (the browser's "save as PDF") from the base's live API:
// the map, every object with the operator's verdict and its photo, per-robot figures, the
// operator's commands and the exports. Works mid-mission (a snapshot) and after it.
"use strict";

async function buildReport() {
  const [status, robots, objects, commands, exports] = await Promise.all([
    getJson("/api/status"), getJson("/api/robots"), getJson("/api/objects"), getJson("/api/commands"),
    getJson("/api/exports"),
  ]);
  document.getElementById("r-time").textContent = fmtTime(status.mission_time_s);
  document.getElementById("r-area").textContent = `${(status.mapped_area_m2 || 0).toFixed(0)} m²`;
  document.getElementById("r-linked").textContent = `${status.linked_robots ?? 0} / ${status.robots ?? 0}`;
  document.getElementById("r-objects").textContent = `${status.objects ?? 0}`;
  document.getElementById("r-generated").textContent = `Generated ${new Date().toLocaleString()} from the base station at ${location.host}.`;
  document.getElementById("r-map").src = `/api/map.png?t=${Date.now()}`;

  replaceRows(document.getElementById("r-object-rows"), objects.map((o) => {
    const p = o.position_m || [0, 0, 0];
    const where = o.frame && o.frame !== "global"
      ? `not on the map: ${o.from_entry ? o.from_entry.text : o.frame}`
      : `(${p[0].toFixed(2)}, ${p[1].toFixed(2)}, ${p[2].toFixed(2)}) m`;
    return el("tr", {}, [
      el("td", { text: o.class }),
      el("td", { text: o.id }),
      el("td", { text: `${o.verdict}${o.verdict_note ? `: ${o.verdict_note}` : ""}` }),
      el("td", { text: where }),
      el("td", { text: `${Math.round(100 * o.confidence)} %` }),
      el("td", { text: (o.robots || []).map((r) => `Robot ${r}`).join(", ") }),
      el("td", {}, o.thumbnail ? [el("img", { class: "thumb", src: o.thumbnail, alt: `${o.class} ${o.id}` })] : []),
    ]);
  }), "No objects", 7);

  replaceRows(document.getElementById("r-robot-rows"), robots.map((r) => {
    const link = r.link || {};
    return el("tr", {}, [
      el("td", { text: `Robot ${r.id}` }),
      el("td", { text: r.linked ? "linked" : "not linked" }),
      el("td", { text: r.time_to_link_s === null || r.time_to_link_s === undefined ? "–" : `${r.time_to_link_s.toFixed(0)} s` }),
      el("td", { text: `${r.keyframes}` }),
      el("td", { text: link.distance_m === undefined ? "–" : `${link.distance_m.toFixed(0)} m` }),
      el("td", { text: fmtBytes(link.bytes_rx) }),
      el("td", { text: link.activity || link.state || "–" }),
    ]);
  }), "No robots", 7);

  const done = commands.filter((c) => c.state === "done").length;
  document.getElementById("r-commands").textContent = commands.length === 0 ? "None." :
    `${commands.length} sent, ${done} done: ` + commands.slice().reverse().map((c) =>
      `#${c.seq} robot ${c.robot} ${c.kind}${c.kind === "goto" ? ` (${c.x_m.toFixed(1)}, ${c.y_m.toFixed(1)})` : ""} ${c.state}`).join("; ");

  const list = document.getElementById("r-exports");
  list.replaceChildren();
  if (!exports.ready) list.appendChild(el("li", { class: "empty", text: exports.note }));
  for (const f of exports.files) list.appendChild(el("li", {}, [el("a", { href: f.url, download: f.name, text: f.name })]));
}

document.getElementById("print").addEventListener("click", () => window.print());
buildReport().catch((e) => {
  document.getElementById("r-generated").textContent = `The base station is unreachable: ${e.message}`;
});
