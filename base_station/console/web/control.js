// Cairn console, control-centre part: select a robot (its marker on the map view), then
// click the map to send it there; stop / resume / home one robot or all; the commands and their
// states. Commands carry the operator token (from the link the base prints: ...#token=<token>),
// kept in this browser's storage; without it the page only watches.
"use strict";

const Control = (() => {
  const TOKEN_KEY = "cairn-operator-token";
  let selected = null;   // robot id
  let commands = [];
  let search = { paused: false, keep_out: [], stopped: [] };
  let keepOutCorner = null;  // drawing a keep-out area: its first corner, once clicked
  let drawing = false;
  let changed = () => {};  // the map view redraws (selection or commands changed)

  function token() { return localStorage.getItem(TOKEN_KEY) || ""; }

  // The token arrives in the address's fragment (never sent to a server); keep it, then hide it.
  function takeTokenFromAddress() {
    const m = /(?:^#|&)token=([0-9A-Za-z_-]+)/.exec(window.location.hash);
    if (!m) return;
    localStorage.setItem(TOKEN_KEY, m[1]);
    history.replaceState(null, "", window.location.pathname + window.location.search);
  }

  function say(text, level) {
    const box = document.getElementById("command-feedback");
    box.textContent = text;
    box.className = `feedback ${level || ""}`;
  }

  async function send(body) {
    if (!token()) return say("Watching only: open the operator link the base printed (…/#token=…) to command.", "bad");
    try {
      const res = await fetch("/api/commands", {
        method: "POST",
        headers: { "Content-Type": "application/json", Authorization: `Bearer ${token()}` },
        body: JSON.stringify(body),
      });
      const reply = await res.json().catch(() => ({}));
      if (res.status === 202) {
        const who = body.robot === "all" ? "every robot" : `Robot ${body.robot}`;
        const where = body.kind === "goto" ? ` to (${body.x_m.toFixed(1)}, ${body.y_m.toFixed(1)}) m` : "";
        say(`Sent ${body.kind}${where} to ${who} (command ${(reply.seqs || []).join(", ")}).`, "ok");
      } else if (res.status === 401) {
        localStorage.removeItem(TOKEN_KEY);
        say(`Refused: ${reply.error || "wrong operator token"}. Open the operator link again.`, "bad");
      } else {
        say(`Refused: ${reply.error || `HTTP ${res.status}`}`, "bad");
      }
    } catch (e) {
      say("The base station is unreachable: nothing was sent.", "bad");
    }
    renderBar();
  }

  function select(id) {
    selected = selected === id ? null : id;
    renderBar();
    changed();
  }

  function renderBar() {
    const label = document.getElementById("selected-robot");
    const mode = document.getElementById("operator-mode");
    mode.textContent = token() ? "operator" : "watching only";
    mode.className = token() ? "badge ok" : "badge warn";
    label.textContent = selected === null ? "no robot selected: click a robot on the map" :
      `Robot ${selected} selected: click the map to send it there`;
    for (const b of document.querySelectorAll("[data-one]")) b.disabled = selected === null || !token();
    for (const b of document.querySelectorAll("[data-all]")) b.disabled = !token();
    const pause = document.getElementById("pause-search");
    pause.textContent = search.paused ? "Resume exploration" : "Pause exploration";
    pause.disabled = !token();
    const draw = document.getElementById("draw-keep-out");
    draw.disabled = !token();
    draw.classList.toggle("active", drawing);
    if (drawing) label.textContent = "Keep-out area: click two opposite corners on the map";
  }

  function mapClicked(x_m, y_m) {
    if (drawing) return keepOutClick(x_m, y_m);
    if (selected === null) return;
    send({ robot: selected, kind: "goto", x_m, y_m });
  }

  // The team's search: pause / resume the exploration, keep-out areas (two corners on the map).
  async function sendSearch(body) {
    if (!token()) return say("Watching only: open the operator link the base printed (…/#token=…) to command.", "bad");
    const res = await fetch("/api/search", {
      method: "POST",
      headers: { "Content-Type": "application/json", Authorization: `Bearer ${token()}` },
      body: JSON.stringify(body),
    }).catch(() => null);
    const reply = res ? await res.json().catch(() => ({})) : {};
    if (res && res.status === 202) say(`Sent: ${reply.queued}.`, "ok");
    else say(`Refused: ${reply.error || "the base station is unreachable"}`, "bad");
  }

  function keepOutClick(x, y) {
    if (!keepOutCorner) {
      keepOutCorner = [x, y];
      say(`Keep-out area: first corner (${x.toFixed(1)}, ${y.toFixed(1)}) m; click the opposite corner.`, "");
      return;
    }
    const [x0, y0] = keepOutCorner;
    keepOutCorner = null;
    drawing = false;
    renderBar();
    sendSearch({ action: "keep_out", area_m: [x0, y0, x, y] });
  }

  function removeKeepOut(id) { sendSearch({ action: "clear_keep_out", area: id }); }

  function updateSearch(s) {
    search = s;
    const badge = document.getElementById("search-state");
    badge.hidden = !s.paused;
    renderBar();
    changed();
  }

  // The operator's word on an object: confirmed, false, or a note; journaled with the map and in
  // every export.
  async function judge(id, verdict, note) {
    if (!token()) return say("Watching only: open the operator link the base printed (…/#token=…) to judge objects.", "bad");
    const res = await fetch(`/api/objects/${id}/verdict`, {
      method: "POST",
      headers: { "Content-Type": "application/json", Authorization: `Bearer ${token()}` },
      body: JSON.stringify({ verdict, note }),
    }).catch(() => null);
    const reply = res ? await res.json().catch(() => ({})) : {};
    if (res && res.status === 202) say(`Object ${id}: ${verdict}${note ? ` (${note})` : ""}.`, "ok");
    else say(`Refused: ${reply.error || "the base station is unreachable"}`, "bad");
  }

  function verdictCell(o) {
    const cell = el("td", { class: "verdict" }, [
      el("span", { class: `verdict-badge ${o.verdict}`, text: o.verdict || "unreviewed" }),
    ]);
    if (o.verdict_note) cell.appendChild(el("div", { class: "muted", text: o.verdict_note }));
    if (!token()) return cell;
    const button = (text, verdict, asksNote) => {
      const b = el("button", { class: `judge ${verdict}`, text });
      b.addEventListener("click", () => {
        const note = asksNote ? window.prompt(`Note on ${o.class} ${o.id}:`, o.verdict_note || "") : o.verdict_note || "";
        if (note !== null) judge(o.id, asksNote ? o.verdict || "unreviewed" : verdict, note);
      });
      return b;
    };
    cell.appendChild(el("div", { class: "judge-buttons" }, [
      button("Confirm", "confirmed", false), button("False", "false", false), button("Note…", "note", true),
    ]));
    return cell;
  }

  function renderCommands(commands) {
    const rows = commands.map((c) => el("tr", {}, [
      el("td", { class: "num", text: c.seq }),
      el("td", { text: `Robot ${c.robot}` }),
      el("td", { text: c.kind === "goto" ? `go to (${c.x_m.toFixed(1)}, ${c.y_m.toFixed(1)}) m` : c.kind }),
      el("td", { text: fmtTime(c.sent_s) }),
      el("td", {}, [el("span", { class: `state ${c.state}`, text: c.state })]),
      el("td", { class: "muted", text: c.note || "" }),
    ]));
    replaceRows(document.getElementById("commands"), rows, "No commands sent", 6);
  }

  function updateCommands(newCommands) {
    commands = newCommands;
    renderCommands(commands);
    changed();
  }

  function init(onChange) {
    changed = onChange;
    takeTokenFromAddress();
    for (const b of document.querySelectorAll("[data-one]")) {
      b.addEventListener("click", () => selected !== null && send({ robot: selected, kind: b.dataset.one }));
    }
    for (const b of document.querySelectorAll("[data-all]")) {
      b.addEventListener("click", () => send({ robot: "all", kind: b.dataset.all }));
    }
    document.getElementById("pause-search").addEventListener("click",
      () => sendSearch({ action: search.paused ? "resume" : "pause" }));
    document.getElementById("draw-keep-out").addEventListener("click", () => {
      drawing = !drawing;
      keepOutCorner = null;
      renderBar();
    });
    renderBar();
  }

  // "Acknowledge" for an alert (null without the token: watching only).
  function ackButton(key) {
    if (!token()) return null;
    const b = el("button", { class: "ack", text: "Acknowledge" });
    b.addEventListener("click", async () => {
      const res = await fetch("/api/alerts/ack", {
        method: "POST",
        headers: { "Content-Type": "application/json", Authorization: `Bearer ${token()}` },
        body: JSON.stringify({ key }),
      }).catch(() => null);
      if (res && res.status === 202) {
        b.closest("li").classList.add("acked");
        b.remove();
      } else {
        say("The acknowledgement did not reach the base station.", "bad");
      }
    });
    return b;
  }

  /// POSTs JSON with the operator token: {status, reply} (status 0: the base is unreachable).
  async function post(path, body) {
    if (!token()) return { status: 401, reply: { error: "watching only: open the operator link the base printed (…/#token=…)" } };
    const res = await fetch(path, {
      method: "POST",
      headers: { "Content-Type": "application/json", Authorization: `Bearer ${token()}` },
      body: JSON.stringify(body),
    }).catch(() => null);
    return { status: res ? res.status : 0, reply: res ? await res.json().catch(() => ({})) : {} };
  }

  return {
    init,
    post,
    ackButton,
    verdictCell,
    mapClicked,
    removeKeepOut,
    updateSearch,
    search: () => search,
    canCommand: () => Boolean(token()),
    claimsMapClick: () => drawing || selected !== null,
    robotClicked: select,
    selected: () => selected,
    commands: () => commands,
    updateCommands,
  };
})();
