// Cairn console: fetches the base station's JSON API when the base's event stream says it changed;
// the map view is mapview.js, the operator's commands control.js. Plain JS, no build step.
"use strict";

const REFRESH_MS = 10000;  // the slow poll; changes are pushed (listen())
const CLASS_COLOURS = { victim: "#dc1e1e", hazard: "#ff8c00", exit: "#28a028" };

// How long after the base received a keyframe the page showed it (the status's keyframe_wall_s:
// the oldest keyframe that snapshot shows first); same clock when the page runs on the base's
// machine, as in the benchmark (bench/console_page.mjs). The last 1000, for the benchmark.
window.cairnUpdateLags = [];
let lastKeyframeWall = null;
function noteUpdateLag(status) {
  const t = status.keyframe_wall_s;
  if (t === null || t === undefined || t === lastKeyframeWall) return;
  lastKeyframeWall = t;
  window.cairnUpdateLags.push(Date.now() / 1000 - t);
  if (window.cairnUpdateLags.length > 1000) window.cairnUpdateLags.shift();
}

function renderStatus(status) {
  document.getElementById("mission-time").textContent = fmtTime(status.mission_time_s);
  document.getElementById("mapped-area").textContent = `${(status.mapped_area_m2 || 0).toFixed(0)} m²`;
  document.getElementById("robots-linked").textContent = `${status.linked_robots ?? 0} / ${status.robots ?? 0}`;
  document.getElementById("object-count").textContent = `${status.objects ?? 0}`;
  const list = document.getElementById("alerts");
  list.replaceChildren();
  const alerts = status.alerts || [];
  if (alerts.length === 0) list.appendChild(el("li", { class: "empty", text: "No alerts" }));
  for (const a of alerts) {
    const since = a.first_seen_s ? ` · since ${new Date(a.first_seen_s * 1000).toLocaleTimeString()}` : "";
    const item = el("li", { class: `alert ${a.level}${a.acked ? " acked" : ""}` }, [
      el("span", { text: a.text }), el("span", { class: "when", text: `${a.acked ? "acknowledged" : ""}${since}` }),
    ]);
    if (!a.acked && a.key) {
      const ack = Control.ackButton(a.key);
      if (ack) item.appendChild(ack);
    }
    list.appendChild(item);
  }
}

// Bytes per second received from each robot, from the byte counts the page sees (one sample per
// refresh), drawn as a small sparkline: the last 60 samples.
const byteSamples = new Map();  // robot id -> [{t_s, bytes}]
function rateSparkline(id, bytes) {
  const samples = byteSamples.get(id) || [];
  const t_s = Date.now() / 1000;
  if (bytes !== undefined && (!samples.length || t_s - samples[samples.length - 1].t_s > 0.5)) samples.push({ t_s, bytes });
  while (samples.length > 61) samples.shift();
  byteSamples.set(id, samples);
  const rates = [];
  for (let i = 1; i < samples.length; ++i)
    rates.push(Math.max(0, (samples[i].bytes - samples[i - 1].bytes) / (samples[i].t_s - samples[i - 1].t_s)));
  const cell = el("td", { class: "rate" });
  if (!rates.length) return cell.appendChild(document.createTextNode("–")), cell;
  const max = Math.max(...rates, 1), w = 80, h = 18;
  const points = rates.map((r, i) => `${(i * w) / Math.max(1, rates.length - 1)},${h - (r * h) / max}`).join(" ");
  const svg = document.createElementNS("http://www.w3.org/2000/svg", "svg");
  svg.setAttribute("width", w);
  svg.setAttribute("height", h);
  svg.setAttribute("class", "sparkline");
  const line = document.createElementNS("http://www.w3.org/2000/svg", "polyline");
  line.setAttribute("points", points);
  svg.appendChild(line);
  cell.append(svg, document.createTextNode(` ${fmtBytes(rates[rates.length - 1])}/s`));
  return cell;
}

// The robot's own planner obeys the keep-out areas once its status reports the version the base sent.
const keepOutPending = (link) => (link.keep_out_sent ?? 0) > 0 && link.keep_out_held !== link.keep_out_sent;

function renderRobots(robots) {
  const rows = robots.map((r) => {
    const link = r.link || {};
    const linkText = link.state ? `${link.state}${link.rtt_ms !== undefined ? ` · ${link.rtt_ms} ms` : ""}` : "–";
    const sentText = (received, sent) => sent === undefined ? `${received}` : `${received} / ${sent}`;
    return el("tr", {}, [
      // A robot that restarted without its state runs a new session, shown as its own row (label).
      el("td", { text: link.label ? link.label.replace(/^robot(\d+)/, "Robot $1") : `Robot ${r.id}` }),
      el("td", {}, [el("span", { class: r.linked ? "badge ok" : "badge warn", text: r.linked ? "linked" : "not linked",
        title: r.alignment ? alignmentText(r.alignment) : "" }),
      document.createTextNode(r.linked && r.alignment && r.alignment.state === "accepted" ? " (by your alignment)" : "")]),
      el("td", { text: r.time_to_link_s === null || r.time_to_link_s === undefined ? "–" : `${r.time_to_link_s.toFixed(0)} s` }),
      el("td", {
        class: link.nav_state === "stuck" || link.nav_state === "unreachable" || keepOutPending(link) ? "bad" : "",
        title: link.keep_out_sent ? `keep-out areas: holds version ${link.keep_out_held} of ${link.keep_out_sent} sent` : "",
        text: (link.activity ? `${link.activity}${link.nav_state && link.nav_state !== "driving" ? ` (goal ${link.nav_state})` : ""}` : "–") +
          (keepOutPending(link) ? " · keep-out areas not confirmed" : ""),
      }),
      el("td", { text: link.distance_m === undefined ? "–" : `${link.distance_m.toFixed(0)} m` }),
      el("td", { title: "received at the base / sent by the robot",
        text: sentText(r.keyframes, link.keyframes_sent) + (r.missing_keyframes ? ` (${r.missing_keyframes} missing)` : "") }),
      el("td", { title: "received at the base / sent by the robot", text: sentText(r.objects ?? 0, link.objects_sent) }),
      el("td", { text: fmtBytes(link.bytes_rx) }),
      rateSparkline(r.id, link.bytes_rx),
      el("td", { class: link.state === "lost" ? "bad" : "", text: linkText }),
      el("td", { text: link.last_heard_age_s === undefined || link.last_heard_age_s < 0 ? "–" : `${link.last_heard_age_s.toFixed(1)} s ago` }),
      el("td", { text: link.battery_pct === null || link.battery_pct === undefined ? "not reported" : `${link.battery_pct.toFixed(0)} %` }),
      el("td", { class: link.collision_risk || link.laser_lost ? "bad" : "",
        title: link.laser_lost ? "its laser is silent: placed by odometry alone, going home by the map it has" : "",
        text: [link.laser_lost ? "laser lost" : "", link.collision_risk ? "risk ahead" : ""].filter(Boolean).join(" · ") || "clear" }),
    ]);
  });
  replaceRows(document.getElementById("robots"), rows, "No robots yet", 13);
}

// Robots the base has not placed yet: their own maps, so that nothing they found is hidden, and
// the operator's alignment of each over the global map (align.js) with the base's verdict. An
// image is fetched again every 10 keyframes (about 10 s), not at every refresh: it is a whole
// rendered map, the page's dearest download.
let alignFeedback = null;  // {robot, ok, text}: what the page said when the operator sent an alignment
function renderOwnMaps(unlinked) {
  const panel = document.getElementById("own-maps-panel");
  panel.hidden = unlinked.length === 0;
  const box = document.getElementById("own-maps");
  const shown = new Map([...box.querySelectorAll("figure")].map((f) => [f.dataset.robot, f]));
  if (Align.aligning() !== null && !unlinked.some((r) => r.id === Align.aligning())) Align.stop();
  box.replaceChildren(...unlinked.map((r) => {
    const src = `${r.own_map}?keyframes=${Math.floor(r.keyframes / 10) * 10}`;
    let figure = shown.get(String(r.id));
    if (!figure || figure.dataset.src !== src) {
      figure = el("figure", { class: "own-map" }, [
        el("img", { src, alt: `Robot ${r.id}'s own map` }),
        el("figcaption", { text: `Robot ${r.id}, not yet placed on the map: its own map, from where it entered` }),
        el("div", { class: "align-box" }),
      ]);
      figure.dataset.robot = String(r.id);
      figure.dataset.src = src;
    }
    figure.querySelector(".align-box").replaceChildren(...alignControls(r));
    return figure;
  }));
}

function alignmentText(a) {
  const p = a.requested;
  const where = `entry at (${p.x_m.toFixed(2)}, ${p.y_m.toFixed(2)}) m, heading ${p.yaw_deg.toFixed(1)} deg`;
  if (a.state === "pending") return `Verifying your alignment (${where})…`;
  if (a.state === "accepted") return `Placed on the map: ${a.reason}.`;
  return `Your alignment (${where}) was refused: ${a.reason}.`;
}

function alignControls(r) {
  const out = [];
  if (r.alignment) out.push(el("p", { class: `align-verdict ${r.alignment.state}`, text: alignmentText(r.alignment) }));
  if (alignFeedback && alignFeedback.robot === r.id)
    out.push(el("p", { class: `feedback ${alignFeedback.ok ? "ok" : "bad"}`, text: alignFeedback.text }));
  const outline = (view.layers.own_frames || {})[r.id];
  if (!Control.canCommand() || !outline) return out;
  const button = (cls, text, action) => {
    const b = el("button", { class: cls, text });
    b.addEventListener("click", action);
    return b;
  };
  const rerender = () => renderOwnMaps(view.robots.filter((x) => x.own_map));
  if (Align.aligning() === r.id) {
    out.push(el("p", { class: "hint", text: "Drag ✥ (where it entered) and ↻ (its heading) until its walls sit on the map's." }),
      el("p", { class: "align-readout", "data-robot": String(r.id), text: Align.readout() }),
      button("align-verify", "Ask the base to verify", () => Align.verify((ok, text) => {
        alignFeedback = { robot: r.id, ok, text };
        rerender();
      })),
      button("align-cancel", "Cancel", () => { Align.stop(); rerender(); }));
  } else {
    out.push(button("align-start", "Align on the map", () => {
      alignFeedback = null;
      Align.start(r.id, outline, MapView.robotColour(r.id), r.alignment ? r.alignment.requested : null);
      rerender();
    }));
  }
  return out;
}

function renderObjects(objects) {
  const rows = objects.map((o) => {
    const colour = CLASS_COLOURS[o.class] || "#3c3cb4";
    const photo = el("div", {}, [o.thumbnail
      ? el("a", { href: o.thumbnail, target: "_blank" }, [el("img", { class: "thumb", src: o.thumbnail, alt: `${o.class} ${o.id}` })])
      : el("span", { class: "muted", text: "none" })]);
    if (o.cloud_points > 0) {
      const view = el("button", { class: "view-3d", text: "3D" });
      view.addEventListener("click", () => window.Cloud3D && Cloud3D.show(o.id, `${o.class} ${o.id}: its coloured cloud`));
      photo.appendChild(view);
    }
    const p = o.position_m || [0, 0, 0];
    const unplaced = o.frame && o.frame !== "global";
    const where = unplaced
      ? el("span", { class: "badge warn", text: `not on the map: ${o.from_entry ? o.from_entry.text : o.frame}` })
      : el("span", { class: "muted", text: "on the map" });
    const aliases = (o.aliases || []).length ? ` (was ${o.aliases.join(", ")})` : "";
    return el("tr", { class: unplaced ? "unplaced" : "" }, [
      el("td", {}, [el("span", { class: "chip", style: `background:${colour}` }), document.createTextNode(o.class)]),
      el("td", { text: o.id + aliases }),
      el("td", {}, [where]),
      el("td", { text: `${Math.round(100 * o.confidence)} %` }),
      el("td", { class: "num", text: p[0].toFixed(2) }),
      el("td", { class: "num", text: p[1].toFixed(2) }),
      el("td", { class: "num", text: p[2].toFixed(2) }),
      el("td", { text: (o.robots || []).map((r) => `Robot ${r}`).join(", ") }),
      el("td", {}, [photo]),
      Control.verdictCell(o),
    ]);
  });
  replaceRows(document.getElementById("objects"), rows, "No objects yet", 10);
}

function renderGoals(exploration) {
  if (!exploration) return;
  const rows = (exploration.goals || []).map((g) => el("tr", {}, [
    el("td", { text: `Robot ${g.robot}` }),
    el("td", { class: "num", text: g.x_m.toFixed(1) }),
    el("td", { class: "num", text: g.y_m.toFixed(1) }),
    el("td", { text: `${g.path_m.toFixed(1)} m` }),
    el("td", { text: `${g.frontier_m.toFixed(1)} m` }),
  ]));
  for (const m of exploration.meetings || []) {  // active linking: driving toward a teammate instead
    rows.push(el("tr", {}, [
      el("td", { text: `Robot ${m.robot}` }),
      el("td", { class: "num", text: m.x_m.toFixed(1) }),
      el("td", { class: "num", text: m.y_m.toFixed(1) }),
      el("td", { colspan: 2, class: "muted", text: `meeting Robot ${m.teammate}, to link their maps` }),
    ]));
  }
  for (const r of exploration.idle || []) {
    rows.push(el("tr", {}, [el("td", { text: `Robot ${r}` }), el("td", { colspan: 4, class: "muted", text: "nothing reachable left to explore" })]));
  }
  const none = exploration.frontiers > 0 ? "Frontiers are left, but no robot is free to explore them (the operator drives them)" : "Nothing left to explore";
  replaceRows(document.getElementById("goals"), rows, none, 5);
}

// What the map view draws besides its tiles, kept from the last fetch so that a selection or a
// command redraws it at once.
const view = { robots: [], objects: [], exploration: null, layers: {} };
function drawMap() {
  MapView.update({ ...view, commands: Control.commands(), selected: Control.selected(), search: Control.search() });
}

function renderAlertLog(entries) {
  const list = document.getElementById("alert-log");
  list.replaceChildren(...entries.map((e) => el("li", { class: e.active ? "" : "muted", text:
    `${new Date(e.first_seen_s * 1000).toLocaleTimeString()} ${e.text}${e.acked ? " (acknowledged)" : ""}${e.active ? "" : " (over)"}` })));
}

function renderExports(exports) {
  const list = document.getElementById("exports");
  list.replaceChildren();
  if (!exports.ready) list.appendChild(el("li", { class: "empty", text: exports.note }));
  for (const f of exports.files || []) {
    list.appendChild(el("li", {}, [el("a", { href: f.url, download: f.name, text: f.name }),
      document.createTextNode(` (${fmtBytes(f.bytes)})`)]));
  }
}

async function refresh() {
  const conn = document.getElementById("connection");
  try {
    const [status, robots, objects, commands, exports, alertLog, layers, search] = await Promise.all([
      getJson("/api/status"), getJson("/api/robots"), getJson("/api/objects"), getJson("/api/commands"),
      getJson("/api/exports"), getJson("/api/alerts/log"), getJson("/api/layers"), getJson("/api/search"),
    ]);
    renderExports(exports);
    renderAlertLog(alertLog);
    renderStatus(status);
    renderGoals(status.exploration);
    renderRobots(robots);
    renderObjects(objects);
    Object.assign(view, { robots, objects, exploration: status.exploration, layers });
    renderOwnMaps(robots.filter((r) => r.own_map));
    Align.update(layers.own_frames);
    Control.updateSearch(search);
    Control.updateCommands(commands);  // redraws the map view
    MapView.refreshTiles();
    noteUpdateLag(status);
    conn.textContent = "live";
    conn.className = "connection ok";
  } catch (e) {
    conn.textContent = "base station unreachable";
    conn.className = "connection bad";
  }
}

// Pushed: the base's event stream (/api/events) says when the map or the commands changed and the
// page fetches then; EventSource reconnects by itself. A slow poll keeps the robots' link ages
// fresh while nothing changes, and covers a stream that cannot be opened.
let mapVersion = null;
function listen() {
  const events = new EventSource("/api/events");
  events.onmessage = (e) => {
    const v = JSON.parse(e.data);
    if (v.map_version !== mapVersion) {
      mapVersion = v.map_version;
      refresh();
    } else {
      getJson("/api/commands").then(Control.updateCommands).catch(() => {});
      getJson("/api/search").then(Control.updateSearch).catch(() => {});
    }
  };
  events.onerror = () => {
    const conn = document.getElementById("connection");
    conn.textContent = "reconnecting…";
    conn.className = "connection bad";
  };
}

MapView.init({ mapClick: Control.mapClicked, robotClick: Control.robotClicked });
Align.init(MapView.leaflet());
Control.init(drawMap);
refresh();
listen();
setInterval(refresh, REFRESH_MS);
